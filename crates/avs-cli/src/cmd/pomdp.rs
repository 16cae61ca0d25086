//! (Being built.)

use std::process::ExitCode;

/// `avs pomdp` subcommands.
#[derive(clap::Subcommand)]
pub enum Command {}

/// Run the subcommand.
pub fn run(c: Command) -> anyhow::Result<ExitCode> {
    match c {}
}
