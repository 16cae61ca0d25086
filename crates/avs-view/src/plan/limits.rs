//! The distance limits of a class for view planning (Sjöö et al. `004` §2.1.3, §3.2, eq. 1).
//!
//! "For recognition, the minimum distance is simply defined as the range at which the object
//! would fill an entire image with a default zoom. The maximum distance is defined as the range
//! at which the object would occupy an entire image if maximum zoom was used." For detection the
//! maximum is "the distance at which an object would occupy a single cell at no zoom" (§3.2);
//! the minimum is "given by the parameters of the detection algorithm".
//!
//! **Our choice for the detection minimum:** the attention votes with the class's whole
//! appearance, so the object must fit in the image: the recognition minimum (the object fills
//! the image at zoom 1). Views are planned for *detection* (the zoom pipeline recognises on the
//! hypotheses it finds, §3).

use crate::zoom::ObjectModel;
use crate::DetectionRange;
use avs_robot::{Camera, ImageGeometry};
use serde::Serialize;

/// An object class sought by the view planner.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SoughtClass {
    /// The class name.
    pub class: String,
    /// The horizontal distances from the standpoint at which a view may detect it, metres.
    pub range: DetectionRange,
    /// The heights its centre may be at, `[lowest, highest]`, metres.
    pub heights: [f64; 2],
    /// Whether there is only one: once found, its pairs leave the plan ([`crate::plan::drop_class`]).
    pub unique: bool,
    /// Measured ranges at given zoom levels, `(zoom, range)`: a view at one of these zooms uses
    /// its range instead of `range` × zoom (empty: `range` × zoom at every level).
    pub zoom_ranges: Vec<(f64, DetectionRange)>,
}

impl SoughtClass {
    /// A class's detection limits from its front face, the image and the camera (module docs):
    /// `[fill distance at zoom 1, distance at which it covers one vote cell]`. At zoom `z` a
    /// view multiplies both by `z` (the same image detail at `z` times the distance).
    pub fn from_model(
        model: &ObjectModel,
        camera: &Camera,
        image: &ImageGeometry,
        heights: [f64; 2],
    ) -> Self {
        Self {
            class: model.class.clone(),
            range: DetectionRange {
                min: model.fill_distance(1.0, camera, image),
                max: model.single_cell_distance(camera, image),
            },
            heights,
            unique: true,
            zoom_ranges: Vec::new(),
        }
    }

    /// The range of a view at `zoom`: the measured one at that zoom when there is one,
    /// `range` × zoom otherwise (the same image detail at `zoom` times the distance).
    pub fn range_at(&self, zoom: f64) -> DetectionRange {
        self.zoom_ranges
            .iter()
            .find(|(z, _)| (z - zoom).abs() < 1e-9)
            .map_or(
                DetectionRange {
                    min: self.range.min * zoom,
                    max: self.range.max * zoom,
                },
                |(_, r)| *r,
            )
    }

    /// The recognition limits of §2.1.3: the object fills the image at zoom 1 and at the
    /// camera's largest zoom.
    pub fn recognition_range(
        model: &ObjectModel,
        camera: &Camera,
        image: &ImageGeometry,
    ) -> DetectionRange {
        DetectionRange {
            min: model.fill_distance(1.0, camera, image),
            max: model.fill_distance(camera.max_zoom.max(1.0), camera, image),
        }
    }

    /// Why this class cannot be planned for, if it cannot: a range that is not `0 ≤ min < max <
    /// ∞`, or heights that are not a finite `[low, high]`.
    pub fn problem(&self) -> Option<String> {
        let r = self.range;
        if !(r.min >= 0.0 && r.max > r.min && r.max.is_finite()) {
            return Some(format!(
                "class `{}`: range [{}, {}] is not 0 ≤ min < max < ∞",
                self.class, r.min, r.max
            ));
        }
        let [lo, hi] = self.heights;
        if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
            return Some(format!(
                "class `{}`: heights [{lo}, {hi}] are not a finite [low, high]",
                self.class
            ));
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_big_object_is_detected_farther_and_not_as_near_as_a_small_one() {
        let camera = Camera {
            hfov: 47.5f64.to_radians(),
            vfov: 36.2f64.to_radians(),
            max_zoom: 13.0,
            height: 1.0,
            ..Camera::default()
        };
        let image = ImageGeometry::default();
        let model = |w: f64, h: f64| ObjectModel {
            class: "x".into(),
            width: w,
            height: h,
            vote_threshold: 0.35,
        };
        let cup = SoughtClass::from_model(&model(0.14, 0.10), &camera, &image, [0.7, 0.8]);
        let robot = SoughtClass::from_model(&model(0.63, 0.55), &camera, &image, [0.3, 0.3]);
        assert!(robot.range.max > 4.0 * cup.range.max);
        assert!(robot.range.min > 4.0 * cup.range.min);
        assert!(cup.problem().is_none());
        // The cup fills the image well inside its detection range; zoomed fully, far beyond it.
        let rec = SoughtClass::recognition_range(&model(0.14, 0.10), &camera, &image);
        assert!((rec.min - cup.range.min).abs() < 1e-12);
        // tan is not linear: a little more than 13 × the zoom-1 distance.
        assert!((13.0..14.0).contains(&(rec.max / rec.min)), "{rec:?}");
        let bad = SoughtClass {
            heights: [1.0, 0.5],
            ..cup
        };
        assert!(bad.problem().unwrap().contains("heights"));
    }
}
