//! The surfaces small objects rest on: which landmark classes are surfaces, the disc a known
//! piece of furniture's top may occupy, and the points on a top the laser never saw.

use avs_format::knowledge::{Knowledge, Relation};
use avs_map::grid::{Cell, OccupancyGrid};
use avs_map::places::dist;
use std::collections::BTreeSet;

/// The landmark classes the knowledge puts objects of class `of` *on* — or, with `None`, any
/// object (tables, counters, desks): the surfaces small objects rest on.
pub fn surface_classes<'k>(knowledge: &'k Knowledge, of: Option<&str>) -> BTreeSet<&'k str> {
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
/// class's height. (Which room it stands in is the caller's business: rooms belong to the
/// place map, not to geometry.)
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    /// Estimated centre, metres.
    pub center: [f64; 2],
    /// Radius of the disc, metres.
    pub radius: f64,
    /// Height of the top, metres.
    pub top: f64,
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

/// Every how many cells of `grid` a room's points lie: `spacing` metres in cells (at least 1).
pub fn lattice_step(grid: &OccupancyGrid, spacing: f64) -> usize {
    (spacing / grid.resolution()).round().max(1.0) as usize
}

/// The points on top of `surfaces` where an object of half height `half` may rest unseen by
/// the laser: the unknown cells of `grid` inside each surface's disc, on the lattice of every
/// `step`-th row and column (the lattice of the room's points), at the surface's top plus
/// `half`. A cell under two surfaces counts once.
pub fn unseen_tops(
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

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    pub(crate) fn office() -> Knowledge {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../knowledge/office.yaml");
        avs_format::load_yaml(std::path::Path::new(path)).unwrap()
    }

    /// A 3 m × 2 m room (0.1 m cells) with a wall along its top (y 1.9–2.0) and a table
    /// against it (x 1.0–2.2, y 1.2–1.9) of which the laser saw only the front edge (y
    /// 1.2–1.3): the rest of the footprint is unknown. Returns the grid and the table's top.
    pub(crate) fn room_with_a_table_against_the_wall() -> (OccupancyGrid, Surface) {
        let mut g = OccupancyGrid::new(30, 20, 0.1, [0.0, 0.0], Cell::Free).unwrap();
        for col in 0..30 {
            g.set(col, 19, Cell::Occupied);
        }
        for col in 10..=21 {
            g.set(col, 12, Cell::Occupied);
            for row in 13..=18 {
                g.set(col, row, Cell::Unknown);
            }
        }
        let table = Surface {
            center: [1.6, 1.55],
            radius: 0.5 * 1.2f64.hypot(0.8),
            top: 0.75,
        };
        (g, table)
    }

    #[test]
    fn surfaces_are_the_landmarks_something_lies_on() {
        let k = office();
        // Shelves hold things *in* them: not a surface.
        let kinds = surface_classes(&k, None);
        assert_eq!(kinds, ["counter", "desk", "table"].into_iter().collect());
        assert_eq!(
            surface_classes(&k, Some("stapler")),
            ["desk"].into_iter().collect()
        );
    }

    #[test]
    fn the_line_leaves_a_disc_at_its_radius_from_the_centre() {
        let s = Surface {
            center: [0.0, 0.0],
            radius: 0.5,
            top: 0.75,
        };
        assert!((s.exit_distance([0.0, 0.0], [3.0, 0.0]) - 0.5).abs() < 1e-12);
        assert!((s.exit_distance([0.3, 0.0], [3.0, 0.0]) - 0.2).abs() < 1e-12);
        assert!((s.exit_distance([0.3, 0.0], [-3.0, 0.0]) - 0.8).abs() < 1e-12);
        // From inside the disc, no farther than the camera.
        assert!((s.exit_distance([0.3, 0.0], [0.1, 0.0]) - 0.2).abs() < 1e-12);
    }

    #[test]
    fn points_just_below_a_top_still_rest_on_it() {
        let (_, table) = room_with_a_table_against_the_wall();
        assert!(table.holds([1.6, 1.8, 0.75 - 0.05], 0.1));
        assert!(!table.holds([1.6, 1.8, 0.75 - 0.2], 0.1));
        assert!(!table.holds([3.0, 1.8, 0.75], 0.1), "outside the disc");
    }

    #[test]
    fn unseen_tops_are_the_unknown_lattice_cells_on_the_table_at_its_height() {
        let (g, table) = room_with_a_table_against_the_wall();
        // Lattice every 4 cells: of the unknown rows 13–18 only row 16 (y 1.65) is on it, and
        // of columns 10–21 columns 12, 16 and 20 (x 1.25, 1.65, 2.05), all within 0.72 m of
        // the centre (1.6, 1.55). The seen edge (row 12) is a room point already.
        let mut pts = unseen_tops(&g, &[table], 4, 0.035);
        pts.sort_by(|a, b| a[0].total_cmp(&b[0]));
        let want = [[1.25, 1.65], [1.65, 1.65], [2.05, 1.65]];
        assert_eq!(pts.len(), want.len(), "{pts:?}");
        for (p, w) in pts.iter().zip(want) {
            assert!(
                (p[0] - w[0]).abs() < 1e-9 && (p[1] - w[1]).abs() < 1e-9,
                "{pts:?}"
            );
            assert!((p[2] - 0.785).abs() < 1e-9);
        }
        // The same table known twice (two sightings) gives each point once.
        assert_eq!(unseen_tops(&g, &[table, table], 4, 0.035).len(), 3);
        // A small surface whose disc holds no lattice cell gives none.
        let tiny = Surface {
            radius: 0.05,
            ..table
        };
        assert!(unseen_tops(&g, &[tiny], 4, 0.035).is_empty());
        assert_eq!(lattice_step(&g, 0.4), 4);
    }
}
