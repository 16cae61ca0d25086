//! The three-step object search of one view (Sjöö et al. `004` §3.1, Fig. 3): an unzoomed
//! image, zoom windows shared between classes, and a final zoom per eq. 1 that ends in
//! recognition (§3.5).
//!
//! What the paper says (§3.1): "Starting with an image at 1× magnification, each object is
//! processed independently, whereupon the resulting zoom windows are merged and each gives rise
//! to a new, zoomed image and the procedure repeats for each of them."
//! * **Initial**: no magnification; after distance estimation and zooming, on to the middle
//!   step — or, the "short-cut", straight to the final step "if the current magnification is
//!   found to be essentially equal to the middle magnification (within 1.8×)".
//! * **Middle**: magnification from zoom window sharing (§3.4.2). "If new distance estimate
//!   indicates current magnification is too small (not within 1.8× of new desired middle
//!   magnification), repeats this step. If on the other hand it is within 1.2× of the desired
//!   final magnification, skips straight to recognition. Otherwise, moves to final step."
//! * **Final**: magnification by eq. 1; recognition.
//!
//! "In the first two steps, an RFCH vote cell grid is created and used to extract a set of
//! hypotheses. Then, distance is estimated using the strongest hypothesis. If the distance
//! found is small enough (here, such that it would require less than 3× the current
//! magnification), SIFT matching is performed for a more accurate distance measure. If this
//! estimate in turn says that the object is sufficiently magnified the algorithm jumps to
//! recognition; otherwise, the most reliable distance is used to produce a zoom window for the
//! next step." Recognition (§3.5) is an RFCH "sanity check" on the whole image, then SIFT
//! matching; the object is found when at least 5 % of the model's features match, and placed
//! from "the pan and tilt angles of the camera, the estimated position of the object inside
//! the image and the distance".
//!
//! ## Choices where the paper is vague
//! * **Images.** Every robot call is one image ([`avs_robot::Robot::attention`] and
//!   [`avs_robot::Robot::recognise`] each take one), recorded in
//!   [`ZoomOutcome::images`]; a search never asks for more than [`ZoomConfig::max_images`]
//!   (the call that would exceed it is not made, and [`ZoomOutcome::budget_exhausted`] says
//!   so). The middle step repeats at most [`MAX_MIDDLE_ROUNDS`] times in a row before going to
//!   the final step anyway.
//! * **Magnifications.** Eq. 1 gives the *final* zoom `Z_f = model.zoom_for(d)` (absolute,
//!   clamped to the camera's `[1, max_zoom]`). "Within `k`× of" is symmetric:
//!   `max(Z_f / z, z / Z_f) ≤ k` for the current zoom `z`. The desired middle magnification is
//!   [`MIDDLE_MIN`] × `Z_f` (the paper: "it is most important to get the minimum zoom right");
//!   the middle step repeats only when it is *too small*, i.e. `MIDDLE_MIN · Z_f / z >
//!   repeat_middle_factor`, and the same test sends the initial step straight to the final one
//!   when it fails. SIFT is tried when the unclamped eq.-1 zoom over the current one is below
//!   [`ZoomConfig::sift_zoom_factor`], and its distance replaces the vote distance when at least
//!   [`super::MIN_MATCHES_FOR_DISTANCE`] matches give one.
//! * **Windows.** A class's hypotheses are grouped at its lowest middle magnification
//!   `MIDDLE_MIN · Z_f / z` relative to the current image (the largest windows, the fewest),
//!   with the range `[MIDDLE_MIN, MIDDLE_MAX] · Z_f / z`, reduced, and shared across the image's
//!   classes; the windows are visited strongest hypothesis first. A window becomes a cone aimed
//!   by [`avs_robot::Camera::pan_tilt_towards`] at its centre, zoomed by `z` × its
//!   magnification, with pan, tilt and zoom kept inside the camera's limits; when the clamped
//!   camera would no longer see the window's centre the window is dropped and noted in
//!   [`ZoomOutcome::skipped`].
//! * **Final step.** One final image per class and middle image, for the class's strongest
//!   hypothesis there (others in the same window are not followed): zoom `Z_f`, aimed at the
//!   centre of the bounding box of the hypothesis's associated cells (where the cells say the
//!   object is; its peak cell may sit anywhere on a uniformly textured object).
//! * **Recognition.** The sanity check is an attention for the class alone on the final image,
//!   passed when its strongest vote is above the class's threshold; when recognition follows
//!   directly on an initial or middle image, that image's attention is the sanity check (it
//!   had a hypothesis) and a recognition already made there for the distance is reused. The
//!   object is recognised when the matches reach `recognition_share × model_features` (never
//!   with a model of no features). It is placed by [`avs_robot::Camera::unproject`] through the
//!   component-wise median pixel of the matches, at the SIFT distance of the recognition image
//!   (≥ 4 usable matches) or else the vote distance of its sanity check (or, failing that, the
//!   distance that chose the zoom). Both estimates are depths along the optical axis (similar
//!   triangles), so they are turned into the range along the pixel's ray first.
//! * **Uniqueness.** A recognised class is not looked for again in this search (the paper
//!   treats objects as unique: "objects should be discarded once they are found").
//! * **Failures.** A robot without attention or recogniser (`Unsupported`) is an error
//!   ([`ZoomError::Unsupported`]), so the caller falls back to
//!   [`avs_robot::Robot::process_view_cone`]; so is a failed or malformed initial image. Any
//!   other failure, or a malformed report, ends only the window or class it concerned, noted
//!   in [`ZoomOutcome::skipped`].
//! * **Geometry.** Every image is expected to have [`ZoomConfig::image`]'s geometry and
//!   vote matrices of its cells; a report that does not is malformed.

use super::distance::{distance_from_matches, distance_from_votes};
use super::error::ZoomError;
use super::hypotheses::{hypotheses, Hypothesis};
use super::model::{ObjectModel, RECOGNITION_SHARE};
use super::sharing::{share, MIDDLE_MAX, MIDDLE_MIN};
use super::windows::{group_into_windows, reduce, ZoomWindow, EPS};
use avs_robot::{
    ActionFailure, AttentionReport, Camera, FailureReason, ImageGeometry, Point3,
    RecognitionReport, Robot, ViewCone, VoteMatrix,
};
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// The most middle steps in a row before the final step is taken anyway.
pub const MAX_MIDDLE_ROUNDS: usize = 3;

/// Settings of the three-step search.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ZoomConfig {
    /// The geometry of the camera's images (size and vote cells).
    pub image: ImageGeometry,
    /// The most images one search may take (attention and recognition images alike).
    pub max_images: usize,
    /// SIFT gives the distance when the object needs less than this many times the current
    /// magnification (§3.1: 3).
    pub sift_zoom_factor: f64,
    /// The middle step repeats when the desired middle magnification is more than this many
    /// times the current one (§3.1: 1.8).
    pub repeat_middle_factor: f64,
    /// An image within this factor of the final magnification goes straight to recognition
    /// (§3.1: 1.2).
    pub skip_to_final_factor: f64,
    /// The share of a model's features that must match for recognition (§3.5: 5 %).
    pub recognition_share: f64,
}

impl Default for ZoomConfig {
    /// The paper's settings: 320 × 240 images with 15 px cells, factors 3, 1.8 and 1.2, 5 %
    /// of the features; at most 40 images.
    fn default() -> Self {
        Self {
            image: ImageGeometry::default(),
            max_images: 40,
            sift_zoom_factor: 3.0,
            repeat_middle_factor: 1.8,
            skip_to_final_factor: 1.2,
            recognition_share: RECOGNITION_SHARE,
        }
    }
}

impl ZoomConfig {
    /// Check every field: a usable image geometry, factors that are finite numbers (≥ 1 for
    /// the two "within" factors, > 0 for the SIFT factor) and a share in `(0, 1]`.
    pub fn check(&self) -> Result<(), ZoomError> {
        let bad = |field, message: String| Err(ZoomError::InvalidInput { field, message });
        if let Some(m) = self.image.problem() {
            return bad("image", m);
        }
        if !(self.sift_zoom_factor.is_finite() && self.sift_zoom_factor > 0.0) {
            return bad(
                "sift_zoom_factor",
                format!("{}: expected a positive number", self.sift_zoom_factor),
            );
        }
        for (field, v) in [
            ("repeat_middle_factor", self.repeat_middle_factor),
            ("skip_to_final_factor", self.skip_to_final_factor),
        ] {
            if !(v.is_finite() && v >= 1.0) {
                return bad(field, format!("{v}: expected a number ≥ 1"));
            }
        }
        if !(self.recognition_share > 0.0 && self.recognition_share <= 1.0) {
            return bad(
                "recognition_share",
                format!("{}: expected a number in (0, 1]", self.recognition_share),
            );
        }
        Ok(())
    }
}

/// The step of the search an image belongs to (§3.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Step {
    /// The unzoomed image of the view.
    Initial,
    /// A zoom window's image (magnification from window sharing).
    Middle,
    /// The eq.-1 image of one class's hypothesis, with its sanity check.
    Final,
}

/// What an image was taken for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ImageKind {
    /// Vote matrices ([`avs_robot::Robot::attention`]).
    Attention,
    /// Feature matching ([`avs_robot::Robot::recognise`]).
    Recognition,
}

/// One image the search took.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ZoomImage {
    /// The step it belongs to.
    pub step: Step,
    /// What it was taken for.
    pub kind: ImageKind,
    /// Where the camera looked.
    pub cone: ViewCone,
    /// The classes it was processed for.
    pub classes: Vec<String>,
    /// Its processing time, as the robot reported it, seconds.
    pub seconds: f64,
}

/// An object the search recognised.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Recognised {
    /// Its class.
    pub class: String,
    /// Where it is: the point at `distance` along the ray through its pixel.
    pub position: Point3,
    /// Its distance from the camera along that ray, metres.
    pub distance: f64,
    /// The features matched in the recognition image.
    pub matches: usize,
    /// The features of the class's model.
    pub model_features: u32,
    /// The cone of the recognition image.
    pub cone: ViewCone,
}

/// A window or class the search gave up on, and why.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Skipped {
    /// The step it was in.
    pub step: Step,
    /// The classes concerned.
    pub classes: Vec<String>,
    /// What happened.
    pub reason: String,
}

/// What one three-step search found and what it cost.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ZoomOutcome {
    /// The objects recognised, in the order recognised (at most one per class).
    pub found: Vec<Recognised>,
    /// Every image taken, in order.
    pub images: Vec<ZoomImage>,
    /// Distance the robot travelled for the images, metres.
    pub travelled: f64,
    /// Processing time of all images, seconds.
    pub seconds: f64,
    /// Windows and classes given up on (a failed image, a malformed report, a window the
    /// camera cannot turn to).
    pub skipped: Vec<Skipped>,
    /// Whether the search stopped because it reached [`ZoomConfig::max_images`].
    pub budget_exhausted: bool,
}

/// Run the three-step search of one view cone for `models`' classes (module docs): the
/// unzoomed image at `cone`, then middle and final images as the hypotheses ask, until every
/// class is recognised or its hypotheses are exhausted, or the image budget is spent.
///
/// Errors: bad input (configuration, camera, cone, models), a robot without attention or
/// recogniser ([`ZoomError::Unsupported`]), a failed or malformed initial image.
pub fn three_step_search<R: Robot + ?Sized>(
    robot: &mut R,
    cone: &ViewCone,
    models: &[ObjectModel],
    config: &ZoomConfig,
) -> Result<ZoomOutcome, ZoomError> {
    config.check()?;
    let camera = robot.camera();
    check_camera(&camera)?;
    cone.check(&camera).map_err(|f| ZoomError::InvalidInput {
        field: "cone",
        message: f.message,
    })?;
    let mut unique: Vec<ObjectModel> = Vec::new();
    for m in models {
        check_model(m)?;
        if !unique.iter().any(|u| u.class == m.class) {
            unique.push(m.clone());
        }
    }
    let classes: Vec<String> = unique.iter().map(|m| m.class.clone()).collect();
    let mut s = Search {
        robot,
        camera,
        config: *config,
        models: unique,
        out: ZoomOutcome::default(),
    };
    if classes.is_empty() {
        return Ok(s.out);
    }
    let report = match s.attend(Step::Initial, cone, &classes)? {
        Shot::Taken(r) => r,
        Shot::Budget => return Ok(s.out),
        Shot::Failed(f) => return Err(ZoomError::Robot(f)),
    };
    s.check_attention(&report, &classes)
        .map_err(ZoomError::BadReport)?;
    let mut queue: VecDeque<Task> = s.analyse(Step::Initial, cone, &report, &classes, 0)?.into();
    while let Some(task) = queue.pop_front() {
        if s.out.budget_exhausted {
            break;
        }
        let children = match task {
            Task::Middle {
                cone,
                classes,
                round,
            } => s.middle(&cone, classes, round)?,
            Task::Final {
                cone,
                class,
                distance,
            } => {
                s.finale(&cone, &class, distance)?;
                Vec::new()
            }
        };
        for t in children.into_iter().rev() {
            queue.push_front(t);
        }
    }
    Ok(s.out)
}

/// A camera the search can aim: fields of view in `(0, π)`, ordered finite limits, a finite
/// largest zoom ≥ 1.
fn check_camera(c: &Camera) -> Result<(), ZoomError> {
    let fov = |f: f64| f > 0.0 && f < std::f64::consts::PI;
    let limits = |l: [f64; 2]| l[0].is_finite() && l[1].is_finite() && l[0] <= l[1];
    if fov(c.hfov)
        && fov(c.vfov)
        && limits(c.pan_limits)
        && limits(c.tilt_limits)
        && c.max_zoom.is_finite()
        && c.max_zoom >= 1.0
        && c.height.is_finite()
    {
        Ok(())
    } else {
        Err(ZoomError::InvalidInput {
            field: "camera",
            message: format!(
                "{c:?}: expected fields of view in (0, π), ordered finite limits and a finite \
                 largest zoom ≥ 1"
            ),
        })
    }
}

/// A model the search can use: a named class with a finite positive face and a threshold.
fn check_model(m: &ObjectModel) -> Result<(), ZoomError> {
    if m.class.is_empty()
        || !(m.width.is_finite() && m.width > 0.0)
        || !(m.height.is_finite() && m.height > 0.0)
        || m.vote_threshold.is_nan()
    {
        return Err(ZoomError::InvalidInput {
            field: "models",
            message: format!(
                "class `{}` ({} × {} m, threshold {}): expected a name, a positive finite face \
                 and a threshold",
                m.class, m.width, m.height, m.vote_threshold
            ),
        });
    }
    Ok(())
}

/// Whether zooms `a` and `b` are within a factor `k` of each other.
fn within(a: f64, b: f64, k: f64) -> bool {
    a > 0.0 && b > 0.0 && (a / b).max(b / a) <= k + EPS
}

/// The median of some numbers (the mean of the middle two for an even count); `None` for none.
fn median(mut xs: Vec<f64>) -> Option<f64> {
    xs.retain(|x| x.is_finite());
    if xs.is_empty() {
        return None;
    }
    xs.sort_by(f64::total_cmp);
    let n = xs.len();
    Some(if n % 2 == 1 {
        xs[n / 2]
    } else {
        (xs[n / 2 - 1] + xs[n / 2]) / 2.0
    })
}

/// Work left to do.
enum Task {
    /// A zoom window's image for its classes.
    Middle {
        cone: ViewCone,
        classes: Vec<String>,
        round: usize,
    },
    /// A class's final image, with the distance that chose its zoom.
    Final {
        cone: ViewCone,
        class: String,
        distance: f64,
    },
}

/// What asking the robot for an image gave.
enum Shot<T> {
    Taken(T),
    Budget,
    Failed(ActionFailure),
}

/// One search in progress.
struct Search<'r, R: Robot + ?Sized> {
    robot: &'r mut R,
    camera: Camera,
    config: ZoomConfig,
    models: Vec<ObjectModel>,
    out: ZoomOutcome,
}

impl<R: Robot + ?Sized> Search<'_, R> {
    fn model(&self, class: &str) -> Option<ObjectModel> {
        self.models.iter().find(|m| m.class == class).cloned()
    }

    fn found(&self, class: &str) -> bool {
        self.out.found.iter().any(|r| r.class == class)
    }

    fn skip(&mut self, step: Step, classes: &[String], reason: String) {
        tracing::debug!(?step, ?classes, %reason, "zoom search skips");
        self.out.skipped.push(Skipped {
            step,
            classes: classes.to_vec(),
            reason,
        });
    }

    fn budget_left(&mut self) -> bool {
        if self.out.images.len() >= self.config.max_images {
            self.out.budget_exhausted = true;
            return false;
        }
        true
    }

    fn record(
        &mut self,
        step: Step,
        kind: ImageKind,
        cone: &ViewCone,
        classes: &[String],
        seconds: f64,
        travelled: f64,
    ) {
        let seconds = if seconds.is_finite() {
            seconds.max(0.0)
        } else {
            0.0
        };
        if travelled.is_finite() {
            self.out.travelled += travelled.max(0.0);
        }
        self.out.seconds += seconds;
        self.out.images.push(ZoomImage {
            step,
            kind,
            cone: *cone,
            classes: classes.to_vec(),
            seconds,
        });
    }

    /// An attention image, within the budget.
    fn attend(
        &mut self,
        step: Step,
        cone: &ViewCone,
        classes: &[String],
    ) -> Result<Shot<AttentionReport>, ZoomError> {
        if !self.budget_left() {
            return Ok(Shot::Budget);
        }
        match self.robot.attention(cone, classes) {
            Ok(r) => {
                self.record(
                    step,
                    ImageKind::Attention,
                    cone,
                    classes,
                    r.seconds,
                    r.travelled,
                );
                Ok(Shot::Taken(r))
            }
            Err(f) if f.reason == FailureReason::Unsupported => Err(ZoomError::Unsupported {
                capability: "attention",
                message: f.message,
            }),
            Err(f) => Ok(Shot::Failed(f)),
        }
    }

    /// A recognition image, within the budget; a report for another class or geometry is a
    /// failure.
    fn recognise(
        &mut self,
        step: Step,
        cone: &ViewCone,
        class: &str,
    ) -> Result<Shot<RecognitionReport>, ZoomError> {
        if !self.budget_left() {
            return Ok(Shot::Budget);
        }
        match self.robot.recognise(cone, class) {
            Ok(r) => {
                let classes = [class.to_string()];
                self.record(
                    step,
                    ImageKind::Recognition,
                    cone,
                    &classes,
                    r.seconds,
                    r.travelled,
                );
                if r.class != class || r.image != self.config.image {
                    return Ok(Shot::Failed(ActionFailure::new(
                        FailureReason::ExecutionFailed,
                        format!(
                            "recognition report for `{}` on a {:?} image, asked for `{class}` \
                             on {:?}",
                            r.class, r.image, self.config.image
                        ),
                    )));
                }
                Ok(Shot::Taken(r))
            }
            Err(f) if f.reason == FailureReason::Unsupported => Err(ZoomError::Unsupported {
                capability: "recogniser",
                message: f.message,
            }),
            Err(f) => Ok(Shot::Failed(f)),
        }
    }

    /// Why an attention report does not fit the request, if it does not.
    fn check_attention(&self, r: &AttentionReport, classes: &[String]) -> Result<(), String> {
        let g = self.config.image;
        if r.image != g {
            return Err(format!("a {:?} image, expected {g:?}", r.image));
        }
        for class in classes {
            let v = vote_matrix(r, class).ok_or_else(|| format!("no vote matrix for `{class}`"))?;
            if let Some(p) = v.problem() {
                return Err(format!("`{class}`: {p}"));
            }
            if (v.cols, v.rows) != (g.cols(), g.rows()) {
                return Err(format!(
                    "`{class}`: {} × {} cells, expected {} × {}",
                    v.cols,
                    v.rows,
                    g.cols(),
                    g.rows()
                ));
            }
        }
        Ok(())
    }

    /// A cone through `from`'s pixel `px` with zoom `zoom`, kept inside the camera's limits;
    /// `None` when the kept cone no longer sees the pixel's direction.
    fn aim(&self, from: &ViewCone, px: (f64, f64), zoom: f64) -> Option<ViewCone> {
        let (c, g) = (&self.camera, &self.config.image);
        if !(zoom.is_finite() && px.0.is_finite() && px.1.is_finite()) {
            return None;
        }
        let (pan, tilt) = c.pan_tilt_towards(from, g, px);
        if !(pan.is_finite() && tilt.is_finite()) {
            return None;
        }
        let cone = ViewCone::new(
            from.pose,
            c.clamp_pan(pan),
            c.clamp_tilt(tilt),
            zoom.clamp(1.0, c.max_zoom),
        );
        let target = c.unproject(from, g, px, 1.0);
        let (u, v, _) = c.project(&cone, g, target)?;
        let inside = (-EPS..=f64::from(g.width_px) + EPS).contains(&u)
            && (-EPS..=f64::from(g.height_px) + EPS).contains(&v);
        inside.then_some(cone)
    }

    /// The horizontal field of view of an image through `cone`.
    fn hfov_at(&self, cone: &ViewCone) -> f64 {
        self.camera.hfov / cone.zoom.max(1.0)
    }

    /// The hypotheses of `class` in an attention report already checked.
    fn hypotheses_of(
        &self,
        r: &AttentionReport,
        model: &ObjectModel,
    ) -> Result<Vec<Hypothesis>, ZoomError> {
        match vote_matrix(r, &model.class) {
            Some(v) => hypotheses(v, model.vote_threshold),
            None => Ok(Vec::new()),
        }
    }

    /// The initial or middle step on one attention image: per class, hypotheses, distance,
    /// and either recognition here, a final image, or zoom windows; the windows of all classes
    /// shared into middle images.
    fn analyse(
        &mut self,
        step: Step,
        cone: &ViewCone,
        report: &AttentionReport,
        classes: &[String],
        round: usize,
    ) -> Result<Vec<Task>, ZoomError> {
        let g = self.config.image;
        let z = cone.zoom.max(1.0);
        let hfov = self.hfov_at(cone);
        let mut finals = Vec::new();
        let mut windows: Vec<ZoomWindow> = Vec::new();
        for class in classes {
            if self.found(class) || self.out.budget_exhausted {
                continue;
            }
            let Some(model) = self.model(class) else {
                continue;
            };
            let one = std::slice::from_ref(class);
            let hyps = match self.hypotheses_of(report, &model) {
                Ok(h) => h,
                Err(e) if step == Step::Initial => return Err(ZoomError::BadReport(e.to_string())),
                Err(e) => {
                    self.skip(step, one, e.to_string());
                    continue;
                }
            };
            let Some(h) = hyps.first() else {
                continue;
            };
            let mut d = distance_from_votes(&model, h, hfov, &g);
            if !(d.is_finite() && d > 0.0) {
                self.skip(step, one, format!("no usable vote distance ({d})"));
                continue;
            }
            let mut sift = None;
            if model.fill_zoom(d, &self.camera, &g) / z < self.config.sift_zoom_factor {
                match self.recognise(step, cone, class)? {
                    Shot::Taken(r) => {
                        if let Some(ds) = distance_from_matches(&model, &r.matches, hfov, &g) {
                            d = ds;
                        }
                        sift = Some(r);
                    }
                    Shot::Budget => break,
                    Shot::Failed(f) => self.skip(
                        step,
                        one,
                        format!("recognition for the distance failed: {f}"),
                    ),
                }
            }
            let fin = model.zoom_for(d, &self.camera, &g);
            if within(z, fin, self.config.skip_to_final_factor) {
                // Recognition on this image: its attention had a hypothesis (the sanity check).
                let r = match sift {
                    Some(r) => r,
                    None => match self.recognise(step, cone, class)? {
                        Shot::Taken(r) => r,
                        Shot::Budget => break,
                        Shot::Failed(f) => {
                            self.skip(step, one, format!("recognition failed: {f}"));
                            continue;
                        }
                    },
                };
                self.conclude(class, cone, &r, d, h.vote_box_centre_px(&g));
                continue;
            }
            let middle = MIDDLE_MIN * fin / z;
            if middle <= self.config.repeat_middle_factor || round >= MAX_MIDDLE_ROUNDS {
                match self.aim(cone, h.vote_box_centre_px(&g), fin) {
                    Some(c) => finals.push(Task::Final {
                        cone: c,
                        class: class.clone(),
                        distance: d,
                    }),
                    None => self.skip(
                        step,
                        one,
                        "the final image's centre is beyond the camera's pan/tilt limits".into(),
                    ),
                }
            } else {
                let mut ws = group_into_windows(&hyps, class, middle, &g);
                for w in &mut ws {
                    w.min_zoom = middle;
                    w.max_zoom = MIDDLE_MAX * fin / z;
                }
                windows.extend(reduce(ws));
            }
        }
        let mut shared = share(windows, &g);
        shared.sort_by(|a, b| b.strongest().total_cmp(&a.strongest()));
        let mut tasks = finals;
        for w in shared {
            match self.aim(cone, w.centre_px(), z * w.zoom) {
                Some(c) => tasks.push(Task::Middle {
                    cone: c,
                    classes: w.classes,
                    round: round + 1,
                }),
                None => self.skip(
                    step,
                    &w.classes,
                    format!(
                        "zoom window {:?} is beyond the camera's pan/tilt limits",
                        w.box_px
                    ),
                ),
            }
        }
        Ok(tasks)
    }

    /// A middle step: the window's image for its classes still sought, then [`Self::analyse`].
    fn middle(
        &mut self,
        cone: &ViewCone,
        mut classes: Vec<String>,
        round: usize,
    ) -> Result<Vec<Task>, ZoomError> {
        classes.retain(|c| !self.found(c));
        if classes.is_empty() {
            return Ok(Vec::new());
        }
        let report = match self.attend(Step::Middle, cone, &classes)? {
            Shot::Taken(r) => r,
            Shot::Budget => return Ok(Vec::new()),
            Shot::Failed(f) => {
                self.skip(Step::Middle, &classes, format!("attention failed: {f}"));
                return Ok(Vec::new());
            }
        };
        if let Err(m) = self.check_attention(&report, &classes) {
            self.skip(
                Step::Middle,
                &classes,
                format!("malformed attention report: {m}"),
            );
            return Ok(Vec::new());
        }
        self.analyse(Step::Middle, cone, &report, &classes, round)
    }

    /// The final step of one class: the sanity-check attention, then recognition.
    fn finale(&mut self, cone: &ViewCone, class: &str, distance: f64) -> Result<(), ZoomError> {
        if self.found(class) {
            return Ok(());
        }
        let Some(model) = self.model(class) else {
            return Ok(());
        };
        let one = [class.to_string()];
        let report = match self.attend(Step::Final, cone, &one)? {
            Shot::Taken(r) => r,
            Shot::Budget => return Ok(()),
            Shot::Failed(f) => {
                self.skip(
                    Step::Final,
                    &one,
                    format!("sanity-check attention failed: {f}"),
                );
                return Ok(());
            }
        };
        if let Err(m) = self.check_attention(&report, &one) {
            self.skip(
                Step::Final,
                &one,
                format!("malformed attention report: {m}"),
            );
            return Ok(());
        }
        let hyps = match self.hypotheses_of(&report, &model) {
            Ok(h) => h,
            Err(e) => {
                self.skip(Step::Final, &one, e.to_string());
                return Ok(());
            }
        };
        // The strongest vote is above the threshold exactly when there is a hypothesis (the
        // strongest cell is a maximum).
        let Some(h) = hyps.first() else {
            return Ok(());
        };
        let g = self.config.image;
        let votes = distance_from_votes(&model, h, self.hfov_at(cone), &g);
        let fallback = if votes.is_finite() && votes > 0.0 {
            votes
        } else {
            distance
        };
        let centre = h.vote_box_centre_px(&g);
        match self.recognise(Step::Final, cone, class)? {
            Shot::Taken(r) => self.conclude(class, cone, &r, fallback, centre),
            Shot::Budget => {}
            Shot::Failed(f) => self.skip(Step::Final, &one, format!("recognition failed: {f}")),
        }
        Ok(())
    }

    /// Decide recognition on a report (§3.5) and place the object if recognised.
    fn conclude(
        &mut self,
        class: &str,
        cone: &ViewCone,
        r: &RecognitionReport,
        vote_distance: f64,
        fallback_px: (f64, f64),
    ) {
        let Some(model) = self.model(class) else {
            return;
        };
        let n = r.matches.len();
        let needed = self.config.recognition_share * f64::from(r.model_features);
        if r.model_features == 0 || (n as f64) < needed {
            return;
        }
        let g = self.config.image;
        let depth = distance_from_matches(&model, &r.matches, self.hfov_at(cone), &g)
            .unwrap_or(vote_distance);
        if !(depth.is_finite() && depth > 0.0) {
            return;
        }
        let px = match (
            median(r.matches.iter().map(|m| m.u).collect()),
            median(r.matches.iter().map(|m| m.v).collect()),
        ) {
            (Some(u), Some(v)) => (u, v),
            _ => fallback_px,
        };
        let range = depth_to_range(&self.camera, cone, &g, px, depth);
        let position = self.camera.unproject(cone, &g, px, range);
        tracing::debug!(
            class,
            ?position,
            range,
            matches = n,
            "zoom search recognised"
        );
        self.out.found.push(Recognised {
            class: class.to_string(),
            position,
            distance: range,
            matches: n,
            model_features: r.model_features,
            cone: *cone,
        });
    }
}

/// The vote matrix of `class` in a report.
fn vote_matrix<'a>(r: &'a AttentionReport, class: &str) -> Option<&'a VoteMatrix> {
    r.votes.iter().find(|v| v.class == class)
}

/// The range along the ray through pixel `(u, v)` of a point at `depth` along the optical axis
/// (the pinhole model of [`avs_robot::Camera::project`]).
fn depth_to_range(
    c: &Camera,
    cone: &ViewCone,
    g: &ImageGeometry,
    (u, v): (f64, f64),
    depth: f64,
) -> f64 {
    let z = cone.zoom.max(1.0);
    let (w, h) = (f64::from(g.width_px), f64::from(g.height_px));
    let fx = w / (2.0 * (c.hfov / z / 2.0).tan());
    let fy = h / (2.0 * (c.vfov / z / 2.0).tan());
    let (a, b) = ((u - w / 2.0) / fx, (h / 2.0 - v) / fy);
    depth * (1.0 + a * a + b * b).sqrt()
}

#[cfg(test)]
mod tests;
