//! The grounded SAS+ task (Bäckström & Nebel 1995): finite-domain variables, an initial state,
//! a partial goal state and operators with precondition and effect lists, each operator carrying
//! a cost and a success probability (paper 002, §II-A.1).

use std::fmt;

/// Index of a state variable.
pub type Var = u32;
/// Index of a value in a variable's domain.
pub type Val = u32;

/// One finite-domain state variable.
#[derive(Debug, Clone, PartialEq)]
pub struct Variable {
    /// Printable name, e.g. `category(room1)` or `at(ball1, rooma)`.
    pub name: String,
    /// Names of the values; the domain is `0..values.len()`.
    pub values: Vec<String>,
    /// A search-control variable: it only orders operators (to cut symmetric plans, as the
    /// grounding's assumption chain does) and is copied into operators once per value it may
    /// hold. The delete-relaxation heuristics drop its conditions and merge the copies that
    /// become identical (`heuristics`): an admissible weakening that makes each
    /// evaluation several times cheaper.
    pub control: bool,
}

impl Variable {
    /// An ordinary (not control) variable.
    pub fn new(name: impl Into<String>, values: Vec<String>) -> Self {
        Variable {
            name: name.into(),
            values,
            control: false,
        }
    }
}

/// One grounded operator.
#[derive(Debug, Clone, PartialEq)]
pub struct Operator {
    /// Name of the operator schema it was grounded from (e.g. `move`).
    pub schema: String,
    /// The schema's arguments, in parameter order.
    pub args: Vec<String>,
    /// How the step is printed in a plan listing (e.g. `MOVE place1`).
    pub display: String,
    /// Preconditions `var = val`, sorted by variable, at most one per variable.
    pub pre: Vec<(Var, Val)>,
    /// Effects `var := val`, sorted by variable, at most one per variable.
    pub eff: Vec<(Var, Val)>,
    /// Non-negative cost.
    pub cost: f64,
    /// Success probability in (0, 1].
    pub prob: f64,
    /// Whether this is an assumptive operator (it sets what is not known).
    pub assumption: bool,
}

impl Operator {
    /// `schema arg1 arg2 …`: the key by which a step is matched across re-groundings.
    pub fn key(&self) -> String {
        key_of(&self.schema, &self.args)
    }
}

/// The key of a step: its schema and arguments joined by spaces.
pub fn key_of(schema: &str, args: &[String]) -> String {
    let mut s = schema.to_string();
    for a in args {
        s.push(' ');
        s.push_str(a);
    }
    s
}

/// A grounded SAS+ planning task with costs and success probabilities.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Task {
    /// The state variables.
    pub variables: Vec<Variable>,
    /// The initial value of every variable.
    pub init: Vec<Val>,
    /// The goal: a partial assignment.
    pub goal: Vec<(Var, Val)>,
    /// The operators.
    pub operators: Vec<Operator>,
}

impl Task {
    /// Whether every operator costs exactly 1 (the competition's "unit cost").
    pub fn is_unit_cost(&self) -> bool {
        self.operators.iter().all(|o| o.cost == 1.0)
    }

    /// Whether every operator succeeds with probability 1.
    pub fn is_deterministic(&self) -> bool {
        self.operators.iter().all(|o| o.prob >= 1.0)
    }

    /// Whether `state` satisfies the goal.
    pub fn is_goal(&self, state: &[Val]) -> bool {
        self.goal.iter().all(|&(v, x)| state[v as usize] == x)
    }

    /// Fact numbering: fact `(v, x)` is `offsets[v] + x`; also the number of facts.
    pub(crate) fn fact_offsets(&self) -> (Vec<usize>, usize) {
        let mut offsets = Vec::with_capacity(self.variables.len());
        let mut n = 0;
        for v in &self.variables {
            offsets.push(n);
            n += v.values.len();
        }
        (offsets, n)
    }

    /// The operators that can contribute to the goal: backward relevance analysis on facts
    /// (as in Helmert's translator, *Concise finite-domain representations for PDDL planning
    /// tasks*, AIJ 2009, §6, here on facts rather than variables). A fact is relevant when it is
    /// a goal fact or a precondition of a relevant operator; an operator is relevant when it
    /// adds a relevant fact. Operators whose success probability is below `min_probability`
    /// are left out from the start (a plan containing one is less likely than that). Returns
    /// the relevant operators' indices, ascending.
    ///
    /// Dropping the other operators loses no plan quality: in any plan, the subsequence of
    /// relevant operators is itself a plan (every precondition of a relevant operator, and every
    /// goal fact, was last written by a relevant operator or holds initially, since an operator
    /// only writes facts through its effects), with no more cost and no less probability.
    pub fn relevant_operators(&self, min_probability: f64) -> Vec<usize> {
        let (offsets, n_facts) = self.fact_offsets();
        let fact = |(v, x): (Var, Val)| offsets[v as usize] + x as usize;
        let mut adders: Vec<Vec<usize>> = vec![Vec::new(); n_facts];
        for (i, o) in self.operators.iter().enumerate() {
            if o.prob < min_probability {
                continue;
            }
            for &e in &o.eff {
                adders[fact(e)].push(i);
            }
        }
        let mut relevant_fact = vec![false; n_facts];
        let mut relevant_op = vec![false; self.operators.len()];
        let mut stack: Vec<usize> = Vec::new();
        for &g in &self.goal {
            let f = fact(g);
            if !relevant_fact[f] {
                relevant_fact[f] = true;
                stack.push(f);
            }
        }
        while let Some(f) = stack.pop() {
            for &o in &adders[f] {
                if relevant_op[o] {
                    continue;
                }
                relevant_op[o] = true;
                for &p in &self.operators[o].pre {
                    let pf = fact(p);
                    if !relevant_fact[pf] {
                        relevant_fact[pf] = true;
                        stack.push(pf);
                    }
                }
            }
        }
        (0..self.operators.len())
            .filter(|&i| relevant_op[i])
            .collect()
    }

    /// Check internal consistency (indices in range, probabilities in (0,1], costs ≥ 0 and finite).
    pub fn check(&self) -> Result<(), crate::PlanError> {
        let bad = |m: String| Err(crate::PlanError::InvalidTask(m));
        if self.init.len() != self.variables.len() {
            return bad(format!(
                "initial state has {} values for {} variables",
                self.init.len(),
                self.variables.len()
            ));
        }
        let in_range = |v: Var, x: Val| {
            (v as usize) < self.variables.len()
                && (x as usize) < self.variables[v as usize].values.len()
        };
        for (i, &x) in self.init.iter().enumerate() {
            if !in_range(i as Var, x) {
                return bad(format!("initial value {x} of variable {i} out of range"));
            }
        }
        for &(v, x) in &self.goal {
            if !in_range(v, x) {
                return bad(format!("goal fact {v}={x} out of range"));
            }
        }
        for o in &self.operators {
            if !(o.cost.is_finite() && o.cost >= 0.0) {
                return bad(format!("operator `{}` has cost {}", o.key(), o.cost));
            }
            if !(o.prob > 0.0 && o.prob <= 1.0) {
                return bad(format!("operator `{}` has probability {}", o.key(), o.prob));
            }
            for &(v, x) in o.pre.iter().chain(&o.eff) {
                if !in_range(v, x) {
                    return bad(format!(
                        "operator `{}` mentions {v}={x} out of range",
                        o.key()
                    ));
                }
            }
        }
        Ok(())
    }
}

/// A plan: operator indices into a [`Task`], with its cost and success probability.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The steps (indices into `Task::operators`).
    pub steps: Vec<usize>,
    /// Σ cost(a).
    pub cost: f64,
    /// Π p(a).
    pub probability: f64,
    /// The objective cost(π) + R·(1 − p(π)) with the reward used in the search.
    pub objective: f64,
}

/// What one search did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SearchStats {
    /// States expanded.
    pub expanded: u64,
    /// Successors generated.
    pub generated: u64,
    /// Heuristic evaluations.
    pub evaluated: u64,
}

impl SearchStats {
    /// Add another search's counts (searches made one after another for one answer).
    pub fn add(&mut self, other: SearchStats) {
        self.expanded += other.expanded;
        self.generated += other.generated;
        self.evaluated += other.evaluated;
    }
}

/// A plan validated against a task by simulation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Validated {
    /// Σ cost(a).
    pub cost: f64,
    /// Π p(a).
    pub probability: f64,
}

/// Why a plan is not valid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InvalidPlan {
    /// A step's operator index does not exist.
    #[error("step {step}: no operator with index {index}")]
    NoSuchOperator {
        /// 0-based step.
        step: usize,
        /// The index.
        index: usize,
    },
    /// A step's precondition does not hold.
    #[error("step {step} ({action}): precondition {fact} does not hold")]
    Precondition {
        /// 0-based step.
        step: usize,
        /// The step as printed.
        action: String,
        /// The failed fact.
        fact: String,
    },
    /// The final state does not satisfy the goal.
    #[error("the plan ends in a state where goal {fact} does not hold")]
    GoalNotReached {
        /// The first unsatisfied goal fact.
        fact: String,
    },
}

impl fmt::Display for Task {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "SAS+ task: {} variables, {} operators, {} goal facts",
            self.variables.len(),
            self.operators.len(),
            self.goal.len()
        )
    }
}

/// Print `var = value` by name.
pub fn fact_name(task: &Task, v: Var, x: Val) -> String {
    let var = &task.variables[v as usize];
    format!(
        "{} = {}",
        var.name,
        var.values
            .get(x as usize)
            .map(String::as_str)
            .unwrap_or("?")
    )
}

/// Simulate `steps` on `task` from its initial state (SAS+ semantics: an operator applies when
/// all its preconditions hold and sets its effects) and check that the goal holds at the end.
///
/// This is deliberately written without any of the search code's data structures.
pub fn validate_sas(task: &Task, steps: &[usize]) -> Result<Validated, InvalidPlan> {
    let mut state = task.init.clone();
    let mut cost = 0.0;
    let mut probability = 1.0;
    for (i, &s) in steps.iter().enumerate() {
        let op = task
            .operators
            .get(s)
            .ok_or(InvalidPlan::NoSuchOperator { step: i, index: s })?;
        for &(v, x) in &op.pre {
            if state[v as usize] != x {
                return Err(InvalidPlan::Precondition {
                    step: i,
                    action: op.display.clone(),
                    fact: fact_name(task, v, x),
                });
            }
        }
        for &(v, x) in &op.eff {
            state[v as usize] = x;
        }
        cost += op.cost;
        probability *= op.prob;
    }
    for &(v, x) in &task.goal {
        if state[v as usize] != x {
            return Err(InvalidPlan::GoalNotReached {
                fact: fact_name(task, v, x),
            });
        }
    }
    Ok(Validated { cost, probability })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn op(name: &str, pre: &[(Var, Val)], eff: &[(Var, Val)], prob: f64) -> Operator {
        Operator {
            schema: name.into(),
            args: vec![],
            display: name.into(),
            pre: pre.to_vec(),
            eff: eff.to_vec(),
            cost: 1.0,
            prob,
            assumption: prob < 1.0,
        }
    }

    /// Variables a, b, c with values 0/1; the goal is a = 1.
    fn task(operators: Vec<Operator>) -> Task {
        let var = |n: &str| Variable::new(n, vec!["0".into(), "1".into()]);
        Task {
            variables: vec![var("a"), var("b"), var("c")],
            init: vec![0, 0, 0],
            goal: vec![(0, 1)],
            operators,
        }
    }

    #[test]
    fn operators_that_cannot_lead_to_the_goal_are_not_relevant() {
        let t = task(vec![
            op("set-c", &[], &[(2, 1)], 1.0),          // c = 1: nothing needs it
            op("set-b", &[(2, 1)], &[(1, 1)], 1.0),    // b = 1 from c = 1
            op("a-from-b", &[(1, 1)], &[(0, 1)], 1.0), // the goal from b = 1
            op("reset-a", &[], &[(0, 0)], 1.0),        // a = 0 is never needed
        ]);
        // c = 1 is needed by set-b, which is needed by a-from-b: all three are relevant.
        assert_eq!(t.relevant_operators(0.0), vec![0, 1, 2]);
        let u = task(vec![
            op("set-c", &[], &[(2, 1)], 1.0),
            op("a", &[], &[(0, 1)], 1.0),
        ]);
        assert_eq!(u.relevant_operators(0.0), vec![1]);
    }

    #[test]
    fn operators_less_likely_than_the_threshold_are_left_out_with_what_only_they_need() {
        let t = task(vec![
            op("unlikely", &[(1, 1)], &[(0, 1)], 0.01), // the goal, but p = 0.01
            op("set-b", &[], &[(1, 1)], 1.0),           // only needed by `unlikely`
            op("likely", &[], &[(0, 1)], 0.5),
        ]);
        assert_eq!(t.relevant_operators(0.0), vec![0, 1, 2]);
        assert_eq!(t.relevant_operators(0.1), vec![2]);
    }
}
