//! `avs examples DIR`: every printed command runs on the written files and exits 0 with the
//! output its example promises; existing files are not overwritten without `--force`.

mod common;
use common::avs_in;

use std::path::Path;
use std::process::Output;

fn text(o: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// The `$ avs …` lines of `avs examples`' output, each once, in order.
fn printed_commands(stdout: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for line in stdout.lines() {
        if let Some(c) = line.trim_start().strip_prefix("$ ") {
            if !out.iter().any(|o| o == c) {
                out.push(c.to_string());
            }
        }
    }
    out
}

/// What each command's output must show (beyond exit 0).
fn check_output(cmd: &str, dir: &Path, stdout: &str, stderr: &str) {
    let words: Vec<&str> = cmd.split_whitespace().collect();
    let ctx = format!("{cmd}\nstdout:\n{stdout}\nstderr:\n{stderr}");
    match words[1] {
        "validate" => assert!(stderr.contains("5 file(s) valid"), "{ctx}"),
        "search" | "run" => assert!(stdout.contains("found:                true"), "{ctx}"),
        "segment" if cmd.contains("office.yaml") => {
            assert!(stdout.contains(": 4 rooms"), "{ctx}");
            assert!(
                stdout.contains("truth rooms 4 (the environment's rooms)"),
                "{ctx}"
            );
        }
        "segment" => {
            assert!(stdout.contains(": 3 rooms"), "{ctx}");
            assert!(
                stdout.contains("truth rooms 3 (the environment's rooms)"),
                "{ctx}"
            );
            let svg = std::fs::read_to_string(dir.join("flat_rooms.svg")).expect("--svg wrote");
            assert!(svg.starts_with("<svg"), "{ctx}");
        }
        "render" => {
            let svg = std::fs::read_to_string(dir.join("flat.svg")).expect("--svg wrote");
            assert!(svg.contains("<svg"), "{ctx}");
        }
        "scenario" => {
            assert!(stdout.contains("PASS  expect.found"), "{ctx}");
            assert!(!stdout.contains("FAIL"), "{ctx}");
        }
        "infer" => {
            // MAR, 3 variables, then per variable its cardinality and marginal.
            let nums: Vec<f64> = stdout
                .split_whitespace()
                .skip(2)
                .map(|w| w.parse().unwrap())
                .collect();
            assert_eq!(nums.len(), 9, "{ctx}");
            // Seeing a counter makes room B likely a kitchen (prior 0.3; exactly 0.819).
            let b_kitchen = nums[5];
            assert!((b_kitchen - 0.8189).abs() < 1e-3, "{ctx}");
            assert_eq!(nums[8], 1.0, "the evidence is clamped: {ctx}");
        }
        "plan" => {
            assert!(stdout.contains("(drive corridor kitchen)"), "{ctx}");
            assert!(stdout.contains("; cost = 6 (general cost)"), "{ctx}");
        }
        "pomdp" if words[2] == "solve" => {
            let value = |key: &str| -> f64 {
                let line = stdout.lines().find(|l| l.starts_with(key)).expect(key);
                line[key.len()..].trim().parse().unwrap()
            };
            let (lo, up) = (value("lower"), value("upper"));
            assert!(lo <= up + 1e-9 && up - lo <= 1e-2, "{ctx}");
            // Looking first and reporting right earns more than guessing (0.5·20 − 0.5·50 < 0).
            assert!(lo > 0.0, "{ctx}");
            assert!(stdout.contains("first       look_"), "{ctx}");
        }
        "pomdp" => assert!(stdout.contains("runs        200 (seed 1"), "{ctx}"),
        other => panic!("no check for `avs {other}`: {ctx}"),
    }
}

#[test]
fn every_printed_command_runs_on_the_written_files_and_exits_0() {
    let tmp = tempfile::tempdir().unwrap();
    let root = tmp.path();
    let o = avs_in(root, &["examples", "ex"]);
    let (stdout, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(0), "{stdout}\n{stderr}");
    let dir = root.join("ex");
    for name in [
        "office.yaml",
        "office_knowledge.yaml",
        "object_search.yaml",
        "flat.yaml",
        "scenario.yaml",
        "rooms.uai",
        "rooms.uai.evid",
        "find_domain.pddl",
        "find_problem.pddl",
        "view_cones.pomdp",
    ] {
        assert!(dir.join(name).is_file(), "{name} not written:\n{stdout}");
        assert!(
            stdout.lines().any(|l| l == format!("ex/{name}")),
            "{name}:\n{stdout}"
        );
    }
    let commands = printed_commands(&stdout);
    // One command per tool at least: validate, search (2), segment (2), render, scenario,
    // infer, plan, pomdp solve and simulate, run.
    assert!(commands.len() >= 12, "{commands:#?}");
    for tool in [
        "validate", "search", "segment", "scenario", "infer", "plan", "pomdp", "run",
    ] {
        assert!(
            commands
                .iter()
                .any(|c| c.starts_with(&format!("avs {tool}"))),
            "no `avs {tool}` among {commands:#?}"
        );
    }
    for cmd in &commands {
        let words: Vec<&str> = cmd.split_whitespace().collect();
        assert_eq!(words[0], "avs", "{cmd}");
        let o = avs_in(root, &words[1..]);
        let (out, err) = text(&o);
        assert_eq!(o.status.code(), Some(0), "{cmd}\n{out}\n{err}");
        check_output(cmd, &dir, &out, &err);
    }
}

#[test]
fn existing_files_are_kept_unless_force_is_given() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let d = dir.to_str().unwrap();
    let o = avs_in(dir, &["examples", d]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o).1);
    let mine = dir.join("rooms.uai");
    std::fs::write(&mine, "my own model\n").unwrap();

    let o = avs_in(dir, &["examples", d]);
    let (_, err) = text(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains(&mine.display().to_string()), "{err}");
    assert!(err.contains("already exist"), "{err}");
    assert!(err.contains("--force"), "{err}");
    assert_eq!(
        std::fs::read_to_string(&mine).unwrap(),
        "my own model\n",
        "a refused run wrote nothing"
    );

    let o = avs_in(dir, &["examples", d, "--force"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o).1);
    assert!(std::fs::read_to_string(&mine).unwrap().contains("MARKOV"));
}

#[test]
fn only_the_clashing_file_is_named_and_a_fresh_subfolder_is_created() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("view_cones.pomdp"), "mine\n").unwrap();
    let o = avs_in(dir, &["examples", "."]);
    let (_, err) = text(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("view_cones.pomdp: already exists"), "{err}");
    assert!(!err.contains("office.yaml"), "{err}");
    assert!(!dir.join("office.yaml").exists(), "nothing written");

    let o = avs_in(dir, &["examples", "a/b"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o).1);
    assert!(dir.join("a/b/flat.yaml").is_file());
}

#[test]
fn usage_errors_exit_2() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for args in [vec!["examples"], vec!["examples", "x", "--no-such-flag"]] {
        let o = avs_in(dir, &args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", text(&o).1);
    }
    assert!(!dir.join("x").exists(), "a usage error writes nothing");
}
