//! Distance estimates from one image (Sjöö et al. `004` §3.3): from the vote area of the
//! strongest hypothesis (§3.3.1) and from the scale ratios of matched features (§3.3.2).
//!
//! What the paper says:
//! * §3.3.1: `D = W_real W_im / (tan(α/2) 2 D_vote)`, `D_vote` the width in pixels of the
//!   bounding box of the cells associated with the hypothesis, `α` the horizontal field of
//!   view ([`ObjectModel::distance_from_vote_width`]).
//! * §3.3.2: each matched pair of keypoints gives `D = W_real W_im S_tr / (tan(α/2) 2 W_tr
//!   S_real)` ([`ObjectModel::distance_from_scale`]); "the final estimate of the object
//!   distance is taken as the median of the distance estimates from all matches … With 4
//!   matches or more a passable rough estimate is typically obtained (within about 30 %). If
//!   there are fewer than 4 matches, the result is … not used."
//!
//! ## Choices where the paper is vague
//! * **What a distance is.** Both formulas are similar triangles of a pinhole camera, so they
//!   give the object's *depth* along the optical axis, not its range along the ray through its
//!   pixel; the search converts one into the other before placing the object in space.
//! * **Unusable matches.** A match whose scale ratio is not a finite positive number, or
//!   whose distance is not, is left out before counting; fewer than
//!   [`MIN_MATCHES_FOR_DISTANCE`] usable matches give no estimate.
//! * **Median of an even count.** The mean of the two middle distances.
//! * **Field of view.** `α` is the horizontal field of view *at the image's zoom* (the zoom-1
//!   field divided by the zoom); a field of view that is not in `(0, π)` or an unusable image
//!   geometry gives no estimate.

use super::hypotheses::Hypothesis;
use super::model::ObjectModel;
use avs_robot::{FeatureMatch, ImageGeometry};

/// The fewest usable matches from which [`distance_from_matches`] gives a distance (§3.3.2:
/// "with 4 matches or more a passable rough estimate").
pub const MIN_MATCHES_FOR_DISTANCE: usize = 4;

/// The median of the per-match distances (§3.3.2), metres (a depth: module docs); `None` with
/// fewer than [`MIN_MATCHES_FOR_DISTANCE`] usable matches, a field of view outside `(0, π)` or
/// an unusable image geometry.
pub fn distance_from_matches(
    model: &ObjectModel,
    matches: &[FeatureMatch],
    hfov_at_zoom: f64,
    image: &ImageGeometry,
) -> Option<f64> {
    if image.problem().is_some() || !(hfov_at_zoom > 0.0 && hfov_at_zoom < std::f64::consts::PI) {
        return None;
    }
    let mut d: Vec<f64> = matches
        .iter()
        .filter(|m| m.scale_ratio.is_finite() && m.scale_ratio > 0.0)
        .map(|m| model.distance_from_scale(m.scale_ratio, hfov_at_zoom, image))
        .filter(|d| d.is_finite() && *d > 0.0)
        .collect();
    if d.len() < MIN_MATCHES_FOR_DISTANCE {
        return None;
    }
    d.sort_by(f64::total_cmp);
    let n = d.len();
    Some(if n % 2 == 1 {
        d[n / 2]
    } else {
        (d[n / 2 - 1] + d[n / 2]) / 2.0
    })
}

/// The distance from a hypothesis's vote area (§3.3.1), metres (a depth): a thin wrapper over
/// [`ObjectModel::distance_from_vote_width`] with `D_vote` = [`Hypothesis::vote_width_px`]. Not
/// a finite positive number when the field of view or the image is unusable.
pub fn distance_from_votes(
    model: &ObjectModel,
    h: &Hypothesis,
    hfov_at_zoom: f64,
    image: &ImageGeometry,
) -> f64 {
    model.distance_from_vote_width(h.vote_width_px(image), hfov_at_zoom, image)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::zoom::model::DEFAULT_VOTE_THRESHOLD;

    fn book() -> ObjectModel {
        ObjectModel {
            class: "book".into(),
            width: 0.2,
            height: 0.25,
            vote_threshold: DEFAULT_VOTE_THRESHOLD,
        }
    }

    /// A match of a keypoint on the book seen `d` metres away.
    fn seen_at(d: f64, hfov: f64, g: &ImageGeometry) -> FeatureMatch {
        let m = book();
        let px = m.width * g.focal_px(hfov) / d;
        FeatureMatch {
            u: 100.0,
            v: 100.0,
            scale_ratio: px / m.train_px(g).0,
        }
    }

    #[test]
    fn the_median_of_the_matches_ignores_an_outlier() {
        let (g, hfov) = (ImageGeometry::default(), 45f64.to_radians());
        // Four good matches around 2 m and a background match that says 0.5 m.
        let matches = [
            seen_at(1.9, hfov, &g),
            seen_at(2.0, hfov, &g),
            seen_at(0.5, hfov, &g),
            seen_at(2.05, hfov, &g),
            seen_at(2.1, hfov, &g),
        ];
        let d = distance_from_matches(&book(), &matches, hfov, &g).unwrap();
        // (the mean would have been pulled to about 1.7 m);
        assert!((d - 2.0).abs() < 1e-9, "{d}");
        // an even count takes the mean of the middle two.
        let d = distance_from_matches(&book(), &matches[..4], hfov, &g).unwrap();
        assert!((d - 1.95).abs() < 1e-9, "{d}");
    }

    #[test]
    fn fewer_than_four_usable_matches_give_no_distance() {
        let (g, hfov) = (ImageGeometry::default(), 45f64.to_radians());
        let good = seen_at(2.0, hfov, &g);
        let bad = |scale_ratio| FeatureMatch {
            scale_ratio,
            ..good
        };
        assert!(distance_from_matches(&book(), &[good; 3], hfov, &g).is_none());
        assert!(distance_from_matches(&book(), &[good; 4], hfov, &g).is_some());
        // Three good and unusable ratios: still three.
        let m = [
            good,
            good,
            good,
            bad(0.0),
            bad(-1.0),
            bad(f64::NAN),
            bad(f64::INFINITY),
        ];
        assert!(distance_from_matches(&book(), &m, hfov, &g).is_none());
        // A NaN field of view or a zero-size image: none.
        assert!(distance_from_matches(&book(), &[good; 5], f64::NAN, &g).is_none());
        let empty = ImageGeometry { width_px: 0, ..g };
        assert!(distance_from_matches(&book(), &[good; 5], hfov, &empty).is_none());
    }

    #[test]
    fn the_vote_distance_uses_the_width_of_the_associated_cells() {
        let (g, hfov) = (ImageGeometry::default(), 45f64.to_radians());
        let h = Hypothesis {
            class: "book".into(),
            col: 5,
            row: 5,
            value: 0.9,
            min_col: 4,
            min_row: 3,
            max_col: 7,
            max_row: 8,
        };
        // Four cells wide: 60 px.
        let d = distance_from_votes(&book(), &h, hfov, &g);
        assert!((d - 0.2 * g.focal_px(hfov) / 60.0).abs() < 1e-12);
        // The same cells at twice the zoom: more than twice as far.
        let d2 = distance_from_votes(&book(), &h, hfov / 2.0, &g);
        assert!(d2 > 2.0 * d);
    }
}
