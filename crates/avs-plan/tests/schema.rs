//! The domain file's JSON Schema (`avs schema domain`) against an independent validator
//! (the `jsonschema` crate): it accepts every shipped domain file and rejects broken ones.

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Every `kind: domain` YAML file under `domains/`.
fn shipped_domains() -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(root().join("domains")).expect("domains/") {
        let p = e.expect("entry").path();
        let is_domain = p.extension().is_some_and(|x| x == "yaml")
            && std::fs::read_to_string(&p).is_ok_and(|t| t.lines().any(|l| l == "kind: domain"));
        if is_domain {
            out.push(p);
        }
    }
    out
}

fn as_json(yaml: &str) -> serde_json::Value {
    let v: serde_yaml::Value = serde_yaml::from_str(yaml).expect("YAML");
    serde_json::to_value(v).expect("JSON")
}

fn validator() -> jsonschema::Validator {
    let schema: serde_json::Value =
        serde_json::from_str(&avs_plan::domain::schema_json()).expect("the schema is JSON");
    jsonschema::validator_for(&schema).expect("the schema is a valid JSON Schema")
}

#[test]
fn the_schema_accepts_every_shipped_domain_file() {
    let v = validator();
    let files = shipped_domains();
    assert!(!files.is_empty(), "no domain files found");
    for f in files {
        let doc = as_json(&std::fs::read_to_string(&f).unwrap());
        let errors: Vec<String> = v.iter_errors(&doc).map(|e| e.to_string()).collect();
        assert!(errors.is_empty(), "{}: {errors:?}", f.display());
        // And the loader agrees.
        avs_plan::domain::Domain::load(&f).expect("the shipped domain loads");
    }
}

#[test]
fn the_schema_rejects_a_missing_part_a_wrong_type_an_unknown_field_and_another_kind() {
    let v = validator();
    let text = std::fs::read_to_string(root().join("domains/object_search.yaml")).unwrap();
    let good = as_json(&text);
    assert!(v.is_valid(&good));
    let broken = |f: &dyn Fn(&mut serde_json::Value)| {
        let mut d = good.clone();
        f(&mut d);
        d
    };
    let no_operators = broken(&|d| {
        d.as_object_mut().unwrap().remove("operators");
    });
    let types_not_a_list = broken(&|d| d["types"] = serde_json::json!("place"));
    let unknown_field = broken(&|d| d["operatorz"] = serde_json::json!([]));
    let other_kind = broken(&|d| d["kind"] = serde_json::json!("knowledge"));
    let cost_not_a_quantity = broken(&|d| d["operators"][0]["cost"] = serde_json::json!([1]));
    for (what, d) in [
        ("no operators", no_operators),
        ("types not a list", types_not_a_list),
        ("an unknown field", unknown_field),
        ("another kind", other_kind),
        (
            "a cost that is neither number nor expression",
            cost_not_a_quantity,
        ),
    ] {
        assert!(!v.is_valid(&d), "accepted {what}");
    }
}
