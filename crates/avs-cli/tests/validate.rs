//! `avs validate` and `avs schema` end to end: the corpus in `tests/validate/` (every malformed
//! file rejected with its expected message and exit status, every good file accepted) and the
//! shipped domains and knowledge files accepted.

mod common;
use common::avs_in as avs;

use std::path::{Path, PathBuf};
use std::process::Output;

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn corpus() -> PathBuf {
    workspace().join("tests/validate")
}

fn text(o: &Output) -> String {
    format!(
        "status {:?}\n--- stdout\n{}--- stderr\n{}",
        o.status.code(),
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

struct Expect {
    exit: i32,
    args: Vec<String>,
    contains: Vec<String>,
}

fn read_expect(path: &Path) -> Expect {
    let s = std::fs::read_to_string(path).expect("read .expect");
    let mut e = Expect {
        exit: -1,
        args: Vec::new(),
        contains: Vec::new(),
    };
    for line in s.lines() {
        if let Some(v) = line.strip_prefix("exit: ") {
            e.exit = v.trim().parse().expect("exit status");
        } else if let Some(v) = line.strip_prefix("args: ") {
            e.args = v.split_whitespace().map(String::from).collect();
        } else if let Some(v) = line.strip_prefix("contains: ") {
            e.contains.push(v.to_string());
        }
    }
    assert!(e.exit >= 0, "{}: no `exit:` line", path.display());
    assert!(
        !e.contains.is_empty(),
        "{}: no `contains:` line",
        path.display()
    );
    e
}

fn sorted_files(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("read corpus folder")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == ext))
        .collect();
    v.sort();
    v
}

#[test]
fn every_malformed_file_is_rejected_with_its_expected_message() {
    let bad = corpus().join("bad");
    let files = sorted_files(&bad, "yaml");
    assert!(
        files.len() >= 20,
        "only {} malformed files in the corpus",
        files.len()
    );
    let mut failures = Vec::new();
    for f in &files {
        let name = f.file_stem().unwrap().to_string_lossy().into_owned();
        let exp_path = bad.join(format!("{name}.expect"));
        assert!(exp_path.is_file(), "{} has no .expect", f.display());
        let e = read_expect(&exp_path);
        let rel = format!("bad/{name}.yaml");
        let mut args: Vec<&str> = vec!["validate"];
        args.extend(e.args.iter().map(String::as_str));
        args.push(&rel);
        let o = avs(&corpus(), &args);
        let out = String::from_utf8_lossy(&o.stdout);
        let missing: Vec<&String> = e
            .contains
            .iter()
            .filter(|c| !out.contains(c.as_str()))
            .collect();
        if o.status.code() != Some(e.exit) || !missing.is_empty() {
            failures.push(format!(
                "{name}: expected exit {} and {missing:?}\n{}",
                e.exit,
                text(&o)
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn every_expect_file_has_its_malformed_file() {
    let bad = corpus().join("bad");
    for e in sorted_files(&bad, "expect") {
        assert!(
            e.with_extension("yaml").is_file(),
            "{} has no .yaml",
            e.display()
        );
    }
}

#[test]
fn good_corpus_files_are_accepted_and_cross_checked_against_their_knowledge() {
    let o = avs(&corpus(), &["validate", "good"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(o.stdout.is_empty(), "{}", text(&o));
    // An environment naming a class the knowledge file lacks is rejected only with the knowledge.
    let o = avs(&corpus(), &["validate", "bad/unknown_class.yaml"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let o = avs(
        &corpus(),
        &["validate", "good/knowledge.yaml", "bad/unknown_class.yaml"],
    );
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
}

/// The files that ship with avs: every `domains/**/*.yaml` and `knowledge/*.yaml`.
fn shipped() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(rd) = std::fs::read_dir(dir) else {
            return;
        };
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "yaml") {
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    walk(&workspace().join("domains"), &mut out);
    walk(&workspace().join("knowledge"), &mut out);
    out.sort();
    out
}

#[test]
fn shipped_domains_environments_and_knowledge_are_accepted() {
    let files = shipped();
    assert!(
        files
            .iter()
            .any(|f| f.ends_with("domains/environments/office.yaml")),
        "the default environment is not shipped: {files:?}"
    );
    let args: Vec<String> = std::iter::once("validate".to_string())
        .chain(files.iter().map(|f| f.display().to_string()))
        .collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = avs(&workspace(), &args);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    // Each shipped environment `X.yaml` is also cross-checked against `knowledge/X.yaml`.
    let mut paired = 0;
    for env in files
        .iter()
        .filter(|f| f.parent().is_some_and(|p| p.ends_with("environments")))
    {
        let k = workspace().join("knowledge").join(env.file_name().unwrap());
        if k.is_file() {
            let (k, env) = (k.display().to_string(), env.display().to_string());
            let o = avs(&workspace(), &["validate", "--knowledge", &k, &env]);
            assert_eq!(o.status.code(), Some(0), "{}", text(&o));
            paired += 1;
        }
    }
    assert!(
        paired >= 1,
        "no environment has a knowledge file of the same name"
    );
}

#[test]
fn several_files_report_every_problem_and_exit_1() {
    let o = avs(
        &corpus(),
        &[
            "validate",
            "good/two_rooms.yaml",
            "bad/unknown_room.yaml",
            "bad/nan_pose.yaml",
        ],
    );
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("bad/unknown_room.yaml:"), "{}", text(&o));
    assert!(out.contains("bad/nan_pose.yaml:"), "{}", text(&o));
    assert!(!out.contains("good/two_rooms.yaml"), "{}", text(&o));
}

#[test]
fn usage_errors_exit_2_and_a_missing_file_exits_1() {
    let o = avs(&corpus(), &["validate"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    // A file that does not exist is invalid input, as the README's conventions say.
    let o = avs(&corpus(), &["validate", "no/such/file.yaml"]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let o = avs(&corpus(), &["schema", "planet"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
}

#[test]
fn json_output_gives_one_diagnostic_object_per_line() {
    let o = avs(
        &corpus(),
        &["validate", "--json", "bad/duplicate_room_name.yaml"],
    );
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    let lines: Vec<serde_json::Value> = out
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON object per line"))
        .collect();
    assert!(!lines.is_empty());
    assert_eq!(lines[0]["path"], "rooms[1].name");
    assert_eq!(lines[0]["line"], 18);
}

#[test]
fn schemas_describe_environment_knowledge_and_scenario_files() {
    let o = avs(&corpus(), &["schema", "environment"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON schema");
    for field in ["kind", "map", "rooms", "doors", "objects", "robot"] {
        assert!(s["properties"].get(field).is_some(), "no `{field}` in {s}");
    }
    let o = avs(&corpus(), &["schema", "knowledge"]);
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON schema");
    assert!(s["properties"].get("object_classes").is_some());
    let o = avs(&corpus(), &["schema", "scenario"]);
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON schema");
    let req: Vec<&str> = s["required"]
        .as_array()
        .expect("required fields")
        .iter()
        .filter_map(|v| v.as_str())
        .collect();
    for f in ["kind", "environment", "goal", "seed", "expect"] {
        assert!(req.contains(&f), "{f} not required: {req:?}");
    }
    assert!(s["definitions"]["Expect"]["properties"]
        .get("never_searched_in")
        .is_some());
}

#[test]
fn domain_schema_requires_the_parts_of_a_domain_and_the_kind_domain() {
    let o = avs(&corpus(), &["schema", "domain"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON schema");
    let req: Vec<&str> = s["required"]
        .as_array()
        .expect("required fields")
        .iter()
        .filter_map(|v| v.as_str())
        .collect();
    for f in ["kind", "name", "types", "variables", "operators"] {
        assert!(req.contains(&f), "{f} not required: {req:?}");
    }
    assert_eq!(s["properties"]["kind"]["enum"][0], "domain");
}

/// Issue 19: without a knowledge file, an environment's classes and categories went unchecked
/// in silence; validate now says so, and says nothing when it can check them.
#[test]
fn validate_says_when_it_skips_class_checks_for_want_of_knowledge() {
    let root = workspace();
    let alone = avs(&root, &["validate", "domains/environments/office.yaml"]);
    assert_eq!(alone.status.code(), Some(0), "{}", text(&alone));
    let err = String::from_utf8_lossy(&alone.stderr);
    assert!(
        err.contains("not checked") && err.contains("--knowledge"),
        "{err}"
    );
    let with = avs(
        &root,
        &[
            "validate",
            "domains/environments/office.yaml",
            "--knowledge",
            "knowledge/office.yaml",
        ],
    );
    assert_eq!(with.status.code(), Some(0), "{}", text(&with));
    assert!(!String::from_utf8_lossy(&with.stderr).contains("not checked"));
}
