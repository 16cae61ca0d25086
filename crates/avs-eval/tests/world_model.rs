//! The world model keeps the conceptual map's rooms, doors and placeholders in step with the
//! place map while the simulated robot explores.

use avs_agent::world_model::WorldModel;
use avs_concepts::RoomId;
use avs_format::knowledge::Knowledge;
use avs_map::places::PlaceMapParams;
use avs_sim::{Explorer, World};
use std::collections::BTreeSet;
use std::path::Path;

fn shipped(rel: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

fn explore_in_step(world: &World, k: &Knowledge) -> (WorldModel, usize, usize) {
    let mut ex = Explorer::new(world, PlaceMapParams::default(), 1);
    let mut wm = WorldModel::new("office.yaml", k, PlaceMapParams::default()).unwrap();
    let (mut splits, mut adds) = (0, 0);
    loop {
        wm.places = ex.places.clone();
        let report = wm
            .sync(&ex.robot.known)
            .expect("every map change is a valid event");
        splits += report.split.len();
        adds += report.added.len();
        // In step: the same room ids, door adjacencies and placeholders on both sides.
        let rooms = wm.places.rooms();
        let ids: BTreeSet<RoomId> = rooms.rooms.iter().map(|r| RoomId(r.id as u64)).collect();
        let known: BTreeSet<RoomId> = wm.concepts.rooms().collect();
        assert_eq!(ids, known, "rooms after step {}", ex.steps);
        for i in 0..wm.places.placeholders.len() {
            let p = wm
                .concepts
                .p_new_room(avs_concepts::PlaceholderId(i as u64))
                .unwrap();
            assert!((0.0..=1.0).contains(&p));
        }
        if !ex.step() {
            break;
        }
    }
    (wm, splits, adds)
}

#[test]
fn exploring_the_default_office_keeps_both_maps_in_step() {
    let world = World::load(&shipped("domains/environments/office.yaml")).unwrap();
    let k: Knowledge = avs_format::load_yaml(&shipped("knowledge/office.yaml")).unwrap();
    let (wm, splits, adds) = explore_in_step(&world, &k);
    assert_eq!(
        wm.concepts.rooms().count(),
        4,
        "corridor, office1, kitchen, office2"
    );
    // Rooms appear either as new components or by a door splitting a room the robot walked into.
    assert!(adds + splits >= 4, "adds {adds}, splits {splits}");
    // Every room's category distribution is a distribution.
    for r in wm.concepts.rooms() {
        let d = wm.concepts.category_distribution(r).unwrap();
        assert!((d.iter().sum::<f64>() - 1.0).abs() < 1e-9, "{d:?}");
    }
}

#[test]
fn seeing_a_counter_and_a_table_from_a_kitchen_place_makes_it_a_kitchen() {
    let world = World::load(&shipped("domains/environments/office.yaml")).unwrap();
    let k: Knowledge = avs_format::load_yaml(&shipped("knowledge/office.yaml")).unwrap();
    let (mut wm, _, _) = explore_in_step(&world, &k);
    // The place nearest to the kitchen table stands for the kitchen.
    let table = world.env.objects.iter().find(|o| o.id == "table1").unwrap();
    let place = wm
        .places
        .graph
        .node_indices()
        .filter(|&n| wm.places.graph[n].door.is_none())
        .min_by(|&a, &b| {
            let d = |n: petgraph::graph::NodeIndex| {
                let p = wm.places.graph[n].pos;
                (p[0] - table.pose.x).hypot(p[1] - table.pose.y)
            };
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    let room = wm.room_of(place).unwrap();
    let before = wm.concepts.p_category(room, "kitchen").unwrap();
    // Looking around the whole room: one counter, one table, no desk, no shelf.
    for (class, n) in [("counter", 1), ("table", 1), ("desk", 0), ("shelf", 0)] {
        wm.saw_objects(place, class, n, 1.0).unwrap();
    }
    let after = wm.concepts.p_category(room, "kitchen").unwrap();
    assert!(
        after > 0.8 && after > before,
        "P(kitchen) {before} -> {after}"
    );
    // A landmark found there becomes an in/on location of the same room.
    let l = wm.found_landmark(place, "table").unwrap();
    let on_table = avs_concepts::Location::Landmark(l, avs_concepts::Relation::On);
    let p = wm.concepts.p_object_at(on_table, "cerealbox").unwrap();
    assert!(p > 0.2, "P(cerealbox on the kitchen table) = {p}");
}
