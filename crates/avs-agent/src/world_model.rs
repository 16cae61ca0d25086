//! The agent's world model: the place map and the conceptual map kept in step.
//!
//! The place map (avs-map) says which places form which rooms and how doors join them; the
//! conceptual map (avs-concepts) holds a category variable per room. After every map change
//! [`WorldModel::sync`] turns the difference between the place map's rooms and the rooms the
//! conceptual map knows into its events — a new room, a room split by a newly confirmed door, rooms
//! merged by a newly found path, a renamed room (its smallest place was absorbed into a door
//! place), a new or removed door adjacency, the current placeholders — so inference runs
//! warm-started on the changed graph instead of from scratch (Aydemir et al. 2011, §II-B.4).
//!
//! Room ids are the place map's stable room ids (the smallest place index in the room).

use avs_concepts::{
    ConceptError, ConceptualMap, LandmarkId, PlaceId, Placeholder, PlaceholderId, RoomId,
};
use avs_format::knowledge::Knowledge;
use avs_map::grid::OccupancyGrid;
use avs_map::places::{PlaceMap, PlaceMapParams};
use petgraph::graph::NodeIndex;
use std::collections::{BTreeMap, BTreeSet};

/// Errors of the world model.
#[derive(Debug, thiserror::Error)]
pub enum WorldModelError {
    /// The conceptual map refused an event.
    #[error(transparent)]
    Concepts(#[from] ConceptError),
    /// An observation was made from a place that belongs to no room (a door place).
    #[error("place {0} belongs to no room (door places do not); expected a place inside a room")]
    PlaceNotInRoom(usize),
}

/// What a [`WorldModel::sync`] changed in the conceptual map.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SyncReport {
    /// Rooms added.
    pub added: Vec<u64>,
    /// `(from, new)`: room `new` split off room `from`.
    pub split: Vec<(u64, u64)>,
    /// `(keep, gone)`: room `gone` merged into room `keep`.
    pub merged: Vec<(u64, u64)>,
    /// Rooms removed (all their places were removed).
    pub removed: Vec<u64>,
    /// Door adjacencies added.
    pub doors_added: usize,
}

impl SyncReport {
    /// Whether the room structure changed.
    pub fn changed(&self) -> bool {
        !(self.added.is_empty()
            && self.split.is_empty()
            && self.merged.is_empty()
            && self.removed.is_empty())
            || self.doors_added > 0
    }
}

/// The place map and the conceptual map, in step.
#[derive(Debug, Clone)]
pub struct WorldModel {
    /// Places, paths, doors, placeholders, rooms.
    pub places: PlaceMap,
    /// Room categories and object priors.
    pub concepts: ConceptualMap,
    /// The rooms as last synced: room id → its places.
    rooms: BTreeMap<u64, BTreeSet<NodeIndex>>,
    adjacency: BTreeSet<(u64, u64)>,
    placeholders: usize,
    /// Where each landmark was seen from (its room follows that place's room).
    landmark_place: BTreeMap<LandmarkId, NodeIndex>,
}

impl WorldModel {
    /// An empty world model over a knowledge file (`file` names it in errors).
    pub fn new(
        file: &str,
        knowledge: &Knowledge,
        params: PlaceMapParams,
    ) -> Result<Self, ConceptError> {
        Ok(Self {
            places: PlaceMap::new(params),
            concepts: ConceptualMap::new(file, knowledge)?,
            rooms: BTreeMap::new(),
            adjacency: BTreeSet::new(),
            placeholders: 0,
            landmark_place: BTreeMap::new(),
        })
    }

    /// The room (id) a place belongs to, as last synced.
    pub fn room_of(&self, place: NodeIndex) -> Option<RoomId> {
        self.rooms
            .iter()
            .find(|(_, ps)| ps.contains(&place))
            .map(|(&id, _)| RoomId(id))
    }

    /// The rooms as last synced, by id.
    pub fn rooms(&self) -> impl Iterator<Item = (RoomId, &BTreeSet<NodeIndex>)> + '_ {
        self.rooms.iter().map(|(&id, ps)| (RoomId(id), ps))
    }

    /// Refresh the place map from the known grid and bring the conceptual map in step.
    pub fn sync(&mut self, known: &OccupancyGrid) -> Result<SyncReport, WorldModelError> {
        self.places.update(known);
        let now = self.places.rooms();
        let new: BTreeMap<u64, BTreeSet<NodeIndex>> = now
            .rooms
            .iter()
            .map(|r| (r.id as u64, r.places.iter().copied().collect()))
            .collect();
        let mut report = SyncReport::default();
        let mut handled: BTreeSet<u64> = BTreeSet::new();
        for (&id, places) in &new {
            let overlapping: Vec<u64> = self
                .rooms
                .iter()
                .filter(|(o, ps)| **o != id && !ps.is_disjoint(places))
                .map(|(&o, _)| o)
                .collect();
            if self.rooms.contains_key(&id) {
                // Same id: other old rooms sharing its places merged into it.
                for o in overlapping.into_iter().filter(|o| !new.contains_key(o)) {
                    self.concepts.merge_rooms(RoomId(id), RoomId(o))?;
                    report.merged.push((id, o));
                    handled.insert(o);
                }
                continue;
            }
            // A new id: split off a surviving room, or a renamed / merged successor, or new.
            let mut rest = overlapping.clone();
            if let Some(pos) = rest.iter().position(|o| new.contains_key(o)) {
                let from = rest.remove(pos);
                let moved: Vec<PlaceId> = places.iter().map(|&p| place_id(p)).collect();
                let landmarks: Vec<LandmarkId> = self
                    .landmark_place
                    .iter()
                    .filter(|(_, p)| places.contains(p))
                    .map(|(&l, _)| l)
                    .collect();
                self.concepts
                    .split_room(RoomId(from), RoomId(id), &moved, &landmarks)?;
                report.split.push((from, id));
            } else {
                self.concepts.add_room(RoomId(id))?;
                report.added.push(id);
            }
            for o in rest.into_iter().filter(|o| !new.contains_key(o)) {
                self.concepts.merge_rooms(RoomId(id), RoomId(o))?;
                report.merged.push((id, o));
                handled.insert(o);
            }
        }
        for (&o, _) in self.rooms.iter() {
            if !new.contains_key(&o) && !handled.contains(&o) {
                self.concepts.remove_room(RoomId(o))?;
                report.removed.push(o);
            }
        }
        self.rooms = new;
        // Door adjacency.
        let adjacency: BTreeSet<(u64, u64)> = now
            .adjacency
            .iter()
            .map(|&(a, b, _)| {
                let (a, b) = (now.rooms[a].id as u64, now.rooms[b].id as u64);
                (a.min(b), a.max(b))
            })
            .collect();
        for &(a, b) in adjacency.difference(&self.adjacency) {
            self.concepts.add_adjacency(RoomId(a), RoomId(b))?;
            report.doors_added += 1;
        }
        for &(a, b) in self.adjacency.difference(&adjacency) {
            self.concepts.remove_adjacency(RoomId(a), RoomId(b))?;
        }
        self.adjacency = adjacency;
        // Placeholders: replace the set.
        for i in 0..self.placeholders {
            self.concepts.remove_placeholder(PlaceholderId(i as u64))?;
        }
        self.placeholders = 0;
        for (i, ph) in self.places.placeholders.iter().enumerate() {
            let Some(room) = self
                .room_of(ph.place)
                .or_else(|| self.rooms.keys().next().map(|&r| RoomId(r)))
            else {
                continue;
            };
            self.concepts.set_placeholder(
                PlaceholderId(i as u64),
                Placeholder {
                    room,
                    open_area_m2: ph.open_area,
                    door_distance_m: ph.door_distance,
                },
            )?;
            self.placeholders = i + 1;
        }
        Ok(report)
    }

    /// The room of `place`, or the error that it has none.
    fn room_of_known(&self, place: NodeIndex) -> Result<RoomId, WorldModelError> {
        self.room_of(place)
            .ok_or(WorldModelError::PlaceNotInRoom(place.index()))
    }

    /// `count` new objects of `class` were seen from `place`, looking at a share `coverage` of
    /// its room.
    pub fn saw_objects(
        &mut self,
        place: NodeIndex,
        class: &str,
        count: u32,
        coverage: f64,
    ) -> Result<(), WorldModelError> {
        let room = self.room_of_known(place)?;
        Ok(self
            .concepts
            .observe_objects(room, place_id(place), class, count, coverage)?)
    }

    /// A place classifier read `property` at `place`: `likelihood[v]` = P(reading | value v),
    /// soft evidence on the room's category through the knowledge's `place_properties`
    /// (`002` §III, the property variables of the chain graph).
    pub fn saw_place_property(
        &mut self,
        place: NodeIndex,
        property: &str,
        likelihood: &[f64],
    ) -> Result<(), WorldModelError> {
        let room = self.room_of_known(place)?;
        Ok(self
            .concepts
            .observe_property_soft(room, place_id(place), property, likelihood)?)
    }

    /// A landmark of `class` was found from `place`: it becomes a location for in/on searches.
    pub fn found_landmark(
        &mut self,
        place: NodeIndex,
        class: &str,
    ) -> Result<LandmarkId, WorldModelError> {
        let room = self.room_of_known(place)?;
        let l = self.concepts.add_landmark(room, class)?;
        self.landmark_place.insert(l, place);
        Ok(l)
    }
}

/// The conceptual map's id of place-map node `n`.
fn place_id(n: NodeIndex) -> PlaceId {
    PlaceId(n.index() as u64)
}
