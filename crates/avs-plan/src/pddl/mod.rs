//! PDDL import: STRIPS with typing, negative preconditions, equality and action costs
//! (`:action-costs`, `(increase (total-cost) …)`), grounded by relaxed reachability into the
//! same SAS+ [`Task`](crate::task::Task) as the YAML domains (one binary variable per
//! reachable fluent atom), and an independent plan validator that simulates a plan on the
//! *lifted* task with PDDL semantics (deletes before adds) without any of the grounding or
//! search code. One job per file: this one parses, `ground.rs` grounds, `validate.rs`
//! validates.
//!
//! Grounding ([`ground`], in its own file) stays within
//! [`GroundingLimits`](crate::limits::GroundingLimits) (see [`crate::limits`]): an action whose
//! groundings pass them ends the grounding with [`PlanError::GroundingLimit`] naming it.

use crate::PlanError;
use std::collections::{BTreeMap, BTreeSet, HashMap};

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

mod ground;
mod validate;

pub use ground::{ground, ground_with};
pub use validate::{parse_plan, validate_plan};
