//! What validates runs (issue 18): random mutations of the shipped office, and for each one
//! either `avs validate`'s checks refuse it (and then building its world refuses it too: one
//! gate), or the world builds and a search on it ends, within the agent's budgets, in a report
//! or a clean error — never a panic.

use avs_agent::{Agent, AgentConfig, Goal};
use avs_format::environment::Environment;
use avs_format::knowledge::Knowledge;
use avs_plan::domain::Domain;
use avs_sim::sim_robot::{SimAgentRobot, SimRobotConfig};
use avs_sim::World;
use proptest::prelude::*;
use std::path::{Path, PathBuf};

fn shipped(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

/// A value for a mutated number: ordinary, extreme, or not a number.
fn number() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => -20.0f64..40.0,
        1 => prop::sample::select(vec![
            0.0, -0.0, 1e-9, -1.0, 1e6, -1e6, 1e19, -1e19, 1e308, f64::INFINITY,
            f64::NEG_INFINITY, f64::NAN,
        ]),
    ]
}

/// One mutation of an environment: which field, and the new number.
#[derive(Debug, Clone)]
enum Mutation {
    Start(usize, f64),
    Laser(usize, f64),
    Camera(usize, f64),
    ObjectPose(usize, usize, f64),
    ObjectSize(usize, usize, f64),
    DoorWidth(usize, f64),
    DoorYaw(usize, f64),
    DoorOpen(usize),
    RobotRadius(f64),
    RemoveObject(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (0usize..3, number()).prop_map(|(i, v)| Mutation::Start(i, v)),
        (0usize..3, number()).prop_map(|(i, v)| Mutation::Laser(i, v)),
        (0usize..8, number()).prop_map(|(i, v)| Mutation::Camera(i, v)),
        (0usize..64, 0usize..4, number()).prop_map(|(o, i, v)| Mutation::ObjectPose(o, i, v)),
        (0usize..64, 0usize..3, number()).prop_map(|(o, i, v)| Mutation::ObjectSize(o, i, v)),
        (0usize..16, number()).prop_map(|(d, v)| Mutation::DoorWidth(d, v)),
        (0usize..16, number()).prop_map(|(d, v)| Mutation::DoorYaw(d, v)),
        (0usize..16).prop_map(Mutation::DoorOpen),
        number().prop_map(Mutation::RobotRadius),
        (0usize..64).prop_map(Mutation::RemoveObject),
    ]
}

fn apply(env: &mut Environment, m: &Mutation) {
    let n_obj = env.objects.len().max(1);
    let n_door = env.doors.len().max(1);
    match *m {
        Mutation::Start(i, v) => match i {
            0 => env.robot.start.x = v,
            1 => env.robot.start.y = v,
            _ => env.robot.start.yaw_deg = v,
        },
        Mutation::Laser(i, v) => match i {
            0 => env.laser.range = v,
            1 => env.laser.fov_deg = v,
            _ => {
                env.laser.beams = if v.is_finite() {
                    v.abs().min(1e7) as usize
                } else {
                    0
                }
            }
        },
        Mutation::Camera(i, v) => match i {
            0 => env.camera.hfov_deg = v,
            1 => env.camera.vfov_deg = v,
            2 => env.camera.pan_deg[0] = v,
            3 => env.camera.pan_deg[1] = v,
            4 => env.camera.tilt_deg[0] = v,
            5 => env.camera.tilt_deg[1] = v,
            6 => env.camera.max_zoom = v,
            _ => env.camera.height = v,
        },
        Mutation::ObjectPose(o, i, v) => {
            if let Some(obj) = env.objects.get_mut(o % n_obj) {
                match i {
                    0 => obj.pose.x = v,
                    1 => obj.pose.y = v,
                    2 => obj.pose.z = v,
                    _ => obj.pose.yaw_deg = v,
                }
            }
        }
        Mutation::ObjectSize(o, i, v) => {
            if let Some(obj) = env.objects.get_mut(o % n_obj) {
                obj.size[i] = v;
            }
        }
        Mutation::DoorWidth(d, v) => {
            if let Some(door) = env.doors.get_mut(d % n_door) {
                door.width = v;
            }
        }
        Mutation::DoorYaw(d, v) => {
            if let Some(door) = env.doors.get_mut(d % n_door) {
                door.pose.yaw_deg = v;
            }
        }
        Mutation::DoorOpen(d) => {
            if let Some(door) = env.doors.get_mut(d % n_door) {
                door.open = !door.open;
            }
        }
        Mutation::RobotRadius(v) => env.robot.radius = v,
        Mutation::RemoveObject(o) => {
            if !env.objects.is_empty() {
                env.objects.remove(o % n_obj);
            }
        }
    }
}

/// Budgets small enough for a debug-build test, large enough to plan, move, look and cover.
fn small_budgets() -> AgentConfig {
    AgentConfig {
        max_plans: 4,
        plans_per_room: 0,
        max_actions: 25,
        actions_per_room: 0,
        max_cover_actions: 25,
        ..AgentConfig::default()
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn a_mutated_office_is_refused_by_both_gates_or_searched_to_a_verdict(
        mutations in prop::collection::vec(mutation(), 1..=3),
        seed in 0u64..1000,
    ) {
        let path = shipped("domains/environments/office.yaml");
        let knowledge: Knowledge = avs_format::load_yaml(&shipped("knowledge/office.yaml")).unwrap();
        let domain = Domain::load(&shipped("domains/object_search.yaml")).unwrap();
        let mut env: Environment = avs_format::load_yaml(&path).unwrap();
        for m in &mutations {
            apply(&mut env, m);
        }
        let base = path.parent().unwrap();
        let problems = avs_sim::check::check_environment("office.yaml", &env, base, Some(&knowledge));
        let built = World::new(env, base);
        if !problems.is_empty() {
            // Validation refused it: building its world must refuse it too.
            prop_assert!(built.is_err(), "validate refused {problems:?} but the world built");
            return Ok(());
        }
        let world = built.map_err(|e| TestCaseError::fail(format!("validates, yet: {e}")))?;
        let mut robot = SimAgentRobot::new(&world, knowledge.clone(), SimRobotConfig::default(), seed)
            .map_err(|e| TestCaseError::fail(format!("validates, yet the robot: {e}")))?;
        let mut agent = Agent::new(domain, knowledge, small_budgets()).unwrap();
        // Returning at all, with a report or a typed error, is the property; a panic fails.
        match agent.search(&mut robot, Goal::find("cerealbox")) {
            Ok(report) => prop_assert!(!report.reason.is_empty()),
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }
}
