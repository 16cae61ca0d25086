//! `avs run` — the default job: the agent searches the shipped office environment for the
//! cerealbox (knowledge `knowledge/office.yaml`, domain `domains/object_search.yaml`, seed 1),
//! printing the plan trace as it happens and a summary.

use super::defaults::{shipped, KNOWLEDGE};
use super::search::{print_summary, run_search};
use std::path::PathBuf;
use std::process::ExitCode;

/// The shipped default environment.
pub const ENVIRONMENT: &str = "domains/environments/office.yaml";
/// The shipped planning domain.
pub const DOMAIN: &str = "domains/object_search.yaml";

/// Flags (none required).
#[derive(clap::Args)]
pub struct Args {
    /// Write the plan trace as JSON lines to this file.
    #[arg(long)]
    pub trace_json: Option<PathBuf>,
}

/// Run the subcommand.
pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let s = run_search(
        &shipped(ENVIRONMENT),
        &shipped(KNOWLEDGE),
        &shipped(DOMAIN),
        "cerealbox",
        1,
        a.trace_json.as_deref(),
        false,
    )?;
    print_summary(&s);
    Ok(if s.found {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
