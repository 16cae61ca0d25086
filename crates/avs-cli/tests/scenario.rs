//! `avs scenario FILE... [--seed N,...] [--json]`: per-property PASS/FAIL from any directory,
//! the JSON contract `{"scenarios": [{"file", "seed", "properties": [{"name", "pass",
//! "detail"}]}]}`, and the
//! exit status (0 all hold, 3 one fails, 1 a file that cannot be run).

mod common;
use common::avs_in;

use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn a_scenario_copied_elsewhere_runs_from_there_and_passes_with_exit_0() {
    // The file's paths are relative to the repository; neither the file's folder nor the
    // current directory has them.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let file = dir.join("stapler.yaml");
    std::fs::copy(
        repo().join("tests/plan_traces/fig3d_office_stapler.yaml"),
        &file,
    )
    .unwrap();
    let out = avs_in(dir, &["scenario", "stapler.yaml", "--json"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_str(&stdout).expect("--json prints JSON");
    let sc = &v["scenarios"][0];
    assert_eq!(sc["file"], "stapler.yaml");
    let props = sc["properties"].as_array().unwrap();
    assert!(props.len() >= 3, "{v:#}");
    for p in props {
        assert_eq!(p["pass"], true, "{p:#}");
        assert!(p["name"].is_string() && p["detail"].is_string(), "{p:#}");
    }
    assert!(props.iter().any(|p| p["name"] == "expect.found"), "{v:#}");
    assert!(
        props.iter().any(|p| p["name"] == "no_wrong_report"),
        "{v:#}"
    );
}

#[test]
fn seed_runs_each_file_once_per_seed_and_names_the_seed() {
    let file = repo().join("tests/plan_traces/fig3d_office_stapler.yaml");
    let out = avs_in(
        &repo(),
        &[
            "scenario",
            file.to_str().unwrap(),
            "--seed",
            "2,3",
            "--json",
        ],
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let v: serde_json::Value = serde_json::from_str(&stdout).expect("--json prints JSON");
    let runs = v["scenarios"].as_array().unwrap();
    let seeds: Vec<u64> = runs.iter().map(|r| r["seed"].as_u64().unwrap()).collect();
    assert_eq!(seeds, [2, 3], "{v:#}");
    assert!(runs.iter().all(|r| r["file"] == runs[0]["file"]), "{v:#}");
    // Without --seed the file's own seed is reported.
    let out = avs_in(&repo(), &["scenario", file.to_str().unwrap(), "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["scenarios"][0]["seed"], 1, "{v:#}");
}

#[test]
fn a_failing_property_prints_fail_and_exits_3() {
    // The stapler run with one more expectation it cannot meet.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let text = std::fs::read_to_string(repo().join("tests/plan_traces/fig3d_office_stapler.yaml"))
        .unwrap()
        .replace(
            "  found_within_m: ",
            "  min_plans: 1000\n  found_within_m: ",
        );
    let file = dir.join("too_many_plans.yaml");
    std::fs::write(&file, text).unwrap();
    let out = avs_in(&repo(), &["scenario", file.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(3), "{stdout}");
    assert!(stdout.contains("FAIL  expect.min_plans"), "{stdout}");
    assert!(stdout.contains("PASS  expect.found"), "{stdout}");
}

#[test]
fn a_scenario_that_cannot_be_run_exits_1_naming_the_file_and_field() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let text = std::fs::read_to_string(repo().join("tests/plan_traces/fig3d_office_stapler.yaml"))
        .unwrap()
        .replace(
            "environment: domains/environments/office.yaml",
            "environment: nowhere/office.yaml",
        );
    assert!(text.contains("nowhere/office.yaml"), "the edit applies");
    let file = dir.join("nowhere.yaml");
    std::fs::write(&file, text).unwrap();
    let out = avs_in(dir, &["scenario", "nowhere.yaml"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("nowhere.yaml") && stderr.contains("environment"),
        "{stderr}"
    );
}
