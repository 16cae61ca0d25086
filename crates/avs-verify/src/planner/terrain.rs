//! [`GridTerrain`]: the planners' [`Terrain`] on an occupancy grid — the one the verification
//! bench and the search agent both use.

use super::Terrain;
use avs_map::grid::OccupancyGrid;
use avs_map::nav::{shortest_path_within, Traversability};
use avs_map::raycast::{cells_on_segment, line_of_sight};
use std::cell::RefCell;
use std::collections::HashMap;

type Cell = (i64, i64);

/// A grid as the planners see it: the robot stands where its disc fits (`trav`), sees a
/// candidate when the straight line to it crosses no occupied cell (and no unknown one when
/// `unknown_blocks`), and drives straight legs where they are clear, grid paths elsewhere
/// (no longer than `max_path` metres: a leg longer than that counts as unreachable, so that
/// one planning call's cost stays bounded on a large map). Grid paths are cached by their end
/// cells for the terrain's lifetime (one planning call, or one bench trial on a fixed map).
pub struct GridTerrain<'g> {
    grid: &'g OccupancyGrid,
    trav: &'g Traversability,
    unknown_blocks: bool,
    max_path: f64,
    cache: RefCell<HashMap<(Cell, Cell), f64>>,
}

impl<'g> GridTerrain<'g> {
    /// The terrain of `grid` for a robot that fits where `trav` says.
    pub fn new(
        grid: &'g OccupancyGrid,
        trav: &'g Traversability,
        unknown_blocks: bool,
        max_path: f64,
    ) -> Self {
        Self {
            grid,
            trav,
            unknown_blocks,
            max_path,
            cache: RefCell::new(HashMap::new()),
        }
    }

    /// Whether the robot can stand at `p`.
    pub fn stands(&self, p: [f64; 2]) -> bool {
        let (c, r) = self.grid.world_to_cell(p[0], p[1]);
        self.trav.ok(c, r)
    }
}

impl Terrain for GridTerrain<'_> {
    fn can_view(&self, at: [f64; 2], target: [f64; 2]) -> bool {
        self.stands(at) && line_of_sight(self.grid, at, target, self.unknown_blocks)
    }

    fn distance(&self, a: [f64; 2], b: [f64; 2]) -> f64 {
        let g = self.grid;
        let clear = cells_on_segment(g, a, b)
            .into_iter()
            .all(|(c, r)| self.trav.ok(c, r));
        if clear {
            return (a[0] - b[0]).hypot(a[1] - b[1]);
        }
        let key = (g.world_to_cell(a[0], a[1]), g.world_to_cell(b[0], b[1]));
        if let Some(d) = self.cache.borrow().get(&key) {
            return *d;
        }
        let d = shortest_path_within(self.trav, a, b, 0.5, self.max_path)
            .map_or(f64::INFINITY, |p| p.length);
        self.cache.borrow_mut().insert(key, d);
        d
    }
}
