//! The simulated robot's detector scores (`Robot::detector_scores`) and its correlated detector
//! kind: scores separate objects from clutter, follow the image and occlusion, share each
//! feature's nuisance field between looks (fixed by the seed and the feature, not by the order
//! of queries), and drive the correlated detections of `DetectorKind::Correlated`.

use avs_format::knowledge::{Knowledge, ObjectClass};
use avs_robot::{FailureReason, Point3, Pose2D, Robot, ViewCone};
use avs_sim::detector::ScoreProfile;
use avs_sim::sim_robot::{DetectorKind, FailureRates, SimAgentRobot, SimRobotConfig};
use avs_sim::world_scores::{FeatureKey, WorldScores, MATCH_RADIUS};
use avs_sim::World;
use std::path::Path;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn knowledge() -> Knowledge {
    avs_format::load_yaml(&root().join("knowledge/office.yaml")).unwrap()
}

fn class(k: &Knowledge, name: &str) -> ObjectClass {
    k.class(name).unwrap().clone()
}

/// The cereal box in the west room (its profile: max range 4 m, best range 4/3 m).
const BOX: [f64; 3] = [5.0, 4.0, 0.14];
/// The mug look-alike in the west room.
const MUG: [f64; 2] = [5.0, 6.5];
/// A second cereal box, in the east room behind the wall.
const BOX_EAST: [f64; 2] = [10.0, 4.0];

/// Two rooms, 12 m x 8 m in all: the west room (x < 8) and the east room behind a 0.2 m wall
/// at x = 8, joined by a doorway at y in [1, 2] whose door is `door_open`. The west room holds
/// a cereal box at [`BOX`] and a mug look-alike at [`MUG`]; the east room a cereal box at
/// [`BOX_EAST`].
fn two_rooms(door_open: bool) -> World {
    let (w, h) = (120usize, 80usize);
    let mut rows = Vec::new();
    for r in (0..h).rev() {
        let row: String = (0..w)
            .map(|c| {
                let border = r < 2 || r >= h - 2 || c < 2 || c >= w - 2;
                let wall = (80..82).contains(&c) && !(10..20).contains(&r);
                if border || wall {
                    '#'
                } else {
                    '.'
                }
            })
            .collect();
        rows.push(format!("    {row}"));
    }
    let text = format!(
        "kind: environment\nname: two-rooms\nmap:\n  resolution: 0.1\n  ascii: |\n{}\n\
         rooms:\n\
         \x20 - {{ name: west, category: office, seed: {{ x: 2.0, y: 4.0 }} }}\n\
         \x20 - {{ name: east, category: office, seed: {{ x: 10.0, y: 6.0 }} }}\n\
         doors:\n\
         \x20 - {{ name: door1, pose: {{ x: 8.1, y: 1.5, yaw_deg: 0 }}, width: 1.0, open: {door_open}, rooms: [west, east] }}\n\
         objects:\n\
         \x20 - {{ id: cerealbox1, class: cerealbox, role: target, room: west, pose: {{ x: {}, y: {}, yaw_deg: 30 }}, size: [0.19, 0.07, 0.28] }}\n\
         \x20 - {{ id: mug1, class: mug, role: distractor, room: west, pose: {{ x: {}, y: {} }}, size: [0.09, 0.09, 0.1] }}\n\
         \x20 - {{ id: cerealbox2, class: cerealbox, role: target, room: east, pose: {{ x: {}, y: {} }}, size: [0.19, 0.07, 0.28] }}\n\
         robot: {{ start: {{ x: 1.0, y: 4.0 }}, radius: 0.2 }}\n",
        rows.join("\n"),
        BOX[0],
        BOX[1],
        MUG[0],
        MUG[1],
        BOX_EAST[0],
        BOX_EAST[1],
    );
    let env = avs_format::load_yaml_str("two-rooms.yaml", &text).unwrap();
    World::new(env, Path::new(".")).unwrap()
}

fn new_robot(world: &World, kind: DetectorKind, seed: u64) -> SimAgentRobot<'_> {
    let config = SimRobotConfig {
        detector_kind: kind,
        ..SimRobotConfig::default()
    };
    SimAgentRobot::new(world, knowledge(), config, seed).unwrap()
}

/// A zoom-`zoom` view from `at` with the target on the optical axis.
fn aimed(at: [f64; 2], target: [f64; 3], zoom: f64) -> ViewCone {
    let (dx, dy) = (target[0] - at[0], target[1] - at[1]);
    let tilt = (target[2] - 1.2).atan2(dx.hypot(dy));
    ViewCone::new(Pose2D::new(at[0], at[1], dy.atan2(dx)), 0.0, tilt, zoom)
}

fn p3(p: [f64; 3]) -> Point3 {
    Point3 {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

/// Spots 0.6 m high on a fan in front of a robot at (2, 4) facing +x: `ranges = [first,
/// step, count]` metres × `bearings = [first, step, count]` degrees, range fastest.
fn fan(ranges: [f64; 3], bearings: [f64; 3]) -> Vec<Point3> {
    let (nr, nb) = (ranges[2] as usize, bearings[2] as usize);
    (0..nr * nb)
        .map(|i| {
            let r = ranges[0] + ranges[1] * (i % nr) as f64;
            let b = (bearings[0] + bearings[1] * (i / nr) as f64).to_radians();
            Point3 {
                x: 2.0 + r * b.cos(),
                y: 4.0 + r * b.sin(),
                z: 0.6,
            }
        })
        .collect()
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

fn variance(x: &[f64]) -> f64 {
    let m = mean(x);
    x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (x.len() as f64 - 1.0)
}

fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let (ma, mb) = (mean(a), mean(b));
    let c: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = a.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f64 = b.iter().map(|y| (y - mb).powi(2)).sum();
    c / (va * vb).sqrt()
}

/// The cereal box's profile and its best range.
fn box_profile() -> ScoreProfile {
    ScoreProfile::for_class(class(&knowledge(), "cerealbox").detection_range)
}

#[test]
fn scores_at_a_true_object_average_clearly_above_scores_at_clutter() {
    let world = two_rooms(true);
    let r = box_profile().r_best;
    let at = [BOX[0] - r, BOX[1]];
    // Clutter at the same range, 20° off the axis: 0.46 m from the box, free of any object.
    let off = [
        at[0] + r * 20f64.to_radians().cos(),
        at[1] - r * 20f64.to_radians().sin(),
        BOX[2],
    ];
    assert!((off[0] - BOX[0]).hypot(off[1] - BOX[1]) > MATCH_RADIUS);
    let (mut object, mut clutter) = (Vec::new(), Vec::new());
    for seed in 0..150 {
        let mut robot = new_robot(&world, DetectorKind::Independent, seed);
        let report = robot
            .detector_scores(&aimed(at, BOX, 1.0), "cerealbox", &[p3(BOX), p3(off)])
            .unwrap();
        object.push(report.scores[0].expect("the box is in view"));
        clutter.push(report.scores[1].expect("the clutter spot is in view"));
    }
    let (mo, mc) = (mean(&object), mean(&clutter));
    eprintln!("mean score at the box {mo:.3}, at clutter {mc:.3}");
    // Profile means at the best range: 2.0 (object) and 0.8 (no-object).
    assert!((mo - 2.0).abs() < 0.2, "{mo}");
    assert!((mc - 0.8).abs() < 0.25, "{mc}");
    assert!(mo - mc > 0.8, "{mo} vs {mc}");
}

#[test]
fn scores_are_none_outside_the_image_behind_a_wall_or_closed_door_and_beyond_range() {
    for door_open in [false, true] {
        let world = two_rooms(door_open);
        let mut robot = new_robot(&world, DetectorKind::Independent, 3);
        // At (6, 1.5) looking east along the doorway, slightly down.
        let cone = ViewCone::new(Pose2D::new(6.0, 1.5, 0.0), 0.0, -0.2, 1.0);
        let at = [
            Point3 {
                x: 7.0,
                y: 1.5,
                z: 1.0,
            }, // ahead, in the image
            Point3 {
                x: 5.0,
                y: 1.5,
                z: 1.0,
            }, // behind the camera
            Point3 {
                x: 7.0,
                y: 4.5,
                z: 1.0,
            }, // 72° to the side
            Point3 {
                x: 7.0,
                y: 1.5,
                z: 4.0,
            }, // far above the image
            Point3 {
                x: 9.0,
                y: 1.5,
                z: 1.0,
            }, // through the doorway, 3 m: the door decides
            Point3 {
                x: 9.0,
                y: 2.6,
                z: 1.0,
            }, // behind the wall beside the doorway, 3.2 m
        ];
        let s = robot
            .detector_scores(&cone, "cerealbox", &at)
            .unwrap()
            .scores;
        assert!(s[0].is_some(), "door open {door_open}: {s:?}");
        assert!(s[1..4].iter().all(Option::is_none), "{s:?}");
        assert_eq!(s[4].is_some(), door_open, "through the doorway: {s:?}");
        assert!(s[5].is_none(), "behind the wall: {s:?}");
    }
    // From the west end, a spot 6 m away is beyond the cereal box's 4 m: no score at zoom 1,
    // a score at zoom 2 (the zoomed image sees as from 3 m).
    let world = two_rooms(true);
    let mut robot = new_robot(&world, DetectorKind::Independent, 3);
    let far = [7.0, 6.0, 0.5];
    let s1 = robot
        .detector_scores(&aimed([1.0, 6.0], far, 1.0), "cerealbox", &[p3(far)])
        .unwrap();
    let s2 = robot
        .detector_scores(&aimed([1.0, 6.0], far, 2.0), "cerealbox", &[p3(far)])
        .unwrap();
    assert_eq!((s1.scores[0], s2.scores[0].is_some()), (None, true));
}

#[test]
fn two_looks_from_one_pose_differ_only_by_white_noise() {
    let world = two_rooms(true);
    let cone = ViewCone::new(Pose2D::new(2.0, 4.0, 0.0), 0.0, -0.35, 1.0);
    // 150 spots on a fan in front of the robot (1.2 to 3.4 m, ±18°), most of them clutter.
    let at = fan([1.2, 0.16, 15.0], [-18.0, 4.0, 10.0]);
    let (mut diff, mut first) = (Vec::new(), Vec::new());
    for seed in 11..15 {
        let mut robot = new_robot(&world, DetectorKind::Independent, seed);
        let mut look = || {
            robot
                .detector_scores(&cone, "cerealbox", &at)
                .unwrap()
                .scores
        };
        let (a, b) = (look(), look());
        for (x, y) in a.iter().zip(&b) {
            let (x, y) = (x.expect("in view"), y.expect("in view"));
            diff.push(x - y);
            first.push(x);
        }
    }
    let sn = box_profile().no_object.noise_std;
    let want = 2.0 * sn * sn;
    let got = variance(&diff);
    eprintln!("variance of the difference {got:.4} vs 2σ_n² {want:.4}");
    assert!((got / want - 1.0).abs() < 0.2, "{got} vs {want}");
    assert!(mean(&diff).abs() < 0.05);
    // Yet the scores themselves vary far more than the noise: the fields differ by spot.
    assert!(variance(&first) > 3.0 * sn * sn, "{}", variance(&first));
}

#[test]
fn looks_from_far_apart_vantages_are_less_correlated_than_looks_from_one_pose() {
    let world = two_rooms(true);
    // A clutter spot, seen from 2 m west (aspect π) twice and from 2 m south (aspect −π/2).
    let c = [5.5, 3.0, 0.5];
    let (west, south) = ([3.5, 3.0], [5.5, 1.0]);
    let (mut a1, mut a2, mut b) = (Vec::new(), Vec::new(), Vec::new());
    for seed in 0..300 {
        let mut robot = new_robot(&world, DetectorKind::Independent, 1000 + seed);
        let at = [p3(c)];
        let mut look = |from: [f64; 2]| {
            robot
                .detector_scores(&aimed(from, c, 1.0), "cerealbox", &at)
                .unwrap()
                .scores[0]
                .expect("in view")
        };
        a1.push(look(west));
        a2.push(look(west));
        b.push(look(south));
    }
    let (same, apart) = (correlation(&a1, &a2), correlation(&a1, &b));
    let p = box_profile().no_object;
    let want = p.field_std.powi(2) / (p.field_std.powi(2) + p.noise_std.powi(2));
    eprintln!("correlation from one pose {same:.3} (model {want:.3}), 90° apart {apart:.3}");
    assert!((same - want).abs() < 0.08, "{same} vs {want}");
    assert!(apart < 0.3 && same - apart > 0.5, "{same} vs {apart}");
}

#[test]
fn same_seed_gives_the_same_scores_and_another_seed_other_scores() {
    let world = two_rooms(true);
    let run = |seed| {
        let mut robot = new_robot(&world, DetectorKind::Independent, seed);
        let at = [
            p3(BOX),
            Point3 {
                x: 4.0,
                y: 3.0,
                z: 0.3,
            },
            Point3 {
                x: 5.0,
                y: 6.5,
                z: 0.1,
            },
        ];
        let mut out = Vec::new();
        for from in [[3.0, 4.0], [3.0, 5.0], [2.5, 3.0]] {
            let cone = aimed(from, [4.5, 4.5, 0.3], 1.0);
            out.push(robot.detector_scores(&cone, "cerealbox", &at).unwrap());
            out.push(robot.detector_scores(&cone, "mug", &at).unwrap());
        }
        out
    };
    let (a, b, c) = (run(5), run(5), run(6));
    assert_eq!(a, b);
    assert!(a.iter().flat_map(|r| r.scores.iter()).any(Option::is_some));
    assert_ne!(a, c);
}

#[test]
fn the_order_of_queries_does_not_change_a_features_field() {
    let world = two_rooms(true);
    let k = knowledge();
    let (cereal, mug) = (class(&k, "cerealbox"), class(&k, "mug"));
    let spots: Vec<[f64; 2]> = vec![
        [BOX[0], BOX[1]],
        MUG,
        [3.0, 2.0],
        [3.2, 2.1],
        [6.5, 5.5],
        BOX_EAST,
    ];
    let robot_at = [2.0, 4.0];
    // Forward, one class only.
    let mut forward = WorldScores::new(9);
    let f: Vec<f64> = spots
        .iter()
        .map(|&p| {
            forward
                .latent(
                    &cereal,
                    &WorldScores::locate(&world, &cereal, p),
                    robot_at,
                    1.0,
                )
                .unwrap()
        })
        .collect();
    // Backward, after other classes and other spots.
    let mut backward = WorldScores::new(9);
    for p in [[1.0, 1.0], [7.0, 7.0], MUG] {
        backward
            .latent(&mug, &WorldScores::locate(&world, &mug, p), robot_at, 1.0)
            .unwrap();
        backward
            .latent(
                &cereal,
                &WorldScores::locate(&world, &cereal, p),
                [4.0, 1.0],
                2.0,
            )
            .unwrap();
    }
    let mut g: Vec<f64> = spots
        .iter()
        .rev()
        .map(|&p| {
            backward
                .latent(
                    &cereal,
                    &WorldScores::locate(&world, &cereal, p),
                    robot_at,
                    1.0,
                )
                .unwrap()
        })
        .collect();
    g.reverse();
    assert_eq!(f, g);
    // The two clutter spots in one 0.5 m cell share a field; a robot with another seed has
    // other fields.
    let a = WorldScores::locate(&world, &cereal, spots[2]);
    let b = WorldScores::locate(&world, &cereal, spots[3]);
    assert_eq!(a.key, b.key);
    assert!(matches!(a.key, FeatureKey::Phantom(_)));
    let mut other = WorldScores::new(10);
    assert_ne!(other.latent(&cereal, &a, robot_at, 1.0).unwrap(), f[2]);

    // The robot's scores are those fields plus white noise, whatever it was asked before.
    let mut robot = new_robot(&world, DetectorKind::Independent, 9);
    let cone = ViewCone::new(Pose2D::new(2.0, 4.0, 0.0), 0.0, -0.35, 1.0);
    let fan = fan([1.3, 0.2, 12.0], [-18.0, 3.6, 10.0]);
    let mut reversed = fan.clone();
    reversed.reverse();
    robot.detector_scores(&cone, "mug", &fan).unwrap();
    let report = robot
        .detector_scores(&cone, "cerealbox", &reversed)
        .unwrap();
    let (scores, robot_at) = (report.scores, [report.pose.x, report.pose.y]);
    let mut fresh = WorldScores::new(9);
    let residual: Vec<f64> = reversed
        .iter()
        .zip(&scores)
        .map(|(p, s)| {
            let l = WorldScores::locate(&world, &cereal, [p.x, p.y]);
            s.expect("in view") - fresh.latent(&cereal, &l, robot_at, 1.0).unwrap()
        })
        .collect();
    let sn = box_profile().no_object.noise_std;
    let sd = variance(&residual).sqrt();
    eprintln!("score − fresh latent: sd {sd:.3} vs σ_n {sn}");
    assert!((sd / sn - 1.0).abs() < 0.25, "{sd} vs {sn}");
}

#[test]
fn unknown_class_and_non_finite_location_are_rejected_with_the_field_named() {
    let world = two_rooms(true);
    let mut robot = new_robot(&world, DetectorKind::Independent, 1);
    let cone = ViewCone::new(Pose2D::new(3.0, 4.0, 0.0), 0.0, -0.3, 1.0);
    let ok = Point3 {
        x: 4.0,
        y: 4.0,
        z: 0.3,
    };
    let e = robot.detector_scores(&cone, "unicorn", &[ok]).unwrap_err();
    assert_eq!(e.reason, FailureReason::InvalidRequest);
    assert!(e.message.contains("unicorn"), "{}", e.message);
    let bad = Point3 {
        x: 4.0,
        y: f64::NAN,
        z: 0.3,
    };
    let e = robot
        .detector_scores(&cone, "cerealbox", &[ok, bad])
        .unwrap_err();
    assert_eq!(e.reason, FailureReason::InvalidRequest);
    assert!(e.message.contains("at[1]"), "{}", e.message);
    let e = robot
        .detector_scores(&ViewCone { zoom: 9.0, ..cone }, "cerealbox", &[ok])
        .unwrap_err();
    assert!(e.message.contains("zoom"), "{}", e.message);
    // Nothing happened: no motion, no image.
    assert_eq!((robot.odometry(), robot.score_images()), (0.0, 0));
}

#[test]
fn images_and_detector_seconds_are_counted_and_a_failed_view_takes_none() {
    let world = two_rooms(true);
    let mut robot = new_robot(&world, DetectorKind::Independent, 1);
    let cone = ViewCone::new(Pose2D::new(3.0, 4.0, 0.0), 0.0, -0.3, 1.0);
    for _ in 0..3 {
        let r = robot
            .detector_scores(&cone, "cerealbox", &[p3(BOX)])
            .unwrap();
        assert_eq!(r.detector_seconds, box_profile().processing_seconds);
        assert!(r.pose.distance(&cone.pose) < 0.1);
    }
    assert_eq!(robot.score_images(), 3);
    assert!(
        (robot.score_detector_seconds() - 3.0 * box_profile().processing_seconds).abs() < 1e-12
    );
    let config = SimRobotConfig {
        failures: FailureRates {
            motion: 0.0,
            view: 1.0,
        },
        ..SimRobotConfig::default()
    };
    let mut broken = SimAgentRobot::new(&world, knowledge(), config, 1).unwrap();
    let e = broken
        .detector_scores(&cone, "cerealbox", &[p3(BOX)])
        .unwrap_err();
    assert_eq!(e.reason, FailureReason::ExecutionFailed);
    assert!(broken.odometry() > 1.0, "it moved to the view pose first");
    assert_eq!(broken.score_images(), 0);
}

/// Whether a view from `at` (aimed at the box, zoom 1) reports a cereal box.
fn sees_box(robot: &mut SimAgentRobot<'_>, at: [f64; 2]) -> Option<Point3> {
    let report = robot
        .process_view_cone(&aimed(at, BOX, 1.0), &["cerealbox".to_string()])
        .unwrap();
    report.detections.first().map(|d| d.pose)
}

#[test]
fn correlated_detector_fires_much_more_often_at_the_best_range_than_at_the_max_range() {
    let world = two_rooms(true);
    let p = box_profile();
    let (best, max) = (
        [BOX[0] - p.r_best, BOX[1]],
        [BOX[0] - 0.97 * p.max_range, BOX[1]],
    );
    let (mut at_best, mut at_max) = (0, 0);
    let n = 200;
    for seed in 0..n {
        let mut robot = new_robot(&world, DetectorKind::Correlated, seed);
        at_best += usize::from(sees_box(&mut robot, best).is_some());
        let mut robot = new_robot(&world, DetectorKind::Correlated, seed + 10_000);
        at_max += usize::from(sees_box(&mut robot, max).is_some());
    }
    let (fb, fm) = (at_best as f64 / n as f64, at_max as f64 / n as f64);
    eprintln!("fires at the best range {fb:.3}, at the max range {fm:.3}");
    // Model: P(N(2.0, 0.56²) > 1) ≈ 0.96 and P(N(0.63, 0.56²) > 1) ≈ 0.26.
    assert!(fb > 0.85, "{fb}");
    assert!(fm < 0.45, "{fm}");
    assert!(fb - fm > 0.45, "{fb} vs {fm}");
}

#[test]
fn a_correlated_detection_and_a_later_score_at_its_spot_come_from_one_field() {
    let world = two_rooms(true);
    let p = box_profile();
    // At 3.2 m the box's mean (1.07) is near the threshold: whether it fires is mostly the
    // field's doing.
    let at = [BOX[0] - 0.8 * p.max_range, BOX[1]];
    let (mut fired, mut missed, mut unseen) = (Vec::new(), Vec::new(), 0);
    for seed in 0..250 {
        let mut robot = new_robot(&world, DetectorKind::Correlated, seed);
        let cone = aimed(at, BOX, 1.0);
        match sees_box(&mut robot, at) {
            Some(d) => {
                let s = robot
                    .detector_scores(&cone, "cerealbox", &[d])
                    .unwrap()
                    .scores[0];
                // A report pushed beyond the 4 m range by its range noise is no longer the
                // box's spot (a clutter spot out of range): rare.
                match s {
                    Some(z) => fired.push(z),
                    None => unseen += 1,
                }
            }
            None => {
                let s = robot
                    .detector_scores(&cone, "cerealbox", &[p3(BOX)])
                    .unwrap()
                    .scores[0];
                missed.push(s.expect("the box is in view"));
            }
        }
    }
    let (mf, mm) = (mean(&fired), mean(&missed));
    let above = fired.iter().filter(|&&z| z > p.fire_threshold).count() as f64 / fired.len() as f64;
    eprintln!(
        "{} fired (later score {mf:.3}, {above:.2} above the threshold), {} missed ({mm:.3})",
        fired.len(),
        missed.len()
    );
    assert!(
        fired.len() >= 20 && missed.len() >= 20 && unseen < 10,
        "{unseen} unseen"
    );
    // Independent draws would give both groups the same mean.
    assert!(mf - mm > 0.5, "{mf} vs {mm}");
    assert!(above > 0.7, "{above}");
}

#[test]
fn correlated_look_alikes_fire_consistently_from_one_spot() {
    // The mug fires as a cereal box in some worlds and not in others, and from one spot it
    // mostly does the same thing twice (its field, not a coin, decides).
    let world = two_rooms(true);
    let mug = [MUG[0], MUG[1], 0.05];
    let at = [MUG[0] - box_profile().r_best, MUG[1]];
    let (mut agree, mut fired, n) = (0, 0, 200);
    for seed in 0..n {
        let mut robot = new_robot(&world, DetectorKind::Correlated, seed);
        let cone = aimed(at, mug, 1.0);
        let look = |r: &mut SimAgentRobot<'_>| {
            let d = r
                .process_view_cone(&cone, &["cerealbox".to_string()])
                .unwrap();
            d.detections
                .iter()
                .any(|d| (d.pose.x - MUG[0]).hypot(d.pose.y - MUG[1]) < 0.5)
        };
        let (a, b) = (look(&mut robot), look(&mut robot));
        agree += usize::from(a == b);
        fired += usize::from(a);
    }
    let (fa, ff) = (agree as f64 / n as f64, fired as f64 / n as f64);
    eprintln!("look-alike fires {ff:.3}, two looks agree {fa:.3}");
    assert!(ff > 0.1 && ff < 0.9, "{ff}");
    // Independent looks would agree with probability ff² + (1 − ff)² only.
    assert!(fa > ff * ff + (1.0 - ff).powi(2) + 0.15, "{fa} vs {ff}");
}

#[test]
fn landmark_classes_detect_alike_in_both_modes_and_independent_is_the_default() {
    assert_eq!(
        SimRobotConfig::default().detector_kind,
        DetectorKind::Independent
    );
    assert_eq!(
        serde_yaml::to_string(&DetectorKind::Correlated)
            .unwrap()
            .trim(),
        "correlated"
    );
    let kind: DetectorKind = serde_yaml::from_str("independent").unwrap();
    assert_eq!(kind, DetectorKind::Independent);
    let world = World::load(&root().join("domains/environments/office.yaml")).unwrap();
    let run = |kind, seed| {
        let mut robot = new_robot(&world, kind, seed);
        let mut out = Vec::new();
        for (x, y, yaw) in [
            (5.5, 3.5, 1.57),
            (6.0, 4.0, 1.2),
            (2.0, 5.0, 1.57),
            (10.0, 3.5, 1.57),
        ] {
            let cone = ViewCone::new(Pose2D::new(x, y, yaw), 0.0, -0.3, 1.0);
            let classes = [
                "table".to_string(),
                "desk".to_string(),
                "counter".to_string(),
            ];
            out.push(robot.process_view_cone(&cone, &classes).unwrap());
        }
        out
    };
    let mut seen = 0;
    for seed in 0..5 {
        let independent = run(DetectorKind::Independent, seed);
        seen += independent
            .iter()
            .map(|r| r.detections.len())
            .sum::<usize>();
        assert_eq!(
            independent,
            run(DetectorKind::Correlated, seed),
            "seed {seed}"
        );
    }
    assert!(seen > 5, "{seen} detections");
}

#[test]
fn correlated_views_repeat_with_the_seed() {
    let world = World::load(&root().join("domains/environments/office.yaml")).unwrap();
    let run = |seed| {
        let mut robot = new_robot(&world, DetectorKind::Correlated, seed);
        let classes: Vec<String> = ["cerealbox", "mug", "table", "stapler"]
            .map(String::from)
            .to_vec();
        let mut out = Vec::new();
        for (x, y, yaw) in [
            (5.5, 3.5, 1.57),
            (6.5, 5.0, 1.57),
            (2.0, 5.0, 1.57),
            (2.0, 5.0, 2.2),
        ] {
            let cone = ViewCone::new(Pose2D::new(x, y, yaw), 0.0, -0.3, 1.0);
            out.push(format!("{:?}", robot.process_view_cone(&cone, &classes)));
            let at = [
                Point3 {
                    x: 5.4,
                    y: 5.1,
                    z: 0.9,
                },
                Point3 {
                    x: 1.6,
                    y: 7.4,
                    z: 0.8,
                },
            ];
            out.push(format!("{:?}", robot.detector_scores(&cone, "mug", &at)));
        }
        out
    };
    let a = run(2);
    assert_eq!(a, run(2));
    let differ = (3..8).filter(|&s| run(s) != a).count();
    assert!(differ >= 4, "{differ}");
}

#[test]
fn a_class_detected_nowhere_has_no_scores_and_no_correlated_detector() {
    let world = two_rooms(true);
    let mut k = knowledge();
    let mug = k
        .object_classes
        .iter()
        .position(|c| c.name == "mug")
        .unwrap();
    k.object_classes[mug].detection_range = [0.0, 0.0];
    let config = SimRobotConfig {
        detector_kind: DetectorKind::Correlated,
        ..SimRobotConfig::default()
    };
    let e = SimAgentRobot::new(&world, k.clone(), config, 1)
        .unwrap_err()
        .to_string();
    assert!(e.contains("detector_kind") && e.contains("mug"), "{e}");
    let mut robot = SimAgentRobot::new(&world, k, SimRobotConfig::default(), 1).unwrap();
    let cone = ViewCone::new(Pose2D::new(3.0, 4.0, 0.0), 0.0, -0.3, 1.0);
    let e = robot.detector_scores(&cone, "mug", &[p3(BOX)]).unwrap_err();
    assert_eq!(e.reason, FailureReason::InvalidRequest);
    assert!(e.message.contains("detection_range"), "{}", e.message);
    assert_eq!(robot.odometry(), 0.0);
}
