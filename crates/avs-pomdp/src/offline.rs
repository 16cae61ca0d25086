//! Offline point-based solver: heuristic search value iteration (HSVI2, Smith & Simmons 2005,
//! "Point-based POMDP algorithms: improved analysis and implementation", Algorithm 1).
//!
//! Each trial walks from b₀, choosing the action with the best upper bound
//! `a* = argmax_a Q̄(b, a)` and the observation with the largest weighted excess uncertainty
//! `z* = argmax_z P(z|b,a*) · (V̄ − V̲)(τ(b,a*,z)) − ε γ^{−(t+1)}` (HSVI eq. 9–10), until the gap at the
//! current belief is below `ε γ^{−t}`; then both bounds are backed up along the path in reverse.
//! The solve ends when the gap `V̄(b₀) − V̲(b₀)` is at most the target, or the time/iteration budget is
//! spent: the gap at the initial belief is what drives termination.
//!
//! ## Bounded time and memory
//! * **The time limit is checked inside a trial**, before each step of the forward pass and each
//!   backup, and inside the initial bounds' sweeps ([`Bounds::initial_until`]), not only between
//!   trials: one trial on a model with many states and observations can take minutes (a trial
//!   descends up to `log(ε / gap) / log γ` steps, each a look-ahead over every action and
//!   observation). Stopping anywhere is safe, since every backup keeps both bounds valid, so a
//!   limited solve returns within about one look-ahead of its limit with
//!   [`StopReason::TimeLimit`].
//! * **A trial's memory is bounded**: the forward pass keeps each step's look-ahead for the
//!   backup while the trial holds at most [`MAX_TRIAL_ENTRIES`] numbers (beliefs, Q-values,
//!   posteriors); beyond that, look-aheads are recomputed at backup (same values, more time),
//!   and a trial whose beliefs alone reach the bound ends its descent there. Before this, a
//!   model with 1,000 states and 1,000 observations stored 10⁶ posterior entries per step and
//!   grew past 5 GB within one trial. Model size itself is bounded when the model is built
//!   ([`crate::model::MAX_MODEL_ENTRIES`]).
//! * **Results are checked** before they are returned: bounds that are not finite or cross
//!   (lower above upper, beyond rounding) are [`PomdpError::Numerical`], never a "converged"
//!   solution.

use crate::bounds::Bounds;
use crate::error::{PomdpError, Result};
use crate::model::{to_sparse, Expansion, Pomdp, Sparse};
use std::time::{Duration, Instant};

/// Most numbers one HSVI trial keeps along its path (beliefs, upper Q-values and the stored
/// look-aheads), [`crate::model::MAX_MODEL_ENTRIES`]: about 268 MB at 16 bytes an entry. See
/// the module docs.
pub const MAX_TRIAL_ENTRIES: usize = crate::model::MAX_MODEL_ENTRIES;

/// Numbers held by one look-ahead.
fn expansion_entries(exps: &[Expansion]) -> usize {
    exps.iter()
        .map(|(_, succ)| succ.len() + succ.iter().map(|(_, post)| post.len()).sum::<usize>())
        .sum()
}

/// Budget and precision of an offline solve.
#[derive(Debug, Clone)]
pub struct OfflineOptions {
    /// Stop when `upper − lower` at the initial belief is at most this.
    pub target_gap: f64,
    /// Stop after this much wall time (anytime: the bounds stay valid).
    pub time_limit: Option<Duration>,
    /// Stop after this many HSVI trials.
    pub max_trials: usize,
    /// Sweeps of the initial fixed-point bounds (blind policy, Q_MDP, FIB).
    pub init_iterations: usize,
}

impl Default for OfflineOptions {
    fn default() -> Self {
        Self {
            target_gap: 1e-3,
            time_limit: None,
            max_trials: 1_000_000,
            init_iterations: 2_000,
        }
    }
}

/// Why a solve stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// The gap at the initial belief reached the target.
    Converged,
    /// The time limit was reached.
    TimeLimit,
    /// The trial limit was reached.
    TrialLimit,
}

/// Result of an offline solve: valid bounds everywhere and their values at b₀.
#[derive(Debug, Clone)]
pub struct OfflineSolution {
    /// The bounds (usable by [`crate::online`] and as a policy through [`Bounds::lower_action`]).
    pub bounds: Bounds,
    /// `V̲(b₀)`.
    pub lower: f64,
    /// `V̄(b₀)`.
    pub upper: f64,
    /// HSVI trials run.
    pub trials: usize,
    /// Backups performed.
    pub backups: usize,
    /// Wall time of the solve.
    pub seconds: f64,
    /// Why it stopped.
    pub stop: StopReason,
}

impl OfflineSolution {
    /// `upper − lower` at the initial belief.
    pub fn gap(&self) -> f64 {
        self.upper - self.lower
    }
}

/// Solve from the model's initial belief.
pub fn solve(m: &Pomdp, opts: &OfflineOptions) -> Result<OfflineSolution> {
    solve_from(m, m.initial_belief(), None, opts)
}

/// Solve from belief `b0`, optionally refining existing `bounds` (which must belong to `m`).
pub fn solve_from(
    m: &Pomdp,
    b0: &[f64],
    bounds: Option<Bounds>,
    opts: &OfflineOptions,
) -> Result<OfflineSolution> {
    m.check_belief(b0)?;
    if !(opts.target_gap.is_finite() && opts.target_gap > 0.0) {
        return Err(PomdpError::InvalidArgument(format!(
            "target gap must be a positive number, got {}",
            opts.target_gap
        )));
    }
    let start = Instant::now();
    let deadline = opts.time_limit.and_then(|l| start.checked_add(l));
    let out_of_time = || deadline.is_some_and(|d| Instant::now() >= d);
    let mut bounds = match bounds {
        Some(b) => {
            if b.corners.len() != m.n_states() {
                return Err(PomdpError::InvalidArgument(
                    "bounds belong to a model with a different number of states".into(),
                ));
            }
            b
        }
        None => Bounds::initial_until(m, opts.init_iterations, deadline),
    };
    let b0 = to_sparse(b0);
    let gamma = m.discount();
    let eps = opts.target_gap;
    let mut scratch = vec![0.0; m.n_states()];
    let mut touched = Vec::new();
    let mut trials = 0;
    let mut backups = 0;
    let width = |bd: &Bounds, b: &[(usize, f64)]| bd.upper_sparse(b) - bd.lower_sparse(b).0;
    let max_depth = {
        // Beyond this depth γ^t times the largest possible gap is below ε.
        let span = width(&bounds, &b0).max(eps);
        ((eps / span).ln() / gamma.ln()).ceil().clamp(1.0, 10_000.0) as usize + 1
    };
    let mut last_pruned_size = 0usize;
    let stop = loop {
        if width(&bounds, &b0) <= eps {
            break StopReason::Converged;
        }
        if trials >= opts.max_trials {
            break StopReason::TrialLimit;
        }
        if out_of_time() {
            break StopReason::TimeLimit;
        }
        trials += 1;
        // Forward pass. A node keeps its look-ahead (all actions' posteriors) for the backup
        // while the trial is within its memory bound; otherwise it is recomputed there.
        type Node = (Sparse, Option<Vec<Expansion>>, Vec<f64>, usize);
        let mut path: Vec<Node> = Vec::new();
        let mut held = 0usize;
        let mut b = b0.clone();
        let mut t = 0usize;
        let mut threshold = eps;
        let mut known_width: Option<f64> = None;
        loop {
            let w = known_width.unwrap_or_else(|| width(&bounds, &b));
            if w <= threshold || t >= max_depth || out_of_time() {
                break;
            }
            held = held.saturating_add(b.len() + m.n_actions());
            if held > MAX_TRIAL_ENTRIES && !path.is_empty() {
                break;
            }
            let exps: Vec<Expansion> = (0..m.n_actions())
                .map(|a| m.expand(&b, a, &mut scratch, &mut touched))
                .collect();
            let mut best_a = 0;
            let mut best_q = f64::NEG_INFINITY;
            let mut qs = Vec::with_capacity(exps.len());
            let mut uppers: Vec<Vec<f64>> = Vec::with_capacity(exps.len());
            for (a, (r, succ)) in exps.iter().enumerate() {
                let us: Vec<f64> = succ
                    .iter()
                    .map(|(p, post)| {
                        if *p > 0.0 {
                            bounds.upper_sparse(post)
                        } else {
                            0.0
                        }
                    })
                    .collect();
                let q = r + gamma * succ.iter().zip(&us).map(|((p, _), u)| p * u).sum::<f64>();
                qs.push(q);
                uppers.push(us);
                if q > best_q {
                    best_q = q;
                    best_a = a;
                }
            }
            let next_threshold = threshold / gamma;
            let mut best_z = None;
            let mut best_score = f64::NEG_INFINITY;
            let mut best_width = 0.0;
            for (z, (p, post)) in exps[best_a].1.iter().enumerate() {
                if *p <= 0.0 {
                    continue;
                }
                let wz = uppers[best_a][z] - bounds.lower_sparse(post).0;
                let score = p * (wz - next_threshold);
                if score > best_score {
                    best_score = score;
                    best_z = Some(z);
                    best_width = wz;
                }
            }
            let next = best_z.map(|z| exps[best_a].1[z].1.clone());
            let size = expansion_entries(&exps);
            let keep = held.saturating_add(size) <= MAX_TRIAL_ENTRIES;
            if keep {
                held += size;
            }
            path.push((b, keep.then_some(exps), qs, best_a));
            match next {
                Some(n) => b = n,
                None => break,
            }
            known_width = Some(best_width);
            threshold = next_threshold;
            t += 1;
        }
        // Backward pass (every backup keeps both bounds valid, so it may stop at the limit).
        for (b, exps, qs, best_a) in path.iter().rev() {
            if out_of_time() {
                break;
            }
            let recomputed;
            let exps = match exps {
                Some(e) => e,
                None => {
                    recomputed = (0..m.n_actions())
                        .map(|a| m.expand(b, a, &mut scratch, &mut touched))
                        .collect::<Vec<_>>();
                    &recomputed
                }
            };
            bounds.backup(m, b, exps, Some((qs, *best_a)));
            backups += 1;
        }
        // Prune when the bounds have grown by half since the last pruning (pruning is quadratic).
        let size = bounds.n_upper_points() + bounds.alphas.len();
        if size > last_pruned_size + last_pruned_size / 2 + 16 && !out_of_time() {
            bounds.prune_points();
            bounds.prune_alphas_by_witness(std::slice::from_ref(&b0));
            last_pruned_size = bounds.n_upper_points() + bounds.alphas.len();
        }
    };
    bounds.prune_alphas();
    let lower = bounds.lower_sparse(&b0).0;
    let upper = bounds.upper_sparse(&b0);
    tracing::debug!(
        lower,
        upper,
        trials,
        backups,
        alphas = bounds.alphas.len(),
        upper_points = bounds.n_upper_points(),
        "HSVI finished"
    );
    // Both bounds are valid by construction; what breaks them is arithmetic that f64 cannot carry.
    // Say so instead of printing them (the tolerance allows the rounding of a converged solve).
    if !(lower.is_finite() && upper.is_finite()) {
        return Err(PomdpError::Numerical {
            lower,
            upper,
            reason: "a bound is not finite",
        });
    }
    if lower > upper + 1e-9 * upper.abs().max(1.0) {
        return Err(PomdpError::Numerical {
            lower,
            upper,
            reason: "the lower bound is above the upper",
        });
    }
    Ok(OfflineSolution {
        bounds,
        lower,
        upper,
        trials,
        backups,
        seconds: start.elapsed().as_secs_f64(),
        stop,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::PomdpTables;

    fn coin() -> Pomdp {
        // Two states, one informative observation pair, two actions.
        Pomdp::new(PomdpTables {
            states: vec!["a".into(), "b".into()],
            actions: vec!["stay".into(), "swap".into()],
            observations: vec!["sa".into(), "sb".into()],
            discount: 0.9,
            transitions: vec![1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0],
            observation_probs: vec![0.8, 0.2, 0.2, 0.8, 0.8, 0.2, 0.2, 0.8],
            rewards: vec![1.0, 0.0, 0.0, 1.0],
            initial: vec![0.5, 0.5],
        })
        .unwrap()
    }

    /// A solve whose bounds cross or are not finite is an error, never a "converged" result
    /// (issue 18: rewards of 1e300 printed lower > upper and "Converged").
    #[test]
    fn crossed_or_infinite_bounds_are_an_error_not_a_solution() {
        let m = coin();
        let opts = OfflineOptions {
            max_trials: 10,
            ..Default::default()
        };
        assert!(solve(&m, &opts).is_ok());
        let mut crossed = Bounds::initial(&m, 100);
        crossed.corners.iter_mut().for_each(|c| *c -= 100.0);
        match solve_from(&m, m.initial_belief(), Some(crossed), &opts) {
            Err(PomdpError::Numerical { lower, upper, .. }) => assert!(lower > upper),
            other => panic!("expected a numerical error, got {other:?}"),
        }
        let mut infinite = Bounds::initial(&m, 100);
        infinite.alphas[0].values[0] = f64::INFINITY;
        assert!(matches!(
            solve_from(&m, m.initial_belief(), Some(infinite), &opts),
            Err(PomdpError::Numerical { .. })
        ));
    }

    /// A time limit stops a solve even inside its first trial: a limit of zero returns the
    /// initial bounds at once, marked as stopped by time.
    #[test]
    fn a_zero_time_limit_returns_the_initial_bounds() {
        let m = coin();
        let sol = solve(
            &m,
            &OfflineOptions {
                time_limit: Some(Duration::ZERO),
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(sol.stop, StopReason::TimeLimit);
        assert_eq!(sol.trials, 0);
        assert!(sol.lower <= sol.upper);
    }
}
