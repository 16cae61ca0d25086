//! Whether a door hypothesis sits in a wall ([`in_a_wall`]): the test that keeps the place
//! map's doors to openings in the building's walls, not gaps beside furniture.

use crate::doors::DoorHypothesis;
use crate::grid::{Cell, OccupancyGrid};

/// Whether a door hypothesis sits in a wall: beyond each jamb, along the opening's line, the
/// obstacle continues for at least `WALL_RUN` metres (unknown cells allowed), and each jamb
/// belongs to an obstacle that spans at least [`WALL_SPAN`] ([`spans`]). Gaps between a
/// piece of furniture and a wall running across the opening fail the first; gaps beside
/// free-standing furniture whose side runs along the opening (a table's long edge) fail the
/// second — the most common false doors of narrow-opening detectors.
pub fn in_a_wall(known: &OccupancyGrid, h: &DoorHypothesis) -> bool {
    const WALL_RUN: f64 = 0.3;
    let [a, b] = h.jambs;
    let Some(u) = h.axis() else {
        return false;
    };
    let step = known.resolution() / 2.0;
    let runs = |from: [f64; 2], dir: f64| {
        let n = (WALL_RUN / step).ceil() as usize;
        (0..=n).all(|i| {
            let t = i as f64 * step * dir;
            let (c, r) = known.world_to_cell(from[0] + t * u[0], from[1] + t * u[1]);
            known.get_i(c, r) != Cell::Free
        })
    };
    runs(a, -1.0) && runs(b, 1.0) && spans(known, a, WALL_SPAN) && spans(known, b, WALL_SPAN)
}

/// How far (metres) the obstacle holding a door's jamb must extend for the door to be in a
/// wall: twice the widest door the knowledge allows by default (1.2 m). The walls of a building
/// are one connected obstacle, and a wall the robot has only partly seen runs on into unknown
/// space; free-standing furniture (a 1.2 m table, a 1.6 m desk) is an obstacle of its own,
/// shorter than that. An island longer than 2.4 m (a kitchen counter standing free) passes: a
/// gap beside it can still be taken for a door.
pub const WALL_SPAN: f64 = 2.4;

/// Whether the obstacle at `p` — the connected non-free cells (occupied or unknown, 8-connected)
/// around the cell at `p`, or the nearest non-free cell within one cell — extends at least
/// `span` metres along x or y, or reaches the grid's border. The flood stops as soon as it
/// knows, so a long wall costs a flood of about `span` around the jamb.
pub fn spans(known: &OccupancyGrid, p: [f64; 2], span: f64) -> bool {
    let (c0, r0) = known.world_to_cell(p[0], p[1]);
    let non_free = |c: i64, r: i64| !known.contains(c, r) || known.get_i(c, r) != Cell::Free;
    let start = (-1..=1)
        .flat_map(|dr| (-1..=1).map(move |dc| (c0 + dc, r0 + dr)))
        .filter(|&(c, r)| non_free(c, r))
        .min_by_key(|&(c, r)| (c - c0).abs() + (r - r0).abs());
    let Some(start) = start else {
        return false;
    };
    let need = (span / known.resolution()).ceil() as i64;
    // The flood stays within `need` cells of `start` (popping a cell `need − 1` away already
    // decides), so a window of that radius replaces a hash set; a cell beyond it would decide
    // the same way.
    let side = 2 * need + 1;
    let mut seen = vec![false; (side * side) as usize];
    let slot = |(c, r): (i64, i64)| {
        let (dc, dr) = (c - start.0 + need, r - start.1 + need);
        ((0..side).contains(&dc) && (0..side).contains(&dr)).then(|| (dr * side + dc) as usize)
    };
    seen[slot(start).unwrap_or_default()] = true;
    let mut queue = std::collections::VecDeque::from([start]);
    let (mut lo, mut hi) = (start, start);
    while let Some((c, r)) = queue.pop_front() {
        if !known.contains(c, r) {
            return true; // the obstacle runs off the map: a wall of the building
        }
        lo = (lo.0.min(c), lo.1.min(r));
        hi = (hi.0.max(c), hi.1.max(r));
        if hi.0 - lo.0 + 1 >= need || hi.1 - lo.1 + 1 >= need {
            return true;
        }
        for dr in -1..=1 {
            for dc in -1..=1 {
                let n = (c + dc, r + dr);
                if (dc, dr) == (0, 0) || !non_free(n.0, n.1) {
                    continue;
                }
                let Some(i) = slot(n) else {
                    return true; // as far from `start` as an obstacle of `need` cells
                };
                if !seen[i] {
                    seen[i] = true;
                    queue.push_back(n);
                }
            }
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The definition, by brute force: flood the whole obstacle (off-map cells count as
    /// non-free) and measure it.
    fn spans_by_whole_flood(known: &OccupancyGrid, p: [f64; 2], span: f64) -> bool {
        let (c0, r0) = known.world_to_cell(p[0], p[1]);
        let non_free = |c: i64, r: i64| !known.contains(c, r) || known.get_i(c, r) != Cell::Free;
        let Some(start) = (-1..=1)
            .flat_map(|dr| (-1..=1).map(move |dc| (c0 + dc, r0 + dr)))
            .filter(|&(c, r)| non_free(c, r))
            .min_by_key(|&(c, r)| (c - c0).abs() + (r - r0).abs())
        else {
            return false;
        };
        let mut seen = std::collections::HashSet::from([start]);
        let mut todo = vec![start];
        while let Some((c, r)) = todo.pop() {
            if !known.contains(c, r) {
                return true;
            }
            for (dc, dr) in (-1..=1).flat_map(|dr| (-1..=1).map(move |dc| (dc, dr))) {
                let n = (c + dc, r + dr);
                if non_free(n.0, n.1) && seen.insert(n) {
                    todo.push(n);
                }
            }
        }
        let need = (span / known.resolution()).ceil() as i64;
        let extent = |f: fn(&(i64, i64)) -> i64| {
            seen.iter().map(f).max().unwrap_or(0) - seen.iter().map(f).min().unwrap_or(0) + 1
        };
        extent(|c| c.0) >= need || extent(|c| c.1) >= need
    }

    proptest! {
        #[test]
        fn spans_agrees_with_flooding_the_whole_obstacle(
            cells in proptest::collection::vec(prop_oneof![6 => Just(Cell::Free), 2 => Just(Cell::Occupied), 1 => Just(Cell::Unknown)], 24 * 24),
            at in (0.0f64..6.0, 0.0f64..6.0),
            span in 0.0f64..3.0,
        ) {
            let mut g = OccupancyGrid::new(24, 24, 0.25, [0.0, 0.0], Cell::Free).unwrap();
            for (i, &c) in cells.iter().enumerate() {
                g.set(i % 24, i / 24, c);
            }
            let p = [at.0, at.1];
            prop_assert_eq!(spans(&g, p, span), spans_by_whole_flood(&g, p, span));
        }
    }
}
