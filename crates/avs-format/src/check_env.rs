//! Checks of an environment that need no image: names and references, numbers and ranges,
//! agreement with a knowledge file, and — for inline ASCII maps — the doors against the walls.
//!
//! What is checked:
//! - every number is finite (YAML allows `.nan` and `.inf`);
//! - sizes, widths, resolution, radius, speed, ranges are positive; occupancy thresholds are
//!   probabilities with `free_thresh ≤ occupied_thresh`; angle limits are ordered; the laser
//!   reaches at most [`MAX_LASER_RANGE_M`], sees at most 360° and has at most 100,000 beams;
//! - room names, door names and object ids are unique (each among its own kind);
//! - an object's `room`, a door's `rooms`, an object's `on` / `in` name things that exist;
//!   an object is not `on` and `in` at once, not on/in itself, not in a cycle, and the
//!   supporting object is a landmark in the same room whose (yawed) footprint, plus 5 cm, holds
//!   the object's position;
//! - heights: an object `on` a landmark stands on its top — its `pose.z` is the landmark's
//!   `pose.z + size[2]` within [`HEIGHT_SLACK`]; an object `in` a landmark has its `pose.z`
//!   between the landmark's `pose.z` and its top (within the same slack);
//! - the robot fits through the doors: a door narrower than the robot's diameter
//!   (2 × `robot.radius`) is an error naming the door, and when every door is narrower the one
//!   error is the robot's radius (a robot wider than every door cannot leave its room);
//! - an ASCII map is a rectangle: every row as long as the first (the simulator would pad short
//!   rows with unknown cells, which hides a stripped trailing space or a lost character);
//! - for an ASCII map, each door sits across a gap of the walls: the line along its `yaw_deg`
//!   is free for half a metre each side of its centre, and the gap across it is at least its
//!   width less one cell ([`crate::check_doors`]);
//! - with a knowledge file: room categories and object classes are ones it names, and objects
//!   with role `landmark` have a landmark class.
//!
//! The other geometric checks (the map loads, things inside the map and not inside walls, rooms
//! on both sides of doors) need the decoded grid and live in `avs-sim` (`avs_sim::check`).

use crate::diag::Diagnostic;
use crate::environment::{Environment, MapSource, ObjectRole, Point, Pose};
use crate::knowledge::Knowledge;
use std::collections::{HashMap, HashSet};

/// Collects diagnostics for one file.
struct Report<'a> {
    file: &'a str,
    out: Vec<Diagnostic>,
}

impl Report<'_> {
    fn push(&mut self, path: String, message: String, expected: impl Into<String>) {
        self.out
            .push(Diagnostic::new(self.file, path, message, expected));
    }

    fn finite(&mut self, path: String, v: f64) -> bool {
        if v.is_finite() {
            true
        } else {
            self.push(
                path,
                format!("{v} is not a finite number"),
                "a finite number",
            );
            false
        }
    }

    fn positive(&mut self, path: String, v: f64, unit: &str) {
        if self.finite(path.clone(), v) && v <= 0.0 {
            self.push(
                path,
                format!("{v} is not positive"),
                format!("a positive number of {unit}"),
            );
        }
    }

    fn probability(&mut self, path: String, v: f64) {
        if self.finite(path.clone(), v) && !(0.0..=1.0).contains(&v) {
            self.push(
                path,
                format!("{v} is outside [0, 1]"),
                "a probability between 0 and 1",
            );
        }
    }

    fn point(&mut self, path: &str, p: &Point) {
        self.finite(format!("{path}.x"), p.x);
        self.finite(format!("{path}.y"), p.y);
    }

    fn pose(&mut self, path: &str, p: &Pose) {
        self.finite(format!("{path}.x"), p.x);
        self.finite(format!("{path}.y"), p.y);
        self.finite(format!("{path}.z"), p.z);
        self.finite(format!("{path}.yaw_deg"), p.yaw_deg);
    }

    fn ordered(&mut self, path: &str, v: [f64; 2], lo: f64, hi: f64) {
        let a = self.finite(format!("{path}[0]"), v[0]);
        let b = self.finite(format!("{path}[1]"), v[1]);
        if a && b && !(lo <= v[0] && v[0] <= v[1] && v[1] <= hi) {
            self.push(
                path.to_string(),
                format!(
                    "[{}, {}] is not an ordered range within [{lo}, {hi}]",
                    v[0], v[1]
                ),
                format!("[min, max] with {lo} ≤ min ≤ max ≤ {hi}"),
            );
        }
    }
}

/// Index of each name, reporting duplicates (`what` names the kind of thing).
fn unique<'e>(
    r: &mut Report,
    names: impl Iterator<Item = (String, &'e str)>,
    what: &str,
) -> HashMap<&'e str, usize> {
    let mut seen: HashMap<&str, usize> = HashMap::new();
    for (i, (path, name)) in names.enumerate() {
        if name.is_empty() {
            r.push(
                path,
                format!("empty {what}"),
                format!("a non-empty, unique {what}"),
            );
            continue;
        }
        if let Some(first) = seen.get(name) {
            r.push(
                path,
                format!("duplicate {what} `{name}` (also item {first})"),
                format!("a unique {what}"),
            );
        } else {
            seen.insert(name, i);
        }
    }
    seen
}

/// A sorted, comma-separated list of names for "expected one of" messages (at most 12 shown).
fn one_of<'a>(names: impl Iterator<Item = &'a str>) -> String {
    let mut v: Vec<&str> = names.collect();
    v.sort_unstable();
    v.dedup();
    if v.is_empty() {
        return "(none defined)".to_string();
    }
    let more = v.len().saturating_sub(12);
    let mut s = v
        .iter()
        .take(12)
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ");
    if more > 0 {
        s.push_str(&format!(" and {more} more"));
    }
    s
}

/// Longest laser range accepted, metres.
///
/// Planar laser scanners reach 10–80 m indoors and long-range ones about 300 m, so a larger
/// value is a unit slip (millimetres for metres) or a placeholder like `1e6`. The simulator
/// clips rays to the map's diagonal whatever this says (`avs_map::raycast`), so the bound is
/// about catching the mistake, not about run time; 1 km leaves every real sensor valid.
pub const MAX_LASER_RANGE_M: f64 = 1000.0;

/// Slack around a landmark's footprint for objects standing on or lying in it, metres.
const FOOTPRINT_SLACK: f64 = 0.05;

/// How far an object's `pose.z` may be from the top of the landmark it stands `on` (or outside
/// the heights of one it lies `in`), metres.
pub const HEIGHT_SLACK: f64 = 0.05;

/// The first row of an ASCII map whose length differs from the first row's: its 1-based number,
/// its length and the first row's length (in characters, as the simulator counts cells), and how
/// many rows differ in all.
fn ragged_row(ascii: &str) -> Option<(usize, usize, usize, usize)> {
    let mut lens = ascii.lines().map(|l| l.chars().count());
    let first = lens.next()?;
    let mut found = None;
    let mut differ = 0;
    for (i, n) in lens.enumerate() {
        if n != first {
            differ += 1;
            found.get_or_insert((i + 2, n));
        }
    }
    found.map(|(row, n)| (row, n, first, differ))
}

/// `v` rounded to millimetres, for messages.
fn mm(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

/// Whether a point lies over a landmark's (yawed) footprint, with [`FOOTPRINT_SLACK`]. Points or
/// landmarks with non-finite numbers pass (they are reported elsewhere).
fn over_footprint(p: &Pose, base: &crate::environment::Object) -> bool {
    let (dx, dy) = (p.x - base.pose.x, p.y - base.pose.y);
    let yaw = base.pose.yaw_deg.to_radians();
    let u = dx * yaw.cos() + dy * yaw.sin();
    let v = -dx * yaw.sin() + dy * yaw.cos();
    let inside = u.abs() <= base.size[0].abs() / 2.0 + FOOTPRINT_SLACK
        && v.abs() <= base.size[1].abs() / 2.0 + FOOTPRINT_SLACK;
    inside || !(u.is_finite() && v.is_finite() && base.size.iter().all(|s| s.is_finite()))
}

/// Check everything about `env` that does not need the occupancy grid; `knowledge`, when given,
/// supplies the room categories and object classes that may be used. Diagnostics carry field
/// paths but no positions (see [`crate::positions::locate`]).
pub fn check_environment(
    file: &str,
    env: &Environment,
    knowledge: Option<&Knowledge>,
) -> Vec<Diagnostic> {
    let mut r = Report {
        file,
        out: Vec::new(),
    };
    if env.name.trim().is_empty() {
        r.push(
            "name".into(),
            "empty name".into(),
            "a short, non-empty name",
        );
    }

    // Map.
    let before_map = r.out.len();
    match &env.map {
        MapSource::Ros(m) => {
            if m.image.trim().is_empty() {
                r.push(
                    "map.image".into(),
                    "empty image path".into(),
                    "a PGM or PNG file, relative to this file",
                );
            }
            r.positive("map.resolution".into(), m.resolution, "metres per pixel");
            for (i, v) in m.origin.iter().enumerate() {
                r.finite(format!("map.origin[{i}]"), *v);
            }
            if m.negate > 1 {
                r.push(
                    "map.negate".into(),
                    format!("{} is not 0 or 1", m.negate),
                    "0 (white is free) or 1 (white is occupied)",
                );
            }
            r.probability("map.occupied_thresh".into(), m.occupied_thresh);
            r.probability("map.free_thresh".into(), m.free_thresh);
            if m.free_thresh > m.occupied_thresh {
                r.push(
                    "map.free_thresh".into(),
                    format!(
                        "free_thresh {} is above occupied_thresh {}",
                        m.free_thresh, m.occupied_thresh
                    ),
                    "free_thresh ≤ occupied_thresh",
                );
            }
        }
        MapSource::Ascii(m) => {
            if m.ascii.trim().is_empty() {
                r.push(
                    "map.ascii".into(),
                    "empty ASCII map".into(),
                    "rows of `#` (occupied), `.` (free), `?` (unknown)",
                );
            }
            if let Some((row, n, first, differ)) = ragged_row(&m.ascii) {
                let others = if differ > 1 {
                    format!(" ({} more rows differ)", differ - 1)
                } else {
                    String::new()
                };
                r.push(
                    "map.ascii".into(),
                    format!(
                        "row {row} of the map (line {row} of `ascii`) is {n} cells long but row 1 is {first}{others}"
                    ),
                    "rows of equal length: pad with `?` (unknown) or `#`; an editor may have stripped trailing spaces",
                );
            }
            r.positive("map.resolution".into(), m.resolution, "metres per cell");
            for (i, v) in m.origin.iter().enumerate() {
                r.finite(format!("map.origin[{i}]"), *v);
            }
        }
    }
    let map_sound = r.out.len() == before_map;

    // Names for "one of …" hints and knowledge look-ups, built once (files can be large).
    let categories: HashSet<&str> = knowledge
        .map(|k| k.room_categories.iter().map(String::as_str).collect())
        .unwrap_or_default();
    let classes: HashMap<&str, &crate::knowledge::ObjectClass> = knowledge
        .map(|k| {
            k.object_classes
                .iter()
                .map(|c| (c.name.as_str(), c))
                .collect()
        })
        .unwrap_or_default();
    let category_list = one_of(categories.iter().copied());
    let class_list = one_of(classes.keys().copied());
    let object_list = one_of(env.objects.iter().map(|x| x.id.as_str()));

    // Rooms.
    let rooms = unique(
        &mut r,
        env.rooms
            .iter()
            .enumerate()
            .map(|(i, x)| (format!("rooms[{i}].name"), x.name.as_str())),
        "room name",
    );
    for (i, room) in env.rooms.iter().enumerate() {
        if let Some(s) = &room.seed {
            r.point(&format!("rooms[{i}].seed"), s);
        }
        if let Some(poly) = &room.polygon {
            if poly.len() < 3 {
                r.push(
                    format!("rooms[{i}].polygon"),
                    format!("{} points", poly.len()),
                    "a polygon of at least 3 points",
                );
            }
            for (j, p) in poly.iter().enumerate() {
                r.point(&format!("rooms[{i}].polygon[{j}]"), p);
            }
        }
        if room.seed.is_none() && room.polygon.is_none() {
            r.push(
                format!("rooms[{i}]"),
                format!("room `{}` has neither `seed` nor `polygon`", room.name),
                "a `seed` point inside the room or its outline as a `polygon`",
            );
        }
        if knowledge.is_some() && !categories.contains(room.category.as_str()) {
            r.push(
                format!("rooms[{i}].category"),
                format!("unknown room category `{}`", room.category),
                format!("one of the knowledge file's room_categories: {category_list}"),
            );
        }
    }
    let room_list = one_of(env.rooms.iter().map(|x| x.name.as_str()));

    // Doors.
    unique(
        &mut r,
        env.doors
            .iter()
            .enumerate()
            .map(|(i, x)| (format!("doors[{i}].name"), x.name.as_str())),
        "door name",
    );
    for (i, d) in env.doors.iter().enumerate() {
        r.pose(&format!("doors[{i}].pose"), &d.pose);
        r.positive(format!("doors[{i}].width"), d.width, "metres");
        if !(d.rooms.is_empty() || d.rooms.len() == 2) {
            r.push(
                format!("doors[{i}].rooms"),
                format!("{} rooms", d.rooms.len()),
                "the two rooms the door joins, or none",
            );
        }
        for (j, name) in d.rooms.iter().enumerate() {
            if !rooms.contains_key(name.as_str()) {
                r.push(
                    format!("doors[{i}].rooms[{j}]"),
                    format!("unknown room `{name}`"),
                    format!("one of the rooms: {room_list}"),
                );
            }
        }
        if d.rooms.len() == 2 && d.rooms[0] == d.rooms[1] {
            r.push(
                format!("doors[{i}].rooms"),
                format!("the door joins room `{}` to itself", d.rooms[0]),
                "two different rooms",
            );
        }
    }

    // Objects.
    let ids = unique(
        &mut r,
        env.objects
            .iter()
            .enumerate()
            .map(|(i, x)| (format!("objects[{i}].id"), x.id.as_str())),
        "object id",
    );
    // (object, landmark it rests on, "on" / "in"): heights are checked once cycles are known.
    let mut heights: Vec<(usize, usize, &str)> = Vec::new();
    for (i, o) in env.objects.iter().enumerate() {
        let at = format!("objects[{i}]");
        r.pose(&format!("{at}.pose"), &o.pose);
        for (j, s) in o.size.iter().enumerate() {
            r.positive(format!("{at}.size[{j}]"), *s, "metres");
        }
        if !rooms.contains_key(o.room.as_str()) {
            r.push(
                format!("{at}.room"),
                format!("unknown room `{}`", o.room),
                format!("one of the rooms: {room_list}"),
            );
        }
        if knowledge.is_some() {
            if let Some(c) = classes.get(o.class.as_str()) {
                if o.role == ObjectRole::Landmark && !c.landmark {
                    r.push(
                        format!("{at}.role"),
                        format!(
                            "object `{}` is a landmark but class `{}` is not a landmark class",
                            o.id, o.class
                        ),
                        "role `target` or `distractor`, or `landmark: true` on the class in the knowledge file",
                    );
                }
            } else {
                r.push(
                    format!("{at}.class"),
                    format!("unknown object class `{}`", o.class),
                    format!("one of the knowledge file's object_classes: {}", class_list),
                );
            }
        }
        if o.on.is_some() && o.r#in.is_some() {
            r.push(
                format!("{at}.in"),
                "the object is both `on` and `in` another object".into(),
                "at most one of `on` and `in`",
            );
        }
        for (field, support) in [("on", &o.on), ("in", &o.r#in)] {
            let Some(s) = support else { continue };
            let path = format!("{at}.{field}");
            match ids.get(s.as_str()) {
                None => r.push(
                    path,
                    format!("unknown object `{s}`"),
                    format!("the id of another object: {}", object_list),
                ),
                Some(&j) if j == i => r.push(
                    path,
                    format!("the object is {field} itself"),
                    "the id of another object (a landmark)",
                ),
                Some(&j) => {
                    let base = &env.objects[j];
                    if base.role != ObjectRole::Landmark {
                        r.push(
                            path.clone(),
                            format!("object `{s}` is not a landmark"),
                            "the id of a landmark (role: landmark) to stand on or lie in",
                        );
                    }
                    if base.role == ObjectRole::Landmark {
                        heights.push((i, j, field));
                    }
                    if base.room != o.room && rooms.contains_key(o.room.as_str()) {
                        r.push(
                            path.clone(),
                            format!(
                                "object `{s}` is in room `{}` but this object is in `{}`",
                                base.room, o.room
                            ),
                            "a landmark in the same room",
                        );
                    } else if !over_footprint(&o.pose, base) {
                        r.push(
                            format!("{at}.pose"),
                            format!(
                                "({}, {}) is not over the footprint of `{s}` (centre ({}, {}), {} m × {} m)",
                                o.pose.x, o.pose.y, base.pose.x, base.pose.y, base.size[0], base.size[1]
                            ),
                            format!("a position on the top of / inside `{s}`"),
                        );
                    }
                }
            }
        }
    }
    // Support cycles (a on b, b on a). Each object rests on at most one other, so one walk per
    // chain with three-state marks finds every cycle in linear time.
    let next: Vec<Option<usize>> = env
        .objects
        .iter()
        .map(|o| {
            o.on.as_ref()
                .or(o.r#in.as_ref())
                .and_then(|s| ids.get(s.as_str()).copied())
        })
        .collect();
    let (new, walking, done) = (0u8, 1u8, 2u8);
    let mut state = vec![new; env.objects.len()];
    let mut in_cycle = Vec::new();
    for start in 0..env.objects.len() {
        let mut walk = Vec::new();
        let mut cur = Some(start);
        while let Some(i) = cur {
            if state[i] == done {
                break;
            }
            if state[i] == walking {
                let from = walk.iter().position(|&k| k == i).unwrap_or(walk.len());
                // A cycle of one is "on itself", reported above.
                if walk.len() - from > 1 {
                    in_cycle.extend_from_slice(&walk[from..]);
                }
                break;
            }
            state[i] = walking;
            walk.push(i);
            cur = next[i];
        }
        for k in walk {
            state[k] = done;
        }
    }
    in_cycle.sort_unstable();
    // Heights along a cycle cannot all agree; the cycle is the error.
    for (i, j, field) in heights {
        if in_cycle.binary_search(&i).is_err() {
            height_on_landmark(
                &mut r,
                &format!("objects[{i}]"),
                &env.objects[i],
                &env.objects[j],
                field,
            );
        }
    }
    for i in in_cycle {
        let o = &env.objects[i];
        r.push(
            format!("objects[{i}].{}", if o.on.is_some() { "on" } else { "in" }),
            format!("object `{}` rests on itself through a cycle", o.id),
            "a chain of `on`/`in` that ends at an object on the floor",
        );
    }

    // Robot and sensors.
    r.pose("robot.start", &env.robot.start);
    r.positive("robot.radius".into(), env.robot.radius, "metres");
    r.positive("robot.speed".into(), env.robot.speed, "metres per second");
    robot_through_doors(&mut r, env);
    r.positive("laser.range".into(), env.laser.range, "metres");
    if env.laser.range > MAX_LASER_RANGE_M {
        r.push(
            "laser.range".into(),
            format!(
                "{} m is beyond the reach of any planar laser",
                env.laser.range
            ),
            format!(
                "a range in metres of at most {MAX_LASER_RANGE_M} (real scanners reach 10–300 m)"
            ),
        );
    }
    if r.finite("laser.fov_deg".into(), env.laser.fov_deg)
        && !(env.laser.fov_deg > 0.0 && env.laser.fov_deg <= 360.0)
    {
        r.push(
            "laser.fov_deg".into(),
            format!("{} is outside (0, 360]", env.laser.fov_deg),
            "a field of view in degrees, above 0 and at most 360",
        );
    }
    if env.laser.beams == 0 || env.laser.beams > 100_000 {
        r.push(
            "laser.beams".into(),
            format!("{} beams", env.laser.beams),
            "between 1 and 100000 beams",
        );
    }
    let c = &env.camera;
    for (name, v) in [("hfov_deg", c.hfov_deg), ("vfov_deg", c.vfov_deg)] {
        if r.finite(format!("camera.{name}"), v) && !(v > 0.0 && v < 180.0) {
            r.push(
                format!("camera.{name}"),
                format!("{v} is outside (0, 180)"),
                "a field of view in degrees, above 0 and below 180",
            );
        }
    }
    r.ordered("camera.pan_deg", c.pan_deg, -360.0, 360.0);
    r.ordered("camera.tilt_deg", c.tilt_deg, -90.0, 90.0);
    if r.finite("camera.max_zoom".into(), c.max_zoom) && c.max_zoom < 1.0 {
        r.push(
            "camera.max_zoom".into(),
            format!("{} is below 1", c.max_zoom),
            "a zoom factor of at least 1",
        );
    }
    if r.finite("camera.height".into(), c.height) && c.height < 0.0 {
        r.push(
            "camera.height".into(),
            format!("{} is negative", c.height),
            "a height above the floor in metres (≥ 0)",
        );
    }

    // Doors against the walls, for maps given inline (an image map is decoded by avs-sim).
    if let (true, MapSource::Ascii(m)) = (map_sound, &env.map) {
        if let Some(walls) = crate::check_doors::AsciiWalls::parse(&m.ascii, m.resolution, m.origin)
        {
            r.out
                .extend(crate::check_doors::check_door_openings(file, env, &walls));
        }
    }
    r.out
}

/// The height of object `o` (at path `at`) against the landmark `base` it is `on` or `in`
/// (`field`). Non-finite or non-positive numbers are reported elsewhere and skip the check.
fn height_on_landmark(
    r: &mut Report,
    at: &str,
    o: &crate::environment::Object,
    base: &crate::environment::Object,
    field: &str,
) {
    let (z, floor, h) = (o.pose.z, base.pose.z, base.size[2]);
    if !(z.is_finite() && floor.is_finite() && h.is_finite() && h > 0.0) {
        return;
    }
    let top = floor + h;
    let id = &base.id;
    if field == "on" && (z - top).abs() > HEIGHT_SLACK {
        r.push(
            format!("{at}.pose.z"),
            format!(
                "z = {z} but `{id}`, which the object stands on, has its top at {} m",
                mm(top)
            ),
            format!(
                "z = {} (the landmark's pose.z {floor} plus its height size[2] {h}; within {HEIGHT_SLACK} m): an object's z is the height of its base",
                mm(top)
            ),
        );
    } else if field == "in" && !(floor - HEIGHT_SLACK..=top + HEIGHT_SLACK).contains(&z) {
        r.push(
            format!("{at}.pose.z"),
            format!(
                "z = {z} but `{id}`, which the object lies in, spans heights {floor} to {} m",
                mm(top)
            ),
            format!(
                "a z between {floor} and {} (inside `{id}`): an object's z is the height of its base",
                mm(top)
            ),
        );
    }
}

/// A door narrower than the robot's diameter is an error at the door; when every door is, the one
/// error is at `robot.radius`. Non-finite or non-positive numbers are reported elsewhere.
fn robot_through_doors(r: &mut Report, env: &Environment) {
    let radius = env.robot.radius;
    if !(radius.is_finite() && radius > 0.0) || env.doors.is_empty() {
        return;
    }
    let across = 2.0 * radius;
    let valid = |w: f64| w.is_finite() && w > 0.0;
    // Tolerance for widths written to the millimetre.
    let narrow = |w: f64| valid(w) && w + 1e-9 < across;
    let narrow_doors: Vec<usize> = (0..env.doors.len())
        .filter(|&i| narrow(env.doors[i].width))
        .collect();
    if narrow_doors.is_empty() {
        return;
    }
    if narrow_doors.len() == env.doors.len() {
        let widest = env
            .doors
            .iter()
            .max_by(|a, b| a.width.total_cmp(&b.width))
            .map(|d| (d.name.as_str(), d.width))
            .unwrap_or_default();
        r.push(
            "robot.radius".into(),
            format!(
                "the robot is {} m across (radius {radius}) but the widest door, `{}`, is {} m wide: it cannot leave its room",
                mm(across),
                widest.0,
                widest.1
            ),
            format!(
                "a radius of at most {} m (half the widest door), or wider doors",
                mm(widest.1 / 2.0)
            ),
        );
        return;
    }
    for i in narrow_doors {
        let d = &env.doors[i];
        r.push(
            format!("doors[{i}].width"),
            format!(
                "door `{}` is {} m wide, narrower than the robot ({} m across: robot.radius {radius})",
                d.name,
                d.width,
                mm(across)
            ),
            format!(
                "a width of at least {} m (the robot's diameter), or a smaller robot.radius",
                mm(across)
            ),
        );
    }
}

/// Parse an environment's text, reporting a map that fits neither form with the error of the
/// form it was meant to be (an `image:` map is read as a ROS map, otherwise as an ASCII map).
pub fn load_environment(file: &str, text: &str) -> Result<Environment, crate::LoadError> {
    let err = match crate::load::load_yaml_str_explained::<Environment>(file, text) {
        Ok(env) => return Ok(env),
        Err(e) => e,
    };
    if err.diagnostics.len() == 1
        && err.diagnostics[0].path == "map"
        && err.diagnostics[0].message == crate::load::UNTAGGED_MISMATCH
    {
        // The text passed the bounds walk; re-read only the map to say what is wrong inside it.
        #[derive(serde::Deserialize)]
        struct MapOnly {
            map: serde_yaml::Value,
        }
        if let Ok(m) = serde_yaml::from_str::<MapOnly>(text) {
            let sub = serde_yaml::to_string(&m.map).unwrap_or_default();
            let is_ros = m.map.get("image").is_some();
            let inner = if is_ros {
                crate::load::load_yaml_str_explained::<crate::environment::RosMap>(file, &sub).err()
            } else {
                crate::load::load_yaml_str_explained::<crate::environment::AsciiMap>(file, &sub)
                    .err()
            };
            if let Some(inner) = inner {
                let mut ds: Vec<Diagnostic> = inner
                    .diagnostics
                    .into_iter()
                    .map(|mut d| {
                        d.path = if d.path.is_empty() {
                            "map".into()
                        } else {
                            format!("map.{}", d.path)
                        };
                        d.line = None;
                        d.column = None;
                        if !is_ros && d.message.contains("missing field `ascii`") {
                            d.expected =
                                "a ROS map (`image:`, `resolution:`, …) or an ASCII map (`ascii:`, `resolution:`)".into();
                        }
                        d
                    })
                    .collect();
                crate::positions::locate(&mut ds, text);
                return Err(crate::LoadError { diagnostics: ds });
            }
        }
    }
    Err(err)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env(extra: &str) -> Environment {
        let text = format!(
            "kind: environment\nname: t\nmap: {{ ascii: \"###\\n#.#\\n###\\n\", resolution: 1.0 }}\nrobot: {{ start: {{ x: 1.5, y: 1.5 }} }}\n{extra}"
        );
        crate::load_yaml_str("t.yaml", &text).unwrap()
    }

    #[test]
    fn a_minimal_environment_has_no_problems() {
        assert_eq!(check_environment("t.yaml", &env(""), None), vec![]);
    }

    #[test]
    fn unknown_room_and_support_are_named_with_their_paths() {
        let e = env("rooms: [{name: a, category: office, seed: {x: 1.5, y: 1.5}}]\nobjects:\n  - {id: t, class: table, role: landmark, pose: {x: 1, y: 1}, size: [1, 1, 1], room: b}\n  - {id: m, class: mug, role: target, pose: {x: 1, y: 1}, size: [1, 1, 1], room: a, on: nothing}\n");
        let d = check_environment("t.yaml", &e, None);
        let paths: Vec<&str> = d.iter().map(|d| d.path.as_str()).collect();
        assert!(paths.contains(&"objects[0].room"), "{d:?}");
        assert!(paths.contains(&"objects[1].on"), "{d:?}");
    }

    #[test]
    fn support_cycles_are_found_and_long_chains_are_not_cycles() {
        // Each object stands on the top of the one below (z = its base z + its height 1).
        let obj = |id: &str, on: &str, z: usize| {
            format!("  - {{id: {id}, class: table, role: landmark, pose: {{x: 1, y: 1, z: {z}}}, size: [1, 1, 1], room: a, on: {on}}}\n")
        };
        let rooms = "rooms: [{name: a, category: office, seed: {x: 1.5, y: 1.5}}]\nobjects:\n";
        let mut chain = String::from(rooms);
        chain.push_str("  - {id: o0, class: table, role: landmark, pose: {x: 1, y: 1}, size: [1, 1, 1], room: a}\n");
        for i in 1..2000 {
            chain.push_str(&obj(&format!("o{i}"), &format!("o{}", i - 1), i));
        }
        assert_eq!(check_environment("t.yaml", &env(&chain), None), vec![]);
        let cycle = format!(
            "{rooms}{}{}{}",
            obj("x", "y", 0),
            obj("y", "z", 0),
            obj("z", "x", 0)
        );
        let d = check_environment("t.yaml", &env(&cycle), None);
        let paths: Vec<&str> = d.iter().map(|d| d.path.as_str()).collect();
        assert_eq!(paths, ["objects[0].on", "objects[1].on", "objects[2].on"]);
    }

    /// Issue 18: a laser range of 1e6 m validated, and each scan then cast fov × range /
    /// resolution rays; it is now an input error at the field's line and column.
    #[test]
    fn an_absurd_laser_range_is_rejected_at_its_line() {
        let text = "kind: environment\nname: t\nmap: { ascii: \"###\\n#.#\\n###\\n\", resolution: 1.0 }\nrobot: { start: { x: 1.5, y: 1.5 } }\nlaser:\n  range: 1e6\n  fov_deg: 360\n  beams: 360\n";
        let e: Environment = crate::load_yaml_str("t.yaml", text).unwrap();
        let mut d = check_environment("t.yaml", &e, None);
        crate::positions::locate(&mut d, text);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(
            d[0].to_string(),
            "t.yaml:6:10: laser.range: 1000000 m is beyond the reach of any planar laser; \
             a range in metres of at most 1000 (real scanners reach 10–300 m)"
        );
        let ok = text.replace("1e6", "1000");
        let e: Environment = crate::load_yaml_str("t.yaml", &ok).unwrap();
        assert_eq!(check_environment("t.yaml", &e, None), vec![]);
    }

    #[test]
    fn nan_and_negative_sizes_are_reported() {
        let e = env("rooms: [{name: a, category: office, seed: {x: 1.5, y: 1.5}}]\nobjects:\n  - {id: t, class: table, role: landmark, pose: {x: .nan, y: 1}, size: [-1, 1, 1], room: a}\n");
        let d = check_environment("t.yaml", &e, None);
        assert!(d
            .iter()
            .any(|d| d.path == "objects[0].pose.x" && d.message.contains("finite")));
        assert!(d
            .iter()
            .any(|d| d.path == "objects[0].size[0]" && d.message.contains("positive")));
    }

    /// A table 0.75 m high in room `a` and one object `rel` it at height `z`.
    fn on_table(rel: &str, z: f64) -> Vec<Diagnostic> {
        let e = env(&format!("rooms: [{{name: a, category: office, seed: {{x: 1.5, y: 1.5}}}}]\nobjects:\n  - {{id: t, class: table, role: landmark, pose: {{x: 1.5, y: 1.5}}, size: [0.8, 0.8, 0.75], room: a}}\n  - {{id: m, class: mug, role: target, pose: {{x: 1.5, y: 1.5, z: {z}}}, size: [0.1, 0.1, 0.1], room: a, {rel}: t}}\n"));
        check_environment("t.yaml", &e, None)
    }

    #[test]
    fn an_object_on_a_landmark_must_stand_at_the_landmark_top_height() {
        assert_eq!(on_table("on", 0.75), vec![]);
        assert_eq!(on_table("on", 0.79), vec![], "within the 5 cm slack");
        for z in [2.0, 0.0, 0.6] {
            let d = on_table("on", z);
            assert_eq!(d.len(), 1, "z = {z}: {d:?}");
            assert_eq!(d[0].path, "objects[1].pose.z");
            assert!(
                d[0].message.contains(&format!(
                    "z = {z} but `t`, which the object stands on, has its top at 0.75 m"
                )),
                "{}",
                d[0]
            );
            assert!(d[0].expected.starts_with("z = 0.75 "), "{}", d[0]);
        }
    }

    #[test]
    fn an_object_in_a_landmark_must_lie_between_its_base_and_top() {
        for z in [0.0, 0.4, 0.75] {
            assert_eq!(on_table("in", z), vec![], "z = {z}");
        }
        let d = on_table("in", 1.5);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].path, "objects[1].pose.z");
        assert!(
            d[0].message.contains("spans heights 0 to 0.75 m"),
            "{}",
            d[0]
        );
    }

    #[test]
    fn a_raised_landmark_top_counts_from_its_own_height() {
        // A shelf board mounted at 1 m, 0.02 m thick: its top is at 1.02 m.
        let e = env("rooms: [{name: a, category: office, seed: {x: 1.5, y: 1.5}}]\nobjects:\n  - {id: b, class: shelf, role: landmark, pose: {x: 1.5, y: 1.5, z: 1.0}, size: [0.8, 0.3, 0.02], room: a}\n  - {id: m, class: mug, role: target, pose: {x: 1.5, y: 1.5, z: 1.02}, size: [0.1, 0.1, 0.1], room: a, on: b}\n");
        assert_eq!(check_environment("t.yaml", &e, None), vec![]);
    }

    fn with_doors(radius: f64, widths: &[f64]) -> Vec<Diagnostic> {
        let mut text = format!(
            "kind: environment\nname: t\nmap: {{ ascii: \"###\\n#.#\\n###\\n\", resolution: 1.0 }}\nrobot: {{ start: {{ x: 1.5, y: 1.5 }}, radius: {radius} }}\ndoors:\n"
        );
        for (i, w) in widths.iter().enumerate() {
            // Doors in the wall cells: the door checks against the walls skip them.
            text.push_str(&format!(
                "  - {{ name: d{i}, pose: {{ x: 0.5, y: 0.5 }}, width: {w} }}\n"
            ));
        }
        let e: Environment = crate::load_yaml_str("t.yaml", &text).unwrap();
        check_environment("t.yaml", &e, None)
    }

    #[test]
    fn a_door_narrower_than_the_robot_is_an_error_naming_the_door() {
        assert_eq!(
            with_doors(0.25, &[0.5, 0.9]),
            vec![],
            "a 0.5 m robot fits a 0.5 m door"
        );
        let d = with_doors(0.25, &[0.9, 0.4]);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].path, "doors[1].width");
        assert!(
            d[0].message
                .contains("door `d1` is 0.4 m wide, narrower than the robot (0.5 m across"),
            "{}",
            d[0]
        );
    }

    #[test]
    fn a_robot_wider_than_every_door_is_one_error_at_its_radius() {
        let d = with_doors(0.5, &[0.9, 0.8]);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].path, "robot.radius");
        assert!(
            d[0].message
                .contains("the widest door, `d0`, is 0.9 m wide"),
            "{}",
            d[0]
        );
        assert!(d[0].expected.contains("at most 0.45 m"), "{}", d[0]);
        // No doors: nothing to pass through, nothing to report.
        assert_eq!(with_doors(5.0, &[]), vec![]);
    }

    #[test]
    fn a_ragged_ascii_map_names_the_first_short_row() {
        let text = "kind: environment\nname: t\nmap:\n  resolution: 1.0\n  ascii: |\n    #####\n    #...#\n    #..\n    #...#\n    ####\nrobot: { start: { x: 1.5, y: 1.5 } }\n";
        let e: Environment = crate::load_yaml_str("t.yaml", text).unwrap();
        let mut d = check_environment("t.yaml", &e, None);
        crate::positions::locate(&mut d, text);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].path, "map.ascii");
        // Located at the map's first row (a block scalar's position); the message counts rows.
        assert_eq!(d[0].line, Some(6));
        assert!(
            d[0].message
                .contains("row 3 of the map (line 3 of `ascii`) is 3 cells long but row 1 is 5 (1 more rows differ)"),
            "{}",
            d[0]
        );
        let square = text
            .replace("    #..\n", "    #...#\n")
            .replace("    ####\n", "    #####\n");
        let e: Environment = crate::load_yaml_str("t.yaml", &square).unwrap();
        assert_eq!(check_environment("t.yaml", &e, None), vec![]);
    }

    #[test]
    fn doors_of_an_ascii_map_are_checked_against_its_walls() {
        let text = "kind: environment\nname: t\nmap:\n  resolution: 0.5\n  ascii: |\n    #######\n    #..#..#\n    #.....#\n    #..#..#\n    #######\nrobot: { start: { x: 0.75, y: 0.75 } }\ndoors:\n  - { name: d, pose: { x: 1.75, y: 1.25, yaw_deg: 0 }, width: 0.5 }\n";
        let e: Environment = crate::load_yaml_str("t.yaml", text).unwrap();
        assert_eq!(check_environment("t.yaml", &e, None), vec![]);
        let e: Environment =
            crate::load_yaml_str("t.yaml", &text.replace("yaw_deg: 0", "yaw_deg: 90")).unwrap();
        let d = check_environment("t.yaml", &e, None);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].path, "doors[0].pose.yaw_deg");
        let e: Environment =
            crate::load_yaml_str("t.yaml", &text.replace("width: 0.5", "width: 2.5")).unwrap();
        let d = check_environment("t.yaml", &e, None);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].path, "doors[0].width");
    }
}
