//! What the zoom pipeline knows of an object class (Sjöö et al. `004` §3.3–3.5): the size of
//! its front face, its training image, its attention threshold, and the pinhole geometry that
//! turns apparent sizes into distances and distances into zoom factors.
//!
//! ## Choices where the paper is vague
//! * **Front face.** The knowledge gives a bounding box `[length, width, height]`; the face a
//!   class's training image shows is `length × height` (a cereal box's front, a book's cover
//!   standing up). The paper's objects are measured the same way ("the size of the forward face
//!   of the objects varied, from the cup at 14 × 10 cm to the robot at 63 × 55 cm").
//! * **Training image.** The paper's `W_tr` is the object's width in pixels in its training
//!   image. Ours is the object filling the image as much as its aspect allows, so `W_tr / H_tr =
//!   W_real / H_real` and one of the two spans the image.
//! * **Zoom.** Zoom `z` divides both fields of view by `z` (as in view planning). Eq. 1 gives the
//!   angles `α, β` that make the object fill the image; the magnification is `hfov / α` when
//!   `W_im / W_tr < H_im / H_tr` and `vfov / β` otherwise (the paper's aspect rule), clamped to
//!   the camera's `[1, max_zoom]`.

use avs_format::knowledge::ObjectClass;
use avs_robot::{Camera, ImageGeometry};

/// The attention threshold of a class when none is given: a vote cell is a hypothesis only
/// above it (§3.2, "an object-dependent threshold"). Vote values are similarities in `[0, 1]`.
pub const DEFAULT_VOTE_THRESHOLD: f64 = 0.35;

/// The share of a model's features that must match for the object to count as recognised
/// (§3.5: "at least a 5 % of the SIFT features").
pub const RECOGNITION_SHARE: f64 = 0.05;

/// What the pipeline knows of one class.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ObjectModel {
    /// The class name.
    pub class: String,
    /// Width of the front face, metres (`W_real`).
    pub width: f64,
    /// Height of the front face, metres (`H_real`).
    pub height: f64,
    /// The attention threshold (§3.2).
    pub vote_threshold: f64,
}

impl ObjectModel {
    /// The model of a knowledge class: front face `size[0] × size[2]` (module docs), the
    /// default vote threshold.
    pub fn from_class(class: &ObjectClass) -> Self {
        Self {
            class: class.name.clone(),
            width: class.size[0],
            height: class.size[2],
            vote_threshold: DEFAULT_VOTE_THRESHOLD,
        }
    }

    /// The object's size in its training image, pixels `(W_tr, H_tr)`: as large as the image
    /// allows with the object's aspect (module docs).
    pub fn train_px(&self, image: &ImageGeometry) -> (f64, f64) {
        let (w_im, h_im) = (f64::from(image.width_px), f64::from(image.height_px));
        if self.width / self.height >= w_im / h_im {
            (w_im, w_im * self.height / self.width)
        } else {
            (h_im * self.width / self.height, h_im)
        }
    }

    /// Whether the width decides the magnification (the aspect rule of §3.4:
    /// `W_im / W_tr < H_im / H_tr`); otherwise the height does.
    pub fn width_limits(&self, image: &ImageGeometry) -> bool {
        let (w_tr, h_tr) = self.train_px(image);
        f64::from(image.width_px) / w_tr < f64::from(image.height_px) / h_tr
    }

    /// The magnification that makes the object at `distance` metres fill the image (eq. 1 and
    /// the aspect rule), not clamped to the camera's range. Fields of view at zoom 1.
    pub fn fill_zoom(&self, distance: f64, camera: &Camera, image: &ImageGeometry) -> f64 {
        if self.width_limits(image) {
            let alpha = 2.0 * (self.width / (2.0 * distance)).atan();
            camera.hfov / alpha
        } else {
            let beta = 2.0 * (self.height / (2.0 * distance)).atan();
            camera.vfov / beta
        }
    }

    /// [`ObjectModel::fill_zoom`] kept within the camera's `[1, max_zoom]`.
    pub fn zoom_for(&self, distance: f64, camera: &Camera, image: &ImageGeometry) -> f64 {
        self.fill_zoom(distance, camera, image)
            .clamp(1.0, camera.max_zoom.max(1.0))
    }

    /// The distance at which the object fills the image at zoom `zoom` (the inverse of
    /// [`ObjectModel::fill_zoom`]): at zoom 1 the minimum recognition distance of §2.1.3, at the
    /// camera's largest zoom the maximum.
    pub fn fill_distance(&self, zoom: f64, camera: &Camera, image: &ImageGeometry) -> f64 {
        if self.width_limits(image) {
            self.width / (2.0 * (camera.hfov / zoom / 2.0).tan())
        } else {
            self.height / (2.0 * (camera.vfov / zoom / 2.0).tan())
        }
    }

    /// The distance at which the object's image covers one vote cell at zoom 1: the maximum
    /// detection distance of the planning step (§3.2, "the distance at which an object would
    /// occupy a single cell at no zoom"). *Occupy* read as area: the face's `√(W·H)` spans
    /// the cell's side (a long thin object is not seen as far as a square one of its length).
    pub fn single_cell_distance(&self, camera: &Camera, image: &ImageGeometry) -> f64 {
        let f = image.focal_px(camera.hfov);
        (self.width * self.height).sqrt() * f / f64::from(image.cell_px)
    }

    /// The distance from a hypothesis's vote area (§3.3.1): `D = W_real W_im / (2 tan(α/2)
    /// D_vote)` with `D_vote` the width in pixels of the bounding box of its cells and `α` the
    /// horizontal field of view at the image's zoom.
    pub fn distance_from_vote_width(
        &self,
        vote_width_px: f64,
        hfov_at_zoom: f64,
        image: &ImageGeometry,
    ) -> f64 {
        self.width * image.focal_px(hfov_at_zoom) / vote_width_px
    }

    /// The distance from one matched feature's scale ratio `S_real / S_tr` (§3.3.2):
    /// `D = W_real W_im S_tr / (2 tan(α/2) W_tr S_real)`.
    pub fn distance_from_scale(
        &self,
        scale_ratio: f64,
        hfov_at_zoom: f64,
        image: &ImageGeometry,
    ) -> f64 {
        let (w_tr, _) = self.train_px(image);
        self.width * image.focal_px(hfov_at_zoom) / (w_tr * scale_ratio)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            hfov: 47.5f64.to_radians(),
            vfov: 36.4f64.to_radians(),
            pan_limits: [-1.5, 1.5],
            tilt_limits: [-0.5, 0.5],
            max_zoom: 13.0,
            height: 1.0,
        }
    }

    fn cup() -> ObjectModel {
        ObjectModel {
            class: "cup".into(),
            width: 0.14,
            height: 0.10,
            vote_threshold: DEFAULT_VOTE_THRESHOLD,
        }
    }

    #[test]
    fn a_wide_object_fills_the_images_width_in_training_and_the_width_limits_the_zoom() {
        let g = ImageGeometry::default();
        let (w, h) = cup().train_px(&g);
        assert_eq!(w, 320.0);
        assert!((h - 320.0 * 0.10 / 0.14).abs() < 1e-9);
        assert!(cup().width_limits(&g));
        let tall = ObjectModel {
            width: 0.1,
            height: 0.3,
            ..cup()
        };
        assert!(!tall.width_limits(&g));
        assert_eq!(tall.train_px(&g).1, 240.0);
    }

    #[test]
    fn fill_zoom_and_fill_distance_are_inverse_and_zoom_grows_with_distance() {
        let (c, g) = (camera(), ImageGeometry::default());
        for m in [
            cup(),
            ObjectModel {
                width: 0.1,
                height: 0.3,
                ..cup()
            },
        ] {
            let d1 = m.fill_distance(1.0, &c, &g);
            assert!((m.fill_zoom(d1, &c, &g) - 1.0).abs() < 1e-9);
            let d5 = m.fill_distance(5.0, &c, &g);
            assert!((m.fill_zoom(d5, &c, &g) - 5.0).abs() < 1e-6);
            assert!(d5 > 4.5 * d1);
            assert_eq!(m.zoom_for(100.0, &c, &g), 13.0);
            assert_eq!(m.zoom_for(0.01, &c, &g), 1.0);
        }
    }

    #[test]
    fn distances_from_apparent_size_invert_the_projection() {
        let (c, g) = (camera(), ImageGeometry::default());
        let m = cup();
        let d = 2.0;
        // The cup 2 m away spans this many pixels at zoom 1 …
        let px = m.width * g.focal_px(c.hfov) / d;
        assert!((m.distance_from_vote_width(px, c.hfov, &g) - d).abs() < 1e-9);
        // … and its keypoints appear at this fraction of their training scale.
        let ratio = px / m.train_px(&g).0;
        assert!((m.distance_from_scale(ratio, c.hfov, &g) - d).abs() < 1e-9);
        // At zoom 3 the same cup looks three times larger.
        let zoomed = c.hfov / 3.0;
        let px3 = m.width * g.focal_px(zoomed) / d;
        assert!(px3 > 2.9 * px);
        assert!((m.distance_from_vote_width(px3, zoomed, &g) - d).abs() < 1e-9);
    }

    #[test]
    fn a_cup_spans_one_vote_cell_a_few_metres_away() {
        let (c, g) = (camera(), ImageGeometry::default());
        let d = cup().single_cell_distance(&c, &g);
        // √(14 × 10) cm over 15 px with a 364 px focal length: 2.9 m.
        assert!((d - (0.14f64 * 0.10).sqrt() * g.focal_px(c.hfov) / 15.0).abs() < 1e-12);
        assert!((2.5..3.0).contains(&d), "{d}");
    }
}
