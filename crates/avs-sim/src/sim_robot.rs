//! The simulated robot behind the agent's [`Robot`] trait.
//!
//! [`SimAgentRobot`] wraps a [`SimRobot`] (motion along shortest collision-free paths, laser
//! reveal) and a [`Detector`] (the camera model of [`crate::sensors`]), and adds random action
//! failures at seeded rates ([`FailureRates`], all 0 by default):
//!
//! * a failed **motion** stops at a uniformly random fraction of the shortest path (the robot
//!   has moved and scanned that far) and reports [`FailureReason::ExecutionFailed`];
//! * a failed **view** moves to the view pose as asked but returns no image
//!   ([`FailureReason::ExecutionFailed`]) — a camera or detector fault.
//!
//! **Doors can open or close during a run** ([`SimRobotConfig::door_events`], a list of
//! [`DoorEvent`]s `{ door, after_m, open }`). The shared [`World`] never changes: the robot keeps
//! its own copy of the true grids, and an event rewrites the cells of the door's opening there
//! once the robot's odometry reaches `after_m`. Events are checked when the robot is created, at
//! every laser scan point while it moves (every [`crate::robot::SCAN_EVERY`] m, so a door can
//! shut in front of the robot) and at the end of every motion. From then on motion, the laser
//! and the camera's occlusion all use the changed grid, and so does
//! [`SimRobot::path_to`](crate::SimRobot::path_to). The laser then overwrites known cells with
//! what it sees, so the robot's map shows the change once the laser sees the door, and
//! [`MapUpdate::newly_known`] counts those changed cells as well as newly seen ones. A door
//! never closes onto the robot: while the robot's disc overlaps the opening the event waits
//! until it has left. When a door changes while the robot moves, the robot replans from where
//! it is; if the goal can no longer be reached it stops there and the move reports
//! [`FailureReason::Unreachable`]. Events are deterministic (they depend on odometry only) and
//! validated by [`SimAgentRobot::new`]: an unknown door or a negative or non-finite `after_m`
//! is a [`SensorError::Robot`] naming the field (`door_events[i].door`,
//! `door_events[i].after_m`).
//!
//! ```
//! use avs_robot::{FailureReason, Pose2D, Robot};
//! use avs_sim::sim_robot::{DoorEvent, SimAgentRobot, SimRobotConfig};
//! let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
//! let world = avs_sim::World::load(&root.join("domains/environments/office.yaml")).unwrap();
//! let knowledge = avs_format::load_yaml(&root.join("knowledge/office.yaml")).unwrap();
//! let shut = DoorEvent { door: "door_kitchen".into(), after_m: 1.0, open: false };
//! let config = SimRobotConfig { door_events: vec![shut], ..SimRobotConfig::default() };
//! let mut robot = SimAgentRobot::new(&world, knowledge, config, 1).unwrap();
//! // 3 m along the corridor: the kitchen door shuts on the way, and the kitchen is cut off.
//! robot.move_to(Pose2D::new(4.0, 1.2, 0.0)).unwrap();
//! let e = robot.move_to(Pose2D::new(6.05, 4.0, 0.0)).unwrap_err();
//! assert_eq!(e.reason, FailureReason::Unreachable);
//! ```
//!
//! **Two detectors** ([`SimRobotConfig::detector_kind`], a [`DetectorKind`]). With
//! [`DetectorKind::Independent`] (the default for now) every view draws its detections afresh
//! from the knowledge file's sensor model ([`crate::sensors`]): looking twice from the same spot
//! gives two independent chances. With [`DetectorKind::Correlated`] the detections of a
//! non-landmark class come from the correlated detector of [`crate::world_scores`] (Velez et
//! al. 2012): a visible object of the class, or a visible distractor, in the view is reported
//! when its score — mean over the vantage point plus the feature's own nuisance field plus
//! white noise — exceeds the profile's `fire_threshold`, so a look-alike that fools the
//! detector from one spot fools it from nearby spots too, and an object seen badly from one
//! spot stays hard to see from there. The reported position gets the same range and bearing
//! noise and the confidence is the same geometric one as with the independent detector, and a
//! spurious detection when no object of the class is in view comes at the same rate
//! (`sensor.false_positive` × [`DetectorConfig::false_positive_scale`]). Landmark classes keep
//! the independent model in both modes.
//!
//! **Detector scores** ([`Robot::detector_scores`]). The robot moves to the cone's pose as for
//! a view (the same random view failure), takes one image and reads the correlated detector's
//! score for the class at each location asked: `None` outside the image (the fields of view
//! divided by the zoom, the tilt), when walls or a closed door block the line of sight from the
//! camera to the location (the robot's current grid: door events count), or when the class's
//! profile does not see the feature from there (beyond its range, which the zoom stretches).
//! The feature is the object of the class within [`crate::world_scores::MATCH_RADIUS`], else a
//! look-alike there, else clutter ([`crate::world_scores`]), with the same fields as the
//! correlated detections, so a detection and a later score at its spot agree. The profile of
//! every class is [`ScoreProfile::for_class`](crate::detector::ScoreProfile::for_class) of its
//! detection range
//! ([`SimAgentRobot::score_images`] and [`SimAgentRobot::score_detector_seconds`] count the
//! images and their simulated processing time).
//!
//! Choices where the paper is vague (Velez et al. verify detections of a real detector and
//! never say what it scores where nothing is):
//!
//! * **Where a score is read.** Whether a location gets a score is judged at the location (is
//!   its point in the image, is the line of sight to it clear); its value is that of the
//!   feature there (the object's own position and facing for an object or look-alike within
//!   [`crate::world_scores::MATCH_RADIUS`]), as a detector responds to the thing it sees, not
//!   to the hypothesis. A location with nothing there still scores, as clutter.
//! * **Correlated detections stop at the profile's range.** The independent detector lets the
//!   chance of a detection fall off quadratically beyond the class's detection range; the
//!   correlated one reports nothing beyond `detection_range[1]` × zoom, where its profile no
//!   longer sees the feature.
//! * **What is counted.** [`SimAgentRobot::score_images`] counts the images taken for scores
//!   only; views ([`Robot::process_view_cone`]) are counted by whoever asks for them.
//!
//! ```
//! use avs_robot::{Point3, Pose2D, Robot, ViewCone};
//! use avs_sim::sim_robot::{SimAgentRobot, SimRobotConfig};
//! let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
//! let world = avs_sim::World::load(&root.join("domains/environments/office.yaml")).unwrap();
//! let knowledge = avs_format::load_yaml(&root.join("knowledge/office.yaml")).unwrap();
//! let mut robot = SimAgentRobot::new(&world, knowledge, SimRobotConfig::default(), 1).unwrap();
//! // Into the kitchen; score a spot 1.5 m ahead and one behind the robot.
//! let view = ViewCone::new(Pose2D::new(5.5, 3.5, std::f64::consts::FRAC_PI_2), 0.0, -0.2, 1.0);
//! let ahead = Point3 { x: 5.5, y: 5.0, z: 0.8 };
//! let behind = Point3 { x: 5.5, y: 2.5, z: 0.8 };
//! let report = robot.detector_scores(&view, "cerealbox", &[ahead, behind]).unwrap();
//! assert!(report.scores[0].is_some() && report.scores[1].is_none());
//! assert_eq!((robot.score_images(), report.detector_seconds), (1, 1.0));
//! ```
//!
//! **Camera images** ([`Robot::attention`], [`Robot::recognise`]). The robot moves to the cone's
//! pose as for a view (the same random view failure), and takes an image from where it stands
//! with the cone's pan, tilt and zoom: the scene is every object of the world whose face is in
//! the image and not hidden by walls or closed doors (the robot's current grid), before a
//! background of [`ImageConfig::clutter`] at the distance of the wall along the optical axis
//! ([`crate::image::world_scene`]); faces are the sides of the knowledge's boxes, the one the
//! recogniser does best on of the two turned towards the camera. The
//! attention gives one vote matrix per class, the recogniser the class's matched features
//! ([`crate::image`]). Both draw from a generator of their own (stream [`IMAGE_STREAM`] of the
//! robot's seed), so asking for images changes nothing else the robot draws, and count their
//! simulated processing time ([`SimAgentRobot::images`], [`SimAgentRobot::image_seconds`]).
//! Unknown classes are [`FailureReason::InvalidRequest`].
//!
//! ```
//! use avs_robot::{Pose2D, Robot, ViewCone};
//! use avs_sim::sim_robot::{SimAgentRobot, SimRobotConfig};
//! let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
//! let world = avs_sim::World::load(&root.join("domains/environments/office.yaml")).unwrap();
//! let knowledge = avs_format::load_yaml(&root.join("knowledge/office.yaml")).unwrap();
//! let mut robot = SimAgentRobot::new(&world, knowledge, SimRobotConfig::default(), 1).unwrap();
//! let view = ViewCone::new(Pose2D::new(5.5, 3.5, std::f64::consts::FRAC_PI_2), 0.0, -0.2, 1.0);
//! let seen = robot.attention(&view, &["cerealbox".to_string()]).unwrap();
//! assert_eq!((seen.votes.len(), seen.votes[0].cols, seen.votes[0].rows), (1, 21, 16));
//! let matched = robot.recognise(&view, "cerealbox").unwrap();
//! assert_eq!(matched.model_features, 200);
//! assert_eq!(robot.images(), 2);
//! ```
//!
//! Unreachable goals (no collision-free path in the true world, e.g. behind a closed door)
//! report [`FailureReason::Unreachable`]; bad requests (non-finite numbers, outside the
//! camera's limits, unknown classes) report [`FailureReason::InvalidRequest`] and do nothing.
//! Everything stochastic draws from the robot's seeded `rand_chacha` generator, so the same
//! seed and the same requests give the same outcomes. The trait exposes only what a real robot
//! would report; [`SimAgentRobot::sim`] is for the simulator's own bookkeeping (metrics).
//!
//! ```
//! use avs_robot::{Pose2D, Robot, ViewCone};
//! use avs_sim::sim_robot::{SimAgentRobot, SimRobotConfig};
//! let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
//! let world = avs_sim::World::load(&root.join("domains/environments/office.yaml")).unwrap();
//! let knowledge = avs_format::load_yaml(&root.join("knowledge/office.yaml")).unwrap();
//! let mut robot = SimAgentRobot::new(&world, knowledge, SimRobotConfig::default(), 1).unwrap();
//! // Into the kitchen, then look at the table from its south side, slightly down.
//! let view = ViewCone::new(Pose2D::new(5.5, 3.5, std::f64::consts::FRAC_PI_2), 0.0, -0.2, 1.0);
//! let seen = robot
//!     .process_view_cone(&view, &["table".to_string(), "cerealbox".to_string()])
//!     .unwrap();
//! assert!(seen.travelled > 0.0 && robot.odometry() >= seen.travelled);
//! assert!(seen.detections.iter().all(|d| d.confidence > 0.0 && d.confidence <= 1.0));
//! // Unknown classes are refused, not guessed.
//! assert!(robot.process_view_cone(&view, &["unicorn".to_string()]).is_err());
//! ```

use crate::image::{ClassAppearance, ImageModel};
use crate::place_classifier::{PlaceClassifier, PlaceClassifierConfig};
pub use crate::robot::DoorEvent;
use crate::robot::SimRobot;
use crate::sensors::{Detector, DetectorConfig, SensorError};
use crate::world::{CameraView, SimError, World};
use crate::world_scores::{class_profile, WorldScores};
use avs_format::knowledge::Knowledge;
use avs_map::grid::Cell;
use avs_map::raycast::line_of_sight;
use avs_robot::{
    ActionFailure, ActionResult, AttentionReport, Camera, DoorSighting, FailureReason,
    ImageGeometry, MapUpdate, MoveReport, PlaceReading, Point3, Pose2D, RecognitionReport, Robot,
    ScoreReport, ViewCone, ViewReport,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// Rates of random action failures, each a probability per action in [0, 1].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FailureRates {
    /// Probability that a motion stops part of the way.
    pub motion: f64,
    /// Probability that a view returns no image.
    pub view: f64,
}

/// Which detector the simulated robot's views use (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DetectorKind {
    /// Every view draws its detections independently from the knowledge file's sensor model
    /// ([`crate::sensors`]).
    #[default]
    Independent,
    /// Detections of non-landmark classes fire on the correlated detector's scores
    /// ([`crate::world_scores`]); landmark classes stay independent.
    Correlated,
}

/// Configuration of the simulated robot beyond the environment and knowledge files.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SimRobotConfig {
    /// The detector's parameters.
    pub detector: DetectorConfig,
    /// Random action failure rates.
    pub failures: FailureRates,
    /// Doors that open or close during the run (see the module docs).
    pub door_events: Vec<DoorEvent>,
    /// The place classifier (size, shape, appearance; module `place_classifier`).
    pub place_classifier: PlaceClassifierConfig,
    /// Which detector views use ([`DetectorKind::Independent`] by default).
    pub detector_kind: DetectorKind,
    /// The camera image of [`Robot::attention`] and [`Robot::recognise`].
    pub image: ImageConfig,
}

/// The simulated camera image of [`Robot::attention`] and [`Robot::recognise`] ([`crate::image`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImageConfig {
    /// The image model's parameters.
    pub model: ImageModel,
    /// The image's size and vote cells.
    pub geometry: ImageGeometry,
    /// How cluttered the background behind the objects is, in `[0, 1]` (0 a plain wall, 1 a
    /// typical office scene; 1 by default).
    pub clutter: f64,
}

impl Default for ImageConfig {
    fn default() -> Self {
        Self {
            model: ImageModel::default(),
            geometry: ImageGeometry::default(),
            clutter: 1.0,
        }
    }
}

/// The stream of the robot's seed that the camera images draw from ([`Robot::attention`],
/// [`Robot::recognise`]): never stream 0, the robot's own generator, so images change nothing
/// else the robot draws.
pub const IMAGE_STREAM: u64 = 0x1_3A6E;

/// How far from the requested view pose the robot may be and still take the view there, m.
const AT_POSE: f64 = 0.05;

/// The simulated robot as the agent sees it.
#[derive(Debug, Clone)]
pub struct SimAgentRobot<'w> {
    world: &'w World,
    sim: SimRobot<'w>,
    detector: Detector,
    classifier: PlaceClassifier,
    failures: FailureRates,
    known_cells: usize,
    relabelled: usize,
    trail: Vec<[f64; 2]>,
    detector_kind: DetectorKind,
    /// The correlated detectors of the knowledge classes (scores, correlated detections).
    scores: WorldScores,
    /// Images taken for [`Robot::detector_scores`] and their simulated processing seconds.
    score_images: usize,
    score_seconds: f64,
    /// The camera image's configuration and generator (its own stream, [`IMAGE_STREAM`]).
    image: ImageConfig,
    image_rng: ChaCha8Rng,
    /// Images taken for attention and recognition, and their simulated processing seconds.
    images: usize,
    image_seconds: f64,
}

impl<'w> SimAgentRobot<'w> {
    /// A robot at the world's start pose with `knowledge`'s sensor model, seeded by `seed`.
    /// Errors name the configuration or knowledge field that is out of range (with
    /// [`DetectorKind::Correlated`], a non-landmark class whose `detection_range` gives no
    /// correlated detector is an error of `detector_kind`).
    pub fn new(
        world: &'w World,
        knowledge: Knowledge,
        config: SimRobotConfig,
        seed: u64,
    ) -> Result<Self, SensorError> {
        for (field, value) in [
            ("failures.motion", config.failures.motion),
            ("failures.view", config.failures.view),
        ] {
            if !(0.0..=1.0).contains(&value) {
                return Err(SensorError::Config {
                    field,
                    value,
                    expected: "a probability in [0, 1]",
                });
            }
        }
        if config.detector_kind == DetectorKind::Correlated {
            for c in knowledge.object_classes.iter().filter(|c| !c.landmark) {
                class_profile(c).map_err(|e| SensorError::Robot {
                    field: "detector_kind".to_string(),
                    message: format!("correlated: {e}"),
                })?;
            }
        }
        let classifier = PlaceClassifier::new(&knowledge, config.place_classifier, seed)?;
        let detector = Detector::new(knowledge, config.detector)?;
        let sim =
            SimRobot::with_door_events(world, seed, &config.door_events).map_err(|e| match e {
                SimError::Invalid { field, message } => SensorError::Robot { field, message },
                other => SensorError::Robot {
                    field: "door_events".to_string(),
                    message: other.to_string(),
                },
            })?;
        let trail = vec![[sim.pose[0], sim.pose[1]]];
        if !(0.0..=1.0).contains(&config.image.clutter) {
            return Err(SensorError::Config {
                field: "image.clutter",
                value: config.image.clutter,
                expected: "a clutter in [0, 1]",
            });
        }
        if let Some(problem) = config.image.geometry.problem() {
            return Err(SensorError::Robot {
                field: "image.geometry".to_string(),
                message: problem,
            });
        }
        let mut image_rng = ChaCha8Rng::seed_from_u64(seed);
        image_rng.set_stream(IMAGE_STREAM);
        Ok(Self {
            world,
            sim,
            detector,
            classifier,
            failures: config.failures,
            known_cells: 0,
            relabelled: 0,
            trail,
            detector_kind: config.detector_kind,
            scores: WorldScores::new(seed),
            score_images: 0,
            score_seconds: 0.0,
            image: config.image,
            image_rng,
            images: 0,
            image_seconds: 0.0,
        })
    }

    /// Number of images taken for [`Robot::attention`] and [`Robot::recognise`] so far (a
    /// failed view takes none).
    pub fn images(&self) -> usize {
        self.images
    }

    /// Simulated processing time of those images, seconds (each the `seconds` of its report).
    pub fn image_seconds(&self) -> f64 {
        self.image_seconds
    }

    /// The scene of an image taken through `cone` from where the robot stands now.
    fn image_scene(&self, cone: &ViewCone, camera: &Camera) -> (ViewCone, crate::ImageScene) {
        let taken = ViewCone {
            pose: self.pose(),
            ..*cone
        };
        let scene = crate::image::world_scene(
            self.world,
            self.sim.walls(),
            self.detector.knowledge(),
            camera,
            &taken,
            &self.image,
        );
        (taken, scene)
    }

    /// Which detector the robot's views use.
    pub fn detector_kind(&self) -> DetectorKind {
        self.detector_kind
    }

    /// Number of images taken for [`Robot::detector_scores`] so far (a failed view takes none).
    pub fn score_images(&self) -> usize {
        self.score_images
    }

    /// Simulated detector processing time of those images, seconds (each the class profile's
    /// `processing_seconds`).
    pub fn score_detector_seconds(&self) -> f64 {
        self.score_seconds
    }

    /// Every position the robot passed, from its start, at most 0.25 m apart (for pictures
    /// and metrics of a run).
    pub fn trail(&self) -> &[[f64; 2]] {
        &self.trail
    }

    /// The wrapped simulator robot: ground truth, for the simulator's metrics only. An agent
    /// must never read it.
    pub fn sim(&self) -> &SimRobot<'w> {
        &self.sim
    }

    /// The detector.
    pub fn detector(&self) -> &Detector {
        &self.detector
    }

    fn report(&self, travelled: f64) -> MoveReport {
        MoveReport {
            pose: self.pose(),
            travelled,
        }
    }

    /// The doors the laser has seen, each as the robot's map shows its opening: a door is seen
    /// once a cell of its opening is known, and is closed when the occupied cells of its
    /// opening would span at least half its width (the laser marks only the face it hits, so
    /// a door shut after the robot saw the doorway free keeps free cells behind that face; an
    /// open doorway has no occupied cell). What the robot reports is what it saw, not the
    /// truth: a door that shut out of sight still reads open until the laser sees it again.
    fn doors_seen(&self, known: &avs_map::grid::OccupancyGrid) -> Vec<DoorSighting> {
        let env = &self.world.env;
        env.doors
            .iter()
            .enumerate()
            .filter_map(|(i, d)| {
                let (mut free, mut blocked) = (0usize, 0usize);
                for &(col, row) in self.world.door_opening(i) {
                    match known.get(col, row) {
                        Cell::Free => free += 1,
                        Cell::Occupied => blocked += 1,
                        Cell::Unknown => {}
                    }
                }
                (free + blocked > 0).then(|| DoorSighting {
                    name: d.name.clone(),
                    x: d.pose.x,
                    y: d.pose.y,
                    yaw: d.pose.yaw_deg.to_radians(),
                    width: d.width,
                    open: (blocked as f64) * known.resolution() < d.width / 2.0,
                })
            })
            .collect()
    }

    /// Moves to the view cone's pose unless already there, turns to its heading, and draws the
    /// random view failure: the distance travelled, or why there is no image.
    fn go_to_view(&mut self, cone: &ViewCone) -> ActionResult<f64> {
        let here = self.pose();
        let travelled = if here.distance(&cone.pose) > AT_POSE {
            self.drive([cone.pose.x, cone.pose.y])?
        } else {
            0.0
        };
        self.sim.pose[2] = cone.pose.yaw;
        if self.failures.view > 0.0 && self.sim.rng.gen::<f64>() < self.failures.view {
            return Err(ActionFailure::new(
                FailureReason::ExecutionFailed,
                "camera returned no image",
            ));
        }
        Ok(travelled)
    }

    /// The camera's view from the current pose with `cone`'s pan, tilt and zoom.
    fn camera_view(&self, cone: &ViewCone, camera: &Camera) -> CameraView {
        let pose = self.pose();
        CameraView {
            eye: [pose.x, pose.y, camera.height],
            yaw: pose.yaw + cone.pan,
            tilt: cone.tilt,
            hfov: camera.hfov / cone.zoom,
            vfov: camera.vfov / cone.zoom,
        }
    }

    /// An unknown class as the request error naming it.
    fn unknown_class(class: &str) -> ActionFailure {
        ActionFailure::new(
            FailureReason::InvalidRequest,
            SensorError::UnknownClass(class.to_string()).to_string(),
        )
    }

    /// Move to `goal`, failing at the configured rate part of the way.
    fn drive(&mut self, goal: [f64; 2]) -> ActionResult<f64> {
        let start = [self.sim.pose[0], self.sim.pose[1]];
        let unreachable = |at: [f64; 3]| {
            let stopped = if (at[0] - start[0]).hypot(at[1] - start[1]) > 1e-9 {
                format!(
                    " (stopped at ({:.2}, {:.2}): a door closed on the way)",
                    at[0], at[1]
                )
            } else {
                String::new()
            };
            ActionFailure::new(
                FailureReason::Unreachable,
                format!(
                    "no collision-free path from ({:.2}, {:.2}) to ({:.2}, {:.2}){stopped}",
                    start[0], start[1], goal[0], goal[1]
                ),
            )
        };
        let before = self.sim.path_length;
        // The failure draw comes first so the common case plans the path only once.
        if self.failures.motion > 0.0 && self.sim.rng.gen::<f64>() < self.failures.motion {
            let path = self
                .sim
                .path_to(goal)
                .ok_or_else(|| unreachable(self.sim.pose))?;
            let stop = self.sim.rng.gen::<f64>() * path.length;
            let mut acc = 0.0;
            let mut at = path.points[0];
            for w in path.points.windows(2) {
                let d = (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
                if acc + d > stop {
                    break;
                }
                acc += d;
                at = w[1];
            }
            let m = self.sim.move_to(at);
            self.trail.extend(m.waypoints.iter().skip(1));
            return Err(ActionFailure::new(
                FailureReason::ExecutionFailed,
                format!(
                    "navigation aborted at ({:.2}, {:.2}) after {:.2} m of {:.2} m",
                    self.sim.pose[0],
                    self.sim.pose[1],
                    self.sim.path_length - before,
                    path.length
                ),
            ));
        }
        let m = self.sim.move_to(goal);
        self.trail.extend(m.waypoints.iter().skip(1));
        if !m.reached {
            return Err(unreachable(self.sim.pose));
        }
        Ok(self.sim.path_length - before)
    }
}

impl Robot for SimAgentRobot<'_> {
    fn pose(&self) -> Pose2D {
        let p = self.sim.pose;
        Pose2D::new(p[0], p[1], p[2])
    }

    fn camera(&self) -> Camera {
        Camera::from(&self.world.env.camera)
    }

    fn odometry(&self) -> f64 {
        self.sim.path_length
    }

    fn move_to(&mut self, goal: Pose2D) -> ActionResult<MoveReport> {
        if !goal.is_finite() {
            return Err(ActionFailure::new(
                FailureReason::InvalidRequest,
                format!(
                    "goal ({}, {}, {}): expected finite numbers",
                    goal.x, goal.y, goal.yaw
                ),
            ));
        }
        let travelled = self.drive([goal.x, goal.y])?;
        self.sim.pose[2] = goal.yaw;
        Ok(self.report(travelled))
    }

    fn map_update(&mut self) -> MapUpdate {
        let grid = self.sim.known.clone();
        let known = grid.cells().len() - grid.count(Cell::Unknown);
        // Cells seen for the first time plus known cells seen changed (a door that closed or
        // opened), so an agent that skips unchanged maps notices a door event.
        let relabelled = self.sim.cells_relabelled();
        let newly_known =
            known.saturating_sub(self.known_cells) + relabelled.saturating_sub(self.relabelled);
        self.known_cells = known;
        self.relabelled = relabelled;
        let doors = self.doors_seen(&grid);
        MapUpdate {
            grid,
            newly_known,
            doors,
        }
    }

    fn process_view_cone(
        &mut self,
        cone: &ViewCone,
        classes: &[String],
    ) -> ActionResult<ViewReport> {
        let camera = self.camera();
        cone.check(&camera)?;
        if let Some(c) = classes
            .iter()
            .find(|c| self.detector.knowledge().class(c).is_none())
        {
            return Err(Self::unknown_class(c));
        }
        let travelled = self.go_to_view(cone)?;
        let pose = self.pose();
        let view = self.camera_view(cone, &camera);
        let world = self.world;
        let (walls, rng) = self.sim.walls_and_rng();
        let detections = match self.detector_kind {
            DetectorKind::Independent => self
                .detector
                .detect_through(world, walls, &view, cone.zoom, classes, rng),
            DetectorKind::Correlated => {
                let knowledge = self.detector.knowledge();
                let scores = &mut self.scores;
                let (robot, zoom) = ([pose.x, pose.y], cone.zoom);
                // A visible object of the class or look-alike fires on its correlated score,
                // from the same feature and field as a later `detector_scores` at its spot.
                let mut fires = |c: &str, i: usize| {
                    let Some(class) = knowledge.class(c) else {
                        return false;
                    };
                    // Every non-landmark class has a profile (checked by `new`); one without
                    // never fires.
                    WorldScores::object(world, class, i).is_some_and(|l| {
                        matches!(scores.score(class, &l, robot, zoom), Ok(Some(z))
                            if scores.fires(class, z) == Ok(true))
                    })
                };
                self.detector
                    .detect_scored(world, walls, &view, zoom, classes, rng, &mut fires)
            }
        }
        .map_err(|e| ActionFailure::new(FailureReason::InvalidRequest, e.to_string()))?;
        Ok(ViewReport {
            pose,
            detections,
            travelled,
        })
    }

    fn classify_place(&mut self) -> ActionResult<Vec<PlaceReading>> {
        let p = self.sim.pose;
        Ok(self.classifier.classify(self.world, p[0], p[1]))
    }

    fn detector_scores(
        &mut self,
        cone: &ViewCone,
        class: &str,
        at: &[Point3],
    ) -> ActionResult<ScoreReport> {
        let camera = self.camera();
        cone.check(&camera)?;
        let Some(oc) = self.detector.knowledge().class(class).cloned() else {
            return Err(Self::unknown_class(class));
        };
        if let Some((i, p)) = at
            .iter()
            .enumerate()
            .find(|(_, p)| !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite()))
        {
            return Err(ActionFailure::new(
                FailureReason::InvalidRequest,
                format!(
                    "location at[{i}] = ({}, {}, {}): expected finite numbers",
                    p.x, p.y, p.z
                ),
            ));
        }
        let profile = class_profile(&oc)
            .map_err(|e| ActionFailure::new(FailureReason::InvalidRequest, e.0))?;
        let travelled = self.go_to_view(cone)?;
        let pose = self.pose();
        let view = self.camera_view(cone, &camera);
        let robot = [pose.x, pose.y];
        let world = self.world;
        let walls = self.sim.walls();
        let scores = &mut self.scores;
        let scores = at
            .iter()
            .map(|p| {
                let seen = view.off_axis([p.x, p.y, p.z]).in_image(&view)
                    && line_of_sight(walls, robot, [p.x, p.y], false);
                if !seen {
                    return None;
                }
                let located = WorldScores::locate(world, &oc, [p.x, p.y]);
                // The class's profile was checked above.
                scores.score(&oc, &located, robot, cone.zoom).ok().flatten()
            })
            .collect();
        self.score_images += 1;
        self.score_seconds += profile.processing_seconds;
        Ok(ScoreReport {
            pose,
            travelled,
            scores,
            detector_seconds: profile.processing_seconds,
        })
    }

    fn attention(&mut self, cone: &ViewCone, classes: &[String]) -> ActionResult<AttentionReport> {
        let camera = self.camera();
        cone.check(&camera)?;
        if let Some(c) = classes
            .iter()
            .find(|c| self.detector.knowledge().class(c).is_none())
        {
            return Err(Self::unknown_class(c));
        }
        let travelled = self.go_to_view(cone)?;
        let (taken, scene) = self.image_scene(cone, &camera);
        let geometry = self.image.geometry;
        let model = self.image.model;
        let votes = crate::image::attention(
            &model,
            &scene,
            &camera,
            &taken,
            &geometry,
            classes,
            &mut self.image_rng,
        );
        let seconds = model.attention_seconds(classes.len());
        self.images += 1;
        self.image_seconds += seconds;
        Ok(AttentionReport {
            pose: taken.pose,
            travelled,
            image: geometry,
            votes,
            seconds,
        })
    }

    fn recognise(&mut self, cone: &ViewCone, class: &str) -> ActionResult<RecognitionReport> {
        let camera = self.camera();
        cone.check(&camera)?;
        let Some(oc) = self.detector.knowledge().class(class) else {
            return Err(Self::unknown_class(class));
        };
        let appearance = ClassAppearance {
            name: oc.name.clone(),
            width: oc.size[0],
            height: oc.size[2],
        };
        let travelled = self.go_to_view(cone)?;
        let (taken, scene) = self.image_scene(cone, &camera);
        let geometry = self.image.geometry;
        let model = self.image.model;
        let seen = crate::image::recognition(
            &model,
            &scene,
            &camera,
            &taken,
            &geometry,
            &appearance,
            &mut self.image_rng,
        );
        let seconds = model.recognition_time();
        self.images += 1;
        self.image_seconds += seconds;
        Ok(RecognitionReport {
            pose: taken.pose,
            travelled,
            image: geometry,
            class: appearance.name,
            model_features: seen.model_features,
            matches: seen.matches,
            seconds,
        })
    }
}
