//! Criterion benches: libDAI's testfast model, and a 100-room conceptual map (5 categories,
//! 3 place properties per room) from cold and after one observation (warm start).
#![allow(
    missing_docs,
    reason = "criterion_group! generates an undocumented public function; an allow, not an expect: the example that includes this file as a private module sees no public item"
)]

use avs_concepts::bp::{run_bp, BpOptions, Updates};
use avs_concepts::io::parse_fg;
use avs_concepts::{ConceptualMap, PlaceId, RoomId};
use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use rand::{Rng, SeedableRng};

fn testfast(c: &mut Criterion) {
    let Some(dir) = avs_testdata::reference_data("bp") else {
        return;
    };
    let text = std::fs::read_to_string(dir.join("libdai_testfast.fg")).unwrap();
    let g = parse_fg(&text, "testfast").unwrap().graph;
    for (name, updates) in [
        ("testfast_bp_parall", Updates::Parall),
        ("testfast_bp_seqfix", Updates::SeqFix),
        ("testfast_bp_seqmax", Updates::SeqMax),
    ] {
        let opts = BpOptions {
            updates,
            ..BpOptions::default()
        };
        c.bench_function(name, |b| b.iter(|| run_bp(&g, &opts, None).unwrap()));
    }
}

/// 100 rooms on a 10 × 10 grid of doors (loopy), each with 3 property observations.
pub fn hundred_rooms() -> ConceptualMap {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../knowledge/home.yaml");
    let k = avs_format::load_yaml(std::path::Path::new(path)).unwrap();
    let mut map = ConceptualMap::new("home.yaml", &k).unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let props = [
        ("shape", vec!["elongated", "square"]),
        ("size", vec!["small", "medium", "large"]),
        (
            "appearance",
            vec![
                "hallway_like",
                "kitchen_like",
                "living_like",
                "bedroom_like",
                "bathroom_like",
            ],
        ),
    ];
    for r in 0..100u64 {
        map.add_room(RoomId(r)).unwrap();
        for (name, values) in &props {
            let v = values[rng.gen_range(0..values.len())];
            map.observe_property(RoomId(r), PlaceId(r), name, v)
                .unwrap();
        }
    }
    for r in 0..100u64 {
        if r % 10 != 9 {
            map.add_adjacency(RoomId(r), RoomId(r + 1)).unwrap();
        }
        if r < 90 {
            map.add_adjacency(RoomId(r), RoomId(r + 10)).unwrap();
        }
    }
    map
}

fn conceptual_map(c: &mut Criterion) {
    let map = hundred_rooms();
    c.bench_function("map100_cold_converge", |b| {
        b.iter_batched(
            || {
                let mut m = map.clone();
                m.reset_messages();
                m
            },
            |mut m| {
                m.infer().unwrap();
                m
            },
            BatchSize::SmallInput,
        )
    });
    let mut i = 0u64;
    c.bench_function("map100_one_observation_warm", |b| {
        b.iter_batched(
            || map.clone(),
            |mut m| {
                i = (i + 37) % 100;
                m.observe_property(RoomId(i), PlaceId(1000), "appearance", "kitchen_like")
                    .unwrap();
                m
            },
            BatchSize::SmallInput,
        )
    });
}

criterion_group!(benches, testfast, conceptual_map);
criterion_main!(benches);
