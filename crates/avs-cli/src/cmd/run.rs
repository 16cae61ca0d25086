//! `avs run` — the default job: the agent searches the shipped office environment for the
//! cerealbox (knowledge `knowledge/office.yaml`, domain `domains/object_search.yaml`, seed 1),
//! printing the plan trace as it happens and a summary.

use super::search::{print_summary, run_search, Request};
use avs_eval::inputs::Shipped;
use std::path::PathBuf;
use std::process::ExitCode;

/// Flags (none required).
#[derive(clap::Args)]
pub struct Args {
    /// Write the plan trace as JSON lines to this file.
    #[arg(long)]
    pub trace_json: Option<PathBuf>,
    /// Draw the run as SVG to this file: world, trail, view cones, start, end, report, false
    /// alarms, with a title, a legend and a scale bar (`avs_sim::render::render_search`).
    #[arg(long)]
    pub svg: Option<PathBuf>,
}

/// Run the subcommand.
pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let (env, knowledge, domain) = (
        Shipped::Environment.input(),
        Shipped::Knowledge.input(),
        Shipped::Domain.input(),
    );
    let s = run_search(&Request {
        env: &env,
        knowledge: &knowledge,
        domain: &domain,
        goal: "cerealbox",
        seed: 1,
        strategy: Default::default(),
        zoom_pipeline: avs_agent::AgentConfig::default().zoom_pipeline,
        unfound_landmarks: avs_agent::AgentConfig::default().unfound_landmarks,
        objective: avs_agent::AgentConfig::default().planner.objective,
        wrong_report_price: avs_agent::AgentConfig::default().wrong_report_price,
        goal_in_look_around: avs_agent::AgentConfig::default().goal_in_look_around,
        faults: Default::default(),
        edits: Default::default(),
        before: &[],
        find_all: false,
        cover_before_giving_up: avs_agent::AgentConfig::default().cover_before_giving_up,
        place_classifier: false,
        json_file: a.trace_json.as_deref(),
        svg: a.svg.as_deref(),
        quiet: false,
    })?;
    print_summary(&s);
    Ok(if s.found {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
