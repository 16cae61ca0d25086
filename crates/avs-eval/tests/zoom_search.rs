//! The search agent's looks through the zoom pipeline (Sjöö et al. `004` §3): on the simulated
//! robot, whose camera gives vote matrices and feature matches, every zoomed image is a trace
//! line and the images are counted; a robot without the pipeline's images gets the one-shot
//! detector instead, and finds the same object.

use avs_agent::{
    Agent, AgentConfig, Camera, Detection, Event, Goal, Point3, Pose2D, ScriptedRobot,
};
use avs_format::knowledge::Knowledge;
use avs_map::grid::OccupancyGrid;
use avs_plan::domain::Domain;
use avs_sim::score::SUCCESS_RADIUS;
use avs_sim::sim_robot::{SimAgentRobot, SimRobotConfig};
use avs_sim::World;
use std::path::{Path, PathBuf};

fn shipped(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

fn inputs() -> (Knowledge, Domain) {
    (
        avs_format::load_yaml(&shipped("knowledge/office.yaml")).unwrap(),
        Domain::load(&shipped("domains/object_search.yaml")).unwrap(),
    )
}

fn zoomed() -> AgentConfig {
    AgentConfig {
        zoom_pipeline: true,
        ..AgentConfig::default()
    }
}

#[test]
fn zoomed_looks_find_the_office_objects_and_every_zoomed_image_is_traced_and_counted() {
    let world = World::load(&shipped("domains/environments/office.yaml")).unwrap();
    let (k, d) = inputs();
    for (goal, seed) in [("cerealbox", 1), ("stapler", 2), ("mug", 3)] {
        let mut robot =
            SimAgentRobot::new(&world, k.clone(), SimRobotConfig::default(), seed).unwrap();
        let mut agent = Agent::new(d.clone(), k.clone(), zoomed()).unwrap();
        let r = agent.search(&mut robot, Goal::find(goal)).unwrap();
        let text = avs_agent::trace::render_text(&r.trace);
        let found = r
            .found
            .as_ref()
            .unwrap_or_else(|| panic!("{goal}: not found\n{text}"));
        let near = world
            .objects_of_class(goal)
            .any(|o| (o.pose.x - found.pose.x).hypot(o.pose.y - found.pose.y) <= SUCCESS_RADIUS);
        assert!(near, "{goal}: wrong report {found:?}");
        let zooms: Vec<&Event> = r
            .trace
            .iter()
            .filter(|e| matches!(e, Event::Zoom { .. }))
            .collect();
        assert_eq!(zooms.len(), r.metrics.zoom_images, "{goal}");
        assert!(r.metrics.zoom_images > 0, "{goal}: no zoomed image");
        assert!(r.metrics.images > r.metrics.zoom_images);
        assert!(r.metrics.image_s > 0.0);
        assert!(text.contains(&format!("ZOOM {goal} x")), "{goal}");
        // Zoomed images are for the goal, within the camera's zoom.
        let max_zoom = robot_max_zoom(&world);
        assert!(zooms.iter().all(|e| matches!(e,
            Event::Zoom { classes, zoom, .. }
                if classes.iter().any(|c| c == goal) && *zoom >= 1.0 && *zoom <= max_zoom + 1e-9)));
    }
}

fn robot_max_zoom(world: &World) -> f64 {
    Camera::from(&world.env.camera).max_zoom
}

#[test]
fn a_robot_without_the_pipelines_images_gets_the_one_shot_detector_and_the_same_find() {
    // The agent crate's own example: a room the laser knows whole, a cereal box in a corner.
    let mut map = String::from("##########\n");
    for _ in 0..6 {
        map.push_str("#........#\n");
    }
    map.push_str("##########");
    let (k, d) = inputs();
    let run = |config: AgentConfig| {
        let grid = OccupancyGrid::from_ascii(&map, 0.5, [0.0, 0.0]).unwrap();
        let mut robot = ScriptedRobot::new(grid, Pose2D::new(1.25, 1.25, 0.0), Camera::default());
        robot.place(Detection {
            class: "cerealbox".into(),
            pose: Point3 {
                x: 3.6,
                y: 2.6,
                z: 0.14,
            },
            confidence: 0.8,
        });
        let mut agent = Agent::new(d.clone(), k.clone(), config).unwrap();
        agent.search(&mut robot, Goal::find("cerealbox")).unwrap()
    };
    let plain = run(AgentConfig::default());
    let zoom = run(zoomed());
    assert_eq!(zoom.metrics.zoom_images, 0);
    assert!(!zoom.trace.iter().any(|e| matches!(e, Event::Zoom { .. })));
    assert_eq!(plain.found, zoom.found);
    assert_eq!(plain.metrics.images, zoom.metrics.images);
    assert!(zoom.found.is_some());
}

#[test]
fn the_measured_range_of_a_look_grows_with_the_objects_face_and_is_seeded() {
    let (k, _) = inputs();
    let config = avs_view::zoom::ZoomConfig::default();
    let measure =
        || avs_eval::zoom_sensing::measured_sensing(&k, &Camera::default(), &config).unwrap();
    let m = measure();
    assert_eq!(m, measure(), "the same seed, the same measurement");
    let far = |class: &str| {
        m.iter()
            .find(|s| s.class == class)
            .unwrap_or_else(|| panic!("{class} not measured: {m:?}"))
            .detection_range[1]
    };
    // Faces: cereal box 19 × 28 cm, stapler 15 × 7, mug 9 × 10, marker 13 × 2.
    assert!(far("cerealbox") > far("stapler"), "{m:?}");
    assert!(far("stapler") > far("whiteboardmarker"), "{m:?}");
    assert!(far("mug") > far("whiteboardmarker"), "{m:?}");
    for s in &m {
        assert!(s.detection_range[0] < s.detection_range[1]);
        assert!((0.0..1.0).contains(&s.false_negative) && (0.0..1.0).contains(&s.false_positive));
    }
}

#[test]
fn a_look_repeated_from_the_same_vantage_point_tends_to_repeat_the_first() {
    // The simulated camera sees an object's side and its distance, and both are the same for
    // a repeated look: whether the pipeline finds the object depends on them, so a look and
    // its repeat agree more often than two looks from anywhere in the range would.
    let (k, _) = inputs();
    let config = avs_view::zoom::ZoomConfig::default();
    let m = avs_eval::zoom_sensing::measured_sensing(&k, &Camera::default(), &config).unwrap();
    let rho = |class: &str| {
        m.iter()
            .find(|s| s.class == class)
            .unwrap_or_else(|| panic!("{class} not measured: {m:?}"))
            .repeat_correlation
    };
    // A marker (13 × 2 cm) shows its long side or its end depending on the side it is seen
    // from; a mug (9 × 9 cm) looks alike from every side.
    assert!(rho("whiteboardmarker") > 0.1, "{m:?}");
    assert!(rho("whiteboardmarker") > rho("mug") + 0.1, "{m:?}");
    for s in &m {
        eprintln!(
            "{}: repeat correlation {:.3}",
            s.class, s.repeat_correlation
        );
        assert!((0.0..=0.99).contains(&s.repeat_correlation), "{s:?}");
        // The shares behind the ranges are kept, per zoom level, with their looks.
        assert!(!s.found_by_zoom.is_empty() && s.found_by_zoom.iter().all(|f| f.looks > 0));
        // A miss from a vantage point makes the next look from there less likely to find it.
        if s.repeat_correlation > 0.0 {
            let share = s.found_share(1.0, s.detection_range[0]).unwrap();
            assert!(s.found_next(share, 0, 1) < share, "{s:?}");
            assert!(s.found_next(share, 1, 1) > share, "{s:?}");
        }
    }
}
