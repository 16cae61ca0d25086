//! HSVI's bounds against an independent oracle for two-state POMDPs, whose beliefs are one
//! number p = b(state 1): value iteration on a grid over p, with a point-based lower bound and a
//! grid-interpolation upper bound (see [`oracle::bracket`]). Neither shares code with the solver
//! beyond the model's tables. The solver's bounds must hold at every budget, converged or not:
//! `lower ≤ V* ≤ upper`, so `lower ≤ bracket_high` and `upper ≥ bracket_low`.
//!
//! These pin the underflow bug that made `avs pomdp solve` report a lower bound above the upper on
//! tiger at γ ≥ 0.975 (see the avs-pomdp docs, "Bound validity").

mod common;

use avs_pomdp::{simulate, solve, OfflineOptions, Pomdp, PomdpTables};
use proptest::prelude::*;

/// Value iteration on a grid over the one-dimensional belief simplex of a two-state POMDP.
mod oracle {
    use avs_pomdp::Pomdp;

    /// `f(p) = c + m p` with `c = α(0)`, `m = α(1) − α(0)`, p = b(state 1).
    #[derive(Debug, Clone, Copy)]
    struct Line {
        c: f64,
        m: f64,
    }

    impl Line {
        fn of(a0: f64, a1: f64) -> Self {
            Line { c: a0, m: a1 - a0 }
        }
        fn at(self, p: f64) -> f64 {
            self.c + self.m * p
        }
        /// Where `self` and `o` cross (slopes differ).
        fn cross(self, o: Line) -> f64 {
            (o.c - self.c) / (self.m - o.m)
        }
    }

    /// The lines of the upper envelope over p ∈ [0, 1], in increasing slope (the maximum of the
    /// input at every p is the maximum of the output).
    fn envelope(mut lines: Vec<Line>) -> Vec<Line> {
        lines.sort_by(|x, y| x.m.total_cmp(&y.m).then(x.c.total_cmp(&y.c)));
        let mut hull: Vec<Line> = Vec::with_capacity(lines.len());
        for l in lines {
            // Equal slopes: the later (larger intercept) wins.
            if hull.last().is_some_and(|last| last.m == l.m) {
                hull.pop();
            }
            // The middle of three lines never attains the maximum when the outer two cross at or
            // before it would take over.
            while hull.len() >= 2 {
                let (l1, l2) = (hull[hull.len() - 2], hull[hull.len() - 1]);
                if l1.cross(l) <= l1.cross(l2) {
                    hull.pop();
                } else {
                    break;
                }
            }
            hull.push(l);
        }
        // Restrict to [0, 1]: line k is the maximum on [cross(k−1, k), cross(k, k+1)].
        let n = hull.len();
        let kept: Vec<Line> = (0..n)
            .filter(|&k| {
                let start = if k == 0 {
                    f64::NEG_INFINITY
                } else {
                    hull[k - 1].cross(hull[k])
                };
                let end = if k + 1 == n {
                    f64::INFINITY
                } else {
                    hull[k].cross(hull[k + 1])
                };
                end >= 0.0 && start <= 1.0
            })
            .map(|k| hull[k])
            .collect();
        if kept.is_empty() {
            hull
        } else {
            kept
        }
    }

    /// One look-ahead from a grid point: per action, the reward and per observation
    /// `(P(z|b,a), posterior p', grid cell of p', weight of the cell's left end)`.
    struct Step {
        reward: f64,
        succ: Vec<(f64, f64, usize, f64)>,
    }

    /// `[low, high]` around V*(b₀):
    /// * `low` — point-based backups (PBVI) at the grid points: every α-vector is the value of a
    ///   real conditional plan built from earlier ones, so their maximum never exceeds V*.
    /// * `high` — the grid-interpolation upper bound (Lovejoy 1991; Hauskrecht 2000 §4): V* is
    ///   convex, so the linear interpolation of upper values at the grid points is an upper value
    ///   between them, and a Bellman backup of an upper bound is again one.
    ///
    /// Both start from the trivial bounds and iterate until they are `width` apart at b₀ or
    /// `max_iterations` ran out; the bracket is valid at every iteration.
    pub fn bracket(m: &Pomdp, grid: usize, width: f64, max_iterations: usize) -> (f64, f64) {
        assert_eq!(m.n_states(), 2, "the oracle is for two-state POMDPs");
        let g = m.discount();
        let p0 = m.initial_belief()[1];
        let mut ps: Vec<f64> = (0..grid).map(|i| i as f64 / (grid - 1) as f64).collect();
        ps.push(p0);
        ps.sort_by(f64::total_cmp);
        ps.dedup();
        let i0 = ps.iter().position(|&p| p == p0).unwrap();
        let cell = |p: f64| -> (usize, f64) {
            let i = ps.partition_point(|&x| x <= p).clamp(1, ps.len() - 1) - 1;
            let w = (ps[i + 1] - p) / (ps[i + 1] - ps[i]);
            (i, w.clamp(0.0, 1.0))
        };
        let steps: Vec<Vec<Step>> = ps
            .iter()
            .map(|&p| {
                let b = [1.0 - p, p];
                (0..m.n_actions())
                    .map(|a| {
                        let reward = b[0] * m.reward(0, a) + b[1] * m.reward(1, a);
                        // Where z cannot follow this belief (P = 0) the posterior is unused by the
                        // upper bound and any α is valid for the lower one: keep the belief itself.
                        let succ = (0..m.n_observations())
                            .map(|z| {
                                let w: Vec<f64> = (0..2)
                                    .map(|s2| {
                                        (0..2).map(|s| b[s] * m.transition(s, a, s2)).sum::<f64>()
                                            * m.observation(a, s2, z)
                                    })
                                    .collect();
                                let pz = w[0] + w[1];
                                let post = if pz > 0.0 { w[1] / pz } else { p };
                                let (i, wl) = cell(post);
                                (pz, post, i, wl)
                            })
                            .collect();
                        Step { reward, succ }
                    })
                    .collect()
            })
            .collect();
        let rewards = (0..m.n_actions()).flat_map(|a| [m.reward(0, a), m.reward(1, a)]);
        let (rmin, rmax) = rewards.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
            (lo.min(r), hi.max(r))
        });
        let mut upper = vec![rmax / (1.0 - g); ps.len()];
        let mut lines = vec![Line::of(rmin / (1.0 - g), rmin / (1.0 - g))];
        // The maximiser at p on an envelope (slopes increasing): the first line whose right
        // crossing is at or past p, by bisection.
        let best = |lines: &[Line], p: f64| -> usize {
            let (mut lo, mut hi) = (0, lines.len() - 1);
            while lo < hi {
                let mid = (lo + hi) / 2;
                if lines[mid].cross(lines[mid + 1]) < p {
                    lo = mid + 1;
                } else {
                    hi = mid;
                }
            }
            lo
        };
        for _ in 0..max_iterations {
            let low = lines
                .iter()
                .map(|l| l.at(p0))
                .fold(f64::NEG_INFINITY, f64::max);
            if upper[i0] - low <= width {
                break;
            }
            // Upper: interpolated backup at every grid point.
            upper = steps
                .iter()
                .map(|acts| {
                    acts.iter()
                        .map(|st| {
                            st.reward
                                + g * st
                                    .succ
                                    .iter()
                                    .filter(|&&(pz, ..)| pz > 0.0)
                                    .map(|&(pz, _, i, wl)| {
                                        pz * (wl * upper[i] + (1.0 - wl) * upper[i + 1])
                                    })
                                    .sum::<f64>()
                        })
                        .fold(f64::NEG_INFINITY, f64::max)
                })
                .collect();
            // Lower: the best backed-up α-vector at every grid point.
            let project = |a: usize, z: usize, l: Line, s: usize| -> f64 {
                (0..2)
                    .map(|s2| m.transition(s, a, s2) * m.observation(a, s2, z) * l.at(s2 as f64))
                    .sum()
            };
            let mut next: Vec<Line> = Vec::with_capacity(ps.len());
            for (k, acts) in steps.iter().enumerate() {
                let pk = ps[k];
                let mut chosen: Option<(f64, Line)> = None;
                for (a, st) in acts.iter().enumerate() {
                    let mut alpha = [m.reward(0, a), m.reward(1, a)];
                    for (z, &(_, post, _, _)) in st.succ.iter().enumerate() {
                        let l = lines[best(&lines, post)];
                        for (s, v) in alpha.iter_mut().enumerate() {
                            *v += g * project(a, z, l, s);
                        }
                    }
                    let line = Line::of(alpha[0], alpha[1]);
                    if chosen.is_none_or(|(v, _)| line.at(pk) > v) {
                        chosen = Some((line.at(pk), line));
                    }
                }
                next.push(chosen.unwrap().1);
            }
            lines = envelope(next);
        }
        let low = lines
            .iter()
            .map(|l| l.at(p0))
            .fold(f64::NEG_INFINITY, f64::max);
        (low, upper[i0])
    }
}

use common::tiger;

#[test]
fn the_oracle_reproduces_tigers_published_value() {
    // reference_values.csv (pomdp-solve's exact value iteration): 19.371368.
    let (lo, hi) = oracle::bracket(&tiger(0.95), 1001, 1e-6, 100_000);
    assert!(
        lo <= 19.371368 + 1e-6 && 19.371368 - 1e-6 <= hi,
        "[{lo}, {hi}]"
    );
    assert!(hi - lo <= 1e-6);
}

/// Tiger from the textbook discount up to 0.999: the solver's bounds (after a trial budget that is
/// far from convergence at the high discounts) are ordered, bracket the exact value, and bracket the
/// mean return of the lower bound's own policy within that mean's 95 % interval.
#[test]
fn tiger_bounds_bracket_the_exact_value_and_the_simulated_return_up_to_discount_0_999() {
    for discount in [0.95, 0.975, 0.98, 0.99, 0.998, 0.999] {
        let m = tiger(discount);
        let (v_low, v_high) = oracle::bracket(&m, 401, 1e-3, 200_000);
        let sol = solve(
            &m,
            &OfflineOptions {
                target_gap: 1e-3,
                max_trials: 60,
                ..Default::default()
            },
        )
        .unwrap();
        assert!(
            sol.lower <= sol.upper,
            "γ = {discount}: lower {} above upper {}",
            sol.lower,
            sol.upper
        );
        assert!(
            sol.lower <= v_high + 1e-9 && v_low - 1e-9 <= sol.upper,
            "γ = {discount}: solver [{}, {}] misses the exact value [{v_low}, {v_high}]",
            sol.lower,
            sol.upper
        );
        // The lower bound's policy is worth at least the lower bound and at most V*.
        let horizon = avs_pomdp::horizon_for(&m, 1e-2);
        let sim = simulate(&m, 300, horizon, 7, |b| sol.bounds.lower_action(b)).unwrap();
        assert!(
            sim.ci95_low <= sol.upper && sol.lower <= sim.ci95_high,
            "γ = {discount}: simulated [{}, {}] outside the bounds [{}, {}]",
            sim.ci95_low,
            sim.ci95_high,
            sol.lower,
            sol.upper
        );
        assert!(
            sim.ci95_low <= v_high,
            "γ = {discount}: the policy beats the optimum: {} > {v_high}",
            sim.ci95_low
        );
    }
}

/// A random two-state POMDP: rows of T and O with some exact zeros, rewards in [−10, 10].
fn two_state_pomdp() -> impl Strategy<Value = Pomdp> {
    (
        2usize..=3,
        2usize..=3,
        prop::sample::select(vec![0.9, 0.95, 0.99, 0.995, 0.999]),
    )
        .prop_flat_map(|(na, no, discount)| {
            let row = |n: usize| {
                prop::collection::vec(prop_oneof![1 => Just(0.0), 4 => 0.05f64..1.0], n)
                    .prop_filter("a row needs mass", |r| r.iter().sum::<f64>() > 0.0)
            };
            (
                prop::collection::vec(row(2), na * 2),
                prop::collection::vec(row(no), na * 2),
                prop::collection::vec(-10.0f64..10.0, na * 2),
                0.0f64..=1.0,
                Just((na, no, discount)),
            )
        })
        .prop_map(|(t_rows, o_rows, rewards, p0, (na, no, discount))| {
            let norm = |r: &Vec<f64>| {
                let s: f64 = r.iter().sum();
                r.iter().map(|x| x / s).collect::<Vec<f64>>()
            };
            Pomdp::new(PomdpTables {
                states: vec!["s0".into(), "s1".into()],
                actions: (0..na).map(|a| format!("a{a}")).collect(),
                observations: (0..no).map(|z| format!("z{z}")).collect(),
                discount,
                transitions: t_rows.iter().flat_map(norm).collect(),
                observation_probs: o_rows.iter().flat_map(norm).collect(),
                rewards,
                initial: vec![1.0 - p0, p0],
            })
            .unwrap()
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 40, ..ProptestConfig::default() })]

    #[test]
    fn hsvi_bounds_bracket_the_exact_value_of_random_two_state_pomdps(m in two_state_pomdp()) {
        let (v_low, v_high) = oracle::bracket(&m, 201, 1e-3, 100_000);
        let sol = solve(
            &m,
            &OfflineOptions { target_gap: 1e-3, max_trials: 40, ..Default::default() },
        )
        .unwrap();
        prop_assert!(sol.lower <= sol.upper, "lower {} above upper {}", sol.lower, sol.upper);
        prop_assert!(
            sol.lower <= v_high + 1e-7 * v_high.abs().max(1.0),
            "lower {} above the exact value [{v_low}, {v_high}]",
            sol.lower
        );
        prop_assert!(
            sol.upper >= v_low - 1e-7 * v_low.abs().max(1.0),
            "upper {} below the exact value [{v_low}, {v_high}]",
            sol.upper
        );
    }
}
