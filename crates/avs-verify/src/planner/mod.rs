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
    /// The zoom of the looks at it (≥ 1): a zoomed image magnifies by the zoom (Sjöö et al.,
    /// `004` eq. 1), so a robot `d` metres away sees the candidate as from `d / zoom` — the
    /// vantage range the sensor model is asked about. 1 unless [`Candidate::with_zoom`].
    pub zoom: f64,
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
            zoom: 1.0,
        }
    }

    /// The same candidate looked at through zoom `zoom` (values below 1 or not finite count
    /// as 1).
    pub fn with_zoom(mut self, zoom: f64) -> Self {
        self.zoom = if zoom.is_finite() { zoom.max(1.0) } else { 1.0 };
        self
    }

    /// The waypoint that gives vantage point `v` (the inverse of [`Candidate::vantage`]).
    pub fn waypoint(&self, v: &Vantage) -> [f64; 2] {
        Vantage {
            range: v.range * self.zoom,
            ..*v
        }
        .waypoint(self.position, self.facing)
    }

    /// The grid of vantage points a planner samples for it: [`VantageGrid::for_model`] of its
    /// model, from the closest a robot looks from ([`crate::field::MIN_RANGE`] metres away,
    /// seen through the zoom) outwards.
    pub fn vantage_grid(&self, n_range: usize, n_aspect: usize) -> VantageGrid {
        VantageGrid::for_model_from(
            self.model,
            crate::field::MIN_RANGE / self.zoom,
            n_range,
            n_aspect,
        )
    }

    /// A look at it from `waypoint` returned no score: no evidence, and no reason to go back.
    pub fn unseen_from(&mut self, waypoint: [f64; 2]) {
        self.blind.push(waypoint);
    }

    /// The vantage point of a robot at `waypoint` facing this candidate (its range divided by
    /// the zoom).
    pub fn vantage(&self, waypoint: [f64; 2]) -> Vantage {
        let v = Vantage::of(waypoint, self.position, self.facing);
        Vantage {
            range: v.range / self.zoom,
            ..v
        }
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
        .map(|v| c.waypoint(v))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::MIN_RANGE;
    use crate::gp::SeKernel;
    use crate::sensor::{CorrModel, ModelKind, ScoreGp};

    fn model() -> SensorModel {
        let k = SeKernel {
            signal_variance: 0.1,
            length_scales: vec![1.0, 0.5],
            angular: crate::vantage::ANGULAR.to_vec(),
        };
        let pts = [(Vantage::new(1.0, 0.0), 1.0)];
        let ind = ScoreGp::new(1.0, k.clone(), 0.01, 0.3, &pts).unwrap();
        let corr = CorrModel {
            kernel: k,
            noise_variance: 0.1,
        };
        SensorModel {
            ind: [ind.clone(), ind],
            corr: [corr.clone(), corr],
            kind: ModelKind::Independent,
            aspect_limit: None,
            max_range: 2.0,
        }
    }

    #[test]
    fn a_zoomed_candidate_is_seen_as_from_nearer_and_its_waypoints_lie_farther() {
        let m = model();
        let c = Candidate::new([1.0, 1.0], None, &m, 0.5).with_zoom(2.0);
        // 4 m away through zoom 2: the vantage range the model is asked about is 2 m.
        let v = c.vantage([5.0, 1.0]);
        assert!((v.range - 2.0).abs() < 1e-12 && v.aspect.abs() < 1e-12);
        let w = c.waypoint(&v);
        assert!((w[0] - 5.0).abs() < 1e-12 && (w[1] - 1.0).abs() < 1e-12);
        // The grid starts where a robot MIN_RANGE away sees it through the zoom.
        let g = c.vantage_grid(4, 6);
        let lo = g
            .vantages
            .iter()
            .map(|v| v.range)
            .fold(f64::INFINITY, f64::min);
        assert!((lo - MIN_RANGE / 2.0).abs() < 1e-9, "{lo}");
        // Without zoom, the grid starts at MIN_RANGE; a zoom below 1 counts as 1.
        let plain = Candidate::new([1.0, 1.0], None, &m, 0.5).with_zoom(0.3);
        assert_eq!(plain.zoom, 1.0);
        let lo = plain
            .vantage_grid(4, 6)
            .vantages
            .iter()
            .map(|v| v.range)
            .fold(f64::INFINITY, f64::min);
        assert!((lo - MIN_RANGE).abs() < 1e-9);
    }
}
