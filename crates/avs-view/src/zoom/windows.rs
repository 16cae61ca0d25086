//! Hypothesis grouping and reduction (Sjöö et al. `004` §3.4.1): one class's hypotheses
//! gathered into *zoom windows*, the regions of the current image to magnify next.
//!
//! What the paper says: "The size of these windows is determined by the magnification
//! recommended by the distance estimate of the strongest hypothesis. The position of the window
//! is chosen to cover the maximum number of hypotheses, and this is repeated until all
//! hypotheses are covered." Then "zoom windows which overlap more than 20 % with another
//! containing at least 3 times its number of hypotheses are removed."
//!
//! ## Choices where the paper is vague
//! * **Size.** A window of magnification `m` (relative to the current image) is the image
//!   divided by `m` in both directions, so it keeps the image's aspect and zooming by `m` onto
//!   its centre shows exactly it. A magnification below 1 is taken as 1 (the window is the
//!   whole image); a magnification that is not a finite positive number, or an unusable image
//!   geometry, gives no windows.
//! * **Covering.** A hypothesis is covered when the centre of its peak cell lies in the window
//!   (edges included). Each round chooses, among candidate windows, the one covering the most
//!   not-yet-covered hypotheses (ties: the larger sum of their values, then the first
//!   candidate). The candidates are the windows whose left edge lies on the centre of an
//!   uncovered hypothesis and whose top edge lies on the centre of an uncovered hypothesis
//!   (each pair of them), shifted back inside the image where they stick out. These suffice:
//!   any window covering a set of centres can be slid right and down until its left and top
//!   edges touch the leftmost and topmost of them without losing one, and shifting it back
//!   inside the image loses none either (the centres are inside the image). The chosen set's
//!   window is then centred on the bounding box of the set's centres (kept inside the image),
//!   so that a lone hypothesis sits in the middle of its window rather than on its edge; any
//!   other uncovered hypothesis it then covers joins it. The rounds are a greedy set cover:
//!   they end when all hypotheses are covered, with at most one window per hypothesis, though
//!   not always the fewest windows possible.
//! * **Which hypotheses.** Only those of the given class; a hypothesis whose centre lies
//!   outside the image (a vote matrix that does not fit the image) is left out.
//! * **Overlap.** "Overlap more than 20 %" is the intersection's area over the *smaller* of
//!   the two windows' areas, strictly above [`REDUCE_OVERLAP`]. Only windows sharing a class
//!   are compared (a book's rich window does not make a cup's window redundant). Windows are
//!   decided richest first and a window is removed only for a window that is kept, so the
//!   result does not depend on the input order; the kept windows stay in input order.

use super::hypotheses::Hypothesis;
use avs_robot::ImageGeometry;
use serde::{Deserialize, Serialize};

/// Windows overlapping a richer one by more than this share of the smaller's area are removed
/// (§3.4.1: "more than 20 %").
pub const REDUCE_OVERLAP: f64 = 0.2;

/// A window is removed only for one holding at least this many times its number of hypotheses
/// (§3.4.1: "at least 3 times").
pub const REDUCE_RICHER: usize = 3;

/// Slack for comparisons of pixel coordinates and magnifications.
pub(crate) const EPS: f64 = 1e-9;

/// A region of the current image to magnify next, with the hypotheses it covers (§3.4.1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ZoomWindow {
    /// The classes to look for in it (one after grouping; more after sharing, §3.4.2). The
    /// first is the class that owns it.
    pub classes: Vec<String>,
    /// The window in the current image, pixels `[u0, v0, u1, v1]` (left, top, right, bottom).
    pub box_px: [f64; 4],
    /// The hypotheses it covers, strongest first.
    pub hypotheses: Vec<Hypothesis>,
    /// Its magnification relative to the current image (image size over window size).
    pub zoom: f64,
    /// The lowest magnification its classes allow (the largest size it may grow to).
    pub min_zoom: f64,
    /// The highest magnification its classes want (the smallest size it shrinks to).
    pub max_zoom: f64,
}

impl ZoomWindow {
    /// The centre of the window, pixels: where the camera turns to zoom onto it.
    pub fn centre_px(&self) -> (f64, f64) {
        let [u0, v0, u1, v1] = self.box_px;
        ((u0 + u1) / 2.0, (v0 + v1) / 2.0)
    }

    /// Its area, square pixels.
    pub fn area_px(&self) -> f64 {
        let [u0, v0, u1, v1] = self.box_px;
        (u1 - u0).max(0.0) * (v1 - v0).max(0.0)
    }

    /// Whether pixel `(u, v)` lies in it (edges included).
    pub fn contains_px(&self, (u, v): (f64, f64)) -> bool {
        inside(&self.box_px, (u, v))
    }

    /// The strongest vote value among its hypotheses (`-∞` with none).
    pub fn strongest(&self) -> f64 {
        self.hypotheses
            .iter()
            .map(|h| h.value)
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// Whether `(u, v)` lies in `b` (edges included, with [`EPS`] of slack).
pub(crate) fn inside(b: &[f64; 4], (u, v): (f64, f64)) -> bool {
    u >= b[0] - EPS && u <= b[2] + EPS && v >= b[1] - EPS && v <= b[3] + EPS
}

/// A `w × h` box centred on `(cu, cv)`, shifted inside a `iw × ih` image (a box larger than
/// the image is the image).
pub(crate) fn place_box(
    (cu, cv): (f64, f64),
    (w, h): (f64, f64),
    (iw, ih): (f64, f64),
) -> [f64; 4] {
    let (w, h) = (w.min(iw), h.min(ih));
    let u0 = (cu - w / 2.0).clamp(0.0, iw - w);
    let v0 = (cv - h / 2.0).clamp(0.0, ih - h);
    [u0, v0, u0 + w, v0 + h]
}

/// The bounding box `[u0, v0, u1, v1]` of some points (`None` for none).
pub(crate) fn bounds(points: impl IntoIterator<Item = (f64, f64)>) -> Option<[f64; 4]> {
    points.into_iter().fold(None, |b, (u, v)| {
        Some(match b {
            None => [u, v, u, v],
            Some([u0, v0, u1, v1]) => [u0.min(u), v0.min(v), u1.max(u), v1.max(v)],
        })
    })
}

/// Group one class's hypotheses into zoom windows of magnification `magnification` relative to
/// the current image (§3.4.1; module docs for the candidates and the placement). Every
/// hypothesis of `class` inside the image ends in exactly one window; each window's
/// `min_zoom` and `max_zoom` are its magnification (the search widens them for sharing).
pub fn group_into_windows(
    hyps: &[Hypothesis],
    class: &str,
    magnification: f64,
    image: &ImageGeometry,
) -> Vec<ZoomWindow> {
    if image.problem().is_some() || !(magnification.is_finite() && magnification > 0.0) {
        return Vec::new();
    }
    let m = magnification.max(1.0);
    let (iw, ih) = (f64::from(image.width_px), f64::from(image.height_px));
    let (w, h) = (iw / m, ih / m);
    let pts: Vec<(&Hypothesis, (f64, f64))> = hyps
        .iter()
        .filter(|h| h.class == class)
        .map(|h| (h, h.centre_px(image)))
        .filter(|(_, (u, v))| (0.0..=iw).contains(u) && (0.0..=ih).contains(v))
        .collect();
    let mut covered = vec![false; pts.len()];
    let mut out = Vec::new();
    while covered.iter().any(|c| !c) {
        let open: Vec<usize> = (0..pts.len()).filter(|&i| !covered[i]).collect();
        // (count, value sum, members) of the best candidate so far.
        let mut best: Option<(usize, f64, Vec<usize>)> = None;
        // Candidate left and top edges, each once (hypotheses share cell columns and rows),
        // strongest hypothesis first.
        let mut lefts: Vec<f64> = Vec::new();
        let mut tops: Vec<f64> = Vec::new();
        for &k in &open {
            let u0 = pts[k].1 .0.clamp(0.0, iw - w);
            let v0 = pts[k].1 .1.clamp(0.0, ih - h);
            if !lefts.contains(&u0) {
                lefts.push(u0);
            }
            if !tops.contains(&v0) {
                tops.push(v0);
            }
        }
        for &u0 in &lefts {
            for &v0 in &tops {
                let b = [u0, v0, u0 + w, v0 + h];
                let members: Vec<usize> = open
                    .iter()
                    .copied()
                    .filter(|&k| inside(&b, pts[k].1))
                    .collect();
                let value: f64 = members.iter().map(|&k| pts[k].0.value).sum();
                let better = match &best {
                    None => true,
                    Some((n, s, _)) => members.len() > *n || (members.len() == *n && value > *s),
                };
                if better {
                    best = Some((members.len(), value, members));
                }
            }
        }
        let Some((n, _, members)) = best else { break };
        if n == 0 {
            break;
        }
        let Some([u0, v0, u1, v1]) = bounds(members.iter().map(|&k| pts[k].1)) else {
            break;
        };
        let b = place_box(((u0 + u1) / 2.0, (v0 + v1) / 2.0), (w, h), (iw, ih));
        let mut inside_now: Vec<usize> = open
            .iter()
            .copied()
            .filter(|&k| inside(&b, pts[k].1))
            .collect();
        // The set chosen is in the recentred box by construction; guard against rounding.
        for k in members {
            if !inside_now.contains(&k) {
                inside_now.push(k);
            }
        }
        let mut hs: Vec<Hypothesis> = inside_now
            .iter()
            .map(|&k| {
                covered[k] = true;
                pts[k].0.clone()
            })
            .collect();
        hs.sort_by(|a, b| {
            b.value
                .total_cmp(&a.value)
                .then(a.row.cmp(&b.row))
                .then(a.col.cmp(&b.col))
        });
        out.push(ZoomWindow {
            classes: vec![class.to_string()],
            box_px: b,
            hypotheses: hs,
            zoom: m,
            min_zoom: m,
            max_zoom: m,
        });
    }
    out
}

/// The area of the intersection of two boxes, square pixels.
fn intersection(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    let w = a[2].min(b[2]) - a[0].max(b[0]);
    let h = a[3].min(b[3]) - a[1].max(b[1]);
    w.max(0.0) * h.max(0.0)
}

/// Remove the windows that overlap more than [`REDUCE_OVERLAP`] of the smaller window's area
/// with a kept window of a common class holding at least [`REDUCE_RICHER`] times as many
/// hypotheses (§3.4.1; module docs). The kept windows stay in input order.
pub fn reduce(windows: Vec<ZoomWindow>) -> Vec<ZoomWindow> {
    let mut order: Vec<usize> = (0..windows.len()).collect();
    order.sort_by(|&a, &b| {
        windows[b]
            .hypotheses
            .len()
            .cmp(&windows[a].hypotheses.len())
            .then(a.cmp(&b))
    });
    let mut kept = vec![false; windows.len()];
    for &i in &order {
        let w = &windows[i];
        let dominated = order.iter().any(|&j| {
            let o = &windows[j];
            if j == i || !kept[j] || o.hypotheses.len() < REDUCE_RICHER * w.hypotheses.len() {
                return false;
            }
            if !w.classes.iter().any(|c| o.classes.contains(c)) {
                return false;
            }
            let smaller = w.area_px().min(o.area_px());
            smaller > 0.0 && intersection(&w.box_px, &o.box_px) / smaller > REDUCE_OVERLAP
        });
        kept[i] = !dominated;
    }
    windows
        .into_iter()
        .zip(kept)
        .filter_map(|(w, k)| k.then_some(w))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A hypothesis of `class` at cell `(col, row)` with value `value` (its own cell as box).
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

    /// The fewest candidate windows (module docs) covering every hypothesis: brute force over
    /// subsets of 1, 2, 3 … candidates.
    fn brute_force_min(hs: &[Hypothesis], m: f64, g: &ImageGeometry) -> usize {
        let (iw, ih) = (f64::from(g.width_px), f64::from(g.height_px));
        let (w, h) = (iw / m, ih / m);
        let pts: Vec<(f64, f64)> = hs.iter().map(|h| h.centre_px(g)).collect();
        let mut cands: Vec<u64> = Vec::new();
        for a in &pts {
            for b in &pts {
                let (u0, v0) = (a.0.clamp(0.0, iw - w), b.1.clamp(0.0, ih - h));
                let bx = [u0, v0, u0 + w, v0 + h];
                let mask = pts
                    .iter()
                    .enumerate()
                    .filter(|(_, p)| inside(&bx, **p))
                    .fold(0u64, |m, (k, _)| m | (1 << k));
                cands.push(mask);
            }
        }
        let all = (1u64 << pts.len()) - 1;
        (1..=pts.len())
            .find(|&k| covers_with(&cands, all, k, 0, 0))
            .unwrap_or(pts.len())
    }

    /// Whether `k` more of `cands[start..]` cover `all` together with `mask`.
    fn covers_with(cands: &[u64], all: u64, k: usize, start: usize, mask: u64) -> bool {
        mask == all
            || (k > 0
                && (start..cands.len())
                    .any(|i| covers_with(cands, all, k - 1, i + 1, mask | cands[i])))
    }

    fn assert_covers(ws: &[ZoomWindow], hs: &[Hypothesis], g: &ImageGeometry, m: f64) {
        let (iw, ih) = (f64::from(g.width_px), f64::from(g.height_px));
        for h in hs {
            let n = ws.iter().filter(|w| w.hypotheses.contains(h)).count();
            assert_eq!(n, 1, "{h:?} is in {n} windows");
            let w = ws.iter().find(|w| w.hypotheses.contains(h)).unwrap();
            assert!(
                w.contains_px(h.centre_px(g)),
                "{h:?} outside {:?}",
                w.box_px
            );
        }
        for w in ws {
            let [u0, v0, u1, v1] = w.box_px;
            assert!(u0 >= -EPS && v0 >= -EPS && u1 <= iw + EPS && v1 <= ih + EPS);
            assert!((u1 - u0 - iw / m).abs() < 1e-9 && (v1 - v0 - ih / m).abs() < 1e-9);
            assert_eq!(w.zoom, m);
        }
    }

    #[test]
    fn grouping_covers_every_hypothesis_with_as_few_windows_as_brute_force() {
        let g = ImageGeometry::default();
        let cases: Vec<(Vec<Hypothesis>, f64)> = vec![
            // Two clusters far apart at magnification 3 (windows of 106.7 × 80 px).
            (
                vec![
                    hyp("book", 1, 1, 0.9),
                    hyp("book", 3, 2, 0.8),
                    hyp("book", 13, 10, 0.7),
                    hyp("book", 15, 11, 0.6),
                    hyp("book", 19, 14, 0.5),
                ],
                3.0,
            ),
            // A row of five 3 cells apart: at magnification 4 (80 px wide) two fit a window
            // (45 px apart), three do not (90 px): three windows.
            (
                (0..5)
                    .map(|i| hyp("book", 2 + 3 * i, 7, 0.9 - 0.1 * i as f64))
                    .collect(),
                4.0,
            ),
            // A diagonal where the strongest hypothesis sits in the middle.
            (
                vec![
                    hyp("book", 10, 8, 0.9),
                    hyp("book", 6, 5, 0.5),
                    hyp("book", 14, 11, 0.5),
                    hyp("book", 2, 2, 0.4),
                ],
                3.0,
            ),
            // One hypothesis in a corner.
            (vec![hyp("book", 20, 15, 0.9)], 5.0),
        ];
        for (hs, m) in cases {
            let ws = group_into_windows(&hs, "book", m, &g);
            assert_covers(&ws, &hs, &g, m);
            assert_eq!(ws.len(), brute_force_min(&hs, m, &g), "{hs:?}");
        }
    }

    #[test]
    fn two_clusters_give_two_windows_each_centred_on_its_cluster() {
        let g = ImageGeometry::default();
        let hs = vec![
            hyp("book", 4, 4, 0.9),
            hyp("book", 6, 5, 0.8),
            hyp("book", 16, 12, 0.7),
        ];
        let ws = group_into_windows(&hs, "book", 4.0, &g);
        assert_eq!(ws.len(), 2);
        // The first window holds the first two, centred on their centres' box:
        // u from 67.5 to 97.5, v from 67.5 to 82.5.
        assert_eq!(ws[0].hypotheses.len(), 2);
        let (cu, cv) = ws[0].centre_px();
        assert!((cu - 82.5).abs() < 1e-9 && (cv - 75.0).abs() < 1e-9);
        // The lone third hypothesis is in the middle of its own window.
        let (cu, cv) = ws[1].centre_px();
        assert_eq!((cu, cv), hs[2].centre_px(&g));
    }

    #[test]
    fn windows_at_the_image_border_stay_inside_the_image() {
        let g = ImageGeometry::default();
        let hs = vec![hyp("book", 0, 0, 0.9), hyp("book", 20, 15, 0.8)];
        let ws = group_into_windows(&hs, "book", 2.0, &g);
        assert_eq!(ws.len(), 2);
        assert_eq!(ws[0].box_px, [0.0, 0.0, 160.0, 120.0]);
        assert_eq!(ws[1].box_px, [160.0, 120.0, 320.0, 240.0]);
    }

    #[test]
    fn grouping_takes_only_the_class_and_bad_magnifications_give_nothing() {
        let g = ImageGeometry::default();
        let hs = vec![hyp("book", 3, 3, 0.9), hyp("cup", 10, 10, 0.9)];
        let ws = group_into_windows(&hs, "book", 3.0, &g);
        assert_eq!(ws.len(), 1);
        assert_eq!(ws[0].classes, vec!["book".to_string()]);
        assert_eq!(ws[0].hypotheses.len(), 1);
        assert!(group_into_windows(&hs, "book", f64::NAN, &g).is_empty());
        assert!(group_into_windows(&hs, "book", 0.0, &g).is_empty());
        let zero = ImageGeometry { width_px: 0, ..g };
        assert!(group_into_windows(&hs, "book", 3.0, &zero).is_empty());
        // Below 1: the whole image.
        let ws = group_into_windows(&hs, "book", 0.5, &g);
        assert_eq!(ws[0].box_px, [0.0, 0.0, 320.0, 240.0]);
        assert_eq!(ws[0].zoom, 1.0);
    }

    #[test]
    fn grouping_random_scatters_covers_every_hypothesis_once() {
        // A small linear congruential generator: deterministic, no dependency.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = |n: usize| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            ((state >> 33) as usize) % n
        };
        let g = ImageGeometry::default();
        for _ in 0..50 {
            let n = 1 + next(12);
            let mut hs: Vec<Hypothesis> = Vec::new();
            while hs.len() < n {
                let h = hyp("book", next(21), next(16), 0.4 + 0.05 * next(10) as f64);
                if !hs.iter().any(|o| (o.col, o.row) == (h.col, h.row)) {
                    hs.push(h);
                }
            }
            let m = 1.0 + next(6) as f64;
            let ws = group_into_windows(&hs, "book", m, &g);
            assert_covers(&ws, &hs, &g, m);
            assert!(ws.len() <= hs.len());
        }
    }

    #[test]
    fn the_densest_field_of_hypotheses_is_grouped_with_every_one_covered() {
        // Every other cell in both directions is a local maximum: 11 × 8 = 88 hypotheses.
        let g = ImageGeometry::default();
        let hs: Vec<Hypothesis> = (0..8)
            .flat_map(|r| {
                (0..11).map(move |c| hyp("book", 2 * c, 2 * r, 0.5 + 0.001 * (c + r) as f64))
            })
            .collect();
        for m in [1.5, 3.0, 6.0] {
            let ws = group_into_windows(&hs, "book", m, &g);
            assert_covers(&ws, &hs, &g, m);
            // At most ⌈2m⌉² windows: four times the m² of a regular tiling, the greedy's slack.
            let tiles = ((m * 2.0).ceil() * (m * 2.0).ceil()) as usize;
            assert!(ws.len() <= tiles, "{} windows at {m}", ws.len());
        }
    }

    fn window(classes: &[&str], b: [f64; 4], n: usize) -> ZoomWindow {
        ZoomWindow {
            classes: classes.iter().map(|c| c.to_string()).collect(),
            box_px: b,
            hypotheses: (0..n).map(|i| hyp(classes[0], i, 0, 0.5)).collect(),
            zoom: 3.0,
            min_zoom: 3.0,
            max_zoom: 3.0,
        }
    }

    #[test]
    fn reduction_removes_exactly_the_dominated_window() {
        let rich = window(&["book"], [0.0, 0.0, 100.0, 80.0], 6);
        // 30 % of its area inside the rich window, a third of its hypotheses: removed.
        let poor = window(&["book"], [70.0, 0.0, 170.0, 80.0], 2);
        // As much overlap but half the hypotheses: kept (6 < 3 × 3).
        let middling = window(&["book"], [0.0, 56.0, 100.0, 136.0], 3);
        // Only 10 % overlap: kept.
        let aside = window(&["book"], [90.0, 0.0, 190.0, 80.0], 1);
        // A cup window as poor and as close: another class, kept.
        let cup = window(&["cup"], [70.0, 0.0, 170.0, 80.0], 1);
        let out = reduce(vec![
            poor.clone(),
            rich.clone(),
            middling.clone(),
            aside.clone(),
            cup.clone(),
        ]);
        assert_eq!(out, vec![rich, middling, aside, cup]);
    }

    #[test]
    fn reduction_needs_more_than_twenty_percent_overlap() {
        let rich = window(&["book"], [0.0, 0.0, 100.0, 80.0], 3);
        // Exactly 20 % (20 px of 100): kept; a pixel more: removed.
        let at = window(&["book"], [80.0, 0.0, 180.0, 80.0], 1);
        let over = window(&["book"], [79.0, 0.0, 179.0, 80.0], 1);
        assert_eq!(reduce(vec![rich.clone(), at.clone()]).len(), 2);
        assert_eq!(reduce(vec![rich.clone(), over]), vec![rich]);
    }

    #[test]
    fn reduction_removes_only_for_a_kept_window() {
        // c is dominated by b, b by a; a and c do not overlap: b goes, c stays.
        let a = window(&["book"], [0.0, 0.0, 100.0, 80.0], 9);
        let b = window(&["book"], [60.0, 0.0, 160.0, 80.0], 3);
        let c = window(&["book"], [130.0, 0.0, 230.0, 80.0], 1);
        assert_eq!(reduce(vec![c.clone(), b, a.clone()]), vec![c, a]);
    }
}
