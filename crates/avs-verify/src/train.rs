//! Training a sensor model from labelled looks (Velez et al. 2012 §4.2.3): looks at features
//! whose label (object or not) is known, each a vantage point and a score, grouped by feature.
//!
//! Per hypothesis `y`:
//! 1. **GP_ind** (eq. 13). The looks are binned on a vantage grid (the paper's per-waypoint
//!    histograms); each bin with looks of two or more features gives a training point (the mean
//!    over its features of their mean vantage and score: looks of one feature share its nuisance
//!    field, so a feature counts once). The spread of single scores about their bin's mean,
//!    pooled over bins, is the variance of one look about the latent mean
//!    ([`ScoreGp::spread`]); the bin means' noise variance is that spread over the median number
//!    of features per bin. The kernel is fitted by
//!    maximum likelihood ([`Gp::fit`]) from a first start at Table 1's values and seeded restarts.
//! 2. **GP_corr** (eq. 14). The residuals of each feature's looks about GP_ind's mean are one
//!    sample of that feature's residual field. The white noise is half the mean squared
//!    difference of two looks taken from the same spot (every feature's training has such a
//!    pair); the field's variance is the residuals' variance minus the white noise; the length
//!    scales maximise the summed log marginal likelihood of the per-feature subsets (a kernel
//!    shared by independent GPs, one per feature — eq. 14's "per-object training subsets").
//! 3. **κ** of eq. 17 maximises the likelihood of every feature's looks in the order taken,
//!    each under the mixture conditioned on the looks before it (the paper's maximum-likelihood
//!    scale factor).
//!
//! # Choices where the paper is vague
//! * GP_corr's two length scales and κ are found by a search over a logarithmic grid (16 × 16
//!   refined by 9 × 9 around its best point; κ by half decades, then golden section) rather
//!   than by gradient: two and one bounded parameters, a likelihood
//!   summed over many small GPs, and a deterministic answer.
//! * Table 1's parameters ([`table1`]) belong to the paper's detectors in the paper's
//!   (unstated) vantage and score units; they are documented for comparison, and a model is
//!   always fitted to its own detector's looks (`avs verify train`).

use crate::gp::{FitBounds, Gp, SeKernel};
use crate::sensor::{CorrModel, Look, ModelKind, ScoreGp, SensorModel, NO_OBJECT, OBJECT};
use crate::vantage::Vantage;
use crate::VerifyError;
use avs_format::verifier::{CorrSpec, KernelSpec};
use serde::{Deserialize, Serialize};

/// One labelled training look.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TrainingLook {
    /// Which feature was looked at (looks of one feature share its residual field).
    pub feature: usize,
    /// Whether the feature is an object.
    pub object: bool,
    /// Where it was looked at from.
    pub vantage: Vantage,
    /// The score.
    pub score: f64,
}

/// Options of [`train`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrainOptions {
    /// Which model the result uses.
    pub kind: ModelKind,
    /// Largest range the detector sees from, metres.
    pub max_range: f64,
    /// Largest |aspect| the detector sees from, radians (`None`: all round).
    pub aspect_limit: Option<f64>,
    /// Range bins of GP_ind's training grid.
    pub range_bins: usize,
    /// Aspect bins of GP_ind's training grid.
    pub aspect_bins: usize,
    /// Restarts of GP_ind's likelihood fit.
    pub restarts: usize,
    /// Seed of the restarts.
    pub seed: u64,
}

pub use avs_format::verifier::{HypothesisSpec, SensorModelSpec, MAX_POINTS};

impl SensorModel {
    /// Build the GP sensor model a spec describes (after [`SensorModelSpec::problems`] found
    /// none; a problem is a [`VerifyError::Invalid`] naming the field).
    pub fn from_spec(spec: &SensorModelSpec) -> Result<SensorModel, VerifyError> {
        build(spec)
    }
}

fn build(spec: &SensorModelSpec) -> Result<SensorModel, VerifyError> {
    if let Some((field, message)) = spec.problems().into_iter().next() {
        return Err(VerifyError::Invalid { field, message });
    }
    let ind = |h: &HypothesisSpec| {
        let pts: Vec<(Vantage, f64)> = h
            .points
            .iter()
            .map(|p| (Vantage::new(p[0], p[1]), p[2]))
            .collect();
        ScoreGp::new(
            h.mean,
            SeKernel::from(&h.kernel),
            h.noise_variance,
            h.spread,
            &pts,
        )
    };
    let corr = |h: &HypothesisSpec| CorrModel {
        kernel: SeKernel::from(&h.corr.kernel),
        noise_variance: h.corr.noise_variance,
    };
    Ok(SensorModel {
        ind: [ind(&spec.no_object)?, ind(&spec.object)?],
        corr: [corr(&spec.no_object), corr(&spec.object)],
        kind: spec.kind,
        aspect_limit: spec.aspect_limit,
        max_range: spec.max_range,
    })
}

/// Table 1 of Velez et al. 2012: the learned (σ, l) of each GP, in the paper's units:
/// `[text ind object, text ind no-object, text corr object, text corr no-object, door ind
/// object, door ind no-object, door corr object, door corr no-object]`.
pub fn table1() -> [(f64, f64); 8] {
    [
        (5.5, 0.15),
        (16.2, 0.23),
        (4.2, 0.14),
        (4.6, 0.09),
        (0.52, 0.58),
        (54.3, 0.49),
        (0.002, 0.17),
        (9303.0, 0.31),
    ]
}

/// Train a sensor model from labelled looks.
pub fn train(looks: &[TrainingLook], opt: &TrainOptions) -> Result<SensorModelSpec, VerifyError> {
    let hyp = |object: bool| -> Result<HypothesisSpec, VerifyError> {
        let mine: Vec<&TrainingLook> = looks.iter().filter(|l| l.object == object).collect();
        if mine.len() < 4 {
            return Err(VerifyError::Invalid {
                field: if object { "object" } else { "no_object" }.into(),
                message: format!("{} training looks; at least 4 are needed", mine.len()),
            });
        }
        fit_hypothesis(&mine, opt, if object { 0 } else { 1 })
    };
    let object = hyp(true)?;
    let no_object = hyp(false)?;
    let mut spec = SensorModelSpec {
        kind: opt.kind,
        max_range: opt.max_range,
        aspect_limit: opt.aspect_limit,
        object,
        no_object,
    };
    if let ModelKind::Dynamic { .. } = opt.kind {
        let kappa = fit_alpha_scale(&spec, looks)?;
        spec.kind = ModelKind::Dynamic { alpha_scale: kappa };
    }
    Ok(spec)
}

fn fit_hypothesis(
    looks: &[&TrainingLook],
    opt: &TrainOptions,
    salt: u64,
) -> Result<HypothesisSpec, VerifyError> {
    let n = looks.len() as f64;
    let mean = looks.iter().map(|l| l.score).sum::<f64>() / n;
    // 1. Bins.
    let lo_r = crate::field::MIN_RANGE.min(opt.max_range);
    let lim = opt.aspect_limit.unwrap_or(std::f64::consts::PI);
    let (nr, na) = (opt.range_bins.max(1), opt.aspect_bins.max(1));
    let bin_of = |v: &Vantage| {
        let i = (((v.range - lo_r) / (opt.max_range - lo_r).max(1e-9)) * nr as f64).floor();
        let j = (((v.aspect + lim) / (2.0 * lim)) * na as f64).floor();
        let i = (i.max(0.0) as usize).min(nr - 1);
        let j = (j.max(0.0) as usize).min(na - 1);
        i * na + j
    };
    let mut bins: Vec<Vec<&TrainingLook>> = vec![Vec::new(); nr * na];
    for l in looks {
        bins[bin_of(&l.vantage)].push(l);
    }
    let mut points = Vec::new();
    let mut ss = 0.0;
    let mut dof = 0.0;
    let mut features_per_bin = Vec::new();
    for b in &bins {
        // Looks of one feature share its nuisance field: a bin's mean is the mean of its
        // features' means, and it is as noisy as the number of features in it says, not the
        // number of looks.
        let mut by_feature: std::collections::BTreeMap<usize, (f64, f64, f64, f64)> =
            Default::default();
        for l in b {
            let e = by_feature.entry(l.feature).or_default();
            e.0 += l.score;
            e.1 += l.vantage.range;
            e.2 += l.vantage.aspect;
            e.3 += 1.0;
        }
        if by_feature.len() < 2 {
            continue;
        }
        let k = b.len() as f64;
        let zm_looks = b.iter().map(|l| l.score).sum::<f64>() / k;
        ss += b.iter().map(|l| (l.score - zm_looks).powi(2)).sum::<f64>();
        dof += k - 1.0;
        let nf = by_feature.len() as f64;
        let (mut zm, mut rm, mut am) = (0.0, 0.0, 0.0);
        for (z, r, a, n) in by_feature.values() {
            zm += z / n / nf;
            rm += r / n / nf;
            am += a / n / nf;
        }
        features_per_bin.push(nf);
        points.push([rm, am, zm]);
    }
    if points.len() < 2 {
        return Err(VerifyError::Invalid {
            field: "training looks".into(),
            message: "fewer than two vantage bins hold looks of two features; take more looks"
                .into(),
        });
    }
    let spread = (ss / dof).max(1e-6);
    features_per_bin.sort_by(f64::total_cmp);
    let noise_variance = spread / features_per_bin[features_per_bin.len() / 2];
    let x: Vec<Vec<f64>> = points.iter().map(|p| vec![p[0], p[1]]).collect();
    let y: Vec<f64> = points.iter().map(|p| p[2] - mean).collect();
    let var_y = y.iter().map(|v| v * v).sum::<f64>() / y.len() as f64;
    let initial = SeKernel {
        signal_variance: var_y.max(1e-3),
        length_scales: vec![0.3 * opt.max_range, 0.5 * lim],
        angular: crate::vantage::ANGULAR.to_vec(),
    };
    let bounds = FitBounds {
        signal_variance: [1e-4, 1e3],
        length_scale: [0.05, 50.0],
    };
    let gp = Gp::fit(
        x,
        y,
        noise_variance,
        &initial,
        &bounds,
        opt.restarts,
        opt.seed.wrapping_mul(2).wrapping_add(salt),
    )?;
    let kernel = gp.kernel().clone();
    let ind = ScoreGp::new(
        mean,
        kernel.clone(),
        noise_variance,
        spread,
        &points
            .iter()
            .map(|p| (Vantage::new(p[0], p[1]), p[2]))
            .collect::<Vec<_>>(),
    )?;
    // 2. GP_corr on the residuals, grouped by feature.
    let by_feature = group_by_feature(looks.iter().copied());
    let mut pair_sq = 0.0;
    let mut pairs = 0.0;
    let mut res_sq = 0.0;
    let mut res_n = 0.0;
    let groups: Vec<(Vec<Vec<f64>>, Vec<f64>)> = by_feature
        .values()
        .map(|ls| {
            for (i, a) in ls.iter().enumerate() {
                for b in &ls[i + 1..] {
                    if a.vantage == b.vantage {
                        pair_sq += (a.score - b.score).powi(2);
                        pairs += 1.0;
                    }
                }
            }
            let x = ls.iter().map(|l| l.vantage.features().to_vec()).collect();
            let r: Vec<f64> = ls
                .iter()
                .map(|l| l.score - ind.mean_at(&l.vantage))
                .collect();
            res_sq += r.iter().map(|v| v * v).sum::<f64>();
            res_n += r.len() as f64;
            (x, r)
        })
        .collect();
    let white = if pairs > 0.0 {
        (pair_sq / (2.0 * pairs)).max(1e-6)
    } else {
        0.1 * spread
    };
    let field_var = (res_sq / res_n - white).max(0.05 * white).max(1e-6);
    let grid = |lo: f64, hi: f64, k: usize| -> Vec<f64> {
        (0..k)
            .map(|i| lo * (hi / lo).powf(i as f64 / (k - 1) as f64))
            .collect()
    };
    let lml = |lr: f64, la: f64| -> f64 {
        let k = SeKernel {
            signal_variance: field_var,
            length_scales: vec![lr, la],
            angular: crate::vantage::ANGULAR.to_vec(),
        };
        let mut total = 0.0;
        for (x, r) in &groups {
            match Gp::new(k.clone(), white, x.clone(), r.clone()) {
                Ok(g) => total += g.log_marginal_likelihood(),
                Err(_) => return f64::NEG_INFINITY,
            }
        }
        total
    };
    // A coarse logarithmic grid, then a finer one around its best point.
    let (r_lo, r_hi, a_lo, a_hi) = (0.1, 4.0 * opt.max_range, 0.02, 2.0 * lim);
    let coarse = 16;
    let mut best = (f64::NEG_INFINITY, [1.0, 0.5]);
    for lr in grid(r_lo, r_hi, coarse) {
        for la in grid(a_lo, a_hi, coarse) {
            let v = lml(lr, la);
            if v > best.0 {
                best = (v, [lr, la]);
            }
        }
    }
    let step_r = (r_hi / r_lo).powf(1.0 / (coarse - 1) as f64);
    let step_a = (a_hi / a_lo).powf(1.0 / (coarse - 1) as f64);
    let [br, ba] = best.1;
    for lr in grid(br / step_r, br * step_r, 9) {
        for la in grid(ba / step_a, ba * step_a, 9) {
            let v = lml(lr, la);
            if v > best.0 {
                best = (v, [lr, la]);
            }
        }
    }
    Ok(HypothesisSpec {
        mean,
        kernel: kernel.spec(),
        noise_variance,
        spread,
        points,
        corr: CorrSpec {
            kernel: KernelSpec {
                signal_variance: field_var,
                length_scales: best.1.to_vec(),
            },
            noise_variance: white,
        },
    })
}

/// Looks grouped by feature, in feature order (each group in the order taken).
fn group_by_feature<'a>(
    looks: impl Iterator<Item = &'a TrainingLook>,
) -> std::collections::BTreeMap<usize, Vec<&'a TrainingLook>> {
    let mut by_feature: std::collections::BTreeMap<usize, Vec<&TrainingLook>> = Default::default();
    for l in looks {
        by_feature.entry(l.feature).or_default().push(l);
    }
    by_feature
}

/// κ of eq. 17 by maximum likelihood of every feature's looks in order: a grid of half decades
/// over [10⁻³, 10³] brackets the best, golden-section search refines it in log κ.
fn fit_alpha_scale(spec: &SensorModelSpec, looks: &[TrainingLook]) -> Result<f64, VerifyError> {
    let by_feature = group_by_feature(looks.iter());
    let loglik = |log_kappa: f64| -> Result<f64, VerifyError> {
        let mut s = spec.clone();
        s.kind = ModelKind::Dynamic {
            alpha_scale: 10f64.powf(log_kappa),
        };
        let model = build(&s)?;
        let mut total = 0.0;
        for ls in by_feature.values() {
            let y = if ls[0].object { OBJECT } else { NO_OBJECT };
            let mut hist: Vec<Look> = Vec::new();
            for l in ls {
                let c = model.condition(&hist)?;
                let p = c.likelihood(&l.vantage, y).pdf(l.score);
                total += p.max(1e-300).ln();
                hist.push(Look {
                    vantage: l.vantage,
                    score: l.score,
                });
            }
        }
        Ok(total)
    };
    let (lo, hi) = (-3.0, 3.0);
    let mut best = (f64::NEG_INFINITY, lo);
    for i in 0..13 {
        let t = lo + 0.5 * i as f64;
        let v = loglik(t)?;
        if v > best.0 {
            best = (v, t);
        }
    }
    // Golden-section search on [best − ½, best + ½] (clipped to the range).
    let (mut a, mut b) = ((best.1 - 0.5).max(lo), (best.1 + 0.5).min(hi));
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (loglik(c)?, loglik(d)?);
    for _ in 0..12 {
        if fc > fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = loglik(c)?;
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = loglik(d)?;
        }
    }
    for (v, t) in [(fc, c), (fd, d)] {
        if v > best.0 {
            best = (v, t);
        }
    }
    Ok(10f64.powf(best.1))
}
