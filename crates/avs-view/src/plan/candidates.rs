//! Candidate views (Sjöö et al. `004` §2.1.2, §2.1.5): for every standpoint and camera
//! direction, the images that see the room's (class, cell) pairs, grouped in *units* chosen
//! whole — the direction's far cells (one image, usually) and its near cells (the tilt rule's
//! images). See the [module docs](super) for the choices.

use super::{Pair, ViewProblem};
use crate::cover::MAX_ANGLE_STEPS;
use crate::error::{Result, ViewError};
use crate::zoom::view_zooms;
use avs_map::geometry::wrap_angle;
use serde::Serialize;
use std::f64::consts::PI;

/// Most tilts one unit takes (a camera with a tiny vertical field of view would otherwise ask
/// for thousands).
pub const MAX_TILTS: usize = 8;

/// A candidate unit: the images of one standpoint and direction that are chosen together, and
/// the pairs they cover.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Unit {
    /// Index of the standpoint.
    pub standpoint: usize,
    /// Camera direction in the world, radians.
    pub yaw: f64,
    /// Zoom of its images.
    pub zoom: f64,
    /// The tilts of its images (one image each), ascending.
    pub tilts: Vec<f64>,
    /// Whether it is the direction's near unit (§2.1.5's extra tilts).
    pub near: bool,
    /// The pairs it covers, ascending.
    pub pairs: Vec<Pair>,
}

impl Unit {
    /// The number of images it takes.
    pub fn images(&self) -> usize {
        self.tilts.len()
    }
}

/// The elevation band, seen from a camera `height` m high, of centres between `heights` above
/// a point `d` m away horizontally.
fn band(height: f64, heights: [f64; 2], d: f64) -> (f64, f64) {
    (
        (heights[0] - height).atan2(d),
        (heights[1] - height).atan2(d),
    )
}

/// The distance (metres) below which some class's height band no longer fits one image's
/// vertical field of view at zoom 1: cells nearer than this need §2.1.5's extra tilts. 0 when
/// every band fits at any distance.
pub fn near_distance(problem: &ViewProblem) -> f64 {
    near_distance_for(problem, problem.camera.vfov)
}

/// [`near_distance`] for a vertical field of view `vfov` (a zoomed image's).
fn near_distance_for(problem: &ViewProblem, vfov: f64) -> f64 {
    let c = &problem.camera;
    let fits = |d: f64| {
        problem.classes.iter().all(|k| {
            let (a, b) = band(c.height, k.heights, d);
            b - a <= vfov + 1e-12
        })
    };
    if fits(1e-6) {
        return 0.0;
    }
    // The band's width falls with the distance: bisect for the first distance where all fit.
    let (mut lo, mut hi) = (1e-6, 1e4);
    if !fits(hi) {
        return hi;
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if fits(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// The fewest evenly spaced tilts whose vertical fields of view together span the elevations
/// `[a, b]`, as far as the tilt limits reach (§2.1.5: "one or more tilt angles are selected,
/// with as little overlap as possible"); ascending, at most [`MAX_TILTS`].
///
/// ```
/// use avs_view::plan::tilt_rule;
/// // 50° of elevation need two 35° images, overlapping by 20°.
/// let t = tilt_rule((-50f64).to_radians(), 0.0, 35f64.to_radians(), [-1.0, 1.0]);
/// assert_eq!(t.len(), 2);
/// assert!((t[0].to_degrees() + 32.5).abs() < 1e-9 && (t[1].to_degrees() + 17.5).abs() < 1e-9);
/// ```
pub fn tilt_rule(a: f64, b: f64, vfov: f64, limits: [f64; 2]) -> Vec<f64> {
    let half = vfov / 2.0;
    let lo = a.max(limits[0] - half);
    let hi = b.min(limits[1] + half);
    if hi <= lo {
        return vec![((a + b) / 2.0).clamp(limits[0], limits[1])];
    }
    // `as usize` saturates; the clamp bounds it.
    let n = (((hi - lo) / vfov - 1e-9).ceil() as usize).clamp(1, MAX_TILTS);
    if n == 1 {
        return vec![((lo + hi) / 2.0).clamp(limits[0], limits[1])];
    }
    let spacing = (hi - lo - vfov) / (n - 1) as f64;
    (0..n)
        .map(|i| (lo + half + spacing * i as f64).clamp(limits[0], limits[1]))
        .collect()
}

/// Check a problem's numbers; the error names the field.
pub(crate) fn check(problem: &ViewProblem) -> Result<()> {
    let bad = |field: &'static str, message: String| ViewError::InvalidInput { field, message };
    if problem.cells.iter().flatten().any(|v| !v.is_finite()) {
        return Err(bad("cells", "coordinates must be finite".into()));
    }
    if problem.standpoints.iter().flatten().any(|v| !v.is_finite()) {
        return Err(bad("standpoints", "coordinates must be finite".into()));
    }
    if let Some(m) = problem.classes.iter().find_map(|c| c.problem()) {
        return Err(bad("classes", m));
    }
    let c = &problem.camera;
    if !(c.hfov > 0.0 && c.hfov <= 2.0 * PI && c.vfov > 0.0 && c.vfov < PI && c.height.is_finite())
    {
        return Err(bad(
            "camera",
            format!(
                "fields of view must be in (0, 2π] and (0, π) and the height finite, got {}, {} and {}",
                c.hfov, c.vfov, c.height
            ),
        ));
    }
    if !(c.tilt_limits[0] <= c.tilt_limits[1] && c.tilt_limits.iter().all(|t| t.is_finite())) {
        return Err(bad(
            "camera",
            format!(
                "tilt limits {:?} are not a finite [min, max]",
                c.tilt_limits
            ),
        ));
    }
    if problem.options.k == 0 {
        return Err(bad("options.k", "expected k ≥ 1".into()));
    }
    if let Some(s) = problem.options.direction_step {
        if !(s.is_finite() && s > 0.0) {
            return Err(bad(
                "options.direction_step",
                format!("expected a positive angle, got {s}"),
            ));
        }
    }
    Ok(())
}

/// A pair a standpoint can see: its bearing, its elevation band and its horizontal distance.
struct Seen {
    pair: Pair,
    bearing: f64,
    band: (f64, f64),
    distance: f64,
}

/// Most candidate directions per standpoint: beyond this many distinct bearings the canonical
/// directions are taken on a grid of `2π / MAX_DIRECTIONS`.
pub const MAX_DIRECTIONS: usize = 720;

/// The camera directions tried from one standpoint. With a `step`, a regular grid of at most
/// [`MAX_ANGLE_STEPS`] directions. Without one, the *canonical* directions: for each bearing of
/// a seen cell, the direction whose field of view starts there. Any set of cells one image
/// sees, an image turned until the first of them is on its edge sees too, so the canonical
/// directions lose no plan the continuum of directions has (and a grid does).
fn directions(seen: &[Seen], hfov: f64, step: Option<f64>) -> Vec<f64> {
    if let Some(step) = step {
        // `as usize` saturates (an enormous count becomes usize::MAX); the clamp bounds it.
        let n = ((2.0 * PI / step).ceil() as usize).clamp(1, MAX_ANGLE_STEPS);
        return (0..n)
            .map(|i| wrap_angle(2.0 * PI * i as f64 / n as f64))
            .collect();
    }
    let mut bearings: Vec<f64> = seen.iter().map(|p| p.bearing).collect();
    bearings.sort_by(f64::total_cmp);
    bearings.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    if bearings.len() > MAX_DIRECTIONS {
        let q = 2.0 * PI / MAX_DIRECTIONS as f64;
        bearings = bearings.iter().map(|b| (b / q).floor() * q).collect();
        bearings.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    }
    bearings
        .into_iter()
        .map(|b| wrap_angle(b + hfov / 2.0))
        .collect()
}

/// The unit of one standpoint, direction and zoom for a group of seen pairs (its far or its
/// near ones): the tilt rule's images over the group's bands, and the pairs whose band they
/// span. `None` when it covers nothing.
fn unit_of(
    group: &[&&Seen],
    standpoint: usize,
    yaw: f64,
    zoom: f64,
    near: bool,
    vfov: f64,
    tilt_limits: [f64; 2],
) -> Option<Unit> {
    if group.is_empty() {
        return None;
    }
    let a = group.iter().map(|p| p.band.0).fold(f64::INFINITY, f64::min);
    let b = group
        .iter()
        .map(|p| p.band.1)
        .fold(f64::NEG_INFINITY, f64::max);
    let mut tilts = tilt_rule(a, b, vfov, tilt_limits);
    tilts.sort_by(f64::total_cmp);
    tilts.dedup_by(|x, y| (*x - *y).abs() < 1e-12);
    let (bottom, top) = (tilts[0] - vfov / 2.0, tilts[tilts.len() - 1] + vfov / 2.0);
    // Neighbouring tilts are at most one field apart, so the union is one interval.
    let mut pairs: Vec<Pair> = group
        .iter()
        .filter(|p| p.band.0 >= bottom - 1e-9 && p.band.1 <= top + 1e-9)
        .map(|p| p.pair)
        .collect();
    if pairs.is_empty() {
        return None;
    }
    pairs.sort_unstable();
    Some(Unit {
        standpoint,
        yaw,
        zoom,
        tilts,
        near,
        pairs,
    })
}

/// Every candidate unit of `problem` (module docs), with the caller's line-of-sight predicate
/// from a standpoint to a cell (`|_, _| true`: the paper's planar maps, where nothing hides a
/// cell).
pub fn candidate_units(
    problem: &ViewProblem,
    line_of_sight: impl Fn([f64; 2], [f64; 2]) -> bool,
) -> Result<Vec<Unit>> {
    check(problem)?;
    let c = &problem.camera;
    let max_zoom = problem
        .options
        .max_zoom
        .unwrap_or(c.max_zoom)
        .min(c.max_zoom);
    let mut units = Vec::new();
    for zoom in view_zooms(max_zoom) {
        let (hfov, vfov) = (c.hfov / zoom, c.vfov / zoom);
        let near = near_distance_for(problem, vfov);
        for (s, at) in problem.standpoints.iter().enumerate() {
            let mut seen = Vec::new();
            for (ci, class) in problem.classes.iter().enumerate() {
                let r = class.range_at(zoom);
                let (lo, hi) = (r.min, r.max);
                for (j, cell) in problem.cells.iter().enumerate() {
                    let d = (cell[0] - at[0]).hypot(cell[1] - at[1]);
                    if d < lo || d > hi || d < 1e-9 || !line_of_sight(*at, *cell) {
                        continue;
                    }
                    seen.push(Seen {
                        pair: Pair { class: ci, cell: j },
                        bearing: (cell[1] - at[1]).atan2(cell[0] - at[0]),
                        band: band(c.height, class.heights, d),
                        distance: d,
                    });
                }
            }
            // Neighbouring canonical directions often see the same pairs: one unit for each set.
            let mut distinct: std::collections::HashSet<(bool, Vec<Pair>)> = Default::default();
            for yaw in directions(&seen, hfov, problem.options.direction_step) {
                let in_view: Vec<&Seen> = seen
                    .iter()
                    .filter(|p| wrap_angle(p.bearing - yaw).abs() <= hfov / 2.0 + 1e-12)
                    .collect();
                for is_near in [false, true] {
                    let group: Vec<&&Seen> = in_view
                        .iter()
                        .filter(|p| (p.distance < near) == is_near)
                        .collect();
                    if let Some(unit) = unit_of(&group, s, yaw, zoom, is_near, vfov, c.tilt_limits)
                    {
                        if distinct.insert((is_near, unit.pairs.clone())) {
                            units.push(unit);
                        }
                    }
                }
            }
        }
    }
    Ok(units)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::{PlanOptions, SoughtClass};
    use crate::DetectionRange;
    use avs_robot::Camera;

    fn problem(heights: [f64; 2]) -> ViewProblem {
        let mut cells = Vec::new();
        for i in 0..8 {
            for j in 0..6 {
                cells.push([0.25 + 0.5 * i as f64, 0.25 + 0.5 * j as f64]);
            }
        }
        ViewProblem {
            cells,
            standpoints: vec![[2.0, 1.5], [0.5, 0.5]],
            classes: vec![SoughtClass {
                class: "book".into(),
                range: DetectionRange { min: 0.3, max: 4.0 },
                heights,
                unique: true,
                zoom_ranges: Vec::new(),
            }],
            camera: Camera {
                hfov: 47.5f64.to_radians(),
                vfov: 36.2f64.to_radians(),
                pan_limits: [-PI, PI],
                tilt_limits: [-0.8, 0.8],
                max_zoom: 13.0,
                height: 1.0,
            },
            options: PlanOptions::default(),
        }
    }

    #[test]
    fn the_near_distance_is_where_the_band_just_fits_the_vertical_field() {
        let p = problem([0.0, 1.5]);
        let d = near_distance(&p);
        let (a, b) = band(1.0, [0.0, 1.5], d);
        assert!((b - a - p.camera.vfov).abs() < 1e-6, "{d}");
        // A band at the camera's height fits anywhere: no extra tilts.
        assert_eq!(near_distance(&problem([1.0, 1.0])), 0.0);
    }

    #[test]
    fn the_tilt_rule_spans_a_tall_band_with_the_fewest_evenly_spaced_tilts() {
        let vfov = 0.6;
        let t = tilt_rule(-1.0, 0.5, vfov, [-2.0, 2.0]);
        assert_eq!(t.len(), 3);
        assert!((t[0] - vfov / 2.0 - -1.0).abs() < 1e-12);
        assert!((t[2] + vfov / 2.0 - 0.5).abs() < 1e-12);
        assert!((t[1] - t[0] - (t[2] - t[1])).abs() < 1e-12);
        // Beyond the limits the band is cut: the lowest tilt is the limit.
        let cut = tilt_rule(-3.0, 0.0, vfov, [-0.5, 0.5]);
        assert_eq!(cut[0], -0.5);
        assert_eq!(tilt_rule(0.0, 0.1, vfov, [-1.0, 1.0]).len(), 1);
    }

    #[test]
    fn every_pair_a_unit_claims_is_in_its_field_range_and_images() {
        let p = problem([0.0, 1.5]);
        let units = candidate_units(&p, |_, _| true).unwrap();
        assert!(units.iter().any(|u| u.near && u.images() > 1));
        let c = &p.camera;
        for u in &units {
            let at = p.standpoints[u.standpoint];
            for pair in &u.pairs {
                let cell = p.cells[pair.cell];
                let d = (cell[0] - at[0]).hypot(cell[1] - at[1]);
                assert!((0.3..=4.0).contains(&d));
                let bearing = (cell[1] - at[1]).atan2(cell[0] - at[0]);
                assert!(wrap_angle(bearing - u.yaw).abs() <= c.hfov / 2.0 + 1e-9);
                let (a, b) = band(c.height, [0.0, 1.5], d);
                let covered = |e: f64| u.tilts.iter().any(|t| (e - t).abs() <= c.vfov / 2.0 + 1e-9);
                // The band's ends and its middle are in some image.
                assert!(covered(a) && covered(b) && covered((a + b) / 2.0));
            }
        }
    }

    #[test]
    fn a_blocked_line_of_sight_hides_the_cell() {
        let p = problem([0.5, 1.0]);
        let all = candidate_units(&p, |_, _| true).unwrap();
        let left_hidden = candidate_units(&p, |_, cell| cell[0] > 2.0).unwrap();
        assert!(all
            .iter()
            .any(|u| u.pairs.iter().any(|q| p.cells[q.cell][0] < 2.0)));
        assert!(left_hidden
            .iter()
            .all(|u| u.pairs.iter().all(|q| p.cells[q.cell][0] > 2.0)));
    }

    #[test]
    fn bad_numbers_are_errors_naming_the_field() {
        let mut p = problem([0.5, 1.0]);
        p.cells[3][0] = f64::NAN;
        assert!(candidate_units(&p, |_, _| true)
            .unwrap_err()
            .to_string()
            .contains("cells"));
        let mut p = problem([0.5, 1.0]);
        p.options.k = 0;
        assert!(candidate_units(&p, |_, _| true)
            .unwrap_err()
            .to_string()
            .contains("options.k"));
        let mut p = problem([0.5, 1.0]);
        p.options.direction_step = Some(1e-300);
        // A tiny step is capped, not a hang.
        assert!(candidate_units(&p, |_, _| true).is_ok());
    }
}
