//! The segmentation scores on labellings whose scores follow from the definitions, and the
//! ground-truth reader on the benchmark's own images.

use avs_map::metrics::{load_truth_image, score, truth_from_mask};

#[test]
fn a_perfect_segmentation_scores_one_whatever_its_label_numbers() {
    let truth = [1, 1, 0, 2, 2, 2, 3, 3];
    let seg = [9, 9, 4, 5, 5, 5, 7, 7];
    let s = score(&seg, &truth).unwrap();
    assert_eq!((s.segments, s.truth_rooms), (3, 3));
    for v in [
        s.precision_per_room,
        s.recall_per_room,
        s.precision_pixel,
        s.recall_pixel,
        s.mcc,
    ] {
        assert!((v - 1.0).abs() < 1e-12, "{s:?}");
    }
}

#[test]
fn one_segment_over_two_equal_rooms_has_full_recall_half_precision_and_zero_mcc() {
    let truth = [1, 1, 1, 2, 2, 2];
    let seg = [1; 6];
    let s = score(&seg, &truth).unwrap();
    assert!((s.recall_per_room - 1.0).abs() < 1e-12);
    assert!((s.precision_per_room - 0.5).abs() < 1e-12);
    assert!((s.precision_pixel - 0.5).abs() < 1e-12);
    // Pairs: TP = 6, FP = 9, FN = 0, TN = 0 → MCC has a vanishing factor → 0.
    assert_eq!(s.mcc, 0.0);
}

#[test]
fn over_segmentation_keeps_precision_and_loses_recall_and_mcc() {
    let truth = [1, 1, 1, 1, 2, 2, 2, 2];
    let seg = [1, 1, 2, 2, 3, 3, 4, 4];
    let s = score(&seg, &truth).unwrap();
    assert!((s.precision_per_room - 1.0).abs() < 1e-12);
    assert!((s.recall_per_room - 0.5).abs() < 1e-12);
    // Pairs: TP = 4, FP = 0, FN = 12 − 4 = 8, TN = 28 − 12 = 16.
    let expect = (4.0 * 16.0) / ((4.0f64) * 12.0 * 16.0 * 24.0).sqrt();
    assert!((s.mcc - expect).abs() < 1e-12, "{} vs {expect}", s.mcc);
}

#[test]
fn unlabelled_cells_inside_rooms_cost_recall() {
    let truth = [1, 1, 1, 1];
    let seg = [1, 1, 1, 0];
    let s = score(&seg, &truth).unwrap();
    assert!((s.recall_pixel - 0.75).abs() < 1e-12);
    assert!((s.precision_pixel - 1.0).abs() < 1e-12);
}

#[test]
fn labellings_of_different_sizes_are_an_error() {
    let err = score(&[1, 1], &[1, 1, 1]).unwrap_err().to_string();
    assert!(err.contains("2 cells") && err.contains("3"), "{err}");
}

#[test]
fn truth_regions_are_eight_connected_and_small_ones_dropped() {
    // Two diagonal 11×11 blocks touching at a corner form one region; a 10×10 block
    // (100 px, not more than 100) is dropped.
    let (w, h) = (40, 40);
    let mut mask = vec![false; w * h];
    let mut fill = |x0: usize, y0: usize, n: usize| {
        for y in y0..y0 + n {
            for x in x0..x0 + n {
                mask[y * w + x] = true;
            }
        }
    };
    fill(0, 0, 11);
    fill(11, 11, 11);
    fill(28, 0, 10);
    let t = truth_from_mask(w, h, &mask, 100);
    assert_eq!(t.rooms, 1);
    assert_eq!(t.labels[0], t.labels[21 * w + 21]);
    assert_eq!(t.labels[30], 0);
}

#[test]
fn benchmark_truth_images_have_the_room_counts_the_readme_states() {
    let Some(dir) = avs_testdata::reference_data("rooms") else {
        return;
    };
    for (map, rooms) in [("lab_ipa", 10), ("Freiburg52_scan", 10)] {
        let t = load_truth_image(&dir.join(format!("{map}_gt_segmentation.png"))).unwrap();
        assert_eq!(t.rooms, rooms, "{map}");
    }
}

#[test]
fn a_missing_truth_image_is_an_error_naming_the_file() {
    let err = load_truth_image(std::path::Path::new("/nonexistent/gt.png"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("/nonexistent/gt.png"), "{err}");
}
