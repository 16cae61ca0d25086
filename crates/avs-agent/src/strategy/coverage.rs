//! The coverage loop shared by the baselines and the planner's last resort.

use crate::binding::{names, Binding};
use crate::body::Body;
use crate::config::Strategy;
use crate::memory::{standable, ConeLoc, ConeSet, Memory, Target};
use crate::reason::GiveUpReason;
use crate::report::{Activity, FoundObject, Goal};
use crate::run::Run;
use crate::skills::look_around::look_around_for_goal;
use crate::skills::verify::verify;
use crate::skills::views::{plan_cones, room_points, view_text};
use crate::skills::Ctx;
use crate::trace::{Event, Outcome};
use crate::AgentError;
use avs_concepts::RoomId;
use avs_format::knowledge::ObjectClass;
use avs_map::places::dist;
use avs_robot::{Detection, Pose2D, Robot, ViewCone};
use avs_view::{lattice_step, unseen_tops, view_zooms, Surface};

/// What a coverage does next.
enum Next {
    Cover(RoomId),
    /// Explore the placeholder with this stable id, at this position.
    Explore(usize, [f64; 2]),
    /// Go to known free space that no room holds (seen through a door that was never crossed,
    /// with no placeholder left to lead there), so that the place map makes a room of it.
    Visit([f64; 2]),
}

/// Cover rooms and explore placeholders by `strategy` until the goal's class is found
/// (`Ok`) or nothing is left or the action budget is spent (`Err` with the reason). Points
/// already in `run.covered` are not looked at again; after `passes` passes over everything
/// the coverage gives up. With `look_around` (the planner's coverage; the baselines use no
/// landmarks), each room entered for the first time is looked around, so that the furniture
/// in it is known and its tops are looked on.
#[expect(
    clippy::too_many_arguments,
    reason = "the four parts of a search (settings, memory, body, run) plus what to cover and how"
)]
pub(crate) fn cover_all<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    goal: &Goal,
    strategy: Strategy,
    passes: usize,
    look_around: bool,
) -> Result<Result<FoundObject, GiveUpReason>, AgentError> {
    let Some(class) = cx.knowledge.class(&goal.class).cloned() else {
        return Ok(Err(GiveUpReason::UnknownClass(goal.class.clone())));
    };
    let mut pass = 1;
    loop {
        if run.stop_requested() {
            return Ok(Err(GiveUpReason::Cancelled));
        }
        if let Some(r) = body.cannot_move(cx.tuning().stuck_motions) {
            return Ok(Err(r));
        }
        if run.metrics.actions >= cx.config.max_cover_actions {
            return Ok(Err(GiveUpReason::ActionBudget {
                actions: run.metrics.actions,
                class: goal.class.clone(),
            }));
        }
        let next = next_step(cx, mem, body.at(), &class, strategy, &goal.region, run)
            .or_else(|| outside_rooms(cx, mem, body.at(), &run.visited).map(Next::Visit));
        let Some(next) = next else {
            if pass < passes {
                pass += 1;
                run.covered.clear();
                run.observe(format!(
                    "every reachable room was covered: covering again (pass {pass} of {passes})"
                ));
                continue;
            }
            return Ok(Err(GiveUpReason::Covered {
                passes,
                class: goal.class.clone(),
            }));
        };
        match next {
            Next::Cover(room) => {
                // The planner's order is chosen afresh after every batch of views (an index
                // policy); the baselines finish the room they started.
                let one_batch = strategy == Strategy::Planner;
                if let Some(f) = cover_room(cx, mem, body, run, goal, room, one_batch)? {
                    return Ok(Ok(f));
                }
            }
            Next::Visit(pos) => {
                let action = format!("VISIT ({:.2}, {:.2})", pos[0], pos[1]);
                run.metrics.actions += 1;
                run.visited.push(pos);
                run.emit(Event::ActionStarted {
                    action: action.clone(),
                });
                let outcome = match body.go_to(mem, pos)? {
                    Ok(()) => Outcome::Ok,
                    Err(e) => Outcome::Failed(e.to_string()),
                };
                mem.sync()?;
                run.finished(action, outcome, body, mem);
                if look_around {
                    if let Some(f) = look_around_for_goal(cx, mem, body, run, goal)? {
                        return Ok(Ok(f));
                    }
                }
            }
            Next::Explore(id, pos) => {
                let action = format!("EXPLORE {}", names::placeholder(id));
                run.metrics.actions += 1;
                run.emit(Event::ActionStarted {
                    action: action.clone(),
                });
                let binding = Binding::of(mem, cx.knowledge, &goal.class);
                let ph = binding.placeholder_arg(id);
                let from = mem.current_room();
                let outcome = match body.go_to(mem, pos)? {
                    Ok(()) => {
                        crate::skills::enter::enter(cx, mem, body, run, &ph, from)?;
                        Outcome::Ok
                    }
                    Err(e) => {
                        // Unreachable or failed: never offered again (a failed motion
                        // leaves the robot nearer, and the next choice is made afresh).
                        mem.mark_unreachable(Target::Placeholder(id), ph.pos, from);
                        Outcome::Failed(e.to_string())
                    }
                };
                run.finished(action, outcome, body, mem);
                if look_around {
                    if let Some(f) = look_around_for_goal(cx, mem, body, run, goal)? {
                        return Ok(Ok(f));
                    }
                }
            }
        }
    }
}

/// The share of room `r`'s points not yet covered.
fn uncovered(cx: Ctx, mem: &Memory, r: RoomId, class: &ObjectClass, run: &Run) -> f64 {
    let pts = cover_points(cx, mem, r, class);
    if pts.is_empty() {
        return 0.0;
    }
    pts.iter()
        .filter(|p| !run.covered.contains(&run.key(**p)))
        .count() as f64
        / pts.len() as f64
}

/// Path length from `from` to the nearest place of room `r` on the known map.
fn room_distance(mem: &Memory, from: [f64; 2], r: RoomId) -> Option<f64> {
    let places = mem.wm.rooms().find(|(id, _)| *id == r)?.1;
    let nearest = places
        .iter()
        .filter(|n| !mem.blocked.contains(n))
        .filter_map(|&n| mem.wm.places.graph.node_weight(n).map(|p| p.pos))
        .min_by(|a, b| dist(*a, from).total_cmp(&dist(*b, from)))?;
    mem.path_len(from, nearest, true)
}

/// The coverage's next step from `at`: a room to cover or a placeholder to explore. `region`
/// is the floor of the target's room for the informed strategy (see [`informed_step`]).
fn next_step(
    cx: Ctx,
    mem: &Memory,
    at: [f64; 2],
    class: &ObjectClass,
    strategy: Strategy,
    region: &[[f64; 2]],
    run: &Run,
) -> Option<Next> {
    let covered_share = cx.tuning().covered_share;
    let rooms: Vec<RoomId> = mem.wm.rooms().map(|(r, _)| r).collect();
    let open: Vec<(RoomId, f64, f64)> = rooms
        .into_iter()
        .map(|r| (r, uncovered(cx, mem, r, class, run)))
        .filter(|&(_, u)| u > 1.0 - covered_share)
        .filter_map(|(r, u)| Some((r, room_distance(mem, at, r)?, u)))
        .collect();
    let pending: Vec<(RoomId, f64)> = open.iter().map(|&(r, d, _)| (r, d)).collect();
    tracing::debug!(
        rooms = ?mem
            .wm
            .rooms()
            .map(|(r, _)| (r.0, uncovered(cx, mem, r, class, run), cover_points(cx, mem, r, class).len()))
            .collect::<Vec<_>>(),
        pending = ?pending,
        "coverage: rooms left"
    );
    let nearest_room = pending
        .iter()
        .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
        .map(|&(r, _)| r);
    // Path searches to every placeholder: only for the strategies that go to the nearest.
    let nearest_ph = || best_placeholder(mem, at, |_| 0.0);
    let here_room = mem.current_room();
    if strategy == Strategy::Informed {
        if let Some(next) = informed_step(mem, at, region, &pending) {
            return Some(next);
        }
    }
    match strategy {
        Strategy::Frontier => {
            if let Some(r) = here_room.filter(|r| pending.iter().any(|(p, _)| p == r)) {
                return Some(Next::Cover(r));
            }
            nearest_ph().or(nearest_room.map(Next::Cover))
        }
        Strategy::Planner => likeliest_per_metre(mem, at, &class.name, &open),
        _ => nearest_room.map(Next::Cover).or_else(nearest_ph),
    }
}

/// The planner's last resort: of the rooms `open` (room, path length to it, share of its
/// points not covered yet) and the open placeholders, the one whose cover gains the most
/// chance of finding `label` per metre — the index rule of optimal search for one object
/// hidden in one of several boxes (Blackwell 1962; Stone, *Theory of Optimal Search*, §2):
/// look next where P(found by the look) / cost of the look is largest.
///
/// * A room's chance is the conceptual map's P(ObjectAt room) (`002` eq. 1–2: the room's rates
///   and its landmarks', mixed over its category posterior and thinned by the planner's
///   failed searches) times the share the coverage has not looked at yet (the object as
///   likely at any of the room's points); its cost is the walk there plus that share of
///   covering the whole room, at the metres per share the planner prices a search of the room
///   at (`skills::views::price_searches`: views processed and the walk between their
///   standpoints; a room not priced yet at the typical room's price).
/// * A placeholder's chance is P(an object in the new rooms behind it) (§III-A.1, the map's
///   structure hypotheses); its cost the walk there plus covering a whole typical room.
///
/// Ties go to the nearer, then to rooms before placeholders and the smaller id. A room or
/// placeholder the map does not hold is not ruled out (P = 1).
fn likeliest_per_metre(
    mem: &Memory,
    at: [f64; 2],
    label: &str,
    open: &[(RoomId, f64, f64)],
) -> Option<Next> {
    let typical = mem.typical_costs.get(label).copied().flatten();
    let per_share = |c: Option<crate::memory::Price>| {
        c.filter(|c| c.share > 0.0 && c.metres.is_finite())
            .map_or(0.0, |c| c.metres / c.share)
    };
    let cm = &mem.wm.concepts;
    let rooms = open.iter().map(|&(r, d, u)| {
        let priced = mem
            .search_costs
            .get(&(label.to_string(), ConeLoc::Room(r.0)))
            .and_then(|(_, c)| *c)
            .or(typical);
        let p = cm
            .p_object_at(avs_concepts::Location::Room(r), label)
            .unwrap_or(1.0);
        (
            Next::Cover(r),
            d,
            p * u / (d + u * per_share(priced)).max(1e-6),
        )
    });
    let placeholders = open_placeholders(mem, at).map(|(id, c, d)| {
        let p = cm
            .p_object_behind_placeholder(avs_concepts::PlaceholderId(c.cm_id), label)
            .unwrap_or(1.0);
        (
            Next::Explore(id, c.pos),
            d,
            p / (d + per_share(typical)).max(1e-6),
        )
    });
    let rank = |n: &Next| match n {
        Next::Cover(r) => (0, r.0),
        Next::Explore(id, _) => (1, *id as u64),
        Next::Visit(_) => (2, 0),
    };
    rooms
        .chain(placeholders)
        .max_by(|a, b| {
            a.2.total_cmp(&b.2)
                .then(b.1.total_cmp(&a.1))
                .then(rank(&b.0).cmp(&rank(&a.0)))
        })
        .map(|(n, _, _)| n)
}

/// Explore the open placeholder minimising the path from `at` to it plus `beyond(its
/// position)`; ties go to the placeholder whose plan name sorts first.
fn best_placeholder(mem: &Memory, at: [f64; 2], beyond: impl Fn([f64; 2]) -> f64) -> Option<Next> {
    open_placeholders(mem, at)
        .map(|(id, c, l)| (names::placeholder(id), id, c.pos, l + beyond(c.pos)))
        .min_by(|a, b| a.3.total_cmp(&b.3).then(a.0.cmp(&b.0)))
        .map(|(_, id, p, _)| Next::Explore(id, p))
}

/// The placeholders not explored yet that a known path from `at` reaches: stable id, the
/// placeholder, path length.
fn open_placeholders<'m>(
    mem: &'m Memory,
    at: [f64; 2],
) -> impl Iterator<Item = (usize, &'m crate::memory::Cand, f64)> + 'm {
    mem.phs
        .iter()
        .filter(|(k, _)| mem.registry[*k].explored.is_none())
        .filter_map(move |(k, c)| Some((mem.registry[*k].id, c, mem.path_len(at, c.pos, true)?)))
}

/// The informed reference's step towards the target's room `region`: the nearest room not yet
/// covered (of `pending`, with path lengths) that holds a point of the region; while part of
/// the region lies in no known room, the placeholder that minimises the path to it plus the
/// straight line from it to the nearest such point (A*'s estimate through the frontier); else
/// nothing (the region is covered: the uninformed coverage goes on). Points the map has
/// seen that no room holds (doorways) count as done.
fn informed_step(
    mem: &Memory,
    at: [f64; 2],
    region: &[[f64; 2]],
    pending: &[(RoomId, f64)],
) -> Option<Next> {
    let mut holding = Vec::new();
    let mut outside = Vec::new();
    for &p in region {
        match mem.room_at(p) {
            Some(r) => holding.push(r),
            None if unknown_at(mem, p) => outside.push(p),
            // Known but in no room (a doorway): nothing to find out there.
            None => {}
        }
    }
    if let Some(&(r, _)) = pending
        .iter()
        .filter(|(r, _)| holding.contains(r))
        .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
    {
        return Some(Next::Cover(r));
    }
    if outside.is_empty() {
        return None;
    }
    best_placeholder(mem, at, |q| {
        outside
            .iter()
            .map(|p| dist(*p, q))
            .fold(f64::INFINITY, f64::min)
    })
}

/// Whether the known map has not seen the point `p` (or it lies off the map).
fn unknown_at(mem: &Memory, p: [f64; 2]) -> bool {
    let (c, r) = mem.grid.world_to_cell(p[0], p[1]);
    !mem.grid.contains(c, r) || mem.grid.get(c as usize, r as usize) == avs_map::grid::Cell::Unknown
}

/// The nearest reachable known free cell that no room holds, at least `outside_rooms_min`
/// from every place and from every point in `visited`.
fn outside_rooms(cx: Ctx, mem: &Memory, at: [f64; 2], visited: &[[f64; 2]]) -> Option<[f64; 2]> {
    let t = cx.tuning();
    let places: Vec<[f64; 2]> = mem.wm.places.graph.node_weights().map(|p| p.pos).collect();
    let mut candidates: Vec<([f64; 2], f64)> = mem
        .with_trav(false, |tr| standable(&mem.grid, tr, t.point_spacing))
        .into_iter()
        .filter(|&p| {
            mem.room_at(p).is_none()
                && !places
                    .iter()
                    .chain(visited)
                    .any(|q| dist(*q, p) < t.outside_rooms_min)
        })
        .map(|p| (p, dist(at, p)))
        .collect();
    candidates.sort_by(|a, b| a.1.total_cmp(&b.1));
    candidates
        .into_iter()
        .map(|(p, _)| p)
        .find(|&p| mem.path_len(at, p, false).is_some())
}

/// Cover room `r` by view planning and process its views nearest-neighbour first; a
/// detection confirmed by a second look is the goal. The views are planned for the room's
/// points not yet covered, again after each pass, until `covered_share` of them are (or
/// no view sees the rest, or a pass covers nothing: the rest is given up on); with
/// `one_batch`, after the first batch of views that leaves more to cover (the caller then
/// chooses the next room afresh).
fn cover_room<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    goal: &Goal,
    room: RoomId,
    one_batch: bool,
) -> Result<Option<FoundObject>, AgentError> {
    let label = goal.class.clone();
    let Some(class) = cx.knowledge.class(&label).cloned() else {
        return Ok(None);
    };
    let covered_share = cx.tuning().covered_share;
    let loc = ConeLoc::Room(room.0);
    loop {
        if run.stop_requested() {
            return Ok(None);
        }
        let all = cover_points(cx, mem, room, &class);
        let todo: Vec<[f64; 3]> = all
            .iter()
            .copied()
            .filter(|p| !run.covered.contains(&run.key(*p)))
            .collect();
        if todo.len() as f64 <= (1.0 - covered_share) * all.len() as f64 {
            return Ok(None);
        }
        let cam = body.camera();
        let set = plan_cones(
            cx,
            mem,
            &cam,
            &label,
            loc,
            Some(todo.clone()),
            &view_zooms(cam.max_zoom),
        )
        .filter(|s| !s.views.is_empty());
        let Some(set) = set else {
            // No view sees what is left: the room is done.
            run.cover(todo.iter().copied());
            return Ok(None);
        };
        run.observe(format!(
            "covering {} with {} view cones for {} of its {} points",
            names::room(room),
            set.views.len(),
            todo.len(),
            all.len()
        ));
        let before = run.covered.len();
        if let Some(f) = process_views(cx, mem, body, run, &label, room, &set)? {
            return Ok(Some(f));
        }
        if run.metrics.actions >= cx.config.max_cover_actions {
            return Ok(None);
        }
        let truncated = set.views.len() >= cx.config.max_cones;
        if run.covered.len() == before || !truncated {
            // Every view was planned and processed (or none got anywhere): what they did
            // not cover, no view can.
            run.cover(todo.iter().copied());
            return Ok(None);
        }
        if one_batch {
            return Ok(None);
        }
    }
}

/// The points covering room `r` looks at for `class`: the room's known cells at the
/// coverage's heights (the floor and every surface's top), and the cells on top of the
/// known furniture in the room that the laser never saw into (it sees a table's edge, not
/// its top: a box at the back of a table against a wall lies at no known cell), each at its
/// surface's height. Both on the one lattice of `point_spacing`, so that a point keeps its
/// key as the map grows.
fn cover_points(cx: Ctx, mem: &Memory, r: RoomId, class: &ObjectClass) -> Vec<[f64; 3]> {
    let mut pts = room_points(cx, mem, r.0, class, true);
    if class.landmark {
        return pts;
    }
    let step = lattice_step(&mem.grid, cx.tuning().point_spacing);
    let surfaces: Vec<Surface> = mem
        .surfaces_in_rooms(cx.knowledge)
        .into_iter()
        .filter(|(_, room)| *room == Some(r))
        .map(|(s, _)| s)
        .collect();
    pts.extend(unseen_tops(&mem.grid, &surfaces, step, 0.5 * class.size[2]));
    pts
}

/// Process `set`'s views nearest-neighbour first, marking their points covered; the first
/// detection a closer look confirms is returned.
fn process_views<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    label: &str,
    room: RoomId,
    set: &ConeSet,
) -> Result<Option<FoundObject>, AgentError> {
    let mut todo: Vec<usize> = (0..set.views.len()).collect();
    while !todo.is_empty() {
        if run.metrics.actions >= cx.config.max_cover_actions {
            return Ok(None);
        }
        let here = body.at();
        let (j, _) = todo
            .iter()
            .enumerate()
            .map(|(j, &v)| {
                let p = set.views[v].pose;
                (j, dist([p[0], p[1]], here))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .expect("not empty");
        let v = todo.remove(j);
        let view = &set.views[v];
        run.metrics.actions += 1;
        let action = format!(
            "PROCESSVIEWCONE {label} {} {}",
            names::room(room),
            view_text(view)
        );
        run.emit(Event::ActionStarted {
            action: action.clone(),
        });
        let moved = body.go_to(mem, [view.pose[0], view.pose[1]])?;
        let vc = ViewCone::new(
            Pose2D::new(view.pose[0], view.pose[1], view.pose[2]),
            view.pan,
            view.tilt,
            view.zoom,
        );
        let first = if moved.is_ok() {
            look(cx, mem, body, &vc, label)
        } else {
            None
        };
        run.zoomed(body.take_zoom_images());
        let confirmed = match first {
            Some(d) => body.with_activity(Activity::Verification, |b| {
                verify(cx, mem, b, run, label, &d)
            })?,
            None => None,
        };
        body.refresh_map(mem);
        if moved.is_ok() {
            run.cover(set.cells[v].iter().map(|&i| set.points[i]));
        }
        let outcome = match (&moved, &confirmed) {
            (Err(e), _) => Outcome::Failed(e.to_string()),
            (_, Some(_)) => Outcome::DetectedAndConfirmed,
            _ => Outcome::Ok,
        };
        run.finished(action, outcome, body, mem);
        if let Some(d) = confirmed {
            return Ok(Some(mem.file_found(label, &d)));
        }
    }
    Ok(None)
}

/// One coverage view: the most confident new sighting of `label`, anywhere in the view (a
/// view from near a door sees past it, and the goal is the object wherever it is:
/// verification decides).
fn look<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &Memory,
    body: &mut Body<R>,
    vc: &ViewCone,
    label: &str,
) -> Option<Detection> {
    let r = body.look(vc, &[label.to_string()]).ok()?;
    for d in &r.detections {
        tracing::debug!(
            class = %d.class,
            x = d.pose.x,
            y = d.pose.y,
            confidence = d.confidence,
            new = mem.is_new_sighting(d),
            "coverage view"
        );
    }
    r.detections
        .into_iter()
        .filter(|d| d.class == label && d.confidence >= cx.config.min_confidence)
        .filter(|d| mem.is_new_sighting(d))
        .max_by(|a, b| a.confidence.total_cmp(&b.confidence))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::AgentConfig;
    use crate::memory::Price;
    use crate::skills::testing;
    use avs_concepts::PlaceId;

    /// The two rooms of [`testing::two_rooms`]: the robot starts in the left one and walks
    /// into the right one (rooms exist where the robot has been), where it stands; a search of
    /// either room priced at 20 m for all of it. Returns the memory, the left and the right
    /// room.
    fn priced_two_rooms() -> (Memory, RoomId, RoomId) {
        let (config, k) = (AgentConfig::default(), testing::knowledge());
        let mut robot = testing::robot(testing::two_rooms(), [2.0, 2.0]);
        let mut mem = testing::memory(&config, &k, &mut robot);
        Body::new(&mut robot)
            .go_to(&mut mem, [6.0, 2.0])
            .expect("the walk runs")
            .expect("the door is open");
        mem.sync().expect("the map syncs");
        let left = mem.room_at([2.0, 2.0]).expect("the left room is known");
        let right = mem.room_at([6.0, 2.0]).expect("the right room is known");
        assert_ne!(left, right, "the door splits the floor into two rooms");
        mem.typical_costs.insert(
            "cerealbox".into(),
            Some(Price {
                metres: 20.0,
                share: 1.0,
            }),
        );
        (mem, left, right)
    }

    fn pick(mem: &Memory, open: &[(RoomId, f64, f64)]) -> Option<RoomId> {
        match likeliest_per_metre(mem, [6.0, 2.0], "cerealbox", open)? {
            Next::Cover(r) => Some(r),
            _ => None,
        }
    }

    #[test]
    fn the_last_resort_covers_the_likeliest_room_per_metre_first_not_the_nearest() {
        let (mut mem, left, right) = priced_two_rooms();
        let open = [(left, 4.0, 1.0), (right, 0.0, 1.0)];
        // Nothing tells the rooms apart: the one the robot stands in costs less.
        assert_eq!(pick(&mem, &open), Some(right));
        // Two counters in the left room make it a kitchen (where cereal is kept), two desks
        // the right one an office: the walk of 4 m is worth it.
        let cm = &mut mem.wm.concepts;
        cm.observe_objects(left, PlaceId(1000), "counter", 2, 1.0)
            .unwrap();
        cm.observe_objects(right, PlaceId(1001), "desk", 2, 1.0)
            .unwrap();
        cm.infer().unwrap();
        let p = |r| {
            cm.p_object_at(avs_concepts::Location::Room(r), "cerealbox")
                .unwrap()
        };
        assert!(p(left) > 1.2 * p(right), "{} vs {}", p(left), p(right));
        assert_eq!(pick(&mem, &open), Some(left));
        // Once most of the kitchen is covered, what is left of it is worth less than the
        // office the robot stands in.
        let open = [(left, 4.0, 0.05), (right, 0.0, 1.0)];
        assert_eq!(pick(&mem, &open), Some(right));
    }
}
