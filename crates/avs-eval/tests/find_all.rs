//! Sjöö et al.'s §4.4 experiment (Fig. 11) re-enacted on the simulator: one room, four objects
//! of four classes on its furniture, searched for all at once — the room's view plan for the
//! four classes (`avs_eval::views`), executed nearest standpoint first, every view through the
//! three-step zoom search, a class dropped once recognised (`avs_view::plan::search_room`) —
//! and every object found and localised within 0.3 m.

use avs_eval::views::{plan_room, ViewsRequest};
use avs_format::knowledge::{Knowledge, ObjectClass};
use avs_sim::sim_robot::{SimAgentRobot, SimRobotConfig};
use avs_sim::World;
use avs_view::plan::search_room;
use avs_view::zoom::{ObjectModel, ZoomConfig};
use std::path::Path;

/// A 7 m × 5 m room (35 m², as the paper's 31.6–40.9 m² rooms) with a table in its middle, a
/// desk and a shelf against its walls, and four objects on them.
const ROOM: &str = r#"kind: environment
name: fig11
map:
  resolution: 0.25
  origin: [0.0, 0.0]
  ascii: |
ASCII
rooms:
  - { name: lab, category: office, seed: { x: 1.0, y: 1.0 } }
objects:
  - { id: table1, class: table, role: landmark, room: lab, pose: { x: 3.6, y: 2.6 }, size: [1.2, 0.8, 0.75] }
  - { id: desk1, class: desk, role: landmark, room: lab, pose: { x: 1.2, y: 4.8 }, size: [1.6, 0.8, 0.75] }
  - { id: counter1, class: counter, role: landmark, room: lab, pose: { x: 6.8, y: 2.6, yaw_deg: 90 }, size: [2.0, 0.6, 0.9] }
  - { id: cerealbox1, class: cerealbox, role: target, room: lab, on: table1, pose: { x: 3.4, y: 2.5, z: 0.75 }, size: [0.19, 0.07, 0.28] }
  - { id: stapler1, class: stapler, role: target, room: lab, on: desk1, pose: { x: 1.5, y: 4.8, z: 0.75 }, size: [0.15, 0.05, 0.07] }
  - { id: mug1, class: mug, role: target, room: lab, on: counter1, pose: { x: 6.8, y: 2.0, z: 0.9 }, size: [0.09, 0.09, 0.10] }
  - { id: book1, class: book, role: target, room: lab, on: table1, pose: { x: 4.0, y: 2.8, z: 0.75 }, size: [0.24, 0.03, 0.17] }
robot:
  start: { x: 0.8, y: 0.8, yaw_deg: 0 }
  radius: 0.25
  speed: 0.5
laser: { range: 8.0, fov_deg: 270, beams: 541 }
camera: { hfov_deg: 45, vfov_deg: 35, pan_deg: [-180, 180], tilt_deg: [-45, 30], max_zoom: 4, height: 1.2 }
"#;

/// The shipped office knowledge with a book (the paper's B) among its classes.
fn knowledge() -> Knowledge {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut k: Knowledge = avs_format::load_yaml(&root.join("knowledge/office.yaml")).unwrap();
    let mut book: ObjectClass = k.class("stapler").unwrap().clone();
    book.name = "book".into();
    book.size = [0.24, 0.03, 0.17];
    k.object_classes.push(book);
    k
}

/// The room of [`ROOM`] with its map.
fn world() -> World {
    let text = ROOM.replace(
        "ASCII",
        &ASCII_MAP
            .lines()
            .map(|l| format!("      {l}"))
            .collect::<Vec<_>>()
            .join("\n"),
    );
    World::read_checked_text("fig11.yaml", &text, Path::new("."), None)
        .map(|env| World::new(env, Path::new(".")).unwrap())
        .unwrap()
}

/// The four classes sought.
const CLASSES: [&str; 4] = ["cerealbox", "stapler", "mug", "book"];

/// How far `reported` lies from the centre of `world`'s object of `class`: in 3-D, or on
/// the floor plan (`planar`).
fn error_m(world: &World, class: &str, reported: avs_robot::Point3, planar: bool) -> f64 {
    let truth = world.objects_of_class(class).next().unwrap();
    let dz = if planar {
        0.0
    } else {
        reported.z - (truth.pose.z + truth.size[2] / 2.0)
    };
    (reported.x - truth.pose.x)
        .hypot(reported.y - truth.pose.y)
        .hypot(dz)
}

#[test]
fn the_agent_finds_all_four_by_one_find_all_with_the_zoom_pipeline_each_within_0_3_m() {
    let (world, k) = (world(), knowledge());
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let domain = avs_plan::domain::Domain::load(&root.join("domains/object_search.yaml")).unwrap();
    let mut config = avs_agent::AgentConfig {
        zoom_pipeline: true,
        ..Default::default()
    };
    config.measured_sensing = avs_eval::zoom_sensing::measured_sensing(
        &k,
        &avs_robot::Camera::from(&world.env.camera),
        &config.zoom,
    )
    .unwrap();
    let mut errors: Vec<(u64, &str, f64)> = Vec::new();
    let mut shared = 0;
    for seed in 1..=3 {
        let mut robot =
            SimAgentRobot::new(&world, k.clone(), SimRobotConfig::default(), seed).unwrap();
        let mut agent = avs_agent::Agent::new(domain.clone(), k.clone(), config.clone()).unwrap();
        let reports = agent
            .search_all(&mut robot, avs_agent::Goal::find_all(CLASSES))
            .unwrap();
        assert_eq!(reports.len(), CLASSES.len());
        for (class, r) in CLASSES.iter().zip(&reports) {
            let err = r
                .found
                .as_ref()
                .map_or(f64::INFINITY, |f| error_m(&world, class, f.pose, true));
            // A class found with no plan of its own was found by verifying what an earlier
            // goal's looks saw of it.
            shared += usize::from(r.found.is_some() && r.metrics.plans == 0);
            eprintln!(
                "seed {seed}: {class}: {err:.2} m off, {:.1} m, {} plans, {} images",
                r.metrics.path_length, r.metrics.plans, r.metrics.images
            );
            errors.push((seed, class, err));
        }
    }
    assert!(errors.iter().all(|e| e.2 <= 0.3), "{errors:?}");
    // The searches share their images: some class is found from an earlier goal's looks.
    assert!(
        shared > 0,
        "no class was found from shared looks: {errors:?}"
    );
}

#[test]
fn four_objects_in_one_room_are_all_found_by_one_search_and_localised_within_0_3_m() {
    let (world, k) = (world(), knowledge());
    let classes = CLASSES;
    // Views are planned where a look of the pipeline finds each class at least half the time,
    // as measured on the simulated camera.
    let camera = avs_robot::Camera::from(&world.env.camera);
    let measured =
        avs_eval::zoom_sensing::measured_sensing(&k, &camera, &ZoomConfig::default()).unwrap();
    let request = ViewsRequest {
        room: "lab".into(),
        classes: classes.iter().map(|c| c.to_string()).collect(),
        k: K,
        spacing: 0.5,
        optimal: None,
        measured,
    };
    let (problem, plan, report) = plan_room(&world, &k, &request).unwrap();
    assert!(
        report.coverage.values().all(|c| *c > 0.9),
        "{:?}",
        report.coverage
    );
    eprintln!(
        "{} cells, {} standpoints, {} used, {} views",
        report.cells.len(),
        report.standpoints.len(),
        report.standpoints_used.len(),
        report.searches
    );
    let models: Vec<ObjectModel> = classes
        .iter()
        .map(|c| ObjectModel::from_class(k.class(c).unwrap()))
        .collect();
    // (seed, class, placement error in metres; infinite when not recognised at all)
    let mut errors: Vec<(u64, &str, f64)> = Vec::new();
    for seed in 1..=5 {
        let mut robot =
            SimAgentRobot::new(&world, k.clone(), SimRobotConfig::default(), seed).unwrap();
        let out =
            search_room(&mut robot, &problem, &plan, &models, &ZoomConfig::default()).unwrap();
        eprintln!(
            "seed {seed}: {} views, {} images, {:.1} m driven",
            out.views, out.images, out.travelled
        );
        // Found classes leave the plan: no more views than it had.
        assert!(out.views <= plan.searches());
        for class in classes {
            let err = out
                .found
                .iter()
                .find(|r| r.class == class)
                .map_or(f64::INFINITY, |r| error_m(&world, class, r.position, false));
            eprintln!("  {class}: {err:.2} m off");
            errors.push((seed, class, err));
        }
    }
    // Every class is recognised on every seed; nearly every recognition is the object, placed
    // within 0.3 m (a recognition elsewhere is the three-step search's own false positive: the
    // room search has no verifier), and typically within a decimetre.
    assert!(errors.iter().all(|e| e.2.is_finite()), "{errors:?}");
    let within = errors.iter().filter(|e| e.2 <= 0.3).count();
    assert!(
        within * 10 >= errors.len() * 9,
        "{within} of {}: {errors:?}",
        errors.len()
    );
    let mut sorted: Vec<f64> = errors.iter().map(|e| e.2).collect();
    sorted.sort_by(f64::total_cmp);
    assert!(sorted[sorted.len() / 2] <= 0.1, "{errors:?}");
}

/// Each (class, cell) pair in two views: one look of the pipeline misses now and then (the
/// measured miss rates are 0.1–0.2).
const K: usize = 2;

const ASCII_MAP: &str = "##############################\n#............................#\n#............................#\n#............................#\n#............................#\n#............................#\n#............................#\n#............................#\n#............................#\n#............................#\n#............................#\n#............................#\n#............................#\n#............................#\n#............................#\n#............................#\n#............................#\n#............................#\n#............................#\n#............................#\n#............................#\n##############################";
