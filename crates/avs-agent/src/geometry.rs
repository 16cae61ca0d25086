//! View geometry the skills share: surfaces small objects rest on, 2½-D sight lines over known
//! furniture, the heights searched, the points on unseen furniture tops, zoom levels.

use avs_concepts::RoomId;
use avs_format::knowledge::{Knowledge, ObjectClass, Relation};
use avs_map::grid::{Cell, OccupancyGrid};
use avs_map::places::dist;
use avs_map::raycast::line_of_sight;
use std::collections::BTreeSet;

/// The landmark classes the knowledge puts objects of class `of` *on* — or, with `None`, any
/// object (tables, counters, desks): the surfaces small objects rest on.
pub(crate) fn surface_classes<'k>(knowledge: &'k Knowledge, of: Option<&str>) -> BTreeSet<&'k str> {
    knowledge
        .landmark_rates
        .iter()
        .filter(|r| {
            of.is_none_or(|c| r.object == c)
                && r.relation == Relation::On
                && r.rates.iter().any(|&x| x > 0.0)
        })
        .map(|r| r.landmark.as_str())
        .collect()
}

/// The top of a known piece of furniture, as sight lines see it: the disc its footprint may
/// occupy (its estimated centre and half its class's diagonal, the yaw being unknown) at the
/// class's height.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Surface {
    pub center: [f64; 2],
    pub radius: f64,
    pub top: f64,
    /// The room the furniture stands in: that of its centre's cell, else that of the place it
    /// was filed under.
    pub room: Option<RoomId>,
}

impl Surface {
    /// Whether a point at `p` (x, y, height) rests on (or above) this surface: inside its disc
    /// and no more than `z_tolerance` below its top.
    pub fn holds(&self, p: [f64; 3], z_tolerance: f64) -> bool {
        p[2] >= self.top - z_tolerance && dist([p[0], p[1]], self.center) <= self.radius
    }

    /// How far from `p` (inside the disc) towards `from` the straight line leaves the disc.
    pub fn exit_distance(&self, p: [f64; 2], from: [f64; 2]) -> f64 {
        let d = dist(p, from);
        if d <= 0.0 {
            return 0.0;
        }
        let u = [(from[0] - p[0]) / d, (from[1] - p[1]) / d];
        let w = [p[0] - self.center[0], p[1] - self.center[1]];
        let b = u[0] * w[0] + u[1] * w[1];
        let c = w[0] * w[0] + w[1] * w[1] - self.radius * self.radius;
        (-b + (b * b - c).max(0.0).sqrt()).clamp(0.0, d)
    }
}

/// Every how many cells of `grid` a room's points lie: `spacing` metres in cells.
pub(crate) fn lattice_step(grid: &OccupancyGrid, spacing: f64) -> usize {
    (spacing / grid.resolution()).round().max(1.0) as usize
}

/// The points on top of `surfaces` where an object of half height `half` may rest unseen by
/// the laser: the unknown cells of `grid` inside each surface's disc, on the lattice of every
/// `step`-th row and column (the lattice of the room's points), at the surface's top plus
/// `half`. A cell under two surfaces counts once.
pub(crate) fn unseen_tops(
    grid: &OccupancyGrid,
    surfaces: &[Surface],
    step: usize,
    half: f64,
) -> Vec<[f64; 3]> {
    let step = step.max(1) as i64;
    let on_lattice = |i: i64| i.rem_euclid(step) == 0;
    let (w, h) = (grid.width() as i64, grid.height() as i64);
    let mut seen = BTreeSet::new();
    let mut pts = Vec::new();
    for s in surfaces {
        let (c0, r0) = grid.world_to_cell(s.center[0] - s.radius, s.center[1] - s.radius);
        let (c1, r1) = grid.world_to_cell(s.center[0] + s.radius, s.center[1] + s.radius);
        for row in r0.max(0)..=r1.min(h - 1) {
            for col in c0.max(0)..=c1.min(w - 1) {
                if !(on_lattice(row) && on_lattice(col)) || grid.get_i(col, row) != Cell::Unknown {
                    continue;
                }
                let (x, y) = grid.cell_center(col, row);
                if dist([x, y], s.center) <= s.radius && seen.insert((col, row)) {
                    pts.push([x, y, s.top + half]);
                }
            }
        }
    }
    pts
}

/// A sight line over known furniture: what [`sight_clear`] needs besides the two ends.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SightLine<'a> {
    pub grid: &'a OccupancyGrid,
    pub surfaces: &'a [Surface],
    /// How far short of the point the line may stop, metres.
    pub slack: f64,
    /// How far below a surface's top a point still rests on it, metres.
    pub z_tolerance: f64,
    /// Whether unknown cells block the line.
    pub unknown_blocks: bool,
}

/// Whether a camera at `from` sees the point `to` (x, y, height) on the known grid: the sight
/// line crosses no occupied cell (nor unknown one, with `unknown_blocks`) up to `slack` short
/// of the point — furniture footprints are obstacles of the map and a small object stands on
/// or beside one — or, when the point rests on one of the surfaces, up to where the line
/// reaches that surface's disc: a camera above a table top sees the whole top over the
/// table's edge, including the part the laser never saw into (a 2½-D sight line over known
/// furniture; our choice, the papers' maps are planar).
pub(crate) fn sight_clear(line: &SightLine, from: [f64; 2], to: [f64; 3]) -> bool {
    let p = [to[0], to[1]];
    let d = dist(from, p);
    let stop = line
        .surfaces
        .iter()
        .filter(|s| s.holds(to, line.z_tolerance))
        .map(|s| s.exit_distance(p, from))
        .fold(line.slack, f64::max);
    if d <= stop {
        return true;
    }
    let t = (d - stop) / d;
    let e = [
        from[0] + t * (p[0] - from[0]),
        from[1] + t * (p[1] - from[1]),
    ];
    line_of_sight(line.grid, from, e, line.unknown_blocks)
}

/// The heights at which an object of `class` is looked for in a room: half its height for
/// furniture; for a small object, the tops of the landmark classes the knowledge puts it
/// *on* (the lowest and the highest, or their middle when less than `height_step` apart; the
/// detector sees an object at its surface plus half its height), or `small_object_z` when
/// the knowledge names none. With `cover` (the coverage before giving up, which looks wherever
/// an object may rest because the knowledge has proved wrong): the tops of every
/// [`surface_classes`] instead of the class's own, and the floor (where the rates "anywhere
/// in a room" may put it).
pub(crate) fn search_heights(
    knowledge: &Knowledge,
    class: &ObjectClass,
    cover: bool,
    height_step: f64,
    small_object_z: f64,
) -> Vec<f64> {
    let half = 0.5 * class.size[2];
    if class.landmark {
        return vec![half];
    }
    let of = (!cover).then_some(class.name.as_str());
    let tops: Vec<f64> = surface_classes(knowledge, of)
        .into_iter()
        .filter_map(|l| knowledge.class(l))
        .map(|l| l.size[2] + half)
        .collect();
    let lo = tops.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = tops.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut zs = if tops.is_empty() {
        vec![small_object_z]
    } else if hi - lo < height_step {
        vec![0.5 * (lo + hi)]
    } else {
        vec![lo, hi]
    };
    if cover {
        zs.insert(0, half);
    }
    zs
}

/// The zoom levels view planning may use with a camera zooming up to `max_zoom`: 1, 2, 4, …
/// (each doubles the distance at which a small object is detected and halves the fields of
/// view; `create_view_cones_zoomed` plans a level only for the points the lower ones cannot
/// cover, such as a small object on the floor beyond its unzoomed range).
pub(crate) fn view_zooms(max_zoom: f64) -> Vec<f64> {
    std::iter::successors(Some(1.0), |z| Some(z * 2.0))
        .take_while(|z| *z <= max_zoom.max(1.0) + 1e-9)
        .take(8)
        .collect()
}
