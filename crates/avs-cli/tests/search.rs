//! `avs search`: the SVG picture of a run and the fault-injection flags.

use std::process::Command;

fn avs(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_avs"))
        .args(args)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .output()
        .expect("the avs binary runs")
}

const OFFICE: [&str; 8] = [
    "search",
    "--env",
    "domains/environments/office.yaml",
    "--knowledge",
    "knowledge/office.yaml",
    "--domain",
    "domains/object_search.yaml",
    "--json",
];

#[test]
fn svg_of_a_search_draws_the_trail_and_the_reported_position() {
    let dir = std::env::temp_dir().join(format!("avs-search-svg-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let svg = dir.join("run.svg");
    let mut args = OFFICE.to_vec();
    let svg_s = svg.to_str().unwrap();
    args.extend(["--goal", "cerealbox", "--svg", svg_s]);
    let out = avs(&args);
    let summary: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON summary");
    let pic = std::fs::read_to_string(&svg).expect("the SVG was written");
    assert!(pic.starts_with("<svg"), "{}", &pic[..pic.len().min(80)]);
    assert!(pic.contains("robot trail"));
    // The trail is as long as the path driven: count its points (0.25 m apart at most).
    let points = pic
        .split("points=\"")
        .nth(1)
        .and_then(|s| s.split('"').next())
        .unwrap_or("")
        .split_whitespace()
        .count();
    let path = summary["path_length"].as_f64().unwrap();
    assert!(
        points as f64 >= path / 0.25,
        "{points} trail points for {path:.1} m"
    );
    if summary["reported_pose"].is_array() {
        assert!(pic.contains("reported cerealbox"));
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn fault_flags_are_checked_and_name_what_is_expected() {
    let mut args = OFFICE.to_vec();
    args.extend(["--goal", "cerealbox", "--close-door", "no_such_door@3"]);
    let out = avs(&args);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("door_events[0].door") && err.contains("door_kitchen"),
        "stderr: {err}"
    );
    let mut args = OFFICE.to_vec();
    args.extend(["--goal", "cerealbox", "--close-door", "door_kitchen"]);
    let err = String::from_utf8_lossy(&avs(&args).stderr).to_string();
    assert!(err.contains("NAME@METRES"), "stderr: {err}");
    let mut args = OFFICE.to_vec();
    args.extend(["--goal", "cerealbox", "--failure-rate", "1.5"]);
    let err = String::from_utf8_lossy(&avs(&args).stderr).to_string();
    assert!(err.contains("--failure-rate 1.5"), "stderr: {err}");
}

#[test]
fn a_door_closing_mid_run_ends_in_a_verdict() {
    // The kitchen door shuts after 5 m, before the robot reaches the kitchen: the search ends
    // (found elsewhere is impossible: the only cerealbox is in the kitchen) with a reason.
    let mut args = OFFICE.to_vec();
    args.extend(["--goal", "cerealbox", "--close-door", "door_kitchen@5"]);
    let out = avs(&args);
    let summary: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON summary");
    assert_eq!(summary["found"], false, "{summary:#}");
    assert!(!summary["reason"].as_str().unwrap().is_empty());
}
