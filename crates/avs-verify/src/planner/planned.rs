//! The planned verifier: REPLANONNEWDETECTION (Velez et al. 2012, Fig. 7).
//!
//! After every look, sample `samples` look sequences of depth `T` from the perception field
//! (eq. 7–8, by PBD), each look's waypoint drawn with probability proportional to the field at
//! it; along each sequence the field is recomputed for the candidate just looked at, with the
//! look added to its history (the correlation model makes a repeated vantage point worth
//! nothing, eq. 9–11, 17) and its information grown by eq. 32. Every prefix of every
//! sequence is a plan, costed by eq. 1/20:
//!
//! `cost = [motion(robot → looks → goal) − motion(robot → goal)] + T_looks · look_cost
//!        + Σ_candidates E[decision cost after the looks]`,
//!
//! the decision cost from the accumulated information alone ([`DecisionCosts::after`]); several
//! candidates' costs add (§5.3). The plan with the lowest cost wins; the empty plan (decide
//! now and drive on) is always a contender. The robot takes the first look of the winner and
//! plans again with the score it got.
//!
//! # Choices where the paper is vague
//! * **Sampling.** Waypoints are drawn from the vantage grid of every candidate (ranges × aspects
//!   within what the detector sees, [`VantageGrid::for_model`]) where the robot can stand and
//!   see the candidate, proportionally to the field; a fixed number of sequences from a seeded
//!   generator, so a plan is deterministic.
//! * **Predicted scores.** A hypothetical look's score (needed only to condition GP_corr's mean)
//!   is the belief-weighted mean score there (Fig. 7, line 28's PREDICT); the information does
//!   not depend on it (eq. 32).
//! * **A look costs `look_cost` metres** (the detector's processing time, which the paper
//!   simulates as a delay). Without it a model that believes every look is fresh (the
//!   independent model) would look forever from one spot; `max_looks` per candidate is a hard
//!   stop on top.

use super::{viable_views, Candidate, Step, Terrain};
use crate::field::{self, FieldMethod, VantageGrid};
use crate::pbd::{covariance_after, covariance_of, DecisionCosts};
use crate::sensor::{Look, LookModel, NO_OBJECT, OBJECT};
use crate::vantage::Vantage;
use crate::VerifyError;
use rand::Rng;
use serde::{Deserialize, Serialize};

/// Settings of the planned verifier.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlannedConfig {
    /// Depth `T` of the sampled look sequences.
    pub depth: usize,
    /// Look sequences sampled per plan.
    pub samples: usize,
    /// Ranges in a candidate's vantage grid.
    pub grid_ranges: usize,
    /// Aspects in a candidate's vantage grid.
    pub grid_aspects: usize,
    /// Costs of right and wrong decisions, metres.
    pub costs: DecisionCosts,
    /// Cost of one look, metres.
    pub look_cost: f64,
    /// Looks at one candidate after which it is decided whatever its belief.
    pub max_looks: usize,
    /// How the field is computed while sampling.
    pub method: FieldMethod,
    /// The camera's horizontal field of view, radians: a look at one candidate also sees the
    /// others inside it.
    pub fov: f64,
}

impl Default for PlannedConfig {
    fn default() -> Self {
        Self {
            depth: 5,
            samples: 256,
            grid_ranges: 8,
            grid_aspects: 13,
            costs: DecisionCosts::default(),
            look_cost: 0.5,
            max_looks: 12,
            method: FieldMethod::Pbd,
            fov: 60f64.to_radians(),
        }
    }
}

/// A plan of the planned verifier: its first step and what the chosen sequence costs.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// What to do now.
    pub step: Step,
    /// The chosen sequence's looks (candidate, waypoint).
    pub looks: Vec<(usize, [f64; 2])>,
    /// Its extra motion plus look costs, metres.
    pub motion: f64,
    /// Its expected decision cost, metres.
    pub decision: f64,
    /// Perception-field evaluations made (vantage points × candidates × steps).
    pub field_evaluations: usize,
}

impl Plan {
    /// Total expected cost, metres.
    pub fn cost(&self) -> f64 {
        self.motion + self.decision
    }
}

#[derive(Clone)]
struct Sampled {
    candidate: usize,
    vantage: Vantage,
    waypoint: [f64; 2],
    model: LookModel,
    value: f64,
}

/// Plan the next step for `candidates` with the robot at `robot` on its way to `goal`.
pub fn plan(
    candidates: &[Candidate<'_>],
    robot: [f64; 2],
    goal: [f64; 2],
    terrain: &dyn Terrain,
    cfg: &PlannedConfig,
    rng: &mut impl Rng,
) -> Result<Plan, VerifyError> {
    let beliefs: Vec<f64> = candidates.iter().map(|c| c.belief).collect();
    let sigma0: Vec<f64> = beliefs.iter().map(|&p| covariance_of(p)).collect();
    let decision_now: f64 = beliefs.iter().map(|&p| cfg.costs.now(p)).sum();
    let mut best = Plan {
        step: Step::Decide,
        looks: Vec::new(),
        motion: 0.0,
        decision: decision_now,
        field_evaluations: 0,
    };
    let open: Vec<bool> = candidates
        .iter()
        .map(|c| c.looks.len() < cfg.max_looks)
        .collect();
    if !open.iter().any(|&o| o) {
        return Ok(best);
    }
    let grids: Vec<VantageGrid> = candidates
        .iter()
        .map(|c| c.vantage_grid(cfg.grid_ranges, cfg.grid_aspects))
        .collect();
    let views: Vec<Vec<super::View>> = candidates
        .iter()
        .zip(&grids)
        .map(|(c, g)| viable_views(c, g, terrain))
        .collect();
    let mut evaluations = 0usize;
    let field_of = |i: usize,
                    looks: &[Look],
                    sigma: f64,
                    evals: &mut usize|
     -> Result<Vec<Sampled>, VerifyError> {
        if !open[i] {
            return Ok(Vec::new());
        }
        let c = &candidates[i];
        let cond = c.model.condition(looks)?;
        let mut out = Vec::with_capacity(views[i].len());
        for view in &views[i] {
            *evals += 1;
            let Some(m) = cond.at_with(&view.vantage, &view.ind) else {
                continue;
            };
            let value = match cfg.method {
                FieldMethod::Pbd => 0.5 * (1.0 + sigma * m.information()).ln(),
                other => field::value(&m, beliefs[i], other),
            };
            if value > 0.0 && value.is_finite() {
                out.push(Sampled {
                    candidate: i,
                    vantage: view.vantage,
                    waypoint: view.waypoint,
                    model: m,
                    value,
                });
            }
        }
        Ok(out)
    };
    // The fields before any hypothetical look are the same for every sample.
    let mut initial = Vec::with_capacity(candidates.len());
    for (i, c) in candidates.iter().enumerate() {
        initial.push(field_of(i, &c.looks, sigma0[i], &mut evaluations)?);
    }
    let direct = terrain.distance(robot, goal);
    if !direct.is_finite() {
        // No route to the goal to cost detours against: decide now.
        best.field_evaluations = evaluations;
        return Ok(best);
    }
    for _ in 0..cfg.samples {
        let mut fields: Vec<Option<Vec<Sampled>>> = vec![None; candidates.len()];
        let mut looks: Vec<Vec<Look>> = candidates.iter().map(|c| c.looks.clone()).collect();
        let mut sigma = sigma0.clone();
        let mut info = vec![0.0; candidates.len()];
        let mut count = vec![0usize; candidates.len()];
        let mut pos = robot;
        let mut path = 0.0;
        let mut seq: Vec<(usize, Vantage, [f64; 2])> = Vec::new();
        for _ in 0..cfg.depth {
            let all = || {
                (0..candidates.len()).flat_map(|i| fields[i].as_ref().unwrap_or(&initial[i]).iter())
            };
            let total: f64 = all().map(|v| v.value).sum();
            if total.is_nan() || total <= 0.0 {
                break;
            }
            let mut u = rng.gen::<f64>() * total;
            let mut pick = None;
            for v in all() {
                pick = Some(v);
                u -= v.value;
                if u <= 0.0 {
                    break;
                }
            }
            let Some(v) = pick.cloned() else { break };
            let (i, waypoint) = (v.candidate, v.waypoint);
            let leg = terrain.distance(pos, waypoint);
            if !leg.is_finite() {
                break;
            }
            path += leg;
            pos = waypoint;
            seq.push((i, v.vantage, waypoint));
            // The image sees the candidate faced and every other one in its field of view.
            let target = candidates[i].position;
            let heading = (target[1] - waypoint[1]).atan2(target[0] - waypoint[0]);
            for (j, c) in candidates.iter().enumerate() {
                if !open[j] || candidates[j].looks.len() + count[j] >= cfg.max_looks {
                    continue;
                }
                let m = if j == i {
                    v.model
                } else {
                    let b = (c.position[1] - waypoint[1]).atan2(c.position[0] - waypoint[0]);
                    if crate::vantage::wrap(b - heading).abs() > 0.5 * cfg.fov
                        || !terrain.can_view(waypoint, c.position)
                    {
                        continue;
                    }
                    let Some(m) = c.model.condition(&looks[j])?.at(&c.vantage(waypoint)) else {
                        continue;
                    };
                    m
                };
                let gained = m.information();
                info[j] += gained;
                sigma[j] = covariance_after(sigma[j], [gained]);
                let n1 = m.likelihood[OBJECT].moments().mean;
                let n0 = m.likelihood[NO_OBJECT].moments().mean;
                looks[j].push(Look {
                    vantage: c.vantage(waypoint),
                    score: beliefs[j] * n1 + (1.0 - beliefs[j]) * n0,
                });
                count[j] += 1;
                // The field the next look is drawn from: the faced candidate's with this look
                // in its history. (The others seen on the side keep theirs for sampling; their
                // information above is exact.)
                if c.looks.len() + count[j] >= cfg.max_looks {
                    fields[j] = Some(Vec::new());
                } else if j == i {
                    fields[j] = Some(field_of(j, &looks[j], sigma[j], &mut evaluations)?);
                }
            }
            // This prefix as a plan.
            let home = terrain.distance(pos, goal);
            if !home.is_finite() {
                continue;
            }
            let motion = path + home - direct + seq.len() as f64 * cfg.look_cost;
            let decision: f64 = (0..candidates.len())
                .map(|j| cfg.costs.after(beliefs[j], info[j]))
                .sum();
            if motion + decision < best.cost() - 1e-12 {
                let (c0, v0, w0) = seq[0];
                best = Plan {
                    step: Step::Look {
                        candidate: c0,
                        waypoint: w0,
                        vantage: v0,
                    },
                    looks: seq.iter().map(|&(c, _, w)| (c, w)).collect(),
                    motion,
                    decision,
                    field_evaluations: 0,
                };
            }
        }
    }
    best.field_evaluations = evaluations;
    Ok(best)
}
