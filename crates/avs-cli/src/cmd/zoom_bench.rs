//! `avs zoom-bench`: the calibration bench of the simulated camera image against Sjöö et al.'s
//! Figs. 7–10 (`avs_eval::zoom_calibration`): tables (or JSON) and four SVG charts.

use anyhow::Context;
use avs_eval::zoom_calibration::{draw, run_calibration, CalibrationParams};
use std::path::PathBuf;
use std::process::ExitCode;

/// Flags of `avs zoom-bench`.
#[derive(clap::Args)]
pub struct Args {
    /// The bench's seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Images per object, background and distance (the paper took 5).
    #[arg(long, default_value_t = CalibrationParams::default().images_per_position)]
    pub images_per_position: usize,
    /// Folder for the four SVG charts.
    #[arg(long, default_value = "docs/benchmarks/zoom")]
    pub out: PathBuf,
    /// Print one JSON object (the four figures' series) instead of the tables.
    #[arg(long)]
    pub json: bool,
}

/// Run `avs zoom-bench`.
pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    if a.images_per_position == 0 || a.images_per_position > 10_000 {
        anyhow::bail!(
            "--images-per-position {}: expected 1 to 10000",
            a.images_per_position
        );
    }
    let params = CalibrationParams {
        seed: a.seed,
        images_per_position: a.images_per_position,
        ..CalibrationParams::default()
    };
    let report = run_calibration(&params).context("zoom calibration bench")?;
    let files = draw(&report, &a.out).with_context(|| format!("charts in {}", a.out.display()))?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", report.tables());
        println!();
        for f in files {
            println!("wrote {}", f.display());
        }
    }
    Ok(ExitCode::SUCCESS)
}
