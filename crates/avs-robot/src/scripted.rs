//! [`ScriptedRobot`]: a [`Robot`] whose world a test writes down — a fixed map, straight-line
//! motion, objects the camera sees when they lie in its image, and scripted replies and
//! failures — with a log of every call the agent made. For unit tests of the agent's skills
//! without the simulator.

use crate::{
    ActionFailure, ActionResult, Camera, Detection, FailureReason, MapUpdate, MoveReport,
    PlaceReading, Point3, Pose2D, Robot, ScoreReport, ViewCone, ViewReport,
};
use avs_map::grid::{Cell, OccupancyGrid};
use std::collections::VecDeque;

/// One call the agent made of a [`ScriptedRobot`], in order.
#[derive(Debug, Clone, PartialEq)]
pub enum Call {
    /// `move_to(goal)`.
    Move(Pose2D),
    /// `map_update()`.
    MapUpdate,
    /// `process_view_cone(cone, classes)`.
    View(ViewCone, Vec<String>),
    /// `classify_place()`.
    ClassifyPlace,
    /// `detector_scores(cone, class, at)`.
    Scores(ViewCone, String, Vec<Point3>),
}

/// The score a [`ScriptedRobot`] reads at a location in its image within
/// [`SCRIPTED_MATCH_RADIUS`] of a placed object of the class asked for (unless scripted).
pub const SCRIPTED_OBJECT_SCORE: f64 = 2.0;
/// The score a [`ScriptedRobot`] reads at a location in its image with no placed object of the
/// class near it (unless scripted).
pub const SCRIPTED_NO_OBJECT_SCORE: f64 = 0.0;
/// How near (metres) a placed object must be to a hypothesised location to score there.
pub const SCRIPTED_MATCH_RADIUS: f64 = 0.3;

/// A scripted robot: the map is what the test gives ([`ScriptedRobot::set_grid`]), motion goes
/// in a straight line and always arrives unless a failure is scripted
/// ([`ScriptedRobot::script_move`]), and a view returns the next scripted reply
/// ([`ScriptedRobot::script_view`]) or, when none is left, every placed object
/// ([`ScriptedRobot::place`]) whose position lies inside the view's image (fields of view
/// divided by the zoom; no occlusion, no noise). With [`ScriptedRobot::with_laser`] the map
/// grows as the robot moves: every cell of a true map within the laser's range of a pose the
/// robot reaches becomes known (no occlusion). Deterministic; nothing random.
#[derive(Debug, Clone)]
pub struct ScriptedRobot {
    grid: OccupancyGrid,
    pose: Pose2D,
    camera: Camera,
    odometry: f64,
    known_reported: usize,
    moves: VecDeque<ActionFailure>,
    views: VecDeque<ActionResult<Vec<Detection>>>,
    places: VecDeque<Vec<PlaceReading>>,
    scores: VecDeque<ActionResult<Vec<Option<f64>>>>,
    gives_scores: bool,
    objects: Vec<Detection>,
    calls: Vec<Call>,
    laser: Option<(OccupancyGrid, f64)>,
}

impl ScriptedRobot {
    /// A robot at `pose` on `grid` (its whole laser map) with `camera`.
    pub fn new(grid: OccupancyGrid, pose: Pose2D, camera: Camera) -> Self {
        Self {
            grid,
            pose,
            camera,
            odometry: 0.0,
            known_reported: 0,
            moves: VecDeque::new(),
            views: VecDeque::new(),
            places: VecDeque::new(),
            scores: VecDeque::new(),
            gives_scores: true,
            objects: Vec::new(),
            calls: Vec::new(),
            laser: None,
        }
    }

    /// A robot whose laser reveals `truth` within `range` metres of every pose it reaches,
    /// starting with what it sees from `pose` (the map starts all unknown).
    pub fn with_laser(truth: OccupancyGrid, range: f64, pose: Pose2D, camera: Camera) -> Self {
        let mut unknown = truth.clone();
        for row in 0..truth.height() {
            for col in 0..truth.width() {
                unknown.set(col, row, Cell::Unknown);
            }
        }
        let mut r = Self::new(unknown, pose, camera);
        r.laser = Some((truth, range));
        r.scan();
        r
    }

    /// Reveal the true map around the current pose.
    fn scan(&mut self) {
        let Some((truth, range)) = &self.laser else {
            return;
        };
        for row in 0..truth.height() {
            for col in 0..truth.width() {
                let (x, y) = truth.cell_center(col as i64, row as i64);
                if (x - self.pose.x).hypot(y - self.pose.y) <= *range {
                    self.grid.set(col, row, truth.get(col, row));
                }
            }
        }
    }

    /// Replace the laser map (e.g. to reveal more of it); the next update counts the change.
    pub fn set_grid(&mut self, grid: OccupancyGrid) {
        self.grid = grid;
    }

    /// The next motion fails with `failure` (the robot stays where it is); queued in order.
    pub fn script_move(&mut self, failure: ActionFailure) {
        self.moves.push_back(failure);
    }

    /// The reply of the next view: its detections or a failure; queued in order. Views beyond
    /// the scripted ones see the placed objects.
    pub fn script_view(&mut self, reply: ActionResult<Vec<Detection>>) {
        self.views.push_back(reply);
    }

    /// The readings of the next place classification; queued in order. Classifications
    /// beyond the scripted ones read nothing.
    pub fn script_place(&mut self, readings: Vec<PlaceReading>) {
        self.places.push_back(readings);
    }

    /// The reply of the next [`Robot::detector_scores`]: one score per asked location, or a
    /// failure; queued in order. Calls beyond the scripted ones read
    /// [`SCRIPTED_OBJECT_SCORE`] at locations in the image near a placed object of the class,
    /// [`SCRIPTED_NO_OBJECT_SCORE`] at other locations in the image and `None` outside it.
    pub fn script_scores(&mut self, reply: ActionResult<Vec<Option<f64>>>) {
        self.scores.push_back(reply);
    }

    /// A robot whose detector reports no scores: [`Robot::detector_scores`] fails with
    /// [`FailureReason::Unsupported`], as the trait's default does.
    pub fn without_scores(mut self) -> Self {
        self.gives_scores = false;
        self
    }

    /// An object every view sees while its position lies inside the image, reported as given.
    pub fn place(&mut self, object: Detection) {
        self.objects.push(object);
    }

    /// Every call the agent made so far, in order.
    pub fn calls(&self) -> &[Call] {
        &self.calls
    }

    /// The views asked for so far, in order.
    pub fn views(&self) -> Vec<ViewCone> {
        self.calls
            .iter()
            .filter_map(|c| match c {
                Call::View(v, _) => Some(*v),
                _ => None,
            })
            .collect()
    }

    /// Whether `p` (x, y, height) lies inside the image of `cone` taken from the cone's pose.
    pub fn in_image(&self, cone: &ViewCone, p: [f64; 3]) -> bool {
        let (dx, dy) = (p[0] - cone.pose.x, p[1] - cone.pose.y);
        let horiz = dx.hypot(dy);
        if horiz < 1e-9 {
            return false;
        }
        let yaw = avs_map::geometry::wrap_angle(dy.atan2(dx) - cone.camera_yaw());
        let el = (p[2] - self.camera.height).atan2(horiz) - cone.tilt;
        yaw.abs() <= 0.5 * self.camera.hfov / cone.zoom
            && el.abs() <= 0.5 * self.camera.vfov / cone.zoom
    }
}

impl Robot for ScriptedRobot {
    fn pose(&self) -> Pose2D {
        self.pose
    }

    fn camera(&self) -> Camera {
        self.camera
    }

    fn odometry(&self) -> f64 {
        self.odometry
    }

    fn move_to(&mut self, goal: Pose2D) -> ActionResult<MoveReport> {
        self.calls.push(Call::Move(goal));
        if let Some(f) = self.moves.pop_front() {
            return Err(f);
        }
        let travelled = self.pose.distance(&goal);
        self.odometry += travelled;
        self.pose = goal;
        self.scan();
        Ok(MoveReport {
            pose: goal,
            travelled,
        })
    }

    fn map_update(&mut self) -> MapUpdate {
        self.calls.push(Call::MapUpdate);
        let known = self.grid.cells().len() - self.grid.count(Cell::Unknown);
        let newly_known = known.saturating_sub(self.known_reported);
        self.known_reported = known;
        MapUpdate {
            grid: self.grid.clone(),
            newly_known,
            doors: Vec::new(),
        }
    }

    fn process_view_cone(
        &mut self,
        cone: &ViewCone,
        classes: &[String],
    ) -> ActionResult<ViewReport> {
        self.calls.push(Call::View(*cone, classes.to_vec()));
        cone.check(&self.camera)?;
        let travelled = self.pose.distance(&cone.pose);
        self.odometry += travelled;
        self.pose = cone.pose;
        let detections = match self.views.pop_front() {
            Some(reply) => reply?,
            None => self
                .objects
                .iter()
                .filter(|o| classes.contains(&o.class))
                .filter(|o| self.in_image(cone, [o.pose.x, o.pose.y, o.pose.z]))
                .cloned()
                .collect(),
        };
        Ok(ViewReport {
            pose: self.pose,
            detections,
            travelled,
        })
    }

    fn classify_place(&mut self) -> ActionResult<Vec<PlaceReading>> {
        self.calls.push(Call::ClassifyPlace);
        Ok(self.places.pop_front().unwrap_or_default())
    }

    fn detector_scores(
        &mut self,
        cone: &ViewCone,
        class: &str,
        at: &[Point3],
    ) -> ActionResult<ScoreReport> {
        self.calls
            .push(Call::Scores(*cone, class.to_string(), at.to_vec()));
        if !self.gives_scores {
            return Err(ActionFailure::new(
                FailureReason::Unsupported,
                "this scripted robot's detector reports no scores",
            ));
        }
        cone.check(&self.camera)?;
        let travelled = self.pose.distance(&cone.pose);
        self.odometry += travelled;
        self.pose = cone.pose;
        let scores = match self.scores.pop_front() {
            Some(reply) => reply?,
            None => at
                .iter()
                .map(|p| {
                    self.in_image(cone, [p.x, p.y, p.z]).then(|| {
                        let near = self.objects.iter().any(|o| {
                            o.class == class
                                && o.pose.planar_distance(p.x, p.y) <= SCRIPTED_MATCH_RADIUS
                        });
                        if near {
                            SCRIPTED_OBJECT_SCORE
                        } else {
                            SCRIPTED_NO_OBJECT_SCORE
                        }
                    })
                })
                .collect(),
        };
        Ok(ScoreReport {
            pose: self.pose,
            travelled,
            scores,
            detector_seconds: 0.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{FailureReason, Point3};

    fn robot() -> ScriptedRobot {
        let grid = OccupancyGrid::from_ascii("######\n#....#\n#....#\n######", 0.5, [0.0, 0.0])
            .expect("valid map");
        ScriptedRobot::new(grid, Pose2D::new(0.75, 0.75, 0.0), Camera::default())
    }

    fn mug(x: f64, y: f64) -> Detection {
        Detection {
            class: "mug".into(),
            pose: Point3 { x, y, z: 1.2 },
            confidence: 0.8,
        }
    }

    #[test]
    fn a_placed_object_is_seen_only_inside_the_image() {
        let mut r = robot();
        r.place(mug(2.25, 0.75));
        let ahead = ViewCone::new(r.pose(), 0.0, 0.0, 1.0);
        let behind = ViewCone::new(r.pose(), std::f64::consts::PI, 0.0, 1.0);
        let mug_only = ["mug".to_string()];
        assert_eq!(
            r.process_view_cone(&ahead, &mug_only)
                .unwrap()
                .detections
                .len(),
            1
        );
        assert!(r
            .process_view_cone(&behind, &mug_only)
            .unwrap()
            .detections
            .is_empty());
        assert!(r
            .process_view_cone(&ahead, &["cup".to_string()])
            .unwrap()
            .detections
            .is_empty());
    }

    #[test]
    fn scripted_replies_come_first_and_in_order() {
        let mut r = robot();
        r.place(mug(2.25, 0.75));
        r.script_view(Ok(vec![]));
        r.script_view(Err(ActionFailure::new(
            FailureReason::ExecutionFailed,
            "no image",
        )));
        let cone = ViewCone::new(r.pose(), 0.0, 0.0, 1.0);
        let classes = ["mug".to_string()];
        assert!(r
            .process_view_cone(&cone, &classes)
            .unwrap()
            .detections
            .is_empty());
        assert!(r.process_view_cone(&cone, &classes).is_err());
        assert_eq!(
            r.process_view_cone(&cone, &classes)
                .unwrap()
                .detections
                .len(),
            1
        );
        assert_eq!(r.views().len(), 3);
    }

    #[test]
    fn a_scripted_move_failure_leaves_the_robot_in_place_and_odometry_counts_the_rest() {
        let mut r = robot();
        r.script_move(ActionFailure::new(FailureReason::Unreachable, "door shut"));
        let goal = Pose2D::new(2.25, 0.75, 0.0);
        assert_eq!(
            r.move_to(goal).unwrap_err().reason,
            FailureReason::Unreachable
        );
        assert_eq!(r.odometry(), 0.0);
        r.move_to(goal).unwrap();
        assert!((r.odometry() - 1.5).abs() < 1e-12);
        assert_eq!(r.pose(), goal);
    }

    #[test]
    fn the_first_map_update_counts_every_known_cell_and_later_ones_only_the_change() {
        let mut r = robot();
        let first = r.map_update();
        assert_eq!(first.newly_known, 24);
        assert_eq!(r.map_update().newly_known, 0);
    }

    #[test]
    fn the_laser_reveals_the_true_map_around_each_pose_reached() {
        let truth = OccupancyGrid::from_ascii(
            &format!("{}\n{}", "#".repeat(40), ".".repeat(40)),
            0.5,
            [0.0, 0.0],
        )
        .expect("valid map");
        let mut r =
            ScriptedRobot::with_laser(truth, 2.0, Pose2D::new(0.25, 0.25, 0.0), Camera::default());
        let known = |r: &mut ScriptedRobot| {
            let g = r.map_update().grid;
            g.cells().len() - g.count(Cell::Unknown)
        };
        let before = known(&mut r);
        assert!(before > 0 && before < 80);
        r.move_to(Pose2D::new(10.25, 0.25, 0.0)).unwrap();
        assert!(known(&mut r) > before);
        assert_eq!(
            r.map_update().grid.get(39, 0),
            Cell::Unknown,
            "beyond the range"
        );
    }

    #[test]
    fn a_view_outside_the_camera_limits_is_refused() {
        let mut r = robot();
        let cone = ViewCone::new(r.pose(), 0.0, -1.5, 1.0);
        let e = r.process_view_cone(&cone, &[]).unwrap_err();
        assert_eq!(e.reason, FailureReason::InvalidRequest);
    }

    #[test]
    fn scores_read_a_placed_object_high_empty_floor_low_and_nothing_outside_the_image() {
        let mut r = robot();
        r.place(Detection {
            class: "mug".into(),
            pose: Point3 {
                x: 2.25,
                y: 0.75,
                z: 0.8,
            },
            confidence: 0.9,
        });
        let cone = ViewCone::new(Pose2D::new(0.75, 0.75, 0.0), 0.0, 0.0, 1.0);
        let at = |x: f64, y: f64| Point3 { x, y, z: 0.8 };
        let rep = r
            .detector_scores(
                &cone,
                "mug",
                &[at(2.25, 0.75), at(2.25, 1.25), at(-3.0, 0.75)],
            )
            .unwrap();
        assert_eq!(
            rep.scores,
            vec![
                Some(SCRIPTED_OBJECT_SCORE),
                Some(SCRIPTED_NO_OBJECT_SCORE),
                None
            ]
        );
        // Another class scores nothing at the mug; a scripted reply comes first.
        let rep = r.detector_scores(&cone, "cup", &[at(2.25, 0.75)]).unwrap();
        assert_eq!(rep.scores, vec![Some(SCRIPTED_NO_OBJECT_SCORE)]);
        r.script_scores(Ok(vec![Some(0.7)]));
        let rep = r.detector_scores(&cone, "mug", &[at(2.25, 0.75)]).unwrap();
        assert_eq!(rep.scores, vec![Some(0.7)]);
        let e = r
            .clone()
            .without_scores()
            .detector_scores(&cone, "mug", &[at(2.25, 0.75)])
            .unwrap_err();
        assert_eq!(e.reason, FailureReason::Unsupported);
    }
}
