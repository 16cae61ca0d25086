//! Scoring a search against ground truth (the agent never sees it; the scorer does).
//!
//! A search succeeds when the agent reported an object of the goal class within
//! [`SUCCESS_RADIUS`] of a true one. SPL (success weighted by path length, Anderson et al.
//! 2018, as the issue defines it) is `success × ℓ / max(p, ℓ)` with `ℓ` the shortest
//! collision-free path from the start to the nearest true object of the class and `p` the
//! distance the robot drove.
//!
//! ```
//! use avs_sim::score::{score, shortest_path_to_class};
//! let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
//! let world = avs_sim::World::load(&root.join("domains/environments/office.yaml")).unwrap();
//! let l = shortest_path_to_class(&world, "cerealbox").unwrap();
//! // Reporting the true position after driving twice the shortest path scores 0.5.
//! let truth = world.objects_of_class("cerealbox").next().unwrap().pose.clone();
//! let s = score(&world, "cerealbox", Some([truth.x, truth.y, truth.z]), 2.0 * l);
//! assert!(s.found && (s.spl - 0.5).abs() < 1e-9);
//! ```

use crate::world::World;
use avs_map::nav::{shortest_path, Traversability};
use serde::Serialize;

/// A reported position counts as the object when it is within this planar distance, metres.
pub const SUCCESS_RADIUS: f64 = 1.0;

/// How a search did against the truth.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Score {
    /// Whether the report lies within [`SUCCESS_RADIUS`] of a true object of the class.
    pub found: bool,
    /// Planar distance from the report to the nearest true object of the class, metres.
    pub error: Option<f64>,
    /// Shortest collision-free path from the start to the nearest true object, metres
    /// (`None` when no object of the class is reachable).
    pub shortest_path_length: Option<f64>,
    /// Success weighted by path length.
    pub spl: f64,
}

/// Length of the shortest collision-free path (robot radius, true map, doors as in the
/// environment file) from the start pose to the nearest object of `class`, metres.
pub fn shortest_path_to_class(world: &World, class: &str) -> Option<f64> {
    let start = &world.env.robot.start;
    geodesic_to_class(world, class, [start.x, start.y])
}

/// Length of the shortest collision-free path (as [`shortest_path_to_class`]) from `from` to
/// the nearest object of `class`, metres: habitat's geodesic distance to the goal.
pub fn geodesic_to_class(world: &World, class: &str, from: [f64; 2]) -> Option<f64> {
    nearest_by_path(world, class, from).map(|(_, l)| l)
}

/// The object of `class` nearest `from` by a collision-free path (robot radius, true map), with
/// that path's length in metres.
fn nearest_by_path<'w>(
    world: &'w World,
    class: &'w str,
    from: [f64; 2],
) -> Option<(&'w avs_format::environment::Object, f64)> {
    let trav = Traversability::new(&world.truth, world.env.robot.radius, false);
    world
        .objects_of_class(class)
        .filter_map(|o| {
            shortest_path(&trav, from, [o.pose.x, o.pose.y], 1.5).map(|p| (o, p.length))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// The floor of the room that holds the object of `class` nearest `from` by a collision-free
/// path: the room's free cells of the true map (furniture excluded), one every `spacing`
/// metres, as points. What the informed reference strategy is told (and nothing else). An
/// object outside every labelled room gives its own position; none reachable gives none.
pub fn target_room_floor(
    world: &World,
    class: &str,
    from: [f64; 2],
    spacing: f64,
) -> Vec<[f64; 2]> {
    let Some(target) = nearest_by_path(world, class, from).map(|(o, _)| [o.pose.x, o.pose.y])
    else {
        return Vec::new();
    };
    let Some(room) = world.room_at(target[0], target[1]) else {
        return vec![target];
    };
    let g = &world.truth;
    let step = ((spacing / g.resolution()).round() as usize).max(1);
    let mut points = Vec::new();
    for row in (0..g.height()).step_by(step) {
        for col in (0..g.width()).step_by(step) {
            if world.room_of_cell[g.index(col, row)] == Some(room)
                && g.get(col, row) == avs_map::grid::Cell::Free
            {
                let (x, y) = g.cell_center(col as i64, row as i64);
                points.push([x, y]);
            }
        }
    }
    if points.is_empty() {
        points.push(target);
    }
    points
}

/// Planar distance from a reported position to the nearest true object of `class`, metres
/// (`None` when the world has none).
pub fn report_error(world: &World, class: &str, reported: [f64; 2]) -> Option<f64> {
    world
        .objects_of_class(class)
        .map(|t| (reported[0] - t.pose.x).hypot(reported[1] - t.pose.y))
        .min_by(f64::total_cmp)
}

/// Score a report (`None` when the agent gave up) after driving `path_length` metres.
pub fn score(world: &World, class: &str, reported: Option<[f64; 3]>, path_length: f64) -> Score {
    let start = &world.env.robot.start;
    score_from(world, class, [start.x, start.y], reported, path_length)
}

/// [`score`] for a search that started at `from` (not the environment's start pose, e.g. a
/// search after others by the same robot).
pub fn score_from(
    world: &World,
    class: &str,
    from: [f64; 2],
    reported: Option<[f64; 3]>,
    path_length: f64,
) -> Score {
    let shortest = geodesic_to_class(world, class, from);
    let error = reported.and_then(|r| report_error(world, class, [r[0], r[1]]));
    let found = error.is_some_and(|e| e <= SUCCESS_RADIUS);
    let spl = match (found, shortest) {
        (true, Some(l)) if l.max(path_length) > 0.0 => l / l.max(path_length),
        (true, _) => 1.0,
        _ => 0.0,
    };
    Score {
        found,
        error,
        shortest_path_length: shortest,
        spl,
    }
}
