//! # avs-verify
//!
//! Detection verification as a decision (Velez, Hemann, Huang, Posner, Roy — *Modelling
//! observation correlations for active exploration and robust object detection*, JAIR 44, 2012;
//! `000` in `../shared/papers`): a detector that fired is a *candidate*; whether it is an object
//! is a belief, sharpened by looks from well-chosen vantage points and settled by a decision
//! whose price (16 m for a wrong one) is weighed against the detour.
//!
//! * [`gp`] — Gaussian-process regression: squared-exponential kernel with a length scale per
//!   input, predictive mean and variance, log marginal likelihood and its gradient, and a
//!   maximum-likelihood fit;
//! * [`vantage`] — vantage points (range, aspect) relative to a candidate (§5.3);
//! * [`sensor`] — the sensor models: static disc (eq. 10–11) and dynamic (GP_ind and GP_corr
//!   mixed by eq. 9, 16, 17), and Bayes' rule on a look (eq. 6);
//! * [`pbd`] — posterior belief distributions: the belief's covariance after future looks
//!   without enumerating their scores (eq. 25–32) and the expected decision cost from it;
//! * [`field`] — perception fields (eq. 7–8) over a vantage grid, by PBD or by enumeration;
//! * [`planner`] — the planned verifier (Fig. 7) and the GREEDY(τ) and RTBSS baselines;
//! * [`sequential`] — verification with a binary detector whose looks are independent: the
//!   exact Bayes-optimal look / accept / reject policy over a budget of looks;
//! * [`train`] — fitting a sensor model to labelled looks (§4.2.3).
//!
//! ## Example
//! ```
//! use avs_format::verifier::{CorrSpec, KernelSpec};
//! use avs_verify::planner::planned::{plan, PlannedConfig};
//! use avs_verify::planner::{Candidate, OpenPlane, Step};
//! use avs_verify::sensor::{ModelKind, SensorModel};
//! use avs_verify::train::{HypothesisSpec, SensorModelSpec};
//! use rand::SeedableRng;
//! // A detector that scores an object about 2 and a look-alike about 0.8 from 1–6 m, each
//! // feature with its own smooth nuisance field (GP_corr) — in practice `train::train` fits
//! // this to labelled looks (`avs verify train`).
//! let hyp = |m: f64| HypothesisSpec {
//!     mean: m,
//!     kernel: KernelSpec { signal_variance: 0.1, length_scales: vec![2.0, 0.8] },
//!     noise_variance: 0.01,
//!     spread: 0.56,
//!     points: vec![[1.0, 0.0, m], [3.0, 0.0, m], [6.0, 0.0, m]],
//!     corr: CorrSpec {
//!         kernel: KernelSpec { signal_variance: 0.5, length_scales: vec![1.5, 0.4] },
//!         noise_variance: 0.06,
//!     },
//! };
//! let model = SensorModel::from_spec(&SensorModelSpec {
//!     kind: ModelKind::Dynamic { alpha_scale: 1.0 },
//!     max_range: 6.0,
//!     aspect_limit: Some(1.4),
//!     object: hyp(2.0),
//!     no_object: hyp(0.8),
//! })
//! .unwrap();
//! // The detector fired on a sign 2 m beside the route (facing it) with a middling score.
//! let mut sign = Candidate::new([4.0, 2.0], Some(-std::f64::consts::FRAC_PI_2), &model, 0.5);
//! sign.observe([2.0, 0.0], 1.4).unwrap();
//! // Plan: another look is worth its detour against a 16 m wrong decision.
//! let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
//! let p = plan(&[sign.clone()], [2.0, 0.0], [12.0, 0.0], &OpenPlane, &PlannedConfig::default(), &mut rng).unwrap();
//! let Step::Look { waypoint, .. } = p.step else { panic!("expected a look") };
//! // Object-like scores from there and from a metre and a half further on make it near certain.
//! sign.observe(waypoint, 2.1).unwrap();
//! sign.observe([waypoint[0] + 1.5, waypoint[1]], 2.0).unwrap();
//! assert!(sign.belief > 0.9, "{}", sign.belief);
//! ```
#![warn(missing_docs)]

pub mod field;
pub mod gp;
pub mod pbd;
pub mod planner;
pub mod sensor;
pub mod sequential;
pub mod train;
pub mod vantage;

/// What can go wrong in verification.
#[derive(Debug, thiserror::Error)]
pub enum VerifyError {
    /// A Gaussian process could not be built (bad parameters or data).
    #[error(transparent)]
    Gp(#[from] gp::GpError),
    /// A model parameter is out of its range.
    #[error("{field}: {message}")]
    Invalid {
        /// The parameter, as a path (e.g. `object.noise_variance`).
        field: String,
        /// What is expected.
        message: String,
    },
}
