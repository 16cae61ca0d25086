//! `avs search --env E --knowledge K --domain D --goal CLASS [--seed N] [--trace-json F]
//! [--svg F] [--json] [--strategy planner|uninformed|frontier] [--failure-rate P]
//! [--fp-scale X] [--close-door NAME@METRES]...`
//!
//! One object search by the agent in the simulated environment (an `avs_eval` episode), with the
//! plan trace printed as it happens and a summary. The agent never sees ground truth; this command reads it only to
//! score the result (error of the reported pose, shortest path, SPL).

use anyhow::{anyhow, Context};
use avs_agent::{AgentConfig, Event, Strategy};
use avs_eval::episode::{load_inputs, run_episode, EpisodeSpec};
pub use avs_eval::episode::{Faults, Summary};
use avs_sim::robot::DoorEvent;
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
    /// Draw the run (world, robot trail, reported position) as SVG to this file.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Print only the summary, as JSON.
    #[arg(long)]
    pub json: bool,
    /// planner | uninformed | frontier.
    #[arg(long, default_value = "planner")]
    pub strategy: Strategy,
    /// Fault injection: probability that a motion or a view fails.
    #[arg(long, default_value_t = 0.0)]
    pub failure_rate: f64,
    /// Fault injection: multiply the knowledge's false-positive rate (2 doubles false alarms).
    #[arg(long, default_value_t = 1.0)]
    pub fp_scale: f64,
    /// Fault injection: close door NAME once the robot has driven METRES (repeatable).
    #[arg(long, value_name = "NAME@METRES", value_parser = parse_door_event)]
    pub close_door: Vec<DoorEvent>,
}

/// `NAME@METRES` → a door-closing event.
fn parse_door_event(s: &str) -> Result<DoorEvent, String> {
    let (name, m) = s
        .rsplit_once('@')
        .ok_or_else(|| format!("`{s}`: expected NAME@METRES, e.g. door_kitchen@12.5"))?;
    let after_m: f64 = m
        .parse()
        .map_err(|_| format!("`{s}`: `{m}` is not a number of metres"))?;
    if name.is_empty() || !after_m.is_finite() || after_m < 0.0 {
        return Err(format!(
            "`{s}`: expected a door name and a finite, non-negative number of metres"
        ));
    }
    Ok(DoorEvent {
        door: name.to_string(),
        after_m,
        open: false,
    })
}

/// What to search, and how to report it.
pub struct Request<'a> {
    /// Environment file.
    pub env: &'a Path,
    /// Knowledge file.
    pub knowledge: &'a Path,
    /// Planning domain file.
    pub domain: &'a Path,
    /// Object class.
    pub goal: &'a str,
    /// Robot seed.
    pub seed: u64,
    /// Strategy.
    pub strategy: Strategy,
    /// Fault injection.
    pub faults: Faults,
    /// JSON-lines trace file.
    pub json_file: Option<&'a Path>,
    /// SVG picture of the run.
    pub svg: Option<&'a Path>,
    /// Print no trace.
    pub quiet: bool,
}

/// Print the trace (text, unless `quiet`), write JSON lines to `json_file` (flushing each) and
/// the picture to `svg`.
pub fn run_search(r: &Request) -> anyhow::Result<Summary> {
    let Request {
        env,
        knowledge,
        domain,
        goal,
        seed,
        json_file,
        quiet,
        ..
    } = *r;
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
    let (world, k, d) = load_inputs(env, knowledge, domain)?;
    let spec = EpisodeSpec {
        knowledge: &k,
        domain: &d,
        goal,
        seed,
        config: AgentConfig {
            strategy: r.strategy,
            ..AgentConfig::default()
        },
        faults: r.faults.clone(),
    };
    let out = run_episode(&world, &spec, &mut on_event)
        .with_context(|| format!("searching {}", env.display()))?;
    if let Some(e) = write_err {
        return Err(anyhow!("writing the trace: {e}"));
    }
    if let Some(p) = r.svg {
        let pic = avs_sim::render::render_search(
            &world,
            goal,
            &out.trail,
            out.summary.reported_pose,
            avs_sim::score::SUCCESS_RADIUS,
        );
        std::fs::write(p, pic).with_context(|| format!("writing {}", p.display()))?;
    }
    Ok(out.summary)
}

/// Run the subcommand.
pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    anyhow::ensure!(
        (0.0..=1.0).contains(&a.failure_rate),
        "--failure-rate {}: expected a probability in [0, 1]",
        a.failure_rate
    );
    anyhow::ensure!(
        a.fp_scale.is_finite() && a.fp_scale >= 0.0,
        "--fp-scale {}: expected a finite number ≥ 0",
        a.fp_scale
    );
    let s = run_search(&Request {
        env: &a.env,
        knowledge: &a.knowledge,
        domain: &a.domain,
        goal: &a.goal,
        seed: a.seed,
        strategy: a.strategy,
        faults: Faults {
            failure_rate: a.failure_rate,
            fp_scale: Some(a.fp_scale),
            door_events: a.close_door.clone(),
        },
        json_file: a.trace_json.as_deref(),
        svg: a.svg.as_deref(),
        quiet: a.json,
    })?;
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
    let by = &s.path_by_activity;
    println!(
        "    by activity:        exploration {:.1} m, view cones {:.1} m, verification {:.1} m, coverage {:.1} m",
        by.exploration, by.view_cones, by.verification, by.coverage
    );
    println!(
        "  rooms:                {} visited, {} revisits",
        s.rooms_visited, s.room_revisits
    );
    if let Some(d) = s.distance_to_goal {
        println!("  distance to goal:     {d:.1} m at the end");
    }
    println!("  SPL:                  {:.3}", s.spl);
    println!("  SoftSPL:              {:.3}", s.soft_spl);
    if s.wrong_report {
        println!("  WRONG REPORT:         no object of the class within 1 m of the report");
    }
    println!("  plans:                {}", s.plans);
    println!("  DT sessions:          {}", s.dt_sessions);
    println!("  plan time (median):   {:.1} ms", s.plan_ms_median);
    println!("  DT decision (median): {:.1} ms", s.dt_ms_median);
    println!("  ended:                {}", s.reason);
}
