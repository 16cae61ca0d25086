//! Generated floors are deterministic, load as worlds, and every room is reachable.

use avs_format::knowledge::Knowledge;
use avs_map::nav::{shortest_path, Traversability};
use avs_sim::generate::{generate, GenerateParams};
use avs_sim::World;
use std::path::Path;

fn knowledge() -> Knowledge {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../knowledge/office.yaml");
    avs_format::load_yaml(&p).expect("shipped knowledge loads")
}

#[test]
fn same_seed_gives_the_same_floor_and_different_seeds_differ() {
    let k = knowledge();
    let p = |seed| GenerateParams {
        seed,
        rooms: 5,
        ensure_class: None,
        placement: Default::default(),
        ..Default::default()
    };
    let a = serde_yaml::to_string(&generate(&k, &p(7)).unwrap()).unwrap();
    let b = serde_yaml::to_string(&generate(&k, &p(7)).unwrap()).unwrap();
    let c = serde_yaml::to_string(&generate(&k, &p(8)).unwrap()).unwrap();
    assert_eq!(a, b);
    assert_ne!(a, c);
}

#[test]
fn generated_floors_load_and_every_room_and_ensured_target_is_reachable() {
    let k = knowledge();
    for seed in 0..12u64 {
        for rooms in [1usize, 3, 6] {
            let env = generate(
                &k,
                &GenerateParams {
                    seed,
                    rooms,
                    ensure_class: Some("cerealbox".into()),
                    placement: Default::default(),
                    ..Default::default()
                },
            )
            .unwrap_or_else(|e| panic!("seed {seed} rooms {rooms}: {e}"));
            assert_eq!(env.rooms.len(), rooms + 1, "corridor plus {rooms} rooms");
            assert_eq!(env.doors.len(), rooms);
            for d in &env.doors {
                assert!(
                    (k.door_width[0]..=k.door_width[1] + 1e-9).contains(&d.width),
                    "door width {}",
                    d.width
                );
            }
            assert!(
                env.objects.iter().any(|o| o.class == "cerealbox"),
                "seed {seed}: no cerealbox"
            );
            let world = World::new(env, Path::new(".")).expect("generated world builds");
            let trav = Traversability::new(&world.truth, world.env.robot.radius, false);
            let start = [world.env.robot.start.x, world.env.robot.start.y];
            for r in &world.env.rooms {
                let s = r.seed.unwrap();
                assert!(
                    shortest_path(&trav, start, [s.x, s.y], 1.0).is_some(),
                    "seed {seed} rooms {rooms}: room {} unreachable",
                    r.name
                );
            }
            for o in world.env.objects.iter().filter(|o| o.class == "cerealbox") {
                assert!(
                    shortest_path(&trav, start, [o.pose.x, o.pose.y], 1.5).is_some(),
                    "seed {seed}: {} cannot be approached",
                    o.id
                );
            }
        }
    }
}
