//! Continual planning (paper 002, §II-A.1): plan from the current state, execute, monitor after
//! every step, replan when the plan has become invalid, give up when no plan is likely enough.

use crate::domain::Domain;
use crate::ground::ground;
use crate::lifted::{step_value, LiftedState};
use crate::problem::{Functions, Instance, Problem};
use crate::search::{search, SearchOptions};
use crate::task::{validate_sas, SearchStats, Task};
use crate::PlanError;
use std::collections::HashMap;
use std::fmt;

/// Settings of the continual planner.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContinualOptions {
    /// Search settings (mode, reward R).
    pub search: SearchOptions,
    /// Give up when no plan reaches at least this success probability.
    pub min_success: f64,
    /// Replan when an assumption the plan relies on becomes less likely than this.
    pub min_assumption: f64,
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
            min_assumption: 0.05,
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
#[derive(Debug, Clone)]
pub struct ContinualPlanner {
    /// The domain.
    pub domain: Domain,
    /// Settings.
    pub options: ContinualOptions,
}

impl ContinualPlanner {
    /// A planner for `domain`.
    pub fn new(domain: Domain, options: ContinualOptions) -> Self {
        ContinualPlanner { domain, options }
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
        let g = ground(&self.domain, inst, f)?;
        let task = &g.task;
        let mut opts = self.options.search;
        opts.min_probability = self.options.min_success;
        let result = search(task, &opts);
        tracing::debug!(
            variables = task.variables.len(),
            operators = task.operators.len(),
            mode = ?opts.mode,
            stats = ?result.as_ref().ok().map(|r| r.1),
            "searched"
        );
        let (plan, stats) = result?;
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
