//! The finite POMDP ⟨S, A, Z, T, O, R, γ, b₀⟩ and its belief update.

use crate::error::{PomdpError, Result};

/// Tolerance on probability rows: a row of T or O must sum to one within this.
pub const ROW_TOLERANCE: f64 = 1e-4;

/// Largest `|S| × |A| × |Z|` of a model (and largest dense table the `.pomdp` reader builds:
/// `|A| × |S|²` for T, `|A| × |S|² × |Z|` for rewards that depend on s' or z): 2²⁴ ≈ 16.8 M.
///
/// Why this product: the observation table holds `|A| × |S| × |Z|` numbers, and one look-ahead
/// of the solvers from a belief over every state builds `|A| × |Z|` posteriors of up to `|S|`
/// entries each — the same product, 16 bytes an entry. At the limit that is 134 MB for the table
/// and 268 MB for the worst look-ahead, so any model that loads can be expanded. Counting only
/// states and actions (as the reader once did) let a 9-line model with 1,000 states and 1,000
/// observations through to a solve that grew past 5 GB. The largest model avs builds itself, a
/// view-cone POMDP of [`crate::MAX_CONES`] cones, has 10,202 states, 201 actions and 2
/// observations (4.1 M).
pub const MAX_MODEL_ENTRIES: usize = 1 << 24;

/// Largest `max |R(s, a)| / (1 − γ)` accepted: 10¹², the largest value a policy can earn.
///
/// Why: the solvers add, compare and subtract values of this size, and an f64 near 10¹²
/// resolves steps of 1.2·10⁻⁴, still below the default target gap of 10⁻³; far beyond it the
/// difference of the bounds is rounding noise (rewards of 10³⁰⁰ gave a lower bound above the
/// upper, rewards of ±10³⁰⁸ gave `-inf` and a NaN gap). Real models are far below (tiger: 2·10³;
/// view-cone sessions: about 10⁴), and rewards can always be rescaled without changing the
/// optimal policy.
pub const MAX_VALUE_MAGNITUDE: f64 = 1e12;

/// Check `|S| × |A| × |Z|` against [`MAX_MODEL_ENTRIES`].
pub(crate) fn check_size(ns: usize, na: usize, no: usize) -> Result<()> {
    let size = ns.checked_mul(na).and_then(|x| x.checked_mul(no));
    if size.is_some_and(|x| x <= MAX_MODEL_ENTRIES) {
        Ok(())
    } else {
        Err(PomdpError::TooLarge {
            states: ns,
            actions: na,
            observations: no,
            limit: MAX_MODEL_ENTRIES,
        })
    }
}

/// Whether a reward of magnitude `r` keeps values within [`MAX_VALUE_MAGNITUDE`] at discount
/// `discount` (compared as `r ≤ M (1 − γ)`, which cannot overflow).
pub(crate) fn reward_in_range(r: f64, discount: f64) -> bool {
    r.abs() <= MAX_VALUE_MAGNITUDE * (1.0 - discount)
}

/// A belief stored sparsely: `(state, probability)` pairs with positive probability, sorted by state.
pub(crate) type Sparse = Vec<(usize, f64)>;

/// One action's look-ahead: `(R(b,a), [(P(z|b,a), τ(b,a,z))])`.
pub(crate) type Expansion = (f64, Vec<(f64, Sparse)>);

/// A finite, discounted POMDP with dense tables.
///
/// Rewards are kept as the expected immediate reward
/// `R(s, a) = Σ_{s'} T(s, a, s') Σ_z O(a, s', z) R(s, a, s', z)` (Cassandra's file format allows rewards that
/// depend on the next state and observation; the expectation is all any solver needs).
#[derive(Debug, Clone)]
pub struct Pomdp {
    states: Vec<String>,
    actions: Vec<String>,
    observations: Vec<String>,
    discount: f64,
    /// Non-zero transitions per (a, s), sorted by next state (T is kept sparse only).
    trans_sparse: Vec<Vec<(usize, f64)>>,
    /// O[a][s'][z] at `(a * ns + s') * no + z`.
    obs: Vec<f64>,
    /// R[a][s] at `a * ns + s`.
    reward: Vec<f64>,
    initial: Vec<f64>,
}

/// The raw tables of a POMDP, in the layouts documented on each field; see [`Pomdp::new`].
#[derive(Debug, Clone)]
pub struct PomdpTables {
    /// State names.
    pub states: Vec<String>,
    /// Action names.
    pub actions: Vec<String>,
    /// Observation names.
    pub observations: Vec<String>,
    /// Discount factor γ in [0, 1).
    pub discount: f64,
    /// `T(s' | s, a)` at `(a * |S| + s) * |S| + s'`.
    pub transitions: Vec<f64>,
    /// `O(z | a, s')` at `(a * |S| + s') * |Z| + z`.
    pub observation_probs: Vec<f64>,
    /// Expected immediate reward `R(s, a)` at `a * |S| + s`.
    pub rewards: Vec<f64>,
    /// Initial belief b₀ over states.
    pub initial: Vec<f64>,
}

impl Pomdp {
    /// Build a model from its tables, checking sizes, finiteness and that every row of T and O and
    /// the initial belief are probability distributions (within [`ROW_TOLERANCE`]; rows are then
    /// renormalised exactly). `|S| × |A| × |Z|` must be at most [`MAX_MODEL_ENTRIES`]
    /// ([`PomdpError::TooLarge`]) and `|R| / (1 − γ)` at most [`MAX_VALUE_MAGNITUDE`].
    pub fn new(t: PomdpTables) -> Result<Self> {
        let (ns, na) = (t.states.len(), t.actions.len());
        if t.transitions.len() != na * ns * ns {
            return Err(PomdpError::InvalidModel(format!(
                "transitions has {} entries, expected {}",
                t.transitions.len(),
                na * ns * ns
            )));
        }
        let rows = (0..na * ns)
            .map(|i| {
                t.transitions[i * ns..(i + 1) * ns]
                    .iter()
                    .enumerate()
                    .filter(|(_, p)| **p != 0.0)
                    .map(|(j, p)| (j, *p))
                    .collect()
            })
            .collect();
        Self::with_sparse_transitions(t, rows)
    }

    /// Like [`Pomdp::new`] but with T given sparsely: `rows[a * |S| + s]` lists `(s', T(s'|s,a))`
    /// (for large models such as many-cone view-cone POMDPs). `tables.transitions` is ignored.
    pub fn with_sparse_transitions(
        t: PomdpTables,
        mut rows: Vec<Vec<(usize, f64)>>,
    ) -> Result<Self> {
        let ns = t.states.len();
        let na = t.actions.len();
        let no = t.observations.len();
        if ns == 0 || na == 0 || no == 0 {
            return Err(PomdpError::InvalidModel(format!(
                "a POMDP needs at least one state, action and observation (got {ns}, {na}, {no})"
            )));
        }
        if !(t.discount.is_finite() && (0.0..1.0).contains(&t.discount)) {
            return Err(PomdpError::InvalidModel(format!(
                "discount must be in [0, 1) for an infinite-horizon solve, got {}",
                t.discount
            )));
        }
        check_size(ns, na, no)?;
        let check_len = |name: &str, v: &[f64], want: usize| -> Result<()> {
            if v.len() != want {
                return Err(PomdpError::InvalidModel(format!(
                    "{name} has {} entries, expected {want}",
                    v.len()
                )));
            }
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return Err(PomdpError::InvalidModel(format!(
                    "{name} entry {i} is not a finite number"
                )));
            }
            Ok(())
        };
        check_len("observation_probs", &t.observation_probs, na * ns * no)?;
        check_len("rewards", &t.rewards, na * ns)?;
        check_len("initial", &t.initial, ns)?;
        if let Some(i) = t
            .rewards
            .iter()
            .position(|r| !reward_in_range(*r, t.discount))
        {
            return Err(PomdpError::InvalidModel(format!(
                "reward R({}, {}) = {:e} at discount {} allows values up to {:.2e}; expected |R| / (1 − discount) ≤ {MAX_VALUE_MAGNITUDE:e} (rescale the rewards)",
                t.states[i % ns],
                t.actions[i / ns],
                t.rewards[i],
                t.discount,
                t.rewards[i].abs() / (1.0 - t.discount)
            )));
        }
        if rows.len() != na * ns {
            return Err(PomdpError::InvalidModel(format!(
                "sparse transitions have {} rows, expected {}",
                rows.len(),
                na * ns
            )));
        }
        let mut obs = t.observation_probs;
        let mut initial = t.initial;
        for a in 0..na {
            for s in 0..ns {
                let row = &mut rows[a * ns + s];
                row.sort_by_key(|(j, _)| *j);
                let ctx = || {
                    format!(
                        "T row for action `{}`, state `{}`",
                        t.actions[a], t.states[s]
                    )
                };
                if row.iter().any(|(j, _)| *j >= ns) || row.windows(2).any(|w| w[0].0 == w[1].0) {
                    return Err(PomdpError::InvalidModel(format!(
                        "{}: next-state indices must be distinct and below {ns}",
                        ctx()
                    )));
                }
                let mut probs: Vec<f64> = row.iter().map(|(_, p)| *p).collect();
                normalise_row(&mut probs)
                    .map_err(|m| PomdpError::InvalidModel(format!("{}: {m}", ctx())))?;
                for ((_, p), q) in row.iter_mut().zip(probs) {
                    *p = q;
                }
                row.retain(|(_, p)| *p > 0.0);
                let orow = &mut obs[(a * ns + s) * no..(a * ns + s + 1) * no];
                normalise_row(orow).map_err(|m| {
                    PomdpError::InvalidModel(format!(
                        "O row for action `{}`, next state `{}`: {m}",
                        t.actions[a], t.states[s]
                    ))
                })?;
            }
        }
        normalise_row(&mut initial)
            .map_err(|m| PomdpError::InvalidModel(format!("initial belief: {m}")))?;
        Ok(Self {
            states: t.states,
            actions: t.actions,
            observations: t.observations,
            discount: t.discount,
            trans_sparse: rows,
            obs,
            reward: t.rewards,
            initial,
        })
    }

    /// Number of states |S|.
    pub fn n_states(&self) -> usize {
        self.states.len()
    }
    /// Number of actions |A|.
    pub fn n_actions(&self) -> usize {
        self.actions.len()
    }
    /// Number of observations |Z|.
    pub fn n_observations(&self) -> usize {
        self.observations.len()
    }
    /// State names.
    pub fn states(&self) -> &[String] {
        &self.states
    }
    /// Action names.
    pub fn actions(&self) -> &[String] {
        &self.actions
    }
    /// Observation names.
    pub fn observations(&self) -> &[String] {
        &self.observations
    }
    /// Discount factor γ.
    pub fn discount(&self) -> f64 {
        self.discount
    }
    /// Initial belief b₀.
    pub fn initial_belief(&self) -> &[f64] {
        &self.initial
    }
    /// `T(s' | s, a)`.
    pub fn transition(&self, s: usize, a: usize, s2: usize) -> f64 {
        let row = self.successors(s, a);
        match row.binary_search_by_key(&s2, |(j, _)| *j) {
            Ok(k) => row[k].1,
            Err(_) => 0.0,
        }
    }
    /// `O(z | a, s')`.
    pub fn observation(&self, a: usize, s2: usize, z: usize) -> f64 {
        let (ns, no) = (self.n_states(), self.n_observations());
        self.obs[(a * ns + s2) * no + z]
    }
    /// Expected immediate reward `R(s, a)`.
    pub fn reward(&self, s: usize, a: usize) -> f64 {
        self.reward[a * self.n_states() + s]
    }
    /// Non-zero successors `(s', T(s'|s,a))`.
    pub(crate) fn successors(&self, s: usize, a: usize) -> &[(usize, f64)] {
        &self.trans_sparse[a * self.n_states() + s]
    }
    /// Row `O(· | a, s')`.
    pub(crate) fn obs_row(&self, a: usize, s2: usize) -> &[f64] {
        let (ns, no) = (self.n_states(), self.n_observations());
        &self.obs[(a * ns + s2) * no..(a * ns + s2 + 1) * no]
    }
    /// Row `R(·, a)`.
    pub(crate) fn reward_row(&self, a: usize) -> &[f64] {
        let ns = self.n_states();
        &self.reward[a * ns..(a + 1) * ns]
    }

    /// Index of a state by name.
    pub fn state_index(&self, name: &str) -> Option<usize> {
        self.states.iter().position(|s| s == name)
    }
    /// Index of an action by name.
    pub fn action_index(&self, name: &str) -> Option<usize> {
        self.actions.iter().position(|s| s == name)
    }
    /// Index of an observation by name.
    pub fn observation_index(&self, name: &str) -> Option<usize> {
        self.observations.iter().position(|s| s == name)
    }

    /// Check that `b` is a belief over this model's states.
    pub fn check_belief(&self, b: &[f64]) -> Result<()> {
        if b.len() != self.n_states() {
            return Err(PomdpError::InvalidArgument(format!(
                "belief has {} entries, the model has {} states",
                b.len(),
                self.n_states()
            )));
        }
        let mut sum = 0.0;
        for (i, p) in b.iter().enumerate() {
            if !p.is_finite() || *p < 0.0 {
                return Err(PomdpError::InvalidArgument(format!(
                    "belief entry {i} is {p}, expected a probability"
                )));
            }
            sum += p;
        }
        if (sum - 1.0).abs() > ROW_TOLERANCE {
            return Err(PomdpError::InvalidArgument(format!(
                "belief sums to {sum}, expected 1"
            )));
        }
        Ok(())
    }

    /// Expected immediate reward of action `a` in belief `b`: `R(b, a) = Σ_s b(s) R(s, a)`.
    pub fn expected_reward(&self, b: &[f64], a: usize) -> f64 {
        b.iter().zip(self.reward_row(a)).map(|(p, r)| p * r).sum()
    }

    /// The Bayes filter (Kaelbling, Littman & Cassandra 1998, eq. 1):
    /// `b'(s') = O(z | a, s') Σ_s T(s' | s, a) b(s) / P(z | b, a)`.
    ///
    /// Returns the posterior and `P(z | b, a)`; errors when `a` or `z` is out of range, `b` is not a
    /// belief, or `z` has probability zero after `a` in `b`.
    pub fn update(&self, b: &[f64], a: usize, z: usize) -> Result<(Vec<f64>, f64)> {
        self.check_belief(b)?;
        self.check_action(a)?;
        if z >= self.n_observations() {
            return Err(PomdpError::InvalidArgument(format!(
                "observation index {z} out of range (model has {})",
                self.n_observations()
            )));
        }
        let ns = self.n_states();
        let mut pred = vec![0.0; ns];
        for (s, p) in b.iter().enumerate() {
            if *p > 0.0 {
                for &(s2, t) in self.successors(s, a) {
                    pred[s2] += p * t;
                }
            }
        }
        let mut norm = 0.0;
        for (s2, x) in pred.iter_mut().enumerate() {
            *x *= self.observation(a, s2, z);
            norm += *x;
        }
        if norm <= 0.0 {
            return Err(PomdpError::InvalidArgument(format!(
                "observation `{}` is impossible after action `{}` in this belief",
                self.observations[z], self.actions[a]
            )));
        }
        pred.iter_mut().for_each(|x| *x /= norm);
        Ok((pred, norm))
    }

    pub(crate) fn check_action(&self, a: usize) -> Result<()> {
        if a >= self.n_actions() {
            return Err(PomdpError::InvalidArgument(format!(
                "action index {a} out of range (model has {})",
                self.n_actions()
            )));
        }
        Ok(())
    }

    /// Sparse one-step look-ahead: for action `a` from sparse belief `b`, the expected reward and,
    /// per observation, `(P(z|b,a), posterior)` (posterior empty when P = 0). `scratch` must have
    /// |S| zeros and is left zeroed.
    pub(crate) fn expand(
        &self,
        b: &[(usize, f64)],
        a: usize,
        scratch: &mut [f64],
        touched: &mut Vec<usize>,
    ) -> (f64, Vec<(f64, Sparse)>) {
        let r = self.reward_row(a);
        let mut reward = 0.0;
        touched.clear();
        for &(s, p) in b {
            reward += p * r[s];
            for &(s2, t) in self.successors(s, a) {
                // A contribution that underflows to zero is dropped: `scratch[s2] == 0.0` is the
                // "not yet touched" mark, and adding a zero would leave it set, so `s2` would be
                // pushed twice and appear twice in every posterior (doubling its mass there and
                // breaking the sawtooth ratio, which assumes one entry per state).
                let w = p * t;
                if w == 0.0 {
                    continue;
                }
                if scratch[s2] == 0.0 {
                    touched.push(s2);
                }
                scratch[s2] += w;
            }
        }
        touched.sort_unstable();
        let no = self.n_observations();
        let mut out = Vec::with_capacity(no);
        for z in 0..no {
            let mut post: Sparse = Vec::with_capacity(touched.len());
            let mut norm = 0.0;
            for &s2 in touched.iter() {
                let v = scratch[s2] * self.observation(a, s2, z);
                if v > 0.0 {
                    post.push((s2, v));
                    norm += v;
                }
            }
            if norm > 0.0 {
                post.iter_mut().for_each(|(_, v)| *v /= norm);
                // Entries that underflow in the normalisation leave the support (a zero entry
                // would give the sawtooth an infinite inverse).
                post.retain(|(_, v)| *v > 0.0);
            } else {
                post.clear();
            }
            out.push((norm, post));
        }
        for &s2 in touched.iter() {
            scratch[s2] = 0.0;
        }
        (reward, out)
    }
}

/// Dense belief → sparse.
pub(crate) fn to_sparse(b: &[f64]) -> Sparse {
    b.iter()
        .enumerate()
        .filter(|(_, p)| **p > 0.0)
        .map(|(i, p)| (i, *p))
        .collect()
}

fn normalise_row(row: &mut [f64]) -> std::result::Result<(), String> {
    if let Some(p) = row.iter().find(|p| !(p.is_finite() && **p >= -1e-12)) {
        return Err(format!("entry {p} is not a probability"));
    }
    let sum: f64 = row.iter().sum();
    if (sum - 1.0).abs() > ROW_TOLERANCE {
        return Err(format!("sums to {sum}, expected 1"));
    }
    row.iter_mut().for_each(|p| *p = p.max(0.0) / sum);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_state(discount: f64) -> Pomdp {
        // One action that keeps the state with probability 1/2 and one observation.
        Pomdp::new(PomdpTables {
            states: vec!["a".into(), "b".into()],
            actions: vec!["stay".into()],
            observations: vec!["z".into()],
            discount,
            transitions: vec![0.5, 0.5, 0.5, 0.5],
            observation_probs: vec![1.0, 1.0],
            rewards: vec![0.0, 0.0],
            initial: vec![0.5, 0.5],
        })
        .unwrap()
    }

    #[test]
    fn a_posterior_lists_each_state_once_when_a_contribution_underflows() {
        let m = two_state(0.9);
        // 5e-324 · 0.5 rounds to zero: the smallest subnormal's contribution vanishes.
        let b = vec![(0, 5e-324), (1, 1.0)];
        let mut scratch = vec![0.0; 2];
        let mut touched = Vec::new();
        let (_, succ) = m.expand(&b, 0, &mut scratch, &mut touched);
        let (p, post) = &succ[0];
        assert!((p - 1.0).abs() < 1e-12);
        assert_eq!(post.iter().map(|(s, _)| *s).collect::<Vec<_>>(), [0, 1]);
        assert!(
            post.iter().all(|(_, q)| (q - 0.5).abs() < 1e-12),
            "{post:?}"
        );
        assert!(scratch.iter().all(|x| *x == 0.0), "scratch left zeroed");
    }
}
