//! Seeded Monte-Carlo simulation of a policy on a POMDP.

use crate::error::{PomdpError, Result};
use crate::model::Pomdp;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Mean discounted return over independent runs, with a normal-approximation 95% interval.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SimulationSummary {
    /// Number of runs.
    pub runs: usize,
    /// Steps per run.
    pub horizon: usize,
    /// Mean discounted return.
    pub mean: f64,
    /// Standard error of the mean.
    pub std_error: f64,
    /// `mean − 1.96 · std_error`.
    pub ci95_low: f64,
    /// `mean + 1.96 · std_error`.
    pub ci95_high: f64,
}

fn sample(rng: &mut ChaCha8Rng, probs: impl Iterator<Item = (usize, f64)>) -> Option<usize> {
    let u: f64 = rng.gen();
    let mut acc = 0.0;
    let mut last = None;
    for (i, p) in probs {
        if p <= 0.0 {
            continue;
        }
        acc += p;
        last = Some(i);
        if u < acc {
            return Some(i);
        }
    }
    last
}

/// Horizon after which `γ^h · max|R| / (1 − γ)` falls below `tolerance`.
pub fn horizon_for(m: &Pomdp, tolerance: f64) -> usize {
    let rmax = (0..m.n_actions())
        .flat_map(|a| (0..m.n_states()).map(move |s| (s, a)))
        .map(|(s, a)| m.reward(s, a).abs())
        .fold(0.0, f64::max);
    let g = m.discount();
    if rmax == 0.0 || g == 0.0 {
        return 1;
    }
    let tail = rmax / (1.0 - g);
    ((tolerance / tail).ln() / g.ln())
        .ceil()
        .clamp(1.0, 100_000.0) as usize
}

/// Simulate `runs` episodes of `horizon` steps from the model's initial belief with ChaCha8 seeded by
/// `seed`. `policy(belief)` picks the action; the filter tracks the belief.
pub fn simulate(
    m: &Pomdp,
    runs: usize,
    horizon: usize,
    seed: u64,
    mut policy: impl FnMut(&[f64]) -> usize,
) -> Result<SimulationSummary> {
    if runs == 0 {
        return Err(PomdpError::InvalidArgument(
            "runs must be at least 1".into(),
        ));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut returns = Vec::with_capacity(runs);
    for _ in 0..runs {
        let mut b = m.initial_belief().to_vec();
        let mut s = sample(&mut rng, b.iter().copied().enumerate())
            .ok_or_else(|| PomdpError::InvalidModel("empty initial belief".into()))?;
        let mut total = 0.0;
        let mut disc = 1.0;
        for _ in 0..horizon {
            let a = policy(&b);
            m.check_action(a)?;
            total += disc * m.reward(s, a);
            disc *= m.discount();
            let s2 = sample(&mut rng, m.successors(s, a).iter().copied())
                .ok_or_else(|| PomdpError::InvalidModel("state without successor".into()))?;
            let z = sample(&mut rng, m.obs_row(a, s2).iter().copied().enumerate())
                .ok_or_else(|| PomdpError::InvalidModel("state without observation".into()))?;
            b = m.update(&b, a, z)?.0;
            s = s2;
        }
        returns.push(total);
    }
    let n = runs as f64;
    let mean = returns.iter().sum::<f64>() / n;
    let var = if runs > 1 {
        returns.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (n - 1.0)
    } else {
        0.0
    };
    let se = (var / n).sqrt();
    Ok(SimulationSummary {
        runs,
        horizon,
        mean,
        std_error: se,
        ci95_low: mean - 1.96 * se,
        ci95_high: mean + 1.96 * se,
    })
}
