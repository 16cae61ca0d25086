//! `check_domain`: the shipped domain is clean; each kind of mistake is reported with its path.

use avs_plan::check_domain;

fn shipped() -> String {
    std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/object_search.yaml"),
    )
    .unwrap()
}

#[test]
fn shipped_object_search_domain_is_valid() {
    let d = check_domain("object_search.yaml", &shipped());
    assert!(d.is_empty(), "{d:#?}");
}

#[test]
fn each_mistake_is_reported_with_field_path_and_fix() {
    let base = shipped();
    let cases: &[(&str, &str, &str)] = &[
        (
            "cost: distance(?from, ?to)",
            "cost: -3",
            "operators[0].cost",
        ),
        (
            "probability: p-category(?r, ?c)",
            "probability: 1.5",
            "operators[4].probability",
        ),
        (
            "probability: p-category(?r, ?c)",
            "probability: .nan",
            "operators[4].probability",
        ),
        (
            "\"robot-at = ?from\"",
            "\"robot-at = ?nowhere\"",
            "operators[0].precondition[0]",
        ),
        (
            "\"robot-at = ?from\"",
            "\"robot-where = ?from\"",
            "operators[0].precondition[0]",
        ),
        (
            "\"connected(?from, ?to)\"",
            "\"connected(?from)\"",
            "operators[0].precondition[1]",
        ),
        (
            "\"robot-at := ?to\"",
            "\"robot-at := kitchen\"",
            "operators[0].effect[0]",
        ),
        (
            "\"category(?r) := ?c\"]",
            "\"category(?r) := purple\"]",
            "operators[3].effect[1]",
        ),
        (
            "\"?to: place\", \"?r: room\"]",
            "\"?to: planet\", \"?r: room\"]",
            "operators[0].parameters[1]",
        ),
        (
            "display: MOVE ?to",
            "display: MOVE ?where",
            "operators[0].display",
        ),
        (
            "in-room: [place, room]",
            "in-room: [place, rooom]",
            "relations.in-room[1]",
        ),
        ("- succ(n1, n0)", "- succ(n1, n99)", "facts[0]"),
        ("kind: domain", "kind: knowledge", "kind"),
    ];
    for (from, to, path) in cases {
        assert!(
            base.contains(from),
            "test setup: `{from}` not in the domain"
        );
        let text = base.replacen(from, to, 1);
        let d = check_domain("os.yaml", &text);
        assert!(
            d.iter()
                .any(|x| x.path == *path && !x.expected.is_empty() && x.file == "os.yaml"),
            "`{to}`: expected a diagnostic at {path}, got {d:#?}"
        );
    }
}

#[test]
fn yaml_errors_have_positions() {
    let d = check_domain("x.yaml", "kind: domain\nname: [\n");
    assert!(!d.is_empty());
    assert!(d[0].line.is_some());
    let d = check_domain(
        "x.yaml",
        "kind: domain\nname: x\ntypes: []\nvariables: {}\noperators: []\nextra: 1\n",
    );
    assert!(d.iter().any(|x| x.message.contains("extra")), "{d:?}");
}
