//! The executive's tests: plans made and executed against scripted robots.

use super::*;
use crate::skills::testing;

/// An agent with the default settings over the shipped domain and knowledge.
fn default_agent() -> Agent {
    agent_with(AgentConfig::default())
}

/// An agent with `config` over the shipped domain and knowledge.
fn agent_with(config: AgentConfig) -> Agent {
    Agent::new(testing::domain(), testing::knowledge(), config).unwrap()
}

/// An agent with the default settings but `goal_in_look_around`.
fn agent_looking_around_for_the_goal(goal_in_look_around: bool) -> Agent {
    agent_with(AgentConfig {
        goal_in_look_around,
        ..AgentConfig::default()
    })
}

#[test]
fn a_domain_missing_an_operator_the_agent_executes_is_rejected_by_new_naming_it() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../domains/object_search.yaml"
    );
    let text = std::fs::read_to_string(path)
        .unwrap()
        .replace("  - name: createviewcones-on", "  - name: look-on-top");
    let domain = Domain::from_yaml("no-cones-on.yaml", &text).expect("still a valid domain");
    let e = Agent::new(domain, testing::knowledge(), AgentConfig::default()).unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, AgentError::Domain { .. }), "{msg}");
    assert!(
        msg.contains("operator `createviewcones-on` is missing"),
        "{msg}"
    );
    assert!(msg.contains("object-search"), "{msg}");
}

#[test]
fn an_agent_finds_an_object_in_a_known_room_with_a_scripted_robot() {
    let mut robot = testing::robot(testing::room(5.0, 4.0), [1.0, 1.0]);
    robot.place(testing::object("cerealbox", 3.6, 2.8, 0.14));
    // The planner's search: the look around looks for landmarks only.
    let mut agent = agent_looking_around_for_the_goal(false);
    let report = agent.search(&mut robot, Goal::find("cerealbox")).unwrap();
    let text = crate::trace::render_text(&report.trace);
    let f = report.found.unwrap_or_else(|| panic!("{text}"));
    assert!(f.pose.planar_distance(3.6, 2.8) < 1e-9, "{text}");
    assert!(report.gave_up.is_none());
    // Every metre driven is booked to one activity; the robot drove to view cones.
    let (by, total) = (report.metrics.path_by_activity, report.metrics.path_length);
    assert!((by.total() - total).abs() < 1e-9, "{by:?} vs {total}");
    assert!(by.view_cones > 0.0 && by.coverage == 0.0, "{by:?}");
    assert!(
        report.reason.starts_with("found cerealbox"),
        "{}",
        report.reason
    );
}

#[test]
fn a_run_of_moves_ends_at_its_last_target_past_assumptions_and_stops_at_other_steps() {
    let place = |x: f64| PlaceArg {
        name: format!("place{x}"),
        target: crate::memory::Target::Place(petgraph::graph::NodeIndex::new(0)),
        pos: Some([x, 0.0]),
        attach: None,
    };
    let mv = |x: f64| {
        Ok(Action::Move {
            to: place(x),
            pos: [x, 0.0],
        })
    };
    let report = Ok(Action::Report {
        object: "object0".into(),
        known: None,
    });
    assert_eq!(route_end(&[]), None);
    assert_eq!(route_end(&[report.clone(), mv(1.0)]), None);
    assert_eq!(
        route_end(&[mv(1.0), Ok(Action::Assume), mv(2.0), report, mv(3.0)]),
        Some([2.0, 0.0])
    );
}

#[test]
fn a_move_on_the_way_ends_where_the_route_passes_its_place_not_at_it() {
    let config = AgentConfig::default();
    let k = testing::knowledge();
    let mut robot = testing::robot(testing::room(6.0, 4.0), [1.0, 1.0]);
    let mem = testing::memory(&config, &k, &mut robot);
    let here = avs_robot::Robot::pose(&robot);
    // A place 2 m off the straight way from (1, 1) to (5, 1).
    let (via, end) = ([3.0, 3.0], [5.0, 1.0]);
    let p = passing_point(&mem, here, via, end);
    let d = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    // On the straight way (within the grid's steps), beside the place: no detour to it.
    assert!(
        (d([here.x, here.y], p) + d(p, end) - d([here.x, here.y], end)).abs() < 0.3,
        "{p:?} is off the way"
    );
    assert!((p[0] - via[0]).abs() < 0.3 && p[1] < 1.5, "{p:?}");
    // Without a way to the end, the place itself.
    assert_eq!(passing_point(&mem, here, via, [50.0, 50.0]), via);
}

/// Two 4 m × 4 m rooms side by side, a 0.9 m door at x = 4 m, the robot in the west one
/// with a laser that sees through the door: the memory knows the door hypothesis.
fn two_rooms() -> (AgentConfig, Knowledge, avs_robot::ScriptedRobot) {
    let (config, k) = (AgentConfig::default(), testing::knowledge());
    let robot = avs_robot::ScriptedRobot::with_laser(
        testing::two_rooms(),
        6.0,
        avs_robot::Pose2D::new(2.0, 2.0, 0.0),
        avs_robot::Camera::default(),
    );
    (config, k, robot)
}

#[test]
fn entering_a_placeholder_stops_a_step_past_the_last_door_on_the_way() {
    let (config, k, mut robot) = two_rooms();
    let mem = testing::memory(&config, &k, &mut robot);
    assert!(
        mem.wm
            .places
            .doors
            .iter()
            .any(|d| (d.hypothesis.center[0] - 4.0).abs() < 0.3),
        "the door is a hypothesis: {:?}",
        mem.wm.places.doors
    );
    let depth = config.tuning.enter_depth;
    // A frontier at the east room's far wall: the robot stops `depth` past the door.
    let p = entry_point(&mem, [2.0, 2.0], [7.5, 2.0], depth);
    assert!(
        p[0] > 4.0 + depth - 0.2 && p[0] < 4.0 + depth + 0.3,
        "{p:?}: not a step past the door"
    );
    // A frontier just past the door is the stop itself.
    assert_eq!(entry_point(&mem, [2.0, 2.0], [4.8, 2.0], depth), [4.8, 2.0]);
    // No door on the way: the target.
    assert_eq!(entry_point(&mem, [2.0, 2.0], [3.0, 3.0], depth), [3.0, 3.0]);
    // Through a door the robot has been through (into space it knows, say a corridor it
    // came along, to a frontier at its far end): the target.
    let mut mem = mem;
    for d in &mut mem.wm.places.doors {
        d.confirmed = true;
    }
    assert_eq!(entry_point(&mem, [2.0, 2.0], [7.5, 2.0], depth), [7.5, 2.0]);
}

/// The robot is told to enter a placeholder in the east room's far corner: it stops inside
/// the door, does not drive to the corner (the room is seen whole from there), and the
/// placeholder leads to the east room.
#[test]
fn a_room_seen_whole_from_inside_its_door_is_not_driven_into() {
    let (config, k, mut robot) = two_rooms();
    let mut mem = testing::memory(&config, &k, &mut robot);
    let from = mem.current_room().expect("a room");
    let binding = Binding::of(&mem, &k, "cerealbox");
    let (id, pos) = mem
        .phs
        .iter()
        .map(|(i, c)| (mem.registry[*i].id, c.pos))
        .filter(|(_, p)| p[0] > 4.2)
        .max_by(|a, b| a.1[0].total_cmp(&b.1[0]))
        .unwrap_or_else(|| panic!("no placeholder beyond the door: {:?}", mem.phs));
    assert!(
        pos[0] > 6.0,
        "the frontier is deep in the east room: {pos:?}"
    );
    let ph = binding.placeholder_arg(id);
    let mut sink = testing::sink();
    let mut run = testing::run(&mut sink);
    let cx = testing::ctx(&k, &config);
    let mut body = Body::new(&mut robot);
    let end = go(cx, &mut mem, &mut body, &mut run, &ph, pos, true).unwrap();
    assert!(matches!(end, StepEnd::Continue));
    let at = body.at();
    assert!(
        at[0] > 4.5 && at[0] < 4.0 + 2.0 * config.tuning.enter_depth,
        "{at:?}"
    );
    assert!(
        body.odometry() < 2.0 * (pos[0] - 2.0),
        "{} m driven",
        body.odometry()
    );
    let e = mem.registry.iter().find(|e| e.id == id).expect("tracked");
    let led = e
        .explored
        .and_then(|(_, led)| led)
        .expect("it led to a room");
    assert_ne!(mem.wm.room_of(led), Some(from), "{}", testing::text(&run));
}

#[test]
fn a_find_all_goal_verifies_what_earlier_looks_saw_of_its_class_before_it_plans() {
    let world = || {
        let mut robot = testing::robot(testing::room(5.0, 4.0), [1.0, 1.0]);
        robot.place(testing::object("cerealbox", 3.6, 2.8, 0.14));
        robot.place(testing::object("mug", 3.9, 2.5, 0.05));
        robot
    };
    let mut robot = world();
    let mut agent = default_agent();
    let goals = Goal::find_all(["cerealbox", "mug", "cerealbox"]);
    assert_eq!(goals.len(), 2, "duplicates are dropped");
    assert_eq!(goals[0].also, ["mug"]);
    assert!(goals[1].also.is_empty());
    let reports = agent.search_all(&mut robot, goals).unwrap();
    let text = |r: &SearchReport| crate::trace::render_text(&r.trace);
    for (r, (x, y)) in reports.iter().zip([(3.6, 2.8), (3.9, 2.5)]) {
        let f = r.found.as_ref().unwrap_or_else(|| panic!("{}", text(r)));
        assert!(f.pose.planar_distance(x, y) < 1e-9, "{}", text(r));
    }
    // The cereal box's looks asked for the mug too; the mug's search verified that
    // sighting and needed no plan and no view-cone session of its own.
    assert!(robot.calls().iter().any(|c| matches!(
        c,
        avs_robot::Call::View(_, classes) if classes.len() == 2 && classes.contains(&"mug".to_string())
    )));
    let mug = &reports[1];
    assert_eq!(
        (mug.metrics.plans, mug.metrics.dt_sessions),
        (0, 0),
        "{}",
        text(mug)
    );
    assert_eq!(mug.metrics.candidates_accepted, 1, "{}", text(mug));
    assert!(
        text(mug).contains("sighting(s) of mug by earlier looks"),
        "{}",
        text(mug)
    );

    // The same two goals on their own: the mug's search has to find it by its own looks
    // (its look around, which looks for the mug; without that, a planned search).
    for goal_in_look_around in [true, false] {
        let mut robot = world();
        let mut agent = agent_looking_around_for_the_goal(goal_in_look_around);
        agent.search(&mut robot, Goal::find("cerealbox")).unwrap();
        let alone = agent.search(&mut robot, Goal::find("mug")).unwrap();
        let t = text(&alone);
        assert!(alone.found.is_some(), "{t}");
        assert!(!t.contains("by earlier looks"), "{t}");
        assert_eq!(
            t.contains("sighting(s) of mug in the look around"),
            goal_in_look_around,
            "{t}"
        );
        assert_eq!(alone.metrics.dt_sessions > 0, !goal_in_look_around, "{t}");
    }
}

/// A target in view when the robot looks around is verified and reported then: no plan, no
/// view-cone session, the path spent on closer looks alone. Without the goal in the look
/// around the same world takes a planned search.
#[test]
fn a_target_in_view_of_the_look_around_is_verified_and_reported_without_a_plan() {
    for goal_in_look_around in [true, false] {
        let mut robot = testing::robot(testing::room(5.0, 4.0), [1.0, 1.0]);
        robot.place(testing::object("cerealbox", 3.6, 2.8, 0.14));
        let mut agent = agent_looking_around_for_the_goal(goal_in_look_around);
        let report = agent.search(&mut robot, Goal::find("cerealbox")).unwrap();
        let text = crate::trace::render_text(&report.trace);
        let f = report.found.unwrap_or_else(|| panic!("{text}"));
        assert!(f.pose.planar_distance(3.6, 2.8) < 1e-9, "{text}");
        let m = &report.metrics;
        if goal_in_look_around {
            assert_eq!((m.plans, m.dt_sessions), (0, 0), "{text}");
            assert_eq!(m.candidates_accepted, 1, "{text}");
            assert_eq!(m.path_by_activity.view_cones, 0.0, "{text}");
            assert!(
                text.contains("1 sighting(s) of cerealbox in the look around"),
                "{text}"
            );
        } else {
            assert!(m.plans > 0 && m.dt_sessions > 0, "{text}");
            assert!(!text.contains("in the look around"), "{text}");
        }
    }
}

#[test]
fn an_object_the_agent_already_knows_is_reported_by_one_plan_not_planned_again_and_again() {
    let mut robot = testing::robot(testing::room(5.0, 4.0), [1.0, 1.0]);
    robot.place(testing::object("cerealbox", 3.6, 2.8, 0.14));
    let mut agent = default_agent();
    let first = agent.search(&mut robot, Goal::find("cerealbox")).unwrap();
    assert!(first.found.is_some());
    // The same class again: the known cereal box is the goal's object.
    let again = agent.search(&mut robot, Goal::find("cerealbox")).unwrap();
    let text = crate::trace::render_text(&again.trace);
    let f = again.found.as_ref().unwrap_or_else(|| panic!("{text}"));
    assert!(f.pose.planar_distance(3.6, 2.8) < 1e-9, "{text}");
    assert_eq!(f.name, first.found.unwrap().name, "{text}");
    assert_eq!(
        (again.metrics.plans, again.metrics.dt_sessions),
        (1, 0),
        "{text}"
    );
    assert!(!text.contains("was not found"), "{text}");
    assert_eq!(text.matches("> REPORTPOSITION").count(), 1, "{text}");
}

#[test]
fn a_find_all_goal_naming_an_unknown_class_is_refused_naming_it() {
    let mut robot = testing::robot(testing::room(5.0, 4.0), [1.0, 1.0]);
    let mut agent = default_agent();
    let goals = Goal::find_all(["cerealbox", "unicorn"]);
    let e = agent.search(&mut robot, goals[0].clone()).unwrap_err();
    assert!(
        matches!(&e, AgentError::UnknownClass { class, .. } if class == "unicorn"),
        "{e}"
    );
}

#[test]
fn a_search_that_made_no_progress_is_not_planned_again_in_the_same_map() {
    let domain = testing::domain();
    // A detector that sees cereal boxes only from 5-6 cm: no pose in the room gives a view
    // cone that covers any point, so every search of the room looks at nothing.
    let mut k = testing::knowledge();
    let c = k
        .object_classes
        .iter_mut()
        .find(|c| c.name == "cerealbox")
        .unwrap();
    c.detection_range = [0.05, 0.06];
    let mut robot = testing::robot(testing::room(5.0, 4.0), [1.0, 1.0]);
    let mut agent = Agent::new(domain, k, AgentConfig::default()).unwrap();
    let report = agent.search(&mut robot, Goal::find("cerealbox")).unwrap();
    let text = crate::trace::render_text(&report.trace);
    assert!(text.contains("made no progress"), "{text}");
    let plans: Vec<(&str, &Vec<String>)> = report
        .trace
        .iter()
        .filter_map(|e| match e {
            Event::PlanMade { reason, steps, .. } => Some((reason.as_str(), steps)),
            _ => None,
        })
        .collect();
    for w in plans.windows(2) {
        if w[1].0.contains("made no progress") {
            assert_ne!(
                w[0].1, w[1].1,
                "the same plan again after no progress:\n{text}"
            );
        }
    }
    assert!(
        !matches!(report.gave_up, Some(GiveUpReason::PlanBudget { .. })),
        "{text}"
    );
    assert!(report.found.is_none());
}

/// With one plan allowed, but two per known room, a search of a two-room map that finds
/// nothing plans more than once and stops at the budget of the rooms it knows.
#[test]
fn the_plan_budget_grows_with_the_rooms_the_robot_knows() {
    use avs_robot::{Camera, Pose2D, ScriptedRobot};
    let domain = testing::domain();
    let mut robot = ScriptedRobot::with_laser(
        testing::two_rooms(),
        3.5,
        Pose2D::new(2.0, 2.0, 0.0),
        Camera::default(),
    );
    let mut config = AgentConfig {
        max_plans: 1,
        plans_per_room: 2,
        cover_before_giving_up: false,
        ..AgentConfig::default()
    };
    // A reward that pays for any plan: without coverage the search would otherwise stop once
    // no plan is worth its cost, before the budget this test is about.
    config.planner.search.reward = 1e9;
    let mut agent = Agent::new(domain, testing::knowledge(), config.clone()).unwrap();
    let report = agent.search(&mut robot, Goal::find("cerealbox")).unwrap();
    let text = crate::trace::render_text(&report.trace);
    assert!(report.found.is_none(), "{text}");
    assert!(report.metrics.plans > config.max_plans, "{text}");
    if let Some(GiveUpReason::PlanBudget { plans, .. }) = &report.gave_up {
        // Two rooms at most: the budget never went past four.
        assert!(*plans <= config.plan_budget(2), "{text}");
    }
}
