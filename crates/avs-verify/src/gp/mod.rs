//! Gaussian-process regression with a squared-exponential kernel.
//!
//! Velez et al. (2012) model a detector's scores over vantage points with GPs (§4, eq. 12–14):
//! a zero-mean GP prior `f ~ GP(0, k)` with the squared-exponential kernel [`SeKernel`]
//! `k(x, x') = σ² · exp(−½ Σ_d (x_d − x'_d)² / l_d²)`, observed through Gaussian noise of
//! variance `σ_n²`. This module conditions such a GP on training data ([`Gp`]), predicts the
//! latent function, scores hyper-parameters by the log marginal likelihood and its gradient, and
//! fits σ² and the `l_d` by maximum likelihood ([`Gp::fit`]). [`cases`] reads and evaluates the
//! reference cases computed with scikit-learn (`shared/data/gp/sklearn_gpr.json`).
//!
//! ## Equations
//!
//! Rasmussen & Williams, *Gaussian Processes for Machine Learning* (2006), Algorithm 2.1, with
//! `K = K_f + σ_n² I`, `K_f[i][j] = k(x_i, x_j)`:
//!
//! * `L = cholesky(K)`, `α = Lᵀ \ (L \ y)`;
//! * predictive mean `f̄* = k*ᵀ α`, with `k*[i] = k(x_i, x*)`;
//! * `v = L \ k*`, predictive variance of the latent `f*`: `V[f*] = k(x*, x*) − vᵀv`;
//! * `log p(y | X) = −½ yᵀα − Σ_i log L_ii − (n/2) log 2π`.
//!
//! The gradient with respect to a hyper-parameter `θ_j` is eq. 5.9,
//! `∂ log p(y | X) / ∂θ_j = ½ tr((ααᵀ − K⁻¹) ∂K/∂θ_j)`, taken with respect to the log
//! parameters as scikit-learn does: `∂K/∂ log σ² = K_f` and
//! `∂K/∂ log l_d = K_f ⊙ [(x_id − x_jd)² / l_d²]_ij`.
//!
//! ## Choices where the sources leave room
//!
//! * **Noise.** `σ_n²` is added to the diagonal only (scikit-learn's `alpha`) and is not a fitted
//!   parameter; it may be 0 for noise-free data, as long as `K` stays positive definite.
//! * **Predictive variance.** [`Gp::predict`] returns the variance of the latent `f*`, without
//!   `σ_n²` (as scikit-learn's `return_std=True`); add `σ_n²` for the variance of a new
//!   observation. Round-off can make `k(x*, x*) − vᵀv` slightly negative next to a training
//!   point; it is clamped to 0, as scikit-learn does.
//! * **Cost.** `K⁻¹` for the gradient and `L \ K*` for a batch of queries are one blocked
//!   forward substitution each (diagonal blocks solved directly, the rest by matrix
//!   multiplication), `O(n³)` and `O(n² m)`; a factorisation is `O(n³)`. [`cases`] bounds the
//!   sizes it accepts.
//! * **No data.** A GP with `n = 0` is the prior: mean 0, variance σ², log marginal likelihood 0.
//! * **Isotropic kernels.** scikit-learn's `RBF` with one length scale for several inputs shares
//!   `l` across them: its gradient has one length-scale component, the sum of the per-input ones
//!   ([`Gp::lml_gradient_wrt_log_params_isotropic`]), and [`Gp::fit_isotropic`] fits that one
//!   `l`. [`SeKernel`] itself always stores one length scale per input.
//! * **Fitting.** Maximum likelihood over `θ = (log σ², log l_1, …, log l_d)` inside box bounds,
//!   by a projected L-BFGS of our own (`lbfgs.rs`): argmin 0.11's L-BFGS has no box constraints
//!   (only an L1 penalty), a sigmoid reparametrisation cannot reach an optimum on a bound and
//!   flattens the gradient near it, and clamping after an unconstrained step corrupts the
//!   quasi-Newton pairs. The first start is the initial kernel (projected into the bounds), then
//!   `restarts` starts drawn uniformly in log space inside the bounds from
//!   `ChaCha8Rng::seed_from_u64(seed)`, as scikit-learn's `n_restarts_optimizer`; the best
//!   likelihood wins. Parameters at which `K` is not positive definite score `−∞`, as in
//!   scikit-learn.
//!
//! ## Example
//!
//! ```
//! use avs_verify::gp::{FitBounds, Gp, SeKernel};
//!
//! let x: Vec<Vec<f64>> = (0..8).map(|i| vec![i as f64]).collect();
//! let y: Vec<f64> = x.iter().map(|p| p[0].sin()).collect();
//! let kernel = SeKernel { signal_variance: 1.0, length_scales: vec![1.0], angular: vec![] };
//! let gp = Gp::new(kernel.clone(), 1e-6, x.clone(), y.clone())?;
//!
//! // Between training points the mean follows sin, with a small variance.
//! let (mean, var) = gp.predict(&[2.5]);
//! assert!((mean - 2.5f64.sin()).abs() < 0.05, "mean {mean}");
//! assert!(var < 0.01, "variance {var}");
//! // Far away the prediction is the prior again: mean 0, variance σ².
//! let (mean, var) = gp.predict(&[100.0]);
//! assert!(mean.abs() < 1e-12 && (var - 1.0).abs() < 1e-12);
//!
//! // Fitting σ² and l never lowers the likelihood of the starting kernel.
//! let bounds = FitBounds { signal_variance: [1e-2, 1e2], length_scale: [1e-2, 1e2] };
//! let fitted = Gp::fit(x, y, 1e-6, &kernel, &bounds, 2, 7)?;
//! assert!(fitted.log_marginal_likelihood() >= gp.log_marginal_likelihood());
//! let l = fitted.kernel().length_scales[0];
//! assert!((1e-2..=1e2).contains(&l));
//! # Ok::<(), avs_verify::gp::GpError>(())
//! ```

use nalgebra::{DMatrix, DMatrixView, DVector};

pub mod cases;
mod fit;
mod kernel;
mod lbfgs;

pub use cases::{eval_case, GpCase, GpCaseFile, GpCaseResult};
pub use fit::FitBounds;
pub use kernel::SeKernel;

/// What can be wrong with a GP's inputs.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GpError {
    /// The kernel has no length scale, so no inputs.
    #[error("the kernel has no length scales: a GP needs at least one input dimension")]
    NoInputs,
    /// A point has a different number of coordinates than the kernel has length scales.
    #[error("{what} has {found} coordinates, but the kernel has {expected} length scales")]
    DimensionMismatch {
        /// The offending point, e.g. `x[3]`.
        what: String,
        /// The kernel's number of inputs.
        expected: usize,
        /// The point's number of coordinates.
        found: usize,
    },
    /// Different numbers of training inputs and targets.
    #[error("{inputs} training inputs but {targets} targets")]
    LengthMismatch {
        /// Number of training inputs.
        inputs: usize,
        /// Number of training targets.
        targets: usize,
    },
    /// A NaN or infinite number.
    #[error("{what} is not finite ({value})")]
    NonFinite {
        /// Which number, e.g. `y[2]` or `length_scales[0]`.
        what: String,
        /// Its value.
        value: f64,
    },
    /// A parameter that must be positive is zero or negative.
    #[error("{what} must be positive, got {value}")]
    NonPositive {
        /// Which parameter.
        what: String,
        /// Its value.
        value: f64,
    },
    /// A parameter that must be non-negative (the noise variance) is negative.
    #[error("{what} must not be negative, got {value}")]
    Negative {
        /// Which parameter.
        what: String,
        /// Its value.
        value: f64,
    },
    /// Fit bounds that are not `0 < lo ≤ hi < ∞`.
    #[error("bounds for {what} must satisfy 0 < lo <= hi < inf, got [{lo}, {hi}]")]
    InvalidBounds {
        /// Which parameter's bounds.
        what: String,
        /// Lower bound.
        lo: f64,
        /// Upper bound.
        hi: f64,
    },
    /// The Cholesky factorisation of `K_f + σ_n² I` failed.
    #[error(
        "the {n}×{n} kernel matrix plus noise is not positive definite \
         (duplicate inputs with too little noise_variance?)"
    )]
    NotPositiveDefinite {
        /// Number of training points.
        n: usize,
    },
    /// No start of the fit reached parameters at which the kernel matrix is positive definite.
    #[error(
        "fitting failed: the kernel matrix (n = {n}) is not positive definite at any start \
         (increase noise_variance)"
    )]
    FitFailed {
        /// Number of training points.
        n: usize,
    },
    /// A field of a case file is malformed (see [`cases`]).
    #[error("field `{field}`: {reason}")]
    Field {
        /// The field, as named in the file, e.g. `y` or `X_query[2]`.
        field: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A case file is not valid JSON or does not have the expected shape.
    #[error("at `{path}`: {message}")]
    Parse {
        /// Where in the document, e.g. `cases[0].X[1][0]` (`.` for the document itself).
        path: String,
        /// The parser's message.
        message: String,
    },
}

/// A zero-mean GP with kernel [`SeKernel`] and noise variance `σ_n²`, conditioned on training
/// data (Rasmussen & Williams 2006, Alg. 2.1; see the [module docs](self)).
#[derive(Debug, Clone)]
pub struct Gp {
    kernel: SeKernel,
    noise_variance: f64,
    x: Vec<Vec<f64>>,
    y: Vec<f64>,
    factor: Factor,
}

/// The Cholesky factor of `K_f + σ_n² I`, `α = K⁻¹ y` and the log marginal likelihood.
#[derive(Debug, Clone)]
struct Factor {
    l: DMatrix<f64>,
    alpha: DVector<f64>,
    lml: f64,
}

const LN_2PI: f64 = 1.837_877_066_409_345_5;

/// Factorises `K_f + noise I` for data that have been validated. `Err` when it is not
/// (numerically) positive definite.
fn factorise(
    kernel: &SeKernel,
    noise_variance: f64,
    x: &[Vec<f64>],
    y: &[f64],
) -> Result<Factor, GpError> {
    let n = x.len();
    if n == 0 {
        return Ok(Factor {
            l: DMatrix::zeros(0, 0),
            alpha: DVector::zeros(0),
            lml: 0.0,
        });
    }
    let k = DMatrix::from_fn(n, n, |i, j| {
        let v = kernel.eval(&x[i], &x[j]);
        if i == j {
            v + noise_variance
        } else {
            v
        }
    });
    let chol = nalgebra::Cholesky::new(k).ok_or(GpError::NotPositiveDefinite { n })?;
    let l = chol.unpack();
    let yv = DVector::from_column_slice(y);
    let alpha = l
        .solve_lower_triangular(&yv)
        .and_then(|z| l.tr_solve_lower_triangular(&z))
        .ok_or(GpError::NotPositiveDefinite { n })?;
    let log_det_half: f64 = l.diagonal().iter().map(|d| d.ln()).sum();
    let lml = -0.5 * yv.dot(&alpha) - log_det_half - 0.5 * n as f64 * LN_2PI;
    if !lml.is_finite() || alpha.iter().any(|a| !a.is_finite()) {
        return Err(GpError::NotPositiveDefinite { n });
    }
    Ok(Factor { l, alpha, lml })
}

/// Rows of `L` below which [`solve_lower`] substitutes directly.
const SOLVE_BLOCK: usize = 64;

/// `L⁻¹ B` for a lower-triangular `L` with a non-zero diagonal (a Cholesky factor): forward
/// substitution, blocked so that the bulk of the work is matrix multiplication
/// (`X₁ = L₁₁⁻¹ B₁`, `X₂ = L₂₂⁻¹ (B₂ − L₂₁ X₁)`).
fn solve_lower(l: DMatrixView<'_, f64>, mut b: DMatrix<f64>) -> DMatrix<f64> {
    let n = l.nrows();
    if n <= SOLVE_BLOCK {
        // `false` only for a zero on the diagonal, which a Cholesky factor does not have.
        let solved = l.solve_lower_triangular_mut(&mut b);
        debug_assert!(solved);
        return b;
    }
    let h = n / 2;
    let x1 = solve_lower(l.view((0, 0), (h, h)), b.rows(0, h).into_owned());
    let mut b2 = b.rows(h, n - h).into_owned();
    b2.gemm(-1.0, &l.view((h, 0), (n - h, h)), &x1, 1.0);
    let x2 = solve_lower(l.view((h, h), (n - h, n - h)), b2);
    b.rows_mut(0, h).copy_from(&x1);
    b.rows_mut(h, n - h).copy_from(&x2);
    b
}

/// `∂ log p / ∂ (log σ², log l_1, …, log l_d)` by eq. 5.9, `O(n³ + n² d)`.
fn lml_gradient(kernel: &SeKernel, x: &[Vec<f64>], f: &Factor) -> Vec<f64> {
    let n = x.len();
    let dim = kernel.dim();
    let mut grad = vec![0.0; 1 + dim];
    if n == 0 {
        return grad;
    }
    // K⁻¹ = L⁻ᵀ L⁻¹ (the product by matrix multiplication, much faster than `tr_mul`).
    let l_inv = solve_lower(f.l.as_view(), DMatrix::identity(n, n));
    let k_inv = l_inv.transpose() * &l_inv;
    let inv_l2: Vec<f64> = kernel.length_scales.iter().map(|l| 1.0 / (l * l)).collect();
    for j in 0..n {
        for i in j..n {
            // W = ααᵀ − K⁻¹, symmetric: off-diagonal entries count twice.
            let w = f.alpha[i] * f.alpha[j] - k_inv[(i, j)];
            let kf = kernel.eval(&x[i], &x[j]);
            let wk = if i == j { 0.5 * w * kf } else { w * kf };
            grad[0] += wk;
            if i != j {
                for d in 0..dim {
                    let r = kernel.diff(d, x[i][d], x[j][d]);
                    grad[1 + d] += wk * r * r * inv_l2[d];
                }
            }
        }
    }
    grad
}

/// Checks the training data against a kernel of `dim` inputs.
fn validate_data(dim: usize, x: &[Vec<f64>], y: &[f64]) -> Result<(), GpError> {
    if x.len() != y.len() {
        return Err(GpError::LengthMismatch {
            inputs: x.len(),
            targets: y.len(),
        });
    }
    for (i, p) in x.iter().enumerate() {
        validate_point(dim, &format!("x[{i}]"), p)?;
    }
    for (i, &v) in y.iter().enumerate() {
        if !v.is_finite() {
            return Err(GpError::NonFinite {
                what: format!("y[{i}]"),
                value: v,
            });
        }
    }
    Ok(())
}

fn validate_point(dim: usize, what: &str, p: &[f64]) -> Result<(), GpError> {
    if p.len() != dim {
        return Err(GpError::DimensionMismatch {
            what: what.to_string(),
            expected: dim,
            found: p.len(),
        });
    }
    if let Some((d, &v)) = p.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(GpError::NonFinite {
            what: format!("{what}[{d}]"),
            value: v,
        });
    }
    Ok(())
}

fn validate_noise(noise_variance: f64) -> Result<(), GpError> {
    if !noise_variance.is_finite() {
        Err(GpError::NonFinite {
            what: "noise_variance".into(),
            value: noise_variance,
        })
    } else if noise_variance < 0.0 {
        Err(GpError::Negative {
            what: "noise_variance".into(),
            value: noise_variance,
        })
    } else {
        Ok(())
    }
}

impl Gp {
    /// Conditions the zero-mean GP with `kernel` on `x` (one point of `kernel.dim()`
    /// coordinates per row) and `y`, with `noise_variance` added to the diagonal
    /// (scikit-learn's `alpha`). `x` and `y` may be empty: the GP is then its prior.
    ///
    /// Errors: a kernel without inputs or with a non-positive or non-finite parameter, a negative
    /// or non-finite noise variance, `x` and `y` of different lengths, a point with the wrong
    /// number of coordinates, a non-finite coordinate or target, or a kernel matrix that is not
    /// positive definite (duplicate points without noise).
    pub fn new(
        kernel: SeKernel,
        noise_variance: f64,
        x: Vec<Vec<f64>>,
        y: Vec<f64>,
    ) -> Result<Gp, GpError> {
        kernel.validate()?;
        validate_noise(noise_variance)?;
        validate_data(kernel.dim(), &x, &y)?;
        let factor = factorise(&kernel, noise_variance, &x, &y)?;
        Ok(Gp {
            kernel,
            noise_variance,
            x,
            y,
            factor,
        })
    }

    /// The GP without data: mean 0 and variance σ² everywhere.
    pub fn prior(kernel: SeKernel, noise_variance: f64) -> Result<Gp, GpError> {
        Gp::new(kernel, noise_variance, Vec::new(), Vec::new())
    }

    /// This GP conditioned on one more observation `y` at `x` (refactorised from scratch:
    /// `O(n³)`, meant for the few looks of a verification).
    pub fn with_observation(&self, x: Vec<f64>, y: f64) -> Result<Gp, GpError> {
        let mut xs = self.x.clone();
        let mut ys = self.y.clone();
        xs.push(x);
        ys.push(y);
        Gp::new(self.kernel.clone(), self.noise_variance, xs, ys)
    }

    /// The kernel.
    pub fn kernel(&self) -> &SeKernel {
        &self.kernel
    }

    /// The noise variance `σ_n²` on the diagonal.
    pub fn noise_variance(&self) -> f64 {
        self.noise_variance
    }

    /// The number of training points.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether the GP has no training points (it is its prior).
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// The training inputs.
    pub fn inputs(&self) -> &[Vec<f64>] {
        &self.x
    }

    /// The training targets.
    pub fn targets(&self) -> &[f64] {
        &self.y
    }

    /// Mean and variance of the latent `f(xq)` (without the noise variance).
    ///
    /// # Panics
    /// If `xq` does not have [`SeKernel::dim`] coordinates; [`Gp::try_predict_batch`] checks
    /// instead.
    pub fn predict(&self, xq: &[f64]) -> (f64, f64) {
        assert_eq!(
            xq.len(),
            self.kernel.dim(),
            "Gp::predict: the query point has the wrong number of coordinates"
        );
        let n = self.x.len();
        let sv = self.kernel.signal_variance;
        if n == 0 {
            return (0.0, sv);
        }
        // One point: forward substitution `L v = k*` row by row, on the stack for small n (the
        // verifier's per-candidate GPs hold a handful of looks and are asked at every vantage
        // point of a grid).
        let mut stack = [0.0; 32];
        let mut heap = Vec::new();
        let v: &mut [f64] = if n <= stack.len() {
            &mut stack[..n]
        } else {
            heap.resize(n, 0.0);
            &mut heap
        };
        let l = &self.factor.l;
        let mut mean = 0.0;
        let mut vv = 0.0;
        for i in 0..n {
            let k = self.kernel.eval(&self.x[i], xq);
            mean += k * self.factor.alpha[i];
            let mut s = k;
            for (j, vj) in v.iter().enumerate().take(i) {
                s -= l[(i, j)] * vj;
            }
            v[i] = s / l[(i, i)];
            vv += v[i] * v[i];
        }
        (mean, (sv - vv).max(0.0))
    }

    /// The mean of the latent `f(xq)` alone: `O(n)`, where [`predict`](Self::predict)'s
    /// variance costs `O(n²)`.
    ///
    /// # Panics
    /// If `xq` does not have [`SeKernel::dim`] coordinates.
    pub fn predict_mean(&self, xq: &[f64]) -> f64 {
        assert_eq!(
            xq.len(),
            self.kernel.dim(),
            "Gp::predict_mean: the query point has the wrong number of coordinates"
        );
        self.x
            .iter()
            .zip(self.factor.alpha.iter())
            .map(|(x, a)| self.kernel.eval(x, xq) * a)
            .sum()
    }

    /// [`predict`](Self::predict) at many points with one triangular solve for all of them.
    ///
    /// # Panics
    /// If a point does not have [`SeKernel::dim`] coordinates; [`Gp::try_predict_batch`]
    /// checks instead.
    pub fn predict_batch(&self, xq: &[Vec<f64>]) -> Vec<(f64, f64)> {
        let dim = self.kernel.dim();
        assert!(
            xq.iter().all(|p| p.len() == dim),
            "Gp::predict_batch: a query point has the wrong number of coordinates"
        );
        self.predict_unchecked(xq)
    }

    /// [`predict_batch`](Self::predict_batch) with the query points checked: a point with the
    /// wrong number of coordinates or a non-finite coordinate is an error.
    pub fn try_predict_batch(&self, xq: &[Vec<f64>]) -> Result<Vec<(f64, f64)>, GpError> {
        for (i, p) in xq.iter().enumerate() {
            validate_point(self.kernel.dim(), &format!("query[{i}]"), p)?;
        }
        Ok(self.predict_unchecked(xq))
    }

    fn predict_unchecked<P: AsRef<[f64]>>(&self, xq: &[P]) -> Vec<(f64, f64)> {
        let sv = self.kernel.signal_variance;
        let n = self.x.len();
        let m = xq.len();
        if n == 0 {
            return vec![(0.0, sv); m];
        }
        let k_star = DMatrix::from_fn(n, m, |i, j| self.kernel.eval(&self.x[i], xq[j].as_ref()));
        let mean = k_star.tr_mul(&self.factor.alpha);
        let v = solve_lower(self.factor.l.as_view(), k_star);
        (0..m)
            .map(|j| {
                let vv = v.column(j).norm_squared();
                (mean[j], (sv - vv).max(0.0))
            })
            .collect()
    }

    /// `log p(y | X, θ)`, Rasmussen & Williams eq. 2.30 (0 for no data).
    pub fn log_marginal_likelihood(&self) -> f64 {
        self.factor.lml
    }

    /// The gradient of [`log_marginal_likelihood`](Self::log_marginal_likelihood) with respect
    /// to `(log σ², log l_1, …, log l_d)` (eq. 5.9), scikit-learn's `eval_gradient` order for
    /// `ConstantKernel * RBF`; the noise variance is fixed. `O(n³)`.
    pub fn lml_gradient_wrt_log_params(&self) -> Vec<f64> {
        lml_gradient(&self.kernel, &self.x, &self.factor)
    }

    /// The gradient with respect to `(log σ², log l)` for a kernel whose length scales are all
    /// one shared `l` (scikit-learn's isotropic `RBF`): the length-scale component is the sum of
    /// the per-input ones.
    pub fn lml_gradient_wrt_log_params_isotropic(&self) -> Vec<f64> {
        let g = self.lml_gradient_wrt_log_params();
        vec![g[0], g[1..].iter().sum()]
    }
}

#[cfg(test)]
mod tests;
