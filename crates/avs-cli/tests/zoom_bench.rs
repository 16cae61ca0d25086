//! `avs zoom-bench`, end to end: the four charts are written and the JSON has the four figures'
//! series.

mod common;
use common::avs;

#[test]
fn zoom_bench_writes_four_charts_and_prints_the_four_series() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("charts");
    let out = dir.to_str().unwrap();
    let o = avs(&[
        "zoom-bench",
        "--seed",
        "2",
        "--images-per-position",
        "2",
        "--out",
        out,
        "--json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["seed"], 2);
    assert_eq!(v["images_per_position"], 2);
    for key in [
        "fig7_false_hypotheses",
        "fig8_correct_strongest",
        "fig9_distance",
        "fig10_better_estimate",
    ] {
        let series = v[key]
            .as_array()
            .unwrap_or_else(|| panic!("{key} missing: {v}"));
        assert_eq!(series.len(), 8, "{key}");
        assert!(series.iter().all(|x| x["distance"].is_number()), "{key}");
    }
    for name in [
        "fig7_false_hypotheses.svg",
        "fig8_correct_strongest.svg",
        "fig9_distance.svg",
        "fig10_better_estimate.svg",
    ] {
        let svg = std::fs::read_to_string(dir.join(name)).unwrap();
        assert!(svg.contains("<svg"), "{name}");
    }
    // Without --json: the tables.
    let o = avs(&["zoom-bench", "--images-per-position", "1", "--out", out]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("Fig. 7") && text.contains("Fig. 10"),
        "{text}"
    );
    // A bad count is named.
    let o = avs(&["zoom-bench", "--images-per-position", "0", "--out", out]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--images-per-position"));
}
