//! The scenario file's JSON Schema (`avs schema scenario`) against an independent validator
//! (the `jsonschema` crate): it accepts every plan-trace scenario and rejects broken ones; the
//! crate's own check agrees.

use avs_format::scenario::check;
use avs_format::schema::schema_json;
use avs_format::FileKind;
use std::path::{Path, PathBuf};

fn scenario_files() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/plan_traces");
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("tests/plan_traces")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "yaml"))
        .collect();
    v.sort();
    v
}

fn as_json(yaml: &str) -> serde_json::Value {
    let v: serde_yaml::Value = serde_yaml::from_str(yaml).expect("YAML");
    serde_json::to_value(v).expect("JSON")
}

fn validator() -> jsonschema::Validator {
    let schema: serde_json::Value =
        serde_json::from_str(&schema_json(FileKind::Scenario).expect("a scenario schema"))
            .expect("JSON");
    jsonschema::validator_for(&schema).expect("a valid JSON Schema")
}

#[test]
fn the_schema_and_the_check_accept_every_plan_trace_scenario() {
    let v = validator();
    let files = scenario_files();
    assert!(files.len() >= 6, "{files:?}");
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        let errors: Vec<String> = v
            .iter_errors(&as_json(&text))
            .map(|e| e.to_string())
            .collect();
        assert!(errors.is_empty(), "{}: {errors:?}", f.display());
        let ds = check(&f.display().to_string(), &text);
        assert!(ds.is_empty(), "{}: {ds:?}", f.display());
    }
}

#[test]
fn the_schema_rejects_a_missing_goal_a_misspelt_expectation_and_a_wrong_seed() {
    let v = validator();
    let text = std::fs::read_to_string(&scenario_files()[0]).unwrap();
    let good = as_json(&text);
    assert!(v.is_valid(&good));
    let edit = |f: &dyn Fn(&mut serde_json::Value)| {
        let mut d = good.clone();
        f(&mut d);
        d
    };
    let cases = [
        (
            "no goal",
            edit(&|d| {
                d.as_object_mut().unwrap().remove("goal");
            }),
        ),
        (
            "a misspelt expectation",
            edit(&|d| d["expect"]["foundd"] = serde_json::json!(true)),
        ),
        (
            "a seed that is no number",
            edit(&|d| d["seed"] = serde_json::json!("one")),
        ),
        (
            "another kind",
            edit(&|d| d["kind"] = serde_json::json!("environment")),
        ),
    ];
    for (what, d) in cases {
        assert!(!v.is_valid(&d), "accepted {what}");
    }
}
