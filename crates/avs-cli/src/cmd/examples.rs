//! `avs examples DIR [--force]`: write small, working example inputs for every command into
//! `DIR`, and print each file with the commands that use it.
//!
//! The office environment, its knowledge and the object-search domain are the shipped defaults
//! (`avs_eval::inputs::Shipped`, the text `avs run` uses). The other files live in
//! `crates/avs-cli/examples-data/` and are built into the binary with `include_str!`: they
//! belong to this command alone, so they sit beside it in its crate (a top-level `examples/`
//! folder would read as Cargo examples, `cargo run --example`). Every printed command is run on
//! the written files by `tests/examples.rs`.
//!
//! Existing files are not overwritten unless `--force` is given; the error names them.

use anyhow::Context;
use avs_eval::inputs::Shipped;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Flags.
#[derive(clap::Args)]
pub struct Args {
    /// The folder to write the examples into (created when missing).
    pub dir: PathBuf,
    /// Overwrite example files that already exist in DIR.
    #[arg(long)]
    pub force: bool,
}

/// One example file.
struct Example {
    /// File name inside DIR.
    name: &'static str,
    /// What it is, in a few words.
    what: &'static str,
    /// Its content.
    text: &'static str,
}

/// The example files, in the order they are listed.
const EXAMPLES: &[Example] = &[
    Example {
        name: "office.yaml",
        what: "environment: the shipped office floor, a corridor with two offices and a kitchen off it",
        text: Shipped::Environment.text(),
    },
    Example {
        name: "office_knowledge.yaml",
        what: "knowledge: room categories, object classes and where they are found",
        text: Shipped::Knowledge.text(),
    },
    Example {
        name: "object_search.yaml",
        what: "planning domain: the object-search domain the agent plans with",
        text: Shipped::Domain.text(),
    },
    Example {
        name: "flat.yaml",
        what: "environment: a small floor of our own in an ASCII map: a corridor, an office, a kitchen",
        text: include_str!("../../examples-data/flat.yaml"),
    },
    Example {
        name: "scenario.yaml",
        what: "scenario: a search in office.yaml and what it should show",
        text: include_str!("../../examples-data/scenario.yaml"),
    },
    Example {
        name: "rooms.uai",
        what: "factor graph in the UAI format: two rooms' categories and a counter seen in one",
        text: include_str!("../../examples-data/rooms.uai"),
    },
    Example {
        name: "rooms.uai.evid",
        what: "evidence for rooms.uai: the counter was seen",
        text: include_str!("../../examples-data/rooms.uai.evid"),
    },
    Example {
        name: "find_domain.pddl",
        what: "PDDL domain: drive between rooms, look, report",
        text: include_str!("../../examples-data/find_domain.pddl"),
    },
    Example {
        name: "find_problem.pddl",
        what: "PDDL problem: find the cereal box on a four-room floor",
        text: include_str!("../../examples-data/find_problem.pddl"),
    },
    Example {
        name: "view_cones.pomdp",
        what: "POMDP in Cassandra's format: is the object in view cone A or in view cone B?",
        text: include_str!("../../examples-data/view_cones.pomdp"),
    },
];

/// The commands that use the examples, one word per element; `@NAME` stands for the example
/// file NAME in DIR (an output file there too, such as an SVG).
const COMMANDS: &[&[&str]] = &[
    &[
        "avs",
        "validate",
        "@office.yaml",
        "@flat.yaml",
        "@office_knowledge.yaml",
        "@object_search.yaml",
        "@scenario.yaml",
    ],
    &[
        "avs",
        "search",
        "--env",
        "@office.yaml",
        "--knowledge",
        "@office_knowledge.yaml",
        "--domain",
        "@object_search.yaml",
        "--goal",
        "cerealbox",
    ],
    &[
        "avs",
        "search",
        "--env",
        "@flat.yaml",
        "--knowledge",
        "@office_knowledge.yaml",
        "--goal",
        "stapler",
    ],
    &["avs", "segment", "@office.yaml"],
    &["avs", "segment", "@flat.yaml", "--svg", "@flat_rooms.svg"],
    &["avs", "render", "@flat.yaml", "--svg", "@flat.svg"],
    &["avs", "scenario", "@scenario.yaml"],
    &["avs", "infer", "@rooms.uai", "--evid", "@rooms.uai.evid"],
    &["avs", "plan", "@find_domain.pddl", "@find_problem.pddl"],
    &["avs", "pomdp", "solve", "@view_cones.pomdp"],
    &[
        "avs",
        "pomdp",
        "simulate",
        "@view_cones.pomdp",
        "--runs",
        "200",
        "--seed",
        "1",
    ],
];

/// Run the subcommand.
pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let dir = &a.dir;
    if !a.force {
        let existing: Vec<String> = EXAMPLES
            .iter()
            .map(|e| dir.join(e.name))
            .filter(|p| p.exists())
            .map(|p| p.display().to_string())
            .collect();
        if !existing.is_empty() {
            anyhow::bail!(
                "{}: already exist{}; expected a folder without the example files \
                 (pass --force to overwrite them)",
                existing.join(", "),
                if existing.len() == 1 { "s" } else { "" }
            );
        }
    }
    std::fs::create_dir_all(dir).with_context(|| format!("creating folder {}", dir.display()))?;
    for e in EXAMPLES {
        let path = dir.join(e.name);
        std::fs::write(&path, e.text).with_context(|| format!("writing {}", path.display()))?;
    }

    println!(
        "wrote {} example files to {}; each with the commands that use it:",
        EXAMPLES.len(),
        dir.display()
    );
    for e in EXAMPLES {
        println!();
        println!("{}", dir.join(e.name).display());
        println!("    {}", e.what);
        let file = format!("@{}", e.name);
        for c in COMMANDS.iter().filter(|c| c.contains(&file.as_str())) {
            println!("    $ {}", command_line(dir, c));
        }
    }
    println!();
    println!(
        "`avs run` is the cerealbox search in office.yaml, with the three shipped files built in:"
    );
    println!("    $ avs run");
    Ok(ExitCode::SUCCESS)
}

/// A command as a shell line: `@NAME` words become paths in `dir`, and words a shell would
/// split or expand are single-quoted.
fn command_line(dir: &Path, words: &[&str]) -> String {
    words
        .iter()
        .map(|w| match w.strip_prefix('@') {
            Some(name) => shell_word(&dir.join(name).display().to_string()),
            None => shell_word(w),
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// `s` as one shell word: unchanged when it has only characters no shell treats specially,
/// else in single quotes (a `'` inside written `'\''`).
fn shell_word(s: &str) -> String {
    let plain = !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "_-./,:=+%@".contains(c));
    if plain {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', r"'\''"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_command_names_only_example_or_output_files_and_every_file_has_a_command() {
        let outputs = ["@flat_rooms.svg", "@flat.svg"];
        for c in COMMANDS {
            for w in c.iter().filter(|w| w.starts_with('@')) {
                assert!(
                    outputs.contains(w) || EXAMPLES.iter().any(|e| format!("@{}", e.name) == *w),
                    "{w} in {c:?} is no example file"
                );
            }
        }
        for e in EXAMPLES {
            let file = format!("@{}", e.name);
            assert!(
                COMMANDS.iter().any(|c| c.contains(&file.as_str())),
                "no command uses {}",
                e.name
            );
        }
    }

    #[test]
    fn words_a_shell_would_split_are_quoted() {
        assert_eq!(shell_word("ex/office.yaml"), "ex/office.yaml");
        assert_eq!(shell_word("my dir/a.yaml"), "'my dir/a.yaml'");
        assert_eq!(shell_word("it's"), r"'it'\''s'");
        assert_eq!(shell_word(""), "''");
    }
}
