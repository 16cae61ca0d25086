//! Random mutations of valid avs files (byte flips, truncation, duplicated lines, deep nesting,
//! YAML-significant insertions) fed to the loader and the map-free checks: whatever the text,
//! they return — an environment or located diagnostics — and never panic.

use avs_format::check_env::{check_environment, load_environment};
use avs_format::knowledge::{self, Knowledge};
use avs_format::{load_yaml_str, positions, read_kind, Diagnostic};
use proptest::prelude::*;
use std::path::{Path, PathBuf};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The valid files mutations start from: the validation corpus's good files and the shipped
/// environments and knowledge (whatever exists when the test runs).
fn seeds() -> Vec<String> {
    let mut out = Vec::new();
    for dir in ["tests/validate/good", "domains/environments", "knowledge"] {
        let Ok(entries) = std::fs::read_dir(workspace().join(dir)) else {
            continue;
        };
        let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
        paths.sort();
        for p in paths {
            if p.extension().is_some_and(|e| e == "yaml") {
                if let Ok(t) = std::fs::read_to_string(&p) {
                    out.push(t);
                }
            }
        }
    }
    assert!(!out.is_empty(), "no seed files found under the workspace");
    out
}

const TOKENS: &[&str] = &[
    "&a ",
    "*a",
    "&b ",
    "*b",
    ": ",
    "- ",
    "{",
    "}",
    "[",
    "]",
    "\n",
    "\t",
    "#",
    "'",
    "\"",
    ".nan",
    ".inf",
    "-1",
    "-1e308",
    "1e400",
    "---\n",
    "? ",
    "!!str ",
    "%YAML 1.2\n",
    "<<: *a\n",
    "~",
    "\u{feff}",
    "é",
    "\r\n",
    "|\n",
    ">-\n",
    "0x7f",
    "null",
];

#[derive(Debug, Clone)]
enum Mutation {
    Flip { at: usize, byte: u8 },
    Truncate { at: usize },
    Delete { at: usize, len: usize },
    DuplicateLine { line: usize, times: usize },
    Insert { at: usize, token: usize },
    Nest { at: usize, depth: usize, flow: bool },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(at, byte)| Mutation::Flip { at, byte }),
        any::<usize>().prop_map(|at| Mutation::Truncate { at }),
        (any::<usize>(), 1usize..40).prop_map(|(at, len)| Mutation::Delete { at, len }),
        (any::<usize>(), 1usize..50)
            .prop_map(|(line, times)| Mutation::DuplicateLine { line, times }),
        (any::<usize>(), 0..TOKENS.len()).prop_map(|(at, token)| Mutation::Insert { at, token }),
        (any::<usize>(), 1usize..400, any::<bool>()).prop_map(|(at, depth, flow)| Mutation::Nest {
            at,
            depth,
            flow
        }),
    ]
}

fn apply(text: &mut Vec<u8>, m: &Mutation) {
    let n = text.len().max(1);
    match *m {
        Mutation::Flip { at, byte } => {
            if !text.is_empty() {
                let i = at % text.len();
                text[i] ^= byte;
            }
        }
        Mutation::Truncate { at } => text.truncate(at % n),
        Mutation::Delete { at, len } => {
            let a = at % n;
            let b = (a + len).min(text.len());
            if a < b {
                text.drain(a..b);
            }
        }
        Mutation::DuplicateLine { line, times } => {
            let s = String::from_utf8_lossy(text).into_owned();
            let mut lines: Vec<&str> = s.split('\n').collect();
            let i = line % lines.len();
            let l = lines[i];
            for _ in 0..times {
                lines.insert(i, l);
            }
            *text = lines.join("\n").into_bytes();
        }
        Mutation::Insert { at, token } => {
            let i = at % (text.len() + 1);
            text.splice(i..i, TOKENS[token].bytes());
        }
        Mutation::Nest { at, depth, flow } => {
            let i = at % (text.len() + 1);
            let ins: Vec<u8> = if flow {
                let mut v = "[".repeat(depth).into_bytes();
                v.extend("]".repeat(depth).bytes());
                v
            } else {
                (0..depth)
                    .flat_map(|d| format!("{}k:\n", " ".repeat(d)).into_bytes())
                    .collect()
            };
            text.splice(i..i, ins);
        }
    }
}

fn all_named(ds: &[Diagnostic], file: &str) -> bool {
    ds.iter()
        .all(|d| d.file == file && !d.to_string().is_empty() && !d.expected.is_empty())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1000, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn mutated_files_load_or_fail_with_diagnostics_and_never_panic(
        seed in any::<usize>(),
        muts in proptest::collection::vec(mutation(), 1..6),
    ) {
        let seeds = seeds();
        let mut bytes = seeds[seed % seeds.len()].clone().into_bytes();
        for m in &muts {
            apply(&mut bytes, m);
        }
        // The loader reads UTF-8 text (read_text rejects other bytes); test its text paths.
        let text = String::from_utf8_lossy(&bytes).into_owned();
        let file = "mutant.yaml";
        if let Err(e) = read_kind(file, &text) {
            prop_assert!(!e.diagnostics.is_empty());
            prop_assert!(all_named(&e.diagnostics, file));
        }
        let k = load_yaml_str::<Knowledge>(file, &text).ok();
        let ds = knowledge::check(file, &text);
        prop_assert!(all_named(&ds, file));
        match load_environment(file, &text) {
            Ok(env) => {
                let mut ds = check_environment(file, &env, k.as_ref());
                positions::locate(&mut ds, &text);
                prop_assert!(all_named(&ds, file));
            }
            Err(e) => {
                prop_assert!(!e.diagnostics.is_empty());
                prop_assert!(all_named(&e.diagnostics, file));
            }
        }
    }
}

#[test]
fn unmutated_seed_environments_load_and_pass_the_map_free_checks() {
    for text in seeds() {
        if read_kind("seed.yaml", &text).ok() == Some(avs_format::FileKind::Environment) {
            let env = load_environment("seed.yaml", &text).expect("seed environment loads");
            assert_eq!(check_environment("seed.yaml", &env, None), vec![]);
        }
    }
}
