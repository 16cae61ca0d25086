//! The view-cone POMDP of the switching planner's decision-theoretic half (Aydemir et al. 2011,
//! `002` §II-A.2) and a closed-loop session over it.
//!
//! States are `(robot at pose p, target t)` with `p ∈ {start, cone 0 … cone n−1}` and
//! `t ∈ {in cone 0 … in cone n−1, not in the location}`, plus an absorbing `done` state. The robot's
//! pose is known (it is the last processed cone), so every reachable belief has support on one pose
//! only; it is kept in the state so that travel costs between cone poses enter the rewards.
//!
//! Actions: `process_i` (move to cone i's pose and process it: reward `−(travel(p, i) + process_cost)`,
//! observation *detected* with probability `1 − FN` when the target is in cone i and `FP` otherwise),
//! `found_i` (declare the target found in cone i) and `absent` (declare it not in the location); a
//! declaration ends the session (moves to `done`, where nothing more is earned) with reward
//! `found` / `absent` when right and `wrong` otherwise. Repeated processing of a cone gives independent
//! observations (the paper's sensing model is a fixed FN/FP pair, 0.2 / 0.05).

use crate::bounds::{AlphaVector, Bounds};
use crate::error::{PomdpError, Result};
use crate::model::{to_sparse, Pomdp, PomdpTables};
use crate::offline::{solve_from, OfflineOptions};
use crate::online::{rtbss_sparse, OnlineOptions};
use crate::rollout::{OnePassModel, OnePassState};

/// The paper's false-negative rate, "an educated guess" (`002` §IV): the default when the knowledge
/// file gives none.
pub const PAPER_FALSE_NEGATIVE: f64 = 0.2;
/// The paper's false-positive rate (`002` §IV).
pub const PAPER_FALSE_POSITIVE: f64 = 0.05;

/// Largest number of cones a view-cone POMDP may have: the product state space grows as (n+1)², and
/// a location needing more cones should be split (or its cones merged) before a DT session.
pub const MAX_CONES: usize = 100;

/// Rewards of the declarations (in the same unit as travel and processing costs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DecisionRewards {
    /// Reward for declaring the target found in the cone that holds it.
    pub found: f64,
    /// Reward for declaring the target absent when it is not in the location.
    pub absent: f64,
    /// Reward (usually negative) for any wrong declaration.
    pub wrong: f64,
}

impl Default for DecisionRewards {
    /// The values of the project's reference model `viewcones2.POMDP`: +10, +5, −20.
    fn default() -> Self {
        Self {
            found: 10.0,
            absent: 5.0,
            wrong: -20.0,
        }
    }
}

/// A view-cone search problem for one location.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ViewConeProblem {
    /// Prior probability that the target lies in each cone (the rest is "not in the location");
    /// see [`cone_priors`] to derive it from P(ObjectAt L) and the location's cells.
    pub cone_prior: Vec<f64>,
    /// Travel cost from the robot's current pose to each cone's pose.
    pub travel_from_start: Vec<f64>,
    /// Travel cost between cone poses, `travel[i][j]` from cone i to cone j (zero on the diagonal).
    pub travel: Vec<Vec<f64>>,
    /// Cost of processing one view cone.
    pub process_cost: f64,
    /// P(not detected | target in the processed cone); the paper's default 0.2.
    pub false_negative: f64,
    /// P(detected | target not in the processed cone); the paper's default 0.05.
    pub false_positive: f64,
    /// Declaration rewards.
    pub rewards: DecisionRewards,
    /// Discount factor in (0, 1).
    pub discount: f64,
}

/// Spread `p_object_at_location` over the location's cells by `cell_weights` (normalised) and collect the
/// mass of each cone: each cell counts for the first cone in `cone_cells` that covers it (greedy set
/// cover lists the cones in that order), so the cone events are disjoint. Mass of uncovered cells is
/// merged with "not in the location" (the robot cannot tell them apart).
pub fn cone_priors(
    cone_cells: &[Vec<usize>],
    cell_weights: &[f64],
    p_object_at_location: f64,
) -> Result<Vec<f64>> {
    if !(0.0..=1.0).contains(&p_object_at_location) {
        return Err(PomdpError::InvalidInput {
            field: "p_object_at_location",
            message: format!("{p_object_at_location} is not a probability"),
        });
    }
    if cell_weights.iter().any(|w| !w.is_finite() || *w < 0.0) {
        return Err(PomdpError::InvalidInput {
            field: "cell_weights",
            message: "weights must be finite and non-negative".into(),
        });
    }
    let total: f64 = cell_weights.iter().sum();
    if total <= 0.0 {
        return Err(PomdpError::InvalidInput {
            field: "cell_weights",
            message: "weights must have a positive sum".into(),
        });
    }
    let mut taken = vec![false; cell_weights.len()];
    cone_cells
        .iter()
        .map(|cells| {
            let mut mass = 0.0;
            for &c in cells {
                let Some(w) = cell_weights.get(c) else {
                    return Err(PomdpError::InvalidInput {
                        field: "cone_cells",
                        message: format!(
                            "cell index {c} is out of range ({} cells)",
                            cell_weights.len()
                        ),
                    });
                };
                if !taken[c] {
                    taken[c] = true;
                    mass += w / total;
                }
            }
            Ok(mass * p_object_at_location)
        })
        .collect()
}

/// Travel costs as Euclidean distance × `cost_per_metre` between 2-D positions.
/// Returns `(travel_from_start, travel)` for [`ViewConeProblem`].
pub fn euclidean_travel(
    start: [f64; 2],
    cone_positions: &[[f64; 2]],
    cost_per_metre: f64,
) -> (Vec<f64>, Vec<Vec<f64>>) {
    let d = |a: [f64; 2], b: [f64; 2]| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
    let from_start = cone_positions
        .iter()
        .map(|p| d(start, *p) * cost_per_metre)
        .collect();
    let between = cone_positions
        .iter()
        .map(|a| {
            cone_positions
                .iter()
                .map(|b| d(*a, *b) * cost_per_metre)
                .collect()
        })
        .collect();
    (from_start, between)
}

/// An action of the view-cone session.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(tag = "action", rename_all = "snake_case")]
pub enum ViewConeAction {
    /// Move to the cone's pose and process it (then call [`ViewConeSession::observe`]).
    Process {
        /// Cone index.
        cone: usize,
    },
    /// Declare the target found in the cone (ends the session).
    DeclareFound {
        /// Cone index.
        cone: usize,
    },
    /// Declare the target not in the location (ends the session).
    DeclareAbsent,
}

/// How a session ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(tag = "outcome", rename_all = "snake_case")]
pub enum Outcome {
    /// The target was declared found in this cone.
    Found {
        /// Cone index.
        cone: usize,
    },
    /// The target was declared not in the location.
    Absent,
}

/// The belief of a session, for the plan trace.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ConeBelief {
    /// P(target in cone i).
    pub in_cone: Vec<f64>,
    /// P(target not in the location).
    pub absent: f64,
}

/// The view-cone POMDP built from a [`ViewConeProblem`].
#[derive(Debug, Clone)]
pub struct ViewConePomdp {
    n: usize,
    pomdp: Pomdp,
}

impl ViewConePomdp {
    /// Build and check the model.
    pub fn new(p: &ViewConeProblem) -> Result<Self> {
        let n = p.cone_prior.len();
        let bad =
            |field: &'static str, message: String| PomdpError::InvalidInput { field, message };
        if n == 0 || n > MAX_CONES {
            return Err(bad(
                "cone_prior",
                format!("needs between 1 and {MAX_CONES} cones, got {n}"),
            ));
        }
        let prior_sum: f64 = p.cone_prior.iter().sum();
        if p.cone_prior.iter().any(|x| !x.is_finite() || *x < 0.0) || prior_sum > 1.0 + 1e-9 {
            return Err(bad(
                "cone_prior",
                format!("must be probabilities summing to at most 1 (sum {prior_sum})"),
            ));
        }
        if p.travel_from_start.len() != n {
            return Err(bad(
                "travel_from_start",
                format!("has {} entries, expected {n}", p.travel_from_start.len()),
            ));
        }
        if p.travel.len() != n || p.travel.iter().any(|r| r.len() != n) {
            return Err(bad("travel", format!("must be an {n}×{n} matrix")));
        }
        let costs_ok = p
            .travel_from_start
            .iter()
            .chain(p.travel.iter().flatten())
            .chain(std::iter::once(&p.process_cost))
            .all(|c| c.is_finite() && *c >= 0.0);
        if !costs_ok {
            return Err(bad(
                "travel/process_cost",
                "costs must be finite and non-negative".into(),
            ));
        }
        for (field, v) in [
            ("false_negative", p.false_negative),
            ("false_positive", p.false_positive),
        ] {
            if !(0.0..=1.0).contains(&v) {
                return Err(bad(field, format!("{v} is not a probability")));
            }
        }
        let r = p.rewards;
        if ![r.found, r.absent, r.wrong].iter().all(|x| x.is_finite()) {
            return Err(bad("rewards", "must be finite".into()));
        }
        if !(p.discount > 0.0 && p.discount < 1.0) {
            return Err(bad("discount", format!("{} is not in (0, 1)", p.discount)));
        }

        let nt = n + 1; // targets: cones + absent
        let ns = (n + 1) * nt + 1;
        let done = ns - 1;
        let na = 2 * n + 1;
        let no = 2;
        let idx = |pos: usize, t: usize| pos * nt + t;
        let mut states = Vec::with_capacity(ns);
        for pos in 0..=n {
            let at = if pos == 0 {
                "start".to_string()
            } else {
                format!("c{}", pos - 1)
            };
            for t in 0..nt {
                let target = if t < n {
                    format!("in{t}")
                } else {
                    "absent".into()
                };
                states.push(format!("{at}-{target}"));
            }
        }
        states.push("done".into());
        let mut actions: Vec<String> = (0..n).map(|i| format!("process{i}")).collect();
        actions.extend((0..n).map(|i| format!("found{i}")));
        actions.push("absent".into());
        let observations = vec!["detected".to_string(), "nothing".to_string()];

        let mut trans: Vec<Vec<(usize, f64)>> = vec![Vec::new(); na * ns];
        let mut obs = vec![0.0; na * ns * no];
        let mut rew = vec![0.0; na * ns];
        for a in 0..na {
            trans[a * ns + done] = vec![(done, 1.0)];
            for s2 in 0..ns {
                obs[(a * ns + s2) * no + 1] = 1.0;
            }
        }
        for i in 0..n {
            let a = i;
            for pos in 0..=n {
                let travel = if pos == 0 {
                    p.travel_from_start[i]
                } else {
                    p.travel[pos - 1][i]
                };
                for t in 0..nt {
                    let s = idx(pos, t);
                    trans[a * ns + s] = vec![(idx(i + 1, t), 1.0)];
                    rew[a * ns + s] = -(travel + p.process_cost);
                }
            }
            for t in 0..nt {
                let s2 = idx(i + 1, t);
                let det = if t == i {
                    1.0 - p.false_negative
                } else {
                    p.false_positive
                };
                obs[(a * ns + s2) * no] = det;
                obs[(a * ns + s2) * no + 1] = 1.0 - det;
            }
        }
        for pos in 0..=n {
            for t in 0..nt {
                let s = idx(pos, t);
                for i in 0..n {
                    let a = n + i;
                    trans[a * ns + s] = vec![(done, 1.0)];
                    rew[a * ns + s] = if t == i { r.found } else { r.wrong };
                }
                let a = 2 * n;
                trans[a * ns + s] = vec![(done, 1.0)];
                rew[a * ns + s] = if t == n { r.absent } else { r.wrong };
            }
        }
        let mut initial = vec![0.0; ns];
        for (t, q) in p.cone_prior.iter().enumerate() {
            initial[idx(0, t)] = *q / prior_sum.max(1.0);
        }
        initial[idx(0, n)] = (1.0 - prior_sum).max(0.0);
        let pomdp = Pomdp::with_sparse_transitions(
            PomdpTables {
                states,
                actions,
                observations,
                discount: p.discount,
                transitions: Vec::new(),
                observation_probs: obs,
                rewards: rew,
                initial,
            },
            trans,
        )?;
        Ok(Self { n, pomdp })
    }

    /// Number of cones.
    pub fn n_cones(&self) -> usize {
        self.n
    }

    /// The underlying generic POMDP (product states; see the module docs).
    pub fn pomdp(&self) -> &Pomdp {
        &self.pomdp
    }

    /// Lower-bound α-vectors of *sweep* policies: process the cones in a nearest-neighbour order,
    /// declare the target found in the first cone that detects it, and declare it absent after
    /// the last cone; one tour from the start pose and one beginning at each cone. Each is a
    /// fixed policy, so its value vector is a valid lower bound on V* (any policy's value is).
    ///
    /// The blind-policy bounds alone value "process the nearest cone forever" at
    /// −cost / (1 − γ): when declarations look worse than that (a room of many cones), a
    /// depth-limited online search whose leaves carry those bounds re-processes the cone it stands
    /// at until the step guard ends the session. A sweep's value counts what covering the
    /// location is worth.
    pub fn sweep_vectors(&self) -> Vec<AlphaVector> {
        let (n, m) = (self.n, &self.pomdp);
        let nt = n + 1;
        let idx = |pos: usize, t: usize| pos * nt + t;
        let gamma = m.discount();
        // Travel plus processing from pose `pos` to cone `i`, read off the reward table.
        let cost = |pos: usize, i: usize| -m.reward(idx(pos, 0), i);
        let found = |t: usize, i: usize| m.reward(idx(0, t), n + i);
        let absent = |t: usize| m.reward(idx(0, t), 2 * n);
        // Process cone `i` at cost `c`, declare it found on a detection (the declaration's reward
        // one step later), else go on with value `rest`; the target is `t` (`n`: absent).
        let step = |c: f64, t: usize, i: usize, rest: f64| {
            let det = m.observation(i, idx(i + 1, t), 0);
            -c + gamma * (det * found(t, i) + (1.0 - det) * rest)
        };
        let tour = |first: Option<usize>| {
            let mut order: Vec<usize> = Vec::with_capacity(n);
            let mut left = vec![true; n];
            let mut pos = 0; // the start pose
            if let Some(j) = first {
                order.push(j);
                left[j] = false;
                pos = j + 1;
            }
            while let Some(i) = (0..n)
                .filter(|&i| left[i])
                .min_by(|&a, &b| cost(pos, a).total_cmp(&cost(pos, b)).then(a.cmp(&b)))
            {
                order.push(i);
                left[i] = false;
                pos = i + 1;
            }
            order
        };
        // The vector of "process `order` in turn, then declare absent", from any pose.
        let vector = |order: &[usize]| {
            let mut values = vec![0.0; m.n_states()];
            for t in 0..nt {
                let mut rest = absent(t);
                for j in (1..order.len()).rev() {
                    rest = step(cost(order[j - 1] + 1, order[j]), t, order[j], rest);
                }
                for pos in 0..=n {
                    values[idx(pos, t)] = step(cost(pos, order[0]), t, order[0], rest);
                }
            }
            AlphaVector {
                values,
                action: order[0],
            }
        };
        std::iter::once(None)
            .chain((0..n).map(Some))
            .map(|first| vector(&tour(first)))
            .collect()
    }

    /// The generic action index of a view-cone action (the inverse of [`Self::action`]).
    pub fn index(&self, a: ViewConeAction) -> usize {
        match a {
            ViewConeAction::Process { cone } => cone,
            ViewConeAction::DeclareFound { cone } => self.n + cone,
            ViewConeAction::DeclareAbsent => 2 * self.n,
        }
    }

    /// Map a generic action index to a view-cone action.
    pub fn action(&self, a: usize) -> ViewConeAction {
        if a < self.n {
            ViewConeAction::Process { cone: a }
        } else if a < 2 * self.n {
            ViewConeAction::DeclareFound { cone: a - self.n }
        } else {
            ViewConeAction::DeclareAbsent
        }
    }

    /// Marginal belief over the target's whereabouts from a product-state belief.
    pub fn cone_belief(&self, b: &[f64]) -> ConeBelief {
        let nt = self.n + 1;
        let mut m = vec![0.0; nt];
        for (s, p) in b.iter().enumerate().take(nt * (self.n + 1)) {
            m[s % nt] += p;
        }
        let total: f64 = m.iter().sum();
        if total > 0.0 {
            m.iter_mut().for_each(|x| *x /= total);
        }
        let absent = m.pop().unwrap_or(0.0);
        ConeBelief { in_cone: m, absent }
    }
}

/// Options of a [`ViewConeSession`].
#[derive(Debug, Clone)]
pub struct SessionOptions {
    /// Offline bounds computed when the session starts (HSVI from the initial belief).
    pub offline: OfflineOptions,
    /// Online RTBSS search per action.
    pub online: OnlineOptions,
    /// After this many processed cones the session declares by the best immediate reward
    /// (a guard; a converged policy declares long before).
    pub max_steps: usize,
    /// Start the offline lower bound from the sweep policies' values as well as the blind
    /// policies' ([`ViewConePomdp::sweep_vectors`]); for locations with many cones. Off by
    /// default: with a perfect sensor and a one-step look-ahead, a session whose bound holds
    /// only whole sweeps can keep re-processing a cone it has emptied (no tour's tail is in the
    /// bound).
    pub sweep_bounds: bool,
    /// How the session decides (see [`SessionPolicy`]).
    pub policy: SessionPolicy,
}

/// How a [`ViewConeSession`] chooses its actions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SessionPolicy {
    /// RTBSS ([`crate::online`]) over HSVI bounds refined when the session starts: any cone may be
    /// processed any number of times.
    #[default]
    Rtbss,
    /// One search of the location ([`crate::rollout`]): each cone is processed once, and again
    /// only to confirm a detection there; decisions are an expectimax to `online.depth` whose
    /// leaves are a nearest-neighbour pass's exact value. No offline solve.
    OnePassRollout,
}

impl Default for SessionOptions {
    fn default() -> Self {
        Self {
            // A trial budget, not a time budget, so that a session's decisions (and the plan traces
            // built from them) are the same on every machine.
            offline: OfflineOptions {
                target_gap: 1e-3,
                time_limit: None,
                max_trials: 30,
                init_iterations: 500,
            },
            online: OnlineOptions::default(),
            max_steps: 100,
            sweep_bounds: false,
            policy: SessionPolicy::Rtbss,
        }
    }
}

/// How a session decides: RTBSS over its offline bounds, or the one-pass rollout with its state.
#[derive(Debug, Clone)]
enum Decider {
    Rtbss(Bounds),
    OnePass(OnePassModel, OnePassState),
}

/// A closed-loop DT session: `next_action()`, `observe(detected)`, …, until `outcome()` is `Some`.
///
/// ```
/// use avs_pomdp::*;
/// let positions = [[1.0, 0.0], [3.0, 0.0]];
/// let (travel_from_start, travel) = euclidean_travel([0.0, 0.0], &positions, 0.5);
/// let problem = ViewConeProblem {
///     cone_prior: vec![0.5, 0.3], // P(ObjectAt L) = 0.8 spread over the two cones
///     travel_from_start,
///     travel,
///     process_cost: 1.0,
///     false_negative: PAPER_FALSE_NEGATIVE,
///     false_positive: PAPER_FALSE_POSITIVE,
///     rewards: DecisionRewards::default(),
///     discount: 0.95,
/// };
/// let mut session = ViewConeSession::new(&problem, SessionOptions::default()).unwrap();
/// // The target is in cone 1; the sensor happens to be right every time here.
/// while session.outcome().is_none() {
///     match session.next_action().unwrap() {
///         ViewConeAction::Process { cone } => session.observe(cone == 1).unwrap(),
///         ViewConeAction::DeclareFound { .. } | ViewConeAction::DeclareAbsent => {}
///     }
///     let b = session.belief(); // for the plan trace
///     assert!((b.in_cone.iter().sum::<f64>() + b.absent - 1.0).abs() < 1e-9);
/// }
/// assert_eq!(session.outcome(), Some(Outcome::Found { cone: 1 }));
/// ```
#[derive(Debug, Clone)]
pub struct ViewConeSession {
    model: ViewConePomdp,
    decider: Decider,
    belief: Vec<f64>,
    opts: SessionOptions,
    pending: Option<usize>,
    outcome: Option<Outcome>,
    steps: usize,
}

impl ViewConeSession {
    /// Start a session: build the model and compute offline bounds from the prior.
    pub fn new(problem: &ViewConeProblem, opts: SessionOptions) -> Result<Self> {
        let model = ViewConePomdp::new(problem)?;
        Self::with_model(model, opts)
    }

    /// Start a session over an already built model.
    pub fn with_model(model: ViewConePomdp, opts: SessionOptions) -> Result<Self> {
        if opts.online.depth == 0 {
            return Err(PomdpError::InvalidArgument(
                "online search depth must be at least 1".into(),
            ));
        }
        let m = model.pomdp();
        let decider = match opts.policy {
            SessionPolicy::Rtbss => {
                let mut bounds = Bounds::initial(m, opts.offline.init_iterations);
                if opts.sweep_bounds {
                    for v in model.sweep_vectors() {
                        bounds.add_alpha(v);
                    }
                }
                let sol = solve_from(m, m.initial_belief(), Some(bounds), &opts.offline)?;
                tracing::debug!(
                    lower = sol.lower,
                    upper = sol.upper,
                    trials = sol.trials,
                    "view-cone session bounds"
                );
                Decider::Rtbss(sol.bounds)
            }
            SessionPolicy::OnePassRollout => {
                let state = OnePassState::start(&model.cone_belief(m.initial_belief()).in_cone);
                Decider::OnePass(OnePassModel::new(&model), state)
            }
        };
        Ok(Self {
            belief: m.initial_belief().to_vec(),
            decider,
            model,
            opts,
            pending: None,
            outcome: None,
            steps: 0,
        })
    }

    /// The model.
    pub fn model(&self) -> &ViewConePomdp {
        &self.model
    }

    /// The offline bounds in use (`None` for a one-pass session, which needs none).
    pub fn bounds(&self) -> Option<&Bounds> {
        match &self.decider {
            Decider::Rtbss(b) => Some(b),
            Decider::OnePass(..) => None,
        }
    }

    /// The current belief over the target's whereabouts.
    pub fn belief(&self) -> ConeBelief {
        self.model.cone_belief(&self.belief)
    }

    /// How the session ended, once it has.
    pub fn outcome(&self) -> Option<Outcome> {
        self.outcome
    }

    /// Number of cones processed so far.
    pub fn steps(&self) -> usize {
        self.steps
    }

    /// Decide the next action. A declaration ends the session (see [`Self::outcome`]); a
    /// `Process` must be followed by [`Self::observe`]. Calling it again before observing returns
    /// the same action.
    pub fn next_action(&mut self) -> Result<ViewConeAction> {
        if self.outcome.is_some() {
            return Err(PomdpError::SessionEnded);
        }
        if let Some(a) = self.pending {
            return Ok(self.model.action(a));
        }
        let m = self.model.pomdp();
        let guard = self.steps >= self.opts.max_steps;
        let a = match &self.decider {
            Decider::OnePass(model, state) => self.model.index(if guard {
                model.declare(state)
            } else {
                model.decide(state, self.opts.online.depth).1
            }),
            // Guard: best declaration by expected immediate reward.
            Decider::Rtbss(_) if guard => (self.model.n..m.n_actions())
                .max_by(|x, y| {
                    m.expected_reward(&self.belief, *x)
                        .total_cmp(&m.expected_reward(&self.belief, *y))
                })
                .unwrap_or(2 * self.model.n),
            Decider::Rtbss(bounds) => {
                rtbss_sparse(m, bounds, &to_sparse(&self.belief), &self.opts.online)?.action
            }
        };
        let action = self.model.action(a);
        match action {
            ViewConeAction::Process { .. } => self.pending = Some(a),
            ViewConeAction::DeclareFound { cone } => self.outcome = Some(Outcome::Found { cone }),
            ViewConeAction::DeclareAbsent => self.outcome = Some(Outcome::Absent),
        }
        Ok(action)
    }

    /// Report the result of processing the cone chosen by [`Self::next_action`].
    pub fn observe(&mut self, detected: bool) -> Result<()> {
        if self.outcome.is_some() {
            return Err(PomdpError::SessionEnded);
        }
        let Some(a) = self.pending else {
            return Err(PomdpError::InvalidArgument(
                "observe() called without a pending Process action".into(),
            ));
        };
        let z = if detected { 0 } else { 1 };
        let (b, _) = self.model.pomdp().update(&self.belief, a, z)?;
        self.belief = b;
        if let Decider::OnePass(model, state) = &mut self.decider {
            match model.after(state, a, detected) {
                Some((_, next)) => *state = next,
                None => {
                    return Err(PomdpError::InvalidArgument(format!(
                        "cone {a}: an observation the one-pass model calls impossible"
                    )))
                }
            }
        }
        self.pending = None;
        self.steps += 1;
        Ok(())
    }
}
