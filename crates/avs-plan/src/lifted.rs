//! The lifted semantics of YAML domains: a state maps ground variables to value names; a step
//! names an operator and its arguments. Used by the independent plan validator
//! ([`validate_steps`]) and by plan monitoring; it shares nothing with grounding or search but
//! the resolved problem.

use crate::domain::{Cond, Domain, OpSchema, Quantity};
use crate::problem::{cond_text, Functions, GroundVar, Instance, Problem};
use crate::PlanError;
use std::collections::{HashMap, HashSet};

/// A lifted state.
#[derive(Debug, Clone)]
pub struct LiftedState<'a> {
    /// The domain.
    pub d: &'a Domain,
    /// The resolved problem.
    pub inst: &'a Instance,
    values: HashMap<GroundVar, String>,
    created: HashSet<usize>,
}

/// A step's cost and probability.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepValue {
    /// Cost.
    pub cost: f64,
    /// Success probability.
    pub prob: f64,
}

impl<'a> LiftedState<'a> {
    /// The initial state of a problem.
    pub fn initial(d: &'a Domain, inst: &'a Instance) -> Self {
        LiftedState {
            d,
            inst,
            values: HashMap::new(),
            created: HashSet::new(),
        }
    }

    /// The value of a ground variable.
    pub fn get(&self, gv: &GroundVar) -> Option<String> {
        self.values
            .get(gv)
            .cloned()
            .or_else(|| self.inst.initial(self.d, gv).ok())
    }

    /// Set a ground variable.
    pub fn set(&mut self, gv: GroundVar, val: String) {
        self.values.insert(gv, val);
    }

    /// Resolve step arguments to objects of the parameters' types.
    pub fn binding(&self, op: &OpSchema, args: &[String]) -> Result<Vec<usize>, String> {
        if args.len() != op.params.len() {
            return Err(format!(
                "`{}` takes {} arguments, got {}",
                op.name,
                op.params.len(),
                args.len()
            ));
        }
        op.params
            .iter()
            .zip(args)
            .map(|(p, a)| match self.inst.objects.index.get(a) {
                Some(&o) if self.inst.objects.types[o] == p.ty => Ok(o),
                Some(_) => Err(format!("`{a}` is not of type `{}`", self.d.types[p.ty])),
                None => Err(format!("unknown object `{a}`")),
            })
            .collect()
    }

    /// The first precondition of `op` under `b` that does not hold, as text.
    pub fn failed_condition(&self, op: &OpSchema, b: &[usize]) -> Option<String> {
        let objs = &self.inst.objects;
        for (p, &o) in op.params.iter().zip(b) {
            if p.new {
                if !objs.virtual_[o] {
                    return Some(format!("`{}` is a virtual object", objs.names[o]));
                }
                if self.created.contains(&o) {
                    return Some(format!("`{}` is not yet in use", objs.names[o]));
                }
            } else if objs.virtual_[o] && !self.created.contains(&o) {
                return Some(format!("`{}` has been brought into being", objs.names[o]));
            }
        }
        for c in &op.pre {
            if !self.holds(c, b) {
                return Some(cond_text(self.d, self.inst, c, b));
            }
        }
        None
    }

    fn holds(&self, c: &Cond, b: &[usize]) -> bool {
        match c {
            Cond::Rel { rel, args, negated } => match self.inst.obj_args(args, b) {
                Some(a) => self.inst.facts.contains(*rel, &a) != *negated,
                None => *negated,
            },
            Cond::Eq { a, b: y, negated } => {
                (self.inst.name(a, b) == self.inst.name(y, b)) != *negated
            }
            Cond::Var {
                var,
                args,
                value,
                negated,
            } => {
                let Some(a) = self.inst.obj_args(args, b) else {
                    return false;
                };
                let cur = self.get(&(*var, a));
                (cur.as_deref() == Some(self.inst.name(value, b))) != *negated
            }
        }
    }

    /// The effects of `op` under `b`: (variable, value).
    pub fn effects(&self, op: &OpSchema, b: &[usize]) -> Vec<(GroundVar, String)> {
        op.eff
            .iter()
            .filter_map(|e| {
                let a = self.inst.obj_args(&e.args, b)?;
                Some(((e.var, a), self.inst.name(&e.value, b).to_string()))
            })
            .collect()
    }

    /// Apply `op`'s effects under `b` (without checking preconditions).
    pub fn apply(&mut self, op: &OpSchema, b: &[usize]) {
        for (gv, v) in self.effects(op, b) {
            self.values.insert(gv, v);
        }
        for (p, &o) in op.params.iter().zip(b) {
            if p.new {
                self.created.insert(o);
            }
        }
    }

    /// Mark a virtual object as in use.
    pub fn create(&mut self, o: usize) {
        self.created.insert(o);
    }

    /// The first goal condition that does not hold, as text.
    pub fn unmet_goal(&self) -> Option<String> {
        self.inst
            .goal
            .iter()
            .find(|(gv, v)| self.get(gv).as_deref() != Some(v.as_str()))
            .map(|(gv, v)| format!("{} = {v}", self.inst.var_name(self.d, gv)))
    }
}

/// Evaluate a step's cost and probability.
pub fn step_value(
    inst: &Instance,
    op: &OpSchema,
    b: &[usize],
    f: &dyn Functions,
) -> Result<StepValue, PlanError> {
    let q = |q: &Quantity, what: &str| -> Result<f64, PlanError> {
        match q {
            Quantity::Const(v) => Ok(*v),
            Quantity::Func { name, args } => {
                let a: Vec<&str> = args.iter().map(|t| inst.name(t, b)).collect();
                let call = format!("{name}({})", a.join(", "));
                let v = f.value(name, &a).ok_or_else(|| PlanError::Function {
                    call: call.clone(),
                    message: format!("not supplied by the caller (the {what} of `{}`)", op.name),
                })?;
                let ok = if what == "probability" {
                    (0.0..=1.0).contains(&v)
                } else {
                    v.is_finite() && v >= 0.0
                };
                if ok {
                    Ok(v)
                } else {
                    Err(PlanError::Function {
                        call,
                        message: format!("{what} {v} is out of range"),
                    })
                }
            }
        }
    };
    Ok(StepValue {
        cost: q(&op.cost, "cost")?,
        prob: q(&op.prob, "probability")?,
    })
}

/// Simulate `steps` (operator name and arguments) on `problem` with the domain's lifted
/// semantics and return the plan's cost and success probability; an error names the first
/// inapplicable step or the unmet goal.
pub fn validate_steps(
    d: &Domain,
    problem: &Problem,
    steps: &[(String, Vec<String>)],
    f: &dyn Functions,
) -> Result<StepValue, String> {
    let inst = Instance::new(d, problem).map_err(|e| e.to_string())?;
    let mut s = LiftedState::initial(d, &inst);
    let mut total = StepValue {
        cost: 0.0,
        prob: 1.0,
    };
    for (i, (name, args)) in steps.iter().enumerate() {
        let op = d
            .operators
            .iter()
            .find(|o| &o.name == name)
            .ok_or_else(|| format!("step {}: unknown operator `{name}`", i + 1))?;
        let b = s
            .binding(op, args)
            .map_err(|m| format!("step {} ({name}): {m}", i + 1))?;
        if let Some(c) = s.failed_condition(op, &b) {
            return Err(format!(
                "step {} ({}): precondition {c} does not hold",
                i + 1,
                op.display_with(args)
            ));
        }
        let v = step_value(&inst, op, &b, f).map_err(|e| e.to_string())?;
        total.cost += v.cost;
        total.prob *= v.prob;
        s.apply(op, &b);
    }
    if let Some(g) = s.unmet_goal() {
        return Err(format!("goal {g} does not hold at the end of the plan"));
    }
    Ok(total)
}
