//! [`Beliefs`]: what the agent believes about the world right now, as plain data for a person
//! or a tool — the rooms with their category distributions (`002` §III, the conceptual map's
//! loopy BP marginals), the placeholders with their hypotheses (§III-A.1: the six structure
//! hypotheses h1…h6, and from them P(a new room of category k)), the door hypotheses of the
//! place map, the
//! objects found, and P(ObjectAt L) of a class at every location (eq. 1–2 over the room
//! posterior, rates thinned by failed searches).
//!
//! Names are the plan names (`roomN`, `placeholderK`, `objectK`), so a
//! belief can be matched with the plan and trace lines that use it. The beliefs are read, not
//! recomputed: they are the marginals of the conceptual map's last inference, as the planner
//! used them.

use crate::binding::names;
use crate::memory::Memory;
use crate::trace::CategoryBelief;
use avs_concepts::{Location, PlaceholderId, RoomId};
use avs_format::knowledge::{Knowledge, Relation};
use schemars::JsonSchema;
use serde::Serialize;

/// The agent's beliefs; see the module docs.
#[derive(Debug, Clone, Default, PartialEq, Serialize, JsonSchema)]
pub struct Beliefs {
    /// The class the object probabilities are for (the goal's class), if any.
    pub class: Option<String>,
    /// The rooms of the place map, by id.
    pub rooms: Vec<RoomBelief>,
    /// The placeholders offered to the planner (frontiers and known but unvisited areas).
    pub placeholders: Vec<PlaceholderBelief>,
    /// The door hypotheses of the place map.
    pub doors: Vec<DoorBelief>,
    /// The objects found so far (landmarks and targets).
    pub objects: Vec<ObjectBelief>,
    /// P(an object of `class` at L) for every room and every landmark that can hold one;
    /// empty without a class.
    pub locations: Vec<LocationBelief>,
}

/// One room.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct RoomBelief {
    /// The plan name, `room<N>`.
    pub name: String,
    /// Its id.
    pub id: u64,
    /// The positions of its places `[x, y]`, metres.
    pub places: Vec<[f64; 2]>,
    /// Its category distribution, in the knowledge file's order.
    pub categories: Vec<CategoryBelief>,
}

/// One placeholder: a frontier or an unvisited area the planner may assume leads to a room.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct PlaceholderBelief {
    /// The plan name, `placeholder<K>`.
    pub name: String,
    /// Where it is `[x, y]`, metres.
    pub at: [f64; 2],
    /// P(it leads to at least one new room).
    pub p_new_room: f64,
    /// P(h1) … P(h6), the six structure hypotheses of `002` §III-A.1 (no new places; new
    /// places, no new room; places leading to one new room; to a room and another beyond; a
    /// new room directly; a new room directly leading to another; `avs_concepts::placeholder`),
    /// summing to 1.
    pub hypotheses: [f64; 6],
    /// P(at least one object of the class behind it), for the beliefs' class.
    pub p_object: Option<f64>,
    /// Per category k: P(some new room behind it is of category k), in the knowledge file's
    /// order (the `p-leads-to-room` of the planning problem).
    pub categories: Vec<CategoryBelief>,
}

/// One door hypothesis of the place map.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct DoorBelief {
    /// Midpoint between the jambs `[x, y]`, metres.
    pub at: [f64; 2],
    /// The two jambs `[[x, y], [x, y]]`, metres.
    pub jambs: [[f64; 2]; 2],
    /// Free width of the opening, metres.
    pub width: f64,
    /// Whether the robot has passed through it.
    pub confirmed: bool,
}

/// One object the agent found.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct ObjectBelief {
    /// The plan name, `object<K>`.
    pub name: String,
    /// Its class.
    pub class: String,
    /// Its estimated position `[x, y, z]`, metres.
    pub at: [f64; 3],
    /// The detector's confidence in the sighting that found it.
    pub confidence: f64,
    /// The room it is in, by the place it was seen from.
    pub room: Option<String>,
}

/// P(ObjectAt L) of the class at one location.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct LocationBelief {
    /// The location in plan words: `room3`, `on object2`, `in object5`.
    pub location: String,
    /// The room (plan name) the location is in.
    pub room: String,
    /// The landmark object (plan name), for a location on or in one.
    pub object: Option<String>,
    /// P(at least one object of the class there).
    pub p: f64,
}

/// The beliefs held in `mem`, with object probabilities for `class`.
pub(crate) fn beliefs_of(mem: &Memory, knowledge: &Knowledge, class: Option<&str>) -> Beliefs {
    let cm = &mem.wm.concepts;
    let categories = &cm.model().categories;
    let named = |ps: &[f64]| -> Vec<CategoryBelief> {
        categories
            .iter()
            .zip(ps)
            .map(|(c, &p)| CategoryBelief {
                category: c.clone(),
                p,
            })
            .collect()
    };
    let places = &mem.wm.places;
    let rooms: Vec<RoomBelief> = mem
        .wm
        .rooms()
        .filter_map(|(id, ps)| {
            let dist = cm.category_distribution(id).ok()?;
            Some(RoomBelief {
                name: names::room(id),
                id: id.0,
                places: ps
                    .iter()
                    .filter_map(|&n| places.graph.node_weight(n).map(|p| p.pos))
                    .collect(),
                categories: named(&dist),
            })
        })
        .collect();
    let placeholders = mem
        .phs
        .iter()
        .filter_map(|&(reg, cand)| {
            let entry = mem.registry.get(reg)?;
            let h = cm.placeholder_hypotheses(PlaceholderId(cand.cm_id)).ok()?;
            Some(PlaceholderBelief {
                name: names::placeholder(entry.id),
                at: cand.pos,
                p_new_room: h.p_new_room(),
                hypotheses: h.probabilities,
                p_object: class
                    .filter(|c| knowledge.class(c).is_some())
                    .and_then(|c| {
                        cm.p_object_behind_placeholder(PlaceholderId(cand.cm_id), c)
                            .ok()
                    }),
                categories: named(&h.p_category),
            })
        })
        .collect();
    let doors = places
        .doors
        .iter()
        .map(|d| DoorBelief {
            at: d.hypothesis.center,
            jambs: d.hypothesis.jambs,
            width: d.hypothesis.width,
            confirmed: d.confirmed,
        })
        .collect();
    let objects = mem
        .objects
        .iter()
        .enumerate()
        .map(|(k, o)| ObjectBelief {
            name: names::object(k),
            class: o.class.clone(),
            at: [o.pos.x, o.pos.y, o.pos.z],
            confidence: o.confidence,
            room: mem.wm.room_of(o.place).map(names::room),
        })
        .collect();
    let mut locations = Vec::new();
    if let Some(class) = class.filter(|c| knowledge.class(c).is_some()) {
        for r in &rooms {
            if let Ok(p) = cm.p_object_at(Location::Room(RoomId(r.id)), class) {
                locations.push(LocationBelief {
                    location: r.name.clone(),
                    room: r.name.clone(),
                    object: None,
                    p,
                });
            }
        }
        for (k, o) in mem.objects.iter().enumerate() {
            let (Some(l), Some(room)) = (o.landmark, mem.wm.room_of(o.place)) else {
                continue;
            };
            for (rel, word) in [(Relation::On, "on"), (Relation::In, "in")] {
                match cm.p_object_at(Location::Landmark(l, rel), class) {
                    Ok(p) if p > 0.0 => locations.push(LocationBelief {
                        location: format!("{word} {}", names::object(k)),
                        room: names::room(room),
                        object: Some(names::object(k)),
                        p,
                    }),
                    _ => {}
                }
            }
        }
    }
    Beliefs {
        class: class.map(str::to_string),
        rooms,
        placeholders,
        doors,
        objects,
        locations,
    }
}
