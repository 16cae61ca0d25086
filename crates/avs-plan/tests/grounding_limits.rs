//! Issue 18: grounding is bounded (operators, facts, estimated bytes, bindings tried) and the
//! error names the operator (or variable) that passed a limit.

use avs_plan::continual::ContinualPlanner;
use avs_plan::domain::Domain;
use avs_plan::limits::{GroundingLimits, GroundingResource};
use avs_plan::problem::Problem;
use avs_plan::{pddl, PlanError};

/// Gripper (IPC 1998) with `EXTRA` unused parameters appended to `move`.
fn gripper(extra: usize) -> String {
    let unused: String = (1..=extra).map(|i| format!(" ?u{i}")).collect();
    format!(
        "(define (domain gripper-strips)
   (:predicates (room ?r) (ball ?b) (gripper ?g) (at-robby ?r) (at ?b ?r) (free ?g) (carry ?o ?g))
   (:action move
       :parameters (?from ?to{unused})
       :precondition (and (room ?from) (room ?to) (at-robby ?from))
       :effect (and (at-robby ?to) (not (at-robby ?from))))
   (:action pick
       :parameters (?obj ?room ?gripper)
       :precondition (and (ball ?obj) (room ?room) (gripper ?gripper)
                          (at ?obj ?room) (at-robby ?room) (free ?gripper))
       :effect (and (carry ?obj ?gripper) (not (at ?obj ?room)) (not (free ?gripper))))
   (:action drop
       :parameters (?obj ?room ?gripper)
       :precondition (and (ball ?obj) (room ?room) (gripper ?gripper)
                          (carry ?obj ?gripper) (at-robby ?room))
       :effect (and (at ?obj ?room) (free ?gripper) (not (carry ?obj ?gripper)))))"
    )
}

/// Gripper's prob01: two rooms, four balls, two grippers (8 objects).
const PROB01: &str = "(define (problem strips-gripper-x-1)
   (:domain gripper-strips)
   (:objects rooma roomb ball4 ball3 ball2 ball1 left right)
   (:init (room rooma) (room roomb) (ball ball4) (ball ball3) (ball ball2) (ball ball1)
          (at-robby rooma) (free left) (free right)
          (at ball4 rooma) (at ball3 rooma) (at ball2 rooma) (at ball1 rooma)
          (gripper left) (gripper right))
   (:goal (and (at ball4 roomb) (at ball3 roomb) (at ball2 roomb) (at ball1 roomb))))";

fn ground(extra: usize, limits: &GroundingLimits) -> Result<avs_plan::Task, PlanError> {
    let d = pddl::parse_domain("gripper.pddl", &gripper(extra)).unwrap();
    let p = pddl::parse_problem("prob01.pddl", PROB01).unwrap();
    pddl::ground_with("gripper.pddl", &d, &p, limits)
}

/// The reproducer: `move` with 8 extra unused parameters has 2 × 2 × 8⁸ ≈ 6.7·10⁷ groundings;
/// grounding ran past 40 s and 1.8 GB. It now stops at the operator limit and says which
/// action exploded.
#[test]
fn gripper_move_with_unused_parameters_stops_at_the_limit_naming_move() {
    let e = ground(8, &GroundingLimits::default()).unwrap_err();
    match &e {
        PlanError::GroundingLimit {
            what,
            resource,
            limit,
        } => {
            assert_eq!(what, "action `move`");
            assert_eq!(*resource, GroundingResource::Operators);
            assert_eq!(*limit, 1_000_000);
        }
        other => panic!("expected a grounding limit, got {other:?}"),
    }
    let text = e.to_string();
    assert!(
        text.starts_with(
            "grounding action `move` passed the limit of 1000000 ground operators; expected"
        ),
        "{text}"
    );
    // Plain gripper grounds as before: 4 moves, 16 picks, 16 drops.
    let task = ground(0, &GroundingLimits::default()).unwrap();
    assert_eq!(task.operators.len(), 36);
}

#[test]
fn each_resource_has_its_limit() {
    let plain = GroundingLimits::default();
    let cases = [
        (
            GroundingLimits {
                max_operators: 20,
                ..plain
            },
            GroundingResource::Operators,
        ),
        (
            GroundingLimits {
                max_facts: 20,
                ..plain
            },
            GroundingResource::Facts,
        ),
        (
            GroundingLimits {
                max_bytes: 4_000,
                ..plain
            },
            GroundingResource::Bytes,
        ),
        (
            GroundingLimits {
                max_bindings: 50,
                ..plain
            },
            GroundingResource::Bindings,
        ),
    ];
    for (limits, want) in cases {
        match ground(0, &limits) {
            Err(PlanError::GroundingLimit { resource, what, .. }) => {
                assert_eq!(resource, want, "{what}");
                assert!(what.starts_with("action `") || what.starts_with("the initial"));
            }
            other => panic!("{want:?}: expected a grounding limit, got {other:?}"),
        }
    }
}

/// YAML domains are grounded within the same limits: an operator with five free parameters
/// over 40 places, and a state variable with five parameters, are each named.
#[test]
fn yaml_domains_name_the_operator_or_variable_that_exploded() {
    let domain = |op_params: &str, var_params: &str| {
        format!(
            r#"
kind: domain
name: wide
types: [place]
variables:
  robot-at: {{ type: place }}
  seen: {{ parameters: [{var_params}], values: ["no", "yes"], default: "no" }}
  done: {{ values: ["no", "yes"], default: "no" }}
operators:
  - name: wander
    parameters: [{op_params}]
    precondition: ["robot-at = ?a"]
    effect: ["done := yes"]
"#
        )
    };
    let mut problem = Problem::new().init("robot-at = p0").goal("done = yes");
    for i in 0..40 {
        problem = problem.object(&format!("p{i}"), "place");
    }
    let f = |_: &str, _: &[&str]| None;
    let ground = |text: &str| {
        let d = Domain::from_yaml("wide.yaml", text).unwrap();
        ContinualPlanner::new(d, Default::default()).ground(&problem, &f)
    };
    let free5 = r#""?a: place", "?b: place", "?c: place", "?d: place", "?e: place""#;
    match ground(&domain(free5, "place")) {
        Err(PlanError::GroundingLimit { what, resource, .. }) => {
            assert_eq!(what, "operator `wander`");
            assert_eq!(resource, GroundingResource::Operators);
        }
        other => panic!("expected a grounding limit, got {other:?}"),
    }
    match ground(&domain(r#""?a: place""#, "place, place, place, place")) {
        Err(PlanError::GroundingLimit { what, resource, .. }) => {
            assert_eq!(what, "variable `seen`");
            assert_eq!(resource, GroundingResource::Facts);
        }
        other => panic!("expected a grounding limit, got {other:?}"),
    }
    assert!(ground(&domain(r#""?a: place""#, "place")).is_ok());
}
