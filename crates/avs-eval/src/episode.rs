//! One scored episode: a world, a simulated robot with faults, an agent, one search, and the
//! result scored against the ground truth the agent never saw (`avs_sim::score`).

use crate::inputs::Input;
use crate::stats::median;
use crate::EvalError;
use avs_agent::{Agent, AgentConfig, Event, Goal, PathBreakdown, SearchReport, Strategy};
use avs_format::knowledge::Knowledge;
use avs_plan::domain::Domain;
use avs_sim::robot::DoorEvent;
use avs_sim::score::{geodesic_to_class, score_from, target_room_floor};
use avs_sim::sim_robot::{DetectorKind, SimAgentRobot, SimRobotConfig};
use avs_sim::World;
use serde::Serialize;
use std::path::Path;

/// The simulated robot's fault injection and detector.
#[derive(Debug, Clone, Default)]
pub struct Faults {
    /// Which detector its views use (`avs_sim::sim_robot::DetectorKind`).
    pub detector: DetectorKind,
    /// Probability that a motion or a view fails.
    pub failure_rate: f64,
    /// Multiplier of the false-positive rate.
    pub fp_scale: Option<f64>,
    /// Doors closing (or opening) during the run.
    pub door_events: Vec<DoorEvent>,
}

impl Faults {
    /// The simulated robot's settings with these faults.
    pub fn robot_config(&self) -> SimRobotConfig {
        let mut c = SimRobotConfig::default();
        c.failures.motion = self.failure_rate;
        c.failures.view = self.failure_rate;
        if let Some(x) = self.fp_scale {
            c.detector.false_positive_scale = x;
        }
        c.door_events = self.door_events.clone();
        c.detector_kind = self.detector;
        c
    }
}

/// The figures of one search.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    /// Whether the agent reported an object of the goal class within 1 m of a true one
    /// ([`avs_sim::score::SUCCESS_RADIUS`]).
    pub found: bool,
    /// The reported position `[x, y, z]`, if any.
    pub reported_pose: Option<[f64; 3]>,
    /// Planar distance from the reported position to the nearest true object of the class, m.
    pub error: Option<f64>,
    /// Distance driven, m.
    pub path_length: f64,
    /// Shortest collision-free path from the start to the nearest true object of the class, m.
    pub shortest_path_length: Option<f64>,
    /// Success weighted by path length: found × shortest / max(path, shortest).
    pub spl: f64,
    /// Reported, but more than 1 m from every true object of the class.
    pub wrong_report: bool,
    /// Geodesic distance from where the robot ended to the nearest true object of the class, m
    /// (habitat's DistanceToGoal at the episode's end; `None` when none is reachable).
    pub distance_to_goal: Option<f64>,
    /// Habitat's SoftSPL: `max(0, 1 − d_end/d_start) × d_start / max(path, d_start)` with the
    /// geodesic distances to the goal at the start and the end; credit for getting closer even
    /// without a report.
    pub soft_spl: f64,
    /// `path_length` by what the robot was doing (exploration, view cones, verification,
    /// coverage after the planner gave up).
    pub path_by_activity: PathBreakdown,
    /// True rooms the robot was in.
    pub rooms_visited: usize,
    /// Entries into a true room the robot had been in and left before.
    pub room_revisits: usize,
    /// Plans made.
    pub plans: usize,
    /// View-cone POMDP sessions.
    pub dt_sessions: usize,
    /// Candidate detections handed to verification, and how many it accepted and rejected.
    pub candidates: usize,
    /// Candidates accepted.
    pub candidates_accepted: usize,
    /// Candidates rejected.
    pub candidates_rejected: usize,
    /// Verification looks taken.
    pub verification_looks: usize,
    /// The detector's processing time of those looks' images, seconds.
    pub verification_detector_s: f64,
    /// Camera images the looks processed (one per one-shot detection; every image of the zoom
    /// pipeline).
    pub images: usize,
    /// Of those, the zoom pipeline's images after a look's first (middle, final, recognition).
    pub zoom_images: usize,
    /// Median planning time, ms.
    pub plan_ms_median: f64,
    /// Median time per DT decision, ms.
    pub dt_ms_median: f64,
    /// Wall-clock seconds of the whole search (the agent's planning, sessions and map
    /// updates, and the simulated robot's sensing).
    pub compute_s: f64,
    /// Why the search ended.
    pub reason: String,
}

/// What one episode gave: the scored summary, the agent's report, and the robot's trail.
#[derive(Debug, Clone)]
pub struct Episode {
    /// The figures.
    pub summary: Summary,
    /// The agent's report (trace, metrics).
    pub report: SearchReport,
    /// Every position the robot passed.
    pub trail: Vec<[f64; 2]>,
}

/// Read a knowledge file.
pub fn load_knowledge(path: &Path) -> Result<Knowledge, EvalError> {
    Input::read(path)?.knowledge()
}

/// Read and check a planning domain file; the message lists every problem.
pub fn load_domain(path: &Path) -> Result<Domain, EvalError> {
    Input::read(path)?.domain()
}

/// Read an environment file into a world.
pub fn load_world(path: &Path) -> Result<World, EvalError> {
    World::load(path).map_err(|e| EvalError::environment(&path.display().to_string(), e))
}

/// Read the environment, knowledge and domain files of a search.
pub fn load_inputs(
    env: &Path,
    knowledge: &Path,
    domain: &Path,
) -> Result<(World, Knowledge, Domain), EvalError> {
    Ok((
        load_world(env)?,
        load_knowledge(knowledge)?,
        load_domain(domain)?,
    ))
}

/// What an episode searches and how.
#[derive(Debug, Clone)]
pub struct EpisodeSpec<'a> {
    /// The knowledge the agent (and the simulated detector) use.
    pub knowledge: &'a Knowledge,
    /// The planning domain.
    pub domain: &'a Domain,
    /// The object class searched for.
    pub goal: &'a str,
    /// The simulated robot's seed.
    pub seed: u64,
    /// The agent's settings.
    pub config: AgentConfig,
    /// Fault injection.
    pub faults: Faults,
    /// Classes the same agent searches for first, in order (its memory carries over); the
    /// summary is the goal's search.
    pub before: &'a [String],
    /// Whether `before` and the goal are one [`Goal::find_all`] (the goal last): every look of
    /// a search also seeks the classes after it, and each later search first verifies what
    /// earlier looks saw of its class. Otherwise each `before` search seeks its class alone.
    pub find_all: bool,
    /// Whether the simulated robot has its place classifier
    /// (`avs_sim::place_classifier`; off by default).
    pub place_classifier: bool,
}

/// One search in `world` as `spec` says; `on_event` sees every trace event as it happens. The
/// result is scored against the truth.
pub fn run_episode(
    world: &World,
    spec: &EpisodeSpec,
    on_event: &mut dyn FnMut(&Event),
) -> Result<Episode, EvalError> {
    let mut robot_config = spec.faults.robot_config();
    robot_config.place_classifier.enabled = spec.place_classifier;
    let mut robot = SimAgentRobot::new(world, spec.knowledge.clone(), robot_config, spec.seed)
        .map_err(|e| EvalError::Sim(format!("simulated robot: {e}")))?;
    let mut agent = Agent::new(
        spec.domain.clone(),
        spec.knowledge.clone(),
        spec.config.clone(),
    )?;
    let mut sink = |e: &Event| on_event(e);
    // The goal's own search is the last; with `find_all`, a `before` class that is the goal
    // is sought there.
    let mut goals: Vec<Goal> = if spec.find_all {
        Goal::find_all(
            spec.before
                .iter()
                .map(String::as_str)
                .filter(|c| *c != spec.goal)
                .chain([spec.goal]),
        )
    } else {
        spec.before
            .iter()
            .map(|c| Goal::find(c))
            .chain([Goal::find(spec.goal)])
            .collect()
    };
    let mut goal = goals.pop().unwrap_or_else(|| Goal::find(spec.goal));
    for g in goals {
        agent.search_with(&mut robot, g, &mut sink)?;
    }
    let origin = [world.env.robot.start.x, world.env.robot.start.y];
    let goal_from = robot.trail().len().saturating_sub(1);
    let start = robot.trail().last().copied().unwrap_or(origin);
    if spec.config.strategy == Strategy::Informed {
        // The informed reference is told the target's room (its floor) and nothing else.
        let mut region = target_room_floor(world, spec.goal, start, 0.5);
        if region.is_empty() {
            // No object of the class is reachable: told where they are.
            region = world
                .objects_of_class(spec.goal)
                .map(|o| [o.pose.x, o.pose.y])
                .collect();
        }
        goal = goal.in_region(region);
    }
    let clock = std::time::Instant::now();
    let report = agent.search_with(&mut robot, goal, &mut sink)?;
    let compute_s = clock.elapsed().as_secs_f64();
    let trail = robot.trail().to_vec();
    let summary = summarize(
        Some(world),
        spec.goal,
        start,
        &report,
        &trail[goal_from.min(trail.len())..],
        compute_s,
    );
    Ok(Episode {
        summary,
        report,
        trail,
    })
}

/// The figures of one search for `goal` that started at `start` and drove along `trail`, as
/// `avs search --json` prints them. With the `world` the robot searched in, the report is
/// scored against its truth (found within 1 m, SPL, distance to the goal at the end, rooms
/// visited); without one (a real robot, whose world the agent never saw whole), the figures
/// that need the truth are `None` or 0 and `found` is the agent's own verdict.
pub fn summarize(
    world: Option<&World>,
    goal: &str,
    start: [f64; 2],
    report: &SearchReport,
    trail: &[[f64; 2]],
    compute_s: f64,
) -> Summary {
    let reported = report
        .found
        .as_ref()
        .map(|f| [f.pose.x, f.pose.y, f.pose.z]);
    let path = report.metrics.path_length;
    let end = trail.last().copied().unwrap_or(start);
    let (found, error, shortest, spl, distance_to_goal, (rooms_visited, room_revisits)) =
        match world {
            Some(world) => {
                // Scoring against ground truth (the agent never saw it).
                let sc = score_from(world, goal, start, reported, path);
                (
                    sc.found,
                    sc.error,
                    sc.shortest_path_length,
                    sc.spl,
                    geodesic_to_class(world, goal, end),
                    room_visits(world, trail),
                )
            }
            None => (reported.is_some(), None, None, 0.0, None, (0, 0)),
        };
    Summary {
        found,
        reported_pose: reported,
        error,
        path_length: path,
        shortest_path_length: shortest,
        spl,
        wrong_report: reported.is_some() && !found,
        distance_to_goal,
        soft_spl: soft_spl(shortest, distance_to_goal, path),
        path_by_activity: report.metrics.path_by_activity,
        rooms_visited,
        room_revisits,
        plans: report.metrics.plans,
        dt_sessions: report.metrics.dt_sessions,
        candidates: report.metrics.candidates,
        candidates_accepted: report.metrics.candidates_accepted,
        candidates_rejected: report.metrics.candidates_rejected,
        verification_looks: report.metrics.verification_looks,
        verification_detector_s: report.metrics.verification_detector_s,
        images: report.metrics.images,
        zoom_images: report.metrics.zoom_images,
        plan_ms_median: median(&report.metrics.plan_ms),
        dt_ms_median: median(&report.metrics.dt_ms),
        compute_s,
        reason: report.reason.clone(),
    }
}

/// Habitat's SoftSPL from the geodesic distances to the goal at the start and at the end and
/// the path driven; 0 when no goal is reachable.
pub fn soft_spl(start: Option<f64>, end: Option<f64>, path: f64) -> f64 {
    match (start, end) {
        (Some(d0), Some(d_end)) if d0 > 0.0 => (1.0 - d_end / d0).max(0.0) * d0 / d0.max(path),
        (Some(_), Some(_)) => 1.0,
        _ => 0.0,
    }
}

/// The true rooms along `trail` (positions in no room, such as door cells, are skipped): how
/// many rooms were visited and how many times the robot came back into a room it had left.
pub fn room_visits(world: &World, trail: &[[f64; 2]]) -> (usize, usize) {
    let mut seen = std::collections::BTreeSet::new();
    let mut current = None;
    let mut revisits = 0;
    for r in trail.iter().filter_map(|p| world.room_at(p[0], p[1])) {
        if current != Some(r) {
            if !seen.insert(r) {
                revisits += 1;
            }
            current = Some(r);
        }
    }
    (seen.len(), revisits)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn soft_spl_credits_getting_closer_and_charges_the_detour() {
        // Halfway to the goal along a path as long as the start distance: 0.5.
        assert!((soft_spl(Some(10.0), Some(5.0), 10.0) - 0.5).abs() < 1e-12);
        // The same end after twice the path: half of that.
        assert!((soft_spl(Some(10.0), Some(5.0), 20.0) - 0.25).abs() < 1e-12);
        // Ending farther away than the start earns nothing; no reachable goal earns nothing.
        assert_eq!(soft_spl(Some(10.0), Some(12.0), 3.0), 0.0);
        assert_eq!(soft_spl(None, Some(1.0), 3.0), 0.0);
        // At the goal after the shortest path: 1.
        assert!((soft_spl(Some(10.0), Some(0.0), 10.0) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_room_entered_again_after_leaving_it_counts_as_a_revisit() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let world = load_world(&root.join("domains/environments/office.yaml")).unwrap();
        // A point in each of two different true rooms.
        let g = &world.walls;
        let mut by_room: std::collections::BTreeMap<usize, [f64; 2]> = Default::default();
        for row in 0..g.height() {
            for col in 0..g.width() {
                if let Some(r) = world.room_of_cell[g.index(col, row)] {
                    let (x, y) = g.cell_center(col as i64, row as i64);
                    by_room.entry(r).or_insert([x, y]);
                }
            }
        }
        let mut rooms = by_room.values().copied();
        let (a, b) = (rooms.next().unwrap(), rooms.next().unwrap());
        assert_eq!(room_visits(&world, &[a, a, b, b]), (2, 0));
        assert_eq!(room_visits(&world, &[a, b, a]), (2, 1));
        assert_eq!(room_visits(&world, &[a, b, a, b, a]), (2, 3));
        assert_eq!(room_visits(&world, &[]), (0, 0));
    }
}
