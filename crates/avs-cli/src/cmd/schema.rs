//! `avs schema KIND` — print the JSON Schema of an avs file kind, for editors.

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
    /// A scenario (only its `kind:` header is defined so far).
    Scenario,
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
        Kind::Domain => FileKind::Domain,
        Kind::Scenario => FileKind::Scenario,
    };
    match avs_format::schema::schema_json(kind) {
        Some(s) => {
            println!("{s}");
            Ok(ExitCode::SUCCESS)
        }
        None => anyhow::bail!(
            "no JSON Schema for `{}` files yet: avs-plan does not expose one (its domain file type \
             needs a schemars `JsonSchema` derive and a public schema function); \
             `avs validate` still checks domain files",
            kind.name()
        ),
    }
}
