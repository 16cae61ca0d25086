//! Verification planners: given the candidates under verification, where to look next, or
//! that it is time to decide.
//!
//! * [`planned`] — Velez et al.'s REPLANONNEWDETECTION (Fig. 7): sampled look sequences, each
//!   costed by its extra motion plus the expected decision cost after it (eq. 1, 20, 32);
//! * [`greedy`] — the GREEDY(τ) baseline (§8.1): the best field point of each undecided
//!   candidate until its belief passes τ;
//! * [`rtbss`] — the RTBSS baseline (§8.1): an online POMDP search with the independent model
//!   on a 2.5 m grid.
//!
//! A planner is called again after every look (the new score may change everything), so it
//! returns one [`Step`]: the next look, or the decision.

pub mod greedy;
pub mod planned;
pub mod rtbss;
pub mod terrain;

pub use terrain::GridTerrain;

use crate::field::VantageGrid;
use crate::sensor::{IndAt, Look, SensorModel};
use crate::vantage::Vantage;
use serde::{Deserialize, Serialize};

/// A candidate detection under verification: where it is, which way it faces, its sensor
/// model, the belief that it is an object and the looks taken at it.
#[derive(Debug, Clone)]
pub struct Candidate<'m> {
    /// Position, metres.
    pub position: [f64; 2],
    /// Facing, radians (`None` when unknown or meaningless).
    pub facing: Option<f64>,
    /// The detector's model for the candidate's class.
    pub model: &'m SensorModel,
    /// P(object) now.
    pub belief: f64,
    /// The looks taken at it so far.
    pub looks: Vec<Look>,
    /// Waypoints from which a look at it returned no score (an occlusion the map does not show,
    /// the edge of what the detector sees): planners do not send the robot there again.
    pub blind: Vec<[f64; 2]>,
}

impl<'m> Candidate<'m> {
    /// A new candidate with a prior belief and no looks.
    pub fn new(
        position: [f64; 2],
        facing: Option<f64>,
        model: &'m SensorModel,
        prior: f64,
    ) -> Self {
        Self {
            position,
            facing,
            model,
            belief: prior,
            looks: Vec::new(),
            blind: Vec::new(),
        }
    }

    /// A look at it from `waypoint` returned no score: no evidence, and no reason to go back.
    pub fn unseen_from(&mut self, waypoint: [f64; 2]) {
        self.blind.push(waypoint);
    }

    /// The vantage point of a robot at `waypoint` facing this candidate.
    pub fn vantage(&self, waypoint: [f64; 2]) -> Vantage {
        Vantage::of(waypoint, self.position, self.facing)
    }

    /// Take a look's score into account: the belief by Bayes' rule (eq. 6/11, through the model
    /// conditioned on the earlier looks), then the look joins the history.
    pub fn observe(&mut self, waypoint: [f64; 2], score: f64) -> Result<(), crate::VerifyError> {
        let v = self.vantage(waypoint);
        let c = self.model.condition(&self.looks)?;
        self.belief = c.update(self.belief, &v, score).clamp(1e-9, 1.0 - 1e-9);
        self.looks.push(Look { vantage: v, score });
        Ok(())
    }
}

/// The space the robot moves in, as the planners need it.
pub trait Terrain {
    /// Whether the robot can stand at `at` and see a candidate at `target` from there.
    fn can_view(&self, at: [f64; 2], target: [f64; 2]) -> bool;
    /// Travel distance from `a` to `b`, metres (infinite when unreachable).
    fn distance(&self, a: [f64; 2], b: [f64; 2]) -> f64;
}

/// An open plane: every point reachable in a straight line, every candidate in view.
#[derive(Debug, Clone, Copy, Default)]
pub struct OpenPlane;

impl Terrain for OpenPlane {
    fn can_view(&self, _: [f64; 2], _: [f64; 2]) -> bool {
        true
    }
    fn distance(&self, a: [f64; 2], b: [f64; 2]) -> f64 {
        (a[0] - b[0]).hypot(a[1] - b[1])
    }
}

/// The next thing to do.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Step {
    /// Go to `waypoint`, face candidate `candidate` and look at it.
    Look {
        /// Index of the candidate looked at.
        candidate: usize,
        /// Where to look from.
        waypoint: [f64; 2],
        /// The vantage point that gives.
        vantage: Vantage,
    },
    /// Decide every candidate now (accept those with belief above ½) and go on.
    Decide,
    /// Decide candidate `candidate` alone now (accept it if its belief is above ½).
    Settle {
        /// Index of the candidate decided.
        candidate: usize,
    },
}

/// The views of a candidate's vantage grid that the robot can use: where it can stand and see
/// the candidate, and the detector sees it from.
pub fn viable_views(c: &Candidate<'_>, grid: &VantageGrid, terrain: &dyn Terrain) -> Vec<View> {
    grid.vantages
        .iter()
        .map(|v| v.waypoint(c.position, c.facing))
        // The vantage point as the look will see it (recomputed from the waypoint).
        .map(|w| (c.vantage(w), w))
        .filter(|(v, _)| c.model.sees(v))
        .filter(|(_, w)| {
            !c.blind
                .iter()
                .any(|b| (b[0] - w[0]).hypot(b[1] - w[1]) < BLIND_RADIUS)
        })
        .filter(|(_, w)| terrain.can_view(*w, c.position))
        .map(|(vantage, waypoint)| View {
            vantage,
            waypoint,
            ind: c.model.ind_at(&vantage),
        })
        .collect()
}

/// Waypoints closer than this (metres) to one from which a candidate was not seen are not
/// offered again.
pub const BLIND_RADIUS: f64 = 0.3;

/// A usable vantage point of a candidate: where the robot stands, and GP_ind's predictions
/// there (computed once per plan: they do not depend on the history).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// The vantage point.
    pub vantage: Vantage,
    /// The waypoint it puts the robot on.
    pub waypoint: [f64; 2],
    /// GP_ind's predictions there.
    pub ind: IndAt,
}

/// A verification planner with its settings: the one place that turns a choice of verifier
/// into its next [`Step`] (the verification bench and the search agent both call it).
#[derive(Debug, Clone, PartialEq)]
pub enum Verifier {
    /// The planned verifier (REPLANONNEWDETECTION, Fig. 7).
    Planned(planned::PlannedConfig),
    /// GREEDY(τ).
    Greedy(greedy::GreedyConfig),
    /// RTBSS (decides one candidate at a time with [`Step::Settle`]).
    Rtbss(rtbss::RtbssConfig),
}

impl Verifier {
    /// The next step for `candidates` with the robot at `robot` on its way to `goal`
    /// (`rng` draws the planned verifier's look sequences; the others are deterministic).
    pub fn next_step(
        &self,
        candidates: &[Candidate<'_>],
        robot: [f64; 2],
        goal: [f64; 2],
        terrain: &dyn Terrain,
        rng: &mut impl rand::Rng,
    ) -> Result<Step, crate::VerifyError> {
        match self {
            Verifier::Planned(cfg) => {
                Ok(planned::plan(candidates, robot, goal, terrain, cfg, rng)?.step)
            }
            Verifier::Greedy(cfg) => greedy::plan(candidates, robot, terrain, cfg),
            Verifier::Rtbss(cfg) => rtbss::plan(candidates, robot, terrain, cfg),
        }
    }

    /// Looks at one candidate after which it is decided whatever its belief.
    pub fn max_looks(&self) -> usize {
        match self {
            Verifier::Planned(c) => c.max_looks,
            Verifier::Greedy(c) => c.max_looks,
            Verifier::Rtbss(c) => c.max_looks,
        }
    }
}
