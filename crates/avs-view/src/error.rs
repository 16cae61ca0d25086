//! [`ViewError`]: a view-planning request with a bad field.

/// Errors of view planning.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ViewError {
    /// A coverage request has a bad field.
    #[error("invalid view-cone input: field `{field}`: {message}")]
    InvalidInput {
        /// The offending field.
        field: &'static str,
        /// What is wrong and what is expected.
        message: String,
    },
    /// The exact view plan's solver failed (a numerical failure it could not recover from).
    #[error("the exact view plan could not be solved: {0}")]
    Solver(String),
}

/// The result of view planning.
pub type Result<T> = std::result::Result<T, ViewError>;
