//! `avs pomdp solve|simulate`: POMDPs in Cassandra's `.pomdp` format.

use anyhow::Context;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

/// `avs pomdp` subcommands.
#[derive(clap::Subcommand)]
pub enum Command {
    /// Solve offline (HSVI) and print the lower and upper value at the initial belief.
    Solve(SolveArgs),
    /// Solve, then simulate the lower bound's policy and report the mean discounted return.
    Simulate(SimulateArgs),
}

/// Flags of `avs pomdp solve`.
#[derive(clap::Args)]
pub struct SolveArgs {
    /// The `.pomdp` file.
    pub file: PathBuf,
    /// Stop when upper − lower at the initial belief is at most this.
    #[arg(long, default_value_t = 1e-3)]
    pub gap: f64,
    /// Stop after this many seconds (the bounds stay valid).
    #[arg(long)]
    pub time: Option<f64>,
    /// Print a JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Flags of `avs pomdp simulate`.
#[derive(clap::Args)]
pub struct SimulateArgs {
    /// The `.pomdp` file.
    pub file: PathBuf,
    /// Number of simulated episodes.
    #[arg(long, default_value_t = 1000)]
    pub runs: usize,
    /// Random seed.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Steps per episode (default: until γ^h · max|R|/(1−γ) < 1e-3).
    #[arg(long)]
    pub horizon: Option<usize>,
    /// Gap of the offline solve that provides the policy.
    #[arg(long, default_value_t = 1e-3)]
    pub gap: f64,
    /// Time limit of the offline solve, seconds.
    #[arg(long)]
    pub time: Option<f64>,
    /// Print a JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

fn time_limit(t: Option<f64>) -> anyhow::Result<Option<Duration>> {
    match t {
        None => Ok(None),
        Some(s) if s.is_finite() && s > 0.0 => Ok(Some(Duration::from_secs_f64(s))),
        Some(s) => anyhow::bail!("--time must be a positive number of seconds, got {s}"),
    }
}

fn solve_file(
    file: &PathBuf,
    gap: f64,
    time: Option<f64>,
) -> anyhow::Result<(avs_pomdp::Pomdp, avs_pomdp::OfflineSolution)> {
    let model = avs_pomdp::read_pomdp_file(file)?;
    let opts = avs_pomdp::OfflineOptions {
        target_gap: gap,
        time_limit: time_limit(time)?,
        ..Default::default()
    };
    let sol =
        avs_pomdp::solve(&model, &opts).with_context(|| format!("solving {}", file.display()))?;
    Ok((model, sol))
}

/// Run the subcommand.
pub fn run(c: Command) -> anyhow::Result<ExitCode> {
    match c {
        Command::Solve(a) => {
            let (model, sol) = solve_file(&a.file, a.gap, a.time)?;
            let first = model.actions()[sol.bounds.lower_action(model.initial_belief())].clone();
            if a.json {
                let v = serde_json::json!({
                    "file": a.file.display().to_string(),
                    "lower": sol.lower,
                    "upper": sol.upper,
                    "gap": sol.gap(),
                    "iterations": sol.trials,
                    "backups": sol.backups,
                    "seconds": sol.seconds,
                    "stop": sol.stop,
                    "alpha_vectors": sol.bounds.alpha_vectors().len(),
                    "upper_points": sol.bounds.n_upper_points(),
                    "first_action": first,
                });
                println!("{}", serde_json::to_string_pretty(&v)?);
            } else {
                println!("file        {}", a.file.display());
                println!("lower       {:.6}", sol.lower);
                println!("upper       {:.6}", sol.upper);
                println!("gap         {:.3e}", sol.gap());
                println!("iterations  {} trials, {} backups", sol.trials, sol.backups);
                println!("time        {:.3} s", sol.seconds);
                println!("stopped     {:?}", sol.stop);
                println!("first       {first}");
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Simulate(a) => {
            let (model, sol) = solve_file(&a.file, a.gap, a.time)?;
            let horizon = a
                .horizon
                .unwrap_or_else(|| avs_pomdp::horizon_for(&model, 1e-3));
            let bounds = &sol.bounds;
            let sum =
                avs_pomdp::simulate(&model, a.runs, horizon, a.seed, |b| bounds.lower_action(b))?;
            if a.json {
                let v = serde_json::json!({
                    "file": a.file.display().to_string(),
                    "runs": sum.runs,
                    "seed": a.seed,
                    "horizon": sum.horizon,
                    "mean": sum.mean,
                    "std_error": sum.std_error,
                    "ci95": [sum.ci95_low, sum.ci95_high],
                    "solver_lower": sol.lower,
                    "solver_upper": sol.upper,
                });
                println!("{}", serde_json::to_string_pretty(&v)?);
            } else {
                println!("file        {}", a.file.display());
                println!(
                    "runs        {} (seed {}, horizon {})",
                    sum.runs, a.seed, sum.horizon
                );
                println!(
                    "return      {:.4}  95% CI [{:.4}, {:.4}]",
                    sum.mean, sum.ci95_low, sum.ci95_high
                );
                println!("solver      lower {:.6}  upper {:.6}", sol.lower, sol.upper);
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}
