use super::cases::{MAX_DIM, MAX_FIT_POINTS};
use super::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

fn random_data(rng: &mut ChaCha8Rng, n: usize, dim: usize) -> (Vec<Vec<f64>>, Vec<f64>) {
    let x: Vec<Vec<f64>> = (0..n)
        .map(|_| (0..dim).map(|_| rng.gen_range(-3.0..3.0)).collect())
        .collect();
    let y = x
        .iter()
        .map(|p| p.iter().map(|v| v.sin()).sum::<f64>() + 0.1 * rng.gen_range(-1.0..1.0))
        .collect();
    (x, y)
}

fn lml_at(log_params: &[f64], noise: f64, x: &[Vec<f64>], y: &[f64]) -> f64 {
    lml_at_angular(log_params, &[], noise, x, y)
}

fn lml_at_angular(
    log_params: &[f64],
    angular: &[bool],
    noise: f64,
    x: &[Vec<f64>],
    y: &[f64],
) -> f64 {
    let kernel = SeKernel {
        signal_variance: log_params[0].exp(),
        length_scales: log_params[1..].iter().map(|t| t.exp()).collect(),
        angular: angular.to_vec(),
    };
    Gp::new(kernel, noise, x.to_vec(), y.to_vec())
        .unwrap()
        .log_marginal_likelihood()
}

fn bounds() -> FitBounds {
    FitBounds {
        signal_variance: [1e-2, 1e2],
        length_scale: [1e-2, 1e2],
    }
}

#[test]
fn the_gradient_matches_central_differences() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for trial in 0..6 {
        let dim = 1 + trial % 3;
        let (x, y) = random_data(&mut rng, 12 + trial, dim);
        let theta: Vec<f64> = (0..=dim).map(|_| rng.gen_range(-1.0..1.0)).collect();
        // Every other trial has an angle for its last input (the chord difference).
        let angular: Vec<bool> = (0..dim).map(|d| trial % 2 == 1 && d + 1 == dim).collect();
        let noise = 0.05;
        let gp = Gp::new(
            SeKernel {
                signal_variance: theta[0].exp(),
                length_scales: theta[1..].iter().map(|t| t.exp()).collect(),
                angular: angular.clone(),
            },
            noise,
            x.clone(),
            y.clone(),
        )
        .unwrap();
        let g = gp.lml_gradient_wrt_log_params();
        assert_eq!(g.len(), 1 + dim);
        let h = 1e-5;
        for k in 0..=dim {
            let mut up = theta.clone();
            let mut down = theta.clone();
            up[k] += h;
            down[k] -= h;
            let fd = (lml_at_angular(&up, &angular, noise, &x, &y)
                - lml_at_angular(&down, &angular, noise, &x, &y))
                / (2.0 * h);
            assert!(
                (g[k] - fd).abs() <= 1e-6 * fd.abs().max(1.0),
                "trial {trial}, component {k}: analytic {} vs finite difference {fd}",
                g[k]
            );
        }
        // The isotropic gradient is the derivative along all log length scales at once.
        let iso = gp.lml_gradient_wrt_log_params_isotropic();
        let shift = |t: f64| -> Vec<f64> {
            std::iter::once(theta[0])
                .chain(theta[1..].iter().map(|v| v + t))
                .collect()
        };
        let fd = (lml_at_angular(&shift(h), &angular, noise, &x, &y)
            - lml_at_angular(&shift(-h), &angular, noise, &x, &y))
            / (2.0 * h);
        assert!(
            (iso[1] - fd).abs() <= 1e-6 * fd.abs().max(1.0),
            "{iso:?} vs {fd}"
        );
    }
}

#[test]
fn a_training_point_is_reproduced_with_tiny_noise() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let (x, y) = random_data(&mut rng, 10, 2);
    let gp = Gp::new(
        SeKernel::isotropic(1.5, 0.8, 2),
        1e-10,
        x.clone(),
        y.clone(),
    )
    .unwrap();
    for (p, t) in x.iter().zip(&y) {
        let (m, v) = gp.predict(p);
        assert!((m - t).abs() < 1e-6, "mean {m} vs target {t}");
        assert!((0.0..1e-8).contains(&v), "variance {v}");
    }
    // Noise keeps the variance at a training point away from zero and the mean off the target.
    let noisy = Gp::new(SeKernel::isotropic(1.5, 0.8, 2), 0.5, x.clone(), y).unwrap();
    assert!(noisy.predict(&x[0]).1 > 0.05);
}

#[test]
fn far_from_the_data_the_prediction_is_the_prior() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let (x, y) = random_data(&mut rng, 15, 3);
    let kernel = SeKernel {
        signal_variance: 2.5,
        length_scales: vec![0.5, 1.0, 2.0],
        angular: Vec::new(),
    };
    let gp = Gp::new(kernel.clone(), 1e-3, x, y).unwrap();
    let (m, v) = gp.predict(&[100.0, -100.0, 100.0]);
    assert!(m.abs() < 1e-12, "mean {m}");
    assert!((v - 2.5).abs() < 1e-12, "variance {v}");
    // Near the data the variance is well below the prior's.
    let (_, v) = gp.predict(gp.inputs()[0].clone().as_slice());
    assert!(v < 0.1 * 2.5);

    // And with no data at all the GP is its prior everywhere.
    let prior = Gp::prior(kernel, 1e-3).unwrap();
    assert!(prior.is_empty());
    assert_eq!(prior.len(), 0);
    assert_eq!(prior.predict(&[0.0, 0.0, 0.0]), (0.0, 2.5));
    assert_eq!(prior.log_marginal_likelihood(), 0.0);
    assert_eq!(prior.lml_gradient_wrt_log_params(), vec![0.0; 4]);
}

#[test]
fn batch_prediction_and_incremental_conditioning_agree() {
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let (x, y) = random_data(&mut rng, 9, 2);
    let kernel = SeKernel {
        signal_variance: 1.0,
        length_scales: vec![0.7, 1.3],
        angular: Vec::new(),
    };
    let all = Gp::new(kernel.clone(), 0.01, x.clone(), y.clone()).unwrap();
    let mut inc = Gp::prior(kernel, 0.01).unwrap();
    for (p, t) in x.iter().zip(&y) {
        inc = inc.with_observation(p.clone(), *t).unwrap();
    }
    assert_eq!(inc.len(), 9);
    let (q, _) = random_data(&mut rng, 7, 2);
    let batch = all.predict_batch(&q);
    for (p, (m, v)) in q.iter().zip(&batch) {
        let (m1, v1) = all.predict(p);
        let (m2, v2) = inc.predict(p);
        assert!((m - m1).abs() < 1e-12 && (v - v1).abs() < 1e-12);
        assert!((m - m2).abs() < 1e-9 && (v - v2).abs() < 1e-9);
    }
    assert!((all.log_marginal_likelihood() - inc.log_marginal_likelihood()).abs() < 1e-9);
}

#[test]
fn fit_is_deterministic_for_a_seed_and_stays_in_bounds() {
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let (x, y) = random_data(&mut rng, 20, 2);
    let init = SeKernel::isotropic(1.0, 1.0, 2);
    let fit = |seed| Gp::fit(x.clone(), y.clone(), 1e-2, &init, &bounds(), 4, seed).unwrap();
    let a = fit(9);
    let b = fit(9);
    assert_eq!(a.kernel(), b.kernel());
    assert_eq!(
        a.log_marginal_likelihood().to_bits(),
        b.log_marginal_likelihood().to_bits()
    );
    let start = Gp::new(init.clone(), 1e-2, x.clone(), y.clone()).unwrap();
    assert!(a.log_marginal_likelihood() > start.log_marginal_likelihood());
    let k = a.kernel();
    assert!((1e-2..=1e2).contains(&k.signal_variance));
    assert!(k.length_scales.iter().all(|l| (1e-2..=1e2).contains(l)));
    // At an interior optimum the gradient vanishes.
    let g = a.lml_gradient_wrt_log_params();
    assert!(g.iter().all(|c| c.abs() < 1e-4), "gradient {g:?} at {k:?}");
}

#[test]
fn fit_reaches_the_best_likelihood_on_a_grid() {
    // One input: the likelihood over (log σ², log l) on a 60 × 60 grid inside the bounds; the
    // fit must be at least as good as every grid point.
    let x: Vec<Vec<f64>> = (0..12).map(|i| vec![i as f64 * 0.7]).collect();
    let y: Vec<f64> = x.iter().map(|p| 3.0 * (0.8 * p[0]).sin() + 0.5).collect();
    let noise = 1e-4;
    let init = SeKernel {
        signal_variance: 1.0,
        length_scales: vec![1.0],
        angular: Vec::new(),
    };
    let gp = Gp::fit(x.clone(), y.clone(), noise, &init, &bounds(), 0, 0).unwrap();
    let (lo, hi) = (1e-2f64.ln(), 1e2f64.ln());
    let mut best = f64::NEG_INFINITY;
    for i in 0..60 {
        for j in 0..60 {
            let t = [
                lo + (hi - lo) * i as f64 / 59.0,
                lo + (hi - lo) * j as f64 / 59.0,
            ];
            let kernel = SeKernel {
                signal_variance: t[0].exp(),
                length_scales: vec![t[1].exp()],
                angular: Vec::new(),
            };
            if let Ok(g) = Gp::new(kernel, noise, x.clone(), y.clone()) {
                best = best.max(g.log_marginal_likelihood());
            }
        }
    }
    assert!(
        gp.log_marginal_likelihood() >= best - 1e-9,
        "fit {} < grid {best}",
        gp.log_marginal_likelihood()
    );
}

#[test]
fn an_optimum_beyond_a_bound_stops_on_the_bound() {
    // A smooth function wants a long length scale; with l ≤ 0.3 the fit must end on l = 0.3
    // with the gradient pointing outward.
    let x: Vec<Vec<f64>> = (0..10).map(|i| vec![i as f64 * 0.2]).collect();
    let y: Vec<f64> = x.iter().map(|p| 0.5 * p[0]).collect();
    let b = FitBounds {
        signal_variance: [1e-2, 1e2],
        length_scale: [1e-2, 0.3],
    };
    let init = SeKernel {
        signal_variance: 1.0,
        length_scales: vec![0.1],
        angular: Vec::new(),
    };
    for fit in [Gp::fit, Gp::fit_isotropic] {
        let gp = fit(x.clone(), y.clone(), 1e-4, &init, &b, 3, 1).unwrap();
        assert_eq!(gp.kernel().length_scales, vec![0.3]);
        let g = gp.lml_gradient_wrt_log_params();
        assert!(g[1] > 0.0, "gradient {g:?}");
        assert!(g[0].abs() < 1e-4, "σ² is interior: gradient {g:?}");
    }
}

#[test]
fn isotropic_fit_shares_one_length_scale() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let (x, y) = random_data(&mut rng, 15, 3);
    let init = SeKernel {
        signal_variance: 1.0,
        length_scales: vec![0.5, 1.0, 2.0],
        angular: Vec::new(),
    };
    let iso = Gp::fit_isotropic(x.clone(), y.clone(), 1e-2, &init, &bounds(), 2, 4).unwrap();
    let ls = &iso.kernel().length_scales;
    assert_eq!(ls.len(), 3);
    assert!(ls.iter().all(|l| *l == ls[0]));
    assert!(iso.lml_gradient_wrt_log_params_isotropic()[1].abs() < 1e-4);
    // Free length scales can only do better.
    let ard = Gp::fit(x, y, 1e-2, &init, &bounds(), 2, 4).unwrap();
    assert!(ard.log_marginal_likelihood() >= iso.log_marginal_likelihood() - 1e-9);
}

#[test]
fn bad_inputs_are_typed_errors() {
    let k1 = SeKernel {
        signal_variance: 1.0,
        length_scales: vec![1.0],
        angular: Vec::new(),
    };
    let x = vec![vec![0.0], vec![1.0]];
    let y = vec![0.0, 1.0];
    let new = |k: &SeKernel, noise: f64, x: Vec<Vec<f64>>, y: Vec<f64>| {
        Gp::new(k.clone(), noise, x, y).unwrap_err()
    };
    assert!(matches!(
        new(&k1, 0.1, vec![vec![0.0], vec![1.0, 2.0]], y.clone()),
        GpError::DimensionMismatch { ref what, expected: 1, found: 2 } if what == "x[1]"
    ));
    assert_eq!(
        new(&k1, 0.1, x.clone(), vec![0.0]),
        GpError::LengthMismatch {
            inputs: 2,
            targets: 1
        }
    );
    assert!(matches!(
        new(&k1, 0.1, vec![vec![0.0], vec![f64::NAN]], y.clone()),
        GpError::NonFinite { ref what, .. } if what == "x[1][0]"
    ));
    assert!(matches!(
        new(&k1, 0.1, x.clone(), vec![0.0, f64::INFINITY]),
        GpError::NonFinite { ref what, .. } if what == "y[1]"
    ));
    let zero_l = SeKernel {
        signal_variance: 1.0,
        length_scales: vec![0.0],
        angular: Vec::new(),
    };
    let e = new(&zero_l, 0.1, x.clone(), y.clone());
    assert!(matches!(e, GpError::NonPositive { ref what, .. } if what == "length_scales[0]"));
    assert!(e.to_string().contains("length_scales[0]"), "{e}");
    let nan_sv = SeKernel {
        signal_variance: f64::NAN,
        length_scales: vec![1.0],
        angular: Vec::new(),
    };
    assert!(matches!(
        new(&nan_sv, 0.1, x.clone(), y.clone()),
        GpError::NonFinite { .. }
    ));
    let no_inputs = SeKernel {
        signal_variance: 1.0,
        length_scales: vec![],
        angular: Vec::new(),
    };
    assert_eq!(new(&no_inputs, 0.1, vec![], vec![]), GpError::NoInputs);
    assert!(matches!(
        new(&k1, -1.0, x.clone(), y.clone()),
        GpError::Negative { .. }
    ));
    // The same point twice without noise: K is singular.
    assert_eq!(
        new(&k1, 0.0, vec![vec![1.0], vec![1.0]], y.clone()),
        GpError::NotPositiveDefinite { n: 2 }
    );
    // Fitting checks the same, and the bounds.
    let bad_bounds = FitBounds {
        signal_variance: [1.0, 0.5],
        length_scale: [1e-2, 1e2],
    };
    assert!(matches!(
        Gp::fit(x.clone(), y.clone(), 0.1, &k1, &bad_bounds, 0, 0),
        Err(GpError::InvalidBounds { .. })
    ));
    assert!(matches!(
        Gp::fit(vec![vec![0.0, 1.0]], vec![0.0], 0.1, &k1, &bounds(), 0, 0),
        Err(GpError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        Gp::fit(x.clone(), y.clone(), f64::NAN, &k1, &bounds(), 0, 0),
        Err(GpError::NonFinite { .. })
    ));
    // Duplicates without noise: singular at every start.
    assert_eq!(
        Gp::fit(
            vec![vec![1.0], vec![1.0]],
            y.clone(),
            0.0,
            &k1,
            &bounds(),
            2,
            0
        )
        .unwrap_err(),
        GpError::FitFailed { n: 2 }
    );
    // Checked prediction.
    let gp = Gp::new(k1, 0.1, x, y).unwrap();
    assert!(matches!(
        gp.try_predict_batch(&[vec![0.0], vec![0.0, 1.0]]),
        Err(GpError::DimensionMismatch { ref what, .. }) if what == "query[1]"
    ));
    assert!(gp.try_predict_batch(&[vec![f64::NAN]]).is_err());
    assert_eq!(
        gp.try_predict_batch(&[vec![0.5]]).unwrap(),
        vec![gp.predict(&[0.5])]
    );
}

#[test]
fn malformed_cases_name_the_field() {
    let good = r#"{"name": "c", "X": [[0.0], [1.0]], "y": [0.0, 1.0], "X_query": [[0.5]],
        "noise_variance_alpha": 1e-6, "fitted": false, "signal_variance": 1.0,
        "length_scale": [1.0]}"#;
    let parse = |case: &str| GpCaseFile::from_json(&format!(r#"{{"cases": [{case}]}}"#));
    let case = parse(good).unwrap().cases.remove(0);
    assert_eq!(eval_case(&case, 0).unwrap().mean.len(), 1);

    let field_of = |c: &GpCase| match eval_case(c, 0) {
        Err(GpError::Field { field, .. }) => field,
        other => panic!("expected a field error, got {other:?}"),
    };
    let mut c = case.clone();
    c.y.pop();
    assert_eq!(field_of(&c), "y");
    let mut c = case.clone();
    c.x_query[0].push(1.0);
    assert_eq!(field_of(&c), "X_query[0]");
    let mut c = case.clone();
    c.length_scale = vec![1.0, 2.0];
    assert_eq!(field_of(&c), "length_scale");
    let mut c = case.clone();
    c.length_scale = vec![0.0];
    assert_eq!(field_of(&c), "length_scale[0]");
    let mut c = case.clone();
    c.fitted = true;
    assert_eq!(field_of(&c), "bounds");
    let mut c = case.clone();
    c.x = vec![vec![0.0; MAX_DIM + 1]];
    assert_eq!(field_of(&c), "X");
    let mut c = case.clone();
    c.fitted = true;
    c.bounds = Some(bounds());
    c.x = (0..=MAX_FIT_POINTS).map(|i| vec![i as f64]).collect();
    c.y = vec![0.0; MAX_FIT_POINTS + 1];
    assert_eq!(field_of(&c), "X");

    // Parse errors say where.
    let e = parse(&good.replace("[[0.5]]", r#"[["a"]]"#)).unwrap_err();
    assert!(
        matches!(e, GpError::Parse { ref path, .. } if path == "cases[0].X_query[0][0]"),
        "{e}"
    );
    let e = parse(&good.replace(r#""y": [0.0, 1.0],"#, "")).unwrap_err();
    assert!(e.to_string().contains("missing field `y`"), "{e}");
    assert!(matches!(
        GpCaseFile::from_json("{\"cases\": [").unwrap_err(),
        GpError::Parse { .. }
    ));
}

#[test]
fn the_blocked_triangular_solve_matches_forward_substitution() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    for n in [1, 64, 65, 150, 301] {
        let l = DMatrix::from_fn(n, n, |i, j| match i.cmp(&j) {
            std::cmp::Ordering::Less => 0.0,
            std::cmp::Ordering::Equal => rng.gen_range(1.0..2.0),
            std::cmp::Ordering::Greater => rng.gen_range(-1.0..1.0) / n as f64,
        });
        let b = DMatrix::from_fn(n, 7, |_, _| rng.gen_range(-1.0..1.0));
        let x = solve_lower(l.as_view(), b.clone());
        let direct = l.solve_lower_triangular(&b).unwrap();
        assert!((&x - &direct).amax() < 1e-12, "n = {n}");
        assert!((&l * &x - &b).amax() < 1e-12, "n = {n}");
    }
    // And through a GP large enough to take the blocked path: the gradient still matches
    // finite differences.
    let (x, y) = random_data(&mut rng, 140, 2);
    let theta = [0.2f64, -0.3, 0.4];
    let gp = Gp::new(
        SeKernel {
            signal_variance: theta[0].exp(),
            length_scales: vec![theta[1].exp(), theta[2].exp()],
            angular: Vec::new(),
        },
        0.05,
        x.clone(),
        y.clone(),
    )
    .unwrap();
    let g = gp.lml_gradient_wrt_log_params();
    let h = 1e-5;
    for k in 0..3 {
        let (mut up, mut down) = (theta.to_vec(), theta.to_vec());
        up[k] += h;
        down[k] -= h;
        let fd = (lml_at(&up, 0.05, &x, &y) - lml_at(&down, 0.05, &x, &y)) / (2.0 * h);
        assert!(
            (g[k] - fd).abs() <= 1e-6 * fd.abs().max(1.0),
            "{k}: {} vs {fd}",
            g[k]
        );
    }
}

#[test]
fn the_mean_alone_is_the_mean_of_predict() {
    let k = SeKernel {
        signal_variance: 1.3,
        length_scales: vec![0.7, 2.0],
        angular: Vec::new(),
    };
    let x = vec![
        vec![0.0, 0.0],
        vec![1.0, 0.5],
        vec![2.0, -1.0],
        vec![0.3, 3.0],
    ];
    let y = vec![0.5, -1.0, 2.0, 0.1];
    let gp = Gp::new(k, 0.05, x, y).unwrap();
    for q in [[0.2, 0.1], [1.5, -0.5], [5.0, 5.0]] {
        assert!((gp.predict_mean(&q) - gp.predict(&q).0).abs() < 1e-12);
    }
}

#[test]
fn an_angular_input_has_no_seam_at_plus_minus_pi() {
    let k = SeKernel {
        signal_variance: 1.0,
        length_scales: vec![1.0, 0.3],
        angular: vec![false, true],
    };
    // 3.1 and −3.1 rad are 0.083 rad apart on the circle: as correlated as 0.0 and 0.083.
    let across = k.eval(&[1.0, 3.1], &[1.0, -3.1]);
    let near = k.eval(&[1.0, 0.0], &[1.0, 2.0 * PI - 6.2]);
    assert!(
        (across - near).abs() < 1e-12 && across > 0.9,
        "{across} vs {near}"
    );
    // A full turn is no difference at all; the linear input is unchanged.
    assert!((k.eval(&[0.0, 0.5], &[0.0, 0.5 + 2.0 * PI]) - 1.0).abs() < 1e-12);
    let plain = SeKernel {
        angular: vec![],
        ..k.clone()
    };
    assert!(plain.eval(&[1.0, 3.1], &[1.0, -3.1]) < 1e-50);
    assert_eq!(
        k.eval(&[0.0, 1.0], &[2.0, 1.0]),
        plain.eval(&[0.0, 1.0], &[2.0, 1.0])
    );
}
