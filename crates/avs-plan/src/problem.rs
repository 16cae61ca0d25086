//! Problems for YAML domains: the objects the robot knows, static facts, the current values of
//! state variables and the goal. The caller (the agent) builds one from its maps before each
//! planning call; the strings use the domain files' expression syntax.

use crate::domain::{Cond, Domain, Objects, Term};
use crate::expr::{self, RawExpr, RawTerm};
use crate::PlanError;
use std::collections::{HashMap, HashSet};

/// Caller-supplied numeric functions: costs (e.g. travel distance) and probabilities (e.g.
/// P_category(room, c)). `None` means "not defined for these arguments".
pub trait Functions {
    /// The value of `name(args)`.
    fn value(&self, name: &str, args: &[&str]) -> Option<f64>;
}

impl<F: Fn(&str, &[&str]) -> Option<f64>> Functions for F {
    fn value(&self, name: &str, args: &[&str]) -> Option<f64> {
        self(name, args)
    }
}

/// A planning problem over a [`Domain`].
#[derive(Debug, Clone, Default, PartialEq, serde::Deserialize)]
pub struct Problem {
    /// Objects as (name, type).
    #[serde(default)]
    pub objects: Vec<(String, String)>,
    /// Static facts, e.g. `connected(place0, place1)`.
    #[serde(default)]
    pub facts: Vec<String>,
    /// Variable values, e.g. `category(room0) = unknown`.
    #[serde(default)]
    pub init: Vec<String>,
    /// Goal conditions, e.g. `reported(cerealbox) = yes`.
    #[serde(default)]
    pub goal: Vec<String>,
}

impl Problem {
    /// An empty problem.
    pub fn new() -> Self {
        Self::default()
    }
    /// Add an object of a type.
    pub fn object(mut self, name: &str, ty: &str) -> Self {
        self.objects.push((name.into(), ty.into()));
        self
    }
    /// Add a static fact.
    pub fn fact(mut self, f: &str) -> Self {
        self.facts.push(f.into());
        self
    }
    /// Set a variable's value.
    pub fn init(mut self, s: &str) -> Self {
        self.init.push(s.into());
        self
    }
    /// Add a goal condition.
    pub fn goal(mut self, s: &str) -> Self {
        self.goal.push(s.into());
        self
    }
    /// Replace (or add) the value of the variable named on the left of `s`.
    pub fn set(mut self, s: &str) -> Self {
        let lhs = s.split('=').next().unwrap_or("").trim().to_string();
        self.init
            .retain(|x| x.split('=').next().unwrap_or("").trim() != lhs);
        self.init.push(s.into());
        self
    }
}

/// A ground variable: schema index and argument objects.
pub type GroundVar = (usize, Vec<usize>);

/// Static facts `relation(objects)`, one set per relation, so that a lookup borrows its
/// arguments (grounding checks one per candidate binding).
#[derive(Debug, Clone, Default)]
pub struct StaticFacts(Vec<HashSet<Vec<usize>, foldhash::fast::FixedState>>);

impl StaticFacts {
    /// Add `rel(args)`.
    pub fn insert(&mut self, rel: usize, args: Vec<usize>) {
        if self.0.len() <= rel {
            self.0.resize_with(rel + 1, Default::default);
        }
        self.0[rel].insert(args);
    }

    /// Whether `rel(args)` holds.
    pub fn contains(&self, rel: usize, args: &[usize]) -> bool {
        self.0.get(rel).is_some_and(|s| s.contains(args))
    }
}

/// A problem resolved against a domain.
#[derive(Debug, Clone)]
pub struct Instance {
    /// All objects (constants, problem objects, virtual objects).
    pub objects: Objects,
    /// Static facts (relation, objects).
    pub facts: StaticFacts,
    /// Given initial values.
    pub init: HashMap<GroundVar, String>,
    /// Goal: (variable, value).
    pub goal: Vec<(GroundVar, String)>,
}

fn perr(m: String) -> PlanError {
    PlanError::Problem(m)
}

impl Instance {
    /// Resolve `p` against `d`.
    pub fn new(d: &Domain, p: &Problem) -> Result<Instance, PlanError> {
        let mut objects = Objects::default();
        for (c, t) in &d.constants {
            objects.add(c, *t, false);
        }
        for (i, (o, t)) in p.objects.iter().enumerate() {
            let ti = d.type_index(t).ok_or_else(|| {
                perr(format!(
                    "objects[{i}]: `{o}` has unknown type `{t}`; expected one of {:?}",
                    d.types
                ))
            })?;
            if !objects.add(o, ti, false) {
                return Err(perr(format!(
                    "objects[{i}]: `{o}` is declared twice (or is a domain constant)"
                )));
            }
        }
        for pool in &d.pools {
            for n in &pool.names {
                if !objects.add(n, pool.ty, true) {
                    return Err(perr(format!(
                        "object `{n}` clashes with a virtual object of the domain"
                    )));
                }
            }
        }
        let mut inst = Instance {
            objects,
            facts: StaticFacts::default(),
            init: HashMap::new(),
            goal: Vec::new(),
        };
        for (ri, args) in &d.facts {
            let objs = args.iter().map(|a| inst.objects.index[a]).collect();
            inst.facts.insert(*ri, objs);
        }
        for (i, f) in p.facts.iter().enumerate() {
            let e = expr::parse(f).map_err(|m| perr(format!("facts[{i}] `{f}`: {m}")))?;
            match e {
                RawExpr::Call {
                    name,
                    args,
                    rhs: None,
                    negated: false,
                } => {
                    let ri = d.rel_index(&name).ok_or_else(|| {
                        perr(format!("facts[{i}] `{f}`: unknown relation `{name}`"))
                    })?;
                    let objs = inst
                        .objs(&args, &d.relations[ri].1, d)
                        .map_err(|m| perr(format!("facts[{i}] `{f}`: {m}")))?;
                    inst.facts.insert(ri, objs);
                }
                _ => {
                    return Err(perr(format!(
                        "facts[{i}] `{f}`: expected `relation(object, …)`"
                    )))
                }
            }
        }
        for (i, s) in p.init.iter().enumerate() {
            let (gv, val) = inst
                .assignment(d, s)
                .map_err(|m| perr(format!("init[{i}] `{s}`: {m}")))?;
            inst.init.insert(gv, val);
        }
        for (i, s) in p.goal.iter().enumerate() {
            let (gv, val) = inst
                .assignment(d, s)
                .map_err(|m| perr(format!("goal[{i}] `{s}`: {m}")))?;
            inst.goal.push((gv, val));
        }
        Ok(inst)
    }

    fn objs(&self, args: &[RawTerm], types: &[usize], d: &Domain) -> Result<Vec<usize>, String> {
        if args.len() != types.len() {
            return Err(format!(
                "{} argument(s) given, {} expected",
                args.len(),
                types.len()
            ));
        }
        args.iter()
            .zip(types)
            .map(|(a, &t)| match a {
                RawTerm::Name(n) => match self.objects.index.get(n) {
                    Some(&o) if self.objects.types[o] == t => Ok(o),
                    Some(_) => Err(format!("`{n}` is not of type `{}`", d.types[t])),
                    None => Err(format!("unknown object `{n}`")),
                },
                RawTerm::Param(p) => Err(format!("`?{p}`: parameters are not allowed here")),
            })
            .collect()
    }

    fn assignment(&self, d: &Domain, s: &str) -> Result<(GroundVar, String), String> {
        match expr::parse(s)? {
            RawExpr::Call {
                name,
                args,
                rhs: Some((op, RawTerm::Name(val))),
                negated: false,
            } if op == "=" || op == ":=" => {
                let vi = d
                    .var_index(&name)
                    .ok_or_else(|| format!("unknown variable `{name}`"))?;
                let objs = self.objs(&args, &d.variables[vi].params, d)?;
                if !self.is_value(d, vi, &val) {
                    return Err(format!("`{val}` is not a value of `{name}`"));
                }
                Ok(((vi, objs), val))
            }
            _ => Err("expected `variable(object, …) = value`".into()),
        }
    }

    /// Whether `val` is in the domain of variable schema `vi`.
    pub fn is_value(&self, d: &Domain, vi: usize, val: &str) -> bool {
        let v = &d.variables[vi];
        v.values.iter().any(|x| x == val)
            || v.ty.is_some_and(|t| {
                self.objects
                    .index
                    .get(val)
                    .is_some_and(|&o| self.objects.types[o] == t)
            })
    }

    /// The value names of variable schema `vi`: objects of its type, then its listed values.
    pub fn values_of(&self, d: &Domain, vi: usize) -> Vec<String> {
        let v = &d.variables[vi];
        let mut out: Vec<String> = match v.ty {
            Some(t) => self
                .objects
                .of_type(t)
                .map(|o| self.objects.names[o].clone())
                .collect(),
            None => Vec::new(),
        };
        out.extend(v.values.iter().cloned());
        out
    }

    /// The initial value of a ground variable (given, else the default).
    pub fn initial(&self, d: &Domain, gv: &GroundVar) -> Result<String, PlanError> {
        if let Some(v) = self.init.get(gv) {
            return Ok(v.clone());
        }
        d.variables[gv.0].default.clone().ok_or_else(|| {
            perr(format!(
                "variable {} has no initial value and no default; expected an `init` entry",
                self.var_name(d, gv)
            ))
        })
    }

    /// `name(arg, …)`.
    pub fn var_name(&self, d: &Domain, gv: &GroundVar) -> String {
        let args: Vec<&str> =
            gv.1.iter()
                .map(|&o| self.objects.names[o].as_str())
                .collect();
        if args.is_empty() {
            d.variables[gv.0].name.clone()
        } else {
            format!("{}({})", d.variables[gv.0].name, args.join(", "))
        }
    }

    /// Resolve a term under a binding to a name.
    pub fn name<'a>(&'a self, t: &'a Term, binding: &[usize]) -> &'a str {
        match t {
            Term::Param(i) => &self.objects.names[binding[*i]],
            Term::Name(n) => n,
        }
    }

    /// [`Self::obj_args`] into `out` (cleared first), without allocating; `false` when a
    /// term names no object.
    pub fn obj_args_into(&self, ts: &[Term], binding: &[usize], out: &mut Vec<usize>) -> bool {
        out.clear();
        for t in ts {
            match t {
                Term::Param(i) => out.push(binding[*i]),
                Term::Name(n) => match self.objects.index.get(n) {
                    Some(&o) => out.push(o),
                    None => return false,
                },
            }
        }
        true
    }

    /// Resolve terms that must be objects.
    pub fn obj_args(&self, ts: &[Term], binding: &[usize]) -> Option<Vec<usize>> {
        ts.iter()
            .map(|t| match t {
                Term::Param(i) => Some(binding[*i]),
                Term::Name(n) => self.objects.index.get(n).copied(),
            })
            .collect()
    }
}

/// The text of a condition under a binding, for messages.
pub fn cond_text(d: &Domain, inst: &Instance, c: &Cond, b: &[usize]) -> String {
    let args = |ts: &[Term]| -> String {
        ts.iter()
            .map(|t| inst.name(t, b))
            .collect::<Vec<_>>()
            .join(", ")
    };
    match c {
        Cond::Var {
            var,
            args: a,
            value,
            negated,
        } => format!(
            "{}({}) {} {}",
            d.variables[*var].name,
            args(a),
            if *negated { "!=" } else { "=" },
            inst.name(value, b)
        ),
        Cond::Rel {
            rel,
            args: a,
            negated,
        } => format!(
            "{}{}({})",
            if *negated { "not " } else { "" },
            d.relations[*rel].0,
            args(a)
        ),
        Cond::Eq { a, b: y, negated } => format!(
            "{} {} {}",
            inst.name(a, b),
            if *negated { "!=" } else { "=" },
            inst.name(y, b)
        ),
    }
}
