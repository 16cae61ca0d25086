//! The simulated robot: pose, motion along collision-free shortest paths, and a laser that
//! reveals the true map into what the robot knows.

use crate::world::World;
use avs_map::grid::{Cell, OccupancyGrid};
use avs_map::nav::{shortest_path, Traversability};
use avs_map::raycast::{reveal_scan, LaserModel};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Distance between laser scans while moving, metres.
pub const SCAN_EVERY: f64 = 0.25;

/// A simulated robot in a [`World`].
#[derive(Debug, Clone)]
pub struct SimRobot<'w> {
    world: &'w World,
    /// Pose `[x, y, heading (radians)]`.
    pub pose: [f64; 3],
    /// What the robot has seen of the map.
    pub known: OccupancyGrid,
    /// Distance travelled so far, metres.
    pub path_length: f64,
    /// The laser model.
    pub laser: LaserModel,
    /// Seeded randomness for everything stochastic the robot does.
    pub rng: ChaCha8Rng,
    truth_nav: Traversability,
}

/// The outcome of a motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    /// The points passed, from the start pose to the end pose, at most [`SCAN_EVERY`] apart.
    pub waypoints: Vec<[f64; 2]>,
    /// Length travelled, metres.
    pub length: f64,
    /// Whether the goal was reached (else no collision-free path existed).
    pub reached: bool,
}

impl<'w> SimRobot<'w> {
    /// Put a robot at the world's start pose, with nothing known, and take a first scan.
    pub fn new(world: &'w World, seed: u64) -> Self {
        let env = &world.env;
        let t = &world.truth;
        let known = OccupancyGrid::new(
            t.width(),
            t.height(),
            t.resolution(),
            t.origin(),
            Cell::Unknown,
        )
        .expect("same geometry as a valid grid");
        let laser = LaserModel {
            range: env.laser.range,
            fov: env.laser.fov_deg.to_radians(),
            beams: env.laser.beams,
        };
        let mut r = Self {
            world,
            pose: [
                env.robot.start.x,
                env.robot.start.y,
                env.robot.start.yaw_deg.to_radians(),
            ],
            known,
            path_length: 0.0,
            laser,
            rng: ChaCha8Rng::seed_from_u64(seed),
            truth_nav: Traversability::new(&world.truth, env.robot.radius, false),
        };
        r.scan();
        r
    }

    /// The world the robot lives in (for the simulator's own bookkeeping only: an agent must
    /// never read it).
    pub fn world(&self) -> &'w World {
        self.world
    }

    /// The shortest collision-free path from the robot to `goal` in the true world (goal and
    /// start snap to free cells within 0.5 m), as [`Self::move_to`] would drive it.
    pub fn path_to(&self, goal: [f64; 2]) -> Option<avs_map::nav::GridPath> {
        shortest_path(&self.truth_nav, [self.pose[0], self.pose[1]], goal, 0.5)
    }

    /// Take a laser scan from the current pose; returns how many cells became known.
    pub fn scan(&mut self) -> usize {
        reveal_scan(&self.world.truth, &mut self.known, self.pose, &self.laser)
    }

    /// Take a scan looking all around (as a robot turning in place would).
    pub fn scan_around(&mut self) -> usize {
        let full = LaserModel {
            fov: std::f64::consts::TAU,
            ..self.laser
        };
        reveal_scan(&self.world.truth, &mut self.known, self.pose, &full)
    }

    /// Move to `goal` along a shortest collision-free path in the true world (the path a local
    /// planner would find), scanning every [`SCAN_EVERY`] metres.
    pub fn move_to(&mut self, goal: [f64; 2]) -> Motion {
        let start = [self.pose[0], self.pose[1]];
        let Some(path) = self.path_to(goal) else {
            return Motion {
                waypoints: vec![start],
                length: 0.0,
                reached: false,
            };
        };
        let mut waypoints = vec![start];
        let mut since_scan = 0.0;
        let mut prev = start;
        for &p in path.points.iter().skip(1) {
            let d = ((p[0] - prev[0]).powi(2) + (p[1] - prev[1]).powi(2)).sqrt();
            if d < 1e-12 {
                continue;
            }
            self.pose = [p[0], p[1], (p[1] - prev[1]).atan2(p[0] - prev[0])];
            self.path_length += d;
            since_scan += d;
            if since_scan >= SCAN_EVERY {
                self.scan();
                waypoints.push(p);
                since_scan = 0.0;
            }
            prev = p;
        }
        if waypoints.last() != Some(&prev) {
            waypoints.push(prev);
        }
        self.scan();
        Motion {
            waypoints,
            length: path.length,
            reached: true,
        }
    }
}
