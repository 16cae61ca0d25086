//! CREATEVIEWCONES: coverage under field of view, distance limits and line of sight.

use avs_view::{
    create_view_cones, create_view_cones_at_levels, create_view_cones_costed,
    create_view_cones_zoomed, CameraModel, CoverOptions, DetectionRange,
};
use std::f64::consts::PI;

fn camera() -> CameraModel {
    CameraModel {
        hfov: 60f64.to_radians(),
        vfov: 45f64.to_radians(),
        pan_limits: [-PI, PI],
        tilt_limits: [-0.6, 0.2],
        height: 1.2,
    }
}

/// A 6 m × 4 m room sampled every 0.5 m at table height 0.75 m.
fn room_points() -> Vec<[f64; 3]> {
    let mut pts = Vec::new();
    for i in 0..12 {
        for j in 0..8 {
            pts.push([0.25 + 0.5 * i as f64, 0.25 + 0.5 * j as f64, 0.75]);
        }
    }
    pts
}

/// Independent check of §2.1.2–2.1.3 for one view and one point.
fn sees(view: &avs_view::PlannedView, cam: &CameraModel, r: DetectionRange, p: [f64; 3]) -> bool {
    let c = [view.pose[0], view.pose[1], cam.height];
    let (dx, dy, dz) = (p[0] - c[0], p[1] - c[1], p[2] - c[2]);
    let horiz = dx.hypot(dy);
    let d = horiz.hypot(dz);
    let yaw = view.pose[2] + view.pan;
    let mut dyaw = dy.atan2(dx) - yaw;
    while dyaw > PI {
        dyaw -= 2.0 * PI;
    }
    while dyaw < -PI {
        dyaw += 2.0 * PI;
    }
    d >= r.min
        && d <= r.max
        && dyaw.abs() <= cam.hfov / 2.0 + 1e-9
        && (dz.atan2(horiz) - view.tilt).abs() <= cam.vfov / 2.0 + 1e-9
}

/// [`sees`] at the view's zoom: fields of view divided by it, distance interval multiplied by it.
fn sees_zoomed(
    view: &avs_view::PlannedView,
    cam: &CameraModel,
    r: DetectionRange,
    p: [f64; 3],
) -> bool {
    let at_zoom = CameraModel {
        hfov: cam.hfov / view.zoom,
        vfov: cam.vfov / view.zoom,
        ..*cam
    };
    let r = DetectionRange {
        min: r.min * view.zoom,
        max: r.max * view.zoom,
    };
    sees(view, &at_zoom, r, p)
}

#[test]
fn greedy_cover_covers_the_whole_room_and_every_claimed_point_is_visible() {
    let pts = room_points();
    let poses = [[1.0, 2.0, 0.0], [3.0, 2.0, 0.0], [5.0, 2.0, 0.0]];
    let range = DetectionRange { min: 0.5, max: 4.0 };
    let plan = create_view_cones(&pts, &poses, &camera(), range, |_, _| true).unwrap();
    assert_eq!(plan.covered_share, 1.0);
    assert!(plan.uncovered.is_empty());
    let mut seen = vec![false; pts.len()];
    for v in &plan.views {
        for &k in &v.covered {
            assert!(
                sees(v, &camera(), range, pts[k]),
                "point {k} is not visible from {v:?}"
            );
        }
        for &k in &v.newly_covered {
            assert!(!seen[k], "point {k} newly covered twice");
            seen[k] = true;
        }
    }
    // Greedy order: each view adds no more new points than the one before it.
    for w in plan.views.windows(2) {
        assert!(w[0].newly_covered.len() >= w[1].newly_covered.len());
    }
}

#[test]
fn points_outside_the_detection_range_of_every_pose_stay_uncovered() {
    let pts = room_points();
    let poses = [[0.5, 0.5, 0.0]];
    let range = DetectionRange { min: 1.0, max: 3.0 };
    let plan = create_view_cones(&pts, &poses, &camera(), range, |_, _| true).unwrap();
    assert!(plan.covered_share > 0.0 && plan.covered_share < 1.0);
    // The pan range is a full turn and the tilts span every elevation here, so a point is uncovered
    // exactly when its distance from the camera is outside [1, 3] m.
    for (k, p) in pts.iter().enumerate() {
        let d =
            ((p[0] - 0.5f64).powi(2) + (p[1] - 0.5f64).powi(2) + (p[2] - 1.2f64).powi(2)).sqrt();
        assert_eq!(
            plan.uncovered.contains(&k),
            !(1.0..=3.0).contains(&d),
            "point {k} at {d} m"
        );
    }
    let expected = (plan
        .views
        .iter()
        .map(|v| v.newly_covered.len())
        .sum::<usize>()) as f64
        / pts.len() as f64;
    assert!((plan.covered_share - expected).abs() < 1e-12);
}

#[test]
fn a_wall_blocking_line_of_sight_hides_the_far_half() {
    let pts = room_points();
    let poses = [[1.0, 2.0, 0.0]];
    let range = DetectionRange {
        min: 0.2,
        max: 10.0,
    };
    // A wall at x = 3 blocks every ray that crosses it.
    let los = |a: [f64; 3], b: [f64; 3]| (a[0] < 3.0) == (b[0] < 3.0);
    let plan = create_view_cones(&pts, &poses, &camera(), range, los).unwrap();
    for v in &plan.views {
        assert!(v.covered.iter().all(|&k| pts[k][0] < 3.0));
    }
    let behind: Vec<usize> = (0..pts.len()).filter(|&k| pts[k][0] > 3.0).collect();
    assert_eq!(plan.uncovered, behind);
    assert!(
        (plan.covered_share - 0.5).abs() < 1e-12,
        "{}",
        plan.covered_share
    );
}

#[test]
fn bad_inputs_are_rejected_with_the_field_named() {
    let pts = room_points();
    let poses = [[1.0, 2.0, 0.0]];
    let bad_range = DetectionRange { min: 3.0, max: 1.0 };
    let e = create_view_cones(&pts, &poses, &camera(), bad_range, |_, _| true).unwrap_err();
    assert!(e.to_string().contains("range"));
    let nan_pose = [[f64::NAN, 0.0, 0.0]];
    let e = create_view_cones(
        &pts,
        &nan_pose,
        &camera(),
        DetectionRange { min: 0.0, max: 1.0 },
        |_, _| true,
    )
    .unwrap_err();
    assert!(e.to_string().contains("poses"));
}

#[test]
fn absurd_pan_and_tilt_limits_are_clamped_not_enumerated() {
    let pts = room_points();
    let poses = [[3.0, 2.0, 0.0]];
    let mut cam = camera();
    cam.pan_limits = [-1e9, 1e9];
    cam.tilt_limits = [-1e9, 1e9];
    let range = DetectionRange {
        min: 0.1,
        max: 10.0,
    };
    let plan = create_view_cones(&pts, &poses, &cam, range, |_, _| true).unwrap();
    assert_eq!(plan.covered_share, 1.0);
}

/// The shipped office camera: 45° × 35°, tilting 45° down and 30° up, 1.2 m high.
fn office_camera() -> CameraModel {
    CameraModel {
        hfov: 45f64.to_radians(),
        vfov: 35f64.to_radians(),
        pan_limits: [-PI, PI],
        tilt_limits: [-45f64.to_radians(), 30f64.to_radians()],
        height: 1.2,
    }
}

/// Whether any view at zoom 1 (any pan, any tilt within the limits) from one of `poses` can
/// cover `p`: the point is in the distance interval and within half the vertical field of
/// view of the tilt range (the pan turns all the way round).
fn unzoomed_can_cover(
    poses: &[[f64; 3]],
    cam: &CameraModel,
    r: DetectionRange,
    p: [f64; 3],
) -> bool {
    poses.iter().any(|q| {
        let (dx, dy, dz) = (p[0] - q[0], p[1] - q[1], p[2] - cam.height);
        let horiz = dx.hypot(dy);
        let d = horiz.hypot(dz);
        let el = dz.atan2(horiz);
        d >= r.min
            && d <= r.max
            && el >= cam.tilt_limits[0] - cam.vfov / 2.0 - 1e-9
            && el <= cam.tilt_limits[1] + cam.vfov / 2.0 + 1e-9
    })
}

#[test]
fn zoomed_views_cover_the_floor_where_no_unzoomed_view_reaches_a_small_object() {
    // A whiteboard marker on the floor of a 4 m × 4 m room, seen from poses every 0.7 m, with
    // the distance interval the agent plans with (0.3 m to 80% of the way to the detection
    // range's 1.5 m): unzoomed, the floor is in range only closer than 0.4 m, where the camera
    // cannot tilt. The same grid at table height (0.76 m) is in unzoomed range.
    let mut pts = Vec::new();
    for z in [0.01, 0.76] {
        for i in 0..10 {
            for j in 0..10 {
                pts.push([0.2 + 0.4 * i as f64, 0.2 + 0.4 * j as f64, z]);
            }
        }
    }
    let on_floor = |k: usize| pts[k][2] < 0.5;
    let mut poses = Vec::new();
    for i in 0..5 {
        for j in 0..5 {
            poses.push([0.6 + 0.7 * i as f64, 0.6 + 0.7 * j as f64, 0.0]);
        }
    }
    let cam = office_camera();
    let range = DetectionRange {
        min: 0.3,
        max: 1.26,
    };
    let flat = create_view_cones(&pts, &poses, &cam, range, |_, _| true).unwrap();
    let zoomed =
        create_view_cones_zoomed(&pts, &poses, &cam, range, &[4.0, 1.0, 2.0], |_, _| true).unwrap();
    // Unzoomed: every table-height point, no floor point.
    for (k, p) in pts.iter().enumerate() {
        assert_eq!(flat.uncovered.contains(&k), on_floor(k), "point {k}: {p:?}");
    }
    assert!(
        zoomed.covered_share > 0.9,
        "zoomed {} vs unzoomed {}",
        zoomed.covered_share,
        flat.covered_share
    );
    let mut seen = vec![false; pts.len()];
    for v in &zoomed.views {
        assert!([1.0, 2.0, 4.0].contains(&v.zoom), "zoom {}", v.zoom);
        // At zoom z the fields of view shrink by z and the distance interval grows by z.
        for &k in &v.covered {
            assert!(
                sees_zoomed(v, &cam, range, pts[k]),
                "point {k} not visible from {v:?}"
            );
            // Zoomed views are planned only for what no unzoomed view can cover.
            if v.zoom > 1.0 {
                assert!(
                    !unzoomed_can_cover(&poses, &cam, range, pts[k]),
                    "point {k}"
                );
                assert!(on_floor(k), "zoomed view {v:?} covers table point {k}");
            }
        }
        for &k in &v.newly_covered {
            assert!(!seen[k], "point {k} newly covered twice");
            seen[k] = true;
        }
    }
    // Every point the unzoomed planning covers, the zoomed one covers too.
    for (k, seen) in seen.iter().enumerate() {
        assert!(*seen || flat.uncovered.contains(&k), "point {k} lost");
    }
}

#[test]
fn levels_at_the_zoom_times_the_unzoomed_range_plan_exactly_the_zoomed_views() {
    let pts = room_points();
    let poses = [[1.0, 2.0, 0.0], [3.0, 2.0, 0.0], [5.0, 2.0, 0.0]];
    let range = DetectionRange { min: 0.3, max: 0.9 };
    let zooms = [1.0, 2.0, 4.0];
    let levels: Vec<(f64, DetectionRange)> = zooms
        .iter()
        .map(|&z| {
            (
                z,
                DetectionRange {
                    min: range.min * z,
                    max: range.max * z,
                },
            )
        })
        .collect();
    let costs = CoverOptions::VIEWS_ONLY;
    let a = create_view_cones_costed(&pts, &poses, &camera(), range, &zooms, costs, |_, _| true)
        .unwrap();
    let b =
        create_view_cones_at_levels(&pts, &poses, &camera(), &levels, costs, |_, _| true).unwrap();
    assert_eq!(a, b);
    assert!(a.views.iter().any(|v| v.zoom > 1.0), "{a:?}");
}

#[test]
fn a_measured_zoomed_range_shorter_than_the_scaled_one_is_the_one_planned_with() {
    // Zoom 4 measured to reach 2 m, not the 3.6 m the unzoomed 0.9 m would scale to: no
    // zoomed view claims a point beyond 2 m, and the room is covered less.
    let pts = room_points();
    let poses = [[1.0, 2.0, 0.0], [5.0, 2.0, 0.0]];
    let cam = camera();
    let unzoomed = DetectionRange { min: 0.3, max: 0.9 };
    let measured = DetectionRange { min: 1.0, max: 2.0 };
    let costs = CoverOptions::VIEWS_ONLY;
    let scaled =
        create_view_cones_costed(&pts, &poses, &cam, unzoomed, &[1.0, 4.0], costs, |_, _| {
            true
        })
        .unwrap();
    let plan = create_view_cones_at_levels(
        &pts,
        &poses,
        &cam,
        &[(1.0, unzoomed), (4.0, measured)],
        costs,
        |_, _| true,
    )
    .unwrap();
    for v in plan.views.iter().filter(|v| v.zoom == 4.0) {
        let at_zoom = CameraModel {
            hfov: cam.hfov / 4.0,
            vfov: cam.vfov / 4.0,
            ..cam
        };
        for &k in &v.covered {
            assert!(sees(v, &at_zoom, measured, pts[k]), "point {k} from {v:?}");
        }
    }
    assert!(plan.views.iter().any(|v| v.zoom == 4.0), "{plan:?}");
    assert!(
        plan.covered_share < scaled.covered_share,
        "{} vs {}",
        plan.covered_share,
        scaled.covered_share
    );
    // A level with an empty range is refused, naming the field.
    let bad = DetectionRange { min: 2.0, max: 1.0 };
    let e = create_view_cones_at_levels(&pts, &poses, &cam, &[(1.0, bad)], costs, |_, _| true)
        .unwrap_err();
    assert!(e.to_string().contains("range"), "{e}");
}

#[test]
fn zoom_one_alone_plans_exactly_the_unzoomed_views() {
    let pts = room_points();
    let poses = [[1.0, 2.0, 0.0], [3.0, 2.0, 0.0], [5.0, 2.0, 0.0]];
    let range = DetectionRange { min: 0.5, max: 4.0 };
    let a = create_view_cones(&pts, &poses, &camera(), range, |_, _| true).unwrap();
    let b = create_view_cones_zoomed(&pts, &poses, &camera(), range, &[1.0], |_, _| true).unwrap();
    assert_eq!(a, b);
    assert!(a.views.iter().all(|v| v.zoom == 1.0));
}

#[test]
fn zoom_levels_below_one_or_not_finite_are_rejected() {
    let pts = room_points();
    let poses = [[1.0, 2.0, 0.0]];
    let range = DetectionRange { min: 0.5, max: 4.0 };
    for zooms in [
        &[][..],
        &[0.5][..],
        &[1.0, f64::NAN][..],
        &[f64::INFINITY][..],
    ] {
        let e = create_view_cones_zoomed(&pts, &poses, &camera(), range, zooms, |_, _| true)
            .unwrap_err();
        assert!(e.to_string().contains("zoom"), "{zooms:?}: {e}");
    }
}

/// Issue 18: a camera with a 1e-9° field of view validated and then asked for 10^12 candidate
/// angles per pose (an allocation of 1.6 TB). The angle grid is capped: the plan returns, every
/// claimed point is still inside its view, and the gaps between the sparse views are reported.
#[test]
fn a_needle_thin_field_of_view_plans_on_a_capped_angle_grid_and_reports_the_gaps() {
    let pts = room_points();
    let poses = [[1.0, 2.0, 0.0], [5.0, 2.0, PI]];
    let range = DetectionRange { min: 0.5, max: 4.0 };
    let cam = CameraModel {
        hfov: 1e-9f64.to_radians(),
        vfov: 1e-9f64.to_radians(),
        ..camera()
    };
    let plan = create_view_cones_zoomed(
        &pts,
        &poses,
        &cam,
        range,
        &[1.0, 2.0, 4.0, 128.0],
        |_, _| true,
    )
    .unwrap();
    for v in &plan.views {
        for &k in &v.covered {
            assert!(
                sees_zoomed(v, &cam, range, pts[k]),
                "point {k} is not visible from {v:?}"
            );
        }
    }
    assert!(
        !plan.uncovered.is_empty(),
        "a needle-thin camera cannot cover a room"
    );
    assert_eq!(
        plan.uncovered.len()
            + plan
                .views
                .iter()
                .map(|v| v.newly_covered.len())
                .sum::<usize>(),
        pts.len()
    );
}

#[test]
fn views_weighed_by_no_travel_are_the_unweighted_greedy_view_for_view() {
    let pts = room_points();
    let poses = [[1.0, 2.0, 0.0], [3.0, 2.0, 0.0], [5.0, 2.0, 0.0]];
    let range = DetectionRange { min: 0.5, max: 4.0 };
    let plain = create_view_cones(&pts, &poses, &camera(), range, |_, _| true).unwrap();
    let free_walk = CoverOptions {
        point_radius: 0.0,
        per_view: 2.5,
        per_metre: 0.0,
        from: Some([5.0, 2.0]),
    };
    let costed =
        create_view_cones_costed(&pts, &poses, &camera(), range, &[1.0], free_walk, |_, _| {
            true
        })
        .unwrap();
    assert_eq!(plain, costed);
}

/// Two standpoints: the robot stands on A, B is 4 m away. B's best view sees the whole 3 × 3
/// cluster of points in front of it (9 points), A's sees only the nearest row of 3. Counted
/// alone, B's view wins; with a walk costing 1 per metre and a view 1, A's view is worth
/// 3 / 1 = 3 new points per unit and B's 9 / (1 + 4) = 1.8, so A's view comes first and B's
/// view (then worth 6 / 5 = 1.2) second, for the rest. Both plans cover every point.
#[test]
fn a_walk_to_a_far_standpoint_is_paid_for_in_the_greedy_choice() {
    // Points at camera height in a 3 × 3 cluster around (5.5, 0); A at the origin sees only
    // those within 5.3 m (the row at x = 5), B at (4, 0) sees all of them.
    let mut pts = Vec::new();
    for i in 0..3 {
        for j in 0..3 {
            pts.push([5.0 + 0.5 * i as f64, -0.5 + 0.5 * j as f64, 1.2]);
        }
    }
    let cam = CameraModel {
        hfov: 120f64.to_radians(),
        vfov: 45f64.to_radians(),
        pan_limits: [0.0, 0.0],
        tilt_limits: [0.0, 0.0],
        height: 1.2,
    };
    let range = DetectionRange { min: 0.5, max: 5.3 };
    let poses = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0]];
    let seen_from_a = pts.iter().filter(|p| p[0].hypot(p[1]) <= range.max).count();
    assert_eq!(seen_from_a, 3, "the scene is built so that A sees 3 points");
    let plain = create_view_cones(&pts, &poses, &cam, range, |_, _| true).unwrap();
    assert_eq!(plain.views.len(), 1);
    assert_eq!(
        plain.views[0].pose_index, 1,
        "counted alone, B's 9 points win"
    );
    let walk = CoverOptions {
        point_radius: 0.0,
        per_view: 1.0,
        per_metre: 1.0,
        from: Some([0.0, 0.0]),
    };
    let costed =
        create_view_cones_costed(&pts, &poses, &cam, range, &[1.0], walk, |_, _| true).unwrap();
    let order: Vec<usize> = costed.views.iter().map(|v| v.pose_index).collect();
    assert_eq!(
        order,
        vec![0, 1],
        "A's cheap view first, then B's for the rest"
    );
    assert_eq!(costed.views[0].newly_covered.len(), 3);
    assert_eq!(costed.views[1].newly_covered.len(), 6);
    assert_eq!(costed.covered_share, 1.0);
    assert_eq!(plain.covered_share, 1.0);
}

#[test]
fn view_costs_that_are_not_positive_and_finite_are_rejected() {
    let pts = room_points();
    let poses = [[1.0, 2.0, 0.0]];
    let range = DetectionRange { min: 0.5, max: 4.0 };
    for costs in [
        CoverOptions {
            per_view: 0.0,
            ..CoverOptions::VIEWS_ONLY
        },
        CoverOptions {
            point_radius: -0.1,
            ..CoverOptions::VIEWS_ONLY
        },
        CoverOptions {
            per_view: f64::NAN,
            ..CoverOptions::VIEWS_ONLY
        },
        CoverOptions {
            per_metre: -1.0,
            ..CoverOptions::VIEWS_ONLY
        },
        CoverOptions {
            from: Some([f64::INFINITY, 0.0]),
            ..CoverOptions::VIEWS_ONLY
        },
    ] {
        let e =
            create_view_cones_costed(&pts, &poses, &camera(), range, &[1.0], costs, |_, _| true)
                .unwrap_err();
        assert!(e.to_string().contains("costs"), "{costs:?}: {e}");
    }
}

/// A point stands for the cell around it: with a cell radius, a view covers the point only when
/// the whole cell is in the field of view, so a point 1 m away at 25° off the axis of a 60°
/// camera (inside by 5°) is covered bare, and not with a 0.2 m cell (atan(0.2 / 1) = 11°).
#[test]
fn a_point_counts_as_covered_only_when_its_whole_cell_is_in_view() {
    let cam = CameraModel {
        hfov: 60f64.to_radians(),
        vfov: 45f64.to_radians(),
        pan_limits: [0.0, 0.0],
        tilt_limits: [0.0, 0.0],
        height: 1.2,
    };
    let range = DetectionRange { min: 0.1, max: 4.0 };
    let b = 25f64.to_radians();
    let pts = [[b.cos(), b.sin(), 1.2]];
    let poses = [[0.0, 0.0, 0.0]];
    let bare = create_view_cones(&pts, &poses, &cam, range, |_, _| true).unwrap();
    assert_eq!(bare.covered_share, 1.0);
    let cells = CoverOptions {
        point_radius: 0.2,
        ..CoverOptions::VIEWS_ONLY
    };
    let celled =
        create_view_cones_costed(&pts, &poses, &cam, range, &[1.0], cells, |_, _| true).unwrap();
    assert!(celled.views.is_empty(), "{:?}", celled.views);
    assert_eq!(celled.uncovered, vec![0]);
    // Farther out on the same bearing the cell subtends less: at 4 m, atan(0.2 / 4) = 2.9°.
    let far = [[3.9 * b.cos(), 3.9 * b.sin(), 1.2]];
    let celled_far =
        create_view_cones_costed(&far, &poses, &cam, range, &[1.0], cells, |_, _| true).unwrap();
    assert_eq!(celled_far.covered_share, 1.0);
}
