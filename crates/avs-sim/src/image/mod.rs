//! The simulated camera image of Sjöö et al. `004` §3: what the robot's attention (RFCH vote
//! matrices, §3.2) and its recogniser (SIFT matches with scale ratios, §3.3.2 and §3.5) report
//! on one image of a scene, for the zoom pipeline (`avs_view::zoom`) to work on.
//!
//! * [`ImageScene`] — what is in front of the camera: objects (front faces in the world) and
//!   a background (how cluttered, how far). Usable on its own (the calibration bench of
//!   `avs-eval` puts one object in front of a wall) or built from a [`crate::World`] by
//!   [`world_scene`] (what [`crate::sim_robot::SimAgentRobot`]'s `attention` and `recognise`
//!   look at);
//! * [`attention`] — one [`VoteMatrix`] per class asked for;
//! * [`recognition`] — the class's model features matched in the image;
//! * [`ImageModel`] — every parameter of both, documented and with the defaults the
//!   calibration bench (`avs zoom-bench`, `docs/benchmarks/zoom/`) was tuned with.
//!
//! Every projection goes through [`Camera::project`], the one pinhole model of an image; the
//! zoom divides the fields of view.
//!
//! # Model
//!
//! **Objects.** A [`SceneObject`] is the front face of an object: a `width × height` rectangle
//! centred on `centre`, vertical, facing along `yaw` (its normal points that way). Its image is
//! the bounding box of its four projected corners ([`FaceImage`]); an object with a corner
//! behind the camera is not in the image. Its *apparent size* is what the face would span
//! straight on at its depth, `f·W / depth` × `f·H / depth` pixels, and its *view angle* the
//! planar angle between the face's normal and the direction to the camera.
//!
//! **Attention** ([`attention`]). The value of a vote cell is the similarity of the cell's
//! histogram to the class's training histograms. A cell sees a mix of the background and of
//! whatever objects cover part of it, so the objects are painted over the background from the
//! farthest to the nearest:
//! `v ← φ^γ·q + (1 − φ^γ)·v`, with `φ` the share of the cell the object's box covers,
//! `γ` = [`ImageModel::cover_exponent`] (< 1: co-occurrences of the object's colours stand out
//! of a plain background, so a cell half covered counts for more than half), and `q` the
//! object's similarity in that cell:
//! `q = s(class, object) · g(n) · a(θ) · t(cell)`, where
//! * `s` is the class similarity ([`ImageModel::class_similarity`]): 1 for the object's own
//!   class, [`ImageModel::lookalike_similarity`] for a look-alike (`role: distractor`) of
//!   another class, and otherwise a fixed similarity of the two class names in
//!   [`ImageModel::other_class_similarity`] (a stable hash of the pair: two classes' colours
//!   resemble each other or not, the same way in every image);
//! * `g = 1 / (1 + (n₀ / n)^κ)` with `n` the apparent size in pixels (geometric mean of width
//!   and height), `n₀` = [`ImageModel::small_object_px`], `κ` =
//!   [`ImageModel::small_object_steepness`]: a co-occurrence histogram needs pixels, and a small
//!   object's colours blur into the background's (the signal-to-noise ratio drops with
//!   distance, §4.2);
//! * `a = 1 − k·(1 − |cos θ|)`, `k` = [`ImageModel::attention_angle_loss`]: colours survive a
//!   turn better than keypoints do;
//! * `t = 1 − τ·e − ε·p`: a cell off the face's centre (`e` ∈ `[0, 1]`, the squared offset from
//!   the centre relative to the half box) has receptive fields that reach past the object's
//!   edge, and each cell sees its own patch of the object (`p` ∈ `[0, 1]`, a smooth random
//!   field over the object's cells, [`ImageModel::patch_noise`] = `ε`); `τ` grows with the
//!   number of cells the object spans, up to [`ImageModel::patch_variation`], so a large
//!   object's votes form one broad hill rather than a plateau.
//!
//! The background's similarity is a smooth random field: a floor
//! ([`ImageModel::clutter_floor`]) plus Gaussian blobs (background structures: shelves,
//! posters, a window, the floor's edge), each `a_k · exp(−d² / 2ρ_k²)`. Their number is Poisson
//! with mean `B(clutter) · depth`, `B` interpolated between [`ImageModel::clutter_blobs`]`[0]`
//! (a plain wall, `clutter` 0) and `[1]` (an office scene, `clutter` 1) per metre of the
//! background's depth (a far scene puts more of the room into the image); their radii are
//! world sizes in [`ImageModel::clutter_size`] seen at the background's depth
//! (`ρ = f·R / depth`), so a far scene shows more, smaller structures per cell; their peak
//! similarity is `A · u_k · w_k,class` with `u_k, w_k,class` uniform in `[0, 1]` and
//! `A = A(clutter) · depth / (depth + D½)` (`A` interpolated in
//! [`ImageModel::clutter_amplitude`], `D½` = [`ImageModel::clutter_depth_half`]): the farther
//! the scene, the more background falls into one cell and the more it resembles something.
//! Blobs add up where they overlap. White noise of standard deviation
//! [`ImageModel::vote_noise`] is added to every cell, and values are clamped to `[0, 1]`.
//!
//! **Recognition** ([`recognition`]). The class's model has
//! [`ImageModel::model_features`] features. Each object of the class matches
//! `Binomial(N, p)` of them, `p = p_max · d(n) · α(θ) · visible`, with
//! * `p_max` = [`ImageModel::match_rate`] (matches are "much lower than the number extracted
//!   from the training image", §3.5);
//! * `d(n) = 1 / (1 + (n½ / n)^k)`, the detail left at apparent size `n` pixels,
//!   `n½` = [`ImageModel::detail_px`], `k` = [`ImageModel::detail_steepness`]: a keypoint needs
//!   a few pixels of scale, so the model's fine keypoints disappear first and the count
//!   "rapidly deteriorates" once the object spans a few dozen pixels (§4.2);
//! * `α(θ) = clamp((cos θ − cos θ_max) / (1 − cos θ_max), 0, 1)`, `θ_max` =
//!   [`ImageModel::max_view_angle`] (SIFT is invariant "up to a certain level", §3.5; the back
//!   of a face matches nothing);
//! * `visible`, the share of the face's box inside the image.
//!
//! A true match lies uniformly inside the visible part of the face's box; its scale ratio is
//! the apparent scale `r = (f / depth) / (W_tr / W)` — the object's pixels per metre in this
//! image over those of its training image (`W` the class's width, `W_tr` the object's width
//! in its training image, [`ClassAppearance::train_px`]) — times a log-normal error of standard deviation
//! `σ₀ + σ₁·(n½ / n)²` ([`ImageModel::scale_noise`], [`ImageModel::small_scale_noise`]): the
//! scale of a keypoint a few pixels across is poorly resolved. Mismatches come from the
//! background: their number is Poisson with mean interpolated in
//! [`ImageModel::mismatches`] by the clutter, they lie uniformly in the image, and their scale
//! ratios put the object at a random distance: with probability
//! [`ImageModel::close_mismatch_share`] in [`ImageModel::close_mismatch_distance`] (large
//! background structures mistaken for a close-up object: the paper's "outliers, erroneously
//! assigned values of 0.5–1 m", §4.2), otherwise in [`ImageModel::far_mismatch_distance`],
//! log-uniform (the distance at zoom 1: a mismatch's scale ratio is a property of the image).
//!
//! **Processing time.** An image costs [`ImageModel::capture_seconds`], the attention
//! [`ImageModel::attention_seconds_per_class`] per class, a recognition
//! [`ImageModel::recognition_seconds`] (SIFT extraction and matching: the paper's most
//! expensive step, "a couple of seconds" a cycle, §4.5).
//!
//! # Choices where the paper is vague
//!
//! * **Similarity as a mix.** RFCH matches a cell's histogram against the training one; a cell
//!   that is part object and part background gets a mix of both similarities, weighted by
//!   area. The paper gives no formula; the mix makes a small object's votes fall with the
//!   share of the cell it fills, which is what limits detection at range (§3.2: the maximum
//!   detection distance is where the object "would occupy a single cell").
//! * **Detail in pixels, not relative to training.** A model keypoint's scale is a fraction of
//!   the object's size, so whether it survives depends on how many pixels the object spans,
//!   not on how large its training image was. Recognition falls with the apparent size `n`.
//! * **Clutter is drawn per image** (a seed per image): it is not anchored in the world, so two
//!   images of the same place differ in clutter as in white noise; look-alikes
//!   (`role: distractor`) are anchored, being objects.
//! * **Classes are independent.** The background's structures (where, how large) are the
//!   image's; how much each resembles a class, and the noise, are drawn from a generator of
//!   the image's seed and the class name, so a class's vote matrix does not depend on which
//!   other classes were asked for.
//!
//! ```
//! use avs_robot::{Camera, ImageGeometry, Point3, Pose2D, ViewCone};
//! use avs_sim::image::{attention, Background, ImageModel, ImageScene, SceneObject};
//! use rand::SeedableRng;
//! let camera = Camera::default();
//! let image = ImageGeometry::default();
//! // A book 1 m ahead of the camera, facing it, in front of a plain wall.
//! let book = SceneObject {
//!     class: "book".into(),
//!     centre: Point3 { x: 1.0, y: 0.0, z: camera.height },
//!     width: 0.16,
//!     height: 0.23,
//!     yaw: std::f64::consts::PI,
//!     lookalike: false,
//! };
//! let scene = ImageScene { objects: vec![book], background: Background { clutter: 0.0, depth: 1.5 } };
//! let cone = ViewCone::new(Pose2D::new(0.0, 0.0, 0.0), 0.0, 0.0, 1.0);
//! let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
//! let votes = attention(&ImageModel::default(), &scene, &camera, &cone, &image, &["book".into()], &mut rng);
//! // The cell at the image centre sees the book.
//! let (col, row) = (image.cols() / 2, image.rows() / 2);
//! assert!(votes[0].get(col, row).unwrap() > 0.5);
//! ```

mod attention;
mod recognition;
mod scene;

pub use attention::attention;
pub use recognition::{recognition, Recognition};
pub use scene::{background_depth, world_scene, BoxObject};

use avs_robot::{Camera, ImageGeometry, Point3, ViewCone};
use serde::{Deserialize, Serialize};

/// The front face of an object in front of the camera.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SceneObject {
    /// The object's class.
    pub class: String,
    /// The centre of its front face, world frame, metres.
    pub centre: Point3,
    /// Width of the face, metres.
    pub width: f64,
    /// Height of the face, metres.
    pub height: f64,
    /// The direction the face looks, radians in the world frame.
    pub yaw: f64,
    /// Whether the object is a look-alike of other classes (an environment object with
    /// `role: distractor`): the attention of every other class sees it as
    /// [`ImageModel::lookalike_similarity`].
    pub lookalike: bool,
}

/// What lies behind the objects.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Background {
    /// How much structure the background shows: 0 a plain wall, 1 a typical office scene.
    pub clutter: f64,
    /// Distance from the camera to the background along the optical axis, metres.
    pub depth: f64,
}

/// Everything in front of the camera for one image.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ImageScene {
    /// The objects (front faces), in any order.
    pub objects: Vec<SceneObject>,
    /// The background.
    pub background: Background,
}

/// What the recogniser knows of a class: the size of the face its training image shows.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ClassAppearance {
    /// The class name.
    pub name: String,
    /// Width of the trained face, metres (`W_real`).
    pub width: f64,
    /// Height of the trained face, metres.
    pub height: f64,
}

impl ClassAppearance {
    /// The object's size in its training image, pixels `(W_tr, H_tr)`: as large as `image`
    /// allows with the face's aspect (the convention of `avs_view::zoom::ObjectModel::train_px`,
    /// which `avs-eval`'s calibration tests check this agrees with).
    pub fn train_px(&self, image: &ImageGeometry) -> (f64, f64) {
        let (w_im, h_im) = (f64::from(image.width_px), f64::from(image.height_px));
        if self.width / self.height >= w_im / h_im {
            (w_im, w_im * self.height / self.width)
        } else {
            (h_im * self.width / self.height, h_im)
        }
    }
}

/// The parameters of the simulated image (see the [module documentation](self) for where each
/// enters). The defaults are those the calibration bench was tuned with (`avs zoom-bench`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ImageModel {
    /// Similarity range `[min, max]` of an object of an unrelated class (by a stable hash of
    /// the two class names).
    pub other_class_similarity: [f64; 2],
    /// Similarity of a look-alike to the classes it resembles.
    pub lookalike_similarity: f64,
    /// `n₀`: the apparent size, pixels, at which an object's signal is half its full value.
    pub small_object_px: f64,
    /// `κ`: how steeply the signal falls below `n₀` (`g = 1 / (1 + (n₀ / n)^κ)`).
    pub small_object_steepness: f64,
    /// `k` in the attention's angle factor `1 − k·(1 − |cos θ|)`, in `[0, 1]`.
    pub attention_angle_loss: f64,
    /// `γ`: a cell that an object covers by a share `φ` weighs the object by `φ^γ` (≤ 1: a
    /// histogram's co-occurrences favour the object's colours over a plain background).
    pub cover_exponent: f64,
    /// `ε`: how much less a cell may match for seeing its own patch of the object (a smooth
    /// random field over the object's cells).
    pub patch_noise: f64,
    /// `τ` at most: how much less a cell that sees only a patch of a large object may match.
    pub patch_variation: f64,
    /// Similarity of any background to any class, before the blobs.
    pub clutter_floor: f64,
    /// Expected number of background blobs per metre of background depth, for a plain wall and
    /// for an office scene.
    pub clutter_blobs: [f64; 2],
    /// Peak blob similarity `A` of a far plain wall and a far office scene.
    pub clutter_amplitude: [f64; 2],
    /// `D½`: background depth, metres, at which the blobs reach half their far amplitude.
    pub clutter_depth_half: f64,
    /// World radius range `[min, max]` of a background structure, metres (log-uniform).
    pub clutter_size: [f64; 2],
    /// Standard deviation of the white noise on every vote cell.
    pub vote_noise: f64,
    /// `N`: features in every class's model (its training image's keypoints).
    pub model_features: u32,
    /// `p_max`: share of the model matched on a large, frontal, whole object.
    pub match_rate: f64,
    /// `n½`: apparent size, pixels, at which half the matchable features are left.
    pub detail_px: f64,
    /// `k`: how steeply the features disappear below `n½`.
    pub detail_steepness: f64,
    /// `θ_max`: view angle off the face's normal beyond which nothing matches, radians.
    pub max_view_angle: f64,
    /// `σ₀`: log-normal standard deviation of a true match's scale ratio.
    pub scale_noise: f64,
    /// `σ₁`: extra log-normal standard deviation at apparent size `n½` (grows as `(n½/n)²`).
    pub small_scale_noise: f64,
    /// Expected background mismatches for a plain wall and for an office scene.
    pub mismatches: [f64; 2],
    /// Share of the mismatches that look like a close-up object.
    pub close_mismatch_share: f64,
    /// Distance range, metres, a close-up mismatch implies (at zoom 1).
    pub close_mismatch_distance: [f64; 2],
    /// Distance range, metres, any other mismatch implies (at zoom 1, log-uniform).
    pub far_mismatch_distance: [f64; 2],
    /// Seconds to take an image.
    pub capture_seconds: f64,
    /// Seconds of attention per class on one image.
    pub attention_seconds_per_class: f64,
    /// Seconds of one recognition (feature extraction and matching).
    pub recognition_seconds: f64,
}

impl Default for ImageModel {
    /// The parameters the calibration bench was tuned with (`avs zoom-bench`; the figures are
    /// in `docs/benchmarks/zoom/`).
    fn default() -> Self {
        Self {
            other_class_similarity: [0.1, 0.4],
            lookalike_similarity: 0.8,
            small_object_px: 22.0,
            small_object_steepness: 1.0,
            attention_angle_loss: 0.3,
            cover_exponent: 0.7,
            patch_variation: 0.4,
            patch_noise: 0.05,
            clutter_floor: 0.05,
            clutter_blobs: [0.8, 1.6],
            clutter_amplitude: [2.1, 2.3],
            clutter_depth_half: 1.5,
            clutter_size: [0.03, 0.2],
            vote_noise: 0.02,
            model_features: 200,
            match_rate: 0.25,
            detail_px: 42.0,
            detail_steepness: 6.0,
            max_view_angle: 70f64.to_radians(),
            scale_noise: 0.04,
            small_scale_noise: 0.25,
            mismatches: [0.5, 3.0],
            close_mismatch_share: 0.5,
            close_mismatch_distance: [0.5, 1.0],
            far_mismatch_distance: [0.3, 5.0],
            capture_seconds: 0.2,
            attention_seconds_per_class: 0.4,
            recognition_seconds: 1.5,
        }
    }
}

impl ImageModel {
    /// The attention's similarity of an object of class `object` (a look-alike when
    /// `lookalike`) to class `class`: 1 for the same class, [`ImageModel::lookalike_similarity`]
    /// for a look-alike, else a value in [`ImageModel::other_class_similarity`] fixed by the
    /// two names (symmetric).
    pub fn class_similarity(&self, class: &str, object: &str, lookalike: bool) -> f64 {
        if class == object {
            return 1.0;
        }
        if lookalike {
            return self.lookalike_similarity;
        }
        let (a, b) = if class < object {
            (class, object)
        } else {
            (object, class)
        };
        let h = mix(name_hash(a) ^ mix(name_hash(b)));
        let u = (h >> 11) as f64 / (1u64 << 53) as f64;
        let [lo, hi] = self.other_class_similarity;
        lo + (hi - lo) * u
    }

    /// Simulated seconds of one attention image with `classes` classes.
    pub fn attention_seconds(&self, classes: usize) -> f64 {
        self.capture_seconds + self.attention_seconds_per_class * classes as f64
    }

    /// Simulated seconds of one recognition image.
    pub fn recognition_time(&self) -> f64 {
        self.capture_seconds + self.recognition_seconds
    }

    /// Interpolate a `[plain wall, office scene]` pair at `clutter` (clamped to `[0, 1]`).
    fn by_clutter(pair: [f64; 2], clutter: f64) -> f64 {
        let c = if clutter.is_finite() {
            clutter.clamp(0.0, 1.0)
        } else {
            0.0
        };
        pair[0] + (pair[1] - pair[0]) * c
    }

    /// The share `p_max · d(n) · α(θ)` of a class's model features one object matches when its
    /// whole face is in the image (see the [module documentation](self)): `n` its apparent
    /// size, pixels, `view_angle` the angle `θ` between its face's normal and the direction to
    /// the camera, radians.
    pub fn match_share(&self, n: f64, view_angle: f64) -> f64 {
        let detail = 1.0 / (1.0 + (self.detail_px / n.max(1e-9)).powf(self.detail_steepness));
        let cos_max = self.max_view_angle.cos();
        let angle = ((view_angle.cos() - cos_max) / (1.0 - cos_max)).clamp(0.0, 1.0);
        (self.match_rate * detail * angle).clamp(0.0, 1.0)
    }
}

/// Where a [`SceneObject`] appears in an image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceImage {
    /// Bounding box of the projected face `[u0, v0, u1, v1]`, pixels (may reach outside the
    /// image).
    pub bbox: [f64; 4],
    /// Depth of the face's centre along the optical axis, metres.
    pub depth: f64,
    /// Apparent width and height straight on at that depth, pixels.
    pub apparent_px: (f64, f64),
    /// Planar angle between the face's normal and the direction to the camera, radians in
    /// `[0, π]`.
    pub view_angle: f64,
}

impl FaceImage {
    /// The apparent size `n`: geometric mean of the apparent width and height, pixels.
    pub fn size_px(&self) -> f64 {
        (self.apparent_px.0 * self.apparent_px.1).sqrt()
    }

    /// The box cut to the image, `None` when nothing of it is inside.
    pub fn visible_box(&self, image: &ImageGeometry) -> Option<[f64; 4]> {
        let [u0, v0, u1, v1] = self.bbox;
        let b = [
            u0.max(0.0),
            v0.max(0.0),
            u1.min(f64::from(image.width_px)),
            v1.min(f64::from(image.height_px)),
        ];
        (b[2] > b[0] && b[3] > b[1]).then_some(b)
    }

    /// The share of the box's area inside the image.
    pub fn visible_share(&self, image: &ImageGeometry) -> f64 {
        let [u0, v0, u1, v1] = self.bbox;
        let area = (u1 - u0) * (v1 - v0);
        match self.visible_box(image) {
            Some(b) if area > 0.0 => ((b[2] - b[0]) * (b[3] - b[1]) / area).min(1.0),
            _ => 0.0,
        }
    }
}

/// Where `object` appears in an image taken through `cone`: `None` when a corner of its face
/// is behind the camera or its box lies wholly outside the image.
pub fn face_image(
    object: &SceneObject,
    camera: &Camera,
    cone: &ViewCone,
    image: &ImageGeometry,
) -> Option<FaceImage> {
    let (ax, ay) = (-object.yaw.sin(), object.yaw.cos());
    let (hw, hh) = (object.width / 2.0, object.height / 2.0);
    let c = object.centre;
    let mut bbox = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for (s, t) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)] {
        let corner = Point3 {
            x: c.x + s * hw * ax,
            y: c.y + s * hw * ay,
            z: c.z + t * hh,
        };
        let (u, v, _) = camera.project(cone, image, corner)?;
        bbox = [
            bbox[0].min(u),
            bbox[1].min(v),
            bbox[2].max(u),
            bbox[3].max(v),
        ];
    }
    let (_, _, depth) = camera.project(cone, image, c)?;
    let zoom = cone.zoom.max(1.0);
    let fx = image.focal_px(camera.hfov / zoom);
    let fy = f64::from(image.height_px) / (2.0 * (camera.vfov / zoom / 2.0).tan());
    let (tx, ty) = (cone.pose.x - c.x, cone.pose.y - c.y);
    let to_camera = ty.atan2(tx);
    let view_angle = avs_map::geometry::wrap_angle(to_camera - object.yaw).abs();
    let face = FaceImage {
        bbox,
        depth,
        apparent_px: (fx * object.width / depth, fy * object.height / depth),
        view_angle,
    };
    face.visible_box(image).map(|_| face)
}

/// The area of the overlap of the pixel box `b` with vote cell `(col, row)`, over the cell's
/// area.
pub fn cell_cover(b: [f64; 4], col: usize, row: usize, image: &ImageGeometry) -> f64 {
    let c = f64::from(image.cell_px);
    let (x0, y0) = (col as f64 * c, row as f64 * c);
    let w = (b[2].min(x0 + c) - b[0].max(x0)).max(0.0);
    let h = (b[3].min(y0 + c) - b[1].max(y0)).max(0.0);
    w * h / (c * c)
}

/// SplitMix64's finaliser: a bijective mix of 64 bits.
pub(crate) fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The 64-bit FNV-1a hash of a name (stable across runs and platforms).
pub(crate) fn name_hash(name: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in name.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

#[cfg(test)]
mod tests;
