use super::*;
use crate::sim_robot::{SimAgentRobot, SimRobotConfig};
use crate::World;
use avs_robot::{FailureReason, Pose2D, Robot};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::Path;

fn root() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn knowledge() -> avs_format::knowledge::Knowledge {
    avs_format::load_yaml(&root().join("knowledge/office.yaml")).unwrap()
}

/// A book `d` metres straight ahead of a level camera at the origin, facing it.
fn book_at(d: f64, camera: &Camera) -> SceneObject {
    SceneObject {
        class: "book".into(),
        centre: Point3 {
            x: d,
            y: 0.0,
            z: camera.height,
        },
        width: 0.16,
        height: 0.23,
        yaw: std::f64::consts::PI,
        lookalike: false,
    }
}

fn level() -> ViewCone {
    ViewCone::new(Pose2D::new(0.0, 0.0, 0.0), 0.0, 0.0, 1.0)
}

fn scene(objects: Vec<SceneObject>, clutter: f64, depth: f64) -> ImageScene {
    ImageScene {
        objects,
        background: Background { clutter, depth },
    }
}

fn votes(scene: &ImageScene, seed: u64, classes: &[&str]) -> Vec<avs_robot::VoteMatrix> {
    let classes: Vec<String> = classes.iter().map(|c| c.to_string()).collect();
    attention(
        &ImageModel::default(),
        scene,
        &Camera::default(),
        &level(),
        &ImageGeometry::default(),
        &classes,
        &mut ChaCha8Rng::seed_from_u64(seed),
    )
}

#[test]
fn the_same_seed_gives_the_same_vote_matrices_and_another_seed_others() {
    let s = scene(vec![book_at(1.5, &Camera::default())], 1.0, 2.5);
    let a = votes(&s, 7, &["book", "cup"]);
    assert_eq!(a, votes(&s, 7, &["book", "cup"]));
    assert_ne!(a, votes(&s, 8, &["book", "cup"]));
    for m in &a {
        assert!(m.problem().is_none());
        assert!(m.values.iter().all(|v| (0.0..=1.0).contains(v)));
    }
    // A class's matrix does not depend on the other classes asked for.
    assert_eq!(a[0], votes(&s, 7, &["book"])[0]);
}

#[test]
fn an_object_in_the_image_raises_the_votes_on_the_cells_it_covers() {
    let camera = Camera::default();
    let image = ImageGeometry::default();
    let book = book_at(1.0, &camera);
    let face = face_image(&book, &camera, &level(), &image).unwrap();
    let with = votes(&scene(vec![book], 1.0, 1.5), 3, &["book"]);
    let without = votes(&scene(vec![], 1.0, 1.5), 3, &["book"]);
    let (mut covered, mut raised) = (0, 0);
    for row in 0..image.rows() {
        for col in 0..image.cols() {
            let phi = cell_cover(face.bbox, col, row, &image);
            let (a, b) = (
                with[0].get(col, row).unwrap(),
                without[0].get(col, row).unwrap(),
            );
            if phi >= 0.99 {
                covered += 1;
                raised += usize::from(a > b + 0.2);
                assert!(a > 0.5, "cell ({col}, {row}) of the book votes {a}");
            } else if phi == 0.0 {
                // Cells the book does not touch keep their background (the same draws).
                assert!((a - b).abs() < 1e-12, "cell ({col}, {row}): {a} vs {b}");
            }
        }
    }
    assert!(covered >= 4 && raised == covered, "{raised} of {covered}");
    // Another class sees the book only as much as the two classes resemble each other.
    let other = votes(
        &scene(vec![book_at(1.0, &camera)], 1.0, 1.5),
        3,
        &["book", "cup"],
    );
    let (c, r) = (image.cols() / 2, image.rows() / 2);
    assert!(other[1].get(c, r).unwrap() < other[0].get(c, r).unwrap());
}

#[test]
fn an_object_behind_a_wall_is_not_in_the_image() {
    let text = [
        "kind: environment",
        "name: walled",
        "map:",
        "  resolution: 0.5",
        "  ascii: |",
        "    ###########",
        "    #....#....#",
        "    #....#....#",
        "    #....#....#",
        "    ###########",
        "rooms:",
        "  - { name: left, category: office, seed: { x: 1.0, y: 1.25 } }",
        "  - { name: right, category: office, seed: { x: 4.0, y: 1.25 } }",
        "objects:",
        "  - { id: near, class: cerealbox, role: target, room: left, pose: { x: 2.25, y: 1.25, z: 0.9 }, size: [0.19, 0.07, 0.28] }",
        "  - { id: far, class: mug, role: distractor, room: right, pose: { x: 4.25, y: 1.25, z: 0.9 }, size: [0.09, 0.09, 0.1] }",
        "robot: { start: { x: 0.75, y: 1.25 }, radius: 0.2 }",
    ]
    .join("\n");
    let env: avs_format::environment::Environment =
        avs_format::load_yaml_str("walled.yaml", &text).unwrap();
    let world = World::new(env, Path::new(".")).unwrap();
    let camera = Camera::from(&world.env.camera);
    let cone = ViewCone::new(Pose2D::new(0.75, 1.25, 0.0), 0.0, 0.0, 1.0);
    let s = world_scene(
        &world,
        &world.walls,
        &knowledge(),
        &camera,
        &cone,
        &crate::sim_robot::ImageConfig::default(),
    );
    let classes: Vec<&str> = s.objects.iter().map(|o| o.class.as_str()).collect();
    assert_eq!(classes, ["cerealbox"]);
    // The face is the knowledge's, centred half its height above the pose.
    assert_eq!((s.objects[0].width, s.objects[0].height), (0.19, 0.28));
    assert!((s.objects[0].centre.z - 1.04).abs() < 1e-12);
    // The wall is 1.75 m ahead (its near side, within a cell).
    assert!(
        (s.background.depth - 1.75).abs() <= 0.25 + 1e-9,
        "{}",
        s.background.depth
    );
    // Looking away from the wall, the mug is behind the camera: still not in the image.
    let back = ViewCone::new(Pose2D::new(4.75, 1.25, 0.0), 0.0, 0.0, 1.0);
    let s = world_scene(
        &world,
        &world.walls,
        &knowledge(),
        &camera,
        &back,
        &crate::sim_robot::ImageConfig::default(),
    );
    assert!(s.objects.is_empty());
}

/// A room with a shelf 1.75 m ahead of the robot, a cereal box in it 5 cm behind the
/// shelf's middle (`shelf: false` leaves the shelf out).
fn shelf_world(shelf: bool) -> World {
    let mut text = vec![
        "kind: environment",
        "name: shelved",
        "map:",
        "  resolution: 0.5",
        "  ascii: |",
        "    ########",
        "    #......#",
        "    #......#",
        "    #......#",
        "    ########",
        "rooms:",
        "  - { name: kitchen, category: kitchen, seed: { x: 1.0, y: 1.25 } }",
        "objects:",
    ];
    if shelf {
        text.push("  - { id: box, class: cerealbox, role: target, room: kitchen, in: shelf1, pose: { x: 2.55, y: 1.25, z: 0.9, yaw_deg: 180 }, size: [0.19, 0.07, 0.28] }");
        text.push("  - { id: shelf1, class: shelf, role: landmark, room: kitchen, pose: { x: 2.5, y: 1.25, z: 0.0, yaw_deg: 180 }, size: [0.9, 0.4, 1.8] }");
    } else {
        text.push("  - { id: box, class: cerealbox, role: target, room: kitchen, pose: { x: 2.55, y: 1.25, z: 0.9, yaw_deg: 180 }, size: [0.19, 0.07, 0.28] }");
    }
    text.push("robot: { start: { x: 0.75, y: 1.25 }, radius: 0.2 }");
    let env: avs_format::environment::Environment =
        avs_format::load_yaml_str("shelved.yaml", &text.join("\n")).unwrap();
    World::new(env, Path::new(".")).unwrap()
}

#[test]
fn a_shelf_shows_what_lies_in_it_in_front_of_its_back_panel() {
    let cone = ViewCone::new(Pose2D::new(0.75, 1.25, 0.0), 0.0, -0.1, 1.0);
    let config = crate::sim_robot::ImageConfig::default();
    let strongest = |world: &World| -> (ImageScene, f64) {
        let camera = Camera::from(&world.env.camera);
        let s = world_scene(world, &world.walls, &knowledge(), &camera, &cone, &config);
        let classes = ["cerealbox".to_string()];
        let best = (0..20)
            .map(|seed| {
                let m = attention(
                    &config.model,
                    &s,
                    &camera,
                    &cone,
                    &config.geometry,
                    &classes,
                    &mut ChaCha8Rng::seed_from_u64(seed),
                );
                m[0].values.iter().copied().fold(0.0, f64::max)
            })
            .sum::<f64>()
            / 20.0;
        (s, best)
    };
    let (with, in_shelf) = strongest(&shelf_world(true));
    let (_, alone) = strongest(&shelf_world(false));
    // The shelf's face stands at its back, behind the box (its middle is nearer than the box).
    let x = |class: &str| {
        with.objects
            .iter()
            .find(|o| o.class == class)
            .unwrap()
            .centre
            .x
    };
    assert!((x("shelf") - 2.7).abs() < 1e-9, "{}", x("shelf"));
    assert!(x("shelf") > x("cerealbox"));
    // So the attention sees the box in the shelf as it does without it.
    assert!(
        in_shelf > 0.9 * alone,
        "in the shelf {in_shelf}, alone {alone}"
    );
}

fn recognise(s: &ImageScene, seed: u64) -> Recognition {
    let book = ClassAppearance {
        name: "book".into(),
        width: 0.16,
        height: 0.23,
    };
    recognition(
        &ImageModel::default(),
        s,
        &Camera::default(),
        &level(),
        &ImageGeometry::default(),
        &book,
        &mut ChaCha8Rng::seed_from_u64(seed),
    )
}

#[test]
fn a_close_object_at_the_right_scale_is_recognised_and_an_empty_scene_almost_never() {
    let camera = Camera::default();
    let image = ImageGeometry::default();
    let close = scene(vec![book_at(0.6, &camera)], 1.0, 1.1);
    let empty = scene(vec![], 1.0, 1.1);
    let needed = 0.05 * f64::from(ImageModel::default().model_features);
    let recognised = |s: &ImageScene, seed| recognise(s, seed).matches.len() as f64 >= needed;
    assert_eq!((0..50).filter(|&k| recognised(&close, k)).count(), 50);
    assert!((0..200).filter(|&k| recognised(&empty, k)).count() <= 2);
    // The true matches lie on the book, at its scale relative to the training image.
    let face = face_image(&close.objects[0], &camera, &level(), &image).unwrap();
    let m = recognise(&close, 1);
    let on_book: Vec<_> = m
        .matches
        .iter()
        .filter(|f| {
            f.u >= face.bbox[0] && f.u <= face.bbox[2] && f.v >= face.bbox[1] && f.v <= face.bbox[3]
        })
        .collect();
    assert!(on_book.len() >= 20, "{}", on_book.len());
    let mut ratios: Vec<f64> = on_book.iter().map(|f| f.scale_ratio).collect();
    ratios.sort_by(f64::total_cmp);
    let (w_tr, _) = ClassAppearance {
        name: "book".into(),
        width: 0.16,
        height: 0.23,
    }
    .train_px(&image);
    assert!((w_tr - 240.0 * 0.16 / 0.23).abs() < 1e-9);
    let median = ratios[ratios.len() / 2];
    let truth = face.apparent_px.0 / w_tr;
    assert!((median / truth - 1.0).abs() < 0.05, "{median} vs {truth}");
    // A far object keeps too little detail.
    let far = scene(vec![book_at(4.0, &camera)], 1.0, 4.5);
    assert!((0..50).filter(|&k| recognised(&far, k)).count() <= 5);
}

#[test]
fn class_similarity_is_one_for_the_class_symmetric_and_fixed_for_others() {
    let m = ImageModel::default();
    assert_eq!(m.class_similarity("cup", "cup", false), 1.0);
    assert_eq!(
        m.class_similarity("cup", "mug", true),
        m.lookalike_similarity
    );
    let (a, b) = (
        m.class_similarity("cup", "book", false),
        m.class_similarity("book", "cup", false),
    );
    assert_eq!(a, b);
    assert!((m.other_class_similarity[0]..=m.other_class_similarity[1]).contains(&a));
}

fn office() -> (World, avs_format::knowledge::Knowledge) {
    let world = World::load(&root().join("domains/environments/office.yaml")).unwrap();
    (world, knowledge())
}

#[test]
fn a_robots_images_count_their_processing_time_and_change_nothing_else_it_draws() {
    let (world, knowledge) = office();
    let view = ViewCone::new(
        Pose2D::new(5.5, 3.5, std::f64::consts::FRAC_PI_2),
        0.0,
        -0.2,
        1.0,
    );
    let classes = vec!["cerealbox".to_string(), "mug".to_string()];
    let mut a =
        SimAgentRobot::new(&world, knowledge.clone(), SimRobotConfig::default(), 4).unwrap();
    let seen = a.attention(&view, &classes).unwrap();
    let model = ImageModel::default();
    assert_eq!(seen.votes.len(), 2);
    assert_eq!(seen.seconds, model.attention_seconds(2));
    assert!(seen.seconds > 0.0 && seen.travelled > 0.0);
    let matched = a.recognise(&view, "cerealbox").unwrap();
    assert_eq!(matched.seconds, model.recognition_time());
    assert_eq!(a.images(), 2);
    assert!((a.image_seconds() - seen.seconds - matched.seconds).abs() < 1e-12);
    // The cereal box on the table, about 1.6 m ahead, is in the image (its narrow side): its
    // class votes above the default threshold on its cells, and its features match.
    let camera = Camera::from(&world.env.camera);
    let image = ImageGeometry::default();
    let s = world_scene(
        &world,
        &world.walls,
        &knowledge,
        &camera,
        &view,
        &crate::sim_robot::ImageConfig::default(),
    );
    let cereal = s.objects.iter().find(|o| o.class == "cerealbox").unwrap();
    assert_eq!(cereal.width, 0.07);
    let face = face_image(cereal, &camera, &view, &image).unwrap();
    let on_box = (0..image.rows())
        .flat_map(|r| (0..image.cols()).map(move |c| (c, r)))
        .filter(|&(c, r)| cell_cover(face.bbox, c, r, &image) > 0.0)
        .map(|(c, r)| seen.votes[0].get(c, r).unwrap())
        .fold(0.0, f64::max);
    assert!(on_box > 0.35, "{on_box}");
    let needed = 0.05 * f64::from(matched.model_features);
    assert!(
        matched.matches.len() as f64 >= needed,
        "{}",
        matched.matches.len()
    );
    // Images draw from their own stream: the views afterwards are those of a robot that took
    // none.
    let mut b =
        SimAgentRobot::new(&world, knowledge.clone(), SimRobotConfig::default(), 4).unwrap();
    b.move_to(view.pose).unwrap();
    let (va, vb) = (
        a.process_view_cone(&view, &classes).unwrap(),
        b.process_view_cone(&view, &classes).unwrap(),
    );
    assert_eq!(va.detections, vb.detections);
    // Unknown classes are refused.
    let e = a.attention(&view, &["unicorn".to_string()]).unwrap_err();
    assert_eq!(e.reason, FailureReason::InvalidRequest);
    let e = a.recognise(&view, "unicorn").unwrap_err();
    assert_eq!(e.reason, FailureReason::InvalidRequest);
    assert_eq!(a.images(), 2);
}

#[test]
fn a_long_thin_object_shows_the_side_the_recogniser_matches_best_until_seen_end_on() {
    let camera = Camera::default();
    let image = ImageGeometry::default();
    let model = ImageModel::default();
    // A marker (13 × 2 × 2 cm) at the camera's height, its front facing +x.
    let marker = BoxObject {
        class: "whiteboardmarker".into(),
        base: Point3 {
            x: 0.0,
            y: 0.0,
            z: camera.height - 0.01,
        },
        yaw: 0.0,
        size: [0.13, 0.02, 0.02],
        lookalike: false,
    };
    // A zoomed camera 1 m away, `off` degrees round from the marker's front, looking at it.
    let seen = |off: f64| {
        let a = off.to_radians();
        let (x, y) = (a.cos(), a.sin());
        let cone = ViewCone::new(Pose2D::new(x, y, 0.0), (-y).atan2(-x), 0.0, 4.0);
        let face = marker.seen_face(&model, &camera, &cone, &image).unwrap();
        let share = face_image(&face, &camera, &cone, &image)
            .map(|f| model.match_share(f.size_px(), f.view_angle))
            .unwrap();
        (face.width, share)
    };
    // Straight on and 60° round (nearer the end in angle than the front is, but the long side
    // still matches): the long side. The side nearest in angle would be the 2 cm end.
    for off in [0.0, 60.0, -60.0, 120.0, 180.0] {
        let (w, share) = seen(off);
        assert_eq!(w, 0.13, "{off}°");
        assert!(share > 0.0, "{off}°");
    }
    // Nearly end-on the long side is beyond the recogniser's angle: the end (its best) is shown.
    for off in [85.0, -85.0, 95.0] {
        assert_eq!(seen(off).0, 0.02, "{off}°");
    }
    // The choice is the better of the two: the long side 60° round matches more than the end.
    let end = BoxObject {
        size: [0.02, 0.13, 0.02],
        yaw: std::f64::consts::FRAC_PI_2,
        ..marker.clone()
    };
    let cone = ViewCone::new(
        Pose2D::new(0.5, 0.866, 0.0),
        (-0.866f64).atan2(-0.5),
        0.0,
        4.0,
    );
    assert_eq!(
        end.seen_face(&model, &camera, &cone, &image).unwrap().width,
        0.13
    );
}
