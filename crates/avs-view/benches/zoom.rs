//! One three-step search (Sjöö et al. `004` §3.1) on a cheap test robot: the pipeline's own
//! compute per view cone (hypotheses, distances, windows, sharing, placement), without any
//! image processing. Target: ≤ 5 ms per search.
#![allow(
    missing_docs,
    reason = "criterion_group! generates an undocumented public function"
)]

use avs_robot::{Camera, ImageGeometry, Point3, Pose2D, ViewCone};
use avs_view::zoom::{
    group_into_windows, three_step_search, Hypothesis, ObjectModel, ZoomConfig,
    DEFAULT_VOTE_THRESHOLD,
};
use criterion::{criterion_group, criterion_main, Criterion};

#[allow(dead_code, reason = "the test robot's knobs the bench does not turn")]
#[path = "../src/zoom/testbed.rs"]
mod testbed;

use testbed::{BoxObject, BoxRobot};

fn camera() -> Camera {
    Camera {
        hfov: 45f64.to_radians(),
        vfov: 35f64.to_radians(),
        pan_limits: [-std::f64::consts::PI, std::f64::consts::PI],
        tilt_limits: [-0.8, 0.6],
        max_zoom: 13.0,
        height: 1.2,
    }
}

fn model(class: &str) -> ObjectModel {
    ObjectModel {
        class: class.into(),
        width: 0.3,
        height: 0.3,
        vote_threshold: DEFAULT_VOTE_THRESHOLD,
    }
}

fn object(class: &str, x: f64, y: f64, z: f64) -> BoxObject {
    let m = model(class);
    BoxObject {
        class: class.into(),
        centre: Point3 { x, y, z },
        width: m.width,
        height: m.height,
        train_width_px: m.train_px(&ImageGeometry::default()).0,
    }
}

fn bench(c: &mut Criterion) {
    // Two classes side by side 3 m away and a third class absent, with distractor cells for
    // every class: hypotheses to group, windows to share, a final image per found class.
    let mut robot = BoxRobot::new(
        camera(),
        Pose2D::new(0.0, 0.0, 0.0),
        vec![
            object("book", 3.0, 0.2, 1.0),
            object("box", 3.0, -0.15, 1.0),
        ],
    );
    for class in ["book", "box", "cup"] {
        robot.distractors.push((class.into(), 3, 3, 0.6));
        robot.distractors.push((class.into(), 17, 12, 0.5));
    }
    let models = [model("book"), model("box"), model("cup")];
    let cone = ViewCone::new(Pose2D::new(0.0, 0.0, 0.0), 0.0, 0.0, 1.0);
    let config = ZoomConfig::default();
    let out = three_step_search(&mut robot, &cone, &models, &config).expect("the search runs");
    assert_eq!(out.found.len(), 2, "{out:#?}");
    c.bench_function("three_step_search/2_of_3_classes", |b| {
        b.iter(|| {
            let out = three_step_search(&mut robot, &cone, &models, &config);
            std::hint::black_box(out)
        })
    });
}

/// The worst case of grouping (§3.4.1): every other cell a hypothesis (88 of them), grouped at
/// magnification 3.
fn dense_grouping(c: &mut Criterion) {
    let g = ImageGeometry::default();
    let hs: Vec<Hypothesis> = (0..8)
        .flat_map(|r| {
            (0..11).map(move |col| Hypothesis {
                class: "book".into(),
                col: 2 * col,
                row: 2 * r,
                value: 0.5 + 0.001 * (col + r) as f64,
                min_col: 2 * col,
                min_row: 2 * r,
                max_col: 2 * col,
                max_row: 2 * r,
            })
        })
        .collect();
    c.bench_function("group_into_windows/88_hypotheses", |b| {
        b.iter(|| std::hint::black_box(group_into_windows(&hs, "book", 3.0, &g)))
    });
}

criterion_group!(benches, bench, dense_grouping);
criterion_main!(benches);
