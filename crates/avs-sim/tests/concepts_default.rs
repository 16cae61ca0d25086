//! The conceptual map fed by a real exploration of the default environment: the kitchen's
//! P(kitchen) rises above 0.8 once its counter and table are seen, and a placeholder at a door
//! off the corridor predicts a new room more strongly than one at a dead end.
//!
//! The glue here (place-map rooms → conceptual-map rooms, landmark sightings → object counts)
//! stands in for the agent's world model; the detector is ground truth within the knowledge
//! file's detection range and the walls' line of sight.

use avs_concepts::{ConceptualMap, PlaceId, Placeholder, PlaceholderId, RoomId};
use avs_format::environment::ObjectRole;
use avs_format::knowledge::Knowledge;
use avs_map::places::{dist, PlaceMapParams};
use avs_map::raycast::line_of_sight;
use avs_sim::{Explorer, World};
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

fn shipped(rel: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

/// Build the conceptual map of what the explorer knows now. Returns the map and, per
/// place-map room, the landmark ids (indices into `env.objects`) seen in it.
fn conceptual_map(
    world: &World,
    ex: &Explorer,
    k: &Knowledge,
) -> (ConceptualMap, BTreeMap<usize, BTreeSet<usize>>) {
    let mut cm = ConceptualMap::new("office.yaml", k).unwrap();
    let rooms = ex.places.rooms();
    for r in &rooms.rooms {
        cm.add_room(RoomId(r.id as u64)).unwrap();
    }
    let mut pairs = BTreeSet::new();
    for &(a, b, _) in &rooms.adjacency {
        pairs.insert((a.min(b), a.max(b)));
    }
    for (a, b) in pairs {
        cm.add_adjacency(
            RoomId(rooms.rooms[a].id as u64),
            RoomId(rooms.rooms[b].id as u64),
        )
        .unwrap();
    }
    // Landmarks seen from a room's places; each counted once, in the room of its nearest place.
    let mut seen: BTreeMap<usize, BTreeSet<usize>> = BTreeMap::new();
    for (i, o) in world
        .env
        .objects
        .iter()
        .enumerate()
        .filter(|(_, o)| o.role == ObjectRole::Landmark)
    {
        let range = k.class(&o.class).unwrap().detection_range[1];
        let pos = [o.pose.x, o.pose.y];
        let viewed = ex.places.graph.node_indices().any(|n| {
            let p = ex.places.graph[n].pos;
            dist(p, pos) <= range && line_of_sight(&world.walls, p, pos, false)
        });
        if !viewed {
            continue;
        }
        let nearest = ex
            .places
            .graph
            .node_indices()
            .filter(|&n| ex.places.graph[n].door.is_none())
            .min_by(|&a, &b| {
                dist(ex.places.graph[a].pos, pos).total_cmp(&dist(ex.places.graph[b].pos, pos))
            })
            .unwrap();
        if let Some(r) = rooms.room_of(nearest) {
            seen.entry(r).or_default().insert(i);
        }
    }
    for (ri, r) in rooms.rooms.iter().enumerate() {
        for cls in k.object_classes.iter().filter(|c| c.landmark) {
            let n = seen.get(&ri).map_or(0, |s| {
                s.iter()
                    .filter(|&&i| world.env.objects[i].class == cls.name)
                    .count()
            });
            cm.observe_objects(
                RoomId(r.id as u64),
                PlaceId(r.places[0].index() as u64),
                &cls.name,
                n as u32,
                1.0,
            )
            .unwrap();
        }
    }
    for (i, ph) in ex.places.placeholders.iter().enumerate() {
        let room = rooms
            .room_of(ph.place)
            .map(|r| rooms.rooms[r].id)
            .unwrap_or(rooms.rooms[0].id);
        cm.set_placeholder(
            PlaceholderId(i as u64),
            Placeholder {
                room: RoomId(room as u64),
                open_area_m2: ph.open_area,
                door_distance_m: ph.door_distance,
            },
        )
        .unwrap();
    }
    (cm, seen)
}

#[test]
fn kitchen_becomes_a_kitchen_once_counter_and_table_are_seen() {
    let world = World::load(&shipped("domains/environments/office.yaml")).unwrap();
    let k: Knowledge = avs_format::load_yaml(&shipped("knowledge/office.yaml")).unwrap();
    let kitchen = world
        .env
        .rooms
        .iter()
        .position(|r| r.name == "kitchen")
        .unwrap();
    let ids = |cls: &str| {
        world
            .env
            .objects
            .iter()
            .position(|o| o.class == cls && o.room == "kitchen")
            .unwrap()
    };
    let (counter, table) = (ids("counter"), ids("table"));
    let mut ex = Explorer::new(&world, PlaceMapParams::default(), 1);
    let mut before = None;
    let mut after = None;
    for _ in 0..50 {
        let (cm, seen) = conceptual_map(&world, &ex, &k);
        let rooms = ex.places.rooms();
        for (ri, r) in rooms.rooms.iter().enumerate() {
            let truth: BTreeSet<usize> = r
                .places
                .iter()
                .filter_map(|&p| {
                    world.room_at(ex.places.graph[p].pos[0], ex.places.graph[p].pos[1])
                })
                .collect();
            if truth != BTreeSet::from([kitchen]) {
                continue;
            }
            let p = cm.p_category(RoomId(r.id as u64), "kitchen").unwrap();
            let s = seen.get(&ri).cloned().unwrap_or_default();
            if s.contains(&counter) && s.contains(&table) {
                after.get_or_insert(p);
            } else {
                before.get_or_insert(p);
            }
        }
        if after.is_some() || !ex.step() {
            break;
        }
    }
    let after = after.expect("the kitchen's counter and table were seen");
    eprintln!("P(kitchen) before {before:?} after {after}");
    assert!(
        after > 0.8,
        "P(kitchen) = {after} after seeing the counter and the table"
    );
    if let Some(b) = before {
        assert!(b < after, "P(kitchen) before {b}, after {after}");
    }
}

#[test]
fn placeholders_at_doors_predict_a_new_room_more_than_dead_ends() {
    let world = World::load(&shipped("domains/environments/office.yaml")).unwrap();
    let k: Knowledge = avs_format::load_yaml(&shipped("knowledge/office.yaml")).unwrap();
    let door_d = |p: [f64; 2]| {
        world
            .env
            .doors
            .iter()
            .map(|d| dist(p, [d.pose.x, d.pose.y]))
            .fold(f64::INFINITY, f64::min)
    };
    // Over a whole exploration: placeholders in a doorway (within 1 m of a true door) against
    // dead ends (little open space behind, no door within 1.5 m).
    let (mut at_doors, mut dead_ends) = (Vec::new(), Vec::new());
    let mut ex = Explorer::new(&world, PlaceMapParams::default(), 1);
    loop {
        let (cm, _) = conceptual_map(&world, &ex, &k);
        for (i, ph) in ex.places.placeholders.iter().enumerate() {
            let p = cm.p_new_room(PlaceholderId(i as u64)).unwrap();
            if door_d(ph.pos) < 1.0 {
                at_doors.push((p, ph.clone()));
            } else if door_d(ph.pos) > 1.5 && ph.open_area < 3.0 {
                dead_ends.push((p, ph.clone()));
            }
        }
        if !ex.step() {
            break;
        }
    }
    assert!(
        !at_doors.is_empty() && !dead_ends.is_empty(),
        "doors {at_doors:?}, dead ends {dead_ends:?}"
    );
    let weakest_door = at_doors.iter().map(|d| d.0).fold(f64::INFINITY, f64::min);
    let strongest_dead_end = dead_ends.iter().map(|d| d.0).fold(0.0, f64::max);
    eprintln!(
        "{} doorway placeholders (weakest {weakest_door:.3}), {} dead ends (strongest {strongest_dead_end:.3})",
        at_doors.len(),
        dead_ends.len()
    );
    assert!(
        weakest_door > strongest_dead_end,
        "P(new room): doorways {at_doors:?}; dead ends {dead_ends:?}"
    );
}
