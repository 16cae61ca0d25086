//! The search bench: generated floors (`avs_sim::generate` with seeds S, S+1, …), each with a
//! target object — the class drawn uniformly from the knowledge's non-landmark classes unless
//! fixed, placed where the knowledge's rates say, or in the room they make least likely
//! (`misleading`) — searched by one strategy with the robot seeded by the floor's seed.
//! Success rate and SPL are over the floors whose target is reachable from the start. Floors
//! run in parallel (rayon); every figure except the timings is independent of the scheduling.

use crate::episode::{run_episode, EpisodeSpec, Faults, Summary};
use crate::stats::{mean, median};
use crate::EvalError;
use avs_agent::{AgentConfig, PathBreakdown, Strategy};
use avs_format::knowledge::Knowledge;
use avs_plan::domain::Domain;
use avs_sim::generate::{generate, GenerateParams, Placement};
use avs_sim::World;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// What to bench.
#[derive(Debug, Clone)]
pub struct BenchParams {
    /// Number of floors.
    pub floors: usize,
    /// Seed of the first floor (floor i uses seed S + i for the floor and the robot).
    pub seed: u64,
    /// Rooms per floor besides the corridor.
    pub rooms: usize,
    /// The strategy searching.
    pub strategy: Strategy,
    /// Put each target in the room the knowledge makes least likely.
    pub misleading: bool,
    /// Search this class on every floor (default: drawn per floor).
    pub goal: Option<String>,
    /// Write each floor's environment to `DIR/floor-SEED.yaml`.
    pub save_floors: Option<PathBuf>,
    /// Whether the simulated robot has its place classifier (off by default).
    pub place_classifier: bool,
    /// Look-alikes per room on the generated floors (Poisson mean;
    /// `avs_sim::generate::DEFAULT_LOOKALIKES_PER_ROOM` by default).
    pub lookalikes_per_room: f64,
    /// The simulated robot's detector.
    pub detector: avs_sim::sim_robot::DetectorKind,
    /// Whether the agent's looks run the zoom pipeline ([`AgentConfig::zoom_pipeline`]).
    pub zoom_pipeline: bool,
    /// Whether rooms count their landmarks not found yet ([`AgentConfig::unfound_landmarks`]).
    pub unfound_landmarks: bool,
    /// Which plan the planner starts (`AgentConfig::planner`'s `objective`).
    pub objective: avs_plan::continual::Objective,
    /// What a wrong report costs the verifier, in failed searches
    /// (`AgentConfig::wrong_report_price`).
    pub wrong_report_price: f64,
    /// Whether a look around also looks for the goal (`AgentConfig::goal_in_look_around`).
    pub goal_in_look_around: bool,
}

/// One floor's run.
#[derive(Debug, Clone, Serialize)]
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

/// The bench's figures.
#[derive(Debug, Clone, Serialize)]
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
    /// Mean SoftSPL over the reachable floors (habitat's convention, see [`Summary`]).
    pub soft_spl_mean: f64,
    /// Runs (reachable or not) that reported an object more than 1 m from every true one.
    pub wrong_reports: usize,
    /// Mean distance driven over the reachable floors, m.
    pub path_length_mean: f64,
    /// Mean metres per activity over the reachable floors.
    pub path_by_activity_mean: PathBreakdown,
    /// Mean number of entries into a room already left before, over the reachable floors.
    pub room_revisits_mean: f64,
    /// Mean number of plans over the reachable floors.
    pub plans_mean: f64,
    /// Mean camera images processed per search (reachable floors).
    pub images_mean: f64,
    /// Mean zoom-pipeline images after a look's first, per search (reachable floors).
    pub zoom_images_mean: f64,
    /// Median planning time over every plan of every run, ms.
    pub plan_ms_median: f64,
    /// The longest search's wall-clock seconds (see [`crate::episode::Summary::compute_s`]).
    pub compute_s_max: f64,
    /// Seed of the first floor.
    pub seed: u64,
    /// Rooms per floor.
    pub rooms: usize,
    /// Whether targets were put where the knowledge makes them least likely.
    pub misleading: bool,
    /// Every run, by seed.
    pub runs: Vec<BenchRun>,
}

/// Floor `seed` with a `goal` object, saved to `save` when given.
pub(crate) fn floor(
    k: &Knowledge,
    seed: u64,
    p: &BenchParams,
    goal: &str,
    save: Option<&Path>,
) -> Result<World, EvalError> {
    let failed = |message: String| EvalError::Sim(format!("floor {seed}: {message}"));
    let env = generate(
        k,
        &GenerateParams {
            seed,
            rooms: p.rooms,
            ensure_class: Some(goal.to_string()),
            placement: if p.misleading {
                Placement::Unlikely
            } else {
                Placement::AsKnowledge
            },
            lookalikes_per_room: p.lookalikes_per_room,
        },
    )
    .map_err(|e| failed(format!("generating: {e}")))?;
    if let Some(dir) = save {
        let path = dir.join(format!("floor-{seed}.yaml"));
        let yaml = serde_yaml::to_string(&env).map_err(|e| failed(e.to_string()))?;
        let text = format!(
            "# Floor {seed} of `avs bench --rooms {}{}`; target {goal}.\n{yaml}",
            p.rooms,
            if p.misleading { " --misleading" } else { "" },
        );
        std::fs::write(&path, text)
            .map_err(|e| failed(format!("writing {}: {e}", path.display())))?;
    }
    World::new(env, Path::new(".")).map_err(|e| failed(e.to_string()))
}

/// Run the bench; `tick` is called after each floor.
pub fn bench(
    knowledge: &Knowledge,
    domain: &Domain,
    p: &BenchParams,
    tick: &(dyn Fn() + Sync),
) -> Result<BenchResult, EvalError> {
    let targets = goal_classes(knowledge, p.goal.as_deref())?;
    let mut config = AgentConfig {
        strategy: p.strategy,
        zoom_pipeline: p.zoom_pipeline,
        unfound_landmarks: p.unfound_landmarks,
        ..AgentConfig::default()
    };
    config.planner.objective = p.objective;
    config.wrong_report_price = p.wrong_report_price;
    config.goal_in_look_around = p.goal_in_look_around;
    if p.zoom_pipeline {
        // The pipeline's ranges and rates, measured once on the simulated camera (every
        // generated floor has the default camera).
        config.measured_sensing = crate::zoom_sensing::measured_sensing(
            knowledge,
            &avs_robot::Camera::default(),
            &config.zoom,
        )?;
    }
    let mut runs: Vec<BenchRun> = (0..p.floors as u64)
        .into_par_iter()
        .map(|i| -> Result<BenchRun, EvalError> {
            let s = p.seed + i;
            let g = goal_of_floor(&targets, p.goal.as_deref(), s);
            let world = floor(knowledge, s, p, &g, p.save_floors.as_deref())?;
            let spec = EpisodeSpec {
                knowledge,
                domain,
                goal: &g,
                seed: s,
                config: config.clone(),
                before: &[],
                find_all: false,
                faults: Faults {
                    detector: p.detector,
                    ..Faults::default()
                },
                place_classifier: p.place_classifier,
            };
            let out = run_episode(&world, &spec, &mut |_| {})
                .map_err(|e| EvalError::Sim(format!("floor {s}: {e}")))?;
            tick();
            Ok(BenchRun {
                seed: s,
                goal: g,
                reachable: out.summary.shortest_path_length.is_some(),
                summary: out.summary,
                plan_ms: out.report.metrics.plan_ms,
            })
        })
        .collect::<Result<_, _>>()?;
    runs.sort_by_key(|r| r.seed);
    let ok: Vec<&BenchRun> = runs.iter().filter(|r| r.reachable).collect();
    let plan_ms: Vec<f64> = runs
        .iter()
        .flat_map(|r| r.plan_ms.iter().copied())
        .collect();
    Ok(BenchResult {
        strategy: p.strategy,
        floors: p.floors,
        reachable: ok.len(),
        success_rate: mean(&ok, |r| f64::from(u8::from(r.summary.found))),
        spl_mean: mean(&ok, |r| r.summary.spl),
        soft_spl_mean: mean(&ok, |r| r.summary.soft_spl),
        wrong_reports: runs.iter().filter(|r| r.summary.wrong_report).count(),
        path_length_mean: mean(&ok, |r| r.summary.path_length),
        path_by_activity_mean: PathBreakdown {
            exploration: mean(&ok, |r| r.summary.path_by_activity.exploration),
            view_cones: mean(&ok, |r| r.summary.path_by_activity.view_cones),
            verification: mean(&ok, |r| r.summary.path_by_activity.verification),
            coverage: mean(&ok, |r| r.summary.path_by_activity.coverage),
        },
        room_revisits_mean: mean(&ok, |r| r.summary.room_revisits as f64),
        plans_mean: mean(&ok, |r| r.summary.plans as f64),
        images_mean: mean(&ok, |r| r.summary.images as f64),
        zoom_images_mean: mean(&ok, |r| r.summary.zoom_images as f64),
        plan_ms_median: median(&plan_ms),
        compute_s_max: runs.iter().map(|r| r.summary.compute_s).fold(0.0, f64::max),
        seed: p.seed,
        rooms: p.rooms,
        misleading: p.misleading,
        runs,
    })
}

/// The classes a bench may search for: the knowledge's non-landmark classes. An error when
/// `goal` (the class fixed for every floor) is not a class of the knowledge, or when there is
/// none to draw from.
pub(crate) fn goal_classes<'k>(
    knowledge: &'k Knowledge,
    goal: Option<&str>,
) -> Result<Vec<&'k str>, EvalError> {
    let targets: Vec<&str> = knowledge
        .object_classes
        .iter()
        .filter(|c| !c.landmark)
        .map(|c| c.name.as_str())
        .collect();
    if let Some(g) = goal {
        if knowledge.class(g).is_none() {
            return Err(EvalError::Field {
                file: "bench".into(),
                field: format!("--goal {g}"),
                message: format!(
                    "not an object class of the knowledge file; expected one of {}",
                    targets.join(", ")
                ),
            });
        }
    }
    if goal.is_none() && targets.is_empty() {
        return Err(EvalError::Field {
            file: "bench".into(),
            field: "knowledge".into(),
            message: "the knowledge file has no non-landmark object class to search for".into(),
        });
    }
    Ok(targets)
}

/// The class searched on floor `seed`: `goal` when fixed, else drawn uniformly from `targets`
/// by the floor's seed.
pub(crate) fn goal_of_floor(targets: &[&str], goal: Option<&str>, seed: u64) -> String {
    match goal {
        Some(g) => g.to_string(),
        None => {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            targets[rng.gen_range(0..targets.len())].to_string()
        }
    }
}
