//! The scenario runner: a scenario file (`avs_format::scenario::Scenario`) re-enacted — its
//! world built (the environment with the start pose, closed doors and removed objects edited
//! in, in memory), one long-lived agent searching the `before` goals and then the goal — and
//! judged: the properties of [`properties`] and the golden text trace of [`golden`].

pub mod golden;
pub mod properties;

use crate::edits::{edit_environment, EditField, WorldEdits};
use crate::episode::{load_domain, load_knowledge};
use crate::EvalError;
use avs_agent::trace::{render_json_lines, render_text};
use avs_agent::{Agent, AgentConfig, Goal, SearchReport};
use avs_format::environment::Environment;
use avs_format::knowledge::Knowledge;
use avs_format::scenario::Scenario;
use avs_sim::sim_robot::{SimAgentRobot, SimRobotConfig};
use avs_sim::World;
use std::path::Path;

/// Read a scenario file and check its fields; errors name the file and the field.
pub fn load_scenario(path: &Path) -> Result<Scenario, EvalError> {
    let file = path.display().to_string();
    let sc: Scenario = avs_format::load_yaml(path)?;
    let ds = sc.check_fields(&file);
    if !ds.is_empty() {
        return Err(avs_format::LoadError { diagnostics: ds }.into());
    }
    Ok(sc)
}

/// The scenario's world: its environment (relative to `root`) with the start pose, doors and
/// objects edited in. `file` is the scenario's path, for messages.
pub fn build_world(sc: &Scenario, file: &Path, root: &Path) -> Result<World, EvalError> {
    let f = file.display().to_string();
    let field = |field: String, message: String| EvalError::Field {
        file: f.clone(),
        field,
        message,
    };
    let env_path = root.join(&sc.environment);
    let mut env: Environment =
        avs_format::load_yaml(&env_path).map_err(|e| field("environment".into(), e.to_string()))?;
    let edits = WorldEdits {
        start: sc.start,
        close_doors: sc.close_doors.clone(),
        remove: sc.remove_objects.clone().unwrap_or_default(),
    };
    edit_environment(&mut env, &edits, &sc.environment).map_err(|(which, message)| {
        let name = match which {
            EditField::CloseDoor(i) => format!("close_doors[{i}]"),
            EditField::RemoveClass(i) => format!("remove_objects.classes[{i}]"),
            EditField::RemoveId(i) => format!("remove_objects.ids[{i}]"),
        };
        field(name, message)
    })?;
    let base = env_path.parent().unwrap_or(Path::new("."));
    World::named(&sc.environment, env, base).map_err(|e| field("environment".into(), e.to_string()))
}

/// A scenario run: the world and every search's report.
#[derive(Debug)]
pub struct ScenarioRun {
    /// The edited world.
    pub world: World,
    /// The `before` searches, then the scenario goal's search (last), with their goals.
    pub reports: Vec<(String, SearchReport)>,
    /// The robot's trail during the scenario goal's search (from where it started).
    pub trail: Vec<[f64; 2]>,
}

impl ScenarioRun {
    /// The scenario goal's search.
    pub fn main(&self) -> &SearchReport {
        &self
            .reports
            .last()
            .expect("a run has at least the goal's search")
            .1
    }

    /// The golden text: every search's text trace under a header line.
    pub fn text(&self, name: &str, seed: u64) -> String {
        let mut s = format!("# plan trace of scenario {name}, seed {seed}\n");
        let n = self.reports.len();
        for (k, (goal, r)) in self.reports.iter().enumerate() {
            let role = if k + 1 == n { "goal" } else { "before" };
            s.push_str(&format!("# search {}/{n} ({role}): {goal}\n", k + 1));
            s.push_str(&render_text(&r.trace));
        }
        s
    }

    /// Every search's trace as JSON lines.
    pub fn json(&self) -> String {
        self.reports
            .iter()
            .map(|(_, r)| render_json_lines(&r.trace))
            .collect()
    }
}

/// Rooms, categories and classes named in `expect` exist (a typo would make a "never" property
/// hold vacuously).
fn check_names(sc: &Scenario, world: &World, k: &Knowledge, file: &str) -> Result<(), EvalError> {
    let x = &sc.expect;
    let rooms: Vec<&str> = world.env.rooms.iter().map(|r| r.name.as_str()).collect();
    let cats: Vec<&str> = k.room_categories.iter().map(String::as_str).collect();
    let classes: Vec<&str> = k.object_classes.iter().map(|c| c.name.as_str()).collect();
    let mut named: Vec<(String, &String, &[&str], &str)> = Vec::new();
    for (i, r) in x.entered_rooms.iter().enumerate() {
        named.push((format!("expect.entered_rooms[{i}]"), r, &rooms, "room"));
    }
    for (i, r) in x.never_searched_in.iter().enumerate() {
        named.push((format!("expect.never_searched_in[{i}]"), r, &rooms, "room"));
    }
    if let Some(r) = &x.first_search_in {
        named.push(("expect.first_search_in".into(), r, &rooms, "room"));
    }
    if let Some(c) = &x.first_plan_assumes_category {
        named.push((
            "expect.first_plan_assumes_category".into(),
            c,
            &cats,
            "category",
        ));
    }
    if let Some(c) = &x.some_plan_assumes_new_room {
        named.push((
            "expect.some_plan_assumes_new_room".into(),
            c,
            &cats,
            "category",
        ));
    }
    for (i, c) in x.searched_on.iter().enumerate() {
        named.push((
            format!("expect.searched_on[{i}]"),
            c,
            &classes,
            "object class",
        ));
    }
    for (i, c) in x.searched_for.iter().enumerate() {
        named.push((
            format!("expect.searched_for[{i}]"),
            c,
            &classes,
            "object class",
        ));
    }
    for (field, v, known, what) in named {
        if !known.contains(&v.as_str()) {
            return Err(EvalError::Field {
                file: file.to_string(),
                field,
                message: format!("unknown {what} `{v}`; one of {}", known.join(", ")),
            });
        }
    }
    Ok(())
}

/// Re-enact scenario `sc` (read from `file`; paths relative to `root`).
pub fn run_scenario(sc: &Scenario, file: &Path, root: &Path) -> Result<ScenarioRun, EvalError> {
    let world = build_world(sc, file, root)?;
    let f = file.display().to_string();
    let knowledge = load_knowledge(&root.join(&sc.knowledge))?;
    let domain = load_domain(&root.join(&sc.domain))?;
    check_names(sc, &world, &knowledge, &f)?;
    let (reports, trail) = {
        let mut robot = SimAgentRobot::new(
            &world,
            knowledge.clone(),
            SimRobotConfig::default(),
            sc.seed,
        )
        .map_err(|e| EvalError::Sim(format!("{f}: simulated robot: {e}")))?;
        let config = AgentConfig {
            cover_before_giving_up: sc.cover_before_giving_up,
            goal_in_look_around: sc.goal_in_look_around,
            ..AgentConfig::default()
        };
        let mut agent = Agent::new(domain, knowledge, config)?;
        let mut reports = Vec::new();
        let goals = sc
            .before
            .iter()
            .enumerate()
            .map(|(i, g)| (format!("before[{i}]"), g));
        let mut from = 0;
        for (field, goal) in goals.chain([("goal".to_string(), &sc.goal)]) {
            from = robot.trail().len().saturating_sub(1);
            let r = agent
                .search(&mut robot, Goal::find(goal))
                .map_err(|e| EvalError::Field {
                    file: f.clone(),
                    field,
                    message: e.to_string(),
                })?;
            reports.push((goal.clone(), r));
        }
        (reports, robot.trail()[from..].to_vec())
    };
    Ok(ScenarioRun {
        world,
        reports,
        trail,
    })
}
