//! The view-cone POMDP and its closed-loop session.

use avs_pomdp::{
    read_pomdp_file, solve, DecisionRewards, OfflineOptions, OnlineOptions, Outcome, PomdpError,
    SessionOptions, ViewConeAction, ViewConePomdp, ViewConeProblem, ViewConeSession,
};
use rand::{Rng, SeedableRng};

/// The model of `viewcones2.POMDP` expressed as a view-cone problem: processing cone 0 always costs 1
/// and cone 1 always costs 2 (travel to cone 1 costs 1 from anywhere, processing 1).
fn viewcones2_problem() -> ViewConeProblem {
    ViewConeProblem {
        cone_prior: vec![0.5, 0.3],
        travel_from_start: vec![0.0, 1.0],
        travel: vec![vec![0.0, 1.0], vec![0.0, 1.0]],
        process_cost: 1.0,
        false_negative: 0.2,
        false_positive: 0.05,
        rewards: DecisionRewards::default(),
        discount: 0.95,
    }
}

#[test]
fn the_builder_reproduces_the_value_of_the_viewcones2_reference_model() {
    let Some(dir) = avs_testdata::reference_data("pomdp") else {
        return;
    };
    let csv = std::fs::read_to_string(dir.join("reference_values.csv")).unwrap();
    let row = csv
        .lines()
        .find(|l| l.starts_with("viewcones2.POMDP,"))
        .expect("viewcones2 row");
    let cols: Vec<&str> = row.split(',').collect();
    let (reference, tol) = (
        cols[2].parse::<f64>().unwrap(),
        cols[3].parse::<f64>().unwrap(),
    );
    let file_model = read_pomdp_file(dir.join("viewcones2.POMDP")).unwrap();
    let built = ViewConePomdp::new(&viewcones2_problem()).unwrap();
    let opts = OfflineOptions {
        target_gap: tol,
        ..Default::default()
    };
    let a = solve(&file_model, &opts).unwrap();
    let b = solve(built.pomdp(), &opts).unwrap();
    for v in [a.lower, a.upper, b.lower, b.upper] {
        assert!((v - reference).abs() <= tol, "{v} vs {reference}");
    }
}

fn three_cones(false_negative: f64, false_positive: f64) -> ViewConeProblem {
    let pos = [[0.0, 1.0], [2.0, 1.0], [2.0, -1.0]];
    let (from_start, travel) = avs_pomdp::euclidean_travel([0.0, 0.0], &pos, 0.5);
    ViewConeProblem {
        cone_prior: vec![0.35, 0.25, 0.2],
        travel_from_start: from_start,
        travel,
        process_cost: 0.5,
        false_negative,
        false_positive,
        rewards: DecisionRewards::default(),
        discount: 0.95,
    }
}

fn quick_options() -> SessionOptions {
    SessionOptions {
        offline: OfflineOptions {
            target_gap: 0.1,
            max_trials: 8,
            ..Default::default()
        },
        online: OnlineOptions {
            depth: 2,
            time_limit: None,
            node_limit: None,
        },
        max_steps: 12,
        sweep_bounds: false,
        policy: Default::default(),
    }
}

#[test]
fn the_session_exposes_a_normalised_belief_that_follows_the_observations() {
    let mut s = ViewConeSession::new(&three_cones(0.2, 0.05), quick_options()).unwrap();
    let b0 = s.belief();
    assert!((b0.in_cone.iter().sum::<f64>() + b0.absent - 1.0).abs() < 1e-12);
    assert!((b0.absent - 0.2).abs() < 1e-12);
    let ViewConeAction::Process { cone } = s.next_action().unwrap() else {
        panic!("a 20% absent prior with +10/−20 rewards must look first");
    };
    // Asking again before observing returns the same action.
    assert_eq!(s.next_action().unwrap(), ViewConeAction::Process { cone });
    s.observe(false).unwrap();
    let b1 = s.belief();
    // Bayes: a miss in cone i scales it by FN = 0.2 and the rest by 1 − FP = 0.95.
    let prior = b0.in_cone[cone];
    let expected = prior * 0.2 / (prior * 0.2 + (1.0 - prior) * 0.95);
    assert!((b1.in_cone[cone] - expected).abs() < 1e-12);
    assert!((b1.in_cone.iter().sum::<f64>() + b1.absent - 1.0).abs() < 1e-12);
    assert_eq!(s.steps(), 1);
}

#[test]
fn the_session_rejects_out_of_order_calls() {
    let mut s = ViewConeSession::new(&three_cones(0.2, 0.05), quick_options()).unwrap();
    assert!(matches!(
        s.observe(true),
        Err(PomdpError::InvalidArgument(_))
    ));
    // Drive it to the end with detections everywhere.
    while s.outcome().is_none() {
        if let ViewConeAction::Process { .. } = s.next_action().unwrap() {
            s.observe(true).unwrap();
        }
    }
    assert!(matches!(s.next_action(), Err(PomdpError::SessionEnded)));
    assert!(matches!(s.observe(true), Err(PomdpError::SessionEnded)));
}

#[test]
fn a_perfect_sensor_finds_the_target_in_its_cone() {
    for k in 0..3 {
        let mut s = ViewConeSession::new(&three_cones(0.0, 0.0), quick_options()).unwrap();
        while s.outcome().is_none() {
            if let ViewConeAction::Process { cone } = s.next_action().unwrap() {
                s.observe(cone == k).unwrap();
            }
        }
        assert_eq!(s.outcome(), Some(Outcome::Found { cone: k }));
    }
}

#[test]
fn bad_problems_are_rejected_with_the_field_named() {
    let mut p = three_cones(0.2, 0.05);
    p.false_negative = f64::NAN;
    let e = ViewConePomdp::new(&p).unwrap_err().to_string();
    assert!(e.contains("false_negative"), "{e}");
    let mut p = three_cones(0.2, 0.05);
    p.travel.pop();
    assert!(ViewConePomdp::new(&p)
        .unwrap_err()
        .to_string()
        .contains("travel"));
    let mut p = three_cones(0.2, 0.05);
    p.cone_prior = vec![0.7, 0.7, 0.1];
    assert!(ViewConePomdp::new(&p)
        .unwrap_err()
        .to_string()
        .contains("cone_prior"));
}

/// Exact probability of each outcome of the (deterministic) closed-loop policy when the target is in
/// `target` (`None`: not in the location), by enumerating every observation sequence.
fn exact_outcomes(
    s: &ViewConeSession,
    target: Option<usize>,
    p: &ViewConeProblem,
) -> Vec<(Outcome, f64)> {
    fn rec(
        mut s: ViewConeSession,
        prob: f64,
        target: Option<usize>,
        p: &ViewConeProblem,
        out: &mut Vec<(Outcome, f64)>,
    ) {
        match s.next_action().unwrap() {
            ViewConeAction::Process { cone } => {
                let pd = if Some(cone) == target {
                    1.0 - p.false_negative
                } else {
                    p.false_positive
                };
                for (det, q) in [(true, pd), (false, 1.0 - pd)] {
                    if q > 0.0 {
                        let mut c = s.clone();
                        c.observe(det).unwrap();
                        rec(c, prob * q, target, p, out);
                    }
                }
            }
            _ => out.push((s.outcome().unwrap(), prob)),
        }
    }
    let mut out = Vec::new();
    rec(s.clone(), 1.0, target, p, &mut out);
    out
}

#[test]
fn seeded_simulation_matches_the_rates_the_fn_fp_model_predicts() {
    let p = three_cones(0.2, 0.05);
    let session = ViewConeSession::new(&p, quick_options()).unwrap();
    let runs = 1000;
    for target in [Some(0), Some(1), Some(2), None] {
        let exact = exact_outcomes(&session, target, &p);
        let total: f64 = exact.iter().map(|(_, q)| q).sum();
        assert!((total - 1.0).abs() < 1e-9, "outcome mass {total}");
        let right = match target {
            Some(k) => Outcome::Found { cone: k },
            None => Outcome::Absent,
        };
        let predicted: f64 = exact
            .iter()
            .filter(|(o, _)| *o == right)
            .map(|(_, q)| q)
            .sum();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7 + target.unwrap_or(9) as u64);
        let mut hits = 0;
        for _ in 0..runs {
            let mut s = session.clone();
            while s.outcome().is_none() {
                if let ViewConeAction::Process { cone } = s.next_action().unwrap() {
                    let pd = if Some(cone) == target {
                        1.0 - p.false_negative
                    } else {
                        p.false_positive
                    };
                    s.observe(rng.gen::<f64>() < pd).unwrap();
                }
            }
            if s.outcome() == Some(right) {
                hits += 1;
            }
        }
        let rate = hits as f64 / runs as f64;
        let sd = (predicted * (1.0 - predicted) / runs as f64).sqrt();
        assert!(
            (rate - predicted).abs() <= 4.0 * sd + 1e-9,
            "target {target:?}: simulated {rate} vs predicted {predicted}"
        );
        // With FN 0.2 and FP 0.05 the policy is right far more often than a blind guess.
        assert!(
            predicted > 0.6,
            "target {target:?}: predicted success {predicted}"
        );
    }
}

/// Sixteen cones on a 4 × 4 grid a metre apart, P(ObjectAt L) = 0.8 spread evenly,
/// declarations worth +100 / +20 / −50 and γ = 0.99 (as the agent uses them).
fn sixteen_cones() -> ViewConeProblem {
    let pos: Vec<[f64; 2]> = (0..16).map(|i| [(i % 4) as f64, (i / 4) as f64]).collect();
    let (from_start, travel) = avs_pomdp::euclidean_travel([-1.0, 0.0], &pos, 0.5);
    ViewConeProblem {
        cone_prior: vec![0.05; 16],
        travel_from_start: from_start,
        travel,
        process_cost: 1.0,
        false_negative: 0.2,
        false_positive: 0.05,
        rewards: DecisionRewards {
            found: 100.0,
            absent: 20.0,
            wrong: -50.0,
        },
        discount: 0.99,
    }
}

#[test]
fn sweep_policy_vectors_never_exceed_the_optimal_value() {
    for problem in [
        viewcones2_problem(),
        three_cones(0.2, 0.05),
        sixteen_cones(),
    ] {
        let model = ViewConePomdp::new(&problem).unwrap();
        let sol = solve(
            model.pomdp(),
            &OfflineOptions {
                target_gap: 0.5,
                max_trials: 50,
                ..Default::default()
            },
        )
        .unwrap();
        let b0 = model.pomdp().initial_belief();
        let vectors = model.sweep_vectors();
        assert_eq!(vectors.len(), problem.cone_prior.len() + 1);
        for v in &vectors {
            let value: f64 = v.values.iter().zip(b0).map(|(a, b)| a * b).sum();
            assert!(
                value <= sol.upper + 1e-9,
                "a sweep is worth {value} > the upper bound {}",
                sol.upper
            );
        }
    }
}

#[test]
fn a_session_over_sixteen_empty_cones_looks_at_each_at_most_twice_then_declares_absent() {
    let opts = SessionOptions {
        offline: OfflineOptions {
            max_trials: 10,
            init_iterations: 40,
            ..Default::default()
        },
        online: OnlineOptions::default(),
        max_steps: 100,
        sweep_bounds: true,
        policy: Default::default(),
    };
    let mut session = ViewConeSession::new(&sixteen_cones(), opts).unwrap();
    let mut looks = [0usize; 16];
    let mut steps = 0;
    while session.outcome().is_none() {
        match session.next_action().unwrap() {
            ViewConeAction::Process { cone } => {
                looks[cone] += 1;
                steps += 1;
                session.observe(false).unwrap();
            }
            _ => break,
        }
    }
    assert_eq!(session.outcome(), Some(Outcome::Absent), "looks {looks:?}");
    assert!(steps < 100, "the step guard ended the session: {looks:?}");
    assert!(
        looks.iter().all(|&k| k <= 2),
        "a cone processed more than twice: {looks:?}"
    );
    let distinct = looks.iter().filter(|&&k| k > 0).count();
    assert!(distinct >= 8, "only {distinct} cones looked at: {looks:?}");
}
