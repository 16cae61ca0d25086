//! The agent searches the simulated default office end to end.

use avs_agent::trace::render_json_lines;
use avs_agent::{Agent, AgentConfig, Event, Goal, SearchReport};
use avs_format::knowledge::Knowledge;
use avs_plan::domain::Domain;
use avs_sim::sim_robot::{FailureRates, SimAgentRobot, SimRobotConfig};
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

/// One search in `world` with the robot's action failures `failures` and the agent's `config`;
/// the trace is printed for a failing test's output.
fn search_in(
    world: &World,
    seed: u64,
    failures: FailureRates,
    config: AgentConfig,
    goal: &str,
) -> SearchReport {
    let robot_config = SimRobotConfig {
        failures,
        ..SimRobotConfig::default()
    };
    search_by(world, seed, robot_config, config, goal)
}

/// One search in `world` by a simulated robot configured as `robot_config`.
fn search_by(
    world: &World,
    seed: u64,
    robot_config: SimRobotConfig,
    config: AgentConfig,
    goal: &str,
) -> SearchReport {
    let mut robot = SimAgentRobot::new(world, knowledge(), robot_config, seed).unwrap();
    let mut agent = Agent::new(domain(), knowledge(), config).unwrap();
    let report = agent.search(&mut robot, Goal::find(goal)).unwrap();
    eprint!("{}", avs_agent::trace::render_text(&report.trace));
    report
}

fn search(world: &World, seed: u64, failures: FailureRates, goal: &str) -> SearchReport {
    search_in(world, seed, failures, AgentConfig::default(), goal)
}

#[test]
fn default_search_finds_the_cerealbox_after_a_violated_assumption() {
    let world = World::load(&shipped("domains/environments/office.yaml")).unwrap();
    let r = search(&world, 1, FailureRates::default(), "cerealbox");
    let found = r.found.as_ref().expect("the cerealbox is found");
    assert_eq!(found.class, "cerealbox");
    let truth = world
        .env
        .objects
        .iter()
        .find(|o| o.id == "cerealbox1")
        .unwrap();
    let err = (found.pose.x - truth.pose.x).hypot(found.pose.y - truth.pose.y);
    assert!(
        err < 1.0,
        "reported {:?}, {err:.2} m from the truth",
        found.pose
    );
    assert!(matches!(r.trace.last(), Some(Event::GoalReached { .. })));
    assert!(r.metrics.plans >= 2, "at least one replan");
    assert!(
        r.trace
            .iter()
            .any(|e| matches!(e, Event::AssumptionViolated { .. })),
        "the trace shows a violated assumption"
    );
    // The first plan assumes a placeholder leads to a kitchen.
    let first = r.trace.iter().find_map(|e| match e {
        Event::PlanMade { steps, .. } => Some(steps.clone()),
        _ => None,
    });
    let first = first.expect("a plan was made");
    assert!(
        first[0].starts_with("ASSUME-LEADS-TO-ROOM") && first[0].ends_with("kitchen"),
        "{first:?}"
    );
    // Found through a verified candidate: the look around on entering the kitchen sees the
    // cereal box on its table (`AgentConfig::goal_in_look_around`), or a view-cone session does.
    assert_eq!(r.metrics.candidates_accepted, 1);
}

#[test]
fn same_seed_gives_byte_identical_json_trace() {
    let world = World::load(&shipped("domains/environments/office.yaml")).unwrap();
    let a = search(&world, 7, FailureRates::default(), "cerealbox");
    let b = search(&world, 7, FailureRates::default(), "cerealbox");
    let (ja, jb) = (render_json_lines(&a.trace), render_json_lines(&b.trace));
    assert!(ja.lines().count() > 5, "a real trace:\n{ja}");
    assert_eq!(ja, jb);
}

/// An edit of one line: the needle that finds it, and what the line becomes.
type LineEdit<'a> = (&'a str, &'a dyn Fn(&str) -> String);

/// The shipped office with each line containing an edit's needle replaced by
/// `edit(line)`; `name` names the edited file in errors.
fn office_edited(name: &str, edits: &[LineEdit]) -> World {
    let path = shipped("domains/environments/office.yaml");
    let mut text = std::fs::read_to_string(&path).unwrap();
    for (needle, edit) in edits {
        let line = text
            .lines()
            .find(|l| l.contains(needle))
            .unwrap_or_else(|| panic!("the shipped office has a line with `{needle}`"))
            .to_string();
        text = text.replace(&line, &edit(&line));
    }
    let env = avs_format::load_yaml_str(name, &text).unwrap();
    World::new(env, path.parent().unwrap()).unwrap()
}

fn close(line: &str) -> String {
    assert!(line.contains("open: true"));
    line.replace("open: true", "open: false")
}

fn office_with_closed_kitchen_door() -> World {
    office_edited(
        "office-closed-kitchen.yaml",
        &[("name: door_kitchen", &close)],
    )
}

#[test]
fn closed_kitchen_door_makes_the_agent_give_up_with_a_reason() {
    let world = office_with_closed_kitchen_door();
    let r = search(&world, 1, FailureRates::default(), "cerealbox");
    assert!(
        r.found.is_none(),
        "the cerealbox is behind a closed door: {:?}",
        r.found
    );
    match r.trace.last() {
        Some(Event::GaveUp { reason }) => {
            // No plan clears the success threshold, and covering what is left finds nothing.
            assert!(reason.contains("threshold"), "{reason}");
            assert!(
                reason.contains("every reachable room was covered"),
                "{reason}"
            );
            assert!(covered_after_giving_up(&r));
            assert_eq!(reason, &r.reason);
        }
        other => panic!("expected to give up, got {other:?}"),
    }
}

/// The office with the kitchen door closed and the cerealbox on the desk in office2: where the
/// knowledge makes it least likely (a cereal box on an office desk has no rate of its own). The
/// look-alike mug on office1's desk is taken out: this world tests coverage, not verification.
fn office_with_cerealbox_on_an_office_desk() -> World {
    let moved = |_: &str| {
        "  - { id: cerealbox1, class: cerealbox, role: target, room: office2, on: desk2, \
         pose: { x: 11.2, y: 7.3, z: 0.75 }, size: [0.2, 0.07, 0.3] }"
            .to_string()
    };
    office_edited(
        "office-cereal-on-desk.yaml",
        &[
            ("name: door_kitchen", &close),
            ("id: cerealbox1", &moved),
            ("id: mug2", &|_: &str| String::new()),
        ],
    )
}

fn search_with(world: &World, seed: u64, config: AgentConfig, goal: &str) -> SearchReport {
    search_in(world, seed, FailureRates::default(), config, goal)
}

fn covered_after_giving_up(r: &SearchReport) -> bool {
    r.trace
        .iter()
        .any(|e| matches!(e, Event::Observed { what } if what.contains("covering what no search")))
}

#[test]
fn a_target_the_plans_missed_is_found_by_covering_before_giving_up() {
    let world = office_with_cerealbox_on_an_office_desk();
    // One plan (into the kitchen, whose door is closed) spends the plan budget; the coverage
    // that follows goes through the rooms nearest first and finds the box on the office desk.
    let config = AgentConfig {
        max_plans: 1,
        plans_per_room: 0,
        ..AgentConfig::default()
    };
    let r = search_with(&world, 1, config, "cerealbox");
    assert!(
        covered_after_giving_up(&r),
        "no coverage phase: {}",
        r.reason
    );
    assert_eq!(r.metrics.plans, 1);
    let found = r
        .found
        .as_ref()
        .expect("the cerealbox is found by coverage");
    let err = (found.pose.x - 11.2).hypot(found.pose.y - 7.3);
    assert!(err < 1.0, "reported {:?}, {err:.2} m off", found.pose);
    assert!(matches!(r.trace.last(), Some(Event::GoalReached { .. })));
}

/// The office with the whiteboard marker dropped on the floor of office2, away from the
/// furniture: no unzoomed view can see it there (in range only closer than the camera can
/// tilt), and a verification look from close by would have it below the image.
fn office_with_a_marker_on_the_floor() -> World {
    let dropped = |_: &str| {
        "  - { id: whiteboardmarker1, class: whiteboardmarker, role: target, room: office2, \
         pose: { x: 9.0, y: 6.3, z: 0.0 }, size: [0.13, 0.02, 0.02] }"
            .to_string()
    };
    office_edited(
        "office-marker-on-the-floor.yaml",
        &[("id: whiteboardmarker1", &dropped)],
    )
}

/// Seeds a coverage test runs: a single seed pins the luck of one path (whether the detector
/// fires on the one look that passes the object, whether a verification look confirms it), so a
/// behaviour the coverage has is asserted as more often than not over these seeds. At 7839f66
/// (the paper's view greedy) the two coverage tests below found their object on 6 of these 8
/// seeds each; with the view planning weighing the walk, 7 (the marker) and 5 (the stapler).
const COVERAGE_SEEDS: std::ops::RangeInclusive<u64> = 1..=8;

/// Search `world` for `goal` on every seed of [`COVERAGE_SEEDS`] with two plans before the
/// coverage, check every report with `check(seed, report, found)`, and assert that the object is
/// found more often than not; `what` names it in the messages.
fn found_more_often_than_not(
    world: &World,
    goal: &str,
    what: &str,
    check: impl Fn(u64, &SearchReport, &avs_agent::FoundObject),
) {
    let mut found_on = Vec::new();
    for seed in COVERAGE_SEEDS {
        let config = AgentConfig {
            max_plans: 2,
            plans_per_room: 0,
            ..AgentConfig::default()
        };
        let r = search_with(world, seed, config, goal);
        assert!(covered_after_giving_up(&r), "seed {seed}: {}", r.reason);
        let Some(found) = r.found.as_ref() else {
            eprintln!("seed {seed}: the {what} is not found: {}", r.reason);
            continue;
        };
        check(seed, &r, found);
        found_on.push(seed);
    }
    let n = COVERAGE_SEEDS.count();
    assert!(
        2 * found_on.len() > n,
        "the {what} is found on {found_on:?} of {n} seeds: not more often than not"
    );
}

#[test]
fn a_small_object_on_the_floor_is_found_by_zoomed_coverage_and_verified() {
    let world = office_with_a_marker_on_the_floor();
    found_more_often_than_not(&world, "whiteboardmarker", "marker", |seed, r, found| {
        // Whatever is reported is the marker, on the floor.
        let err = (found.pose.x - 9.0).hypot(found.pose.y - 6.3);
        assert!(
            err < 0.6,
            "seed {seed}: reported {:?}, {err:.2} m off",
            found.pose
        );
        assert!(
            found.pose.z < 0.3,
            "seed {seed}: reported at height {}",
            found.pose.z
        );
        let zoomed = |e: &Event| match e {
            Event::ActionStarted { action } => action.contains(" zoom "),
            _ => false,
        };
        assert!(
            r.trace.iter().any(zoomed),
            "seed {seed}: no zoomed view in the coverage"
        );
        // The verification looks that confirmed it saw it.
        assert!(r.trace.iter().any(|e| matches!(
            e,
            Event::DtAction { action, detected: Some(true), .. } if action.starts_with("VERIFY")
        )));
    });
}

/// The office with office2's meeting table pushed against the corridor wall, east of the door,
/// and the stapler moved from office1's desk to the back of that table: the knowledge puts
/// staplers on desks (and in shelves) only, and the laser sees the table's sides, never the top
/// behind its front edge, so no known cell lies under the stapler.
fn office_with_a_stapler_at_the_back_of_a_table() -> World {
    let table = |_: &str| {
        "  - { id: table2, class: table, role: landmark, room: office2, \
         pose: { x: 11.15, y: 3.12 }, size: [1.2, 0.8, 0.75] }"
            .to_string()
    };
    let marker = |_: &str| {
        "  - { id: whiteboardmarker1, class: whiteboardmarker, role: target, room: office2, \
         on: table2, pose: { x: 11.4, y: 3.3, z: 0.75 }, size: [0.13, 0.02, 0.02] }"
            .to_string()
    };
    let stapler = |_: &str| {
        "  - { id: stapler1, class: stapler, role: target, room: office2, on: table2, \
         pose: { x: 10.9, y: 2.85, z: 0.75 }, size: [0.15, 0.04, 0.06] }"
            .to_string()
    };
    office_edited(
        "office-stapler-at-the-back-of-a-table.yaml",
        &[
            ("id: table2", &table),
            ("id: whiteboardmarker1", &marker),
            ("id: stapler1", &stapler),
        ],
    )
}

#[test]
fn a_stapler_at_the_back_of_a_table_in_a_room_first_entered_by_the_coverage_is_found() {
    // The two plans do not reach office2; it is first entered by the coverage, which looks
    // around there (without it the table stays unknown and its top unlooked) and finds the
    // stapler on the table, more often than not (see `COVERAGE_SEEDS`).
    let world = office_with_a_stapler_at_the_back_of_a_table();
    found_more_often_than_not(&world, "stapler", "stapler", |seed, _, found| {
        // Whatever is reported is the stapler, on the table.
        let err = (found.pose.x - 10.9).hypot(found.pose.y - 2.85);
        assert!(
            err < 0.6,
            "seed {seed}: reported {:?}, {err:.2} m off",
            found.pose
        );
        assert!(
            found.pose.z > 0.6,
            "seed {seed}: reported at height {}",
            found.pose.z
        );
    });
}

#[test]
fn without_coverage_the_planner_gives_up_at_the_threshold_as_in_the_paper() {
    let world = office_with_closed_kitchen_door();
    let config = AgentConfig {
        cover_before_giving_up: false,
        ..AgentConfig::default()
    };
    let r = search_with(&world, 1, config, "cerealbox");
    assert!(r.found.is_none(), "found {:?}", r.found);
    assert!(!covered_after_giving_up(&r));
    assert!(r.reason.contains("below the threshold"), "{}", r.reason);
    assert!(!r.reason.contains("covered"), "{}", r.reason);
}

#[test]
fn ten_percent_action_failures_never_crash_and_end_with_a_verdict() {
    let world = World::load(&shipped("domains/environments/office.yaml")).unwrap();
    let failures = FailureRates {
        motion: 0.1,
        view: 0.1,
    };
    for seed in 1..=3 {
        let r = search(&world, seed, failures, "cerealbox");
        let last = r.trace.last();
        assert!(
            matches!(last, Some(Event::GoalReached { .. } | Event::GaveUp { .. })),
            "seed {seed}: ends with {last:?}"
        );
        // Failed actions were reported in the trace, and replanned from.
        assert_eq!(
            r.found.is_some(),
            matches!(last, Some(Event::GoalReached { .. }))
        );
    }
}

#[test]
fn unknown_goal_class_is_an_error_naming_the_known_classes() {
    let world = World::load(&shipped("domains/environments/office.yaml")).unwrap();
    let mut robot = SimAgentRobot::new(&world, knowledge(), SimRobotConfig::default(), 1).unwrap();
    let mut agent = Agent::new(domain(), knowledge(), AgentConfig::default()).unwrap();
    let e = agent
        .search(&mut robot, Goal::find("unicorn"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("unicorn") && e.contains("cerealbox"), "{e}");
}

#[test]
fn bad_session_settings_are_errors_naming_the_field() {
    let error = |c: AgentConfig| {
        Agent::new(domain(), knowledge(), c)
            .unwrap_err()
            .to_string()
    };
    let d = AgentConfig::default();
    let e = error(AgentConfig {
        session_discount: 1.0,
        ..d.clone()
    });
    assert!(e.contains("session_discount"), "{e}");
    let mut rewards = d.session_rewards;
    rewards.wrong = f64::NAN;
    let e = error(AgentConfig {
        session_rewards: rewards,
        ..d.clone()
    });
    assert!(e.contains("session_rewards.wrong"), "{e}");
    let mut rewards = d.session_rewards;
    rewards.found = rewards.wrong - 1.0;
    let e = error(AgentConfig {
        session_rewards: rewards,
        ..d
    });
    assert!(e.contains("session_rewards.found"), "{e}");
}

#[test]
fn the_informed_reference_covers_the_room_it_was_told_first_and_beats_the_uninformed_path() {
    use avs_agent::Strategy;
    use avs_eval::episode::{run_episode, EpisodeSpec, Faults};
    let world = World::load(&shipped("domains/environments/office.yaml")).unwrap();
    let (k, d) = (knowledge(), domain());
    let run = |strategy: Strategy, seed: u64| {
        let spec = EpisodeSpec {
            knowledge: &k,
            domain: &d,
            goal: "cerealbox",
            seed,
            // The reference's coverage views are what this test is about: its look around
            // looks for landmarks only (with the goal, it sees the cereal box from the
            // kitchen door before any view).
            config: AgentConfig {
                strategy,
                goal_in_look_around: false,
                ..AgentConfig::default()
            },
            faults: Faults::default(),
            before: &[],
            find_all: false,
            place_classifier: false,
        };
        // Where the first coverage view was taken (the robot's pose after it).
        let mut first_view: Option<[f64; 3]> = None;
        let out = run_episode(&world, &spec, &mut |e: &Event| {
            if let Event::ActionFinished { action, pose, .. } = e {
                if action.starts_with("PROCESSVIEWCONE") && first_view.is_none() {
                    first_view = Some(*pose);
                }
            }
        })
        .unwrap();
        (out.summary, first_view)
    };
    // Over seeds 1–5: a single seed's coverage of the kitchen may miss the cerealbox and walk
    // on (seed 1: 102 m against the uninformed 72 m; seed 4 gives up after 178 m, the closer
    // looks rejecting each sighting), so the reference is judged by its median path.
    let (mut informed_paths, mut uninformed_paths) = (Vec::new(), Vec::new());
    let mut informed_found = 0;
    for seed in 1..=5 {
        let (informed, first) = run(Strategy::Informed, seed);
        let (uninformed, _) = run(Strategy::Uninformed, seed);
        // The kitchen holds the cerealbox: the informed reference's first view is taken there
        // (the uninformed strategy covers the corridor it starts in first).
        let [x, y, _] = first.expect("the informed reference took a view");
        let room = world
            .room_at(x, y)
            .map(|r| world.env.rooms[r].name.as_str());
        assert_eq!(
            room,
            Some("kitchen"),
            "seed {seed}: first view at ({x:.2}, {y:.2})"
        );
        informed_found += usize::from(informed.found);
        informed_paths.push(informed.path_length);
        uninformed_paths.push(uninformed.path_length);
    }
    // Told the room, the reference finds the cerealbox on most seeds.
    assert!(informed_found >= 3, "found on {informed_found} of 5 seeds");
    assert!(
        avs_eval::stats::median(&informed_paths) < avs_eval::stats::median(&uninformed_paths),
        "informed {informed_paths:.1?} m, uninformed {uninformed_paths:.1?} m"
    );
}

#[test]
fn the_informed_strategy_without_a_told_room_is_an_error_naming_it() {
    let world = World::load(&shipped("domains/environments/office.yaml")).unwrap();
    let mut robot = SimAgentRobot::new(&world, knowledge(), SimRobotConfig::default(), 1).unwrap();
    let config = AgentConfig {
        strategy: avs_agent::Strategy::Informed,
        ..AgentConfig::default()
    };
    let mut agent = Agent::new(domain(), knowledge(), config).unwrap();
    let e = agent
        .search(&mut robot, Goal::find("cerealbox"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("strategy") && e.contains("in_region"), "{e}");
}

#[test]
fn a_cerealbox_inside_a_kitchen_cupboard_is_found_by_a_search_in_the_cupboard() {
    // The shipped office with its kitchen's table taken out, a cupboard (a shelf, 1.8 m high)
    // against the kitchen's east wall, and the cerealbox on its middle level: the counter
    // makes the room a kitchen (a kitchen holding only a shelf reads as an office, and the
    // search rightly goes elsewhere first), and a search IN the cupboard (`002` §II-B.1's
    // L_o) looks where the box is.
    let path = shipped("domains/environments/office.yaml");
    let mut env: avs_format::environment::Environment = avs_format::load_yaml(&path).unwrap();
    env.objects.retain(|o| o.id != "table1" && o.id != "mug1");
    let mut cupboard = env
        .objects
        .iter()
        .find(|o| o.id == "shelf1")
        .expect("the office has a shelf")
        .clone();
    cupboard.id = "cupboard1".into();
    cupboard.room = "kitchen".into();
    cupboard.pose.x = 7.65;
    cupboard.pose.y = 4.5;
    cupboard.pose.yaw_deg = 90.0;
    let (cx, cy) = (cupboard.pose.x, cupboard.pose.y);
    env.objects.push(cupboard);
    let box1 = env
        .objects
        .iter_mut()
        .find(|o| o.id == "cerealbox1")
        .expect("the office has a cerealbox");
    box1.on = None;
    box1.r#in = Some("cupboard1".into());
    box1.pose.x = cx - 0.1;
    box1.pose.y = cy;
    box1.pose.z = 0.9;
    // The robot starts in the kitchen, in front of the cupboard. (From the corridor, a
    // search of the whole kitchen, which counts what the cupboard holds, is the better plan
    // per metre, and it finds the box through the open shelf.)
    env.robot.start.x = 6.0;
    env.robot.start.y = 5.5;
    env.robot.start.yaw_deg = 90.0;
    let world = World::new(env, path.parent().unwrap()).unwrap();
    // A detector as sharp at the image's border as at its centre: what the look-around finds
    // (the counter that makes the room a kitchen, the cupboard) is not what this test is
    // about, and with the default falloff it misses one of the two on some seeds.
    let mut robot_config = SimRobotConfig::default();
    robot_config.detector.angle_falloff = 0.0;
    // The search in the cupboard is what this test is about: the look around looks for
    // landmarks only (with the goal, it may see the box through the open shelf first).
    let config = AgentConfig {
        goal_in_look_around: false,
        ..AgentConfig::default()
    };
    let r = search_by(&world, 1, robot_config, config, "cerealbox");
    let found = r.found.as_ref().expect("the cerealbox is found");
    let err = (found.pose.x - cx + 0.1).hypot(found.pose.y - cy);
    assert!(err < 1.0, "reported {:?}, {err:.2} m off", found.pose);
    // The session that found it searched IN a landmark the agent had found (an object, not a
    // room), after an assumption that the box is in it.
    let inside = r.trace.iter().any(|e| match e {
        Event::PlanMade { steps, .. } => steps.iter().any(|s| {
            let w: Vec<&str> = s.split_whitespace().collect();
            matches!(w.as_slice(), ["ASSUME-OBJECT-EXISTS", "cerealbox", "IN", lm, "shelf", _]
                if lm.starts_with("object"))
        }),
        _ => false,
    });
    assert!(inside, "a plan assumes the cerealbox in the shelf");
    let found_by = r.trace.iter().rev().find_map(|e| match e {
        Event::DtSessionStarted { search, .. } => Some(search.clone()),
        _ => None,
    });
    let found_by = found_by.expect("a session ran");
    let w: Vec<&str> = found_by.split_whitespace().collect();
    assert!(
        matches!(w.as_slice(), ["SEARCHFOROBJECT", "cerealbox", "IN", lm, _] if lm.starts_with("object")),
        "the last session searched the cupboard: {found_by}"
    );
}
