//! CREATEVIEWCONES: view planning by coverage over a location's points (Sjöö et al., `004`
//! §2.1) with line of sight on the known map — a room's known cells at the search heights, or
//! the top of a known landmark.

use super::Ctx;
use crate::memory::{standable, ConeLoc, ConeSet, Memory, Price, PriceKey};
use crate::run::Run;
use avs_concepts::RoomId;
use avs_format::knowledge::{ObjectClass, Relation};
use avs_map::grid::Cell;
use avs_map::places::dist;
use avs_robot::Camera;
use avs_view::{
    create_view_cones_at_levels, lattice_step, search_heights, sight_clear, CameraModel,
    CoverOptions, DetectionRange, PlannedView, SightLine,
};
use std::collections::{BTreeMap, BTreeSet};

/// CREATEVIEWCONES for `label` at `loc` (unzoomed, as the paper plans them): the cones are
/// kept in memory for the session that follows. Where earlier searches for `label` looked
/// ([`Memory::looks`]), the cones are planned for the location's points not looked at yet, so
/// that a second search of a large room looks at the rest rather than through the same
/// capped cones again; only when no view sees any of those (or none is left) are they
/// planned over all its points, for a second look.
pub(crate) fn create_cones(
    cx: Ctx,
    mem: &mut Memory,
    cam: &Camera,
    run: &mut Run,
    label: &str,
    loc: ConeLoc,
) {
    let Some((set, not_looked)) = next_cones(cx, mem, cam, label, loc) else {
        return;
    };
    run.observe(format!(
        "{} view cones for {label} cover {:.0}% of {} points{}",
        set.views.len(),
        100.0 * set.covered_share,
        set.n_points,
        if not_looked { " not looked at yet" } else { "" }
    ));
    mem.cones.insert((label.to_string(), loc), set);
}

/// The cones the next CREATEVIEWCONES for `label` at `loc` plans ([`create_cones`]), and
/// whether they are planned for the points not looked at yet. `None` for an unknown class.
fn next_cones(
    cx: Ctx,
    mem: &Memory,
    cam: &Camera,
    label: &str,
    loc: ConeLoc,
) -> Option<(ConeSet, bool)> {
    let fresh: Option<Vec<[f64; 3]>> = match cx.knowledge.class(label) {
        Some(class) if mem.looks.get(label).is_some_and(|l| !l.is_empty()) => {
            let all = location_points(cx, mem, class, loc);
            let n = all.len();
            let fresh: Vec<[f64; 3]> = all
                .into_iter()
                .filter(|&p| mem.looks_at(label, p) == 0)
                .collect();
            (!fresh.is_empty() && fresh.len() < n).then_some(fresh)
        }
        _ => None,
    };
    let planned_fresh = fresh
        .and_then(|pts| plan_cones(cx, mem, cam, label, loc, Some(pts), &[1.0]))
        .filter(|s| !s.views.is_empty());
    let not_looked = planned_fresh.is_some();
    let set = planned_fresh.or_else(|| plan_cones(cx, mem, cam, label, loc, None, &[1.0]))?;
    Some((set, not_looked))
}

/// Price the searches a plan for `goal` may make ([`search_cost`]), for each class that can
/// lead to the goal: every known room, and the top of every known landmark the knowledge puts
/// the class on; again only where what the price was computed on changed ([`PriceKey`]: the
/// room's known cells, its points looked at for the class, its known landmarks; for a
/// landmark, those of its room). A room not known yet is priced once per class
/// ([`typical_room_cost`]). Searches inside a landmark are not priced (the crate docs say
/// why).
pub(crate) fn price_searches(cx: Ctx, mem: &mut Memory, cam: &Camera, goal: &str) {
    let labels = crate::binding::relevant_classes(cx.knowledge, goal);
    let mut known_cells: BTreeMap<u64, usize> = BTreeMap::new();
    for r in mem.cell_rooms.iter().flatten() {
        *known_cells.entry(*r as u64).or_default() += 1;
    }
    // A room's points include the tops of its known landmarks (`room_points`), and a
    // landmark is looked at from its own room: each landmark with its room.
    let mut tops: BTreeMap<u64, usize> = BTreeMap::new();
    let mut landmarks: Vec<(usize, Option<u64>)> = Vec::new();
    for (k, o) in mem.objects.iter().enumerate() {
        if o.landmark.is_none() {
            continue;
        }
        let r = mem
            .room_at([o.pos.x, o.pos.y])
            .or_else(|| mem.room_for(o.place))
            .map(|r| r.0);
        if let Some(r) = r {
            *tops.entry(r).or_default() += 1;
        }
        landmarks.push((k, r));
    }
    let rooms: Vec<u64> = mem.wm.rooms().map(|(r, _)| r.0).collect();
    // Only where the knowledge puts the label on the landmark's class.
    let lies_on = |label: &str, class: &str| {
        cx.knowledge.landmark_rates.iter().any(|r| {
            r.object == label
                && r.landmark == class
                && r.relation == Relation::On
                && r.rates.iter().any(|&x| x > 0.0)
        })
    };
    let res = mem.tuning.cover_key_resolution;
    for label in &labels {
        if !mem.typical_costs.contains_key(label) {
            let c = typical_room_cost(cx, cam, label);
            mem.typical_costs.insert(label.clone(), c);
        }
        // The points looked at for the label, per room.
        let mut looked: BTreeMap<u64, usize> = BTreeMap::new();
        for k in mem.looks.get(label).into_iter().flat_map(|l| l.keys()) {
            if let Some(r) = mem.room_at([k.0 as f64 * res, k.1 as f64 * res]) {
                *looked.entry(r.0).or_default() += 1;
            }
        }
        let at = |m: &BTreeMap<u64, usize>, r: Option<u64>| {
            r.and_then(|r| m.get(&r)).copied().unwrap_or(0)
        };
        let room_key = |r: Option<u64>| (at(&known_cells, r), at(&looked, r), at(&tops, r));
        let mut locs: Vec<(ConeLoc, PriceKey)> = rooms
            .iter()
            .map(|&r| (ConeLoc::Room(r), room_key(Some(r))))
            .collect();
        for &(k, r) in &landmarks {
            let class = &mem.objects[k].class;
            if lies_on(label, class) {
                locs.push((ConeLoc::On(k), room_key(r)));
            }
        }
        for (loc, key) in locs {
            let entry = (label.clone(), loc);
            if mem.search_costs.get(&entry).is_some_and(|(k, _)| *k == key) {
                continue;
            }
            let c = search_cost(cx, mem, cam, label, loc);
            tracing::debug!(label = %label, ?loc, ?key, price = ?c, "search priced");
            mem.search_costs.insert(entry, (key, c));
        }
    }
}

/// What a SEARCHFOROBJECT of `loc` for `label` costs, in metres of travel: the views the
/// next CREATEVIEWCONES there would plan ([`next_cones`]), each processed at the
/// configuration's `process_cost` (in metres at `travel_cost_per_m`), and the walk between
/// their standpoints, nearest next. `None` for an unknown class or when no view sees a point
/// of the location (the caller then prices it as a room not known yet,
/// [`typical_room_cost`]).
pub(crate) fn search_cost(
    cx: Ctx,
    mem: &Memory,
    cam: &Camera,
    label: &str,
    loc: ConeLoc,
) -> Option<Price> {
    let (set, _) = next_cones(cx, mem, cam, label, loc)?;
    Some(Price {
        metres: views_cost(cx, &set.views)?,
        share: set.covered_share,
    })
}

/// The cost, in metres, of processing `views` and walking between their standpoints
/// (nearest next from the first); `None` for no views.
fn views_cost(cx: Ctx, views: &[PlannedView]) -> Option<f64> {
    if views.is_empty() {
        return None;
    }
    let per_view = cx.config.process_cost / cx.config.travel_cost_per_m.max(f64::MIN_POSITIVE);
    let mut stands: Vec<[f64; 2]> = Vec::new();
    for v in views {
        let p = [v.pose[0], v.pose[1]];
        if !stands.iter().any(|q| dist(*q, p) < 1e-9) {
            stands.push(p);
        }
    }
    let mut at = stands.swap_remove(0);
    let mut walk = 0.0;
    while !stands.is_empty() {
        let (i, d) = stands
            .iter()
            .enumerate()
            .map(|(i, q)| (i, dist(at, *q)))
            .min_by(|a, b| a.1.total_cmp(&b.1))?;
        walk += d;
        at = stands.swap_remove(i);
    }
    Some(views.len() as f64 * per_view + walk)
}

/// What searching a room not known yet for `label` costs, in metres ([`search_cost`]'s
/// measure): the views CREATEVIEWCONES plans for an empty square room of the knowledge's
/// `placeholder.room_area_m2` (the room a placeholder is expected to lead to), with the same
/// camera, ranges, point and standpoint lattices, and the share of its points they cover.
/// `None` for an unknown class.
pub(crate) fn typical_room_cost(cx: Ctx, cam: &Camera, label: &str) -> Option<Price> {
    let t = cx.tuning();
    let class = cx.knowledge.class(label)?;
    // Planned over at most `TYPICAL_ROOM_MAX_M2` (bounded work for any knowledge file); a
    // larger room's capped views cost about the same and see a share smaller by the areas.
    let area = cx.knowledge.placeholder.room_area_m2.max(1.0);
    let planned = area.min(TYPICAL_ROOM_MAX_M2);
    let side = planned.sqrt();
    let lattice = |step: f64, inset: f64| -> Vec<f64> {
        let n = ((side - 2.0 * inset) / step).floor().max(0.0) as usize;
        (0..=n).map(|i| inset + i as f64 * step).collect()
    };
    let heights = search_heights(cx.knowledge, class, false, t.height_step, t.small_object_z);
    let xs = lattice(t.point_spacing, 0.5 * t.point_spacing);
    let points: Vec<[f64; 3]> = xs
        .iter()
        .flat_map(|&x| xs.iter().map(move |&y| (x, y)))
        .flat_map(|(x, y)| heights.iter().map(move |&z| [x, y, z]))
        .collect();
    let ps = lattice(t.pose_spacing, cx.config.robot_radius);
    let poses: Vec<[f64; 3]> = ps
        .iter()
        .flat_map(|&x| ps.iter().map(move |&y| [x, y, 0.0]))
        .collect();
    let levels = range_levels(cx, class, &[1.0], cam.max_zoom);
    let plan = create_view_cones_at_levels(
        &points,
        &poses,
        &cover_camera(cx, cam),
        &levels,
        cover_costs(cx, None),
        |_, _| true,
    )
    .ok()?;
    let mut views = plan.views;
    views.truncate(cx.config.max_cones);
    Some(Price {
        metres: views_cost(cx, &views)?,
        share: covered_share(&views, points.len()) * planned / area,
    })
}

/// What the weighted greedy of view planning counts against a view: processing it, and the
/// walk to a new standpoint (from `from`, the robot, for the first; `None`: the first is
/// free). Points count bare (`point_radius` 0), as the paper's do; see [`plan_cones`].
fn cover_costs(cx: Ctx, from: Option<[f64; 2]>) -> CoverOptions {
    CoverOptions {
        point_radius: 0.0,
        per_view: cx.config.process_cost.max(f64::MIN_POSITIVE),
        per_metre: cx.config.travel_cost_per_m,
        from,
    }
}

/// The share of `n_points` points that at least one of `views` covers.
fn covered_share(views: &[PlannedView], n_points: usize) -> f64 {
    let covered: BTreeSet<usize> = views
        .iter()
        .flat_map(|v| v.covered.iter().copied())
        .collect();
    covered.len() as f64 / n_points.max(1) as f64
}

/// The largest room [`typical_room_cost`] plans views for, m²: 24 views of a cereal box cover
/// about 100 m², and a knowledge file may say any area.
const TYPICAL_ROOM_MAX_M2: f64 = 100.0;

/// The camera of view planning: a point counts as covered only in the central part of the
/// image (`tuning.cover_fov_share`); towards the border the detector's confidence falls
/// (partly cut-off objects) below `min_confidence`.
fn cover_camera(cx: Ctx, cam: &Camera) -> CameraModel {
    let t = cx.tuning();
    CameraModel {
        hfov: t.cover_fov_share * cam.hfov,
        vfov: t.cover_fov_share * cam.vfov,
        pan_limits: cam.pan_limits,
        tilt_limits: cam.tilt_limits,
        height: cam.height,
    }
}

/// The points of location `loc` where an object of `class` may be: a room's known cells at
/// the search heights ([`room_points`]), a grid over a landmark's top at the height an
/// object of `class` standing on it has its centre, or the same grid inside the landmark at
/// the centre heights of its levels ([`interior_levels`]).
pub(crate) fn location_points(
    cx: Ctx,
    mem: &Memory,
    class: &ObjectClass,
    loc: ConeLoc,
) -> Vec<[f64; 3]> {
    match loc {
        ConeLoc::Room(r) => room_points(cx, mem, r, class, false),
        ConeLoc::On(k) | ConeLoc::In(k) => {
            let o = &mem.objects[k];
            let lm = cx.knowledge.class(&o.class);
            let (w, h) = lm.map_or((1.0, 0.75), |c| (c.size[0].max(c.size[1]), c.size[2]));
            let heights = match loc {
                ConeLoc::In(_) => interior_levels(h, class.size[2]),
                _ => vec![h + class.size[2] * 0.5],
            };
            let mut pts = Vec::new();
            let n = ((w / 0.2).ceil() as i64).max(1);
            for &z in &heights {
                for i in -n / 2..=n / 2 {
                    for j in -n / 2..=n / 2 {
                        pts.push([o.pos.x + 0.2 * i as f64, o.pos.y + 0.2 * j as f64, z]);
                    }
                }
            }
            pts
        }
    }
}

/// The centre heights of an object of height `object_h` standing on the levels of a landmark
/// of height `h`: the paper names the interior of a landmark (`002` §II-B.1) but not its
/// levels, so the choice here is an expert's one: shelves about every 0.4 m from the floor
/// (a shelf, a cupboard, a bookcase), at least one level, none above the landmark's top.
pub(crate) fn interior_levels(h: f64, object_h: f64) -> Vec<f64> {
    const LEVEL_M: f64 = 0.4;
    let levels = ((h / LEVEL_M).floor() as usize).max(1);
    let step = h / levels as f64;
    (0..levels)
        .map(|i| (i as f64 * step + 0.5 * object_h).min(h))
        .collect()
}

/// The distances at which a look detects `class` at zoom 1: measured
/// ([`crate::AgentConfig::measured_sensing`]) when the configuration has it, the knowledge's
/// `detection_range` otherwise.
fn detection_range(cx: Ctx, class: &avs_format::knowledge::ObjectClass) -> [f64; 2] {
    cx.config
        .sensing(&class.name)
        .map_or(class.detection_range, |m| m.detection_range)
}

/// View planning for `label` at `loc` (CREATEVIEWCONES, Sjöö et al. `004` §2.1): cones
/// covering `points`, or the location's own points when `None`, with views at the zoom
/// levels `zooms` (and at the measured levels, [`range_levels`]); at most
/// [`AgentConfig::max_cones`](crate::AgentConfig::max_cones) of them. `None` for an unknown
/// class.
///
/// The plan's searches keep the paper's unzoomed views (`&[1.0]`) unless the zoom pipeline's
/// sensing was measured: their points are the tops of the surfaces the knowledge names,
/// within unzoomed range of some pose. The coverage before giving up also looks at the
/// floor, where a small object is beyond its unzoomed range wherever the camera's tilt limit
/// lets it look, and plans with [`view_zooms`](avs_view::view_zooms).
pub(crate) fn plan_cones(
    cx: Ctx,
    mem: &Memory,
    cam: &Camera,
    label: &str,
    loc: ConeLoc,
    points: Option<Vec<[f64; 3]>>,
    zooms: &[f64],
) -> Option<ConeSet> {
    plan_cones_from(cx, mem, cam, label, loc, points, zooms, None)
}

/// [`plan_cones`] from the one standpoint `at`: the unzoomed views a camera turning all
/// round there needs for the points of `loc` it can see (what a look around from `at` looked
/// at). `None` for an unknown class.
pub(crate) fn cones_from(
    cx: Ctx,
    mem: &Memory,
    cam: &Camera,
    label: &str,
    loc: ConeLoc,
    at: [f64; 2],
) -> Option<ConeSet> {
    plan_cones_from(cx, mem, cam, label, loc, None, &[1.0], Some(at))
}

/// [`plan_cones`] from the standpoints of the location, or from `at` alone.
#[allow(clippy::too_many_arguments)]
fn plan_cones_from(
    cx: Ctx,
    mem: &Memory,
    cam: &Camera,
    label: &str,
    loc: ConeLoc,
    points: Option<Vec<[f64; 3]>>,
    zooms: &[f64],
    at: Option<[f64; 2]>,
) -> Option<ConeSet> {
    let t = cx.tuning();
    let class = cx.knowledge.class(label)?;
    let grid = &mem.grid;
    let in_room = |x: f64, y: f64, r: u64| mem.room_at([x, y]) == Some(RoomId(r));
    let points = points.unwrap_or_else(|| location_points(cx, mem, class, loc));
    let levels = range_levels(cx, class, zooms, cam.max_zoom);
    let farthest = levels.iter().map(|(_, r)| r.max).fold(0.0, f64::max);
    // A landmark is looked at from within its detection reach and from inside its own room:
    // the disc its top may occupy (`avs_view::Surface`) reaches through the wall behind a
    // counter or desk standing against it, and a sight line that may skip the disc would look
    // through that wall from the next room (a standpoint there cost a walk out of the room
    // and back, and its view saw nothing).
    let (center, reach, home): (Option<[f64; 2]>, f64, Option<RoomId>) = match loc {
        ConeLoc::Room(_) => (None, 0.0, None),
        ConeLoc::On(k) | ConeLoc::In(k) => {
            let o = &mem.objects[k];
            let half = cx
                .knowledge
                .class(&o.class)
                .map_or(0.6, |c| 0.5 * c.size[0].hypot(c.size[1]));
            let home = mem.room_around([o.pos.x, o.pos.y], half + 0.5);
            (Some([o.pos.x, o.pos.y]), farthest + 0.5, home)
        }
    };
    // A landmark's top is small: poses on a finer grid, so that one lies near the middle of a
    // small object's detection range wherever the furniture lets the robot stand.
    let spacing = match loc {
        ConeLoc::Room(_) => t.pose_spacing,
        ConeLoc::On(_) | ConeLoc::In(_) => 0.5 * t.pose_spacing,
    };
    // The one standpoint given, or the location's own.
    let poses: Vec<[f64; 3]> = match at {
        Some([x, y]) => vec![[x, y, 0.0]],
        None => mem
            .with_trav(false, |tr| standable(grid, tr, spacing))
            .into_iter()
            .filter(|&[x, y]| match (loc, center) {
                (ConeLoc::Room(r), _) => in_room(x, y, r),
                (_, Some(c)) => {
                    dist([x, y], c) <= reach && home.is_none_or(|r| mem.room_at([x, y]) == Some(r))
                }
                _ => false,
            })
            .map(|[x, y]| [x, y, 0.0])
            .collect(),
    };
    let camera = cover_camera(cx, cam);
    // The grid holds furniture footprints: stop the sight line short of the target point,
    // or where it reaches the top the point rests on.
    let surfaces = mem.surfaces(cx.knowledge);
    let line = SightLine {
        grid,
        surfaces: &surfaces,
        slack: t.los_slack,
        z_tolerance: t.surface_z_tolerance,
        unknown_blocks: true,
    };
    let los = |a: [f64; 3], b: [f64; 3]| sight_clear(&line, [a[0], a[1]], b);
    let planned = if points.is_empty() || poses.is_empty() {
        None
    } else {
        // Views weighed by what the session will pay for them: processing, and the walk to a
        // new standpoint from the robot or the standpoints already chosen (the weighted greedy
        // of `avs_view::create_view_cones_costed`). The paper's greedy, which counts views
        // alone, put a room's 16 cones on 6 to 8 standpoints and walked the room over twice.
        //
        // Points count bare (`point_radius` 0), as the paper's do. Counting a point covered
        // only with its whole lattice cell in view found objects the bare count misses near
        // the image border at close range, but it leaves a zoomed view (a narrow field at
        // short range) almost no cell to cover: the coverage before giving up then looked
        // through one or two points per cone until it ran out of actions (BENCHMARKS.md).
        let costs = cover_costs(cx, Some(mem.at));
        create_view_cones_at_levels(&points, &poses, &camera, &levels, costs, los).ok()
    };
    Some(match planned {
        Some(mut p) => {
            p.views.truncate(cx.config.max_cones);
            let n_points = points.len();
            let share = covered_share(&p.views, n_points);
            ConeSet {
                cells: p.cone_cells(),
                views: p.views,
                points: points.clone(),
                n_points,
                covered_share: share,
            }
        }
        None => ConeSet {
            views: Vec::new(),
            points: points.clone(),
            cells: Vec::new(),
            n_points: 0,
            covered_share: 0.0,
        },
    })
}

/// The points of room `r` where an object of `class` may be: known cells every
/// `point_spacing`, at each of the [`search_heights`] (those of the coverage when `cover`),
/// and the unknown cells on top of the room's known landmarks and in its pockets
/// ([`Memory::pockets`]).
pub(crate) fn room_points(
    cx: Ctx,
    mem: &Memory,
    r: u64,
    class: &ObjectClass,
    cover: bool,
) -> Vec<[f64; 3]> {
    let t = cx.tuning();
    let grid = &mem.grid;
    let heights = search_heights(cx.knowledge, class, cover, t.height_step, t.small_object_z);
    let step = lattice_step(grid, t.point_spacing);
    // The known landmarks of the room, as the squares `location_points` searches on them: a
    // laser sees a table's or a counter's edge, not its top, so the cells under a landmark
    // stay unknown, and without these a search of the room never looked at what lies on its
    // furniture (a cerealbox a table search missed was never looked at again).
    let tops: Vec<([f64; 2], f64)> = mem
        .objects
        .iter()
        .filter(|o| {
            // A landmark's centre cell is often unknown (no room of its own): then the room
            // of the place it was seen from.
            o.landmark.is_some()
                && mem
                    .room_at([o.pos.x, o.pos.y])
                    .or_else(|| mem.room_for(o.place))
                    == Some(RoomId(r))
        })
        .filter_map(|o| {
            let c = cx.knowledge.class(&o.class)?;
            Some(([o.pos.x, o.pos.y], 0.5 * c.size[0].max(c.size[1])))
        })
        .collect();
    let on_a_landmark = |x: f64, y: f64| {
        tops.iter()
            .any(|(c, h)| (x - c[0]).abs() <= *h && (y - c[1]).abs() <= *h)
    };
    // And the pockets of the room: the unknown insides of furniture whether or not the look
    // around reported it (a table it missed still has a top).
    let pocket_top = crate::memory::pocket_top(cx.knowledge);
    let pockets: BTreeSet<(i64, i64)> = mem
        .pockets
        .iter()
        .filter(|p| p.room as u64 == r)
        .flat_map(|p| p.cells.iter().copied())
        .collect();
    let mut pts = Vec::new();
    for row in (0..grid.height()).step_by(step) {
        for col in (0..grid.width()).step_by(step) {
            let (x, y) = grid.cell_center(col as i64, row as i64);
            let in_room = if grid.get(col, row) == Cell::Unknown {
                if !on_a_landmark(x, y) && pockets.contains(&(col as i64, row as i64)) {
                    // Inside furniture not known: only on its top (nothing under a table's
                    // top is seen over its rim).
                    let on_top = heights
                        .iter()
                        .filter(|&&z| z >= pocket_top - t.surface_z_tolerance);
                    pts.extend(on_top.map(|&z| [x, y, z]));
                    continue;
                }
                on_a_landmark(x, y)
            } else {
                mem.room_at([x, y]) == Some(RoomId(r))
            };
            if in_room {
                pts.extend(heights.iter().map(|&z| [x, y, z]));
            }
        }
    }
    pts
}

/// The zoom levels a CREATEVIEWCONES for `class` plans with, each with the distances at which
/// its views count a point covered: the levels `zooms`, and with a measured sensing
/// ([`crate::AgentConfig::measured_sensing`], the zoom pipeline's) every level it was measured
/// at too, each with its measured range — a zoomed look of the pipeline reaches less than the
/// zoom times its unzoomed range, and a class whose unzoomed range is short (a marker: 0.25–
/// 0.71 m) is looked for from afar only through the zoom. Otherwise a level's range is the
/// zoom times the unzoomed one. Of a range from the knowledge only the nearer part counts: at
/// its far end the detector misses most of the time
/// ([`Tuning::cover_range_share`](crate::config::Tuning)). A measured range counts whole: it
/// already ends where the share of looks that found the object crosses ½, and cutting it
/// again left a whiteboard marker on the floor in no view's range — zoom 4 finds it from
/// 1.0–1.73 m, the floor lies 1.19 m below the camera and the tilt limit (−45°, the image's
/// central three quarters) shows it from 1.06 m on, so 80 % of the range (to 1.58 m, 1.04 m
/// along the floor) reached no floor point at all. Measured levels beyond the camera's
/// `max_zoom` are left out.
fn range_levels(
    cx: Ctx,
    class: &ObjectClass,
    zooms: &[f64],
    max_zoom: f64,
) -> Vec<(f64, DetectionRange)> {
    let share = cx.tuning().cover_range_share;
    let measured = cx.config.sensing(&class.name);
    let mut levels: Vec<f64> = zooms.to_vec();
    levels.extend(
        measured
            .iter()
            .flat_map(|m| m.ranges_by_zoom.iter().map(|l| l.0))
            .filter(|&z| z <= max_zoom.max(1.0)),
    );
    levels.sort_by(f64::total_cmp);
    levels.dedup();
    levels
        .into_iter()
        .map(|z| {
            let near_part = |[near, far]: [f64; 2]| [near, near + share * (far - near)];
            let [min, max] = match measured.and_then(|m| m.ranges_by_zoom.iter().find(|l| l.0 == z))
            {
                Some(l) => l.1,
                None => near_part(detection_range(cx, class)).map(|d| d * z),
            };
            (z, DetectionRange { min, max })
        })
        .collect()
}

/// The zoom of a view as the trace shows it: nothing for none.
pub(crate) fn zoom_text(zoom: f64) -> String {
    if zoom > 1.0 {
        format!(" zoom {zoom:.1}")
    } else {
        String::new()
    }
}

/// A planned view as the trace shows it: "from (x, y) pan p° tilt t°[ zoom z]", the angles in
/// degrees as every file of avs writes them (and as the JSON event's `view` carries them).
pub(crate) fn view_text(v: &PlannedView) -> String {
    format!(
        "from ({:.2}, {:.2}) pan {:.1}° tilt {:.1}°{}",
        v.pose[0],
        v.pose[1],
        v.pan.to_degrees(),
        v.tilt.to_degrees(),
        zoom_text(v.zoom)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_view_reads_with_its_zoom_only_when_zoomed() {
        assert_eq!(zoom_text(1.0), "");
        assert_eq!(zoom_text(2.0), " zoom 2.0");
    }

    #[test]
    fn a_view_reads_its_angles_in_degrees() {
        let v = PlannedView {
            pose_index: 0,
            pose: [1.0, 2.5, 0.3],
            pan: std::f64::consts::FRAC_PI_2,
            tilt: (-10f64).to_radians(),
            zoom: 2.0,
            covered: Vec::new(),
            newly_covered: Vec::new(),
        };
        assert_eq!(
            view_text(&v),
            "from (1.00, 2.50) pan 90.0° tilt -10.0° zoom 2.0"
        );
    }
}

#[cfg(test)]
mod planning_tests;
