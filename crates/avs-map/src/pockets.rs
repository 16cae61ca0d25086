//! Pockets: small pieces of unknown space walled in by one room, where a laser map has
//! furniture it never saw into.
//!
//! A laser at one height sees the edge of a table, a desk or a counter and none of its top:
//! the footprint's rim becomes occupied cells, its inside stays unknown. Once a room is
//! mapped, such an inside is a *pocket*: a 4-connected component of unknown cells that
//! touches neither the grid's border nor any cell of another room (nor an unlabelled one, such
//! as the space beyond an unvisited door), and that is no larger than a piece of furniture, in
//! area and in extent (the inside of a thick wall seen from one side only is a long thin strip
//! of unknown cells, not furniture).
//! A search of the room must look at what may lie on it, whether or not a detector ever
//! reported the furniture: a table the look around missed still has a top.
//!
//! Choices (an expert's where nothing is published): 4-connectivity, as the room labels of
//! [`crate::places::PlaceMap::cell_rooms`] are 4-connected, so a component cannot slip
//! diagonally out through a wall's corner; the size bounds are the caller's (the agent derives
//! them from the largest landmark of its knowledge), so that the unknown inside of a closed
//! room walled in by one neighbour is not taken for furniture.
//!
//! ```
//! use avs_map::grid::OccupancyGrid;
//! use avs_map::pockets::enclosed_pockets;
//! // A room with a table whose top the laser never saw (the `?` cells).
//! let g = OccupancyGrid::from_ascii(
//!     "#######\n#.....#\n#.###.#\n#.#?#.#\n#.###.#\n#.....#\n#######\n",
//!     0.5,
//!     [0.0, 0.0],
//! )
//! .unwrap();
//! // Every known cell is in room 7.
//! let labels = vec![Some(7); g.width() * g.height()];
//! let p = enclosed_pockets(&g, &labels, 1.0, 1.0);
//! assert_eq!(p.len(), 1);
//! assert_eq!((p[0].room, p[0].cells.len()), (7, 1));
//! assert!((p[0].center[0] - 1.75).abs() < 1e-9 && (p[0].center[1] - 1.75).abs() < 1e-9);
//! ```

use crate::grid::{Cell, OccupancyGrid};

/// A pocket of unknown cells inside one room ([module docs](self)).
#[derive(Debug, Clone, PartialEq)]
pub struct Pocket {
    /// The room label (as in the labels given to [`enclosed_pockets`]) of every cell around it.
    pub room: usize,
    /// Its cells, `(col, row)`, in the order the flood met them.
    pub cells: Vec<(i64, i64)>,
    /// The mean of its cell centres, metres.
    pub center: [f64; 2],
    /// The largest distance from `center` to a corner of one of its cells, metres: the disc of
    /// this radius holds the whole pocket.
    pub radius: f64,
}

/// The pockets of `known` ([module docs](self)): components of unknown cells of at most
/// `max_area` square metres and of a [`Pocket::radius`] of at most `max_radius` metres, away
/// from the grid's border, every 4-neighbour of which outside the component is a known cell
/// labelled with one and the same room in `labels` (row-major, one per cell, as
/// [`crate::places::PlaceMap::cell_rooms`] gives them). Linear in the number of cells. Panics
/// if `labels` is not one label per cell.
pub fn enclosed_pockets(
    known: &OccupancyGrid,
    labels: &[Option<usize>],
    max_area: f64,
    max_radius: f64,
) -> Vec<Pocket> {
    let (w, h) = (known.width() as i64, known.height() as i64);
    assert_eq!(labels.len(), (w * h) as usize, "one label per cell");
    let res = known.resolution();
    let max_cells = (max_area / (res * res)).floor().max(0.0) as usize;
    let idx = |c: i64, r: i64| (r * w + c) as usize;
    const STEPS: [(i64, i64); 4] = [(1, 0), (-1, 0), (0, 1), (0, -1)];
    let mut seen = vec![false; (w * h) as usize];
    let mut pockets = Vec::new();
    let mut stack = Vec::new();
    for r0 in 0..h {
        for c0 in 0..w {
            if seen[idx(c0, r0)] || known.get_i(c0, r0) != Cell::Unknown {
                continue;
            }
            // Flood the whole component (so that no cell of it starts another), noting
            // whether it stays a pocket.
            seen[idx(c0, r0)] = true;
            stack.push((c0, r0));
            let mut cells = Vec::new();
            let mut room: Option<usize> = None;
            let mut pocket = true;
            while let Some((c, r)) = stack.pop() {
                if pocket {
                    cells.push((c, r));
                    pocket = cells.len() <= max_cells;
                }
                for (dc, dr) in STEPS {
                    let (nc, nr) = (c + dc, r + dr);
                    if !known.contains(nc, nr) {
                        pocket = false;
                        continue;
                    }
                    if known.get_i(nc, nr) == Cell::Unknown {
                        if !seen[idx(nc, nr)] {
                            seen[idx(nc, nr)] = true;
                            stack.push((nc, nr));
                        }
                        continue;
                    }
                    match (labels[idx(nc, nr)], room) {
                        (None, _) => pocket = false,
                        (Some(l), None) => room = Some(l),
                        (Some(l), Some(k)) if l != k => pocket = false,
                        _ => {}
                    }
                }
            }
            let Some(room) = room.filter(|_| pocket) else {
                continue;
            };
            let centers: Vec<(f64, f64)> = cells
                .iter()
                .map(|&(c, r)| known.cell_center(c, r))
                .collect();
            let n = centers.len() as f64;
            let center = [
                centers.iter().map(|p| p.0).sum::<f64>() / n,
                centers.iter().map(|p| p.1).sum::<f64>() / n,
            ];
            let half_diagonal = res * std::f64::consts::FRAC_1_SQRT_2;
            let radius = centers
                .iter()
                .map(|p| (p.0 - center[0]).hypot(p.1 - center[1]) + half_diagonal)
                .fold(0.0, f64::max);
            if radius > max_radius {
                continue;
            }
            pockets.push(Pocket {
                room,
                cells,
                center,
                radius,
            });
        }
    }
    pockets
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(rows: &str) -> OccupancyGrid {
        OccupancyGrid::from_ascii(rows, 0.5, [0.0, 0.0]).unwrap()
    }

    /// Labels: `room_of(col, row)` for known cells, `None` for unknown ones.
    fn labels(
        g: &OccupancyGrid,
        room_of: impl Fn(i64, i64) -> Option<usize>,
    ) -> Vec<Option<usize>> {
        let mut l = vec![None; g.width() * g.height()];
        for r in 0..g.height() as i64 {
            for c in 0..g.width() as i64 {
                if g.get_i(c, r) != Cell::Unknown {
                    l[(r * g.width() as i64 + c) as usize] = room_of(c, r);
                }
            }
        }
        l
    }

    const TABLE: &str =
        "#########\n#.......#\n#..####.#\n#..#??#.#\n#..####.#\n#.......#\n#########\n";

    #[test]
    fn the_unseen_top_of_furniture_in_a_room_is_a_pocket_of_that_room() {
        let g = grid(TABLE);
        let p = enclosed_pockets(&g, &labels(&g, |_, _| Some(3)), 2.0, 10.0);
        assert_eq!(p.len(), 1);
        assert_eq!(p[0].room, 3);
        assert_eq!(p[0].cells.len(), 2);
        // The disc holds both cells whole.
        for &(c, r) in &p[0].cells {
            let (x, y) = g.cell_center(c, r);
            let d = (x - p[0].center[0]).hypot(y - p[0].center[1]);
            assert!(d + 0.25 * std::f64::consts::SQRT_2 <= p[0].radius + 1e-9);
        }
    }

    #[test]
    fn a_pocket_larger_than_furniture_is_not_one() {
        let g = grid(TABLE);
        // Two cells are 0.5 m²: not a pocket below that.
        assert!(enclosed_pockets(&g, &labels(&g, |_, _| Some(3)), 0.49, 10.0).is_empty());
        assert_eq!(
            enclosed_pockets(&g, &labels(&g, |_, _| Some(3)), 0.5, 10.0).len(),
            1
        );
    }

    #[test]
    fn a_long_thin_strip_is_no_pocket_whatever_its_area() {
        // The unknown inside of a thick wall, seen from one room only: 4 m long, 2 m² in all.
        let g = grid("##########\n#........#\n#........#\n##########\n#????????#\n##########\n");
        let l = labels(&g, |_, _| Some(1));
        assert!(enclosed_pockets(&g, &l, 3.0, 1.0).is_empty());
        assert_eq!(enclosed_pockets(&g, &l, 3.0, 2.5).len(), 1);
    }

    #[test]
    fn unknown_space_bordering_two_rooms_or_unlabelled_cells_is_no_pocket() {
        let g = grid(TABLE);
        // The table's rim split between rooms 1 (west of column 5) and 2.
        let split = labels(&g, |c, _| Some(if c < 5 { 1 } else { 2 }));
        assert!(enclosed_pockets(&g, &split, 2.0, 10.0).is_empty());
        // One rim cell no room reaches (space beyond a door, say).
        let hole = labels(&g, |c, r| (!(c == 6 && r == 3)).then_some(1));
        assert!(enclosed_pockets(&g, &hole, 2.0, 10.0).is_empty());
    }

    #[test]
    fn unknown_space_at_the_grid_border_is_no_pocket() {
        // The unknown outside of the building touches the border.
        let g = grid("??????\n?####?\n?#..#?\n?####?\n??????\n");
        assert!(enclosed_pockets(&g, &labels(&g, |_, _| Some(0)), 100.0, 100.0).is_empty());
    }

    #[test]
    fn every_unknown_component_is_flooded_once() {
        // Two tables: two pockets, each cell in exactly one.
        let g =
            grid("#########\n#.......#\n#.##.##.#\n#.#?.?#.#\n#.##.##.#\n#.......#\n#########\n");
        let p = enclosed_pockets(&g, &labels(&g, |_, _| Some(0)), 1.0, 10.0);
        assert_eq!(p.len(), 2);
        let mut cells: Vec<_> = p.iter().flat_map(|q| q.cells.clone()).collect();
        cells.sort();
        cells.dedup();
        assert_eq!(cells.len(), 2);
    }
}
