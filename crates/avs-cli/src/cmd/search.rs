//! `avs search [--env E] [--knowledge K] [--domain D] --goal CLASS [--seed N] [--trace-json F]
//! [--svg F] [--json] [--strategy planner|uninformed|frontier|informed] [--failure-rate P]
//! [--fp-scale X] [--close-door NAME[@METRES]]... [--start X,Y,YAW_DEG] [--remove CLASS_OR_ID]...
//! [--before CLASS]... [--find-all] [--give-up paper|cover]`
//!
//! Exit status: 0 found, 3 searched and not found, 1 invalid input, 2 usage.
//!
//! `--env`, `--knowledge` and `--domain` default to the shipped office, its knowledge and the
//! object-search domain: the files of the checkout in the current directory when there is one,
//! else the copies built into the binary (`avs_eval::inputs`).
//!
//! One object search by the agent in the simulated environment (an `avs_eval` episode), with the
//! plan trace printed as it happens and a summary. The agent never sees ground truth; this command reads it only to
//! score the result (error of the reported pose, shortest path, SPL).

use anyhow::{anyhow, Context};
use avs_agent::{AgentConfig, Event, Strategy};
use avs_eval::edits::{EditField, RemoveObjects, Start, WorldEdits};
use avs_eval::episode::{run_episode, EpisodeSpec};
pub use avs_eval::episode::{Faults, Summary};
use avs_eval::inputs::{Input, Shipped};
use avs_sim::robot::DoorEvent;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Flags.
#[derive(clap::Args)]
pub struct Args {
    /// The environment file (default: the shipped office).
    #[arg(long)]
    pub env: Option<PathBuf>,
    /// The knowledge file (default: the shipped office knowledge).
    #[arg(long)]
    pub knowledge: Option<PathBuf>,
    /// The planning domain file (default: the shipped object-search domain).
    #[arg(long)]
    pub domain: Option<PathBuf>,
    /// The object class to find.
    #[arg(long)]
    pub goal: String,
    /// Seed of the simulated robot (sensor noise, action failures).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Write the plan trace as JSON lines to this file, flushed as events happen.
    #[arg(long)]
    pub trace_json: Option<PathBuf>,
    /// Draw the run as SVG to this file: world, trail, view cones, start, end, report, false
    /// alarms, with a title, a legend and a scale bar (`avs_sim::render::render_search`).
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Print only the summary, as JSON.
    #[arg(long)]
    pub json: bool,
    /// planner | uninformed | frontier | informed (told the target's room: a reference).
    #[arg(long, default_value = "planner")]
    pub strategy: Strategy,
    /// Fault injection: probability that a motion or a view fails.
    #[arg(long, default_value_t = 0.0)]
    pub failure_rate: f64,
    /// Fault injection: multiply the knowledge's false-positive rate (2 doubles false alarms).
    #[arg(long, default_value_t = 1.0)]
    pub fp_scale: f64,
    /// Close door NAME from the start, or (NAME@METRES, fault injection) once the robot has
    /// driven METRES (repeatable).
    #[arg(long, value_name = "NAME[@METRES]", value_parser = parse_door)]
    pub close_door: Vec<DoorClosing>,
    /// Start the robot here instead of the environment's start pose.
    #[arg(long, value_name = "X,Y,YAW_DEG", value_parser = parse_start)]
    pub start: Option<Start>,
    /// Take an object out of the world (with what stands on or lies in it): an object id, or
    /// every object of a class (repeatable).
    #[arg(long, value_name = "CLASS_OR_ID")]
    pub remove: Vec<String>,
    /// Search for these classes first with the same agent, in order (repeatable); the summary
    /// is the goal's search.
    #[arg(long, value_name = "CLASS")]
    pub before: Vec<String>,
    /// Seek the `--before` classes and the goal at once (`Goal::find_all`): every look also
    /// runs the detector for the classes not searched yet, and each search first verifies
    /// what earlier looks saw of its class.
    #[arg(long)]
    pub find_all: bool,
    /// When the planner gives up: `paper` ends the search there (the paper's threshold, or
    /// no plan worth its cost by the paper's objective), `cover` first covers what no search
    /// has looked at.
    #[arg(long, value_enum, default_value_t = GiveUp::Cover)]
    pub give_up: GiveUp,
    /// Give the simulated robot its place classifier (size, shape, appearance readings as
    /// evidence on room categories; off by default).
    #[arg(long)]
    pub place_classifier: bool,
    /// The simulated robot's object detector.
    #[arg(long, value_enum, default_value_t = DetectorArg::default())]
    pub detector: DetectorArg,
    /// The planner's model: `--unfound-landmarks`, `--objective`.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Looks run the zoom pipeline (attention, zoom windows, three-step search, recognition)
    /// instead of the one-shot detector; the trace shows each zoomed image (`ZOOM …`).
    #[arg(long)]
    pub zoom: bool,
}

/// The simulated robot's object detector (`--detector`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum DetectorArg {
    /// Every view an independent draw from the knowledge file's sensor model.
    #[default]
    Independent,
    /// Scores correlated over nearby vantage points (Velez et al. 2012); detections fire on
    /// them. A knowledge file's `sensor.correlation` tells the `sequential` verifier to take
    /// each closer look from a new vantage point.
    Correlated,
}

impl From<DetectorArg> for avs_sim::sim_robot::DetectorKind {
    fn from(d: DetectorArg) -> Self {
        match d {
            DetectorArg::Independent => Self::Independent,
            DetectorArg::Correlated => Self::Correlated,
        }
    }
}

/// The planner's model options of `avs search` and `avs bench`.
#[derive(Debug, Clone, clap::Args)]
pub struct ModelArgs {
    /// Rooms count the landmarks not found yet in their chance of holding the object, and a
    /// room behind a placeholder all it is expected to hold (`002` §III-A's whole hierarchy;
    /// on by default, `--unfound-landmarks false` turns it off; see BENCHMARKS.md).
    #[arg(long, value_name = "BOOL", num_args = 0..=1, default_value_t = true,
          default_missing_value = "true", action = clap::ArgAction::Set)]
    pub unfound_landmarks: bool,
    /// Which plan the planner starts: `fixed` (the paper's R) or `ratio` (the most success
    /// probability per unit of cost, the default).
    #[arg(long, value_enum, default_value_t = ObjectiveArg::default())]
    pub objective: ObjectiveArg,
    /// What a wrong report costs the `sequential` verifier, in failed searches (at least 1):
    /// the higher, the surer it must be of a candidate before reporting it, and the more
    /// closer looks a real target needs (see `AgentConfig::wrong_report_price`).
    #[arg(long, value_name = "FAILED_SEARCHES", value_parser = parse_wrong_report_price,
          default_value_t = AgentConfig::default().wrong_report_price)]
    pub wrong_report_price: f64,
    /// Every look around on entering a room also looks for the goal, and a target seen then
    /// is verified and reported at once (on by default; `--goal-in-look-around false` looks
    /// for landmarks only, as the paper's robot did).
    #[arg(long, value_name = "BOOL", num_args = 0..=1, default_value_t = true,
          default_missing_value = "true", action = clap::ArgAction::Set)]
    pub goal_in_look_around: bool,
}

/// `--wrong-report-price`: a finite number of failed searches, at least 1.
fn parse_wrong_report_price(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .parse()
        .map_err(|_| format!("`{s}` is not a number (expected failed searches, at least 1)"))?;
    if v.is_finite() && v >= 1.0 {
        Ok(v)
    } else {
        Err(format!(
            "{v}: a wrong report costs at least one failed search (expected a finite number ≥ 1)"
        ))
    }
}

/// Which plan the planner starts (`--objective`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum ObjectiveArg {
    /// The best for the paper's fixed reward R.
    Fixed,
    /// The one with the most success probability per unit of cost (Dinkelbach's iteration;
    /// the default).
    #[default]
    Ratio,
}

impl From<ObjectiveArg> for avs_plan::continual::Objective {
    fn from(o: ObjectiveArg) -> Self {
        match o {
            ObjectiveArg::Fixed => Self::Fixed,
            ObjectiveArg::Ratio => Self::Ratio,
        }
    }
}

/// What the agent does when the planner gives up.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum GiveUp {
    /// End the search (the paper's threshold, or no plan worth its cost).
    Paper,
    /// Cover what no search has looked at first.
    Cover,
}

/// A door to close: from the start, or during the run.
#[derive(Debug, Clone)]
pub enum DoorClosing {
    /// Closed before the search starts.
    AtStart(String),
    /// Closed once the robot has driven some distance (fault injection).
    During(DoorEvent),
}

/// `NAME` or `NAME@METRES`.
fn parse_door(s: &str) -> Result<DoorClosing, String> {
    if s.contains('@') {
        parse_door_event(s).map(DoorClosing::During)
    } else if s.is_empty() {
        Err("expected a door name, or NAME@METRES".into())
    } else {
        Ok(DoorClosing::AtStart(s.to_string()))
    }
}

/// `X,Y,YAW_DEG` (metres, metres, degrees).
fn parse_start(s: &str) -> Result<Start, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("`{s}`: expected X,Y,YAW_DEG, three numbers, e.g. 2.5,3,90"))?;
    match v[..] {
        [x, y, yaw_deg] if v.iter().all(|n| n.is_finite()) => Ok(Start { x, y, yaw_deg }),
        _ => Err(format!(
            "`{s}`: expected X,Y,YAW_DEG, three finite numbers, e.g. 2.5,3,90"
        )),
    }
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
    pub env: &'a Input,
    /// Knowledge file.
    pub knowledge: &'a Input,
    /// Planning domain file.
    pub domain: &'a Input,
    /// Object class.
    pub goal: &'a str,
    /// Robot seed.
    pub seed: u64,
    /// Strategy.
    pub strategy: Strategy,
    /// Looks run the zoom pipeline.
    pub zoom_pipeline: bool,
    /// Rooms count their landmarks not found yet.
    pub unfound_landmarks: bool,
    /// Which plan the planner starts.
    pub objective: avs_plan::continual::Objective,
    /// What a wrong report costs the verifier, in failed searches.
    pub wrong_report_price: f64,
    /// Whether a look around also looks for the goal.
    pub goal_in_look_around: bool,
    /// Fault injection.
    pub faults: Faults,
    /// World edits before the search.
    pub edits: WorldEdits,
    /// Classes searched for first by the same agent.
    pub before: &'a [String],
    /// `before` and the goal sought at once.
    pub find_all: bool,
    /// Cover what no search has looked at before giving up.
    pub cover_before_giving_up: bool,
    /// Give the simulated robot its place classifier.
    pub place_classifier: bool,
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
    // Output paths are checked before the search, not after it.
    if let Some(p) = r.svg {
        std::fs::File::create(p).with_context(|| format!("creating {}", p.display()))?;
    }
    let mut file = match json_file {
        Some(p) => Some(std::io::BufWriter::new(
            std::fs::File::create(p).with_context(|| format!("creating {}", p.display()))?,
        )),
        None => None,
    };
    let (k, d) = (knowledge.knowledge()?, domain.domain()?);
    // The environment gets `avs validate --knowledge`'s checks, class names included.
    let world = env.edited_world(Some(&k), &r.edits, |f| match f {
        EditField::CloseDoor(i) => format!("--close-door #{}", i + 1),
        EditField::RemoveClass(i) | EditField::RemoveId(i) => format!("--remove #{}", i + 1),
    })?;
    let mut write_err: Option<std::io::Error> = None;
    let stdout = std::io::stdout();
    // Every event of the run (the `--before` searches' too), for the picture.
    let mut events: Vec<Event> = Vec::new();
    let mut on_event = |e: &Event| {
        if r.svg.is_some() {
            events.push(e.clone());
        }
        if !quiet {
            let mut out = stdout.lock();
            let _ = out.write_all(e.text().as_bytes());
            // In simulation the agent's rooms can be named: the true room the robot stood in
            // when it looked around (the agent itself never sees the truth).
            if let Event::LookedAround { room, at, .. } = e {
                if let Some(t) = world
                    .room_at(at[0], at[1])
                    .and_then(|i| world.env.rooms.get(i))
                {
                    let _ = writeln!(
                        out,
                        "    (truth: room{room} is in `{}`, a {})",
                        t.name, t.category
                    );
                }
            }
            let _ = out.flush();
        }
        if let Some(f) = file.as_mut() {
            let r = writeln!(f, "{}", e.json_line()).and_then(|_| f.flush());
            if let Err(err) = r {
                write_err.get_or_insert(err);
            }
        }
    };
    for class in r.before.iter().chain([&goal.to_string()]) {
        anyhow::ensure!(
            k.class(class).is_some(),
            "--before/--goal {class}: not an object class of {}; expected one of {}",
            knowledge.name,
            k.object_classes
                .iter()
                .map(|c| c.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let mut config = AgentConfig {
        strategy: r.strategy,
        cover_before_giving_up: r.cover_before_giving_up,
        zoom_pipeline: r.zoom_pipeline,
        unfound_landmarks: r.unfound_landmarks,
        wrong_report_price: r.wrong_report_price,
        goal_in_look_around: r.goal_in_look_around,
        ..AgentConfig::default()
    };
    config.planner.objective = r.objective;
    if r.zoom_pipeline {
        // The pipeline's ranges and rates, measured on this world's simulated camera.
        config.measured_sensing = avs_eval::zoom_sensing::measured_sensing(
            &k,
            &avs_agent::Camera::from(&world.env.camera),
            &config.zoom,
        )?;
    }
    let spec = EpisodeSpec {
        knowledge: &k,
        domain: &d,
        goal,
        seed,
        config,
        faults: r.faults.clone(),
        before: r.before,
        find_all: r.find_all,
        place_classifier: r.place_classifier,
    };
    let out = run_episode(&world, &spec, &mut on_event)
        .with_context(|| format!("searching {}", env.name))?;
    if let Some(e) = write_err {
        return Err(anyhow!("writing the trace: {e}"));
    }
    if let Some(p) = r.svg {
        let picture = search_picture(&world, goal, seed, &events, &out.trail, &out.summary);
        let pic = avs_sim::render::render_search(&world, &picture);
        std::fs::write(p, pic).with_context(|| format!("writing {}", p.display()))?;
    }
    Ok(out.summary)
}

/// What the picture of a search shows, read from its plan trace `events`, the robot's `trail`
/// and the summary:
///
/// * every `DtAction` with a view is a look (the coverage's `PROCESSVIEWCONE` actions are only
///   counted): `PROCESSVIEWCONE` views are planned at heading 0
///   (`avs_agent`'s view planner; the robot turns to the view's heading before looking), so
///   their pan is the camera's world direction; a `VERIFY` look points from its standpoint at
///   the sighting its listing line names (`VERIFY class at (x, y) from (x, y)`); the field of
///   view is the environment camera's divided by the zoom;
/// * a false alarm is a sighting whose `VERIFY` looks were followed by neither a session found
///   nor a coverage look "detected and confirmed" nor a reached goal;
/// * the agent's room beliefs come from its `LookedAround` events: the likeliest category,
///   placed in the true room where the robot stood.
pub fn search_picture(
    world: &avs_sim::World,
    goal: &str,
    seed: u64,
    events: &[Event],
    trail: &[[f64; 2]],
    summary: &Summary,
) -> avs_sim::render::SearchPicture {
    use avs_agent::{Outcome, SessionOutcome};
    use avs_sim::render::{Look, LookKind, SearchPicture};
    let hfov = world.env.camera.hfov_deg.to_radians();
    let mut pic = SearchPicture {
        goal: goal.to_string(),
        seed: Some(seed),
        path_length: summary.path_length,
        trail: trail.to_vec(),
        reported: summary.reported_pose,
        ..Default::default()
    };
    let mut pose: Option<[f64; 3]> = None;
    // The sighting whose VERIFY looks have not been decided yet.
    let mut pending: Option<[f64; 2]> = None;
    for e in events {
        match e {
            Event::Started { pose: p, .. } => {
                pic.start.get_or_insert(*p);
                pose = Some(*p);
            }
            Event::ActionFinished {
                pose: p, outcome, ..
            } => {
                pose = Some(*p);
                if let Some(t) = pending.take() {
                    if *outcome != Outcome::DetectedAndConfirmed {
                        pic.false_alarms.push(t);
                    }
                }
            }
            Event::DtSessionEnded { outcome, .. } => {
                if let Some(t) = pending.take() {
                    if *outcome != SessionOutcome::Found {
                        pic.false_alarms.push(t);
                    }
                }
            }
            Event::GoalReached { .. } => pending = None,
            Event::ActionStarted { action } if action.starts_with("PROCESSVIEWCONE") => {
                pic.coverage_looks += 1;
            }
            Event::DtAction {
                action,
                detected,
                view: Some(v),
                target,
            } => {
                let detected = detected.unwrap_or(false);
                let label = format!(
                    "{action}: {}",
                    if detected { "detected" } else { "not detected" }
                );
                let pan = v.pan_deg.to_radians();
                let (kind, direction) = match target {
                    // A verification look points at the sighting it checks.
                    Some([tx, ty]) => {
                        if let Some(t) = pending.replace([*tx, *ty]) {
                            if (t[0] - tx).hypot(t[1] - ty) > 1e-6 {
                                // A new sighting before the last was decided: it was not
                                // confirmed.
                                pic.false_alarms.push(t);
                            }
                        }
                        (LookKind::Verify, (ty - v.y).atan2(tx - v.x))
                    }
                    None => (LookKind::Cone, pan),
                };
                pic.looks.push(Look {
                    at: [v.x, v.y],
                    direction,
                    hfov: hfov / v.zoom.max(1e-3),
                    detected,
                    kind,
                    label,
                });
            }
            Event::LookedAround { at, categories, .. } => {
                let belief = categories
                    .iter()
                    .max_by(|a, b| a.p.total_cmp(&b.p))
                    .map(|c| (c.category.clone(), c.p));
                push_belief(world, &mut pic.room_beliefs, Some(*at), belief);
            }
            _ => {}
        }
    }
    if let Some(t) = pending {
        pic.false_alarms.push(t);
    }
    let yaw = pose.map(|p| p[2]);
    pic.end = match (trail.last(), pose) {
        (Some(t), _) => Some([t[0], t[1], yaw.unwrap_or(0.0)]),
        (None, p) => p,
    };
    pic
}

/// Record the agent's likeliest category `belief` for the true room at `at`, if both are known.
fn push_belief(
    world: &avs_sim::World,
    beliefs: &mut Vec<avs_sim::render::RoomBelief>,
    at: Option<[f64; 2]>,
    belief: Option<(String, f64)>,
) {
    let room = at.and_then(|p| world.room_at(p[0], p[1]));
    if let (Some((category, probability)), Some(room)) = (belief, room) {
        beliefs.push(avs_sim::render::RoomBelief {
            room,
            category,
            probability,
        });
    }
}

/// Run the subcommand: 0 found, 3 searched and not found, 1 invalid input (clap exits 2 for
/// usage errors before this runs).
pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    match search(a) {
        Ok(found) => Ok(if found {
            ExitCode::SUCCESS
        } else {
            ExitCode::from(3)
        }),
        Err(e) => {
            eprintln!("error: {e:#}");
            Ok(ExitCode::from(1))
        }
    }
}

/// The search of `a`; whether the target was found.
fn search(a: Args) -> anyhow::Result<bool> {
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
    // An id of the environment is removed as that object, anything else as a class.
    let inputs = (
        Input::or_shipped(a.env.as_deref(), Shipped::Environment)?,
        Input::or_shipped(a.knowledge.as_deref(), Shipped::Knowledge)?,
        Input::or_shipped(a.domain.as_deref(), Shipped::Domain)?,
    );
    let env: avs_format::environment::Environment =
        avs_format::load_yaml_str(&inputs.0.name, &inputs.0.text)?;
    let mut remove = RemoveObjects::default();
    for x in &a.remove {
        if env.objects.iter().any(|o| &o.id == x) {
            remove.ids.push(x.clone());
        } else {
            remove.classes.push(x.clone());
        }
    }
    let (mut close_doors, mut door_events) = (Vec::new(), Vec::new());
    for c in &a.close_door {
        match c {
            DoorClosing::AtStart(n) => close_doors.push(n.clone()),
            DoorClosing::During(e) => door_events.push(e.clone()),
        }
    }
    let s = run_search(&Request {
        env: &inputs.0,
        knowledge: &inputs.1,
        domain: &inputs.2,
        goal: &a.goal,
        seed: a.seed,
        strategy: a.strategy,
        zoom_pipeline: a.zoom,
        unfound_landmarks: a.model.unfound_landmarks,
        objective: a.model.objective.into(),
        wrong_report_price: a.model.wrong_report_price,
        goal_in_look_around: a.model.goal_in_look_around,
        faults: Faults {
            detector: a.detector.into(),
            failure_rate: a.failure_rate,
            fp_scale: Some(a.fp_scale),
            door_events,
        },
        edits: WorldEdits {
            start: a.start,
            close_doors,
            remove,
        },
        before: &a.before,
        find_all: a.find_all,
        cover_before_giving_up: a.give_up == GiveUp::Cover,
        place_classifier: a.place_classifier,
        json_file: a.trace_json.as_deref(),
        svg: a.svg.as_deref(),
        quiet: a.json,
    })?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&s)?);
    } else {
        print_summary(&s);
    }
    Ok(s.found)
}

/// Print the summary as text.
pub fn print_summary(s: &Summary) {
    print!("{}", summary_text(s));
}

/// The summary as `print_summary` prints it.
pub fn summary_text(s: &Summary) -> String {
    use std::fmt::Write as _;
    let mut out = String::new();
    let _ = writeln!(out);
    let _ = writeln!(out, "summary");
    // Scored against the truth: a report more than 1 m from every true object is not a find,
    // whatever the agent's own verdict ("ended") says.
    if s.wrong_report {
        let _ = writeln!(
            out,
            "  found:                false (WRONG REPORT: no object of the class within 1 m of the reported pose)"
        );
    } else {
        let _ = writeln!(out, "  found:                {}", s.found);
    }
    if let Some(p) = s.reported_pose {
        let _ = writeln!(
            out,
            "  reported pose:        ({:.2}, {:.2}, {:.2})",
            p[0], p[1], p[2]
        );
    }
    if let Some(e) = s.error {
        let _ = writeln!(out, "  error to true pose:   {e:.2} m");
    }
    let _ = writeln!(out, "  path length:          {:.1} m", s.path_length);
    if let Some(l) = s.shortest_path_length {
        let _ = writeln!(out, "  shortest path:        {l:.1} m");
    }
    let by = &s.path_by_activity;
    let _ = writeln!(
            out,
        "    by activity:        exploration {:.1} m, view cones {:.1} m, verification {:.1} m, coverage {:.1} m",
        by.exploration, by.view_cones, by.verification, by.coverage
    );
    let _ = writeln!(
        out,
        "  rooms:                {} visited, {} revisits",
        s.rooms_visited, s.room_revisits
    );
    let _ = writeln!(
        out,
        "  candidates:           {} ({} accepted, {} rejected; {} verification looks, {:.1} s of detector time)",
        s.candidates,
        s.candidates_accepted,
        s.candidates_rejected,
        s.verification_looks,
        s.verification_detector_s
    );
    let _ = writeln!(
        out,
        "  images:               {} ({} by the zoom pipeline)",
        s.images, s.zoom_images
    );
    if let Some(d) = s.distance_to_goal {
        let _ = writeln!(out, "  distance to goal:     {d:.1} m at the end");
    }
    let _ = writeln!(out, "  SPL:                  {:.3}", s.spl);
    let _ = writeln!(out, "  SoftSPL:              {:.3}", s.soft_spl);
    let _ = writeln!(out, "  plans:                {}", s.plans);
    let _ = writeln!(out, "  DT sessions:          {}", s.dt_sessions);
    let _ = writeln!(out, "  plan time (median):   {:.1} ms", s.plan_ms_median);
    let _ = writeln!(out, "  DT decision (median): {:.1} ms", s.dt_ms_median);
    let _ = writeln!(out, "  search time:          {:.1} s", s.compute_s);
    let _ = writeln!(out, "  ended (the agent's):  {}", s.reason);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn summary(found: bool, wrong_report: bool) -> Summary {
        Summary {
            found,
            reported_pose: Some([5.13, 1.73, 0.74]),
            error: Some(if found { 0.2 } else { 3.0 }),
            path_length: 12.0,
            shortest_path_length: Some(6.0),
            spl: if found { 0.5 } else { 0.0 },
            wrong_report,
            distance_to_goal: Some(3.0),
            soft_spl: 0.25,
            path_by_activity: Default::default(),
            rooms_visited: 2,
            room_revisits: 0,
            plans: 3,
            dt_sessions: 1,
            candidates: 1,
            candidates_accepted: usize::from(found || wrong_report),
            candidates_rejected: usize::from(!(found || wrong_report)),
            verification_looks: 2,
            verification_detector_s: 2.0,
            images: 40,
            zoom_images: 0,
            plan_ms_median: 1.0,
            dt_ms_median: 0.1,
            compute_s: 0.1,
            reason: "found cerealbox object4 at (5.13, 1.73, 0.74)".into(),
        }
    }

    /// Issue 19: `--fp-scale 10` printed `found: false` and, further down, `ended: found
    /// cerealbox`, with nothing to reconcile the two.
    #[test]
    fn a_wrong_report_reads_as_not_found_next_to_the_agents_own_verdict() {
        let wrong = summary_text(&summary(false, true));
        assert!(
            wrong.contains("found:                false (WRONG REPORT"),
            "{wrong}"
        );
        assert!(
            wrong.contains("ended (the agent's):  found cerealbox"),
            "{wrong}"
        );
        let right = summary_text(&summary(true, false));
        assert!(right.contains("found:                true\n"), "{right}");
        assert!(!right.contains("WRONG"), "{right}");
    }
}
