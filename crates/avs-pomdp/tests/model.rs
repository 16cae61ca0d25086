//! The Bayes filter and model checks.

use avs_pomdp::{parse_pomdp, Pomdp, PomdpError, PomdpTables};

mod common;
use common::TIGER;

#[test]
fn hearing_the_tiger_twice_on_the_left_follows_bayes_rule() {
    let m = parse_pomdp(TIGER, "tiger").unwrap();
    let (b1, p1) = m.update(m.initial_belief(), 0, 0).unwrap();
    assert!((p1 - 0.5).abs() < 1e-12);
    assert!((b1[0] - 0.85).abs() < 1e-12);
    let (b2, p2) = m.update(&b1, 0, 0).unwrap();
    // P(hl | b1) = 0.85·0.85 + 0.15·0.15; posterior 0.85² / that.
    let pz = 0.85f64 * 0.85 + 0.15 * 0.15;
    assert!((p2 - pz).abs() < 1e-12);
    assert!((b2[0] - 0.85 * 0.85 / pz).abs() < 1e-12);
    // Opening a door resets the belief.
    let (b3, _) = m.update(&b2, 1, 1).unwrap();
    assert!((b3[0] - 0.5).abs() < 1e-12);
    assert!((m.expected_reward(&b1, 1) - (0.85 * -100.0 + 0.15 * 10.0)).abs() < 1e-12);
}

#[test]
fn bad_beliefs_actions_and_observations_are_errors() {
    let m = parse_pomdp(TIGER, "tiger").unwrap();
    assert!(matches!(
        m.update(&[1.0], 0, 0),
        Err(PomdpError::InvalidArgument(_))
    ));
    assert!(matches!(
        m.update(&[f64::NAN, 1.0], 0, 0),
        Err(PomdpError::InvalidArgument(_))
    ));
    assert!(matches!(
        m.update(&[0.7, 0.7], 0, 0),
        Err(PomdpError::InvalidArgument(_))
    ));
    assert!(matches!(
        m.update(&[0.5, 0.5], 3, 0),
        Err(PomdpError::InvalidArgument(_))
    ));
    assert!(matches!(
        m.update(&[0.5, 0.5], 0, 2),
        Err(PomdpError::InvalidArgument(_))
    ));
}

#[test]
fn an_impossible_observation_is_reported_not_divided_by_zero() {
    let text = TIGER.replace(
        "O: listen\n0.85 0.15\n0.15 0.85",
        "O: listen\nidentity_placeholder",
    );
    // identity is not valid for O; build a deterministic sensor instead.
    let text = text.replace("identity_placeholder", "1 0\n0 1");
    let m = parse_pomdp(&text, "t").unwrap();
    let e = m.update(&[1.0, 0.0], 0, 1).unwrap_err();
    assert!(e.to_string().contains("impossible"), "{e}");
}

#[test]
fn tables_that_are_not_distributions_are_rejected() {
    let base = PomdpTables {
        states: vec!["a".into(), "b".into()],
        actions: vec!["x".into()],
        observations: vec!["o".into()],
        discount: 0.9,
        transitions: vec![1.0, 0.0, 0.0, 1.0],
        observation_probs: vec![1.0, 1.0],
        rewards: vec![0.0, 1.0],
        initial: vec![0.5, 0.5],
    };
    assert!(Pomdp::new(base.clone()).is_ok());
    let mut t = base.clone();
    t.transitions[1] = 0.5;
    let e = Pomdp::new(t).unwrap_err().to_string();
    assert!(e.contains("T row") && e.contains("`a`"), "{e}");
    let mut t = base.clone();
    t.discount = 1.0;
    assert!(Pomdp::new(t).is_err());
    let mut t = base.clone();
    t.rewards[0] = f64::INFINITY;
    assert!(Pomdp::new(t).is_err());
    let mut t = base;
    t.initial = vec![0.2, 0.2];
    assert!(Pomdp::new(t).unwrap_err().to_string().contains("initial"));
}

fn tiger_solution() -> &'static avs_pomdp::OfflineSolution {
    static SOL: std::sync::OnceLock<avs_pomdp::OfflineSolution> = std::sync::OnceLock::new();
    SOL.get_or_init(|| {
        let m = parse_pomdp(TIGER, "tiger").unwrap();
        avs_pomdp::solve(&m, &avs_pomdp::OfflineOptions::default()).unwrap()
    })
}

proptest::proptest! {
    #[test]
    fn offline_bounds_stay_ordered_and_bracket_the_optimum_at_every_belief(p in 0.0f64..=1.0) {
        let sol = tiger_solution();
        let b = [p, 1.0 - p];
        let (lo, up) = (sol.bounds.lower(&b), sol.bounds.upper(&b));
        proptest::prop_assert!(lo <= up + 1e-9);
        // Any valid lower bound is at least the best blind policy and at most the full-information value.
        let open_best = (10.0 * p.max(1.0 - p) - 100.0 * p.min(1.0 - p)) + 0.95 * sol.lower;
        proptest::prop_assert!(up + 1e-9 >= open_best.max(-1.0 + 0.95 * sol.lower));
        proptest::prop_assert!(up <= 10.0 / 0.05 + 1e-9);
    }
}
