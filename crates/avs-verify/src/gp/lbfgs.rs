//! A projected L-BFGS for minimisation inside a box `lo ≤ x ≤ hi`.
//!
//! Each iteration fixes the variables that sit on a bound with the gradient pushing outward,
//! takes the L-BFGS two-loop direction in the remaining (free) variables, using the stored
//! curvature pairs restricted to them, and searches along the projected path
//! `x(t) = P(x + t d)` with an Armijo backtracking test `f(x(t)) ≤ f(x) + c₁ gᵀ(x(t) − x)`
//! (Bertsekas 1982's projected Newton scheme with an L-BFGS metric; Kim, Sra & Dhillon 2010).
//! It stops when the projected gradient `P(x − g) − x` is below `pg_tolerance` in every
//! component, when an accepted step lowers `f` by less than `f_tolerance · max(|f|, 1)`, or
//! after `max_iterations` / `max_evaluations`. Points where the objective is undefined
//! (`None`, or a non-finite value) count as `+∞` and make the line search backtrack.

use std::collections::VecDeque;

/// Settings of [`minimize`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct Settings {
    /// Number of curvature pairs kept.
    pub memory: usize,
    /// Iteration limit.
    pub max_iterations: usize,
    /// Objective-evaluation limit.
    pub max_evaluations: usize,
    /// Stop when every projected-gradient component is at most this.
    pub pg_tolerance: f64,
    /// Stop when a step lowers `f` by at most this times `max(|f|, 1)`.
    pub f_tolerance: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            memory: 10,
            max_iterations: 1000,
            max_evaluations: 5000,
            pg_tolerance: 1e-9,
            f_tolerance: 1e-14,
        }
    }
}

/// The result of [`minimize`].
#[derive(Debug, Clone)]
pub(crate) struct Minimum {
    /// The best point found (inside the box).
    pub x: Vec<f64>,
    /// The objective there.
    pub f: f64,
}

struct Pair {
    s: Vec<f64>,
    y: Vec<f64>,
}

fn dot_masked(a: &[f64], b: &[f64], free: &[bool]) -> f64 {
    a.iter()
        .zip(b)
        .zip(free)
        .filter(|(_, &f)| f)
        .map(|((x, y), _)| x * y)
        .sum()
}

/// `−H g` in the free variables by the two-loop recursion (Nocedal & Wright, Alg. 7.4), 0 in the
/// fixed ones. Pairs without positive curvature in the free subspace are skipped.
fn direction(g: &[f64], free: &[bool], pairs: &VecDeque<Pair>) -> Vec<f64> {
    let mut q: Vec<f64> = g
        .iter()
        .zip(free)
        .map(|(&gi, &f)| if f { gi } else { 0.0 })
        .collect();
    let usable: Vec<(&Pair, f64)> = pairs
        .iter()
        .filter_map(|p| {
            let sy = dot_masked(&p.s, &p.y, free);
            let yy = dot_masked(&p.y, &p.y, free);
            (sy > 1e-12 * yy.max(f64::MIN_POSITIVE) && sy > 0.0).then_some((p, 1.0 / sy))
        })
        .collect();
    let mut a = vec![0.0; usable.len()];
    for (k, (p, rho)) in usable.iter().enumerate().rev() {
        a[k] = rho * dot_masked(&p.s, &q, free);
        for i in 0..q.len() {
            if free[i] {
                q[i] -= a[k] * p.y[i];
            }
        }
    }
    if let Some((p, rho)) = usable.last() {
        let gamma = 1.0 / (rho * dot_masked(&p.y, &p.y, free));
        q.iter_mut().for_each(|v| *v *= gamma);
    }
    for (k, (p, rho)) in usable.iter().enumerate() {
        let b = rho * dot_masked(&p.y, &q, free);
        for i in 0..q.len() {
            if free[i] {
                q[i] += (a[k] - b) * p.s[i];
            }
        }
    }
    q.iter_mut().for_each(|v| *v = -*v);
    q
}

fn project(x: &[f64], lo: &[f64], hi: &[f64]) -> Vec<f64> {
    x.iter()
        .zip(lo.iter().zip(hi))
        .map(|(&v, (&l, &h))| v.clamp(l, h))
        .collect()
}

/// Minimises `f` (value and gradient, `None` where undefined) from `x0` inside `[lo, hi]`.
/// `None` when `f` is undefined at the projected start.
pub(crate) fn minimize<F>(
    mut f: F,
    x0: &[f64],
    lo: &[f64],
    hi: &[f64],
    s: &Settings,
) -> Option<Minimum>
where
    F: FnMut(&[f64]) -> Option<(f64, Vec<f64>)>,
{
    let n = x0.len();
    let evals = std::cell::Cell::new(0usize);
    let mut eval = |x: &[f64]| -> Option<(f64, Vec<f64>)> {
        evals.set(evals.get() + 1);
        f(x).filter(|(v, g)| v.is_finite() && g.len() == n && g.iter().all(|c| c.is_finite()))
    };
    let mut x = project(x0, lo, hi);
    let (mut fx, mut g) = eval(&x)?;
    let mut pairs: VecDeque<Pair> = VecDeque::new();
    for _ in 0..s.max_iterations {
        // Projected gradient and the free variables.
        let pg_max = (0..n)
            .map(|i| ((x[i] - g[i]).clamp(lo[i], hi[i]) - x[i]).abs())
            .fold(0.0, f64::max);
        if pg_max <= s.pg_tolerance {
            break;
        }
        let free: Vec<bool> = (0..n)
            .map(|i| !((x[i] <= lo[i] && g[i] > 0.0) || (x[i] >= hi[i] && g[i] < 0.0)))
            .collect();
        let mut d = direction(&g, &free, &pairs);
        let mut slope: f64 = d.iter().zip(&g).map(|(a, b)| a * b).sum();
        if slope >= 0.0 || pairs.is_empty() {
            // Steepest descent in the free variables, first step at most 1 in every coordinate.
            pairs.clear();
            d = (0..n).map(|i| if free[i] { -g[i] } else { 0.0 }).collect();
            let dmax = d.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            if dmax > 1.0 {
                d.iter_mut().for_each(|v| *v /= dmax);
            }
            slope = d.iter().zip(&g).map(|(a, b)| a * b).sum();
            if slope >= 0.0 {
                break;
            }
        }
        // Backtracking along the projected path.
        let mut t = 1.0;
        let mut accepted = None;
        for _ in 0..60 {
            if evals.get() >= s.max_evaluations {
                break;
            }
            let xt: Vec<f64> = project(
                &x.iter().zip(&d).map(|(a, b)| a + t * b).collect::<Vec<_>>(),
                lo,
                hi,
            );
            let step: Vec<f64> = xt.iter().zip(&x).map(|(a, b)| a - b).collect();
            if step.iter().all(|v| *v == 0.0) {
                break;
            }
            let decrease: f64 = step.iter().zip(&g).map(|(a, b)| a * b).sum();
            if let Some((ft, gt)) = eval(&xt) {
                if ft <= fx + 1e-4 * decrease {
                    accepted = Some((xt, step, ft, gt));
                    break;
                }
            }
            t *= 0.5;
        }
        let Some((xt, step, ft, gt)) = accepted else {
            if pairs.is_empty() {
                break; // not even a steepest-descent step helps: converged as far as we can
            }
            pairs.clear();
            continue;
        };
        let yv: Vec<f64> = gt.iter().zip(&g).map(|(a, b)| a - b).collect();
        let sy: f64 = step.iter().zip(&yv).map(|(a, b)| a * b).sum();
        let yy: f64 = yv.iter().map(|v| v * v).sum();
        if sy > 1e-12 * yy {
            if pairs.len() == s.memory {
                pairs.pop_front();
            }
            pairs.push_back(Pair { s: step, y: yv });
        }
        let reduction = fx - ft;
        let scale = fx.abs().max(ft.abs()).max(1.0);
        x = xt;
        fx = ft;
        g = gt;
        if reduction <= s.f_tolerance * scale || evals.get() >= s.max_evaluations {
            break;
        }
    }
    Some(Minimum { x, f: fx })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rosenbrock(x: &[f64]) -> Option<(f64, Vec<f64>)> {
        let (a, b) = (x[0], x[1]);
        let f = (1.0 - a).powi(2) + 100.0 * (b - a * a).powi(2);
        let g = vec![
            -2.0 * (1.0 - a) - 400.0 * a * (b - a * a),
            200.0 * (b - a * a),
        ];
        Some((f, g))
    }

    #[test]
    fn finds_the_unconstrained_minimum_of_rosenbrock() {
        let m = minimize(
            rosenbrock,
            &[-1.2, 1.0],
            &[-5.0, -5.0],
            &[5.0, 5.0],
            &Settings::default(),
        )
        .unwrap();
        assert!(
            (m.x[0] - 1.0).abs() < 1e-5 && (m.x[1] - 1.0).abs() < 1e-5,
            "{m:?}"
        );
    }

    #[test]
    fn stops_on_an_active_bound() {
        // Rosenbrock with b ≤ 0.5: the minimum is on the bound b = 0.5, at a = √0.5 roughly
        // (f restricted to b = 0.5 is minimised where ∂f/∂a = 0).
        let m = minimize(
            rosenbrock,
            &[-1.2, 0.0],
            &[-5.0, -5.0],
            &[5.0, 0.5],
            &Settings::default(),
        )
        .unwrap();
        assert_eq!(m.x[1], 0.5);
        let (_, g) = rosenbrock(&m.x).unwrap();
        assert!(g[0].abs() < 1e-6, "{m:?} {g:?}");
        assert!(g[1] < 0.0, "the bound must be the reason to stop: {g:?}");
    }

    #[test]
    fn an_undefined_region_is_avoided() {
        // f = (x − 3)² undefined beyond x > 2: the search must stop near the edge.
        let f = |x: &[f64]| (x[0] <= 2.0).then(|| ((x[0] - 3.0).powi(2), vec![2.0 * (x[0] - 3.0)]));
        let m = minimize(f, &[0.0], &[-10.0], &[10.0], &Settings::default()).unwrap();
        assert!(m.x[0] <= 2.0 && m.x[0] > 1.9, "{m:?}");
    }
}
