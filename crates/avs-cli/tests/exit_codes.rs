//! Exit codes as the README's conventions say, over every subcommand (issue 19): 2 for a usage
//! error (a flag clap cannot parse), 1 for invalid input (a missing, unreadable or malformed
//! file, an unknown name), 0 for success; `search` exits 3 when it searched and did not find,
//! `scenario` when a property fails. Each error names the file once.

mod common;
use common::avs;

const MISSING: &str = "no/such/input.file";

/// Every subcommand, with arguments that name a missing input file.
fn with_missing_input() -> Vec<Vec<&'static str>> {
    vec![
        vec!["search", "--goal", "mug", "--env", MISSING],
        vec!["bench", "--generate", "1", "--knowledge", MISSING],
        vec!["validate", MISSING],
        vec!["scenario", MISSING],
        vec!["segment", MISSING],
        vec!["render", MISSING, "--svg", "/tmp/avs-exit-codes.svg"],
        vec![
            "generate",
            "--seed",
            "1",
            "--out",
            "/tmp/avs-x.yaml",
            "--knowledge",
            MISSING,
        ],
        vec!["infer", MISSING],
        vec!["plan", MISSING, MISSING],
        vec!["pomdp", "solve", MISSING],
        vec!["pomdp", "simulate", MISSING],
        vec!["gp", "eval", MISSING],
        vec!["verify-bench", "--scenario", MISSING, "--trials", "1"],
    ]
}

#[test]
fn a_missing_input_file_exits_1_and_names_the_file_once() {
    for args in with_missing_input() {
        let o = avs(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        assert_eq!(err.matches(MISSING).count(), 1, "{args:?}: {err}");
    }
}

#[test]
fn an_unknown_flag_exits_2_on_every_subcommand() {
    for sub in [
        vec!["run"],
        vec!["search"],
        vec!["bench"],
        vec!["validate"],
        vec!["scenario"],
        vec!["schema"],
        vec!["segment"],
        vec!["render"],
        vec!["generate"],
        vec!["infer"],
        vec!["plan"],
        vec!["pomdp", "solve"],
        vec!["pomdp", "simulate"],
        vec!["gp", "eval"],
        vec!["verify", "train"],
        vec!["verify-bench"],
    ] {
        let mut args = sub.clone();
        args.push("--no-such-flag");
        let o = avs(&args);
        assert_eq!(
            o.status.code(),
            Some(2),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}

#[test]
fn invalid_input_exits_1_and_success_exits_0() {
    // An unknown goal class and an unknown door are input errors, not usage errors.
    for args in [
        vec!["search", "--goal", "unicorn"],
        vec!["search", "--goal", "mug", "--close-door", "no_such_door"],
        vec!["bench", "--generate", "1", "--goal", "unicorn"],
    ] {
        let o = avs(&args);
        assert_eq!(
            o.status.code(),
            Some(1),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    for args in [
        vec!["schema", "environment"],
        vec!["validate", "domains/environments/office.yaml"],
        vec!["search", "--goal", "mug"],
    ] {
        let o = avs(&args);
        assert_eq!(
            o.status.code(),
            Some(0),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}
