//! Ground truth of the simulated world: room labels, closed doors, camera queries.

use avs_sim::{CameraView, SimRobot, World};
use std::path::Path;

fn office() -> World {
    World::load(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/environments/office.yaml"),
    )
    .unwrap()
}

fn index_of(world: &World, id: &str) -> usize {
    world.env.objects.iter().position(|o| o.id == id).unwrap()
}

#[test]
fn room_labels_follow_the_room_seeds_and_stop_at_doors() {
    let w = office();
    let name = |x, y| w.room_at(x, y).map(|i| w.env.rooms[i].name.as_str());
    assert_eq!(name(6.0, 1.2), Some("corridor"));
    assert_eq!(name(1.0, 4.0), Some("office1"));
    assert_eq!(name(6.0, 4.0), Some("kitchen"));
    assert_eq!(name(11.0, 4.0), Some("office2"));
    assert_eq!(name(4.1, 5.0), None, "wall between office1 and the kitchen");
    // The rooms cover the floor: 12 m × 8 m less walls and furniture is ~80 m².
    let total: f64 = w.room_areas().iter().sum();
    assert!((70.0..90.0).contains(&total), "total room area {total}");
}

#[test]
fn a_closed_door_blocks_the_robot_and_the_camera() {
    let mut w = office();
    let kitchen_door = w
        .env
        .doors
        .iter()
        .position(|d| d.name == "door_kitchen")
        .unwrap();
    w.env.doors[kitchen_door].open = false;
    let w = World::new(w.env.clone(), Path::new(".")).unwrap();
    let mut r = SimRobot::new(&w, 1);
    // Into the kitchen only through another room — there is none, so the kitchen is unreachable.
    assert!(!r.move_to([6.0, 5.0]).reached);
    // office1 is still reachable.
    assert!(r.move_to([2.0, 5.0]).reached);
    // From the corridor in front of the kitchen door, looking north, the cereal box is occluded.
    let view = CameraView {
        eye: [6.0, 1.5, 1.2],
        yaw: 90f64.to_radians(),
        tilt: 0.0,
        hfov: 1.0,
        vfov: 1.0,
    };
    let cereal = index_of(&w, "cerealbox1");
    let seen = w.objects_in_view(&view);
    let c = seen
        .iter()
        .find(|v| v.index == cereal)
        .expect("in the field of view");
    assert!(!c.visible, "the closed door occludes it");
}

#[test]
fn camera_sees_objects_in_its_field_of_view_with_line_of_sight_only() {
    let w = office();
    let cereal = index_of(&w, "cerealbox1");
    let stapler = index_of(&w, "stapler1");
    // Standing in the kitchen, looking at the table.
    let at_table = CameraView {
        eye: [5.5, 3.5, 1.2],
        yaw: 90f64.to_radians(),
        tilt: -0.3,
        hfov: 0.8,
        vfov: 0.6,
    };
    let seen = w.objects_in_view(&at_table);
    let c = seen
        .iter()
        .find(|v| v.index == cereal)
        .expect("cereal box in view");
    assert!(c.visible);
    assert!(
        (c.distance - ((0.1f64).powi(2) + 1.6f64.powi(2) + 0.3f64.powi(2)).sqrt()).abs() < 0.05,
        "{}",
        c.distance
    );
    // The stapler is in office1, behind the wall and outside this narrow view.
    assert!(seen.iter().all(|v| v.index != stapler));
    // Turned around, the cereal box is out of view.
    let away = CameraView {
        yaw: -90f64.to_radians(),
        ..at_table
    };
    assert!(w.objects_in_view(&away).iter().all(|v| v.index != cereal));
    // Looking west through the wall into office1: the shelf is in the field of view but occluded.
    let west = CameraView {
        eye: [5.0, 5.0, 1.2],
        yaw: std::f64::consts::PI,
        tilt: 0.0,
        hfov: 0.5,
        vfov: 1.0,
    };
    let shelf = index_of(&w, "shelf1");
    let s = w
        .objects_in_view(&west)
        .into_iter()
        .find(|v| v.index == shelf)
        .expect("shelf in the cone");
    assert!(!s.visible);
}

/// Issue 18 reproducer: a laser of range 1e6 m (or a field of view of 1e9°) made every scan cast
/// fov × range / resolution rays (a minute and more per scan). Such a world is now refused when
/// it is built (the checks of `avs validate`, one gate for every command), and within what
/// validates (up to 1 km) rays are clipped to the map: the robot starts, scans and moves, and
/// sees exactly what a 360° laser reaching across the map sees.
#[test]
fn an_absurd_laser_is_refused_and_a_long_one_clipped_to_the_map() {
    let w = office();
    let mut env = w.env.clone();
    env.laser.range = 1e6;
    env.laser.fov_deg = 1e9;
    let refused = World::new(env.clone(), Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(
        refused.contains("laser.range") && refused.contains("laser.fov_deg"),
        "{refused}"
    );
    env.laser.range = 1000.0;
    env.laser.fov_deg = 360.0;
    let absurd = World::new(env.clone(), Path::new(".")).unwrap();
    env.laser.range = avs_map::raycast::max_ray_length(&w.truth);
    env.laser.fov_deg = 360.0;
    let reaching = World::new(env, Path::new(".")).unwrap();
    let mut a = SimRobot::new(&absurd, 1);
    let mut b = SimRobot::new(&reaching, 1);
    assert_eq!(a.known, b.known);
    assert!(a.move_to([6.0, 1.2]).reached && b.move_to([6.0, 1.2]).reached);
    assert_eq!(a.scan(), b.scan());
    assert_eq!(a.known, b.known);
}
