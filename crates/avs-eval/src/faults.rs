//! The fault matrix (issue 18): generated floors × faults, each floor searched once per fault
//! by the planner with the robot seeded by the floor's seed, judged for what a deployed robot
//! must never do — crash, hang, give up without saying why, or report a wrong object.
//!
//! The faults ([`Fault::matrix`]):
//! * **action failures** at 10 % and 30 %: every motion and every view fails at that rate
//!   (`avs_sim::sim_robot::FailureRates`);
//! * **false positives** ×2 and ×5: the detector's false-alarm rate scaled;
//! * **a door closing early** (after [`EARLY_M`] of driving) and **late** (after [`LATE_M`]):
//!   every door of the rooms holding the goal's objects;
//! * **the target behind a closed door**: those doors closed from the start.
//!
//! The door faults leave alone a room the robot starts in (shutting the robot in with the
//! target tests nothing), and a floor whose goal objects all stand in such a room gets no
//! door fault ([`FaultRun::applicable`] is false).
//!
//! What each give-up must name ([`names_its_cause`]): under action failures, the failed
//! actions (or that the robot cannot move); under a door fault, a closed door it saw. A give-up
//! under false positives has no single cause to name. It may be an absent-looking target as on
//! an undisturbed floor, or sightings that a closer look did not confirm. The table counts how
//! many of those give-ups name unconfirmed sightings, and asserts nothing about them.

use crate::bench::{floor, goal_classes, goal_of_floor, BenchParams};
use crate::episode::{run_episode, EpisodeSpec, Faults};
use crate::EvalError;
use avs_agent::{AgentConfig, GiveUpReason, Strategy};
use avs_format::knowledge::Knowledge;
use avs_plan::domain::Domain;
use avs_sim::robot::DoorEvent;
use avs_sim::World;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeSet;
use std::path::Path;

/// Odometry at which an early door fault shuts the doors, metres: before the robot can have
/// reached the target's room on a generated floor.
pub const EARLY_M: f64 = 1.0;
/// Odometry at which a late door fault shuts the doors, metres: in the middle of a typical
/// search (the 50-floor bench's mean path is over 150 m, its shortest paths 5–25 m).
pub const LATE_M: f64 = 40.0;

/// One fault of the matrix.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Fault {
    /// Every motion and every view fails with this probability.
    ActionFailures {
        /// The failure probability.
        rate: f64,
    },
    /// The detector's false-alarm rate times `scale`.
    FalsePositives {
        /// The multiplier.
        scale: f64,
    },
    /// The doors of the target's rooms shut after [`EARLY_M`] of driving.
    DoorClosesEarly,
    /// The doors of the target's rooms shut after [`LATE_M`] of driving.
    DoorClosesLate,
    /// The doors of the target's rooms are closed from the start.
    TargetBehindClosedDoor,
}

impl Fault {
    /// The matrix's faults, in the order of its table.
    pub fn matrix() -> Vec<Fault> {
        vec![
            Fault::ActionFailures { rate: 0.1 },
            Fault::ActionFailures { rate: 0.3 },
            Fault::FalsePositives { scale: 2.0 },
            Fault::FalsePositives { scale: 5.0 },
            Fault::DoorClosesEarly,
            Fault::DoorClosesLate,
            Fault::TargetBehindClosedDoor,
        ]
    }

    /// A short label for tables.
    pub fn label(&self) -> String {
        match self {
            Fault::ActionFailures { rate } => format!("{:.0} % action failures", rate * 100.0),
            Fault::FalsePositives { scale } => format!("false positives ×{scale}"),
            Fault::DoorClosesEarly => format!("door closes after {EARLY_M} m"),
            Fault::DoorClosesLate => format!("door closes after {LATE_M} m"),
            Fault::TargetBehindClosedDoor => "target behind a closed door".into(),
        }
    }

    /// Whether the fault shuts doors.
    fn shuts_doors(&self) -> bool {
        matches!(
            self,
            Fault::DoorClosesEarly | Fault::DoorClosesLate | Fault::TargetBehindClosedDoor
        )
    }
}

/// What to run.
#[derive(Debug, Clone)]
pub struct FaultParams {
    /// Number of floors.
    pub floors: usize,
    /// Seed of the first floor (floor i uses seed S + i for the floor and the robot).
    pub seed: u64,
    /// Rooms per floor besides the corridor.
    pub rooms: usize,
    /// The faults (default: [`Fault::matrix`]).
    pub faults: Vec<Fault>,
    /// The agent's settings (the planner strategy is used whatever this says).
    pub config: AgentConfig,
}

/// One search under one fault.
#[derive(Debug, Clone, Serialize)]
pub struct FaultRun {
    /// Seed of the floor and the robot.
    pub seed: u64,
    /// The target class.
    pub goal: String,
    /// The fault.
    pub fault: Fault,
    /// False for a door fault on a floor where it shuts no door (see the module docs).
    pub applicable: bool,
    /// The doors the fault shut.
    pub doors: Vec<String>,
    /// Reported an object of the goal class within 1 m of a true one.
    pub found: bool,
    /// Reported an object more than 1 m from every true one.
    pub wrong_report: bool,
    /// Gave up.
    pub gave_up: bool,
    /// The give-up names what the fault did (see [`names_its_cause`]); `None` when the search
    /// did not give up or the fault has no single cause to name.
    pub cause_named: Option<bool>,
    /// The give-up names sightings a closer look did not confirm.
    pub names_unconfirmed: bool,
    /// Plans made.
    pub plans: usize,
    /// Actions executed (plan and coverage actions).
    pub actions: usize,
    /// Distance driven, m.
    pub path_length: f64,
    /// Wall-clock seconds of the search.
    pub compute_s: f64,
    /// Why the search ended.
    pub reason: String,
}

/// One row of the table: a fault over every floor it applies to.
#[derive(Debug, Clone, Serialize)]
pub struct FaultRow {
    /// The fault.
    pub fault: Fault,
    /// Its label.
    pub label: String,
    /// Runs (floors it applies to).
    pub runs: usize,
    /// Runs that found the target.
    pub found: usize,
    /// Runs that gave up.
    pub gave_up: usize,
    /// Give-ups that name their cause (of those with a cause to name).
    pub cause_named: usize,
    /// Give-ups with a cause to name.
    pub cause_expected: usize,
    /// Give-ups that name unconfirmed sightings.
    pub names_unconfirmed: usize,
    /// Runs that reported a wrong object.
    pub wrong_reports: usize,
    /// The slowest search's wall-clock seconds.
    pub slowest_s: f64,
    /// The most actions of one run.
    pub most_actions: usize,
}

/// The matrix: one row per fault, and every run.
#[derive(Debug, Clone, Serialize)]
pub struct FaultMatrix {
    /// Floors.
    pub floors: usize,
    /// Seed of the first floor.
    pub seed: u64,
    /// Rooms per floor.
    pub rooms: usize,
    /// One row per fault, in the order asked.
    pub rows: Vec<FaultRow>,
    /// Every run, by fault then seed.
    pub runs: Vec<FaultRun>,
}

/// Whether a give-up under `fault` names what the fault did: the failed actions (or a robot
/// that cannot move) under action failures, a closed door it saw under a door fault. `None`
/// for false positives, whose give-ups have no single cause (see the module docs).
pub fn names_its_cause(fault: &Fault, reason: &GiveUpReason) -> Option<bool> {
    let by = reason.hindrances();
    match fault {
        Fault::ActionFailures { .. } => {
            Some(reason.cannot_move() || by.is_some_and(|h| h.failed_actions.is_some()))
        }
        Fault::FalsePositives { .. } => None,
        Fault::DoorClosesEarly | Fault::DoorClosesLate | Fault::TargetBehindClosedDoor => {
            Some(by.is_some_and(|h| !h.closed_doors.is_empty()))
        }
    }
}

/// The doors of the rooms holding an object of `goal`, leaving out the rooms the robot starts
/// in (by the doors' `rooms` lists, which generated floors fill in).
fn doors_to_goal(world: &World, goal: &str) -> Vec<String> {
    let env = &world.env;
    let start = world
        .room_at(env.robot.start.x, env.robot.start.y)
        .and_then(|i| env.rooms.get(i))
        .map(|r| r.name.as_str());
    let rooms: BTreeSet<&str> = world
        .objects_of_class(goal)
        .map(|o| o.room.as_str())
        .filter(|r| Some(*r) != start)
        .collect();
    env.doors
        .iter()
        .filter(|d| d.open && d.rooms.iter().any(|r| rooms.contains(r.as_str())))
        .map(|d| d.name.clone())
        .collect()
}

/// One floor under one fault.
fn run_one(
    knowledge: &Knowledge,
    domain: &Domain,
    world: &World,
    goal: &str,
    seed: u64,
    fault: Fault,
    config: &AgentConfig,
) -> Result<FaultRun, EvalError> {
    let doors = if fault.shuts_doors() {
        doors_to_goal(world, goal)
    } else {
        Vec::new()
    };
    let applicable = !fault.shuts_doors() || !doors.is_empty();
    let mut faults = Faults::default();
    let shut = |after_m: f64| -> Vec<DoorEvent> {
        doors
            .iter()
            .map(|d| DoorEvent {
                door: d.clone(),
                after_m,
                open: false,
            })
            .collect()
    };
    let closed_world;
    let mut world = world;
    match fault {
        Fault::ActionFailures { rate } => faults.failure_rate = rate,
        Fault::FalsePositives { scale } => faults.fp_scale = Some(scale),
        Fault::DoorClosesEarly => faults.door_events = shut(EARLY_M),
        Fault::DoorClosesLate => faults.door_events = shut(LATE_M),
        Fault::TargetBehindClosedDoor => {
            let mut env = world.env.clone();
            for d in env.doors.iter_mut().filter(|d| doors.contains(&d.name)) {
                d.open = false;
            }
            closed_world = World::new(env, Path::new("."))
                .map_err(|e| EvalError::Sim(format!("floor {seed}, doors closed: {e}")))?;
            world = &closed_world;
        }
    }
    let spec = EpisodeSpec {
        knowledge,
        domain,
        goal,
        seed,
        config: AgentConfig {
            strategy: Strategy::Planner,
            ..config.clone()
        },
        before: &[],
        find_all: false,
        faults,
        place_classifier: false,
    };
    let out = run_episode(world, &spec, &mut |_| {})
        .map_err(|e| EvalError::Sim(format!("floor {seed}, {}: {e}", fault.label())))?;
    let gave_up = out.report.gave_up.as_ref();
    Ok(FaultRun {
        seed,
        goal: goal.to_string(),
        fault,
        applicable,
        doors,
        found: out.summary.found,
        wrong_report: out.summary.wrong_report,
        gave_up: gave_up.is_some(),
        cause_named: gave_up.and_then(|g| names_its_cause(&fault, g)),
        names_unconfirmed: gave_up
            .and_then(GiveUpReason::hindrances)
            .is_some_and(|h| h.unconfirmed > 0),
        plans: out.report.metrics.plans,
        actions: out.report.metrics.actions,
        path_length: out.summary.path_length,
        compute_s: out.summary.compute_s,
        reason: out.summary.reason,
    })
}

/// Run the matrix; `tick` is called after each run. Runs go in parallel (rayon); every figure
/// except the timings is independent of the scheduling.
pub fn fault_matrix(
    knowledge: &Knowledge,
    domain: &Domain,
    p: &FaultParams,
    tick: &(dyn Fn() + Sync),
) -> Result<FaultMatrix, EvalError> {
    let targets = goal_classes(knowledge, None)?;
    let bench = BenchParams {
        floors: p.floors,
        seed: p.seed,
        rooms: p.rooms,
        strategy: Strategy::Planner,
        misleading: false,
        goal: None,
        save_floors: None,
        place_classifier: false,
        lookalikes_per_room: avs_sim::generate::DEFAULT_LOOKALIKES_PER_ROOM,
        detector: Default::default(),
        zoom_pipeline: false,
        unfound_landmarks: AgentConfig::default().unfound_landmarks,
        objective: AgentConfig::default().planner.objective,
        wrong_report_price: AgentConfig::default().wrong_report_price,
        goal_in_look_around: AgentConfig::default().goal_in_look_around,
    };
    let floors: Vec<(u64, String, World)> = (0..p.floors as u64)
        .into_par_iter()
        .map(|i| {
            let s = p.seed + i;
            let g = goal_of_floor(&targets, None, s);
            floor(knowledge, s, &bench, &g, None).map(|w| (s, g, w))
        })
        .collect::<Result<_, _>>()?;
    let jobs: Vec<(usize, &(u64, String, World))> = (0..p.faults.len())
        .flat_map(|f| floors.iter().map(move |fl| (f, fl)))
        .collect();
    let runs: Vec<FaultRun> = jobs
        .into_par_iter()
        .map(|(f, (s, g, w))| {
            let r = run_one(knowledge, domain, w, g, *s, p.faults[f], &p.config);
            tick();
            r
        })
        .collect::<Result<_, _>>()?;
    let rows = p
        .faults
        .iter()
        .map(|fault| {
            let mine: Vec<&FaultRun> = runs
                .iter()
                .filter(|r| r.fault == *fault && r.applicable)
                .collect();
            let count = |f: &dyn Fn(&FaultRun) -> bool| mine.iter().filter(|r| f(r)).count();
            FaultRow {
                fault: *fault,
                label: fault.label(),
                runs: mine.len(),
                found: count(&|r| r.found),
                gave_up: count(&|r| r.gave_up),
                cause_named: count(&|r| r.cause_named == Some(true)),
                cause_expected: count(&|r| r.cause_named.is_some()),
                names_unconfirmed: count(&|r| r.names_unconfirmed),
                wrong_reports: count(&|r| r.wrong_report),
                slowest_s: mine.iter().map(|r| r.compute_s).fold(0.0, f64::max),
                most_actions: mine.iter().map(|r| r.actions).max().unwrap_or(0),
            }
        })
        .collect();
    Ok(FaultMatrix {
        floors: p.floors,
        seed: p.seed,
        rooms: p.rooms,
        rows,
        runs,
    })
}
