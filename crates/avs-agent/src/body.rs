//! [`Body`]: the only code that moves the robot, points its camera and reads its laser map.
//! Every motion goes along the agent's own shortest path on the known map, in short
//! waypoints, so that the place map sees every door crossing; after each, the map update is
//! written into the [`Memory`] and the memory synced.

use crate::memory::Memory;
use crate::reason::MoveFailure;
use crate::report::{Activity, PathBreakdown};
use crate::AgentError;
use avs_map::nav::shortest_path;
use avs_map::places::dist;
use avs_robot::{ActionResult, Camera, Pose2D, Robot, ViewCone, ViewReport};

/// The robot as the agent drives it.
pub(crate) struct Body<'r, R: Robot + ?Sized> {
    robot: &'r mut R,
    /// What the motions are for now.
    activity: Activity,
    /// Metres driven per activity.
    path: PathBreakdown,
}

impl<'r, R: Robot + ?Sized> Body<'r, R> {
    /// The body of `robot`.
    pub fn new(robot: &'r mut R) -> Self {
        Self {
            robot,
            activity: Activity::default(),
            path: PathBreakdown::default(),
        }
    }

    /// Run `f` with its motions booked to `activity` (the one before is restored after).
    pub fn with_activity<T>(&mut self, activity: Activity, f: impl FnOnce(&mut Self) -> T) -> T {
        let before = std::mem::replace(&mut self.activity, activity);
        let r = f(self);
        self.activity = before;
        r
    }

    /// Metres driven so far through this body, per activity.
    pub fn path_by_activity(&self) -> PathBreakdown {
        self.path
    }

    /// Book the odometry since `before` to the current activity.
    fn book(&mut self, before: f64) {
        let moved = self.robot.odometry() - before;
        if moved > 0.0 {
            self.path.add(self.activity, moved);
        }
    }

    /// The robot's pose estimate.
    pub fn pose(&self) -> Pose2D {
        self.robot.pose()
    }

    /// The robot's planar position.
    pub fn at(&self) -> [f64; 2] {
        let p = self.robot.pose();
        [p.x, p.y]
    }

    /// The robot's pose as `[x, y, yaw]` (for the trace).
    pub fn pose3(&self) -> [f64; 3] {
        let p = self.robot.pose();
        [p.x, p.y, p.yaw]
    }

    /// The robot's camera.
    pub fn camera(&self) -> Camera {
        self.robot.camera()
    }

    /// Odometry so far, metres.
    pub fn odometry(&self) -> f64 {
        self.robot.odometry()
    }

    /// The laser map as the robot knows it now.
    pub fn laser_map(&mut self) -> avs_map::grid::OccupancyGrid {
        self.robot.map_update().grid
    }

    /// Write the robot's current laser map into `mem` (no sync).
    pub fn refresh_map(&mut self, mem: &mut Memory) {
        mem.grid = self.robot.map_update().grid;
    }

    /// Point the camera along `cone` (moving to its pose first if needed) and run the detector
    /// for `classes`.
    pub fn look(&mut self, cone: &ViewCone, classes: &[String]) -> ActionResult<ViewReport> {
        let before = self.robot.odometry();
        let r = self.robot.process_view_cone(cone, classes);
        self.book(before);
        r
    }

    /// The first survey of a new memory: turn in place so the laser sees all around, drop the
    /// first place and sync.
    pub fn survey(&mut self, mem: &mut Memory) -> Result<(), AgentError> {
        let p = self.robot.pose();
        let before = self.robot.odometry();
        let _ = self
            .robot
            .move_to(Pose2D::new(p.x, p.y, p.yaw + std::f64::consts::PI));
        let _ = self.robot.move_to(p);
        self.book(before);
        let grid = self.robot.map_update().grid;
        mem.wm.places.robot_moved(&grid, [p.x, p.y], [p.x, p.y]);
        mem.grid = grid;
        mem.sync()
    }

    /// Turn in place so that the laser sees all around, and update the maps.
    pub fn turn_around(&mut self, mem: &mut Memory) -> Result<(), AgentError> {
        let here = self.robot.pose();
        let before = self.robot.odometry();
        let _ = self
            .robot
            .move_to(Pose2D::new(here.x, here.y, here.yaw + std::f64::consts::PI));
        let _ = self.robot.move_to(here);
        self.book(before);
        let grid = self.robot.map_update().grid;
        mem.wm.places.update(&grid);
        mem.grid = grid;
        mem.sync()
    }

    /// Drive to `target` along a path on the known map, updating the place map on the way.
    /// The inner result says whether the motion arrived.
    pub fn go_to(
        &mut self,
        mem: &mut Memory,
        target: [f64; 2],
    ) -> Result<Result<(), MoveFailure>, AgentError> {
        let here = self.robot.pose();
        let from = [here.x, here.y];
        let path = mem
            .with_trav(false, |t| shortest_path(t, from, target, 1.0))
            .or_else(|| mem.with_trav(true, |t| shortest_path(t, from, target, 1.0)));
        let mut wps: Vec<[f64; 2]> = match &path {
            Some(p) => p.points.iter().skip(1).step_by(5).copied().collect(),
            None => Vec::new(),
        };
        // The path ends at the traversable cell nearest the target (the goal snaps to it).
        wps.push(
            path.as_ref()
                .and_then(|p| p.points.last().copied())
                .unwrap_or(target),
        );
        let detour_factor = mem.tuning.detour_factor;
        let mut result = Ok(());
        let mut prev = [here.x, here.y];
        for w in wps {
            if dist(prev, w) < 1e-6 {
                continue;
            }
            let yaw = (w[1] - prev[1]).atan2(w[0] - prev[0]);
            let odo = self.robot.odometry();
            let r = self.robot.move_to(Pose2D::new(w[0], w[1], yaw));
            self.book(odo);
            let detour = self.robot.odometry() - odo > detour_factor * dist(prev, w) + 1.0;
            let now = self.robot.pose();
            let grid = self.robot.map_update().grid;
            mem.wm.places.robot_moved(&grid, prev, [now.x, now.y]);
            mem.wm.places.update(&grid);
            mem.grid = grid;
            mem.at = [now.x, now.y];
            prev = [now.x, now.y];
            if let Err(e) = r {
                result = Err(MoveFailure::Robot(e));
                break;
            }
            if detour {
                result = Err(MoveFailure::Detour { target });
                break;
            }
        }
        mem.sync()?;
        Ok(result)
    }
}
