//! The squared-exponential kernel with a length scale per input.

use serde::{Deserialize, Serialize};

use super::GpError;

/// Squared-exponential (Gaussian) covariance with a length scale per input:
/// `k(x, x') = σ² · exp(−½ Σ_d (x_d − x'_d)² / l_d²)` (Velez et al. 2012, eq. 12;
/// scikit-learn's `ConstantKernel(σ²) * RBF(length_scale=[l_1, …, l_d])`).
///
/// ```
/// use avs_verify::gp::SeKernel;
/// let k = SeKernel { signal_variance: 2.0, length_scales: vec![1.0, 10.0], angular: vec![] };
/// assert_eq!(k.dim(), 2);
/// assert_eq!(k.eval(&[0.0, 0.0], &[0.0, 0.0]), 2.0);
/// // One length scale away along the first input: σ² · e^{−½}.
/// assert!((k.eval(&[0.0, 0.0], &[1.0, 0.0]) - 2.0 * (-0.5f64).exp()).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SeKernel {
    /// σ², the prior variance of the latent function (`k(x, x)`).
    pub signal_variance: f64,
    /// `l_d`, one per input dimension, in the inputs' units.
    pub length_scales: Vec<f64>,
    /// Which inputs are angles (radians): `angular[d]` true makes input `d`'s difference the
    /// chord `2 sin(Δ/2)` of the unit circle instead of `Δ`, so that the kernel has no seam at
    /// ±π (−3.1 and 3.1 rad are 0.08 rad apart, not 6.2) and stays positive definite: it is
    /// the squared-exponential kernel of the point `(cos φ, sin φ)` on the circle (MacKay's
    /// periodic kernel, `exp(−2 sin²(Δ/2) / l²)`). For small differences the chord is `Δ`.
    /// Missing entries (an empty vector, the default) are ordinary inputs.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub angular: Vec<bool>,
}

impl From<&avs_format::verifier::KernelSpec> for SeKernel {
    fn from(k: &avs_format::verifier::KernelSpec) -> Self {
        SeKernel {
            signal_variance: k.signal_variance,
            length_scales: k.length_scales.clone(),
            angular: Vec::new(),
        }
    }
}

impl SeKernel {
    /// The kernel's parameters as plain data (what a knowledge file stores).
    pub fn spec(&self) -> avs_format::verifier::KernelSpec {
        avs_format::verifier::KernelSpec {
            signal_variance: self.signal_variance,
            length_scales: self.length_scales.clone(),
        }
    }

    /// A kernel with the same length scale `length_scale` for all `dim` inputs (scikit-learn's
    /// isotropic `RBF(length_scale=l)`).
    pub fn isotropic(signal_variance: f64, length_scale: f64, dim: usize) -> SeKernel {
        SeKernel {
            signal_variance,
            length_scales: vec![length_scale; dim],
            angular: Vec::new(),
        }
    }

    /// The covariance `k(a, b)`. `a` and `b` must have [`dim`](Self::dim) entries (checked in
    /// debug builds only; extra entries of the longer slice would be ignored).
    pub fn eval(&self, a: &[f64], b: &[f64]) -> f64 {
        debug_assert_eq!(a.len(), self.length_scales.len());
        debug_assert_eq!(b.len(), self.length_scales.len());
        self.signal_variance * (-0.5 * self.scaled_sq_dist(a, b)).exp()
    }

    /// The number of inputs, one per length scale.
    pub fn dim(&self) -> usize {
        self.length_scales.len()
    }

    /// This kernel with input `d` an angle for every `d` where `angular[d]` (see
    /// [`SeKernel::angular`]).
    pub fn with_angular(mut self, angular: &[bool]) -> SeKernel {
        self.angular = angular.to_vec();
        self
    }

    /// The difference of input `d` between `x` and `y`: `x − y`, or for an angle the chord
    /// `2 sin((x − y)/2)`.
    pub(crate) fn diff(&self, d: usize, x: f64, y: f64) -> f64 {
        if self.angular.get(d).copied().unwrap_or(false) {
            2.0 * (0.5 * (x - y)).sin()
        } else {
            x - y
        }
    }

    /// `Σ_d δ_d(a, b)² / l_d²`, `δ_d` the difference of input `d` ([`SeKernel::diff`]).
    pub(crate) fn scaled_sq_dist(&self, a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .zip(&self.length_scales)
            .enumerate()
            .map(|(d, ((&x, &y), l))| {
                let r = self.diff(d, x, y) / l;
                r * r
            })
            .sum()
    }

    /// Checks that σ² and every length scale are finite and positive and that there is at
    /// least one input.
    pub fn validate(&self) -> Result<(), GpError> {
        positive("signal_variance", self.signal_variance)?;
        if self.length_scales.is_empty() {
            return Err(GpError::NoInputs);
        }
        for (d, &l) in self.length_scales.iter().enumerate() {
            positive(&format!("length_scales[{d}]"), l)?;
        }
        Ok(())
    }
}

/// `value` must be finite and > 0.
pub(crate) fn positive(what: &str, value: f64) -> Result<(), GpError> {
    if !value.is_finite() {
        Err(GpError::NonFinite {
            what: what.to_string(),
            value,
        })
    } else if value <= 0.0 {
        Err(GpError::NonPositive {
            what: what.to_string(),
            value,
        })
    } else {
        Ok(())
    }
}
