//! The simulated robot: pose, motion along collision-free shortest paths, a laser that
//! reveals the true map into what the robot knows, and doors that open or close during a run.
//!
//! # Door events
//!
//! The [`World`] is immutable and shared; the robot keeps its own copy of the true grids
//! ([`SimRobot::walls`], [`SimRobot::truth`]) that its motion, laser and (through
//! [`crate::sim_robot::SimAgentRobot`]) camera use. A [`DoorEvent`] changes the cells of a
//! door's opening ([`World::door_opening`]) in those copies when the robot's odometry
//! ([`SimRobot::path_length`]) reaches the event's `after_m`:
//!
//! * Events are checked when the robot is created (odometry 0), at every scan point while it
//!   moves (every [`SCAN_EVERY`] metres) and at the end of every motion, in order of `after_m`
//!   (ties in the order given). A due event fires before the scan taken at that point.
//! * A closing door never shuts onto the robot: while any cell of the opening overlaps the
//!   robot's disc (the environment's `robot.radius`), the event is postponed to the first check
//!   after the robot has left; later events of the same door wait behind it, events of other
//!   doors do not. Opening is never postponed.
//! * When a door changes while the robot moves, the robot replans from where it stands (as a
//!   local planner would); when no collision-free path to the goal is left, it stops there and
//!   the motion reports `reached: false`.
//! * [`SimRobot::path_to`] always means the current true world.
//! * Once a door has changed, the laser overwrites every cell it sees with what it sees now
//!   (before, it only fills unknown cells, which is the same in a static world): the robot's
//!   map shows a door that shut after it was seen open, and the reverse.
//!   [`SimRobot::cells_relabelled`] counts the known cells changed that way.

use crate::world::{SimError, World};
use avs_map::grid::{Cell, OccupancyGrid};
use avs_map::nav::{shortest_path, Traversability};
use avs_map::raycast::{reveal_scan, walk_segment, LaserModel};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Distance between laser scans while moving, metres.
pub const SCAN_EVERY: f64 = 0.25;

/// A door that opens or closes when the robot has driven a given distance.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DoorEvent {
    /// The door's `name` as in the environment file's `doors`.
    pub door: String,
    /// Odometry (metres driven since the start) at which it happens, ≥ 0.
    pub after_m: f64,
    /// `true` opens the door, `false` closes it.
    pub open: bool,
}

/// A validated door event: the door's index in `env.doors`, when, and what it does.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Scheduled {
    door: usize,
    after_m: f64,
    open: bool,
}

/// Check door events against `world`: every `door` names a door of the environment and every
/// `after_m` is a finite number ≥ 0. The error names the field (`door_events[i].door` or
/// `door_events[i].after_m`) and what is expected.
pub fn validate_door_events(world: &World, events: &[DoorEvent]) -> Result<(), SimError> {
    for (i, e) in events.iter().enumerate() {
        if world.door_index(&e.door).is_none() {
            let known: Vec<&str> = world.env.doors.iter().map(|d| d.name.as_str()).collect();
            return Err(SimError::Invalid {
                field: format!("door_events[{i}].door"),
                message: format!(
                    "unknown door `{}`; expected one of the environment's doors: [{}]",
                    e.door,
                    known.join(", ")
                ),
            });
        }
        if !(e.after_m.is_finite() && e.after_m >= 0.0) {
            return Err(SimError::Invalid {
                field: format!("door_events[{i}].after_m"),
                message: format!(
                    "got {}; expected a finite distance ≥ 0 in metres",
                    e.after_m
                ),
            });
        }
    }
    Ok(())
}

/// A simulated robot in a [`World`].
#[derive(Debug, Clone)]
pub struct SimRobot<'w> {
    world: &'w World,
    /// Walls and closed doors as they are now (camera occlusion).
    walls: OccupancyGrid,
    /// `walls` plus furniture as it is now (motion and laser).
    truth: OccupancyGrid,
    /// Whether each door (`env.doors` order) is open now.
    door_open: Vec<bool>,
    /// Door events not yet applied, in order of `after_m`.
    pending: Vec<Scheduled>,
    /// Whether any door event has happened (known cells may be out of date).
    doors_changed: bool,
    /// Known cells a scan has changed so far.
    relabelled: usize,
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
    /// Whether the goal was reached (else no collision-free path existed, or none was left
    /// after a door changed on the way).
    pub reached: bool,
}

impl<'w> SimRobot<'w> {
    /// Put a robot at the world's start pose, with nothing known, and take a first scan.
    pub fn new(world: &'w World, seed: u64) -> Self {
        Self::build(world, seed, Vec::new())
    }

    /// [`SimRobot::new`] with door events (see the module docs); events due at odometry 0
    /// happen before the first scan. Errors name the event field that is invalid
    /// ([`validate_door_events`]).
    pub fn with_door_events(
        world: &'w World,
        seed: u64,
        events: &[DoorEvent],
    ) -> Result<Self, SimError> {
        validate_door_events(world, events)?;
        let mut pending: Vec<Scheduled> = events
            .iter()
            .filter_map(|e| {
                Some(Scheduled {
                    door: world.door_index(&e.door)?,
                    after_m: e.after_m,
                    open: e.open,
                })
            })
            .collect();
        // Stable: ties keep the order given.
        pending.sort_by(|a, b| a.after_m.total_cmp(&b.after_m));
        Ok(Self::build(world, seed, pending))
    }

    fn build(world: &'w World, seed: u64, pending: Vec<Scheduled>) -> Self {
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
            walls: world.walls.clone(),
            truth: world.truth.clone(),
            door_open: world.env.doors.iter().map(|d| d.open).collect(),
            pending,
            doors_changed: false,
            relabelled: 0,
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
        r.apply_due_door_events();
        r.scan();
        r
    }

    /// Walls and closed doors as they are now: what blocks the camera.
    pub fn walls(&self) -> &OccupancyGrid {
        &self.walls
    }

    /// Walls, closed doors and furniture as they are now: what blocks motion and the laser.
    pub fn truth(&self) -> &OccupancyGrid {
        &self.truth
    }

    /// The current walls and the robot's generator together (for the camera, which needs both).
    pub(crate) fn walls_and_rng(&mut self) -> (&OccupancyGrid, &mut ChaCha8Rng) {
        (&self.walls, &mut self.rng)
    }

    /// Whether the door named `name` is open now (`None` for an unknown door).
    pub fn door_is_open(&self, name: &str) -> Option<bool> {
        self.world.door_index(name).map(|i| self.door_open[i])
    }

    /// Number of door events that have not happened yet.
    pub fn pending_door_events(&self) -> usize {
        self.pending.len()
    }

    /// Whether any cell of door `door`'s opening overlaps the robot's disc.
    fn in_doorway(&self, door: usize) -> bool {
        let g = &self.walls;
        let half = g.resolution() / 2.0;
        let radius = self.world.env.robot.radius;
        self.world.door_opening(door).iter().any(|&(col, row)| {
            let (x, y) = g.cell_center(col as i64, row as i64);
            let dx = ((x - self.pose[0]).abs() - half).max(0.0);
            let dy = ((y - self.pose[1]).abs() - half).max(0.0);
            dx.hypot(dy) < radius
        })
    }

    /// Apply the door events that are due at the current odometry (see the module docs);
    /// returns whether any door changed.
    fn apply_due_door_events(&mut self) -> bool {
        let mut changed = false;
        let mut waiting: Vec<usize> = Vec::new();
        let mut i = 0;
        while i < self.pending.len() {
            let e = self.pending[i];
            if e.after_m > self.path_length {
                break;
            }
            if waiting.contains(&e.door) || (!e.open && self.in_doorway(e.door)) {
                waiting.push(e.door);
                i += 1;
                continue;
            }
            self.pending.remove(i);
            let cell = if e.open { Cell::Free } else { Cell::Occupied };
            for &(col, row) in self.world.door_opening(e.door) {
                self.walls.set(col, row, cell);
            }
            self.door_open[e.door] = e.open;
            changed = true;
            tracing::debug!(
                door = %self.world.env.doors[e.door].name,
                open = e.open,
                odometry = self.path_length,
                "door event"
            );
        }
        if changed {
            self.truth = self.world.furnish(&self.walls);
            self.truth_nav = Traversability::new(&self.truth, self.world.env.robot.radius, false);
            self.doors_changed = true;
        }
        changed
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
        let laser = self.laser;
        self.scan_with(&laser)
    }

    /// Take a scan looking all around (as a robot turning in place would).
    pub fn scan_around(&mut self) -> usize {
        let full = LaserModel {
            fov: std::f64::consts::TAU,
            ..self.laser
        };
        self.scan_with(&full)
    }

    /// Number of known cells whose state a scan has changed so far (a door seen open and later
    /// closed, or the reverse); 0 while no door event has happened.
    pub fn cells_relabelled(&self) -> usize {
        self.relabelled
    }

    fn scan_with(&mut self, laser: &LaserModel) -> usize {
        if !self.doors_changed {
            // A static world: known cells are already true, only unknown ones can change.
            return reveal_scan(&self.truth, &mut self.known, self.pose, laser);
        }
        // After a door event a known cell may be out of date: the laser overwrites every cell
        // it sees with what it sees now (the rays of `reveal_scan`).
        let (truth, known) = (&self.truth, &mut self.known);
        let mut revealed = 0;
        let mut relabelled = 0;
        for end in laser.ray_ends(self.pose, truth) {
            walk_segment(truth, [self.pose[0], self.pose[1]], end, |c, r| {
                if !truth.contains(c, r) {
                    return false;
                }
                let t = truth.get_i(c, r);
                let (cu, ru) = (c as usize, r as usize);
                let k = known.get(cu, ru);
                if t != Cell::Unknown && k != t {
                    if k == Cell::Unknown {
                        revealed += 1;
                    } else {
                        relabelled += 1;
                    }
                    known.set(cu, ru, t);
                }
                t == Cell::Free
            });
        }
        self.relabelled += relabelled;
        revealed
    }

    /// Move to `goal` along a shortest collision-free path in the true world (the path a local
    /// planner would find), scanning every [`SCAN_EVERY`] metres. When a door event changes the
    /// world on the way, the robot replans from where it is; when no path is left it stops
    /// there (`reached: false`).
    pub fn move_to(&mut self, goal: [f64; 2]) -> Motion {
        let start = [self.pose[0], self.pose[1]];
        let before = self.path_length;
        let mut waypoints = vec![start];
        let mut since_scan = 0.0;
        let mut prev = start;
        let mut path = self.path_to(goal);
        let reached = loop {
            let Some(p) = path.take() else {
                break false;
            };
            let mut changed = false;
            for &q in p.points.iter().skip(1) {
                let d = ((q[0] - prev[0]).powi(2) + (q[1] - prev[1]).powi(2)).sqrt();
                if d < 1e-12 {
                    continue;
                }
                self.pose = [q[0], q[1], (q[1] - prev[1]).atan2(q[0] - prev[0])];
                self.path_length += d;
                since_scan += d;
                prev = q;
                if since_scan >= SCAN_EVERY {
                    waypoints.push(q);
                    since_scan = 0.0;
                    changed = self.apply_due_door_events();
                    self.scan();
                    if changed {
                        break;
                    }
                }
            }
            if !changed {
                break true;
            }
            path = self.path_to(goal);
        };
        if waypoints.last() != Some(&prev) {
            waypoints.push(prev);
        }
        self.apply_due_door_events();
        self.scan();
        Motion {
            waypoints,
            length: self.path_length - before,
            reached,
        }
    }
}
