//! # avs-plan
//!
//! (Being built; see the crate description.)
#![warn(missing_docs)]

/// Parse and check a domain file's text, returning every problem found (empty when valid).
pub fn check_domain(file: &str, text: &str) -> Vec<avs_format::Diagnostic> {
    match avs_format::load_yaml_str::<serde::de::IgnoredAny>(file, text) {
        Ok(_) => Vec::new(),
        Err(e) => e.diagnostics,
    }
}
