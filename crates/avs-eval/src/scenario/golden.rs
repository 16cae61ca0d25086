//! Judging a scenario run: the verdict on its properties (with `known_failure` notes) and the
//! comparison of its text trace with the golden file `<name>.trace` beside the scenario.

use avs_format::scenario::Scenario;
use std::path::Path;

/// Why a scenario fails: a report for a person, with what to do.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct Failure(pub String);

/// A scenario that did not fail.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// Every property holds.
    Pass,
    /// A property fails, as its `known_failure` note says: the NOTICE to print.
    KnownFailure(String),
}

/// The command that rewrites the golden traces.
pub const BLESS_HINT: &str = "AVS_BLESS=1 cargo test -p avs-eval --test plan_traces";

/// The last `n` lines of `text`.
pub fn tail(text: &str, n: usize) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let from = lines.len().saturating_sub(n);
    lines[from..].join("\n")
}

/// The verdict on a scenario's failed properties `bad` (`text`: its trace, for context).
pub fn verdict(
    name: &str,
    file: &Path,
    sc: &Scenario,
    bad: &[String],
    text: &str,
) -> Result<Verdict, Failure> {
    match (&sc.known_failure, bad.is_empty()) {
        (None, true) => Ok(Verdict::Pass),
        (None, false) => Err(Failure(format!(
            "{name} ({}): the paper's properties do not hold:\n  - {}\nthe paper: {}\ntrace \
             tail:\n{}",
            sc.run,
            bad.join("\n  - "),
            sc.description.trim(),
            tail(text, 30)
        ))),
        (Some(why), false) => Ok(Verdict::KnownFailure(format!(
            "NOTICE: known failure of plan-trace scenario {name} ({}): {}\n  - {}\ntrace \
             tail:\n{}\n",
            sc.run,
            why.trim(),
            bad.join("\n  - "),
            tail(text, 12)
        ))),
        (Some(why), true) => Err(Failure(format!(
            "{name} ({}): marked known_failure ({}) but every property now holds; remove \
             `known_failure` from {}",
            sc.run,
            why.trim(),
            file.display()
        ))),
    }
}

/// The first differing line with a few lines of context on both sides.
pub fn short_diff(expected: &str, actual: &str) -> String {
    let e: Vec<&str> = expected.lines().collect();
    let a: Vec<&str> = actual.lines().collect();
    let i = e
        .iter()
        .zip(&a)
        .position(|(x, y)| x != y)
        .unwrap_or(e.len().min(a.len()));
    let lo = i.saturating_sub(3);
    let mut s = format!(
        "first difference at line {} (golden has {} lines, this run {}):\n",
        i + 1,
        e.len(),
        a.len()
    );
    for (label, v) in [("golden", &e), ("actual", &a)] {
        s.push_str(&format!("--- {label}\n"));
        for (k, l) in v.iter().enumerate().skip(lo).take(i + 4 - lo) {
            let mark = if k == i { '>' } else { ' ' };
            s.push_str(&format!("{mark}{:5} | {l}\n", k + 1));
        }
    }
    s
}

/// Compare `text` with the golden file `dir/<name>.trace`, or with `bless` write it (the
/// returned note says so). An error says what differs and what to do.
pub fn check_golden(
    dir: &Path,
    name: &str,
    text: &str,
    bless: bool,
) -> Result<Option<String>, Failure> {
    let path = dir.join(format!("{name}.trace"));
    if bless {
        std::fs::write(&path, text)
            .map_err(|e| Failure(format!("cannot write {}: {e}", path.display())))?;
        return Ok(Some(format!(
            "AVS_BLESS=1: wrote golden trace {}\n",
            path.display()
        )));
    }
    match std::fs::read_to_string(&path) {
        Err(_) => Err(Failure(format!(
            "golden trace {} is missing; check the trace, then write it with `{BLESS_HINT}`",
            path.display()
        ))),
        Ok(golden) if golden == text => Ok(None),
        Ok(golden) => Err(Failure(format!(
            "the trace differs from the golden trace {}; if the change is intended, re-bless \
             with `{BLESS_HINT}`\n{}",
            path.display(),
            short_diff(&golden, text)
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = "kind: scenario
run: Fig. 3(a)
description: test
environment: e.yaml
knowledge: k.yaml
domain: d.yaml
goal: cerealbox
seed: 1
expect: { found: true }
";

    #[test]
    fn known_failures_print_a_notice_and_fail_once_they_pass() {
        let p = Path::new("verdict.yaml");
        let mut sc: Scenario = avs_format::load_yaml_str("verdict.yaml", GOOD).unwrap();
        let bad = vec!["expect.found: true, but nothing was reported".to_string()];
        // Without a note: a failed property fails, all properties holding passes.
        let e = verdict("v", p, &sc, &bad, "line1\ngave up").unwrap_err().0;
        assert!(e.contains("expect.found") && e.contains("gave up"), "{e}");
        assert_eq!(verdict("v", p, &sc, &[], "t"), Ok(Verdict::Pass));
        // With a note: a failed property is a NOTICE, a pass is an error asking to remove it.
        sc.known_failure = Some("the agent gives up".into());
        let Ok(Verdict::KnownFailure(n)) = verdict("v", p, &sc, &bad, "t") else {
            panic!("a notice");
        };
        assert!(
            n.starts_with("NOTICE") && n.contains("the agent gives up"),
            "{n}"
        );
        let e = verdict("v", p, &sc, &[], "t").unwrap_err().0;
        assert!(e.contains("remove `known_failure`"), "{e}");
    }

    #[test]
    fn golden_mismatch_shows_the_first_differing_line_and_missing_golden_says_how_to_bless() {
        let d = short_diff("a\nb\nc\nd\n", "a\nb\nX\nd\n");
        assert!(d.contains("line 3"), "{d}");
        assert!(d.contains(">    3 | c") && d.contains(">    3 | X"), "{d}");
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        let e = check_golden(dir, "no_such_scenario", "x\n", false)
            .unwrap_err()
            .0;
        assert!(e.contains("missing") && e.contains("AVS_BLESS=1"), "{e}");
        // Blessing writes it; then the same text passes and another fails with a diff.
        assert!(check_golden(dir, "s", "a\nb\n", true).unwrap().is_some());
        assert_eq!(check_golden(dir, "s", "a\nb\n", false), Ok(None));
        let e = check_golden(dir, "s", "a\nc\n", false).unwrap_err().0;
        assert!(e.contains("line 2"), "{e}");
    }
}
