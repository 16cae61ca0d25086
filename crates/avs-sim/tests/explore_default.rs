//! Exploring the shipped default environment from its start by repeatedly going to the best
//! placeholder reveals its free space and finds every door and room.

use avs_map::grid::Cell;
use avs_map::places::{dist, PlaceMapParams};
use avs_sim::{Explorer, World};
use std::collections::BTreeSet;
use std::path::Path;

fn default_world() -> World {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/environments/office.yaml");
    World::load(&path).expect("the default environment loads")
}

#[test]
fn exploring_the_default_office_reveals_its_space_doors_and_rooms() {
    let world = default_world();
    let mut ex = Explorer::new(&world, PlaceMapParams::default(), 1);
    ex.run(200);

    // Free space: every truly free cell that belongs to a room.
    let truth = &world.truth;
    let (mut free, mut seen) = (0usize, 0usize);
    for row in 0..truth.height() {
        for col in 0..truth.width() {
            let k = truth.index(col, row);
            if truth.get(col, row) == Cell::Free && world.room_of_cell[k].is_some() {
                free += 1;
                if ex.robot.known.get(col, row) == Cell::Free {
                    seen += 1;
                }
            }
        }
    }
    let share = seen as f64 / free as f64;
    eprintln!(
        "steps {} share {share:.3} places {} doors {} rooms {}",
        ex.steps,
        ex.places.graph.node_count(),
        ex.places.doors.len(),
        ex.places.rooms().rooms.len()
    );
    assert!(
        share >= 0.95,
        "revealed {:.1}% of the free space in {} steps",
        100.0 * share,
        ex.steps
    );

    // Every door: a confirmed door hypothesis within half a metre of each true door.
    for d in &world.env.doors {
        let c = [d.pose.x, d.pose.y];
        assert!(
            ex.places
                .doors
                .iter()
                .any(|m| m.confirmed && dist(m.hypothesis.center, c) < 0.5),
            "door {} not found; map doors: {:?}",
            d.name,
            ex.places
                .doors
                .iter()
                .map(|m| (m.hypothesis.center, m.confirmed))
                .collect::<Vec<_>>()
        );
    }

    // Every room: the place map's rooms correspond one to one with the true rooms.
    let rooms = ex.places.rooms();
    let mut matched = BTreeSet::new();
    for r in &rooms.rooms {
        let truth_rooms: BTreeSet<usize> = r
            .places
            .iter()
            .filter_map(|&p| {
                let pos = ex.places.graph[p].pos;
                world.room_at(pos[0], pos[1])
            })
            .collect();
        assert_eq!(
            truth_rooms.len(),
            1,
            "place-map room {} spans true rooms {truth_rooms:?}",
            r.id
        );
        matched.insert(*truth_rooms.iter().next().unwrap());
    }
    assert_eq!(rooms.rooms.len(), world.env.rooms.len(), "room count");
    assert_eq!(
        matched.len(),
        world.env.rooms.len(),
        "every true room found once"
    );
    assert_eq!(
        rooms.adjacency.len(),
        world.env.doors.len(),
        "one adjacency per door"
    );
}

#[test]
fn exploring_generated_floors_never_merges_rooms_and_finds_most() {
    let k: avs_format::knowledge::Knowledge = avs_format::load_yaml(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../knowledge/office.yaml"),
    )
    .unwrap();
    let (mut found, mut total) = (0usize, 0usize);
    for seed in 0..8u64 {
        let env = avs_sim::generate::generate(
            &k,
            &avs_sim::generate::GenerateParams {
                seed,
                rooms: 4,
                ensure_class: None,
                placement: Default::default(),
                ..Default::default()
            },
        )
        .unwrap();
        let world = World::new(env, Path::new(".")).unwrap();
        let mut ex = Explorer::new(&world, PlaceMapParams::default(), seed);
        ex.run(200);
        let rooms = ex.places.rooms();
        let mut matched = BTreeSet::new();
        for r in &rooms.rooms {
            let truth: BTreeSet<usize> = r
                .places
                .iter()
                .filter_map(|&p| {
                    world.room_at(ex.places.graph[p].pos[0], ex.places.graph[p].pos[1])
                })
                .collect();
            assert_eq!(
                truth.len(),
                1,
                "seed {seed}: place-map room {} spans true rooms {truth:?}",
                r.id
            );
            matched.extend(truth);
        }
        eprintln!(
            "seed {seed}: {} of {} rooms found as separate rooms",
            matched.len(),
            world.env.rooms.len()
        );
        found += matched.len();
        total += world.env.rooms.len();
    }
    // A room is found only once the robot drops a place inside it: rooms seen whole through
    // their doorway are not entered by pure exploration, and a doorway the detector misses on
    // the partial map leaves the room's places unseparated. Measured: 35 of 40 on these seeds;
    // this floor guards against regressions.
    assert!(
        found as f64 >= 0.8 * total as f64,
        "found {found} of {total} rooms"
    );
}
