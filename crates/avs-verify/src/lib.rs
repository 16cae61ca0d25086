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
//! * [`planner`] — the planned verifier (Fig. 7) and the GREEDY(τ) baseline;
//! * [`train`] — fitting a sensor model to labelled looks (§4.2.3).
#![warn(missing_docs)]

pub mod field;
pub mod gp;
pub mod pbd;
pub mod planner;
pub mod sensor;
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
