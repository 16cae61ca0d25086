//! The CI smoke run of the fuzz targets: every seed in `fuzz/corpus/<target>/` is run through
//! its target. A panic fails the test and names the file; so does a target folder that is
//! missing or empty, a target none of whose seeds is accepted (the Ok path must be exercised,
//! not only the errors), and a shipped input that its reader does not accept.

use avs_fuzz::{Target, Verdict};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus")
}

/// The seeds of `target`, sorted.
fn seeds(target: Target) -> Vec<PathBuf> {
    let dir = corpus().join(target.name());
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}; expected the target's corpus", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files
}

/// Run one seed, turning a panic into an error that names the file.
fn replay(target: Target, path: &Path) -> Result<Verdict, String> {
    let data = std::fs::read(path).unwrap();
    catch_unwind(AssertUnwindSafe(|| target.run(&data))).map_err(|p| {
        let msg = p
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_else(|| "(no message)".into());
        format!("{}: {}: panicked: {msg}", target.name(), path.display())
    })
}

/// One test per target, so that they run in parallel and a failure names its target.
fn replay_target(target: Target, must_accept: &[&str]) {
    let files = seeds(target);
    assert!(
        !files.is_empty(),
        "fuzz/corpus/{}/ is empty; expected seeds",
        target.name()
    );
    let mut failures = Vec::new();
    let mut accepted = Vec::new();
    for path in &files {
        match replay(target, path) {
            Ok(Verdict::Accepted) => accepted.push(path.file_name().unwrap().to_owned()),
            Ok(Verdict::Refused) => {}
            Err(e) => failures.push(e),
        }
    }
    eprintln!(
        "{}: {} seeds, accepted: {accepted:?}",
        target.name(),
        files.len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(
        !accepted.is_empty(),
        "{}: no seed was accepted; expected at least one valid input",
        target.name()
    );
    for name in must_accept {
        assert!(
            accepted.iter().any(|a| a == *name),
            "{}: {name} was refused; expected it to be accepted",
            target.name()
        );
    }
}

#[test]
fn every_target_has_a_corpus_folder_and_nothing_else_is_there() {
    let mut dirs: Vec<String> = std::fs::read_dir(corpus())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    dirs.sort();
    let mut names: Vec<String> = Target::ALL.iter().map(|t| t.name().to_string()).collect();
    names.sort();
    assert_eq!(dirs, names);
}

#[test]
fn environment() {
    replay_target(
        Target::Environment,
        &["office.yaml", "two_rooms.yaml", "two_rooms_pgm.bin"],
    );
}

#[test]
fn knowledge() {
    replay_target(Target::Knowledge, &["office.yaml", "home.yaml"]);
}

#[test]
fn domain() {
    replay_target(Target::Domain, &["object_search.yaml"]);
}

#[test]
fn scenario() {
    replay_target(Target::Scenario, &["fig3d_office_stapler.yaml"]);
}

#[test]
fn map() {
    replay_target(Target::Map, &["two_rooms_pgm.bin", "two_rooms_png.bin"]);
}

#[test]
fn pddl() {
    replay_target(Target::Pddl, &["gripper.bin", "action_costs.bin"]);
}

#[test]
fn pomdp() {
    replay_target(Target::Pomdp, &["tiger.pomdp"]);
}

#[test]
fn uai() {
    replay_target(Target::Uai, &["markov_chain.uai", "bayes.uai"]);
}

#[test]
fn fg() {
    replay_target(Target::Fg, &["two_factors.fg", "labels.fg"]);
}

#[test]
fn search() {
    replay_target(Target::Search, &["office.yaml"]);
}

/// The crate's own oracle works: an environment that is refused is reported as refused (a
/// target that accepted everything would make the assertions above vacuous).
#[test]
fn a_malformed_input_is_refused_not_accepted() {
    for t in Target::ALL {
        assert_eq!(t.run(b"kind: [\n"), Verdict::Refused, "{}", t.name());
    }
}
