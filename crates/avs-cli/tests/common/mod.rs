//! The one home of the CLI tests' way to run the `avs` binary.

use std::path::Path;
use std::process::{Command, Output};

/// Run `avs args…` in the repository root.
#[allow(dead_code, reason = "not every test file uses both helpers")]
pub fn avs(args: &[&str]) -> Output {
    avs_in(
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")),
        args,
    )
}

/// Run `avs args…` in `dir`.
#[allow(dead_code, reason = "not every test file uses both helpers")]
pub fn avs_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_avs"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the avs binary runs")
}
