//! `avs search --svg`: the picture of a search has a title, a legend, a scale bar, one wedge per
//! look of the trace, and the start, end, report and false-alarm marks (issue 19, item 4).

mod common;
use common::avs;

/// Occurrences of `s` in `text`.
fn count(text: &str, s: &str) -> usize {
    text.matches(s).count()
}

#[test]
fn the_search_picture_shows_every_look_of_the_trace_and_says_what_it_shows() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let (svg, trace) = (dir.join("run.svg"), dir.join("run.jsonl"));
    let mut args = common::OFFICE_SEARCH.to_vec();
    args.extend([
        "--goal",
        "cerealbox",
        "--seed",
        "1",
        "--svg",
        svg.to_str().unwrap(),
        "--trace-json",
        trace.to_str().unwrap(),
        // A planned search with view-cone sessions (with the goal in the look around the
        // cereal box is found from the kitchen door, and the picture has no view cone).
        "--goal-in-look-around",
        "false",
    ]);
    let out = avs(&args);
    let summary: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON summary");
    // The svg crate writes a text element's content on a line of its own.
    let pic = std::fs::read_to_string(&svg)
        .expect("the SVG was written")
        .replace(">\n", ">")
        .replace("\n</", "</");
    let events: Vec<serde_json::Value> = std::fs::read_to_string(&trace)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();

    // The title: environment, goal, seed, outcome, path length.
    let outcome = if summary["wrong_report"] == true {
        "wrong report"
    } else if summary["found"] == true {
        "found"
    } else {
        "not found"
    };
    let title = format!(
        "office — search for cerealbox, seed 1: {outcome}, path {:.1} m",
        summary["path_length"].as_f64().unwrap()
    );
    assert!(pic.contains(&title), "no `{title}` in the picture");
    assert_eq!(count(&pic, "id=\"title\""), 1);

    // One wedge per look of the trace, hits and misses told apart.
    let looks = |prefix: &str, detected: bool| {
        events
            .iter()
            .filter(|e| {
                e["event"] == "dt_action"
                    && e["view"].is_object()
                    && e["action"].as_str().unwrap().starts_with(prefix)
                    && e["detected"] == detected
            })
            .count()
    };
    let (misses, hits) = (
        looks("PROCESSVIEWCONE", false),
        looks("PROCESSVIEWCONE", true),
    );
    assert!(misses + hits > 0, "the planned search processes view cones");
    assert_eq!(count(&pic, "class=\"view-cone miss\""), misses);
    assert_eq!(count(&pic, "class=\"view-cone hit\""), hits);
    assert_eq!(
        count(&pic, "class=\"verify-look miss\""),
        looks("VERIFY", false)
    );
    assert_eq!(
        count(&pic, "class=\"verify-look hit\""),
        looks("VERIFY", true)
    );

    // Start, end and the report, once each; false alarms: one per sighting that was looked at
    // again (a VERIFY look) and not accepted, in a session or in the coverage after it.
    assert_eq!(count(&pic, "class=\"start\""), 1);
    assert_eq!(count(&pic, "class=\"end\""), 1);
    let reported = usize::from(summary["reported_pose"].is_array());
    assert_eq!(
        count(&pic, "class=\"report\"") + count(&pic, "class=\"report wrong\""),
        reported
    );
    let false_alarms = events
        .iter()
        .filter(|e| {
            e["event"] == "verification_decision"
                && e["accepted"] == false
                && e["looks"].as_u64().unwrap() > 0
        })
        .count();
    assert_eq!(count(&pic, "class=\"false-alarm\""), false_alarms);

    // The legend has an entry for every kind of mark drawn; the scale bar is 1 m or 2 m.
    let legend = &pic[pic.find("id=\"legend\"").expect("a legend group")..];
    let entries = count(legend, "class=\"legend-entry\"");
    let mut expected = vec!["start", "end pose", "trail", "true cerealbox", "room:"];
    if hits > 0 {
        expected.push("cerealbox detected");
    }
    if misses > 0 {
        expected.push("nothing seen");
    }
    if false_alarms > 0 {
        expected.push("false alarm");
    }
    if reported > 0 {
        expected.push("reported position (correct)");
    }
    for e in &expected {
        assert!(legend.contains(e), "no legend entry `{e}`");
    }
    assert!(entries >= expected.len(), "{entries} legend entries");
    let bar = &pic[pic.find("id=\"scale-bar\"").expect("a scale bar")..];
    let bar = &bar[..bar.find("</g>").unwrap()];
    assert!(bar.contains(">1 m<") || bar.contains(">2 m<"), "{bar}");

    // Every true room labelled; the agent's belief where it looked around.
    for room in ["corridor", "office1", "kitchen", "office2"] {
        assert!(pic.contains(&format!(">{room} (")), "no label for {room}");
    }
    let looked_around = events
        .iter()
        .filter(|e| e["event"] == "looked_around")
        .count();
    assert!(looked_around > 0, "the agent looks around where it starts");
    assert!(pic.contains(">agent: corridor "), "the start's room belief");
}
