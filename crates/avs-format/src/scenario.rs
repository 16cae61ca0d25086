//! `kind: scenario` — what is checked of scenario files until their fields are defined.
//!
//! Scenarios (a search goal run in an environment, with seeds and the expected trace) are
//! defined by a later issue. Until then a scenario file is accepted when it is a YAML mapping
//! whose `kind` is `scenario`; its other fields are kept as opaque values, and the schema says
//! exactly that.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A scenario file's header; every other field is kept unchecked.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ScenarioHeader {
    /// Must be `scenario`.
    pub kind: ScenarioKind,
    /// The scenario's other fields, not yet checked.
    #[serde(flatten)]
    pub rest: serde_json::Map<String, serde_json::Value>,
}

/// The literal `scenario`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ScenarioKind {
    /// `kind: scenario`
    Scenario,
}

/// Parse and check a scenario file's text, returning every problem found (empty when valid).
pub fn check(file: &str, text: &str) -> Vec<crate::Diagnostic> {
    match crate::load_yaml_str::<ScenarioHeader>(file, text) {
        Ok(_) => Vec::new(),
        Err(e) => e.diagnostics,
    }
}
