//! The RTBSS baseline (Velez et al. 2012 §8.1; Paquet, Tobin & Chaib-draa 2005): an online
//! POMDP search over a discretised world, with the *independent* sensor model only (the
//! Markov assumption leaves no room for the history a correlated model needs).
//!
//! The nearest open candidate gets a small POMDP, built afresh at every step:
//! * **States**: the robot at one of `K + 1` places (where it stands now, and the `K` vantage
//!   cells) × whether the candidate is an object, and an absorbing *done*;
//! * **Actions**: go to cell `j` and look (reward `−(distance + look cost)`), accept, reject
//!   (reward `−right` or `−wrong`, then done);
//! * **Observations**: the score in one of `bins` bins over the likely range, with GP_ind's
//!   predictive probabilities at the cell's vantage point; *none* after a decision.
//!
//! and `avs_pomdp::online::rtbss` picks the action to a fixed depth over the offline bounds
//! (blind-policy and fast-informed). A look carries the same information every time it is taken,
//! so RTBSS over-values repeated looks from one place — the paper's point.
//!
//! # Choices where the paper is vague
//! * **Cells**: the centres of a 2.5 m lattice around the candidate (the paper's resolution),
//!   where the robot can stand and the detector sees the candidate; the `max_cells` with the most
//!   information (`d²` of [`crate::sensor::LookModel::information`], independent model) are kept,
//!   so the POMDP stays small enough to search.
//! * **Depth**: the planned verifier's (5), within a budget of belief nodes per decision
//!   (20 000 by default; `avs_pomdp::online`'s `node_limit`): the search deepens from 1 and keeps
//!   the deepest depth it completes, so runs are the same on every machine (a time budget would
//!   make them depend on it). Depth 5 in full is up to `(K + 3)^5 × bins^5` belief nodes.
//! * **One candidate at a time**, the nearest: a joint POMDP over several candidates grows as
//!   the product of their state spaces.

use super::{Candidate, Step, Terrain};
use crate::pbd::DecisionCosts;
use crate::sensor::{LookModel, ModelKind, NO_OBJECT, OBJECT};
use crate::vantage::Vantage;
use crate::VerifyError;
use avs_pomdp::bounds::Bounds;
use avs_pomdp::model::{Pomdp, PomdpTables};
use avs_pomdp::online::{rtbss, OnlineOptions};
use serde::{Deserialize, Serialize};

/// Settings of the RTBSS baseline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RtbssConfig {
    /// Lattice spacing of the vantage cells, metres.
    pub cell: f64,
    /// Most vantage cells in one POMDP.
    pub max_cells: usize,
    /// Score bins.
    pub bins: usize,
    /// Search depth.
    pub depth: usize,
    /// Belief nodes one decision may expand (a deterministic budget: the search deepens from 1
    /// and keeps the deepest depth completed within it); `None` searches `depth` in full.
    #[serde(default)]
    pub node_limit: Option<usize>,
    /// Discount factor.
    pub discount: f64,
    /// Costs of right and wrong decisions, metres.
    pub costs: DecisionCosts,
    /// Cost of one look, metres.
    pub look_cost: f64,
    /// Looks at one candidate after which it is decided whatever its belief.
    pub max_looks: usize,
}

impl Default for RtbssConfig {
    fn default() -> Self {
        Self {
            cell: 2.5,
            max_cells: 10,
            bins: 4,
            depth: 5,
            node_limit: Some(20_000),
            discount: 0.95,
            costs: DecisionCosts::default(),
            look_cost: 0.5,
            max_looks: 12,
        }
    }
}

/// The next step of RTBSS for the nearest open candidate (`Settle` decides it alone).
pub fn plan(
    candidates: &[Candidate<'_>],
    robot: [f64; 2],
    terrain: &dyn Terrain,
    cfg: &RtbssConfig,
) -> Result<Step, VerifyError> {
    let Some((i, c)) = candidates
        .iter()
        .enumerate()
        .filter(|(_, c)| c.looks.len() < cfg.max_looks)
        .map(|(i, c)| (terrain.distance(robot, c.position), i, c))
        .filter(|(d, _, _)| d.is_finite())
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
        .map(|(_, i, c)| (i, c))
    else {
        return Ok(Step::Decide);
    };
    // The independent model: no history.
    let mut independent = c.model.clone();
    independent.kind = ModelKind::Independent;
    let cond = independent.condition(&[])?;
    // Vantage cells.
    let reach = c.model.max_range * c.zoom;
    let n = (reach / cfg.cell).ceil() as i64;
    let mut cells: Vec<(f64, [f64; 2], Vantage, LookModel)> = Vec::new();
    for a in -n..=n {
        for b in -n..=n {
            let w = [
                c.position[0] + a as f64 * cfg.cell,
                c.position[1] + b as f64 * cfg.cell,
            ];
            let v = c.vantage(w);
            if v.range * c.zoom < crate::field::MIN_RANGE
                || c.blind
                    .iter()
                    .any(|p| (p[0] - w[0]).hypot(p[1] - w[1]) < super::BLIND_RADIUS)
            {
                continue;
            }
            let Some(m) = cond.at(&v) else { continue };
            if !terrain.can_view(w, c.position) || !terrain.distance(robot, w).is_finite() {
                continue;
            }
            cells.push((m.information(), w, v, m));
        }
    }
    cells.sort_by(|x, y| {
        y.0.total_cmp(&x.0)
            .then(x.1[0].total_cmp(&y.1[0]))
            .then(x.1[1].total_cmp(&y.1[1]))
    });
    cells.truncate(cfg.max_cells);
    if cells.is_empty() {
        return Ok(Step::Settle { candidate: i });
    }
    let m = build(robot, &cells, terrain, cfg)?;
    let bounds = Bounds::initial(&m, 100);
    let k = cells.len();
    let mut b0 = vec![0.0; m.n_states()];
    b0[state(0, NO_OBJECT)] = 1.0 - c.belief;
    b0[state(0, OBJECT)] = c.belief;
    let d = rtbss(
        &m,
        &bounds,
        &b0,
        &OnlineOptions {
            depth: cfg.depth,
            time_limit: None,
            node_limit: cfg.node_limit,
        },
    )
    .map_err(|e| VerifyError::Invalid {
        field: "rtbss".into(),
        message: e.to_string(),
    })?;
    if d.action < k {
        let (_, w, v, _) = cells[d.action];
        Ok(Step::Look {
            candidate: i,
            waypoint: w,
            vantage: v,
        })
    } else {
        Ok(Step::Settle { candidate: i })
    }
}

/// State index of (place, y); place 0 is where the robot stands now, place j ≥ 1 cell j − 1.
fn state(place: usize, y: usize) -> usize {
    2 * place + y
}

fn build(
    robot: [f64; 2],
    cells: &[(f64, [f64; 2], Vantage, LookModel)],
    terrain: &dyn Terrain,
    cfg: &RtbssConfig,
) -> Result<Pomdp, VerifyError> {
    let k = cells.len();
    let places: Vec<[f64; 2]> = std::iter::once(robot)
        .chain(cells.iter().map(|c| c.1))
        .collect();
    let ns = 2 * (k + 1) + 1;
    let done = ns - 1;
    let na = k + 2;
    let (accept, reject) = (k, k + 1);
    let nb = cfg.bins.max(2);
    let no = nb + 1;
    let none = nb;
    // Score bins over every cell's likely scores.
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for cell in cells {
        let [a, b] = cell.3.score_range(2.5);
        lo = lo.min(a);
        hi = hi.max(b);
    }
    let edges: Vec<f64> = (1..nb)
        .map(|i| lo + (hi - lo) * i as f64 / nb as f64)
        .collect();
    let mut t = vec![0.0; na * ns * ns];
    let mut o = vec![0.0; na * ns * no];
    let mut r = vec![0.0; na * ns];
    for a in 0..na {
        for s in 0..ns {
            let row = (a * ns + s) * ns;
            if s == done {
                t[row + done] = 1.0;
                continue;
            }
            let (place, y) = (s / 2, s % 2);
            if a < k {
                t[row + state(a + 1, y)] = 1.0;
                let d = terrain.distance(places[place], places[a + 1]);
                r[a * ns + s] = -(if d.is_finite() { d } else { 1e3 } + cfg.look_cost);
            } else {
                t[row + done] = 1.0;
                let right = (a == accept && y == OBJECT) || (a == reject && y == NO_OBJECT);
                r[a * ns + s] = -(if right {
                    cfg.costs.right
                } else {
                    cfg.costs.wrong
                });
            }
        }
        // Observations on arrival.
        for s2 in 0..ns {
            let base = (a * ns + s2) * no;
            if a >= k || s2 == done {
                o[base + none] = 1.0;
                continue;
            }
            let y = s2 % 2;
            let lik = cells[a].3.likelihood[y].ind;
            let sd = lik.var.sqrt();
            let cdf = |x: f64| crate::pbd::std_normal_cdf((x - lik.mean) / sd);
            let mut prev = 0.0;
            for (bin, e) in edges.iter().enumerate() {
                let p = cdf(*e);
                o[base + bin] = (p - prev).max(0.0);
                prev = p;
            }
            o[base + nb - 1] = (1.0 - prev).max(0.0);
            let total: f64 = o[base..base + nb].iter().sum();
            for v in &mut o[base..base + nb] {
                *v /= total;
            }
        }
    }
    let mut initial = vec![0.0; ns];
    initial[0] = 0.5;
    initial[1] = 0.5;
    Pomdp::new(PomdpTables {
        states: (0..ns).map(|s| format!("s{s}")).collect(),
        actions: (0..na).map(|a| format!("a{a}")).collect(),
        observations: (0..no).map(|z| format!("z{z}")).collect(),
        discount: cfg.discount,
        transitions: t,
        observation_probs: o,
        rewards: r,
        initial,
    })
    .map_err(|e| VerifyError::Invalid {
        field: "rtbss".into(),
        message: e.to_string(),
    })
}
