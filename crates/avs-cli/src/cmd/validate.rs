//! `avs validate FILE...` — parse and cross-check avs files and report every problem as
//! `FILE:LINE:COLUMN: field.path: what is wrong; what is expected`.
//!
//! Each file is dispatched on its `kind:`: environments get the map-free and geometric checks
//! (`avs_sim::check`), knowledge files `avs_format::knowledge::check`, domains
//! `avs_plan::check_domain`, scenarios `avs_format::scenario::check` (every field). When exactly one
//! knowledge file is among the arguments (or given with `--knowledge`), environments are also
//! checked against its room categories and object classes. Folders are searched for `*.yaml`.
//!
//! Exit status: 0 when every file is valid, 1 when a problem was found (a file that does not
//! exist included), 2 for usage errors.

use anyhow::Context;
use avs_format::knowledge::Knowledge;
use avs_format::{Diagnostic, FileKind};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Flags.
#[derive(clap::Args)]
pub struct Args {
    /// Files (or folders, searched for *.yaml / *.yml) to check.
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,
    /// Check environments against this knowledge file (default: the one knowledge file among FILE).
    #[arg(long, value_name = "FILE")]
    pub knowledge: Option<PathBuf>,
    /// Print diagnostics as JSON lines instead of text.
    #[arg(long)]
    pub json: bool,
}

struct Input {
    name: String,
    path: PathBuf,
    text: String,
    kind: FileKind,
}

/// Run the subcommand.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let mut paths = Vec::new();
    for p in &args.files {
        if p.is_dir() {
            collect_yaml(p, &mut paths)
                .with_context(|| format!("reading folder {}", p.display()))?;
        } else if p.exists() {
            paths.push(p.clone());
        } else {
            anyhow::bail!("{}: no such file", p.display());
        }
    }
    let mut problems: Vec<Diagnostic> = Vec::new();
    let mut inputs = Vec::new();
    for path in &paths {
        let name = path.display().to_string();
        let text = match avs_format::load::read_text(path) {
            Ok(t) => t,
            Err(e) => {
                problems.extend(e.diagnostics);
                continue;
            }
        };
        match avs_format::read_kind(&name, &text) {
            Ok(kind) => inputs.push(Input {
                name,
                path: path.clone(),
                text,
                kind,
            }),
            Err(e) => problems.extend(e.diagnostics),
        }
    }

    let knowledge = knowledge_for_cross_checks(&args, &inputs, &mut problems)?;

    for input in &inputs {
        let mut found = match input.kind {
            FileKind::Environment => {
                let base = input.path.parent().unwrap_or(Path::new("."));
                avs_sim::check::check_environment_text(
                    &input.name,
                    &input.text,
                    base,
                    knowledge.as_ref(),
                )
            }
            FileKind::Knowledge => avs_format::knowledge::check(&input.name, &input.text),
            FileKind::Domain => avs_plan::check_domain(&input.name, &input.text),
            FileKind::Scenario => avs_format::scenario::check(&input.name, &input.text),
            FileKind::Verification => avs_format::verification::check(&input.name, &input.text),
        };
        avs_format::positions::locate(&mut found, &input.text);
        problems.extend(found);
    }

    for d in &problems {
        if args.json {
            println!("{}", serde_json::to_string(d)?);
        } else {
            println!("{d}");
        }
    }
    let bad_files = {
        let mut f: Vec<&str> = problems.iter().map(|d| d.file.as_str()).collect();
        f.sort_unstable();
        f.dedup();
        f.len()
    };
    if problems.is_empty() {
        eprintln!("{} file(s) valid", paths.len());
        Ok(ExitCode::SUCCESS)
    } else {
        eprintln!(
            "{} problem(s) in {bad_files} of {} file(s)",
            problems.len(),
            paths.len()
        );
        Ok(ExitCode::from(1))
    }
}

/// The knowledge that environments are cross-checked against: `--knowledge`, or the single
/// valid knowledge file among the inputs. None (with a note) when it is ambiguous.
fn knowledge_for_cross_checks(
    args: &Args,
    inputs: &[Input],
    problems: &mut Vec<Diagnostic>,
) -> anyhow::Result<Option<Knowledge>> {
    if let Some(path) = &args.knowledge {
        if !path.is_file() {
            anyhow::bail!("--knowledge {}: no such file", path.display());
        }
        // Read and parsed as a knowledge input is, so that a missing field names its section's
        // fields here too.
        let parsed = avs_format::load::read_text(path).and_then(|text| {
            avs_format::load::load_yaml_str_explained::<Knowledge>(
                &path.display().to_string(),
                &text,
            )
        });
        return match parsed {
            Ok(k) => Ok(Some(k)),
            Err(e) => {
                problems.extend(e.diagnostics);
                Ok(None)
            }
        };
    }
    let ks: Vec<&Input> = inputs
        .iter()
        .filter(|i| i.kind == FileKind::Knowledge)
        .collect();
    let has_env = inputs.iter().any(|i| i.kind == FileKind::Environment);
    match ks.as_slice() {
        [one] => Ok(avs_format::load_yaml_str::<Knowledge>(&one.name, &one.text).ok()),
        [] => {
            if has_env {
                eprintln!(
                    "note: no knowledge file given; environments' room categories and object \
                     classes are not checked (add --knowledge FILE, e.g. knowledge/office.yaml)"
                );
            }
            Ok(None)
        }
        _ => {
            if has_env {
                eprintln!(
                    "note: {} knowledge files given; environments are not cross-checked \
                     (choose one with --knowledge FILE)",
                    ks.len()
                );
            }
            Ok(None)
        }
    }
}

/// Every `*.yaml` / `*.yml` file under `dir`, sorted.
fn collect_yaml(dir: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)?
        .map(|e| e.map(|e| e.path()))
        .collect::<Result<_, _>>()?;
    entries.sort();
    for p in entries {
        if p.is_dir() {
            collect_yaml(&p, out)?;
        } else if matches!(
            p.extension().and_then(|e| e.to_str()),
            Some("yaml") | Some("yml")
        ) {
            out.push(p);
        }
    }
    Ok(())
}
