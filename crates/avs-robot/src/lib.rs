//! # avs-robot
//!
//! The boundary between the avs agent and a robot: the [`Robot`] trait (everything the agent may
//! ask of a robot) and the plain data it gets back, in SI units and radians. A real robot
//! implements [`Robot`] with its own drivers; the simulator (`avs-sim`) implements it with the
//! knowledge file's sensor models; [`ScriptedRobot`] is a test double whose map, motion and
//! detections a test writes down, so that the agent's skills can be tested without a simulator.
//! The agent and the simulator both depend on this crate and not on each other.
//!
//! Angles are radians everywhere in this crate. The files users write give the camera in
//! degrees (`avs_format::environment::Camera`); [`Camera::from`] converts them once, at that
//! edge.
//!
//! ```
//! use avs_robot::{Camera, Detection, Point3, Pose2D, Robot, ScriptedRobot, ViewCone};
//! use avs_map::grid::OccupancyGrid;
//! let grid = OccupancyGrid::from_ascii("#####\n#...#\n#####", 0.5, [0.0, 0.0]).unwrap();
//! let mut robot = ScriptedRobot::new(grid, Pose2D::new(0.75, 0.75, 0.0), Camera::default());
//! // The next view sees a mug 1 m ahead.
//! robot.script_view(Ok(vec![Detection {
//!     class: "mug".into(),
//!     pose: Point3 { x: 1.75, y: 0.75, z: 0.8 },
//!     confidence: 0.9,
//! }]));
//! let cone = ViewCone::new(robot.pose(), 0.0, -0.2, 1.0);
//! let seen = robot.process_view_cone(&cone, &["mug".to_string()]).unwrap();
//! assert_eq!(seen.detections.len(), 1);
//! robot.move_to(Pose2D::new(1.75, 0.75, 0.0)).unwrap();
//! assert!((robot.odometry() - 1.0).abs() < 1e-12);
//! ```
use avs_map::grid::OccupancyGrid;
use serde::{Deserialize, Serialize};

mod camera;
mod image;
mod scripted;

pub use camera::Camera;
pub use image::{AttentionReport, FeatureMatch, ImageGeometry, RecognitionReport, VoteMatrix};
pub use scripted::{
    Call, ScriptedRobot, SCRIPTED_MATCH_RADIUS, SCRIPTED_NO_OBJECT_SCORE, SCRIPTED_OBJECT_SCORE,
};

/// A planar pose: position (metres) and heading (radians, counter-clockwise from +x).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pose2D {
    /// x, metres.
    pub x: f64,
    /// y, metres.
    pub y: f64,
    /// Heading, radians.
    pub yaw: f64,
}

impl Pose2D {
    /// A pose from its parts.
    pub fn new(x: f64, y: f64, yaw: f64) -> Self {
        Self { x, y, yaw }
    }

    /// Planar distance to another pose, metres.
    pub fn distance(&self, o: &Pose2D) -> f64 {
        (self.x - o.x).hypot(self.y - o.y)
    }

    /// Whether every component is finite.
    pub fn is_finite(&self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.yaw.is_finite()
    }
}

/// A point in space: x, y (metres, world frame) and height above the floor z (metres).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Point3 {
    /// x, metres.
    pub x: f64,
    /// y, metres.
    pub y: f64,
    /// Height above the floor, metres.
    pub z: f64,
}

impl Point3 {
    /// Planar distance to a point `(x, y)`, metres.
    pub fn planar_distance(&self, x: f64, y: f64) -> f64 {
        (self.x - x).hypot(self.y - y)
    }
}

/// A view cone request (Aydemir et al. 2011, §I-A: a sensing action
/// `s = s(x_c, y_c, z_c, p, t, f, a)`): take a picture from `pose` with the camera panned by
/// `pan` (radians, relative to the robot's heading, positive to the left), tilted by `tilt`
/// (radians, negative looks down) and zoomed by `zoom` (≥ 1; divides the fields of view).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ViewCone {
    /// The robot pose from which the view is taken; the robot moves there first.
    pub pose: Pose2D,
    /// Pan, radians, relative to the robot heading.
    pub pan: f64,
    /// Tilt, radians (negative looks down).
    pub tilt: f64,
    /// Zoom factor, ≥ 1.
    pub zoom: f64,
}

impl ViewCone {
    /// A view cone from its parts.
    pub fn new(pose: Pose2D, pan: f64, tilt: f64, zoom: f64) -> Self {
        Self {
            pose,
            pan,
            tilt,
            zoom,
        }
    }

    /// The camera heading in the world frame: robot heading plus pan, radians.
    pub fn camera_yaw(&self) -> f64 {
        self.pose.yaw + self.pan
    }

    /// Check the request against a camera's limits: finite numbers, pan and tilt inside the
    /// limits, zoom in `[1, max_zoom]`. The error names the field and what is expected.
    pub fn check(&self, camera: &Camera) -> Result<(), ActionFailure> {
        let bad = |m: String| Err(ActionFailure::new(FailureReason::InvalidRequest, m));
        if !self.pose.is_finite() {
            return bad(format!(
                "view cone pose ({}, {}, {}): expected finite numbers",
                self.pose.x, self.pose.y, self.pose.yaw
            ));
        }
        let eps = 1e-9;
        let [p0, p1] = camera.pan_limits;
        if !(self.pan.is_finite() && self.pan >= p0 - eps && self.pan <= p1 + eps) {
            return bad(format!(
                "view cone pan {} rad: expected a number in [{p0:.3}, {p1:.3}] rad",
                self.pan
            ));
        }
        let [t0, t1] = camera.tilt_limits;
        if !(self.tilt.is_finite() && self.tilt >= t0 - eps && self.tilt <= t1 + eps) {
            return bad(format!(
                "view cone tilt {} rad: expected a number in [{t0:.3}, {t1:.3}] rad",
                self.tilt
            ));
        }
        if !(self.zoom.is_finite() && self.zoom >= 1.0 && self.zoom <= camera.max_zoom + eps) {
            return bad(format!(
                "view cone zoom {}: expected a number in [1, {}]",
                self.zoom, camera.max_zoom
            ));
        }
        Ok(())
    }
}

/// One object the detector reports in a view.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Detection {
    /// The object class reported.
    pub class: String,
    /// The estimated position of the object (from the estimated range and the image bearing).
    pub pose: Point3,
    /// The detector's confidence in (0, 1].
    pub confidence: f64,
}

/// What a view returned.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ViewReport {
    /// The robot pose the view was taken from (after moving there).
    pub pose: Pose2D,
    /// Detections, possibly none; may include false positives and miss true objects.
    pub detections: Vec<Detection>,
    /// Distance travelled to reach the view pose, metres.
    pub travelled: f64,
}

/// What the detector said about hypothesised locations in one image
/// ([`Robot::detector_scores`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ScoreReport {
    /// The robot pose the image was taken from (after moving there).
    pub pose: Pose2D,
    /// Distance travelled to reach that pose, metres.
    pub travelled: f64,
    /// One entry per asked location, in order: the detector's score for the class there, or
    /// `None` when the detector could not see the location in this image (outside the image,
    /// occluded, too far, seen edge-on).
    pub scores: Vec<Option<f64>>,
    /// The detector's processing time for the image, seconds.
    pub detector_seconds: f64,
}

/// What a motion achieved.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MoveReport {
    /// The robot pose at the end of the motion.
    pub pose: Pose2D,
    /// Distance travelled, metres.
    pub travelled: f64,
}

/// The robot's laser map after an update.
#[derive(Debug, Clone, PartialEq)]
pub struct MapUpdate {
    /// The whole map as the robot knows it now.
    pub grid: OccupancyGrid,
    /// Cells that became known since the previous map update.
    pub newly_known: usize,
    /// The doors the robot has seen so far, each as it was last seen (empty for a robot
    /// without a door detector: a closed door is then only a wall in `grid`).
    pub doors: Vec<DoorSighting>,
}

/// A door as the robot last saw it: a robot stack that knows its building's doors (a semantic
/// map, door signs, a door detector) reports them, so that the agent can say which closed door
/// cuts off the space it could not search.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DoorSighting {
    /// The door's name in the robot stack (e.g. the environment file's `doors[].name`).
    pub name: String,
    /// Centre of the opening, metres.
    pub x: f64,
    /// Centre of the opening, metres.
    pub y: f64,
    /// Direction of passage through the door, radians.
    pub yaw: f64,
    /// Width of the opening, metres.
    pub width: f64,
    /// Whether the door stood open when last seen.
    pub open: bool,
}

/// One reading of a place classifier (the size, shape and appearance classifiers of Pronobis
/// et al., ref. \[12\] of Aydemir et al. 2011, `002` §III) at the place the robot stands on.
///
/// A classifier is not right every time, so a reading is *soft evidence*: for every value
/// of the property (in the order of the knowledge file's `place_properties[].values`), the
/// likelihood P(this output | the place's value is that value), from the classifier's
/// confusion. Only ratios matter.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlaceReading {
    /// The property classified (a `place_properties[].name` of the knowledge file).
    pub property: String,
    /// The value the classifier output (one of the property's values).
    pub value: String,
    /// P(output | value v) for every value v of the property, in the knowledge file's order.
    pub likelihood: Vec<f64>,
}

/// Why an action failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FailureReason {
    /// No collision-free path to the goal exists (e.g. behind a closed door).
    Unreachable,
    /// The action started but did not complete (navigation aborted, camera fault); the robot
    /// may have moved part of the way.
    ExecutionFailed,
    /// The request itself is invalid (non-finite numbers, outside the camera's limits, an
    /// unknown object class).
    InvalidRequest,
    /// The robot cannot do this at all (e.g. its detector reports no scores): asking again
    /// will not help.
    Unsupported,
}

/// A failed action: the reason and a human-readable explanation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, thiserror::Error)]
#[error("{reason:?}: {message}")]
pub struct ActionFailure {
    /// Why it failed.
    pub reason: FailureReason,
    /// What happened, for the trace.
    pub message: String,
}

impl ActionFailure {
    /// A failure from its parts.
    pub fn new(reason: FailureReason, message: impl Into<String>) -> Self {
        Self {
            reason,
            message: message.into(),
        }
    }
}

/// The outcome of an action: what it achieved, or why it failed.
pub type ActionResult<T> = Result<T, ActionFailure>;

/// What the agent may ask of a robot. Implementations report only what a real robot would
/// observe: no ground truth.
pub trait Robot {
    /// The robot's current pose estimate.
    fn pose(&self) -> Pose2D;

    /// The robot's pan-tilt-zoom camera: fields of view at zoom 1, limits (radians) and height.
    fn camera(&self) -> Camera;

    /// Total distance travelled so far (odometry), metres.
    fn odometry(&self) -> f64;

    /// Move to `goal` (position; the heading is taken on arrival). Scans the laser on the way.
    fn move_to(&mut self, goal: Pose2D) -> ActionResult<MoveReport>;

    /// The laser map as known now, with the cells newly known since the previous update.
    fn map_update(&mut self) -> MapUpdate;

    /// Move to the view cone's pose if not there, point the camera and run the object detector
    /// for `classes` (object class names of the knowledge file).
    fn process_view_cone(
        &mut self,
        cone: &ViewCone,
        classes: &[String],
    ) -> ActionResult<ViewReport>;

    /// Run the place classifiers at the robot's current pose: one reading per property the
    /// robot can classify. A robot without place classifiers returns none (the default), and
    /// room categories then come from objects alone.
    fn classify_place(&mut self) -> ActionResult<Vec<PlaceReading>> {
        Ok(Vec::new())
    }

    /// Move to the view cone's pose if not there, point the camera, run the detector for
    /// `class` and read its score at each hypothesised location of `at` — whether or not the
    /// detector fires there (Velez et al. 2012, §5: the verifier reasons about the raw score
    /// `z` of a candidate, not about a thresholded detection). A detector's score is
    /// whatever real number it outputs (e.g. an SVM margin); the verifier's sensor model is
    /// trained on the same detector, so only consistency matters.
    ///
    /// A robot whose detector gives no scores keeps the default, which fails with
    /// [`FailureReason::Unsupported`]; the agent then verifies by counting detections.
    fn detector_scores(
        &mut self,
        cone: &ViewCone,
        class: &str,
        at: &[Point3],
    ) -> ActionResult<ScoreReport> {
        let _ = (cone, class, at);
        Err(ActionFailure::new(
            FailureReason::Unsupported,
            "this robot's detector reports no scores at hypothesised locations",
        ))
    }

    /// Move to the view cone's pose if not there, point the camera, zoom, take an image and
    /// run the attention for each of `classes`: one vote matrix per class (Sjöö et al. `004`
    /// §3.2). The zoom pipeline (`avs_view::zoom`) finds hypotheses in them.
    ///
    /// A robot without an attention mechanism keeps the default, which fails with
    /// [`FailureReason::Unsupported`]; the agent then uses [`Robot::process_view_cone`].
    fn attention(&mut self, cone: &ViewCone, classes: &[String]) -> ActionResult<AttentionReport> {
        let _ = (cone, classes);
        Err(ActionFailure::new(
            FailureReason::Unsupported,
            "this robot has no attention mechanism (vote matrices)",
        ))
    }

    /// Move to the view cone's pose if not there, point the camera, zoom, take an image and
    /// match the features of `class`'s model in it (Sjöö et al. `004` §3.5): the matches with
    /// their scale ratios, from which the zoom pipeline estimates the distance (§3.3.2) and
    /// decides recognition (≥ 5 % of the model's features).
    ///
    /// The default fails with [`FailureReason::Unsupported`].
    fn recognise(&mut self, cone: &ViewCone, class: &str) -> ActionResult<RecognitionReport> {
        let _ = (cone, class);
        Err(ActionFailure::new(
            FailureReason::Unsupported,
            "this robot has no feature recogniser",
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn view_cone_outside_the_camera_limits_is_rejected_with_the_field_named() {
        let cam = Camera::default();
        let ok = ViewCone::new(Pose2D::new(0.0, 0.0, 0.0), 0.0, 0.0, 1.0);
        assert!(ok.check(&cam).is_ok());
        let e = ViewCone { zoom: 9.0, ..ok }.check(&cam).unwrap_err();
        assert_eq!(e.reason, FailureReason::InvalidRequest);
        assert!(e.message.contains("zoom"), "{}", e.message);
        let e = ViewCone { tilt: -1.5, ..ok }.check(&cam).unwrap_err();
        assert!(e.message.contains("tilt"), "{}", e.message);
        let e = ViewCone {
            pan: f64::NAN,
            ..ok
        }
        .check(&cam)
        .unwrap_err();
        assert!(e.message.contains("pan"), "{}", e.message);
    }

    #[test]
    fn camera_yaw_adds_pan_to_the_robot_heading() {
        let c = ViewCone::new(Pose2D::new(0.0, 0.0, 1.0), 0.5, 0.0, 1.0);
        assert!((c.camera_yaw() - 1.5).abs() < 1e-12);
    }
}
