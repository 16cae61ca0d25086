//! Sensor models: the likelihood of a detector score `z` seen from a vantage point, given
//! whether the candidate is an object (`y = 1`) or not (`y = 0`) and what was seen of it before.
//!
//! # The two models of Velez et al. 2012
//! * **Static disc** (§4.2.1, eq. 10–11). The independent model `p(z | y, v)` (GP_ind) is used
//!   as is, but a look close to an earlier one is discounted: with `d` the distance from the
//!   new waypoint to the nearest earlier one and `α = min(d / d_max, 1)` (eq. 10, d_max = 3 m),
//!   the belief moves only the fraction α of the way a fresh look would move it:
//!   `p(y | T^K) = [α p(z | y, v) / p(z | v) + (1 − α)] p(y | T^{K−1})` (eq. 11).
//! * **Dynamic** (§4.2.2–4.2.3, eq. 9, 13–17). The score is a mixture of an independent draw
//!   (GP_ind, learned over many objects) and a draw correlated with this candidate's own
//!   history (GP_corr, conditioned on the looks taken at it so far):
//!   `p(z | y, v, T) = α p_ind(z | y, v) + (1 − α) p_corr(z | y, v, T)` (eq. 9, 16), with
//!   `α = 1 − exp(−κ σ²_corr(v))` (eq. 17), `σ²_corr(v)` GP_corr's predictive variance at `v`.
//!   Far from every earlier look σ²_corr is the prior variance and α ≈ 1; at an earlier
//!   vantage point σ²_corr → 0, α → 0 and the score is predicted to repeat what was seen there,
//!   whatever `y` is — a second look from the same spot carries no new evidence.
//!
//! # Choices where the paper is vague
//! * **Prior means.** A GP with zero prior mean predicts 0 far from its data, which for a
//!   detector score means nothing. GP_ind has a constant prior mean per `y` (the mean score of
//!   the class's training looks), and GP_corr models the *residual* of this candidate's scores
//!   about GP_ind's mean under the same `y`: `p_corr(z | y) = N(m_ind,y(v) + m_corr,y(v),
//!   σ²_corr,y(v) + σ²_n,corr)`, GP_corr conditioned on `(v_i, z_i − m_ind,y(v_i))`. With no
//!   history p_corr is GP_ind's mean with the prior variance of the residual, as it should.
//! * **One α per hypothesis.** Table 1 gives GP_corr a kernel per `y`, so eq. 17's α is
//!   computed from the variance of the GP_corr of the `y` whose likelihood is evaluated.
//! * **κ scales the variance** inside eq. 17's exponent (the papers' README reading); κ is a
//!   model parameter (the paper's learned door 6.5, text 5.4).
//! * **Vantage points** are `(range m, aspect rad)` (§5.3); a class may be *planar* (signs,
//!   doors): beyond its aspect limit the detector cannot see it, the look carries no evidence
//!   and the perception field is 0 there (§4.3, the text field cut beyond 45°).
//! * **The aspect is an angle.** Velez et al.'s kernels are squared-exponential in `(r, φ)`;
//!   their doors and signs are seen within ±80° and ±45°, where `φ` never wraps. A candidate
//!   whose facing is unknown (every object class in a search) has its bearing from +x as
//!   aspect, and a robot west of it sees it at ±π: with a plain kernel two looks 0.04 rad apart
//!   on either side of the seam were independent, and a look-alike on a floor seen along that
//!   line was believed at 0.99 after four looks from within 2 m. Every vantage GP
//!   ([`Vantage::kernel`]) takes the aspect's difference as the chord `2 sin(Δφ/2)` (the
//!   squared-exponential kernel of the point on the circle; the same as `Δφ` for small `Δφ`,
//!   so the Table 1 length scales keep their meaning). The same four looks now leave it at
//!   0.81, and the planner, looking on, rejects it.
//! * **The disc distance** `d` of eq. 10 is the distance between waypoints, computed from the
//!   two vantage points (the candidate is their common origin).

use crate::gp::{Gp, GpError, SeKernel};
use crate::vantage::Vantage;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Index of the hypothesis "not an object" in per-`y` arrays.
pub const NO_OBJECT: usize = 0;
/// Index of the hypothesis "an object" in per-`y` arrays.
pub const OBJECT: usize = 1;

/// A normal distribution of a score.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Normal {
    /// Mean.
    pub mean: f64,
    /// Variance (> 0).
    pub var: f64,
}

impl Normal {
    /// Density at `z`.
    pub fn pdf(&self, z: f64) -> f64 {
        let d = z - self.mean;
        (-0.5 * d * d / self.var).exp() / (2.0 * PI * self.var).sqrt()
    }
}

/// The likelihood of a score under one hypothesis `y`: `α N_ind + (1 − α) N_corr` (eq. 9/16;
/// the disc model and the independent model use α = 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Likelihood {
    /// Weight of the independent component, in [0, 1].
    pub alpha: f64,
    /// The independent component.
    pub ind: Normal,
    /// The correlated component.
    pub corr: Normal,
}

impl Likelihood {
    /// Density at `z`.
    pub fn pdf(&self, z: f64) -> f64 {
        if self.alpha >= 1.0 {
            return self.ind.pdf(z);
        }
        self.alpha * self.ind.pdf(z) + (1.0 - self.alpha) * self.corr.pdf(z)
    }

    /// Mean and variance of the mixture (moment matching).
    pub fn moments(&self) -> Normal {
        let a = self.alpha;
        let mean = a * self.ind.mean + (1.0 - a) * self.corr.mean;
        let second = a * (self.ind.var + self.ind.mean.powi(2))
            + (1.0 - a) * (self.corr.var + self.corr.mean.powi(2));
        Normal {
            mean,
            var: (second - mean * mean).max(1e-300),
        }
    }
}

/// A GP over vantage points predicting a detector's score under one hypothesis (GP_ind of
/// eq. 13): a constant prior mean plus a zero-mean GP of the latent mean score, and the spread
/// of single scores about that latent mean.
///
/// The GP is trained on *binned* looks — the mean score of the looks that fall in each cell of
/// a vantage grid, the paper's per-waypoint histograms (§4.2.3) — so its noise variance is that
/// of a bin mean, while a single new look varies about the latent mean by `spread` (the
/// nuisance of each feature plus the detector's white noise).
#[derive(Debug, Clone)]
pub struct ScoreGp {
    mean: f64,
    spread: f64,
    gp: Gp,
}

impl ScoreGp {
    /// A score GP from its prior mean, kernel, the noise variance of its training targets, the
    /// variance of a single score about the latent mean, and the training points
    /// `(vantage, mean score)`.
    pub fn new(
        mean: f64,
        kernel: SeKernel,
        noise_variance: f64,
        spread: f64,
        points: &[(Vantage, f64)],
    ) -> Result<Self, GpError> {
        let x = points.iter().map(|(v, _)| v.features().to_vec()).collect();
        let y = points.iter().map(|(_, z)| z - mean).collect();
        Ok(Self {
            mean,
            spread,
            gp: Gp::new(Vantage::kernel(kernel), noise_variance, x, y)?,
        })
    }

    /// The constant prior mean.
    pub fn prior_mean(&self) -> f64 {
        self.mean
    }

    /// The variance of a single score about the latent mean.
    pub fn spread(&self) -> f64 {
        self.spread
    }

    /// The underlying GP (zero-mean, on scores minus the prior mean).
    pub fn gp(&self) -> &Gp {
        &self.gp
    }

    /// The latent mean score at `v`.
    pub fn mean_at(&self, v: &Vantage) -> f64 {
        self.mean + self.gp.predict_mean(&v.features())
    }

    /// The predictive distribution of one score at `v`: the latent mean, with the latent
    /// variance plus the spread of single scores.
    pub fn predict(&self, v: &Vantage) -> Normal {
        let (m, var) = self.gp.predict(&v.features());
        Normal {
            mean: self.mean + m,
            var: var + self.spread,
        }
    }
}

/// GP_corr's hyper-parameters for one hypothesis (eq. 14): the kernel of the residual field and
/// the white noise of single scores about it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CorrModel {
    /// Kernel of the per-candidate residual field.
    pub kernel: SeKernel,
    /// Variance of a single score about the residual field.
    pub noise_variance: f64,
}

pub use avs_format::verifier::ModelKind;

/// One look taken at a candidate: the vantage point and the score.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Look {
    /// Where the robot looked from, relative to the candidate.
    pub vantage: Vantage,
    /// The detector score.
    pub score: f64,
}

/// A class's detector model: GP_ind and GP_corr per hypothesis, the model kind and where the
/// detector can see the class from.
#[derive(Debug, Clone)]
pub struct SensorModel {
    /// GP_ind per `y` ([`NO_OBJECT`], [`OBJECT`]).
    pub ind: [ScoreGp; 2],
    /// GP_corr per `y`.
    pub corr: [CorrModel; 2],
    /// Disc, dynamic or independent.
    pub kind: ModelKind,
    /// Largest |aspect| the detector sees the class from, radians (`None`: every side).
    pub aspect_limit: Option<f64>,
    /// Largest range the detector sees the class from, metres.
    pub max_range: f64,
}

/// A sensor model conditioned on one candidate's history: GP_corr per `y` fitted to the
/// residuals of the looks taken so far, ready to predict at many vantage points.
#[derive(Debug, Clone)]
pub struct Conditioned<'m> {
    model: &'m SensorModel,
    corr: Option<[Gp; 2]>,
    looks: Vec<Look>,
}

/// GP_ind's predictions at one vantage point, per hypothesis: the predictive distribution of
/// one score and the latent mean.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IndAt {
    /// Predictive distribution of one score, per `y`.
    pub predictive: [Normal; 2],
    /// Latent mean score, per `y`.
    pub mean: [f64; 2],
    /// The variance of GP_ind's estimate of the difference of the two latent means (the sum of
    /// their latent variances): how far the model's own training leaves it unsure what a look
    /// here can tell.
    pub uncertainty: f64,
}

impl SensorModel {
    /// GP_ind's predictions at `v`.
    pub fn ind_at(&self, v: &Vantage) -> IndAt {
        let p = [self.ind[NO_OBJECT].predict(v), self.ind[OBJECT].predict(v)];
        let latent = |y: usize| (p[y].var - self.ind[y].spread()).max(0.0);
        IndAt {
            predictive: p,
            mean: [p[0].mean, p[1].mean],
            uncertainty: latent(NO_OBJECT) + latent(OBJECT),
        }
    }

    /// Whether the detector can see the candidate from `v` at all.
    pub fn sees(&self, v: &Vantage) -> bool {
        v.range <= self.max_range && self.aspect_limit.is_none_or(|a| v.aspect.abs() <= a)
    }

    /// Condition the model on a candidate's looks (only those it could see count).
    pub fn condition(&self, looks: &[Look]) -> Result<Conditioned<'_>, GpError> {
        let looks: Vec<Look> = looks
            .iter()
            .copied()
            .filter(|l| self.sees(&l.vantage))
            .collect();
        let corr = match self.kind {
            ModelKind::Dynamic { .. } => {
                let fit = |y: usize| {
                    let x = looks
                        .iter()
                        .map(|l| l.vantage.features().to_vec())
                        .collect();
                    let r = looks
                        .iter()
                        .map(|l| l.score - self.ind[y].mean_at(&l.vantage))
                        .collect();
                    Gp::new(
                        Vantage::kernel(self.corr[y].kernel.clone()),
                        self.corr[y].noise_variance,
                        x,
                        r,
                    )
                };
                Some([fit(NO_OBJECT)?, fit(OBJECT)?])
            }
            _ => None,
        };
        Ok(Conditioned {
            model: self,
            corr,
            looks,
        })
    }
}

impl<'m> Conditioned<'m> {
    /// The model.
    pub fn model(&self) -> &'m SensorModel {
        self.model
    }

    /// The looks conditioned on.
    pub fn looks(&self) -> &[Look] {
        &self.looks
    }

    /// α of eq. 10: the distance from `v`'s waypoint to the nearest earlier one over d_max,
    /// capped at 1 (1 with no earlier look).
    pub fn disc_alpha(&self, v: &Vantage, d_max: f64) -> f64 {
        let d = self
            .looks
            .iter()
            .map(|l| waypoint_distance(v, &l.vantage))
            .fold(f64::INFINITY, f64::min);
        (d / d_max).min(1.0)
    }

    /// The likelihood of a score at `v` under hypothesis `y` (eq. 9 and 16 for the dynamic
    /// model; GP_ind alone, α = 1, for the disc and independent models — the disc's α acts on
    /// the update, eq. 11, not on the likelihood).
    pub fn likelihood(&self, v: &Vantage, y: usize) -> Likelihood {
        self.likelihood_with(v, &self.model.ind_at(v), y)
    }

    /// [`Conditioned::likelihood`] with GP_ind's predictions at `v` given.
    pub fn likelihood_with(&self, v: &Vantage, ind: &IndAt, y: usize) -> Likelihood {
        let pred = ind.predictive[y];
        match (&self.corr, self.model.kind) {
            (Some(corr), ModelKind::Dynamic { alpha_scale }) => {
                let (m, var) = corr[y].predict(&v.features());
                let alpha = 1.0 - (-alpha_scale * var).exp();
                Likelihood {
                    alpha,
                    ind: pred,
                    corr: Normal {
                        mean: ind.mean[y] + m,
                        var: var + corr[y].noise_variance(),
                    },
                }
            }
            _ => Likelihood {
                alpha: 1.0,
                ind: pred,
                corr: pred,
            },
        }
    }

    /// What one look from `v` can tell: both hypotheses' likelihoods and the disc model's
    /// damping; `None` where the detector cannot see the candidate (the look carries no
    /// evidence).
    pub fn at(&self, v: &Vantage) -> Option<LookModel> {
        if !self.model.sees(v) {
            return None;
        }
        self.at_with(v, &self.model.ind_at(v))
    }

    /// [`Conditioned::at`] with GP_ind's predictions at `v` given (a perception field over a
    /// fixed grid computes them once: they do not depend on the candidate's history).
    pub fn at_with(&self, v: &Vantage, ind: &IndAt) -> Option<LookModel> {
        if !self.model.sees(v) {
            return None;
        }
        let damping = match self.model.kind {
            ModelKind::Disc { d_max } => self.disc_alpha(v, d_max),
            _ => 1.0,
        };
        Some(LookModel {
            likelihood: [
                self.likelihood_with(v, ind, NO_OBJECT),
                self.likelihood_with(v, ind, OBJECT),
            ],
            damping,
            uncertainty: ind.uncertainty,
        })
    }

    /// Bayes' rule for one look (eq. 6 with eq. 9, or eq. 11 for the disc model): the new
    /// P(object) after seeing `score` from `v`, from `prior`. A look from where the detector
    /// cannot see the candidate leaves the belief unchanged.
    pub fn update(&self, prior: f64, v: &Vantage, score: f64) -> f64 {
        self.at(v).map_or(prior, |m| m.posterior(prior, score))
    }
}

/// One look's model: the likelihood of its score under each hypothesis and how far the
/// belief moves on it (the disc model's α of eq. 10; 1 for the other models).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LookModel {
    /// Likelihood per `y` ([`NO_OBJECT`], [`OBJECT`]).
    pub likelihood: [Likelihood; 2],
    /// The fraction of the Bayes update applied (eq. 11), in [0, 1].
    pub damping: f64,
    /// [`IndAt::uncertainty`] at the look's vantage point.
    pub uncertainty: f64,
}

impl LookModel {
    /// P(object) after a score `z`, from `prior` (eq. 6 / eq. 11).
    pub fn posterior(&self, prior: f64, z: f64) -> f64 {
        let l1 = self.likelihood[OBJECT].pdf(z);
        let l0 = self.likelihood[NO_OBJECT].pdf(z);
        let evidence = prior * l1 + (1.0 - prior) * l0;
        let bayes = if evidence > 0.0 && evidence.is_finite() {
            prior * l1 / evidence
        } else {
            // Both densities underflowed: the score is far from both hypotheses; compare the
            // log densities of their moment-matched normals.
            let ln = |y: usize| {
                let n = self.likelihood[y].moments();
                -0.5 * (z - n.mean).powi(2) / n.var - 0.5 * n.var.ln()
            };
            let d = ln(OBJECT) - ln(NO_OBJECT) + (prior / (1.0 - prior)).ln();
            1.0 / (1.0 + (-d).exp())
        };
        self.damping * bayes + (1.0 - self.damping) * prior
    }

    /// The look's information about the hypothesis, `G b̈ Gᵀ` of the exponential-family Kalman
    /// filter (eq. 28–31) in log-odds: `d² = (m₁ − m₀)² / s²` for the moment-matched scores
    /// under each hypothesis, `s²` the mean of their spreads — the variance of the look's
    /// log-likelihood ratio ([`crate::pbd`]). The disc model scales it by its damping (eq. 11
    /// moves the belief only that fraction of the way).
    ///
    /// The squared difference of two estimated means overstates the true one by the variance of
    /// the estimate, so `(m₁ − m₀)²` is taken less [`LookModel::uncertainty`] (at least 0): a
    /// planner that seeks the most informative vantage points would otherwise be drawn to where
    /// the training data are thin and the means' difference is noise (Velez et al. do not say;
    /// our choice, after the door models' overconfidence at short range).
    pub fn information(&self) -> f64 {
        let n1 = self.likelihood[OBJECT].moments();
        let n0 = self.likelihood[NO_OBJECT].moments();
        let g2 = ((n1.mean - n0.mean).powi(2) - self.uncertainty).max(0.0);
        self.damping * g2 / (0.5 * (n1.var + n0.var))
    }

    /// The range of scores worth enumerating: both hypotheses' means ± `k` standard deviations
    /// of either mixture component.
    pub fn score_range(&self, k: f64) -> [f64; 2] {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for l in &self.likelihood {
            for n in [l.ind, l.corr] {
                let s = n.var.sqrt();
                lo = lo.min(n.mean - k * s);
                hi = hi.max(n.mean + k * s);
            }
        }
        [lo, hi]
    }
}

/// Distance between the waypoints of two vantage points of the same candidate (law of cosines).
pub fn waypoint_distance(a: &Vantage, b: &Vantage) -> f64 {
    let d2 =
        a.range.powi(2) + b.range.powi(2) - 2.0 * a.range * b.range * (a.aspect - b.aspect).cos();
    d2.max(0.0).sqrt()
}
