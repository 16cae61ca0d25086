//! The GP module against scikit-learn 1.9.1's `GaussianProcessRegressor`
//! (`shared/data/gp/sklearn_gpr.json`, found by `avs_testdata::reference_data("gp")`: at
//! `$AVS_REFERENCE_DATA/gp` or `../shared/data/gp` beside the checkout; skipped with a notice
//! when absent).
//!
//! Tolerances: "1e-6 relative" is read as `|ours − ref| ≤ 1e-6 · max(|ref|, 1)` for the log
//! marginal likelihood, every gradient component, every mean and every std (pure relative error
//! is meaningless for a gradient component near 0). Fitted cases: the likelihood reached must be
//! at least scikit-learn's − 1e-3 and the parameters inside the bounds.

use avs_verify::gp::{eval_case, FitBounds, Gp, GpCase, GpCaseFile, SeKernel};

const TOL: f64 = 1e-6;
const LML_SLACK: f64 = 1e-3;

fn cases() -> Option<Vec<GpCase>> {
    let dir = avs_testdata::reference_data("gp")?;
    let path = dir.join("sklearn_gpr.json");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
    let file = GpCaseFile::from_json(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(!file.cases.is_empty(), "{} has no cases", path.display());
    Some(file.cases)
}

/// `|a − b|` in units of `max(|b|, 1)`.
fn err(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1.0)
}

fn worst(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| err(*x, *y))
        .fold(0.0, f64::max)
}

fn in_bounds(signal_variance: f64, length_scales: &[f64], b: &FitBounds) -> bool {
    // The fit works in log space: allow the round trip exp(ln(bound)).
    let inside = |v: f64, [lo, hi]: [f64; 2]| v >= lo * (1.0 - 1e-12) && v <= hi * (1.0 + 1e-12);
    inside(signal_variance, b.signal_variance)
        && length_scales.iter().all(|&l| inside(l, b.length_scale))
}

#[test]
fn fixed_cases_match_scikit_learn() {
    let Some(cases) = cases() else { return };
    let mut checked = 0;
    for case in cases.iter().filter(|c| !c.fitted) {
        let r = eval_case(case, 0).unwrap_or_else(|e| panic!("{}: {e}", case.name));
        let lml = err(
            r.log_marginal_likelihood,
            case.log_marginal_likelihood.unwrap(),
        );
        let grad = worst(
            &r.lml_gradient_wrt_log_params,
            case.lml_gradient_wrt_log_params.as_ref().unwrap(),
        );
        let mean = worst(&r.mean, case.mean.as_ref().unwrap());
        let std = worst(&r.std, case.std.as_ref().unwrap());
        eprintln!(
            "{:>16}: errors / max(|ref|, 1): lml {lml:.1e}, gradient {grad:.1e}, mean {mean:.1e}, std {std:.1e}",
            case.name
        );
        assert!(
            lml <= TOL,
            "{}: lml {} vs {:?}",
            case.name,
            r.log_marginal_likelihood,
            case.log_marginal_likelihood
        );
        assert!(
            grad <= TOL,
            "{}: gradient {:?} vs {:?}",
            case.name,
            r.lml_gradient_wrt_log_params,
            case.lml_gradient_wrt_log_params
        );
        assert!(
            mean <= TOL,
            "{}: mean {:?} vs {:?}",
            case.name,
            r.mean,
            case.mean
        );
        assert!(
            std <= TOL,
            "{}: std {:?} vs {:?}",
            case.name,
            r.std,
            case.std
        );
        // The parameters are the given ones.
        assert_eq!(r.signal_variance, case.signal_variance);
        assert_eq!(r.length_scale, case.length_scale);
        checked += 1;
    }
    assert!(
        checked >= 2,
        "only {checked} fixed cases in the reference file"
    );
}

#[test]
fn fitted_cases_reach_scikit_learns_likelihood() {
    let Some(cases) = cases() else { return };
    let mut checked = 0;
    for case in cases.iter().filter(|c| c.fitted) {
        let reference = case.log_marginal_likelihood.unwrap();
        let bounds = case.bounds.unwrap();
        // As the CLI does: the case's parameters (scikit-learn's optimum) as the first start.
        let r = eval_case(case, 0).unwrap_or_else(|e| panic!("{}: {e}", case.name));
        eprintln!(
            "{:>16}: lml {:.9} vs scikit-learn {reference:.9} ({:+.1e}; σ² {:.6} vs {:.6}, l {:?} vs {:?})",
            case.name,
            r.log_marginal_likelihood,
            r.log_marginal_likelihood - reference,
            r.signal_variance,
            case.signal_variance,
            r.length_scale,
            case.length_scale
        );
        assert!(
            r.log_marginal_likelihood >= reference - LML_SLACK,
            "{}",
            case.name
        );
        assert!(
            in_bounds(r.signal_variance, &r.length_scale, &bounds),
            "{}: {r:?}",
            case.name
        );
        assert_eq!(r.length_scale.len(), case.length_scale.len());

        // From a neutral start (σ² = 1, l = 1) the optimiser must find the optimum itself:
        // once from that start alone, and with restarts.
        let dim = case.x[0].len();
        let neutral = SeKernel::isotropic(1.0, 1.0, dim);
        let shared = case.length_scale.len() == 1 && dim > 1;
        for restarts in [0, 10] {
            let fit = if shared { Gp::fit_isotropic } else { Gp::fit };
            let gp = fit(
                case.x.clone(),
                case.y.clone(),
                case.noise_variance_alpha,
                &neutral,
                &bounds,
                restarts,
                1,
            )
            .unwrap_or_else(|e| panic!("{}: {e}", case.name));
            let k = gp.kernel();
            eprintln!(
                "{:>16}: from σ² = 1, l = 1 with {restarts} restarts: lml {:.9} ({:+.1e})",
                case.name,
                gp.log_marginal_likelihood(),
                gp.log_marginal_likelihood() - reference
            );
            assert!(
                gp.log_marginal_likelihood() >= reference - LML_SLACK,
                "{}",
                case.name
            );
            assert!(
                in_bounds(k.signal_variance, &k.length_scales, &bounds),
                "{k:?}"
            );
        }
        checked += 1;
    }
    assert!(checked >= 1, "no fitted case in the reference file");
}
