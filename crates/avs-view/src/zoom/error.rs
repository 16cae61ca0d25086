//! [`ZoomError`]: why the zoom pipeline could not run, as opposed to running and finding
//! nothing.
//!
//! A malformed vote matrix, a nonsense configuration or a robot without the attention or the
//! recogniser the pipeline needs is an error; a hypothesis that leads nowhere, a window the
//! camera cannot turn to or a failed image of one window is not (the search notes it in
//! [`crate::zoom::ZoomOutcome::skipped`] and goes on).

use avs_robot::ActionFailure;

/// Errors of the zoom pipeline.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ZoomError {
    /// An argument has a bad field (a configuration factor, an object model, the view cone).
    #[error("invalid zoom input: field `{field}`: {message}")]
    InvalidInput {
        /// The offending field.
        field: &'static str,
        /// What is wrong and what is expected.
        message: String,
    },
    /// A vote matrix whose value count is not `cols × rows`, holds a non-finite value, or does
    /// not fit the image's vote cells.
    #[error("malformed vote matrix for class `{class}`: {message}")]
    MalformedVotes {
        /// The matrix's class.
        class: String,
        /// What is wrong.
        message: String,
    },
    /// The robot cannot do what the pipeline needs (its [`avs_robot::Robot::attention`] or
    /// [`avs_robot::Robot::recognise`] failed with
    /// [`avs_robot::FailureReason::Unsupported`]): the caller falls back to
    /// [`avs_robot::Robot::process_view_cone`].
    #[error("the robot has no {capability}: {message}")]
    Unsupported {
        /// `"attention"` or `"recogniser"`.
        capability: &'static str,
        /// The robot's explanation.
        message: String,
    },
    /// The first (unzoomed) image failed: without it there is nothing to zoom on.
    #[error("the initial image failed: {0}")]
    Robot(#[source] ActionFailure),
    /// The robot's report on the initial image does not fit the request (a missing class, a
    /// different image geometry).
    #[error("the robot's report on the initial image is malformed: {0}")]
    BadReport(String),
}
