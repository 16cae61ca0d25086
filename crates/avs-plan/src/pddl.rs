//! PDDL import: STRIPS with typing, negative preconditions, equality and action costs
//! (`:action-costs`, `(increase (total-cost) …)`), grounded by relaxed reachability into the
//! same SAS+ [`Task`] as the YAML domains (one binary variable per reachable fluent atom), and an
//! independent plan validator that simulates a plan on the *lifted* task with PDDL semantics
//! (deletes before adds) without any of the grounding or search code.
//!
//! Grounding stays within [`GroundingLimits`] (see [`crate::limits`]): an action whose
//! groundings pass them ends the grounding with [`PlanError::GroundingLimit`] naming it.

use crate::limits::{Budget, GroundingLimits};
use crate::task::{Operator, Task, Variable};
use crate::PlanError;
use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};

/// An s-expression.
#[derive(Debug, Clone, PartialEq)]
enum Sx {
    Atom(String),
    List(Vec<Sx>),
}

fn err(file: &str, message: impl Into<String>) -> PlanError {
    PlanError::Pddl {
        file: file.to_string(),
        message: message.into(),
    }
}

fn parse_sx(file: &str, text: &str) -> Result<Sx, PlanError> {
    let mut stack: Vec<Vec<Sx>> = vec![Vec::new()];
    // The line each open list started on, for an unbalanced `(`.
    let mut opened: Vec<usize> = Vec::new();
    let mut chars = text.char_indices().peekable();
    let mut line = 1;
    while let Some((i, c)) = chars.next() {
        match c {
            '\n' => line += 1,
            ';' => {
                while let Some(&(_, d)) = chars.peek() {
                    if d == '\n' {
                        break;
                    }
                    chars.next();
                }
            }
            '(' => {
                if stack.len() > 200 {
                    return Err(err(file, format!("line {line}: nesting deeper than 200")));
                }
                stack.push(Vec::new());
                opened.push(line);
            }
            ')' => {
                opened.pop();
                let done = stack.pop().unwrap_or_default();
                match stack.last_mut() {
                    Some(top) => top.push(Sx::List(done)),
                    None => return Err(err(file, format!("line {line}: unbalanced `)`"))),
                }
            }
            c if c.is_whitespace() => {}
            _ => {
                let mut end = i + c.len_utf8();
                while let Some(&(j, d)) = chars.peek() {
                    if d.is_whitespace() || d == '(' || d == ')' || d == ';' {
                        break;
                    }
                    end = j + d.len_utf8();
                    chars.next();
                }
                stack
                    .last_mut()
                    .expect("stack never empty here")
                    .push(Sx::Atom(text[i..end].to_lowercase()));
            }
        }
    }
    if let Some(open) = opened.last() {
        return Err(err(
            file,
            format!("line {open}: unbalanced `(`: the list opened here is never closed"),
        ));
    }
    let mut top = stack.pop().unwrap_or_default();
    match top.len() {
        1 => Ok(top.remove(0)),
        0 => Err(err(file, "empty file; expected `(define …)`")),
        _ => Err(err(file, "more than one top-level expression")),
    }
}

/// A term: a parameter (`?x`) or an object name.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Term {
    /// `?x`, by index into the action's parameters.
    Param(usize),
    /// An object or constant.
    Object(String),
}

/// A precondition or goal formula (conjunctions of literals).
#[derive(Debug, Clone, PartialEq)]
pub enum Literal {
    /// `(p t…)` or `(not (p t…))`.
    Atom {
        /// Predicate.
        pred: String,
        /// Arguments.
        args: Vec<Term>,
        /// Negated.
        negated: bool,
    },
    /// `(= a b)` or `(not (= a b))`.
    Equal {
        /// Left.
        a: Term,
        /// Right.
        b: Term,
        /// Negated.
        negated: bool,
    },
}

/// A cost expression.
#[derive(Debug, Clone, PartialEq)]
pub enum CostExpr {
    /// A number.
    Number(f64),
    /// A numeric fluent `(f t…)` from the initial state.
    Fluent(String, Vec<Term>),
}

/// An action schema.
#[derive(Debug, Clone, PartialEq)]
pub struct Action {
    /// Name.
    pub name: String,
    /// Parameters: (name, type).
    pub params: Vec<(String, String)>,
    /// Precondition literals.
    pub pre: Vec<Literal>,
    /// Add effects (predicate, args).
    pub add: Vec<(String, Vec<Term>)>,
    /// Delete effects.
    pub del: Vec<(String, Vec<Term>)>,
    /// `increase (total-cost)` terms.
    pub cost: Vec<CostExpr>,
}

/// A parsed PDDL domain.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Domain {
    /// Name.
    pub name: String,
    /// type → parent type.
    pub types: BTreeMap<String, String>,
    /// Constants: name → type.
    pub constants: Vec<(String, String)>,
    /// Predicates and arities.
    pub predicates: BTreeMap<String, usize>,
    /// Actions.
    pub actions: Vec<Action>,
    /// Whether `:action-costs` is required.
    pub action_costs: bool,
}

/// A parsed PDDL problem.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Problem {
    /// Name.
    pub name: String,
    /// Objects: name → type.
    pub objects: Vec<(String, String)>,
    /// Initial atoms.
    pub init: Vec<(String, Vec<String>)>,
    /// Initial numeric fluent values.
    pub numeric: HashMap<(String, Vec<String>), f64>,
    /// Goal literals (no parameters).
    pub goal: Vec<Literal>,
    /// Whether the metric is `(minimize (total-cost))`.
    pub metric_total_cost: bool,
}

fn atom(s: &Sx) -> Option<&str> {
    match s {
        Sx::Atom(a) => Some(a),
        _ => None,
    }
}

fn list<'a>(file: &str, s: &'a Sx, what: &str) -> Result<&'a [Sx], PlanError> {
    match s {
        Sx::List(l) => Ok(l),
        Sx::Atom(a) => Err(err(file, format!("{what}: found `{a}`; expected a list"))),
    }
}

/// `a b - t c - u d` → [(a,t),(b,t),(c,u),(d,object)]
fn typed_list(file: &str, items: &[Sx], what: &str) -> Result<Vec<(String, String)>, PlanError> {
    let mut out = Vec::new();
    let mut pending = Vec::new();
    let mut i = 0;
    while i < items.len() {
        let a = atom(&items[i]).ok_or_else(|| {
            err(
                file,
                format!("{what}: found a list; expected names and `- type`"),
            )
        })?;
        if a == "-" {
            let t = items.get(i + 1).and_then(atom).ok_or_else(|| {
                err(
                    file,
                    format!(
                        "{what}: `-` must be followed by a type name (`either` is not supported)"
                    ),
                )
            })?;
            for p in pending.drain(..) {
                out.push((p, t.to_string()));
            }
            i += 2;
        } else {
            pending.push(a.to_string());
            i += 1;
        }
    }
    for p in pending {
        out.push((p, "object".to_string()));
    }
    Ok(out)
}

fn term(file: &str, s: &Sx, params: &[(String, String)]) -> Result<Term, PlanError> {
    let a = atom(s).ok_or_else(|| err(file, "found a list where a term was expected"))?;
    if a.starts_with('?') {
        params
            .iter()
            .position(|(n, _)| n == a)
            .map(Term::Param)
            .ok_or_else(|| err(file, format!("unknown parameter `{a}`")))
    } else {
        Ok(Term::Object(a.to_string()))
    }
}

fn literals(
    file: &str,
    s: &Sx,
    params: &[(String, String)],
    out: &mut Vec<Literal>,
) -> Result<(), PlanError> {
    let l = list(file, s, "formula")?;
    if l.is_empty() {
        return Ok(());
    }
    let head = atom(&l[0]).ok_or_else(|| err(file, "formula starts with a list"))?;
    match head {
        "and" => {
            for x in &l[1..] {
                literals(file, x, params, out)?;
            }
        }
        "not" => {
            if l.len() != 2 {
                return Err(err(file, "`not` takes exactly one formula"));
            }
            let mut inner = Vec::new();
            literals(file, &l[1], params, &mut inner)?;
            match inner.as_slice() {
                [Literal::Atom {
                    pred,
                    args,
                    negated: false,
                }] => out.push(Literal::Atom {
                    pred: pred.clone(),
                    args: args.clone(),
                    negated: true,
                }),
                [Literal::Equal {
                    a,
                    b,
                    negated: false,
                }] => out.push(Literal::Equal {
                    a: a.clone(),
                    b: b.clone(),
                    negated: true,
                }),
                _ => {
                    return Err(err(
                        file,
                        "`not` over a compound formula is not supported; expected (not (p …))",
                    ))
                }
            }
        }
        "or" | "imply" | "forall" | "exists" | "when" => {
            return Err(err(
                file,
                format!("`{head}` is not supported; expected STRIPS conjunctions of literals"),
            ))
        }
        "=" => {
            if l.len() != 3 {
                return Err(err(file, "`=` takes two terms"));
            }
            out.push(Literal::Equal {
                a: term(file, &l[1], params)?,
                b: term(file, &l[2], params)?,
                negated: false,
            });
        }
        p => {
            let args = l[1..]
                .iter()
                .map(|x| term(file, x, params))
                .collect::<Result<Vec<_>, _>>()?;
            out.push(Literal::Atom {
                pred: p.to_string(),
                args,
                negated: false,
            });
        }
    }
    Ok(())
}

fn effects(
    file: &str,
    s: &Sx,
    params: &[(String, String)],
    a: &mut Action,
) -> Result<(), PlanError> {
    let l = list(file, s, "effect")?;
    if l.is_empty() {
        return Ok(());
    }
    let head = atom(&l[0]).ok_or_else(|| err(file, "effect starts with a list"))?;
    match head {
        "and" => {
            for x in &l[1..] {
                effects(file, x, params, a)?;
            }
        }
        "increase" => {
            let target = l.get(1).map(|x| list(file, x, "increase target"));
            let ok = matches!(target, Some(Ok([Sx::Atom(t)])) if t == "total-cost");
            if !ok || l.len() != 3 {
                return Err(err(
                    file,
                    "only `(increase (total-cost) N)` or `(increase (total-cost) (f …))` is supported",
                ));
            }
            let e = match &l[2] {
                Sx::Atom(n) => CostExpr::Number(
                    n.parse::<f64>()
                        .map_err(|_| err(file, format!("cost `{n}` is not a number")))?,
                ),
                Sx::List(f) => {
                    let name = f
                        .first()
                        .and_then(atom)
                        .ok_or_else(|| err(file, "cost function without a name"))?;
                    let args = f[1..]
                        .iter()
                        .map(|x| term(file, x, params))
                        .collect::<Result<Vec<_>, _>>()?;
                    CostExpr::Fluent(name.to_string(), args)
                }
            };
            a.cost.push(e);
        }
        _ => {
            let mut lits = Vec::new();
            literals(file, s, params, &mut lits)?;
            for lit in lits {
                match lit {
                    Literal::Atom {
                        pred,
                        args,
                        negated,
                    } => {
                        if negated {
                            a.del.push((pred, args))
                        } else {
                            a.add.push((pred, args))
                        }
                    }
                    Literal::Equal { .. } => {
                        return Err(err(file, "`=` cannot be an effect"));
                    }
                }
            }
        }
    }
    Ok(())
}

/// Parse a PDDL domain (`file` names it in errors).
pub fn parse_domain(file: &str, text: &str) -> Result<Domain, PlanError> {
    let sx = parse_sx(file, text)?;
    let top = list(file, &sx, "domain")?;
    if top.first().and_then(atom) != Some("define") {
        return Err(err(file, "expected `(define (domain NAME) …)`"));
    }
    let mut d = Domain::default();
    for sec in &top[1..] {
        let l = list(file, sec, "domain section")?;
        let head = l.first().and_then(atom).unwrap_or("");
        match head {
            "domain" => d.name = l.get(1).and_then(atom).unwrap_or("").to_string(),
            ":requirements" => {
                for r in &l[1..] {
                    let r = atom(r).unwrap_or("");
                    match r {
                        ":strips" | ":typing" | ":negative-preconditions" | ":equality" => {}
                        ":action-costs" => d.action_costs = true,
                        _ => {
                            return Err(err(
                                file,
                                format!("requirement `{r}` is not supported; expected :strips, :typing, :negative-preconditions, :equality or :action-costs"),
                            ))
                        }
                    }
                }
            }
            ":types" => {
                for (t, p) in typed_list(file, &l[1..], ":types")? {
                    d.types.insert(t, p);
                }
            }
            ":constants" => d.constants = typed_list(file, &l[1..], ":constants")?,
            ":predicates" => {
                for p in &l[1..] {
                    let pl = list(file, p, ":predicates entry")?;
                    let name = pl
                        .first()
                        .and_then(atom)
                        .ok_or_else(|| err(file, "predicate without a name"))?;
                    let args = typed_list(file, &pl[1..], "predicate parameters")?;
                    d.predicates.insert(name.to_string(), args.len());
                }
            }
            ":functions" => {}
            ":action" => {
                let name = l
                    .get(1)
                    .and_then(atom)
                    .ok_or_else(|| err(file, "action without a name"))?;
                let mut a = Action {
                    name: name.to_string(),
                    params: Vec::new(),
                    pre: Vec::new(),
                    add: Vec::new(),
                    del: Vec::new(),
                    cost: Vec::new(),
                };
                let mut i = 2;
                while i + 1 < l.len() {
                    let key = atom(&l[i]).unwrap_or("");
                    match key {
                        ":parameters" => {
                            a.params = typed_list(
                                file,
                                list(file, &l[i + 1], ":parameters")?,
                                ":parameters",
                            )?
                        }
                        ":precondition" => {
                            let ps = a.params.clone();
                            literals(file, &l[i + 1], &ps, &mut a.pre)?
                        }
                        ":effect" => {
                            let ps = a.params.clone();
                            effects(file, &l[i + 1], &ps, &mut a)?
                        }
                        k => {
                            return Err(err(
                                file,
                                format!("action `{name}`: unknown key `{k}`; expected :parameters, :precondition or :effect"),
                            ))
                        }
                    }
                    i += 2;
                }
                d.actions.push(a);
            }
            h => return Err(err(file, format!("domain section `{h}` is not supported"))),
        }
    }
    for a in &d.actions {
        let check = |p: &str, n: usize| -> Result<(), PlanError> {
            match d.predicates.get(p) {
                Some(&k) if k == n => Ok(()),
                Some(&k) => Err(err(
                    file,
                    format!(
                        "action `{}`: predicate `{p}` used with {n} arguments; declared with {k}",
                        a.name
                    ),
                )),
                None => Err(err(
                    file,
                    format!("action `{}`: unknown predicate `{p}`", a.name),
                )),
            }
        };
        for l in &a.pre {
            if let Literal::Atom { pred, args, .. } = l {
                check(pred, args.len())?;
            }
        }
        for (p, args) in a.add.iter().chain(&a.del) {
            check(p, args.len())?;
        }
    }
    Ok(d)
}

/// Parse a PDDL problem.
pub fn parse_problem(file: &str, text: &str) -> Result<Problem, PlanError> {
    let sx = parse_sx(file, text)?;
    let top = list(file, &sx, "problem")?;
    if top.first().and_then(atom) != Some("define") {
        return Err(err(file, "expected `(define (problem NAME) …)`"));
    }
    let mut p = Problem::default();
    for sec in &top[1..] {
        let l = list(file, sec, "problem section")?;
        let head = l.first().and_then(atom).unwrap_or("");
        match head {
            "problem" => p.name = l.get(1).and_then(atom).unwrap_or("").to_string(),
            ":domain" | ":requirements" => {}
            ":objects" => p.objects = typed_list(file, &l[1..], ":objects")?,
            ":init" => {
                for f in &l[1..] {
                    let fl = list(file, f, ":init entry")?;
                    if fl.first().and_then(atom) == Some("=") {
                        let lhs = fl.get(1).map(|x| list(file, x, "numeric fluent"));
                        let val = fl.get(2).and_then(atom).and_then(|v| v.parse::<f64>().ok());
                        match (lhs, val) {
                            (Some(Ok(names)), Some(v)) if !names.is_empty() => {
                                let names: Vec<String> = names
                                    .iter()
                                    .map(|x| atom(x).unwrap_or("").to_string())
                                    .collect();
                                p.numeric.insert((names[0].clone(), names[1..].to_vec()), v);
                            }
                            _ => return Err(err(file, ":init: expected `(= (f o…) NUMBER)`")),
                        }
                        continue;
                    }
                    let names: Option<Vec<String>> =
                        fl.iter().map(|x| atom(x).map(str::to_string)).collect();
                    let names = names
                        .filter(|n| !n.is_empty())
                        .ok_or_else(|| err(file, ":init: expected ground atoms `(p o…)`"))?;
                    p.init.push((names[0].clone(), names[1..].to_vec()));
                }
            }
            ":goal" => {
                let g = l.get(1).ok_or_else(|| err(file, ":goal is empty"))?;
                literals(file, g, &[], &mut p.goal)?;
            }
            ":metric" => {
                let ok = l.get(1).and_then(atom) == Some("minimize")
                    && matches!(l.get(2), Some(Sx::List(x)) if x.len() == 1 && atom(&x[0]) == Some("total-cost"));
                if !ok {
                    return Err(err(
                        file,
                        "only `(:metric minimize (total-cost))` is supported",
                    ));
                }
                p.metric_total_cost = true;
            }
            h => return Err(err(file, format!("problem section `{h}` is not supported"))),
        }
    }
    Ok(p)
}

/// Objects with all their types (including ancestors).
fn object_types(d: &Domain, p: &Problem) -> Result<HashMap<String, BTreeSet<String>>, String> {
    let mut out: HashMap<String, BTreeSet<String>> = HashMap::new();
    for (o, t) in d.constants.iter().chain(&p.objects) {
        let set = out.entry(o.clone()).or_default();
        let mut cur = t.clone();
        let mut guard = 0;
        loop {
            set.insert(cur.clone());
            if cur == "object" {
                break;
            }
            match d.types.get(&cur) {
                Some(parent) => cur = parent.clone(),
                None if d.types.is_empty() || cur == "object" => break,
                None => return Err(format!("object `{o}` has undeclared type `{cur}`")),
            }
            guard += 1;
            if guard > 100 {
                return Err(format!("type `{t}` has a cyclic parent chain"));
            }
        }
        set.insert("object".to_string());
    }
    Ok(out)
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
                    let args: Vec<String> = args
                        .iter()
                        .map(|t| resolve(t, &b, &objs).to_string())
                        .collect();
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
            let args: Vec<String> = args
                .iter()
                .map(|t| match t {
                    Term::Object(o) => o.clone(),
                    Term::Param(_) => String::new(),
                })
                .collect();
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
                let args: Vec<String> = args
                    .iter()
                    .map(|t| match t {
                        Term::Object(o) => o.clone(),
                        Term::Param(_) => String::new(),
                    })
                    .collect();
                let key = (pred.clone(), args);
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
                let key = (
                    pred.clone(),
                    args.iter()
                        .map(|t| resolve(t, &b, &objs).to_string())
                        .collect(),
                );
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
        let mut eff: BTreeMap<u32, u32> = BTreeMap::new();
        for (pred, args) in &a.del {
            let key = (
                pred.clone(),
                args.iter()
                    .map(|t| resolve(t, &b, &objs).to_string())
                    .collect(),
            );
            if let Some(&v) = var_of.get(&key) {
                eff.insert(v, 0);
            }
        }
        for (pred, args) in &a.add {
            let key = (
                pred.clone(),
                args.iter()
                    .map(|t| resolve(t, &b, &objs).to_string())
                    .collect(),
            );
            if let Some(&v) = var_of.get(&key) {
                eff.insert(v, 1);
            }
        }
        let cost = if use_costs {
            let mut c = 0.0;
            for e in &a.cost {
                c += match e {
                    CostExpr::Number(n) => *n,
                    CostExpr::Fluent(f, args) => {
                        let key = (
                            f.clone(),
                            args.iter()
                                .map(|t| resolve(t, &b, &objs).to_string())
                                .collect(),
                        );
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
                    let key = (
                        pred.clone(),
                        args.iter()
                            .map(|t| resolve(t, binding, objs).to_string())
                            .collect(),
                    );
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

/// Parse a plan in the competition format: one `(action arg …)` per line; `;` starts a comment.
pub fn parse_plan(text: &str) -> Result<Vec<(String, Vec<String>)>, PlanError> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split(';').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let inner = line
            .strip_prefix('(')
            .and_then(|l| l.strip_suffix(')'))
            .ok_or_else(|| err("plan", format!("line {}: expected `(action arg …)`", i + 1)))?;
        let mut words = inner.split_whitespace().map(str::to_lowercase);
        let name = words
            .next()
            .ok_or_else(|| err("plan", format!("line {}: empty step", i + 1)))?;
        out.push((name, words.collect()));
    }
    Ok(out)
}

/// Simulate a plan on the lifted PDDL task and return its cost; an error names the first step
/// that is not applicable, or the goal that does not hold at the end.
///
/// Written from the PDDL semantics alone: a step binds the action's parameters to objects of the
/// declared types, its precondition is evaluated on the current set of true atoms (closed-world),
/// its delete effects are removed and then its add effects are added.
pub fn validate_plan(
    d: &Domain,
    p: &Problem,
    plan: &[(String, Vec<String>)],
) -> Result<f64, String> {
    let types = object_types(d, p)?;
    let mut state: HashSet<(String, Vec<String>)> = p.init.iter().cloned().collect();
    let use_costs = d.action_costs && p.metric_total_cost;
    let mut total = 0.0;
    let ground = |t: &Term, args: &[String]| -> String {
        match t {
            Term::Param(i) => args[*i].clone(),
            Term::Object(o) => o.clone(),
        }
    };
    let holds = |l: &Literal, args: &[String], state: &HashSet<(String, Vec<String>)>| -> bool {
        match l {
            Literal::Atom {
                pred,
                args: ts,
                negated,
            } => {
                let key = (
                    pred.clone(),
                    ts.iter().map(|t| ground(t, args)).collect::<Vec<_>>(),
                );
                state.contains(&key) != *negated
            }
            Literal::Equal { a, b, negated } => (ground(a, args) == ground(b, args)) != *negated,
        }
    };
    for (i, (name, args)) in plan.iter().enumerate() {
        let a = d
            .actions
            .iter()
            .find(|a| &a.name == name)
            .ok_or_else(|| format!("step {}: unknown action `{name}`", i + 1))?;
        if a.params.len() != args.len() {
            return Err(format!(
                "step {}: `{name}` takes {} arguments, got {}",
                i + 1,
                a.params.len(),
                args.len()
            ));
        }
        for ((pn, pt), o) in a.params.iter().zip(args) {
            match types.get(o) {
                Some(ts) if ts.contains(pt) => {}
                Some(_) => {
                    return Err(format!(
                        "step {}: `{o}` for {pn} is not of type {pt}",
                        i + 1
                    ))
                }
                None => return Err(format!("step {}: unknown object `{o}`", i + 1)),
            }
        }
        for l in &a.pre {
            if !holds(l, args, &state) {
                return Err(format!(
                    "step {} ({name} {}): precondition {l:?} does not hold",
                    i + 1,
                    args.join(" ")
                ));
            }
        }
        for (pred, ts) in &a.del {
            state.remove(&(
                pred.clone(),
                ts.iter().map(|t| ground(t, args)).collect::<Vec<_>>(),
            ));
        }
        for (pred, ts) in &a.add {
            state.insert((
                pred.clone(),
                ts.iter().map(|t| ground(t, args)).collect::<Vec<_>>(),
            ));
        }
        if use_costs {
            for c in &a.cost {
                total += match c {
                    CostExpr::Number(n) => *n,
                    CostExpr::Fluent(f, ts) => *p
                        .numeric
                        .get(&(
                            f.clone(),
                            ts.iter().map(|t| ground(t, args)).collect::<Vec<_>>(),
                        ))
                        .ok_or_else(|| format!("step {}: cost fluent `{f}` undefined", i + 1))?,
                };
            }
        } else {
            total += 1.0;
        }
    }
    for g in &p.goal {
        if !holds(g, &[], &state) {
            return Err(format!("goal {g:?} does not hold at the end of the plan"));
        }
    }
    Ok(total)
}
