//! Grounding a YAML domain and a problem into a SAS+ [`Task`] by relaxed reachability.
//!
//! Operators are instantiated by backtracking over their parameters; a condition is checked as
//! soon as its parameters are bound: static relations and equalities exactly, and so are
//! conditions on ground variables that no effect of any operator can write (over every binding,
//! reachable or not), since those keep their initial values; other variable conditions only
//! need a value of the variable's domain here. Starting from the initial facts, the loop then
//! adds the effects of every instantiated operator whose conditions are all reached, until no
//! new fact is reached (the delete relaxation's fixpoint), so operators that can never apply
//! are left out. An operator's cost and probability (the caller's functions) are evaluated when
//! it is first reached, and its names built once it is kept (one 30-room object-search plan
//! found 30 225 bindings and kept 1 321 operators before assumption-chain copies).
//! An operator of probability 0 never applies. Variables no kept operator changes are then
//! removed (their conditions are decided on the initial state).
//!
//! Virtual objects get a built-in variable `exists(v)`; an operator parameter marked `new` binds
//! a virtual object with `exists = no` (and requires the pool's previous object to exist, so
//! `new-room2` is only used after `new-room1`, which removes symmetric plans), and sets it to
//! `yes`; any other parameter bound to a virtual object requires `exists = yes`.
//!
//! Grounding stays within [`GroundingLimits`] (see [`crate::limits`]): the ground variables of
//! a state variable are counted before they are built, and an operator whose groundings pass
//! a limit ends the grounding with [`PlanError::GroundingLimit`] naming it.

use crate::domain::{Cond, Domain, Quantity};
use crate::limits::{Budget, GroundingLimits};
use crate::problem::{Functions, Instance};
use crate::task::{Operator, Task, Variable};
use crate::PlanError;
use std::collections::BTreeMap;

/// A hash map with foldhash's fixed-seed hasher: the grounding's lookups are a third of its
/// time under the standard SipHash.
type HashMap<K, V> = std::collections::HashMap<K, V, foldhash::fast::FixedState>;

/// A grounded task with the maps back to the lifted domain.
#[derive(Debug, Clone)]
pub struct Grounded {
    /// The SAS+ task.
    pub task: Task,
    /// The resolved problem.
    pub instance: Instance,
}

/// A partial assignment, variable → value, kept sorted by variable: an operator touches a
/// handful of variables, where a B-tree's nodes cost more than a binary search (a fifth of the
/// grounding's time went to them).
#[derive(Debug, Clone, Default)]
struct Assignment(Vec<(usize, u32)>);

impl Assignment {
    /// Set `v` to `x`; the value it had, if any (as `BTreeMap::insert`).
    fn insert(&mut self, v: usize, x: u32) -> Option<u32> {
        match self.0.binary_search_by_key(&v, |p| p.0) {
            Ok(i) => Some(std::mem::replace(&mut self.0[i].1, x)),
            Err(i) => {
                self.0.insert(i, (v, x));
                None
            }
        }
    }

    /// The value of `v`, if set.
    fn get(&self, v: &usize) -> Option<&u32> {
        self.0
            .binary_search_by_key(v, |p| p.0)
            .ok()
            .map(|i| &self.0[i].1)
    }
}

/// A ground operator before its cost, probability and names are known.
struct Skeleton {
    /// Index of its (operator schema, binding) in the grounding's list.
    binding: u32,
    pre: Vec<(u32, u32)>,
    eff: Vec<(u32, u32)>,
}

struct VarTable {
    /// per schema: args → ground variable id (before pruning); looked up by slice, so a
    /// lookup needs no key of its own.
    ids: Vec<HashMap<Vec<usize>, usize>>,
    /// virtual object → its `exists` variable id.
    exists: HashMap<usize, usize>,
    /// per ground variable: value names.
    values: Vec<std::rc::Rc<[String]>>,
    names: Vec<String>,
    init: Vec<u32>,
    /// per schema: value name → index.
    value_index: Vec<HashMap<String, u32>>,
    /// per ground variable: schema (usize::MAX for exists).
    schema: Vec<usize>,
}

/// Assumption chains (domain flag `assumption_chains`, crate docs): a variable
/// `(assumption-chain)` holds which set of variables the last assumption wrote (`none` before
/// the first and once acting starts), and each assumption is copied once per such set it reads,
/// with that value as a precondition, plus once for `none`. The state then tells exactly which
/// assumptions may follow, so duplicate detection stays exact; an assumption nothing reads can
/// only end the chain, so a plan carries at most one, not every subset of them.
///
/// Only copies that can apply are made, which on a 30-room floor removes about half of the
/// assumptive operators (and the heuristic's work on them):
/// * the `none` copy only when the operator's preconditions hold initially: with assumptions
///   first, `(assumption-chain) = none` while assuming means no assumption was made yet, so the
///   state is the initial one;
/// * the copy after write set k only when some assumption writing k sets every shared variable
///   to the value the operator needs (else the operator cannot follow it), and shares a variable
///   other than the pool order's `exists(previous) = yes` (`pool_pred`: a new object's `exists`
///   variable → its pool predecessor's, and the predecessor's name), unless the operator also
///   takes the predecessor as an argument. That precondition only breaks the pool's symmetry: a
///   plan whose assumption is linked to the one before by it alone is no better than the same
///   plan without the earlier assumption (read by nothing else) and with the object renamed to
///   the earlier one, so the best plan survives.
fn chain_assumptions(
    ops: Vec<Operator>,
    vt: &mut VarTable,
    pool_pred: &HashMap<u32, (u32, &str)>,
) -> Vec<Operator> {
    let phase = (vt.values.len() - 1) as u32;
    let chain = vt.values.len() as u32;
    let writes = |o: &Operator| -> Vec<u32> {
        o.eff
            .iter()
            .map(|&(v, _)| v)
            .filter(|&v| v != phase)
            .collect()
    };
    // Value 0 is `none`; value k ≥ 1 the k-th distinct write set.
    let mut sets: BTreeMap<Vec<u32>, u32> = BTreeMap::new();
    for o in ops.iter().filter(|o| o.assumption) {
        let n = sets.len() as u32 + 1;
        sets.entry(writes(o)).or_insert(n);
    }
    let mut by_id: Vec<Vec<u32>> = vec![Vec::new(); sets.len() + 1];
    for (w, &k) in &sets {
        by_id[k as usize] = w.clone();
    }
    let mut sets_writing: HashMap<u32, Vec<usize>> = HashMap::default();
    for (k, w) in by_id.iter().enumerate().skip(1) {
        for &v in w {
            sets_writing.entry(v).or_default().push(k);
        }
    }
    // Per assumption: its own set, whether it may start a chain, the sets it may follow.
    struct Links {
        own: usize,
        first: bool,
        linked: Vec<usize>,
    }
    let links: Vec<Option<Links>> = ops
        .iter()
        .map(|o| {
            o.assumption.then(|| {
                // The pool order's precondition links to nothing (see above).
                let order = o
                    .eff
                    .iter()
                    .filter(|&&(_, x)| x == 1)
                    .find_map(|(v, _)| pool_pred.get(v))
                    .filter(|(_, name)| !o.args.iter().any(|a| a == name))
                    .map(|&(v, _)| v);
                let mut linked: Vec<usize> = o
                    .pre
                    .iter()
                    .filter(|&&(v, _)| Some(v) != order)
                    .filter_map(|(v, _)| sets_writing.get(v))
                    .flatten()
                    .copied()
                    .collect();
                linked.sort_unstable();
                linked.dedup();
                Links {
                    own: sets[&writes(o)] as usize,
                    first: o.pre.iter().all(|&(v, x)| vt.init[v as usize] == x),
                    linked,
                }
            })
        })
        .collect();
    // Which copies can apply, to a fixpoint: a copy after set k needs a writer of k that agrees
    // with it, and that writer needs a copy that can apply itself.
    let mut after: Vec<Vec<u32>> = vec![Vec::new(); ops.len()];
    let mut alive: Vec<bool> = links.iter().map(Option::is_some).collect();
    let mut writers: Vec<Vec<usize>> = vec![Vec::new(); by_id.len()];
    for (i, l) in links.iter().enumerate() {
        if let Some(l) = l {
            writers[l.own].push(i);
        }
    }
    loop {
        // Per (set, variables a reader shares with it): the values the set's live writers give
        // those variables. A set such as "an object of some class somewhere" has hundreds of
        // writers, so readers look their values up instead of comparing with each writer.
        let mut written: HashMap<(usize, Vec<u32>), std::collections::HashSet<Vec<u32>>> =
            HashMap::default();
        let mut changed = false;
        for (i, l) in links.iter().enumerate() {
            let Some(l) = l.as_ref().filter(|_| alive[i]) else {
                continue;
            };
            let o = &ops[i];
            after[i] = l.first.then_some(0).into_iter().collect();
            for &k in &l.linked {
                let (vars, want): (Vec<u32>, Vec<u32>) = o
                    .pre
                    .iter()
                    .filter(|(v, _)| by_id[k].contains(v))
                    .copied()
                    .unzip();
                let values = written.entry((k, vars)).or_insert_with_key(|(_, vars)| {
                    writers[k]
                        .iter()
                        .filter(|&&w| alive[w])
                        .map(|&w| {
                            let eff = &ops[w].eff;
                            vars.iter()
                                .map(|v| eff.iter().find(|e| e.0 == *v).map_or(u32::MAX, |e| e.1))
                                .collect()
                        })
                        .collect()
                });
                if values.contains(&want) {
                    after[i].push(k as u32);
                }
            }
            if after[i].is_empty() {
                alive[i] = false;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    let mut values = vec!["none".to_string()];
    values.extend(by_id.iter().skip(1).map(|w| {
        let names: Vec<&str> = w.iter().map(|&v| vt.names[v as usize].as_str()).collect();
        format!("wrote {}", names.join(", "))
    }));
    vt.names.push("(assumption-chain)".into());
    vt.values.push(values.into());
    vt.init.push(0);
    vt.schema.push(usize::MAX);
    let mut out = Vec::with_capacity(ops.len());
    for (mut o, (l, after)) in ops.into_iter().zip(links.iter().zip(&after)) {
        let Some(l) = l else {
            o.eff.push((chain, 0));
            o.eff.sort_unstable();
            out.push(o);
            continue;
        };
        o.eff.push((chain, l.own as u32));
        o.eff.sort_unstable();
        for &k in after {
            let mut copy = o.clone();
            copy.pre.push((chain, k));
            copy.pre.sort_unstable();
            out.push(copy);
        }
    }
    out
}

/// Per ground variable (of `n`): whether some operator of `ops` writes it.
fn written_vars(ops: &[Operator], n: usize) -> Vec<bool> {
    let mut written = vec![false; n];
    for o in ops {
        for &(v, _) in &o.eff {
            written[v as usize] = true;
        }
    }
    written
}

fn cartesian(lists: &[Vec<usize>]) -> Vec<Vec<usize>> {
    let mut out = vec![Vec::new()];
    for l in lists {
        let mut next = Vec::with_capacity(out.len() * l.len());
        for prefix in &out {
            for &x in l {
                let mut p = prefix.clone();
                p.push(x);
                next.push(p);
            }
        }
        out = next;
    }
    out
}

fn eval(
    q: &Quantity,
    inst: &Instance,
    binding: &[usize],
    f: &dyn Functions,
    what: &str,
    op: &dyn Fn() -> String,
) -> Result<f64, PlanError> {
    match q {
        Quantity::Const(v) => Ok(*v),
        Quantity::Func { name, args } => {
            let a: Vec<&str> = args.iter().map(|t| inst.name(t, binding)).collect();
            // Names for the messages only: built when there is an error to report (grounding
            // evaluates thousands of calls per plan).
            let call = || format!("{name}({})", a.join(", "));
            let v = f.value(name, &a).ok_or_else(|| PlanError::Function {
                call: call(),
                message: format!(
                    "not supplied by the caller (needed for the {what} of `{}`)",
                    op()
                ),
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
                    call: call(),
                    message: format!(
                        "{what} {v} for `{}`; expected {}",
                        op(),
                        if what == "probability" {
                            "a number in [0, 1]"
                        } else {
                            "a finite number ≥ 0"
                        }
                    ),
                })
            }
        }
    }
}

/// Ground `d` with problem `inst`, evaluating costs and probabilities with `f`, within the
/// default [`GroundingLimits`].
pub fn ground(d: &Domain, inst: Instance, f: &dyn Functions) -> Result<Grounded, PlanError> {
    ground_with(d, inst, f, &GroundingLimits::default())
}

/// [`ground`] within `limits`: passing one is [`PlanError::GroundingLimit`], naming the
/// operator or state variable being grounded.
pub fn ground_with(
    d: &Domain,
    inst: Instance,
    f: &dyn Functions,
    limits: &GroundingLimits,
) -> Result<Grounded, PlanError> {
    let mut budget = Budget::new(limits);
    let objs = &inst.objects;
    // Ground variables.
    let mut vt = VarTable {
        ids: vec![HashMap::default(); d.variables.len()],
        exists: HashMap::default(),
        values: Vec::new(),
        names: Vec::new(),
        init: Vec::new(),
        value_index: Vec::new(),
        schema: Vec::new(),
    };
    for (vi, v) in d.variables.iter().enumerate() {
        let values: std::rc::Rc<[String]> = inst.values_of(d, vi).into();
        vt.value_index.push(
            values
                .iter()
                .enumerate()
                .map(|(i, s)| (s.clone(), i as u32))
                .collect(),
        );
        let lists: Vec<Vec<usize>> = v
            .params
            .iter()
            .map(|&t| objs.of_type(t).collect())
            .collect();
        // Counted before `cartesian` builds them: a variable's ground instances are the
        // product of its parameters' object counts. Each keeps its own list of value names.
        let what = || format!("variable `{}`", v.name);
        let product = lists.iter().try_fold(1usize, |n, l| n.checked_mul(l.len()));
        budget.facts_ahead(what, product.and_then(|p| p.checked_add(vt.values.len())))?;
        for args in cartesian(&lists) {
            budget.fact(what, vt.values.len() + 1, args.len() + values.len())?;
            let gv = (vi, args);
            let init = inst.initial(d, &gv)?;
            let ii = *vt.value_index[vi].get(&init).ok_or_else(|| {
                PlanError::Problem(format!(
                    "initial value `{init}` of {} is not in its domain",
                    inst.var_name(d, &gv)
                ))
            })?;
            vt.ids[vi].insert(gv.1.clone(), vt.values.len());
            vt.names.push(inst.var_name(d, &gv));
            vt.values.push(values.clone());
            vt.init.push(ii);
            vt.schema.push(vi);
        }
    }
    for (o, &is_virtual) in objs.virtual_.iter().enumerate() {
        if is_virtual {
            vt.exists.insert(o, vt.values.len());
            vt.names.push(format!("exists({})", objs.names[o]));
            vt.values.push(["no".to_string(), "yes".to_string()].into());
            vt.init.push(0);
            vt.schema.push(usize::MAX);
        }
    }
    // Previous virtual object in the same pool.
    let mut prev_virtual: HashMap<usize, usize> = HashMap::default();
    for pool in &d.pools {
        for w in pool.names.windows(2) {
            prev_virtual.insert(objs.index[&w[1]], objs.index[&w[0]]);
        }
    }
    let mut reached: Vec<Vec<bool>> = vt.values.iter().map(|v| vec![false; v.len()]).collect();
    for (v, &x) in vt.init.iter().enumerate() {
        reached[v][x as usize] = true;
    }
    // Condition depth per operator.
    let depth_of = |c: &Cond| -> usize {
        let terms: Vec<&crate::domain::Term> = match c {
            Cond::Var { args, value, .. } => args.iter().chain(std::iter::once(value)).collect(),
            Cond::Rel { args, .. } => args.iter().collect(),
            Cond::Eq { a, b, .. } => vec![a, b],
        };
        terms
            .iter()
            .filter_map(|t| match t {
                crate::domain::Term::Param(i) => Some(i + 1),
                _ => None,
            })
            .max()
            .unwrap_or(0)
    };
    // Candidates per operator parameter: the objects of its type (virtual ones for `new`).
    let cands_of = |op: &crate::domain::OpSchema| -> Vec<Vec<usize>> {
        op.params
            .iter()
            .map(|p| {
                objs.of_type(p.ty)
                    .filter(|&o| !p.new || objs.virtual_[o])
                    .collect()
            })
            .collect()
    };
    // The ground variables some effect of some operator may write (over every binding of its
    // parameters, reachable or not). Any other variable keeps its initial value, so a
    // condition on it is decided while enumerating, exactly as reachability would decide it
    // later: operators that need another value of a fixed variable (an object's class once
    // seen, where a found landmark lies) are never built.
    let mut writable = vec![false; vt.values.len()];
    for op in &d.operators {
        let cands = cands_of(op);
        for e in &op.eff {
            let lists: Option<Vec<Vec<usize>>> = e
                .args
                .iter()
                .map(|t| match t {
                    crate::domain::Term::Param(i) => Some(cands[*i].clone()),
                    crate::domain::Term::Name(n) => objs.index.get(n).map(|&o| vec![o]),
                })
                .collect();
            let Some(lists) = lists else { continue };
            for args in cartesian(&lists) {
                if let Some(&v) = vt.ids[e.var].get(args.as_slice()) {
                    writable[v] = true;
                }
            }
        }
    }
    // Instantiate every operator whose static conditions hold (conditions on writable
    // variables only need a value of the variable's domain); reachability is decided below on
    // the ground operators.
    let mut found: Vec<(usize, Vec<usize>)> = Vec::new();
    for (oi, op) in d.operators.iter().enumerate() {
        let mut at: Vec<Vec<&Cond>> = vec![Vec::new(); op.params.len() + 1];
        for c in &op.pre {
            at[depth_of(c)].push(c);
        }
        let cands = cands_of(op);
        let mut bindings = Vec::new();
        let mut b = Vec::new();
        let mut ctx = Enum {
            inst: &inst,
            vt: &vt,
            writable: &writable,
            scratch: Vec::new(),
            budget: &mut budget,
            found_before: found.len(),
        };
        ctx.enumerate(op, &at, &cands, &mut b, &mut bindings)?;
        found.extend(bindings.into_iter().map(|b| (oi, b)));
    }
    // Build operators: conditions and effects only (their costs, probabilities and names
    // wait for reachability).
    let mut skels: Vec<Skeleton> = Vec::new();
    let mut bindings: Vec<(usize, Vec<usize>)> = Vec::new();
    let mut scratch: Vec<usize> = Vec::new();
    for (oi, b) in found {
        let op = &d.operators[oi];
        let mut pre = Assignment::default();
        let mut excluded: Vec<(usize, u32)> = Vec::new();
        let mut ok = true;
        for c in &op.pre {
            if let Cond::Var {
                var,
                args,
                value,
                negated,
            } = c
            {
                if !inst.obj_args_into(args, &b, &mut scratch) {
                    ok = false;
                    break;
                }
                let v = vt.ids[*var][scratch.as_slice()];
                let Some(&x) = vt.value_index[*var].get(inst.name(value, &b)) else {
                    ok = *negated;
                    if !ok {
                        break;
                    }
                    continue;
                };
                if *negated {
                    excluded.push((v, x));
                } else if pre.insert(v, x).is_some_and(|old| old != x) {
                    ok = false;
                }
            }
        }
        for (pi, p) in op.params.iter().enumerate() {
            if let Some(&v) = vt.exists.get(&b[pi]) {
                let want = if p.new { 0 } else { 1 };
                if pre.insert(v, want).is_some_and(|old| old != want) {
                    ok = false;
                }
                if p.new {
                    if let Some(prev) = prev_virtual.get(&b[pi]) {
                        pre.insert(vt.exists[prev], 1);
                    }
                }
            }
        }
        if !ok {
            continue;
        }
        let mut eff = Assignment::default();
        for e in &op.eff {
            if !inst.obj_args_into(&e.args, &b, &mut scratch) {
                continue;
            }
            let v = vt.ids[e.var][scratch.as_slice()];
            if let Some(&x) = vt.value_index[e.var].get(inst.name(&e.value, &b)) {
                eff.insert(v, x);
            }
        }
        for (pi, p) in op.params.iter().enumerate() {
            if p.new {
                eff.insert(vt.exists[&b[pi]], 1);
            }
        }
        // Expand `!=` conditions into one operator per remaining reachable value.
        let what = || format!("operator `{}`", op.name);
        let mut variants: Vec<Assignment> = vec![pre];
        for &(v, x) in &excluded {
            let mut next = Vec::new();
            for p in variants {
                match p.get(&v) {
                    Some(&y) if y == x => {}
                    Some(_) => next.push(p),
                    None => {
                        for y in 0..vt.values[v].len() as u32 {
                            if y != x {
                                let mut q = p.clone();
                                q.insert(v, y);
                                next.push(q);
                            }
                        }
                    }
                }
                budget.found(what, skels.len() + next.len(), b.len())?;
            }
            variants = next;
        }
        let eff: Vec<(u32, u32)> = eff.0.iter().map(|&(v, x)| (v as u32, x)).collect();
        for p in variants {
            budget.operator(what, skels.len() + 1, b.len())?;
            skels.push(Skeleton {
                binding: bindings.len() as u32,
                pre: p.0.into_iter().map(|(v, x)| (v as u32, x)).collect(),
                eff: eff.clone(),
            });
        }
        bindings.push((oi, b));
    }
    // Relaxed reachability on the ground operators: keep those whose preconditions can all
    // be reached from the initial state when nothing is ever deleted. A binding's cost and
    // probability are evaluated when one of its operators is first reached (most never are),
    // and an operator of probability 0 never applies.
    let mut values: Vec<Option<(f64, f64)>> = vec![None; bindings.len()];
    let mut live = vec![false; skels.len()];
    let mut dead = vec![false; skels.len()];
    loop {
        let mut changed = false;
        for (k, o) in skels.iter().enumerate() {
            if live[k] || dead[k] || !o.pre.iter().all(|&(v, x)| reached[v as usize][x as usize]) {
                continue;
            }
            let bi = o.binding as usize;
            let (cost, prob) = match values[bi] {
                Some(cp) => cp,
                None => {
                    let (oi, b) = &bindings[bi];
                    let op = &d.operators[*oi];
                    let key = || format!("{} {:?}", op.name, b);
                    let cp = (
                        eval(&op.cost, &inst, b, f, "cost", &key)?,
                        eval(&op.prob, &inst, b, f, "probability", &key)?,
                    );
                    values[bi] = Some(cp);
                    cp
                }
            };
            let cost_ok = cost.is_finite() && cost >= 0.0;
            if !(cost_ok && (0.0..=1.0).contains(&prob)) {
                let (oi, b) = &bindings[bi];
                let op = &d.operators[*oi];
                let args: Vec<String> = b.iter().map(|&o| objs.names[o].clone()).collect();
                let message = if !cost_ok {
                    format!("cost {cost}; expected a finite number ≥ 0")
                } else {
                    format!("probability {prob}; expected a number in [0, 1]")
                };
                return Err(PlanError::Function {
                    call: op.display_with(&args),
                    message,
                });
            }
            if prob == 0.0 {
                dead[k] = true;
                continue;
            }
            live[k] = true;
            changed = true;
            for &(v, x) in &o.eff {
                reached[v as usize][x as usize] = true;
            }
        }
        if !changed {
            break;
        }
    }
    // The reachable operators, in the order they were built, with their names.
    let mut ops = Vec::with_capacity(live.iter().filter(|&&l| l).count());
    let mut named: Option<(u32, Vec<String>, String)> = None;
    for (k, sk) in skels.into_iter().enumerate() {
        if !live[k] {
            continue;
        }
        let (oi, b) = &bindings[sk.binding as usize];
        let op = &d.operators[*oi];
        if named.as_ref().is_none_or(|n| n.0 != sk.binding) {
            let args: Vec<String> = b.iter().map(|&o| objs.names[o].clone()).collect();
            let display = op.display_with(&args);
            named = Some((sk.binding, args, display));
        }
        let Some((_, args, display)) = &named else {
            unreachable!("named just above")
        };
        let Some((cost, prob)) = values[sk.binding as usize] else {
            unreachable!("a live operator's binding was evaluated")
        };
        ops.push(Operator {
            schema: op.name.clone(),
            args: args.clone(),
            display: display.clone(),
            pre: sk.pre,
            eff: sk.eff,
            cost,
            prob,
            assumption: op.assumption,
        });
    }

    // Operators reading a value no operator writes, other than the initial one, never apply;
    // dropped before the chains so that no copy waits for an assumption that cannot be made.
    let written = written_vars(&ops, vt.values.len());
    ops.retain(|o| {
        o.pre
            .iter()
            .all(|&(v, x)| written[v as usize] || vt.init[v as usize] == x)
    });
    // The assumption chain's variable, a search-control variable (`Variable::control`).
    let mut control = None;
    // Assumptions first: a phase variable (assuming → acting) orders them.
    if d.assumptions_first {
        let v = vt.values.len();
        vt.names.push("(phase)".into());
        vt.values
            .push(["assuming".to_string(), "acting".to_string()].into());
        vt.init.push(0);
        vt.schema.push(usize::MAX);
        for o in &mut ops {
            if o.assumption {
                o.pre.push((v as u32, 0));
                o.pre.sort_unstable();
            } else {
                o.eff.push((v as u32, 1));
                o.eff.sort_unstable();
            }
        }
        if d.assumption_chains {
            control = Some(vt.values.len());
            let pool_pred = prev_virtual
                .iter()
                .map(|(o, prev)| {
                    let pred = (vt.exists[prev] as u32, objs.names[*prev].as_str());
                    (vt.exists[o] as u32, pred)
                })
                .collect();
            ops = chain_assumptions(ops, &mut vt, &pool_pred);
        }
    }
    // Goal.
    let mut goal: BTreeMap<usize, u32> = BTreeMap::new();
    let mut impossible = false;
    for (gv, val) in &inst.goal {
        let v = vt.ids[gv.0][&gv.1];
        let x = vt.value_index[gv.0][val];
        if goal.insert(v, x).is_some_and(|o| o != x) {
            impossible = true;
        }
    }
    // Remove variables no operator changes.
    let changed = written_vars(&ops, vt.values.len());
    let mut new_id = vec![u32::MAX; vt.values.len()];
    let mut task = Task::default();
    for v in 0..vt.values.len() {
        if changed[v] {
            new_id[v] = task.variables.len() as u32;
            task.variables.push(Variable {
                control: control == Some(v),
                ..Variable::new(vt.names[v].clone(), vt.values[v].to_vec())
            });
            task.init.push(vt.init[v]);
        }
    }
    for o in ops {
        if o.pre
            .iter()
            .any(|&(v, x)| !changed[v as usize] && vt.init[v as usize] != x)
        {
            continue;
        }
        let pre = o
            .pre
            .iter()
            .filter(|&&(v, _)| changed[v as usize])
            .map(|&(v, x)| (new_id[v as usize], x))
            .collect();
        let eff = o
            .eff
            .iter()
            .map(|&(v, x)| (new_id[v as usize], x))
            .collect();
        task.operators.push(Operator { pre, eff, ..o });
    }
    for (&v, &x) in &goal {
        if changed[v] {
            task.goal.push((new_id[v], x));
        } else if vt.init[v] != x {
            impossible = true;
        }
    }
    if impossible {
        task.variables.push(Variable::new(
            "(goal-unreachable)",
            vec!["no".into(), "yes".into()],
        ));
        task.init.push(0);
        task.goal = vec![(task.variables.len() as u32 - 1, 1)];
    }
    tracing::debug!(%task, "grounded domain `{}`", d.name);
    Ok(Grounded {
        task,
        instance: inst,
    })
}

struct Enum<'a> {
    inst: &'a Instance,
    vt: &'a VarTable,
    /// Per ground variable: whether some effect may write it.
    writable: &'a [bool],
    scratch: Vec<usize>,
    budget: &'a mut Budget,
    /// Bindings of earlier operators already found.
    found_before: usize,
}

impl Enum<'_> {
    fn holds(&mut self, c: &Cond, b: &[usize]) -> bool {
        match c {
            Cond::Rel { rel, args, negated } => {
                if self.inst.obj_args_into(args, b, &mut self.scratch) {
                    self.inst.facts.contains(*rel, &self.scratch) != *negated
                } else {
                    *negated
                }
            }
            Cond::Eq { a, b: y, negated } => {
                (self.inst.name(a, b) == self.inst.name(y, b)) != *negated
            }
            Cond::Var {
                var,
                args,
                value,
                negated,
            } => {
                let Some(&x) = self.vt.value_index[*var].get(self.inst.name(value, b)) else {
                    return *negated;
                };
                // A variable no effect writes keeps its initial value; any other condition is
                // decided by reachability later.
                if self.inst.obj_args_into(args, b, &mut self.scratch) {
                    if let Some(&v) = self.vt.ids[*var].get(self.scratch.as_slice()) {
                        if !self.writable[v] {
                            return (self.vt.init[v] == x) != *negated;
                        }
                    }
                }
                true
            }
        }
    }

    /// Extend `b` by every candidate whose bound conditions hold, collecting complete bindings
    /// in `out`; every binding tried and every one found counts against the budget.
    fn enumerate(
        &mut self,
        op: &crate::domain::OpSchema,
        at: &[Vec<&Cond>],
        cands: &[Vec<usize>],
        b: &mut Vec<usize>,
        out: &mut Vec<Vec<usize>>,
    ) -> Result<(), PlanError> {
        let what = || format!("operator `{}`", op.name);
        self.budget.tried(what)?;
        let depth = b.len();
        if depth > 0 {
            let o = b[depth - 1];
            if op.params[depth - 1].new && b[..depth - 1].contains(&o) {
                return Ok(());
            }
        }
        for c in &at[depth] {
            if !self.holds(c, b) {
                return Ok(());
            }
        }
        if depth == op.params.len() {
            out.push(b.clone());
            return self
                .budget
                .found(what, self.found_before + out.len(), b.len());
        }
        for &o in &cands[depth] {
            b.push(o);
            self.enumerate(op, at, cands, b, out)?;
            b.pop();
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::Assignment;

    #[test]
    fn an_assignment_keeps_one_value_per_variable_in_variable_order() {
        let mut a = Assignment::default();
        assert_eq!(a.insert(7, 1), None);
        assert_eq!(a.insert(2, 0), None);
        assert_eq!(a.insert(7, 3), Some(1), "the old value comes back");
        assert_eq!(a.get(&7), Some(&3));
        assert_eq!(a.get(&5), None);
        assert_eq!(a.0, vec![(2, 0), (7, 3)]);
    }
}
