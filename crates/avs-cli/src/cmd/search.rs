//! `avs search --env E --knowledge K --domain D --goal CLASS [--seed N] [--trace-json F] [--json]`
//!
//! One object search by the agent in the simulated environment, with the plan trace printed as
//! it happens and a summary. The agent never sees ground truth; this command reads it only to
//! score the result (error of the reported pose, shortest path, SPL).

use anyhow::{anyhow, Context};
use avs_agent::agent::median;
use avs_agent::{Agent, AgentConfig, Event, Goal, SearchReport};
use avs_format::knowledge::Knowledge;
use avs_map::nav::{shortest_path, Traversability};
use avs_plan::domain::Domain;
use avs_sim::sim_robot::{SimAgentRobot, SimRobotConfig};
use avs_sim::World;
use serde::Serialize;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Flags.
#[derive(clap::Args)]
pub struct Args {
    /// The environment file.
    #[arg(long)]
    pub env: PathBuf,
    /// The knowledge file.
    #[arg(long)]
    pub knowledge: PathBuf,
    /// The planning domain file.
    #[arg(long)]
    pub domain: PathBuf,
    /// The object class to find.
    #[arg(long)]
    pub goal: String,
    /// Seed of the simulated robot (sensor noise, action failures).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Write the plan trace as JSON lines to this file, flushed as events happen.
    #[arg(long)]
    pub trace_json: Option<PathBuf>,
    /// Print only the summary, as JSON.
    #[arg(long)]
    pub json: bool,
}

/// The figures of one search.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// Whether the agent reported an object of the goal class within 1 m of a true one.
    pub found: bool,
    /// The reported position `[x, y, z]`, if any.
    pub reported_pose: Option<[f64; 3]>,
    /// Planar distance from the reported position to the nearest true object of the class, m.
    pub error: Option<f64>,
    /// Distance driven, m.
    pub path_length: f64,
    /// Shortest collision-free path from the start to the nearest true object of the class, m.
    pub shortest_path_length: Option<f64>,
    /// Success weighted by path length: found × shortest / max(path, shortest).
    pub spl: f64,
    /// Plans made.
    pub plans: usize,
    /// View-cone POMDP sessions.
    pub dt_sessions: usize,
    /// Median planning time, ms.
    pub plan_ms_median: f64,
    /// Median time per DT decision, ms.
    pub dt_ms_median: f64,
    /// Why the search ended.
    pub reason: String,
}

/// A reported position counts as the object when it is within this distance of it, m.
const SUCCESS_RADIUS: f64 = 1.0;

/// Run one search; `on_event` sees every trace event as it happens.
pub fn search(
    env: &Path,
    knowledge: &Path,
    domain: &Path,
    goal: &str,
    seed: u64,
    on_event: &mut dyn FnMut(&Event),
) -> anyhow::Result<(Summary, SearchReport)> {
    let world =
        World::load(env).with_context(|| format!("loading environment {}", env.display()))?;
    let k: Knowledge = avs_format::load_yaml(knowledge)
        .with_context(|| format!("loading knowledge {}", knowledge.display()))?;
    let d = Domain::load(domain).map_err(|diags| {
        let msgs: Vec<String> = diags.iter().map(|d| d.to_string()).collect();
        anyhow!(
            "domain {} is invalid:\n{}",
            domain.display(),
            msgs.join("\n")
        )
    })?;
    let mut robot = SimAgentRobot::new(&world, k.clone(), SimRobotConfig::default(), seed)
        .with_context(|| format!("simulated robot for {}", env.display()))?;
    let mut agent = Agent::new(d, k, AgentConfig::default())?;
    let mut sink = |e: &Event| on_event(e);
    let report = agent.search_with(&mut robot, Goal::find(goal), &mut sink)?;
    // Scoring against ground truth (the agent never saw it).
    let targets: Vec<[f64; 2]> = world
        .env
        .objects
        .iter()
        .filter(|o| o.class == goal)
        .map(|o| [o.pose.x, o.pose.y])
        .collect();
    let start = &world.env.robot.start;
    let trav = Traversability::new(&world.truth, world.env.robot.radius, false);
    let shortest = targets
        .iter()
        .filter_map(|t| shortest_path(&trav, [start.x, start.y], *t, 1.5).map(|p| p.length))
        .min_by(f64::total_cmp);
    let reported = report
        .found
        .as_ref()
        .map(|f| [f.pose.x, f.pose.y, f.pose.z]);
    let error = reported.and_then(|r| {
        targets
            .iter()
            .map(|t| (r[0] - t[0]).hypot(r[1] - t[1]))
            .min_by(f64::total_cmp)
    });
    let found = error.is_some_and(|e| e <= SUCCESS_RADIUS);
    let path = report.metrics.path_length;
    let spl = match (found, shortest) {
        (true, Some(l)) if l.max(path) > 0.0 => l / l.max(path),
        (true, Some(_)) => 1.0,
        _ => 0.0,
    };
    let summary = Summary {
        found,
        reported_pose: reported,
        error,
        path_length: path,
        shortest_path_length: shortest,
        spl,
        plans: report.metrics.plans,
        dt_sessions: report.metrics.dt_sessions,
        plan_ms_median: median(&report.metrics.plan_ms),
        dt_ms_median: median(&report.metrics.dt_ms),
        reason: report.reason.clone(),
    };
    Ok((summary, report))
}

/// Print the trace (text, unless `quiet`) and write JSON lines to `json_file`, flushing each.
pub fn run_search(
    env: &Path,
    knowledge: &Path,
    domain: &Path,
    goal: &str,
    seed: u64,
    json_file: Option<&Path>,
    quiet: bool,
) -> anyhow::Result<Summary> {
    let mut file = match json_file {
        Some(p) => Some(std::io::BufWriter::new(
            std::fs::File::create(p).with_context(|| format!("creating {}", p.display()))?,
        )),
        None => None,
    };
    let mut write_err: Option<std::io::Error> = None;
    let stdout = std::io::stdout();
    let mut on_event = |e: &Event| {
        if !quiet {
            let mut out = stdout.lock();
            let _ = out.write_all(e.text().as_bytes());
            let _ = out.flush();
        }
        if let Some(f) = file.as_mut() {
            let r = writeln!(f, "{}", e.json_line()).and_then(|_| f.flush());
            if let Err(err) = r {
                write_err.get_or_insert(err);
            }
        }
    };
    let (summary, _) = search(env, knowledge, domain, goal, seed, &mut on_event)?;
    if let Some(e) = write_err {
        return Err(anyhow!("writing the trace: {e}"));
    }
    Ok(summary)
}

/// Run the subcommand.
pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let s = run_search(
        &a.env,
        &a.knowledge,
        &a.domain,
        &a.goal,
        a.seed,
        a.trace_json.as_deref(),
        a.json,
    )?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&s)?);
    } else {
        print_summary(&s);
    }
    Ok(if s.found {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// Print the summary as text.
pub fn print_summary(s: &Summary) {
    println!();
    println!("summary");
    println!("  found:                {}", s.found);
    if let Some(p) = s.reported_pose {
        println!(
            "  reported pose:        ({:.2}, {:.2}, {:.2})",
            p[0], p[1], p[2]
        );
    }
    if let Some(e) = s.error {
        println!("  error to true pose:   {e:.2} m");
    }
    println!("  path length:          {:.1} m", s.path_length);
    if let Some(l) = s.shortest_path_length {
        println!("  shortest path:        {l:.1} m");
    }
    println!("  SPL:                  {:.3}", s.spl);
    println!("  plans:                {}", s.plans);
    println!("  DT sessions:          {}", s.dt_sessions);
    println!("  plan time (median):   {:.1} ms", s.plan_ms_median);
    println!("  DT decision (median): {:.1} ms", s.dt_ms_median);
    println!("  ended:                {}", s.reason);
}
