//! GREEDY(τ) (Velez et al. 2012 §8.1): for each candidate whose belief has not yet passed the
//! threshold, go to the best point of its perception field and look, until every belief has.
//! It weighs no motion: the field's best point may be far.
//!
//! # Choices where the paper is vague
//! * "Exceeded a threshold τ" is read both ways: a candidate is settled when P(object) > τ
//!   (accept) or P(object) < 1 − τ (reject); settled or not, one with `max_looks` looks is
//!   decided on its belief.
//! * Of several unsettled candidates the nearest is served first.

use super::{viable_views, Candidate, Step, Terrain};
use crate::field::{self, FieldMethod};
use crate::VerifyError;
use serde::{Deserialize, Serialize};

/// Settings of GREEDY(τ).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GreedyConfig {
    /// τ: the belief a candidate must pass (P > τ or P < 1 − τ), in (½, 1).
    pub threshold: f64,
    /// Looks at one candidate after which it is decided whatever its belief.
    pub max_looks: usize,
    /// Ranges in a candidate's vantage grid.
    pub grid_ranges: usize,
    /// Aspects in a candidate's vantage grid.
    pub grid_aspects: usize,
    /// How the field is computed.
    pub method: FieldMethod,
}

impl Default for GreedyConfig {
    fn default() -> Self {
        Self {
            threshold: 0.8,
            max_looks: 12,
            grid_ranges: 8,
            grid_aspects: 13,
            method: FieldMethod::Pbd,
        }
    }
}

/// Whether GREEDY(τ) still wants to look at a candidate.
pub fn unsettled(c: &Candidate<'_>, cfg: &GreedyConfig) -> bool {
    c.looks.len() < cfg.max_looks && c.belief <= cfg.threshold && c.belief >= 1.0 - cfg.threshold
}

/// The next step of GREEDY(τ).
pub fn plan(
    candidates: &[Candidate<'_>],
    robot: [f64; 2],
    terrain: &dyn Terrain,
    cfg: &GreedyConfig,
) -> Result<Step, VerifyError> {
    let mut order: Vec<(f64, usize)> = candidates
        .iter()
        .enumerate()
        .filter(|(_, c)| unsettled(c, cfg))
        .map(|(i, c)| (terrain.distance(robot, c.position), i))
        .filter(|(d, _)| d.is_finite())
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    for (_, i) in order {
        let c = &candidates[i];
        let cond = c.model.condition(&c.looks)?;
        let grid = c.vantage_grid(cfg.grid_ranges, cfg.grid_aspects);
        let best = viable_views(c, &grid, terrain)
            .into_iter()
            .filter(|view| terrain.distance(robot, view.waypoint).is_finite())
            .filter_map(|view| {
                cond.at_with(&view.vantage, &view.ind).map(|m| {
                    (
                        field::value(&m, c.belief, cfg.method),
                        view.vantage,
                        view.waypoint,
                    )
                })
            })
            .filter(|(f, _, _)| *f > 0.0)
            .max_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((_, vantage, waypoint)) = best {
            return Ok(Step::Look {
                candidate: i,
                waypoint,
                vantage,
            });
        }
    }
    Ok(Step::Decide)
}
