//! CREATEVIEWCONES: view planning by coverage (Sjöö et al., `004` §2.1).
//!
//! Candidate views are every reachable robot pose × camera pan × tilt on a grid of half the field of
//! view (so neighbouring views overlap by half), at most [`MAX_ANGLE_STEPS`] angles per axis. A point is covered by a view when (§2.1.2–2.1.3)
//! * it lies inside the horizontal and vertical field of view around the view direction,
//! * its distance from the camera is within the object class's `[min, max]` detection range, and
//! * the caller's line-of-sight predicate holds from the camera to the point (the paper ignores
//!   occlusion by laser-level obstacles; pass `|_, _| true` for that behaviour).
//!
//! Views are then chosen greedily (§2.1.4): repeatedly the view covering most not-yet-covered points,
//! until every point is covered or no view adds any. Greedy set cover is within a factor `H(k) ≤ ln k + 1`
//! of the minimum number of views (Chvátal 1979).
//!
//! **Travel** ([`create_view_cones_costed`]). The paper counts views; a robot pays for the walk
//! between standpoints too, and a plan whose 12 views stand on 7 standpoints walks a room over
//! twice. Our choice: the weighted greedy of Chvátal (1979) — repeatedly the view with the most
//! new points per unit of cost — where a view costs [`CoverOptions::per_view`] plus
//! [`CoverOptions::per_metre`] times the straight-line distance from its standpoint to the nearest
//! standpoint already chosen (or to where the robot stands, [`CoverOptions::from`]); a view from a
//! chosen standpoint adds no travel. That distance is the growth of the minimum spanning tree
//! over the standpoints as Prim's algorithm adds them, and a tour through them is at most twice
//! that tree, so the greedy trades new points against a bound on the walk. With `per_metre = 0`
//! it is the unweighted greedy above, view for view.
//!
//! **Zoom** ([`create_view_cones_zoomed`]). The paper plans its views at no zoom and zooms only on
//! hypotheses (§3.4), with the planning step's maximum detection distance set by the unzoomed
//! image (§3.2). For a small object that leaves whole regions no unzoomed view can cover: a
//! whiteboard marker on the floor, seen from a 1.2 m camera, is beyond its unzoomed detection
//! range wherever the tilt limit lets the camera look at it. At zoom `z` the fields of view are
//! divided by `z` and the distance interval multiplied by `z` (the same image detail at `z`
//! times the distance, §3.4). Our choice: the candidates at zoom `z > 1` cover only the points
//! that no candidate at a lower zoom level covers, so zoomed views are planned where they are
//! needed and nowhere else (the candidate set stays small, and the wide unzoomed views keep
//! doing the rest); the greedy choice then runs over all candidates together.

use crate::error::{Result, ViewError};
use avs_map::geometry::wrap_angle;
use std::f64::consts::PI;

/// Camera geometry (angles in radians, lengths in metres).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CameraModel {
    /// Horizontal field of view.
    pub hfov: f64,
    /// Vertical field of view.
    pub vfov: f64,
    /// Pan limits relative to the robot's heading, `[min, max]`.
    pub pan_limits: [f64; 2],
    /// Tilt limits (positive up), `[min, max]`.
    pub tilt_limits: [f64; 2],
    /// Height of the camera's optical centre above the floor.
    pub height: f64,
}

/// Detection range of the object class searched for.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DetectionRange {
    /// Minimum distance from the camera.
    pub min: f64,
    /// Maximum distance from the camera.
    pub max: f64,
}

/// One planned view: where the robot stands and where the camera points.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PlannedView {
    /// Index of the candidate pose used.
    pub pose_index: usize,
    /// Robot pose `[x, y, heading]`.
    pub pose: [f64; 3],
    /// Camera pan relative to the heading.
    pub pan: f64,
    /// Camera tilt.
    pub tilt: f64,
    /// Camera zoom (1: none; fields of view divided by it, detection range multiplied by it).
    pub zoom: f64,
    /// Every point this view covers.
    pub covered: Vec<usize>,
    /// The points it covered first (disjoint across views; in greedy order).
    pub newly_covered: Vec<usize>,
}

/// How [`create_view_cones_costed`] counts a point as covered and what a view costs in its
/// greedy choice (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CoverOptions {
    /// Half the spacing of the points' horizontal lattice times √2 (≥ 0, metres): a point
    /// stands for the cell around it, where the object may be anywhere, so a view covers it
    /// only when the whole cell is inside the horizontal field of view — the bearing to the
    /// point plus `atan(point_radius / horizontal distance)` within half the field. 0 counts
    /// the point alone, as the paper's points are.
    pub point_radius: f64,
    /// Cost of processing one view (> 0).
    pub per_view: f64,
    /// Cost per metre of the straight line from a new standpoint to the nearest standpoint
    /// already chosen (≥ 0).
    pub per_metre: f64,
    /// Where the robot stands when the views are planned: the first standpoint's travel is
    /// measured from here. `None`: the first standpoint costs no travel.
    pub from: Option<[f64; 2]>,
}

impl CoverOptions {
    /// Views counted alone, as the paper's greedy does (§2.1.4), over bare points.
    pub const VIEWS_ONLY: CoverOptions = CoverOptions {
        point_radius: 0.0,
        per_view: 1.0,
        per_metre: 0.0,
        from: None,
    };
}

/// The result of CREATEVIEWCONES.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ViewConePlan {
    /// Chosen views in greedy order.
    pub views: Vec<PlannedView>,
    /// Share of the location's points covered by some chosen view.
    pub covered_share: f64,
    /// Points no candidate view can cover.
    pub uncovered: Vec<usize>,
}

impl ViewConePlan {
    /// Cells per view, in the form `avs_pomdp::cone_priors` takes.
    pub fn cone_cells(&self) -> Vec<Vec<usize>> {
        self.views.iter().map(|v| v.covered.clone()).collect()
    }
}

/// Most camera angle steps per axis and zoom level: a pan over a full turn at steps of 2.8°. A
/// field of view so narrow that half of it is a finer step (under 5.6° wide, after zoom, over a
/// full turn) is sampled at this many steps instead, leaving gaps between neighbouring views that the plan's `uncovered`
/// list reports; without the cap a camera of a 1e-9° field of view asked for 10^12 candidate
/// angles per pose (issue 18: what validates must run in bounded time and memory).
pub const MAX_ANGLE_STEPS: usize = 128;

/// `lo..=hi` in equal steps no longer than `step`, at most [`MAX_ANGLE_STEPS`] + 1 angles.
fn angle_steps(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    if hi - lo <= 1e-12 {
        return vec![(lo + hi) / 2.0];
    }
    // `as usize` saturates (a NaN becomes 0), so the clamp bounds every input.
    let k = (((hi - lo) / step).ceil() as usize).clamp(1, MAX_ANGLE_STEPS);
    (0..=k)
        .map(|i| lo + (hi - lo) * i as f64 / k as f64)
        .collect()
}

/// Generate view cones covering `points` (world `[x, y, z]`: the location's cells or sample points)
/// from `poses` (reachable robot poses `[x, y, heading]`), for an object class with detection range
/// `range`, using the caller's line-of-sight predicate.
pub fn create_view_cones(
    points: &[[f64; 3]],
    poses: &[[f64; 3]],
    camera: &CameraModel,
    range: DetectionRange,
    line_of_sight: impl Fn([f64; 3], [f64; 3]) -> bool,
) -> Result<ViewConePlan> {
    create_view_cones_zoomed(points, poses, camera, range, &[1.0], line_of_sight)
}

/// [`create_view_cones`] with the camera's zoom levels `zooms` (each ≥ 1, in any order; `camera`
/// and `range` are at zoom 1): candidates at a zoom level cover only the points no candidate at
/// a lower level covers (see the module docs).
pub fn create_view_cones_zoomed(
    points: &[[f64; 3]],
    poses: &[[f64; 3]],
    camera: &CameraModel,
    range: DetectionRange,
    zooms: &[f64],
    line_of_sight: impl Fn([f64; 3], [f64; 3]) -> bool,
) -> Result<ViewConePlan> {
    create_view_cones_costed(
        points,
        poses,
        camera,
        range,
        zooms,
        CoverOptions::VIEWS_ONLY,
        line_of_sight,
    )
}

/// [`create_view_cones_zoomed`] with the weighted greedy: each view's new points per unit of
/// `costs` (processing plus the walk to a new standpoint; see the module docs).
pub fn create_view_cones_costed(
    points: &[[f64; 3]],
    poses: &[[f64; 3]],
    camera: &CameraModel,
    range: DetectionRange,
    zooms: &[f64],
    costs: CoverOptions,
    line_of_sight: impl Fn([f64; 3], [f64; 3]) -> bool,
) -> Result<ViewConePlan> {
    let bad = |field: &'static str, message: String| ViewError::InvalidInput { field, message };
    if zooms.is_empty() || zooms.iter().any(|z| !(z.is_finite() && *z >= 1.0)) {
        return Err(bad(
            "zooms",
            format!("expected one or more zoom levels, each a number ≥ 1, got {zooms:?}"),
        ));
    }
    // Zooming by z narrows the field by z and stretches the detection range by z (the object
    // fills as many pixels at z times the distance).
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
    create_view_cones_at_levels(points, poses, camera, &levels, costs, line_of_sight)
}

/// [`create_view_cones_costed`] with a detection range of its own at each zoom level
/// (`levels`: the zoom and the range at that zoom), for a detector whose zoomed reach is
/// measured rather than taken as the zoom times the unzoomed one (a zoomed look sees a
/// farther, busier scene: Sjöö et al. `004` §4.2).
pub fn create_view_cones_at_levels(
    points: &[[f64; 3]],
    poses: &[[f64; 3]],
    camera: &CameraModel,
    levels: &[(f64, DetectionRange)],
    costs: CoverOptions,
    line_of_sight: impl Fn([f64; 3], [f64; 3]) -> bool,
) -> Result<ViewConePlan> {
    let bad = |field: &'static str, message: String| ViewError::InvalidInput { field, message };
    if points.iter().flatten().any(|v| !v.is_finite()) {
        return Err(bad("points", "coordinates must be finite".into()));
    }
    if poses.iter().flatten().any(|v| !v.is_finite()) {
        return Err(bad("poses", "coordinates must be finite".into()));
    }
    let c = camera;
    if !(c.hfov > 0.0 && c.hfov <= 2.0 * PI && c.vfov > 0.0 && c.vfov < PI) {
        return Err(bad(
            "camera",
            format!(
                "fields of view must be in (0, 2π] and (0, π), got {} and {}",
                c.hfov, c.vfov
            ),
        ));
    }
    if !(c.pan_limits[0] <= c.pan_limits[1]
        && c.tilt_limits[0] <= c.tilt_limits[1]
        && c.pan_limits
            .iter()
            .chain(&c.tilt_limits)
            .all(|x| x.is_finite())
        && c.height.is_finite())
    {
        return Err(bad(
            "camera",
            "pan/tilt limits must be finite [min, max] pairs and the height finite".into(),
        ));
    }
    if let Some((_, range)) = levels
        .iter()
        .find(|(_, r)| !(r.min >= 0.0 && r.max > r.min && r.max.is_finite()))
    {
        return Err(bad(
            "range",
            format!(
                "expected 0 ≤ min < max < ∞, got [{}, {}]",
                range.min, range.max
            ),
        ));
    }
    if levels.is_empty() || levels.iter().any(|(z, _)| !(z.is_finite() && *z >= 1.0)) {
        let zooms: Vec<f64> = levels.iter().map(|l| l.0).collect();
        return Err(bad(
            "zooms",
            format!("expected one or more zoom levels, each a number ≥ 1, got {zooms:?}"),
        ));
    }
    if !(costs.point_radius.is_finite()
        && costs.point_radius >= 0.0
        && costs.per_view.is_finite()
        && costs.per_view > 0.0
        && costs.per_metre.is_finite()
        && costs.per_metre >= 0.0
        && costs.from.is_none_or(|f| f.iter().all(|v| v.is_finite())))
    {
        return Err(bad(
            "costs",
            format!(
                "expected point_radius ≥ 0, per_view > 0, per_metre ≥ 0 and a finite start, got radius {}, {} per view, {} per metre, from {:?}",
                costs.point_radius, costs.per_view, costs.per_metre, costs.from
            ),
        ));
    }
    let mut levels = levels.to_vec();
    levels.sort_by(|a, b| a.0.total_cmp(&b.0));
    levels.dedup_by(|a, b| a.0 == b.0);
    // Candidate views with their coverage, zoom level by zoom level; a level's candidates
    // cover only what the lower levels' candidates cannot.
    let mut candidates: Vec<Candidate> = Vec::new();
    let mut coverable = vec![false; points.len()];
    for &(zoom, range) in &levels {
        let wanted: Vec<usize> = (0..points.len()).filter(|&k| !coverable[k]).collect();
        if wanted.is_empty() {
            break;
        }
        let before = candidates.len();
        zoom_candidates(
            points,
            &wanted,
            poses,
            c,
            range,
            zoom,
            costs.point_radius,
            &line_of_sight,
            &mut candidates,
        );
        for cand in &candidates[before..] {
            cand.covered.iter().for_each(|&k| coverable[k] = true);
        }
    }
    // Greedy set cover (§2.1.4), weighted by each view's cost (module docs): `reach[p]` is the
    // straight-line distance from pose p to the nearest standpoint chosen so far (or to the
    // start; infinite while there is neither), 0 once p itself is chosen.
    let mut reach: Vec<f64> = poses
        .iter()
        .map(|p| costs.from.map_or(f64::INFINITY, |f| dist2(f, [p[0], p[1]])))
        .collect();
    let mut is_covered = vec![false; points.len()];
    let mut views = Vec::new();
    loop {
        let best = candidates
            .iter()
            .enumerate()
            .map(|(i, cand)| {
                let n = cand.covered.iter().filter(|k| !is_covered[**k]).count();
                // Infinite before the first standpoint when there is no start: no travel.
                let walk = Some(reach[cand.pose])
                    .filter(|r| r.is_finite())
                    .unwrap_or(0.0);
                let cost = costs.per_view + costs.per_metre * walk;
                (i, n, n as f64 / cost)
            })
            .filter(|(_, n, _)| *n > 0)
            .max_by(|x, y| x.2.total_cmp(&y.2).then(x.1.cmp(&y.1)).then(y.0.cmp(&x.0)));
        let Some((i, _, _)) = best else { break };
        let cand = candidates.swap_remove(i);
        let at = poses[cand.pose];
        for (r, p) in reach.iter_mut().zip(poses) {
            *r = r.min(dist2([at[0], at[1]], [p[0], p[1]]));
        }
        reach[cand.pose] = 0.0;
        let newly: Vec<usize> = cand
            .covered
            .iter()
            .copied()
            .filter(|k| !is_covered[*k])
            .collect();
        newly.iter().for_each(|k| is_covered[*k] = true);
        views.push(PlannedView {
            pose_index: cand.pose,
            pose: poses[cand.pose],
            pan: cand.pan,
            tilt: cand.tilt,
            zoom: cand.zoom,
            covered: cand.covered,
            newly_covered: newly,
        });
    }
    let n_cov = is_covered.iter().filter(|x| **x).count();
    Ok(ViewConePlan {
        views,
        covered_share: if points.is_empty() {
            1.0
        } else {
            n_cov as f64 / points.len() as f64
        },
        uncovered: (0..points.len()).filter(|k| !is_covered[*k]).collect(),
    })
}

/// Straight-line distance in the plane.
fn dist2(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// A candidate view: pose index, camera angles and zoom, and the points it covers.
struct Candidate {
    pose: usize,
    pan: f64,
    tilt: f64,
    zoom: f64,
    covered: Vec<usize>,
}

/// Append to `out` the candidate views at `zoom` (fields of view divided by it, distance
/// interval multiplied by it) that cover some of the points `wanted` (each with the cell of
/// `point_radius` around it): every pose × pan × tilt on a grid of half the (zoomed) field
/// of view.
#[expect(
    clippy::too_many_arguments,
    reason = "the candidate generator needs the points, the camera, the range and the zoom level"
)]
fn zoom_candidates(
    points: &[[f64; 3]],
    wanted: &[usize],
    poses: &[[f64; 3]],
    c: &CameraModel,
    range: DetectionRange,
    zoom: f64,
    point_radius: f64,
    line_of_sight: &impl Fn([f64; 3], [f64; 3]) -> bool,
    out: &mut Vec<Candidate>,
) {
    let (hfov, vfov) = (c.hfov / zoom, c.vfov / zoom);
    let (d_min, d_max) = (range.min, range.max);
    // A pan range beyond a full turn, or tilts beyond straight up/down, add no new directions.
    let pan_hi = c.pan_limits[1].min(c.pan_limits[0] + 2.0 * PI);
    let pans = angle_steps(c.pan_limits[0], pan_hi, hfov / 2.0);
    let tilt_lo = c.tilt_limits[0].max(-PI / 2.0);
    let tilt_hi = c.tilt_limits[1].min(PI / 2.0).max(tilt_lo);
    let tilts = angle_steps(tilt_lo, tilt_hi, vfov / 2.0);
    for (pi, pose) in poses.iter().enumerate() {
        let cam = [pose[0], pose[1], c.height];
        // Points in range and in line of sight do not depend on the camera angles.
        let visible: Vec<(usize, f64, f64, f64)> = wanted
            .iter()
            .filter_map(|&k| {
                let p = points[k];
                let (dx, dy, dz) = (p[0] - cam[0], p[1] - cam[1], p[2] - cam[2]);
                let horiz = (dx * dx + dy * dy).sqrt();
                let d = (horiz * horiz + dz * dz).sqrt();
                if d < d_min || d > d_max || !line_of_sight(cam, p) {
                    return None;
                }
                // The half-width, seen from here, of the cell the point stands for.
                let margin = if point_radius > 0.0 {
                    point_radius.atan2(horiz)
                } else {
                    0.0
                };
                Some((k, dy.atan2(dx), dz.atan2(horiz), margin))
            })
            .collect();
        if visible.is_empty() {
            continue;
        }
        for &pan in &pans {
            let yaw = pose[2] + pan;
            for &tilt in &tilts {
                let covered: Vec<usize> = visible
                    .iter()
                    .filter(|(_, az, el, margin)| {
                        wrap_angle(az - yaw).abs() + margin <= hfov / 2.0 + 1e-12
                            && (el - tilt).abs() <= vfov / 2.0 + 1e-12
                    })
                    .map(|(k, _, _, _)| *k)
                    .collect();
                if !covered.is_empty() {
                    out.push(Candidate {
                        pose: pi,
                        pan,
                        tilt,
                        zoom,
                        covered,
                    });
                }
            }
        }
    }
}
