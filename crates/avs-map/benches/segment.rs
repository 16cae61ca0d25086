//! Room segmentation time on the IPA benchmark maps (`../shared/data/rooms`); skipped when the
//! reference data is absent.
#![expect(
    missing_docs,
    reason = "criterion_group! generates an undocumented public function"
)]

use avs_map::grid::OccupancyGrid;
use avs_map::segment::{segment_rooms, SegmentParams};
use criterion::{criterion_group, criterion_main, Criterion};

use avs_testdata::ROOM_MAPS as MAPS;

fn bench(c: &mut Criterion) {
    let Some(dir) = avs_testdata::reference_data("rooms") else {
        return;
    };
    let params = SegmentParams::default();
    let mut group = c.benchmark_group("segment_rooms");
    group.sample_size(10);
    for variant in ["", "_furnitures"] {
        for map in MAPS {
            let name = format!("{map}{variant}");
            let grid = OccupancyGrid::from_map_server_yaml(&dir.join(format!("{name}.yaml")))
                .expect("benchmark map loads");
            group.bench_function(&name, |b| {
                b.iter(|| segment_rooms(&grid, &params).expect("valid parameters"))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
