//! The one home of the CLI tests' way to run the `avs` binary.

#[allow(dead_code, reason = "only the serve tests start a server")]
pub mod serve;

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

/// `avs search` on the shipped office, knowledge and domain, printing the JSON summary: the
/// start of the search tests' command lines.
#[allow(dead_code, reason = "not every test file searches the office")]
pub const OFFICE_SEARCH: [&str; 8] = [
    "search",
    "--env",
    "domains/environments/office.yaml",
    "--knowledge",
    "knowledge/office.yaml",
    "--domain",
    "domains/object_search.yaml",
    "--json",
];
