//! Faults never crash or hang the agent: a door closing mid-run, doubled false positives and
//! 10 % action failures end in a verdict, with a replan after every failure, and wrong reports
//! stay rare.

use avs_agent::{
    ActionResult, Agent, AgentConfig, Camera, Event, Goal, MapUpdate, MoveReport, Pose2D, Robot,
    SearchReport, ViewCone, ViewReport,
};

use avs_format::knowledge::Knowledge;
use avs_plan::domain::Domain;
use avs_sim::sensors::DetectorConfig;
use avs_sim::sim_robot::{DoorEvent, FailureRates, SimAgentRobot, SimRobotConfig};
use avs_sim::World;
use std::path::{Path, PathBuf};

fn shipped(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

fn knowledge() -> Knowledge {
    avs_format::load_yaml(&shipped("knowledge/office.yaml")).unwrap()
}

fn domain() -> Domain {
    Domain::load(&shipped("domains/object_search.yaml")).unwrap()
}

fn office() -> World {
    World::load(&shipped("domains/environments/office.yaml")).unwrap()
}

/// A robot that records where it was after every call (the agent moves in short waypoints, so
/// this is the trajectory) and counts the calls.
struct Recorder<'w> {
    inner: SimAgentRobot<'w>,
    /// `(odometry, [x, y])` after each motion or view.
    track: Vec<(f64, [f64; 2])>,
    /// Motions the simulator refused or aborted.
    failed_moves: Vec<String>,
    calls: usize,
}

impl Recorder<'_> {
    fn log(&mut self) {
        let p = self.inner.pose();
        self.track.push((self.inner.odometry(), [p.x, p.y]));
    }
}

impl Robot for Recorder<'_> {
    fn pose(&self) -> Pose2D {
        self.inner.pose()
    }
    fn camera(&self) -> Camera {
        self.inner.camera()
    }
    fn odometry(&self) -> f64 {
        self.inner.odometry()
    }
    fn move_to(&mut self, goal: Pose2D) -> ActionResult<MoveReport> {
        self.calls += 1;
        let r = self.inner.move_to(goal);
        if let Err(e) = &r {
            self.failed_moves.push(format!(
                "move_to ({:.2}, {:.2}) at {:.2} m: {e}",
                goal.x,
                goal.y,
                self.inner.odometry()
            ));
        }
        self.log();
        r
    }
    fn map_update(&mut self) -> MapUpdate {
        self.inner.map_update()
    }
    fn process_view_cone(
        &mut self,
        cone: &ViewCone,
        classes: &[String],
    ) -> ActionResult<ViewReport> {
        self.calls += 1;
        let r = self.inner.process_view_cone(cone, classes);
        self.log();
        r
    }
}

/// A finished search and what the robot recorded.
struct Run {
    report: SearchReport,
    track: Vec<(f64, [f64; 2])>,
    failed_moves: Vec<String>,
}

/// One search for the cerealbox, bounded by the agent's own budgets (at most
/// `AgentConfig::max_plans` plans and `max_actions` actions). `Agent::search` returning at all
/// is the "no hang" check; a panic fails the test.
fn search(world: &World, config: SimRobotConfig, seed: u64) -> Run {
    let inner = SimAgentRobot::new(world, knowledge(), config, seed).unwrap();
    let mut robot = Recorder {
        inner,
        track: Vec::new(),
        failed_moves: Vec::new(),
        calls: 0,
    };
    let mut agent = Agent::new(domain(), knowledge(), AgentConfig::default()).unwrap();
    let report = agent.search(&mut robot, Goal::find("cerealbox")).unwrap();
    // The budgets bound the robot calls too: every call belongs to one of at most
    // `max_actions` steps (waypoints of 0.5 m, views of a bounded session).
    assert!(robot.calls < 20_000, "{} robot calls", robot.calls);
    Run {
        report,
        track: robot.track,
        failed_moves: robot.failed_moves,
    }
}

/// Odometry at which the trajectory first stands in `room` (a ground-truth room name), or in
/// any room but the corridor when `room` is `None`, at least `clear` metres from every door
/// centre; with that room's name.
fn first_in_room(
    world: &World,
    track: &[(f64, [f64; 2])],
    room: Option<&str>,
    clear: f64,
) -> Option<(f64, String)> {
    track.iter().find_map(|&(odo, [x, y])| {
        let name = &world.env.rooms[world.room_at(x, y)?].name;
        let hit = match room {
            Some(r) => name == r,
            None => name != "corridor",
        };
        let away = world
            .env
            .doors
            .iter()
            .all(|d| (d.pose.x - x).hypot(d.pose.y - y) >= clear);
        (hit && away).then(|| (odo, name.clone()))
    })
}

fn close_kitchen_door_after(after_m: f64) -> SimRobotConfig {
    SimRobotConfig {
        door_events: vec![DoorEvent {
            door: "door_kitchen".into(),
            after_m,
            open: false,
        }],
        ..SimRobotConfig::default()
    }
}

fn tail(r: &SearchReport) -> String {
    let n = r.trace.len().saturating_sub(12);
    avs_agent::trace::render_text(&r.trace[n..])
}

/// The search ended with a verdict, and `found` agrees with it.
fn assert_verdict(r: &SearchReport, what: &str) {
    let last = r.trace.last();
    assert!(
        matches!(last, Some(Event::GoalReached { .. } | Event::GaveUp { .. })),
        "{what}: ends with {last:?}\n{}",
        tail(r)
    );
    assert_eq!(
        r.found.is_some(),
        matches!(last, Some(Event::GoalReached { .. })),
        "{what}"
    );
    if let Some(Event::GaveUp { reason }) = last {
        assert!(!reason.is_empty(), "{what}: gave up without a reason");
    }
}

/// Every failed action is followed by a new plan or by the verdict (the agent never carries on
/// with a plan whose step failed); returns how many actions failed.
fn assert_replans_after_failures(r: &SearchReport, what: &str) -> usize {
    let mut failures = 0;
    for (i, e) in r.trace.iter().enumerate() {
        if let Event::ActionFinished { outcome, .. } = e {
            if outcome.succeeded() {
                continue;
            }
            failures += 1;
            let next = r.trace[i + 1..].iter().find(|e| {
                matches!(
                    e,
                    Event::PlanMade { .. } | Event::GoalReached { .. } | Event::GaveUp { .. }
                )
            });
            assert!(
                next.is_some(),
                "{what}: no replan after the failure {outcome}\n{}",
                tail(r)
            );
        }
    }
    failures
}

/// Whether the agent replanned because the map changed under its plan (a placeholder or
/// door it planned through gone), or after seeing a door shut, once the robot had driven
/// `shut` metres.
fn replanned_on_map_change_after(r: &SearchReport, shut: f64) -> bool {
    let Some(from) = r.trace.iter().position(
        |e| matches!(e, Event::ActionFinished { path_length, .. } if *path_length >= shut),
    ) else {
        return false;
    };
    let after = &r.trace[from..];
    let map_changed = after.iter().any(|e| {
        matches!(e, Event::PlanMade { reason, .. }
            if reason.contains("map changed") || reason.contains("no longer holds"))
    });
    // Or the door was seen shut and a plan followed (its reason may be the assumption the
    // shut door contradicted: the placeholder behind it leads nowhere now).
    let seen_shut = after
        .iter()
        .position(|e| matches!(e, Event::DoorSeen { open: false, .. }));
    map_changed
        || seen_shut.is_some_and(|i| {
            after[i..]
                .iter()
                .any(|e| matches!(e, Event::PlanMade { .. }))
        })
}

/// Planar distance from the report to the nearest true cerealbox.
fn report_error(world: &World, r: &SearchReport) -> Option<f64> {
    let f = r.found.as_ref()?;
    world
        .objects_of_class("cerealbox")
        .map(|o| (f.pose.x - o.pose.x).hypot(f.pose.y - o.pose.y))
        .min_by(f64::total_cmp)
}

const SEEDS: [u64; 3] = [1, 2, 3];

/// A report within this planar distance of a true cerealbox is the box (the scorer's radius).
const SUCCESS_RADIUS: f64 = 1.0;

/// The kitchen door shuts 2 m of driving before the robot would first stand in the kitchen
/// (found from the same seed's undisturbed run: the runs are identical up to the door event),
/// so it shuts in front of the robot on its way in.
fn door_shut_in_front(world: &World, seed: u64) -> (Run, String, f64) {
    let free = search(world, SimRobotConfig::default(), seed);
    let (at, _) =
        first_in_room(world, &free.track, Some("kitchen"), 0.0).expect("enters the kitchen");
    let shut = (at - 2.0).max(0.0);
    let run = search(world, close_kitchen_door_after(shut), seed);
    let what = format!("seed {seed}, kitchen door shut at {shut:.2} m");
    eprintln!(
        "{what}:\n{}simulator refused: {:#?}",
        avs_agent::trace::render_text(&run.report.trace),
        run.failed_moves
    );
    (run, what, shut)
}

#[test]
fn kitchen_door_shutting_in_front_of_the_robot_ends_in_a_verdict_without_a_wrong_report() {
    let world = office();
    for seed in SEEDS {
        let (run, what, shut) = door_shut_in_front(&world, seed);
        let r = &run.report;
        assert_verdict(r, &what);
        assert_replans_after_failures(r, &what);
        // It ran into the shut door, or its laser saw the door shut from the last waypoint
        // before it and the agent replanned because the plan's way through had vanished.
        assert!(
            !run.failed_moves.is_empty() || replanned_on_map_change_after(r, shut),
            "{what}: the robot neither ran into the shut door nor replanned on seeing it"
        );
        // The cerealbox is behind the shut door: a report must be of the real box (seen
        // before the door shut), never a guess.
        if let Some(e) = report_error(&world, r) {
            assert!(
                e <= SUCCESS_RADIUS,
                "{what}: reported {e:.2} m from the box\n{}",
                tail(r)
            );
        }
    }
}

#[test]
fn kitchen_door_shutting_in_front_of_the_robot_shows_the_failure_and_a_replan_in_the_trace() {
    let world = office();
    for seed in SEEDS {
        let (run, what, shut) = door_shut_in_front(&world, seed);
        let r = &run.report;
        let failures = assert_replans_after_failures(r, &what);
        let mentioned = r.trace.iter().any(|e| match e {
            Event::PlanMade { reason, .. } => {
                reason.contains("Unreachable") || reason.contains("failed")
            }
            Event::Observed { what } => what.contains("Unreachable"),
            _ => false,
        });
        assert!(
            failures >= 1 || mentioned || replanned_on_map_change_after(r, shut),
            "{what}: the simulator refused {:?} but the trace shows no failure\n{}",
            run.failed_moves,
            tail(r)
        );
    }
}

#[test]
fn kitchen_door_shutting_while_the_robot_is_in_another_room_ends_in_a_verdict() {
    let world = office();
    for seed in SEEDS {
        // The first time this seed's undisturbed run stands in a room (not the corridor), 1 m
        // or more from every door.
        let free = search(&world, SimRobotConfig::default(), seed);
        let (at, room) = first_in_room(&world, &free.track, None, 1.0).expect("enters a room");
        let run = search(&world, close_kitchen_door_after(at), seed);
        let r = &run.report;
        let what = format!("seed {seed}, kitchen door shut at {at:.2} m in {room}");
        eprintln!("{what}:\n{}", avs_agent::trace::render_text(&r.trace));
        assert_verdict(r, &what);
        assert_replans_after_failures(r, &what);
        let error = report_error(&world, r);
        if room == "kitchen" {
            // Shut in with the box: nothing is out of reach.
            continue;
        }
        if let Some(e) = error {
            assert!(
                e <= SUCCESS_RADIUS,
                "{what}: reported {e:.2} m from the box\n{}",
                tail(r)
            );
        }
    }
}

/// Runs with doubled false alarms (`false_positive_scale` 2), with and without 10 % action
/// failures: every run ends in a verdict, and how many report a wrong object.
fn false_positive_runs(
    failures: FailureRates,
    seeds: std::ops::RangeInclusive<u64>,
) -> (usize, usize) {
    let world = office();
    let mut wrong = 0;
    let mut n = 0;
    for seed in seeds {
        let config = SimRobotConfig {
            detector: DetectorConfig {
                false_positive_scale: 2.0,
                ..DetectorConfig::default()
            },
            failures,
            ..SimRobotConfig::default()
        };
        let run = search(&world, config, seed);
        let r = &run.report;
        let what = format!("seed {seed}, failures {failures:?}");
        assert_verdict(r, &what);
        assert_replans_after_failures(r, &what);
        let error = report_error(&world, r);
        eprintln!(
            "{what}: {} plans, reported error {error:?}, {}",
            r.metrics.plans, r.reason
        );
        if error.is_some_and(|e| e > SUCCESS_RADIUS) {
            eprintln!("{what}: WRONG report\n{}", tail(r));
            wrong += 1;
        }
        n += 1;
    }
    (wrong, n)
}

// The bound: the issue asks that faults never crash or hang the agent and that wrong reports
// stay rare. "Rare" is read as a strict minority of the runs — fewer than half report an object
// more than 1 m from every true cerealbox. The bound comes from that demand, not from the runs:
// with the knowledge's false-alarm rate doubled to 0.1 per view a single look can still be
// fooled, but an agent that needs more than one look to commit must be right most of the time.
fn assert_wrong_reports_are_a_minority(wrong: usize, n: usize) {
    assert!(2 * wrong < n, "{wrong} of {n} runs reported a wrong object");
}

#[test]
fn doubled_false_positives_end_in_a_verdict_and_wrong_reports_stay_a_minority() {
    let (wrong, n) = false_positive_runs(FailureRates::default(), 1..=6);
    eprintln!("doubled false positives: {wrong} wrong reports in {n} runs");
    assert_wrong_reports_are_a_minority(wrong, n);
}

#[test]
fn doubled_false_positives_with_ten_percent_failures_end_in_a_verdict_and_wrong_reports_stay_a_minority(
) {
    let failures = FailureRates {
        motion: 0.1,
        view: 0.1,
    };
    let (wrong, n) = false_positive_runs(failures, 1..=6);
    eprintln!("doubled false positives + 10 % failures: {wrong} wrong reports in {n} runs");
    assert_wrong_reports_are_a_minority(wrong, n);
}

#[test]
fn closed_kitchen_door_reopened_by_an_event_lets_the_robot_into_the_kitchen() {
    // The kitchen door is closed in the environment and opens when the robot has driven 1 m.
    let path = shipped("domains/environments/office.yaml");
    let mut world = office();
    let i = world.door_index("door_kitchen").unwrap();
    world.env.doors[i].open = false;
    let world = World::new(world.env.clone(), path.parent().unwrap()).unwrap();
    let reopen = SimRobotConfig {
        door_events: vec![DoorEvent {
            door: "door_kitchen".into(),
            after_m: 1.0,
            open: true,
        }],
        ..SimRobotConfig::default()
    };
    for seed in SEEDS {
        let run = search(&world, reopen.clone(), seed);
        let r = &run.report;
        let what = format!("seed {seed}");
        assert_verdict(r, &what);
        let (at, _) = first_in_room(&world, &run.track, Some("kitchen"), 0.5)
            .unwrap_or_else(|| panic!("{what}: the robot got into the kitchen\n{}", tail(r)));
        assert!(
            at > 1.0,
            "{what}: in the kitchen only after the door opened"
        );
        eprintln!("{what}: in the kitchen at {at:.2} m; {}", r.reason);
    }
}

/// A robot whose wheels are dead: every motion is refused where it stands (the camera and
/// the laser still work).
struct Immobile<'w>(SimAgentRobot<'w>, usize);

impl Robot for Immobile<'_> {
    fn pose(&self) -> Pose2D {
        self.0.pose()
    }
    fn camera(&self) -> Camera {
        self.0.camera()
    }
    fn odometry(&self) -> f64 {
        self.0.odometry()
    }
    fn move_to(&mut self, _goal: Pose2D) -> ActionResult<MoveReport> {
        self.1 += 1;
        Err(avs_robot::ActionFailure::new(
            avs_robot::FailureReason::ExecutionFailed,
            "drive fault: the wheels do not turn",
        ))
    }
    fn map_update(&mut self) -> MapUpdate {
        self.0.map_update()
    }
    fn process_view_cone(
        &mut self,
        cone: &ViewCone,
        classes: &[String],
    ) -> ActionResult<ViewReport> {
        self.0.process_view_cone(cone, classes)
    }
}

/// Issue 18: a robot that cannot move gives up early, naming the cause (before, it spent the
/// plan budget and a whole coverage of refused motions, and said "every reachable room was
/// covered twice").
#[test]
fn a_robot_that_cannot_move_gives_up_early_and_says_so() {
    let world = office();
    let inner = SimAgentRobot::new(&world, knowledge(), SimRobotConfig::default(), 1).unwrap();
    let mut robot = Immobile(inner, 0);
    let config = AgentConfig::default();
    let limit = config.tuning.stuck_motions;
    let mut agent = Agent::new(domain(), knowledge(), config).unwrap();
    let report = agent.search(&mut robot, Goal::find("cerealbox")).unwrap();
    assert!(report.found.is_none());
    assert!(
        report.reason.contains("cannot move") && report.reason.contains("wheels do not turn"),
        "{}",
        report.reason
    );
    // The limit counts the motions of the plans' and the coverage's moves; turns in place
    // (look-arounds) are refused too and come on top.
    assert!(
        robot.1 <= 3 * limit,
        "{} motions tried for a limit of {limit}",
        robot.1
    );
    assert!(
        matches!(
            report.gave_up,
            Some(avs_agent::GiveUpReason::CannotMove { failures, .. }) if failures == limit
        ),
        "{:?}",
        report.gave_up
    );
}
