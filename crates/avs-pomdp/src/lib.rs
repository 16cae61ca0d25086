//! # avs-pomdp
//!
//! Discrete POMDPs for the decision-theoretic half of the avs switching planner (Aydemir et al. 2011,
//! `002` §II-A.2): when the continual planner reaches SEARCHFOROBJECT, a small POMDP over the view cones
//! of one location decides, closed loop, where to move and which cone to process until the target is
//! confirmed or the location rejected.
//!
//! * [`model`] — the finite POMDP and its Bayes filter; [`cassandra`] — Cassandra's `.pomdp` format.
//! * [`offline`] — HSVI2 (Smith & Simmons 2005): α-vector lower bound, sawtooth upper bound, trials
//!   driven by the gap at the initial belief; [`bounds`] — the bounds and their initialisation.
//! * [`online`] — RTBSS (Ross, Pineau, Paquet & Chaib-draa 2008, Algorithm 3.2): depth-limited
//!   forward search with branch-and-bound on the offline bounds; [`online::expectimax`] is the
//!   brute-force reference.
//! * [`rollout`] — the one-pass rollout policy of view-cone sessions: expectimax whose leaves
//!   are a nearest-neighbour pass's exact value (Bertsekas' rollout), one look per cone.
//! * [`viewcone`] — the view-cone POMDP and the closed-loop [`ViewConeSession`] (the cones
//!   themselves come from CREATEVIEWCONES, which lives in `avs-view`).
//! * [`simulate`](mod@simulate) — seeded Monte-Carlo evaluation of a policy.
//!
//! ## Choices where the papers are vague
//! * **Offline solver.** HSVI2 rather than SARSOP: both keep the same two bounds and stop on the
//!   gap at b₀; HSVI's exploration needs no learned heuristics and is exact in its guarantees. The
//!   upper bound starts from the fast informed bound (itself started from Q_MDP), the lower bound from
//!   blind-policy vectors. Pointwise-dominated α-vectors and redundant upper-bound points are pruned,
//!   and α-vectors that are maximal at no stored belief are dropped (HSVI2's pruning), whenever the
//!   bounds have grown by half. Each backup builds the α-vector of the best action only (chosen from
//!   the posteriors' values) and reuses the forward pass's upper Q-values for the actions whose
//!   successors did not change (stale upper values are still upper bounds). T is stored sparsely.
//! * **Rewards.** Cassandra rewards `R(s,a,s',z)` are reduced to their expectation `R(s,a)`, which is
//!   all a value-based solver needs; `values: cost` negates them.
//! * **View-cone POMDP.** The robot's pose (start or the last processed cone) is part of the state so
//!   that travel costs between cone poses enter the rewards; it is always known, so beliefs stay
//!   sparse. "Move to cone i" and "process cone i" are one action (the paper's MOVE + PROCESSVIEWCONE):
//!   moving without processing never gains information. Declarations end the session. Overlapping cones
//!   are made disjoint by giving each cell to the first cone (greedy order) that covers it; mass of
//!   uncovered cells joins "not in the location", since no observation can tell them apart. The paper's
//!   FN/FP rates 0.2/0.05 are the defaults a caller would read from the knowledge file.
//! * **Session.** Each `next_action()` runs RTBSS (default depth 2) on bounds refined by HSVI for a
//!   short budget when the session starts (default 30 trials — a trial budget rather than a time
//!   budget, so decisions and plan traces do not depend on the machine); a step guard forces a
//!   declaration after `max_steps`. An observation the model calls impossible (e.g. a detection
//!   with FP = 0 where the belief rules the target out) is an error, not a silent reset.
//! * **Bound validity and underflow.** A sparse belief lists each state once: the sawtooth ratio
//!   `min_s b(s)/b_i(s)` and the corner interpolation read one entry per state. Up to this fix the
//!   one-step look-ahead ([`Pomdp`]'s `expand`) marked a next state "touched" by a non-zero
//!   accumulator; when a contribution `b(s)·T(s'|s,a)` underflowed to 0 (beliefs driven to a corner
//!   by informative observations, which HSVI's deep trials at γ ≥ 0.975 reach), the mark stayed off
//!   and the state was listed twice, each entry carrying its full mass before normalisation. Such a
//!   posterior, stored as an upper-bound point, gave ratios up to 2 at ordinary beliefs, so the
//!   sawtooth fell below V*: tiger at γ = 0.98 "converged" to lower 22.82 above upper 19.62 (V* =
//!   51.90). Zero contributions are now skipped and posterior entries that underflow in the
//!   normalisation leave the support. The solve also refuses to return bounds that are not finite
//!   or crossed ([`PomdpError::Numerical`]); `tests/bounds_oracle.rs` checks the bounds against a
//!   grid oracle on tiger up to γ = 0.999 and on random two-state POMDPs.
//! * **Resource bounds.** A model is at most [`model::MAX_MODEL_ENTRIES`] (2²⁴) in
//!   `|S| × |A| × |Z|` — the size of its observation table and of one look-ahead from a full
//!   belief — and its rewards at most [`model::MAX_VALUE_MAGNITUDE`] (10¹²) in `|R| / (1 − γ)`;
//!   the `.pomdp` reader reports both at the offending line before allocating. A solve's time
//!   limit is checked inside trials and initial sweeps, a trial keeps at most
//!   [`offline::MAX_TRIAL_ENTRIES`] numbers, and the fast informed bound is skipped (Q_MDP
//!   corners instead) when its weights would exceed [`bounds::MAX_FIB_WEIGHTS`]. The reasons for
//!   each number are on the constants; the issue-18 reproducers are in `tests/resource_bounds.rs`.
//! * **Known limitation.** The sawtooth upper bound converges slowly on view-cone models with noisy
//!   sensors (thousands of points for a 2-cone model at gap 1e-2), which is why sessions rely on
//!   RTBSS over a bounded offline solve rather than on a converged policy. The initial upper bound
//!   is iterated down from rmax/(1−γ), so with γ near 1 and few `init_iterations` (the agent's
//!   sessions: γ = 0.99, 40) it stays near that trivial bound, and HSVI's trials run to their depth
//!   limit. Starting Q_MDP from below with a residual certificate would tighten it a
//!   hundredfold, but it changes the sessions' decisions (see BENCHMARKS.md, `avs run`).
//! * **One-pass sessions** ([`SessionPolicy::OnePassRollout`], what the agent uses): a session
//!   is one search of the location, matching the continual planner's success model for
//!   SEARCHFOROBJECT; a cone is processed again only to confirm a detection, and "found" is
//!   declared only where the last look detected. The leaf's base pass confirms a detection
//!   with one more look, which is our choice (the paper's DT planner has no base policy).
//! * **RTBSS leaves.** At depth 1 the children are leaves, so all actions are evaluated exactly
//!   instead of being ordered by U (same value, less work); deeper, Algorithm 3.2 is followed.
//!
//! ## Example
//! ```
//! use avs_pomdp::{parse_pomdp, solve, OfflineOptions};
//! let text = "discount: 0.95\nvalues: reward\nstates: tiger-left tiger-right\n\
//!             actions: listen open-left open-right\nobservations: hear-left hear-right\n\
//!             start: uniform\n\
//!             T: listen\nidentity\nT: open-left\nuniform\nT: open-right\nuniform\n\
//!             O: listen\n0.85 0.15\n0.15 0.85\nO: open-left\nuniform\nO: open-right\nuniform\n\
//!             R: listen : * : * : * -1\n\
//!             R: open-left : tiger-left : * : * -100\nR: open-left : tiger-right : * : * 10\n\
//!             R: open-right : tiger-left : * : * 10\nR: open-right : tiger-right : * : * -100\n";
//! let model = parse_pomdp(text, "tiger").unwrap();
//! let sol = solve(&model, &OfflineOptions { target_gap: 1e-2, ..Default::default() }).unwrap();
//! assert!(sol.upper - sol.lower <= 1e-2);
//! assert!((sol.lower - 19.37).abs() < 0.05); // the known optimum 19.3714
//! // The first action of the lower bound's policy at b₀ is to listen.
//! assert_eq!(sol.bounds.lower_action(model.initial_belief()), 0);
//! ```
pub mod bounds;
pub mod cassandra;
pub mod error;
pub mod model;
pub mod offline;
pub mod online;
pub mod rollout;
pub mod simulate;
pub mod viewcone;

pub use bounds::{AlphaVector, Bounds};
pub use cassandra::{parse_pomdp, read_pomdp_file};
pub use error::{PomdpError, Result};
pub use model::{Pomdp, PomdpTables};
pub use offline::{solve, solve_from, OfflineOptions, OfflineSolution, StopReason};
pub use online::{expectimax, rtbss, OnlineDecision, OnlineOptions};
pub use rollout::{OnePassModel, OnePassState};
pub use simulate::{horizon_for, simulate, SimulationSummary};
pub use viewcone::{
    cone_priors, euclidean_travel, ConeBelief, DecisionRewards, Outcome, SessionOptions,
    SessionPolicy, ViewConeAction, ViewConePomdp, ViewConeProblem, ViewConeSession, MAX_CONES,
    PAPER_FALSE_NEGATIVE, PAPER_FALSE_POSITIVE,
};
