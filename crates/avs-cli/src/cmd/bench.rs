//! `avs bench --generate N --seed S [--rooms K] [--strategy planner|uninformed|frontier]
//! [--misleading] [--goal CLASS] [--json]`
//!
//! The search benchmark: N generated floors (`avs generate` with seeds S, S+1, …), each with a
//! target object — the class drawn uniformly from the knowledge file's non-landmark classes
//! unless `--goal` fixes it, placed where the knowledge's rates say, or in the room they make
//! least likely with `--misleading` — searched by one strategy with the robot seeded by the
//! floor's seed. Success rate and SPL are over the floors whose target is reachable from the
//! start. Floors run in parallel (rayon); every figure except the timings is independent of
//! the scheduling.

use super::defaults::{shipped, KNOWLEDGE};
use super::run::DOMAIN;
use super::search::{load_domain, search_world, Faults, Summary};
use anyhow::Context;
use avs_agent::agent::median;
use avs_agent::agent::Strategy;
use avs_agent::AgentConfig;
use avs_format::knowledge::Knowledge;
use avs_sim::generate::{generate, GenerateParams, Placement};
use avs_sim::World;
use indicatif::{ProgressBar, ProgressStyle};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::Serialize;
use std::path::PathBuf;
use std::process::ExitCode;

/// Flags.
#[derive(clap::Args)]
pub struct Args {
    /// Number of generated floors.
    #[arg(long)]
    pub generate: usize,
    /// Seed of the first floor (floor i uses seed S + i for the floor and the robot).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Rooms per floor besides the corridor.
    #[arg(long, default_value_t = 6)]
    pub rooms: usize,
    /// planner | uninformed | frontier.
    #[arg(long, default_value = "planner")]
    pub strategy: Strategy,
    /// Put each target in the room the knowledge makes least likely.
    #[arg(long)]
    pub misleading: bool,
    /// Search this class on every floor (default: drawn per floor).
    #[arg(long)]
    pub goal: Option<String>,
    /// Knowledge file (default: the shipped office knowledge).
    #[arg(long)]
    pub knowledge: Option<PathBuf>,
    /// Planning domain (default: the shipped object-search domain).
    #[arg(long)]
    pub domain: Option<PathBuf>,
    /// Print the result as JSON (with every run).
    #[arg(long)]
    pub json: bool,
    /// Write each floor's environment to DIR/floor-SEED.yaml, to replay one run with
    /// `avs search --env DIR/floor-SEED.yaml --goal CLASS --seed SEED`.
    #[arg(long, value_name = "DIR")]
    pub save_floors: Option<PathBuf>,
}

/// One floor's run.
#[derive(Debug, Serialize)]
pub struct BenchRun {
    /// Seed of the floor and the robot.
    pub seed: u64,
    /// The target class.
    pub goal: String,
    /// Whether some target is reachable from the start.
    pub reachable: bool,
    /// The search's summary.
    #[serde(flatten)]
    pub summary: Summary,
    /// Wall time of each plan, ms.
    #[serde(skip)]
    pub plan_ms: Vec<f64>,
}

/// The benchmark's figures.
#[derive(Debug, Serialize)]
pub struct BenchResult {
    /// The strategy.
    pub strategy: Strategy,
    /// Floors generated.
    pub floors: usize,
    /// Floors whose target is reachable.
    pub reachable: usize,
    /// Share of reachable floors where the target was found.
    pub success_rate: f64,
    /// Mean SPL over the reachable floors.
    pub spl_mean: f64,
    /// Mean distance driven over the reachable floors, m.
    pub path_length_mean: f64,
    /// Mean number of plans over the reachable floors.
    pub plans_mean: f64,
    /// Median planning time over every plan of every run, ms.
    pub plan_ms_median: f64,
    /// Seed of the first floor.
    pub seed: u64,
    /// Rooms per floor.
    pub rooms: usize,
    /// Whether targets were put where the knowledge makes them least likely.
    pub misleading: bool,
    /// Every run, by seed.
    pub runs: Vec<BenchRun>,
}

fn floor(
    k: &Knowledge,
    seed: u64,
    rooms: usize,
    goal: &str,
    misleading: bool,
    save: Option<&std::path::Path>,
) -> anyhow::Result<World> {
    let env = generate(
        k,
        &GenerateParams {
            seed,
            rooms,
            ensure_class: Some(goal.to_string()),
            placement: if misleading {
                Placement::Unlikely
            } else {
                Placement::AsKnowledge
            },
        },
    )
    .with_context(|| format!("generating floor {seed}"))?;
    if let Some(dir) = save {
        let path = dir.join(format!("floor-{seed}.yaml"));
        let text = format!(
            "# Floor {seed} of `avs bench --rooms {rooms}{}`; target {goal}.\n{}",
            if misleading { " --misleading" } else { "" },
            serde_yaml::to_string(&env)?
        );
        std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
    }
    World::new(env, std::path::Path::new(".")).with_context(|| format!("floor {seed}"))
}

/// Run the benchmark; `tick` is called after each floor.
#[expect(
    clippy::too_many_arguments,
    reason = "the bench takes every flag of the command"
)]
pub fn bench(
    knowledge: &Knowledge,
    domain: &avs_plan::domain::Domain,
    n: usize,
    seed: u64,
    rooms: usize,
    strategy: Strategy,
    misleading: bool,
    goal: Option<&str>,
    save_floors: Option<&std::path::Path>,
    tick: &(dyn Fn() + Sync),
) -> anyhow::Result<BenchResult> {
    let targets: Vec<&str> = knowledge
        .object_classes
        .iter()
        .filter(|c| !c.landmark)
        .map(|c| c.name.as_str())
        .collect();
    if let Some(g) = goal {
        anyhow::ensure!(
            knowledge.class(g).is_some(),
            "--goal {g}: not an object class of the knowledge file; expected one of {}",
            targets.join(", ")
        );
    }
    anyhow::ensure!(
        goal.is_some() || !targets.is_empty(),
        "the knowledge file has no non-landmark object class to search for"
    );
    let config = AgentConfig {
        strategy,
        ..AgentConfig::default()
    };
    let mut runs: Vec<BenchRun> = (0..n as u64)
        .into_par_iter()
        .map(|i| -> anyhow::Result<BenchRun> {
            let s = seed + i;
            let g = match goal {
                Some(g) => g.to_string(),
                None => {
                    let mut rng = ChaCha8Rng::seed_from_u64(s);
                    targets[rng.gen_range(0..targets.len())].to_string()
                }
            };
            let world = floor(knowledge, s, rooms, &g, misleading, save_floors)?;
            let out = search_world(
                &world,
                knowledge,
                domain,
                &g,
                s,
                config.clone(),
                &Faults::default(),
                &mut |_| {},
            )
            .with_context(|| format!("floor {s}"))?;
            let (summary, report) = (out.summary, out.report);
            tick();
            Ok(BenchRun {
                seed: s,
                goal: g,
                reachable: summary.shortest_path_length.is_some(),
                summary,
                plan_ms: report.metrics.plan_ms,
            })
        })
        .collect::<anyhow::Result<_>>()?;
    runs.sort_by_key(|r| r.seed);
    let ok: Vec<&BenchRun> = runs.iter().filter(|r| r.reachable).collect();
    let mean = |f: &dyn Fn(&BenchRun) -> f64| {
        if ok.is_empty() {
            0.0
        } else {
            ok.iter().map(|r| f(r)).sum::<f64>() / ok.len() as f64
        }
    };
    let plan_ms: Vec<f64> = runs
        .iter()
        .flat_map(|r| r.plan_ms.iter().copied())
        .collect();
    Ok(BenchResult {
        strategy,
        floors: n,
        reachable: ok.len(),
        success_rate: mean(&|r| f64::from(u8::from(r.summary.found))),
        spl_mean: mean(&|r| r.summary.spl),
        path_length_mean: mean(&|r| r.summary.path_length),
        plans_mean: mean(&|r| r.summary.plans as f64),
        plan_ms_median: median(&plan_ms),
        seed,
        rooms,
        misleading,
        runs,
    })
}

/// Run the subcommand.
pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    anyhow::ensure!(a.generate > 0, "--generate 0: expected at least one floor");
    let kpath = a.knowledge.unwrap_or_else(|| shipped(KNOWLEDGE));
    let dpath = a.domain.unwrap_or_else(|| shipped(DOMAIN));
    let knowledge: Knowledge = avs_format::load_yaml(&kpath)
        .with_context(|| format!("loading knowledge {}", kpath.display()))?;
    let domain = load_domain(&dpath)?;
    if let Some(dir) = &a.save_floors {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let bar = ProgressBar::new(a.generate as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{prefix} [{bar:30}] {pos}/{len} floors, {elapsed}, eta {eta}",
        )
        .context("progress bar template")?
        .progress_chars("=> "),
    );
    bar.set_prefix(format!("{:?}", a.strategy).to_lowercase());
    let tick = || bar.inc(1);
    let r = bench(
        &knowledge,
        &domain,
        a.generate,
        a.seed,
        a.rooms,
        a.strategy,
        a.misleading,
        a.goal.as_deref(),
        a.save_floors.as_deref(),
        &tick,
    )?;
    bar.finish_and_clear();
    if a.json {
        println!("{}", serde_json::to_string_pretty(&r)?);
    } else {
        println!(
            "strategy {:?}, {} floors ({} reachable), {} rooms, seed {}{}",
            r.strategy,
            r.floors,
            r.reachable,
            r.rooms,
            r.seed,
            if r.misleading { ", misleading" } else { "" }
        );
        println!("  success_rate      {:.3}", r.success_rate);
        println!("  spl_mean          {:.3}", r.spl_mean);
        println!("  path_length_mean  {:.1} m", r.path_length_mean);
        println!("  plans_mean        {:.1}", r.plans_mean);
        println!("  plan_ms_median    {:.2} ms", r.plan_ms_median);
        for run in r.runs.iter().filter(|r| r.reachable && !r.summary.found) {
            println!(
                "  missed: seed {} {}: {}",
                run.seed, run.goal, run.summary.reason
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}
