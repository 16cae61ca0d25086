//! Print BP statistics of the 100-room benchmark map (cold and after one observation) for a
//! few message tolerances: `cargo run --release -p avs-concepts --example map_stats`.
#[path = "../benches/bp.rs"]
#[allow(
    dead_code,
    reason = "the example uses the bench's map builder, not its criterion groups (an expect on a module is not seen as fulfilled by dead code inside it)"
)]
mod bench;
use avs_concepts::{MapBpOptions, PlaceId, RoomId};
fn main() {
    for tol in [1e-9, 1e-7, 1e-6, 1e-5] {
        let mut m = bench::hundred_rooms();
        m.set_bp_options(MapBpOptions {
            tol,
            ..MapBpOptions::default()
        })
        .unwrap();
        let mut reference = m.clone();
        reference
            .set_bp_options(MapBpOptions {
                tol: 1e-13,
                ..MapBpOptions::default()
            })
            .unwrap();
        m.reset_messages();
        let t = std::time::Instant::now();
        m.infer().unwrap();
        println!("tol {tol:e} cold: {:?} in {:?}", m.stats(), t.elapsed());
        let t = std::time::Instant::now();
        m.observe_property(RoomId(45), PlaceId(1000), "appearance", "kitchen_like")
            .unwrap();
        let el = t.elapsed();
        reference
            .observe_property(RoomId(45), PlaceId(1000), "appearance", "kitchen_like")
            .unwrap();
        let err = m
            .rooms()
            .flat_map(|r| {
                let a = m.category_distribution(r).unwrap();
                let b = reference.category_distribution(r).unwrap();
                a.into_iter()
                    .zip(b)
                    .map(|(x, y)| (x - y).abs())
                    .collect::<Vec<_>>()
            })
            .fold(0.0, f64::max);
        println!(
            "tol {tol:e} warm: {:?} in {el:?}; max belief error vs tol 1e-13: {err:.1e}",
            m.stats()
        );
    }
}
