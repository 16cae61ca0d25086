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
}

/// The result of view planning.
pub type Result<T> = std::result::Result<T, ViewError>;
