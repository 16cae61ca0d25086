//! Typed errors of the crate.

use std::path::PathBuf;

/// Everything that can go wrong when reading, building or solving a POMDP.
#[derive(Debug, thiserror::Error)]
pub enum PomdpError {
    /// A Cassandra `.pomdp` file could not be read from disk.
    #[error("cannot read POMDP file {path}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// A Cassandra `.pomdp` file is malformed.
    #[error("{file}:{line}: {message}")]
    Parse {
        /// File name (or `<string>` for in-memory text).
        file: String,
        /// 1-based line number of the offending token.
        line: usize,
        /// What was found and what is expected.
        message: String,
    },
    /// A model is inconsistent (probabilities that do not sum to one, NaN, sizes that disagree).
    #[error("invalid POMDP model: {0}")]
    InvalidModel(String),
    /// A model is larger than the solvers can expand in bounded memory
    /// ([`crate::model::MAX_MODEL_ENTRIES`]).
    #[error("model too large: {states} states × {actions} actions × {observations} observations is above {limit} (the size of one look-ahead from a full belief); expected a smaller model")]
    TooLarge {
        /// |S|.
        states: usize,
        /// |A|.
        actions: usize,
        /// |Z|.
        observations: usize,
        /// [`crate::model::MAX_MODEL_ENTRIES`].
        limit: usize,
    },
    /// A view-cone problem or coverage request has a bad field.
    #[error("invalid view-cone input: field `{field}`: {message}")]
    InvalidInput {
        /// The offending field.
        field: &'static str,
        /// What is wrong and what is expected.
        message: String,
    },
    /// An action, observation or belief given to a solver or session does not fit the model.
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
    /// A solve ended with bounds that cannot be right (not finite, or the lower above the upper):
    /// the model's numbers are beyond what f64 arithmetic carries. Models are checked when built
    /// ([`crate::model::MAX_VALUE_MAGNITUDE`]), so this is the backstop that keeps such bounds
    /// from ever being reported as a solution.
    #[error("the solve produced invalid bounds (lower {lower}, upper {upper}): {reason}")]
    Numerical {
        /// The lower bound at the initial belief.
        lower: f64,
        /// The upper bound at the initial belief.
        upper: f64,
        /// What is wrong with them.
        reason: &'static str,
    },
    /// The closed-loop session already ended with an outcome.
    #[error("the view-cone session has already ended")]
    SessionEnded,
}

/// Result alias for this crate.
pub type Result<T> = std::result::Result<T, PomdpError>;
