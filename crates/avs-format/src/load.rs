//! Reading avs YAML files safely.
//!
//! Files are read with a size bound; serde_yaml bounds nesting depth and alias expansion;
//! deserialisation goes through `serde_path_to_error` so a wrong field is reported with its
//! dotted path and the parser's line and column.

use crate::diag::Diagnostic;
use serde::de::DeserializeOwned;
use std::path::Path;

/// Largest avs file we read, in bytes.
pub const MAX_FILE_BYTES: u64 = 16 * 1024 * 1024;

/// The `kind:` of an avs file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FileKind {
    /// A world: map, rooms, doors, objects, robot and sensors.
    Environment,
    /// Common-sense knowledge: categories, object classes, priors, sensor models.
    Knowledge,
    /// A planning domain.
    Domain,
    /// A plan-trace scenario.
    Scenario,
}

impl FileKind {
    /// All kinds, in documentation order.
    pub const ALL: [FileKind; 4] = [
        FileKind::Environment,
        FileKind::Knowledge,
        FileKind::Domain,
        FileKind::Scenario,
    ];

    /// The name used after `kind:`.
    pub fn name(self) -> &'static str {
        match self {
            FileKind::Environment => "environment",
            FileKind::Knowledge => "knowledge",
            FileKind::Domain => "domain",
            FileKind::Scenario => "scenario",
        }
    }
}

/// A file could not be read or parsed.
#[derive(Debug, thiserror::Error)]
#[error("{}", .diagnostics.iter().map(|d| d.to_string()).collect::<Vec<_>>().join("\n"))]
pub struct LoadError {
    /// What went wrong, one entry per problem.
    pub diagnostics: Vec<Diagnostic>,
}

impl From<Diagnostic> for LoadError {
    fn from(d: Diagnostic) -> Self {
        LoadError {
            diagnostics: vec![d],
        }
    }
}

/// Read a YAML file from disk into `T`.
pub fn load_yaml<T: DeserializeOwned>(path: &Path) -> Result<T, LoadError> {
    let text = read_text(path)?;
    load_yaml_str(&path.display().to_string(), &text)
}

/// Read a file's text with the size bound, reporting problems as diagnostics.
pub fn read_text(path: &Path) -> Result<String, LoadError> {
    let file = path.display().to_string();
    let meta = std::fs::metadata(path).map_err(|e| {
        Diagnostic::new(
            &file,
            "",
            format!("cannot read file: {e}"),
            "an existing, readable file",
        )
    })?;
    if meta.len() > MAX_FILE_BYTES {
        return Err(Diagnostic::new(
            &file,
            "",
            format!("file is {} bytes", meta.len()),
            format!("at most {MAX_FILE_BYTES} bytes"),
        )
        .into());
    }
    let bytes = std::fs::read(path).map_err(|e| {
        Diagnostic::new(
            &file,
            "",
            format!("cannot read file: {e}"),
            "an existing, readable file",
        )
    })?;
    String::from_utf8(bytes).map_err(|e| {
        Diagnostic::new(
            &file,
            "",
            format!(
                "not UTF-8 text (invalid byte at offset {})",
                e.utf8_error().valid_up_to()
            ),
            "a UTF-8 YAML file",
        )
        .into()
    })
}

/// Parse YAML text (named `file` in diagnostics) into `T`.
pub fn load_yaml_str<T: DeserializeOwned>(file: &str, text: &str) -> Result<T, LoadError> {
    let de = serde_yaml::Deserializer::from_str(text);
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let path = if path == "." { String::new() } else { path };
        let inner = e.into_inner();
        let mut d = Diagnostic::new(
            file,
            path,
            yaml_message(&inner),
            "a value of the documented type (see `avs schema KIND`)",
        );
        if let Some(loc) = inner.location() {
            d = d.at(loc.line(), loc.column());
        }
        d.into()
    })
}

fn yaml_message(e: &serde_yaml::Error) -> String {
    // serde_yaml appends " at line L column C"; we print the position in front instead.
    let s = e.to_string();
    match s.find(" at line ") {
        Some(i) => s[..i].to_string(),
        None => s,
    }
}

/// Read only the `kind:` of a YAML document.
pub fn read_kind(file: &str, text: &str) -> Result<FileKind, LoadError> {
    #[derive(serde::Deserialize)]
    struct KindOnly {
        kind: FileKind,
    }
    let k: KindOnly = load_yaml_str(file, text).map_err(|mut e| {
        for d in &mut e.diagnostics {
            if d.path.is_empty() || d.path == "kind" {
                d.path = "kind".into();
                d.expected = "`kind:` one of environment, knowledge, domain, scenario".into();
            }
        }
        e
    })?;
    Ok(k.kind)
}
