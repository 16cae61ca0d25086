//! The independent plan validator: a plan in the competition format simulated on the *lifted*
//! task with PDDL semantics, without any of the grounding or search code.

use super::{err, object_types, CostExpr, Domain, Literal, Problem, Term};
use crate::PlanError;
use std::collections::HashSet;
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
