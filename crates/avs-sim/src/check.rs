//! Checks of an environment that need its occupancy grid, on top of the map-free checks of
//! [`avs_format::check_env`].
//!
//! - the map loads: the image file exists and decodes, the ASCII grid has only known characters;
//! - the robot's start, room seeds, polygon corners, doors and objects lie inside the map;
//! - the robot's start, room seeds, door centres and object centres are not inside walls
//!   (the map holds walls only; furniture is given as objects);
//! - footprints and door openings are smaller than the map (they are rasterised into it);
//! - with the world built: each object lies in the room it names, each door's `rooms` are the
//!   rooms found on either side of its opening (along `yaw_deg`, from 3 cells to 1.5 m away),
//!   and the robot does not start inside a piece of furniture.
//!
//! A point is "inside a wall" when the grid cell containing it is occupied; the convention that
//! maps hold walls only (furniture comes from `objects`) is the one [`crate::world::World`] uses.

use crate::world::{load_grid, SimError, World};
use avs_format::environment::{Environment, MapSource};
use avs_format::knowledge::Knowledge;
use avs_format::Diagnostic;
use avs_map::grid::{Cell, MapError, OccupancyGrid};
use std::path::Path;

/// Every problem in `env` (a file named `file`, whose image paths are relative to `base_dir`):
/// the map-free checks of [`avs_format::check_env::check_environment`], then the geometric ones
/// (which run only when the map itself is sound). Diagnostics carry field paths but no positions;
/// [`check_environment_text`] adds them.
pub fn check_environment(
    file: &str,
    env: &Environment,
    base_dir: &Path,
    knowledge: Option<&Knowledge>,
) -> Vec<Diagnostic> {
    let mut out = avs_format::check_env::check_environment(file, env, knowledge);
    if out.iter().any(|d| d.path.starts_with("map")) {
        return out;
    }
    let grid = match load_map(file, env, base_dir) {
        Ok(g) => g,
        Err(d) => {
            out.push(*d);
            return out;
        }
    };
    geometry(file, env, &grid, &mut out);
    // The world (room labels, furniture) is only meaningful when names and places are sound.
    if out.is_empty() {
        world_checks(file, env, base_dir, grid.cells().len(), &mut out);
    }
    out
}

/// Parse an environment's text and check it: load errors, or every problem found by
/// [`check_environment`], each with the line and column of its field in `text`.
pub fn check_environment_text(
    file: &str,
    text: &str,
    base_dir: &Path,
    knowledge: Option<&Knowledge>,
) -> Vec<Diagnostic> {
    let mut out = match avs_format::check_env::load_environment(file, text) {
        Ok(env) => check_environment(file, &env, base_dir, knowledge),
        Err(e) => e.diagnostics,
    };
    avs_format::positions::locate(&mut out, text);
    out
}

fn load_map(
    file: &str,
    env: &Environment,
    base_dir: &Path,
) -> Result<OccupancyGrid, Box<Diagnostic>> {
    if let MapSource::Ros(r) = &env.map {
        let path = base_dir.join(&r.image);
        if !path.is_file() {
            return Err(Box::new(Diagnostic::new(
                file,
                "map.image",
                format!("image file `{}` not found", path.display()),
                "a PGM or PNG file, relative to the environment file",
            )));
        }
    }
    load_grid(env, base_dir).map_err(|e| {
        let (path, message, expected) = match e {
            SimError::Map(MapError::Io { path, source }) => (
                "map.image",
                format!("cannot read `{}`: {source}", path.display()),
                "a readable PGM or PNG file".to_string(),
            ),
            SimError::Map(MapError::Image { path, message }) => (
                "map.image",
                format!("cannot decode `{}`: {message}", path.display()),
                "a PGM or PNG image".to_string(),
            ),
            SimError::Map(MapError::Invalid { field, message }) => {
                let path = match field {
                    "ascii" => "map.ascii",
                    "resolution" => "map.resolution",
                    "origin" => "map.origin",
                    _ => "map",
                };
                // MapError messages read "what; expected what".
                let (m, x) = match message.split_once("; expected ") {
                    Some((m, x)) => (m.to_string(), format!("expected {x}")),
                    None => (message, "a map avs can load".to_string()),
                };
                (path, m, x)
            }
            other => ("map", other.to_string(), "a map avs can load".to_string()),
        };
        Box::new(Diagnostic::new(file, path, message, expected))
    })
}

/// Where a point falls in the grid.
enum Spot {
    Outside,
    Wall,
    Open,
}

fn spot(grid: &OccupancyGrid, x: f64, y: f64) -> Spot {
    let (c, r) = grid.world_to_cell(x, y);
    if !grid.contains(c, r) {
        Spot::Outside
    } else if grid.get_i(c, r) == Cell::Occupied {
        Spot::Wall
    } else {
        Spot::Open
    }
}

fn extent(grid: &OccupancyGrid) -> String {
    let [ox, oy] = grid.origin();
    let w = grid.width() as f64 * grid.resolution();
    let h = grid.height() as f64 * grid.resolution();
    format!("x in [{ox}, {}), y in [{oy}, {})", ox + w, oy + h)
}

fn geometry(file: &str, env: &Environment, grid: &OccupancyGrid, out: &mut Vec<Diagnostic>) {
    let mut place =
        |path: String, what: String, x: f64, y: f64, walls_ok: bool| match spot(grid, x, y) {
            // Non-finite coordinates are reported by the map-free checks already.
            _ if !(x.is_finite() && y.is_finite()) => {}
            Spot::Outside => out.push(Diagnostic::new(
                file,
                path,
                format!("{what} at ({x}, {y}) is outside the map"),
                format!("a point inside the map: {}", extent(grid)),
            )),
            Spot::Wall if !walls_ok => out.push(Diagnostic::new(
                file,
                path,
                format!("{what} at ({x}, {y}) is inside a wall"),
                "a point in free space (the map's occupied cells are walls)",
            )),
            _ => {}
        };
    let s = env.robot.start;
    place(
        "robot.start".into(),
        "the robot's start".into(),
        s.x,
        s.y,
        false,
    );
    for (i, room) in env.rooms.iter().enumerate() {
        if let Some(p) = room.seed {
            place(
                format!("rooms[{i}].seed"),
                format!("the seed of room `{}`", room.name),
                p.x,
                p.y,
                false,
            );
        }
        for (j, p) in room.polygon.iter().flatten().enumerate() {
            place(
                format!("rooms[{i}].polygon[{j}]"),
                format!("corner {j} of room `{}`", room.name),
                p.x,
                p.y,
                true,
            );
        }
    }
    for (i, d) in env.doors.iter().enumerate() {
        place(
            format!("doors[{i}].pose"),
            format!("door `{}`", d.name),
            d.pose.x,
            d.pose.y,
            false,
        );
    }
    for (i, o) in env.objects.iter().enumerate() {
        place(
            format!("objects[{i}].pose"),
            format!("object `{}`", o.id),
            o.pose.x,
            o.pose.y,
            false,
        );
    }
    // Footprints and door openings are rasterised into the grid: they must fit in the map.
    let span = (grid.width() + grid.height()) as f64 * grid.resolution();
    let too_big = |v: f64| v.is_finite() && v > span;
    for (i, d) in env.doors.iter().enumerate() {
        if too_big(d.width) {
            out.push(Diagnostic::new(
                file,
                format!("doors[{i}].width"),
                format!("door `{}` is {} m wide, more than the map", d.name, d.width),
                format!("a width below the map's extent ({span} m)"),
            ));
        }
    }
    for (i, o) in env.objects.iter().enumerate() {
        for (j, v) in o.size.iter().enumerate() {
            if too_big(*v) {
                out.push(Diagnostic::new(
                    file,
                    format!("objects[{i}].size[{j}]"),
                    format!("object `{}` is {v} m across, more than the map", o.id),
                    format!("a size below the map's extent ({span} m)"),
                ));
            }
        }
    }
}

/// Most cell visits spent labelling rooms (the world visits every cell once per door and per
/// polygon corner); beyond it the room checks would take minutes.
const MAX_LABEL_WORK: f64 = 2e8;

fn world_checks(
    file: &str,
    env: &Environment,
    base_dir: &Path,
    cells: usize,
    out: &mut Vec<Diagnostic>,
) {
    let passes = 1
        + env.doors.len()
        + env
            .rooms
            .iter()
            .map(|r| r.polygon.as_ref().map_or(0, Vec::len))
            .sum::<usize>();
    let work = cells as f64 * passes as f64;
    if work > MAX_LABEL_WORK {
        out.push(Diagnostic::new(
            file,
            "doors",
            format!(
                "{cells} map cells × {passes} doors and polygon corners are too many to label rooms"
            ),
            format!(
                "at most {MAX_LABEL_WORK:e} cell visits: fewer doors or corners, or a coarser map"
            ),
        ));
        return;
    }
    let world = match World::build(env.clone(), base_dir) {
        Ok(w) => w,
        Err(SimError::Invalid { field, message }) => {
            let (m, x) = match message.split_once("; expected ") {
                Some((m, x)) => (m.to_string(), format!("expected {x}")),
                None => (message, "a consistent environment".to_string()),
            };
            out.push(Diagnostic::new(file, field, m, x));
            return;
        }
        Err(e) => {
            out.push(Diagnostic::new(
                file,
                "",
                e.to_string(),
                "an environment the simulator can build",
            ));
            return;
        }
    };
    for (i, o) in env.objects.iter().enumerate() {
        let Some(named) = env.rooms.iter().position(|r| r.name == o.room) else {
            continue;
        };
        if let Some(actual) = world.room_at(o.pose.x, o.pose.y) {
            if actual != named {
                out.push(Diagnostic::new(
                    file,
                    format!("objects[{i}].room"),
                    format!(
                        "object `{}` at ({}, {}) lies in room `{}`, not `{}`",
                        o.id, o.pose.x, o.pose.y, env.rooms[actual].name, o.room
                    ),
                    "the room that contains the object's position",
                ));
            }
        }
    }
    for (i, d) in env.doors.iter().enumerate() {
        let named: Vec<usize> = d
            .rooms
            .iter()
            .filter_map(|n| env.rooms.iter().position(|r| r.name == *n))
            .collect();
        if named.len() != 2 {
            continue;
        }
        let sides = [door_side(&world, d, -1.0), door_side(&world, d, 1.0)];
        let [Some(a), Some(b)] = sides else {
            continue;
        };
        let ok = (a == named[0] && b == named[1]) || (a == named[1] && b == named[0]);
        if !ok {
            let name = |k: usize| env.rooms[k].name.as_str();
            let message = if a == b {
                format!(
                    "both sides of door `{}` lie in room `{}` (is the door's pose or yaw_deg wrong, or is there another opening?)",
                    d.name,
                    name(a)
                )
            } else {
                format!(
                    "the map puts rooms `{}` and `{}` on the two sides of door `{}`",
                    name(a),
                    name(b),
                    d.name
                )
            };
            out.push(Diagnostic::new(
                file,
                format!("doors[{i}].rooms"),
                message,
                format!(
                    "the rooms on either side of the opening along yaw_deg {} ({} and {} are named)",
                    d.pose.yaw_deg,
                    name(named[0]),
                    name(named[1])
                ),
            ));
        }
    }
    let s = env.robot.start;
    let (c, r) = world.truth.world_to_cell(s.x, s.y);
    if world.truth.get_i(c, r) == Cell::Occupied {
        out.push(Diagnostic::new(
            file,
            "robot.start",
            format!(
                "the robot's start ({}, {}) is inside a piece of furniture",
                s.x, s.y
            ),
            "a point in free space, clear of landmark footprints",
        ));
    }
}

/// The ground-truth room on one side (`sign` ±1) of a door, along its direction of passage:
/// the first labelled cell from 3 cells (clear of the opening) up to 1.5 m away.
fn door_side(world: &World, d: &avs_format::environment::Door, sign: f64) -> Option<usize> {
    let yaw = d.pose.yaw_deg.to_radians();
    let (px, py) = (yaw.cos(), yaw.sin());
    let res = world.walls.resolution();
    let steps = ((1.5 / res).ceil() as usize).clamp(4, 1000);
    (3..=steps).find_map(|k| {
        let t = sign * k as f64 * res;
        world.room_at(d.pose.x + px * t, d.pose.y + py * t)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const BASE: &str = "kind: environment\nname: t\nmap:\n  resolution: 1.0\n  ascii: |\n    #####\n    #...#\n    #...#\n    #####\nrooms: [{name: a, category: office, seed: {x: 2.5, y: 2.5}}]\n";

    fn check(extra: &str) -> Vec<Diagnostic> {
        check_environment_text("t.yaml", &format!("{BASE}{extra}"), Path::new("."), None)
    }

    #[test]
    fn a_sound_environment_passes() {
        assert_eq!(check("robot: {start: {x: 1.5, y: 1.5}}\n"), vec![]);
    }

    #[test]
    fn robot_in_a_wall_and_object_outside_the_map_are_located() {
        let d = check("robot: {start: {x: 0.5, y: 0.5}}\nobjects:\n  - {id: m, class: mug, role: target, room: a, pose: {x: 9, y: 1}, size: [0.1, 0.1, 0.1]}\n");
        let wall = d.iter().find(|d| d.path == "robot.start").expect("robot");
        assert!(wall.message.contains("inside a wall"), "{wall}");
        assert_eq!(wall.line, Some(11));
        let out = d
            .iter()
            .find(|d| d.path == "objects[0].pose")
            .expect("object");
        assert!(out.message.contains("outside the map"), "{out}");
        assert_eq!(out.line, Some(13));
    }

    use proptest::prelude::*;

    fn number() -> impl Strategy<Value = f64> {
        prop_oneof![
            -1.0f64..6.0,
            any::<f64>(),
            Just(f64::NAN),
            Just(f64::INFINITY),
            Just(1e300),
            Just(0.0),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 200, failure_persistence: None, ..ProptestConfig::default() })]

        /// Any numbers in poses, sizes, widths and seeds: the checks return (no panic, no
        /// runaway rasterisation) and every diagnostic names a field.
        #[test]
        fn random_geometry_is_checked_without_panicking(
            v in proptest::collection::vec(number(), 12),
        ) {
            let text = format!(
                "{BASE}doors: [{{name: d, pose: {{x: {}, y: {}}}, width: {}}}]\nobjects:\n  - {{id: t, class: table, role: landmark, room: a, pose: {{x: {}, y: {}}}, size: [{}, {}, 1]}}\n  - {{id: m, class: mug, role: target, room: a, on: t, pose: {{x: {}, y: {}, z: 1}}, size: [0.1, 0.1, 0.1]}}\nrobot: {{start: {{x: {}, y: {}, yaw_deg: {}}}}}\n",
                yaml(v[0]), yaml(v[1]), yaml(v[2]), yaml(v[3]), yaml(v[4]), yaml(v[5]),
                yaml(v[6]), yaml(v[7]), yaml(v[8]), yaml(v[9]), yaml(v[10]), yaml(v[11]),
            );
            let d = check_environment_text("t.yaml", &text, Path::new("."), None);
            prop_assert!(d.iter().all(|d| !d.path.is_empty() && d.line.is_some()), "{d:?}");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 300, failure_persistence: None, ..ProptestConfig::default() })]

        /// Random character edits of a valid two-room environment: whatever still parses goes
        /// through every check, including building the world, and the checks return.
        #[test]
        fn mutated_environments_are_checked_without_panicking(
            edits in proptest::collection::vec((any::<usize>(), 0usize..18), 1..8),
        ) {
            const GOOD: &str = include_str!("../../../tests/validate/good/two_rooms.yaml");
            const CHARS: &[u8] = b"0123456789.-#\n: [],{}e";
            let mut bytes = GOOD.as_bytes().to_vec();
            for (at, c) in edits {
                let i = at % bytes.len();
                bytes[i] = CHARS[c % CHARS.len()];
            }
            let text = String::from_utf8_lossy(&bytes);
            let d = check_environment_text("m.yaml", &text, Path::new("."), None);
            prop_assert!(d.iter().all(|d| d.file == "m.yaml" && !d.expected.is_empty()));
        }
    }

    /// A float as YAML writes it.
    fn yaml(v: f64) -> String {
        if v.is_nan() {
            ".nan".into()
        } else if v.is_infinite() {
            if v > 0.0 {
                ".inf".into()
            } else {
                "-.inf".into()
            }
        } else {
            format!("{v:e}")
        }
    }

    #[test]
    fn a_missing_image_is_reported_at_map_image() {
        let text = "kind: environment\nname: t\nmap: {image: no-such.pgm, resolution: 0.05}\nrobot: {start: {x: 1, y: 1}}\n";
        let d = check_environment_text("t.yaml", text, Path::new("."), None);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].path, "map.image");
        assert!(d[0].message.contains("not found"));
        assert_eq!(d[0].line, Some(3));
    }
}
