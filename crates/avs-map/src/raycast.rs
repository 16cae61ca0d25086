//! Line traversal and what a laser reveals.
//!
//! One home for walking the grid cells along a segment ([`cells_on_segment`], the
//! Amanatides–Woo voxel traversal), used for laser scans, line of sight and camera visibility.
//!
//! ## Rays are clipped to the map
//! A scan casts enough rays to leave no gap of more than one cell at full range, so its cost
//! grows as `fov × range / resolution` rays of `range / resolution` cells each. The simulator
//! only reveals cells of the grid, and a ray stops at the grid's edge, so a range beyond the
//! grid's diagonal ([`max_ray_length`]) reveals nothing more; a field of view beyond a full
//! turn only repeats rays. [`LaserModel::ray_ends`] therefore clips the range to the diagonal
//! and the field of view to 360° before fanning out (a range of 1e6 m on a 20 m map casts the
//! rays of a 28 m laser, not 6·10⁸ rays), and [`crate::explore::new_area`] clips its range the
//! same way. The fan keeps its promise of no gap wider than one cell: every cell of the grid
//! lies within one diagonal of any pose inside it, and a pose outside the grid reveals nothing
//! either way. For lasers that reach no farther than the diagonal nothing changes.

use crate::grid::{Cell, OccupancyGrid};

/// The cells crossed by the segment from world point `a` to `b`, in order, starting with the
/// cell containing `a` (Amanatides & Woo 1987, "A fast voxel traversal algorithm").
pub fn cells_on_segment(grid: &OccupancyGrid, a: [f64; 2], b: [f64; 2]) -> Vec<(i64, i64)> {
    let mut out = Vec::new();
    walk_segment(grid, a, b, |c, r| {
        out.push((c, r));
        true
    });
    out
}

/// Visit the cells crossed by the segment `a → b` in order until `visit` returns false.
/// Returns whether the walk reached the cell containing `b`.
pub fn walk_segment(
    grid: &OccupancyGrid,
    a: [f64; 2],
    b: [f64; 2],
    mut visit: impl FnMut(i64, i64) -> bool,
) -> bool {
    walk_segment_spans(grid, a, b, |c, r, _| visit(c, r))
}

/// [`walk_segment`] with the part of the segment inside each cell: `visit(col, row, [t0, t1])`
/// where `a + t·(b − a)` for `t` in `[t0, t1] ⊆ [0, 1]` lies in the cell (the first cell
/// starts at 0, the cell of `b` ends at 1). What a ray sees of a region is then measured in
/// lengths along the ray, not in cells touched, and does not grow with the cell size.
pub fn walk_segment_spans(
    grid: &OccupancyGrid,
    a: [f64; 2],
    b: [f64; 2],
    mut visit: impl FnMut(i64, i64, [f64; 2]) -> bool,
) -> bool {
    let r = grid.resolution();
    let o = grid.origin();
    let (mut c, mut row) = grid.world_to_cell(a[0], a[1]);
    let (ec, er) = grid.world_to_cell(b[0], b[1]);
    let dx = b[0] - a[0];
    let dy = b[1] - a[1];
    let step_c: i64 = if dx > 0.0 { 1 } else { -1 };
    let step_r: i64 = if dy > 0.0 { 1 } else { -1 };
    let next_boundary = |idx: i64, step: i64, origin: f64| -> f64 {
        origin + (idx + if step > 0 { 1 } else { 0 }) as f64 * r
    };
    let mut t_max_c = if dx.abs() < 1e-12 {
        f64::INFINITY
    } else {
        (next_boundary(c, step_c, o[0]) - a[0]) / dx
    };
    let mut t_max_r = if dy.abs() < 1e-12 {
        f64::INFINITY
    } else {
        (next_boundary(row, step_r, o[1]) - a[1]) / dy
    };
    let t_delta_c = if dx.abs() < 1e-12 {
        f64::INFINITY
    } else {
        r / dx.abs()
    };
    let t_delta_r = if dy.abs() < 1e-12 {
        f64::INFINITY
    } else {
        r / dy.abs()
    };
    // A segment crosses at most |Δc| + |Δr| + 1 cells; the bound also guards against NaN input
    // (and saturates for end points far outside any grid).
    let max_steps = ec
        .abs_diff(c)
        .saturating_add(er.abs_diff(row))
        .saturating_add(1);
    let mut t_in = 0.0_f64;
    for _ in 0..max_steps {
        let last = c == ec && row == er;
        let t_out = if last {
            1.0
        } else {
            t_max_c.min(t_max_r).clamp(t_in, 1.0)
        };
        if !visit(c, row, [t_in, t_out]) {
            return false;
        }
        if last {
            return true;
        }
        t_in = t_out;
        if t_max_c < t_max_r {
            t_max_c += t_delta_c;
            c += step_c;
        } else {
            t_max_r += t_delta_r;
            row += step_r;
        }
    }
    false
}

/// Whether the straight line from `a` to `b` crosses no occupied cell of `grid` (unknown cells
/// count as see-through when `unknown_blocks` is false).
///
/// Only a blocking cell makes the answer false: an end point on a cell boundary (0.1 m
/// multiples on a 0.1 m grid) may round into the neighbouring cell, so the walk need not end
/// exactly in the cell [`OccupancyGrid::world_to_cell`] gives for `b`.
pub fn line_of_sight(grid: &OccupancyGrid, a: [f64; 2], b: [f64; 2], unknown_blocks: bool) -> bool {
    let mut blocked = false;
    walk_segment(grid, a, b, |c, r| {
        let see_through = match grid.get_i(c, r) {
            Cell::Occupied => false,
            Cell::Unknown => !unknown_blocks,
            Cell::Free => true,
        };
        blocked |= !see_through;
        see_through
    });
    !blocked
}

/// The longest ray that can matter on `grid`: its diagonal, in metres (a ray from any point
/// of the grid leaves it within this length). See the module docs, "Rays are clipped to the map".
pub fn max_ray_length(grid: &OccupancyGrid) -> f64 {
    let r = grid.resolution();
    (grid.width() as f64 * r).hypot(grid.height() as f64 * r)
}

/// A planar laser: `beams` rays spread over `fov` radians centred on the heading, up to `range` m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaserModel {
    /// Maximum range, metres.
    pub range: f64,
    /// Field of view, radians.
    pub fov: f64,
    /// Number of rays.
    pub beams: usize,
}

impl LaserModel {
    /// This laser as far as `grid` can see it: the range clipped to [`max_ray_length`] and the
    /// field of view to a full turn (NaN or negative values become 0: such a laser casts
    /// `beams` rays of length 0). The clipped fan still leaves no gap wider than one cell
    /// anywhere in the grid.
    pub fn clipped_to(&self, grid: &OccupancyGrid) -> LaserModel {
        let clip = |v: f64, hi: f64| if v > 0.0 { v.min(hi) } else { 0.0 };
        LaserModel {
            range: clip(self.range, max_ray_length(grid)),
            fov: clip(self.fov, std::f64::consts::TAU),
            beams: self.beams,
        }
    }

    /// The end points of a scan's rays from `pose` (`[x, y, heading]`) on `grid`: spread over
    /// the field of view centred on the heading (over the full circle without repeating the
    /// first ray), spaced no wider than one cell at full range whatever `beams` says, so a scan
    /// never leaves unrevealed gaps between rays (the simulator reveals cells, not returns).
    /// Range and field of view are first clipped to the grid ([`Self::clipped_to`]), which
    /// bounds the number of rays by `2π × diagonal / resolution` (or `beams`). The one home of
    /// the ray fan.
    pub fn ray_ends(&self, pose: [f64; 3], grid: &OccupancyGrid) -> impl Iterator<Item = [f64; 2]> {
        let laser = self.clipped_to(grid);
        let n = laser.beams.max(1);
        let needed = ((laser.fov * laser.range / grid.resolution()).ceil() as usize).max(n);
        let full_circle = laser.fov >= std::f64::consts::TAU - 1e-9;
        let (fov, range) = (laser.fov, laser.range);
        (0..needed).map(move |i| {
            let frac = if full_circle || needed == 1 {
                i as f64 / needed as f64
            } else {
                i as f64 / (needed - 1) as f64
            };
            let ang = pose[2] - fov / 2.0 + frac * fov;
            [pose[0] + range * ang.cos(), pose[1] + range * ang.sin()]
        })
    }
}

/// Cast a laser scan from `(x, y, heading)` in the true world `truth` and copy what it sees into
/// `known`: every cell a ray crosses becomes free until the ray hits an occupied cell, which
/// becomes occupied. Returns how many cells of `known` changed from unknown. Both grids must share
/// geometry.
pub fn reveal_scan(
    truth: &OccupancyGrid,
    known: &mut OccupancyGrid,
    pose: [f64; 3],
    laser: &LaserModel,
) -> usize {
    let mut revealed = 0;
    for end in laser.ray_ends(pose, truth) {
        walk_segment(truth, [pose[0], pose[1]], end, |c, r| {
            if !truth.contains(c, r) {
                return false;
            }
            let t = truth.get_i(c, r);
            let (cu, ru) = (c as usize, r as usize);
            if known.get(cu, ru) == Cell::Unknown && t != Cell::Unknown {
                revealed += 1;
                known.set(cu, ru, t);
            }
            t == Cell::Free
        });
    }
    revealed
}

#[cfg(test)]
mod tests {
    use super::*;

    fn room() -> OccupancyGrid {
        OccupancyGrid::from_ascii(
            "##########\n#........#\n#........#\n#...##...#\n#........#\n##########\n",
            1.0,
            [0.0, 0.0],
        )
        .unwrap()
    }

    #[test]
    fn segment_walk_visits_contiguous_cells_from_start_to_end() {
        let g = room();
        let cells = cells_on_segment(&g, [1.5, 1.5], [8.5, 4.2]);
        assert_eq!(cells.first(), Some(&(1, 1)));
        assert_eq!(cells.last(), Some(&(8, 4)));
        for w in cells.windows(2) {
            let d = (w[0].0 - w[1].0).abs() + (w[0].1 - w[1].1).abs();
            assert_eq!(d, 1, "cells {:?} and {:?} are not 4-neighbours", w[0], w[1]);
        }
    }

    #[test]
    fn wall_blocks_line_of_sight() {
        let g = room();
        // Row 2 (from the bottom) holds the `##` block at columns 4 and 5.
        assert!(!line_of_sight(&g, [2.5, 2.5], [7.5, 2.5], true));
        assert!(line_of_sight(&g, [2.5, 1.5], [7.5, 1.5], true));
    }

    #[test]
    fn free_space_is_see_through_even_when_an_end_lies_on_a_cell_boundary() {
        // 0.1 m cells: 5.4 and 5.1 are cell boundaries, where rounding may put the walk's last
        // cell next to the one `world_to_cell` names. Every such segment over free space is
        // clear.
        let g = OccupancyGrid::new(120, 80, 0.1, [0.0, 0.0], Cell::Free).unwrap();
        for (a, b) in [
            ([5.85, 6.25], [5.4, 5.1]),
            ([6.55, 6.05], [5.4, 5.1]),
            ([1.0, 1.0], [3.3, 7.7]),
            ([10.05, 0.55], [0.3, 4.9]),
        ] {
            assert!(line_of_sight(&g, a, b, true), "{a:?} -> {b:?}");
            assert!(line_of_sight(&g, b, a, true), "{b:?} -> {a:?}");
        }
    }

    #[test]
    fn full_scan_reveals_the_whole_convex_room_and_stops_at_walls() {
        let truth =
            OccupancyGrid::from_ascii("#######\n#.....#\n#.....#\n#######\n", 0.5, [0.0, 0.0])
                .unwrap();
        let mut known = OccupancyGrid::new(7, 4, 0.5, [0.0, 0.0], Cell::Unknown).unwrap();
        let laser = LaserModel {
            range: 10.0,
            fov: std::f64::consts::TAU,
            beams: 8,
        };
        let n = reveal_scan(&truth, &mut known, [1.0, 1.0, 0.0], &laser);
        assert_eq!(known.count(Cell::Free), truth.count(Cell::Free));
        assert_eq!(n, known.count(Cell::Free) + known.count(Cell::Occupied));
        // Corners behind walls stay unknown only if no ray reaches them; walls adjacent to free
        // space are all seen.
        assert!(known.count(Cell::Occupied) >= 14);
    }

    #[test]
    fn nan_pose_terminates() {
        let g = room();
        let _ = cells_on_segment(&g, [f64::NAN, 1.0], [3.0, 3.0]);
    }

    #[test]
    fn far_end_points_do_not_overflow_the_walk() {
        let g = room();
        // |Δcol| is beyond i64: the step bound saturates instead of overflowing.
        assert!(!line_of_sight(&g, [-1e19, 1.5], [1e19, 1.5], true));
    }

    /// Issue 18 reproducer: a laser range of 1e6 m with a field of view of 1e9 degrees cast
    /// `fov × range / resolution` ≈ 1.7e16 rays per scan. Clipped to the map it casts the rays
    /// of a 360° laser reaching the map's diagonal, and reveals what that laser reveals.
    #[test]
    fn absurd_range_and_fov_are_clipped_to_the_map() {
        let truth = room();
        let absurd = LaserModel {
            range: 1e6,
            fov: 1e9_f64.to_radians(),
            beams: 360,
        };
        let diagonal = max_ray_length(&truth);
        assert!((diagonal - 10f64.hypot(6.0)).abs() < 1e-12);
        let clipped = absurd.clipped_to(&truth);
        assert_eq!(clipped.range, diagonal);
        assert_eq!(clipped.fov, std::f64::consts::TAU);
        let pose = [1.5, 1.5, 0.3];
        let n = absurd.ray_ends(pose, &truth).count();
        let bound = (std::f64::consts::TAU * diagonal / truth.resolution()).ceil() as usize;
        assert_eq!(n, bound.max(360));
        let mut seen_absurd = OccupancyGrid::new(10, 6, 1.0, [0.0, 0.0], Cell::Unknown).unwrap();
        let mut seen_clipped = seen_absurd.clone();
        reveal_scan(&truth, &mut seen_absurd, pose, &absurd);
        reveal_scan(&truth, &mut seen_clipped, pose, &clipped);
        assert_eq!(seen_absurd, seen_clipped);
        // NaN and negative values cast rays of length 0 instead of misbehaving.
        let broken = LaserModel {
            range: f64::NAN,
            fov: -1.0,
            beams: 4,
        };
        assert!(broken
            .ray_ends(pose, &truth)
            .all(|e| e == [pose[0], pose[1]]));
    }
}
