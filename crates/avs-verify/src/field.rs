//! Perception fields (Velez et al. 2012 §3.2, eq. 7–8): the expected reduction of the
//! uncertainty about a candidate from one more look, at every vantage point of a grid.
//!
//! `I(Y, Z; v) = H(Y) − E_z[H(Y | z, v)]` with `z ~ p(z | v, T) = Σ_y p(z | y, v, T) p(y)`.
//! Two ways to compute it:
//! * [`FieldMethod::Bins`] — the definition, with the score integral replaced by `B` bins over
//!   the likely scores (the paper's Table 6 compares 10 and 100 bins);
//! * [`FieldMethod::Pbd`] — the posterior belief distribution (eq. 32): the belief's normal
//!   covariance after the look, `Σ' = (Σ⁻¹ + G b̈ Gᵀ)⁻¹`, and the normal's entropy drop
//!   `½ ln(Σ / Σ')` — no integral over scores at all.
//!
//! The two are different measures of the same thing (nats of a binary variable vs nats of its
//! normal approximation); they rank vantage points alike, which is what sampling from the
//! field needs. Both are 0 where the detector cannot see the candidate.

use crate::pbd::covariance_of;
use crate::sensor::{Conditioned, IndAt, LookModel, SensorModel};
use crate::vantage::Vantage;
use serde::{Deserialize, Serialize};

/// How a perception field is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum FieldMethod {
    /// The posterior belief distribution's closed form (eq. 32).
    Pbd,
    /// Explicit enumeration of the score over this many bins (eq. 8).
    Bins(usize),
}

/// The closest a robot looks at a candidate from, metres: its body and the camera's near
/// limit (our choice).
pub const MIN_RANGE: f64 = 0.75;

/// A grid of vantage points around a candidate: ranges × aspects.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VantageGrid {
    /// The vantage points, range-major.
    pub vantages: Vec<Vantage>,
}

impl VantageGrid {
    /// `n_range` ranges evenly from `range[0]` to `range[1]` metres × `n_aspect` aspects evenly
    /// from `−aspect_max` to `aspect_max` radians (`aspect_max = π` goes all round; the
    /// aspect −π is then left out, being π).
    pub fn regular(range: [f64; 2], n_range: usize, aspect_max: f64, n_aspect: usize) -> Self {
        let step = |lo: f64, hi: f64, n: usize, i: usize| {
            if n <= 1 {
                0.5 * (lo + hi)
            } else {
                lo + (hi - lo) * i as f64 / (n - 1) as f64
            }
        };
        let full = aspect_max >= std::f64::consts::PI - 1e-9;
        let mut vantages = Vec::with_capacity(n_range * n_aspect);
        for i in 0..n_range {
            for j in 0..n_aspect {
                let a = if full {
                    -std::f64::consts::PI
                        + 2.0 * std::f64::consts::PI * (j + 1) as f64 / n_aspect as f64
                } else {
                    step(-aspect_max, aspect_max, n_aspect, j)
                };
                vantages.push(Vantage::new(step(range[0], range[1], n_range, i), a));
            }
        }
        Self { vantages }
    }

    /// The grid a planner samples for a class: ranges from [`MIN_RANGE`] to the model's
    /// largest, aspects within its aspect limit (all round without one), each kept a hair
    /// inside the limit so that a waypoint's recomputed vantage point is still seen.
    pub fn for_model(m: &SensorModel, n_range: usize, n_aspect: usize) -> Self {
        Self::for_model_from(m, MIN_RANGE, n_range, n_aspect)
    }

    /// [`VantageGrid::for_model`] with ranges from `min_range` (vantage units) instead of
    /// [`MIN_RANGE`].
    pub fn for_model_from(
        m: &SensorModel,
        min_range: f64,
        n_range: usize,
        n_aspect: usize,
    ) -> Self {
        let inset = 1.0 - 1e-6;
        Self::regular(
            [min_range.min(m.max_range), m.max_range * inset],
            n_range,
            m.aspect_limit.map_or(std::f64::consts::PI, |a| a * inset),
            n_aspect,
        )
    }

    /// Number of vantage points.
    pub fn len(&self) -> usize {
        self.vantages.len()
    }

    /// Whether the grid is empty.
    pub fn is_empty(&self) -> bool {
        self.vantages.is_empty()
    }
}

/// Binary entropy in nats.
pub fn entropy(p: f64) -> f64 {
    let h = |q: f64| if q > 0.0 { -q * q.ln() } else { 0.0 };
    h(p) + h(1.0 - p)
}

/// The field's value for one look model at belief `p`.
pub fn value(m: &LookModel, p: f64, method: FieldMethod) -> f64 {
    match method {
        FieldMethod::Pbd => {
            let s = covariance_of(p);
            0.5 * (1.0 + s * m.information()).ln()
        }
        FieldMethod::Bins(b) => {
            let b = b.max(1);
            let [lo, hi] = m.score_range(4.0);
            let w = (hi - lo) / b as f64;
            let mut total = 0.0;
            let mut h = 0.0;
            for i in 0..b {
                let z = lo + (i as f64 + 0.5) * w;
                let pz = p * m.likelihood[1].pdf(z) + (1.0 - p) * m.likelihood[0].pdf(z);
                total += pz;
                h += pz * entropy(m.posterior(p, z));
            }
            if total > 0.0 {
                (entropy(p) - h / total).max(0.0)
            } else {
                0.0
            }
        }
    }
}

/// A vantage grid with GP_ind's predictions at its points, computed once for a model: they do
/// not depend on a candidate's history, so every field over the grid reuses them.
#[derive(Debug, Clone)]
pub struct PreparedGrid {
    /// The grid.
    pub grid: VantageGrid,
    /// GP_ind's predictions at each of its points (`None` where the detector cannot see).
    pub ind: Vec<Option<IndAt>>,
}

impl PreparedGrid {
    /// Prepare `grid` for `model`.
    pub fn new(model: &SensorModel, grid: VantageGrid) -> Self {
        let ind = grid
            .vantages
            .iter()
            .map(|v| model.sees(v).then(|| model.ind_at(v)))
            .collect();
        Self { grid, ind }
    }
}

/// The perception field of a candidate with belief `p` over a prepared grid, for the sensor
/// model conditioned on its looks so far.
pub fn perception_field(
    c: &Conditioned<'_>,
    p: f64,
    grid: &PreparedGrid,
    method: FieldMethod,
) -> Vec<f64> {
    grid.grid
        .vantages
        .iter()
        .zip(&grid.ind)
        .map(|(v, ind)| {
            ind.as_ref()
                .and_then(|ind| c.at_with(v, ind))
                .map_or(0.0, |m| value(&m, p, method))
        })
        .collect()
}
