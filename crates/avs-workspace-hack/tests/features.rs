//! The README's two commands build each dependency once: every crate that `cargo run -p avs-cli`
//! builds gets the same features as in `cargo test --workspace`. When a dependency change breaks
//! this, run `cargo hakari generate` (`.config/hakari.toml`).

use std::collections::{BTreeMap, BTreeSet};
use std::process::Command;

/// `cargo tree` with `args`: each package (name and version) with its enabled features.
fn features(args: &[&str]) -> BTreeMap<String, BTreeSet<String>> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let out = Command::new(env!("CARGO"))
        .args(["tree", "--locked", "--prefix", "none", "-f", "{p}|{f}"])
        .args(args)
        .current_dir(root)
        .output()
        .expect("cargo runs");
    assert!(
        out.status.success(),
        "cargo tree {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut map: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let Some((package, feats)) = line.split_once('|') else {
            continue;
        };
        // "name vX.Y.Z (path)" → "name vX.Y.Z"; "(*)" marks a repeat.
        let id: Vec<&str> = package.split_whitespace().take(2).collect();
        let feats = feats.trim_end_matches("(*)").trim();
        map.entry(id.join(" ")).or_default().extend(
            feats
                .split(',')
                .filter(|f| !f.is_empty())
                .map(str::to_string),
        );
    }
    map
}

#[test]
fn the_run_and_the_tests_build_every_shared_dependency_with_the_same_features() {
    let run = features(&["-p", "avs-cli", "-e", "no-dev"]);
    let tests = features(&["--workspace"]);
    assert!(run.len() > 50, "cargo tree listed too little: {run:?}");
    let differ: Vec<String> = run
        .iter()
        .filter_map(|(p, f)| {
            let t = tests.get(p)?;
            (t != f).then(|| format!("{p}: run {f:?}, tests {t:?}"))
        })
        .collect();
    assert!(
        differ.is_empty(),
        "features differ (run `cargo hakari generate`):\n{}",
        differ.join("\n")
    );
}
