//! The zoom pipeline's sensing measured, not assumed (issue 21): per class, how often one look
//! — the three-step search (`avs_view::zoom::three_step_search`) from an unzoomed image —
//! recognises the object at each distance in front of the simulated camera, and how often it
//! recognises the class where nothing of it is. The agent then plans its views within the
//! distances where a look finds the object at least half the time and runs its view-cone
//! sessions with the measured miss and false-alarm rates ([`avs_agent::MeasuredSensing`]),
//! instead of the knowledge's hand-set `detection_range` and `sensor`.
//!
//! ## Protocol
//! For each non-landmark class of the knowledge: the object (its knowledge `size`, a box)
//! at distances 0.25, 0.5, … 6 m along the optical axis, at the camera's height, turned any
//! way (its yaw uniform: a robot meets objects from every side, and the simulator's camera
//! sees the side the recogniser does best on, `avs_sim::image::BoxObject::seen_face`), off
//! the axis by up to a quarter of the half field, against an office
//! background (clutter 1) 0.5–2 m behind it; `looks` looks per distance; and the same at every
//! zoom level of the camera with the distances times the zoom (a zoomed look's range is
//! measured too: it is not the zoom times the unzoomed one, a farther scene being busier). A look finds the
//! object when it recognises the class within [`FOUND_WITHIN`] of the face's centre. The
//! range is the run of distances around the best one where the share found is at least ½,
//! to where the share crosses ½ (linear between the distances measured: at zoom 4 they are
//! 1 m apart, the whole range of a marker);
//! the miss rate is one minus the mean share found over it. False alarms: `looks` looks per
//! class at empty scenes (a background 1–6 m away), the share that recognised the class.
//! A class whose looks never reach ½ keeps the knowledge's sensing (it is left out). The
//! shares themselves are kept in the sensing too (with the looks they were counted from): a
//! verifier weighs a look by the share measured where it is taken.
//!
//! ## Repeated looks
//! Each look is taken a second time on the same scene — the same object, side, distance and
//! background, a new image — from a stream of its own ([`REPEAT_STREAM`]), so the first
//! looks, and the shares and ranges, are unchanged by it. The sensing's
//! `repeat_correlation` is the correlation of a look's outcome with its repeat's, pooled
//! over every zoom level and distance (the moment estimate of the intraclass correlation,
//! each cell centred on its own share): how much a second look from one vantage point says
//! what the first said.

use avs_agent::MeasuredSensing;
use avs_format::knowledge::Knowledge;
use avs_map::grid::OccupancyGrid;
use avs_robot::{
    ActionFailure, ActionResult, AttentionReport, Camera, FailureReason, ImageGeometry, MapUpdate,
    MoveReport, Point3, Pose2D, RecognitionReport, Robot, ViewCone, ViewReport,
};
use avs_sim::image::{attention, recognition, Background, BoxObject, ClassAppearance, SceneObject};
use avs_sim::{ImageModel, ImageScene};
use avs_view::zoom::{three_step_search, ObjectModel, ZoomConfig};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

/// A look found the object when it recognised the class within this of the face's centre,
/// metres.
pub const FOUND_WITHIN: f64 = 0.3;

/// The distances looked from at `zoom`, metres: 0.25, 0.5, … 6 m times the zoom.
fn distances(zoom: f64) -> Vec<f64> {
    (1..=24).map(|i| 0.25 * f64::from(i) * zoom).collect()
}

/// A robot standing at the origin facing +x in front of one fixed scene: its images are the
/// simulator's ([`avs_sim::image`]); it never moves.
struct SceneRobot<'a> {
    scene: ImageScene,
    /// A one-cell map: the pipeline never asks for one.
    grid: &'a OccupancyGrid,
    camera: Camera,
    image: ImageGeometry,
    model: &'a ImageModel,
    appearances: &'a [ClassAppearance],
    rng: ChaCha8Rng,
}

impl Robot for SceneRobot<'_> {
    fn pose(&self) -> Pose2D {
        Pose2D::new(0.0, 0.0, 0.0)
    }

    fn camera(&self) -> Camera {
        self.camera
    }

    fn odometry(&self) -> f64 {
        0.0
    }

    fn move_to(&mut self, _goal: Pose2D) -> ActionResult<MoveReport> {
        Ok(MoveReport {
            pose: self.pose(),
            travelled: 0.0,
        })
    }

    fn map_update(&mut self) -> MapUpdate {
        MapUpdate {
            grid: self.grid.clone(),
            newly_known: 0,
            doors: Vec::new(),
        }
    }

    fn process_view_cone(
        &mut self,
        _cone: &ViewCone,
        _classes: &[String],
    ) -> ActionResult<ViewReport> {
        Err(ActionFailure::new(
            FailureReason::Unsupported,
            "the calibration robot only takes zoom-pipeline images",
        ))
    }

    fn attention(&mut self, cone: &ViewCone, classes: &[String]) -> ActionResult<AttentionReport> {
        let votes = attention(
            self.model,
            &self.scene,
            &self.camera,
            cone,
            &self.image,
            classes,
            &mut self.rng,
        );
        Ok(AttentionReport {
            pose: self.pose(),
            travelled: 0.0,
            image: self.image,
            votes,
            seconds: 0.0,
        })
    }

    fn recognise(&mut self, cone: &ViewCone, class: &str) -> ActionResult<RecognitionReport> {
        let Some(appearance) = self.appearances.iter().find(|a| a.name == class) else {
            return Err(ActionFailure::new(
                FailureReason::InvalidRequest,
                format!("unknown class `{class}`"),
            ));
        };
        let seen = recognition(
            self.model,
            &self.scene,
            &self.camera,
            cone,
            &self.image,
            appearance,
            &mut self.rng,
        );
        Ok(RecognitionReport {
            pose: self.pose(),
            travelled: 0.0,
            image: self.image,
            class: class.to_string(),
            model_features: seen.model_features,
            matches: seen.matches,
            seconds: 0.0,
        })
    }
}

/// The share of looks at one zoom that found the object, per distance (the agent's type: the
/// measurement is kept in the sensing it gives, [`MeasuredSensing::found_by_zoom`]).
pub type ZoomMeasurement = avs_agent::FoundByDistance;

/// One class's measurement: the share of looks that found the object at each distance, per
/// zoom level of the camera ([`avs_view::view_zooms`]), and the sensing derived from it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ClassMeasurement {
    /// The class.
    pub class: String,
    /// Per zoom level, zoom 1 first.
    pub by_zoom: Vec<ZoomMeasurement>,
    /// The share of looks at empty scenes that recognised the class.
    pub false_alarms: f64,
    /// The sensing derived (module docs); `None` when no distance reaches ½.
    pub sensing: Option<MeasuredSensing>,
}

/// Measure every non-landmark class of `knowledge` with `camera`, the simulator's image
/// `model` and the pipeline's `config` (module docs), `looks` looks per distance, seeded.
pub fn measure(
    knowledge: &Knowledge,
    camera: &Camera,
    model: &ImageModel,
    config: &ZoomConfig,
    looks: usize,
    seed: u64,
) -> Result<Vec<ClassMeasurement>, crate::EvalError> {
    let grid = OccupancyGrid::new(1, 1, 1.0, [0.0, 0.0], avs_map::grid::Cell::Unknown)
        .map_err(|e| crate::EvalError::Sim(e.to_string()))?;
    let appearances: Vec<ClassAppearance> = knowledge
        .object_classes
        .iter()
        .filter(|c| !c.landmark)
        .map(|c| ClassAppearance {
            name: c.name.clone(),
            width: c.size[0],
            height: c.size[2],
        })
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    // The repeated looks draw from a stream of their own: the first looks, and so the shares
    // and ranges, are those measured before repeats were.
    let mut again = ChaCha8Rng::seed_from_u64(seed);
    again.set_stream(REPEAT_STREAM);
    let mut out = Vec::new();
    for class in knowledge.object_classes.iter().filter(|c| !c.landmark) {
        let models = [ObjectModel::from_class(class)];
        let look =
            |objects: Vec<SceneObject>, depth: f64, cone: &ViewCone, rng: &mut ChaCha8Rng| {
                let mut robot = SceneRobot {
                    scene: ImageScene {
                        objects,
                        background: Background {
                            clutter: 1.0,
                            depth,
                        },
                    },
                    grid: &grid,
                    camera: *camera,
                    image: config.image,
                    model,
                    appearances: &appearances,
                    rng: ChaCha8Rng::seed_from_u64(rng.gen()),
                };
                three_step_search(&mut robot, cone, &models, config)
                    .map(|o| o.found)
                    .unwrap_or_default()
            };
        let mut by_zoom = Vec::new();
        // Per look, whether it and its repeat found the object, with its cell (a zoom level
        // and a distance).
        let mut pairs: Vec<(bool, bool, usize)> = Vec::new();
        let mut cells = 0usize;
        // A camera at the origin looking along +x at `zoom`.
        let ahead = |zoom: f64| ViewCone::new(Pose2D::new(0.0, 0.0, 0.0), 0.0, 0.0, zoom);
        for zoom in avs_view::view_zooms(camera.max_zoom) {
            let cone = ahead(zoom);
            let ds = distances(zoom);
            let mut found = Vec::with_capacity(ds.len());
            for &d in &ds {
                let mut hits = 0usize;
                for _ in 0..looks {
                    let mut sym = |x: f64| (2.0 * rng.gen::<f64>() - 1.0) * x;
                    let (hfov, vfov) = (camera.hfov / zoom, camera.vfov / zoom);
                    let centre = Point3 {
                        x: d,
                        y: sym(0.25 * d * (hfov / 2.0).tan()),
                        z: camera.height + sym(0.25 * d * (vfov / 2.0).tan()),
                    };
                    let object = BoxObject {
                        class: class.name.clone(),
                        base: Point3 {
                            z: centre.z - class.size[2] / 2.0,
                            ..centre
                        },
                        yaw: rng.gen_range(-PI..PI),
                        size: class.size,
                        lookalike: false,
                    };
                    let depth = d + rng.gen_range(0.5..2.0);
                    let faces: Vec<SceneObject> = object
                        .seen_face(model, camera, &cone, &config.image)
                        .into_iter()
                        .collect();
                    let found_it = |seen: Vec<avs_view::zoom::Recognised>| {
                        seen.iter().any(|r| {
                            r.class == class.name
                                && (r.position.x - centre.x)
                                    .hypot(r.position.y - centre.y)
                                    .hypot(r.position.z - centre.z)
                                    <= FOUND_WITHIN
                        })
                    };
                    let hit = found_it(look(faces.clone(), depth, &cone, &mut rng));
                    // The same look again: the same scene, from the same vantage point.
                    let repeat = found_it(look(faces, depth, &cone, &mut again));
                    pairs.push((hit, repeat, cells));
                    hits += usize::from(hit);
                }
                found.push(hits as f64 / looks.max(1) as f64);
                cells += 1;
            }
            by_zoom.push(ZoomMeasurement {
                zoom,
                distances: ds,
                found,
                looks,
            });
        }
        let mut false_hits = 0usize;
        for _ in 0..looks {
            let depth = rng.gen_range(1.0..6.0);
            false_hits += usize::from(!look(Vec::new(), depth, &ahead(1.0), &mut rng).is_empty());
        }
        let false_alarms = false_hits as f64 / looks.max(1) as f64;
        let repeat_correlation = repeat_correlation(&pairs, cells);
        let sensing = derive(&class.name, &by_zoom, false_alarms).map(|m| MeasuredSensing {
            repeat_correlation,
            ..m
        });
        out.push(ClassMeasurement {
            class: class.name.clone(),
            by_zoom,
            false_alarms,
            sensing,
        });
    }
    Ok(out)
}

/// The `ChaCha8Rng` stream (of the calibration's seed) the repeated looks draw from.
pub const REPEAT_STREAM: u64 = 1;

/// The correlation of a look's outcome and its repeat's from the same vantage point (module
/// docs, "Repeated looks"): pooled over the cells (a zoom level and a distance), `Σ (h₁ − m)
/// (h₂ − m) / Σ m (1 − m)`, with `m` the share of the cell's looks and repeats that found the
/// object (the moment estimate of the intraclass correlation); inside [0, 0.99], 0 when no
/// cell has both outcomes.
fn repeat_correlation(pairs: &[(bool, bool, usize)], cells: usize) -> f64 {
    let mut share = vec![(0usize, 0usize); cells];
    for &(a, b, c) in pairs {
        share[c].0 += usize::from(a) + usize::from(b);
        share[c].1 += 2;
    }
    let m = |c: usize| share[c].0 as f64 / share[c].1.max(1) as f64;
    let (mut num, mut den) = (0.0, 0.0);
    for &(a, b, c) in pairs {
        let mc = m(c);
        num += (f64::from(u8::from(a)) - mc) * (f64::from(u8::from(b)) - mc);
        den += mc * (1.0 - mc);
    }
    if den > 0.0 {
        (num / den).clamp(0.0, 0.99)
    } else {
        0.0
    }
}

/// The run of distances around the best one where the share found is at least ½, its ends
/// moved out to where the share crosses ½ (linear between the measured distances next to
/// them), and the mean share over the run's measured distances; `None` when no distance
/// reaches ½.
fn run_at_half(ds: &[f64], found: &[f64]) -> Option<([f64; 2], f64)> {
    let best = (0..found.len()).max_by(|&a, &b| found[a].total_cmp(&found[b]).then(b.cmp(&a)))?;
    if found[best] < 0.5 {
        return None;
    }
    let mut lo = best;
    while lo > 0 && found[lo - 1] >= 0.5 {
        lo -= 1;
    }
    let mut hi = best;
    while hi + 1 < found.len() && found[hi + 1] >= 0.5 {
        hi += 1;
    }
    // Where the share falls to ½ between measured distance `i` (≥ ½) and `j` (< ½).
    let crossing =
        |i: usize, j: usize| ds[i] + (ds[j] - ds[i]) * (found[i] - 0.5) / (found[i] - found[j]);
    let near = if lo > 0 { crossing(lo, lo - 1) } else { ds[lo] };
    let far = if hi + 1 < found.len() {
        crossing(hi, hi + 1)
    } else {
        ds[hi]
    };
    let mean = found[lo..=hi].iter().sum::<f64>() / (hi - lo + 1) as f64;
    Some(([near, far], mean))
}

/// The sensing of one class from its measurements (module docs): the unzoomed run decides the
/// range and the miss rate, the zoomed runs their own ranges.
fn derive(class: &str, by_zoom: &[ZoomMeasurement], false_alarms: f64) -> Option<MeasuredSensing> {
    let first = by_zoom.first()?;
    let (range, mean) = run_at_half(&first.distances, &first.found)?;
    Some(MeasuredSensing {
        class: class.to_string(),
        detection_range: range,
        ranges_by_zoom: by_zoom
            .iter()
            .filter_map(|m| run_at_half(&m.distances, &m.found).map(|(r, _)| (m.zoom, r)))
            .collect(),
        false_negative: (1.0 - mean).clamp(0.01, 0.99),
        false_positive: false_alarms.clamp(0.001, 0.99),
        found_by_zoom: by_zoom.to_vec(),
        repeat_correlation: 0.0,
    })
}

/// The measured sensing of `knowledge`'s classes for an agent (the classes whose looks reach
/// ½ somewhere), with the simulator's default image model and `config`'s image: what the
/// episode runner gives an agent whose looks run the zoom pipeline.
pub fn measured_sensing(
    knowledge: &Knowledge,
    camera: &Camera,
    config: &ZoomConfig,
) -> Result<Vec<MeasuredSensing>, crate::EvalError> {
    Ok(
        measure(knowledge, camera, &ImageModel::default(), config, 20, 1)?
            .into_iter()
            .filter_map(|m| m.sensing)
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pairs whose repeat copies the first outcome with probability ρ and is a new draw
    /// otherwise have outcome correlation ρ exactly (P(both) = ρ m + (1 − ρ) m²): the
    /// estimate finds it whatever the cells' shares; copies throughout give the clamp 0.99.
    #[test]
    fn the_repeat_correlation_is_the_correlation_the_pairs_were_drawn_with() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let shares = [0.2, 0.5, 0.8, 0.95];
        let draw = |rho: f64, rng: &mut ChaCha8Rng| {
            let mut pairs = Vec::new();
            for (c, &m) in shares.iter().enumerate() {
                for _ in 0..4000 {
                    let a = rng.gen::<f64>() < m;
                    let b = if rng.gen::<f64>() < rho {
                        a
                    } else {
                        rng.gen::<f64>() < m
                    };
                    pairs.push((a, b, c));
                }
            }
            repeat_correlation(&pairs, shares.len())
        };
        for rho in [0.0, 0.1, 0.3, 0.6] {
            let est = draw(rho, &mut rng);
            assert!((est - rho).abs() < 0.03, "ρ {rho}: estimated {est}");
        }
        assert_eq!(draw(1.0, &mut rng), 0.99);
        // A cell every look finds (or none does) says nothing of the correlation.
        assert_eq!(
            repeat_correlation(&[(true, true, 0), (true, true, 0)], 1),
            0.0
        );
    }

    #[test]
    fn the_range_is_the_run_around_the_best_distance_at_or_above_one_half_to_where_it_crosses_one_half(
    ) {
        let at = |zoom: f64, found: &[f64]| ZoomMeasurement {
            zoom,
            distances: [0.5, 1.0, 1.5, 2.0, 2.5, 3.0].map(|d| d * zoom).to_vec(),
            found: found.to_vec(),
            looks: 20,
        };
        let m = [
            at(1.0, &[0.4, 0.6, 0.9, 0.7, 0.3, 0.6]),
            at(2.0, &[0.9, 0.8, 0.2, 0.1, 0.0, 0.0]),
            at(4.0, &[0.1; 6]),
        ];
        let s = derive("mug", &m, 0.02).unwrap();
        // Zoom 1: 0.6 at 1 m, 0.4 at 0.5 m: ½ at 0.75 m; 0.7 at 2 m, 0.3 at 2.5 m: ½ at 2.25 m.
        // Zoom 2: from the first distance (1 m) to ½ between 0.8 at 2 m and 0.2 at 3 m.
        let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() + (a[1] - b[1]).abs() < 1e-12;
        assert!(close(s.detection_range, [0.75, 2.25]), "{s:?}");
        assert_eq!(s.ranges_by_zoom.len(), 2, "{s:?}");
        assert!(close(s.ranges_by_zoom[0].1, [0.75, 2.25]), "{s:?}");
        assert_eq!(s.ranges_by_zoom[1].0, 2.0);
        assert!(
            close(s.ranges_by_zoom[1].1, [1.0, 2.0 + 1.0 * 0.3 / 0.6]),
            "{s:?}"
        );
        assert!((s.false_negative - (1.0 - (0.6 + 0.9 + 0.7) / 3.0)).abs() < 1e-12);
        assert_eq!(s.false_positive, 0.02);
        assert!(derive("mug", &[at(1.0, &[0.1; 6])], 0.0).is_none());
    }
}
