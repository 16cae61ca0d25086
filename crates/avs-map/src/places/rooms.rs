//! The place map's rooms: the connected components of its place graph (door places cut out,
//! a door's same-side neighbours joined), and the room each known cell belongs to.

use super::{dist, MapRoom, PlaceMap, Rooms};
use crate::grid::{Cell, OccupancyGrid};
use petgraph::graph::NodeIndex;
use petgraph::unionfind::UnionFind;
use std::collections::{BTreeMap, VecDeque};

impl PlaceMap {
    /// The room of every cell of `known` (row-major, `MapRoom::id`), or `None` for cells no
    /// room reaches: each known free cell takes the room of the place nearest to it *through
    /// known free space* (a multi-source breadth-first search from the rooms' places, 4-connected
    /// so that it cannot slip diagonally through a line), with every door hypothesis's opening
    /// closed, so that a room never spills through a doorway into the space beyond it, seen but
    /// not visited. Obstacle cells (furniture footprints, walls) then take the room of the
    /// labelled free space around them, up to `OBSTACLE_REACH` metres deep. This is the room
    /// extent a search of "the room" covers; the nearest place in a straight line would hand
    /// the far half of a room entered only at its door to the corridor outside.
    pub fn cell_rooms(&self, known: &OccupancyGrid) -> Vec<Option<usize>> {
        const OBSTACLE_REACH: f64 = 1.0;
        let (w, h) = (known.width() as i64, known.height() as i64);
        let res = known.resolution();
        let idx = |c: i64, r: i64| (r * w + c) as usize;
        let mut closed = vec![false; (w * h) as usize];
        for d in &self.doors {
            let [a, b] = d.hypothesis.jambs;
            let n = (dist(a, b) / (0.25 * res)).ceil().max(1.0) as usize;
            for i in 0..=n {
                let t = i as f64 / n as f64;
                let (c, r) =
                    known.world_to_cell(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]));
                if known.contains(c, r) {
                    closed[idx(c, r)] = true;
                }
            }
        }
        let mut label: Vec<Option<usize>> = vec![None; (w * h) as usize];
        let mut q = VecDeque::new();
        for room in self.rooms().rooms {
            for &n in &room.places {
                let p = self.graph[n].pos;
                let (c, r) = known.world_to_cell(p[0], p[1]);
                if known.contains(c, r)
                    && known.get_i(c, r) == Cell::Free
                    && !closed[idx(c, r)]
                    && label[idx(c, r)].is_none()
                {
                    label[idx(c, r)] = Some(room.id);
                    q.push_back((c, r));
                }
            }
        }
        const STEPS: [(i64, i64); 4] = [(1, 0), (-1, 0), (0, 1), (0, -1)];
        let mut edge = Vec::new();
        while let Some((c, r)) = q.pop_front() {
            let l = label[idx(c, r)];
            for (dc, dr) in STEPS {
                let (nc, nr) = (c + dc, r + dr);
                if !known.contains(nc, nr) || label[idx(nc, nr)].is_some() {
                    continue;
                }
                match known.get_i(nc, nr) {
                    Cell::Free if !closed[idx(nc, nr)] => {
                        label[idx(nc, nr)] = l;
                        q.push_back((nc, nr));
                    }
                    Cell::Occupied => edge.push((c, r)),
                    _ => {}
                }
            }
        }
        // Into the obstacles, breadth first from the labelled free cells that touch them.
        let depth = (OBSTACLE_REACH / res).round() as usize;
        let mut q: VecDeque<(i64, i64, usize)> = edge.into_iter().map(|(c, r)| (c, r, 0)).collect();
        while let Some((c, r, k)) = q.pop_front() {
            if k >= depth {
                continue;
            }
            let l = label[idx(c, r)];
            for (dc, dr) in STEPS {
                let (nc, nr) = (c + dc, r + dr);
                if known.contains(nc, nr)
                    && label[idx(nc, nr)].is_none()
                    && known.get_i(nc, nr) == Cell::Occupied
                {
                    label[idx(nc, nr)] = l;
                    q.push_back((nc, nr, k + 1));
                }
            }
        }
        label
    }

    /// Rooms: connected components of the place graph without door places, the neighbours of
    /// a door place on the same side of its opening joined (see the module docs).
    pub fn rooms(&self) -> Rooms {
        let mut comp: BTreeMap<NodeIndex, usize> = BTreeMap::new();
        let mut rooms: Vec<MapRoom> = Vec::new();
        for start in self.graph.node_indices() {
            if self.graph[start].door.is_some() || comp.contains_key(&start) {
                continue;
            }
            let k = rooms.len();
            let mut places = vec![];
            let mut q = VecDeque::from([start]);
            comp.insert(start, k);
            while let Some(n) = q.pop_front() {
                places.push(n);
                for m in self.graph.neighbors(n) {
                    if self.graph[m].door.is_none() && !comp.contains_key(&m) {
                        comp.insert(m, k);
                        q.push_back(m);
                    }
                }
            }
            places.sort();
            rooms.push(MapRoom {
                id: places[0].index(),
                places,
            });
        }
        // A door separates its two sides, not the places on one side: two neighbours of a door
        // place on the same side of its opening are in one room even when no path joins them
        // except through the door place (the robot walked from one to the door and from the
        // door to the other; a corridor split in two at every door otherwise).
        let mut joined = UnionFind::<usize>::new(rooms.len());
        for n in self.graph.node_indices() {
            let Some(h) = self.graph[n].door.and_then(|d| self.doors.get(d)) else {
                continue;
            };
            let [a, b] = h.hypothesis.jambs;
            let side =
                |p: [f64; 2]| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]) >= 0.0;
            let mut first: [Option<usize>; 2] = [None, None];
            for m in self.graph.neighbors(n) {
                let Some(&k) = comp.get(&m) else { continue };
                let s = usize::from(side(self.graph[m].pos));
                match first[s] {
                    None => first[s] = Some(k),
                    Some(j) => {
                        joined.union(j, k);
                    }
                }
            }
        }
        let top = joined.into_labeling();
        if top.iter().enumerate().any(|(k, &t)| t != k) {
            // One room per set, named by its smallest place and kept in id order.
            let mut merged: BTreeMap<usize, Vec<NodeIndex>> = BTreeMap::new();
            for (k, r) in rooms.iter().enumerate() {
                merged.entry(top[k]).or_default().extend(&r.places);
            }
            let mut sets: Vec<(usize, Vec<NodeIndex>)> = merged.into_iter().collect();
            for (_, places) in &mut sets {
                places.sort();
            }
            sets.sort_by_key(|(_, places)| places[0]);
            let new_index: BTreeMap<usize, usize> =
                sets.iter().enumerate().map(|(i, (t, _))| (*t, i)).collect();
            rooms = sets
                .into_iter()
                .map(|(_, places)| MapRoom {
                    id: places[0].index(),
                    places,
                })
                .collect();
            for k in comp.values_mut() {
                *k = new_index[&top[*k]];
            }
        }
        let mut adjacency = Vec::new();
        for n in self.graph.node_indices() {
            if let Some(door) = self.graph[n].door {
                let mut sides: Vec<usize> = self
                    .graph
                    .neighbors(n)
                    .filter_map(|m| comp.get(&m).copied())
                    .collect();
                sides.sort();
                sides.dedup();
                for i in 0..sides.len() {
                    for j in i + 1..sides.len() {
                        adjacency.push((sides[i], sides[j], door));
                    }
                }
            }
        }
        Rooms { rooms, adjacency }
    }
}
