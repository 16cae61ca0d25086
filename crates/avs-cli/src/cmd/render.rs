//! `avs render ENV.yaml --svg OUT.svg [--explore STEPS] [--seed N]`

use anyhow::Context;
use avs_map::places::PlaceMapParams;
use avs_sim::{Explorer, World};
use std::path::PathBuf;
use std::process::ExitCode;

/// Flags.
#[derive(clap::Args)]
pub struct Args {
    /// The environment file.
    pub env: PathBuf,
    /// Where to write the picture.
    #[arg(long)]
    pub svg: PathBuf,
    /// Explore from the start for this many steps (going to the best placeholder each time) and
    /// draw the partly known state with its place map; without it, draw the fully known world.
    #[arg(long)]
    pub explore: Option<usize>,
    /// Seed for the simulated robot.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// Run the subcommand.
pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let world = World::load(&a.env).context("loading the environment")?;
    let svg = match a.explore {
        None => avs_sim::render::render_world(&world),
        Some(steps) => {
            let mut ex = Explorer::new(&world, PlaceMapParams::default(), a.seed);
            ex.run(steps);
            tracing::info!(
                steps = ex.steps,
                places = ex.places.graph.node_count(),
                "explored"
            );
            avs_sim::render::render_exploration(&ex)
        }
    };
    std::fs::write(&a.svg, svg).with_context(|| format!("writing {}", a.svg.display()))?;
    Ok(ExitCode::SUCCESS)
}
