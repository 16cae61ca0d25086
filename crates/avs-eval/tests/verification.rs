//! The detection-verification harness: the shipped scenarios, the strategies against each
//! other (with fewer trials than the bench), and impossible candidates.

use avs_eval::verification::{
    model_kind, profile_of, run_bench, run_bench_with, run_trial, train_model, Strategy,
    VerificationWorld, SHIPPED,
};
use avs_format::verification::DetectorName;
use std::path::Path;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

#[test]
fn the_shipped_scenarios_are_the_files_in_the_repository_and_build() {
    for (name, text) in SHIPPED {
        let path = root().join(format!("domains/verification/{name}.yaml"));
        assert_eq!(std::fs::read_to_string(&path).unwrap(), text, "{name}");
        let w = VerificationWorld::named_or_file(name).unwrap();
        assert_eq!(w.scenario.name, name);
        VerificationWorld::load(&path).unwrap();
    }
    // The paper's scenario sizes (objects + look-alikes).
    let count = |n: &str| {
        let w = VerificationWorld::named_or_file(n).unwrap();
        let o = w.scenario.features.iter().filter(|f| f.object).count();
        (o, w.scenario.features.len() - o)
    };
    assert_eq!(count("single-door"), (1, 2));
    assert_eq!(count("multi-door"), (4, 6));
    assert_eq!(count("single-sign"), (1, 1));
    assert_eq!(count("multi-sign"), (2, 2));
}

#[test]
fn a_trial_is_deterministic_for_a_seed() {
    let w = VerificationWorld::named_or_file("single-sign").unwrap();
    let spec = train_model(
        &profile_of(DetectorName::Sign),
        model_kind(Strategy::Planned, DetectorName::Sign),
        5,
    )
    .unwrap();
    let m = avs_verify::sensor::SensorModel::from_spec(&spec).unwrap();
    let a = run_trial(&w, &m, Strategy::Planned, 3).unwrap();
    let b = run_trial(&w, &m, Strategy::Planned, 3).unwrap();
    assert_eq!(a.decisions, b.decisions);
    assert_eq!(a.path_length, b.path_length);
}

#[test]
fn features_inside_walls_or_behind_them_never_hang_a_trial() {
    // A look-alike inside the wall block and an object in a closed-off pocket: neither can be
    // seen, so neither becomes a candidate; the robot drives to the goal.
    let text = "kind: verification
name: walled
map:
  resolution: 0.5
  ascii: |
    ####################
    #..................#
    #.......####.......#
    #.......#..#.......#
    #.......####.......#
    #..................#
    ####################
start: { x: 1.25, y: 1.25 }
goal: { x: 8.75, y: 1.25 }
detector: generic
fov_deg: 180
features:
  - { x: 4.25, y: 2.25, object: false }
  - { x: 5.25, y: 1.75, object: true }
  - { x: 2.25, y: 2.75, object: true }
";
    let w = VerificationWorld::from_text("walled.yaml", text, Path::new(".")).unwrap();
    for strategy in [Strategy::Planned, Strategy::Greedy(0.8)] {
        let r = run_bench(&w, strategy, 3, 1).unwrap();
        for t in &r.trial_results {
            assert!(
                t.decisions.iter().all(|d| d.feature == 2),
                "{:?}",
                t.decisions
            );
            assert!(t.path_length < 30.0, "{}", t.path_length);
        }
    }
}

#[test]
fn a_scenario_whose_goal_is_walled_off_is_rejected_naming_the_field() {
    let text = "kind: verification
name: shut
map:
  resolution: 0.5
  ascii: |
    ##########
    #...#....#
    #...#....#
    ##########
start: { x: 0.75, y: 0.75 }
goal: { x: 3.75, y: 0.75 }
detector: door
features:
  - { x: 1.25, y: 1.25, object: true }
";
    let e = VerificationWorld::from_text("shut.yaml", text, Path::new("."))
        .err()
        .expect("an unreachable goal is an error");
    let msg = e.to_string();
    assert!(msg.contains("shut.yaml") && msg.contains("goal"), "{msg}");
}

/// What the planned verifier's cost function promises against the two GREEDY baselines, with
/// fewer trials than the bench (the tables are in BENCHMARKS.md): it weighs motion, so it
/// drives less than GREEDY(0.8), which chases each candidate's best vantage point whatever the
/// detour; and it weighs wrong decisions at 16 m, so it is at least as precise as GREEDY(0.6),
/// which accepts at 0.6 (within their combined standard error).
///
/// (Velez et al.'s stronger claim — the best baseline's precision *and* recall at no more than
/// its path + 10 % — holds on the sign scenarios but not yet on the door scenarios: see the
/// issue notes and BENCHMARKS.md.)
#[test]
fn the_planned_verifier_drives_less_than_greedy_and_decides_no_worse_than_its_loose_form() {
    let trials = 12;
    for (name, ours) in [
        ("single-door", Strategy::PlannedDisc),
        ("single-sign", Strategy::Planned),
        ("multi-sign", Strategy::Planned),
    ] {
        let w = VerificationWorld::named_or_file(name).unwrap();
        let d = w.scenario.detector;
        // One trained model per kind (GREEDY uses the disc model on doors, the dynamic one on
        // signs: the same kind as ours here).
        let spec = train_model(&profile_of(d), model_kind(ours, d), 7).unwrap();
        let model = avs_verify::sensor::SensorModel::from_spec(&spec).unwrap();
        assert_eq!(model_kind(ours, d), model_kind(Strategy::Greedy(0.8), d));
        let p = run_bench_with(&w, &model, ours, trials, 100).unwrap();
        let g8 = run_bench_with(&w, &model, Strategy::Greedy(0.8), trials, 100).unwrap();
        let g6 = run_bench_with(&w, &model, Strategy::Greedy(0.6), trials, 100).unwrap();
        assert!(
            p.path_length_mean < g8.path_length_mean,
            "{name}: path {:.1} vs GREEDY(0.8) {:.1}",
            p.path_length_mean,
            g8.path_length_mean
        );
        let margin = (p.precision_se.powi(2) + g6.precision_se.powi(2)).sqrt();
        assert!(
            p.precision >= g6.precision - margin,
            "{name}: precision {:.2} vs GREEDY(0.6) {:.2}",
            p.precision,
            g6.precision
        );
    }
}

/// The trained GP_corr recovers the simulated detector's own nuisance field and white noise
/// (the simulator's profile is the oracle): variance, both length scales and the noise within
/// 20 %.
#[test]
fn training_recovers_the_simulated_detectors_correlation() {
    for d in [DetectorName::Door, DetectorName::Sign] {
        let profile = profile_of(d);
        let spec = train_model(&profile, model_kind(Strategy::Planned, d), 7).unwrap();
        for (h, truth) in [
            (&spec.object, &profile.object),
            (&spec.no_object, &profile.no_object),
        ] {
            let near = |fit: f64, want: f64, what: &str| {
                assert!(
                    (fit / want - 1.0).abs() < 0.2,
                    "{d:?} {what}: fitted {fit:.3}, simulated {want:.3}"
                );
            };
            near(
                h.corr.kernel.signal_variance,
                truth.field_std.powi(2),
                "field variance",
            );
            near(
                h.corr.kernel.length_scales[0],
                truth.field_length[0],
                "range length scale",
            );
            near(
                h.corr.kernel.length_scales[1],
                truth.field_length[1],
                "aspect length scale",
            );
            near(
                h.corr.noise_variance,
                truth.noise_std.powi(2),
                "white noise",
            );
        }
    }
}
