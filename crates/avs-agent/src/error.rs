//! [`AgentError`]: what stops the agent before or during a search (bad goal, inconsistent
//! knowledge, a domain it cannot execute, a world model that refuses an update).

use crate::world_model::WorldModelError;
use avs_concepts::ConceptError;

/// Errors that stop the agent before it can search (bad goal, inconsistent knowledge, a
/// domain without the operators the executive runs).
#[derive(Debug, thiserror::Error)]
pub enum AgentError {
    /// The goal names a class the knowledge file does not know.
    #[error("goal class `{class}` is not an object class of the knowledge file; expected one of {known}")]
    UnknownClass {
        /// The class asked for.
        class: String,
        /// The known classes.
        known: String,
    },
    /// A configuration value is out of range.
    #[error("agent configuration `{field}` = {value}: expected {expected}")]
    Config {
        /// The field.
        field: &'static str,
        /// Its value.
        value: f64,
        /// What is expected.
        expected: &'static str,
    },
    /// The planning domain lacks something the executive needs (an operator it executes, a
    /// function it supplies, a variable or relation it writes), or has it with another shape.
    #[error("planning domain `{domain}`: {what} `{name}` {problem}")]
    Domain {
        /// The domain's name.
        domain: String,
        /// `operator`, `function`, `variable`, `relation` or `type`.
        what: &'static str,
        /// Its name.
        name: String,
        /// What is wrong and what is expected.
        problem: String,
    },
    /// A class's verifier block cannot be used (no such model, a model that does not build).
    #[error("knowledge: the verifier of class `{class}`: {message}")]
    Verifier {
        /// The class.
        class: String,
        /// What is wrong.
        message: String,
    },
    /// The knowledge file is not usable by the conceptual map.
    #[error(transparent)]
    Concepts(#[from] ConceptError),
    /// The world model refused an update.
    #[error(transparent)]
    WorldModel(#[from] WorldModelError),
}
