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
    /// A detection-verification scenario.
    Verification,
}

impl FileKind {
    /// All kinds, in documentation order.
    pub const ALL: [FileKind; 5] = [
        FileKind::Environment,
        FileKind::Knowledge,
        FileKind::Domain,
        FileKind::Scenario,
        FileKind::Verification,
    ];

    /// The name used after `kind:`.
    pub fn name(self) -> &'static str {
        match self {
            FileKind::Environment => "environment",
            FileKind::Knowledge => "knowledge",
            FileKind::Domain => "domain",
            FileKind::Scenario => "scenario",
            FileKind::Verification => "verification",
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

/// [`load_yaml_str`] for a type with a JSON Schema: a missing field is also explained from the
/// schema ([`explain_missing_fields`]) — what the field holds and which fields its section has.
pub fn load_yaml_str_explained<T: DeserializeOwned + schemars::JsonSchema>(
    file: &str,
    text: &str,
) -> Result<T, LoadError> {
    load_yaml_str(file, text).map_err(|mut e| {
        explain_missing_fields::<T>(&mut e.diagnostics);
        e
    })
}

/// Parse a file's text as a `T` ([`load_yaml_str_explained`]), then run its field checks
/// `fields(&t, file)` and locate what they report in the text: the one home of every
/// `check` that `avs validate` runs on a kind of file. The value, or every problem found.
pub fn parse_checked<T: DeserializeOwned + schemars::JsonSchema>(
    file: &str,
    text: &str,
    fields: impl Fn(&T, &str) -> Vec<Diagnostic>,
) -> Result<T, LoadError> {
    let t = load_yaml_str_explained::<T>(file, text)?;
    let mut diagnostics = fields(&t, file);
    if diagnostics.is_empty() {
        return Ok(t);
    }
    crate::positions::locate(&mut diagnostics, text);
    Err(LoadError { diagnostics })
}

/// The problems [`parse_checked`] finds (empty when the text is valid).
pub fn check_with<T: DeserializeOwned + schemars::JsonSchema>(
    file: &str,
    text: &str,
    fields: impl Fn(&T, &str) -> Vec<Diagnostic>,
) -> Vec<Diagnostic> {
    parse_checked(file, text, fields)
        .err()
        .map_or_else(Vec::new, |e| e.diagnostics)
}

/// Rewrite the `expected` half of each "missing field `f`" diagnostic (as [`load_yaml_str`]
/// makes them, with paths relative to a `T`) from `T`'s JSON Schema: the field's description and
/// the required and optional fields of the section it is missing from, e.g. "the field
/// `category` is required: room category, one of the knowledge file's `room_categories`; this
/// section has `name`, `category` (required) and `seed`, `polygon` (optional)". Diagnostics
/// whose section the schema does not pin down (several forms fit) are left as they are.
pub fn explain_missing_fields<T: schemars::JsonSchema>(diagnostics: &mut [Diagnostic]) {
    let missing = |d: &Diagnostic| {
        d.message
            .strip_prefix("missing field `")
            .and_then(|r| r.strip_suffix('`'))
            .map(str::to_string)
    };
    if !diagnostics.iter().any(|d| missing(d).is_some()) {
        return;
    }
    let Ok(root) = serde_json::to_value(schemars::schema_for!(T)) else {
        return;
    };
    for d in diagnostics.iter_mut() {
        let Some(field) = missing(d) else { continue };
        if let Some(expected) = schema_hint::explain(&root, &d.path, &field) {
            d.expected = expected;
        }
    }
}

/// Reading a JSON Schema (schemars 0.8: `definitions`, `$ref`, `allOf` / `anyOf` wrappers) to
/// explain a missing field. Every walk is bounded by the path's length and a fixed depth.
mod schema_hint {
    use serde_json::Value;

    /// Most `$ref` / `allOf` / `anyOf` levels followed from one node.
    const MAX_HOPS: usize = 16;

    /// Follow `$ref` and single-element `allOf` wrappers.
    fn deref<'a>(root: &'a Value, mut node: &'a Value) -> &'a Value {
        for _ in 0..MAX_HOPS {
            if let Some(r) = node.get("$ref").and_then(Value::as_str) {
                let name = r.rsplit('/').next().unwrap_or(r);
                match root.get("definitions").and_then(|d| d.get(name)) {
                    Some(n) => node = n,
                    None => break,
                }
            } else if let Some([one]) = node
                .get("allOf")
                .and_then(Value::as_array)
                .map(Vec::as_slice)
            {
                node = one;
            } else {
                break;
            }
        }
        node
    }

    /// The alternatives a node stands for (`anyOf` / `oneOf` flattened, e.g. an optional value
    /// or an untagged enum), each dereferenced.
    fn forms<'a>(root: &'a Value, node: &'a Value, depth: usize, out: &mut Vec<&'a Value>) {
        let node = deref(root, node);
        let alts = node
            .get("anyOf")
            .or_else(|| node.get("oneOf"))
            .and_then(Value::as_array);
        match alts {
            Some(alts) if depth < MAX_HOPS => {
                for a in alts {
                    forms(root, a, depth + 1, out);
                }
            }
            _ => out.push(node),
        }
    }

    /// One step of a dotted path: a field name or a list index.
    enum Step<'p> {
        Field(&'p str),
        Index(usize),
    }

    /// `rooms[0].seed` → `rooms`, 0, `seed`; `None` for a path this walk cannot read.
    fn steps(path: &str) -> Option<Vec<Step<'_>>> {
        let mut out = Vec::new();
        if path.is_empty() {
            return Some(out);
        }
        for part in path.split('.') {
            let (name, mut rest) = match part.find('[') {
                Some(i) => (&part[..i], &part[i..]),
                None => (part, ""),
            };
            if !name.is_empty() {
                out.push(Step::Field(name));
            }
            while let Some(r) = rest.strip_prefix('[') {
                let (num, tail) = r.split_once(']')?;
                out.push(Step::Index(num.parse().ok()?));
                rest = tail;
            }
            if !rest.is_empty() {
                return None;
            }
        }
        Some(out)
    }

    /// The section (an object schema) at `path` that has a property `field`, when exactly one
    /// form fits.
    fn section<'a>(root: &'a Value, path: &str, field: &str) -> Option<&'a Value> {
        let mut node = root;
        for step in steps(path)? {
            let mut fs = Vec::new();
            forms(root, node, 0, &mut fs);
            node = match step {
                Step::Field(name) => fs
                    .into_iter()
                    .find_map(|f| f.get("properties").and_then(|p| p.get(name)))?,
                Step::Index(i) => fs.into_iter().find_map(|f| match f.get("items")? {
                    Value::Array(tuple) => tuple.get(i),
                    one => Some(one),
                })?,
            };
        }
        let mut fs = Vec::new();
        forms(root, node, 0, &mut fs);
        let mut fits = fs
            .into_iter()
            .filter(|f| f.get("properties").and_then(|p| p.get(field)).is_some());
        let one = fits.next()?;
        fits.next().is_none().then_some(one)
    }

    /// The first sentence of a description, lower-cased at the start, at most 160 characters.
    fn first_sentence(s: &str) -> String {
        let s = s.trim();
        let end = s.find(". ").or_else(|| s.find('\n')).unwrap_or(s.len());
        let mut t: String = s[..end].trim_end_matches('.').chars().take(160).collect();
        let mut cs = t.chars();
        if let (Some(a), Some(b)) = (cs.next(), cs.next()) {
            if a.is_uppercase() && !b.is_uppercase() {
                t = a.to_lowercase().chain(t.chars().skip(1)).collect();
            }
        }
        t
    }

    /// The `expected` text for field `field` missing at `path`, or `None`.
    pub(super) fn explain(root: &Value, path: &str, field: &str) -> Option<String> {
        let sec = section(root, path, field)?;
        let props = sec.get("properties")?.as_object()?;
        let required: Vec<&str> = sec
            .get("required")
            .and_then(Value::as_array)
            .map(|v| v.iter().filter_map(Value::as_str).collect())
            .unwrap_or_default();
        let list = |names: Vec<&str>| {
            names
                .iter()
                .map(|n| format!("`{n}`"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let names: Vec<&str> = props.keys().map(String::as_str).collect();
        let req: Vec<&str> = names
            .iter()
            .copied()
            .filter(|n| required.contains(n))
            .collect();
        let opt: Vec<&str> = names
            .iter()
            .copied()
            .filter(|n| !required.contains(n))
            .collect();
        let about = props
            .get(field)
            .map(|p| {
                p.get("description")
                    .or_else(|| deref(root, p).get("description"))
                    .and_then(Value::as_str)
                    .map(first_sentence)
                    .unwrap_or_default()
            })
            .unwrap_or_default();
        let mut s = format!("the field `{field}` is required");
        if !about.is_empty() {
            s.push_str(&format!(": {about}"));
        }
        s.push_str(&format!("; this section has {} (required)", list(req)));
        if !opt.is_empty() {
            s.push_str(&format!(" and {} (optional)", list(opt)));
        }
        Some(s)
    }
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
    const KINDS: &str = "`kind:` one of environment, knowledge, domain, scenario, verification";
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
            .contains("environment, knowledge, domain, scenario, verification"));
        let d = &read_kind("f.yaml", "kind: planet\n")
            .unwrap_err()
            .diagnostics[0];
        assert_eq!((d.path.as_str(), d.line), ("kind", Some(1)));
        assert_eq!(
            read_kind("f.yaml", "kind: knowledge\nother: 1\n").unwrap(),
            FileKind::Knowledge
        );
    }

    #[test]
    fn a_missing_field_lists_the_fields_of_its_section() {
        let text = "kind: environment\nname: x\nmap: {ascii: \"#\", resolution: 1}\nrobot: {start: {x: 0, y: 0}}\nrooms:\n  - {name: office, seed: {x: 1, y: 1}}\n";
        let e = load_yaml_str_explained::<Environment>("f.yaml", text).unwrap_err();
        let d = &e.diagnostics[0];
        assert_eq!(d.path, "rooms[0]");
        assert!(d.message.contains("missing field `category`"), "{d}");
        assert_eq!(
            d.expected,
            "the field `category` is required: room category, one of the knowledge file's \
             `room_categories`; this section has `category`, `name` (required) and `polygon`, \
             `seed` (optional)"
        );
        // Inside an optional section (`seed` is an Option<Point>) and at the top.
        let e = load_yaml_str_explained::<Environment>(
            "f.yaml",
            &text
                .replace("name: office,", "name: office, category: office,")
                .replace("{x: 1, y: 1}", "{x: 1}"),
        )
        .unwrap_err();
        assert_eq!(e.diagnostics[0].path, "rooms[0].seed");
        assert!(
            e.diagnostics[0]
                .expected
                .contains("this section has `x`, `y` (required)"),
            "{}",
            e.diagnostics[0]
        );
        let e = load_yaml_str_explained::<Environment>(
            "f.yaml",
            "kind: environment\nname: x\nmap: {ascii: \"#\", resolution: 1}\n",
        )
        .unwrap_err();
        let d = &e.diagnostics[0];
        assert!(d.message.contains("missing field `robot`"), "{d}");
        assert!(
            d.expected
                .contains("`kind`, `map`, `name`, `robot` (required)"),
            "{d}"
        );
        assert!(
            d.expected
                .contains("`camera`, `doors`, `laser`, `objects`, `rooms` (optional)"),
            "{d}"
        );
    }

    #[test]
    fn a_missing_field_in_an_ambiguous_section_keeps_the_plain_hint() {
        // `map` is either form: which fields it needs depends on the form meant.
        let mut ds = vec![Diagnostic::new(
            "f.yaml",
            "map",
            "missing field `resolution`",
            "x",
        )];
        explain_missing_fields::<Environment>(&mut ds);
        assert_eq!(ds[0].expected, "x");
        // A path the schema does not have is left alone too.
        let mut ds = vec![Diagnostic::new(
            "f.yaml",
            "nothing[3]",
            "missing field `a`",
            "x",
        )];
        explain_missing_fields::<Environment>(&mut ds);
        assert_eq!(ds[0].expected, "x");
    }
}
