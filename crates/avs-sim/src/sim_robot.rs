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

use crate::place_classifier::{PlaceClassifier, PlaceClassifierConfig};
pub use crate::robot::DoorEvent;
use crate::robot::SimRobot;
use crate::sensors::{Detector, DetectorConfig, SensorError};
use crate::world::{CameraView, SimError, World};
use avs_format::knowledge::Knowledge;
use avs_map::grid::Cell;
use avs_robot::{
    ActionFailure, ActionResult, Camera, DoorSighting, FailureReason, MapUpdate, MoveReport,
    PlaceReading, Pose2D, Robot, ViewCone, ViewReport,
};
use rand::Rng;

/// Rates of random action failures, each a probability per action in [0, 1].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FailureRates {
    /// Probability that a motion stops part of the way.
    pub motion: f64,
    /// Probability that a view returns no image.
    pub view: f64,
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
}

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
}

impl<'w> SimAgentRobot<'w> {
    /// A robot at the world's start pose with `knowledge`'s sensor model, seeded by `seed`.
    /// Errors name the configuration or knowledge field that is out of range.
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
        Ok(Self {
            world,
            sim,
            detector,
            classifier,
            failures: config.failures,
            known_cells: 0,
            relabelled: 0,
            trail,
        })
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
            return Err(ActionFailure::new(
                FailureReason::InvalidRequest,
                SensorError::UnknownClass(c.clone()).to_string(),
            ));
        }
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
        let pose = self.pose();
        let view = CameraView {
            eye: [pose.x, pose.y, camera.height],
            yaw: pose.yaw + cone.pan,
            tilt: cone.tilt,
            hfov: camera.hfov / cone.zoom,
            vfov: camera.vfov / cone.zoom,
        };
        let (walls, rng) = self.sim.walls_and_rng();
        let detections = self
            .detector
            .detect_through(self.world, walls, &view, cone.zoom, classes, rng)
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
}
