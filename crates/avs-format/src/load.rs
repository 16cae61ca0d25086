//! Reading avs YAML files safely.
//!
//! Files are read with a size bound; before deserialising, the text is walked by an event parser
//! that bounds nesting depth and alias expansion (serde_yaml's own limits — recursion 128, alias
//! jumps up to 100 × the number of events — still let a 16 MB file expand quadratically);
//! deserialisation goes through `serde_path_to_error` so a wrong field is reported with its
//! dotted path and the parser's line and column.

use crate::diag::Diagnostic;
use serde::de::DeserializeOwned;
use std::io::Read;
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
    // Read at most one byte past the bound: special files (pipes, devices) report length 0.
    let cannot = |e: std::io::Error| {
        Diagnostic::new(
            &file,
            "",
            format!("cannot read file: {e}"),
            "an existing, readable file",
        )
    };
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(MAX_FILE_BYTES + 1).read_to_end(&mut bytes))
        .map_err(cannot)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(Diagnostic::new(
            &file,
            "",
            format!("file is more than {MAX_FILE_BYTES} bytes"),
            format!("at most {MAX_FILE_BYTES} bytes"),
        )
        .into());
    }
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
///
/// The text is first walked without building anything ([`crate::positions::check_bounds`]):
/// at most [`MAX_FILE_BYTES`] bytes, [`crate::positions::MAX_DEPTH`] levels of nesting and
/// [`crate::positions::MAX_ALIAS_NODES`] nodes added by aliases. Errors carry the dotted path of
/// the field (`objects[2].pose.x`), the parser's line and column, and what was expected.
pub fn load_yaml_str<T: DeserializeOwned>(file: &str, text: &str) -> Result<T, LoadError> {
    if text.len() as u64 > MAX_FILE_BYTES {
        return Err(Diagnostic::new(
            file,
            "",
            format!("text is {} bytes", text.len()),
            format!("at most {MAX_FILE_BYTES} bytes"),
        )
        .into());
    }
    // Editors on some systems start files with a byte-order mark; YAML allows it, serde_yaml
    // misreads it as a document of its own.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    crate::positions::check_bounds(file, text)?;
    let de = serde_yaml::Deserializer::from_str(text);
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let path = if path == "." || path == "?" {
            String::new()
        } else {
            path
        };
        let inner = e.into_inner();
        let (message, expected) = split_message(strip_path_prefix(&yaml_message(&inner), &path));
        let mut d = Diagnostic::new(file, path, message, expected);
        match inner.location() {
            Some(loc) => d = d.at(loc.line(), loc.column()),
            None => crate::positions::locate(std::slice::from_mut(&mut d), text),
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

/// The message for a value that fits none of the forms of an untagged enum (e.g. `map:`).
pub(crate) const UNTAGGED_MISMATCH: &str = "this value fits none of the accepted forms";

/// serde_yaml starts some messages with its own rendering of the path (`a.b: invalid type…`);
/// the diagnostic prints the path already.
fn strip_path_prefix<'m>(message: &'m str, path: &str) -> &'m str {
    if let Some((head, rest)) = message.split_once(": ") {
        let is_prefix = path.starts_with(head)
            && matches!(
                path.as_bytes().get(head.len()),
                None | Some(b'.') | Some(b'[')
            );
        if !head.is_empty() && !head.contains(' ') && is_prefix {
            return rest;
        }
    }
    message
}

/// Split serde's "what is wrong, expected what" into the two halves of a diagnostic.
fn split_message(s: &str) -> (String, String) {
    const GENERIC: &str = "a value of the documented type (see `avs schema KIND`)";
    if let Some(i) = s.find(", expected ") {
        let (wrong, exp) = (&s[..i], &s[i + ", expected ".len()..]);
        let exp = match exp {
            "f64" | "f32" => "a number",
            "u8" | "u16" | "u32" | "u64" | "usize" => "a whole number ≥ 0",
            "i32" | "i64" | "isize" => "a whole number",
            "a boolean" | "bool" => "`true` or `false`",
            other => other,
        };
        return (wrong.to_string(), format!("expected {exp}"));
    }
    if let Some(field) = s
        .strip_prefix("missing field `")
        .and_then(|r| r.strip_suffix('`'))
    {
        return (s.to_string(), format!("the field `{field}` is required"));
    }
    if s.contains("more than one document") {
        return (
            "several YAML documents in one file".to_string(),
            "a single document (no `---` line after the first one)".to_string(),
        );
    }
    if s.contains("did not match any variant of untagged enum") {
        return (UNTAGGED_MISMATCH.to_string(), GENERIC.to_string());
    }
    (s.to_string(), GENERIC.to_string())
}

/// Read only the `kind:` of a YAML document.
pub fn read_kind(file: &str, text: &str) -> Result<FileKind, LoadError> {
    #[derive(serde::Deserialize)]
    struct KindOnly {
        kind: FileKind,
    }
    const KINDS: &str = "`kind:` one of environment, knowledge, domain, scenario";
    let k: KindOnly = load_yaml_str(file, text).map_err(|mut e| {
        for d in &mut e.diagnostics {
            if d.path == "kind" {
                d.expected = KINDS.into();
            } else if d.path.is_empty() && d.message.starts_with("missing field") {
                d.path = "kind".into();
                d.expected = KINDS.into();
            } else if d.path.is_empty() && d.message.starts_with("invalid type") {
                d.expected = format!("a mapping that starts with {KINDS}");
            }
        }
        e
    })?;
    Ok(k.kind)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::environment::Environment;

    #[test]
    fn unknown_field_names_the_field_and_the_accepted_ones() {
        let e = load_yaml_str::<Environment>("f.yaml", "kind: environment\nnmae: x\n").unwrap_err();
        let d = &e.diagnostics[0];
        assert_eq!(d.path, "nmae");
        assert_eq!((d.line, d.column), (Some(2), Some(1)));
        assert!(d.message.contains("unknown field `nmae`"), "{d}");
        assert!(d.expected.starts_with("expected one of"), "{d}");
    }

    #[test]
    fn wrong_type_deep_in_a_list_has_its_full_path_once() {
        let text = "kind: environment\nname: x\nmap: {ascii: \"#\", resolution: 1}\nrobot: {start: {x: 0, y: 0}}\nobjects:\n  - {id: a, class: c, role: target, room: r, pose: {x: 0, y: yes}, size: [1, 1, 1]}\n";
        let d = &load_yaml_str::<Environment>("f.yaml", text)
            .unwrap_err()
            .diagnostics[0];
        assert_eq!(d.path, "objects[0].pose.y");
        assert_eq!(d.line, Some(6));
        assert!(!d.message.starts_with("objects"), "path repeated: {d}");
        assert_eq!(d.expected, "expected a number");
    }

    #[test]
    fn oversized_and_special_files_are_bounded() {
        let big = " ".repeat(MAX_FILE_BYTES as usize + 1);
        let e = load_yaml_str::<Environment>("big.yaml", &big).unwrap_err();
        assert!(e.diagnostics[0].expected.contains("at most"));
        #[cfg(unix)]
        {
            let e = read_text(Path::new("/dev/zero")).unwrap_err();
            assert!(e.diagnostics[0].message.contains("more than"), "{e}");
        }
    }

    #[test]
    fn a_leading_byte_order_mark_is_accepted() {
        assert_eq!(
            read_kind("f.yaml", "\u{feff}kind: scenario\n").unwrap(),
            FileKind::Scenario
        );
    }

    #[test]
    fn read_kind_explains_a_missing_or_unknown_kind() {
        let d = &read_kind("f.yaml", "name: x\n").unwrap_err().diagnostics[0];
        assert_eq!(d.path, "kind");
        assert!(d
            .expected
            .contains("environment, knowledge, domain, scenario"));
        let d = &read_kind("f.yaml", "kind: planet\n")
            .unwrap_err()
            .diagnostics[0];
        assert_eq!((d.path.as_str(), d.line), ("kind", Some(1)));
        assert_eq!(
            read_kind("f.yaml", "kind: knowledge\nother: 1\n").unwrap(),
            FileKind::Knowledge
        );
    }
}
