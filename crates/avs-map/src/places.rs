//! The place map: places, paths, doors, placeholders and rooms (Aydemir et al.,
//! `002_ff7a0884d9f6f2df.txt` §II-B.1–2; Sjöö et al., `004_eb11ea0b2ea7be93.txt` §2).
//!
//! * **Places** are dropped along the space the robot traverses, one whenever no existing place
//!   within `spacing` (default 1 m) is in sight over known free space ([`PlaceMap::place_at`]):
//!   the robot walking along a corridor wall is not at the place a metre away in the room
//!   behind it, and the path that moving "to" that place would record joins the two rooms
//!   beside their door.
//! * **Paths** join places the robot travelled between, and places that see each other over
//!   known free space within `2.5 × spacing` — but a path never crosses a door opening unless one
//!   end is that door's place, so doors stay cut points.
//! * **Doors** are the hypotheses of [`crate::doors::detect_doors`], run on an optimistic copy of
//!   the known grid (unknown taken as free, so a doorway seen from one side qualifies) and kept
//!   when the opening has been seen and sits in a wall ([`in_a_wall`]: the obstacle continues
//!   along the opening's line beyond both jambs, and each jamb is part of an obstacle at least
//!   [`WALL_SPAN`] long — the gap between a table and a wall is neither).
//!   When the robot's motion crosses an opening the door is *confirmed*: a door place is put at
//!   its centre, places dropped in the doorway before are absorbed into it, and earlier paths
//!   across the opening (or across the wall within a metre of it, between places that do not
//!   see each other) are cut, so every way through runs via the door place; a walk recorded
//!   later is routed through the door place by the same rule.
//! * **Placeholders** sit on the frontier between known free and unknown space: one per connected
//!   frontier segment at least `min_frontier` long, hanging off the nearest place that sees it,
//!   with the open area around it and the distance to the nearest door hypothesis — the two cues
//!   of the placeholder hypotheses of §III-A.1. The open area is the space not yet covered by
//!   places: a flood fill from the frontier segment through unknown cells and through known free
//!   cells farther than `covered_distance` from every place (space seen, e.g. through an open
//!   door, but not visited), up to `open_area_radius` from the placeholder and bounded by known
//!   obstacles. This follows the papers' placeholders, which stand for free space beyond the
//!   place graph rather than for laser frontiers alone. A placeholder seen through a door — the
//!   straight line from the place it hangs off crosses the door's line at the opening or within a
//!   metre beyond a jamb — lies in the room behind that door, so its door distance is 0.
//! * **Rooms** are the connected components of the place graph once door places are cut out,
//!   with the neighbours of a door place on the same side of its opening in one room: the robot
//!   that walked from the corridor to a door and from the door along the corridor left two
//!   corridor places joined only through the door place, and the corridor was two rooms at
//!   some cell sizes and one at others. Each room is named by its smallest place index, so
//!   names are stable while it grows.

use crate::doors::{detect_doors, DoorHypothesis, DoorParams};
use crate::grid::{Cell, OccupancyGrid};
use crate::memo::Memo;
use crate::raycast::line_of_sight;

mod rooms;
mod walls;
use petgraph::graph::NodeIndex;
use petgraph::stable_graph::StableUnGraph;
use petgraph::visit::{EdgeRef, IntoEdgeReferences};
use std::collections::VecDeque;
pub use walls::{in_a_wall, spans, WALL_SPAN};

/// Parameters of the place map.
#[derive(Debug, Clone, PartialEq)]
pub struct PlaceMapParams {
    /// Distance between dropped places, metres.
    pub spacing: f64,
    /// Door detection parameters (width range from the knowledge file).
    pub doors: DoorParams,
    /// Shortest frontier segment that gets a placeholder, metres.
    pub min_frontier: f64,
    /// How far around a placeholder open space is counted, metres.
    pub open_area_radius: f64,
    /// Known free space farther than this from every place counts as open (not yet visited),
    /// metres.
    pub covered_distance: f64,
}

impl Default for PlaceMapParams {
    fn default() -> Self {
        Self {
            spacing: 1.0,
            doors: DoorParams::default(),
            min_frontier: 0.5,
            open_area_radius: 3.0,
            covered_distance: 2.0,
        }
    }
}

/// A place.
#[derive(Debug, Clone, PartialEq)]
pub struct Place {
    /// World position, metres.
    pub pos: [f64; 2],
    /// The door (index into [`PlaceMap::doors`]) if this is a door place.
    pub door: Option<usize>,
}

/// A path between two places.
#[derive(Debug, Clone, PartialEq)]
pub struct PathEdge {
    /// Straight-line length, metres.
    pub length: f64,
    /// Whether the robot travelled it (otherwise it was seen to be free).
    pub traversed: bool,
}

/// A door hypothesis in the place map.
#[derive(Debug, Clone, PartialEq)]
pub struct MapDoor {
    /// The geometric hypothesis.
    pub hypothesis: DoorHypothesis,
    /// Whether the robot has passed through it.
    pub confirmed: bool,
    /// Its door place, once confirmed.
    pub place: Option<NodeIndex>,
}

/// A placeholder: where the known free space meets the unknown.
#[derive(Debug, Clone, PartialEq)]
pub struct Placeholder {
    /// World position: the frontier cell nearest to the segment's centroid.
    pub pos: [f64; 2],
    /// The place it hangs off.
    pub place: NodeIndex,
    /// Length of the frontier segment, metres.
    pub frontier_length: f64,
    /// Open area around it (unknown, or seen but farther than `covered_distance` from every
    /// place), m².
    pub open_area: f64,
    /// Distance to the nearest door hypothesis, metres; 0 when it is seen through a door.
    pub door_distance: Option<f64>,
}

/// A room of the place map.
#[derive(Debug, Clone, PartialEq)]
pub struct MapRoom {
    /// Stable id: the smallest place index in the room.
    pub id: usize,
    /// Its places (no door places).
    pub places: Vec<NodeIndex>,
}

/// Rooms and how doors join them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Rooms {
    /// The rooms, ordered by id.
    pub rooms: Vec<MapRoom>,
    /// `(room a, room b, door index)` for every door place joining two rooms (room indices into
    /// `rooms`).
    pub adjacency: Vec<(usize, usize, usize)>,
}

impl Rooms {
    /// Index into `rooms` of the room holding `place` (door places belong to no room).
    pub fn room_of(&self, place: NodeIndex) -> Option<usize> {
        self.rooms.iter().position(|r| r.places.contains(&place))
    }
}

/// The place map.
#[derive(Debug, Clone)]
pub struct PlaceMap {
    /// Places and paths.
    pub graph: StableUnGraph<Place, PathEdge>,
    /// Door hypotheses; confirmed ones are kept, the rest are refreshed by [`Self::update`].
    pub doors: Vec<MapDoor>,
    /// Placeholders, refreshed by [`Self::update`].
    pub placeholders: Vec<Placeholder>,
    /// Parameters.
    pub params: PlaceMapParams,
    current: Option<NodeIndex>,
    /// The known grid of the last door detection and its hypotheses: most updates see the map
    /// of the one before (a look, a turn, the sync after a move), and detection is a pure
    /// function of the grid.
    door_cache: Memo<OccupancyGrid, Vec<DoorHypothesis>>,
    /// The placeholders of the last update and what they were found from (the known grid, and
    /// every place with its position and whether it is a door place): as pure a function of
    /// those as the doors are of the grid, and most of an update's time on large maps.
    placeholder_cache: Memo<PlaceholderInputs, Vec<Placeholder>>,
}

/// What [`PlaceMap::find_placeholders`] reads: the known grid, and every place with its
/// position and whether it is a door place.
type PlaceholderInputs = (OccupancyGrid, Vec<(NodeIndex, [f64; 2], bool)>);

impl PlaceMap {
    /// An empty place map.
    pub fn new(params: PlaceMapParams) -> Self {
        Self {
            graph: StableUnGraph::default(),
            doors: Vec::new(),
            placeholders: Vec::new(),
            params,
            current: None,
            door_cache: Memo::default(),
            placeholder_cache: Memo::default(),
        }
    }

    /// The place the robot is at (the last one it reached).
    pub fn current_place(&self) -> Option<NodeIndex> {
        self.current
    }

    /// The place nearest to a point.
    pub fn nearest_place(&self, p: [f64; 2]) -> Option<NodeIndex> {
        self.graph
            .node_indices()
            .min_by(|&a, &b| dist(self.graph[a].pos, p).total_cmp(&dist(self.graph[b].pos, p)))
    }

    /// The place whose region holds `p`: the nearest place within `spacing` that `p` sees over
    /// known free space, or `None` when there is none. A place on the far side of a wall is
    /// not where the robot stands, however near: the robot walking along a corridor within a
    /// metre of a place inside a room would otherwise "travel" to it through the wall, and the
    /// path recorded for that joins the room to the corridor beside its door.
    pub fn place_at(&self, known: &OccupancyGrid, p: [f64; 2]) -> Option<NodeIndex> {
        let mut near: Vec<(f64, NodeIndex)> = self
            .graph
            .node_indices()
            .map(|n| (dist(self.graph[n].pos, p), n))
            .filter(|&(d, _)| d <= self.params.spacing)
            .collect();
        near.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        near.into_iter()
            .map(|(_, n)| n)
            .find(|&n| line_of_sight(known, self.graph[n].pos, p, true))
    }

    /// The robot moved in a straight line from `from` to `to` over the known grid: confirm the
    /// doors it passed through and drop places along the way.
    pub fn robot_moved(&mut self, known: &OccupancyGrid, from: [f64; 2], to: [f64; 2]) {
        if self.current.is_none() {
            self.current = Some(self.add_place(known, from, None));
        }
        // Doors crossed on this step, in order along the segment.
        let mut crossed: Vec<(f64, usize)> = self
            .doors
            .iter()
            .enumerate()
            .filter(|(_, d)| d.hypothesis.crossed_by(from, to))
            .map(|(i, d)| (dist(from, d.hypothesis.center), i))
            .collect();
        crossed.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (_, i) in crossed {
            let place = match self.doors[i].place {
                Some(p) => p,
                None => {
                    let p = self.add_place(known, self.doors[i].hypothesis.center, Some(i));
                    self.doors[i].place = Some(p);
                    self.absorb_places_in_opening(i, p);
                    self.cut_paths_through(known, i);
                    p
                }
            };
            self.doors[i].confirmed = true;
            self.link_traversed(known, self.current.expect("set above"), place);
            self.current = Some(place);
        }
        let cur = self.current.expect("set above");
        let Some(near) = self.place_at(known, to) else {
            let p = self.add_place(known, to, None);
            self.link_traversed(known, cur, p);
            self.current = Some(p);
            return;
        };
        if near != cur {
            // The robot is now in the region of another existing place: it travelled there.
            if !self.crosses_foreign_door(self.graph[cur].pos, self.graph[near].pos, &[cur, near]) {
                self.link_traversed(known, cur, near);
            }
            self.current = Some(near);
        }
    }

    /// Refresh door hypotheses and placeholders from the known grid.
    pub fn update(&mut self, known: &OccupancyGrid) {
        self.refresh_doors(known);
        let places: Vec<(NodeIndex, [f64; 2], bool)> = self
            .graph
            .node_indices()
            .map(|n| (n, self.graph[n].pos, self.graph[n].door.is_some()))
            .collect();
        let mut memo = std::mem::take(&mut self.placeholder_cache);
        self.placeholders =
            memo.get_or_insert_with((known.clone(), places), || self.find_placeholders(known));
        self.placeholder_cache = memo;
    }

    /// Refresh the door hypotheses alone from the known grid (the first half of
    /// [`Self::update`]; the detection is cached on the grid): what a motion step checks its
    /// crossings against before its places and placeholders are updated.
    pub fn refresh_doors(&mut self, known: &OccupancyGrid) {
        // Keep confirmed doors; replace the rest by the current hypotheses that do not
        // duplicate a confirmed one.
        self.doors.retain(|d| d.confirmed);
        // Doorways seen from one side have unknown space behind them: detect on the optimistic
        // map (unknown taken as free) and keep the hypotheses whose opening the robot has seen.
        let params = &self.params.doors;
        let hypotheses = self.door_cache.get_or_insert_with(known.clone(), || {
            let mut optimistic = known.clone();
            for row in 0..known.height() {
                for col in 0..known.width() {
                    if known.get(col, row) == Cell::Unknown {
                        optimistic.set(col, row, Cell::Free);
                    }
                }
            }
            detect_doors(&optimistic, params)
        });
        for h in hypotheses {
            let (c, r) = known.world_to_cell(h.center[0], h.center[1]);
            if known.get_i(c, r) != Cell::Free || !in_a_wall(known, &h) {
                continue;
            }
            if self
                .doors
                .iter()
                .all(|d| dist(d.hypothesis.center, h.center) > self.params.doors.max_width)
            {
                self.doors.push(MapDoor {
                    hypothesis: h,
                    confirmed: false,
                    place: None,
                });
            }
        }
        // Door indices of door places may have moved: re-point them.
        for (i, d) in self.doors.iter().enumerate() {
            if let Some(p) = d.place {
                self.graph[p].door = Some(i);
            }
        }
    }

    fn add_place(
        &mut self,
        known: &OccupancyGrid,
        pos: [f64; 2],
        door: Option<usize>,
    ) -> NodeIndex {
        let n = self.graph.add_node(Place { pos, door });
        // Paths to places it can see nearby, never through another door's opening.
        let reach = 2.5 * self.params.spacing;
        let others: Vec<NodeIndex> = self.graph.node_indices().filter(|&m| m != n).collect();
        for m in others {
            let pm = self.graph[m].pos;
            let d = dist(pm, pos);
            if d <= reach
                && line_of_sight(known, pm, pos, true)
                && !self.crosses_foreign_door(pm, pos, &[n, m])
                && self.graph.find_edge(n, m).is_none()
            {
                self.graph.add_edge(
                    n,
                    m,
                    PathEdge {
                        length: d,
                        traversed: false,
                    },
                );
            }
        }
        n
    }

    /// Places dropped in the doorway before door `i` was known become its door place `p`: their
    /// paths move to `p` and they are removed (node indices are stable).
    fn absorb_places_in_opening(&mut self, i: usize, p: NodeIndex) {
        let [a, b] = self.doors[i].hypothesis.jambs;
        let inside: Vec<NodeIndex> = self
            .graph
            .node_indices()
            .filter(|&n| {
                n != p
                    && self.graph[n].door.is_none()
                    && point_segment_distance(self.graph[n].pos, a, b) < 0.3
            })
            .collect();
        for n in inside {
            let nbrs: Vec<NodeIndex> = self.graph.neighbors(n).filter(|&m| m != p).collect();
            for m in nbrs {
                let (pm, pp) = (self.graph[m].pos, self.graph[p].pos);
                if self.graph.find_edge(m, p).is_none()
                    && !self.crosses_foreign_door(pm, pp, &[m, p])
                {
                    self.graph.add_edge(
                        m,
                        p,
                        PathEdge {
                            length: dist(pm, pp),
                            traversed: true,
                        },
                    );
                }
            }
            self.graph.remove_node(n);
            if self.current == Some(n) {
                self.current = Some(p);
            }
        }
    }

    /// Remove the paths made before door `i` was known that cross its opening: from now on the
    /// only way through is its door place.
    fn cut_paths_through(&mut self, known: &OccupancyGrid, i: usize) {
        let d = &self.doors[i];
        let crossing: Vec<_> = self
            .graph
            .edge_indices()
            .filter(|&e| {
                let (a, b) = self.graph.edge_endpoints(e).expect("live edge");
                let (pa, pb) = (self.graph[a].pos, self.graph[b].pos);
                Some(a) != d.place
                    && Some(b) != d.place
                    && goes_through(known, &d.hypothesis, pa, pb)
            })
            .collect();
        for e in crossing {
            self.graph.remove_edge(e);
        }
    }

    fn link_traversed(&mut self, known: &OccupancyGrid, a: NodeIndex, b: NodeIndex) {
        if a == b {
            return;
        }
        // A travelled path whose straight line goes through a confirmed door ([`goes_through`])
        // went through that door: record it as two paths via the door place, so the door stays
        // a cut point.
        let (pa, pb) = (self.graph[a].pos, self.graph[b].pos);
        let via = self.doors.iter().find_map(|d| {
            let p = d.place?;
            (d.confirmed && p != a && p != b && goes_through(known, &d.hypothesis, pa, pb))
                .then_some(p)
        });
        if let Some(p) = via {
            for (x, y) in [(a, p), (p, b)] {
                if self.graph.find_edge(x, y).is_none() {
                    let length = dist(self.graph[x].pos, self.graph[y].pos);
                    self.graph.add_edge(
                        x,
                        y,
                        PathEdge {
                            length,
                            traversed: true,
                        },
                    );
                }
            }
            return;
        }
        let length = dist(self.graph[a].pos, self.graph[b].pos);
        match self.graph.find_edge(a, b) {
            Some(e) => self.graph[e].traversed = true,
            None => {
                self.graph.add_edge(
                    a,
                    b,
                    PathEdge {
                        length,
                        traversed: true,
                    },
                );
            }
        }
    }

    /// Whether the segment crosses a door opening whose door place is not one of `ends`.
    fn crosses_foreign_door(&self, a: [f64; 2], b: [f64; 2], ends: &[NodeIndex]) -> bool {
        self.doors.iter().any(|d| {
            let crosses = if d.confirmed {
                crosses_door_wall(&d.hypothesis, a, b)
            } else {
                d.hypothesis.crossed_by(a, b) || d.hypothesis.crossed_by(b, a)
            };
            crosses && !d.place.is_some_and(|p| ends.contains(&p))
        })
    }

    fn find_placeholders(&self, known: &OccupancyGrid) -> Vec<Placeholder> {
        if self.graph.node_count() == 0 {
            return Vec::new();
        }
        let (w, h) = (known.width() as i64, known.height() as i64);
        let is_frontier = |c: i64, r: i64| {
            known.get_i(c, r) == Cell::Free
                && [(1, 0), (-1, 0), (0, 1), (0, -1)].iter().any(|(dc, dr)| {
                    known.contains(c + dc, r + dr) && known.get_i(c + dc, r + dr) == Cell::Unknown
                })
        };
        let mut seen = vec![false; (w * h) as usize];
        let res = known.resolution();
        let min_cells = (self.params.min_frontier / res).ceil() as usize;
        let mut out = Vec::new();
        for r in 0..h {
            for c in 0..w {
                let k = (r * w + c) as usize;
                if seen[k] || !is_frontier(c, r) {
                    continue;
                }
                let mut cluster = vec![];
                let mut q = VecDeque::from([(c, r)]);
                seen[k] = true;
                while let Some((cc, rr)) = q.pop_front() {
                    cluster.push((cc, rr));
                    for dc in -1..=1 {
                        for dr in -1..=1 {
                            let (nc, nr) = (cc + dc, rr + dr);
                            if known.contains(nc, nr) {
                                let nk = (nr * w + nc) as usize;
                                if !seen[nk] && is_frontier(nc, nr) {
                                    seen[nk] = true;
                                    q.push_back((nc, nr));
                                }
                            }
                        }
                    }
                }
                if cluster.len() < min_cells {
                    continue;
                }
                let (sx, sy) = cluster.iter().fold((0.0, 0.0), |(sx, sy), &(cc, rr)| {
                    let p = known.cell_center(cc, rr);
                    (sx + p.0, sy + p.1)
                });
                let centroid = [sx / cluster.len() as f64, sy / cluster.len() as f64];
                let &(pc, pr) = cluster
                    .iter()
                    .min_by(|a, b| {
                        let pa = known.cell_center(a.0, a.1);
                        let pb = known.cell_center(b.0, b.1);
                        dist([pa.0, pa.1], centroid).total_cmp(&dist([pb.0, pb.1], centroid))
                    })
                    .expect("non-empty cluster");
                let p = known.cell_center(pc, pr);
                let pos = [p.0, p.1];
                let Some(place) = self.attach_place(known, pos) else {
                    continue;
                };
                let open_area = self.open_area_behind(known, &cluster, pos);
                let from = self.graph[place].pos;
                let door_distance = self
                    .doors
                    .iter()
                    .map(|d| {
                        if crosses_door_wall(&d.hypothesis, from, pos) {
                            0.0
                        } else {
                            dist(d.hypothesis.center, pos)
                        }
                    })
                    .min_by(f64::total_cmp);
                out.push(Placeholder {
                    pos,
                    place,
                    frontier_length: cluster.len() as f64 * res,
                    open_area,
                    door_distance,
                });
            }
        }
        out
    }

    /// The nearest non-door place that sees `pos` over known free space, else the nearest place.
    fn attach_place(&self, known: &OccupancyGrid, pos: [f64; 2]) -> Option<NodeIndex> {
        let mut cands: Vec<NodeIndex> = self.graph.node_indices().collect();
        cands.sort_by(|&a, &b| {
            dist(self.graph[a].pos, pos).total_cmp(&dist(self.graph[b].pos, pos))
        });
        cands
            .iter()
            .copied()
            .find(|&n| {
                self.graph[n].door.is_none() && line_of_sight(known, self.graph[n].pos, pos, true)
            })
            .or_else(|| cands.first().copied())
    }

    fn open_area_behind(
        &self,
        known: &OccupancyGrid,
        cluster: &[(i64, i64)],
        pos: [f64; 2],
    ) -> f64 {
        let res = known.resolution();
        let r2 = (self.params.open_area_radius / res).powi(2);
        let (pc, pr) = known.world_to_cell(pos[0], pos[1]);
        // Places near enough to cover some cell within the radius.
        let reach = self.params.open_area_radius + self.params.covered_distance;
        let near: Vec<[f64; 2]> = self
            .graph
            .node_weights()
            .map(|p| p.pos)
            .filter(|&q| dist(q, pos) <= reach)
            .collect();
        let covered2 = self.params.covered_distance.powi(2);
        let open = |c: i64, r: i64| match known.get_i(c, r) {
            Cell::Unknown => true,
            Cell::Free => {
                let (x, y) = known.cell_center(c, r);
                near.iter()
                    .all(|q| (q[0] - x).powi(2) + (q[1] - y).powi(2) > covered2)
            }
            _ => false,
        };
        // The fill never leaves the cluster's cells and their neighbours or the disc around `pos`:
        // mark visited cells in a bitmap over that box.
        let reach_cells = r2.sqrt().ceil() as i64;
        let (mut c0, mut r0, mut c1, mut r1) = (
            pc - reach_cells,
            pr - reach_cells,
            pc + reach_cells,
            pr + reach_cells,
        );
        for &(c, r) in cluster {
            (c0, r0, c1, r1) = (c0.min(c - 1), r0.min(r - 1), c1.max(c + 1), r1.max(r + 1));
        }
        let bw = c1 - c0 + 1;
        let mut seen = vec![false; (bw * (r1 - r0 + 1)) as usize];
        let at = |c: i64, r: i64| ((r - r0) * bw + (c - c0)) as usize;
        let mut q = VecDeque::new();
        for &(c, r) in cluster {
            for (dc, dr) in [(0, 0), (1, 0), (-1, 0), (0, 1), (0, -1)] {
                let (nc, nr) = (c + dc, r + dr);
                if known.contains(nc, nr) && !seen[at(nc, nr)] && open(nc, nr) {
                    seen[at(nc, nr)] = true;
                    q.push_back((nc, nr));
                }
            }
        }
        let mut count = 0usize;
        while let Some((c, r)) = q.pop_front() {
            count += 1;
            for (dc, dr) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
                let (nc, nr) = (c + dc, r + dr);
                let d2 = ((nc - pc).pow(2) + (nr - pr).pow(2)) as f64;
                if d2 <= r2 && known.contains(nc, nr) && !seen[at(nc, nr)] && open(nc, nr) {
                    seen[at(nc, nr)] = true;
                    q.push_back((nc, nr));
                }
            }
        }
        count as f64 * res * res
    }

    /// Paths as `(a, b, edge)` triples, for drawing.
    pub fn paths(&self) -> impl Iterator<Item = (NodeIndex, NodeIndex, &PathEdge)> + '_ {
        self.graph
            .edge_references()
            .map(|e| (e.source(), e.target(), e.weight()))
    }
}

/// Whether the way between two places the robot travelled between went through door `h`:
/// their straight line crosses its opening, or crosses the wall within a metre beside it
/// ([`crosses_door_wall`]) and the two do not see each other over the known grid (the robot
/// cannot have walked through the wall, so it went round through the door). A line that
/// crosses the door's line beyond a jamb in plain sight crosses no wall there: the door's line
/// runs on into open space (a door near a room's corner, or a gap taken for a door), and the
/// robot walked straight — recording that walk through the door place joined the rooms on
/// either side of the wall the line runs into.
fn goes_through(known: &OccupancyGrid, h: &DoorHypothesis, a: [f64; 2], b: [f64; 2]) -> bool {
    h.crossed_by(a, b)
        || h.crossed_by(b, a)
        || (crosses_door_wall(h, a, b) && !line_of_sight(known, a, b, true))
}

/// Whether the segment `a`–`b` crosses the door's line within a metre beyond either jamb: a path
/// between places that crosses there went through the doorway (or through the wall around
/// it), so it must go through the door place instead. Checked both ways, so it is symmetric.
fn crosses_door_wall(h: &DoorHypothesis, a: [f64; 2], b: [f64; 2]) -> bool {
    const BEYOND: f64 = 1.0;
    let [ja, jb] = h.jambs;
    let Some(u) = h.axis() else {
        return false;
    };
    let wide = DoorHypothesis {
        jambs: [
            [ja[0] - BEYOND * u[0], ja[1] - BEYOND * u[1]],
            [jb[0] + BEYOND * u[0], jb[1] + BEYOND * u[1]],
        ],
        ..*h
    };
    wide.crossed_by(a, b) || wide.crossed_by(b, a)
}

/// Distance from point `p` to the segment `a`–`b`.
pub fn point_segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist(p, [a[0] + t * dx, a[1] + t * dy])
}

pub use crate::geometry::dist;

#[cfg(test)]
mod tests;
