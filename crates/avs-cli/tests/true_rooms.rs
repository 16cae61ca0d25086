//! In simulation the CLI names the true room under each of the agent's rooms (issue 19 item 5):
//! after every look around, the true room the robot stood in, from the environment — the agent
//! itself never sees it.

mod common;

#[test]
fn every_look_around_is_followed_by_the_true_room_it_was_in() {
    let out = common::avs(&["run"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<&str> = text.lines().collect();
    let mut looks = 0;
    let mut named = std::collections::BTreeSet::new();
    for (i, l) in lines.iter().enumerate() {
        let Some(rest) = l.trim_start().strip_prefix("* looked around in room") else {
            continue;
        };
        looks += 1;
        let id: String = rest.chars().take_while(char::is_ascii_digit).collect();
        let next = lines.get(i + 1).copied().unwrap_or_default();
        let prefix = format!("(truth: room{id} is in `");
        let truth = next
            .trim_start()
            .strip_prefix(&prefix)
            .unwrap_or_else(|| panic!("no true room after {l:?}: {next:?}"));
        named.insert(truth.split('`').next().unwrap_or_default().to_string());
    }
    assert!(looks >= 2, "{text}");
    // The default search starts in the corridor and finds the cereal box in the kitchen.
    assert!(named.contains("corridor"), "{named:?}");
    assert!(named.contains("kitchen"), "{named:?}");
}
