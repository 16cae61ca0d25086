//! Plan steps as typed actions, and the check that a domain has what the executive runs.

use super::Binding;
use crate::memory::{ConeLoc, Target};
use crate::reason::ReplanReason;
use crate::AgentError;
use avs_plan::continual::Step;
use avs_plan::domain::{Domain, Quantity};

/// A place or placeholder argument of a plan step, read through the binding.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PlaceArg {
    /// Its plan name (for the trace).
    pub name: String,
    pub target: Target,
    /// Its position, when the problem has one.
    pub pos: Option<[f64; 2]>,
    /// For a placeholder, the position of the place it hangs off.
    pub attach: Option<[f64; 2]>,
}

/// The object a SEARCHFOROBJECT looks for: a known one, or one the plan assumes.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ObjArg {
    /// Its plan name.
    pub name: String,
    /// Whether it is a virtual object an assumption of the plan brought into being.
    pub assumed: bool,
}

/// A plan step as the executive runs it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Action {
    /// An assumption: nothing to execute.
    Assume,
    /// MOVE to a place of the plan.
    Move { to: PlaceArg, pos: [f64; 2] },
    /// MOVE into a placeholder whose room the plan assumes: go there and enter.
    Enter { to: PlaceArg, pos: [f64; 2] },
    /// EXPLORE-PLACEHOLDER: look into the space behind it.
    Explore { ph: PlaceArg },
    /// CREATEVIEWCONES for a class at a location.
    CreateCones { label: String, loc: ConeLoc },
    /// SEARCHFOROBJECT: a view-cone POMDP session.
    Search {
        label: String,
        loc: ConeLoc,
        obj: ObjArg,
        /// The step's listing line.
        display: String,
    },
    /// REPORTPOSITION of an object: a known one (`known`, its index in the memory's objects)
    /// is reported where it was found; a virtual one was not found, and the plan is wrong.
    Report {
        object: String,
        known: Option<usize>,
    },
}

/// The operators the executive runs, with their arities (the domain's parameter counts).
const OPERATORS: [(&str, usize); 10] = [
    ("move", 3),
    ("enter", 3),
    ("explore-placeholder", 4),
    ("createviewcones-in", 3),
    ("createviewcones-on", 4),
    ("searchforobject-in", 3),
    ("searchforobject-on", 4),
    ("createviewcones-inside", 4),
    ("searchforobject-inside", 4),
    ("reportposition", 2),
];

/// The functions the agent supplies to the planner ([`super::Probs`]), with their arities.
const FUNCTIONS: [(&str, usize); 10] = [
    ("distance", 2),
    ("search-cost-in", 2),
    ("search-cost-on", 2),
    ("p-leads-to-room", 2),
    ("p-category", 2),
    ("p-object-in", 3),
    ("p-object-on", 3),
    ("p-object-inside", 3),
    ("p-detect", 1),
    ("p-detect-in", 2),
];

/// The state variables the binding sets, with their parameter counts.
const VARIABLES: [(&str, usize); 14] = [
    ("robot-at", 0),
    ("robot-room", 0),
    ("category", 1),
    ("leads-to", 1),
    ("open-placeholders", 1),
    ("class", 1),
    ("located-in", 1),
    ("located-on", 1),
    ("located-inside", 1),
    ("found", 1),
    ("cones-in", 2),
    ("cones-on", 2),
    ("cones-inside", 2),
    ("reported", 1),
];

/// The static relations the binding states, with their arities.
const RELATIONS: [(&str, usize); 4] = [
    ("connected", 2),
    ("in-room", 2),
    ("placeholder", 1),
    ("landmark", 1),
];

/// The types the binding declares objects of.
const TYPES: [&str; 5] = ["place", "room", "category", "label", "object"];

/// Check that `domain` has every operator the executive executes, every variable, relation
/// and type the binding uses, with the shapes they are used with, and calls no function the
/// agent does not supply. The error names the first thing missing or misshapen.
pub(crate) fn check_domain(domain: &Domain) -> Result<(), AgentError> {
    let err = |what: &'static str, name: &str, problem: String| AgentError::Domain {
        domain: domain.name.clone(),
        what,
        name: name.to_string(),
        problem,
    };
    for ty in TYPES {
        if domain.type_index(ty).is_none() {
            return Err(err(
                "type",
                ty,
                "is missing; the agent declares its objects with it".into(),
            ));
        }
    }
    for (name, arity) in OPERATORS {
        let Some(i) = domain.op_index(name) else {
            return Err(err(
                "operator",
                name,
                format!("is missing; the agent executes it (expected {arity} parameters)"),
            ));
        };
        let n = domain.operators[i].params.len();
        if n != arity {
            return Err(err(
                "operator",
                name,
                format!("has {n} parameters; the agent executes it with {arity}"),
            ));
        }
    }
    for (name, arity) in VARIABLES {
        let Some(i) = domain.var_index(name) else {
            return Err(err(
                "variable",
                name,
                format!("is missing; the agent sets it (expected {arity} parameters)"),
            ));
        };
        let n = domain.variables[i].params.len();
        if n != arity {
            return Err(err(
                "variable",
                name,
                format!("has {n} parameters; the agent sets it with {arity}"),
            ));
        }
    }
    for (name, arity) in RELATIONS {
        let Some(i) = domain.rel_index(name) else {
            return Err(err(
                "relation",
                name,
                format!("is missing; the agent states it (expected {arity} arguments)"),
            ));
        };
        let n = domain.relations[i].1.len();
        if n != arity {
            return Err(err(
                "relation",
                name,
                format!("has {n} arguments; the agent states it with {arity}"),
            ));
        }
    }
    let supplied: Vec<String> = FUNCTIONS.iter().map(|(f, _)| f.to_string()).collect();
    for op in &domain.operators {
        for q in [&op.cost, &op.prob] {
            for (name, n) in functions_of(q) {
                match FUNCTIONS.iter().find(|(f, _)| *f == name) {
                    None => {
                        return Err(err(
                            "function",
                            &name,
                            format!(
                                "(in operator `{}`) is not one the agent supplies; expected one of {}",
                                op.name,
                                supplied.join(", ")
                            ),
                        ))
                    }
                    Some((_, arity)) if *arity != n => {
                        return Err(err(
                            "function",
                            &name,
                            format!(
                                "(in operator `{}`) has {n} arguments; the agent supplies it with {arity}",
                                op.name
                            ),
                        ))
                    }
                    Some(_) => {}
                }
            }
        }
    }
    Ok(())
}

/// The functions a quantity calls, with their argument counts.
fn functions_of(q: &Quantity) -> Vec<(String, usize)> {
    match q {
        Quantity::Const(_) => Vec::new(),
        Quantity::Func { name, args } => vec![(name.clone(), args.len())],
    }
}

impl Binding {
    /// A place argument of a step.
    fn place(&self, name: &str) -> Option<PlaceArg> {
        Some(PlaceArg {
            name: name.to_string(),
            target: *self.targets.get(name)?,
            pos: self.pos.get(name).copied(),
            attach: self.attach.get(name).copied(),
        })
    }

    fn room(&self, name: &str) -> Result<ConeLoc, ReplanReason> {
        self.rooms
            .get(name)
            .map(|r| ConeLoc::Room(r.0))
            .ok_or_else(|| ReplanReason::NoLongerARoom {
                room: name.to_string(),
            })
    }

    fn on(&self, name: &str) -> Result<ConeLoc, ReplanReason> {
        self.landmark(name, ConeLoc::On)
    }

    fn inside(&self, name: &str) -> Result<ConeLoc, ReplanReason> {
        self.landmark(name, ConeLoc::In)
    }

    fn landmark(&self, name: &str, loc: fn(usize) -> ConeLoc) -> Result<ConeLoc, ReplanReason> {
        self.objects
            .get(name)
            .map(|&k| loc(k))
            .ok_or_else(|| ReplanReason::UnknownObject {
                object: name.to_string(),
            })
    }

    fn obj(&self, name: &str) -> ObjArg {
        ObjArg {
            name: name.to_string(),
            assumed: !self.objects.contains_key(name),
        }
    }

    /// Step `step` of a plan made for this binding, as a typed action; a name the binding
    /// does not hold (or an operator the executive does not run) is the reason to replan.
    pub fn action(&self, step: &Step) -> Result<Action, ReplanReason> {
        if step.assumption {
            return Ok(Action::Assume);
        }
        let a: Vec<&str> = step.args.iter().map(String::as_str).collect();
        let moved = |to: &str| {
            let gone = || ReplanReason::GoneFromMap {
                place: to.to_string(),
            };
            let arg = self.place(to).ok_or_else(gone)?;
            let pos = arg.pos.ok_or_else(gone)?;
            Ok((arg, pos))
        };
        match (step.schema.as_str(), a.as_slice()) {
            ("move", [_, to, _]) => moved(to).map(|(to, pos)| Action::Move { to, pos }),
            ("enter", [_, to, _]) => moved(to).map(|(to, pos)| Action::Enter { to, pos }),
            ("explore-placeholder", [p, _, _, _]) => match self.place(p) {
                Some(ph) => Ok(Action::Explore { ph }),
                None => Err(ReplanReason::GoneFromMap {
                    place: p.to_string(),
                }),
            },
            ("createviewcones-in", [l, r, _]) => Ok(Action::CreateCones {
                label: l.to_string(),
                loc: self.room(r)?,
            }),
            ("createviewcones-on", [l, lm, _, _]) => Ok(Action::CreateCones {
                label: l.to_string(),
                loc: self.on(lm)?,
            }),
            ("searchforobject-in", [l, r, o]) => Ok(Action::Search {
                label: l.to_string(),
                loc: self.room(r)?,
                obj: self.obj(o),
                display: step.display.clone(),
            }),
            ("searchforobject-on", [l, lm, o, _]) => Ok(Action::Search {
                label: l.to_string(),
                loc: self.on(lm)?,
                obj: self.obj(o),
                display: step.display.clone(),
            }),
            ("createviewcones-inside", [l, lm, _, _]) => Ok(Action::CreateCones {
                label: l.to_string(),
                loc: self.inside(lm)?,
            }),
            ("searchforobject-inside", [l, lm, o, _]) => Ok(Action::Search {
                label: l.to_string(),
                loc: self.inside(lm)?,
                obj: self.obj(o),
                display: step.display.clone(),
            }),
            ("reportposition", [o, _]) => Ok(Action::Report {
                object: o.to_string(),
                known: self.objects.get(*o).copied(),
            }),
            _ => Err(ReplanReason::CannotExecute {
                step: step.display.clone(),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shipped_domain() -> Domain {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../domains/object_search.yaml"
        );
        Domain::load(std::path::Path::new(path)).expect("the shipped domain loads")
    }

    /// The shipped domain's text with `edit` applied.
    fn edited(edit: impl Fn(String) -> String) -> Domain {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../domains/object_search.yaml"
        );
        let text = edit(std::fs::read_to_string(path).unwrap());
        Domain::from_yaml("edited.yaml", &text).expect("the edited domain is valid")
    }

    #[test]
    fn the_shipped_domain_has_everything_the_executive_runs() {
        check_domain(&shipped_domain()).unwrap();
    }

    #[test]
    fn a_domain_without_an_operator_the_agent_executes_is_rejected_naming_it() {
        let d = edited(|t| t.replace("  - name: reportposition", "  - name: announce-position"));
        let e = check_domain(&d).unwrap_err().to_string();
        assert!(e.contains("operator `reportposition` is missing"), "{e}");
    }

    #[test]
    fn an_operator_with_other_parameters_is_rejected_with_both_counts() {
        let d = edited(|t| {
            t.replace(
                "parameters: [\"?o: object\", \"?l: label\"]",
                "parameters: [\"?o: object\", \"?l: label\", \"?r: room\"]",
            )
        });
        let e = check_domain(&d).unwrap_err().to_string();
        assert!(e.contains("`reportposition` has 3 parameters"), "{e}");
        assert!(e.contains("with 2"), "{e}");
    }

    #[test]
    fn a_function_the_agent_does_not_supply_is_rejected_naming_it_and_the_known_ones() {
        let d = edited(|t| t.replace("probability: p-detect(?l)", "probability: p-see(?l)"));
        let e = check_domain(&d).unwrap_err().to_string();
        assert!(e.contains("function `p-see`"), "{e}");
        assert!(e.contains("p-detect"), "{e}");
    }
}
