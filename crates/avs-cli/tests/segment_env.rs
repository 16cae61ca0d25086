//! `avs segment` on avs environment files: the shipped office is segmented into its rooms and
//! scored against the environment's own rooms; other kinds and broken environments are
//! errors naming the file.

mod common;
use common::{avs, avs_in};

fn json(args: &[&str]) -> serde_json::Value {
    let o = avs(args);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{args:?}\n{stdout}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_str(&stdout).expect("--json prints JSON")
}

#[test]
fn the_shipped_office_splits_into_its_four_rooms_and_scores_well_against_them() {
    let v = json(&["segment", "domains/environments/office.yaml", "--json"]);
    assert_eq!(v["format"], "environment", "{v:#}");
    assert_eq!(v["rooms"], 4, "{v:#}");
    assert_eq!(v["doors"].as_array().map(Vec::len), Some(3), "{v:#}");
    assert_eq!(v["truth"], "environment", "{v:#}");
    assert_eq!(v["truth_rooms"], 4, "{v:#}");
    for key in [
        "precision_per_room",
        "recall_per_room",
        "precision_pixel",
        "recall_pixel",
    ] {
        let x = v[key].as_f64().unwrap();
        assert!(x > 0.95, "{key} {x}: {v:#}");
    }
    assert!(v["mcc"].as_f64().unwrap() > 0.9, "{v:#}");
    // 120 × 80 cells of 0.1 m.
    assert_eq!(
        (v["width"].clone(), v["height"].clone()),
        (120.into(), 80.into())
    );
}

#[test]
fn a_segmentation_that_misses_the_doors_scores_badly() {
    // Doors of 0.9 m are outside 1.5–2.0 m: no door is found, the floor is one room, and the
    // score shows it.
    let v = json(&[
        "segment",
        "domains/environments/office.yaml",
        "--json",
        "--min-door-width",
        "1.5",
        "--max-door-width",
        "2.0",
    ]);
    assert_eq!(v["rooms"], 1, "{v:#}");
    assert!(v["precision_per_room"].as_f64().unwrap() < 0.6, "{v:#}");
    assert!(v["mcc"].as_f64().unwrap() < 0.5, "{v:#}");
}

#[test]
fn text_output_names_the_truth_and_a_roomless_environment_is_not_scored() {
    let o = avs(&["segment", "domains/environments/office.yaml"]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{stdout}");
    assert!(stdout.contains("office.yaml: 4 rooms, 3 doors"), "{stdout}");
    assert!(
        stdout.contains("truth rooms 4 (the environment's rooms)"),
        "{stdout}"
    );

    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let office = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../domains/environments/office.yaml"
    ))
    .unwrap();
    // Without rooms, doors and objects (they name rooms), the map and robot remain.
    let cut = |s: &str| {
        s[..s.find("\nrooms:").unwrap() + 1].to_string() + &s[s.find("\nrobot:").unwrap() + 1..]
    };
    std::fs::write(dir.join("bare.yaml"), cut(&office)).unwrap();
    let o = avs_in(dir, &["segment", "bare.yaml"]);
    let (stdout, stderr) = (
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr),
    );
    assert_eq!(o.status.code(), Some(0), "{stdout}\n{stderr}");
    assert!(stdout.contains("bare.yaml: 4 rooms"), "{stdout}");
    assert!(!stdout.contains("truth rooms"), "{stdout}");
    assert!(
        stdout.contains("note: the environment has no rooms: not scored"),
        "{stdout}"
    );
}

#[test]
fn other_kinds_and_broken_environments_exit_1_naming_the_file() {
    let o = avs(&["segment", "knowledge/office.yaml"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("knowledge/office.yaml: kind: knowledge"),
        "{err}"
    );
    assert!(err.contains("expected an environment"), "{err}");

    // The checks of `avs validate`: a start inside a wall, with its line.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let office = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../domains/environments/office.yaml"
    ))
    .unwrap()
    .replace(
        "start: { x: 1.0, y: 1.2, yaw_deg: 0 }",
        "start: { x: 0.05, y: 0.05, yaw_deg: 0 }",
    );
    std::fs::write(dir.join("walled_in.yaml"), office).unwrap();
    let o = avs_in(dir, &["segment", "walled_in.yaml"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("walled_in.yaml:"), "{err}");
    assert!(err.contains("robot.start"), "{err}");
}
