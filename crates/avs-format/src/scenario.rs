//! `kind: scenario` — a search re-enacted for a test or an experiment: the world (an
//! environment file, edited in memory: start pose, doors closed, objects removed), the
//! knowledge and domain, the goal and the robot's seed, goals searched first, and the
//! properties the run must show ([`Expect`]). The scenario runner is `avs-eval`'s; the plan-trace
//! suite (`tests/plan_traces/`) is a folder of these files.
//!
//! Paths (`environment`, `knowledge`, `domain`) are relative to the repository root (the
//! directory the runner is given). [`check`] checks a file's fields (what `avs validate`
//! runs); names that need the files themselves (doors, rooms, classes) are checked by the
//! runner, which names the field too.

use crate::Diagnostic;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A scenario file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Must be `scenario`.
    pub kind: ScenarioKind,
    /// What it re-enacts, e.g. `Fig. 3(a)`.
    pub run: String,
    /// What the source reports for the run, and how the scenario maps it onto the world.
    pub description: String,
    /// Environment file, relative to the repository root.
    pub environment: String,
    /// Knowledge file, relative to the repository root.
    pub knowledge: String,
    /// Domain file, relative to the repository root.
    pub domain: String,
    /// The object class searched for.
    pub goal: String,
    /// Seed of the simulated robot.
    pub seed: u64,
    /// Start pose instead of the environment's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<Start>,
    /// Doors to close (by name).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub close_doors: Vec<String>,
    /// Objects to take out of the world (with everything standing on or lying in them).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub remove_objects: Option<RemoveObjects>,
    /// Goals the same agent searches first (a partly explored start).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub before: Vec<String>,
    /// The agent's `cover_before_giving_up`; `false` re-enacts the paper's rule (give up as
    /// soon as no plan clears the success threshold).
    #[serde(default = "yes")]
    pub cover_before_giving_up: bool,
    /// The agent's `goal_in_look_around`; `false` re-enacts the paper's robot, whose object
    /// detector ran only in the view cones of SEARCHFOROBJECT (`002` §IV), so that the run
    /// shows the planner's searches rather than a target seen from a door.
    #[serde(default = "yes")]
    pub goal_in_look_around: bool,
    /// The properties the run must show.
    pub expect: Expect,
    /// Why the current agent does not show them yet: a failed property then prints a NOTICE
    /// instead of failing, and all properties holding fails (so the note gets removed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub known_failure: Option<String>,
}

fn yes() -> bool {
    true
}

/// The literal `scenario`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ScenarioKind {
    /// `kind: scenario`
    Scenario,
}

/// A start pose.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Start {
    /// x, metres.
    pub x: f64,
    /// y, metres.
    pub y: f64,
    /// Heading, degrees.
    #[serde(default)]
    pub yaw_deg: f64,
}

/// Objects to take out of the world.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RemoveObjects {
    /// Every object of these classes.
    #[serde(default)]
    pub classes: Vec<String>,
    /// These objects, by id.
    #[serde(default)]
    pub ids: Vec<String>,
}

/// Properties of the scenario goal's search (the `before` searches are not checked).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Expect {
    /// Whether an object was reported.
    #[serde(default)]
    pub found: Option<bool>,
    /// The reported position is within this many metres (planar) of a true object of the
    /// class.
    #[serde(default)]
    pub found_within_m: Option<f64>,
    /// The first plan's first ASSUME-LEADS-TO-ROOM / ASSUME-CATEGORY line ends with this
    /// category.
    #[serde(default)]
    pub first_plan_assumes_category: Option<String>,
    /// Whether the first plan assumes a placeholder leads to a new room (ASSUME-LEADS-TO-ROOM).
    #[serde(default)]
    pub first_plan_assumes_new_room: Option<bool>,
    /// Some plan assumes a placeholder leads to a new room of this category.
    #[serde(default)]
    pub some_plan_assumes_new_room: Option<String>,
    /// Whether the trace shows a violated assumption.
    #[serde(default)]
    pub assumption_violated: Option<bool>,
    /// At least this many plans.
    #[serde(default)]
    pub min_plans: Option<usize>,
    /// The reason of giving up contains this text.
    #[serde(default)]
    pub gave_up_reason_contains: Option<String>,
    /// Landmark classes the goal class was searched ON, each at least once.
    #[serde(default)]
    pub searched_on: Vec<String>,
    /// Classes searched for (executed SEARCHFOROBJECT steps), in this order (a subsequence).
    #[serde(default)]
    pub searched_for: Vec<String>,
    /// True rooms the robot was in, in this order (a subsequence of the rooms along its path).
    #[serde(default)]
    pub entered_rooms: Vec<String>,
    /// The true room the first view cone of the search was processed from.
    #[serde(default)]
    pub first_search_in: Option<String>,
    /// True rooms no view cone was processed from.
    #[serde(default)]
    pub never_searched_in: Vec<String>,
}

impl Scenario {
    /// The checks beyond the types: a description, finite start numbers, a positive
    /// `found_within_m` that does not contradict `found: false`. Diagnostics name `file` and
    /// the field.
    pub fn check_fields(&self, file: &str) -> Vec<Diagnostic> {
        let mut out = Vec::new();
        if self.description.trim().is_empty() {
            out.push(Diagnostic::new(
                file,
                "description",
                "empty",
                "what the source reports for the run",
            ));
        }
        if let Some(s) = &self.start {
            for (field, v) in [
                ("start.x", s.x),
                ("start.y", s.y),
                ("start.yaw_deg", s.yaw_deg),
            ] {
                if !v.is_finite() {
                    out.push(Diagnostic::new(
                        file,
                        field,
                        format!("{v} is not a finite number"),
                        "a finite number",
                    ));
                }
            }
        }
        if let Some(d) = self.expect.found_within_m {
            if !(d.is_finite() && d > 0.0) {
                out.push(Diagnostic::new(
                    file,
                    "expect.found_within_m",
                    format!("{d}"),
                    "a positive distance in metres",
                ));
            }
            if self.expect.found == Some(false) {
                out.push(Diagnostic::new(
                    file,
                    "expect.found_within_m",
                    "set although expect.found is false",
                    "no distance when nothing is to be found",
                ));
            }
        }
        for (field, v) in [
            ("run", &self.run),
            ("environment", &self.environment),
            ("knowledge", &self.knowledge),
            ("domain", &self.domain),
            ("goal", &self.goal),
        ] {
            if v.trim().is_empty() {
                out.push(Diagnostic::new(file, field, "empty", "a non-empty string"));
            }
        }
        out
    }
}

/// Parse and check a scenario file's text, returning every problem found (empty when valid),
/// each located in the text where the field is.
pub fn check(file: &str, text: &str) -> Vec<Diagnostic> {
    crate::load::check_with(file, text, Scenario::check_fields)
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = "kind: scenario
run: Fig. 3(a)
description: test
environment: domains/environments/office.yaml
knowledge: knowledge/office.yaml
domain: domains/object_search.yaml
goal: cerealbox
seed: 1
expect: { found: true }
";

    #[test]
    fn a_minimal_scenario_is_valid_and_runs_the_default_agent() {
        assert!(check("s.yaml", GOOD).is_empty());
        let sc: Scenario = crate::load_yaml_str("s.yaml", GOOD).unwrap();
        assert!(sc.cover_before_giving_up && sc.goal_in_look_around);
        assert_eq!(sc.expect.found, Some(true));
    }

    #[test]
    fn bad_fields_are_named_with_their_line() {
        let cases = [
            (
                GOOD.replace("{ found: true }", "{ foundd: true }"),
                "expect",
            ),
            (GOOD.replace("seed: 1", "seed: one"), "seed"),
            (format!("{GOOD}start: {{ x: 1.0, y: yes }}\n"), "start.y"),
            (GOOD.replace("goal: cerealbox\n", ""), "goal"),
            (
                GOOD.replace("{ found: true }", "{ found: false, found_within_m: 1.0 }"),
                "expect.found_within_m",
            ),
            (
                GOOD.replace("description: test", "description: ' '"),
                "description",
            ),
        ];
        for (text, field) in cases {
            let ds = check("s.yaml", &text);
            assert!(
                ds.iter()
                    .any(|d| d.path.starts_with(field) || d.to_string().contains(field)),
                "{field}: {ds:?}"
            );
            assert!(
                ds.iter().all(|d| d.line.is_some()),
                "{field}: unlocated {ds:?}"
            );
        }
    }
}
