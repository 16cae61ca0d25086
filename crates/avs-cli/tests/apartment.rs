//! The worked example of `docs/environments.md` ("From scratch: a two-room apartment") stays
//! valid against the home knowledge, and the search it shows finds the cereal box.

mod common;

const ENV: &str = "docs/examples/apartment.yaml";
const KNOWLEDGE: &str = "knowledge/home.yaml";

#[test]
fn the_guides_apartment_validates_against_the_home_knowledge() {
    let out = common::avs(&["validate", ENV, "--knowledge", KNOWLEDGE]);
    // The verdict line goes to stderr, the diagnostics (none here) to stdout.
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "{text}");
    assert!(text.contains("1 file(s) valid"), "{text}");
}

#[test]
fn the_guides_apartment_search_finds_the_cereal_box_on_the_counter() {
    let out = common::avs(&[
        "search",
        "--env",
        ENV,
        "--knowledge",
        KNOWLEDGE,
        "--goal",
        "cerealbox",
        "--json",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_str(&text).expect("one JSON summary");
    assert_eq!(v["found"], true, "{v}");
    assert_eq!(v["wrong_report"], false, "{v}");
    // The box is on the counter at (5.9, 3.85).
    let p = &v["reported_pose"];
    let (x, y) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
    assert!((x - 5.9).hypot(y - 3.85) < 1.0, "{v}");
}
