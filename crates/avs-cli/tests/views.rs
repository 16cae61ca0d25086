//! `avs views`, end to end: the contract keys, the greedy never below the optimum, the picture,
//! and clear errors.

mod common;
use common::avs;

#[test]
fn views_json_has_the_contract_keys_and_covers_the_kitchen_for_three_classes() {
    let tmp = tempfile::tempdir().unwrap();
    let svg = tmp.path().join("views.svg");
    let o = avs(&[
        "views",
        "domains/environments/office.yaml",
        "--room",
        "kitchen",
        "--classes",
        "cerealbox,mug,stapler",
        "--optimal",
        "--svg",
        svg.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    for key in [
        "standpoints",
        "standpoints_used",
        "searches",
        "coverage",
        "optimal_searches",
        "views",
    ] {
        assert!(v.get(key).is_some(), "{key} missing: {v}");
    }
    let searches = v["searches"].as_u64().unwrap();
    let optimum = v["optimal_searches"].as_u64().unwrap();
    assert!(optimum <= searches && searches > 0);
    assert_eq!(v["views"].as_array().unwrap().len() as u64, searches);
    for class in ["cerealbox", "mug", "stapler"] {
        assert_eq!(v["coverage"][class], 1.0, "{class}: {}", v["coverage"]);
    }
    // Every standpoint used is one of the candidates, and every view stands on a used one.
    let n = v["standpoints"].as_array().unwrap().len() as u64;
    let used: Vec<u64> = v["standpoints_used"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap())
        .collect();
    assert!(used.iter().all(|u| *u < n));
    assert!(v["views"]
        .as_array()
        .unwrap()
        .iter()
        .all(|view| used.contains(&view["standpoint"].as_u64().unwrap())));
    let picture = std::fs::read_to_string(&svg).unwrap();
    assert!(picture.starts_with("<svg") && picture.contains("standpoint used"));
}

#[test]
fn views_without_optimal_omits_the_optimum_and_twice_coverage_takes_more_images() {
    let run = |k: &str| {
        let o = avs(&[
            "views",
            "domains/environments/office.yaml",
            "--room",
            "office1",
            "--classes",
            "stapler",
            "--k",
            k,
            "--json",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    let (once, twice) = (run("1"), run("2"));
    assert!(once.get("optimal_searches").is_none());
    assert!(twice["searches"].as_u64() > once["searches"].as_u64());
}

#[test]
fn views_names_an_unknown_room_or_class_and_exits_1() {
    for (flag, value, expect) in [
        ("--room", "attic", "no room `attic`"),
        ("--classes", "unicorn", "unknown class `unicorn`"),
    ] {
        let mut args = vec![
            "views",
            "domains/environments/office.yaml",
            "--room",
            "kitchen",
            "--classes",
            "mug",
        ];
        let i = args.iter().position(|a| *a == flag).unwrap();
        args[i + 1] = value;
        let o = avs(&args);
        assert_eq!(o.status.code(), Some(1));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(expect), "{err}");
    }
}
