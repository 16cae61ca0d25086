//! The correlated detector's acceptance criterion: the correlation of scores from two looks
//! falls with the vantage distance between them, as the field's length scales say; plus its
//! determinism, visibility, class separation, counters and profile checks.

use avs_sim::detector::{CorrelatedDetector, Feature, ScoreProfile, Sidedness};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

/// `n` features of one class, scattered over a plane with random facings.
fn scattered(n: usize, is_object: bool, seed: u64) -> Vec<Feature> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| Feature {
            position: [rng.gen_range(-50.0..50.0), rng.gen_range(-50.0..50.0)],
            facing: rng.gen_range(-PI..PI),
            is_object,
        })
        .collect()
}

/// The waypoint from which a robot facing `f` has vantage point `(range, aspect)`.
fn waypoint(f: &Feature, range: f64, aspect: f64) -> [f64; 2] {
    let a = f.facing + aspect;
    [
        f.position[0] + range * a.cos(),
        f.position[1] + range * a.sin(),
    ]
}

fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let ma = a.iter().sum::<f64>() / n;
    let mb = b.iter().sum::<f64>() / n;
    let (mut c, mut va, mut vb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        c += (x - ma) * (y - mb);
        va += (x - ma).powi(2);
        vb += (y - mb).powi(2);
    }
    c / (va * vb).sqrt()
}

#[test]
fn score_correlation_falls_with_vantage_distance_as_the_length_scales_say() {
    let n = 4000;
    let separations = [0.0, 0.5, 1.0, 2.0, 4.0];
    // (name, profile, class, base range): every vantage below stays within range and limit.
    let cases = [
        ("door object", ScoreProfile::door(), true, 2.0),
        ("door no-object", ScoreProfile::door(), false, 2.0),
        ("sign object", ScoreProfile::sign(), true, 1.5),
        ("sign no-object", ScoreProfile::sign(), false, 1.5),
        ("generic no-object", ScoreProfile::generic(), false, 0.5),
    ];
    for (case, (name, profile, is_object, r0)) in cases.into_iter().enumerate() {
        let p = profile.params(is_object).clone();
        let (sg2, sn2) = (p.field_std.powi(2), p.noise_std.powi(2));
        let features = scattered(n, is_object, 100 + case as u64);
        let mut det = CorrelatedDetector::new(profile, features.clone(), 2012 + case as u64);
        for (axis, axis_name) in [(0, "range"), (1, "aspect")] {
            let l = p.field_length[axis];
            let mut rhos = Vec::new();
            for &t in &separations {
                let d = t * l;
                // Range: from r0 outwards at aspect 0.1; aspect: symmetric about 0 at range 3.
                let (v1, v2) = if axis == 0 {
                    ((r0, 0.1), (r0 + d, 0.1))
                } else {
                    ((3.0, -d / 2.0), (3.0, d / 2.0))
                };
                let (mut a, mut b) = (Vec::with_capacity(n), Vec::with_capacity(n));
                for (i, f) in features.iter().enumerate() {
                    let s1 = det.score(i, waypoint(f, v1.0, v1.1));
                    let s2 = det.score(i, waypoint(f, v2.0, v2.1));
                    a.push(s1.unwrap_or_else(|| panic!("{name}: {v1:?} unseen")));
                    b.push(s2.unwrap_or_else(|| panic!("{name}: {v2:?} unseen")));
                }
                let rho = correlation(&a, &b);
                let predicted = sg2 * (-0.5 * t * t).exp() / (sg2 + sn2);
                eprintln!(
                    "{name:18} {axis_name:6} Δ = {t:3} l = {d:5.2}: correlation {rho:+.3}, \
                     predicted {predicted:+.3}"
                );
                assert!(
                    (rho - predicted).abs() < 0.06,
                    "{name}, {axis_name} Δ = {t} l: correlation {rho} vs predicted {predicted}"
                );
                rhos.push(rho);
            }
            for w in rhos.windows(2) {
                assert!(
                    w[1] < w[0],
                    "{name}, {axis_name}: correlations not decreasing: {rhos:?}"
                );
            }
            let last = rhos[rhos.len() - 1];
            assert!(last.abs() < 0.06, "{name}, {axis_name}: {last} at 4 l");
        }
    }
}

#[test]
fn same_seed_gives_same_scores_and_another_seed_different_ones() {
    let features = scattered(20, true, 1);
    let run = |seed: u64| -> Vec<Option<f64>> {
        let mut det = CorrelatedDetector::new(ScoreProfile::generic(), features.clone(), seed);
        let mut out = Vec::new();
        for (i, f) in features.iter().enumerate() {
            for r in [1.0, 2.0, 3.0] {
                out.push(det.score(i, waypoint(f, r, 0.3)));
            }
        }
        out
    };
    let a = run(42);
    assert!(a.iter().all(Option::is_some));
    assert_eq!(a, run(42));
    assert_ne!(a, run(43));
}

#[test]
fn adding_a_feature_at_the_end_leaves_earlier_latent_fields_unchanged() {
    let mut features = scattered(10, false, 3);
    features.extend(scattered(10, true, 4));
    let before = CorrelatedDetector::new(ScoreProfile::door(), features.clone(), 9);
    features.push(Feature {
        position: [1.0, 2.0],
        facing: 0.5,
        is_object: true,
    });
    let mut after = CorrelatedDetector::new(ScoreProfile::door(), features.clone(), 9);
    // Looking at the new feature first must not matter to the others' latent values either.
    assert!(after.score(20, waypoint(&features[20], 3.0, 0.0)).is_some());
    let mut differs_from_mean = false;
    for (i, f) in features.iter().enumerate().take(20) {
        for (r, phi) in [(1.0, 0.0), (3.0, 0.7), (6.0, -1.2), (2.5, 2.9)] {
            let l = before.latent(i, r, phi);
            assert_eq!(l, after.latent(i, r, phi), "feature {i} at ({r}, {phi})");
            let m = before.profile().mean(f.is_object, r, phi);
            differs_from_mean |= (l - m).abs() > 1e-3;
        }
    }
    // The field is really there (not all zero).
    assert!(differs_from_mean);
}

#[test]
fn one_sided_sign_is_unseen_from_behind_or_beyond_45_degrees() {
    let sign = Feature {
        position: [1.0, -2.0],
        facing: PI / 2.0,
        is_object: true,
    };
    let mut det = CorrelatedDetector::new(ScoreProfile::sign(), vec![sign.clone()], 5);
    assert!(det.score(0, waypoint(&sign, 3.0, 0.0)).is_some());
    assert!(det
        .score(0, waypoint(&sign, 3.0, 40f64.to_radians()))
        .is_some());
    assert!(det
        .score(0, waypoint(&sign, 3.0, -40f64.to_radians()))
        .is_some());
    assert!(det
        .score(0, waypoint(&sign, 3.0, 50f64.to_radians()))
        .is_none());
    assert!(det
        .score(0, waypoint(&sign, 3.0, -50f64.to_radians()))
        .is_none());
    assert!(det.score(0, waypoint(&sign, 3.0, PI)).is_none());
    assert!(det
        .score(0, waypoint(&sign, 3.0, 170f64.to_radians()))
        .is_none());
    assert!(det.score(0, waypoint(&sign, 8.5, 0.0)).is_none());
    // The vantage really is behind: aspect π from the opposite side.
    let (r, phi) = det.vantage(0, waypoint(&sign, 3.0, PI));
    assert!((r - 3.0).abs() < 1e-9 && (phi.abs() - PI).abs() < 1e-9);
}

#[test]
fn two_sided_door_is_seen_from_both_sides_within_80_degrees() {
    let door = Feature {
        position: [0.0, 0.0],
        facing: 0.3,
        is_object: true,
    };
    let mut det = CorrelatedDetector::new(ScoreProfile::door(), vec![door.clone()], 5);
    for deg in [0.0, 75.0, -75.0, 105.0, -105.0, 180.0] {
        let w = waypoint(&door, 4.0, f64::to_radians(deg));
        assert!(det.score(0, w).is_some(), "door unseen at {deg}°");
    }
    for deg in [85.0, -85.0, 95.0, -95.0] {
        let w = waypoint(&door, 4.0, f64::to_radians(deg));
        assert!(det.score(0, w).is_none(), "door seen edge-on at {deg}°");
    }
    assert!(det.score(0, waypoint(&door, 10.5, PI)).is_none());
    // The mean is symmetric front to back.
    let p = det.profile();
    assert!((p.mean(true, 4.0, 0.2) - p.mean(true, 4.0, PI - 0.2)).abs() < 1e-12);
}

#[test]
fn objects_score_higher_than_no_objects_at_the_best_range_and_fire_above_the_threshold() {
    let profile = ScoreProfile::door();
    let n = 2000;
    let mut features = scattered(n, true, 7);
    features.extend(scattered(n, false, 8));
    let mut det = CorrelatedDetector::new(profile.clone(), features.clone(), 77);
    let (mut sum, mut fired) = ([0.0; 2], [0usize; 2]);
    for (i, f) in features.iter().enumerate() {
        let z = det.score(i, waypoint(f, profile.r_best, 0.0)).unwrap();
        let c = usize::from(!f.is_object);
        sum[c] += z;
        fired[c] += usize::from(det.fires(z));
    }
    let (obj, non) = (sum[0] / n as f64, sum[1] / n as f64);
    eprintln!(
        "mean score at r_best: objects {obj:.3}, no-objects {non:.3}; fired {fired:?} of {n}"
    );
    assert!((obj - 2.0).abs() < 0.1, "{obj}");
    assert!((non - 0.9).abs() < 0.1, "{non}");
    assert!(obj > non + 0.8);
    assert!(fired[0] > fired[1] + n / 4, "{fired:?}");
    assert!(!det.fires(profile.fire_threshold));
    assert!(det.fires(profile.fire_threshold + 1e-9));
    assert!(!det.fires(0.5));
}

#[test]
fn look_scores_features_in_the_field_of_view_and_counts_processing_time() {
    let ahead = Feature {
        position: [3.0, 0.0],
        facing: PI,
        is_object: true,
    };
    let behind = Feature {
        position: [-3.0, 0.0],
        facing: 0.0,
        is_object: false,
    };
    let side_on = Feature {
        position: [3.0, 0.5],
        facing: PI / 2.0,
        is_object: true,
    };
    let mut det = CorrelatedDetector::new(ScoreProfile::sign(), vec![ahead, behind, side_on], 1);
    let seen = det.look([0.0, 0.0], 0.0, 0.5);
    // `behind` is outside the field of view; `side_on` is within it but seen beyond 45°.
    assert_eq!(seen.iter().map(|s| s.0).collect::<Vec<_>>(), vec![0]);
    assert_eq!((det.images(), det.processing_seconds()), (1, 8.0));
    let seen = det.look([0.0, 0.0], PI, 0.5);
    assert_eq!(seen.iter().map(|s| s.0).collect::<Vec<_>>(), vec![1]);
    // Scoring a single feature counts no image.
    assert!(det.score(0, [0.0, 0.0]).is_some());
    assert_eq!((det.images(), det.processing_seconds()), (2, 16.0));
}

#[test]
fn check_rejects_a_negative_length_scale_naming_the_field() {
    let mut p = ScoreProfile::door();
    p.object.field_length[0] = -1.5;
    let e = p.check().unwrap_err();
    assert!(
        e.contains("object.field_length[0]") && e.contains("> 0"),
        "{e}"
    );
    let mut p = ScoreProfile::sign();
    p.no_object.field_length[1] = -0.2;
    let e = p.check().unwrap_err();
    assert!(e.contains("no_object.field_length[1]"), "{e}");
    let mut p = ScoreProfile::generic();
    p.r_width = 0.0;
    assert!(p.check().unwrap_err().contains("r_width"));
}

#[test]
#[should_panic(expected = "object.field_std")]
fn new_detector_refuses_an_invalid_profile() {
    let mut p = ScoreProfile::generic();
    p.object.field_std = -0.5;
    CorrelatedDetector::new(p, Vec::new(), 0);
}

#[test]
fn profiles_round_trip_through_yaml_with_snake_case_sidedness() {
    let text = serde_yaml::to_string(&ScoreProfile::door()).unwrap();
    assert!(text.contains("sidedness: two_sided"), "{text}");
    let back: ScoreProfile = serde_yaml::from_str(&text).unwrap();
    assert_eq!(back, ScoreProfile::door());
    let s: Sidedness = serde_yaml::from_str("one_sided").unwrap();
    assert_eq!(s, Sidedness::OneSided);
    assert_eq!(
        serde_yaml::to_string(&Sidedness::AllRound).unwrap().trim(),
        "all_round"
    );
}
