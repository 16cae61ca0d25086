//! The simulated camera detector and the simulated robot behind the agent's `Robot` trait:
//! seeded statistical tests of the sensor model of the knowledge file (binomial 4-sigma bounds).

use avs_format::knowledge::Knowledge;
use avs_robot::{FailureReason, Pose2D, Robot, ViewCone};
use avs_sim::sensors::{Detector, DetectorConfig};
use avs_sim::sim_robot::{FailureRates, SimAgentRobot, SimRobotConfig};
use avs_sim::{CameraView, World};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::Path;

const TRIALS: usize = 2000;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn office() -> World {
    World::load(&root().join("domains/environments/office.yaml")).unwrap()
}

fn office_with_door(door: &str, open: bool) -> World {
    let mut w = office();
    let i = w.env.doors.iter().position(|d| d.name == door).unwrap();
    w.env.doors[i].open = open;
    World::new(w.env.clone(), Path::new(".")).unwrap()
}

fn knowledge() -> Knowledge {
    avs_format::load_yaml(&root().join("knowledge/office.yaml")).unwrap()
}

fn knowledge_without_false_positives() -> Knowledge {
    let mut k = knowledge();
    k.sensor.false_positive = 0.0;
    k
}

/// The top centre of an object (what the camera aims at).
fn top(w: &World, id: &str) -> [f64; 3] {
    let o = w.env.objects.iter().find(|o| o.id == id).unwrap();
    [o.pose.x, o.pose.y, o.pose.z + o.size[2] / 2.0]
}

/// A zoom-1 view from `eye` aimed exactly at `target` (on the optical axis).
fn aimed(w: &World, eye: [f64; 3], target: [f64; 3]) -> CameraView {
    let (dx, dy, dz) = (target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]);
    CameraView {
        eye,
        yaw: dy.atan2(dx),
        tilt: dz.atan2(dx.hypot(dy)),
        hfov: w.env.camera.hfov_deg.to_radians(),
        vfov: w.env.camera.vfov_deg.to_radians(),
    }
}

fn dist3(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Over `TRIALS` views, the fraction with a detection of `class` within `tol` metres (planar)
/// of `near`, and the planar errors of those detections.
fn rate_near(
    det: &Detector,
    w: &World,
    view: &CameraView,
    class: &str,
    near: [f64; 3],
    tol: f64,
    seed: u64,
) -> (f64, Vec<f64>) {
    rate_near_zoomed(det, w, view, 1.0, class, near, tol, seed)
}

/// As [`rate_near`], with the view's fields of view already divided by `zoom`.
#[expect(
    clippy::too_many_arguments,
    reason = "a test helper mirroring the detector's own parameters one by one"
)]
fn rate_near_zoomed(
    det: &Detector,
    w: &World,
    view: &CameraView,
    zoom: f64,
    class: &str,
    near: [f64; 3],
    tol: f64,
    seed: u64,
) -> (f64, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let classes = vec![class.to_string()];
    let mut hits = 0;
    let mut errors = Vec::new();
    for _ in 0..TRIALS {
        let d = det.detect(w, view, zoom, &classes, &mut rng).unwrap();
        let close: Vec<f64> = d
            .iter()
            .map(|x| x.pose.planar_distance(near[0], near[1]))
            .filter(|&e| e < tol)
            .collect();
        if !close.is_empty() {
            hits += 1;
            errors.extend(close);
        }
    }
    (hits as f64 / TRIALS as f64, errors)
}

/// The binomial 4-sigma half-width for `TRIALS` trials at probability `p`.
fn four_sigma(p: f64, n: usize) -> f64 {
    4.0 * (p * (1.0 - p) / n as f64).sqrt()
}

#[test]
fn detection_rate_inside_the_range_on_axis_matches_one_minus_false_negative() {
    let w = office();
    let k = knowledge();
    let p = 1.0 - k.sensor.false_negative;
    let det = Detector::new(k, DetectorConfig::default()).unwrap();
    let cereal = top(&w, "cerealbox1");
    let view = aimed(&w, [5.5, 3.5, 1.2], cereal);
    let d = dist3(view.eye, cereal);
    assert!(
        (0.5..4.0).contains(&d),
        "inside cerealbox detection_range: {d}"
    );
    let (rate, _) = rate_near(&det, &w, &view, "cerealbox", cereal, 0.5, 11);
    assert!(
        (rate - p).abs() < four_sigma(p, TRIALS),
        "rate {rate}, expected {p}"
    );
}

#[test]
fn detection_rate_falls_with_distance_beyond_the_range() {
    // The whiteboard marker (detection range [0.3, 1.5] m) seen from the south at growing
    // distances, through the open office2 door for the farthest.
    let w = office();
    let k = knowledge();
    let p0 = 1.0 - k.sensor.false_negative;
    let range = k.class("whiteboardmarker").unwrap().detection_range;
    let det = Detector::new(k, DetectorConfig::default()).unwrap();
    let marker = top(&w, "whiteboardmarker1");
    let mut last = f64::INFINITY;
    for (i, back) in [1.0, 2.5, 3.9].into_iter().enumerate() {
        let view = aimed(&w, [marker[0], marker[1] - back, 1.2], marker);
        let d = dist3(view.eye, marker);
        // Beyond the range the apparent area falls with the square of the distance ratio.
        let expected = p0 * (range[1] / d).min(1.0).powi(2);
        let (rate, _) = rate_near(
            &det,
            &w,
            &view,
            "whiteboardmarker",
            marker,
            1.0,
            20 + i as u64,
        );
        assert!(
            (rate - expected).abs() < four_sigma(expected, TRIALS).max(0.01),
            "at {d:.2} m: rate {rate}, expected {expected}"
        );
        assert!(
            rate < last,
            "rate {rate} at {d:.2} m did not fall (before: {last})"
        );
        last = rate;
    }
    assert!(
        last < 0.2,
        "far outside the range the marker is rarely seen: {last}"
    );
}

#[test]
fn zoom_extends_the_detection_distance_by_the_zoom_factor() {
    // At 2.5 m the marker (range [0.3, 1.5] m) is outside the range at zoom 1 and inside it
    // at zoom 2 (Sjöö, Gálvez López et al., §3.4 eq. 1: magnification scales the apparent size).
    let w = office();
    let k = knowledge();
    let p0 = 1.0 - k.sensor.false_negative;
    let det = Detector::new(k, DetectorConfig::default()).unwrap();
    let marker = top(&w, "whiteboardmarker1");
    let wide = aimed(&w, [marker[0], marker[1] - 2.5, 1.2], marker);
    let zoomed = CameraView {
        hfov: wide.hfov / 2.0,
        vfov: wide.vfov / 2.0,
        ..wide
    };
    let (r1, _) = rate_near_zoomed(&det, &w, &wide, 1.0, "whiteboardmarker", marker, 1.0, 30);
    let (r2, _) = rate_near_zoomed(&det, &w, &zoomed, 2.0, "whiteboardmarker", marker, 1.0, 31);
    assert!(r1 < p0 - 4.0 * four_sigma(p0, TRIALS), "zoom 1: {r1}");
    assert!(
        (r2 - p0).abs() < four_sigma(p0, TRIALS),
        "zoom 2: {r2}, expected {p0}"
    );
}

#[test]
fn objects_behind_a_closed_door_are_never_detected_and_seen_when_it_is_open() {
    let det = Detector::new(
        knowledge_without_false_positives(),
        DetectorConfig::default(),
    )
    .unwrap();
    // From the corridor, through the kitchen door, at the cereal box (3.7 m: in range).
    for (open, want_some) in [(false, false), (true, true)] {
        let w = office_with_door("door_kitchen", open);
        let cereal = top(&w, "cerealbox1");
        let view = aimed(&w, [6.0, 1.5, 1.2], cereal);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let classes = vec!["cerealbox".to_string()];
        let n: usize = (0..TRIALS)
            .map(|_| {
                det.detect(&w, &view, 1.0, &classes, &mut rng)
                    .unwrap()
                    .len()
            })
            .sum();
        if want_some {
            assert!(n > TRIALS / 2, "open door: {n} detections");
        } else {
            assert_eq!(n, 0, "closed door: the cereal box is occluded");
        }
    }
}

#[test]
fn a_distractor_fires_as_the_searched_class_at_the_configured_rate() {
    let w = office();
    let cfg = DetectorConfig {
        distractor_rate: 0.3,
        ..Default::default()
    };
    let det = Detector::new(knowledge_without_false_positives(), cfg).unwrap();
    let mug = top(&w, "mug1");
    // 2.6 m away: inside the cereal box's detection range [0.5, 4] m, beyond its recognition
    // range [0.5, 2] m, so the look-alike fires at ρ.
    let view = aimed(&w, [7.0, 4.8, 1.2], mug);
    let (rate, _) = rate_near(&det, &w, &view, "cerealbox", mug, 0.5, 5);
    let p = cfg.distractor_rate;
    assert!(
        (rate - p).abs() < four_sigma(p, TRIALS),
        "rate {rate}, expected {p}"
    );
    // 1.5 m away, inside the recognition range, the recogniser tells it apart: ρ_r.
    let close = aimed(&w, [7.0, 5.9, 1.2], mug);
    let (rate, _) = rate_near(&det, &w, &close, "cerealbox", mug, 0.5, 7);
    let p = cfg.recognised_distractor_rate;
    assert!(
        (rate - p).abs() < four_sigma(p, TRIALS),
        "rate {rate} within the recognition range, expected {p}"
    );
    // A mug does not look like a table: landmark classes are not confused with distractors.
    let (table_rate, _) = rate_near(&det, &w, &view, "table", mug, 0.5, 6);
    assert_eq!(table_rate, 0.0);
}

#[test]
fn an_empty_view_fires_false_positives_at_the_knowledge_rate_and_scales() {
    let w = office();
    let k = knowledge();
    let fp = k.sensor.false_positive;
    // From the corridor's west end looking at the west wall: nothing in view.
    let view = aimed(&w, [1.0, 1.2, 1.2], [0.0, 1.2, 1.2]);
    for scale in [1.0, 2.0] {
        let cfg = DetectorConfig {
            false_positive_scale: scale,
            ..Default::default()
        };
        let det = Detector::new(k.clone(), cfg).unwrap();
        let (rate, _) = rate_near(&det, &w, &view, "cerealbox", view.eye, 100.0, 8);
        let p = fp * scale;
        assert!(
            (rate - p).abs() < four_sigma(p, TRIALS),
            "scale {scale}: rate {rate}, expected {p}"
        );
    }
}

#[test]
fn estimated_pose_error_grows_with_distance() {
    let w = office();
    let det = Detector::new(knowledge(), DetectorConfig::default()).unwrap();
    let cereal = top(&w, "cerealbox1");
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let near = aimed(&w, [5.4, 4.1, 1.2], cereal);
    let far = aimed(&w, [6.0, 1.5, 1.2], cereal);
    let (_, e_near) = rate_near(&det, &w, &near, "cerealbox", cereal, 2.0, 9);
    let (_, e_far) = rate_near(&det, &w, &far, "cerealbox", cereal, 2.0, 10);
    let (m_near, m_far) = (mean(&e_near), mean(&e_far));
    assert!(m_near < m_far, "near {m_near}, far {m_far}");
    assert!(
        m_near < 0.15,
        "a 1 m detection is placed within centimetres: {m_near}"
    );
    assert!(m_near > 0.0);
}

fn robot(w: &World, failures: FailureRates, seed: u64) -> SimAgentRobot<'_> {
    let cfg = SimRobotConfig {
        failures,
        ..Default::default()
    };
    SimAgentRobot::new(w, knowledge(), cfg, seed).unwrap()
}

fn views(r: &mut SimAgentRobot<'_>) -> Vec<avs_robot::ViewReport> {
    let classes = vec!["cerealbox".to_string(), "table".to_string()];
    let mut out = Vec::new();
    for i in 0..40 {
        let pose = Pose2D::new(5.5 + 0.02 * (i % 5) as f64, 3.5, 1.5);
        let cone = ViewCone::new(pose, 0.1 * (i % 7) as f64 - 0.3, -0.3, 1.0 + (i % 3) as f64);
        out.push(r.process_view_cone(&cone, &classes).unwrap());
    }
    out
}

#[test]
fn same_seed_gives_identical_detections_and_another_seed_differs() {
    let w = office();
    let a = views(&mut robot(&w, FailureRates::default(), 42));
    let b = views(&mut robot(&w, FailureRates::default(), 42));
    let c = views(&mut robot(&w, FailureRates::default(), 43));
    assert_eq!(a, b);
    assert_ne!(a, c);
    assert!(a.iter().any(|v| !v.detections.is_empty()));
}

#[test]
fn view_failures_occur_at_the_configured_rate() {
    let w = office();
    let rate = 0.1;
    let mut r = robot(
        &w,
        FailureRates {
            motion: 0.0,
            view: rate,
        },
        4,
    );
    let here = r.pose();
    let cone = ViewCone::new(here, 0.0, 0.0, 1.0);
    let classes = vec!["cerealbox".to_string()];
    let failed = (0..TRIALS)
        .filter(|_| match r.process_view_cone(&cone, &classes) {
            Ok(_) => false,
            Err(e) => {
                assert_eq!(e.reason, FailureReason::ExecutionFailed);
                true
            }
        })
        .count();
    let f = failed as f64 / TRIALS as f64;
    assert!(
        (f - rate).abs() < four_sigma(rate, TRIALS),
        "failure rate {f}"
    );
}

#[test]
fn motion_failures_occur_at_the_configured_rate_and_stop_part_of_the_way() {
    let w = office();
    let rate = 0.3;
    let n = 300;
    let mut r = robot(
        &w,
        FailureRates {
            motion: rate,
            view: 0.0,
        },
        5,
    );
    let goals = [Pose2D::new(1.0, 1.2, 0.0), Pose2D::new(3.0, 1.2, 0.0)];
    let mut failed = 0;
    for i in 0..n {
        let before = r.odometry();
        match r.move_to(goals[i % 2]) {
            Ok(m) => assert!(m.pose.distance(&goals[i % 2]) < 0.2, "{m:?}"),
            Err(e) => {
                assert_eq!(e.reason, FailureReason::ExecutionFailed, "{e}");
                assert!(r.odometry() - before <= 2.1);
                failed += 1;
            }
        }
    }
    let f = failed as f64 / n as f64;
    assert!((f - rate).abs() < four_sigma(rate, n), "failure rate {f}");
}

#[test]
fn without_failures_motion_reaches_the_goal_and_the_map_grows() {
    let w = office();
    let mut r = robot(&w, FailureRates::default(), 1);
    let first = r.map_update();
    assert!(first.newly_known > 0);
    assert_eq!(r.map_update().newly_known, 0, "nothing new without moving");
    let m = r.move_to(Pose2D::new(7.0, 4.0, 0.5)).unwrap();
    assert!(m.pose.distance(&Pose2D::new(7.0, 4.0, 0.0)) < 0.1, "{m:?}");
    assert_eq!(m.pose.yaw, 0.5);
    assert!(m.travelled > 4.0 && (r.odometry() - m.travelled).abs() < 1e-9);
    assert!(r.map_update().newly_known > 0, "the kitchen became known");
}

#[test]
fn goals_behind_a_closed_door_are_unreachable_and_bad_requests_are_rejected() {
    let w = office_with_door("door_kitchen", false);
    let mut r = robot(&w, FailureRates::default(), 1);
    let e = r.move_to(Pose2D::new(6.0, 5.0, 0.0)).unwrap_err();
    assert_eq!(e.reason, FailureReason::Unreachable);
    let start = r.pose();
    let e = r.move_to(Pose2D::new(f64::NAN, 1.0, 0.0)).unwrap_err();
    assert_eq!(e.reason, FailureReason::InvalidRequest);
    let cone = ViewCone::new(start, 0.0, 0.0, 1.0);
    let e = r
        .process_view_cone(&cone, &["unicorn".to_string()])
        .unwrap_err();
    assert_eq!(e.reason, FailureReason::InvalidRequest);
    assert!(e.message.contains("unicorn"), "{}", e.message);
    let e = r
        .process_view_cone(&ViewCone { zoom: 0.5, ..cone }, &["table".to_string()])
        .unwrap_err();
    assert_eq!(e.reason, FailureReason::InvalidRequest);
    assert_eq!(r.pose(), start, "rejected requests do not move the robot");
}
