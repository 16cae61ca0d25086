//! Grounding builds only what reachability keeps, and asks the caller's functions only for
//! operators that can be reached.

use avs_plan::continual::{ContinualOptions, ContinualPlanner};
use avs_plan::domain::Domain;
use avs_plan::problem::Problem;
use std::cell::RefCell;

/// Sorting items into bins: `color` is never written by any operator, so an item's colour is
/// fixed by the problem; only red items may be put away.
const SORT: &str = r#"
kind: domain
name: sort
types: [item, bin]
variables:
  color: { parameters: [item], values: [red, blue], default: red }
  in-bin: { parameters: [item], type: bin, values: [none], default: none }
operators:
  - name: put
    display: PUT ?i ?b
    parameters: ["?i: item", "?b: bin"]
    precondition: ["color(?i) = red", "in-bin(?i) = none"]
    effect: ["in-bin(?i) := ?b"]
    cost: effort(?i, ?b)
    probability: p-put(?i, ?b)
"#;

fn problem() -> Problem {
    Problem::new()
        .object("i1", "item")
        .object("i2", "item")
        .object("i3", "item")
        .object("b1", "bin")
        .object("b2", "bin")
        .init("color(i1) = blue")
        .init("color(i3) = blue")
        .goal("in-bin(i2) = b1")
}

#[test]
fn costs_and_probabilities_are_asked_only_for_operators_that_can_be_reached() {
    let planner = ContinualPlanner::new(
        Domain::from_yaml("sort.yaml", SORT).unwrap(),
        ContinualOptions::default(),
    );
    let calls = RefCell::new(Vec::new());
    let f = |name: &str, args: &[&str]| {
        calls
            .borrow_mut()
            .push(format!("{name}({})", args.join(", ")));
        // A blue item's functions are missing: asking for one would be an error.
        (args[0] == "i2").then_some(if name == "effort" { 2.0 } else { 0.5 })
    };
    let task = planner.ground(&problem(), &f).unwrap();
    let mut ops: Vec<String> = task.operators.iter().map(|o| o.display.clone()).collect();
    ops.sort();
    assert_eq!(ops, ["PUT i2 b1", "PUT i2 b2"]);
    let mut asked = calls.into_inner();
    asked.sort();
    assert_eq!(
        asked,
        [
            "effort(i2, b1)",
            "effort(i2, b2)",
            "p-put(i2, b1)",
            "p-put(i2, b2)"
        ],
        "only the red item's operators are evaluated"
    );
    let put = &task.operators[0];
    assert_eq!((put.cost, put.prob), (2.0, 0.5));
}

#[test]
fn a_missing_function_of_a_reachable_operator_is_still_an_error_naming_the_call() {
    let planner = ContinualPlanner::new(
        Domain::from_yaml("sort.yaml", SORT).unwrap(),
        ContinualOptions::default(),
    );
    let f = |name: &str, args: &[&str]| (name == "effort" || args[1] == "b1").then_some(0.5);
    let e = planner.ground(&problem(), &f).unwrap_err().to_string();
    assert!(e.contains("p-put(i2, b2)"), "{e}");
}
