//! CREATEVIEWCONES feeding the view-cone session: the path SEARCHFOROBJECT takes.

use std::f64::consts::{FRAC_PI_2, PI};

use avs_pomdp::{
    cone_priors, euclidean_travel, DecisionRewards, OfflineOptions, OnlineOptions, Outcome,
    SessionOptions, ViewConeAction, ViewConeProblem, ViewConeSession,
};
use avs_view::{create_view_cones, CameraModel, DetectionRange};

#[test]
fn cones_planned_for_a_room_lead_a_perfect_sensor_to_the_target_cell() {
    // A 4 m × 3 m table top sampled every 0.5 m; the robot may stand on three spots.
    let mut cells = Vec::new();
    for i in 0..8 {
        for j in 0..6 {
            cells.push([0.25 + 0.5 * i as f64, 0.25 + 0.5 * j as f64, 0.8]);
        }
    }
    let poses = [[-0.5, 1.5, 0.0], [2.0, -0.5, FRAC_PI_2], [4.5, 1.5, PI]];
    let camera = CameraModel {
        hfov: 1.0,
        vfov: 0.8,
        pan_limits: [-1.5, 1.5],
        tilt_limits: [-0.8, 0.0],
        height: 1.3,
    };
    let plan = create_view_cones(
        &cells,
        &poses,
        &camera,
        DetectionRange { min: 0.3, max: 3.5 },
        |_, _| true,
    )
    .unwrap();
    assert_eq!(plan.covered_share, 1.0);
    let cone_cells: Vec<Vec<usize>> = plan.views.iter().map(|v| v.newly_covered.clone()).collect();
    let prior = cone_priors(&cone_cells, &vec![1.0; cells.len()], 0.7).unwrap();
    let positions: Vec<[f64; 2]> = plan.views.iter().map(|v| [v.pose[0], v.pose[1]]).collect();
    let (from_start, travel) = euclidean_travel([0.0, -1.0], &positions, 0.2);
    let problem = ViewConeProblem {
        cone_prior: prior,
        travel_from_start: from_start,
        travel,
        process_cost: 0.2,
        false_negative: 0.0,
        false_positive: 0.0,
        rewards: DecisionRewards::default(),
        discount: 0.95,
    };
    let opts = SessionOptions {
        offline: OfflineOptions {
            max_trials: 5,
            ..Default::default()
        },
        online: OnlineOptions {
            depth: 1,
            time_limit: None,
            node_limit: None,
        },
        max_steps: 2 * plan.views.len(),
        sweep_bounds: false,
        policy: Default::default(),
    };
    let session = ViewConeSession::new(&problem, opts).unwrap();
    // Put the target in a few cells; the session must declare the cone that first covered that cell.
    for target_cell in [0, 17, 47] {
        let cone = cone_cells
            .iter()
            .position(|c| c.contains(&target_cell))
            .unwrap();
        let mut s = session.clone();
        while s.outcome().is_none() {
            if let ViewConeAction::Process { cone: c } = s.next_action().unwrap() {
                s.observe(c == cone).unwrap();
            }
        }
        assert_eq!(
            s.outcome(),
            Some(Outcome::Found { cone }),
            "target cell {target_cell}"
        );
    }
}

/// The room of the coverage tests (`avs-view`).
fn cover_room_points() -> Vec<[f64; 3]> {
    let mut pts = Vec::new();
    for i in 0..12 {
        for j in 0..8 {
            pts.push([0.25 + 0.5 * i as f64, 0.25 + 0.5 * j as f64, 0.75]);
        }
    }
    pts
}

/// The camera of the coverage tests (`avs-view`).
fn cover_camera() -> CameraModel {
    CameraModel {
        hfov: 60f64.to_radians(),
        vfov: 45f64.to_radians(),
        pan_limits: [-PI, PI],
        tilt_limits: [-0.6, 0.2],
        height: 1.2,
    }
}

#[test]
fn cone_priors_split_the_location_mass_without_double_counting() {
    let pts = cover_room_points();
    let poses = [[1.0, 2.0, 0.0], [3.0, 2.0, 0.0], [5.0, 2.0, 0.0]];
    let range = DetectionRange { min: 0.5, max: 4.0 };
    let plan = create_view_cones(&pts, &poses, &cover_camera(), range, |_, _| true).unwrap();
    let weights = vec![1.0; pts.len()];
    let priors = cone_priors(&plan.cone_cells(), &weights, 0.6).unwrap();
    assert!((priors.iter().sum::<f64>() - 0.6).abs() < 1e-9);
    for (p, v) in priors.iter().zip(&plan.views) {
        assert!((p - 0.6 * v.newly_covered.len() as f64 / pts.len() as f64).abs() < 1e-12);
    }
}

#[test]
fn cone_priors_name_a_cell_out_of_range() {
    assert!(cone_priors(&[vec![99]], &[1.0], 0.5)
        .unwrap_err()
        .to_string()
        .contains("cone_cells"));
}
