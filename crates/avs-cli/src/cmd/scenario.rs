//! `avs scenario FILE... [--seed N,...] [--json]` — re-enact scenario files from any directory
//! and judge their properties (the checks made in every scenario, then each `expect` field the
//! file sets). `--seed` runs every file once per given seed of the simulated robot instead of
//! the file's own `seed` (the properties should hold whatever the seed).
//!
//! A scenario's `environment`, `knowledge` and `domain` paths are resolved against the
//! scenario file's folder when they exist there, else against the repository (the current
//! directory when it is a checkout, else the checkout the binary was built from).
//!
//! Exit status: 0 when every property of every file holds, 3 when one does not, 1 for a file
//! that cannot be read or run, 2 for usage errors.

use super::defaults::built_checkout;
use avs_eval::scenario::properties::{evaluate_properties, PropertyResult};
use avs_eval::scenario::{load_scenario, run_scenario};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Flags.
#[derive(clap::Args)]
pub struct Args {
    /// Scenario files to run.
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,
    /// Run each file with these seeds of the simulated robot (comma-separated or repeated)
    /// instead of the file's own `seed`.
    #[arg(long = "seed", value_name = "N", value_delimiter = ',')]
    pub seeds: Vec<u64>,
    /// Print `{"scenarios": [{"file", "seed", "properties": [{"name", "pass", "detail"}]}]}`.
    #[arg(long)]
    pub json: bool,
}

/// One file's judged properties.
#[derive(Serialize)]
struct FileResult {
    file: String,
    seed: u64,
    properties: Vec<PropertyResult>,
}

/// The folder the scenario's paths are relative to: the file's own when every path exists
/// there, else the current directory when they exist there (a checkout), else the checkout
/// the binary was built from.
fn root_for(file: &Path, paths: [&str; 3]) -> PathBuf {
    let dir = file
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."));
    let dir = if dir.as_os_str().is_empty() {
        PathBuf::from(".")
    } else {
        dir
    };
    [dir, PathBuf::from("."), built_checkout()]
        .into_iter()
        .find(|root| paths.iter().all(|p| root.join(p).exists()))
        .unwrap_or_else(|| PathBuf::from("."))
}

/// Run the subcommand: an input that cannot be read or run exits 1, naming the file.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let mut results = Vec::new();
    let seeds: Vec<Option<u64>> = if args.seeds.is_empty() {
        vec![None]
    } else {
        args.seeds.iter().copied().map(Some).collect()
    };
    for file in &args.files {
        for &seed in &seeds {
            match judge(file, seed) {
                Ok(r) => results.push(r),
                Err(e) => {
                    eprintln!("error: {e:#}");
                    return Ok(ExitCode::from(1));
                }
            }
        }
    }
    report(&results, args.json)
}

/// Re-enact one scenario file (with `seed` in place of its own when given) and judge its
/// properties.
fn judge(file: &Path, seed: Option<u64>) -> anyhow::Result<FileResult> {
    {
        let mut sc = load_scenario(file)?;
        if let Some(seed) = seed {
            sc.seed = seed;
        }
        let root = root_for(
            file,
            [
                sc.environment.as_str(),
                sc.knowledge.as_str(),
                sc.domain.as_str(),
            ],
        );
        let out = run_scenario(&sc, file, &root)?;
        Ok(FileResult {
            file: file.display().to_string(),
            seed: sc.seed,
            properties: evaluate_properties(&sc, &out),
        })
    }
}

/// Print the results; exit 0 when every property holds, 3 otherwise.
fn report(results: &[FileResult], json: bool) -> anyhow::Result<ExitCode> {
    let all = results.iter().all(|f| f.properties.iter().all(|p| p.pass));
    if json {
        #[derive(Serialize)]
        struct Out<'a> {
            scenarios: &'a [FileResult],
        }
        println!(
            "{}",
            serde_json::to_string_pretty(&Out { scenarios: results })?
        );
    } else {
        for f in results {
            println!("{} (seed {})", f.file, f.seed);
            for p in &f.properties {
                let verdict = if p.pass { "PASS" } else { "FAIL" };
                println!("  {verdict}  {}: {}", p.name, p.detail);
            }
        }
    }
    Ok(if all {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(3)
    })
}
