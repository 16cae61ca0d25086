//! Navigation on the grid: obstacle clearance, collision-free shortest paths (A*), and travel
//! distance fields (Dijkstra) for costing many goals at once.
//!
//! Moves are 8-connected (diagonals cost √2 cells); a cell is traversable when it is free and its
//! clearance — Euclidean distance to the nearest blocking cell, from the exact transform of
//! [`crate::doors::ClearanceMap`] — is at least the robot's radius.
//! Blocking cells are the occupied ones, and the unknown ones too unless the caller allows them.

use crate::doors::ClearanceMap;
use crate::grid::{Cell, OccupancyGrid};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

const SQRT2: f64 = std::f64::consts::SQRT_2;
const NEIGHBOURS: [(i64, i64, f64); 8] = [
    (1, 0, 1.0),
    (-1, 0, 1.0),
    (0, 1, 1.0),
    (0, -1, 1.0),
    (1, 1, SQRT2),
    (1, -1, SQRT2),
    (-1, 1, SQRT2),
    (-1, -1, SQRT2),
];

/// Which cells a robot of a given radius may occupy.
#[derive(Debug, Clone)]
pub struct Traversability {
    width: usize,
    height: usize,
    resolution: f64,
    origin: [f64; 2],
    ok: Vec<bool>,
    /// Occupied cells, and unknown ones unless they count as free.
    blocked: Vec<bool>,
}

impl Traversability {
    /// Traversable cells for a robot of `radius` metres; unknown cells block unless
    /// `unknown_is_free`.
    pub fn new(grid: &OccupancyGrid, radius: f64, unknown_is_free: bool) -> Self {
        let (w, h) = (grid.width(), grid.height());
        let blocked: Vec<bool> = grid
            .cells()
            .iter()
            .map(|&c| c == Cell::Occupied || (c == Cell::Unknown && !unknown_is_free))
            .collect();
        let free: Vec<bool> = blocked.iter().map(|b| !b).collect();
        let clearance = ClearanceMap::new(w, h, &free).expect("grid dimensions are valid");
        // The transform measures centre to centre; the nearest obstacle's edge is half a cell
        // closer. A robot of radius r fits where that clearance is at least r. Cells past the
        // grid's edge count as obstacles too.
        let r_cells = radius.max(0.0) / grid.resolution();
        let ok = (0..w * h)
            .map(|i| !blocked[i] && clearance.distance(i) - 0.5 >= r_cells)
            .collect();
        Self {
            width: w,
            height: h,
            resolution: grid.resolution(),
            origin: grid.origin(),
            ok,
            blocked,
        }
    }

    /// Whether the robot may stand in cell `(col, row)`.
    pub fn ok(&self, col: i64, row: i64) -> bool {
        col >= 0
            && row >= 0
            && (col as usize) < self.width
            && (row as usize) < self.height
            && self.ok[row as usize * self.width + col as usize]
    }

    /// The traversable cell nearest to cell `(col, row)` through free space, within
    /// `max_cells` of it (Chebyshev): the one with the shortest 8-connected way there that
    /// never steps from a free cell into a blocked one.
    ///
    /// A goal inside an obstacle (an object on a table, a point in a wall) leaves it on any
    /// side; a goal in free space stays on its own side of the walls. The nearest cell in a
    /// straight line may be behind a wall: a point just inside a room, closer to the wall than
    /// the robot's radius, would snap into the corridor on the wall's other side — whether it
    /// does depends on where the cell boundaries fall, so on the grid's resolution.
    pub fn nearest_ok(&self, col: i64, row: i64, max_cells: i64) -> Option<(i64, i64)> {
        if self.ok(col, row) {
            return Some((col, row));
        }
        // Dijkstra over the window around the cell; cells off the grid are blocked. No window
        // needs to be larger than the grid.
        let max_cells = max_cells.clamp(0, (self.width + self.height) as i64);
        let side = 2 * max_cells + 1;
        let at = |k: usize| {
            (
                col - max_cells + k as i64 % side,
                row - max_cells + k as i64 / side,
            )
        };
        let blocked = |c: i64, r: i64| {
            c < 0
                || r < 0
                || c as usize >= self.width
                || r as usize >= self.height
                || self.blocked[r as usize * self.width + c as usize]
        };
        let start = (max_cells * side + max_cells) as usize;
        let (_, found) = dijkstra(
            (side * side) as usize,
            start,
            |k, push| {
                let c = at(k);
                let from_free = !blocked(c.0, c.1);
                for &(dc, dr, cost) in &NEIGHBOURS {
                    let n = (c.0 + dc, c.1 + dr);
                    if (n.0 - col).abs() <= max_cells
                        && (n.1 - row).abs() <= max_cells
                        && !(from_free && blocked(n.0, n.1))
                    {
                        push(
                            ((n.1 - row + max_cells) * side + (n.0 - col + max_cells)) as usize,
                            cost,
                        );
                    }
                }
            },
            |k| {
                let c = at(k);
                self.ok(c.0, c.1)
            },
        );
        found.map(at)
    }

    fn cell_of(&self, p: [f64; 2]) -> (i64, i64) {
        (
            ((p[0] - self.origin[0]) / self.resolution).floor() as i64,
            ((p[1] - self.origin[1]) / self.resolution).floor() as i64,
        )
    }

    fn center(&self, c: (i64, i64)) -> [f64; 2] {
        [
            self.origin[0] + (c.0 as f64 + 0.5) * self.resolution,
            self.origin[1] + (c.1 as f64 + 0.5) * self.resolution,
        ]
    }
}

/// A path through the grid.
#[derive(Debug, Clone, PartialEq)]
pub struct GridPath {
    /// World points (cell centres) from start to goal.
    pub points: Vec<[f64; 2]>,
    /// Length in metres.
    pub length: f64,
}

#[derive(PartialEq)]
struct Entry {
    f: f64,
    g: f64,
    idx: usize,
}
impl Eq for Entry {}
impl Ord for Entry {
    fn cmp(&self, o: &Self) -> Ordering {
        // Min-heap on f, then larger g first (deeper), then index: deterministic.
        o.f.total_cmp(&self.f)
            .then(self.g.total_cmp(&o.g))
            .then(o.idx.cmp(&self.idx))
    }
}
impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// Shortest 8-connected path from `start` to `goal` (world points) by A* with the octile
/// heuristic. Start and goal snap to the nearest traversable cell within `snap` metres.
pub fn shortest_path(
    t: &Traversability,
    start: [f64; 2],
    goal: [f64; 2],
    snap: f64,
) -> Option<GridPath> {
    shortest_path_within(t, start, goal, snap, f64::INFINITY)
}

/// [`shortest_path`] when its length is at most `max_len` metres, else `None`.
///
/// The search stops as soon as the smallest `f = g + h` left exceeds the bound (the octile
/// heuristic is consistent, so no path through the rest can be shorter): asking whether a
/// short path exists costs a search of the cells within that length, not a flood of every
/// reachable cell when there is none.
pub fn shortest_path_within(
    t: &Traversability,
    start: [f64; 2],
    goal: [f64; 2],
    snap: f64,
    max_len: f64,
) -> Option<GridPath> {
    // In cells, with room for rounding in the sums of step costs.
    let bound = max_len / t.resolution * (1.0 + 1e-12) + 1e-9;
    let snap_cells = (snap / t.resolution).ceil() as i64;
    let s0 = t.cell_of(start);
    let g0 = t.cell_of(goal);
    let s = t.nearest_ok(s0.0, s0.1, snap_cells)?;
    let g = t.nearest_ok(g0.0, g0.1, snap_cells)?;
    let w = t.width;
    let idx = |c: (i64, i64)| c.1 as usize * w + c.0 as usize;
    let octile = |c: (i64, i64)| {
        let dx = (c.0 - g.0).abs() as f64;
        let dy = (c.1 - g.1).abs() as f64;
        dx.max(dy) + (SQRT2 - 1.0) * dx.min(dy)
    };
    SCRATCH.with_borrow_mut(|sc| {
        sc.reset(t.width * t.height);
        sc.set(idx(s), 0.0, usize::MAX);
        let mut heap = BinaryHeap::new();
        heap.push(Entry {
            f: octile(s),
            g: 0.0,
            idx: idx(s),
        });
        while let Some(Entry { f, g: gc, idx: i }) = heap.pop() {
            if f > bound {
                return None;
            }
            if gc > sc.best(i) {
                continue;
            }
            let c = ((i % w) as i64, (i / w) as i64);
            if c == g {
                let mut cells = vec![i];
                let mut cur = i;
                while sc.parent[cur] != usize::MAX {
                    cur = sc.parent[cur];
                    cells.push(cur);
                }
                cells.reverse();
                let points = cells
                    .iter()
                    .map(|&k| t.center(((k % w) as i64, (k / w) as i64)))
                    .collect();
                return Some(GridPath {
                    points,
                    length: gc * t.resolution,
                });
            }
            for &(dc, dr, cost) in &NEIGHBOURS {
                let nc = (c.0 + dc, c.1 + dr);
                if !t.ok(nc.0, nc.1) {
                    continue;
                }
                // No corner cutting: both side cells of a diagonal step must be traversable.
                if dc != 0 && dr != 0 && !(t.ok(c.0 + dc, c.1) && t.ok(c.0, c.1 + dr)) {
                    continue;
                }
                let ng = gc + cost;
                let ni = idx(nc);
                if ng < sc.best(ni) {
                    sc.set(ni, ng, i);
                    heap.push(Entry {
                        f: ng + octile(nc),
                        g: ng,
                        idx: ni,
                    });
                }
            }
        }
        None
    })
}

/// Per-cell costs and parents of one A* search, reused by the next: a cell's entries count only
/// when its stamp is the current search's, so a short search on a large grid costs the cells it
/// touches rather than clearing two arrays of the whole grid (on 30-room floors the agent asks
/// thousands of times whether a path of a few metres exists).
#[derive(Default)]
struct Scratch {
    best: Vec<f64>,
    parent: Vec<usize>,
    stamp: Vec<u32>,
    epoch: u32,
}

impl Scratch {
    fn reset(&mut self, n: usize) {
        if self.stamp.len() < n || self.epoch == u32::MAX {
            self.best = vec![f64::INFINITY; n];
            self.parent = vec![usize::MAX; n];
            self.stamp = vec![0; n];
            self.epoch = 0;
        }
        self.epoch += 1;
    }
    fn best(&self, i: usize) -> f64 {
        if self.stamp[i] == self.epoch {
            self.best[i]
        } else {
            f64::INFINITY
        }
    }
    fn set(&mut self, i: usize, cost: f64, parent: usize) {
        self.stamp[i] = self.epoch;
        self.best[i] = cost;
        self.parent[i] = parent;
    }
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::default();
}

/// Dijkstra over `n` nodes from `start`: `step(node, push)` pushes each neighbour with the
/// cost of the move there; the search stops at the first node settled for which `goal` holds.
/// The least costs found (∞ for nodes not reached) and that node, if any. Ties settle the
/// lower-cost-then-lower-index node first ([`Entry`]), so the result is deterministic.
fn dijkstra(
    n: usize,
    start: usize,
    mut step: impl FnMut(usize, &mut dyn FnMut(usize, f64)),
    mut goal: impl FnMut(usize) -> bool,
) -> (Vec<f64>, Option<usize>) {
    let mut best = vec![f64::INFINITY; n];
    let mut heap = BinaryHeap::new();
    best[start] = 0.0;
    heap.push(Entry {
        f: 0.0,
        g: 0.0,
        idx: start,
    });
    while let Some(Entry { g, idx, .. }) = heap.pop() {
        if g > best[idx] {
            continue;
        }
        if goal(idx) {
            return (best, Some(idx));
        }
        step(idx, &mut |next, cost| {
            let ng = g + cost;
            if ng < best[next] {
                best[next] = ng;
                heap.push(Entry {
                    f: ng,
                    g: ng,
                    idx: next,
                });
            }
        });
    }
    (best, None)
}

/// Travel distance in metres from `start` to every cell (∞ where unreachable), by Dijkstra with
/// the same moves as [`shortest_path`].
pub fn distance_field(t: &Traversability, start: [f64; 2], snap: f64) -> Vec<f64> {
    let n = t.width * t.height;
    let snap_cells = (snap / t.resolution).ceil() as i64;
    let s0 = t.cell_of(start);
    let Some(s) = t.nearest_ok(s0.0, s0.1, snap_cells) else {
        return vec![f64::INFINITY; n];
    };
    let w = t.width;
    let (mut best, _) = dijkstra(
        n,
        s.1 as usize * w + s.0 as usize,
        |i, push| {
            let c = ((i % w) as i64, (i / w) as i64);
            for &(dc, dr, cost) in &NEIGHBOURS {
                let nc = (c.0 + dc, c.1 + dr);
                if t.ok(nc.0, nc.1)
                    && (dc == 0 || dr == 0 || (t.ok(c.0 + dc, c.1) && t.ok(c.0, c.1 + dr)))
                {
                    push(nc.1 as usize * w + nc.0 as usize, cost);
                }
            }
        },
        |_| false,
    );
    for d in &mut best {
        *d *= t.resolution;
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn path_goes_around_a_wall_and_respects_robot_radius() {
        let g = OccupancyGrid::from_ascii(
            "############\n#..........#\n#..........#\n#####.######\n#..........#\n#..........#\n############\n",
            0.5,
            [0.0, 0.0],
        )
        .unwrap();
        // The gap is one cell (0.5 m): a robot of radius 0.2 passes, one of radius 0.3 does not.
        let thin = Traversability::new(&g, 0.2, false);
        let p =
            shortest_path(&thin, [0.75, 0.75], [0.75, 2.75], 0.5).expect("path through the gap");
        assert!(
            p.length > 2.0 + 2.0,
            "must detour via the gap, got {}",
            p.length
        );
        let fat = Traversability::new(&g, 0.3, false);
        assert!(shortest_path(&fat, [0.75, 0.75], [0.75, 2.75], 0.5).is_none());
    }

    #[test]
    fn a_goal_just_behind_a_wall_snaps_on_its_own_side() {
        // Two rooms, one above the other, split by a one-cell wall with a doorway at the east
        // end. Of the upper room only a strip along the wall is known (seen through the
        // doorway); the goal lies in it, too close to the wall for the robot. The nearest
        // traversable cell in a straight line is in the lower room, behind the wall.
        let g = OccupancyGrid::from_ascii(
            "##############\n#????????????#\n#????????????#\n#............#\n##########...#\n#............#\n#............#\n#............#\n##############\n",
            0.5,
            [0.0, 0.0],
        )
        .unwrap();
        let start = [2.25, 1.25];
        let goal = [2.25, 2.75];
        // On the known map no cell the robot fits in is near the goal on its side: no path,
        // rather than one to the wrong side of the wall.
        let known = Traversability::new(&g, 0.3, false);
        if let Some(p) = shortest_path(&known, start, goal, 1.5) {
            let end = *p.points.last().unwrap();
            assert!(end[1] > 2.5, "the goal snapped across the wall to {end:?}");
        }
        // With unknown space free, the path goes to the goal's side through the doorway.
        let optimistic = Traversability::new(&g, 0.3, true);
        let p = shortest_path(&optimistic, start, goal, 1.5).expect("a path via the doorway");
        let end = *p.points.last().unwrap();
        assert!(end[1] > 2.5, "the goal snapped across the wall to {end:?}");
        assert!(
            p.length > 8.0,
            "{} m cannot have used the doorway",
            p.length
        );
        // A goal inside the wall itself snaps to the nearest cell on either side.
        let q = shortest_path(&known, start, [2.25, 2.2], 1.5).expect("a path");
        assert!(
            q.length < 1.5,
            "{} m: a goal in a wall may snap to the near side",
            q.length
        );
    }

    /// A 20 × 14 grid with a wall around it and about one cell in six blocked, from `seed`.
    fn random_grid(seed: u64) -> OccupancyGrid {
        let (w, h) = (20usize, 14usize);
        let mut text = String::new();
        for r in 0..h {
            for c in 0..w {
                let border = r == 0 || c == 0 || r == h - 1 || c == w - 1;
                let v = (seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(((r * w + c) as u64).wrapping_mul(1442695040888963407)))
                    >> 59;
                text.push(if border || v < 5 { '#' } else { '.' });
            }
            text.push('\n');
        }
        OccupancyGrid::from_ascii(&text, 1.0, [0.0, 0.0]).unwrap()
    }

    #[test]
    fn a_path_search_is_not_disturbed_by_the_searches_before_it() {
        // The searches share per-thread scratch arrays: alternate grids of different sizes and
        // compare each path with the distance field computed afresh.
        let big = Traversability::new(&random_grid(7), 0.0, false);
        let open = OccupancyGrid::from_ascii(
            "##########\n#........#\n#..####..#\n#........#\n##########\n",
            1.0,
            [0.0, 0.0],
        )
        .unwrap();
        let small = Traversability::new(&open, 0.0, false);
        for round in 0..3 {
            for (t, w, goal) in [(&big, 20, [18.5, 12.5]), (&small, 10, [8.5, 1.5])] {
                let field = distance_field(t, [1.5, 1.5], 3.0);
                let p = shortest_path(t, [1.5, 1.5], goal, 3.0);
                let end = p.as_ref().and_then(|p| p.points.last().copied());
                match end {
                    Some(end) => {
                        let (c, r) = (end[0] as usize, end[1] as usize);
                        let l = p.as_ref().unwrap().length;
                        assert!((l - field[r * w + c]).abs() < 1e-9, "round {round}: {l}");
                    }
                    None => assert!(field[goal[1] as usize * w + goal[0] as usize].is_infinite()),
                }
            }
        }
    }

    proptest! {
        #[test]
        fn astar_length_equals_dijkstra_distance(seed in 0u64..500) {
            let w = 20usize;
            let g = random_grid(seed);
            let t = Traversability::new(&g, 0.0, false);
            let start = [1.5, 1.5];
            let field = distance_field(&t, start, 3.0);
            for goal in [[18.5, 12.5], [10.5, 7.5], [3.5, 11.5]] {
                match shortest_path(&t, start, goal, 3.0) {
                    Some(p) => {
                        // The goal may have snapped to a nearby traversable cell: compare there.
                        let end = *p.points.last().unwrap();
                        let (gc, gr) = g.world_to_cell(end[0], end[1]);
                        let via_field = field[gr as usize * w + gc as usize];
                        prop_assert!((p.length - via_field).abs() < 1e-9, "{} vs {via_field}", p.length);
                    }
                    None => {
                        let (gc, gr) = g.world_to_cell(goal[0], goal[1]);
                        prop_assert!(!t.ok(gc, gr) || field[gr as usize * w + gc as usize].is_infinite());
                    }
                }
            }
        }

        #[test]
        fn a_bounded_search_finds_the_same_path_when_it_is_short_enough_and_none_otherwise(
            seed in 0u64..300,
            slack in -3.0f64..3.0,
        ) {
            let t = Traversability::new(&random_grid(seed), 0.0, false);
            let start = [1.5, 1.5];
            for goal in [[18.5, 12.5], [10.5, 7.5], [3.5, 11.5]] {
                let full = shortest_path(&t, start, goal, 3.0);
                let max_len = full.as_ref().map_or(20.0, |p| p.length) + slack;
                let bounded = shortest_path_within(&t, start, goal, 3.0, max_len);
                match &full {
                    Some(p) if p.length <= max_len => prop_assert_eq!(bounded.as_ref(), Some(p)),
                    _ => prop_assert!(bounded.is_none()),
                }
            }
        }
    }
}
