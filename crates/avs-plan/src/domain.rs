//! Domain files (`kind: domain`): types, constants, pools of virtual objects, static relations,
//! finite-domain state variables and operators with costs and success probabilities.
//!
//! ```yaml
//! kind: domain
//! name: tiny
//! types: [place, room]
//! virtual: [{ type: room, prefix: new-room, count: 2 }]
//! relations: { connected: [place, place] }
//! variables:
//!   robot-at: { type: place }
//!   leads-to: { parameters: [place], type: room, values: [none, unknown], default: none }
//! operators:
//!   - name: move
//!     display: MOVE ?to
//!     parameters: ["?from: place", "?to: place"]
//!     precondition: ["robot-at = ?from", "connected(?from, ?to)"]
//!     effect: ["robot-at := ?to"]
//!     cost: distance(?from, ?to)        # a caller-supplied function, or a number
//!   - name: assume-leads-to-room
//!     parameters: ["?p: place", "?r: new room"]   # `new`: a fresh virtual object
//!     precondition: ["leads-to(?p) = unknown"]
//!     effect: ["leads-to(?p) := ?r"]
//!     probability: p-room(?p)
//!     assumption: true
//! ```

use crate::expr::{self, RawExpr, RawTerm};
use avs_format::Diagnostic;
use schemars::JsonSchema;
use serde::Deserialize;
use std::collections::{BTreeMap, HashMap, HashSet};

/// A domain file as written.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RawDomain {
    /// Must be `domain`.
    #[schemars(schema_with = "domain_kind")]
    pub kind: avs_format::FileKind,
    /// Name of the domain.
    pub name: String,
    /// Free text.
    #[serde(default)]
    pub description: Option<String>,
    /// Type names.
    pub types: Vec<String>,
    /// Constants per type.
    #[serde(default)]
    pub constants: BTreeMap<String, Vec<String>>,
    /// Pools of virtual objects.
    #[serde(default, rename = "virtual")]
    pub virtual_objects: Vec<RawPool>,
    /// Static relations: name → parameter types.
    #[serde(default)]
    pub relations: BTreeMap<String, Vec<String>>,
    /// Static facts over constants, e.g. `succ(n1, n0)`.
    #[serde(default)]
    pub facts: Vec<String>,
    /// State variables.
    pub variables: BTreeMap<String, RawVariable>,
    /// Operators.
    pub operators: Vec<RawOperator>,
    /// Let assumptive operators apply only before the first non-assumptive step (see the crate
    /// docs for when this loses no plan).
    #[serde(default)]
    pub assumptions_first: bool,
    /// With `assumptions_first`: each assumption after the first of a plan must read a variable
    /// the assumption just before it wrote (see the crate docs for when this loses no plan).
    #[serde(default)]
    pub assumption_chains: bool,
}

/// The schema of `kind:` in a domain file: the one word `domain`.
fn domain_kind(_: &mut schemars::gen::SchemaGenerator) -> schemars::schema::Schema {
    schemars::schema::SchemaObject {
        instance_type: Some(schemars::schema::InstanceType::String.into()),
        enum_values: Some(vec![serde_json::json!("domain")]),
        ..Default::default()
    }
    .into()
}

/// The JSON Schema (pretty-printed JSON) of domain files, generated from [`RawDomain`], for
/// editors and `avs schema domain`. Expressions (`precondition`, `effect`, `cost`, …) are
/// strings to the schema; their grammar is checked by [`Domain::from_yaml`].
pub fn schema_json() -> String {
    let schema = schemars::schema_for!(RawDomain);
    // Serialising a schema (plain maps and strings) cannot fail.
    serde_json::to_string_pretty(&schema).unwrap_or_default()
}

/// A pool of virtual objects `prefix1 … prefixN` of one type.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RawPool {
    /// Their type.
    #[serde(rename = "type")]
    pub ty: String,
    /// Name prefix.
    pub prefix: String,
    /// How many.
    pub count: usize,
}

/// A state variable as written.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RawVariable {
    /// Parameter types.
    #[serde(default)]
    pub parameters: Vec<String>,
    /// Objects of this type are values.
    #[serde(default, rename = "type")]
    pub ty: Option<String>,
    /// Further values (e.g. `unknown`, `none`, `yes`).
    #[serde(default)]
    pub values: Vec<String>,
    /// Initial value when the problem gives none.
    #[serde(default)]
    pub default: Option<String>,
}

/// A number or a function call, as written.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum RawQuantity {
    /// A constant.
    Number(f64),
    /// `function(?a, ?b)`.
    Expr(String),
}

/// An operator as written.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RawOperator {
    /// Name.
    pub name: String,
    /// Listing template, e.g. `MOVE ?to`; default: the upper-case name and all parameters.
    #[serde(default)]
    pub display: Option<String>,
    /// `"?name: type"` or `"?name: new type"`.
    #[serde(default)]
    pub parameters: Vec<String>,
    /// Conditions.
    #[serde(default)]
    pub precondition: Vec<String>,
    /// Assignments.
    #[serde(default)]
    pub effect: Vec<String>,
    /// Cost (default 1).
    #[serde(default)]
    pub cost: Option<RawQuantity>,
    /// Success probability (default 1).
    #[serde(default)]
    pub probability: Option<RawQuantity>,
    /// Whether this operator is an assumption.
    #[serde(default)]
    pub assumption: bool,
}

/// A term of a compiled expression.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Term {
    /// A parameter, by index.
    Param(usize),
    /// An object, constant or value name.
    Name(String),
}

/// A compiled condition.
#[derive(Debug, Clone, PartialEq)]
pub enum Cond {
    /// `var(args) = value` (or `!=`).
    Var {
        /// Variable index.
        var: usize,
        /// Arguments.
        args: Vec<Term>,
        /// Value.
        value: Term,
        /// `!=`.
        negated: bool,
    },
    /// `rel(args)` (or `not rel(args)`).
    Rel {
        /// Relation index.
        rel: usize,
        /// Arguments.
        args: Vec<Term>,
        /// `not`.
        negated: bool,
    },
    /// `?a = ?b` (or `!=`).
    Eq {
        /// Left.
        a: Term,
        /// Right.
        b: Term,
        /// `!=`.
        negated: bool,
    },
}

/// A compiled effect `var(args) := value`.
#[derive(Debug, Clone, PartialEq)]
pub struct Effect {
    /// Variable index.
    pub var: usize,
    /// Arguments.
    pub args: Vec<Term>,
    /// Value.
    pub value: Term,
}

/// A cost or probability.
#[derive(Debug, Clone, PartialEq)]
pub enum Quantity {
    /// A constant.
    Const(f64),
    /// A caller-supplied function.
    Func {
        /// Function name.
        name: String,
        /// Arguments.
        args: Vec<Term>,
    },
}

/// An operator parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    /// Name without `?`.
    pub name: String,
    /// Type index.
    pub ty: usize,
    /// Bound to a fresh virtual object.
    pub new: bool,
}

/// A compiled operator schema.
#[derive(Debug, Clone, PartialEq)]
pub struct OpSchema {
    /// Name.
    pub name: String,
    /// Listing template parts: literal text or a parameter index.
    pub display: Vec<Result<String, usize>>,
    /// Parameters.
    pub params: Vec<Param>,
    /// Preconditions.
    pub pre: Vec<Cond>,
    /// The precondition texts, for messages.
    pub pre_text: Vec<String>,
    /// Effects.
    pub eff: Vec<Effect>,
    /// Cost.
    pub cost: Quantity,
    /// Success probability.
    pub prob: Quantity,
    /// Assumptive.
    pub assumption: bool,
}

impl OpSchema {
    /// The listing line of this schema with `args`.
    pub fn display_with(&self, args: &[String]) -> String {
        let mut s = String::new();
        for p in &self.display {
            match p {
                Ok(t) => s.push_str(t),
                Err(i) => s.push_str(args.get(*i).map(String::as_str).unwrap_or("?")),
            }
        }
        s
    }
}

/// A compiled state-variable schema.
#[derive(Debug, Clone, PartialEq)]
pub struct VarSchema {
    /// Name.
    pub name: String,
    /// Parameter types.
    pub params: Vec<usize>,
    /// Objects of this type are values.
    pub ty: Option<usize>,
    /// Further values.
    pub values: Vec<String>,
    /// Default initial value.
    pub default: Option<String>,
}

/// A pool of virtual objects.
#[derive(Debug, Clone, PartialEq)]
pub struct Pool {
    /// Type index.
    pub ty: usize,
    /// Names, in allocation order.
    pub names: Vec<String>,
}

/// A checked, compiled domain.
#[derive(Debug, Clone, PartialEq)]
pub struct Domain {
    /// Name.
    pub name: String,
    /// Type names.
    pub types: Vec<String>,
    /// Constants (name, type).
    pub constants: Vec<(String, usize)>,
    /// Virtual object pools.
    pub pools: Vec<Pool>,
    /// Static relations (name, parameter types).
    pub relations: Vec<(String, Vec<usize>)>,
    /// Static facts over constants.
    pub facts: Vec<(usize, Vec<String>)>,
    /// State variables.
    pub variables: Vec<VarSchema>,
    /// Operators.
    pub operators: Vec<OpSchema>,
    /// Assumptions only before the first non-assumptive step.
    pub assumptions_first: bool,
    /// Assumptions in one chain, each reading what the one before it wrote.
    pub assumption_chains: bool,
}

impl Domain {
    /// Parse and check a domain file's text; every problem is reported.
    pub fn from_yaml(file: &str, text: &str) -> Result<Domain, Vec<Diagnostic>> {
        let raw: RawDomain = avs_format::load_yaml_str(file, text).map_err(|e| e.diagnostics)?;
        compile(file, &raw)
    }

    /// Read and check a domain file.
    pub fn load(path: &std::path::Path) -> Result<Domain, Vec<Diagnostic>> {
        let text = avs_format::load::read_text(path).map_err(|e| e.diagnostics)?;
        Self::from_yaml(&path.display().to_string(), &text)
    }

    /// Index of a type by name.
    pub fn type_index(&self, name: &str) -> Option<usize> {
        self.types.iter().position(|t| t == name)
    }
    /// Index of a variable by name.
    pub fn var_index(&self, name: &str) -> Option<usize> {
        self.variables.iter().position(|v| v.name == name)
    }
    /// Index of a relation by name.
    pub fn rel_index(&self, name: &str) -> Option<usize> {
        self.relations.iter().position(|r| r.0 == name)
    }
    /// Index of an operator by name.
    pub fn op_index(&self, name: &str) -> Option<usize> {
        self.operators.iter().position(|o| o.name == name)
    }
    /// Whether `name` is a virtual object.
    pub fn is_virtual(&self, name: &str) -> bool {
        self.pools.iter().any(|p| p.names.iter().any(|n| n == name))
    }
}

struct Ctx<'a> {
    file: &'a str,
    diags: Vec<Diagnostic>,
}

impl Ctx<'_> {
    fn err(&mut self, path: String, msg: impl Into<String>, fix: impl Into<String>) {
        self.diags.push(Diagnostic::new(self.file, path, msg, fix));
    }
}

fn compile(file: &str, raw: &RawDomain) -> Result<Domain, Vec<Diagnostic>> {
    let mut cx = Ctx {
        file,
        diags: Vec::new(),
    };
    if raw.kind != avs_format::FileKind::Domain {
        cx.err(
            "kind".into(),
            format!("kind is `{}`", raw.kind.name()),
            "`kind: domain`",
        );
    }
    let mut types: Vec<String> = Vec::new();
    for (i, t) in raw.types.iter().enumerate() {
        if types.contains(t) {
            cx.err(
                format!("types[{i}]"),
                format!("type `{t}` declared twice"),
                "each type once",
            );
        } else if !valid_name(t) {
            cx.err(
                format!("types[{i}]"),
                format!("`{t}` is not a valid name"),
                "letters, digits, `-` or `_`",
            );
        }
        types.push(t.clone());
    }
    let type_of = |cx: &mut Ctx, path: String, t: &str| -> Option<usize> {
        let r = types.iter().position(|x| x == t);
        if r.is_none() {
            cx.err(
                path,
                format!("unknown type `{t}`"),
                format!("one of the declared types: {}", types.join(", ")),
            );
        }
        r
    };
    let mut constants: Vec<(String, usize)> = Vec::new();
    let mut names: HashSet<String> = HashSet::new();
    for (t, list) in &raw.constants {
        let Some(ti) = type_of(&mut cx, format!("constants.{t}"), t) else {
            continue;
        };
        for (i, c) in list.iter().enumerate() {
            if !names.insert(c.clone()) {
                cx.err(
                    format!("constants.{t}[{i}]"),
                    format!("`{c}` declared twice"),
                    "unique object names",
                );
            }
            constants.push((c.clone(), ti));
        }
    }
    let mut pools = Vec::new();
    for (i, p) in raw.virtual_objects.iter().enumerate() {
        let Some(ti) = type_of(&mut cx, format!("virtual[{i}].type"), &p.ty) else {
            continue;
        };
        if p.count == 0 || p.count > 64 {
            cx.err(
                format!("virtual[{i}].count"),
                format!("count is {}", p.count),
                "between 1 and 64",
            );
            continue;
        }
        let ns: Vec<String> = (1..=p.count).map(|k| format!("{}{k}", p.prefix)).collect();
        for n in &ns {
            if !names.insert(n.clone()) {
                cx.err(
                    format!("virtual[{i}].prefix"),
                    format!("virtual object `{n}` clashes with another name"),
                    "a prefix no constant starts with",
                );
            }
        }
        pools.push(Pool { ty: ti, names: ns });
    }
    let mut relations = Vec::new();
    for (r, ps) in &raw.relations {
        let tys: Vec<usize> = ps
            .iter()
            .enumerate()
            .filter_map(|(i, t)| type_of(&mut cx, format!("relations.{r}[{i}]"), t))
            .collect();
        relations.push((r.clone(), tys));
    }
    let mut variables = Vec::new();
    for (v, spec) in &raw.variables {
        if relations.iter().any(|r| &r.0 == v) {
            cx.err(
                format!("variables.{v}"),
                format!("`{v}` is both a relation and a variable"),
                "distinct names",
            );
        }
        let params: Vec<usize> = spec
            .parameters
            .iter()
            .enumerate()
            .filter_map(|(i, t)| type_of(&mut cx, format!("variables.{v}.parameters[{i}]"), t))
            .collect();
        let ty = spec
            .ty
            .as_ref()
            .and_then(|t| type_of(&mut cx, format!("variables.{v}.type"), t));
        if spec.ty.is_none() && spec.values.is_empty() {
            cx.err(
                format!("variables.{v}"),
                "the variable has no values",
                "`type: T` and/or `values: [...]`",
            );
        }
        let mut seen = HashSet::new();
        for (i, x) in spec.values.iter().enumerate() {
            if !seen.insert(x) {
                cx.err(
                    format!("variables.{v}.values[{i}]"),
                    format!("value `{x}` listed twice"),
                    "each value once",
                );
            }
        }
        if let Some(d) = &spec.default {
            let ok = spec.values.contains(d)
                || ty.is_some_and(|t| constants.iter().any(|(c, ct)| c == d && *ct == t));
            if !ok {
                cx.err(
                    format!("variables.{v}.default"),
                    format!("default `{d}` is not a value of `{v}`"),
                    format!("one of {:?} or a constant of its type", spec.values),
                );
            }
        }
        variables.push(VarSchema {
            name: v.clone(),
            params,
            ty,
            values: spec.values.clone(),
            default: spec.default.clone(),
        });
    }
    let mut facts = Vec::new();
    for (i, f) in raw.facts.iter().enumerate() {
        let path = format!("facts[{i}]");
        match expr::parse(f) {
            Ok(RawExpr::Call {
                name,
                args,
                rhs: None,
                negated: false,
            }) => {
                let Some(ri) = relations.iter().position(|r| r.0 == name) else {
                    cx.err(
                        path,
                        format!("unknown relation `{name}`"),
                        "a relation declared under `relations`",
                    );
                    continue;
                };
                if args.len() != relations[ri].1.len() {
                    cx.err(
                        path,
                        format!(
                            "`{name}` takes {} arguments, got {}",
                            relations[ri].1.len(),
                            args.len()
                        ),
                        "the declared arity",
                    );
                    continue;
                }
                let mut objs = Vec::new();
                for (k, a) in args.iter().enumerate() {
                    match a {
                        RawTerm::Name(n)
                            if constants
                                .iter()
                                .any(|(c, t)| c == n && *t == relations[ri].1[k]) =>
                        {
                            objs.push(n.clone())
                        }
                        _ => cx.err(
                            path.clone(),
                            format!(
                                "argument {} is not a constant of type `{}`",
                                k + 1,
                                types[relations[ri].1[k]]
                            ),
                            "constants declared under `constants`",
                        ),
                    }
                }
                facts.push((ri, objs));
            }
            Ok(_) => cx.err(
                path,
                format!("`{f}` is not a fact"),
                "`relation(constant, …)`",
            ),
            Err(e) => cx.err(path, e, "`relation(constant, …)`"),
        }
    }
    let mut operators = Vec::new();
    let mut op_names = HashSet::new();
    for (oi, o) in raw.operators.iter().enumerate() {
        let base = format!("operators[{oi}]");
        if !op_names.insert(o.name.clone()) {
            cx.err(
                format!("{base}.name"),
                format!("operator `{}` declared twice", o.name),
                "unique operator names",
            );
        }
        let mut params: Vec<Param> = Vec::new();
        for (pi, p) in o.parameters.iter().enumerate() {
            let path = format!("{base}.parameters[{pi}]");
            let Some((n, t)) = p.split_once(':') else {
                cx.err(
                    path,
                    format!("`{p}` has no type"),
                    "`?name: type` or `?name: new type`",
                );
                continue;
            };
            let n = n.trim();
            let Some(n) = n.strip_prefix('?') else {
                cx.err(
                    path,
                    format!("parameter `{n}` does not start with `?`"),
                    "`?name: type`",
                );
                continue;
            };
            let t = t.trim();
            let (new, t) = match t.strip_prefix("new ") {
                Some(rest) => (true, rest.trim()),
                None => (false, t),
            };
            if params.iter().any(|q| q.name == n) {
                cx.err(
                    path.clone(),
                    format!("parameter `?{n}` declared twice"),
                    "unique parameter names",
                );
            }
            let Some(ti) = type_of(&mut cx, path.clone(), t) else {
                continue;
            };
            if new && !pools.iter().any(|p| p.ty == ti) {
                cx.err(
                    path,
                    format!("`new {t}` but there is no virtual pool of type `{t}`"),
                    format!("a `virtual:` entry with `type: {t}`"),
                );
            }
            params.push(Param {
                name: n.to_string(),
                ty: ti,
                new,
            });
        }
        let scope = Scope {
            types: &types,
            constants: &constants,
            pools: &pools,
            relations: &relations,
            variables: &variables,
            params: &params,
        };
        let mut pre = Vec::new();
        for (ci, c) in o.precondition.iter().enumerate() {
            let path = format!("{base}.precondition[{ci}]");
            match expr::parse(c).and_then(|e| scope.condition(&e)) {
                Ok(c) => pre.push(c),
                Err(m) => cx.err(path, format!("`{c}`: {m}"), "`var(?a) = value`, `var(?a) != value`, `relation(?a, ?b)`, `not relation(…)` or `?a != ?b` with declared names"),
            }
        }
        let mut eff = Vec::new();
        for (ei, e) in o.effect.iter().enumerate() {
            let path = format!("{base}.effect[{ei}]");
            match expr::parse(e).and_then(|x| scope.effect(&x)) {
                Ok(x) => eff.push(x),
                Err(m) => cx.err(
                    path,
                    format!("`{e}`: {m}"),
                    "`var(?a) := value` with a declared variable and a value of its domain",
                ),
            }
        }
        let mut assigned = HashSet::new();
        for (ei, e) in eff.iter().enumerate() {
            if !assigned.insert((e.var, e.args.clone())) {
                cx.err(
                    format!("{base}.effect[{ei}]"),
                    "the same variable is assigned twice",
                    "one assignment per variable",
                );
            }
        }
        let cost = quantity(
            &mut cx,
            &scope,
            format!("{base}.cost"),
            o.cost.as_ref(),
            false,
        );
        let prob = quantity(
            &mut cx,
            &scope,
            format!("{base}.probability"),
            o.probability.as_ref(),
            true,
        );
        let display = match &o.display {
            Some(d) => {
                let mut parts = Vec::new();
                for (k, w) in d.split(' ').enumerate() {
                    if k > 0 {
                        parts.push(Ok(" ".to_string()));
                    }
                    if let Some(n) = w.strip_prefix('?') {
                        match params.iter().position(|p| p.name == n) {
                            Some(i) => parts.push(Err(i)),
                            None => {
                                cx.err(
                                    format!("{base}.display"),
                                    format!("`?{n}` is not a parameter"),
                                    "parameters of this operator",
                                );
                            }
                        }
                    } else {
                        parts.push(Ok(w.to_string()));
                    }
                }
                parts
            }
            None => {
                let mut parts = vec![Ok(o.name.to_uppercase())];
                for i in 0..params.len() {
                    parts.push(Ok(" ".into()));
                    parts.push(Err(i));
                }
                parts
            }
        };
        operators.push(OpSchema {
            name: o.name.clone(),
            display,
            params,
            pre,
            pre_text: o.precondition.clone(),
            eff,
            cost,
            prob,
            assumption: o.assumption,
        });
    }
    if raw.assumption_chains && !raw.assumptions_first {
        cx.err(
            "assumption_chains".into(),
            "assumption chains are a restriction of the assumptions-first phase",
            "`assumptions_first: true` as well, or no `assumption_chains`",
        );
    }
    if cx.diags.is_empty() {
        Ok(Domain {
            name: raw.name.clone(),
            types,
            constants,
            pools,
            relations,
            facts,
            variables,
            operators,
            assumptions_first: raw.assumptions_first,
            assumption_chains: raw.assumption_chains,
        })
    } else {
        Err(cx.diags)
    }
}

fn valid_name(s: &str) -> bool {
    !s.is_empty()
        && s.chars()
            .all(|c| c.is_alphanumeric() || c == '-' || c == '_')
}

fn quantity(
    cx: &mut Ctx,
    scope: &Scope,
    path: String,
    q: Option<&RawQuantity>,
    probability: bool,
) -> Quantity {
    let what = if probability {
        "a probability in (0, 1] or a function `name(?a, …)`"
    } else {
        "a finite cost ≥ 0 or a function `name(?a, …)`"
    };
    let check = |v: f64| {
        if probability {
            v > 0.0 && v <= 1.0
        } else {
            v.is_finite() && v >= 0.0
        }
    };
    match q {
        None => Quantity::Const(1.0),
        Some(RawQuantity::Number(v)) => {
            if !check(*v) {
                cx.err(path, format!("value {v} is out of range"), what);
            }
            Quantity::Const(*v)
        }
        Some(RawQuantity::Expr(s)) => match expr::parse(s) {
            Ok(RawExpr::Number(v)) => {
                if !check(v) {
                    cx.err(path, format!("value {v} is out of range"), what);
                }
                Quantity::Const(v)
            }
            Ok(RawExpr::Call {
                name,
                args,
                rhs: None,
                negated: false,
            }) => {
                let mut ts = Vec::new();
                for a in &args {
                    match scope.term(a) {
                        Ok(t) => ts.push(t),
                        Err(m) => cx.err(path.clone(), m, what),
                    }
                }
                Quantity::Func { name, args: ts }
            }
            Ok(_) => {
                cx.err(
                    path,
                    format!("`{s}` is not a number or a function call"),
                    what,
                );
                Quantity::Const(1.0)
            }
            Err(e) => {
                cx.err(path, format!("`{s}`: {e}"), what);
                Quantity::Const(1.0)
            }
        },
    }
}

struct Scope<'a> {
    types: &'a [String],
    constants: &'a [(String, usize)],
    pools: &'a [Pool],
    relations: &'a [(String, Vec<usize>)],
    variables: &'a [VarSchema],
    params: &'a [Param],
}

impl Scope<'_> {
    fn term(&self, t: &RawTerm) -> Result<Term, String> {
        match t {
            RawTerm::Param(p) => self
                .params
                .iter()
                .position(|q| &q.name == p)
                .map(Term::Param)
                .ok_or_else(|| format!("unknown parameter `?{p}`")),
            RawTerm::Name(n) => Ok(Term::Name(n.clone())),
        }
    }

    /// Check a term against a type: parameters must have the type; names must be constants.
    fn typed(&self, t: &RawTerm, ty: usize, what: &str) -> Result<Term, String> {
        let x = self.term(t)?;
        match &x {
            Term::Param(i) => {
                if self.params[*i].ty != ty {
                    return Err(format!(
                        "{what}: `?{}` has type `{}`, expected `{}`",
                        self.params[*i].name, self.types[self.params[*i].ty], self.types[ty]
                    ));
                }
            }
            Term::Name(n) => {
                let ok = self.constants.iter().any(|(c, ct)| c == n && *ct == ty)
                    || self.pools.iter().any(|p| p.ty == ty && p.names.contains(n));
                if !ok {
                    return Err(format!(
                        "{what}: `{n}` is not a constant of type `{}`",
                        self.types[ty]
                    ));
                }
            }
        }
        Ok(x)
    }

    fn value(&self, v: &VarSchema, t: &RawTerm) -> Result<Term, String> {
        if let RawTerm::Name(n) = t {
            if v.values.contains(n) {
                return Ok(Term::Name(n.clone()));
            }
        }
        match v.ty {
            Some(ty) => self
                .typed(t, ty, &format!("value of `{}`", v.name))
                .map_err(|e| format!("{e} (or one of the values {:?})", v.values)),
            None => Err(format!(
                "`{}` is not a value of `{}`; its values are {:?}",
                match t {
                    RawTerm::Param(p) => format!("?{p}"),
                    RawTerm::Name(n) => n.clone(),
                },
                v.name,
                v.values
            )),
        }
    }

    fn args(&self, name: &str, want: &[usize], got: &[RawTerm]) -> Result<Vec<Term>, String> {
        if want.len() != got.len() {
            return Err(format!(
                "`{name}` takes {} argument(s), got {}",
                want.len(),
                got.len()
            ));
        }
        want.iter()
            .zip(got)
            .enumerate()
            .map(|(k, (&ty, t))| self.typed(t, ty, &format!("argument {} of `{name}`", k + 1)))
            .collect()
    }

    fn condition(&self, e: &RawExpr) -> Result<Cond, String> {
        match e {
            RawExpr::Compare { a, b, negated } => Ok(Cond::Eq {
                a: self.term(a)?,
                b: self.term(b)?,
                negated: *negated,
            }),
            RawExpr::Number(_) => Err("a number is not a condition".into()),
            RawExpr::Call {
                name,
                args,
                rhs,
                negated,
            } => {
                if let Some(ri) = self.relations.iter().position(|r| &r.0 == name) {
                    if rhs.is_some() {
                        return Err(format!("relation `{name}` takes no `= value`"));
                    }
                    return Ok(Cond::Rel {
                        rel: ri,
                        args: self.args(name, &self.relations[ri].1, args)?,
                        negated: *negated,
                    });
                }
                let Some(vi) = self.variables.iter().position(|v| &v.name == name) else {
                    return Err(format!("unknown variable or relation `{name}`"));
                };
                let v = &self.variables[vi];
                let args = self.args(name, &v.params, args)?;
                match rhs {
                    Some((op, val)) if op == "=" || op == "!=" => Ok(Cond::Var {
                        var: vi,
                        args,
                        value: self.value(v, val)?,
                        negated: (op == "!=") != *negated,
                    }),
                    Some((op, _)) => Err(format!("`{op}` is an assignment, not a condition")),
                    None => Err(format!("variable `{name}` needs `= value`")),
                }
            }
        }
    }

    fn effect(&self, e: &RawExpr) -> Result<Effect, String> {
        match e {
            RawExpr::Call {
                name,
                args,
                rhs: Some((op, val)),
                negated: false,
            } if op == ":=" => {
                let Some(vi) = self.variables.iter().position(|v| &v.name == name) else {
                    return Err(format!("unknown variable `{name}`"));
                };
                let v = &self.variables[vi];
                Ok(Effect {
                    var: vi,
                    args: self.args(name, &v.params, args)?,
                    value: self.value(v, val)?,
                })
            }
            _ => Err("not an assignment".into()),
        }
    }
}

/// Objects of a grounding: domain constants, problem objects and virtual objects, with types.
#[derive(Debug, Clone, Default)]
pub struct Objects {
    /// Names.
    pub names: Vec<String>,
    /// Type per object.
    pub types: Vec<usize>,
    /// Whether virtual.
    pub virtual_: Vec<bool>,
    /// Name → index.
    pub index: HashMap<String, usize>,
}

impl Objects {
    /// Add an object; false if the name exists.
    pub fn add(&mut self, name: &str, ty: usize, virtual_: bool) -> bool {
        if self.index.contains_key(name) {
            return false;
        }
        self.index.insert(name.to_string(), self.names.len());
        self.names.push(name.to_string());
        self.types.push(ty);
        self.virtual_.push(virtual_);
        true
    }
    /// Objects of a type.
    pub fn of_type(&self, ty: usize) -> impl Iterator<Item = usize> + '_ {
        (0..self.names.len()).filter(move |&i| self.types[i] == ty)
    }
}
