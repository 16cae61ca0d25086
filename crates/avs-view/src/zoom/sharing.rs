//! Zoom window sharing between classes (Sjöö et al. `004` §3.4.2): one middle-step image looks
//! for several classes when one class's window can take in another's hypotheses.
//!
//! What the paper says: "a maximum and a minimum magnification is defined for the middle-level
//! detection step … first all zoom windows are shrunk to their minimum size. Then, each zoom
//! window associated with an object A is compared with those of an object B. If the hypotheses
//! contained by one of B's windows can be made to be contained by one of A's – expanding the
//! latter if needed, while conforming its maximum allowed size – then the B window is removed,
//! and object B is added to the A window's list of candidate objects to look for in the next
//! step. This procedure is repeated for each pair of objects. … the maximum middle-level
//! magnification is set to 0.75 of the final, and the minimum to 0.7 of the final zoom level."
//!
//! ## Choices where the paper is vague
//! * **Sizes.** A window of magnification `m` is the image divided by `m`
//!   ([`super::windows`]); its smallest size is at its `max_zoom` ([`MIDDLE_MAX`] of the
//!   final), its largest at its `min_zoom` ([`MIDDLE_MIN`] of the final). Magnifications below 1
//!   are taken as 1 (a window is never larger than the image).
//! * **Shrinking.** A window shrinks to the smallest size its hypotheses allow — its
//!   `max_zoom` size, or the bounding box of its hypotheses' peak-cell centres when that is
//!   larger — centred on that box and kept inside the image. A window whose hypotheses do not
//!   fit even its largest size keeps its box.
//! * **Both classes' limits.** The merged window must hold the hypotheses of both windows, and
//!   may grow no larger than the size of the *higher* of the two windows' `min_zoom`: neither
//!   class is then looked for at less magnification than it allows (the paper's "it is most
//!   important to get the minimum zoom right … the higher the risk that objects are missed
//!   because they appear too small"). B's upper limit is not enforced: the window is at most
//!   A's `max_zoom`, and a B seen larger than planned only brings its final step nearer. The
//!   merged window's `min_zoom` is the higher of the two; its `max_zoom` stays A's.
//! * **Pairs and order.** A window belongs to its first class. Classes are taken in the order
//!   their first window appears; for each ordered pair (A, B) of different classes, each of
//!   B's remaining windows merges into the A window that needs the least expansion (the highest
//!   resulting magnification; ties to the first), if any can take it. A merged window keeps its
//!   owner and can absorb further windows of other classes; a window that was merged away is
//!   gone. The remaining windows keep their input order.

use super::windows::{bounds, place_box, ZoomWindow, EPS};
use avs_robot::ImageGeometry;

/// The lowest middle-step magnification, as a share of the final (§3.4.2: "the minimum to 0.7
/// of the final zoom level").
pub const MIDDLE_MIN: f64 = 0.7;

/// The highest middle-step magnification, as a share of the final (§3.4.2: "the maximum
/// middle-level magnification is set to 0.75 of the final").
pub const MIDDLE_MAX: f64 = 0.75;

/// The magnification at which a `w × h` (pixels) extent of points just fits a window of a
/// `iw × ih` image (infinite for a single point).
fn fitting_zoom((w, h): (f64, f64), (iw, ih): (f64, f64)) -> f64 {
    let mu = if w > 0.0 { iw / w } else { f64::INFINITY };
    let mv = if h > 0.0 { ih / h } else { f64::INFINITY };
    mu.min(mv)
}

/// The peak-cell centres of a window's hypotheses.
fn centres<'a>(
    w: &'a ZoomWindow,
    image: &'a ImageGeometry,
) -> impl Iterator<Item = (f64, f64)> + 'a {
    w.hypotheses.iter().map(move |h| h.centre_px(image))
}

/// The box of magnification `m` around points with bounds `b`, inside the image.
fn box_around(b: [f64; 4], m: f64, (iw, ih): (f64, f64)) -> [f64; 4] {
    let centre = ((b[0] + b[2]) / 2.0, (b[1] + b[3]) / 2.0);
    place_box(centre, (iw / m, ih / m), (iw, ih))
}

/// Share zoom windows between classes (§3.4.2; module docs): shrink every window to its
/// smallest size, then merge each window of a class B into a window of a class A that can be
/// grown to hold B's hypotheses within both classes' lowest magnifications. `image` is the
/// geometry of the image the windows are in (it places the hypotheses' cells in pixels). An
/// unusable geometry returns the windows unchanged.
pub fn share(windows: Vec<ZoomWindow>, image: &ImageGeometry) -> Vec<ZoomWindow> {
    if image.problem().is_some() {
        return windows;
    }
    let size = (f64::from(image.width_px), f64::from(image.height_px));
    let mut ws: Vec<ZoomWindow> = windows.into_iter().map(|w| shrink(w, image)).collect();
    let mut owners: Vec<String> = Vec::new();
    for w in &ws {
        if let Some(c) = w.classes.first() {
            if !owners.contains(c) {
                owners.push(c.clone());
            }
        }
    }
    let owner = |w: &ZoomWindow| w.classes.first().cloned();
    let mut alive = vec![true; ws.len()];
    for a in &owners {
        for b in owners.iter().filter(|b| *b != a) {
            for j in 0..ws.len() {
                if !alive[j] || owner(&ws[j]).as_ref() != Some(b) {
                    continue;
                }
                // The A window needing the least expansion: (index, magnification, bounds).
                let mut best: Option<(usize, f64, [f64; 4])> = None;
                for i in 0..ws.len() {
                    if i == j || !alive[i] || owner(&ws[i]).as_ref() != Some(a) {
                        continue;
                    }
                    let Some(bx) = bounds(centres(&ws[i], image).chain(centres(&ws[j], image)))
                    else {
                        continue;
                    };
                    let need = fitting_zoom((bx[2] - bx[0], bx[3] - bx[1]), size);
                    let m = ws[i].zoom.min(need).max(1.0);
                    let lowest = ws[i].min_zoom.max(ws[j].min_zoom);
                    let fits = m + EPS >= lowest && m <= need + EPS;
                    if fits && best.is_none_or(|(_, bm, _)| m > bm) {
                        best = Some((i, m, bx));
                    }
                }
                if let Some((i, m, bx)) = best {
                    let taken = std::mem::replace(
                        &mut ws[j],
                        ZoomWindow {
                            classes: Vec::new(),
                            box_px: [0.0; 4],
                            hypotheses: Vec::new(),
                            zoom: 1.0,
                            min_zoom: 1.0,
                            max_zoom: 1.0,
                        },
                    );
                    alive[j] = false;
                    let w = &mut ws[i];
                    w.min_zoom = w.min_zoom.max(taken.min_zoom);
                    w.zoom = m;
                    w.box_px = box_around(bx, m, size);
                    for c in taken.classes {
                        if !w.classes.contains(&c) {
                            w.classes.push(c);
                        }
                    }
                    w.hypotheses.extend(taken.hypotheses);
                    w.hypotheses.sort_by(|a, b| {
                        b.value
                            .total_cmp(&a.value)
                            .then(a.row.cmp(&b.row))
                            .then(a.col.cmp(&b.col))
                    });
                }
            }
        }
    }
    ws.into_iter()
        .zip(alive)
        .filter_map(|(w, k)| k.then_some(w))
        .collect()
}

/// A window shrunk to the smallest size its hypotheses and its `max_zoom` allow (module docs).
fn shrink(mut w: ZoomWindow, image: &ImageGeometry) -> ZoomWindow {
    let size = (f64::from(image.width_px), f64::from(image.height_px));
    let Some(bx) = bounds(centres(&w, image)) else {
        return w;
    };
    let need = fitting_zoom((bx[2] - bx[0], bx[3] - bx[1]), size);
    let m = w.max_zoom.min(need).max(1.0);
    if !m.is_finite() || m + EPS < w.min_zoom.min(w.max_zoom) || m > need + EPS {
        return w;
    }
    w.zoom = m;
    w.box_px = box_around(bx, m, size);
    w
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::zoom::hypotheses::Hypothesis;

    fn hyp(class: &str, col: usize, row: usize, value: f64) -> Hypothesis {
        Hypothesis {
            class: class.into(),
            col,
            row,
            value,
            min_col: col,
            min_row: row,
            max_col: col,
            max_row: row,
        }
    }

    /// A window for `class` holding `hs`, with the middle range of a final magnification
    /// `fin`, at its lowest magnification (as the search groups them).
    fn window(class: &str, hs: Vec<Hypothesis>, fin: f64, g: &ImageGeometry) -> ZoomWindow {
        let mut w = crate::zoom::windows::group_into_windows(&hs, class, MIDDLE_MIN * fin, g);
        assert_eq!(w.len(), 1);
        let mut w = w.remove(0);
        w.min_zoom = MIDDLE_MIN * fin;
        w.max_zoom = MIDDLE_MAX * fin;
        w
    }

    #[test]
    fn windows_shrink_to_their_smallest_size_around_their_hypotheses() {
        let g = ImageGeometry::default();
        let w = window("book", vec![hyp("book", 10, 8, 0.9)], 4.0, &g);
        assert!((w.zoom - 2.8).abs() < 1e-12);
        let out = share(vec![w], &g);
        assert_eq!(out.len(), 1);
        assert!((out[0].zoom - 3.0).abs() < 1e-12);
        let [u0, v0, u1, v1] = out[0].box_px;
        assert!((u1 - u0 - 320.0 / 3.0).abs() < 1e-9 && (v1 - v0 - 80.0).abs() < 1e-9);
        let (cu, cv) = out[0].centre_px();
        assert!((cu - 157.5).abs() < 1e-9 && (cv - 127.5).abs() < 1e-9);
        // Two hypotheses 150 px apart fit a window magnified at most 320 / 150 = 2.13: between
        // the book's 0.7 × 3 = 2.1 and 0.75 × 3 = 2.25, so it shrinks only to 2.13.
        let w = window(
            "book",
            vec![hyp("book", 2, 8, 0.9), hyp("book", 12, 8, 0.8)],
            3.0,
            &g,
        );
        let out = share(vec![w], &g);
        assert!(
            (out[0].zoom - 320.0 / 150.0).abs() < 1e-9,
            "{}",
            out[0].zoom
        );
    }

    #[test]
    fn sharing_merges_a_b_window_into_a_compatible_a_window() {
        let g = ImageGeometry::default();
        // The book's final zoom 4 (middle 2.8–3), the cup's 4.2 (middle 2.94–3.15); the cup's
        // hypothesis 30 px right of the book's.
        let book = window("book", vec![hyp("book", 8, 6, 0.9)], 4.0, &g);
        let cup = window("cup", vec![hyp("cup", 10, 7, 0.8)], 4.2, &g);
        let out = share(vec![book, cup], &g);
        assert_eq!(out.len(), 1);
        let w = &out[0];
        assert_eq!(w.classes, vec!["book".to_string(), "cup".to_string()]);
        assert_eq!(w.hypotheses.len(), 2);
        for h in &w.hypotheses {
            assert!(w.contains_px(h.centre_px(&g)), "{h:?}");
        }
        // Still the book's smallest size (both fit), and not below the cup's lowest zoom.
        assert!((w.zoom - 3.0).abs() < 1e-9);
        assert!((w.min_zoom - 0.7 * 4.2).abs() < 1e-12);
    }

    #[test]
    fn sharing_grows_the_a_window_but_refuses_one_that_would_exceed_the_largest_size() {
        let g = ImageGeometry::default();
        // Book middle range 2.1–2.25 (final 3): windows from 142 to 152 px wide. A cup 150 px
        // to the right fits after growing the book's shrunk window from 142 to 150 px; one
        // 165 px away does not.
        let book = window("book", vec![hyp("book", 4, 7, 0.9)], 3.0, &g);
        let near = window("cup", vec![hyp("cup", 14, 7, 0.8)], 3.0, &g);
        let out = share(vec![book.clone(), near], &g);
        assert_eq!(out.len(), 1);
        assert!(
            (out[0].zoom - 320.0 / 150.0).abs() < 1e-9,
            "{}",
            out[0].zoom
        );
        let [u0, _, u1, _] = out[0].box_px;
        assert!((u1 - u0 - 150.0).abs() < 1e-9);
        assert_eq!(out[0].classes.len(), 2);
        let far = window("cup", vec![hyp("cup", 15, 7, 0.8)], 3.0, &g);
        let out = share(vec![book.clone(), far], &g);
        assert_eq!(out.len(), 2);
        assert!(out.iter().all(|w| w.classes.len() == 1));
        // A cup whose own lowest magnification is higher than the grown window's is refused
        // even where the book alone would allow it: final 4 → at least 2.8, but the pair
        // needs 320 / 150 = 2.13.
        let picky = window("cup", vec![hyp("cup", 14, 7, 0.8)], 4.0, &g);
        assert_eq!(share(vec![book, picky], &g).len(), 2);
    }

    #[test]
    fn a_shared_window_takes_in_a_third_class_and_keeps_order() {
        let g = ImageGeometry::default();
        let other = window("book", vec![hyp("book", 18, 2, 0.3)], 4.0, &g);
        let book = window("book", vec![hyp("book", 8, 6, 0.9)], 4.0, &g);
        let cup = window("cup", vec![hyp("cup", 9, 7, 0.8)], 4.0, &g);
        let pad = window("pad", vec![hyp("pad", 7, 5, 0.7)], 4.0, &g);
        let out = share(vec![other.clone(), book, cup, pad], &g);
        assert_eq!(out.len(), 2);
        assert_eq!(out[0].hypotheses, other.hypotheses);
        assert_eq!(out[1].classes, vec!["book", "cup", "pad"]);
        assert_eq!(out[1].hypotheses.len(), 3);
        assert_eq!(out[1].hypotheses[0].value, 0.9);
    }

    #[test]
    fn an_unusable_geometry_leaves_the_windows_alone() {
        let g = ImageGeometry::default();
        let w = window("book", vec![hyp("book", 8, 6, 0.9)], 4.0, &g);
        let bad = ImageGeometry { cell_px: 0, ..g };
        assert_eq!(share(vec![w.clone()], &bad), vec![w]);
    }
}
