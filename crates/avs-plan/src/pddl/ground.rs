//! Grounding a parsed PDDL domain and problem into a SAS+ [`Task`] by relaxed reachability
//! (one binary variable per reachable fluent atom), within [`GroundingLimits`].

use super::{err, object_types, Action, CostExpr, Domain, Literal, Problem, Term};
use crate::limits::{Budget, GroundingLimits};
use crate::task::{Operator, Task, Variable};
use crate::PlanError;
use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};

/// The objects a lifted atom's arguments `args` name under `binding`.
fn ground_args(args: &[Term], binding: &[usize], objs: &[String]) -> Vec<String> {
    args.iter()
        .map(|t| resolve(t, binding, objs).to_string())
        .collect()
}

/// The objects a goal atom's arguments name (a goal has no parameters; one would name no
/// object, "").
fn goal_args(args: &[Term]) -> Vec<String> {
    args.iter()
        .map(|t| match t {
            Term::Object(o) => o.clone(),
            Term::Param(_) => String::new(),
        })
        .collect()
}

/// The ground atom `pred(args)` under `binding`, as grounding keys atoms.
fn ground_atom(
    pred: &str,
    args: &[Term],
    binding: &[usize],
    objs: &[String],
) -> (String, Vec<String>) {
    (pred.to_string(), ground_args(args, binding, objs))
}

fn resolve<'a>(t: &'a Term, binding: &'a [usize], objs: &'a [String]) -> &'a str {
    match t {
        Term::Param(i) => &objs[binding[*i]],
        Term::Object(o) => o,
    }
}

/// Ground a domain and problem into a SAS+ task by relaxed reachability, within the default
/// [`GroundingLimits`].
pub fn ground(domain_file: &str, d: &Domain, p: &Problem) -> Result<Task, PlanError> {
    ground_with(domain_file, d, p, &GroundingLimits::default())
}

/// [`ground`] within `limits`: passing one is [`PlanError::GroundingLimit`], naming the action
/// being grounded.
pub fn ground_with(
    domain_file: &str,
    d: &Domain,
    p: &Problem,
    limits: &GroundingLimits,
) -> Result<Task, PlanError> {
    let mut budget = Budget::new(limits);
    let types = object_types(d, p).map_err(|m| err(domain_file, m))?;
    let mut objs: Vec<String> = types.keys().cloned().collect();
    objs.sort();
    let obj_index: HashMap<&str, usize> = objs
        .iter()
        .enumerate()
        .map(|(i, o)| (o.as_str(), i))
        .collect();
    let fluent: HashSet<&str> = d
        .actions
        .iter()
        .flat_map(|a| a.add.iter().chain(&a.del).map(|(p, _)| p.as_str()))
        .collect();
    for (pred, args) in &p.init {
        if !d.predicates.contains_key(pred) {
            return Err(err(
                domain_file,
                format!("problem :init uses unknown predicate `{pred}`"),
            ));
        }
        for a in args {
            if !obj_index.contains_key(a.as_str()) {
                return Err(err(
                    domain_file,
                    format!("problem :init uses unknown object `{a}`"),
                ));
            }
        }
    }
    // The goal names only declared predicates (with their arity) and known objects: an unknown
    // name is a typo, not an unreachable goal ("no plan: the task is unsolvable").
    for g in &p.goal {
        let (pred, args) = match g {
            Literal::Atom { pred, args, .. } => (Some(pred), vec![args.as_slice()]),
            Literal::Equal { a, b, .. } => {
                (None, vec![std::slice::from_ref(a), std::slice::from_ref(b)])
            }
        };
        if let Some(pred) = pred {
            let n = args[0].len();
            match d.predicates.get(pred) {
                None => {
                    return Err(err(
                        domain_file,
                        format!("problem :goal uses unknown predicate `{pred}`"),
                    ))
                }
                Some(&arity) if arity != n => {
                    return Err(err(
                        domain_file,
                        format!(
                            "problem :goal: `{pred}` takes {arity} arguments, the goal gives it {n}"
                        ),
                    ))
                }
                Some(_) => {}
            }
        }
        for t in args.into_iter().flatten() {
            if let Term::Object(o) = t {
                if !obj_index.contains_key(o.as_str()) {
                    return Err(err(
                        domain_file,
                        format!("problem :goal uses unknown object `{o}`"),
                    ));
                }
            }
        }
    }
    let init: HashSet<(String, Vec<String>)> = p.init.iter().cloned().collect();
    let mut reached: HashSet<(String, Vec<String>)> = init.clone();
    // Candidate objects per action parameter.
    let cands: Vec<Vec<Vec<usize>>> = d
        .actions
        .iter()
        .map(|a| {
            a.params
                .iter()
                .map(|(_, t)| {
                    (0..objs.len())
                        .filter(|&i| types[&objs[i]].contains(t))
                        .collect()
                })
                .collect()
        })
        .collect();
    // For each action and depth, the literals fully bound at that depth.
    let check_at: Vec<Vec<Vec<&Literal>>> = d
        .actions
        .iter()
        .map(|a| {
            let mut v: Vec<Vec<&Literal>> = vec![Vec::new(); a.params.len() + 1];
            for l in &a.pre {
                let terms: Vec<&Term> = match l {
                    Literal::Atom { args, .. } => args.iter().collect(),
                    Literal::Equal { a, b, .. } => vec![a, b],
                };
                let depth = terms
                    .iter()
                    .filter_map(|t| match t {
                        Term::Param(i) => Some(i + 1),
                        _ => None,
                    })
                    .max()
                    .unwrap_or(0);
                v[depth].push(l);
            }
            v
        })
        .collect();
    let mut ground_actions: BTreeMap<(usize, Vec<usize>), ()> = BTreeMap::new();
    for (pred, args) in &reached {
        budget.fact(|| format!("the initial state (`{pred}`)"), 0, args.len())?;
    }
    loop {
        let before = reached.len();
        for (ai, a) in d.actions.iter().enumerate() {
            let what = || format!("action `{}`", a.name);
            let mut binding = Vec::with_capacity(a.params.len());
            let mut found = Vec::new();
            let mut g = Grounding {
                a,
                cands: &cands[ai],
                check_at: &check_at[ai],
                objs: &objs,
                fluent: &fluent,
                init: &init,
                reached: &reached,
                budget: &mut budget,
            };
            g.enumerate(&mut binding, &mut found)?;
            for b in found {
                for (pred, args) in &a.add {
                    let args = ground_args(args, &b, &objs);
                    let arity = args.len();
                    if reached.insert((pred.clone(), args)) {
                        budget.fact(what, reached.len(), arity)?;
                    }
                }
                if ground_actions.insert((ai, b), ()).is_none() {
                    budget.operator(what, ground_actions.len(), a.params.len())?;
                }
            }
        }
        if reached.len() == before {
            break;
        }
    }
    // Variables: reachable fluent atoms, plus unreachable goal atoms (never true).
    let mut atoms: BTreeSet<(String, Vec<String>)> = reached
        .iter()
        .filter(|(p, _)| fluent.contains(p.as_str()))
        .cloned()
        .collect();
    for g in &p.goal {
        if let Literal::Atom { pred, args, .. } = g {
            let args = goal_args(args);
            if fluent.contains(pred.as_str()) || !init.contains(&(pred.clone(), args.clone())) {
                atoms.insert((pred.clone(), args));
            }
        }
    }
    let atoms: Vec<(String, Vec<String>)> = atoms.into_iter().collect();
    let var_of: HashMap<&(String, Vec<String>), u32> = atoms
        .iter()
        .enumerate()
        .map(|(i, a)| (a, i as u32))
        .collect();
    let name = |(p, args): &(String, Vec<String>)| {
        let mut s = format!("({p}");
        for a in args {
            s.push(' ');
            s.push_str(a);
        }
        s.push(')');
        s
    };
    let mut task = Task {
        variables: atoms
            .iter()
            .map(|a| Variable::new(name(a), vec!["false".into(), "true".into()]))
            .collect(),
        init: atoms.iter().map(|a| init.contains(a) as u32).collect(),
        goal: Vec::new(),
        operators: Vec::new(),
    };
    let mut goal = BTreeMap::new();
    for g in &p.goal {
        match g {
            Literal::Atom {
                pred,
                args,
                negated,
            } => {
                let key = (pred.clone(), goal_args(args));
                match var_of.get(&key) {
                    Some(&v) => {
                        goal.insert(v, (!negated) as u32);
                    }
                    None => {
                        // A static atom: true iff in init.
                        if init.contains(&key) == *negated {
                            return Ok(unsolvable(task));
                        }
                    }
                }
            }
            Literal::Equal { a, b, negated } => {
                if (a == b) == *negated {
                    return Ok(unsolvable(task));
                }
            }
        }
    }
    task.goal = goal.into_iter().collect();
    let use_costs = d.action_costs && p.metric_total_cost;
    for ((ai, b), ()) in ground_actions {
        let a = &d.actions[ai];
        let mut pre: BTreeMap<u32, u32> = BTreeMap::new();
        let mut ok = true;
        for l in &a.pre {
            if let Literal::Atom {
                pred,
                args,
                negated,
            } = l
            {
                if !fluent.contains(pred.as_str()) {
                    continue; // static: checked while grounding
                }
                let key = ground_atom(pred, args, &b, &objs);
                match var_of.get(&key) {
                    Some(&v) => {
                        let want = (!negated) as u32;
                        if pre.insert(v, want).is_some_and(|old| old != want) {
                            ok = false;
                        }
                    }
                    None if !negated => ok = false,
                    None => {}
                }
            }
        }
        if !ok {
            continue;
        }
        // Deletes first, then adds (an atom both deleted and added ends true).
        let mut eff: BTreeMap<u32, u32> = BTreeMap::new();
        for (atoms, value) in [(&a.del, 0), (&a.add, 1)] {
            for (pred, args) in atoms {
                if let Some(&v) = var_of.get(&ground_atom(pred, args, &b, &objs)) {
                    eff.insert(v, value);
                }
            }
        }
        let cost = if use_costs {
            let mut c = 0.0;
            for e in &a.cost {
                c += match e {
                    CostExpr::Number(n) => *n,
                    CostExpr::Fluent(f, args) => {
                        let key = ground_atom(f, args, &b, &objs);
                        *p.numeric.get(&key).ok_or_else(|| {
                            err(
                                domain_file,
                                format!(
                                    "numeric fluent ({f} {}) has no value in :init",
                                    key.1.join(" ")
                                ),
                            )
                        })?
                    }
                };
            }
            c
        } else {
            1.0
        };
        let args: Vec<String> = b.iter().map(|&i| objs[i].clone()).collect();
        let mut display = format!("({}", a.name);
        for x in &args {
            display.push(' ');
            display.push_str(x);
        }
        display.push(')');
        task.operators.push(Operator {
            schema: a.name.clone(),
            args,
            display,
            pre: pre.into_iter().collect(),
            eff: eff.into_iter().collect(),
            cost,
            prob: 1.0,
            assumption: false,
        });
    }
    tracing::debug!(%task, "grounded PDDL");
    Ok(task)
}

fn unsolvable(mut task: Task) -> Task {
    task.variables.push(Variable::new(
        "(unreachable-goal)",
        vec!["false".into(), "true".into()],
    ));
    task.init.push(0);
    task.goal = vec![(task.variables.len() as u32 - 1, 1)];
    task.operators.clear();
    task
}

/// One action's enumeration state for one round of the reachability fixpoint.
struct Grounding<'g> {
    a: &'g Action,
    cands: &'g [Vec<usize>],
    check_at: &'g [Vec<&'g Literal>],
    objs: &'g [String],
    fluent: &'g HashSet<&'g str>,
    init: &'g HashSet<(String, Vec<String>)>,
    reached: &'g HashSet<(String, Vec<String>)>,
    budget: &'g mut Budget,
}

impl Grounding<'_> {
    /// Extend `binding` by every candidate whose bound literals hold, collecting complete
    /// bindings in `found`; every binding tried and every one found counts against the budget.
    fn enumerate(
        &mut self,
        binding: &mut Vec<usize>,
        found: &mut Vec<Vec<usize>>,
    ) -> Result<(), PlanError> {
        let (a, objs) = (self.a, self.objs);
        self.budget.tried(|| format!("action `{}`", a.name))?;
        let depth = binding.len();
        for l in &self.check_at[depth] {
            let ok = match l {
                Literal::Equal {
                    a: x,
                    b: y,
                    negated,
                } => (resolve(x, binding, objs) == resolve(y, binding, objs)) != *negated,
                Literal::Atom {
                    pred,
                    args,
                    negated,
                } => {
                    let key = ground_atom(pred, args, binding, objs);
                    if self.fluent.contains(pred.as_str()) {
                        *negated || self.reached.contains(&key)
                    } else {
                        self.init.contains(&key) != *negated
                    }
                }
            };
            if !ok {
                return Ok(());
            }
        }
        if depth == a.params.len() {
            found.push(binding.clone());
            return self
                .budget
                .found(|| format!("action `{}`", a.name), found.len(), depth);
        }
        for &o in &self.cands[depth] {
            binding.push(o);
            self.enumerate(binding, found)?;
            binding.pop();
        }
        Ok(())
    }
}
