//! # avs-plan
//!
//! The strategic half of the switching planner of Aydemir, Göbelbecker, Pronobis, Sjöö and
//! Jensfelt, *Plan-based object search and exploration using semantic spatial knowledge in the
//! real world* (ECMR 2011; `002` in the papers folder), §II-A.1 and §II-B: an assumptive
//! continual planner on SAS+ (Bäckström & Nebel 1995).
//!
//! * [`domain`]: domain files (`kind: domain`, YAML) — types, constants, pools of virtual
//!   objects, static relations, finite-domain state variables, operators with preconditions,
//!   effects, a cost and a success probability (constants or caller-supplied functions such as
//!   `distance(?a, ?b)` or `p-category(?r, ?c)`), assumptive operators. [`check_domain`] reports
//!   every problem of a file.
//! * [`problem`]: the current state as the caller knows it, and the [`problem::Functions`]
//!   trait through which costs and probabilities come in (this crate knows no maps).
//! * [`ground`]: grounding with relaxed-reachability pruning into a [`Task`], within
//!   [`limits::GroundingLimits`] (operators, facts, estimated bytes, bindings tried; the error
//!   names the operator that passed them), as is PDDL grounding.
//! * [`search`](mod@search): best-first search for the plan minimising cost(π) + R·(1 − Π p(a)) (paper 002,
//!   §II-A.1); [`Mode::Optimal`] is A* with LM-cut, [`Mode::Fast`] greedy best-first search with
//!   h^FF and preferred operators. The argument for exactness is in [`search`](mod@search).
//! * [`continual`]: plan, [`monitor`](continual::ContinualPlanner::monitor) after each step
//!   (continue / replan with a reason / goal reached), give up below a success threshold. The
//!   plan handed out is the best for the configured R ([`continual::Objective::Fixed`], the
//!   default) or the one with the most success probability per unit of cost
//!   ([`continual::Objective::Ratio`], found with the paper's objective by Dinkelbach's
//!   iteration over R, [`search_best_ratio`]).
//! * [`pddl`]: PDDL import (STRIPS, typing, negative preconditions, equality, action costs) and
//!   an independent plan validator; [`lifted::validate_steps`] and [`validate_sas`] validate
//!   plans of YAML domains and of grounded tasks.
//!
//! ## Choices where the paper is vague
//! * **The reward R.** The paper minimises cost(π) + R·(1 − p(π)) and says only that a larger
//!   R makes more expensive plans worth it. With a fixed large R (1000 here) the planner picks
//!   the likeliest plan almost whatever it costs: a 1 % gain in p is worth 10 m, so a robot
//!   standing in a room with a 30 % chance drives 60 m to a room with 36 %, and, replanning
//!   there, comes back. A continual planner executes only the start of each plan, then plans
//!   again; for searches made one after another until one succeeds, the expected total cost is
//!   least when they are taken by decreasing p/cost (the index rule of optimal search). So
//!   [`continual::Objective::Ratio`] starts the plan with the largest p(π)/cost(π): the plan
//!   optimal for the paper's objective with R equal to its own cost/p, found by Dinkelbach's
//!   iteration. The success threshold for giving up is on p alone, as in the paper, unless
//!   [`continual::ContinualOptions::give_up_unless_worth_it`] asks for the paper's objective
//!   too: give up when even the plan best for R has p(π)·R ≤ cost(π), since stopping (whose
//!   objective is R) is then no worse; under the ratio objective, whose plans ignore R, this
//!   is the only place R still matters. The default stays the paper's fixed R: on the agent's benches the ratio objective pays off
//!   together with rooms that count their unfound landmarks, and that pair lets more
//!   look-alikes through the agent's fixed verification rule (BENCHMARKS.md).
//! * **Probability of a plan.** p(π) = Π p(a) over all steps; assumptions carry the caller's
//!   probability (P_category, P(ObjectAt L)); sensing steps carry a detection probability.
//! * **Heuristic for the objective.** Two admissible values, one on costs and one on −ln p,
//!   bound the remaining cost and the remaining −Σ ln p separately;
//!   f = g + h_c + R·(1 − e^{ℓ − h_ℓ}). Both come from LM-cut ([`Heuristic::LmCut`], the
//!   default, as Fast Downward's optimal configuration) or from h^max ([`Heuristic::HMax`], the
//!   continual planner's default: in the object-search domain relaxed plans are chains of dependent
//!   steps, where h^max is nearly as informed as LM-cut — 30 instead of 24 expansions on the
//!   40-place benchmark — at about a third of the cost per state).
//!   Child states are queued with the admissible estimate max(0, h(parent) − cost(a)) and
//!   evaluated when popped (deferred evaluation).
//! * **Relevance.** The search drops operators that cannot contribute to a plan with
//!   p ≥ `min_probability` ([`Task::relevant_operators`](task::Task::relevant_operators):
//!   backward relevance on facts, after the translator of Fast Downward) and maps the plan
//!   back; exact, as the property tests check against brute force.
//! * **Duplicates.** Per state the Pareto set of (cost, ln p) labels is kept; see [`search`](mod@search).
//! * **Virtual objects.** A parameter `?o: new T` binds the next unused object of the pool of T
//!   (`new-object1`, then `new-object2`, …); the monitor matches a virtual object to the real
//!   object that the world reveals in its place (paper §II-B.3).
//! * **Assumptions first.** With `assumptions_first: true` a domain lets assumptive operators
//!   apply only before the first non-assumptive step (a `(phase)` variable). This loses no plan
//!   when every plan can be reordered with its assumptions first: no non-assumptive step sets
//!   what an assumption reads, and none reads (and needs unchanged) what a later assumption
//!   writes. Both hold in `object_search.yaml`: physical steps never write categories, classes,
//!   locations or `leads-to = unknown`; the one physical step reading `leads-to = unknown`
//!   (EXPLORE-PLACEHOLDER) overwrites it, so no assumption on that placeholder can follow it.
//!   It removes the interleavings of assumptions with actions that otherwise dominate the
//!   search (42 s → 40 ms on the first plan before other tuning). Plans are printed with
//!   assumptions as early as they stay valid, as in the paper's listings.
//! * **Assumption chains.** With `assumption_chains: true` as well, each assumption after the
//!   first of a plan must read a variable that the assumption just before it wrote (a ground
//!   variable `(assumption-chain)` holds which variables the last one wrote; each assumptive
//!   operator is grounded once per write set it reads, plus once as a chain's first). An
//!   assumption cost nothing and only lowers p, so one that no later step reads is useless; but
//!   when the best plan is unlikely, the slack R·p·(1 − q) such an assumption costs is below the
//!   heuristic's error, and the search enumerated every subset of the rooms' category
//!   assumptions (on a 30-room floor 22,779 expansions for one plan; 91 with chains). This
//!   loses no plan when every plan's assumptions can be ordered as one chain, the last read by
//!   the acting steps. It holds in `object_search.yaml`: a plan looks for one object, and its
//!   assumptions are where a placeholder leads (or a room's category), then an object in that
//!   room, then the goal on that object, each reading the category or the class the one before
//!   set. The test `assumption_chains_keep_the_best_plan_…` checks the objective against the
//!   unchained search. Only copies that can apply are grounded (a first copy only when the
//!   assumption holds initially; a copy after a write set only when a writer of that set, itself
//!   kept, agrees with it on every variable both touch and shares one with it besides the pool
//!   order's `exists`, see `ground`): on a late plan of a 30-room floor 4,526 operators instead
//!   of 8,122, the same plans.
//! * **`unknown`.** The value named `unknown` is what monitoring treats as "not yet observed":
//!   an assumption on a variable still `unknown` stays open; any other value confirms or
//!   contradicts it.
//! * **Fast mode costs.** The relaxed plan is costed with 1 + cost(a) + R·(−ln p(a)), an additive
//!   over-estimate of each step's share of the objective (R·(1 − p) ≤ R·(−ln p)).
//!
//! ```
//! use avs_plan::{check_domain, continual::{ContinualPlanner, Decision}, domain::Domain,
//!     problem::Problem};
//! let text = r#"
//! kind: domain
//! name: rooms
//! types: [place, category]
//! relations: { connected: [place, place] }
//! variables:
//!   robot-at: { type: place }
//!   kind: { parameters: [place], type: category, values: [unknown], default: unknown }
//!   done: { values: ["no", "yes"], default: "no" }
//! operators:
//!   - name: move
//!     display: MOVE ?to
//!     parameters: ["?a: place", "?to: place"]
//!     precondition: ["robot-at = ?a", "connected(?a, ?to)"]
//!     effect: ["robot-at := ?to"]
//!     cost: distance(?a, ?to)
//!   - name: assume-kind
//!     display: ASSUME-KIND ?p ?c
//!     parameters: ["?p: place", "?c: category"]
//!     precondition: ["kind(?p) = unknown"]
//!     effect: ["kind(?p) := ?c"]
//!     probability: p-kind(?p, ?c)
//!     cost: 0
//!     assumption: true
//!   - name: search
//!     display: SEARCH ?p
//!     parameters: ["?p: place", "?c: category"]
//!     precondition: ["robot-at = ?p", "kind(?p) = ?c"]
//!     effect: ["done := yes"]
//! "#;
//! assert!(check_domain("rooms.yaml", text).is_empty());
//! let domain = Domain::from_yaml("rooms.yaml", text).unwrap();
//! let problem = Problem::new()
//!     .object("a", "place").object("b", "place").object("kitchen", "category")
//!     .fact("connected(a, b)").init("robot-at = a").goal("done = yes");
//! let f = |name: &str, args: &[&str]| match (name, args) {
//!     ("distance", _) => Some(2.0),
//!     ("p-kind", [p, _]) => Some(if *p == "b" { 0.9 } else { 0.1 }),
//!     _ => None,
//! };
//! let planner = ContinualPlanner::new(domain, Default::default());
//! let Decision::Plan(plan) = planner.plan(&problem, &f).unwrap() else { panic!() };
//! assert_eq!(plan.listing(), "ASSUME-KIND b kitchen\nMOVE b\nSEARCH b\n");
//! ```
pub mod continual;
pub mod domain;
pub mod expr;
pub mod ground;
pub mod heuristics;
pub mod lifted;
pub mod limits;
pub mod pddl;
pub mod problem;
pub mod search;
pub mod task;

pub use search::{search, search_best_ratio, Heuristic, Mode, SearchOptions};
pub use task::{validate_sas, Plan, SearchStats, Task};

/// Errors of the planner.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlanError {
    /// A PDDL file could not be read.
    #[error("{file}: {message}")]
    Pddl {
        /// The file.
        file: String,
        /// What is wrong and what is expected.
        message: String,
    },
    /// A grounded task is inconsistent.
    #[error("invalid task: {0}")]
    InvalidTask(String),
    /// A search option is out of range.
    #[error("invalid option: {0}")]
    InvalidOption(String),
    /// A problem does not fit its domain.
    #[error("problem: {0}")]
    Problem(String),
    /// A caller-supplied function failed.
    #[error("function {call}: {message}")]
    Function {
        /// The call, e.g. `p-category(room1, kitchen)`.
        call: String,
        /// What is wrong.
        message: String,
    },
    /// The search expanded more states than allowed.
    #[error("search gave up after {0} expansions")]
    SearchLimit(u64),
    /// Grounding passed one of its [`limits::GroundingLimits`].
    #[error("grounding {what} passed the limit of {limit} {resource}; expected operators whose parameters the preconditions constrain (each free parameter multiplies the groundings by the number of objects of its type), fewer objects, or higher limits")]
    GroundingLimit {
        /// What was being grounded, e.g. ``operator `move` `` or ``variable `at` ``.
        what: String,
        /// The resource that ran out.
        resource: limits::GroundingResource,
        /// The limit that was passed.
        limit: u64,
    },
}

/// Parse and check a domain file's text, returning every problem found (empty when valid):
/// YAML and field errors, unknown types, variables, relations, values, parameters and
/// operators, arity and type mismatches, values outside a variable's domain, costs that are
/// negative, infinite or NaN, probabilities outside (0, 1] or NaN, duplicate names, and
/// display templates naming unknown parameters — each with the file, field path and fix.
pub fn check_domain(file: &str, text: &str) -> Vec<avs_format::Diagnostic> {
    match domain::Domain::from_yaml(file, text) {
        Ok(_) => Vec::new(),
        Err(d) => d,
    }
}
