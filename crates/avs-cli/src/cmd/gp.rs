//! `avs gp eval`: Gaussian-process regression cases (the format of scikit-learn's reference
//! file `shared/data/gp/sklearn_gpr.json`, see `avs_verify::gp::cases`).

use anyhow::Context;
use avs_verify::gp::{eval_case, GpCaseFile, GpCaseResult};
use std::path::PathBuf;
use std::process::ExitCode;

/// Largest case file read, bytes: the cases' own limits (points, inputs, queries) bound the
/// work per case, this bounds the number of cases.
const MAX_FILE_BYTES: u64 = 256 << 20;

/// `avs gp` subcommands.
#[derive(clap::Subcommand)]
pub enum Command {
    /// Evaluate GP regression cases: log marginal likelihood, its gradient with respect to the
    /// log parameters, and predictive mean and std at the query points; cases marked `fitted`
    /// are fitted by maximum likelihood within their bounds first.
    Eval(EvalArgs),
}

/// Flags of `avs gp eval`.
#[derive(clap::Args)]
pub struct EvalArgs {
    /// The case file (JSON: `{"cases": [...]}`).
    pub file: PathBuf,
    /// Print a JSON object `{"cases": [...]}` instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Seed of the fits' random restarts.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
}

/// Run the subcommand.
pub fn run(c: Command) -> anyhow::Result<ExitCode> {
    match c {
        Command::Eval(a) => eval(&a),
    }
}

fn eval(a: &EvalArgs) -> anyhow::Result<ExitCode> {
    let file = &a.file;
    let size = std::fs::metadata(file)
        .with_context(|| format!("reading {}", file.display()))?
        .len();
    if size > MAX_FILE_BYTES {
        anyhow::bail!(
            "{}: {size} bytes, more than the {} MiB a case file may have",
            file.display(),
            MAX_FILE_BYTES >> 20
        );
    }
    let text =
        std::fs::read_to_string(file).with_context(|| format!("reading {}", file.display()))?;
    let cases = GpCaseFile::from_json(&text)
        .with_context(|| format!("{}: not a GP case file", file.display()))?
        .cases;
    let results = cases
        .iter()
        .enumerate()
        .map(|(i, case)| {
            eval_case(case, a.seed)
                .with_context(|| format!("{}: case {i} ({:?})", file.display(), case.name))
        })
        .collect::<anyhow::Result<Vec<GpCaseResult>>>()?;
    if a.json {
        // A struct rather than `json!`, so that each case's keys keep the reference file's
        // order (`name` first).
        #[derive(serde::Serialize)]
        struct Out<'a> {
            cases: &'a [GpCaseResult],
        }
        println!(
            "{}",
            serde_json::to_string_pretty(&Out { cases: &results })?
        );
    } else {
        println!("file  {}", file.display());
        println!(
            "{:<20} {:>6} {:>7} {:>6} {:>14} {:>12} {:>10}  length scales",
            "case", "points", "queries", "fitted", "log ML", "max |grad|", "σ²"
        );
        for (case, r) in cases.iter().zip(&results) {
            let grad = r
                .lml_gradient_wrt_log_params
                .iter()
                .fold(0.0f64, |m, g| m.max(g.abs()));
            let ls: Vec<String> = r.length_scale.iter().map(|l| format!("{l:.4}")).collect();
            println!(
                "{:<20} {:>6} {:>7} {:>6} {:>14.6} {:>12.2e} {:>10.4}  {}",
                r.name,
                case.x.len(),
                case.x_query.len(),
                if case.fitted { "yes" } else { "no" },
                r.log_marginal_likelihood,
                grad,
                r.signal_variance,
                ls.join(" ")
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}
