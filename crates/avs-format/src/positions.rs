//! Where things are in a YAML text: bounds checks before deserialising, and the line and column
//! of a dotted field path (`objects[3].room`) for semantic diagnostics.
//!
//! Both walk the event stream of the `yaml-rust2` parser, which never expands aliases and keeps
//! its nesting on the heap (flow nesting is capped at 255 by the scanner), so a walk costs time
//! and memory linear in the text whatever the text is.
//!
//! Alias expansion is measured without expanding: every node counts once where it is written,
//! and an alias `*a` counts as the expanded size of the node anchored `&a` (recorded when that
//! node ended). The sum is the number of nodes a deserialiser would build; a "billion laughs"
//! document is rejected as soon as that sum passes [`MAX_ALIAS_NODES`] above the written nodes.

use crate::diag::Diagnostic;
use std::collections::{HashMap, HashSet};
use yaml_rust2::parser::{Event, Parser};
use yaml_rust2::scanner::Marker;

/// Deepest nesting of mappings and sequences accepted (serde_yaml itself stops at 128).
pub const MAX_DEPTH: usize = 64;

/// Most nodes that aliases may add to a document when expanded.
pub const MAX_ALIAS_NODES: u64 = 100_000;

/// A 1-based line and column.
pub type LineCol = (usize, usize);

fn line_col(m: &Marker) -> LineCol {
    // yaml-rust2 markers: line 1-based, column 0-based.
    (m.line().max(1), m.col() + 1)
}

struct Frame {
    /// Length of the path string of this collection.
    base: usize,
    map: bool,
    /// For mappings: the current key (None while a key is expected).
    key: Option<String>,
    /// Index of the next item (sequences) or key (mappings).
    index: usize,
    anchor: usize,
    /// Expanded-node counter when the collection started.
    start: u64,
}

/// An event walk that tracks the dotted path of the current node.
struct Walker<'w> {
    path: String,
    frames: Vec<Frame>,
    /// Nodes as written.
    written: u64,
    /// Nodes after alias expansion.
    expanded: u64,
    anchor_sizes: HashMap<usize, u64>,
    wanted: Option<&'w HashSet<String>>,
    found: HashMap<String, LineCol>,
}

/// Why a walk stopped early.
enum Stop {
    Syntax(String, LineCol),
    TooDeep(LineCol),
    AliasBomb(LineCol),
}

impl<'w> Walker<'w> {
    fn new(wanted: Option<&'w HashSet<String>>) -> Self {
        Walker {
            path: String::new(),
            frames: Vec::new(),
            written: 0,
            expanded: 0,
            anchor_sizes: HashMap::new(),
            wanted,
            found: HashMap::new(),
        }
    }

    /// Set `self.path` to the path of a node that starts now; false when the node is a mapping key.
    fn begin(&mut self) -> bool {
        let Some(f) = self.frames.last() else {
            self.path.clear();
            return true;
        };
        self.path.truncate(f.base);
        if f.map {
            match &f.key {
                None => {
                    self.path.push_str(".?");
                    false
                }
                Some(k) => {
                    if f.base > 0 {
                        self.path.push('.');
                    }
                    let k = k.clone();
                    self.path.push_str(&k);
                    true
                }
            }
        } else {
            let i = f.index;
            self.path.push_str(&format!("[{i}]"));
            true
        }
    }

    /// A node (scalar, alias or whole collection) is complete; `key_text` names it if it was a key.
    fn end_node(&mut self, key_text: Option<&str>) {
        if let Some(f) = self.frames.last_mut() {
            if f.map {
                f.key = match f.key {
                    None => Some(key_text.unwrap_or("?").to_string()),
                    Some(_) => {
                        f.index += 1;
                        None
                    }
                };
            } else {
                f.index += 1;
            }
        }
    }

    fn record(&mut self, at: LineCol) {
        if let Some(w) = self.wanted {
            if w.contains(&self.path) {
                self.found.entry(self.path.clone()).or_insert(at);
            }
        }
    }

    /// Block mappings start where their first key starts; the parser marks them later.
    fn first_key_marks_mapping(&mut self, at: LineCol) {
        let (Some(f), Some(w)) = (self.frames.last(), self.wanted) else {
            return;
        };
        if f.map && f.index == 0 {
            let p = &self.path[..f.base];
            if w.contains(p) {
                self.found.insert(p.to_string(), at);
            }
        }
    }

    fn count(&mut self, n: u64, at: LineCol) -> Result<(), Stop> {
        self.expanded = self.expanded.saturating_add(n);
        if self.expanded.saturating_sub(self.written) > MAX_ALIAS_NODES {
            return Err(Stop::AliasBomb(at));
        }
        Ok(())
    }

    fn walk(&mut self, text: &str) -> Result<(), Stop> {
        let mut parser = Parser::new_from_str(text);
        loop {
            let (event, mark) = parser.next_token().map_err(|e| {
                let at = line_col(e.marker());
                // The scanner caps flow nesting ([[[…) at 255 levels with this message.
                if e.info() == "recursion limit exceeded" {
                    Stop::TooDeep(at)
                } else {
                    Stop::Syntax(e.info().to_string(), at)
                }
            })?;
            let at = line_col(&mark);
            match event {
                Event::StreamEnd => return Ok(()),
                Event::DocumentStart => {
                    self.frames.clear();
                    self.path.clear();
                }
                Event::Scalar(value, _, anchor, _) => {
                    if self.begin() {
                        self.record(at);
                    } else {
                        self.first_key_marks_mapping(at);
                    }
                    self.written += 1;
                    self.count(1, at)?;
                    if anchor > 0 {
                        self.anchor_sizes.insert(anchor, 1);
                    }
                    self.end_node(Some(&value));
                }
                Event::Alias(id) => {
                    if self.begin() {
                        self.record(at);
                    }
                    self.written += 1;
                    let n = self.anchor_sizes.get(&id).copied().unwrap_or(1);
                    self.count(n, at)?;
                    self.end_node(None);
                }
                Event::MappingStart(anchor, _) | Event::SequenceStart(anchor, _) => {
                    let map = matches!(event, Event::MappingStart(..));
                    if self.begin() {
                        self.record(at);
                    }
                    if self.frames.len() >= MAX_DEPTH {
                        return Err(Stop::TooDeep(at));
                    }
                    self.written += 1;
                    let start = self.expanded;
                    self.count(1, at)?;
                    self.frames.push(Frame {
                        base: self.path.len(),
                        map,
                        key: None,
                        index: 0,
                        anchor,
                        start,
                    });
                }
                Event::MappingEnd | Event::SequenceEnd => {
                    if let Some(f) = self.frames.pop() {
                        if f.anchor > 0 {
                            self.anchor_sizes
                                .insert(f.anchor, self.expanded.saturating_sub(f.start));
                        }
                    }
                    self.end_node(None);
                }
                _ => {}
            }
        }
    }
}

/// Check that `text` is well-formed YAML within the nesting and alias-expansion bounds,
/// without building it. Returns the first problem as a located diagnostic of `file`.
pub fn check_bounds(file: &str, text: &str) -> Result<(), crate::LoadError> {
    let mut w = Walker::new(None);
    w.walk(text).map_err(|stop| {
        let d = match stop {
            Stop::Syntax(msg, (l, c)) => Diagnostic::new(
                file,
                "",
                format!("malformed YAML: {msg}"),
                "well-formed YAML (check indentation, quotes and brackets)",
            )
            .at(l, c),
            Stop::TooDeep((l, c)) => Diagnostic::new(
                file,
                w.path.clone(),
                format!("nesting deeper than {MAX_DEPTH} levels"),
                format!("at most {MAX_DEPTH} nested mappings/sequences"),
            )
            .at(l, c),
            Stop::AliasBomb((l, c)) => Diagnostic::new(
                file,
                w.path.clone(),
                format!(
                    "aliases expand to more than {MAX_ALIAS_NODES} extra nodes (an alias bomb?)"
                ),
                format!("aliases (`*name`) that repeat at most {MAX_ALIAS_NODES} nodes in total"),
            )
            .at(l, c),
        };
        d.into()
    })
}

/// Line and column of each of `paths` (dotted, as in diagnostics) in `text`. A path that is not
/// written out (e.g. a field left at its default, or one reached through an alias) falls back to
/// its longest written prefix. Paths not found at all are absent from the result.
pub fn find_positions<'p>(
    text: &str,
    paths: impl IntoIterator<Item = &'p str>,
) -> HashMap<String, LineCol> {
    let paths: Vec<&str> = paths.into_iter().collect();
    let mut wanted = HashSet::new();
    for p in &paths {
        for pre in prefixes(p) {
            wanted.insert(pre.to_string());
        }
    }
    let mut w = Walker::new(Some(&wanted));
    // A text that fails to walk still yields the positions found before the problem.
    let _ = w.walk(text);
    let mut out = HashMap::new();
    for p in paths {
        if let Some(at) = prefixes(p).find_map(|pre| w.found.get(pre)) {
            out.insert(p.to_string(), *at);
        }
    }
    out
}

/// `a.b[2].c`, `a.b[2]`, `a.b`, `a`, `` — longest first.
fn prefixes(path: &str) -> impl Iterator<Item = &str> {
    let cuts = path
        .char_indices()
        .filter(|&(_, c)| c == '.' || c == '[')
        .map(|(i, _)| i)
        .collect::<Vec<_>>();
    std::iter::once(path)
        .chain(cuts.into_iter().rev().map(move |i| &path[..i]))
        .chain(std::iter::once(""))
}

/// Fill in the line and column of every diagnostic that lacks one, from its field path in `text`.
pub fn locate(diagnostics: &mut [Diagnostic], text: &str) {
    let missing: Vec<String> = diagnostics
        .iter()
        .filter(|d| d.line.is_none())
        .map(|d| d.path.clone())
        .collect();
    if missing.is_empty() {
        return;
    }
    let found = find_positions(text, missing.iter().map(String::as_str));
    for d in diagnostics.iter_mut().filter(|d| d.line.is_none()) {
        if let Some(&(l, c)) = found.get(&d.path) {
            d.line = Some(l);
            d.column = Some(c);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "kind: environment\nobjects:\n  - id: a\n    room: kitchen\n  - id: b\n    pose: {x: 1, y: 2}\n";

    #[test]
    fn paths_map_to_the_line_and_column_of_their_value() {
        let found = find_positions(
            TEXT,
            [
                "kind",
                "objects[0].room",
                "objects[1].pose.y",
                "objects[1].size",
            ],
        );
        assert_eq!(found["kind"], (1, 7));
        assert_eq!(found["objects[0].room"], (4, 11));
        assert_eq!(found["objects[1].pose.y"], (6, 21));
        // not written: falls back to the object
        assert_eq!(found["objects[1].size"], (5, 5));
    }

    #[test]
    fn alias_bomb_is_rejected_without_expanding() {
        let mut s = String::from("a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n");
        for i in 1..12 {
            let p = i - 1;
            s.push_str(&format!(
                "a{i}: &a{i} [*a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}, *a{p}]\n"
            ));
        }
        let e = &check_bounds("bomb.yaml", &s).unwrap_err().diagnostics[0];
        assert!(e.message.contains("alias"), "{e}");
        assert!(e.line.is_some());
    }

    #[test]
    fn deep_nesting_is_rejected() {
        let s = format!("{}{}", "[".repeat(200), "]".repeat(200));
        let e = &check_bounds("deep.yaml", &s).unwrap_err().diagnostics[0];
        assert!(e.message.contains("nesting"), "{e}");
        let s = format!("{}{}", "[".repeat(10), "]".repeat(10));
        assert!(check_bounds("ok.yaml", &s).is_ok());
    }
}
