//! `avs bench --generate N --seed S [--rooms K] [--strategy planner|uninformed|frontier|informed]
//! [--misleading] [--goal CLASS] [--json]`, and `avs bench --faults --generate N …`
//!
//! The search benchmark: N generated floors (`avs generate` with seeds S, S+1, …), each with a
//! target object — the class drawn uniformly from the knowledge file's non-landmark classes
//! unless `--goal` fixes it, placed where the knowledge's rates say, or in the room they make
//! least likely with `--misleading` — searched by one strategy with the robot seeded by the
//! floor's seed. Success rate and SPL are over the floors whose target is reachable from the
//! start. Floors run in parallel (rayon); every figure except the timings is independent of
//! the scheduling. The bench itself is `avs_eval::bench`.
//!
//! With `--faults`, the fault matrix instead (`avs_eval::faults`): each floor searched by the
//! planner once per fault (action failures 10 % and 30 %, false positives ×2 and ×5, the
//! target's doors shutting early or late or closed from the start), with one table row per
//! fault: runs, found, gave up, give-ups naming their cause, wrong reports, the slowest run.

use super::search::{DetectorArg, ModelArgs};
use anyhow::Context;
use avs_agent::AgentConfig;
use avs_agent::Strategy;
use avs_eval::bench::{bench, BenchParams};
use avs_eval::faults::{fault_matrix, Fault, FaultParams};
use avs_eval::inputs::{Input, Shipped};
use avs_format::knowledge::Knowledge;
use avs_plan::domain::Domain;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
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
    /// planner | uninformed | frontier | informed (told the target's room: a reference).
    #[arg(long, default_value = "planner")]
    pub strategy: Strategy,
    /// Put each target in the room the knowledge makes least likely.
    #[arg(long)]
    pub misleading: bool,
    /// Give the simulated robot its place classifier (size, shape, appearance readings as
    /// evidence on room categories; off by default).
    #[arg(long)]
    pub place_classifier: bool,
    /// Look-alikes per room on the generated floors (a Poisson mean in [0, 10]: objects of
    /// another class that a detector may take for the target).
    #[arg(long, value_name = "RATE", default_value_t = avs_sim::generate::DEFAULT_LOOKALIKES_PER_ROOM)]
    pub lookalikes: f64,
    /// The simulated robot's object detector.
    #[arg(long, value_enum, default_value_t = DetectorArg::default())]
    pub detector: DetectorArg,
    /// Looks run the zoom pipeline (attention, zoom windows, three-step search, recognition)
    /// instead of the one-shot detector.
    #[arg(long)]
    pub zoom: bool,
    /// The planner's model: `--unfound-landmarks`, `--objective`.
    #[command(flatten)]
    pub model: ModelArgs,
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
    /// Run the fault matrix on the floors instead (the planner under each fault; see
    /// `avs_eval::faults`); `--strategy`, `--misleading`, `--goal` and `--place-classifier`
    /// do not apply.
    #[arg(long, conflicts_with_all = ["misleading", "goal", "place_classifier", "save_floors"])]
    pub faults: bool,
    /// Write each floor's environment to DIR/floor-SEED.yaml, to replay one run with
    /// `avs search --env DIR/floor-SEED.yaml --goal CLASS --seed SEED`.
    #[arg(long, value_name = "DIR")]
    pub save_floors: Option<PathBuf>,
}

/// Run the subcommand.
pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    anyhow::ensure!(a.generate > 0, "--generate 0: expected at least one floor");
    let knowledge = Input::or_shipped(a.knowledge.as_deref(), Shipped::Knowledge)?.knowledge()?;
    let domain = Input::or_shipped(a.domain.as_deref(), Shipped::Domain)?.domain()?;
    if a.faults {
        return run_faults(&a, &knowledge, &domain);
    }
    if let Some(dir) = &a.save_floors {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let bar = Progress::new(
        a.generate as u64,
        "floors",
        format!("{:?}", a.strategy).to_lowercase(),
    )?;
    let tick = || bar.inc();
    let params = BenchParams {
        floors: a.generate,
        seed: a.seed,
        rooms: a.rooms,
        strategy: a.strategy,
        misleading: a.misleading,
        goal: a.goal.clone(),
        save_floors: a.save_floors.clone(),
        place_classifier: a.place_classifier,
        lookalikes_per_room: a.lookalikes,
        detector: a.detector.into(),
        zoom_pipeline: a.zoom,
        unfound_landmarks: a.model.unfound_landmarks,
        objective: a.model.objective.into(),
        wrong_report_price: a.model.wrong_report_price,
        goal_in_look_around: a.model.goal_in_look_around,
    };
    let r = bench(&knowledge, &domain, &params, &tick)?;
    bar.finish();
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
        println!("  soft_spl_mean     {:.3}", r.soft_spl_mean);
        println!("  wrong_reports     {}", r.wrong_reports);
        println!("  path_length_mean  {:.1} m", r.path_length_mean);
        let by = &r.path_by_activity_mean;
        println!(
            "    by activity     exploration {:.1} m, view cones {:.1} m, verification {:.1} m, coverage {:.1} m",
            by.exploration, by.view_cones, by.verification, by.coverage
        );
        println!("  room_revisits_mean {:.1}", r.room_revisits_mean);
        println!("  plans_mean        {:.1}", r.plans_mean);
        println!(
            "  images_mean       {:.1} ({:.1} by the zoom pipeline)",
            r.images_mean, r.zoom_images_mean
        );
        println!("  plan_ms_median    {:.2} ms", r.plan_ms_median);
        println!("  compute_s_max     {:.1} s", r.compute_s_max);
        for run in r.runs.iter().filter(|r| r.reachable && !r.summary.found) {
            println!(
                "  missed: seed {} {}: {}",
                run.seed, run.goal, run.summary.reason
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// Progress over `len` items named `what`: a bar on a terminal; elsewhere (a log file, CI) a
/// line per item on stderr, so a long bench is never silent.
struct Progress {
    bar: ProgressBar,
    terminal: bool,
    what: &'static str,
}

impl Progress {
    fn new(len: u64, what: &'static str, prefix: String) -> anyhow::Result<Self> {
        let bar = ProgressBar::new(len);
        bar.set_style(
            ProgressStyle::with_template(&format!(
                "{{prefix}} [{{bar:30}}] {{pos}}/{{len}} {what}, {{elapsed}}, eta {{eta}}"
            ))
            .context("progress bar template")?
            .progress_chars("=> "),
        );
        bar.set_prefix(prefix);
        Ok(Self {
            bar,
            terminal: std::io::stderr().is_terminal(),
            what,
        })
    }

    /// One more item done.
    fn inc(&self) {
        self.bar.inc(1);
        if !self.terminal {
            eprintln!(
                "{} {}/{} {} ({:.0} s)",
                self.bar.prefix(),
                self.bar.position(),
                self.bar.length().unwrap_or(0),
                self.what,
                self.bar.elapsed().as_secs_f64()
            );
        }
    }

    fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// `--faults`: the fault matrix on the floors.
fn run_faults(a: &Args, knowledge: &Knowledge, domain: &Domain) -> anyhow::Result<ExitCode> {
    let faults = Fault::matrix();
    let bar = Progress::new((a.generate * faults.len()) as u64, "runs", "faults".into())?;
    let tick = || bar.inc();
    let params = FaultParams {
        floors: a.generate,
        seed: a.seed,
        rooms: a.rooms,
        faults,
        config: AgentConfig::default(),
    };
    let m = fault_matrix(knowledge, domain, &params, &tick)?;
    bar.finish();
    if a.json {
        println!("{}", serde_json::to_string_pretty(&m)?);
        return Ok(ExitCode::SUCCESS);
    }
    println!(
        "fault matrix: {} floors, {} rooms, seed {}",
        m.floors, m.rooms, m.seed
    );
    println!(
        "| fault | runs | found | gave up | cause named | unconfirmed named | wrong reports | slowest | most actions |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for r in &m.rows {
        let named = if r.cause_expected == 0 {
            "–".to_string()
        } else {
            format!("{}/{}", r.cause_named, r.cause_expected)
        };
        println!(
            "| {} | {} | {} | {} | {named} | {} | {} | {:.1} s | {} |",
            r.label,
            r.runs,
            r.found,
            r.gave_up,
            r.names_unconfirmed,
            r.wrong_reports,
            r.slowest_s,
            r.most_actions
        );
    }
    for run in m.runs.iter().filter(|r| r.applicable) {
        if run.cause_named == Some(false) || run.wrong_report {
            println!(
                "  {}: seed {} {}: {}",
                run.fault.label(),
                run.seed,
                run.goal,
                run.reason
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}
