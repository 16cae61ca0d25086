//! Lower and upper bounds on the optimal value function V*.
//!
//! * Lower bound: a set Γ of α-vectors, `V̲(b) = max_{α∈Γ} α·b` (Smith & Simmons 2004, HSVI, §3),
//!   initialised with the blind-policy vectors `α_a = R_a + γ T_a α_a` (Hauskrecht 2000, §5.1).
//! * Upper bound: corner values plus a point set with the sawtooth interpolation
//!   `V̄(b) = min( V̄_c(b), min_i V̄_c(b) + min_{s: b_i(s)>0} b(s)/b_i(s) · (v_i − V̄_c(b_i)) )`
//!   (Hauskrecht 2000, eq. 28; HSVI §3), with corners initialised by the fast informed bound
//!   `Q(s,a) = R(s,a) + γ Σ_z max_{a'} Σ_{s'} T(s'|s,a) O(z|a,s') Q(s',a')` (Hauskrecht 2000, eq. 22),
//!   itself started from the MDP bound (Q_MDP), so every iterate is a valid upper bound.
//!
//! ## Bounded initialisation
//! Every sweep of the three fixed points (blind policy, Q_MDP, FIB) leaves a valid bound, so
//! [`Bounds::initial_until`] stops them at a deadline (after at least one Q_MDP sweep, which
//! the corners need) and an offline solve's time limit covers its initialisation. The FIB's
//! cached weights `T(s'|s,a) O(z|a,s')` number up to `|A| |S| |Z| |S|`; when they would exceed
//! [`MAX_FIB_WEIGHTS`] the corners stay at Q_MDP, a looser but valid upper bound, instead of
//! allocating them (a uniform-transition model of 1,000 states and 1,000 observations would
//! need 10⁹ of them, 16 GB).

use crate::model::{Pomdp, Sparse};
use std::time::Instant;

/// Most cached FIB weights, [`crate::model::MAX_MODEL_ENTRIES`] (16 bytes each: 268 MB at most).
pub const MAX_FIB_WEIGHTS: usize = crate::model::MAX_MODEL_ENTRIES;

fn past(deadline: Option<Instant>) -> bool {
    deadline.is_some_and(|d| Instant::now() >= d)
}

/// An α-vector with the action whose one-step backup produced it.
#[derive(Debug, Clone)]
pub struct AlphaVector {
    /// Value per state.
    pub values: Vec<f64>,
    /// The action to take where this vector is maximal.
    pub action: usize,
}

/// A point of the sawtooth upper bound.
#[derive(Debug, Clone)]
pub(crate) struct UpperPoint {
    belief: Sparse,
    /// `1 / b_i(s)` along the support.
    inverse: Vec<f64>,
    value: f64,
    /// `value − V̄_c(belief)`.
    excess: f64,
}

impl UpperPoint {
    /// `min_{s ∈ supp(self)} b(s) / self(s)`; zero when the support of `self` is not inside `b`'s.
    fn ratio_at(&self, b: &[(usize, f64)]) -> f64 {
        let mut ratio = f64::INFINITY;
        let mut j = 0;
        for (&(s, _), inv) in self.belief.iter().zip(&self.inverse) {
            while j < b.len() && b[j].0 < s {
                j += 1;
            }
            if j < b.len() && b[j].0 == s {
                ratio = ratio.min(b[j].1 * inv);
            } else {
                return 0.0;
            }
        }
        if ratio.is_finite() {
            ratio
        } else {
            0.0
        }
    }
}

/// Lower and upper bounds on V*, both valid at every belief.
#[derive(Debug, Clone)]
pub struct Bounds {
    pub(crate) alphas: Vec<AlphaVector>,
    pub(crate) corners: Vec<f64>,
    /// Upper-bound points `(belief, value, value − corner interpolation at the belief)`, bucketed by
    /// the first state of the belief's support (a point only tightens beliefs whose support contains
    /// its own, so a query visits only the buckets of its support).
    pub(crate) points: Vec<Vec<UpperPoint>>,
    pub(crate) discount: f64,
}

impl Bounds {
    /// Initial bounds: blind-policy α-vectors and fast-informed-bound corners.
    /// `iterations` caps the fixed-point sweeps of each (every sweep keeps the bound valid).
    pub fn initial(m: &Pomdp, iterations: usize) -> Self {
        Self::initial_until(m, iterations, None)
    }

    /// [`Bounds::initial`], ending the sweeps once `deadline` has passed (the bounds are valid
    /// after any number of sweeps; see the module docs).
    pub fn initial_until(m: &Pomdp, iterations: usize, deadline: Option<Instant>) -> Self {
        let alphas = blind_policy_vectors(m, iterations, deadline);
        let corners = fast_informed_bound(m, iterations, deadline);
        Self {
            alphas,
            corners,
            points: vec![Vec::new(); m.n_states()],
            discount: m.discount(),
        }
    }

    /// The α-vectors of the lower bound.
    pub fn alpha_vectors(&self) -> &[AlphaVector] {
        &self.alphas
    }

    /// Number of points in the upper bound (besides the |S| corners).
    pub fn n_upper_points(&self) -> usize {
        self.points.iter().map(Vec::len).sum()
    }

    /// Number of states of the model these bounds belong to.
    pub fn n_states(&self) -> usize {
        self.corners.len()
    }

    /// Dense → sparse, keeping only entries that are states of the model (so a belief of the wrong
    /// length cannot index out of range; callers check beliefs with [`Pomdp::check_belief`]).
    fn sparse_of(&self, b: &[f64]) -> Sparse {
        let mut v = crate::model::to_sparse(b);
        v.retain(|(s, _)| *s < self.corners.len());
        v
    }

    /// Lower bound at a dense belief.
    pub fn lower(&self, b: &[f64]) -> f64 {
        self.lower_sparse(&self.sparse_of(b)).0
    }

    /// Upper bound at a dense belief.
    pub fn upper(&self, b: &[f64]) -> f64 {
        self.upper_sparse(&self.sparse_of(b))
    }

    /// The action of the maximising α-vector at a dense belief (the lower bound's policy).
    pub fn lower_action(&self, b: &[f64]) -> usize {
        let (_, i) = self.lower_sparse(&self.sparse_of(b));
        self.alphas[i].action
    }

    pub(crate) fn lower_sparse(&self, b: &[(usize, f64)]) -> (f64, usize) {
        let mut best = f64::NEG_INFINITY;
        let mut arg = 0;
        for (i, a) in self.alphas.iter().enumerate() {
            let v: f64 = b.iter().map(|&(s, p)| p * a.values[s]).sum();
            if v > best {
                best = v;
                arg = i;
            }
        }
        (best, arg)
    }

    fn corner_value(&self, b: &[(usize, f64)]) -> f64 {
        b.iter().map(|&(s, p)| p * self.corners[s]).sum()
    }

    pub(crate) fn upper_sparse(&self, b: &[(usize, f64)]) -> f64 {
        let vc = self.corner_value(b);
        let mut best = vc;
        for (k, &(s0, _)) in b.iter().enumerate() {
            for pt in &self.points[s0] {
                let excess = pt.excess;
                if excess >= 0.0 {
                    continue;
                }
                // min over s in supp(bp) of b(s)/bp(s); zero when supp(bp) ⊄ supp(b).
                let mut ratio = f64::INFINITY;
                let mut j = k;
                for (&(s, _), inv) in pt.belief.iter().zip(&pt.inverse) {
                    while j < b.len() && b[j].0 < s {
                        j += 1;
                    }
                    if j < b.len() && b[j].0 == s {
                        ratio = ratio.min(b[j].1 * inv);
                    } else {
                        ratio = 0.0;
                        break;
                    }
                }
                if ratio > 0.0 && ratio.is_finite() {
                    best = best.min(vc + ratio * excess);
                }
            }
        }
        best
    }

    /// Point-based backup of both bounds at sparse belief `b`, given the expansions of every action
    /// (`(R(b,a), [(P(z|b,a), τ(b,a,z))])`). `cached` may give upper Q-values computed earlier for every
    /// action and the one action whose successors changed since: the others are reused (the upper bound
    /// only decreases, so an earlier value is still a valid, if looser, upper bound).
    /// Returns the new upper value at `b`.
    pub(crate) fn backup(
        &mut self,
        m: &Pomdp,
        b: &[(usize, f64)],
        expansions: &[(f64, Vec<(f64, Sparse)>)],
        cached: Option<(&[f64], usize)>,
    ) -> f64 {
        let gamma = self.discount;
        // Upper bound (Bellman backup of the sawtooth bound at b).
        let mut u_best = f64::NEG_INFINITY;
        for (a, (r, succ)) in expansions.iter().enumerate() {
            if let Some((qs, fresh)) = cached {
                if a != fresh {
                    u_best = u_best.max(qs[a]);
                    continue;
                }
            }
            let q = r + gamma
                * succ
                    .iter()
                    .filter(|(p, _)| *p > 0.0)
                    .map(|(p, post)| p * self.upper_sparse(post))
                    .sum::<f64>();
            u_best = u_best.max(q);
        }
        let u_now = self.upper_sparse(b);
        if u_best < u_now - 1e-12 {
            if b.len() == 1 {
                let s = b[0].0;
                self.corners[s] = self.corners[s].min(u_best);
                self.refresh_excess();
            } else {
                let vc = self.corner_value(b);
                let bucket = &mut self.points[b[0].0];
                if let Some(slot) = bucket.iter_mut().find(|pt| same_belief(&pt.belief, b)) {
                    slot.value = slot.value.min(u_best);
                    slot.excess = slot.value - vc;
                } else {
                    let new = UpperPoint {
                        belief: b.to_vec(),
                        inverse: b.iter().map(|(_, p)| 1.0 / p).collect(),
                        value: u_best,
                        excess: u_best - vc,
                    };
                    // Drop the points the new one makes redundant (its sawtooth face lies on or
                    // below them), keeping the point set small.
                    if new.excess < 0.0 {
                        for pts in self.points.iter_mut() {
                            pts.retain(|old| {
                                let r = new.ratio_at(&old.belief);
                                let vc_old = old.value - old.excess;
                                !(r > 0.0 && vc_old + r * new.excess <= old.value)
                            });
                        }
                    }
                    self.points[b[0].0].push(new);
                }
            }
        }
        // Lower bound: β_a(s) = R(s,a) + γ Σ_z Σ_{s'} T(s'|s,a) O(z|a,s') α_{a,z}(s'), with
        // α_{a,z} the maximiser at τ(b,a,z). Its value at b is R(b,a) + γ Σ_z P(z|b,a) α_{a,z}·τ(b,a,z),
        // so the best action is found from the posteriors and only its β is built.
        let ns = m.n_states();
        let no = m.n_observations();
        let at_b = self.lower_sparse(b);
        let mut best: Option<(f64, usize, Vec<usize>)> = None;
        for (a, (r, succ)) in expansions.iter().enumerate() {
            let mut v = *r;
            let mut chosen = Vec::with_capacity(succ.len());
            for (p, post) in succ {
                if *p > 0.0 {
                    let (val, i) = self.lower_sparse(post);
                    v += gamma * p * val;
                    chosen.push(i);
                } else {
                    // Any α is a valid choice where z cannot occur from b; take the best at b.
                    chosen.push(at_b.1);
                }
            }
            if !matches!(&best, Some((bv, _, _)) if v <= *bv) {
                best = Some((v, a, chosen));
            }
        }
        if let Some((best_val, a, chosen)) = best {
            if best_val > at_b.0 + 1e-12 {
                let rrow = m.reward_row(a);
                // The observation sum depends on s' only: g(s') = Σ_z O(z|a,s') α_{a,z}(s'),
                // once per s' (|S| |Z| work) instead of once per (s, s') pair (|S|² |Z| with a
                // dense T: 10⁹ operations, seconds per backup, at 1,000 states and
                // observations). Same sums in the same order, so β is unchanged to the bit.
                let g: Vec<f64> = (0..ns)
                    .map(|s2| {
                        let orow = m.obs_row(a, s2);
                        let mut inner = 0.0;
                        for (z, &o) in orow.iter().enumerate().take(no) {
                            if o > 0.0 {
                                inner += o * self.alphas[chosen[z]].values[s2];
                            }
                        }
                        inner
                    })
                    .collect();
                let beta: Vec<f64> = (0..ns)
                    .map(|s| {
                        let mut acc = 0.0;
                        for &(s2, t) in m.successors(s, a) {
                            acc += t * g[s2];
                        }
                        rrow[s] + gamma * acc
                    })
                    .collect();
                self.add_alpha(AlphaVector {
                    values: beta,
                    action: a,
                });
            }
        }
        u_best.min(u_now)
    }

    /// Add an α-vector unless another dominates it pointwise; drop the ones it dominates.
    pub(crate) fn add_alpha(&mut self, new: AlphaVector) {
        if self
            .alphas
            .iter()
            .any(|a| a.values.iter().zip(&new.values).all(|(x, y)| x >= y))
        {
            return;
        }
        self.alphas
            .retain(|a| !a.values.iter().zip(&new.values).all(|(x, y)| y >= x));
        self.alphas.push(new);
    }

    /// Remove α-vectors pointwise dominated by another one (they never attain the maximum).
    pub(crate) fn prune_alphas(&mut self) {
        let mut kept: Vec<AlphaVector> = Vec::with_capacity(self.alphas.len());
        for a in std::mem::take(&mut self.alphas) {
            if kept
                .iter()
                .any(|k| k.values.iter().zip(&a.values).all(|(x, y)| x >= y))
            {
                continue;
            }
            kept.retain(|k| !k.values.iter().zip(&a.values).all(|(x, y)| y >= x));
            kept.push(a);
        }
        self.alphas = kept;
    }

    fn refresh_excess(&mut self) {
        let corners = &self.corners;
        for pt in self.points.iter_mut().flatten() {
            pt.excess = pt.value - pt.belief.iter().map(|&(s, p)| p * corners[s]).sum::<f64>();
        }
    }

    /// Keep only α-vectors that are maximal at one of the upper bound's points, a corner, or one of
    /// `extra` (any subset of Γ is still a valid lower bound; HSVI2's pruning, Smith & Simmons 2005).
    pub(crate) fn prune_alphas_by_witness(&mut self, extra: &[Sparse]) {
        let mut keep = vec![false; self.alphas.len()];
        for s in 0..self.corners.len() {
            keep[self.lower_sparse(&[(s, 1.0)]).1] = true;
        }
        for pt in self.points.iter().flatten() {
            keep[self.lower_sparse(&pt.belief).1] = true;
        }
        for b in extra {
            keep[self.lower_sparse(b).1] = true;
        }
        let mut k = 0;
        self.alphas.retain(|_| {
            k += 1;
            keep[k - 1]
        });
    }

    /// Remove upper-bound points that the remaining points and corners already bound as tightly.
    pub(crate) fn prune_points(&mut self) {
        for k in 0..self.points.len() {
            let mut i = 0;
            while i < self.points[k].len() {
                let pt = self.points[k].swap_remove(i);
                if self.upper_sparse(&pt.belief) <= pt.value + 1e-12 {
                    // redundant: dropped
                } else {
                    self.points[k].push(pt);
                    let last = self.points[k].len() - 1;
                    self.points[k].swap(i, last);
                    i += 1;
                }
            }
        }
    }
}

fn same_belief(x: &[(usize, f64)], y: &[(usize, f64)]) -> bool {
    x.len() == y.len()
        && x.iter()
            .zip(y)
            .all(|(a, b)| a.0 == b.0 && (a.1 - b.1).abs() <= 1e-12)
}

fn blind_policy_vectors(
    m: &Pomdp,
    iterations: usize,
    deadline: Option<Instant>,
) -> Vec<AlphaVector> {
    let (ns, na) = (m.n_states(), m.n_actions());
    let gamma = m.discount();
    let rmin = (0..na)
        .flat_map(|a| m.reward_row(a).iter().copied())
        .fold(f64::INFINITY, f64::min);
    let floor = rmin / (1.0 - gamma);
    (0..na)
        .map(|a| {
            let r = m.reward_row(a);
            let mut v = vec![floor; ns];
            for _ in 0..iterations {
                if past(deadline) {
                    break;
                }
                let mut delta: f64 = 0.0;
                let next: Vec<f64> = (0..ns)
                    .map(|s| {
                        let x = r[s]
                            + gamma
                                * m.successors(s, a)
                                    .iter()
                                    .map(|&(s2, t)| t * v[s2])
                                    .sum::<f64>();
                        delta = delta.max((x - v[s]).abs());
                        x
                    })
                    .collect();
                v = next;
                if delta < 1e-9 {
                    break;
                }
            }
            AlphaVector {
                values: v,
                action: a,
            }
        })
        .collect()
}

fn fast_informed_bound(m: &Pomdp, iterations: usize, deadline: Option<Instant>) -> Vec<f64> {
    let (ns, na, no) = (m.n_states(), m.n_actions(), m.n_observations());
    let gamma = m.discount();
    let rmax = (0..na)
        .flat_map(|a| m.reward_row(a).iter().copied())
        .fold(f64::NEG_INFINITY, f64::max);
    // Q_MDP by value iteration from the trivial bound rmax/(1-γ).
    let mut v = vec![rmax / (1.0 - gamma); ns];
    let mut q = vec![0.0; na * ns];
    for _ in 0..iterations.max(1) {
        let mut delta: f64 = 0.0;
        for a in 0..na {
            let r = m.reward_row(a);
            for s in 0..ns {
                q[a * ns + s] = r[s]
                    + gamma
                        * m.successors(s, a)
                            .iter()
                            .map(|&(s2, t)| t * v[s2])
                            .sum::<f64>();
            }
        }
        for (s, vs) in v.iter_mut().enumerate() {
            let nv = (0..na)
                .map(|a| q[a * ns + s])
                .fold(f64::NEG_INFINITY, f64::max);
            delta = delta.max((nv - *vs).abs());
            *vs = nv;
        }
        // After the first sweep q holds a valid bound; later ones only tighten it.
        if delta < 1e-9 || past(deadline) {
            break;
        }
    }
    let q_mdp = |q: &[f64]| -> Vec<f64> {
        (0..ns)
            .map(|s| {
                (0..na)
                    .map(|a| q[a * ns + s])
                    .fold(f64::NEG_INFINITY, f64::max)
            })
            .collect()
    };
    // The FIB's weights, counted before they are gathered: per (a, s), the successors s' times
    // the observations O(z|a,s') > 0 of each.
    let obs_support: Vec<usize> = (0..na * ns)
        .map(|i| {
            (0..no)
                .filter(|&z| m.observation(i / ns, i % ns, z) > 0.0)
                .count()
        })
        .collect();
    let n_weights = (0..na)
        .flat_map(|a| (0..ns).map(move |s| (a, s)))
        .map(|(a, s)| {
            m.successors(s, a)
                .iter()
                .map(|&(s2, _)| obs_support[a * ns + s2])
                .sum::<usize>()
        })
        .fold(0usize, usize::saturating_add);
    if n_weights.saturating_add(na * ns * no) > MAX_FIB_WEIGHTS || past(deadline) {
        tracing::debug!(
            n_weights,
            "fast informed bound skipped: the corners stay at Q_MDP"
        );
        return q_mdp(&q);
    }
    // FIB sweeps from Q_MDP (monotone non-increasing, each a valid upper bound).
    // The weights T(s'|s,a) O(z|a,s') do not change between sweeps: gather each (a, s, z)'s
    // non-zero ones once. Where a single s' carries weight, max_{a'} w · Q(s',a') = w · max_{a'} Q(s',a'),
    // so the inner maximisation reads the per-state maximum instead of looping over a'.
    let mut weights: Vec<Vec<(usize, f64)>> = Vec::with_capacity(na * ns * no);
    for a in 0..na {
        for s in 0..ns {
            let succ = m.successors(s, a);
            for z in 0..no {
                weights.push(
                    succ.iter()
                        .filter_map(|&(s2, t)| {
                            let o = m.observation(a, s2, z);
                            (o > 0.0).then_some((s2, t * o))
                        })
                        .collect(),
                );
            }
        }
    }
    let mut qn = q.clone();
    let mut vmax = vec![0.0; ns];
    for _ in 0..iterations {
        if past(deadline) {
            break;
        }
        for (s, vs) in vmax.iter_mut().enumerate() {
            *vs = (0..na)
                .map(|a| q[a * ns + s])
                .fold(f64::NEG_INFINITY, f64::max);
        }
        let mut delta: f64 = 0.0;
        for a in 0..na {
            let r = m.reward_row(a);
            for s in 0..ns {
                let mut total = 0.0;
                for w in &weights[(a * ns + s) * no..(a * ns + s + 1) * no] {
                    total += match w.as_slice() {
                        [] => 0.0,
                        [(s2, tw)] => tw * vmax[*s2],
                        many => (0..na)
                            .map(|a2| many.iter().map(|&(s2, tw)| tw * q[a2 * ns + s2]).sum())
                            .fold(f64::NEG_INFINITY, f64::max),
                    };
                }
                let x = (r[s] + gamma * total).min(q[a * ns + s]);
                delta = delta.max((x - q[a * ns + s]).abs());
                qn[a * ns + s] = x;
            }
        }
        std::mem::swap(&mut q, &mut qn);
        if delta < 1e-9 {
            break;
        }
    }
    q_mdp(&q)
}
