//! Continual planning (paper 002, §II-A.1): plan from the current state, execute, monitor after
//! every step, replan when the plan has become invalid, give up when no plan is likely enough.

use crate::domain::Domain;
use crate::ground::ground;
use crate::lifted::{step_value, LiftedState};
use crate::problem::{Functions, Instance, Problem};
use crate::search::{search, search_best_ratio, SearchOptions};
use crate::task::{validate_sas, Plan, SearchStats, Task};
use crate::PlanError;
use std::collections::HashMap;
use std::fmt;
use std::sync::atomic::{AtomicU64, Ordering};

/// Settings of the continual planner.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContinualOptions {
    /// Search settings (mode, reward R).
    pub search: SearchOptions,
    /// Give up when no plan reaches at least this success probability.
    pub min_success: f64,
    /// Also give up when no plan is worth starting by the paper's own objective: when even the
    /// plan that minimises cost(π) + R·(1 − p(π)) has p(π)·R ≤ cost(π), that objective is at
    /// least R, the value of not acting at all (the goal's reward is never earned). The success
    /// threshold is then cost(π)/R, per plan, beside the fixed `min_success`. Off by default
    /// (the paper's rule, on p alone).
    pub give_up_unless_worth_it: bool,
    /// Replan when an assumption the plan relies on becomes less likely than this.
    pub min_assumption: f64,
    /// Which plan to start: the one best for the fixed reward R of `search` (the paper's
    /// objective as written), or the one with the most success probability per unit of cost.
    pub objective: Objective,
}

/// The plan the continual planner hands out.
///
/// The paper (`002` §II-A.1) picks π* = argmin cost(π) + R·(1 − p(π)) for a constant R and
/// says only that a larger R makes more expensive plans worth it. A continual planner runs
/// only the first plan until something changes, then plans again from where it stands; its
/// searches follow one another until the object is found. For independent searches done one
/// after another until one succeeds, the order that minimises the expected total cost takes
/// them by decreasing p/cost (the index rule of optimal search: Blackwell; Kadane & Simon
/// 1977). So the plan to start with is the one with the largest p(π)/cost(π).
/// [`Objective::Ratio`] finds it with the paper's own objective, by Dinkelbach's iteration
/// for fractional programs (Dinkelbach 1967, [`search_best_ratio`]): plan with R, set
/// R ← cost(π)/p(π) of the plan found, plan again; p/cost never decreases from one round to
/// the next, and the plan that is optimal for R = its own cost/p maximises p/cost over all
/// plans. Each plan's iteration starts from the R the planner's previous plan was optimal
/// for ([`ContinualPlanner::reset_objective`] forgets it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Objective {
    /// cost(π) + R·(1 − p(π)) with the configured R (the default).
    #[default]
    Fixed,
    /// max p(π)/cost(π), by Dinkelbach's iteration from the configured R (at most
    /// [`Objective::MAX_ROUNDS`] further searches).
    Ratio,
}

impl Objective {
    /// Further searches [`Objective::Ratio`] makes at most after the first.
    pub const MAX_ROUNDS: usize = 4;
}

impl Default for ContinualOptions {
    fn default() -> Self {
        ContinualOptions {
            // h^max: in the object-search domain relaxed plans are chains (place → room →
            // landmark → object), where it is nearly as informed as LM-cut and much cheaper.
            search: SearchOptions {
                heuristic: crate::search::Heuristic::HMax,
                ..SearchOptions::default()
            },
            min_success: 0.01,
            give_up_unless_worth_it: false,
            min_assumption: 0.05,
            objective: Objective::default(),
        }
    }
}

/// One step of a plan.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// Operator name.
    pub schema: String,
    /// Arguments.
    pub args: Vec<String>,
    /// The listing line (e.g. `MOVE place1`).
    pub display: String,
    /// Cost.
    pub cost: f64,
    /// Success probability.
    pub probability: f64,
    /// Assumptive.
    pub assumption: bool,
}

/// A plan ready for execution.
#[derive(Debug, Clone, PartialEq)]
pub struct ActivePlan {
    /// The steps, assumptions first where the plan allows it (as in the paper's listings).
    pub steps: Vec<Step>,
    /// Σ cost.
    pub cost: f64,
    /// Π p.
    pub probability: f64,
    /// cost + R·(1 − p).
    pub objective: f64,
    /// Search statistics.
    pub stats: SearchStats,
}

impl ActivePlan {
    /// The plan in the paper's listing format, one step per line.
    pub fn listing(&self) -> String {
        let mut s = String::new();
        for st in &self.steps {
            s.push_str(&st.display);
            s.push('\n');
        }
        s
    }
}

/// Why the planner gives up.
#[derive(Debug, Clone, PartialEq)]
pub enum GiveUp {
    /// No plan reaches the goal at all.
    NoPlan,
    /// Plans exist, but the best reaches the goal only with this probability.
    TooUnlikely {
        /// The best plan's success probability (if one was found).
        best: Option<f64>,
        /// The threshold.
        threshold: f64,
    },
    /// Plans exist, but none is worth its cost: the best for the paper's objective succeeds
    /// with `probability` at `cost`, and `probability`·`reward` ≤ `cost`
    /// ([`ContinualOptions::give_up_unless_worth_it`]).
    NotWorthIt {
        /// That plan's success probability.
        probability: f64,
        /// Its cost.
        cost: f64,
        /// The reward R for reaching the goal.
        reward: f64,
    },
}

impl fmt::Display for GiveUp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GiveUp::NoPlan => write!(f, "no plan reaches the goal, even with assumptions"),
            GiveUp::TooUnlikely { best: Some(p), threshold } => write!(
                f,
                "the most promising plan succeeds with probability {p:.4}, below the threshold {threshold}"
            ),
            GiveUp::TooUnlikely { best: None, threshold } => write!(
                f,
                "no plan succeeds with probability at least {threshold}"
            ),
            GiveUp::NotWorthIt {
                probability,
                cost,
                reward,
            } => write!(
                f,
                "the most promising plan succeeds with probability {probability:.4}, below the \
                 threshold {:.4} at which the reward {reward} pays its cost {cost:.1}",
                cost / reward
            ),
        }
    }
}

/// The outcome of a planning call.
#[derive(Debug, Clone, PartialEq)]
pub enum Decision {
    /// Execute this plan.
    Plan(ActivePlan),
    /// The goal already holds.
    GoalReached,
    /// Stop searching.
    GiveUp(GiveUp),
}

/// Why a plan must be replaced.
#[derive(Debug, Clone, PartialEq)]
pub enum Replan {
    /// A step's precondition no longer holds.
    PreconditionFailed {
        /// The step (index into the plan).
        step: usize,
        /// Its listing line.
        action: String,
        /// The failed condition.
        condition: String,
    },
    /// The world contradicts an assumption.
    AssumptionContradicted {
        /// The step.
        step: usize,
        /// Its listing line.
        action: String,
        /// What was assumed.
        assumed: String,
        /// What is now known.
        actual: String,
    },
    /// An assumption has become too unlikely.
    AssumptionUnlikely {
        /// The step.
        step: usize,
        /// Its listing line.
        action: String,
        /// Its new probability.
        probability: f64,
        /// The bound.
        bound: f64,
    },
    /// The rest of the plan no longer reaches the goal.
    GoalNotReached {
        /// The unmet goal condition.
        goal: String,
    },
}

impl fmt::Display for Replan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Replan::PreconditionFailed {
                action, condition, ..
            } => {
                write!(f, "precondition {condition} of `{action}` no longer holds")
            }
            Replan::AssumptionContradicted {
                action,
                assumed,
                actual,
                ..
            } => write!(
                f,
                "assumption `{action}` contradicted: assumed {assumed}, observed {actual}"
            ),
            Replan::AssumptionUnlikely {
                action,
                probability,
                bound,
                ..
            } => write!(
                f,
                "assumption `{action}` has probability {probability:.4}, below {bound}"
            ),
            Replan::GoalNotReached { goal } => {
                write!(f, "the rest of the plan no longer achieves {goal}")
            }
        }
    }
}

/// The monitor's answer after a step.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// Execute the next step.
    Continue,
    /// The goal holds.
    GoalReached,
    /// Make a new plan.
    Replan(Replan),
}

/// The assumptive continual planner over one domain.
#[derive(Debug)]
pub struct ContinualPlanner {
    /// The domain.
    pub domain: Domain,
    /// Settings.
    pub options: ContinualOptions,
    /// [`Objective::Ratio`]: the R its last plan was optimal for (the bits of an `f64`; 0 for
    /// none yet). The next plan's iteration starts there: consecutive plans of one search
    /// have similar costs per probability, so it ends in one or two rounds instead of
    /// starting again from the configured R.
    last_ratio_reward: AtomicU64,
}

impl Clone for ContinualPlanner {
    fn clone(&self) -> Self {
        ContinualPlanner {
            domain: self.domain.clone(),
            options: self.options,
            last_ratio_reward: AtomicU64::new(self.last_ratio_reward.load(Ordering::Relaxed)),
        }
    }
}

impl ContinualPlanner {
    /// A planner for `domain`.
    pub fn new(domain: Domain, options: ContinualOptions) -> Self {
        ContinualPlanner {
            domain,
            options,
            last_ratio_reward: AtomicU64::new(0),
        }
    }

    /// Forget the R the ratio objective's last plan was optimal for (a new goal starts from the
    /// configured R again).
    pub fn reset_objective(&self) {
        self.last_ratio_reward.store(0, Ordering::Relaxed);
    }

    /// Ground `problem` into a SAS+ task (exposed for benchmarks and tools).
    pub fn ground(&self, problem: &Problem, f: &dyn Functions) -> Result<Task, PlanError> {
        let inst = Instance::new(&self.domain, problem)?;
        Ok(ground(&self.domain, inst, f)?.task)
    }

    /// Plan from the state described by `problem`.
    pub fn plan(&self, problem: &Problem, f: &dyn Functions) -> Result<Decision, PlanError> {
        let inst = Instance::new(&self.domain, problem)?;
        if LiftedState::initial(&self.domain, &inst)
            .unmet_goal()
            .is_none()
        {
            return Ok(Decision::GoalReached);
        }
        let t0 = std::time::Instant::now();
        let g = ground(&self.domain, inst, f)?;
        let ground_ms = t0.elapsed().as_secs_f64() * 1e3;
        let task = &g.task;
        if tracing::enabled!(tracing::Level::TRACE) {
            let mut per_schema = std::collections::BTreeMap::<&str, usize>::new();
            for o in &task.operators {
                *per_schema.entry(o.schema.as_str()).or_default() += 1;
            }
            tracing::trace!(?per_schema, "grounded operators per schema");
        }
        let mut opts = self.options.search;
        opts.min_probability = self.options.min_success;
        let warm = f64::from_bits(self.last_ratio_reward.load(Ordering::Relaxed));
        if self.options.objective == Objective::Ratio && warm.is_finite() && warm > 0.0 {
            opts.reward = warm;
        }
        let result = match self.options.objective {
            Objective::Fixed => search(task, &opts),
            Objective::Ratio => search_best_ratio(task, &opts, Objective::MAX_ROUNDS),
        };
        tracing::debug!(
            variables = task.variables.len(),
            operators = task.operators.len(),
            ground_ms,
            search_ms = t0.elapsed().as_secs_f64() * 1e3 - ground_ms,
            mode = ?opts.mode,
            stats = ?result.as_ref().ok().map(|r| r.1),
            "searched"
        );
        let (plan, stats) = result?;
        if let Some(p) = plan
            .as_ref()
            .filter(|_| self.options.objective == Objective::Ratio)
        {
            let r = p.cost / p.probability;
            if r.is_finite() && r > 0.0 {
                self.last_ratio_reward.store(r.to_bits(), Ordering::Relaxed);
            }
        }
        let Some(plan) = plan else {
            // Is there any plan at all, and how likely is the best one?
            let mut any = self.options.search;
            any.min_probability = 0.0;
            any.max_expansions = any.max_expansions.min(200_000);
            let best = match search(task, &any) {
                Ok((Some(p), _)) => Some(p.probability),
                Ok((None, _)) => return Ok(Decision::GiveUp(GiveUp::NoPlan)),
                Err(_) => None,
            };
            return Ok(Decision::GiveUp(GiveUp::TooUnlikely {
                best,
                threshold: self.options.min_success,
            }));
        };
        let reward = self.options.search.reward;
        let worth_it = |p: &Plan| p.probability * reward > p.cost;
        let plan = if self.options.give_up_unless_worth_it && !worth_it(&plan) {
            // The ratio objective's plan may stop short of the best ratio (a bounded number of
            // rounds): the plan that is best for the configured R itself settles it.
            let fixed = match self.options.objective {
                Objective::Fixed => Some(plan.clone()),
                Objective::Ratio => search(task, &SearchOptions { reward, ..opts })?.0,
            };
            match fixed {
                Some(f) if worth_it(&f) => f,
                other => {
                    let p = other.unwrap_or(plan);
                    return Ok(Decision::GiveUp(GiveUp::NotWorthIt {
                        probability: p.probability,
                        cost: p.cost,
                        reward,
                    }));
                }
            }
        } else {
            plan
        };
        let steps = hoist_assumptions(task, &plan.steps);
        tracing::debug!(cost = plan.cost, p = plan.probability, "plan found");
        Ok(Decision::Plan(ActivePlan {
            steps: steps
                .iter()
                .map(|&i| {
                    let o = &task.operators[i];
                    Step {
                        schema: o.schema.clone(),
                        args: o.args.clone(),
                        display: o.display.clone(),
                        cost: o.cost,
                        probability: o.prob,
                        assumption: o.assumption,
                    }
                })
                .collect(),
            cost: plan.cost,
            probability: plan.probability,
            objective: plan.objective,
            stats,
        }))
    }

    /// Check `plan` after its first `executed` steps against the new state `problem` and the
    /// new probabilities `f`.
    ///
    /// Assumptions do not act on the world, so the executed assumptions are checked again
    /// together with the remaining steps, on the lifted state: an assumption whose variables
    /// are still `unknown` is applied as planned (with its new probability); one whose
    /// variables now have the assumed values is confirmed; a virtual object the plan brought
    /// into being is matched to the real object now known in its place (paper 002, §II-B.3);
    /// any other value contradicts the assumption.
    pub fn monitor(
        &self,
        plan: &ActivePlan,
        executed: usize,
        problem: &Problem,
        f: &dyn Functions,
    ) -> Result<Verdict, PlanError> {
        let d = &self.domain;
        let inst = Instance::new(d, problem)?;
        let mut s = LiftedState::initial(d, &inst);
        if s.unmet_goal().is_none() {
            return Ok(Verdict::GoalReached);
        }
        let objs = &inst.objects;
        let mut rename: HashMap<String, String> = HashMap::new();
        let mut total_p = 1.0;
        for (i, st) in plan.steps.iter().enumerate() {
            if i < executed && !st.assumption {
                continue;
            }
            let op = d
                .op_index(&st.schema)
                .map(|k| &d.operators[k])
                .ok_or_else(|| {
                    PlanError::Problem(format!(
                        "plan step `{}` names an unknown operator",
                        st.display
                    ))
                })?;
            let args: Vec<String> = st
                .args
                .iter()
                .map(|a| rename.get(a).cloned().unwrap_or_else(|| a.clone()))
                .collect();
            let b = s
                .binding(op, &args)
                .map_err(|m| PlanError::Problem(format!("plan step `{}`: {m}", st.display)))?;
            let failed = s.failed_condition(op, &b);
            if !st.assumption {
                if let Some(c) = failed {
                    return Ok(Verdict::Replan(Replan::PreconditionFailed {
                        step: i,
                        action: st.display.clone(),
                        condition: c,
                    }));
                }
                total_p *= step_value(&inst, op, &b, f)?.prob;
                s.apply(op, &b);
                continue;
            }
            // Assumption: compare each assumed value with what is known now; a virtual object
            // assumed where the world now shows a real one is renamed, and the step re-checked.
            let (mut args, mut b, mut failed) = (args, b, failed);
            let mut open;
            loop {
                open = false;
                let mut matched = None;
                for (gv, val) in s.effects(op, &b) {
                    let cur = s.get(&gv).unwrap_or_default();
                    if cur == val {
                        continue;
                    }
                    if cur == "unknown" {
                        open = true;
                        continue;
                    }
                    let is_virtual = |n: &str| objs.index.get(n).is_some_and(|&o| objs.virtual_[o]);
                    if is_virtual(&val) && !is_virtual(&cur) && objs.index.contains_key(&cur) {
                        matched = Some((val, cur));
                        break;
                    }
                    return Ok(Verdict::Replan(Replan::AssumptionContradicted {
                        step: i,
                        action: op.display_with(&args),
                        assumed: format!("{} = {val}", inst.var_name(d, &gv)),
                        actual: format!("{} = {cur}", inst.var_name(d, &gv)),
                    }));
                }
                let Some((virt, real)) = matched else { break };
                rename.insert(virt, real);
                args = st
                    .args
                    .iter()
                    .map(|a| rename.get(a).cloned().unwrap_or_else(|| a.clone()))
                    .collect();
                b = s
                    .binding(op, &args)
                    .map_err(|m| PlanError::Problem(format!("plan step `{}`: {m}", st.display)))?;
                failed = s.failed_condition(op, &b);
            }
            let action = op.display_with(&args);
            if open {
                let p = step_value(&inst, op, &b, f)?.prob;
                if p < self.options.min_assumption {
                    return Ok(Verdict::Replan(Replan::AssumptionUnlikely {
                        step: i,
                        action,
                        probability: p,
                        bound: self.options.min_assumption,
                    }));
                }
                if let Some(c) = failed {
                    return Ok(Verdict::Replan(Replan::PreconditionFailed {
                        step: i,
                        action,
                        condition: c,
                    }));
                }
                total_p *= p;
                s.apply(op, &b);
            } else {
                // Confirmed: the world already has every assumed value.
                for (p, &o) in op.params.iter().zip(&b) {
                    if p.new {
                        s.create(o);
                    }
                }
            }
        }
        if let Some(g) = s.unmet_goal() {
            return Ok(Verdict::Replan(Replan::GoalNotReached { goal: g }));
        }
        if total_p < self.options.min_success {
            return Ok(Verdict::Replan(Replan::GoalNotReached {
                goal: format!(
                    "the goal with probability ≥ {} (now {total_p:.4})",
                    self.options.min_success
                ),
            }));
        }
        Ok(Verdict::Continue)
    }
}

/// Move every assumptive step as early as the plan stays valid (same steps, so the same cost and
/// probability), keeping the order among assumptions; the paper's listings state assumptions
/// first.
pub fn hoist_assumptions(task: &Task, steps: &[usize]) -> Vec<usize> {
    let mut out = steps.to_vec();
    let mut front = 0;
    for i in 0..out.len() {
        if !task.operators[out[i]].assumption {
            continue;
        }
        let mut j = i;
        while j > front {
            let mut trial = out.clone();
            trial.swap(j - 1, j);
            if validate_sas(task, &trial).is_ok() {
                out = trial;
                j -= 1;
            } else {
                break;
            }
        }
        if j == front {
            front += 1;
        }
    }
    out
}
