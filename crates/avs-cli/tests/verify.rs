//! `avs verify-bench`, `avs verify train` and `avs validate` on verification scenarios, end to
//! end.

mod common;
use common::avs;

#[test]
fn verify_bench_json_has_the_contract_keys_and_sane_values() {
    let o = avs(&[
        "verify-bench",
        "--scenario",
        "single-sign",
        "--strategy",
        "greedy:0.8",
        "--trials",
        "2",
        "--seed",
        "1",
        "--json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    for key in [
        "precision",
        "recall",
        "path_length_mean",
        "precision_se",
        "recall_se",
        "path_length_se",
        "trials",
        "field_ms_median",
    ] {
        assert!(
            v.get(key).is_some_and(|x| x.is_number()),
            "{key} missing: {v}"
        );
    }
    assert_eq!(v["trials"], 2);
    for key in ["precision", "recall"] {
        let x = v[key].as_f64().unwrap();
        assert!((0.0..=1.0).contains(&x), "{key} {x}");
    }
    // The robot at least drove from the start to the goal (13.5 m apart).
    assert!(v["path_length_mean"].as_f64().unwrap() >= 13.5);
}

#[test]
fn a_bad_strategy_or_scenario_is_rejected_naming_it() {
    let o = avs(&[
        "verify-bench",
        "--scenario",
        "single-sign",
        "--strategy",
        "greedy:1.5",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--strategy"));
    let o = avs(&["verify-bench", "--scenario", "no-such-scenario"]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("no-such-scenario") && err.contains("single-door"),
        "{err}"
    );
}

#[test]
fn validate_accepts_the_shipped_scenarios_and_names_a_bad_field() {
    let mut args = vec!["validate".to_string()];
    for n in ["single-door", "multi-door", "single-sign", "multi-sign"] {
        args.push(format!("domains/verification/{n}.yaml"));
    }
    let o = avs(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));

    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let bad = dir.join("bad.yaml");
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../domains/verification/single-sign.yaml"),
    )
    .unwrap()
    .replace("detector: sign", "detector: sign\nprior: 2");
    std::fs::write(&bad, text).unwrap();
    let path = bad.to_str().unwrap();
    for cmd in [
        vec!["validate", path],
        vec!["verify-bench", "--scenario", path, "--trials", "1"],
    ] {
        let o = avs(&cmd);
        assert_eq!(o.status.code(), Some(1), "{cmd:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        let out = format!("{}{err}", String::from_utf8_lossy(&o.stdout));
        assert!(
            out.contains("bad.yaml") && out.contains("prior"),
            "{cmd:?}: {out}"
        );
    }
}

#[test]
fn verify_train_prints_a_knowledge_sensor_models_block_that_builds() {
    let o = avs(&[
        "verify",
        "train",
        "--detector",
        "door",
        "--strategy",
        "planned-disc",
        "--seed",
        "2",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // A knowledge file's `sensor_models` block, named after the detector.
    #[derive(serde::Deserialize)]
    struct Block {
        sensor_models: Vec<avs_format::verifier::NamedSensorModel>,
    }
    let b: Block = serde_yaml::from_slice(&o.stdout).unwrap();
    assert_eq!(b.sensor_models.len(), 1);
    assert_eq!(b.sensor_models[0].name, "door");
    let m = &b.sensor_models[0].model;
    assert!(matches!(m.kind, avs_verify::sensor::ModelKind::Disc { .. }));
    assert!(m.problems().is_empty());
    avs_verify::sensor::SensorModel::from_spec(m).unwrap();
    let o = avs(&["verify", "train", "--detector", "lamp"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--detector"));
}
