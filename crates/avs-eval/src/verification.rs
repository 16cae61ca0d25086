//! The detection-verification harness (Velez et al. 2012 §8): a robot drives from a start to a
//! goal through a verification scenario's map, runs the simulated correlated detector every
//! `look_every` metres, turns what fires into candidates, and hands them to a verification
//! strategy until it decides; the trial is scored by precision, recall and path length.
//! [`run_bench`] repeats trials with seeds `seed, seed + 1, …` (`avs verify-bench`).
//!
//! The sensor models the strategies use are trained for the scenario's detector on simulated
//! looks at features of the same profile on other seeds ([`train_model`]), so the verifier
//! knows the detector only as well as its training shows it.
//!
//! # Choices where the paper is vague
//! * **Candidates.** A feature becomes a candidate the first time the detector fires on it
//!   (a score above the profile's threshold) in an image with a clear line of sight; its
//!   belief starts at the scenario's `prior` and takes that score. Every later image in which
//!   it is seen updates it, fired or not (the score at a hypothesised location, §3). Data
//!   association is by feature (the paper's stereo position estimate, taken as exact).
//! * **Decisions.** A strategy's `Decide` settles every open candidate: accepted when its
//!   belief is above ½. Candidates left open at the goal are settled the same way.
//! * **Scores.** Precision is accepted objects over accepted candidates, 0 when nothing was
//!   accepted; recall is accepted objects over the scenario's objects. Means and standard
//!   errors over trials, as the paper's tables.
//! * **Motion.** The robot follows 8-connected shortest paths on the grid (for its radius);
//!   the planners cost legs by the straight line when it is clear, else by the grid path.

use crate::EvalError;
use avs_format::verification::{DetectorName, VerificationScenario};
use avs_map::grid::OccupancyGrid;
use avs_map::nav::{shortest_path, Traversability};
use avs_map::raycast::line_of_sight;
use avs_sim::detector::{CorrelatedDetector, Feature, ScoreProfile};
use avs_verify::field::{perception_field, FieldMethod, PreparedGrid, VantageGrid};
use avs_verify::planner::greedy::GreedyConfig;
use avs_verify::planner::planned::PlannedConfig;
use avs_verify::planner::rtbss::RtbssConfig;
use avs_verify::planner::{Candidate, GridTerrain, Step, Verifier};
use avs_verify::sensor::{ModelKind, SensorModel};
use avs_verify::train::{train, SensorModelSpec, TrainOptions, TrainingLook};
use avs_verify::vantage::Vantage;
use rand::{Rng, SeedableRng};
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// A verification strategy (`--strategy`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Strategy {
    /// The planned verifier with the dynamic sensor model.
    Planned,
    /// The planned verifier with the static disc model.
    PlannedDisc,
    /// GREEDY(τ) with the scenario detector's default model.
    Greedy(f64),
    /// RTBSS with the independent model on a 2.5 m grid.
    Rtbss,
}

impl Strategy {
    /// Parse `planned`, `planned-disc`, `greedy:TAU` (τ in (0.5, 1)) or `rtbss`.
    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "planned" => Ok(Self::Planned),
            "planned-disc" => Ok(Self::PlannedDisc),
            "rtbss" => Ok(Self::Rtbss),
            _ => {
                if let Some(t) = s.strip_prefix("greedy:") {
                    let tau: f64 = t
                        .parse()
                        .map_err(|_| format!("greedy:{t}: expected a number after `greedy:`"))?;
                    if !(tau > 0.5 && tau < 1.0) {
                        return Err(format!("greedy:{t}: expected τ in (0.5, 1)"));
                    }
                    Ok(Self::Greedy(tau))
                } else {
                    Err(format!(
                        "unknown strategy `{s}`: expected planned, planned-disc, greedy:TAU or rtbss"
                    ))
                }
            }
        }
    }

    /// The strategy's name as the CLI writes it.
    pub fn name(&self) -> String {
        match self {
            Self::Planned => "planned".into(),
            Self::PlannedDisc => "planned-disc".into(),
            Self::Greedy(t) => format!("greedy:{t}"),
            Self::Rtbss => "rtbss".into(),
        }
    }
}

/// The simulated detector profile of a scenario detector.
pub fn profile_of(d: DetectorName) -> ScoreProfile {
    match d {
        DetectorName::Door => ScoreProfile::door(),
        DetectorName::Sign => ScoreProfile::sign(),
        DetectorName::Generic => ScoreProfile::generic(),
    }
}

/// The model a strategy uses for a detector: the dynamic model for `planned`, the disc model
/// for `planned-disc`, for GREEDY the paper's pairing (disc for doors, dynamic otherwise), and
/// the independent model for RTBSS.
pub fn model_kind(strategy: Strategy, d: DetectorName) -> ModelKind {
    let disc = ModelKind::Disc { d_max: 3.0 };
    let dynamic = ModelKind::Dynamic { alpha_scale: 1.0 };
    match (strategy, d) {
        (Strategy::Planned, _) => dynamic,
        (Strategy::PlannedDisc, _) => disc,
        (Strategy::Greedy(_), DetectorName::Door) => disc,
        (Strategy::Greedy(_), _) => dynamic,
        (Strategy::Rtbss, _) => ModelKind::Independent,
    }
}

/// Simulated training looks for a detector profile: `per_class` features of each label, each
/// seen from `looks` vantage points where the detector sees it, in clusters of four around
/// random centres, plus one repeated look (two images from one spot), from seeded generators.
pub fn training_looks(
    profile: &ScoreProfile,
    per_class: usize,
    looks: usize,
    seed: u64,
) -> Vec<TrainingLook> {
    let features: Vec<Feature> = (0..2 * per_class)
        .map(|i| Feature {
            position: [0.0, 0.0],
            facing: 0.0,
            is_object: i < per_class,
        })
        .collect();
    let mut det = CorrelatedDetector::new(profile.clone(), features, seed);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed ^ 0x7261_696e);
    let lim = profile.aspect_limit.unwrap_or(std::f64::consts::PI);
    let lo = avs_verify::field::MIN_RANGE.min(profile.max_range);
    let mut out = Vec::new();
    for f in 0..2 * per_class {
        let object = f < per_class;
        let mut k = 0;
        let mut centre = Vantage::new(lo, 0.0);
        let mut tries = 0;
        while k < looks && tries < 100 * looks {
            tries += 1;
            // Looks come in clusters of CLUSTER around random centres, so that the data show
            // how fast the correlation falls off (scattered looks are nearly independent and
            // say little about GP_corr's length scales; a design with half the looks scattered
            // fitted the length scales 20–25 % off the simulator's, this one within 15 %).
            let v = if k % CLUSTER == 0 {
                centre = Vantage::new(
                    rng.gen_range(lo..=profile.max_range),
                    rng.gen_range(-lim..=lim),
                );
                centre
            } else {
                Vantage::new(
                    centre.range + rng.gen_range(-0.8..=0.8),
                    centre.aspect + rng.gen_range(-0.3..=0.3),
                )
            };
            if v.range < lo || v.range > profile.max_range || v.aspect.abs() > lim {
                continue;
            }
            let w = v.waypoint([0.0, 0.0], Some(0.0));
            let Some(z) = det.score(f, w) else { continue };
            out.push(TrainingLook {
                feature: f,
                object,
                vantage: v,
                score: z,
            });
            if k == 0 {
                if let Some(z2) = det.score(f, w) {
                    out.push(TrainingLook {
                        feature: f,
                        object,
                        vantage: v,
                        score: z2,
                    });
                }
            }
            k += 1;
        }
    }
    out
}

/// Looks per cluster in [`training_looks`].
const CLUSTER: usize = 4;

/// Train the sensor model a strategy uses for a detector profile on simulated looks
/// (100 features of each label × 12 looks, seed `seed`).
pub fn train_model(
    profile: &ScoreProfile,
    kind: ModelKind,
    seed: u64,
) -> Result<SensorModelSpec, EvalError> {
    let looks = training_looks(profile, 100, 12, seed);
    train(
        &looks,
        &TrainOptions {
            kind,
            max_range: profile.max_range,
            aspect_limit: profile.aspect_limit,
            range_bins: 12,
            aspect_bins: 9,
            restarts: 3,
            seed,
        },
    )
    .map_err(|e| EvalError::Sim(format!("training the sensor model: {e}")))
}

/// The shipped scenarios (Velez et al. 2012 §8), by name, as embedded when the program was
/// built (`domains/verification/NAME.yaml`).
pub const SHIPPED: [(&str, &str); 4] = [
    (
        "single-door",
        include_str!("../../../domains/verification/single-door.yaml"),
    ),
    (
        "multi-door",
        include_str!("../../../domains/verification/multi-door.yaml"),
    ),
    (
        "single-sign",
        include_str!("../../../domains/verification/single-sign.yaml"),
    ),
    (
        "multi-sign",
        include_str!("../../../domains/verification/multi-sign.yaml"),
    ),
];

/// A scenario's world: the map, the robot's traversability, the scenario.
pub struct VerificationWorld {
    /// The scenario as read.
    pub scenario: VerificationScenario,
    grid: OccupancyGrid,
    trav: Traversability,
    file: String,
}

impl VerificationWorld {
    /// Read, check and build a scenario file (the checks of `avs validate`, then that the
    /// start, the goal and every feature lie inside the map, the start and the goal on cells
    /// the robot fits on, and that the goal is reachable).
    pub fn load(path: &Path) -> Result<Self, EvalError> {
        let file = path.display().to_string();
        let text = avs_format::load::read_text(path)?;
        Self::from_text(&file, &text, path.parent().unwrap_or(Path::new(".")))
    }

    /// A shipped scenario by name (`single-door`, …), or a scenario file by path.
    pub fn named_or_file(arg: &str) -> Result<Self, EvalError> {
        if let Some((name, text)) = SHIPPED.iter().find(|(n, _)| *n == arg) {
            let file = format!("domains/verification/{name}.yaml");
            return Self::from_text(&file, text, Path::new("."));
        }
        let path = Path::new(arg);
        if !path.exists() {
            return Err(EvalError::Load {
                what: "verification scenario",
                file: arg.to_string(),
                message: format!(
                    "no such file, and not a shipped scenario name (expected a file or one of {})",
                    SHIPPED.map(|(n, _)| n).join(", ")
                ),
            });
        }
        Self::load(path)
    }

    /// Check and build a scenario from its text (`file` names it in errors, `dir` resolves an
    /// image map).
    pub fn from_text(file: &str, text: &str, dir: &Path) -> Result<Self, EvalError> {
        let sc = avs_format::verification::parse(file, text)?;
        Self::build(sc, file, dir)
    }

    /// Build from a parsed scenario (`file` names it in errors; `dir` resolves an image map).
    pub fn new(scenario: VerificationScenario, file: &str, dir: &Path) -> Result<Self, EvalError> {
        let problems = scenario.check_fields(file);
        if !problems.is_empty() {
            return Err(avs_format::LoadError {
                diagnostics: problems,
            }
            .into());
        }
        Self::build(scenario, file, dir)
    }

    /// [`VerificationWorld::new`] for a scenario whose fields are already checked.
    fn build(scenario: VerificationScenario, file: &str, dir: &Path) -> Result<Self, EvalError> {
        let field = |field: &str, message: String| EvalError::Field {
            file: file.to_string(),
            field: field.to_string(),
            message,
        };
        let grid =
            avs_sim::load_map(&scenario.map, dir).map_err(|e| field("map", e.to_string()))?;
        if grid.width() * grid.height() > 4_000_000 {
            return Err(field(
                "map",
                "more than 4 000 000 cells: expected a smaller map".into(),
            ));
        }
        let trav = Traversability::new(&grid, scenario.robot_radius, false);
        let inside = |p: [f64; 2]| {
            let (c, r) = grid.world_to_cell(p[0], p[1]);
            grid.contains(c, r)
        };
        let fits = |p: [f64; 2]| {
            let (c, r) = grid.world_to_cell(p[0], p[1]);
            trav.ok(c, r)
        };
        let start = [scenario.start.x, scenario.start.y];
        let goal = [scenario.goal.x, scenario.goal.y];
        if !fits(start) {
            return Err(field(
                "start",
                "not on a free cell the robot fits on".into(),
            ));
        }
        if !fits(goal) {
            return Err(field("goal", "not on a free cell the robot fits on".into()));
        }
        for (i, f) in scenario.features.iter().enumerate() {
            if !inside([f.x, f.y]) {
                return Err(field(&format!("features[{i}]"), "outside the map".into()));
            }
        }
        if shortest_path(&trav, start, goal, 0.0).is_none() {
            return Err(field("goal", "unreachable from the start".into()));
        }
        Ok(Self {
            scenario,
            grid,
            trav,
            file: file.to_string(),
        })
    }

    /// The file the scenario came from.
    pub fn file(&self) -> &str {
        &self.file
    }

    fn features(&self) -> Vec<Feature> {
        self.scenario
            .features
            .iter()
            .map(|f| Feature {
                position: [f.x, f.y],
                facing: f.facing_deg.to_radians(),
                is_object: f.object,
            })
            .collect()
    }
}

/// Grid path lengths already computed, by (from cell, to cell).
/// One trial's result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrialResult {
    /// Precision of the accepted candidates (0 when none was accepted).
    pub precision: f64,
    /// Recall of the scenario's objects.
    pub recall: f64,
    /// Distance driven, metres.
    pub path_length: f64,
    /// Candidates created.
    pub candidates: usize,
    /// Candidates accepted.
    pub accepted: usize,
    /// Verification looks taken (images at planned waypoints).
    pub looks: usize,
    /// Detector images in all.
    pub images: usize,
    /// Simulated detector processing time, seconds.
    pub detector_seconds: f64,
    /// Time of one perception field per planning call, milliseconds.
    #[serde(skip)]
    pub field_ms: Vec<f64>,
    /// Every candidate: feature index, whether it is an object, final belief, accepted.
    pub decisions: Vec<Decision>,
}

/// How one candidate ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Decision {
    /// The feature's index in the scenario.
    pub feature: usize,
    /// Whether it is an object (ground truth).
    pub object: bool,
    /// P(object) when decided.
    pub belief: f64,
    /// Looks taken at it (including the one that created it).
    pub looks: usize,
    /// Whether it was accepted.
    pub accepted: bool,
}

struct Open<'m> {
    feature: usize,
    candidate: Candidate<'m>,
    decided: Option<bool>,
}

/// Run one trial of `strategy` on `world` with the trained `model`.
pub fn run_trial<'m>(
    world: &VerificationWorld,
    model: &'m SensorModel,
    strategy: Strategy,
    seed: u64,
) -> Result<TrialResult, EvalError> {
    let sc = &world.scenario;
    let profile = profile_of(sc.detector);
    let features = world.features();
    let mut det = CorrelatedDetector::new(profile, features.clone(), seed);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed ^ 0x706c_616e);
    let terrain = GridTerrain::new(&world.grid, &world.trav, true, f64::INFINITY);
    let half_fov = 0.5 * sc.fov_deg.to_radians();
    let goal = [sc.goal.x, sc.goal.y];
    let mut pos = [sc.start.x, sc.start.y];
    let mut path = 0.0;
    let mut open: Vec<Open<'m>> = Vec::new();
    let mut looks = 0usize;
    let mut field_ms = Vec::new();
    let planned_cfg = PlannedConfig {
        fov: sc.fov_deg.to_radians(),
        ..PlannedConfig::default()
    };
    let verifier = match strategy {
        Strategy::Planned | Strategy::PlannedDisc => Verifier::Planned(planned_cfg.clone()),
        Strategy::Greedy(tau) => Verifier::Greedy(GreedyConfig {
            threshold: tau,
            ..GreedyConfig::default()
        }),
        // The planned verifier's depth, within RTBSS's node budget (the issue: depth = ours).
        Strategy::Rtbss => Verifier::Rtbss(RtbssConfig {
            depth: planned_cfg.depth,
            ..RtbssConfig::default()
        }),
    };
    // The grid of the timed perception field (Table 6): its GP_ind predictions are made once
    // per trial and reused, as the planner does.
    let field_grid = PreparedGrid::new(
        model,
        VantageGrid::for_model(model, planned_cfg.grid_ranges, planned_cfg.grid_aspects),
    );

    let mut image =
        |at: [f64; 2], heading: f64, open: &mut Vec<Open<'m>>| -> Result<(), EvalError> {
            for (f, z) in det.look(at, heading, half_fov) {
                if !line_of_sight(&world.grid, at, features[f].position, true) {
                    continue;
                }
                match open.iter_mut().find(|o| o.feature == f) {
                    Some(o) if o.decided.is_none() => o
                        .candidate
                        .observe(at, z)
                        .map_err(|e| EvalError::Sim(e.to_string()))?,
                    Some(_) => {}
                    None if det.fires(z) => {
                        let mut c = Candidate::new(
                            features[f].position,
                            Some(features[f].facing),
                            model,
                            sc.prior,
                        );
                        c.observe(at, z)
                            .map_err(|e| EvalError::Sim(e.to_string()))?;
                        open.push(Open {
                            feature: f,
                            candidate: c,
                            decided: None,
                        });
                    }
                    None => {}
                }
            }
            Ok(())
        };
    let mut heading = (goal[1] - pos[1]).atan2(goal[0] - pos[0]);
    image(pos, heading, &mut open)?;
    let max_steps = 10_000;
    for _ in 0..max_steps {
        // Verify what is open.
        let mut rounds = 0;
        while open.iter().any(|o| o.decided.is_none()) {
            rounds += 1;
            let idx: Vec<usize> = (0..open.len())
                .filter(|&i| open[i].decided.is_none())
                .collect();
            let cands: Vec<Candidate<'_>> =
                idx.iter().map(|&i| open[i].candidate.clone()).collect();
            {
                let c = &cands[0];
                let t0 = Instant::now();
                let cond = c
                    .model
                    .condition(&c.looks)
                    .map_err(|e| EvalError::Sim(e.to_string()))?;
                let f = perception_field(&cond, c.belief, &field_grid, FieldMethod::Pbd);
                std::hint::black_box(f);
                field_ms.push(t0.elapsed().as_secs_f64() * 1e3);
            }
            let step = verifier
                .next_step(&cands, pos, goal, &terrain, &mut rng)
                .map_err(|e| EvalError::Sim(e.to_string()))?;
            match step {
                Step::Look {
                    candidate,
                    waypoint,
                    ..
                } if rounds < 200 => {
                    let target = open[idx[candidate]].candidate.position;
                    let leg = shortest_path(&world.trav, pos, waypoint, 0.5)
                        .map_or(f64::INFINITY, |p| p.length);
                    if !leg.is_finite() {
                        // The robot cannot get there (the planner's terrain is coarser than the
                        // robot's paths): no look from there, and no going back.
                        open[idx[candidate]].candidate.unseen_from(waypoint);
                        continue;
                    }
                    path += leg;
                    pos = waypoint;
                    heading = (target[1] - pos[1]).atan2(target[0] - pos[0]);
                    looks += 1;
                    let faced = idx[candidate];
                    let before = open[faced].candidate.looks.len();
                    image(pos, heading, &mut open)?;
                    if open[faced].candidate.looks.len() == before {
                        open[faced].candidate.unseen_from(pos);
                    }
                }
                Step::Settle { candidate } => {
                    let o = &mut open[idx[candidate]];
                    o.decided = Some(o.candidate.belief > 0.5);
                }
                _ => settle(&mut open),
            }
        }
        // Drive on towards the goal.
        let Some(route) = shortest_path(&world.trav, pos, goal, 0.5) else {
            return Err(EvalError::Field {
                file: world.file.clone(),
                field: "goal".into(),
                message: format!("unreachable from ({:.2}, {:.2})", pos[0], pos[1]),
            });
        };
        if route.length < 1e-9 || (pos[0] - goal[0]).hypot(pos[1] - goal[1]) < 1e-6 {
            break;
        }
        let (next, driven) = advance(&route.points, pos, sc.look_every);
        if driven <= 0.0 {
            break;
        }
        heading = (next[1] - pos[1]).atan2(next[0] - pos[0]);
        path += driven;
        pos = next;
        image(pos, heading, &mut open)?;
    }
    settle(&mut open);
    let objects = features.iter().filter(|f| f.is_object).count();
    let accepted: Vec<&Open<'_>> = open.iter().filter(|o| o.decided == Some(true)).collect();
    let tp = accepted
        .iter()
        .filter(|o| features[o.feature].is_object)
        .count();
    Ok(TrialResult {
        precision: if accepted.is_empty() {
            0.0
        } else {
            tp as f64 / accepted.len() as f64
        },
        recall: if objects == 0 {
            1.0
        } else {
            tp as f64 / objects as f64
        },
        path_length: path,
        candidates: open.len(),
        accepted: accepted.len(),
        looks,
        images: det.images(),
        detector_seconds: det.processing_seconds(),
        field_ms,
        decisions: open
            .iter()
            .map(|o| Decision {
                feature: o.feature,
                object: features[o.feature].is_object,
                belief: o.candidate.belief,
                looks: o.candidate.looks.len(),
                accepted: o.decided == Some(true),
            })
            .collect(),
    })
}

fn settle(open: &mut [Open<'_>]) {
    for o in open.iter_mut().filter(|o| o.decided.is_none()) {
        o.decided = Some(o.candidate.belief > 0.5);
    }
}

/// The point `step` metres along a polyline from `from` (its first point is `from`'s cell
/// centre), and the distance actually covered.
fn advance(points: &[[f64; 2]], from: [f64; 2], step: f64) -> ([f64; 2], f64) {
    let mut left = step;
    let mut at = from;
    let mut covered = 0.0;
    for p in points.iter().skip(1) {
        let d = (p[0] - at[0]).hypot(p[1] - at[1]);
        if d >= left {
            let t = left / d;
            let q = [at[0] + t * (p[0] - at[0]), at[1] + t * (p[1] - at[1])];
            return (q, covered + left);
        }
        covered += d;
        left -= d;
        at = *p;
    }
    (at, covered)
}

/// A bench's figures: means and standard errors over trials (Velez et al. Tables 2–5).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BenchReport {
    /// The scenario's name.
    pub scenario: String,
    /// The strategy.
    pub strategy: String,
    /// Mean precision.
    pub precision: f64,
    /// Mean recall.
    pub recall: f64,
    /// Mean path length, metres.
    pub path_length_mean: f64,
    /// Standard error of the precision.
    pub precision_se: f64,
    /// Standard error of the recall.
    pub recall_se: f64,
    /// Standard error of the path length, metres.
    pub path_length_se: f64,
    /// Trials run.
    pub trials: usize,
    /// Median time of one perception field, milliseconds.
    pub field_ms_median: f64,
    /// Mean verification looks per trial.
    pub looks_mean: f64,
    /// Mean simulated detector time per trial, seconds.
    pub detector_seconds_mean: f64,
    /// Every trial.
    pub trial_results: Vec<TrialResult>,
}

fn mean_se(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    if v.is_empty() {
        return (0.0, 0.0);
    }
    let m = v.iter().sum::<f64>() / n;
    if v.len() < 2 {
        return (m, 0.0);
    }
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

/// Run `trials` trials of `strategy` with seeds `seed..seed + trials`, the model trained on
/// seed `seed + 1_000_000` (never a trial's).
pub fn run_bench(
    world: &VerificationWorld,
    strategy: Strategy,
    trials: usize,
    seed: u64,
) -> Result<BenchReport, EvalError> {
    let profile = profile_of(world.scenario.detector);
    let spec = train_model(
        &profile,
        model_kind(strategy, world.scenario.detector),
        seed.wrapping_add(1_000_000),
    )?;
    let model = SensorModel::from_spec(&spec).map_err(|e| EvalError::Sim(e.to_string()))?;
    run_bench_with(world, &model, strategy, trials, seed)
}

/// [`run_bench`] with a sensor model already trained (or read from a knowledge file).
pub fn run_bench_with(
    world: &VerificationWorld,
    model: &SensorModel,
    strategy: Strategy,
    trials: usize,
    seed: u64,
) -> Result<BenchReport, EvalError> {
    let results: Vec<TrialResult> = (0..trials as u64)
        .map(|k| run_trial(world, model, strategy, seed.wrapping_add(k)))
        .collect::<Result<_, _>>()?;
    let col = |f: &dyn Fn(&TrialResult) -> f64| results.iter().map(f).collect::<Vec<f64>>();
    let (precision, precision_se) = mean_se(&col(&|r| r.precision));
    let (recall, recall_se) = mean_se(&col(&|r| r.recall));
    let (path_length_mean, path_length_se) = mean_se(&col(&|r| r.path_length));
    let mut ms: Vec<f64> = results
        .iter()
        .flat_map(|r| r.field_ms.iter().copied())
        .collect();
    ms.sort_by(f64::total_cmp);
    let field_ms_median = if ms.is_empty() { 0.0 } else { ms[ms.len() / 2] };
    Ok(BenchReport {
        scenario: world.scenario.name.clone(),
        strategy: strategy.name(),
        precision,
        recall,
        path_length_mean,
        precision_se,
        recall_se,
        path_length_se,
        trials,
        field_ms_median,
        looks_mean: mean_se(&col(&|r| r.looks as f64)).0,
        detector_seconds_mean: mean_se(&col(&|r| r.detector_seconds)).0,
        trial_results: results,
    })
}
