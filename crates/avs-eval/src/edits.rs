//! World edits before a search: the start pose, doors closed from the start, objects taken
//! out. Scenario files (`avs_format::scenario`) and `avs search`'s flags both go through
//! [`edit_environment`], and [`load_edited_world`] reads an environment file with them.

use crate::EvalError;
use avs_format::environment::Environment;
use avs_format::knowledge::Knowledge;
pub use avs_format::scenario::{RemoveObjects, Start};
use avs_sim::World;
use std::collections::BTreeSet;
use std::path::Path;

/// Which edit of [`edit_environment`] went wrong.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EditField {
    /// The `i`-th door to close.
    CloseDoor(usize),
    /// The `i`-th class to remove.
    RemoveClass(usize),
    /// The `i`-th object id to remove.
    RemoveId(usize),
}

/// Edits of an environment before a search: where the robot starts, doors closed from the
/// start, objects taken out (with whatever stands on or lies in them). The one home of the
/// world edits of scenario files and of `avs search`'s flags.
#[derive(Debug, Clone, Default)]
pub struct WorldEdits {
    /// The robot's start pose instead of the file's.
    pub start: Option<Start>,
    /// Doors closed from the start, by name.
    pub close_doors: Vec<String>,
    /// Objects to take out.
    pub remove: RemoveObjects,
}

/// Apply `edits` to `env` (named `env_name` in messages); an error names the edit and what is
/// expected.
pub fn edit_environment(
    env: &mut Environment,
    edits: &WorldEdits,
    env_name: &str,
) -> Result<(), (EditField, String)> {
    if let Some(s) = &edits.start {
        env.robot.start.x = s.x;
        env.robot.start.y = s.y;
        env.robot.start.yaw_deg = s.yaw_deg;
    }
    for (i, name) in edits.close_doors.iter().enumerate() {
        let known: Vec<&str> = env.doors.iter().map(|d| d.name.as_str()).collect();
        let known = known.join(", ");
        let door = env
            .doors
            .iter_mut()
            .find(|d| &d.name == name)
            .ok_or_else(|| {
                (
                    EditField::CloseDoor(i),
                    format!("unknown door `{name}`; one of the environment's doors ({known})"),
                )
            })?;
        door.open = false;
    }
    let r = &edits.remove;
    for (i, c) in r.classes.iter().enumerate() {
        if !env.objects.iter().any(|o| &o.class == c) {
            return Err((
                EditField::RemoveClass(i),
                format!("no object of class `{c}` in {env_name}"),
            ));
        }
    }
    for (i, id) in r.ids.iter().enumerate() {
        if !env.objects.iter().any(|o| &o.id == id) {
            return Err((
                EditField::RemoveId(i),
                format!("no object `{id}` in {env_name}"),
            ));
        }
    }
    let mut gone: BTreeSet<String> = env
        .objects
        .iter()
        .filter(|o| r.classes.contains(&o.class) || r.ids.contains(&o.id))
        .map(|o| o.id.clone())
        .collect();
    // Whatever stands on or lies in a removed object goes with it.
    loop {
        let more: Vec<String> = env
            .objects
            .iter()
            .filter(|o| !gone.contains(&o.id))
            .filter(|o| {
                o.on.as_ref().is_some_and(|s| gone.contains(s))
                    || o.r#in.as_ref().is_some_and(|s| gone.contains(s))
            })
            .map(|o| o.id.clone())
            .collect();
        if more.is_empty() {
            break;
        }
        gone.extend(more);
    }
    env.objects.retain(|o| !gone.contains(&o.id));
    Ok(())
}

/// Read the environment file `path`, check it as `avs validate` does (its class names too,
/// against `knowledge` when given) and apply `edits`; errors name the file and the edit
/// (`describe` turns an [`EditField`] into the caller's name for it, e.g. a flag).
pub fn load_edited_world(
    path: &Path,
    knowledge: Option<&Knowledge>,
    edits: &WorldEdits,
    describe: impl Fn(EditField) -> String,
) -> Result<World, EvalError> {
    crate::inputs::Input::read(path)?.edited_world(knowledge, edits, describe)
}
