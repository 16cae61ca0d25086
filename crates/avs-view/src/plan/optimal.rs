//! The exact minimum number of images of a room's view plan, to measure the greedy's gap
//! (issue 21; Sjöö et al. `004` §2.1.4 call their greedy "not guaranteed to be optimal").
//!
//! The problem is weighted set multi-cover over the candidate units: minimise `Σ images(u)
//! x_u` over `x_u ∈ {0, 1}` subject to `Σ_{u ∋ p} x_u ≥ need(p)` for every pair `p` (need =
//! `min(k, units that see p)`). It is solved as a 0/1 program by `microlp`'s branch and bound
//! (a pure-Rust LP/MIP solver; its LP relaxation gives the bound), warm-started from the
//! greedy plan and stopped after a deterministic number of nodes. With `k = 1` a unit whose
//! pairs are a subset of another's that takes no more images is dropped first (an optimum never
//! needs it); with `k > 1` nothing is dropped (both may be needed).

use super::candidates::{candidate_units, Unit};
use super::greedy::{assemble, greedy_units, needs};
use super::{ViewPlan, ViewProblem};
use crate::error::{Result, ViewError};
use microlp::{
    ComparisonOp, OptimizationDirection, Problem, SolutionStatus, SolveOptions, SolveOutcome,
};
use serde::Serialize;

/// Branch-and-bound nodes [`optimal_views`] may solve by default.
pub const DEFAULT_NODE_LIMIT: u64 = 20_000;

/// The result of [`optimal_views`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OptimalPlan {
    /// The best plan found (the greedy's when the solver found nothing better).
    pub plan: ViewPlan,
    /// Whether the plan is proven to take the fewest images.
    pub proven: bool,
    /// The solver's lower bound on the number of images (equal to the plan's when proven).
    pub lower_bound: f64,
    /// The greedy plan's number of images, for the gap.
    pub greedy_searches: usize,
}

/// Units an optimum with `k = 1` never needs: those whose pairs another unit covers with no
/// more images (ties keep the lower index).
fn undominated(units: &[Unit]) -> Vec<usize> {
    let n = units.len();
    (0..n)
        .filter(|&i| {
            !(0..n).any(|j| {
                j != i
                    && units[j].images() <= units[i].images()
                    && (units[j].pairs.len() > units[i].pairs.len()
                        || (units[j].pairs.len() == units[i].pairs.len()
                            && (units[j].images() < units[i].images() || j < i)))
                    && is_subset(&units[i].pairs, &units[j].pairs)
            })
        })
        .collect()
}

/// Whether sorted `a` is a subset of sorted `b`.
fn is_subset<T: Ord>(a: &[T], b: &[T]) -> bool {
    let mut it = b.iter();
    a.iter().all(|x| it.by_ref().any(|y| y == x))
}

/// The plan of `problem` with the fewest images, as far as `node_limit` branch-and-bound nodes
/// prove (see the module docs).
pub fn optimal_views(
    problem: &ViewProblem,
    line_of_sight: impl Fn([f64; 2], [f64; 2]) -> bool,
    node_limit: u64,
) -> Result<OptimalPlan> {
    let units = candidate_units(problem, line_of_sight)?;
    let greedy = greedy_units(problem, &units);
    let greedy_images: usize = greedy.iter().map(|&u| units[u].images()).sum();
    let keep: Vec<usize> = if problem.options.k == 1 {
        undominated(&units)
    } else {
        (0..units.len()).collect()
    };
    let n_cells = problem.cells.len();
    let need = needs(problem, &units);
    let mut lp = Problem::new(OptimizationDirection::Minimize);
    let vars: Vec<_> = keep
        .iter()
        .map(|&u| lp.add_binary_var(units[u].images() as f64))
        .collect();
    let mut covering: Vec<Vec<usize>> = vec![Vec::new(); need.len()];
    for (v, &u) in keep.iter().enumerate() {
        for p in &units[u].pairs {
            covering[p.class * n_cells + p.cell].push(v);
        }
    }
    for (p, cov) in covering.iter().enumerate() {
        if need[p] > 0 {
            lp.add_constraint(
                cov.iter().map(|&v| (vars[v], 1.0)),
                ComparisonOp::Ge,
                need[p] as f64,
            );
        }
    }
    let solver_error = |e: microlp::Error| ViewError::Solver(e.to_string());
    let mut options = SolveOptions::default();
    options.node_limit = Some(node_limit);
    let fallback = |lower_bound: f64| OptimalPlan {
        plan: assemble(problem, &units, &greedy),
        proven: false,
        lower_bound,
        greedy_searches: greedy_images,
    };
    let solution = match lp.solve_with(options).map_err(solver_error)? {
        SolveOutcome::Solution(s) => s,
        SolveOutcome::Interrupted(i) => {
            return Ok(fallback(i.stats().best_bound.unwrap_or(0.0)));
        }
    };
    let chosen: Vec<usize> = keep
        .iter()
        .zip(&vars)
        .filter(|(_, v)| solution.var_value(**v) > 0.5)
        .map(|(&u, _)| u)
        .collect();
    let images: usize = chosen.iter().map(|&u| units[u].images()).sum();
    let proven = solution.status() == SolutionStatus::Optimal;
    let lower_bound = if proven {
        images as f64
    } else {
        solution.stats().best_bound.unwrap_or(0.0)
    };
    if images > greedy_images {
        return Ok(fallback(lower_bound));
    }
    // Take the chosen units greedily, so the plan's order and class lists read like the greedy's.
    let mut order = Vec::new();
    let sub: Vec<Unit> = chosen.iter().map(|&u| units[u].clone()).collect();
    for i in greedy_units(problem, &sub) {
        order.push(chosen[i]);
    }
    // Units the greedy over the optimum's set skips (all their pairs already covered) still
    // belong to the optimum only if they were needed; they were not, so they are left out.
    Ok(OptimalPlan {
        plan: assemble(problem, &units, &order),
        proven,
        lower_bound,
        greedy_searches: greedy_images,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::greedy::plan_views;
    use crate::plan::{PlanOptions, SoughtClass};
    use crate::DetectionRange;
    use avs_robot::Camera;
    use std::f64::consts::PI;

    /// A small room: few enough units to enumerate every subset.
    fn small(k: usize) -> ViewProblem {
        let mut cells = Vec::new();
        for i in 0..6 {
            for j in 0..4 {
                cells.push([0.25 + 0.5 * i as f64, 0.25 + 0.5 * j as f64]);
            }
        }
        ViewProblem {
            cells,
            standpoints: vec![[0.5, 0.5], [2.5, 1.5]],
            classes: vec![SoughtClass {
                class: "book".into(),
                range: DetectionRange { min: 0.4, max: 2.2 },
                heights: [0.7, 0.9],
                unique: true,
                zoom_ranges: Vec::new(),
            }],
            camera: Camera {
                hfov: 60f64.to_radians(),
                vfov: 45f64.to_radians(),
                pan_limits: [-PI, PI],
                tilt_limits: [-0.6, 0.6],
                max_zoom: 4.0,
                height: 1.0,
            },
            options: PlanOptions {
                k,
                direction_step: Some(PI / 3.0),
                max_zoom: Some(1.0),
            },
        }
    }

    /// The fewest images over every subset of units that covers each pair `need` times.
    fn brute_force(problem: &ViewProblem) -> usize {
        let units = candidate_units(problem, |_, _| true).unwrap();
        assert!(
            units.len() <= 20,
            "{} units: too many to enumerate",
            units.len()
        );
        let need = needs(problem, &units);
        let n = problem.cells.len();
        let mut best = usize::MAX;
        for mask in 0u32..(1 << units.len()) {
            let mut times = vec![0usize; need.len()];
            let mut images = 0;
            for (i, u) in units.iter().enumerate() {
                if mask & (1 << i) != 0 {
                    images += u.images();
                    for p in &u.pairs {
                        times[p.class * n + p.cell] += 1;
                    }
                }
            }
            if images < best && times.iter().zip(&need).all(|(t, r)| t >= r) {
                best = images;
            }
        }
        best
    }

    #[test]
    fn the_exact_plan_matches_a_brute_force_minimum_and_never_exceeds_the_greedy() {
        for k in [1, 2] {
            let p = small(k);
            let exact = optimal_views(&p, |_, _| true, DEFAULT_NODE_LIMIT).unwrap();
            assert!(exact.proven);
            assert_eq!(exact.plan.searches(), brute_force(&p), "k = {k}");
            assert!(exact.plan.searches() <= plan_views(&p, |_, _| true).unwrap().searches());
            assert_eq!(
                exact.greedy_searches,
                plan_views(&p, |_, _| true).unwrap().searches()
            );
            // Every coverable pair is covered: the share left is the uncoverable one.
            let coverable = 1.0 - exact.plan.uncoverable.len() as f64 / p.cells.len() as f64;
            assert!(
                (exact.plan.coverage[0] - coverable).abs() < 1e-12,
                "k = {k}"
            );
            assert!((exact.lower_bound - exact.plan.searches() as f64).abs() < 1e-9);
        }
    }

    #[test]
    fn a_unit_is_dropped_only_for_a_superset_with_no_more_images() {
        let unit = |pairs: &[usize], images: usize| Unit {
            standpoint: 0,
            yaw: 0.0,
            zoom: 1.0,
            tilts: vec![0.0; images],
            near: false,
            pairs: pairs
                .iter()
                .map(|&cell| crate::plan::Pair { class: 0, cell })
                .collect(),
        };
        let units = [
            unit(&[1, 2], 1),
            unit(&[1, 2, 3], 1),
            unit(&[4], 1),
            unit(&[1, 2, 3, 4], 3),
            unit(&[4], 1),
        ];
        // 0 ⊂ 1; 2 and 4 are duplicates (the first kept); 3 takes more images than 1 + 2.
        assert_eq!(undominated(&units), vec![1, 2, 3]);
    }
}
