//! Room segmentation against the IPA room segmentation benchmark's ground truth
//! (`../shared/data/rooms`, see its README); skipped when the reference data is absent.
//! `AVS_SEGMENT_FURNITURE=1` also scores the furniture maps (printed, no target);
//! `AVS_SEGMENT_DEBUG=DIR` writes each segmentation as a PNG into DIR for inspection.

use avs_map::grid::OccupancyGrid;
use avs_map::metrics::{load_truth_image, score, SegmentationScore};
use avs_map::segment::{segment_rooms, SegmentParams};
use std::path::Path;

use avs_testdata::ROOM_MAPS as MAPS;

fn run(dir: &Path, map: &str, variant: &str) -> SegmentationScore {
    let grid = OccupancyGrid::from_map_server_yaml(&dir.join(format!("{map}{variant}.yaml")))
        .expect("benchmark map loads");
    let truth = load_truth_image(&dir.join(format!("{map}_gt_segmentation.png")))
        .expect("benchmark truth loads");
    assert_eq!((truth.width, truth.height), (grid.width(), grid.height()));
    let seg = segment_rooms(&grid, &SegmentParams::default()).expect("default parameters valid");
    let s = score(&seg.labels, &truth.labels).expect("same size");
    if let Some(out) = std::env::var_os("AVS_SEGMENT_DEBUG") {
        let (w, h) = (grid.width(), grid.height());
        let mut img = image::RgbImage::new(w as u32, h as u32);
        for row in 0..h {
            for col in 0..w {
                let l = seg.labels[grid.index(col, row)];
                let c = if l == 0 {
                    [40, 40, 40]
                } else {
                    let k = l.wrapping_mul(2654435761);
                    [
                        (k >> 24) as u8 | 64,
                        (k >> 16) as u8 | 64,
                        (k >> 8) as u8 | 64,
                    ]
                };
                img.put_pixel(col as u32, (h - 1 - row) as u32, image::Rgb(c));
            }
        }
        for d in &seg.doors {
            for j in d.jambs {
                let (x, y) = grid.world_to_cell(j[0], j[1]);
                if grid.contains(x, y) {
                    img.put_pixel(x as u32, (h as i64 - 1 - y) as u32, image::Rgb([255, 0, 0]));
                }
            }
        }
        img.save(Path::new(&out).join(format!("{map}{variant}.png")))
            .unwrap();
    }
    eprintln!(
        "{map}{variant}: rooms {} truth {} P {:.3} R {:.3} Ppx {:.3} Rpx {:.3} MCC {:.3}",
        seg.rooms,
        s.truth_rooms,
        s.precision_per_room,
        s.recall_per_room,
        s.precision_pixel,
        s.recall_pixel,
        s.mcc
    );
    s
}

#[test]
fn plain_maps_reach_mean_per_room_precision_and_recall_of_085() {
    let Some(dir) = avs_testdata::reference_data("rooms") else {
        return;
    };
    let scores: Vec<SegmentationScore> = MAPS.iter().map(|m| run(&dir, m, "")).collect();
    let n = scores.len() as f64;
    let p = scores.iter().map(|s| s.precision_per_room).sum::<f64>() / n;
    let r = scores.iter().map(|s| s.recall_per_room).sum::<f64>() / n;
    eprintln!("mean P {p:.3} R {r:.3}");
    if std::env::var_os("AVS_SEGMENT_FURNITURE").is_some() {
        let f: Vec<SegmentationScore> = MAPS.iter().map(|m| run(&dir, m, "_furnitures")).collect();
        let fp = f.iter().map(|s| s.precision_per_room).sum::<f64>() / n;
        let fr = f.iter().map(|s| s.recall_per_room).sum::<f64>() / n;
        eprintln!("furniture mean P {fp:.3} R {fr:.3}");
    }
    assert!(p >= 0.85, "mean per-room precision {p:.3} < 0.85");
    assert!(r >= 0.85, "mean per-room recall {r:.3} < 0.85");
}
