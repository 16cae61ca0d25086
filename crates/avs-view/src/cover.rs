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
    if !(range.min >= 0.0 && range.max > range.min && range.max.is_finite()) {
        return Err(bad(
            "range",
            format!(
                "expected 0 ≤ min < max < ∞, got [{}, {}]",
                range.min, range.max
            ),
        ));
    }
    if zooms.is_empty() || zooms.iter().any(|z| !(z.is_finite() && *z >= 1.0)) {
        return Err(bad(
            "zooms",
            format!("expected one or more zoom levels, each a number ≥ 1, got {zooms:?}"),
        ));
    }
    let mut levels = zooms.to_vec();
    levels.sort_by(f64::total_cmp);
    levels.dedup();
    // Candidate views with their coverage, zoom level by zoom level; a level's candidates
    // cover only what the lower levels' candidates cannot.
    let mut candidates: Vec<Candidate> = Vec::new();
    let mut coverable = vec![false; points.len()];
    for &zoom in &levels {
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
            &line_of_sight,
            &mut candidates,
        );
        for cand in &candidates[before..] {
            cand.covered.iter().for_each(|&k| coverable[k] = true);
        }
    }
    // Greedy set cover (§2.1.4).
    let mut is_covered = vec![false; points.len()];
    let mut views = Vec::new();
    loop {
        let best = candidates
            .iter()
            .enumerate()
            .map(|(i, cand)| (i, cand.covered.iter().filter(|k| !is_covered[**k]).count()))
            .filter(|(_, n)| *n > 0)
            .max_by(|x, y| x.1.cmp(&y.1).then(y.0.cmp(&x.0)));
        let Some((i, _)) = best else { break };
        let cand = candidates.swap_remove(i);
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

/// A candidate view: pose index, camera angles and zoom, and the points it covers.
struct Candidate {
    pose: usize,
    pan: f64,
    tilt: f64,
    zoom: f64,
    covered: Vec<usize>,
}

/// Append to `out` the candidate views at `zoom` (fields of view divided by it, distance
/// interval multiplied by it) that cover some of the points `wanted`: every pose × pan × tilt
/// on a grid of half the (zoomed) field of view.
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
    line_of_sight: &impl Fn([f64; 3], [f64; 3]) -> bool,
    out: &mut Vec<Candidate>,
) {
    let (hfov, vfov) = (c.hfov / zoom, c.vfov / zoom);
    let (d_min, d_max) = (range.min * zoom, range.max * zoom);
    // A pan range beyond a full turn, or tilts beyond straight up/down, add no new directions.
    let pan_hi = c.pan_limits[1].min(c.pan_limits[0] + 2.0 * PI);
    let pans = angle_steps(c.pan_limits[0], pan_hi, hfov / 2.0);
    let tilt_lo = c.tilt_limits[0].max(-PI / 2.0);
    let tilt_hi = c.tilt_limits[1].min(PI / 2.0).max(tilt_lo);
    let tilts = angle_steps(tilt_lo, tilt_hi, vfov / 2.0);
    for (pi, pose) in poses.iter().enumerate() {
        let cam = [pose[0], pose[1], c.height];
        // Points in range and in line of sight do not depend on the camera angles.
        let visible: Vec<(usize, f64, f64)> = wanted
            .iter()
            .filter_map(|&k| {
                let p = points[k];
                let (dx, dy, dz) = (p[0] - cam[0], p[1] - cam[1], p[2] - cam[2]);
                let horiz = (dx * dx + dy * dy).sqrt();
                let d = (horiz * horiz + dz * dz).sqrt();
                if d < d_min || d > d_max || !line_of_sight(cam, p) {
                    return None;
                }
                Some((k, dy.atan2(dx), dz.atan2(horiz)))
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
                    .filter(|(_, az, el)| {
                        wrap_angle(az - yaw).abs() <= hfov / 2.0 + 1e-12
                            && (el - tilt).abs() <= vfov / 2.0 + 1e-12
                    })
                    .map(|(k, _, _)| *k)
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
