//! Sequential verification with a binary detector whose looks are independent given the truth.
//!
//! The object-search papers' detector answers each look with *detected* or *not detected*,
//! with a miss rate and a false-alarm rate (Aydemir et al. 2011, `002` §IV, the observation
//! model of the view-cone POMDP: `P(detected | object) = 1 − FN`, `P(detected | none) = FP`).
//! Whether a candidate is an object is then a two-state POMDP with three actions: *look* again
//! (a cost), *accept* (wrong when it is no object) and *reject* (wrong when it is one). This
//! module solves it exactly over a finite budget of looks:
//!
//! `V₀(b) = min((1 − b)·C_accept, b·C_reject)`,
//! `Vₙ(b) = min(V₀(b), c + P(hit | b)·Vₙ₋₁(b⁺) + P(miss | b)·Vₙ₋₁(b⁻))`,
//!
//! with `b⁺`, `b⁻` Bayes' rule after a hit and a miss. Because looks are independent given
//! the truth, the belief after any looks depends only on how many hit and how many missed,
//! so the recursion is a table over (hits, misses) with `hits + misses ≤ n`: `O(n²)` per
//! decision. The optimal policy is Wald's sequential probability-ratio test with thresholds
//! that narrow as the budget runs out (accept above one belief, reject below another, look in
//! between); the tests check it against every policy tree by brute force.
//!
//! ```
//! use avs_verify::sequential::{decide, BinaryLooks, Decision, StopCosts};
//! let looks = BinaryLooks { hit_if_object: 0.8, hit_if_not: 0.05 };
//! // A wrong decision costs as much as 1000 m of travel, a look 2 m.
//! let costs = StopCosts { look: 2.0, wrong_accept: 1000.0, wrong_reject: 1000.0 };
//! // A candidate with a 3 % prior is looked at, not decided on the spot.
//! assert_eq!(decide(0.03, 8, looks, costs), Decision::Look);
//! // Four hits in four looks make it near certain: accept.
//! let b = looks.posterior(0.03, 4, 0);
//! assert!(b > 0.998);
//! assert_eq!(decide(b, 4, looks, costs), Decision::Accept);
//! // Two misses leave too little to be worth more looks: reject.
//! assert_eq!(decide(looks.posterior(0.03, 0, 2), 6, looks, costs), Decision::Reject);
//! ```
//!
//! # Choices
//!
//! * **Looks are independent given the truth.** Right for a detector whose errors are fresh
//!   draws each look (the simulator's default detector); wrong for a real one whose errors
//!   follow the vantage point (Velez et al. 2012, this crate's [`crate::planner`]), where
//!   looking again from the same spot proves little.
//! * **One model for every look.** The caller takes each look where the model holds (the
//!   recognition range, centred); the hit rates do not vary with the vantage point.

use serde::{Deserialize, Serialize};

/// A binary detector's hit rates given the truth.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BinaryLooks {
    /// P(detected | an object of the class is there), in (0, 1).
    pub hit_if_object: f64,
    /// P(detected | none is there), in (0, 1).
    pub hit_if_not: f64,
}

/// What a decision costs, in one unit (e.g. metres of travel).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StopCosts {
    /// One more look, ≥ 0.
    pub look: f64,
    /// Accepting a candidate that is no object, ≥ 0.
    pub wrong_accept: f64,
    /// Rejecting a candidate that is an object, ≥ 0.
    pub wrong_reject: f64,
}

/// The Bayes-optimal next step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Decision {
    /// Decide that it is an object.
    Accept,
    /// Decide that it is not.
    Reject,
    /// Look once more.
    Look,
}

impl BinaryLooks {
    /// Whether both rates are in (0, 1) and a hit is evidence for the object.
    pub fn is_valid(&self) -> bool {
        let open = |p: f64| p > 0.0 && p < 1.0;
        open(self.hit_if_object) && open(self.hit_if_not) && self.hit_if_object > self.hit_if_not
    }

    /// The belief after one look from belief `b`: `hit` detected it or not (Bayes' rule).
    pub fn update(&self, b: f64, hit: bool) -> f64 {
        let (o, n) = if hit {
            (self.hit_if_object, self.hit_if_not)
        } else {
            (1.0 - self.hit_if_object, 1.0 - self.hit_if_not)
        };
        let num = b * o;
        let den = num + (1.0 - b) * n;
        if den > 0.0 {
            num / den
        } else {
            b
        }
    }

    /// The belief after `hits` detections and `misses` non-detections from `prior`, in any
    /// order (computed in log-odds, so long runs neither underflow nor overflow).
    pub fn posterior(&self, prior: f64, hits: usize, misses: usize) -> f64 {
        if prior <= 0.0 || prior >= 1.0 {
            return prior.clamp(0.0, 1.0);
        }
        from_log_odds(log_odds(prior) + self.log_likelihood_ratio(hits, misses))
    }

    /// `ln P(looks | object) / P(looks | none)` of `hits` detections and `misses`
    /// non-detections: each hit adds `ln(hit_if_object / hit_if_not)`, each miss
    /// `ln((1 − hit_if_object) / (1 − hit_if_not))`; a kind of look that did not happen adds
    /// nothing, even when its term is infinite (a rate of exactly 0 or 1).
    pub fn log_likelihood_ratio(&self, hits: usize, misses: usize) -> f64 {
        let term = |n: usize, ratio: f64| if n == 0 { 0.0 } else { n as f64 * ratio.ln() };
        term(hits, self.hit_if_object / self.hit_if_not)
            + term(misses, (1.0 - self.hit_if_object) / (1.0 - self.hit_if_not))
    }

    /// P(the next look detects it | belief `b`).
    pub fn p_hit(&self, b: f64) -> f64 {
        b * self.hit_if_object + (1.0 - b) * self.hit_if_not
    }

    /// The binary detector hidden in a scoring one: a look "hits" when its score passes the
    /// midpoint of the two hypotheses' mean scores, with the score under each hypothesis
    /// moment-matched to a normal ([`crate::sensor::Likelihood::moments`]). A quantised score
    /// tells no more than the score (the data-processing inequality), so a policy that prices
    /// the value of a scored look by this detector's ([`decide`]) looks no longer than one that
    /// knew the score's full value would; the belief itself is still moved by the score
    /// ([`crate::sensor::LookModel::posterior`]). A look whose object scores are on average no
    /// higher than the no-object ones gives a detector that is not [`BinaryLooks::is_valid`].
    ///
    /// ```
    /// use avs_verify::sensor::{Likelihood, LookModel, Normal};
    /// use avs_verify::sequential::BinaryLooks;
    /// let n = |mean: f64| Likelihood { alpha: 1.0, ind: Normal { mean, var: 0.25 }, corr: Normal { mean, var: 0.25 } };
    /// let look = LookModel { likelihood: [n(0.8), n(2.0)], damping: 1.0, uncertainty: 0.0 };
    /// let b = BinaryLooks::quantised(&look);
    /// // Means 1.2 apart, standard deviation 0.5: each side of 1.4 with 1 − Φ(−1.2) ≈ 0.885.
    /// assert!((b.hit_if_object - 0.885).abs() < 1e-3 && (b.hit_if_not - 0.115).abs() < 1e-3);
    /// ```
    pub fn quantised(look: &crate::sensor::LookModel) -> BinaryLooks {
        use crate::sensor::{NO_OBJECT, OBJECT};
        let one = look.likelihood[OBJECT].moments();
        let none = look.likelihood[NO_OBJECT].moments();
        let cut = 0.5 * (one.mean + none.mean);
        let above = |n: crate::sensor::Normal| {
            1.0 - crate::pbd::std_normal_cdf((cut - n.mean) / n.var.sqrt())
        };
        // The disc model moves the belief only part of the way (eq. 11): so much less a hit.
        let d = look.damping.clamp(0.0, 1.0);
        let mix = |p: f64| d * p + (1.0 - d) * 0.5;
        BinaryLooks {
            hit_if_object: mix(above(one)),
            hit_if_not: mix(above(none)),
        }
    }
}

/// The log-odds `ln(p / (1 − p))` of a probability in (0, 1) (±∞ at 0 and 1).
///
/// Evidence adds in log-odds: the log-odds after looks is the prior's plus the natural log of
/// the looks' Bayes factor, so `log_odds(posterior) − log_odds(prior)` is what the looks said.
/// ```
/// use avs_verify::sequential::{from_log_odds, log_odds, BinaryLooks};
/// let looks = BinaryLooks { hit_if_object: 0.8, hit_if_not: 0.05 };
/// let b = looks.posterior(0.1, 2, 1);
/// let evidence = log_odds(b) - log_odds(0.1);
/// // The same looks move another prior by the same amount.
/// assert!((from_log_odds(log_odds(0.3) + evidence) - looks.posterior(0.3, 2, 1)).abs() < 1e-12);
/// ```
pub fn log_odds(p: f64) -> f64 {
    (p / (1.0 - p)).ln()
}

/// The probability whose log-odds is `l` (the logistic function; 0 and 1 at −∞ and +∞).
pub fn from_log_odds(l: f64) -> f64 {
    1.0 / (1.0 + (-l).exp())
}

/// The cost of deciding now at belief `b`, and whether accepting is the cheaper decision.
fn stop(b: f64, costs: StopCosts) -> (f64, bool) {
    let accept = (1.0 - b) * costs.wrong_accept;
    let reject = b * costs.wrong_reject;
    if accept <= reject {
        (accept, true)
    } else {
        (reject, false)
    }
}

/// The least expected cost from belief `b` with at most `looks_left` looks, and the first
/// step that reaches it (the module's recursion, over the (hits, misses) table).
pub fn solve(b: f64, looks_left: usize, looks: BinaryLooks, costs: StopCosts) -> (f64, Decision) {
    let n = looks_left;
    // value[h][m]: the value at the belief after h hits and m misses from b, with n − h − m
    // looks left; filled from the last layer (h + m = n) back to the root.
    let mut value = vec![vec![0.0; n + 1]; n + 1];
    let mut root = Decision::Reject;
    for used in (0..=n).rev() {
        for h in 0..=used {
            let m = used - h;
            let bh = looks.posterior(b, h, m);
            let (now, accept) = stop(bh, costs);
            let mut best = now;
            let mut step = if accept {
                Decision::Accept
            } else {
                Decision::Reject
            };
            if used < n {
                let p = looks.p_hit(bh);
                let more = costs.look + p * value[h + 1][m] + (1.0 - p) * value[h][m + 1];
                if more < best {
                    best = more;
                    step = Decision::Look;
                }
            }
            value[h][m] = best;
            if used == 0 {
                root = step;
            }
        }
    }
    (value[0][0], root)
}

/// The Bayes-optimal next step at belief `b` with at most `looks_left` looks ([`solve`]).
pub fn decide(b: f64, looks_left: usize, looks: BinaryLooks, costs: StopCosts) -> Decision {
    solve(b, looks_left, looks, costs).1
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// A policy tree: decide, or look and continue by what the look saw.
    #[derive(Clone)]
    enum Tree {
        Accept,
        Reject,
        Look(Box<Tree>, Box<Tree>),
    }

    /// Every policy tree of depth at most `n` (independent of the recursion under test).
    fn trees(n: usize) -> Vec<Tree> {
        let mut out = vec![Tree::Accept, Tree::Reject];
        if n > 0 {
            let sub = trees(n - 1);
            for a in &sub {
                for b in &sub {
                    out.push(Tree::Look(Box::new(a.clone()), Box::new(b.clone())));
                }
            }
        }
        out
    }

    /// Expected cost of `t` when the truth is `object`, by the chain rule over the looks.
    fn cost_given(t: &Tree, object: bool, looks: BinaryLooks, costs: StopCosts) -> f64 {
        match t {
            Tree::Accept => {
                if object {
                    0.0
                } else {
                    costs.wrong_accept
                }
            }
            Tree::Reject => {
                if object {
                    costs.wrong_reject
                } else {
                    0.0
                }
            }
            Tree::Look(hit, miss) => {
                let p = if object {
                    looks.hit_if_object
                } else {
                    looks.hit_if_not
                };
                costs.look
                    + p * cost_given(hit, object, looks, costs)
                    + (1.0 - p) * cost_given(miss, object, looks, costs)
            }
        }
    }

    fn random_case(rng: &mut impl Rng) -> (f64, BinaryLooks, StopCosts) {
        let hit_if_not = rng.gen_range(0.01..0.4);
        let looks = BinaryLooks {
            hit_if_object: rng.gen_range(hit_if_not + 0.05..0.99),
            hit_if_not,
        };
        let costs = StopCosts {
            look: rng.gen_range(0.0..5.0),
            wrong_accept: rng.gen_range(1.0..100.0),
            wrong_reject: rng.gen_range(1.0..100.0),
        };
        (rng.gen_range(0.001..0.999), looks, costs)
    }

    #[test]
    fn the_value_is_the_least_expected_cost_of_every_policy_tree_by_brute_force() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let all: Vec<Vec<Tree>> = (0..=3).map(trees).collect();
        assert_eq!(all[3].len(), 1446, "2, 6, 38, 1446 trees of depth ≤ 0..3");
        for _ in 0..200 {
            let (b, looks, costs) = random_case(&mut rng);
            for (n, trees) in all.iter().enumerate() {
                let brute = trees
                    .iter()
                    .map(|t| {
                        b * cost_given(t, true, looks, costs)
                            + (1.0 - b) * cost_given(t, false, looks, costs)
                    })
                    .fold(f64::INFINITY, f64::min);
                let (v, step) = solve(b, n, looks, costs);
                assert!((v - brute).abs() < 1e-9 * brute.max(1.0), "{v} vs {brute}");
                // The step's own value is the optimum too.
                let (now, accept) = stop(b, costs);
                match step {
                    Decision::Accept => assert!(accept && (now - v).abs() < 1e-9),
                    Decision::Reject => assert!(!accept && (now - v).abs() < 1e-9),
                    Decision::Look => assert!(n > 0 && v < now),
                }
            }
        }
    }

    #[test]
    fn the_policy_accepts_above_a_belief_rejects_below_another_and_looks_between() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
        for _ in 0..100 {
            let (_, looks, costs) = random_case(&mut rng);
            let n = rng.gen_range(0..10);
            let steps: Vec<Decision> = (1..1000)
                .map(|i| decide(i as f64 / 1000.0, n, looks, costs))
                .collect();
            // Reading beliefs upwards, the decisions never go back: Reject*, Look*, Accept*.
            let rank = |d: &Decision| match d {
                Decision::Reject => 0,
                Decision::Look => 1,
                Decision::Accept => 2,
            };
            assert!(steps.windows(2).all(|w| rank(&w[0]) <= rank(&w[1])));
        }
    }

    #[test]
    fn a_posterior_does_not_depend_on_the_order_of_the_looks() {
        let looks = BinaryLooks {
            hit_if_object: 0.8,
            hit_if_not: 0.05,
        };
        let mut b = 0.02;
        for hit in [true, false, true, true, false, true] {
            b = looks.update(b, hit);
        }
        assert!((b - looks.posterior(0.02, 4, 2)).abs() < 1e-12);
        // Long runs stay finite and in [0, 1].
        assert!(looks.posterior(0.5, 500, 0) <= 1.0 && looks.posterior(0.5, 0, 500) >= 0.0);
    }

    #[test]
    fn the_policy_errs_about_as_often_as_its_costs_say() {
        // Simulate the policy on objects and non-objects at a 5 % prior: the share of wrong
        // decisions stays near what the value says (the value counts looks and errors).
        let looks = BinaryLooks {
            hit_if_object: 0.8,
            hit_if_not: 0.05,
        };
        let costs = StopCosts {
            look: 2.0,
            wrong_accept: 1000.0,
            wrong_reject: 1000.0,
        };
        let (prior, budget) = (0.05, 8);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let runs = 40_000;
        let mut total = 0.0;
        let mut false_accepts = 0usize;
        for _ in 0..runs {
            let object = rng.gen::<f64>() < prior;
            let mut b = prior;
            let mut left = budget;
            loop {
                match decide(b, left, looks, costs) {
                    Decision::Accept => {
                        if !object {
                            total += costs.wrong_accept;
                            false_accepts += 1;
                        }
                        break;
                    }
                    Decision::Reject => {
                        if object {
                            total += costs.wrong_reject;
                        }
                        break;
                    }
                    Decision::Look => {
                        total += costs.look;
                        let p = if object {
                            looks.hit_if_object
                        } else {
                            looks.hit_if_not
                        };
                        b = looks.update(b, rng.gen::<f64>() < p);
                        left -= 1;
                    }
                }
            }
        }
        let mean = total / runs as f64;
        let (v, _) = solve(prior, budget, looks, costs);
        assert!((mean - v).abs() < 0.1 * v, "simulated {mean}, value {v}");
        // With errors priced at 500 looks, a look-alike is almost never accepted.
        assert!((false_accepts as f64 / runs as f64) < 1e-3);
    }
}
