//! Tests of the three-step zoomed search (`super`).

use super::*;
use crate::zoom::model::DEFAULT_VOTE_THRESHOLD;
use crate::zoom::testbed::{BoxObject, BoxRobot};
use avs_robot::Pose2D;

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

fn start() -> ViewCone {
    ViewCone::new(Pose2D::new(0.0, 0.0, 0.0), 0.0, 0.0, 1.0)
}

fn steps(o: &ZoomOutcome) -> Vec<(Step, ImageKind)> {
    o.images.iter().map(|i| (i.step, i.kind)).collect()
}

#[test]
fn an_object_three_metres_away_is_recognised_after_middle_and_final_and_placed_within_a_decimetre()
{
    // A book 3 m ahead, a little left of and below the camera's axis.
    let truth = Point3 {
        x: 3.0,
        y: 0.1,
        z: 1.0,
    };
    let mut robot = BoxRobot::new(
        camera(),
        Pose2D::new(0.0, 0.0, 0.0),
        vec![object("book", truth.x, truth.y, truth.z)],
    );
    let out = three_step_search(
        &mut robot,
        &start(),
        &[model("book")],
        &ZoomConfig::default(),
    )
    .unwrap();
    assert_eq!(out.found.len(), 1, "{out:#?}");
    let f = &out.found[0];
    assert_eq!(f.class, "book");
    let err = ((f.position.x - truth.x).powi(2)
        + (f.position.y - truth.y).powi(2)
        + (f.position.z - truth.z).powi(2))
    .sqrt();
    assert!(err < 0.1, "placed {:?}, {err} m off", f.position);
    // The initial image's vote width (whole cells) underestimates the distance; the middle
    // image's SIFT distance (the object needs < 3× its zoom) says the final zoom is still
    // more than 1.2× away; the final image, sanity check and recognition.
    assert_eq!(
        steps(&out),
        vec![
            (Step::Initial, ImageKind::Attention),
            (Step::Middle, ImageKind::Attention),
            (Step::Middle, ImageKind::Recognition),
            (Step::Final, ImageKind::Attention),
            (Step::Final, ImageKind::Recognition)
        ]
    );
    // The recognition image has eq. 1's zoom for the true distance.
    let eq1 = model("book").zoom_for(3.0, &camera(), &ImageGeometry::default());
    assert!(within(f.cone.zoom, eq1, 1.05), "{:?} vs {eq1}", f.cone);
    assert!(!within(out.images[1].cone.zoom, eq1, 1.2));
    assert_eq!(f.matches, 60);
    assert!(!out.budget_exhausted && out.skipped.is_empty(), "{out:#?}");
    let seconds: f64 = out.images.iter().map(|i| i.seconds).sum();
    assert!((out.seconds - seconds).abs() < 1e-12 && out.seconds > 0.0);
}

#[test]
fn a_middle_image_within_1_2x_of_the_final_zoom_goes_straight_to_recognition() {
    // The same book 10 cm further left: its initial vote area gives a closer middle zoom,
    // within 1.2× of the final one, so the middle image's recognition decides.
    let mut robot = BoxRobot::new(
        camera(),
        Pose2D::new(0.0, 0.0, 0.0),
        vec![object("book", 3.0, 0.2, 1.0)],
    );
    let out = three_step_search(
        &mut robot,
        &start(),
        &[model("book")],
        &ZoomConfig::default(),
    )
    .unwrap();
    assert_eq!(
        steps(&out),
        vec![
            (Step::Initial, ImageKind::Attention),
            (Step::Middle, ImageKind::Attention),
            (Step::Middle, ImageKind::Recognition)
        ]
    );
    let eq1 = model("book").zoom_for(3.0, &camera(), &ImageGeometry::default());
    assert!(within(out.images[1].cone.zoom, eq1, 1.2));
    assert_eq!(out.found.len(), 1);
    assert_eq!(out.found[0].cone, out.images[2].cone);
    let p = out.found[0].position;
    assert!(
        p.planar_distance(3.0, 0.2) < 0.1 && (p.z - 1.0).abs() < 0.1,
        "{p:?}"
    );
}

#[test]
fn an_object_that_already_fills_the_image_is_recognised_on_the_first_image() {
    // 0.3 m at 0.5 m fills the unzoomed image: SIFT on the initial image, straight to
    // recognition.
    let mut robot = BoxRobot::new(
        camera(),
        Pose2D::new(0.0, 0.0, 0.0),
        vec![object("book", 0.5, 0.0, 1.2)],
    );
    let out = three_step_search(
        &mut robot,
        &start(),
        &[model("book")],
        &ZoomConfig::default(),
    )
    .unwrap();
    assert_eq!(
        steps(&out),
        vec![
            (Step::Initial, ImageKind::Attention),
            (Step::Initial, ImageKind::Recognition)
        ]
    );
    assert_eq!(out.found.len(), 1);
    assert!(
        (out.found[0].distance - 0.5).abs() < 0.05,
        "{:?}",
        out.found[0]
    );
}

#[test]
fn two_classes_near_each_other_share_a_middle_image() {
    let objects = vec![
        object("book", 3.0, 0.2, 1.0),
        object("box", 3.0, -0.15, 1.0),
    ];
    let both = [model("book"), model("box")];
    let mut robot = BoxRobot::new(camera(), Pose2D::new(0.0, 0.0, 0.0), objects.clone());
    let out = three_step_search(&mut robot, &start(), &both, &ZoomConfig::default()).unwrap();
    assert_eq!(out.found.len(), 2, "{out:#?}");
    let shared = out
        .images
        .iter()
        .filter(|i| i.step == Step::Middle && i.kind == ImageKind::Attention)
        .filter(|i| i.classes.len() == 2)
        .count();
    assert!(shared >= 1, "{:#?}", out.images);
    // One class at a time takes more images.
    let mut alone = 0;
    for m in &both {
        let mut robot = BoxRobot::new(camera(), Pose2D::new(0.0, 0.0, 0.0), objects.clone());
        let o = three_step_search(
            &mut robot,
            &start(),
            std::slice::from_ref(m),
            &ZoomConfig::default(),
        )
        .unwrap();
        assert_eq!(o.found.len(), 1);
        alone += o.images.len();
    }
    assert!(
        out.images.len() < alone,
        "{} together, {alone} apart",
        out.images.len()
    );
}

#[test]
fn an_image_budget_of_three_stops_the_search_at_three_images() {
    let mut robot = BoxRobot::new(
        camera(),
        Pose2D::new(0.0, 0.0, 0.0),
        vec![object("book", 3.0, 0.1, 1.0)],
    );
    let config = ZoomConfig {
        max_images: 3,
        ..ZoomConfig::default()
    };
    let out = three_step_search(&mut robot, &start(), &[model("book")], &config).unwrap();
    assert_eq!(out.images.len(), 3);
    assert!(out.budget_exhausted);
    assert!(out.found.is_empty());
    // No budget at all: no image.
    let config = ZoomConfig {
        max_images: 0,
        ..config
    };
    let out = three_step_search(&mut robot, &start(), &[model("book")], &config).unwrap();
    assert!(out.images.is_empty() && out.budget_exhausted);
}

#[test]
fn a_robot_without_attention_is_an_unsupported_error() {
    let mut robot = BoxRobot::new(
        camera(),
        Pose2D::new(0.0, 0.0, 0.0),
        vec![object("book", 3.0, 0.2, 1.0)],
    );
    robot.has_attention = false;
    let e = three_step_search(
        &mut robot,
        &start(),
        &[model("book")],
        &ZoomConfig::default(),
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            ZoomError::Unsupported {
                capability: "attention",
                ..
            }
        ),
        "{e:?}"
    );
}

#[test]
fn a_distractor_only_image_recognises_nothing() {
    let mut robot = BoxRobot::new(camera(), Pose2D::new(0.0, 0.0, 0.0), Vec::new());
    robot.distractors = vec![("book".into(), 5, 5, 0.8), ("book".into(), 15, 10, 0.6)];
    let out = three_step_search(
        &mut robot,
        &start(),
        &[model("book")],
        &ZoomConfig::default(),
    )
    .unwrap();
    assert!(out.found.is_empty());
    // It did look: the distractors led to recognition images that matched nothing.
    assert!(
        out.images.iter().any(|i| i.kind == ImageKind::Recognition),
        "{:#?}",
        out.images
    );
    assert!(out.images.len() <= ZoomConfig::default().max_images);
    // No hypothesis at all: one image.
    robot.distractors.clear();
    let out = three_step_search(
        &mut robot,
        &start(),
        &[model("book")],
        &ZoomConfig::default(),
    )
    .unwrap();
    assert_eq!(out.images.len(), 1);
}

#[test]
fn bad_inputs_are_errors_not_panics() {
    let mut robot = BoxRobot::new(camera(), Pose2D::new(0.0, 0.0, 0.0), Vec::new());
    let c = ZoomConfig::default();
    let nan_zoom = ViewCone {
        zoom: f64::NAN,
        ..start()
    };
    assert!(matches!(
        three_step_search(&mut robot, &nan_zoom, &[model("book")], &c),
        Err(ZoomError::InvalidInput { field: "cone", .. })
    ));
    let flat = ObjectModel {
        width: 0.0,
        ..model("book")
    };
    assert!(matches!(
        three_step_search(&mut robot, &start(), &[flat], &c),
        Err(ZoomError::InvalidInput {
            field: "models",
            ..
        })
    ));
    let zero = ZoomConfig {
        image: ImageGeometry {
            width_px: 0,
            ..c.image
        },
        ..c
    };
    assert!(three_step_search(&mut robot, &start(), &[model("book")], &zero).is_err());
    let share = ZoomConfig {
        recognition_share: f64::NAN,
        ..c
    };
    assert!(three_step_search(&mut robot, &start(), &[model("book")], &share).is_err());
    robot.camera.max_zoom = f64::NAN;
    assert!(matches!(
        three_step_search(&mut robot, &start(), &[model("book")], &c),
        Err(ZoomError::InvalidInput {
            field: "camera",
            ..
        })
    ));
    // No classes: nothing to do, no image.
    robot.camera = camera();
    let out = three_step_search(&mut robot, &start(), &[], &c).unwrap();
    assert!(out.images.is_empty());
}

#[test]
fn a_window_beyond_the_pan_limits_is_dropped_and_noted() {
    // The camera cannot pan at all and the book is far off to the left, near the image's
    // edge: the window's centre needs a pan.
    let mut cam = camera();
    cam.pan_limits = [0.0, 0.0];
    let mut robot = BoxRobot::new(
        cam,
        Pose2D::new(0.0, 0.0, 0.0),
        vec![object("book", 3.0, 1.15, 1.2)],
    );
    let out = three_step_search(
        &mut robot,
        &start(),
        &[model("book")],
        &ZoomConfig::default(),
    )
    .unwrap();
    assert!(out.found.is_empty());
    assert!(!out.skipped.is_empty(), "{out:#?}");
    assert!(
        out.skipped[0].reason.contains("pan/tilt"),
        "{:?}",
        out.skipped
    );
}

#[test]
fn depth_becomes_range_off_the_optical_axis() {
    let (c, g) = (camera(), ImageGeometry::default());
    let cone = start();
    assert!((depth_to_range(&c, &cone, &g, (160.0, 120.0), 2.0) - 2.0).abs() < 1e-12);
    // A point projected at the image's edge: its range is its distance from the camera.
    let p = Point3 {
        x: 2.0,
        y: -0.5,
        z: 1.2,
    };
    let (u, v, depth) = c.project(&cone, &g, p).unwrap();
    let range = depth_to_range(&c, &cone, &g, (u, v), depth);
    assert!((range - 2.0f64.hypot(0.5)).abs() < 1e-9, "{range}");
}
