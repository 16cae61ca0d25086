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
mod tests {
    use super::*;

    /// Two 4 m × 3 m rooms side by side, joined by a 0.9 m door in a 0.2 m wall; the free cells
    /// for which `known(col, row)` is false are unknown.
    fn two_rooms_with(known: impl Fn(usize, usize) -> bool) -> OccupancyGrid {
        walled(86, 34, |c, r| {
            if (42..44).contains(&c) && !(12..21).contains(&r) {
                '#'
            } else if known(c, r) {
                '.'
            } else {
                '?'
            }
        })
    }

    /// A `w` × `h` grid of 0.1 m cells, row 0 at the top, with a 0.2 m border wall; inside
    /// it, `cell(col, row)` gives each cell's character (`#`, `.` or `?`).
    fn walled(w: usize, h: usize, cell: impl Fn(usize, usize) -> char) -> OccupancyGrid {
        let rows: Vec<String> = (0..h)
            .map(|r| {
                (0..w)
                    .map(|c| {
                        let border = r < 2 || r >= h - 2 || c < 2 || c >= w - 2;
                        if border {
                            '#'
                        } else {
                            cell(c, r)
                        }
                    })
                    .collect()
            })
            .collect();
        OccupancyGrid::from_ascii(&(rows.join("\n") + "\n"), 0.1, [0.0, 0.0]).unwrap()
    }

    /// A confirmed door with jambs `jambs` and its door place at their middle; the place.
    fn confirmed_door(map: &mut PlaceMap, jambs: [[f64; 2]; 2], width: f64) -> NodeIndex {
        let center = [
            0.5 * (jambs[0][0] + jambs[1][0]),
            0.5 * (jambs[0][1] + jambs[1][1]),
        ];
        map.doors.push(MapDoor {
            hypothesis: DoorHypothesis {
                center,
                jambs,
                width,
            },
            confirmed: true,
            place: None,
        });
        let i = map.doors.len() - 1;
        let p = map.graph.add_node(Place {
            pos: center,
            door: Some(i),
        });
        map.doors[i].place = Some(p);
        p
    }

    /// `two_rooms_with`, the right room unknown or not.
    fn two_rooms(unknown_right: bool) -> OccupancyGrid {
        two_rooms_with(|c, _| !(unknown_right && c >= 44))
    }

    fn walk(map: &mut PlaceMap, g: &OccupancyGrid, pts: &[[f64; 2]]) {
        map.update(g);
        for w in pts.windows(2) {
            let n = (dist(w[0], w[1]) / 0.25).ceil() as usize;
            for i in 0..n {
                let t0 = i as f64 / n as f64;
                let t1 = (i + 1) as f64 / n as f64;
                let a = [
                    w[0][0] + t0 * (w[1][0] - w[0][0]),
                    w[0][1] + t0 * (w[1][1] - w[0][1]),
                ];
                let b = [
                    w[0][0] + t1 * (w[1][0] - w[0][0]),
                    w[0][1] + t1 * (w[1][1] - w[0][1]),
                ];
                map.robot_moved(g, a, b);
                map.update(g);
            }
        }
    }

    /// A free-standing 1.2 m × 0.8 m table in the left room, 1 m from its top wall, its long
    /// edge along the gap: a door-wide gap with a neck, but the table is an obstacle of its
    /// own, not a wall; the doorway's jambs are the building's walls.
    #[test]
    fn a_gap_beside_a_free_standing_table_is_no_door_in_a_wall() {
        let mut g = two_rooms(false);
        // Rows 2..32 are the room (0.2–3.2 m); the table spans x 1.4–2.6 m, y 1.4–2.2 m.
        for c in 14..26 {
            for r in 14..22 {
                g.set(c, r, Cell::Occupied);
            }
        }
        let hyps = detect_doors(&g, &DoorParams::default());
        let beside: Vec<&DoorHypothesis> = hyps
            .iter()
            .filter(|h| h.center[0] < 4.0 && (h.center[0] - 2.0).abs() < 1.0)
            .collect();
        assert!(!beside.is_empty(), "the detector finds the gap: {hyps:?}");
        for h in beside {
            assert!(!spans(&g, h.jambs[0], WALL_SPAN) || !spans(&g, h.jambs[1], WALL_SPAN));
            assert!(!in_a_wall(&g, h), "{h:?}");
        }
        let door = hyps
            .iter()
            .find(|h| (h.center[0] - 4.3).abs() < 0.3)
            .expect("the doorway");
        assert!(in_a_wall(&g, door), "{door:?}");
    }

    #[test]
    fn door_hypotheses_follow_the_grid_they_were_detected_on() {
        let open = two_rooms(false);
        let mut shut = open.clone();
        for c in 42..44 {
            for r in 12..21 {
                shut.set(c, r, Cell::Occupied);
            }
        }
        let mut map = PlaceMap::new(PlaceMapParams::default());
        let doors = |map: &PlaceMap| {
            map.doors
                .iter()
                .filter(|d| (d.hypothesis.center[0] - 4.3).abs() < 0.3)
                .count()
        };
        map.update(&shut);
        assert_eq!(doors(&map), 0, "a wall without a gap has no door");
        map.update(&open);
        assert_eq!(
            doors(&map),
            1,
            "the doorway in the wall is a door hypothesis"
        );
        map.update(&open);
        assert_eq!(doors(&map), 1, "the same grid gives the same hypotheses");
        map.update(&shut);
        assert_eq!(doors(&map), 0, "the gap closed again");
    }

    #[test]
    fn walking_through_a_door_splits_the_places_into_two_rooms() {
        let g = two_rooms(false);
        let mut map = PlaceMap::new(PlaceMapParams::default());
        walk(
            &mut map,
            &g,
            &[[1.0, 1.0], [3.5, 1.6], [5.0, 1.6], [7.5, 2.5]],
        );
        let confirmed: Vec<&MapDoor> = map.doors.iter().filter(|d| d.confirmed).collect();
        assert_eq!(confirmed.len(), 1, "doors: {:?}", map.doors);
        assert!(dist(confirmed[0].hypothesis.center, [4.3, 1.65]) < 0.3);
        let rooms = map.rooms();
        assert_eq!(rooms.rooms.len(), 2);
        assert_eq!(rooms.adjacency.len(), 1);
        for r in &rooms.rooms {
            let left = r.places.iter().all(|&p| map.graph[p].pos[0] < 4.2);
            let right = r.places.iter().all(|&p| map.graph[p].pos[0] > 4.4);
            assert!(left || right, "room {} straddles the wall", r.id);
        }
        // Places are about `spacing` apart along the walk (≈ 7.6 m walked).
        let n = map.graph.node_count();
        assert!((6..=12).contains(&n), "{n} places");
    }

    /// Two 4 m × 5.6 m rooms joined by a 0.9 m door at the bottom of the 0.2 m wall between
    /// them (x 4.2–4.4 m, door y 0.6–1.5 m). The robot enters the right room, walks up beside
    /// the wall, comes back out and walks up the left side of the same wall: for 3.5 m it passes
    /// within 0.8 m of the right room's places, more than a metre beyond the door's jamb. It
    /// is near them, not at them: the wall stays between the rooms.
    #[test]
    fn walking_beside_a_wall_never_joins_the_room_behind_it() {
        let h = 60;
        let g = walled(86, h, |c, r| {
            let y = (h - 1 - r) as f64 * 0.1;
            if (42..44).contains(&c) && !(0.6..1.5).contains(&y) {
                '#'
            } else {
                '.'
            }
        });
        let mut map = PlaceMap::new(PlaceMapParams::default());
        walk(
            &mut map,
            &g,
            &[
                [2.0, 1.05],
                [4.8, 1.05],
                [4.75, 5.0],
                [4.75, 1.05],
                [3.85, 1.05],
                [3.85, 5.0],
            ],
        );
        assert!(
            map.doors.iter().any(|d| d.confirmed),
            "the robot crossed the door: {:?}",
            map.doors
        );
        let rooms = map.rooms();
        assert_eq!(rooms.rooms.len(), 2, "{rooms:?}");
        for r in &rooms.rooms {
            let left = r.places.iter().all(|&p| map.graph[p].pos[0] < 4.2);
            let right = r.places.iter().all(|&p| map.graph[p].pos[0] > 4.4);
            assert!(left || right, "room {} straddles the wall", r.id);
        }
        for (a, b, _) in map.paths() {
            let (pa, pb) = (map.graph[a].pos, map.graph[b].pos);
            let door = map.graph[a].door.is_some() || map.graph[b].door.is_some();
            assert!(
                door || (pa[0] < 4.3) == (pb[0] < 4.3),
                "a path through the wall: {pa:?} – {pb:?}"
            );
        }
    }

    /// A confirmed door whose line runs into a side wall (here a gap between a desk and the
    /// wall, taken for a door): the robot walking in the room on the far side of that wall
    /// crosses the door's line 0.9 m beyond its jamb, in plain sight of where it came from. It
    /// walked straight, not through the door: the rooms on either side of the wall stay apart.
    #[test]
    fn a_walk_across_a_door_line_beyond_its_jamb_in_plain_sight_is_not_through_the_door() {
        let g = walled(86, 40, |c, _| if (42..44).contains(&c) { '#' } else { '.' });
        let mut map = PlaceMap::new(PlaceMapParams::default());
        let door = confirmed_door(&mut map, [[2.85, 0.85], [3.95, 0.95]], 1.0);
        let left = map.graph.add_node(Place {
            pos: [3.05, 1.6],
            door: None,
        });
        map.graph.add_edge(
            left,
            door,
            PathEdge {
                length: dist([3.05, 1.6], [3.4, 0.9]),
                traversed: true,
            },
        );
        map.current = Some(map.add_place(&g, [4.85, 2.0], None));
        for y in [1.75, 1.5, 1.25, 1.0, 0.75, 0.5] {
            let from = map.graph[map.current.unwrap()].pos;
            map.robot_moved(&g, from, [4.85, y]);
        }
        let right: Vec<NodeIndex> = map
            .graph
            .node_indices()
            .filter(|&n| map.graph[n].pos[0] > 4.3)
            .collect();
        assert!(right.len() >= 2, "places along the walk: {right:?}");
        for &n in &right {
            assert!(
                map.graph.find_edge(n, door).is_none(),
                "a path from {:?} to the door place across the wall",
                map.graph[n].pos
            );
        }
        let rooms = map.rooms();
        let of = |n: NodeIndex| rooms.rooms.iter().position(|r| r.places.contains(&n));
        assert_ne!(of(left), of(right[0]), "{rooms:?}");
    }

    /// A corridor below a door: the robot walked from the corridor's west end to the door
    /// and from the door along the corridor to its east end, so the two corridor places are
    /// joined only through the door place. They are one room; the place above the door is
    /// another.
    #[test]
    fn places_on_one_side_of_a_door_are_one_room_even_when_joined_only_through_it() {
        let mut map = PlaceMap::new(PlaceMapParams::default());
        let door = confirmed_door(&mut map, [[4.5, 2.5], [5.5, 2.5]], 0.9);
        let place =
            |map: &mut PlaceMap, pos: [f64; 2]| map.graph.add_node(Place { pos, door: None });
        let west = place(&mut map, [2.0, 1.5]);
        let east = place(&mut map, [8.0, 1.5]);
        let above = place(&mut map, [5.0, 4.0]);
        for p in [west, east, above] {
            let length = dist(map.graph[p].pos, map.graph[door].pos);
            map.graph.add_edge(
                p,
                door,
                PathEdge {
                    length,
                    traversed: true,
                },
            );
        }
        let rooms = map.rooms();
        assert_eq!(rooms.rooms.len(), 2, "{rooms:?}");
        let corridor = rooms
            .rooms
            .iter()
            .find(|r| r.places.contains(&west))
            .expect("a room holds the west place");
        assert!(corridor.places.contains(&east), "{rooms:?}");
        assert!(!corridor.places.contains(&above), "{rooms:?}");
        assert_eq!(rooms.adjacency.len(), 1, "{rooms:?}");
    }

    #[test]
    fn a_placeholder_hangs_at_the_unknown_room_behind_the_door_with_open_area() {
        let g = two_rooms(true);
        let mut map = PlaceMap::new(PlaceMapParams::default());
        walk(&mut map, &g, &[[1.0, 1.0], [3.0, 1.6]]);
        assert!(map.rooms().rooms.len() == 1);
        let ph = map
            .placeholders
            .iter()
            .max_by(|a, b| a.open_area.total_cmp(&b.open_area))
            .expect("a placeholder at the doorway");
        assert!(
            ph.pos[0] > 4.0 && ph.pos[0] < 4.5 && (1.2..2.1).contains(&ph.pos[1]),
            "{:?}",
            ph.pos
        );
        // Behind it lies a 4.1 m × 3 m unknown room, cut at the 3 m radius.
        assert!(ph.open_area > 6.0, "open area {}", ph.open_area);
        assert!(
            ph.door_distance.is_some_and(|d| d < 0.6),
            "{:?}",
            ph.door_distance
        );
    }

    /// `two_rooms` with the right room seen through the door: a band of it in front of the
    /// opening is known free, the rest unknown.
    fn right_room_seen_through_the_door() -> OccupancyGrid {
        two_rooms_with(|c, r| c < 44 || ((8..26).contains(&r) && c < 70))
    }

    #[test]
    fn a_placeholder_seen_through_a_door_is_behind_it_and_counts_the_unvisited_space() {
        let g = right_room_seen_through_the_door();
        let far_side = |params: PlaceMapParams| {
            let mut map = PlaceMap::new(params);
            walk(&mut map, &g, &[[1.0, 1.6], [3.0, 1.6]]);
            assert_eq!(
                map.rooms().rooms.len(),
                1,
                "the robot stayed in the left room"
            );
            map.placeholders
                .iter()
                .filter(|p| p.pos[0] > 4.6)
                .max_by(|a, b| a.open_area.total_cmp(&b.open_area))
                .cloned()
                .expect("a placeholder in the right room")
        };
        let ph = far_side(PlaceMapParams::default());
        // The line from its place in the left room passes through the opening.
        assert_eq!(ph.door_distance, Some(0.0), "{ph:?}");
        // Seen-but-unvisited free space counts: far more open area than the unknown cells
        // alone, which is what a map that counts every known cell as covered reports.
        let unknown_only = far_side(PlaceMapParams {
            covered_distance: f64::INFINITY,
            ..PlaceMapParams::default()
        });
        assert!(
            ph.open_area > unknown_only.open_area + 3.0,
            "open area {} vs unknown only {}",
            ph.open_area,
            unknown_only.open_area
        );
    }

    #[test]
    fn cells_take_the_room_reached_through_free_space_and_never_spill_through_a_door() {
        let g = two_rooms(false);
        let at = |labels: &[Option<usize>], x: f64, y: f64| {
            let (c, r) = g.world_to_cell(x, y);
            labels[(r * g.width() as i64 + c) as usize]
        };
        // Only the left room visited: the right room, seen through the open door, is no room.
        let mut map = PlaceMap::new(PlaceMapParams::default());
        walk(&mut map, &g, &[[1.0, 1.6], [3.6, 1.6]]);
        let rooms = map.rooms().rooms;
        assert_eq!(rooms.len(), 1);
        let labels = map.cell_rooms(&g);
        assert_eq!(
            at(&labels, 0.3, 0.3),
            Some(rooms[0].id),
            "far corner of the left room"
        );
        assert_eq!(at(&labels, 4.1, 0.3), Some(rooms[0].id), "beside the wall");
        assert_eq!(at(&labels, 5.0, 1.6), None, "just through the door");
        assert_eq!(at(&labels, 8.2, 3.0), None, "far corner of the right room");
        // Through the door and one step in: the right room's cells, up to its far corner, are the
        // right room's; the left room's stay the left room's.
        walk(&mut map, &g, &[[3.6, 1.6], [5.4, 1.6]]);
        let rooms = map.rooms();
        assert_eq!(rooms.rooms.len(), 2, "{:?}", rooms.rooms);
        let right = rooms
            .rooms
            .iter()
            .find(|r| r.places.iter().any(|&n| map.graph[n].pos[0] > 4.6))
            .expect("a room right of the wall")
            .id;
        let labels = map.cell_rooms(&g);
        assert_eq!(at(&labels, 8.2, 3.0), Some(right));
        assert_eq!(at(&labels, 4.7, 0.3), Some(right));
        assert_ne!(at(&labels, 3.9, 0.3), Some(right));
        // The wall between them is labelled (by either side), the outer border cell too.
        assert!(at(&labels, 4.3, 0.3).is_some());
    }
}
