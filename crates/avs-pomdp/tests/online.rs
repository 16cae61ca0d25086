//! RTBSS and the offline bounds against brute-force expectimax on small view-cone problems.

use avs_pomdp::{
    expectimax, rtbss, solve, DecisionRewards, OfflineOptions, OfflineSolution, OnlineOptions,
    ViewConePomdp, ViewConeProblem,
};

fn problem(prior: Vec<f64>, travel_scale: f64) -> ViewConeProblem {
    let n = prior.len();
    let pos: Vec<[f64; 2]> = (0..n).map(|i| [i as f64 * 1.5, (i % 2) as f64]).collect();
    let (from_start, travel) = avs_pomdp::euclidean_travel([-1.0, 0.0], &pos, travel_scale);
    ViewConeProblem {
        cone_prior: prior,
        travel_from_start: from_start,
        travel,
        process_cost: 0.5,
        false_negative: 0.2,
        false_positive: 0.05,
        rewards: DecisionRewards::default(),
        discount: 0.95,
    }
}

fn check_agreement(p: &ViewConeProblem, depth: usize, gap: f64) {
    let vc = ViewConePomdp::new(p).unwrap();
    let m = vc.pomdp();
    let sol = solve(
        m,
        &OfflineOptions {
            target_gap: gap,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(sol.gap() <= gap);
    let b0 = m.initial_belief();
    let lower = |b: &[f64]| sol.bounds.lower(b);
    let (ev, ea) = expectimax(m, b0, depth, &lower).unwrap();
    // Online: branch-and-bound must not change the depth-limited value.
    let on = rtbss(
        m,
        &sol.bounds,
        b0,
        &OnlineOptions {
            depth,
            time_limit: None,
            node_limit: None,
        },
    )
    .unwrap();
    assert!(
        (on.value - ev).abs() <= 1e-9,
        "rtbss {} vs expectimax {ev}",
        on.value
    );
    // Same action unless another action ties with it in the expectimax.
    if on.action != ea {
        let q = |a: usize| {
            let mut q = m.expected_reward(b0, a);
            for z in 0..m.n_observations() {
                if let Ok((post, pz)) = m.update(b0, a, z) {
                    q += m.discount() * pz * expectimax(m, &post, depth - 1, &lower).unwrap().0;
                }
            }
            q
        };
        assert!((q(on.action) - q(ea)).abs() <= 1e-9);
    }
    // Offline: the expectimax value with lower-bound leaves lies between the offline bounds, so all
    // three agree within the offline gap.
    assert!(
        ev >= sol.lower - 1e-9 && ev <= sol.upper + 1e-9,
        "{ev} not in [{}, {}]",
        sol.lower,
        sol.upper
    );
    assert!((ev - sol.lower).abs() <= sol.gap() + 1e-9);
}

#[test]
fn online_and_offline_agree_with_expectimax_to_depth_6_on_two_cones() {
    check_agreement(&problem(vec![0.5, 0.3], 1.0), 6, 1e-4);
    check_agreement(&problem(vec![0.2, 0.1], 2.0), 6, 1e-4);
    let mut noisy = problem(vec![0.4, 0.4], 0.3);
    noisy.false_negative = 0.35;
    noisy.false_positive = 0.15;
    check_agreement(&noisy, 6, 0.05);
}

#[test]
fn online_and_offline_agree_with_expectimax_to_depth_4_on_three_cones() {
    check_agreement(&problem(vec![0.3, 0.3, 0.2], 0.5), 4, 0.1);
}

/// Three cones (priors 0.3, 0.3, 0.2), and their offline bounds to a gap of 0.1.
fn three_cones_solved() -> (ViewConePomdp, OfflineSolution) {
    let vc = ViewConePomdp::new(&problem(vec![0.3, 0.3, 0.2], 0.5)).unwrap();
    let sol = solve(
        vc.pomdp(),
        &OfflineOptions {
            target_gap: 0.1,
            ..Default::default()
        },
    )
    .unwrap();
    (vc, sol)
}

#[test]
fn rtbss_prunes_nodes_yet_keeps_the_value() {
    let (vc, sol) = three_cones_solved();
    let m = vc.pomdp();
    let on = rtbss(
        m,
        &sol.bounds,
        m.initial_belief(),
        &OnlineOptions {
            depth: 3,
            time_limit: None,
            node_limit: None,
        },
    )
    .unwrap();
    // Without pruning depth 3 expands 1 + (7·2) + (7·2)² internal nodes.
    assert!(on.nodes < 1 + 14 + 196, "nodes {}", on.nodes);
    assert!(on.value >= sol.lower - 1e-9 && on.value <= sol.upper + 1e-9);
}

#[test]
fn a_time_budgeted_search_still_returns_a_decision() {
    let (vc, sol) = three_cones_solved();
    let m = vc.pomdp();
    let on = rtbss(
        m,
        &sol.bounds,
        m.initial_belief(),
        &OnlineOptions {
            depth: 50,
            time_limit: Some(std::time::Duration::from_millis(5)),
            node_limit: None,
        },
    )
    .unwrap();
    assert!(on.depth >= 1 && on.depth <= 50);
    assert!(on.action < m.n_actions());
}

#[test]
fn a_node_budget_keeps_the_deepest_depth_it_completes_and_its_exact_value() {
    let (vc, sol) = three_cones_solved();
    let m = vc.pomdp();
    let b0 = m.initial_belief();
    let run = |depth: usize, node_limit: Option<usize>| {
        rtbss(
            m,
            &sol.bounds,
            b0,
            &OnlineOptions {
                depth,
                time_limit: None,
                node_limit,
            },
        )
        .unwrap()
    };
    // The nodes a full search of each depth needs, deepening from 1 as the budgeted search does.
    let full: Vec<usize> = (1..=4).map(|d| run(d, None).nodes).collect();
    let cumulative = |d: usize| full[..d].iter().sum::<usize>();
    // Enough for depths 1–3 in turn, not for depth 4 as well: depth 3 is the answer.
    let limit = cumulative(3) + full[3] / 2;
    let on = run(4, Some(limit));
    assert_eq!(on.depth, 3, "budget {limit}, full searches {full:?}");
    let lower = |b: &[f64]| sol.bounds.lower(b);
    let (ev, _) = expectimax(m, b0, 3, &lower).unwrap();
    assert!((on.value - ev).abs() <= 1e-9, "{} vs {ev}", on.value);
    // Deterministic: the same budget gives the same answer, node for node.
    assert_eq!(run(4, Some(limit)), on);
    // A budget too small for depth 2 still answers at depth 1.
    assert_eq!(run(4, Some(1)).depth, 1);
}
