//! 2½-D sight lines: a camera above a known table top sees the whole top over the table's
//! edge, though the table's footprint is an obstacle of the planar map (our choice, the
//! papers' maps are planar).

use crate::surface::Surface;
use avs_map::grid::OccupancyGrid;
use avs_map::places::dist;
use avs_map::raycast::line_of_sight;

/// A sight line over known furniture: what [`sight_clear`] needs besides the two ends.
#[derive(Debug, Clone, Copy)]
pub struct SightLine<'a> {
    /// The known map.
    pub grid: &'a OccupancyGrid,
    /// The known furniture tops.
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
/// table's edge, including the part the laser never saw into.
pub fn sight_clear(line: &SightLine, from: [f64; 2], to: [f64; 3]) -> bool {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::tests::room_with_a_table_against_the_wall;
    use avs_map::grid::Cell;

    const SLACK: f64 = 0.45;
    const Z_TOL: f64 = 0.1;

    fn line<'a>(g: &'a OccupancyGrid, s: &'a [Surface]) -> SightLine<'a> {
        SightLine {
            grid: g,
            surfaces: s,
            slack: SLACK,
            z_tolerance: Z_TOL,
            unknown_blocks: true,
        }
    }

    #[test]
    fn a_table_top_is_seen_over_the_tables_edge_but_the_floor_behind_it_is_not() {
        let (g, table) = room_with_a_table_against_the_wall();
        let eye = [1.6, 0.3];
        let back_of_top = [1.6, 1.8, 0.75 + 0.035];
        // Without knowing the table, the sight line ends in its footprint's edge.
        assert!(!sight_clear(&line(&g, &[]), eye, back_of_top));
        // Knowing it, the camera looks over the edge onto the top.
        assert!(sight_clear(&line(&g, &[table]), eye, back_of_top));
        // A point on the floor behind it (or under it) does not rest on the top.
        assert!(!sight_clear(&line(&g, &[table]), eye, [1.6, 1.8, 0.035]));
    }

    #[test]
    fn a_wall_between_the_camera_and_a_table_still_blocks_the_sight_line() {
        let (mut g, table) = room_with_a_table_against_the_wall();
        // A wall at x 0.5–0.6 with the camera behind it: the point lies on the table's top,
        // 0.5 m from its centre, but the sight line crosses the wall before it reaches the
        // table's disc (whose edge is at x 1.6 − 0.72 = 0.88).
        for row in 0..20 {
            g.set(5, row, Cell::Occupied);
        }
        let eye = [0.2, 1.55];
        let on_top = [1.1, 1.55, 0.785];
        assert!(table.holds(on_top, Z_TOL));
        assert!(!sight_clear(&line(&g, &[table]), eye, on_top));
        // Without the wall it is seen.
        for row in 0..20 {
            g.set(5, row, Cell::Free);
        }
        assert!(sight_clear(&line(&g, &[table]), eye, on_top));
    }
}
