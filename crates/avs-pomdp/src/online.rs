//! Online solver: real-time belief space search (RTBSS; Paquet, Tobin & Chaib-draa 2005), in the form
//! of Ross, Pineau, Paquet & Chaib-draa 2008, *Online planning algorithms for POMDPs*, Algorithm 3.2:
//!
//! ```text
//! Expand(b, d):
//!   if d = 0: return L(b)
//!   sort actions by U(b, a) = R(b,a) + γ Σ_z P(z|b,a) U(τ(b,a,z)) in decreasing order
//!   L_T(b) ← −∞
//!   for each a while U(b, a) > L_T(b):
//!     L_T(b, a) ← R(b,a) + γ Σ_z P(z|b,a) Expand(τ(b,a,z), d − 1)
//!     L_T(b) ← max(L_T(b), L_T(b, a))
//!   return L_T(b)
//! ```
//!
//! `L` and `U` are the offline bounds of [`crate::bounds::Bounds`]. Because `U` bounds the depth-limited
//! value with leaves `L` from above, branch-and-bound never changes the value: it equals brute-force
//! [`expectimax`] to the same depth with the same leaves. The search is anytime: with a budget it
//! deepens iteratively and returns the deepest completed answer. The budget is wall time
//! (`time_limit`, answers depend on the machine) or belief nodes (`node_limit`, deterministic:
//! the same model, belief and limit give the same answer anywhere).

use crate::bounds::Bounds;
use crate::error::{PomdpError, Result};
use crate::model::{to_sparse, Expansion, Pomdp, Sparse};
use std::time::{Duration, Instant};

/// Budget of one online decision.
#[derive(Debug, Clone)]
pub struct OnlineOptions {
    /// Maximum search depth (number of actions looked ahead); at least 1.
    pub depth: usize,
    /// Optional wall-time budget; the search deepens from 1 and keeps the deepest completed result.
    pub time_limit: Option<Duration>,
    /// Optional budget of belief nodes expanded over all depths; like `time_limit`, the search
    /// deepens from 1 and keeps the deepest depth completed within it (depth 1 always completes).
    pub node_limit: Option<usize>,
}

impl Default for OnlineOptions {
    fn default() -> Self {
        Self {
            depth: 2,
            time_limit: None,
            node_limit: None,
        }
    }
}

/// One decision of the online solver.
#[derive(Debug, Clone, PartialEq)]
pub struct OnlineDecision {
    /// The chosen action.
    pub action: usize,
    /// Its depth-limited lower value `L_T(b)` (a lower bound on V*(b)).
    pub value: f64,
    /// Depth of the completed search that produced it.
    pub depth: usize,
    /// Belief nodes expanded.
    pub nodes: usize,
}

struct Search<'a> {
    m: &'a Pomdp,
    bounds: &'a Bounds,
    deadline: Option<Instant>,
    /// Expand no node once `nodes` reaches this.
    node_limit: Option<usize>,
    nodes: usize,
    scratch: Vec<f64>,
    touched: Vec<usize>,
}

impl Search<'_> {
    /// Returns `None` when the deadline passed or the node budget is spent.
    fn expand(&mut self, b: &[(usize, f64)], d: usize) -> Option<(f64, usize)> {
        if d == 0 {
            return Some((self.bounds.lower_sparse(b).0, 0));
        }
        if let Some(t) = self.deadline {
            if self.nodes & 63 == 0 && Instant::now() >= t {
                return None;
            }
        }
        if self.node_limit.is_some_and(|n| self.nodes >= n) {
            return None;
        }
        self.nodes += 1;
        let gamma = self.m.discount();
        if d == 1 {
            // Children are leaves: computing U(b, a) to prune would cost as much as the leaf values
            // themselves, so take the exact maximum over all actions (same value as with pruning).
            let mut best = (f64::NEG_INFINITY, 0);
            for a in 0..self.m.n_actions() {
                let (r, succ) = self.m.expand(b, a, &mut self.scratch, &mut self.touched);
                let q = r + gamma
                    * succ
                        .iter()
                        .filter(|(p, _)| *p > 0.0)
                        .map(|(p, post)| p * self.bounds.lower_sparse(post).0)
                        .sum::<f64>();
                if q > best.0 {
                    best = (q, a);
                }
            }
            return Some(best);
        }
        let mut cands: Vec<(f64, usize, Expansion)> = (0..self.m.n_actions())
            .map(|a| {
                let (r, succ) = self.m.expand(b, a, &mut self.scratch, &mut self.touched);
                let u = r + gamma
                    * succ
                        .iter()
                        .filter(|(p, _)| *p > 0.0)
                        .map(|(p, post)| p * self.bounds.upper_sparse(post))
                        .sum::<f64>();
                (u, a, (r, succ))
            })
            .collect();
        // Stable sort: ties keep the lower action index first.
        cands.sort_by(|x, y| y.0.total_cmp(&x.0));
        let mut best = f64::NEG_INFINITY;
        let mut best_a = cands[0].1;
        for (u, a, (r, succ)) in &cands {
            if *u <= best {
                break;
            }
            let mut q = *r;
            for (p, post) in succ {
                if *p > 0.0 {
                    q += gamma * p * self.expand(post, d - 1)?.0;
                }
            }
            if q > best {
                best = q;
                best_a = *a;
            }
        }
        Some((best, best_a))
    }
}

/// Choose an action at belief `b` by RTBSS over the offline `bounds`.
pub fn rtbss(
    m: &Pomdp,
    bounds: &Bounds,
    b: &[f64],
    opts: &OnlineOptions,
) -> Result<OnlineDecision> {
    m.check_belief(b)?;
    if bounds.n_states() != m.n_states() {
        return Err(PomdpError::InvalidArgument(format!(
            "bounds are for {} states, the model has {}",
            bounds.n_states(),
            m.n_states()
        )));
    }
    if opts.depth == 0 {
        return Err(PomdpError::InvalidArgument(
            "online search depth must be at least 1".into(),
        ));
    }
    rtbss_sparse(m, bounds, &to_sparse(b), opts)
}

pub(crate) fn rtbss_sparse(
    m: &Pomdp,
    bounds: &Bounds,
    b: &Sparse,
    opts: &OnlineOptions,
) -> Result<OnlineDecision> {
    let start = Instant::now();
    let mut search = Search {
        m,
        bounds,
        deadline: opts.time_limit.map(|t| start + t),
        node_limit: opts.node_limit,
        nodes: 0,
        scratch: vec![0.0; m.n_states()],
        touched: Vec::new(),
    };
    let first_depth = if opts.time_limit.is_some() || opts.node_limit.is_some() {
        1
    } else {
        opts.depth
    };
    let mut result: Option<OnlineDecision> = None;
    for d in first_depth..=opts.depth {
        let (deadline, node_limit) = (search.deadline, search.node_limit);
        if result.is_none() {
            // Always complete depth 1 so there is an answer.
            search.deadline = None;
            search.node_limit = None;
        }
        let out = search.expand(b, d);
        (search.deadline, search.node_limit) = (deadline, node_limit);
        match out {
            Some((value, action)) => {
                result = Some(OnlineDecision {
                    action,
                    value,
                    depth: d,
                    nodes: search.nodes,
                })
            }
            None => break,
        }
    }
    result.ok_or_else(|| PomdpError::InvalidArgument("online search produced no decision".into()))
}

/// Brute-force expectimax to `depth` with leaf values `leaf(b)`: the reference that RTBSS must match.
/// Returns `(value, action)`; ties go to the lowest action index. Exponential: for tests and small
/// problems only.
pub fn expectimax(
    m: &Pomdp,
    b: &[f64],
    depth: usize,
    leaf: &dyn Fn(&[f64]) -> f64,
) -> Result<(f64, usize)> {
    m.check_belief(b)?;
    if depth == 0 {
        return Ok((leaf(b), 0));
    }
    let mut best = (f64::NEG_INFINITY, 0);
    for a in 0..m.n_actions() {
        let mut q = m.expected_reward(b, a);
        for z in 0..m.n_observations() {
            if let Ok((post, p)) = m.update(b, a, z) {
                q += m.discount() * p * expectimax(m, &post, depth - 1, leaf)?.0;
            }
        }
        if q > best.0 {
            best = (q, a);
        }
    }
    Ok(best)
}
