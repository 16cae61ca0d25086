//! Seeded simulation of the offline policy agrees with the solver's value.

use avs_pomdp::{horizon_for, read_pomdp_file, simulate, solve, OfflineOptions};

#[test]
fn simulated_return_of_the_tiger_policy_matches_its_value_and_is_reproducible() {
    let Some(dir) = avs_testdata::reference_data("pomdp") else {
        return;
    };
    let m = read_pomdp_file(dir.join("tiger.95.POMDP")).unwrap();
    let sol = solve(&m, &OfflineOptions::default()).unwrap();
    let h = horizon_for(&m, 1e-3);
    let run = |seed| simulate(&m, 1000, h, seed, |b| sol.bounds.lower_action(b)).unwrap();
    let a = run(11);
    // The policy's value is at least the lower bound and at most the optimum ≤ upper bound; the
    // Monte-Carlo mean must be within 4 standard errors of that range.
    assert!(a.mean >= sol.lower - 4.0 * a.std_error - 1e-3, "{a:?}");
    assert!(a.mean <= sol.upper + 4.0 * a.std_error + 1e-3, "{a:?}");
    assert!(a.ci95_low < a.mean && a.mean < a.ci95_high);
    assert_eq!(a, run(11));
    assert_ne!(a.mean, run(12).mean);
}

#[test]
fn zero_runs_is_an_error_not_a_panic() {
    let Some(dir) = avs_testdata::reference_data("pomdp") else {
        return;
    };
    let m = read_pomdp_file(dir.join("parr95.95.POMDP")).unwrap();
    assert!(simulate(&m, 0, 10, 1, |_| 0).is_err());
    assert!(simulate(&m, 5, 10, 1, |_| 99).is_err());
}
