//! The one-pass rollout policy of view-cone sessions: never worse than its base pass (exact
//! expectations on small problems), one look per cone unless confirming a detection, and a
//! pass that follows travel when the cones weigh the same.

use avs_pomdp::{
    euclidean_travel, DecisionRewards, OnePassModel, OnePassState, OnlineOptions, Outcome,
    SessionOptions, SessionPolicy, ViewConeAction, ViewConePomdp, ViewConeProblem, ViewConeSession,
};
use proptest::prelude::*;

fn problem(positions: &[[f64; 2]], prior: Vec<f64>, fneg: f64, fpos: f64) -> ViewConeProblem {
    let (travel_from_start, travel) = euclidean_travel([0.0, 0.0], positions, 0.5);
    ViewConeProblem {
        cone_prior: prior,
        travel_from_start,
        travel,
        process_cost: 1.0,
        false_negative: fneg,
        false_positive: fpos,
        rewards: DecisionRewards {
            found: 100.0,
            absent: 20.0,
            wrong: -50.0,
        },
        discount: 0.99,
    }
}

fn one_pass_options(depth: usize) -> SessionOptions {
    SessionOptions {
        online: OnlineOptions {
            depth,
            time_limit: None,
            node_limit: None,
        },
        policy: SessionPolicy::OnePassRollout,
        ..SessionOptions::default()
    }
}

/// The exact expected value of running `policy` from `s`, by enumerating the observations,
/// with the session's step guard: after `steps_left` looks, the best declaration.
fn policy_value(
    m: &OnePassModel,
    s: &OnePassState,
    steps_left: usize,
    gamma: f64,
    policy: &dyn Fn(&OnePassState) -> ViewConeAction,
    travel_and_process: &dyn Fn(usize, usize) -> f64,
) -> f64 {
    let declare = |a: ViewConeAction| match a {
        ViewConeAction::DeclareFound { cone } => {
            s.mass[cone] * 100.0 + (1.0 - s.mass[cone]) * -50.0
        }
        _ => {
            let absent = s.mass[s.mass.len() - 1];
            absent * 20.0 + (1.0 - absent) * -50.0
        }
    };
    if steps_left == 0 {
        return s
            .recheck
            .map(|(i, _)| declare(ViewConeAction::DeclareFound { cone: i }))
            .unwrap_or(f64::NEG_INFINITY)
            .max(declare(ViewConeAction::DeclareAbsent));
    }
    match policy(s) {
        ViewConeAction::Process { cone } => {
            assert!(s.may_process(cone), "the policy processed a closed cone");
            let mut v = -travel_and_process(s.pos, cone);
            for detected in [true, false] {
                if let Some((p, next)) = m.after(s, cone, detected) {
                    v += gamma
                        * p
                        * policy_value(m, &next, steps_left - 1, gamma, policy, travel_and_process);
                }
            }
            v
        }
        ViewConeAction::DeclareFound { cone } => {
            assert_eq!(
                s.recheck.map(|r| r.0),
                Some(cone),
                "found where nothing was detected"
            );
            declare(ViewConeAction::DeclareFound { cone })
        }
        a => declare(a),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Bertsekas' cost improvement: the rollout's exact value is at least its base policy's,
    /// for depths 1 and 2, on random small rooms and sensors.
    #[test]
    fn the_rollout_is_never_worse_than_its_base_pass(
        xs in prop::collection::vec((-4.0f64..4.0, -4.0f64..4.0, 0.05f64..1.0), 2..=4),
        p_in in 0.1f64..0.95,
        fneg in 0.05f64..0.4,
        fpos in 0.01f64..0.2,
    ) {
        let positions: Vec<[f64; 2]> = xs.iter().map(|&(x, y, _)| [x, y]).collect();
        let w: f64 = xs.iter().map(|&(_, _, w)| w).sum();
        let prior: Vec<f64> = xs.iter().map(|&(_, _, x)| x / w * p_in).collect();
        let p = problem(&positions, prior.clone(), fneg, fpos);
        let model = ViewConePomdp::new(&p).unwrap();
        let m = OnePassModel::new(&model);
        let s0 = OnePassState::start(&prior);
        let cost = |pos: usize, i: usize| {
            let travel = if pos == 0 { p.travel_from_start[i] } else { p.travel[pos - 1][i] };
            travel + p.process_cost
        };
        let steps = 3 * positions.len() + 2;
        let base = policy_value(&m, &s0, steps, p.discount, &|s| m.base_action(s), &cost);
        // The closed form of the base value agrees with the enumeration.
        let closed = m.base_value(&s0);
        prop_assert!((closed - base).abs() < 1e-6 * (1.0 + base.abs()), "closed {closed} vs enumerated {base}");
        for depth in [1, 2] {
            let rollout = policy_value(&m, &s0, steps, p.discount, &|s| m.decide(s, depth).1, &cost);
            prop_assert!(rollout >= base - 1e-6, "depth {depth}: rollout {rollout} < base {base}");
        }
    }

    /// A session processes a cone a second time only right after a look there detected
    /// something, whatever the observations.
    #[test]
    fn a_one_pass_session_looks_again_only_to_confirm_a_detection(
        n in 2usize..12,
        seed in any::<u64>(),
    ) {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let positions: Vec<[f64; 2]> = (0..n).map(|_| [rng.gen_range(-5.0..5.0), rng.gen_range(-5.0..5.0)]).collect();
        let prior = vec![0.8 / n as f64; n];
        let mut session = ViewConeSession::new(&problem(&positions, prior, 0.2, 0.05), one_pass_options(2)).unwrap();
        let mut looked = vec![false; n];
        let mut last: Option<(usize, bool)> = None;
        while session.outcome().is_none() {
            match session.next_action().unwrap() {
                ViewConeAction::Process { cone } => {
                    if looked[cone] {
                        prop_assert_eq!(last, Some((cone, true)), "cone {} looked at again", cone);
                    }
                    looked[cone] = true;
                    let detected = rng.gen_bool(0.15);
                    session.observe(detected).unwrap();
                    last = Some((cone, detected));
                }
                _ => break,
            }
        }
        prop_assert!(session.steps() <= 3 * n, "{} steps for {} cones", session.steps(), n);
    }
}

#[test]
fn cones_of_equal_weight_on_a_line_are_looked_at_in_travel_order_then_absent() {
    let positions: Vec<[f64; 2]> = (0..8).map(|i| [1.0 + i as f64, 0.0]).collect();
    let mut session = ViewConeSession::new(
        &problem(&positions, vec![0.1; 8], 0.2, 0.05),
        one_pass_options(2),
    )
    .unwrap();
    assert!(
        session.bounds().is_none(),
        "a one-pass session solves nothing offline"
    );
    let mut order = Vec::new();
    while session.outcome().is_none() {
        if let ViewConeAction::Process { cone } = session.next_action().unwrap() {
            order.push(cone);
            session.observe(false).unwrap();
        }
    }
    assert_eq!(order, (0..8).collect::<Vec<_>>());
    assert_eq!(session.outcome(), Some(Outcome::Absent));
}

#[test]
fn a_far_cone_holding_most_of_the_mass_is_worth_the_detour() {
    // Two near cones with little mass, one far cone with most of it: the pass is reordered
    // when the mass pays for the travel (the base alone would go nearest first).
    let positions = [[1.0, 0.0], [2.0, 0.0], [-6.0, 0.0]];
    let p = problem(&positions, vec![0.03, 0.03, 0.5], 0.2, 0.05);
    let m = OnePassModel::new(&ViewConePomdp::new(&p).unwrap());
    let s = OnePassState::start(&p.cone_prior);
    assert_eq!(m.base_action(&s), ViewConeAction::Process { cone: 0 });
    assert_eq!(m.decide(&s, 2).1, ViewConeAction::Process { cone: 2 });
}
