//! `avs schema KIND` — print the JSON Schema of an avs file kind (for editors), or of one line
//! of a JSON-lines plan trace (`avs schema trace`).

use avs_format::FileKind;
use std::process::ExitCode;

/// Which kind of file.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Kind {
    /// A world: map, rooms, doors, objects, robot, sensors.
    Environment,
    /// Common-sense knowledge.
    Knowledge,
    /// A planning domain.
    Domain,
    /// A scenario.
    Scenario,
    /// A detection-verification scenario.
    Verification,
    /// One line of a JSON-lines plan trace (`--trace-json`): one event.
    Trace,
}

/// Flags.
#[derive(clap::Args)]
pub struct Args {
    /// The file kind whose schema to print.
    #[arg(value_enum)]
    pub kind: Kind,
}

/// Run the subcommand.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let kind = match args.kind {
        Kind::Environment => FileKind::Environment,
        Kind::Knowledge => FileKind::Knowledge,
        Kind::Domain => {
            println!("{}", avs_plan::domain::schema_json());
            return Ok(ExitCode::SUCCESS);
        }
        Kind::Scenario => FileKind::Scenario,
        Kind::Verification => FileKind::Verification,
        Kind::Trace => {
            println!("{}", avs_agent::trace::schema_json());
            return Ok(ExitCode::SUCCESS);
        }
    };
    match avs_format::schema::schema_json(kind) {
        Some(s) => {
            println!("{s}");
            Ok(ExitCode::SUCCESS)
        }
        None => anyhow::bail!("no JSON Schema for `{}` files", kind.name()),
    }
}
