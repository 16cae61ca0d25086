//! The greedy view plan (Sjöö et al. `004` §2.1.4): "the view covering the most object-cell
//! pairs is chosen iteratively until no pair remains that is not covered by any view, or no
//! view remains that covers further pairs. … The object-cell pairs covered by each view chosen
//! are removed from subsequent iterations when they are covered by the desired number of
//! views." Ours weighs a unit's new pairs by its images (see the [module docs](super)); greedy
//! set cover is within `H(n) ≤ ln n + 1` of the optimum (Chvátal 1979), and [`super::optimal`]
//! measures the actual gap.

use super::candidates::{candidate_units, Unit};
use super::{Pair, View, ViewPlan, ViewProblem};
use crate::error::Result;

/// Plan the views of `problem` greedily, with the caller's line-of-sight predicate from a
/// standpoint to a cell.
pub fn plan_views(
    problem: &ViewProblem,
    line_of_sight: impl Fn([f64; 2], [f64; 2]) -> bool,
) -> Result<ViewPlan> {
    let units = candidate_units(problem, line_of_sight)?;
    let chosen = greedy_units(problem, &units);
    Ok(assemble(problem, &units, &chosen))
}

/// How many times each pair must be covered: `min(k, units that see it)`, indexed by
/// `class × cells + cell`.
pub(crate) fn needs(problem: &ViewProblem, units: &[Unit]) -> Vec<usize> {
    let n_cells = problem.cells.len();
    let mut seen_by = vec![0usize; problem.classes.len() * n_cells];
    for u in units {
        for p in &u.pairs {
            seen_by[p.class * n_cells + p.cell] += 1;
        }
    }
    seen_by
        .into_iter()
        .map(|n| n.min(problem.options.k))
        .collect()
}

/// The cover being built: how often each pair still needs covering, each unit's gain (its
/// pairs still short), which units are chosen. Gains are kept up to date incrementally through
/// the index of the units covering each pair, so a greedy step costs a scan of the gains and
/// the updates of the pairs it fills.
struct Cover<'a> {
    units: &'a [Unit],
    n_cells: usize,
    need: Vec<usize>,
    /// Covers each pair has from the chosen units.
    times: Vec<usize>,
    /// Per unit, its pairs with `times < need`.
    gain: Vec<usize>,
    /// The units covering each pair.
    covering: Vec<Vec<usize>>,
    chosen: Vec<bool>,
    images: usize,
    /// Pairs with `times < need`.
    short: usize,
}

impl<'a> Cover<'a> {
    fn new(problem: &ViewProblem, units: &'a [Unit]) -> Self {
        let n_cells = problem.cells.len();
        let need = needs(problem, units);
        let mut covering: Vec<Vec<usize>> = vec![Vec::new(); need.len()];
        for (u, unit) in units.iter().enumerate() {
            for p in &unit.pairs {
                covering[p.class * n_cells + p.cell].push(u);
            }
        }
        // Every pair a unit covers has need ≥ 1 (the unit sees it).
        let gain = units.iter().map(|u| u.pairs.len()).collect();
        let short = need.iter().filter(|n| **n > 0).count();
        Self {
            short,
            units,
            n_cells,
            times: vec![0; need.len()],
            need,
            gain,
            covering,
            chosen: vec![false; units.len()],
            images: 0,
        }
    }

    fn index(&self, p: &Pair) -> usize {
        p.class * self.n_cells + p.cell
    }

    fn add(&mut self, u: usize) {
        self.chosen[u] = true;
        self.images += self.units[u].images();
        for p in &self.units[u].pairs {
            let i = self.index(p);
            self.times[i] += 1;
            if self.times[i] == self.need[i] {
                self.short -= 1;
                for &v in &self.covering[i] {
                    self.gain[v] -= 1;
                }
            }
        }
    }

    fn remove(&mut self, u: usize) {
        self.chosen[u] = false;
        self.images -= self.units[u].images();
        for p in &self.units[u].pairs {
            let i = self.index(p);
            if self.times[i] == self.need[i] {
                self.short += 1;
                for &v in &self.covering[i] {
                    self.gain[v] += 1;
                }
            }
            self.times[i] -= 1;
        }
    }

    /// The unchosen unit with the most short pairs per image (ties: more pairs, then the lower
    /// index); `None` when no unit adds anything.
    fn best(&self) -> Option<usize> {
        let mut best: Option<(usize, f64)> = None;
        for (u, &g) in self.gain.iter().enumerate() {
            if g == 0 || self.chosen[u] {
                continue;
            }
            let score = g as f64 / self.units[u].images() as f64;
            let better = match best {
                None => true,
                Some((b, s)) => score > s || (score == s && g > self.gain[b]),
            };
            if better {
                best = Some((u, score));
            }
        }
        best.map(|(u, _)| u)
    }

    /// Add the best unit until nothing is short (§2.1.4); the units added, in order.
    fn fill(&mut self) -> Vec<usize> {
        let mut added = Vec::new();
        while let Some(u) = self.best() {
            self.add(u);
            added.push(u);
        }
        added
    }

    /// The repair rule: the short pair the fewest units cover, then among its units the one
    /// with the most short pairs per image (ties: the lower index); `None` when nothing is
    /// short.
    fn best_for_rarest(&self) -> Option<usize> {
        let rarest = (0..self.need.len())
            .filter(|&i| self.times[i] < self.need[i])
            .min_by_key(|&i| (self.covering[i].len(), i))?;
        self.covering[rarest]
            .iter()
            .copied()
            .filter(|&u| !self.chosen[u])
            .max_by(|&a, &b| {
                let score = |u: usize| self.gain[u] as f64 / self.units[u].images() as f64;
                score(a).total_cmp(&score(b)).then(b.cmp(&a))
            })
    }

    /// Fill by the repair rule until nothing is short; the units added, in order.
    fn fill_rarest(&mut self) -> Vec<usize> {
        let mut added = Vec::new();
        while let Some(u) = self.best_for_rarest() {
            self.add(u);
            added.push(u);
        }
        added
    }

    /// Cover what is short with units of at most `budget` images in all, if that can be done:
    /// a depth-first search over the units covering the short pair the fewest units see, the
    /// unit filling most short pairs first, cut where even the best remaining unit repeated
    /// cannot fill what is short within the budget. The units added, or `None` (and nothing
    /// added).
    fn repair_within(&mut self, budget: usize) -> Option<Vec<usize>> {
        if self.short == 0 {
            return Some(Vec::new());
        }
        if budget == 0 {
            return None;
        }
        let rarest = (0..self.need.len())
            .filter(|&i| self.times[i] < self.need[i])
            .min_by_key(|&i| (self.covering[i].len(), i))?;
        let mut options: Vec<usize> = self.covering[rarest]
            .iter()
            .copied()
            .filter(|&u| !self.chosen[u] && self.units[u].images() <= budget)
            .collect();
        options.sort_by(|&a, &b| self.gain[b].cmp(&self.gain[a]).then(a.cmp(&b)));
        for u in options {
            // Each unit of the budget fills at most this one's short pairs (they are sorted).
            if self.gain[u] * budget < self.short {
                break;
            }
            self.add(u);
            if let Some(mut rest) = self.repair_within(budget - self.units[u].images()) {
                rest.insert(0, u);
                return Some(rest);
            }
            self.remove(u);
        }
        None
    }

    /// Whether every pair of `u` is covered more often than it needs without it.
    fn redundant(&self, u: usize) -> bool {
        self.units[u]
            .pairs
            .iter()
            .all(|p| self.times[self.index(p)] > self.need[self.index(p)])
    }

    /// Drop the chosen units made redundant by later ones, from the most images down, then the
    /// last chosen first.
    fn drop_redundant(&mut self, order: &mut Vec<usize>) {
        let mut by_cost: Vec<usize> = order.iter().rev().copied().collect();
        by_cost.sort_by_key(|&u| std::cmp::Reverse(self.units[u].images()));
        for u in by_cost {
            if self.redundant(u) {
                self.remove(u);
            }
        }
        order.retain(|&u| self.chosen[u]);
    }
}

/// The local search removes up to this many chosen units at a time ...
const REMOVE_AT_MOST: usize = 4;
/// ... and sets of three only up to this many chosen units, of four up to the next (the
/// neighbourhood grows as C(m, r)).
const TRIPLES_UP_TO: usize = 16;
/// See [`TRIPLES_UP_TO`].
const QUADRUPLES_UP_TO: usize = 10;

/// The `r`-element subsets of `0..m`, in lexicographic order.
fn subsets(m: usize, r: usize) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    let mut pick: Vec<usize> = (0..r).collect();
    if r == 0 || r > m {
        return out;
    }
    loop {
        out.push(pick.clone());
        // The rightmost position that can still advance.
        let Some(i) = (0..r).rev().find(|&i| pick[i] < m - r + i) else {
            return out;
        };
        pick[i] += 1;
        for j in i + 1..r {
            pick[j] = pick[j - 1] + 1;
        }
    }
}

/// The units the plan takes, in order: the better of two constructions, each followed by the
/// same local search ([`improve`]): the greedy of §2.1.4 (most short pairs per image), and the
/// greedy that serves the pair the fewest units see first (by the unit filling most short
/// pairs per image). The first takes the widest views first and can leave ragged remainders;
/// the second starts from the corners no wide view reaches; which wins depends on the room, and
/// both are cheap.
pub(crate) fn greedy_units(problem: &ViewProblem, units: &[Unit]) -> Vec<usize> {
    let images = |c: &[usize]| c.iter().map(|&u| units[u].images()).sum::<usize>();
    let widest = improve(problem, units, false);
    let rarest = improve(problem, units, true);
    if images(&rarest) < images(&widest) {
        rarest
    } else {
        widest
    }
}

/// One construction (`rarest`: the pair-first rule) and its local search: redundant units
/// dropped, then remove `r` chosen units (`r` = 2, 3, 4 as the plan's size allows) and
/// re-cover what they leave short with fewer images than they took ([`Cover::repair_within`],
/// an exact bounded search) or, failing that, greedily pair by pair with what becomes
/// redundant dropped; keep the result when it takes fewer images, until no removal helps.
/// Every accepted step removes an image, so it ends; the plan stays a full cover.
fn improve(problem: &ViewProblem, units: &[Unit], rarest: bool) -> Vec<usize> {
    let mut cover = Cover::new(problem, units);
    let mut order = if rarest {
        cover.fill_rarest()
    } else {
        cover.fill()
    };
    cover.drop_redundant(&mut order);
    'improve: loop {
        let m = order.len();
        for r in 2..=REMOVE_AT_MOST {
            let allowed = match r {
                2 => true,
                3 => m <= TRIPLES_UP_TO,
                _ => m <= QUADRUPLES_UP_TO,
            };
            if !allowed {
                break;
            }
            for set in subsets(m, r) {
                let removed: Vec<usize> = set.iter().map(|&i| order[i]).collect();
                let before = cover.images;
                let freed: usize = removed.iter().map(|&u| units[u].images()).sum();
                removed.iter().for_each(|&u| cover.remove(u));
                let mut repaired: Vec<usize> = order
                    .iter()
                    .copied()
                    .filter(|u| !removed.contains(u))
                    .collect();
                if let Some(added) = cover.repair_within(freed - 1) {
                    repaired.extend(added);
                    cover.drop_redundant(&mut repaired);
                    order = repaired;
                    continue 'improve;
                }
                let added = cover.fill_rarest();
                repaired.extend(&added);
                cover.drop_redundant(&mut repaired);
                if cover.images < before {
                    order = repaired;
                    continue 'improve;
                }
                // Undo: back to the cover before this removal.
                for u in repaired.iter().copied().filter(|u| added.contains(u)) {
                    cover.remove(u);
                }
                for &u in &order {
                    if !cover.chosen[u] {
                        cover.add(u);
                    }
                }
            }
        }
        return order;
    }
}

/// The plan of the chosen units, in the given order: one view per tilt, each listing the
/// classes of the pairs its unit covered while they still needed covering.
pub(crate) fn assemble(problem: &ViewProblem, units: &[Unit], chosen: &[usize]) -> ViewPlan {
    let n_cells = problem.cells.len();
    let need = needs(problem, units);
    let mut remaining = need.clone();
    let mut views = Vec::new();
    for &i in chosen {
        let u = &units[i];
        let mut classes: Vec<usize> = Vec::new();
        for p in &u.pairs {
            let r = &mut remaining[p.class * n_cells + p.cell];
            if *r > 0 {
                *r -= 1;
                classes.push(p.class);
            }
        }
        classes.sort_unstable();
        classes.dedup();
        for &tilt in &u.tilts {
            views.push(View {
                standpoint: u.standpoint,
                at: problem.standpoints[u.standpoint],
                yaw: u.yaw,
                tilt,
                zoom: u.zoom,
                classes: classes.clone(),
                pairs: u.pairs.clone(),
                unit: i,
            });
        }
    }
    let uncoverable = (0..problem.classes.len())
        .flat_map(|class| (0..n_cells).map(move |cell| Pair { class, cell }))
        .filter(|p| need[p.class * n_cells + p.cell] == 0)
        .collect();
    let coverage = (0..problem.classes.len())
        .map(|c| {
            let idx = c * n_cells..(c + 1) * n_cells;
            let done = idx
                .clone()
                .filter(|&p| need[p] > 0 && remaining[p] == 0)
                .count();
            if n_cells == 0 {
                1.0
            } else {
                done as f64 / n_cells as f64
            }
        })
        .collect();
    ViewPlan {
        views,
        uncoverable,
        coverage,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::{PlanOptions, SoughtClass};
    use crate::DetectionRange;
    use avs_robot::Camera;
    use std::f64::consts::PI;

    /// A 6 m × 4 m room of 0.5 m cells, standpoints on a 2 m lattice, a book and a cup.
    pub(crate) fn room(k: usize) -> ViewProblem {
        let mut cells = Vec::new();
        for i in 0..12 {
            for j in 0..8 {
                cells.push([0.25 + 0.5 * i as f64, 0.25 + 0.5 * j as f64]);
            }
        }
        let class = |name: &str, max: f64| SoughtClass {
            class: name.into(),
            range: DetectionRange { min: 0.5, max },
            heights: [0.7, 0.9],
            unique: true,
            zoom_ranges: Vec::new(),
        };
        ViewProblem {
            cells,
            standpoints: vec![
                [1.0, 1.0],
                [3.0, 1.0],
                [5.0, 1.0],
                [1.0, 3.0],
                [3.0, 3.0],
                [5.0, 3.0],
            ],
            classes: vec![class("book", 4.0), class("cup", 2.4)],
            camera: Camera {
                hfov: 47.5f64.to_radians(),
                vfov: 36.2f64.to_radians(),
                pan_limits: [-PI, PI],
                tilt_limits: [-0.5, 1.5],
                max_zoom: 13.0,
                height: 1.0,
            },
            options: PlanOptions {
                k,
                ..PlanOptions::default()
            },
        }
    }

    #[test]
    fn the_greedy_plan_covers_every_coverable_pair_k_times() {
        for k in [1, 2] {
            let p = room(k);
            let units = candidate_units(&p, |_, _| true).unwrap();
            let plan = plan_views(&p, |_, _| true).unwrap();
            assert!(plan.uncoverable.is_empty());
            assert!(plan.coverage.iter().all(|c| (c - 1.0).abs() < 1e-12));
            // An independent count over the chosen units.
            let mut chosen: Vec<usize> = plan.views.iter().map(|v| v.unit).collect();
            chosen.dedup();
            let n = p.cells.len();
            let mut times = vec![0usize; 2 * n];
            for &u in &chosen {
                for q in &units[u].pairs {
                    times[q.class * n + q.cell] += 1;
                }
            }
            assert!(times.iter().all(|t| *t >= k), "k = {k}");
        }
        assert!(
            plan_views(&room(2), |_, _| true).unwrap().searches()
                > plan_views(&room(1), |_, _| true).unwrap().searches()
        );
    }

    #[test]
    fn a_short_range_class_needs_more_searches_than_a_long_range_one_alone() {
        let both = room(1);
        let mut book = both.clone();
        book.classes.truncate(1);
        let b = plan_views(&book, |_, _| true).unwrap();
        let bc = plan_views(&both, |_, _| true).unwrap();
        assert!(
            bc.searches() > b.searches(),
            "{} vs {}",
            bc.searches(),
            b.searches()
        );
        // Each view looks for the classes whose pairs it was chosen for.
        assert!(bc.views.iter().all(|v| !v.classes.is_empty()));
    }

    #[test]
    fn pairs_out_of_every_standpoints_reach_are_reported_uncoverable() {
        let mut p = room(1);
        p.standpoints = vec![[0.5, 0.5]];
        // Without zoom the classes' limits are their zoom-1 ranges.
        p.options.max_zoom = Some(1.0);
        let plan = plan_views(&p, |_, _| true).unwrap();
        assert!(!plan.uncoverable.is_empty());
        // The cup (2.4 m) reaches fewer cells than the book (4 m).
        assert!(plan.coverage[1] < plan.coverage[0]);
        for q in &plan.uncoverable {
            let c = p.cells[q.cell];
            let d = (c[0] - 0.5).hypot(c[1] - 0.5);
            assert!(
                d > p.classes[q.class].range.max - 1e-9 || d < p.classes[q.class].range.min + 1e-9,
                "{q:?} at {d}"
            );
        }
    }
}
