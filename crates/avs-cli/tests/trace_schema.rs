//! `avs schema trace` (issue 19): the JSON Schema of one line of `--trace-json`, checked by an
//! independent validator (the `jsonschema` crate) against every event of `avs run` and of a
//! search that gives up behind a closed door (door sightings, the give-up).

mod common;
use common::avs;

#[test]
fn every_event_of_a_json_trace_validates_against_avs_schema_trace() {
    let out = avs(&["schema", "trace"]);
    assert!(out.status.success());
    let schema: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let validator = jsonschema::validator_for(&schema).expect("a valid JSON Schema");
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let mut kinds = std::collections::BTreeSet::new();
    for (name, args) in [
        ("run", vec!["run"]),
        (
            "closed",
            vec![
                "search",
                "--goal",
                "cerealbox",
                "--close-door",
                "door_kitchen",
                "--json",
            ],
        ),
    ] {
        let file = dir.join(format!("{name}.jsonl"));
        let mut args = args.clone();
        args.extend(["--trace-json", file.to_str().unwrap()]);
        let out = avs(&args);
        assert!(
            out.status.code().is_some_and(|c| c == 0 || c == 3),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = std::fs::read_to_string(&file).unwrap();
        for line in text.lines() {
            let event: serde_json::Value = serde_json::from_str(line).expect("one JSON per line");
            let errors: Vec<String> = validator
                .iter_errors(&event)
                .map(|e| e.to_string())
                .collect();
            assert!(errors.is_empty(), "{line}: {errors:?}");
            kinds.insert(event["event"].as_str().unwrap_or("").to_string());
        }
    }
    for k in [
        "started",
        "plan_made",
        "dt_action",
        "door_seen",
        "goal_reached",
        "gave_up",
    ] {
        assert!(kinds.contains(k), "no `{k}` event among {kinds:?}");
    }
    // The schema is not vacuous: an event of an unknown kind, or one missing a field, fails.
    for bad in [
        serde_json::json!({"event": "teleported", "to": [0, 0]}),
        serde_json::json!({"event": "gave_up"}),
    ] {
        assert!(!validator.is_valid(&bad), "{bad} validates");
    }
}
