//! GP regression cases: the file format of `shared/data/gp/sklearn_gpr.json` (scikit-learn's
//! `GaussianProcessRegressor` with `ConstantKernel * RBF`) and their evaluation.
//!
//! A case file is `{"cases": [case, …]}` (other top-level keys, such as `generator`, are
//! ignored). A case names training inputs `X` (one row per point), targets `y`, query points
//! `X_query`, the noise variance `noise_variance_alpha` (scikit-learn's `alpha`), the kernel
//! (`signal_variance`, `length_scale` with one entry per input, or a single entry shared by all
//! inputs as scikit-learn's isotropic `RBF`) and whether the kernel is to be `fitted` within
//! `bounds`. The reference answers (`log_marginal_likelihood`, `lml_gradient_wrt_log_params`,
//! `mean`, `std`) are optional: [`eval_case`] does not read them.
//!
//! ```
//! use avs_verify::gp::{eval_case, GpCaseFile};
//! let file = GpCaseFile::from_json(r#"{"cases": [{
//!     "name": "two points", "X": [[0.0], [1.0]], "y": [1.0, -1.0], "X_query": [[0.0], [50.0]],
//!     "noise_variance_alpha": 1e-10, "fitted": false,
//!     "signal_variance": 2.0, "length_scale": [0.5]
//! }]}"#)?;
//! let r = eval_case(&file.cases[0], 0)?;
//! assert_eq!(r.name, "two points");
//! assert!((r.mean[0] - 1.0).abs() < 1e-6 && r.std[0] < 1e-4); // at a training point
//! assert!(r.mean[1].abs() < 1e-12 && (r.std[1] - 2f64.sqrt()).abs() < 1e-12); // prior
//! assert_eq!(r.lml_gradient_wrt_log_params.len(), 2);
//! # Ok::<(), avs_verify::gp::GpError>(())
//! ```

use serde::{Deserialize, Serialize};

use super::{FitBounds, Gp, GpError, SeKernel};

/// Most training points per case: the factorisation is `O(n³)` in time and `O(n²)` in memory.
pub const MAX_POINTS: usize = 2000;
/// Most training points per fitted case: a fit factorises `K` some hundreds of times.
pub const MAX_FIT_POINTS: usize = 500;
/// Most inputs per point.
pub const MAX_DIM: usize = 64;
/// Most query points per case.
pub const MAX_QUERIES: usize = 100_000;
/// Random restarts of a fitted case after the start at its given parameters (scikit-learn's
/// `n_restarts_optimizer=10` in the reference file).
pub const CASE_RESTARTS: usize = 10;
/// Query points per triangular solve in [`eval_case`], bounding its memory.
const QUERY_CHUNK: usize = 1024;

/// A case file: `{"cases": [...]}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GpCaseFile {
    /// The tool that made the reference answers, if recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub generator: Option<String>,
    /// The cases.
    pub cases: Vec<GpCase>,
}

impl GpCaseFile {
    /// Parses a case file from JSON text; the error names where the document is malformed
    /// (e.g. `cases[0].X[2][0]`).
    pub fn from_json(text: &str) -> Result<GpCaseFile, GpError> {
        let de = &mut serde_json::Deserializer::from_str(text);
        let file: GpCaseFile =
            serde_path_to_error::deserialize(de).map_err(|e| GpError::Parse {
                path: e.path().to_string(),
                message: e.inner().to_string(),
            })?;
        Ok(file)
    }
}

/// One regression case (the keys as in the file).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GpCase {
    /// The case's name.
    pub name: String,
    /// Training inputs, one row per point.
    #[serde(rename = "X")]
    pub x: Vec<Vec<f64>>,
    /// Training targets.
    pub y: Vec<f64>,
    /// Query points.
    #[serde(rename = "X_query")]
    pub x_query: Vec<Vec<f64>>,
    /// Noise variance added to the diagonal (scikit-learn's `alpha`).
    pub noise_variance_alpha: f64,
    /// Whether the kernel is fitted (from `signal_variance` and `length_scale` as the first
    /// start) or used as given.
    pub fitted: bool,
    /// σ²: the kernel's, or the first start of a fit. In the reference file, scikit-learn's
    /// fitted value for fitted cases.
    pub signal_variance: f64,
    /// One length scale per input, or one shared by all inputs.
    pub length_scale: Vec<f64>,
    /// Fit bounds (required when `fitted`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bounds: Option<FitBounds>,
    /// Reference log marginal likelihood.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub log_marginal_likelihood: Option<f64>,
    /// Reference gradient with respect to the log parameters.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lml_gradient_wrt_log_params: Option<Vec<f64>>,
    /// Reference predictive means at `X_query`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean: Option<Vec<f64>>,
    /// Reference predictive standard deviations of the latent function at `X_query`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub std: Option<Vec<f64>>,
}

/// What [`eval_case`] computes for a case, serialised with the reference file's keys.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GpCaseResult {
    /// The case's name.
    pub name: String,
    /// `log p(y | X)` at the (fitted) parameters.
    pub log_marginal_likelihood: f64,
    /// Its gradient with respect to `(log σ², log l_1, …)`, one length-scale component per
    /// entry of `length_scale`.
    pub lml_gradient_wrt_log_params: Vec<f64>,
    /// Predictive means at the query points.
    pub mean: Vec<f64>,
    /// Predictive standard deviations of the latent function (without noise).
    pub std: Vec<f64>,
    /// σ² used (fitted, for fitted cases).
    pub signal_variance: f64,
    /// Length scales used, as many as the case gave.
    pub length_scale: Vec<f64>,
}

fn field(field: impl Into<String>, reason: impl Into<String>) -> GpError {
    GpError::Field {
        field: field.into(),
        reason: reason.into(),
    }
}

fn finite_positive(name: &str, v: f64) -> Result<(), GpError> {
    if !v.is_finite() || v <= 0.0 {
        return Err(field(name, format!("must be finite and positive, got {v}")));
    }
    Ok(())
}

fn check_points(name: &str, points: &[Vec<f64>], dim: usize) -> Result<(), GpError> {
    for (i, p) in points.iter().enumerate() {
        if p.len() != dim {
            return Err(field(
                format!("{name}[{i}]"),
                format!("has {} coordinates, expected {dim}", p.len()),
            ));
        }
        if let Some((d, v)) = p.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(field(
                format!("{name}[{i}][{d}]"),
                format!("is not finite ({v})"),
            ));
        }
    }
    Ok(())
}

/// Checks a case; returns the number of inputs and whether the length scale is shared.
fn check(case: &GpCase) -> Result<(usize, bool), GpError> {
    let n = case.x.len();
    let dim = case.x.first().map_or(case.length_scale.len(), Vec::len);
    if dim == 0 {
        return Err(field("X", "points need at least one coordinate"));
    }
    if dim > MAX_DIM {
        return Err(field(
            "X",
            format!("{dim} inputs per point, at most {MAX_DIM}"),
        ));
    }
    let limit = if case.fitted {
        MAX_FIT_POINTS
    } else {
        MAX_POINTS
    };
    if n > limit {
        let kind = if case.fitted { "a fitted" } else { "a" };
        return Err(field(
            "X",
            format!("{n} training points, at most {limit} in {kind} case"),
        ));
    }
    if case.x_query.len() > MAX_QUERIES {
        return Err(field(
            "X_query",
            format!("{} query points, at most {MAX_QUERIES}", case.x_query.len()),
        ));
    }
    if case.y.len() != n {
        return Err(field(
            "y",
            format!("has {} values, but `X` has {n} rows", case.y.len()),
        ));
    }
    check_points("X", &case.x, dim)?;
    check_points("X_query", &case.x_query, dim)?;
    if let Some((i, v)) = case.y.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(field(format!("y[{i}]"), format!("is not finite ({v})")));
    }
    let a = case.noise_variance_alpha;
    if !a.is_finite() || a < 0.0 {
        return Err(field(
            "noise_variance_alpha",
            format!("must be finite and not negative, got {a}"),
        ));
    }
    finite_positive("signal_variance", case.signal_variance)?;
    let shared = match case.length_scale.len() {
        k if k == dim => false,
        1 => true,
        k => {
            return Err(field(
                "length_scale",
                format!("has {k} entries for {dim} inputs (give {dim}, or 1 shared by all)"),
            ))
        }
    };
    for (d, &l) in case.length_scale.iter().enumerate() {
        finite_positive(&format!("length_scale[{d}]"), l)?;
    }
    if case.fitted {
        let b = case
            .bounds
            .as_ref()
            .ok_or_else(|| field("bounds", "a fitted case needs bounds"))?;
        b.validate().map_err(|e| field("bounds", e.to_string()))?;
    }
    Ok((dim, shared))
}

/// Evaluates a case: a fixed case (`fitted: false`) at its parameters; a fitted one by
/// [`Gp::fit`] (or [`Gp::fit_isotropic`] for a shared length scale) inside its bounds, first
/// from its parameters, then [`CASE_RESTARTS`] random starts from `seed`. Then the log marginal
/// likelihood, its gradient, and the predictive mean and standard deviation of the latent
/// function at `X_query`.
///
/// Errors name the malformed field ([`GpError::Field`]: `X` and `y` of different lengths, a
/// point with the wrong number of coordinates, a non-finite number, a non-positive parameter,
/// missing or invalid bounds, more than [`MAX_POINTS`] / [`MAX_FIT_POINTS`] points,
/// [`MAX_DIM`] inputs or [`MAX_QUERIES`] queries), or a kernel matrix that is not positive
/// definite.
pub fn eval_case(case: &GpCase, seed: u64) -> Result<GpCaseResult, GpError> {
    let (dim, shared) = check(case)?;
    let kernel = SeKernel {
        signal_variance: case.signal_variance,
        length_scales: if shared {
            vec![case.length_scale[0]; dim]
        } else {
            case.length_scale.clone()
        },
        angular: Vec::new(),
    };
    let (x, y, alpha) = (case.x.clone(), case.y.clone(), case.noise_variance_alpha);
    let gp = match (case.fitted, shared, case.bounds.as_ref()) {
        (true, false, Some(b)) => Gp::fit(x, y, alpha, &kernel, b, CASE_RESTARTS, seed)?,
        (true, true, Some(b)) => Gp::fit_isotropic(x, y, alpha, &kernel, b, CASE_RESTARTS, seed)?,
        _ => Gp::new(kernel, alpha, x, y)?,
    };
    let gradient = if shared {
        gp.lml_gradient_wrt_log_params_isotropic()
    } else {
        gp.lml_gradient_wrt_log_params()
    };
    let mut mean = Vec::with_capacity(case.x_query.len());
    let mut std = Vec::with_capacity(case.x_query.len());
    for chunk in case.x_query.chunks(QUERY_CHUNK) {
        for (m, v) in gp.predict_batch(chunk) {
            mean.push(m);
            std.push(v.sqrt());
        }
    }
    let k = gp.kernel();
    Ok(GpCaseResult {
        name: case.name.clone(),
        log_marginal_likelihood: gp.log_marginal_likelihood(),
        lml_gradient_wrt_log_params: gradient,
        mean,
        std,
        signal_variance: k.signal_variance,
        length_scale: if shared {
            vec![k.length_scales[0]]
        } else {
            k.length_scales.clone()
        },
    })
}
