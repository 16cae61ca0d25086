//! A generator of office-like floors: a corridor with rooms on both sides, one door each (of
//! varying width within the knowledge file's door range), room categories drawn from the
//! knowledge file's prior, furniture and objects drawn from its Poisson rates.
//!
//! Choices (the papers give no generator): rooms are 3–5 m wide and 3.5–5 m deep, the corridor
//! 2–2.6 m wide; walls are 0.2 m thick on a 0.1 m grid. The corridor gets the category named
//! `corridor` when the knowledge file has one. A room of category c holds Poisson(λ_{l,c}) (at
//! most 3) landmarks of each landmark class l (`object_rates`), either against a wall or
//! free-standing with at least 1.3 m of clearance (never a door-wide gap between furniture and a
//! wall, which neither real offices nor door detectors like); each landmark carries
//! Poisson(λ) objects per `landmark_rates` entry; other objects lie on the floor at their
//! `object_rates`. Placements that do not fit are dropped, never forced.
//!
//! **Look-alikes.** Last, each room (not the corridor) gets Poisson(λ) look-alikes,
//! λ = [`GenerateParams::lookalikes_per_room`] ([`DEFAULT_LOOKALIKES_PER_ROOM`] = 0.5 by
//! default: about one every two rooms): objects with `role: distractor` that a detector of
//! another class may mistake for its target ([`crate::sensors`], [`crate::world_scores`]).
//!
//! # Choices where the papers are vague
//!
//! * **Which look-alikes.** The knowledge file marks no class as a look-alike, so a look-alike
//!   is an everyday object of the room: a non-landmark class other than
//!   [`GenerateParams::ensure_class`] (the search's target must not be faked by an object
//!   that really is one: a distractor of the target's own class is a true target to the
//!   detector), drawn in proportion to the class's `object_rates` for the room's category
//!   (mugs in kitchens), uniformly when those rates are all zero.
//! * **Where.** Half of the time on a landmark of the room that some class stands `on` in
//!   `landmark_rates` (a table, desk or counter), when the room has one; else on the floor,
//!   0.3 m clear of walls and furniture. A look-alike that does not fit is dropped. Its yaw is
//!   uniform, so a detector's aspect-dependent score sees it from a random side.
//! * **A stream of their own.** Look-alikes are drawn after everything else, from their own
//!   `ChaCha8Rng` stream ([`LOOKALIKE_STREAM`] of the same seed): with the rate at 0 a floor is
//!   the one generated before look-alikes existed, byte for byte, and with any rate the rest
//!   of the floor (rooms, doors, furniture, targets) is unchanged; look-alikes only append
//!   objects.
//! * **Targets turned any way.** Every object with `role: target` (on the floor or on a
//!   landmark) gets a yaw uniform in [0°, 360°), from a stream of its own
//!   ([`ORIENTATION_STREAM`]), as the look-alikes do: a camera that sees an object's sides
//!   (`crate::image`) or a detector whose score follows the aspect (`crate::world_scores`)
//!   meets it from a random side. With every target at yaw 0, each long, thin object lay
//!   along the y axis, so on every floor a marker was end-on to any robot north or south of
//!   it. Furniture keeps its axis-aligned footprint (against walls). The one-shot detector and
//!   the laser do not see a target's yaw: a floor's runs with that detector are unchanged.

use avs_format::environment::{
    AsciiMap, Camera, Door, Environment, EnvironmentKind, Laser, MapSource, Object, ObjectRole,
    Point, Pose, Robot, Room,
};
use avs_format::knowledge::{Knowledge, Relation};
use rand::distributions::{Distribution, WeightedIndex};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Default [`GenerateParams::lookalikes_per_room`]: about one look-alike every two rooms.
pub const DEFAULT_LOOKALIKES_PER_ROOM: f64 = 0.5;

/// Largest accepted [`GenerateParams::lookalikes_per_room`].
pub const MAX_LOOKALIKES_PER_ROOM: f64 = 10.0;

/// The `ChaCha8Rng` stream (of the floor's seed) look-alikes are drawn from; everything else
/// uses stream 0 (and [`ORIENTATION_STREAM`]).
pub const LOOKALIKE_STREAM: u64 = 0x100c_a1ce;

/// The `ChaCha8Rng` stream (of the floor's seed) the targets' yaws are drawn from.
pub const ORIENTATION_STREAM: u64 = 0x0_7a11;

/// What to generate.
#[derive(Debug, Clone, PartialEq)]
pub struct GenerateParams {
    /// Seed of every random choice.
    pub seed: u64,
    /// Number of rooms besides the corridor.
    pub rooms: usize,
    /// Make sure at least one object of this class exists (placed where its rates are highest
    /// relative to the others, by a weighted draw), e.g. the target of a benchmark run.
    pub ensure_class: Option<String>,
    /// Where the ensured object goes.
    pub placement: Placement,
    /// Poisson rate λ of look-alikes (objects with `role: distractor`) per room besides the
    /// corridor, in `[0, `[`MAX_LOOKALIKES_PER_ROOM`]`]`; 0 generates none and leaves the floor
    /// exactly as without look-alikes (see the module docs).
    pub lookalikes_per_room: f64,
}

impl Default for GenerateParams {
    /// Seed 0, 4 rooms (as `avs generate`), no ensured class, placement as the knowledge says,
    /// [`DEFAULT_LOOKALIKES_PER_ROOM`] look-alikes per room.
    fn default() -> Self {
        Self {
            seed: 0,
            rooms: 4,
            ensure_class: None,
            placement: Placement::AsKnowledge,
            lookalikes_per_room: DEFAULT_LOOKALIKES_PER_ROOM,
        }
    }
}

/// Where [`GenerateParams::ensure_class`]'s object is placed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Placement {
    /// Where the knowledge file's rates say (a weighted draw; an existing instance is kept).
    #[default]
    AsKnowledge,
    /// Misleading knowledge: every instance the rates produced is removed and one object is
    /// put in the room where the knowledge file expects the fewest (on one of its landmarks
    /// with an `on` relation for some class, else on the floor).
    Unlikely,
}

/// Errors generating a floor.
#[derive(Debug, thiserror::Error)]
pub enum GenerateError {
    /// The request cannot be met.
    #[error("{0}")]
    Invalid(String),
}

/// The indices of `room`'s landmarks that some class of `knowledge` stands `on`: where an
/// object may be put on a surface.
fn surfaces_in(objects: &[Object], knowledge: &Knowledge, room: &str) -> Vec<usize> {
    objects
        .iter()
        .enumerate()
        .filter(|(_, o)| {
            o.room == room
                && o.role == ObjectRole::Landmark
                && knowledge
                    .landmark_rates
                    .iter()
                    .any(|r| r.landmark == o.class && r.relation == Relation::On)
        })
        .map(|(i, _)| i)
        .collect()
}

const RES: f64 = 0.1;
const WALL: usize = 2;

#[derive(Debug, Clone, Copy)]
struct Rect {
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
}

/// A Poisson(λ) draw; λ ≤ 0 (or not finite) gives 0.
fn poisson(rng: &mut ChaCha8Rng, lambda: f64) -> usize {
    match rand_distr::Poisson::new(lambda) {
        Ok(p) => p.sample(rng) as usize,
        Err(_) => 0,
    }
}

/// Generate an office-like floor.
pub fn generate(
    knowledge: &Knowledge,
    params: &GenerateParams,
) -> Result<Environment, GenerateError> {
    if params.rooms == 0 || params.rooms > 40 {
        return Err(GenerateError::Invalid(format!(
            "--rooms {}: expected between 1 and 40 rooms",
            params.rooms
        )));
    }
    let lookalikes = params.lookalikes_per_room;
    if !(lookalikes.is_finite() && (0.0..=MAX_LOOKALIKES_PER_ROOM).contains(&lookalikes)) {
        return Err(GenerateError::Invalid(format!(
            "lookalikes_per_room {lookalikes}: expected a rate in [0, {MAX_LOOKALIKES_PER_ROOM}] \
             look-alikes per room"
        )));
    }
    let cats = &knowledge.room_categories;
    let corridor_cat = cats.iter().position(|c| c == "corridor");
    let room_cats: Vec<usize> = (0..cats.len())
        .filter(|&i| Some(i) != corridor_cat)
        .collect();
    if room_cats.is_empty() {
        return Err(GenerateError::Invalid(
            "the knowledge file has no room category besides `corridor`".into(),
        ));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(params.seed);
    let prior: Vec<f64> = room_cats
        .iter()
        .map(|&i| {
            knowledge
                .category_prior
                .as_ref()
                .map_or(1.0, |p| p[i])
                .max(1e-9)
        })
        .collect();
    let cat_dist = WeightedIndex::new(&prior)
        .map_err(|e| GenerateError::Invalid(format!("category prior: {e}")))?;

    // Layout in cells: rooms above (top row) and below (bottom row) the corridor.
    let n_top = params.rooms.div_ceil(2);
    let n_bot = params.rooms - n_top;
    let widths = |n: usize, rng: &mut ChaCha8Rng| -> Vec<usize> {
        (0..n).map(|_| rng.gen_range(30..=50)).collect()
    };
    let mut top = widths(n_top, &mut rng);
    let mut bot = widths(n_bot, &mut rng);
    let inner = |w: &[usize]| w.iter().sum::<usize>() + WALL * w.len().saturating_sub(1);
    let span = inner(&top).max(inner(&bot)).max(40);
    for row in [&mut top, &mut bot] {
        let extra = span - inner(row);
        if let Some(last) = row.last_mut() {
            *last += extra;
        }
    }
    let depth_top = rng.gen_range(35..=50);
    let depth_bot = if n_bot > 0 { rng.gen_range(35..=50) } else { 0 };
    let corr = rng.gen_range(20..=26);
    let width = span + 2 * WALL;
    let height =
        WALL + if n_bot > 0 { depth_bot + WALL } else { 0 } + corr + WALL + depth_top + WALL;
    let mut grid = vec![vec![b'.'; width]; height]; // grid[row][col], row 0 at the bottom
    let mut wall = |c0: usize, c1: usize, r0: usize, r1: usize, ch: u8| {
        for row in grid.iter_mut().take(r1 + 1).skip(r0) {
            for cell in row.iter_mut().take(c1 + 1).skip(c0) {
                *cell = ch;
            }
        }
    };
    wall(0, width - 1, 0, WALL - 1, b'#');
    wall(0, width - 1, height - WALL, height - 1, b'#');
    wall(0, WALL - 1, 0, height - 1, b'#');
    wall(width - WALL, width - 1, 0, height - 1, b'#');
    let corr_r0 = WALL + if n_bot > 0 { depth_bot + WALL } else { 0 };
    let corr_r1 = corr_r0 + corr - 1;
    let to_m = |cells: usize| cells as f64 * RES;
    let mut rooms = vec![Room {
        name: "corridor1".into(),
        category: corridor_cat.map_or_else(|| cats[room_cats[0]].clone(), |i| cats[i].clone()),
        seed: Some(Point {
            x: to_m(WALL) + 0.5,
            y: to_m(corr_r0 + corr / 2),
        }),
        polygon: None,
    }];
    let mut doors = Vec::new();
    let mut rects = Vec::new();
    let [dmin, dmax] = knowledge.door_width;
    // Real doors are 0.75–1.1 m wide; stay inside the knowledge file's range too.
    let dmin = dmin.max(0.75);
    let dmax = dmax.min(1.1).max(dmin);
    // Horizontal walls between the corridor and each row, then vertical walls between rooms.
    for (is_top, row_w) in [(true, &top), (false, &bot)] {
        if row_w.is_empty() {
            continue;
        }
        let (wr0, r0, r1) = if is_top {
            (corr_r1 + 1, corr_r1 + 1 + WALL, height - WALL - 1)
        } else {
            (WALL + depth_bot, WALL, WALL + depth_bot - 1)
        };
        wall(WALL, width - WALL - 1, wr0, wr0 + WALL - 1, b'#');
        let mut c0 = WALL;
        for (i, &w) in row_w.iter().enumerate() {
            let c1 = c0 + w - 1;
            if i + 1 < row_w.len() {
                wall(c1 + 1, c1 + WALL, r0, r1, b'#');
            }
            // A door somewhere along the room's corridor wall, at least 0.6 m from its corners.
            let dw_cells = ((rng.gen_range(dmin..=dmax) / RES).round() as usize).clamp(7, 12);
            let lo = c0 + 6;
            let hi = c1.saturating_sub(6 + dw_cells).max(lo);
            let d0 = rng.gen_range(lo..=hi);
            wall(d0, d0 + dw_cells - 1, wr0, wr0 + WALL - 1, b'.');
            let k = rooms.len();
            let name = format!("room{k}");
            let cat = cats[room_cats[cat_dist.sample(&mut rng)]].clone();
            let rect = Rect {
                x0: to_m(c0),
                y0: to_m(r0),
                x1: to_m(c1 + 1),
                y1: to_m(r1 + 1),
            };
            rooms.push(Room {
                name: name.clone(),
                category: cat,
                seed: Some(Point {
                    x: (rect.x0 + rect.x1) / 2.0,
                    y: (rect.y0 + rect.y1) / 2.0,
                }),
                polygon: None,
            });
            doors.push(Door {
                name: format!("door{k}"),
                pose: Pose {
                    x: to_m(d0) + to_m(dw_cells) / 2.0,
                    y: to_m(wr0 + WALL / 2),
                    z: 0.0,
                    yaw_deg: 90.0,
                },
                width: to_m(dw_cells),
                open: true,
                rooms: vec!["corridor1".into(), name],
            });
            rects.push((k, rect, is_top));
            c0 = c1 + 1 + WALL;
        }
    }

    // Furniture and objects.
    let mut objects: Vec<Object> = Vec::new();
    let mut next_id = std::collections::BTreeMap::<String, usize>::new();
    let mut new_id = |class: &str| {
        let n = next_id.entry(class.to_string()).or_insert(0);
        *n += 1;
        format!("{class}{n}")
    };
    let cat_index = |name: &str| {
        cats.iter()
            .position(|c| c == name)
            .expect("generated from the list")
    };
    for &(k, rect, is_top) in &rects {
        let c = cat_index(&rooms[k].category);
        let door_x = doors[k - 1].pose.x;
        let door_y = if is_top { rect.y0 } else { rect.y1 };
        let mut footprints: Vec<Rect> = vec![Rect {
            x0: door_x - 1.0,
            y0: door_y - 1.2,
            x1: door_x + 1.0,
            y1: door_y + 1.2,
        }];
        let mut landmarks_here = Vec::new();
        for cls in knowledge.object_classes.iter().filter(|o| o.landmark) {
            let lambda = knowledge.object_rates.get(&cls.name).map_or(0.0, |r| r[c]);
            for _ in 0..poisson(&mut rng, lambda).min(3) {
                if let Some(fp) = place_furniture(&mut rng, rect, cls.size, &footprints) {
                    footprints.push(fp);
                    objects.push(standing(
                        cls,
                        fp,
                        &rooms[k].name,
                        new_id(&cls.name),
                        ObjectRole::Landmark,
                    ));
                    landmarks_here.push(objects.len() - 1);
                }
            }
        }
        for &li in &landmarks_here {
            let lm = objects[li].clone();
            for lr in knowledge
                .landmark_rates
                .iter()
                .filter(|r| r.landmark == lm.class)
            {
                let Some(cls) = knowledge.class(&lr.object) else {
                    continue;
                };
                for _ in 0..poisson(&mut rng, lr.rates[c]).min(3) {
                    objects.push(object_on(
                        &mut rng,
                        &lm,
                        cls,
                        lr.relation,
                        new_id(&cls.name),
                    ));
                }
            }
        }
        for cls in knowledge.object_classes.iter().filter(|o| !o.landmark) {
            let lambda = knowledge.object_rates.get(&cls.name).map_or(0.0, |r| r[c]);
            for _ in 0..poisson(&mut rng, lambda).min(3) {
                if let Some(fp) = place_box(&mut rng, rect, cls.size, &footprints, 0.3) {
                    objects.push(standing(
                        cls,
                        fp,
                        &rooms[k].name,
                        new_id(&cls.name),
                        ObjectRole::Target,
                    ));
                }
            }
        }
    }
    if let (Some(target), Placement::Unlikely) = (&params.ensure_class, params.placement) {
        let cls = knowledge
            .class(target)
            .ok_or_else(|| GenerateError::Invalid(format!("unknown object class `{target}`")))?;
        objects.retain(|o| &o.class != target);
        // Expected number of the target per room: its room rate plus the rates on or in each
        // landmark instance there (Aydemir et al. 2011, eq. 1–2: rates add over locations).
        let expected = |k: usize, objects: &[Object]| {
            let c = cat_index(&rooms[k].category);
            let room = knowledge.object_rates.get(target).map_or(0.0, |r| r[c]);
            let on: f64 = objects
                .iter()
                .filter(|o| o.room == rooms[k].name && o.role == ObjectRole::Landmark)
                .flat_map(|o| {
                    knowledge
                        .landmark_rates
                        .iter()
                        .filter(move |r| &r.object == target && r.landmark == o.class)
                        .map(move |r| r.rates[c])
                })
                .sum();
            room + on
        };
        let least = rects
            .iter()
            .map(|&(k, _, _)| expected(k, &objects))
            .fold(f64::INFINITY, f64::min);
        let unlikely: Vec<(usize, Rect)> = rects
            .iter()
            .filter(|&&(k, _, _)| expected(k, &objects) <= least + 1e-12)
            .map(|&(k, r, _)| (k, r))
            .collect();
        let (k, rect) = unlikely[rng.gen_range(0..unlikely.len())];
        let surfaces = surfaces_in(&objects, knowledge, &rooms[k].name);
        if surfaces.is_empty() {
            let id = new_id(&cls.name);
            objects.push(on_floor(&mut rng, rect, cls, &rooms[k].name, id)?);
        } else {
            let lm = objects[surfaces[rng.gen_range(0..surfaces.len())]].clone();
            objects.push(object_on(
                &mut rng,
                &lm,
                cls,
                Relation::On,
                new_id(&cls.name),
            ));
        }
    } else if let Some(target) = &params.ensure_class {
        let cls = knowledge
            .class(target)
            .ok_or_else(|| GenerateError::Invalid(format!("unknown object class `{target}`")))?;
        if !objects.iter().any(|o| &o.class == target) {
            // Weighted draw over (landmark instance, rate) pairs, else a floor spot in a room.
            let mut options: Vec<(usize, Relation, f64)> = Vec::new();
            for (i, o) in objects
                .iter()
                .enumerate()
                .filter(|(_, o)| o.role == ObjectRole::Landmark)
            {
                let c = cat_index(
                    &rooms
                        .iter()
                        .find(|r| r.name == o.room)
                        .expect("own room")
                        .category,
                );
                for lr in knowledge
                    .landmark_rates
                    .iter()
                    .filter(|r| &r.object == target && r.landmark == o.class)
                {
                    options.push((i, lr.relation, lr.rates[c].max(0.0)));
                }
            }
            let weights: Vec<f64> = options.iter().map(|o| o.2).collect();
            if let Ok(wi) = WeightedIndex::new(&weights) {
                let (li, rel, _) = options[wi.sample(&mut rng)];
                let lm = objects[li].clone();
                objects.push(object_on(&mut rng, &lm, cls, rel, new_id(&cls.name)));
            } else {
                let (k, rect, _) = rects[rng.gen_range(0..rects.len())];
                let id = new_id(&cls.name);
                objects.push(on_floor(&mut rng, rect, cls, &rooms[k].name, id)?);
            }
        }
    }

    if lookalikes > 0.0 {
        let mut la = ChaCha8Rng::seed_from_u64(params.seed);
        la.set_stream(LOOKALIKE_STREAM);
        let classes: Vec<&avs_format::knowledge::ObjectClass> = knowledge
            .object_classes
            .iter()
            .filter(|o| !o.landmark && params.ensure_class.as_deref() != Some(o.name.as_str()))
            .collect();
        if !classes.is_empty() {
            for &(k, rect, _) in &rects {
                let c = cat_index(&rooms[k].category);
                let n = poisson(&mut la, lookalikes);
                if n == 0 {
                    continue;
                }
                let rates: Vec<f64> = classes
                    .iter()
                    .map(|o| {
                        knowledge
                            .object_rates
                            .get(&o.name)
                            .map_or(0.0, |r| r[c].max(0.0))
                    })
                    .collect();
                let pick = WeightedIndex::new(&rates).ok();
                let room = rooms[k].name.clone();
                let surfaces = surfaces_in(&objects, knowledge, &room);
                let footprints: Vec<Rect> = objects
                    .iter()
                    .filter(|o| o.room == room && o.role == ObjectRole::Landmark && o.pose.z <= 0.0)
                    .map(|o| Rect {
                        x0: o.pose.x - o.size[0] / 2.0,
                        y0: o.pose.y - o.size[1] / 2.0,
                        x1: o.pose.x + o.size[0] / 2.0,
                        y1: o.pose.y + o.size[1] / 2.0,
                    })
                    .collect();
                for _ in 0..n {
                    let cls = match &pick {
                        Some(w) => classes[w.sample(&mut la)],
                        None => classes[la.gen_range(0..classes.len())],
                    };
                    let on_surface = !surfaces.is_empty() && la.gen_bool(0.5);
                    let placed = if on_surface {
                        let lm = &objects[surfaces[la.gen_range(0..surfaces.len())]];
                        Some(object_on(&mut la, lm, cls, Relation::On, String::new()))
                    } else {
                        place_box(&mut la, rect, cls.size, &footprints, 0.3)
                            .map(|fp| standing(cls, fp, &room, String::new(), ObjectRole::Target))
                    };
                    let yaw_deg = la.gen_range(0.0..360.0);
                    if let Some(mut o) = placed {
                        o.id = new_id(&cls.name);
                        o.role = ObjectRole::Distractor;
                        o.pose.yaw_deg = yaw_deg;
                        objects.push(o);
                    }
                }
            }
        }
    }
    // Targets turned any way (module docs), from a stream of their own.
    let mut turn = ChaCha8Rng::seed_from_u64(params.seed);
    turn.set_stream(ORIENTATION_STREAM);
    for o in objects.iter_mut().filter(|o| o.role == ObjectRole::Target) {
        o.pose.yaw_deg = turn.gen_range(0.0..360.0);
    }

    let ascii: String = grid
        .iter()
        .rev()
        .map(|row| String::from_utf8(row.clone()).expect("ASCII") + "\n")
        .collect();
    Ok(Environment {
        kind: EnvironmentKind::Environment,
        name: format!("generated-{}-{}", params.seed, params.rooms),
        map: MapSource::Ascii(AsciiMap {
            ascii,
            resolution: RES,
            origin: [0.0, 0.0],
        }),
        rooms,
        doors,
        objects,
        robot: Robot {
            start: Pose {
                x: to_m(WALL) + 0.6,
                y: to_m(corr_r0) + to_m(corr) / 2.0,
                z: 0.0,
                yaw_deg: 0.0,
            },
            radius: 0.25,
            speed: 0.5,
        },
        laser: Laser {
            range: 8.0,
            fov_deg: 270.0,
            beams: 541,
        },
        camera: Camera::default(),
    })
}

/// An object standing on the floor in footprint `fp`.
/// A target object standing on the floor of `rect` (room `room`), or an error when none fits.
fn on_floor(
    rng: &mut ChaCha8Rng,
    rect: Rect,
    cls: &avs_format::knowledge::ObjectClass,
    room: &str,
    id: String,
) -> Result<Object, GenerateError> {
    let fp = place_box(rng, rect, cls.size, &[], 0.3)
        .ok_or_else(|| GenerateError::Invalid(format!("no room fits a `{}`", cls.name)))?;
    Ok(standing(cls, fp, room, id, ObjectRole::Target))
}

fn standing(
    cls: &avs_format::knowledge::ObjectClass,
    fp: Rect,
    room: &str,
    id: String,
    role: ObjectRole,
) -> Object {
    Object {
        id,
        class: cls.name.clone(),
        role,
        pose: Pose {
            x: (fp.x0 + fp.x1) / 2.0,
            y: (fp.y0 + fp.y1) / 2.0,
            z: 0.0,
            yaw_deg: 0.0,
        },
        size: cls.size,
        room: room.to_string(),
        on: None,
        r#in: None,
    }
}

fn object_on(
    rng: &mut ChaCha8Rng,
    lm: &Object,
    cls: &avs_format::knowledge::ObjectClass,
    relation: Relation,
    id: String,
) -> Object {
    let (hx, hy) = (
        (lm.size[0] - cls.size[0]).max(0.0) / 2.0,
        (lm.size[1] - cls.size[1]).max(0.0) / 2.0,
    );
    let z = match relation {
        Relation::On => lm.size[2],
        Relation::In => lm.size[2] / 2.0,
    };
    Object {
        id,
        class: cls.name.clone(),
        role: ObjectRole::Target,
        pose: Pose {
            x: lm.pose.x + rng.gen_range(-hx..=hx),
            y: lm.pose.y + rng.gen_range(-hy..=hy),
            z,
            yaw_deg: 0.0,
        },
        size: cls.size,
        room: lm.room.clone(),
        on: (relation == Relation::On).then(|| lm.id.clone()),
        r#in: (relation == Relation::In).then(|| lm.id.clone()),
    }
}

/// A footprint for a piece of furniture: against a random wall of the room (half the time, when it
/// fits), else free-standing with 1.3 m clearance to walls and other furniture.
fn place_furniture(
    rng: &mut ChaCha8Rng,
    room: Rect,
    size: [f64; 3],
    taken: &[Rect],
) -> Option<Rect> {
    if rng.gen_bool(0.5) {
        let (w, d) = (size[0], size[1]);
        for _ in 0..30 {
            // Along the bottom or top wall, 5 cm off it.
            let x = rng.gen_range(
                (room.x0 + w / 2.0 + 0.05)
                    ..=(room.x1 - w / 2.0 - 0.05).max(room.x0 + w / 2.0 + 0.05),
            );
            let y = if rng.gen_bool(0.5) {
                room.y0 + 0.05 + d / 2.0
            } else {
                room.y1 - 0.05 - d / 2.0
            };
            let r = Rect {
                x0: x - w / 2.0,
                y0: y - d / 2.0,
                x1: x + w / 2.0,
                y1: y + d / 2.0,
            };
            if r.x1 <= room.x1 && clear_of(r, taken, 1.3) {
                return Some(r);
            }
        }
    }
    place_box(rng, room, size, taken, 1.3)
}

/// Whether footprint `r` keeps at least `margin` metres from every footprint in `taken`.
fn clear_of(r: Rect, taken: &[Rect], margin: f64) -> bool {
    taken.iter().all(|t| {
        r.x1 + margin <= t.x0
            || t.x1 + margin <= r.x0
            || r.y1 + margin <= t.y0
            || t.y1 + margin <= r.y0
    })
}

/// A free axis-aligned footprint for a box of `size` in `room`, at least `margin` metres from the
/// walls and from the `taken` footprints (so the robot can walk around it); 30 tries.
fn place_box(
    rng: &mut ChaCha8Rng,
    room: Rect,
    size: [f64; 3],
    taken: &[Rect],
    margin: f64,
) -> Option<Rect> {
    let (w, d) = (size[0], size[1]);
    for _ in 0..30 {
        let (lo_x, hi_x) = (room.x0 + margin + w / 2.0, room.x1 - margin - w / 2.0);
        let (lo_y, hi_y) = (room.y0 + margin + d / 2.0, room.y1 - margin - d / 2.0);
        if lo_x > hi_x || lo_y > hi_y {
            return None;
        }
        let (x, y) = (rng.gen_range(lo_x..=hi_x), rng.gen_range(lo_y..=hi_y));
        let r = Rect {
            x0: x - w / 2.0,
            y0: y - d / 2.0,
            x1: x + w / 2.0,
            y1: y + d / 2.0,
        };
        let clear = clear_of(r, taken, margin);
        if clear {
            return Some(r);
        }
    }
    None
}
