//! Cassandra `.pomdp` reader: every construct of the format, overrides, and errors with line numbers.

use avs_pomdp::{parse_pomdp, PomdpError};

const HEAD: &str =
    "discount: 0.9\nvalues: reward\nstates: a b c\nactions: x y\nobservations: o p\n";

fn line_of(e: PomdpError) -> usize {
    match e {
        PomdpError::Parse { line, .. } => line,
        other => panic!("expected a parse error, got {other}"),
    }
}

#[test]
fn counted_declarations_name_items_by_index() {
    let m = parse_pomdp(
        "discount: 0.5\nstates: 3\nactions: 2\nobservations: 2\nT: * identity\nT: 1 : 0 : 2 1.0\nT: 1 : 0 : 0 0\nO: * uniform\nR: 0 : 2 : * : * 4\n",
        "t",
    )
    .unwrap();
    assert_eq!(m.n_states(), 3);
    assert_eq!(m.states()[2], "2");
    assert_eq!(m.transition(0, 1, 2), 1.0);
    assert_eq!(m.transition(1, 1, 1), 1.0);
    assert_eq!(m.reward(2, 0), 4.0);
    assert_eq!(m.reward(1, 0), 0.0);
    // No start: uniform.
    assert!(m
        .initial_belief()
        .iter()
        .all(|p| (p - 1.0 / 3.0).abs() < 1e-12));
}

#[test]
fn start_accepts_a_distribution_a_state_an_index_include_and_exclude() {
    let tail = "T: * identity\nO: * uniform\n";
    let cases: [(&str, [f64; 3]); 6] = [
        ("start: 0.2 0.3 0.5\n", [0.2, 0.3, 0.5]),
        ("start: b\n", [0.0, 1.0, 0.0]),
        ("start: 2\n", [0.0, 0.0, 1.0]),
        ("start: uniform\n", [1.0 / 3.0; 3]),
        ("start include: a c\n", [0.5, 0.0, 0.5]),
        ("start exclude: a\n", [0.0, 0.5, 0.5]),
    ];
    for (start, want) in cases {
        let m = parse_pomdp(&format!("{HEAD}{start}{tail}"), "s").unwrap();
        for (got, w) in m.initial_belief().iter().zip(want) {
            assert!((got - w).abs() < 1e-12, "{start}: {:?}", m.initial_belief());
        }
    }
}

#[test]
fn rows_matrices_wildcards_and_later_entries_override_earlier_ones() {
    let text = format!(
        "{HEAD}T: x\n0.5 0.5 0\n0 1 0\n0 0 1\nT: y : * \n0 0 1\nT: y : b\nuniform\nT: x : a : c 0.25\nT: x : a : b 0.25\n\
         O: * : * : o 1\nO: * : * : p 0\nO: y\n0.1 0.9\n0.2 0.8\n0.3 0.7\nO: x : c\nuniform\n\
         R: * : * : * : * -1\nR: y : a : * : * 2\n"
    );
    let m = parse_pomdp(&text, "t").unwrap();
    assert_eq!(m.transition(0, 0, 0), 0.5);
    assert_eq!(m.transition(0, 0, 1), 0.25);
    assert_eq!(m.transition(0, 0, 2), 0.25);
    assert_eq!(m.transition(0, 1, 2), 1.0);
    assert!((m.transition(1, 1, 0) - 1.0 / 3.0).abs() < 1e-12);
    assert_eq!(m.observation(1, 2, 0), 0.3);
    assert_eq!(m.observation(0, 0, 0), 1.0);
    assert_eq!(m.observation(0, 2, 1), 0.5);
    assert_eq!(m.reward(0, 1), 2.0);
    assert_eq!(m.reward(1, 1), -1.0);
}

#[test]
fn rewards_on_next_state_and_observation_are_taken_in_expectation() {
    // From a under x: to b w.p. 0.5 (reward 10 if o, o w.p. 0.4), to c w.p. 0.5 (reward 2 via row).
    let text = format!(
        "{HEAD}T: * identity\nT: x : a\n0 0.5 0.5\nO: * : * : o 0.4\nO: * : * : p 0.6\n\
         R: x : a : b : o 10\nR: x : a : c\n2 2\nR: y : c\n1 2\n3 4\n5 6\n"
    );
    let m = parse_pomdp(&text, "t").unwrap();
    assert!((m.reward(0, 0) - (0.5 * 0.4 * 10.0 + 0.5 * 2.0)).abs() < 1e-12);
    // y keeps c → c, so R(c, y) = Σ_z O(z) R(c, y, c, z) = 0.4·5 + 0.6·6.
    assert!((m.reward(2, 1) - (0.4 * 5.0 + 0.6 * 6.0)).abs() < 1e-12);
}

#[test]
fn values_cost_negates_rewards() {
    let text = HEAD.replace("reward", "cost") + "T: * identity\nO: * uniform\nR: x : * : * : * 3\n";
    let m = parse_pomdp(&text, "t").unwrap();
    assert_eq!(m.reward(0, 0), -3.0);
}

#[test]
fn errors_name_the_line_and_what_is_expected() {
    let bad_state = format!("{HEAD}T: * identity\nO: * uniform\nR: x : zz : * : * 1\n");
    let e = parse_pomdp(&bad_state, "f.pomdp").unwrap_err();
    let msg = e.to_string();
    assert!(msg.starts_with("f.pomdp:8:"), "{msg}");
    assert!(msg.contains("unknown state `zz`"), "{msg}");

    let short_row = format!("{HEAD}T: x : a\n0.5 0.5\nO: * uniform\n");
    assert_eq!(line_of(parse_pomdp(&short_row, "f").unwrap_err()), 8);

    let nan = format!("{HEAD}T: x : a : b NaN\n");
    assert_eq!(line_of(parse_pomdp(&nan, "f").unwrap_err()), 6);

    let missing_decl = "discount: 0.9\nT: x identity\n";
    assert_eq!(line_of(parse_pomdp(missing_decl, "f").unwrap_err()), 2);

    let bad_values = "discount: 0.9\nvalues: money\n";
    assert_eq!(line_of(parse_pomdp(bad_values, "f").unwrap_err()), 2);

    // Rows that do not sum to one are reported with the action and state.
    let unnormalised = format!("{HEAD}T: * identity\nT: y : c : a 0.5\nO: * uniform\n");
    let msg = parse_pomdp(&unnormalised, "f").unwrap_err().to_string();
    assert!(
        msg.contains("action `y`") && msg.contains("state `c`"),
        "{msg}"
    );
}

#[test]
fn reading_a_missing_file_names_it() {
    let e = avs_pomdp::read_pomdp_file("/nonexistent/x.pomdp").unwrap_err();
    assert!(e.to_string().contains("/nonexistent/x.pomdp"));
}

proptest::proptest! {
    #[test]
    fn arbitrary_text_never_panics(s in "[a-z0-9:*. \\n#-]{0,200}") {
        let _ = parse_pomdp(&s, "fuzz");
    }

    #[test]
    fn mutated_tiger_never_panics(cut in 0usize..400, insert in "[a-z0-9:*. \\n-]{0,8}") {
        let tiger = "discount: 0.95\nvalues: reward\nstates: tl tr\nactions: listen ol or\nobservations: hl hr\nstart: 0.5 0.5\nT: listen\nidentity\nT: ol\nuniform\nT: or\nuniform\nO: listen\n0.85 0.15\n0.15 0.85\nO: ol\nuniform\nO: or\nuniform\nR: listen : * : * : * -1\nR: ol : tl : * : * -100\n";
        let k = cut.min(tiger.len());
        let text = format!("{}{}{}", &tiger[..k], insert, &tiger[k..]);
        let _ = parse_pomdp(&text, "fuzz");
    }
}
