//! Posterior belief distributions (Velez et al. 2012 §6, after He, Brunskill & Roy 2011): the
//! belief about a candidate treated as normal in the exponential family's natural parameter,
//! and its covariance after `T` future looks in closed form, without enumerating their scores
//! (eq. 32, the exponential-family Kalman filter's covariance update, eq. 28, summed):
//!
//! `Σ_{n+T} = (Σ_n⁻¹ + Σ_{i=1..T} G_i b̈_i G_iᵀ)⁻¹`.
//!
//! The expected cost of the decision taken after those looks follows from the accumulated
//! information alone. In log-odds, each look adds its log-likelihood ratio; for a look whose
//! score is normal under each hypothesis with means `m₀, m₁` and a common spread `s²`, that ratio
//! is normal with mean `±d²/2` and variance `d²` under `y = 1 / 0`, `d² = (m₁ − m₀)² / s²` (the
//! look's `G b̈ Gᵀ`, [`crate::sensor::LookModel::information`]). Information adds over looks
//! (eq. 32), so after
//! looks of total `D² = Σ d²` the final log-odds is `ℓ₀ + Λ`, `Λ | y ~ N(±D²/2, D²)`, and the
//! decision (accept when `ℓ > 0`) is wrong with probability
//! `P_err = p Φ((−ℓ₀ − D²/2)/D) + (1 − p) Φ((ℓ₀ − D²/2)/D)` — the Bayes risk, in closed form,
//! without enumerating a single score. The expected decision cost is
//! `right + (wrong − right) · P_err` ([`DecisionCosts::after`]); with `D = 0` it is deciding now.
//!
//! # Choices where the paper is vague
//! * **The state.** The paper's efKF keeps a normal belief over θ; we keep it in log-odds, where
//!   looks add (the exponential family's natural parameter), and read the decision cost off the
//!   normal law of the accumulated log-likelihood ratio rather than off a normal over a
//!   probability (which cannot reach certainty: its variance is at most `p (1 − p)`).
//! * **The belief itself** is updated exactly, by Bayes' rule on each score (eq. 6 with eq. 9
//!   or 11, [`crate::sensor::LookModel::posterior`]); the efKF's mean update (eq. 27) would only
//!   approximate it. PBD is used where the scores are not known yet: looking ahead.
//! * **Σ_n for the field.** [`covariance_of`] gives the Bernoulli variance `p (1 − p)` as the
//!   prior covariance of eq. 32 when the perception field is computed by PBD
//!   ([`crate::field`]).
//! * **Unequal spreads.** `s²` is the mean of the two hypotheses' spreads.

use serde::{Deserialize, Serialize};

/// The costs of a verification decision, in metres of travel (Velez et al. 2012 §8: a wrong
/// decision costs 16 m, a right one −16 m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DecisionCosts {
    /// Cost of accepting a non-object or rejecting an object, metres.
    pub wrong: f64,
    /// Cost of a right decision, metres (negative: a reward).
    pub right: f64,
}

impl Default for DecisionCosts {
    fn default() -> Self {
        Self {
            wrong: 16.0,
            right: -16.0,
        }
    }
}

impl DecisionCosts {
    /// The expected cost of deciding now with belief `p` (accept when p > ½).
    pub fn now(&self, p: f64) -> f64 {
        self.after(p, 0.0)
    }

    /// The expected cost of the decision after looks of total information `d2` (`Σ d²`), from
    /// belief `p` (accept when the final belief is above ½).
    pub fn after(&self, p: f64, d2: f64) -> f64 {
        let p = p.clamp(1e-12, 1.0 - 1e-12);
        let err = if d2 <= 1e-12 {
            p.min(1.0 - p)
        } else {
            let l0 = (p / (1.0 - p)).ln();
            let d = d2.sqrt();
            p * std_normal_cdf((-l0 - 0.5 * d2) / d)
                + (1.0 - p) * std_normal_cdf((l0 - 0.5 * d2) / d)
        };
        self.right + (self.wrong - self.right) * err
    }
}

/// Σ_n of a belief `p`: the Bernoulli variance `p (1 − p)` (kept above 1e-12 so that its
/// inverse is finite).
pub fn covariance_of(p: f64) -> f64 {
    (p * (1.0 - p)).max(1e-12)
}

/// Eq. 32 in log-odds: the information after looks adds, `Σ_{n+T}⁻¹ = Σ_n⁻¹ + Σ_i G_i b̈_i G_iᵀ`.
pub fn covariance_after(sigma_n: f64, informations: impl IntoIterator<Item = f64>) -> f64 {
    let total: f64 = informations.into_iter().sum();
    1.0 / (1.0 / sigma_n + total)
}

/// The standard normal CDF.
pub fn std_normal_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x / std::f64::consts::SQRT_2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};

    #[test]
    fn the_decision_risk_matches_simulated_log_likelihood_ratios() {
        // Draw y from the prior, then Λ from its law, and count wrong decisions.
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let c = DecisionCosts {
            wrong: 1.0,
            right: 0.0,
        };
        for (p, d2) in [(0.5f64, 1.0f64), (0.3, 4.0), (0.9, 0.5), (0.6, 9.0)] {
            let l0 = (p / (1.0 - p)).ln();
            let n = 200_000;
            let mut wrong = 0usize;
            for _ in 0..n {
                let y = rand::Rng::gen::<f64>(&mut rng) < p;
                let mean = if y { 0.5 * d2 } else { -0.5 * d2 };
                let lam = Normal::new(mean, f64::sqrt(d2)).unwrap().sample(&mut rng);
                if (l0 + lam > 0.0) != y {
                    wrong += 1;
                }
            }
            let mc = wrong as f64 / n as f64;
            let exact = c.after(p, d2);
            assert!((mc - exact).abs() < 4e-3, "p {p} d² {d2}: {mc} vs {exact}");
        }
    }

    #[test]
    fn looking_can_only_lower_the_expected_decision_cost() {
        let c = DecisionCosts::default();
        for p in [0.1, 0.5, 0.7, 0.95] {
            let mut last = c.after(p, 0.0);
            assert!((last - c.now(p)).abs() < 1e-9);
            for info in [0.5, 2.0, 10.0, 100.0] {
                let cost = c.after(p, info);
                assert!(cost <= last + 1e-12, "p {p}: {cost} > {last}");
                last = cost;
            }
            assert!(last >= c.right - 1e-9);
            assert!(
                last < c.right + 0.01 * (c.wrong - c.right),
                "much information is near certainty"
            );
        }
    }

    #[test]
    fn information_adds_up_over_future_looks() {
        let s = covariance_of(0.3);
        let two = covariance_after(s, [1.5, 2.5]);
        let one_by_one = covariance_after(covariance_after(s, [1.5]), [2.5]);
        assert!((two - one_by_one).abs() < 1e-15);
    }
}
