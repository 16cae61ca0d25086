//! [`EvalError`]: what stops an episode, a bench or a scenario before it has a result.

use avs_agent::AgentError;

/// Errors of the experiment harness. Messages name the file (and the field, where one is at
/// fault).
#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    /// A file could not be read, or is invalid.
    #[error("{what} {file}: {message}")]
    Load {
        /// `environment`, `knowledge`, `domain` or `scenario`.
        what: &'static str,
        /// The file.
        file: String,
        /// What is wrong.
        message: String,
    },
    /// A field of a scenario or request names something that is not there.
    #[error("{file}: {field}: {message}")]
    Field {
        /// The file (or the flag's owner).
        file: String,
        /// The field.
        field: String,
        /// What is wrong and what is expected.
        message: String,
    },
    /// An input file could not be read or parsed: its diagnostics name the file (with line and
    /// column where there is one), so they are the message as they are.
    #[error(transparent)]
    Input(#[from] avs_format::LoadError),
    /// The simulated world or robot refused the setup.
    #[error("{0}")]
    Sim(String),
    /// The agent refused the setup.
    #[error(transparent)]
    Agent(#[from] AgentError),
}

impl EvalError {
    /// An environment file's world could not be built: the checks' diagnostics already name
    /// the file (with line and column), so they are the message as they are; anything else is
    /// a load error of `file`.
    pub fn environment(file: &str, e: avs_sim::SimError) -> Self {
        match e {
            avs_sim::SimError::Checks(_) => Self::Sim(e.to_string()),
            e => Self::Load {
                what: "environment",
                file: file.to_string(),
                message: e.to_string(),
            },
        }
    }
}
