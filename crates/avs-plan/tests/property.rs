//! On random small SAS+ tasks with costs and probabilities, the optimal search's objective
//! equals brute-force enumeration's.

use avs_plan::task::{Operator, Task, Variable};
use avs_plan::{search, validate_sas, Heuristic, Mode, SearchOptions};
use proptest::prelude::*;

/// Minimum of cost + R(1 − p) over all plans with p ≥ `theta`, by depth-first enumeration of
/// paths without repeated states (a repeated state never helps: costs ≥ 0 and probabilities ≤ 1).
fn brute_force(task: &Task, reward: f64, theta: f64) -> Option<f64> {
    #[expect(
        clippy::too_many_arguments,
        reason = "the depth-first search threads its whole state through the recursion"
    )]
    fn dfs(
        t: &Task,
        s: &[u32],
        seen: &mut Vec<Vec<u32>>,
        c: f64,
        p: f64,
        r: f64,
        theta: f64,
        best: &mut Option<f64>,
    ) {
        if p < theta {
            return;
        }
        if t.is_goal(s) {
            let j = c + r * (1.0 - p);
            if !matches!(*best, Some(b) if b <= j) {
                *best = Some(j);
            }
        }
        for o in &t.operators {
            if o.pre.iter().all(|&(v, x)| s[v as usize] == x) {
                let mut n = s.to_vec();
                for &(v, x) in &o.eff {
                    n[v as usize] = x;
                }
                if seen.contains(&n) {
                    continue;
                }
                seen.push(n.clone());
                dfs(t, &n, seen, c + o.cost, p * o.prob, r, theta, best);
                seen.pop();
            }
        }
    }
    let mut best = None;
    let s = task.init.clone();
    let mut seen = vec![s.clone()];
    dfs(task, &s, &mut seen, 0.0, 1.0, reward, theta, &mut best);
    best
}

fn arb_task() -> impl Strategy<Value = Task> {
    (2usize..=3, 2u32..=3).prop_flat_map(|(nv, dom)| {
        let fact = (0..nv as u32, 0..dom);
        let op = (
            prop::collection::vec(fact.clone(), 0..=2),
            prop::collection::vec(fact.clone(), 1..=2),
            0u32..=5,
            prop::sample::select(vec![1.0, 0.9, 0.6, 0.3, 0.1]),
        );
        (
            prop::collection::vec(0..dom, nv),
            prop::collection::vec(fact, 1..=2),
            prop::collection::vec(op, 2..=7),
        )
            .prop_map(move |(init, goal, ops)| {
                let norm = |v: Vec<(u32, u32)>| {
                    let mut m = std::collections::BTreeMap::new();
                    for (a, b) in v {
                        m.insert(a, b);
                    }
                    m.into_iter().collect::<Vec<_>>()
                };
                Task {
                    variables: (0..nv)
                        .map(|i| {
                            Variable::new(
                                format!("v{i}"),
                                (0..dom).map(|k| k.to_string()).collect(),
                            )
                        })
                        .collect(),
                    init,
                    goal: norm(goal),
                    operators: ops
                        .into_iter()
                        .enumerate()
                        .map(|(i, (pre, eff, c, p))| Operator {
                            schema: format!("o{i}"),
                            args: vec![],
                            display: format!("o{i}"),
                            pre: norm(pre),
                            eff: norm(eff),
                            cost: c as f64,
                            prob: p,
                            assumption: p < 1.0,
                        })
                        .collect(),
                }
            })
    })
}

/// `task` with a control variable `c` (values 0..=2, initially 0) in the style of the
/// grounding's assumption chain: operator `i` sets `c := 1 + i % 2` and is copied once per value
/// of `c` it may follow (`after[i]`, a bit per value; at least one), so `c` restricts which
/// operator may follow which.
fn with_control_variable(task: &Task, after: &[u8]) -> Task {
    let c = task.variables.len() as u32;
    let mut t = task.clone();
    t.variables.push(Variable {
        control: true,
        ..Variable::new("c", vec!["0".into(), "1".into(), "2".into()])
    });
    t.init.push(0);
    t.operators = Vec::new();
    for (i, o) in task.operators.iter().enumerate() {
        let mask = after[i % after.len()].max(1);
        for k in 0..3u32 {
            if mask & (1 << k) == 0 {
                continue;
            }
            let mut copy = o.clone();
            copy.pre.push((c, k));
            copy.eff.push((c, 1 + i as u32 % 2));
            t.operators.push(copy);
        }
    }
    t
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]
    #[test]
    fn a_control_variable_restricts_orders_and_the_optimum_still_equals_brute_force(
        task in arb_task(),
        after in prop::collection::vec(1u8..8, 1..=7),
        reward in prop::sample::select(vec![0.0, 5.0, 40.0]),
    ) {
        // The heuristics drop conditions on `c` and merge the copies: still admissible.
        let task = with_control_variable(&task, &after);
        let expect = brute_force(&task, reward, 0.0);
        for heuristic in [Heuristic::LmCut, Heuristic::HMax] {
            let (plan, _) = search(&task, &SearchOptions { heuristic, reward, ..Default::default() }).unwrap();
            match (&plan, expect) {
                (None, None) => {}
                (Some(p), Some(e)) => {
                    prop_assert!((p.objective - e).abs() < 1e-9, "{heuristic:?}: {} vs brute force {e}", p.objective);
                    prop_assert!(validate_sas(&task, &p.steps).is_ok());
                }
                _ => prop_assert!(false, "{heuristic:?}: plan {:?} vs brute force {:?}", plan, expect),
            }
        }
        let (fast, _) = search(&task, &SearchOptions { mode: Mode::Fast, reward, ..Default::default() }).unwrap();
        prop_assert_eq!(fast.is_some(), expect.is_some());
        if let Some(f) = fast {
            prop_assert!(validate_sas(&task, &f.steps).is_ok());
        }
    }

    #[test]
    fn optimal_objective_equals_brute_force(task in arb_task(), reward in prop::sample::select(vec![0.0, 5.0, 40.0])) {
        let expect = brute_force(&task, reward, 0.0);
        for (mode, heuristic) in [(Mode::Optimal, Heuristic::LmCut), (Mode::Optimal, Heuristic::HMax), (Mode::Blind, Heuristic::LmCut)] {
            let (plan, _) = search(&task, &SearchOptions { mode, heuristic, reward, ..Default::default() }).unwrap();
            match (&plan, expect) {
                (None, None) => {}
                (Some(p), Some(e)) => {
                    prop_assert!((p.objective - e).abs() < 1e-9, "{mode:?}: {} vs brute force {e}", p.objective);
                    let v = validate_sas(&task, &p.steps).unwrap();
                    prop_assert!((v.cost + reward * (1.0 - v.probability) - e).abs() < 1e-9);
                }
                _ => prop_assert!(false, "{mode:?}: plan {:?} vs brute force {:?}", plan, expect),
            }
        }
        // The fast mode finds a valid plan whenever one exists, never better than the optimum.
        let (fast, _) = search(&task, &SearchOptions { mode: Mode::Fast, reward, ..Default::default() }).unwrap();
        prop_assert_eq!(fast.is_some(), expect.is_some());
        if let (Some(f), Some(e)) = (fast, expect) {
            prop_assert!(validate_sas(&task, &f.steps).is_ok());
            prop_assert!(f.objective >= e - 1e-9);
        }
    }

    #[test]
    fn a_success_threshold_gives_the_best_plan_at_least_that_likely(task in arb_task(), theta in prop::sample::select(vec![0.05, 0.2, 0.5])) {
        let reward = 40.0;
        let expect = brute_force(&task, reward, theta - 1e-12);
        for heuristic in [Heuristic::LmCut, Heuristic::HMax] {
            let opts = SearchOptions { heuristic, reward, min_probability: theta, ..Default::default() };
            let (plan, _) = search(&task, &opts).unwrap();
            match (&plan, expect) {
                (None, None) => {}
                (Some(p), Some(e)) => {
                    prop_assert!(p.probability >= theta - 1e-12);
                    prop_assert!((p.objective - e).abs() < 1e-9, "{heuristic:?}: {} vs brute force {e}", p.objective);
                }
                _ => prop_assert!(false, "{heuristic:?}: plan {:?} vs brute force {:?}", plan, expect),
            }
        }
    }
}

#[test]
fn reward_trades_cost_against_success_probability() {
    // Two routes to the goal: cheap and unlikely (cost 1, p 0.2), dear and likely (cost 10, p 0.9).
    let task = Task {
        variables: vec![Variable::new("g", vec!["no".into(), "yes".into()])],
        init: vec![0],
        goal: vec![(0, 1)],
        operators: vec![
            Operator {
                schema: "cheap".into(),
                args: vec![],
                display: "CHEAP".into(),
                pre: vec![],
                eff: vec![(0, 1)],
                cost: 1.0,
                prob: 0.2,
                assumption: false,
            },
            Operator {
                schema: "dear".into(),
                args: vec![],
                display: "DEAR".into(),
                pre: vec![],
                eff: vec![(0, 1)],
                cost: 10.0,
                prob: 0.9,
                assumption: false,
            },
        ],
    };
    let pick = |reward: f64| {
        let (p, _) = search(
            &task,
            &SearchOptions {
                reward,
                ..Default::default()
            },
        )
        .unwrap();
        task.operators[p.unwrap().steps[0]].display.clone()
    };
    // J(cheap) = 1 + 0.8 R, J(dear) = 10 + 0.1 R: cheap wins below R = 9/0.7.
    assert_eq!(pick(5.0), "CHEAP");
    assert_eq!(pick(20.0), "DEAR");
    assert!(brute_force(&task, 20.0, 0.0).is_some_and(|j| (j - 12.0).abs() < 1e-9));
}
