//! The object-search domain on the default environment: the first plan, and scripted
//! replanning when an assumption fails, when a room turns out to be an office, and when every
//! option falls below the success threshold.

mod common;

use avs_plan::continual::{
    ContinualOptions, ContinualPlanner, Decision, GiveUp, Objective, Replan, Verdict,
};
use avs_plan::lifted::validate_steps;
use avs_plan::problem::Problem;
use common::*;
use std::collections::HashMap;

fn planner() -> ContinualPlanner {
    ContinualPlanner::new(object_search_domain(), ContinualOptions::default())
}

fn functions(xy: &HashMap<String, (f64, f64)>) -> impl Fn(&str, &[&str]) -> Option<f64> + '_ {
    move |n: &str, a: &[&str]| stand_in(n, a, xy)
}

fn plan_of(d: Decision) -> avs_plan::continual::ActivePlan {
    match d {
        Decision::Plan(p) => p,
        other => panic!("expected a plan, got {other:?}"),
    }
}

fn lines(p: &avs_plan::continual::ActivePlan) -> Vec<String> {
    p.steps.iter().map(|s| s.display.clone()).collect()
}

fn steps_of(p: &avs_plan::continual::ActivePlan) -> Vec<(String, Vec<String>)> {
    p.steps
        .iter()
        .map(|s| (s.schema.clone(), s.args.clone()))
        .collect()
}

#[test]
fn first_plan_in_default_environment_has_the_shape_of_the_papers_first_listing() {
    let w = office_start(3, &LABELS, "cerealbox");
    let pl = planner();
    let f = functions(&w.xy);
    let plan = plan_of(pl.plan(&w.problem, &f).unwrap());
    assert_eq!(
        lines(&plan),
        [
            "ASSUME-LEADS-TO-ROOM place1 kitchen",
            "ASSUME-OBJECT-EXISTS table IN new-room1 kitchen",
            "ASSUME-OBJECT-EXISTS cerealbox ON new-object1 table kitchen",
            "MOVE place1",
            "CREATEVIEWCONES table IN new-room1",
            "SEARCHFOROBJECT table IN new-room1 new-object1",
            "CREATEVIEWCONES cerealbox ON new-object1",
            "SEARCHFOROBJECT cerealbox ON new-object1 new-object2",
            "REPORTPOSITION new-object2",
        ]
    );
    assert!(plan.steps[..3].iter().all(|s| s.assumption));
    // The independent lifted validator accepts it with the same cost and probability.
    let v = validate_steps(&pl.domain, &w.problem, &steps_of(&plan), &f).unwrap();
    assert!((v.cost - plan.cost).abs() < 1e-9 && (v.prob - plan.probability).abs() < 1e-12);
    // p = P(kitchen | place1) · P(table | kitchen) · P(cerealbox on table | kitchen) · 0.8²
    assert!((plan.probability - 0.3 * 0.9 * 0.5 * 0.8 * 0.8).abs() < 1e-12);
    assert!((plan.objective - (plan.cost + 1000.0 * (1.0 - plan.probability))).abs() < 1e-9);
}

#[test]
fn fast_mode_plan_is_valid_but_may_be_worse() {
    let w = office_start(3, &LABELS, "cerealbox");
    let mut opts = ContinualOptions::default();
    opts.search.mode = avs_plan::Mode::Fast;
    let fast = ContinualPlanner::new(object_search_domain(), opts);
    let f = functions(&w.xy);
    let pf = plan_of(fast.plan(&w.problem, &f).unwrap());
    let po = plan_of(planner().plan(&w.problem, &f).unwrap());
    validate_steps(&fast.domain, &w.problem, &steps_of(&pf), &f).unwrap();
    assert!(pf.objective >= po.objective - 1e-9);
}

/// After executing `plan` through its MOVE onto a placeholder, the world as the robot now knows it.
fn after_move(start: &Problem, at: &str, updates: &[&str]) -> Problem {
    let mut p = start.clone().set(&format!("robot-at = {at}"));
    for u in updates {
        p = if u.contains('=') { p.set(u) } else { p };
    }
    p
}

#[test]
fn scripted_replanning_first_assumption_fails_room_is_an_office_then_give_up() {
    let pl = planner();
    let w = office_start(3, &LABELS, "cerealbox");
    let f = functions(&w.xy);

    // Plan 1 assumes place1 leads to a kitchen.
    let p1 = plan_of(pl.plan(&w.problem, &f).unwrap());
    eprintln!("plan 1:\n{}", p1.listing());
    assert_eq!(p1.steps[0].display, "ASSUME-LEADS-TO-ROOM place1 kitchen");
    let move1 = p1
        .steps
        .iter()
        .position(|s| s.display == "MOVE place1")
        .unwrap();
    // Before anything changes, the monitor says continue.
    assert_eq!(
        pl.monitor(&p1, 0, &w.problem, &f).unwrap(),
        Verdict::Continue
    );

    // The robot reaches place1: it leads nowhere new (the first assumption fails).
    let s1 = after_move(
        &w.problem,
        "place1",
        &["leads-to(place1) = none", "open-placeholders(room0) = n3"],
    );
    let v1 = pl.monitor(&p1, move1 + 1, &s1, &f).unwrap();
    if let Verdict::Replan(r) = &v1 {
        eprintln!("replan: {r}");
    }
    let Verdict::Replan(Replan::AssumptionContradicted {
        step,
        assumed,
        actual,
        ..
    }) = &v1
    else {
        panic!("expected a contradicted assumption, got {v1:?}")
    };
    assert_eq!(*step, 0);
    assert_eq!(assumed, "leads-to(place1) = new-room1");
    assert_eq!(actual, "leads-to(place1) = none");

    // Plan 2 turns to the next door.
    let p2 = plan_of(pl.plan(&s1, &f).unwrap());
    eprintln!("plan 2:\n{}", p2.listing());
    assert_eq!(p2.steps[0].display, "ASSUME-LEADS-TO-ROOM place2 kitchen");
    assert!(lines(&p2).contains(&"MOVE place2".to_string()));
    validate_steps(&pl.domain, &s1, &steps_of(&p2), &f).unwrap();

    // The robot enters through place2 into a new room, room1, which turns out to be an office.
    let move2 = p2
        .steps
        .iter()
        .position(|s| s.display == "MOVE place2")
        .unwrap();
    let s2 = after_move(&s1, "place2", &[])
        .object("room1", "room")
        .set("leads-to(place2) = room1")
        .set("robot-room = room1")
        .set("category(room1) = office");
    let v2 = pl.monitor(&p2, move2 + 1, &s2, &f).unwrap();
    if let Verdict::Replan(r) = &v2 {
        eprintln!("replan: {r}");
    }
    let Verdict::Replan(Replan::AssumptionContradicted {
        assumed, actual, ..
    }) = &v2
    else {
        panic!("expected the kitchen assumption to be contradicted, got {v2:?}")
    };
    // The virtual room was matched to room1 before the category was compared.
    assert_eq!(assumed, "category(room1) = kitchen");
    assert_eq!(actual, "category(room1) = office");

    // Plan 3 tries the last door.
    let p3 = plan_of(pl.plan(&s2, &f).unwrap());
    eprintln!("plan 3:\n{}", p3.listing());
    assert_eq!(p3.steps[0].display, "ASSUME-LEADS-TO-ROOM place3 kitchen");
    validate_steps(&pl.domain, &s2, &steps_of(&p3), &f).unwrap();

    // The conceptual map now thinks new rooms very unlikely and cereal boxes rare everywhere:
    // every option falls below the 1 % threshold, so the planner gives up.
    let xy = w.xy.clone();
    let bleak = move |n: &str, a: &[&str]| match n {
        "p-leads-to-room" | "p-category" => Some(0.001),
        "p-object-in" | "p-object-on" => stand_in(n, a, &xy).map(|p| p * 0.1),
        _ => stand_in(n, a, &xy),
    };
    let v3 = pl.monitor(&p3, 0, &s2, &bleak).unwrap();
    if let Verdict::Replan(r) = &v3 {
        eprintln!("replan: {r}");
    }
    assert!(
        matches!(
            v3,
            Verdict::Replan(Replan::AssumptionUnlikely { step: 0, .. })
        ),
        "{v3:?}"
    );
    match pl.plan(&s2, &bleak).unwrap() {
        Decision::GiveUp(g @ GiveUp::TooUnlikely { best, threshold }) => {
            eprintln!("give up: {g}");
            assert_eq!(threshold, 0.01);
            assert!(best.is_some_and(|p| p < threshold), "{best:?}");
        }
        other => panic!("expected to give up, got {other:?}"),
    }
}

#[test]
fn monitor_reports_failed_preconditions_and_reached_goals() {
    let pl = planner();
    let w = office_start(3, &LABELS, "cerealbox");
    let f = functions(&w.xy);
    let p1 = plan_of(pl.plan(&w.problem, &f).unwrap());
    // The robot was pushed to the east end of the corridor: MOVE place1 no longer applies.
    let moved = w.problem.clone().set("robot-at = place6");
    let v = pl.monitor(&p1, 3, &moved, &f).unwrap();
    assert!(
        matches!(&v, Verdict::Replan(Replan::PreconditionFailed { action, condition, .. })
            if action == "MOVE place1" && condition.contains("robot-at")),
        "{v:?}"
    );
    let done = w.problem.clone().set("reported(cerealbox) = yes");
    assert_eq!(pl.monitor(&p1, 3, &done, &f).unwrap(), Verdict::GoalReached);
    assert_eq!(pl.plan(&done, &f).unwrap(), Decision::GoalReached);
}

#[test]
fn a_search_that_gives_up_stops_once_no_plan_pays_its_cost() {
    let w = office_start(3, &LABELS, "cerealbox");
    let f = functions(&w.xy);
    for objective in [Objective::Fixed, Objective::Ratio] {
        // The best plan for the default R, and rewards around the one at which it just pays.
        let best = plan_of(planner().plan(&w.problem, &f).unwrap());
        let pays_at = best.cost / best.probability;
        for factor in [0.25, 0.5, 0.9, 1.1, 2.0, 8.0] {
            let reward = pays_at * factor;
            let with = |on: bool| {
                let mut o = ContinualOptions {
                    give_up_unless_worth_it: on,
                    objective,
                    ..ContinualOptions::default()
                };
                o.search.reward = reward;
                ContinualPlanner::new(object_search_domain(), o)
                    .plan(&w.problem, &f)
                    .unwrap()
            };
            // The oracle: the plan that is best for R by the paper's objective, found without
            // the rule, pays its cost exactly when the rule keeps planning.
            let mut fixed = ContinualOptions::default();
            fixed.search.reward = reward;
            let oracle = plan_of(
                ContinualPlanner::new(object_search_domain(), fixed)
                    .plan(&w.problem, &f)
                    .unwrap(),
            );
            let pays = oracle.probability * reward > oracle.cost;
            match with(true) {
                Decision::Plan(p) => {
                    assert!(
                        pays,
                        "{objective:?} R = {reward}: planned though no plan pays"
                    );
                    assert!(
                        p.probability * reward > p.cost,
                        "{objective:?} R = {reward}"
                    );
                }
                Decision::GiveUp(
                    g @ GiveUp::NotWorthIt {
                        probability,
                        cost,
                        reward: r,
                    },
                ) => {
                    assert!(
                        !pays,
                        "{objective:?} R = {reward}: gave up ({g}) though a plan pays"
                    );
                    assert_eq!(r, reward);
                    assert!(probability * r <= cost);
                    assert!(g.to_string().contains("threshold"), "{g}");
                }
                other => panic!("{objective:?} R = {reward}: {other:?}"),
            }
            // Without the rule the planner plans whatever R is.
            assert!(matches!(with(false), Decision::Plan(_)));
        }
        // A reward far below the plan's cost per probability gives up; far above, it plans.
        let mut o = ContinualOptions {
            give_up_unless_worth_it: true,
            objective,
            ..ContinualOptions::default()
        };
        o.search.reward = pays_at * 0.01;
        let low = ContinualPlanner::new(object_search_domain(), o).plan(&w.problem, &f);
        assert!(
            matches!(low, Ok(Decision::GiveUp(GiveUp::NotWorthIt { .. }))),
            "{low:?}"
        );
        o.search.reward = pays_at * 100.0;
        let high = ContinualPlanner::new(object_search_domain(), o).plan(&w.problem, &f);
        assert!(matches!(high, Ok(Decision::Plan(_))), "{high:?}");
    }
}

#[test]
fn no_plan_at_all_gives_up_saying_so() {
    let pl = planner();
    // A world without placeholders and a corridor known to be a corridor with nothing in it.
    let p = Problem::new()
        .object("room0", "room")
        .object("corridor", "category")
        .object("cerealbox", "label")
        .object("place0", "place")
        .fact("in-room(place0, room0)")
        .init("robot-at = place0")
        .init("robot-room = room0")
        .init("category(room0) = corridor")
        .goal("reported(cerealbox) = yes");
    let f = |n: &str, _: &[&str]| match n {
        "p-object-in" | "p-object-on" => Some(0.0),
        _ => Some(0.5),
    };
    assert_eq!(pl.plan(&p, &f).unwrap(), Decision::GiveUp(GiveUp::NoPlan));
}

#[test]
fn missing_or_invalid_functions_are_errors_naming_the_call() {
    let pl = planner();
    let w = office_start(3, &LABELS, "cerealbox");
    let none = |_: &str, _: &[&str]| None;
    let e = pl.plan(&w.problem, &none).unwrap_err().to_string();
    assert!(e.contains("not supplied"), "{e}");
    let xy = w.xy.clone();
    let nan = move |n: &str, a: &[&str]| {
        if n == "p-category" {
            Some(f64::NAN)
        } else {
            stand_in(n, a, &xy)
        }
    };
    let e = pl.plan(&w.problem, &nan).unwrap_err().to_string();
    assert!(e.contains("p-category"), "{e}");
    let bad = w.problem.clone().init("category(room9) = kitchen");
    assert!(pl.plan(&bad, &f_unused).is_err());
}

fn f_unused(_: &str, _: &[&str]) -> Option<f64> {
    Some(1.0)
}

#[test]
fn monitor_matches_the_virtual_room_to_the_real_one_and_continues_when_assumptions_hold() {
    let pl = planner();
    let w = office_start(3, &LABELS, "cerealbox");
    let f = functions(&w.xy);
    let p1 = plan_of(pl.plan(&w.problem, &f).unwrap());
    let move1 = p1
        .steps
        .iter()
        .position(|s| s.display == "MOVE place1")
        .unwrap();
    // Through place1 the robot finds room1, and it is a kitchen, as assumed.
    let s = w
        .problem
        .clone()
        .object("room1", "room")
        .set("robot-at = place1")
        .set("robot-room = room1")
        .set("leads-to(place1) = room1")
        .set("category(room1) = kitchen");
    assert_eq!(
        pl.monitor(&p1, move1 + 1, &s, &f).unwrap(),
        Verdict::Continue
    );
    // Had it been an office with no placeholders left, the category would contradict.
    let office = s.clone().set("category(room1) = office");
    assert!(matches!(
        pl.monitor(&p1, move1 + 1, &office, &f).unwrap(),
        Verdict::Replan(Replan::AssumptionContradicted { .. })
    ));
}

/// The default environment with `rooms` known rooms of unknown category off the corridor (one
/// place each) and, in the first, a table already found.
fn office_with_rooms(rooms: usize, target: &str) -> (Problem, HashMap<String, (f64, f64)>) {
    let w = office_start(6, &LABELS[..5], target);
    let (mut p, mut xy) = (w.problem, w.xy);
    for k in 1..=rooms {
        let (room, place) = (format!("room{k}"), format!("place{}", 100 + k));
        xy.insert(place.clone(), (1.0 + 1.7 * k as f64, 4.0 + (k % 3) as f64));
        p = p
            .object(&room, "room")
            .object(&place, "place")
            .fact(&format!("in-room({place}, {room})"))
            .fact(&format!("connected(place0, {place})"))
            .fact(&format!("connected({place}, place0)"))
            .init(&format!("category({room}) = unknown"));
    }
    if rooms > 0 {
        p = p
            .object("object1", "object")
            .init("class(object1) = table")
            .init("located-in(object1) = room1")
            .init("located-on(object1) = none")
            .init("found(object1) = yes");
    }
    (p, xy)
}

#[test]
fn assumption_chains_keep_the_best_plan_and_spare_the_subsets_of_useless_assumptions() {
    // Brute force for the pruning: the same problems planned with and without the domain's
    // `assumption_chains` must reach the same objective (the pruning is exact on this domain),
    // and the pruned search must expand fewer states once rooms of unknown category offer
    // free, useless category assumptions (measured: 24 against 1088 expansions at 6 rooms).
    let chained = object_search_domain();
    assert!(chained.assumption_chains, "the shipped domain uses chains");
    let mut plain = chained.clone();
    plain.assumption_chains = false;
    let (with, without) = (
        ContinualPlanner::new(chained, ContinualOptions::default()),
        ContinualPlanner::new(plain, ContinualOptions::default()),
    );
    for target in ["cerealbox", "table", "desk"] {
        for rooms in [0usize, 2, 4, 6] {
            let (p, xy) = office_with_rooms(rooms, target);
            let f = functions(&xy);
            let a = plan_of(with.plan(&p, &f).unwrap());
            let b = plan_of(without.plan(&p, &f).unwrap());
            assert!(
                (a.objective - b.objective).abs() < 1e-6,
                "{target}, {rooms} rooms: {} with chains, {} without\n{:#?}\n{:#?}",
                a.objective,
                b.objective,
                lines(&a),
                lines(&b)
            );
            // The cerealbox's best plan is unlikely (p ≈ 0.02), so its slack admits many free
            // category assumptions (a table is found already, a desk plan is likely).
            if rooms >= 4 && target == "cerealbox" {
                assert!(
                    a.stats.expanded < b.stats.expanded,
                    "{target}, {rooms} rooms: {} expansions with chains, {} without",
                    a.stats.expanded,
                    b.stats.expanded
                );
            }
        }
    }
}

#[test]
fn assumption_chains_ground_only_the_copies_that_can_apply() {
    // Each assumption is copied per value of `(assumption-chain)` it may follow. A copy that
    // cannot apply is dead weight for the grounding and the heuristic; check the grounded task
    // against the chain's meaning: `none` while assuming is the initial state, and value k means
    // the last assumption wrote set k, so the copy needs one writer of k that agrees with it on
    // every variable both touch and shares one with it (the pool order aside, crate docs).
    let d = object_search_domain();
    for target in ["cerealbox", "table"] {
        let (p, xy) = office_with_rooms(4, target);
        let f = functions(&xy);
        let inst = avs_plan::problem::Instance::new(&d, &p).unwrap();
        let t = avs_plan::ground::ground(&d, inst, &f).unwrap().task;
        let var = |name: &str| t.variables.iter().position(|v| v.name == name).unwrap() as u32;
        let (chain, phase) = (var("(assumption-chain)"), var("(phase)"));
        let at = |pairs: &[(u32, u32)], v: u32| pairs.iter().find(|e| e.0 == v).map(|e| e.1);
        let pool_order = var("exists(new-object1)");
        let assumptions: Vec<_> = t.operators.iter().filter(|o| o.assumption).collect();
        assert!(
            assumptions.len() > 20,
            "{target}: {} assumptions",
            assumptions.len()
        );
        for o in &assumptions {
            let k = at(&o.pre, chain).expect("every assumption reads the chain");
            let after = if k == 0 {
                o.pre.iter().all(|&(v, x)| t.init[v as usize] == x)
            } else {
                assumptions.iter().any(|w| {
                    let eff: Vec<_> = w
                        .eff
                        .iter()
                        .filter(|e| e.0 != chain && e.0 != phase)
                        .collect();
                    at(&w.eff, chain) == Some(k)
                        && eff.iter().all(|e| at(&o.pre, e.0).is_none_or(|x| x == e.1))
                        && eff.iter().any(|e| {
                            at(&o.pre, e.0).is_some()
                                && !(e.0 == pool_order
                                    && o.eff.contains(&(var("exists(new-object2)"), 1))
                                    && !o.args.iter().any(|a| a == "new-object1"))
                        })
                })
            };
            assert!(
                after,
                "{target}: {} {:?} can never apply after chain value {}",
                o.schema, o.args, t.variables[chain as usize].values[k as usize]
            );
        }
    }
}

#[test]
fn assumption_chains_without_assumptions_first_is_rejected_naming_the_field() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/object_search.yaml");
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("assumptions_first: true", "assumptions_first: false");
    let dir = std::env::temp_dir().join(format!("avs-chains-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("domain.yaml");
    std::fs::write(&file, text).unwrap();
    let err = avs_plan::domain::Domain::load(&file).unwrap_err();
    let text = format!("{err:?}");
    assert!(text.contains("assumption_chains"), "{text}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_ratio_objective_starts_the_plan_with_the_most_success_per_unit_of_cost() {
    // Oracle: the paper's fixed-R objective swept over R from 1 to 10⁵ (every plan it returns
    // is a feasible plan; a plan with the best p/cost is optimal for R = its own cost/p, so a
    // fine sweep meets it). The ratio objective must find a plan at least as good per unit
    // of cost as every swept plan, and as good as the best of them.
    use avs_plan::continual::Objective;
    let domain = object_search_domain();
    let fixed = |r: f64| {
        let mut o = ContinualOptions {
            objective: Objective::Fixed,
            ..ContinualOptions::default()
        };
        o.search.reward = r;
        ContinualPlanner::new(domain.clone(), o)
    };
    let ratio = ContinualPlanner::new(
        domain.clone(),
        ContinualOptions {
            objective: Objective::Ratio,
            ..ContinualOptions::default()
        },
    );
    let mut differs = 0;
    let mut cases = Vec::new();
    for target in ["cerealbox", "table", "desk", "shelf"] {
        for rooms in [0usize, 2, 4] {
            let (p, xy) = office_with_rooms(rooms, target);
            cases.push((format!("{target}, {rooms} rooms"), p, xy, false));
        }
    }
    // A trade-off: room1 near and probably not an office, room2 far (20 m) and surely one.
    let (p, mut xy) = office_with_rooms(2, "desk");
    xy.insert("place102".into(), (20.0, 20.0));
    cases.push((
        "desk, near doubtful room and far office".into(),
        p,
        xy,
        true,
    ));
    for (name, p, xy, tradeoff) in &cases {
        let f = |n: &str, a: &[&str]| match (n, a) {
            ("p-category", [r, c]) if *tradeoff && (*r == "room1" || *r == "room2") => {
                let office = if *r == "room1" { 0.2 } else { 0.95 };
                Some(if *c == "office" {
                    office
                } else {
                    (1.0 - office) / 2.0
                })
            }
            _ => stand_in(n, a, xy),
        };
        let got = plan_of(ratio.plan(p, &f).unwrap());
        let got_ratio = got.probability / got.cost;
        let mut best_swept = 0.0f64;
        for i in 0..=50 {
            let r = 10f64.powf(5.0 * f64::from(i) / 50.0);
            if let Decision::Plan(q) = fixed(r).plan(p, &f).unwrap() {
                let qr = q.probability / q.cost;
                assert!(
                    got_ratio >= qr * (1.0 - 1e-9),
                    "{name}, R = {r}: swept plan p/cost {qr} beats {got_ratio}\n{:#?}\n{:#?}",
                    lines(&q),
                    lines(&got)
                );
                best_swept = best_swept.max(qr);
            }
        }
        assert!(
            (got_ratio - best_swept).abs() <= 1e-9 * best_swept,
            "{name}: {got_ratio} against the sweep's best {best_swept}"
        );
        // The paper's R = 1000 plan is at least as likely, never better per unit of cost.
        let paper = plan_of(fixed(1000.0).plan(p, &f).unwrap());
        assert!(paper.probability >= got.probability - 1e-12, "{name}");
        if lines(&paper) != lines(&got) {
            differs += 1;
            assert!(got.cost < paper.cost, "{name}");
        }
    }
    // The trade-off case must tell the two objectives apart, else this test tests nothing.
    assert!(
        differs > 0,
        "the ratio objective chose the R = 1000 plan everywhere"
    );
}
