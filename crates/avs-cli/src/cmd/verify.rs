//! `avs verify-bench` (detection verification over repeated trials, Velez et al. 2012 Tables
//! 2–5) and `avs verify train` (fit a sensor model to simulated looks).

use anyhow::Context;
use avs_eval::verification::{
    model_kind, profile_of, run_bench, train_model, Strategy, VerificationWorld,
};
use avs_format::verification::DetectorName;
use std::process::ExitCode;

/// Flags of `avs verify-bench`.
#[derive(clap::Args)]
pub struct BenchArgs {
    /// A shipped scenario (single-door, multi-door, single-sign, multi-sign) or a scenario file.
    #[arg(long)]
    pub scenario: String,
    /// planned, planned-disc, greedy:TAU or rtbss.
    #[arg(long, default_value = "planned")]
    pub strategy: String,
    /// Number of trials (seeds SEED, SEED+1, …).
    #[arg(long, default_value_t = 50)]
    pub trials: usize,
    /// First seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// `avs verify` subcommands.
#[derive(clap::Subcommand)]
pub enum Command {
    /// Fit a sensor model for a detector to simulated labelled looks and print it as YAML.
    Train(TrainArgs),
}

/// Flags of `avs verify train`.
#[derive(clap::Args)]
pub struct TrainArgs {
    /// The detector: door, sign or generic.
    #[arg(long)]
    pub detector: String,
    /// The model: planned (dynamic) or planned-disc (static disc).
    #[arg(long, default_value = "planned")]
    pub strategy: String,
    /// Seed of the simulated training looks.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// The model's name in the knowledge file (classes refer to it as `verifier.model`);
    /// default: the detector's name.
    #[arg(long)]
    pub name: Option<String>,
}

/// Run `avs verify-bench`.
pub fn bench(a: BenchArgs) -> anyhow::Result<ExitCode> {
    let strategy = Strategy::parse(&a.strategy).map_err(|e| anyhow::anyhow!("--strategy {e}"))?;
    if a.trials == 0 || a.trials > 100_000 {
        anyhow::bail!("--trials {}: expected 1 to 100000", a.trials);
    }
    let world = VerificationWorld::named_or_file(&a.scenario)?;
    let r = run_bench(&world, strategy, a.trials, a.seed)
        .with_context(|| format!("verification bench on {}", world.file()))?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&r)?);
    } else {
        println!(
            "{} · {} · {} trials\n  precision {:.2} ± {:.2}\n  recall    {:.2} ± {:.2}\n  path      {:.1} ± {:.1} m\n  looks     {:.1} per trial\n  field     {:.3} ms (median)",
            r.scenario,
            r.strategy,
            r.trials,
            r.precision,
            r.precision_se,
            r.recall,
            r.recall_se,
            r.path_length_mean,
            r.path_length_se,
            r.looks_mean,
            r.field_ms_median
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// Run an `avs verify` subcommand.
pub fn run(c: Command) -> anyhow::Result<ExitCode> {
    match c {
        Command::Train(a) => {
            let detector: DetectorName = a
                .detector
                .parse()
                .map_err(|e| anyhow::anyhow!("--detector {e}"))?;
            let strategy =
                Strategy::parse(&a.strategy).map_err(|e| anyhow::anyhow!("--strategy {e}"))?;
            let spec = train_model(
                &profile_of(detector),
                model_kind(strategy, detector),
                a.seed,
            )?;
            // A knowledge file's `sensor_models` block, ready to paste (avs_format::verifier).
            #[derive(serde::Serialize)]
            struct Block {
                sensor_models: [avs_format::verifier::NamedSensorModel; 1],
            }
            let name = a.name.unwrap_or_else(|| detector.as_str().to_string());
            if name.trim().is_empty() {
                anyhow::bail!("--name: expected a non-empty model name");
            }
            print!(
                "# trained by `avs verify train --detector {} --strategy {} --seed {}`\n{}",
                detector.as_str(),
                a.strategy,
                a.seed,
                serde_yaml::to_string(&Block {
                    sensor_models: [avs_format::verifier::NamedSensorModel { name, model: spec }],
                })?
            );
            Ok(ExitCode::SUCCESS)
        }
    }
}
