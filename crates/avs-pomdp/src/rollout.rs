//! One-pass rollout: the view-cone session's online policy when a session is one search of a
//! location (the continual planner's SEARCHFOROBJECT, whose success model is one pass over the
//! cones at the detector's hit rate, `002` §II-A).
//!
//! The state is the session's belief over the target's whereabouts (in cone i, or not in the
//! location), the robot's pose (the start or the last processed cone), the cones still *open*
//! (not processed in this session) and a pending *recheck*: the cone whose last look detected
//! something, with the number of detections in a row there. A cone may be processed while it is
//! open, or again while a detection there is being confirmed; a look that detects nothing closes
//! it. Whether the location deserves a second pass is the planner's decision, made on the rate
//! the pass thinned, not the session's. The target may be declared found only in the cone whose
//! last look detected it: a declaration is a sighting to report, and under the plan's assumed
//! prior a cone holding most of a small landmark's mass was otherwise "found" unseen.
//!
//! Decisions are a depth-limited expectimax (Ross et al. 2008, §3) whose leaves are the exact
//! value of a **base policy** (Bertsekas' rollout, *Dynamic Programming and Optimal Control*
//! vol. I, §6.4): visit the open cones in nearest-neighbour order of travel cost, confirm a
//! detection with one more look at the same cone and declare the target found when it detects
//! again, and declare it absent after the last cone; a leaf is also worth declaring at once
//! when that is better. The nearest-neighbour tour is sequentially consistent (the tour from its
//! second cone is the rest of the tour), and the leaf function `W` satisfies `T W ≥ W` (the
//! base's own next step and each declaration are among the choices), so the rollout policy is
//! never worse than its base, in expectation (tested exactly on small problems). Unlike the
//! generic online search over HSVI bounds (`online`), it needs no offline solve: the leaf
//! values are the base policy's, computed in closed form per target position, O(n²) per leaf.
//!
//! Why a base tour by travel: the cones of one room cover the room's points, each holding the
//! same share of the prior, so the cones' masses differ by a few points while their poses lie
//! metres apart. The generic search over loose bounds looks two steps ahead and then sees a
//! tail worth the same from everywhere, so it chased the heaviest cones across the room and
//! came back to cones it had emptied; a leaf that counts the travel of the whole remaining
//! pass ranks a detour by what it costs the pass.

use crate::viewcone::{ViewConeAction, ViewConePomdp};

/// The one-pass search problem read off a [`ViewConePomdp`].
#[derive(Debug, Clone)]
pub struct OnePassModel {
    n: usize,
    gamma: f64,
    /// `cost[pos][i]`: travel from `pos` (0 = start, `j + 1` = cone j) to cone i plus processing.
    cost: Vec<Vec<f64>>,
    /// `det[i][t]`: P(detected | process cone i, target t); `t = n` is "not in the location".
    det: Vec<Vec<f64>>,
    found: f64,
    wrong: f64,
    absent: f64,
}

/// Where a one-pass session stands.
#[derive(Debug, Clone, PartialEq)]
pub struct OnePassState {
    /// P(target in cone i) for i < n, then P(not in the location); sums to 1.
    pub mass: Vec<f64>,
    /// The robot's pose: 0 at the start, `i + 1` at cone i.
    pub pos: usize,
    /// Cones not processed yet in this session.
    pub open: Vec<bool>,
    /// The cone whose last look detected something, and how many looks in a row did.
    pub recheck: Option<(usize, u32)>,
}

impl OnePassState {
    /// The state at a session's start: every cone open, the robot at the start pose.
    pub fn start(cone_prior: &[f64]) -> Self {
        let n = cone_prior.len();
        let sum: f64 = cone_prior.iter().sum();
        let scale = 1.0 / sum.max(1.0);
        let mut mass: Vec<f64> = cone_prior.iter().map(|p| p * scale).collect();
        mass.push((1.0 - sum * scale).max(0.0));
        Self {
            mass,
            pos: 0,
            open: vec![true; n],
            recheck: None,
        }
    }

    /// May cone `i` be processed now?
    pub fn may_process(&self, i: usize) -> bool {
        self.open.get(i).copied().unwrap_or(false) || matches!(self.recheck, Some((j, _)) if j == i)
    }
}

impl OnePassModel {
    /// Read costs, sensor and rewards off the view-cone model.
    pub fn new(model: &ViewConePomdp) -> Self {
        let m = model.pomdp();
        let n = model.n_cones();
        let nt = n + 1;
        let idx = |pos: usize, t: usize| pos * nt + t;
        Self {
            n,
            gamma: m.discount(),
            cost: (0..=n)
                .map(|pos| (0..n).map(|i| -m.reward(idx(pos, 0), i)).collect())
                .collect(),
            det: (0..n)
                .map(|i| {
                    (0..nt)
                        .map(|t| m.observation(i, idx(i + 1, t), 0))
                        .collect()
                })
                .collect(),
            found: m.reward(idx(0, 0), n),
            wrong: m.reward(idx(0, n), n),
            absent: m.reward(idx(0, n), 2 * n),
        }
    }

    /// Number of cones.
    pub fn n_cones(&self) -> usize {
        self.n
    }

    /// Expected reward of declaring the target found in cone `i`.
    fn found_value(&self, s: &OnePassState, i: usize) -> f64 {
        s.mass[i] * self.found + (1.0 - s.mass[i]) * self.wrong
    }

    /// Expected reward of declaring the target absent.
    fn absent_value(&self, s: &OnePassState) -> f64 {
        s.mass[self.n] * self.absent + (1.0 - s.mass[self.n]) * self.wrong
    }

    /// Reward of a right or wrong "found in cone i" when the target is `t`.
    fn found_reward(&self, t: usize, i: usize) -> f64 {
        if t == i {
            self.found
        } else {
            self.wrong
        }
    }

    /// The state after processing cone `i` and observing `detected`, with the observation's
    /// probability; `None` when the observation is impossible.
    pub fn after(&self, s: &OnePassState, i: usize, detected: bool) -> Option<(f64, OnePassState)> {
        let like = |t: usize| {
            if detected {
                self.det[i][t]
            } else {
                1.0 - self.det[i][t]
            }
        };
        let p: f64 = s.mass.iter().enumerate().map(|(t, m)| m * like(t)).sum();
        if p <= 0.0 || !p.is_finite() {
            return None;
        }
        let mass = s
            .mass
            .iter()
            .enumerate()
            .map(|(t, m)| m * like(t) / p)
            .collect();
        let mut open = s.open.clone();
        open[i] = false;
        let recheck = if detected {
            let before = match s.recheck {
                Some((j, k)) if j == i => k,
                _ => 0,
            };
            Some((i, before + 1))
        } else {
            None
        };
        Some((
            p,
            OnePassState {
                mass,
                pos: i + 1,
                open,
                recheck,
            },
        ))
    }

    /// The base policy's tour: the open cones in nearest-neighbour order of travel cost from
    /// `pos` (ties to the lower index), without the cone being rechecked.
    fn tour(&self, s: &OnePassState) -> Vec<usize> {
        let mut left: Vec<bool> = s.open.clone();
        if let Some((j, _)) = s.recheck {
            left[j] = false;
        }
        let mut pos = s.pos;
        let mut order = Vec::new();
        while let Some(i) = (0..self.n).filter(|&i| left[i]).min_by(|&a, &b| {
            self.cost[pos][a]
                .total_cmp(&self.cost[pos][b])
                .then(a.cmp(&b))
        }) {
            order.push(i);
            left[i] = false;
            pos = i + 1;
        }
        order
    }

    /// The base policy's first action at `s` (see the module docs).
    pub fn base_action(&self, s: &OnePassState) -> ViewConeAction {
        match s.recheck {
            Some((j, k)) if k >= 2 => ViewConeAction::DeclareFound { cone: j },
            Some((j, _)) => ViewConeAction::Process { cone: j },
            None => match self.tour(s).first() {
                Some(&i) => ViewConeAction::Process { cone: i },
                None => ViewConeAction::DeclareAbsent,
            },
        }
    }

    /// The exact expected value of following the base policy from `s`.
    pub fn base_value(&self, s: &OnePassState) -> f64 {
        if let Some((j, k)) = s.recheck {
            if k >= 2 {
                return self.found_value(s, j);
            }
        }
        let order = self.tour(s);
        let g = self.gamma;
        let mut total = 0.0;
        for (t, &m) in s.mass.iter().enumerate() {
            if m <= 0.0 {
                continue;
            }
            // Backwards over the tour: the value of the rest of the pass from each cone on.
            let mut rest = if t == self.n { self.absent } else { self.wrong };
            for (k, &i) in order.iter().enumerate().rev() {
                let from = if k == 0 {
                    match s.recheck {
                        Some((j, _)) => j + 1,
                        None => s.pos,
                    }
                } else {
                    order[k - 1] + 1
                };
                let d = self.det[i][t];
                let confirm =
                    -self.cost[i + 1][i] + g * (d * self.found_reward(t, i) + (1.0 - d) * rest);
                rest = -self.cost[from][i] + g * ((1.0 - d) * rest + d * confirm);
            }
            if let Some((j, _)) = s.recheck {
                // The pending confirmation look comes first.
                let d = self.det[j][t];
                rest = -self.cost[s.pos][j] + g * (d * self.found_reward(t, j) + (1.0 - d) * rest);
            }
            total += m * rest;
        }
        total
    }

    /// The best declaration allowed at `s` by its expected reward (ties to "absent"): the
    /// session's step guard.
    pub fn declare(&self, s: &OnePassState) -> ViewConeAction {
        match s.recheck {
            Some((i, _)) if self.found_value(s, i) > self.absent_value(s) => {
                ViewConeAction::DeclareFound { cone: i }
            }
            _ => ViewConeAction::DeclareAbsent,
        }
    }

    /// The leaf value: the better of declaring now and following the base policy.
    fn leaf(&self, s: &OnePassState) -> f64 {
        let found = s
            .recheck
            .map_or(f64::NEG_INFINITY, |(i, _)| self.found_value(s, i));
        found.max(self.absent_value(s)).max(self.base_value(s))
    }

    /// Depth-limited expectimax over the allowed actions, whose leaves are worth the better of
    /// declaring and following the base pass; returns the value and the action. Ties go to the
    /// lower action index of the view-cone model (process 0…n−1, found 0…n−1, absent).
    pub fn decide(&self, s: &OnePassState, depth: usize) -> (f64, ViewConeAction) {
        let mut best = (f64::NEG_INFINITY, ViewConeAction::DeclareAbsent);
        for i in (0..self.n).filter(|&i| s.may_process(i)) {
            let mut q = -self.cost[s.pos][i];
            for detected in [true, false] {
                if let Some((p, next)) = self.after(s, i, detected) {
                    let v = if depth <= 1 {
                        self.leaf(&next)
                    } else {
                        self.decide(&next, depth - 1).0
                    };
                    q += self.gamma * p * v;
                }
            }
            if q > best.0 {
                best = (q, ViewConeAction::Process { cone: i });
            }
        }
        if let Some((i, _)) = s.recheck {
            let q = self.found_value(s, i);
            if q > best.0 {
                best = (q, ViewConeAction::DeclareFound { cone: i });
            }
        }
        let q = self.absent_value(s);
        if q > best.0 {
            best = (q, ViewConeAction::DeclareAbsent);
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::viewcone::{euclidean_travel, DecisionRewards, ViewConeProblem};

    fn line(n: usize, p_total: f64) -> ViewConePomdp {
        let positions: Vec<[f64; 2]> = (0..n).map(|i| [1.0 + i as f64, 0.0]).collect();
        let (travel_from_start, travel) = euclidean_travel([0.0, 0.0], &positions, 0.5);
        ViewConePomdp::new(&ViewConeProblem {
            cone_prior: vec![p_total / n as f64; n],
            travel_from_start,
            travel,
            process_cost: 1.0,
            false_negative: 0.2,
            false_positive: 0.05,
            rewards: DecisionRewards {
                found: 100.0,
                absent: 20.0,
                wrong: -50.0,
            },
            discount: 0.99,
        })
        .unwrap()
    }

    #[test]
    fn the_base_tour_goes_nearest_first_and_skips_the_cone_being_rechecked() {
        let m = OnePassModel::new(&line(4, 0.8));
        let mut s = OnePassState::start(&[0.2; 4]);
        assert_eq!(m.tour(&s), vec![0, 1, 2, 3]);
        s.pos = 3; // at cone 2
        s.open[2] = false;
        s.recheck = Some((2, 1));
        assert_eq!(m.tour(&s), vec![1, 0, 3]);
    }

    #[test]
    fn a_look_that_detects_nothing_closes_its_cone_and_a_detection_opens_a_recheck() {
        let m = OnePassModel::new(&line(3, 0.9));
        let s = OnePassState::start(&[0.3; 3]);
        let (p_miss, miss) = m.after(&s, 1, false).unwrap();
        assert!(!miss.may_process(1));
        assert!(miss.mass[1] < s.mass[1]);
        let (p_hit, hit) = m.after(&s, 1, true).unwrap();
        assert!((p_miss + p_hit - 1.0).abs() < 1e-12);
        assert_eq!(hit.recheck, Some((1, 1)));
        assert!(hit.may_process(1));
        let (_, twice) = m.after(&hit, 1, true).unwrap();
        assert_eq!(twice.recheck, Some((1, 2)));
        assert!((twice.mass.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    }
}
