//! [`Memory`]: what the agent knows and keeps between goals — the world model (place map and
//! conceptual map in step), the robot's laser map, the placeholders it tracks under stable
//! names, the objects it found, the view cones it planned, the sightings verification
//! rejected — and the questions asked of it: which room a point lies in, how long the known
//! path is, whether a sighting is new. Only [`crate::body::Body`] writes the map; [`sync`]
//! brings the rest in step with it.

mod sync;

use crate::config::Tuning;
use crate::run::PointKey;
use crate::world_model::WorldModel;
use avs_concepts::{LandmarkId, RoomId};
use avs_format::knowledge::{Knowledge, Relation};
use avs_map::grid::{Cell, OccupancyGrid};
use avs_map::memo::Memo;
use avs_map::nav::{shortest_path_within, Traversability};
use avs_map::places::dist;
use avs_map::pockets::Pocket;
use avs_map::raycast::walk_segment;
use avs_robot::{Detection, DoorSighting, Point3};
use avs_view::PlannedView;
use avs_view::Surface;
use petgraph::graph::NodeIndex;
use std::cell::RefCell;
use std::collections::{BTreeMap, BTreeSet};

/// A placeholder the agent tracks under a stable name.
#[derive(Debug, Clone)]
pub(crate) struct PhEntry {
    /// Its stable id (the plan name is `placeholder<id>`).
    pub id: usize,
    pub pos: [f64; 2],
    /// Set once explored: the room it was explored from and the place it led to, if any.
    pub explored: Option<(u64, Option<NodeIndex>)>,
}

/// An object the agent found (landmark or target).
#[derive(Debug, Clone)]
pub(crate) struct Known {
    pub class: String,
    pub pos: Point3,
    pub place: NodeIndex,
    pub landmark: Option<LandmarkId>,
    /// The known object (index) it lies on.
    pub on: Option<usize>,
    /// Whether a look around has counted it as object-count evidence (each instance counts
    /// once; one found by a search is counted by the first look around that sees it).
    pub counted: bool,
    /// The detector's confidence in the sighting that found it.
    pub confidence: f64,
}

/// Where view cones are planned: a room, or on or in a known object (index into the
/// objects).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum ConeLoc {
    Room(u64),
    On(usize),
    /// The interior of a landmark (a shelf's or cupboard's levels, `002` §II-B.1's L_o).
    In(usize),
}

impl ConeLoc {
    /// The landmark object, for a location on or in one.
    pub fn landmark(self) -> Option<usize> {
        match self {
            ConeLoc::Room(_) => None,
            ConeLoc::On(k) | ConeLoc::In(k) => Some(k),
        }
    }

    /// How the location relates to its landmark (`None` for a room).
    pub fn relation(self) -> Option<Relation> {
        match self {
            ConeLoc::Room(_) => None,
            ConeLoc::On(_) => Some(Relation::On),
            ConeLoc::In(_) => Some(Relation::In),
        }
    }
}

/// The view cones of one class at one location (CREATEVIEWCONES).
#[derive(Debug, Clone)]
pub(crate) struct ConeSet {
    pub views: Vec<PlannedView>,
    /// The location's points the cones were planned for.
    pub points: Vec<[f64; 3]>,
    /// The points each cone covers (cones overlap: a point may be in several).
    pub cells: Vec<Vec<usize>>,
    pub n_points: usize,
    pub covered_share: f64,
}

/// What a search's price was computed on: for a room its known cells, the points in it looked
/// at for the class and the known landmarks in it; for a landmark's top the same of its room
/// (it is looked at from there).
pub(crate) type PriceKey = (usize, usize, usize);

/// What a search of a location costs and how much of it the search looks at
/// (`skills::views::search_cost`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Price {
    /// The views' processing and the walk between their standpoints, metres.
    pub metres: f64,
    /// The share of the location's points (those not looked at yet, if any) the views cover.
    pub share: f64,
}

/// A (from, to) pair of positions.
pub(crate) type Segment = ([f64; 2], [f64; 2]);

/// A placeholder offered to the planner: a frontier placeholder of the place map, or a known
/// but unvisited free area (rooms exist only where the robot has been).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Cand {
    pub pos: [f64; 2],
    pub attach: NodeIndex,
    /// Its id in the conceptual map.
    pub cm_id: u64,
}

/// A place the robot can be sent to: a node of the place map, or a tracked placeholder (by
/// its stable id).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) enum Target {
    Place(NodeIndex),
    Placeholder(usize),
}

/// The agent's long-lived state; see the module docs.
#[derive(Debug, Clone)]
pub(crate) struct Memory {
    pub wm: WorldModel,
    pub grid: OccupancyGrid,
    pub registry: Vec<PhEntry>,
    pub next_ph: usize,
    pub objects: Vec<Known>,
    /// Rooms looked around in.
    pub looked: BTreeSet<u64>,
    /// Per class, the looks so far at each point (by [`Memory::point_key`]): how many
    /// processed view cones of the plan's searches held it. A look is a look wherever the
    /// search was (a room, a landmark's top): kept across sessions and searches, it weighs
    /// the next session's prior by `(1 − p_d)^looks` and thins the location's rate by what
    /// the looks removed (module `skills::session`).
    pub looks: BTreeMap<String, BTreeMap<PointKey, u32>>,
    /// Places whose properties were classified (once per place).
    pub classified: BTreeSet<NodeIndex>,
    pub cones: BTreeMap<(String, ConeLoc), ConeSet>,
    /// (object, class): searched on without success.
    pub exhausted: BTreeSet<(usize, String)>,
    /// (class, room) → the room's known cells when a search there for the class made no
    /// progress (no view cone saw any of its points). The search is not planned again until
    /// the room's known map grows ([`crate::binding::Binding`]'s `stalled`).
    pub stalled: BTreeMap<(String, u64), usize>,
    /// (class, location) → what a search there costs and the share of it its views see
    /// (`skills::views::search_cost`; `None`: no view would see a point of it), with what it
    /// was priced on ([`PriceKey`]). Priced again when that changes
    /// (`skills::views::price_searches`).
    pub search_costs: BTreeMap<(String, ConeLoc), (PriceKey, Option<Price>)>,
    /// Class → what a search of a room not known yet costs and the share of it its views see
    /// (`skills::views::typical_room_cost`).
    pub typical_costs: BTreeMap<String, Option<Price>>,
    /// Places that proved unreachable.
    pub blocked: BTreeSet<NodeIndex>,
    /// The placeholders offered to the planner: registry index and what it is.
    pub phs: Vec<(usize, Cand)>,
    /// Conceptual-map ids of the unvisited-area placeholders set at the last sync.
    pub extra_ids: Vec<u64>,
    /// The last unvisited areas and what they were computed from.
    pub unvisited_cache: Memo<sync::UnvisitedKey, sync::Unvisited>,
    /// Which placeholders had no short known path from their place (spurious), by the grid
    /// and the (place, placeholder) positions they were checked on.
    pub spurious_cache: Memo<(OccupancyGrid, Vec<Segment>), Vec<bool>>,
    /// The plan place the robot last moved to, with its position.
    pub last_target: Option<(Target, [f64; 2])>,
    /// Sightings a closer look did not confirm, one entry per failed verification.
    /// Sightings of the class where `rejections_to_ignore` verifications failed are taken
    /// for a look-alike and ignored.
    pub rejected: Vec<Rejection>,
    /// Detections of classes a later goal of a [`Goal::find_all`](crate::Goal::find_all)
    /// seeks, made by the looks of an earlier goal's search and not verified yet: one per
    /// class and spot (the most confident; [`Memory::note_sightings`]). The search for the
    /// class verifies them first (`skills::sighted`).
    pub sightings: Vec<Detection>,
    /// The model verifiers built so far, by class (`skills::verify`): a model is built from
    /// its knowledge-file spec once (a GP with up to 2000 training points per hypothesis), not
    /// once per candidate.
    pub verifiers: BTreeMap<String, std::sync::Arc<crate::skills::verify::Built>>,
    /// The sensor models the `sequential` verifier weighs scores with, built so far, by class.
    pub score_models: BTreeMap<String, std::sync::Arc<avs_verify::sensor::SensorModel>>,
    /// The robot's position as last seen.
    pub at: [f64; 2],
    /// The doors the robot has reported, each as last seen ([`avs_robot::MapUpdate::doors`]).
    pub doors: Vec<DoorSighting>,
    /// Door sightings not yet written to the trace: a door first seen closed, or seen to have
    /// opened or closed since ([`Memory::note_doors`]).
    pub door_news: Vec<DoorSighting>,
    /// The room of every cell of `grid` as of the last sync
    /// ([`avs_map::places::PlaceMap::cell_rooms`]).
    pub cell_rooms: Vec<Option<usize>>,
    /// The pockets of `grid` as of the last sync ([`avs_map::pockets`]): unknown space walled
    /// in by one room and no larger than [`pocket_size`] — the insides of furniture the laser
    /// saw only the rim of, whether or not a detector ever reported the furniture. A room's
    /// search looks at their tops ([`Memory::surfaces_in_rooms`], `skills::views::room_points`).
    pub pockets: Vec<Pocket>,
    /// The largest pocket ([`pocket_size`] of the knowledge).
    pocket_size: PocketSize,
    /// The traversability of the known map for the robot's radius, with unknown cells blocked
    /// and free, kept until the map changes: path lengths are asked for many times between
    /// two map updates (every verification standpoint, placeholder and room), and each map
    /// took a distance transform of the whole grid.
    trav_cache: RefCell<Vec<(OccupancyGrid, bool, Traversability)>>,
    robot_radius: f64,
    pub tuning: Tuning,
}

/// How large a pocket of unknown space may be for a room's search to take it for the inside
/// of furniture ([`Memory::pockets`], [`avs_map::pockets::enclosed_pockets`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PocketSize {
    /// The largest area, square metres.
    pub area: f64,
    /// The largest radius of the disc that holds it, metres.
    pub radius: f64,
}

/// The largest pocket of `knowledge` ([`PocketSize`]): twice the largest footprint of a
/// landmark class in area (a real piece may be larger than its class's typical size, and its
/// inside is smaller than its footprint by the rim the laser saw), and the largest footprint's
/// whole diagonal as the radius (twice what the inside of that footprint needs: the unknown
/// inside of a wall seen from one side only is a long strip, not furniture); zero when the
/// knowledge has no landmark.
pub fn pocket_size(knowledge: &Knowledge) -> PocketSize {
    let landmarks = || knowledge.object_classes.iter().filter(|c| c.landmark);
    PocketSize {
        area: 2.0
            * landmarks()
                .map(|c| c.size[0] * c.size[1])
                .fold(0.0, f64::max),
        radius: landmarks()
            .map(|c| c.size[0].hypot(c.size[1]))
            .fold(0.0, f64::max),
    }
}

/// The height of a pocket's top ([`Memory::pockets`]), metres: a pocket may be any surface
/// the knowledge has, so its top is the lowest of theirs and a point on any of them rests on
/// it. Infinite when the knowledge has no surface (then no pocket is searched).
pub(crate) fn pocket_top(knowledge: &Knowledge) -> f64 {
    avs_view::surface_classes(knowledge, None)
        .into_iter()
        .filter_map(|k| knowledge.class(k))
        .map(|c| c.size[2])
        .fold(f64::INFINITY, f64::min)
}

/// Length of the shortest path on `trav` from `from` to `to` when it is at most `max_len` metres
/// and ends within 0.5 m of `to`, metres (the one home of the agent's path-length questions).
pub(crate) fn path_len_on(
    trav: &Traversability,
    from: [f64; 2],
    to: [f64; 2],
    max_len: f64,
) -> Option<f64> {
    shortest_path_within(trav, from, to, 0.5, max_len)
        .filter(|p| p.points.last().is_some_and(|e| dist(*e, to) <= 0.5))
        .map(|p| p.length)
        .filter(|&l| l <= max_len)
}

/// Centres of the free cells of `grid` the robot can stand on by `trav`, every `spacing`
/// metres along rows and columns.
pub(crate) fn standable(
    grid: &OccupancyGrid,
    trav: &Traversability,
    spacing: f64,
) -> Vec<[f64; 2]> {
    let step = (spacing / grid.resolution()).round().max(1.0) as usize;
    let mut out = Vec::new();
    for row in (0..grid.height()).step_by(step) {
        for col in (0..grid.width()).step_by(step) {
            if grid.get(col, row) == Cell::Free && trav.ok(col as i64, row as i64) {
                let (x, y) = grid.cell_center(col as i64, row as i64);
                out.push([x, y]);
            }
        }
    }
    out
}

/// The failed verifications of `class` whose looks would have seen an object at `pos`: those
/// within their [`Rejection::radius`] of it.
pub(crate) fn rejections_covering<'a>(
    rejected: &'a [Rejection],
    class: &'a str,
    pos: [f64; 2],
) -> impl Iterator<Item = &'a Rejection> + 'a {
    rejected
        .iter()
        .filter(move |r| r.class == class && dist(r.at, pos) < r.radius)
}

/// Whether a sighting of `class` at `pos` is a known look-alike: verification failed at least
/// `times` times within `radius` of it.
pub(crate) fn is_look_alike(
    rejected: &[Rejection],
    class: &str,
    pos: [f64; 2],
    times: usize,
) -> bool {
    rejections_covering(rejected, class, pos).count() >= times
}

/// A sighting a verification did not confirm.
#[derive(Debug, Clone, PartialEq)]
pub struct Rejection {
    /// Its class.
    pub class: String,
    /// Where it was sighted.
    pub at: [f64; 2],
    /// How far around it the verification's looks would have seen an object of the class,
    /// metres: a later sighting this close is taken for the same thing. The closer looks'
    /// image reaches only so far beside the sighting (half its width there); an object
    /// farther off was not looked at, whatever the radius a detection confirms within.
    pub radius: f64,
    /// What the verification's looks said of an object there, as the natural log of their
    /// Bayes factor `P(looks | object) / P(looks | none)` under the verifier's own model
    /// (log-odds of its final belief minus log-odds of its prior); 0 when the verifier keeps
    /// no belief (the `count` rule) or decided on the prior without looking. A later
    /// candidate within `radius` starts from its prior moved by this much
    /// (`skills::verify`, "Earlier looks at the spot").
    pub evidence: f64,
}

impl Memory {
    /// A memory of nothing yet but the first laser map, for a robot of radius `robot_radius`
    /// whose knowledge has pockets of at most `pocket_size` ([`pocket_size`]).
    pub fn new(
        wm: WorldModel,
        grid: OccupancyGrid,
        robot_radius: f64,
        pocket_size: PocketSize,
        tuning: Tuning,
    ) -> Self {
        Self {
            wm,
            grid,
            registry: Vec::new(),
            next_ph: 0,
            objects: Vec::new(),
            looked: BTreeSet::new(),
            classified: BTreeSet::new(),
            looks: BTreeMap::new(),
            cones: BTreeMap::new(),
            exhausted: BTreeSet::new(),
            stalled: BTreeMap::new(),
            search_costs: BTreeMap::new(),
            typical_costs: BTreeMap::new(),
            blocked: BTreeSet::new(),
            phs: Vec::new(),
            extra_ids: Vec::new(),
            unvisited_cache: Memo::default(),
            spurious_cache: Memo::default(),
            last_target: None,
            rejected: Vec::new(),
            sightings: Vec::new(),
            verifiers: BTreeMap::new(),
            score_models: BTreeMap::new(),
            at: [0.0, 0.0],
            doors: Vec::new(),
            door_news: Vec::new(),
            cell_rooms: Vec::new(),
            pockets: Vec::new(),
            pocket_size,
            trav_cache: RefCell::new(Vec::new()),
            robot_radius,
            tuning,
        }
    }

    /// The key of a point in [`Memory::looks`] (on the grid of `tuning.cover_key_resolution`).
    pub fn point_key(&self, p: [f64; 3]) -> PointKey {
        crate::run::point_key(self.tuning.cover_key_resolution, p)
    }

    /// The looks so far at point `p` in searches for `class`.
    pub fn looks_at(&self, class: &str, p: [f64; 3]) -> u32 {
        self.looks
            .get(class)
            .and_then(|l| l.get(&self.point_key(p)))
            .copied()
            .unwrap_or(0)
    }

    /// The place the robot is at, or (a door place) the nearest place with a room.
    pub fn current_place(&self) -> Option<NodeIndex> {
        let cur = self.wm.places.current_place()?;
        if self.wm.room_of(cur).is_some() {
            return Some(cur);
        }
        let p = self.wm.places.graph.node_weight(cur)?.pos;
        self.nearest_room_place(p)
    }

    /// The room the robot is in.
    pub fn current_room(&self) -> Option<RoomId> {
        let p = self.current_place()?;
        self.wm.room_of(p)
    }

    /// The room most of `points` lie in now (ties: the lower id).
    pub fn majority_room(&self, points: &[[f64; 3]]) -> Option<RoomId> {
        let mut votes: BTreeMap<RoomId, usize> = BTreeMap::new();
        for p in points {
            if let Some(r) = self.room_at([p[0], p[1]]) {
                *votes.entry(r).or_default() += 1;
            }
        }
        votes
            .into_iter()
            .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)))
            .map(|(r, _)| r)
    }

    /// The room a point lies in: the room of its cell as of the last sync (`None` for space no
    /// room reaches, such as a room seen through its door but not entered); the room of the
    /// nearest place before the first sync.
    pub fn room_at(&self, p: [f64; 2]) -> Option<RoomId> {
        let (c, r) = self.grid.world_to_cell(p[0], p[1]);
        if self.cell_rooms.len() == self.grid.width() * self.grid.height() {
            return if self.grid.contains(c, r) {
                self.cell_rooms[r as usize * self.grid.width() + c as usize]
                    .map(|id| RoomId(id as u64))
            } else {
                None
            };
        }
        self.nearest_room_place(p).and_then(|n| self.wm.room_of(n))
    }

    /// Number of known cells of the grid in room `r` as of the last sync.
    pub fn room_known_cells(&self, r: u64) -> usize {
        self.cell_rooms
            .iter()
            .filter(|c| **c == Some(r as usize))
            .count()
    }

    /// Keep `seen` (detections of classes sought later) at least `min_confidence` confident
    /// and new ([`Memory::is_new_sighting`]): one sighting per class within
    /// [`Tuning::confirm_radius`] of another, the more confident.
    pub fn note_sightings(&mut self, seen: Vec<Detection>, min_confidence: f64) {
        let radius = self.tuning.confirm_radius;
        for d in seen {
            if d.confidence < min_confidence || !self.is_new_sighting(&d) {
                continue;
            }
            let same = self.sightings.iter_mut().find(|s| {
                s.class == d.class && s.pose.planar_distance(d.pose.x, d.pose.y) < radius
            });
            match same {
                Some(s) if s.confidence < d.confidence => *s = d,
                Some(_) => {}
                None => self.sightings.push(d),
            }
        }
    }

    /// File a verified sighting `d` of `class` found outside a landmark search (not a
    /// landmark, on nothing known) under the place it lies at, or the robot's, and return it
    /// as the goal's object. It is not filed when no place has a room yet; the report names
    /// it all the same.
    pub fn file_found(&mut self, class: &str, d: &Detection) -> crate::report::FoundObject {
        let k = self.objects.len();
        let place = self
            .object_place([d.pose.x, d.pose.y])
            .or_else(|| self.current_place());
        if let Some(place) = place {
            self.objects.push(Known {
                class: class.to_string(),
                pos: d.pose,
                place,
                landmark: None,
                on: None,
                counted: false,
                confidence: d.confidence,
            });
        }
        crate::report::FoundObject {
            name: crate::binding::names::object(k),
            class: class.to_string(),
            pose: d.pose,
            confidence: d.confidence,
        }
    }

    /// The place an object at `p` is filed under: the nearest place of the room it lies in.
    pub fn object_place(&self, p: [f64; 2]) -> Option<NodeIndex> {
        let room = self.room_at(p)?;
        let g = &self.wm.places.graph;
        self.wm
            .rooms()
            .find(|(r, _)| *r == room)
            .and_then(|(_, places)| {
                places
                    .iter()
                    .copied()
                    .min_by(|&a, &b| dist(g[a].pos, p).total_cmp(&dist(g[b].pos, p)))
            })
            .or_else(|| self.nearest_room_place(p))
    }

    /// The place with a room nearest to a point.
    pub fn nearest_room_place(&self, p: [f64; 2]) -> Option<NodeIndex> {
        let g = &self.wm.places.graph;
        g.node_indices()
            .filter(|&n| self.wm.room_of(n).is_some())
            .min_by(|&a, &b| dist(g[a].pos, p).total_cmp(&dist(g[b].pos, p)))
    }

    /// Whether a point seen from `from` lies in the same room as `from`: the sight line
    /// crosses no door hypothesis, and the known free space where it leaves the point —
    /// the first known free cell on the line from the point back to `from` — belongs to the
    /// room `from` is in ([`Memory::room_at`]). A sighting on furniture, or seen over a table
    /// (the camera looks over what the planar map has as an obstacle), is in the room whose
    /// floor surrounds it; one seen through a doorway or past a wall's end is not. (A sight
    /// line checked on the planar map took a counter seen over a table for one in another
    /// room, and a kitchen for a corridor.)
    pub fn same_room(&self, from: [f64; 2], p: [f64; 2]) -> bool {
        if self
            .wm
            .places
            .doors
            .iter()
            .any(|dr| dr.hypothesis.crossed_by(from, p))
        {
            return false;
        }
        let Some(here) = self.room_at(from) else {
            return false;
        };
        let mut floor = None;
        walk_segment(&self.grid, p, from, |c, r| {
            if self.grid.get_i(c, r) == Cell::Free {
                floor = Some(self.grid.cell_center(c, r));
            }
            floor.is_none()
        });
        floor.is_some_and(|(x, y)| self.room_at([x, y]) == Some(here))
    }

    /// The room whose floor surrounds a point (furniture's centre): the room of most of the
    /// known free cells within `radius` metres of it, `None` when none is labelled. The room
    /// an object was filed under is where it was seen from, which may be through a door.
    pub fn room_around(&self, p: [f64; 2], radius: f64) -> Option<RoomId> {
        let g = &self.grid;
        let res = g.resolution();
        let k = (radius / res).ceil() as i64;
        let (pc, pr) = g.world_to_cell(p[0], p[1]);
        let mut votes: BTreeMap<RoomId, usize> = BTreeMap::new();
        for dr in -k..=k {
            for dc in -k..=k {
                let (c, r) = (pc + dc, pr + dr);
                if ((dc * dc + dr * dr) as f64) * res * res > radius * radius
                    || g.get_i(c, r) != Cell::Free
                {
                    continue;
                }
                let (x, y) = g.cell_center(c, r);
                if let Some(room) = self.room_at([x, y]) {
                    *votes.entry(room).or_default() += 1;
                }
            }
        }
        votes
            .into_iter()
            .max_by_key(|&(room, n)| (n, std::cmp::Reverse(room)))
            .map(|(r, _)| r)
    }

    /// The room a place belongs to; a door place belongs to its neighbour's room of smallest id.
    pub fn room_for(&self, n: NodeIndex) -> Option<RoomId> {
        let wm = &self.wm;
        wm.room_of(n).or_else(|| {
            wm.places
                .graph
                .neighbors(n)
                .filter_map(|m| wm.room_of(m))
                .min()
        })
    }

    /// How far short of an object's estimated centre a sight line may stop: half its
    /// footprint's diagonal (furniture footprints are obstacles of the map) plus the
    /// estimate's slack.
    pub fn footprint_slack(&self, knowledge: &Knowledge, class: &str) -> f64 {
        let slack = self.tuning.los_slack;
        knowledge
            .class(class)
            .map_or(slack, |c| 0.5 * c.size[0].hypot(c.size[1]) + slack)
    }

    /// The tops of the known furniture that small objects rest on
    /// ([`avs_view::surface_classes`]).
    pub fn surfaces(&self, knowledge: &Knowledge) -> Vec<Surface> {
        self.surfaces_in_rooms(knowledge)
            .into_iter()
            .map(|(s, _)| s)
            .collect()
    }

    /// [`Self::surfaces`], each with the room the furniture stands in: that of its centre's
    /// cell, else that of the place it was filed under.
    pub fn surfaces_in_rooms(&self, knowledge: &Knowledge) -> Vec<(Surface, Option<RoomId>)> {
        let kinds = avs_view::surface_classes(knowledge, None);
        let known = self
            .objects
            .iter()
            .filter(|o| o.landmark.is_some() && kinds.contains(o.class.as_str()))
            .filter_map(|o| {
                let c = knowledge.class(&o.class)?;
                let center = [o.pos.x, o.pos.y];
                let s = Surface {
                    center,
                    radius: 0.5 * c.size[0].hypot(c.size[1]),
                    top: c.size[2],
                };
                Some((s, self.room_at(center).or_else(|| self.room_for(o.place))))
            });
        let lowest = pocket_top(knowledge);
        let pockets = self.pockets.iter().filter(|_| lowest.is_finite()).map(|p| {
            let s = Surface {
                center: p.center,
                radius: p.radius,
                top: lowest,
            };
            (s, Some(RoomId(p.room as u64)))
        });
        known.chain(pockets).collect()
    }

    /// Whether a detection is of nothing the agent knows: no known object of its class within
    /// 0.8 m and no look-alike rejected there.
    pub fn is_new_sighting(&self, d: &Detection) -> bool {
        let t = &self.tuning;
        !(self
            .objects
            .iter()
            .any(|o| o.class == d.class && o.pos.planar_distance(d.pose.x, d.pose.y) < 0.8)
            || is_look_alike(
                &self.rejected,
                &d.class,
                [d.pose.x, d.pose.y],
                t.rejections_to_ignore,
            ))
    }

    /// Length of the shortest path on the known map, unknown cells free or blocked, metres.
    pub fn path_len(&self, from: [f64; 2], to: [f64; 2], unknown_is_free: bool) -> Option<f64> {
        self.path_len_within(from, to, unknown_is_free, f64::INFINITY)
    }

    /// [`Self::path_len`] when it is at most `max_len` metres, else `None`; the search stops
    /// at that length (asking for a short path costs no flood of the map when there is none).
    pub fn path_len_within(
        &self,
        from: [f64; 2],
        to: [f64; 2],
        unknown_is_free: bool,
        max_len: f64,
    ) -> Option<f64> {
        self.with_trav(unknown_is_free, |t| path_len_on(t, from, to, max_len))
    }

    /// File the robot's door sightings (a robot reports the doors seen so far, or only some of
    /// them: a door it does not mention keeps its last sighting). A door first seen closed, or
    /// seen in another state than before, is news for the trace.
    pub fn note_doors(&mut self, seen: Vec<DoorSighting>) {
        for d in seen {
            match self.doors.iter_mut().find(|k| k.name == d.name) {
                Some(known) => {
                    if known.open != d.open {
                        self.door_news.push(d.clone());
                    }
                    *known = d;
                }
                None => {
                    if !d.open {
                        self.door_news.push(d.clone());
                    }
                    self.doors.push(d);
                }
            }
        }
    }

    /// The doors last seen closed that cut the robot, at `from`, off from space beyond them: on
    /// one side of the door the robot can reach known free space (a point 1 m from the door's centre
    /// along its direction of passage), on the other it cannot (the space there is unknown,
    /// or known but reachable only through the door). Such a door is the cause to name when
    /// a search gives up (issue 18: a give-up names its cause).
    pub fn closed_doors_cutting_off(&self, from: [f64; 2]) -> Vec<&DoorSighting> {
        const PROBE_M: f64 = 1.0;
        self.doors
            .iter()
            .filter(|d| !d.open)
            .filter(|d| {
                let (nx, ny) = (d.yaw.cos(), d.yaw.sin());
                let reach = |s: f64| {
                    let probe = [d.x + s * PROBE_M * nx, d.y + s * PROBE_M * ny];
                    self.path_len(from, probe, false).is_some()
                };
                reach(1.0) != reach(-1.0)
            })
            .collect()
    }

    /// The shortest path from `from` to `to` on the known map (unknown cells blocked), goals
    /// snapped within 1 m: the way the robot drives.
    pub fn known_path(&self, from: [f64; 2], to: [f64; 2]) -> Option<avs_map::nav::GridPath> {
        self.with_trav(false, |t| avs_map::nav::shortest_path(t, from, to, 1.0))
    }

    /// `f` of the traversability of the known map for the robot's radius (unknown cells free
    /// or blocked), computed once per map (see `trav_cache`).
    pub fn with_trav<T>(&self, unknown_is_free: bool, f: impl FnOnce(&Traversability) -> T) -> T {
        let grid = &self.grid;
        let mut cache = self.trav_cache.borrow_mut();
        let k = match cache
            .iter()
            .position(|(g, free, _)| *free == unknown_is_free && g == grid)
        {
            Some(k) => k,
            None => {
                cache.retain(|(_, free, _)| *free != unknown_is_free);
                let t = Traversability::new(grid, self.robot_radius, unknown_is_free);
                cache.push((grid.clone(), unknown_is_free, t));
                cache.len() - 1
            }
        };
        f(&cache[k].2)
    }

    /// Mark the placeholder with stable id `id` explored from room `origin`, leading to `led`
    /// (kept if it was explored before); `pos` files it when the registry forgot it.
    pub fn set_explored(
        &mut self,
        id: usize,
        pos: Option<[f64; 2]>,
        origin: u64,
        led: Option<NodeIndex>,
    ) {
        match self.registry.iter_mut().find(|e| e.id == id) {
            Some(e) => {
                if e.explored.is_none() {
                    e.explored = Some((origin, led));
                }
            }
            None => {
                if let Some(pos) = pos {
                    self.registry.push(PhEntry {
                        id,
                        pos,
                        explored: Some((origin, led)),
                    });
                }
            }
        }
    }

    /// A target proved unreachable: a placeholder counts as explored (leading nowhere) and a
    /// place is left out of later plans.
    pub fn mark_unreachable(
        &mut self,
        target: Target,
        pos: Option<[f64; 2]>,
        room: Option<RoomId>,
    ) {
        match target {
            Target::Placeholder(id) => self.set_explored(id, pos, room.map_or(0, |r| r.0), None),
            Target::Place(n) => {
                self.blocked.insert(n);
            }
        }
    }

    /// The place an explored placeholder led to, if it was explored and led somewhere.
    pub fn explored_led(&self, id: usize) -> Option<NodeIndex> {
        self.registry
            .iter()
            .find(|e| e.id == id)
            .and_then(|e| e.explored)
            .and_then(|(_, led)| led)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::skills::testing;
    use crate::AgentConfig;

    /// Where the robot stands in [`two_rooms`].
    const AT: [f64; 2] = [2.0, 2.0];

    /// Two 4 m × 4 m rooms side by side, the wall between them at x = 4 m with a doorway at
    /// y ∈ [0.5, 1.4] that is `open`, and a second doorway at y ∈ [2.5, 3.4] when `loop_door`;
    /// the robot at (2, 2) in the left room knows the whole map.
    fn two_rooms(open: bool, loop_door: bool) -> Memory {
        let mut g = testing::room(8.0, 4.0);
        for row in 0..40 {
            let first = (5..14).contains(&row) && open;
            let second = (25..34).contains(&row) && loop_door;
            if !first && !second {
                g.set(40, row, Cell::Occupied);
            }
        }
        let (config, k) = (AgentConfig::default(), testing::knowledge());
        let mut robot = testing::robot(g, AT);
        testing::memory(&config, &k, &mut robot)
    }

    fn door(open: bool) -> DoorSighting {
        DoorSighting {
            name: "door_east".into(),
            x: 4.05,
            y: 0.95,
            yaw: 0.0,
            width: 0.9,
            open,
        }
    }

    #[test]
    fn a_door_first_seen_closed_or_seen_to_change_is_news_and_one_seen_open_is_not() {
        let mut mem = two_rooms(true, false);
        mem.note_doors(vec![door(true)]);
        assert!(
            mem.door_news.is_empty(),
            "a door first seen open is no news"
        );
        mem.note_doors(vec![door(true)]);
        assert!(mem.door_news.is_empty());
        mem.note_doors(vec![door(false)]);
        assert_eq!(mem.door_news, vec![door(false)], "seen to close");
        // A robot that no longer mentions the door leaves its last sighting.
        mem.note_doors(Vec::new());
        assert_eq!(mem.doors, vec![door(false)]);
        let mut fresh = two_rooms(true, false);
        fresh.note_doors(vec![door(false)]);
        assert_eq!(fresh.door_news, vec![door(false)], "first seen closed");
    }

    #[test]
    fn a_closed_door_cuts_off_the_far_room_unless_another_door_leads_there() {
        // The doorway is walled up (the door is shut) and the right room is reachable only
        // through it: the door cuts the robot off.
        let mut shut = two_rooms(false, false);
        shut.note_doors(vec![door(false)]);
        let names: Vec<&str> = shut
            .closed_doors_cutting_off(AT)
            .iter()
            .map(|d| d.name.as_str())
            .collect();
        assert_eq!(names, ["door_east"]);
        // The same door seen open cuts off nothing.
        shut.note_doors(vec![door(true)]);
        assert!(shut.closed_doors_cutting_off(AT).is_empty());
        // Shut, with a second doorway into the right room: nothing is cut off.
        let mut looped = two_rooms(false, true);
        looped.note_doors(vec![door(false)]);
        assert!(looped.closed_doors_cutting_off(AT).is_empty());
    }

    #[test]
    fn a_sighting_is_ignored_only_where_verification_failed_twice_within_what_it_saw() {
        let at = |x: f64, y: f64, radius: f64| Rejection {
            class: "cerealbox".to_string(),
            at: [x, y],
            radius,
            evidence: 0.0,
        };
        let mut rejected = vec![at(1.0, 1.0, 0.6)];
        // One failed verification: a real object fails one in ten, so look again.
        assert!(!is_look_alike(&rejected, "cerealbox", [1.1, 1.0], 2));
        rejected.push(at(1.2, 1.1, 0.6));
        assert!(is_look_alike(&rejected, "cerealbox", [1.1, 1.0], 2));
        // Other classes and other places are not affected.
        assert!(!is_look_alike(&rejected, "mug", [1.1, 1.0], 2));
        assert!(!is_look_alike(&rejected, "cerealbox", [2.0, 1.0], 2));
        // A sighting beside the spots, beyond what their looks saw (0.25 m around them), is
        // something else: an object next to a rejected look-alike is still looked at.
        let narrow = vec![at(1.0, 1.0, 0.25), at(1.05, 1.0, 0.25)];
        assert!(is_look_alike(&narrow, "cerealbox", [1.1, 1.0], 2));
        assert!(!is_look_alike(&narrow, "cerealbox", [1.0, 1.4], 2));
    }
}
