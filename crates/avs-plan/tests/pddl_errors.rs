//! Malformed PDDL gets an error naming where and what (issue 19): the line of a list that is
//! never closed, and a goal naming a predicate or object that does not exist (it used to read
//! as an unsolvable task: "no plan").

use avs_plan::pddl::{ground, parse_domain, parse_problem};

const DOMAIN: &str = "(define (domain d)
 (:requirements :strips)
 (:predicates (p ?x) (q ?x ?y))
 (:action a :parameters (?x) :precondition (p ?x) :effect (not (p ?x))))
";

fn ground_goal(goal: &str) -> String {
    let d = parse_domain("d.pddl", DOMAIN).unwrap();
    let text =
        format!("(define (problem t) (:domain d) (:objects a b) (:init (p a)) (:goal {goal}))");
    let p = parse_problem("p.pddl", &text).unwrap();
    match ground("d.pddl", &d, &p) {
        Ok(_) => String::new(),
        Err(e) => e.to_string(),
    }
}

#[test]
fn a_list_never_closed_is_named_by_the_line_it_opens_on() {
    let text = "(define (domain d)\n (:predicates (p ?x))\n (:action b :parameters (\n";
    let e = parse_domain("d.pddl", text).unwrap_err().to_string();
    assert!(
        e.contains("d.pddl") && e.contains("line 3") && e.contains("never closed"),
        "{e}"
    );
}

#[test]
fn a_goal_with_an_unknown_predicate_object_or_arity_is_an_error_not_an_unsolvable_task() {
    assert_eq!(
        ground_goal("(and (p a) (q a b))"),
        "",
        "a well-formed goal grounds"
    );
    let e = ground_goal("(p c)");
    assert!(e.contains("unknown object `c`"), "{e}");
    let e = ground_goal("(r a)");
    assert!(e.contains("unknown predicate `r`"), "{e}");
    let e = ground_goal("(q a)");
    assert!(e.contains("`q` takes 2 arguments"), "{e}");
    let e = ground_goal("(not (= a z))");
    assert!(e.contains("unknown object `z`"), "{e}");
}
