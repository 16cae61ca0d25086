//! Values at the start belief of every reference file against `reference_values.csv`
//! (exact value iteration by pomdp-solve, or SARSOP), with the solver's own gap at most 1e-3.

use avs_pomdp::{read_pomdp_file, solve, OfflineOptions, StopReason};

#[test]
fn every_reference_file_solves_to_its_known_value_with_gap_below_1e_3() {
    let Some(dir) = avs_testdata::reference_data("pomdp") else {
        return;
    };
    let csv = std::fs::read_to_string(dir.join("reference_values.csv")).expect("csv readable");
    let mut checked = 0;
    for line in csv.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let cols: Vec<&str> = line.split(',').collect();
        let (file, discount, value, tol) = (
            cols[0],
            cols[1].parse::<f64>().unwrap(),
            cols[2].parse::<f64>().unwrap(),
            cols[3].parse::<f64>().unwrap(),
        );
        let m = read_pomdp_file(dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(m.discount(), discount, "{file}: discount");
        // Solve to the listed tolerance (at most 1e-3) so both bounds are within it.
        let opts = OfflineOptions {
            target_gap: tol.min(1e-3),
            ..Default::default()
        };
        let sol = solve(&m, &opts).unwrap();
        assert_eq!(sol.stop, StopReason::Converged, "{file}");
        assert!(sol.gap() <= 1e-3, "{file}: gap {}", sol.gap());
        assert!(sol.lower <= sol.upper, "{file}: bounds crossed");
        // The optimum lies in [lower, upper]: the reference (rounded to the digits printed) must too,
        // and with the gap below the tolerance both bounds are then within it.
        let decimals = cols[2].split('.').nth(1).map_or(0, str::len) as i32;
        let rounding = 0.5 * 10f64.powi(-decimals);
        assert!(
            sol.lower - rounding <= value && value <= sol.upper + rounding,
            "{file}: reference {value} outside [{}, {}]",
            sol.lower,
            sol.upper
        );
        for v in [sol.lower, sol.upper] {
            assert!(
                (v - value).abs() <= tol + rounding,
                "{file}: bound {v} vs reference {value} (tolerance {tol})"
            );
        }
        checked += 1;
    }
    assert!(
        checked >= 5,
        "expected every listed file, checked {checked}"
    );
}

#[test]
fn the_lower_bound_policy_of_tiger_listens_first() {
    let Some(dir) = avs_testdata::reference_data("pomdp") else {
        return;
    };
    // reference_values.csv: "first action listen".
    let m = read_pomdp_file(dir.join("tiger.95.POMDP")).unwrap();
    let sol = solve(&m, &OfflineOptions::default()).unwrap();
    let a = sol.bounds.lower_action(m.initial_belief());
    assert_eq!(m.actions()[a], "listen");
}

#[test]
fn a_time_budget_stops_the_solve_with_valid_bounds() {
    let Some(dir) = avs_testdata::reference_data("pomdp") else {
        return;
    };
    let m = read_pomdp_file(dir.join("cheese.95.POMDP")).unwrap();
    let sol = solve(
        &m,
        &OfflineOptions {
            target_gap: 1e-9,
            max_trials: 3,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(sol.stop, StopReason::TrialLimit);
    assert_eq!(sol.trials, 3);
    // Still bounds on the optimum 3.486207.
    assert!(sol.lower <= 3.486207 + 1e-3 && sol.upper >= 3.486207 - 1e-3);
}
