//! The calibration bench of the simulated camera image (`avs zoom-bench`) shows the trends of
//! Sjöö et al. `004` Figs. 7–10: the contract of the simulated attention and recogniser that
//! the zoom pipeline works on. Every trend is asserted on seeds 1–5 (the bench is cheap: 1600
//! images a seed).

use avs_eval::zoom_calibration::{
    draw, run_calibration, CalibrationParams, CalibrationReport, ImageRecord, TestObject,
};
use avs_robot::ImageGeometry;
use avs_sim::image::ClassAppearance;
use avs_view::zoom::{ObjectModel, DEFAULT_VOTE_THRESHOLD};

fn reports() -> Vec<CalibrationReport> {
    (1..=5)
        .map(|seed| {
            run_calibration(&CalibrationParams {
                seed,
                ..CalibrationParams::default()
            })
            .unwrap()
        })
        .collect()
}

/// The records at distances `d` with `keep(d)`.
fn at(r: &CalibrationReport, keep: impl Fn(f64) -> bool) -> Vec<&ImageRecord> {
    r.records.iter().filter(|x| keep(x.distance)).collect()
}

fn share(part: usize, whole: usize) -> f64 {
    part as f64 / whole.max(1) as f64
}

fn false_share(rs: &[&ImageRecord]) -> f64 {
    share(
        rs.iter().map(|r| r.false_hypotheses).sum(),
        rs.iter().map(|r| r.hypotheses).sum(),
    )
}

fn mean(xs: impl Iterator<Item = f64>) -> f64 {
    let v: Vec<f64> = xs.collect();
    assert!(!v.is_empty());
    v.iter().sum::<f64>() / v.len() as f64
}

#[test]
fn fig7_false_hypotheses_are_a_larger_share_at_long_range() {
    for r in reports() {
        let near = false_share(&at(&r, |d| d <= 1.0));
        let far = false_share(&at(&r, |d| d >= 3.5));
        assert!(
            far > near + 0.2,
            "seed {}: {near:.2} near, {far:.2} far",
            r.seed
        );
        assert!(r.fig7_false_hypotheses.iter().all(|x| x.hypotheses > 0));
    }
}

#[test]
fn fig8_the_strongest_hypothesis_is_the_object_at_short_range_and_less_than_half_the_time_from_2_5_m(
) {
    for r in reports() {
        let correct =
            |rs: Vec<&ImageRecord>| share(rs.iter().filter(|x| x.strongest_true).count(), rs.len());
        let near = correct(at(&r, |d| d <= 1.0));
        let far = correct(at(&r, |d| d >= 2.5));
        assert!(near >= 0.5, "seed {}: {near:.2} at ≤ 1 m", r.seed);
        assert!(far < 0.5, "seed {}: {far:.2} at ≥ 2.5 m", r.seed);
        // Reliability decreases with distance (§4.2): the farthest is the worst.
        let by_distance: Vec<f64> = r
            .fig8_correct_strongest
            .iter()
            .map(|x| x.percent_correct)
            .collect();
        assert!(by_distance[0] > by_distance[7] + 50.0, "{by_distance:?}");
    }
}

#[test]
fn fig9_sift_is_accurate_at_short_range_and_poor_beyond_2_5_m_while_rfch_stays_usable() {
    for r in reports() {
        let near = at(&r, |d| d <= 1.5);
        let sift_near = mean(near.iter().filter_map(|x| x.sift_error()));
        let rfch_near = mean(near.iter().filter_map(|x| x.rfch_error()));
        assert!(
            sift_near < rfch_near,
            "seed {}: SIFT {sift_near:.2} m vs RFCH {rfch_near:.2} m at ≤ 1.5 m",
            r.seed
        );
        let far = at(&r, |d| d > 2.5);
        let sift_far = mean(far.iter().filter_map(|x| x.sift_error()));
        assert!(
            sift_far > sift_near + 0.5,
            "seed {}: SIFT {sift_far:.2} m beyond 2.5 m",
            r.seed
        );
        // RFCH at 3–4 m: rough, but adequate for choosing a zoom.
        let long = at(&r, |d| d >= 3.0);
        let relative = mean(
            long.iter()
                .filter_map(|x| x.rfch_error().map(|e| e / x.distance)),
        );
        assert!(
            relative < 0.6,
            "seed {}: RFCH {relative:.2} at 3–4 m",
            r.seed
        );
        // Both methods tend towards the low end at long range (§4.2: outliers of 0.5–1 m).
        let row = r.fig9_distance.last().unwrap();
        assert!(row.sift.mean.is_none_or(|m| m < row.distance));
        assert!(row.rfch.mean.unwrap() < row.distance);
        assert!(row.rfch.min.unwrap() < 1.0, "{:?}", row.rfch);
    }
}

#[test]
fn fig10_rfch_is_the_better_estimate_from_2_m_and_sift_below_1_5_m() {
    for r in reports() {
        let better = |rs: Vec<&ImageRecord>| {
            let n = rs.len();
            let rfch = rs.iter().filter(|x| x.rfch_better() == Some(true)).count();
            let sift = rs.iter().filter(|x| x.rfch_better() == Some(false)).count();
            (share(rfch, n), share(sift, n))
        };
        let (rfch_far, _) = better(at(&r, |d| d >= 2.0));
        let (_, sift_near) = better(at(&r, |d| d <= 1.5));
        assert!(
            rfch_far > 0.5,
            "seed {}: RFCH {rfch_far:.2} at ≥ 2 m",
            r.seed
        );
        assert!(
            sift_near > 0.5,
            "seed {}: SIFT {sift_near:.2} at ≤ 1.5 m",
            r.seed
        );
    }
}

#[test]
fn the_bench_is_seeded_and_its_report_has_the_four_series() {
    let p = CalibrationParams {
        images_per_position: 2,
        ..CalibrationParams::default()
    };
    let a = run_calibration(&p).unwrap();
    assert_eq!(a, run_calibration(&p).unwrap());
    assert_eq!(a.images, 5 * 2 * 8 * 2);
    let json = serde_json::to_value(&a).unwrap();
    for key in [
        "fig7_false_hypotheses",
        "fig8_correct_strongest",
        "fig9_distance",
        "fig10_better_estimate",
    ] {
        assert_eq!(json[key].as_array().map(Vec::len), Some(8), "{key}");
    }
    let text = a.tables();
    assert!(text.contains("Fig. 7") && text.contains("Fig. 10"));
    let dir = std::env::temp_dir().join(format!("avs-zoom-calibration-{}", std::process::id()));
    let files = draw(&a, &dir).unwrap();
    assert_eq!(files.len(), 4);
    for f in &files {
        let svg = std::fs::read_to_string(f).unwrap();
        assert!(
            svg.starts_with("<svg") && svg.contains("</svg>"),
            "{}",
            f.display()
        );
    }
    std::fs::remove_dir_all(&dir).ok();
    // A bad parameter is named.
    let e = run_calibration(&CalibrationParams {
        images_per_position: 0,
        ..CalibrationParams::default()
    })
    .unwrap_err();
    assert!(e.to_string().contains("images_per_position"), "{e}");
}

#[test]
fn the_simulators_training_image_is_the_zoom_pipelines() {
    let image = ImageGeometry::default();
    for o in TestObject::paper_objects() {
        let model = ObjectModel {
            class: o.class.clone(),
            width: o.width,
            height: o.height,
            vote_threshold: DEFAULT_VOTE_THRESHOLD,
        };
        let appearance = ClassAppearance {
            name: o.class.clone(),
            width: o.width,
            height: o.height,
        };
        assert_eq!(
            model.train_px(&image),
            appearance.train_px(&image),
            "{}",
            o.class
        );
    }
}
