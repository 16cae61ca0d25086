//! Placeholder structure hypotheses (Aydemir et al. 2011, §III-A.1).
//!
//! The paper evaluates six hypotheses about the unexplored space behind a placeholder:
//! (1) no new places; (2) new places, no new room; (3) places leading to one new room;
//! (4) places leading to a room connected to another room; (5) a new room directly; (6) a new
//! room directly, leading to another room. It weighs them by "the amount of open space behind
//! the placeholder and the proximity of gateways" without giving the formula; our choice
//! (written down in the crate docs), with open area A, door distance d and the knowledge
//! parameters a₀, a_r, d₀, ρ:
//!
//! * P(h1) = exp(−A / a₀) — little open space, nothing behind;
//! * of the rest, a share g = exp(−d / d₀) (0 without a door hypothesis) goes "directly into a
//!   room" (h5, h6) and 1 − g goes "through new places" (h2–h4);
//! * through places, a room is reached with probability r = 1 − exp(−A / a_r);
//! * a hypothesised room leads on to another room with probability ρ.
//!
//! The hypothesised rooms join the chain graph like regular rooms: the first new room R1 hangs
//! off the placeholder's room R by φ_rc, R2 off R1. They carry no evidence, so they are a leaf
//! chain and their joint is exact given R's belief b_R:
//! P(R1 = x, R2 = y) ∝ Σ_a b_R(a) φ(a, x) π(x) φ(x, y) π(y), with π the category prior.
//! They are not fed back into the real rooms' beliefs, so that a hypothesis never changes what
//! is believed about explored space.

use crate::ids::Placeholder;
use crate::model::Model;

/// The six hypotheses of one placeholder and the categories of their rooms.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Hypotheses {
    /// P(h1) … P(h6), summing to 1.
    pub probabilities: [f64; 6],
    /// P(R1 = k) when one new room is hypothesised (h3, h5).
    pub one_room: Vec<f64>,
    /// P(R1 = x, R2 = y) at `[x][y]` when two new rooms are hypothesised (h4, h6).
    pub two_rooms: Vec<Vec<f64>>,
    /// Per category k: Σ_h P(h) · P(some room of h is of category k).
    pub p_category: Vec<f64>,
}

impl Hypotheses {
    /// P(the placeholder leads to at least one new room).
    pub fn p_new_room(&self) -> f64 {
        self.probabilities[2..].iter().sum()
    }

    /// P(at least one object in the new rooms), for per-category rates λ_k of the object.
    pub fn p_object(&self, rates: &[f64]) -> f64 {
        let p = &self.probabilities;
        let one: f64 = self
            .one_room
            .iter()
            .zip(rates)
            .map(|(b, l)| b * (1.0 - (-l).exp()))
            .sum();
        let mut two = 0.0;
        for (x, row) in self.two_rooms.iter().enumerate() {
            for (y, b) in row.iter().enumerate() {
                two += b * (1.0 - (-(rates[x] + rates[y])).exp());
            }
        }
        (p[2] + p[4]) * one + (p[3] + p[5]) * two
    }
}

/// The hypotheses of placeholder `p` whose room has category belief `room_belief`.
pub(crate) fn hypothesis_probabilities(
    model: &Model,
    p: &Placeholder,
    room_belief: &[f64],
) -> Hypotheses {
    let pm = &model.placeholder;
    let a = p.open_area_m2.max(0.0);
    let p1 = (-a / pm.no_places_area_m2).exp();
    let g = p
        .door_distance_m
        .map_or(0.0, |d| (-d.max(0.0) / pm.door_distance_m).exp());
    let rest = 1.0 - p1;
    let direct = rest * g;
    let via = rest * (1.0 - g);
    let r = 1.0 - (-a / pm.room_area_m2).exp();
    let rho = pm.another_room;
    let probabilities = [
        p1,
        via * (1.0 - r),
        via * r * (1.0 - rho),
        via * r * rho,
        direct * (1.0 - rho),
        direct * rho,
    ];
    let kc = model.num_categories();
    let phi = &model.connectivity;
    let pi = &model.prior;
    // m1(x) = Σ_a b_R(a) φ(a, x) π(x)
    let m1: Vec<f64> = (0..kc)
        .map(|x| (0..kc).map(|a| room_belief[a] * phi[a][x]).sum::<f64>() * pi[x])
        .collect();
    let z1: f64 = m1.iter().sum();
    let one_room: Vec<f64> = if z1 > 0.0 {
        m1.iter().map(|v| v / z1).collect()
    } else {
        pi.clone()
    };
    let mut two: Vec<Vec<f64>> = (0..kc)
        .map(|x| (0..kc).map(|y| m1[x] * phi[x][y] * pi[y]).collect())
        .collect();
    let z2: f64 = two.iter().flatten().sum();
    if z2 > 0.0 {
        two.iter_mut().flatten().for_each(|v| *v /= z2);
    }
    let p_category = (0..kc)
        .map(|k| {
            let any_two: f64 = 1.0
                - (0..kc)
                    .filter(|&x| x != k)
                    .map(|x| (0..kc).filter(|&y| y != k).map(|y| two[x][y]).sum::<f64>())
                    .sum::<f64>();
            (probabilities[2] + probabilities[4]) * one_room[k]
                + (probabilities[3] + probabilities[5]) * any_two
        })
        .collect();
    Hypotheses {
        probabilities,
        one_room,
        two_rooms: two,
        p_category,
    }
}
