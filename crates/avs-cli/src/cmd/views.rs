//! `avs views ENV.yaml --room NAME --classes A,B,… [--knowledge K] [--k K] [--spacing M]
//! [--optimal] [--measured] [--svg F] [--json]`: the view plan of one room for several classes at once
//! (Sjöö et al. `004` §2.1; [`avs_eval::views`]): standpoints used, searches, the share of each
//! class's cells covered, and with `--optimal` the exact optimum's searches beside the greedy's.

use anyhow::Context;
use avs_eval::inputs::{Input, Shipped};
use avs_eval::views::{plan_room, ViewsRequest};
use std::path::PathBuf;
use std::process::ExitCode;

/// Flags.
#[derive(clap::Args)]
pub struct Args {
    /// The environment file.
    pub env: PathBuf,
    /// The room to plan for (`rooms[].name`).
    #[arg(long)]
    pub room: String,
    /// The object classes sought, comma-separated (names of the knowledge's classes).
    #[arg(long, value_delimiter = ',', required = true)]
    pub classes: Vec<String>,
    /// The knowledge file (default: the shipped office knowledge).
    #[arg(long)]
    pub knowledge: Option<PathBuf>,
    /// How many images must see each (class, cell) pair.
    #[arg(long, default_value_t = 1)]
    pub k: usize,
    /// Spacing of the standpoint lattice over the room's floor, metres.
    #[arg(long, default_value_t = 1.0)]
    pub spacing: f64,
    /// Also compute the exact optimum (a 0/1 program) and the greedy's gap to it.
    #[arg(long)]
    pub optimal: bool,
    /// Branch-and-bound nodes the exact optimum may use.
    #[arg(long, default_value_t = avs_eval::views::DEFAULT_NODE_LIMIT)]
    pub optimal_nodes: u64,
    /// Plan each class within the range where a look of the zoom pipeline finds it at least
    /// half the time, measured on the simulated camera per zoom level
    /// (`avs_eval::zoom_sensing`), instead of the limits eq. 1 and the vote cell give.
    #[arg(long)]
    pub measured: bool,
    /// Write the plan as SVG to this file.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Run `avs views`.
pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let env = Input::read(&a.env)?;
    let knowledge = Input::or_shipped(a.knowledge.as_deref(), Shipped::Knowledge)?;
    let k = knowledge.knowledge()?;
    // The environment gets `avs validate --knowledge`'s checks, class names included.
    let world = env.edited_world(Some(&k), &Default::default(), |_| String::new())?;
    let request = ViewsRequest {
        room: a.room.clone(),
        classes: a.classes.clone(),
        k: a.k,
        spacing: a.spacing,
        optimal: a.optimal.then_some(a.optimal_nodes),
        measured: if a.measured {
            avs_eval::zoom_sensing::measured_sensing(
                &k,
                &avs_agent::Camera::from(&world.env.camera),
                &avs_agent::AgentConfig::default().zoom,
            )?
        } else {
            Vec::new()
        },
    };
    let started = std::time::Instant::now();
    let (problem, plan, report) = plan_room(&world, &k, &request)?;
    let seconds = started.elapsed().as_secs_f64();
    if let Some(path) = &a.svg {
        let svg = avs_eval::views::render_svg(&world, &problem, &plan);
        std::fs::write(path, svg).with_context(|| format!("writing {}", path.display()))?;
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(ExitCode::SUCCESS);
    }
    println!(
        "room {} ({:.1} m²): {} cells, {} standpoints, {} used; {} searches ({:.1} ms)",
        report.room,
        report.area,
        report.cells.len(),
        report.standpoints.len(),
        report.standpoints_used.len(),
        report.searches,
        seconds * 1e3
    );
    for (class, share) in &report.coverage {
        println!("  {class}: {:.0} % of its cells covered", 100.0 * share);
    }
    if report.uncoverable > 0 {
        println!(
            "  {} (class, cell) pairs no standpoint sees",
            report.uncoverable
        );
    }
    if let (Some(opt), Some(proven)) = (report.optimal_searches, report.optimal_proven) {
        println!(
            "  optimum: {opt} searches{} (greedy {:+.0} %)",
            if proven {
                ""
            } else {
                ", not proven within the node limit"
            },
            100.0 * (report.searches as f64 / opt.max(1) as f64 - 1.0)
        );
    }
    for (i, v) in report.views.iter().enumerate() {
        println!(
            "  {:>2}. at ({:.2}, {:.2}) look {:>6.1}° tilt {:>5.1}° zoom {:>2}×: {}",
            i + 1,
            v.at[0],
            v.at[1],
            v.yaw_deg,
            v.tilt_deg,
            v.zoom,
            v.classes.join(", ")
        );
    }
    Ok(ExitCode::SUCCESS)
}
