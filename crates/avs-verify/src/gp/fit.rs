//! Maximum-likelihood fit of σ² and the length scales inside box bounds.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use super::lbfgs::{self, Settings};
use super::{factorise, lml_gradient, validate_data, validate_noise, Gp, GpError, SeKernel};

/// Box bounds of a fit (scikit-learn's `constant_value_bounds` and `length_scale_bounds`):
/// `[lo, hi]` for σ², and one `[lo, hi]` for every length scale.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FitBounds {
    /// Bounds of the signal variance σ².
    pub signal_variance: [f64; 2],
    /// Bounds of each length scale.
    pub length_scale: [f64; 2],
}

impl FitBounds {
    /// Checks `0 < lo ≤ hi < ∞` for both.
    pub fn validate(&self) -> Result<(), GpError> {
        for (what, [lo, hi]) in [
            ("signal_variance", self.signal_variance),
            ("length_scale", self.length_scale),
        ] {
            if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && lo <= hi) {
                return Err(GpError::InvalidBounds {
                    what: what.into(),
                    lo,
                    hi,
                });
            }
        }
        Ok(())
    }
}

/// Whether each input gets its own length scale or all share one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Tying {
    PerInput,
    Shared,
}

impl Gp {
    /// Fits σ² and one length scale per input by maximum likelihood inside `bounds`, with
    /// `noise_variance` fixed, and conditions the GP on `x`, `y` with the result.
    ///
    /// Optimises `θ = (log σ², log l_1, …, log l_d)` with a projected L-BFGS (see the
    /// [module docs](super) for why not argmin). The first start is `initial` (projected into
    /// the bounds), then `restarts` starts uniform in log space inside the bounds, drawn from
    /// `ChaCha8Rng::seed_from_u64(seed)`; the largest likelihood wins, the earliest start on a
    /// tie. Deterministic for a seed.
    ///
    /// Errors: as [`Gp::new`] for the data, `initial` and the noise; invalid bounds; `initial`
    /// with another number of inputs than the points; [`GpError::FitFailed`] when the kernel
    /// matrix is not positive definite at any start.
    pub fn fit(
        x: Vec<Vec<f64>>,
        y: Vec<f64>,
        noise_variance: f64,
        initial: &SeKernel,
        bounds: &FitBounds,
        restarts: usize,
        seed: u64,
    ) -> Result<Gp, GpError> {
        fit(
            x,
            y,
            noise_variance,
            initial,
            bounds,
            restarts,
            seed,
            Tying::PerInput,
        )
    }

    /// [`Gp::fit`] with one length scale shared by all inputs (scikit-learn's isotropic `RBF`):
    /// `θ = (log σ², log l)`, starting from the geometric mean of `initial`'s length scales.
    /// The result's kernel repeats the fitted `l` for every input.
    pub fn fit_isotropic(
        x: Vec<Vec<f64>>,
        y: Vec<f64>,
        noise_variance: f64,
        initial: &SeKernel,
        bounds: &FitBounds,
        restarts: usize,
        seed: u64,
    ) -> Result<Gp, GpError> {
        fit(
            x,
            y,
            noise_variance,
            initial,
            bounds,
            restarts,
            seed,
            Tying::Shared,
        )
    }
}

/// The kernel of log parameters `theta` for `dim` inputs.
fn kernel_of(theta: &[f64], dim: usize, tying: Tying, angular: &[bool]) -> SeKernel {
    let length_scales = match tying {
        Tying::PerInput => theta[1..].iter().map(|t| t.exp()).collect(),
        Tying::Shared => vec![theta[1].exp(); dim],
    };
    SeKernel {
        signal_variance: theta[0].exp(),
        length_scales,
        angular: angular.to_vec(),
    }
}

#[allow(clippy::too_many_arguments)]
fn fit(
    x: Vec<Vec<f64>>,
    y: Vec<f64>,
    noise_variance: f64,
    initial: &SeKernel,
    bounds: &FitBounds,
    restarts: usize,
    seed: u64,
    tying: Tying,
) -> Result<Gp, GpError> {
    initial.validate()?;
    validate_noise(noise_variance)?;
    bounds.validate()?;
    let dim = initial.dim();
    validate_data(dim, &x, &y)?;

    let n_theta = match tying {
        Tying::PerInput => 1 + dim,
        Tying::Shared => 2,
    };
    let mut lo = vec![bounds.length_scale[0].ln(); n_theta];
    let mut hi = vec![bounds.length_scale[1].ln(); n_theta];
    lo[0] = bounds.signal_variance[0].ln();
    hi[0] = bounds.signal_variance[1].ln();

    let mut start = vec![initial.signal_variance.ln()];
    match tying {
        Tying::PerInput => start.extend(initial.length_scales.iter().map(|l| l.ln())),
        Tying::Shared => {
            let mean_log = initial.length_scales.iter().map(|l| l.ln()).sum::<f64>() / dim as f64;
            start.push(mean_log);
        }
    }
    let mut starts = vec![start];
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for _ in 0..restarts {
        starts.push(
            lo.iter()
                .zip(&hi)
                .map(|(&l, &h)| l + (h - l) * rng.gen::<f64>())
                .collect(),
        );
    }

    // Minimise −log p(y | X, θ).
    let objective = |theta: &[f64]| -> Option<(f64, Vec<f64>)> {
        let kernel = kernel_of(theta, dim, tying, &initial.angular);
        let factor = factorise(&kernel, noise_variance, &x, &y).ok()?;
        let g = lml_gradient(&kernel, &x, &factor);
        let grad = match tying {
            Tying::PerInput => g.iter().map(|v| -v).collect(),
            Tying::Shared => vec![-g[0], -g[1..].iter().sum::<f64>()],
        };
        Some((-factor.lml, grad))
    };
    let settings = Settings::default();
    let mut best: Option<lbfgs::Minimum> = None;
    for s in &starts {
        if let Some(m) = lbfgs::minimize(objective, s, &lo, &hi, &settings) {
            if best.as_ref().is_none_or(|b| m.f < b.f) {
                best = Some(m);
            }
        }
    }
    let best = best.ok_or(GpError::FitFailed { n: x.len() })?;
    Gp::new(
        kernel_of(&best.x, dim, tying, &initial.angular),
        noise_variance,
        x,
        y,
    )
}
