//! The simulated object detector: which objects a view cone reports, with what estimated pose
//! and confidence, from the ground truth and the knowledge file's sensor model.
//!
//! # The model
//!
//! A view is a camera at `eye` looking along a yaw and tilt with fields of view already divided
//! by the zoom `z` ([`CameraView`]). For each requested class `c` with detection range
//! `[d_min, d_max]` (the knowledge file's `detection_range`, at zoom 1):
//!
//! * **True detections.** Every object of class `c` inside the field of view whose line of
//!   sight is not blocked by a wall or closed door ([`World::objects_in_view`]) is reported with
//!   probability
//!   `P_d = (1 − FN) · f_d(d) · f_a(b, e)`,
//!   where `FN` is the knowledge's `sensor.false_negative` (Aydemir et al. 2011, §IV: "a false
//!   negative probability of 0.2 and a false positive probability of 0.05"). Occluded objects
//!   are never reported.
//! * **Distance.** Zoom `z` magnifies the object by `z` (Sjöö, Gálvez López et al., §3.4
//!   eq. 1: the angle an object subtends is `2 atan(W / 2D)`, ≈ `W / D`), so the distance interval in which the
//!   detector works becomes `[z·d_min, z·d_max]` (§2.1.3: an object is only searched for inside
//!   its distance interval). Inside it `f_d = 1`. Outside it the apparent area, in pixels, of
//!   the object relative to the limit falls with the square of the distance ratio, and so does
//!   the detector's evidence (the RFCH votes of §3.2 are counted over image cells):
//!   `f_d = (z·d_max / d)²` beyond, `f_d = (d / (z·d_min))²` closer (the object overflows the
//!   image). Our choice; the papers give no curve.
//! * **Angle off the optical axis.** With `u = max(|b| / (hfov/2), |e| / (vfov/2))` ∈ [0, 1]
//!   (`b`, `e` the bearing and elevation off the axis), `f_a = 1 − κ u²`, `κ` =
//!   [`DetectorConfig::angle_falloff`] (0.5: at the image border an object is half as likely to
//!   be found, being partly cut off and distorted). Our choice.
//! * **False positives.** When no visible object of class `c` is in the field of view, the
//!   detector reports one spurious `c` with probability `FP` = `sensor.false_positive` ×
//!   [`DetectorConfig::false_positive_scale`] — exactly the `P(detection | no object in view)`
//!   of the POMDP's observation model (Aydemir et al. 2011, §IV), so the planner's model
//!   and the simulator agree. The spurious detection lies at a uniformly random bearing and
//!   elevation in the view and a uniformly random distance in the working interval.
//! * **Distractors.** A visible object with `role: distractor` in view fires as a false
//!   positive of each requested class other than its own that is not a landmark class, with
//!   probability `ρ · f_d(d) · f_a(b, e)` (the requested class's distance interval), `ρ` =
//!   [`DetectorConfig::distractor_rate`] (0.25 by default, our judgement: a look-alike in clear
//!   view is mistaken for the target in one view of four); within the requested class's
//!   `recognition_range` (× zoom), where the image shows the detail a recogniser needs
//!   (Sjöö et al., §3.3: SIFT matching on zoomed views), with `ρ_r` =
//!   [`DetectorConfig::recognised_distractor_rate`] (0.05) instead. Its estimated pose is the
//!   distractor's, with the noise below — it looks just like a real detection.
//! * **Pose noise.** The estimated position is computed as a real robot would: from an
//!   estimated range and the bearing in the image. Range error is normal with standard
//!   deviation `σ_r(d) = σ₀ + k·d` (Sjöö, Gálvez López et al., §4.2 and Fig. 9: distance
//!   estimates deteriorate with distance), bearing and elevation errors independent normal
//!   with `σ_b`. Defaults `σ₀ = 0.03 m`, `k = 0.05`,
//!   `σ_b = 0.015 rad`.
//! * **Confidence.** The detector's confidence is `P_d` evaluated at the *reported* geometry
//!   (estimated range and bearing) — the same formula for true and false detections, so the
//!   confidence carries no ground truth beyond what the geometry says.
//! * **Correlated firing.** [`Detector::detect_scored`] leaves the decision whether a visible
//!   object of a non-landmark class (or a distractor) fires to a correlated detector
//!   (`DetectorKind::Correlated` of [`crate::sim_robot`], scores from
//!   [`crate::world_scores`]); everything else above stays as it is.
//!
//! All randomness comes from the caller's `rand_chacha` generator (the robot's), so the same
//! seed and the same requests give the same detections.

use crate::world::{wrap_angle, CameraView, World};
use avs_format::environment::ObjectRole;
use avs_format::knowledge::Knowledge;
use avs_map::grid::OccupancyGrid;
use avs_robot::{Detection, Point3};
use rand::Rng;
use rand_distr::{Distribution, Normal};

/// Parameters of the simulated detector that the knowledge file does not give.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DetectorConfig {
    /// κ in `f_a = 1 − κ u²`, in [0, 1].
    pub angle_falloff: f64,
    /// ρ: probability that a distractor in clear view fires as a requested class, in [0, 1].
    pub distractor_rate: f64,
    /// ρ_r: the same within the requested class's recognition range (× zoom), where the image
    /// shows enough detail to tell a look-alike apart, in [0, 1].
    pub recognised_distractor_rate: f64,
    /// Multiplies the knowledge's `sensor.false_positive` (2 doubles the false alarms), ≥ 0.
    pub false_positive_scale: f64,
    /// σ₀, metres, ≥ 0.
    pub range_noise_base: f64,
    /// k (metres of range error per metre of distance), ≥ 0.
    pub range_noise_per_m: f64,
    /// σ_b, radians, ≥ 0.
    pub bearing_noise: f64,
}

impl Default for DetectorConfig {
    fn default() -> Self {
        Self {
            angle_falloff: 0.5,
            distractor_rate: 0.25,
            recognised_distractor_rate: 0.05,
            false_positive_scale: 1.0,
            range_noise_base: 0.03,
            range_noise_per_m: 0.05,
            bearing_noise: 0.015,
        }
    }
}

/// Errors of the detector: bad configuration or requests.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SensorError {
    /// A configuration field is out of range.
    #[error("robot config field `{field}` = {value}: expected {expected}")]
    Config {
        /// The field.
        field: &'static str,
        /// Its value.
        value: f64,
        /// What is expected.
        expected: &'static str,
    },
    /// A requested class is not among the knowledge's `object_classes`.
    #[error("unknown object class `{0}`: expected one of the knowledge file's object_classes")]
    UnknownClass(String),
    /// A field of the simulated robot's configuration that is not a number is invalid (e.g. a
    /// door event naming a door the environment does not have).
    #[error("robot config field `{field}`: {message}")]
    Robot {
        /// Dotted path of the field, e.g. `door_events[0].door`.
        field: String,
        /// What is wrong and what is expected.
        message: String,
    },
    /// The knowledge's sensor model is out of range.
    #[error("knowledge field `sensor.{field}` = {value}: expected a probability in [0, 1)")]
    Knowledge {
        /// The field.
        field: &'static str,
        /// Its value.
        value: f64,
    },
}

impl DetectorConfig {
    /// Check every field; the error names the field and what is expected.
    pub fn validate(&self) -> Result<(), SensorError> {
        let unit = |field, value: f64| {
            if (0.0..=1.0).contains(&value) {
                Ok(())
            } else {
                Err(SensorError::Config {
                    field,
                    value,
                    expected: "a number in [0, 1]",
                })
            }
        };
        let nonneg = |field, value: f64| {
            if value.is_finite() && value >= 0.0 {
                Ok(())
            } else {
                Err(SensorError::Config {
                    field,
                    value,
                    expected: "a finite number ≥ 0",
                })
            }
        };
        unit("angle_falloff", self.angle_falloff)?;
        unit("distractor_rate", self.distractor_rate)?;
        unit(
            "recognised_distractor_rate",
            self.recognised_distractor_rate,
        )?;
        nonneg("false_positive_scale", self.false_positive_scale)?;
        nonneg("range_noise_base", self.range_noise_base)?;
        nonneg("range_noise_per_m", self.range_noise_per_m)?;
        nonneg("bearing_noise", self.bearing_noise)
    }
}

/// `f_d`: the distance factor for distance `d` and detection range `[d_min, d_max]` at zoom 1,
/// seen at zoom `zoom` (see the module docs).
pub fn distance_factor(d: f64, range: [f64; 2], zoom: f64) -> f64 {
    let lo = range[0].max(0.0) * zoom;
    let hi = range[1] * zoom;
    if !(d.is_finite() && hi.is_finite() && hi > 0.0) {
        return 0.0;
    }
    if d > hi {
        (hi / d).powi(2)
    } else if d < lo {
        (d / lo).powi(2)
    } else {
        1.0
    }
}

/// `f_a`: the off-axis factor for bearing `b` and elevation `e` off the optical axis in a view
/// with fields of view `hfov`, `vfov` (radians), falloff `kappa` (see the module docs).
pub fn angle_factor(b: f64, e: f64, hfov: f64, vfov: f64, kappa: f64) -> f64 {
    let u = (b.abs() / (hfov / 2.0)).max(e.abs() / (vfov / 2.0));
    if !u.is_finite() {
        return 0.0;
    }
    (1.0 - kappa * u.min(1.0).powi(2)).max(0.0)
}

/// A correlated detector's decision whether the object at an index of the environment's
/// `objects` fires as a class ([`Detector::detect_scored`]).
type Fires<'a> = &'a mut dyn FnMut(&str, usize) -> bool;

/// The simulated object detector: the knowledge's sensor model plus a [`DetectorConfig`].
#[derive(Debug, Clone)]
pub struct Detector {
    knowledge: Knowledge,
    config: DetectorConfig,
}

impl Detector {
    /// A detector for `knowledge`'s classes and sensor model; checks both.
    pub fn new(knowledge: Knowledge, config: DetectorConfig) -> Result<Self, SensorError> {
        config.validate()?;
        for (field, value) in [
            ("false_negative", knowledge.sensor.false_negative),
            ("false_positive", knowledge.sensor.false_positive),
        ] {
            if !(0.0..1.0).contains(&value) {
                return Err(SensorError::Knowledge { field, value });
            }
        }
        Ok(Self { knowledge, config })
    }

    /// The configuration.
    pub fn config(&self) -> &DetectorConfig {
        &self.config
    }

    /// The knowledge the detector works with.
    pub fn knowledge(&self) -> &Knowledge {
        &self.knowledge
    }

    /// `P_d` for class `range` at distance `d` and off-axis angles `b`, `e` in `view` (zoom
    /// `zoom`).
    fn p_detect(
        &self,
        range: [f64; 2],
        d: f64,
        b: f64,
        e: f64,
        view: &CameraView,
        zoom: f64,
    ) -> f64 {
        (1.0 - self.knowledge.sensor.false_negative)
            * distance_factor(d, range, zoom)
            * angle_factor(b, e, view.hfov, view.vfov, self.config.angle_falloff)
    }

    /// Run the detector for `classes` on `view` (fields of view already divided by `zoom`) in
    /// `world`, drawing from `rng`.
    pub fn detect<R: Rng>(
        &self,
        world: &World,
        view: &CameraView,
        zoom: f64,
        classes: &[String],
        rng: &mut R,
    ) -> Result<Vec<Detection>, SensorError> {
        self.detect_through(world, &world.walls, view, zoom, classes, rng)
    }

    /// [`Detector::detect`] with occlusion by `walls` (a grid of the world's geometry in which
    /// doors may have opened or closed since the world was built, e.g.
    /// [`crate::SimRobot::walls`]) instead of [`World::walls`].
    pub fn detect_through<R: Rng>(
        &self,
        world: &World,
        walls: &OccupancyGrid,
        view: &CameraView,
        zoom: f64,
        classes: &[String],
        rng: &mut R,
    ) -> Result<Vec<Detection>, SensorError> {
        self.detect_impl(world, walls, view, zoom, classes, rng, None)
    }

    /// [`Detector::detect_through`] with the firing of objects decided by a correlated
    /// detector: for each requested class `c` that is not a landmark class, a visible object
    /// in view that is of class `c` or a distractor is reported when `fires(c, i)` (`i` its
    /// index in the environment's `objects`) instead of with probability `P_d` (or `ρ`).
    /// Everything else is as in [`Detector::detect_through`] and draws from `rng` in the same
    /// way: landmark classes, the pose noise of a reported object, its geometric confidence,
    /// and the spurious false positive when no visible object of `c` is in view.
    #[allow(clippy::too_many_arguments)]
    pub fn detect_scored<R: Rng>(
        &self,
        world: &World,
        walls: &OccupancyGrid,
        view: &CameraView,
        zoom: f64,
        classes: &[String],
        rng: &mut R,
        fires: &mut dyn FnMut(&str, usize) -> bool,
    ) -> Result<Vec<Detection>, SensorError> {
        self.detect_impl(world, walls, view, zoom, classes, rng, Some(fires))
    }

    #[allow(clippy::too_many_arguments)]
    fn detect_impl<R: Rng>(
        &self,
        world: &World,
        walls: &OccupancyGrid,
        view: &CameraView,
        zoom: f64,
        classes: &[String],
        rng: &mut R,
        mut fires: Option<Fires<'_>>,
    ) -> Result<Vec<Detection>, SensorError> {
        let mut ranges = Vec::with_capacity(classes.len());
        for c in classes {
            let oc = self
                .knowledge
                .class(c)
                .ok_or_else(|| SensorError::UnknownClass(c.clone()))?;
            ranges.push((oc.detection_range, oc.landmark, oc.recognition_range));
        }
        let seen = world.objects_in_view_through(walls, view);
        let objects = &world.env.objects;
        let fp = (self.knowledge.sensor.false_positive * self.config.false_positive_scale).min(1.0);
        let mut out = Vec::new();
        for (c, &(range, landmark, recognition)) in classes.iter().zip(&ranges) {
            let mut any_in_view = false;
            for v in seen.iter().filter(|v| v.visible) {
                let o = &objects[v.index];
                let p = if o.class == *c {
                    any_in_view = true;
                    self.p_detect(range, v.distance, v.bearing, v.elevation, view, zoom)
                } else if o.role == ObjectRole::Distractor && !landmark {
                    // Inside the recognition range (scaled by the zoom) the image has the
                    // detail that tells a look-alike apart (Sjöö et al., §3.3).
                    let close =
                        v.distance >= zoom * recognition[0] && v.distance <= zoom * recognition[1];
                    let rho = if close {
                        self.config.recognised_distractor_rate
                    } else {
                        self.config.distractor_rate
                    };
                    rho * distance_factor(v.distance, range, zoom)
                        * angle_factor(
                            v.bearing,
                            v.elevation,
                            view.hfov,
                            view.vfov,
                            self.config.angle_falloff,
                        )
                } else {
                    continue;
                };
                let reported = match fires.as_mut() {
                    Some(fires) if !landmark => fires(c, v.index),
                    _ => rng.gen::<f64>() < p,
                };
                if reported {
                    let top = o.pose.z + o.size[2] / 2.0;
                    out.push(self.observe(c, range, [o.pose.x, o.pose.y, top], view, zoom, rng));
                }
            }
            if !any_in_view && rng.gen::<f64>() < fp {
                let b = (rng.gen::<f64>() - 0.5) * view.hfov;
                let e = (rng.gen::<f64>() - 0.5) * view.vfov;
                let lo = range[0].max(0.0) * zoom;
                let d = lo + rng.gen::<f64>() * (range[1] * zoom - lo).max(0.0);
                let (yaw, el) = (view.yaw + b, view.tilt + e);
                let g = d * el.cos();
                let p = [
                    view.eye[0] + g * yaw.cos(),
                    view.eye[1] + g * yaw.sin(),
                    (view.eye[2] + d * el.sin()).max(0.0),
                ];
                out.push(self.observe(c, range, p, view, zoom, rng));
            }
        }
        Ok(out)
    }

    /// A detection of class `c` of something at `p` (x, y, height), seen with range and
    /// bearing noise; confidence from the reported geometry.
    fn observe<R: Rng>(
        &self,
        c: &str,
        range: [f64; 2],
        p: [f64; 3],
        view: &CameraView,
        zoom: f64,
        rng: &mut R,
    ) -> Detection {
        let (dx, dy, dz) = (p[0] - view.eye[0], p[1] - view.eye[1], p[2] - view.eye[2]);
        let ground = dx.hypot(dy);
        let d = ground.hypot(dz);
        let yaw = dy.atan2(dx);
        let el = dz.atan2(ground);
        let cfg = &self.config;
        let sr = cfg.range_noise_base + cfg.range_noise_per_m * d;
        let d_est = (d + gauss(rng, sr)).max(0.05);
        let yaw_est = yaw + gauss(rng, cfg.bearing_noise);
        let el_est = el + gauss(rng, cfg.bearing_noise);
        let g = d_est * el_est.cos();
        let pose = Point3 {
            x: view.eye[0] + g * yaw_est.cos(),
            y: view.eye[1] + g * yaw_est.sin(),
            z: (view.eye[2] + d_est * el_est.sin()).max(0.0),
        };
        let b = wrap_angle(yaw_est - view.yaw);
        let e = el_est - view.tilt;
        let confidence = self.p_detect(range, d_est, b, e, view, zoom).max(1e-6);
        Detection {
            class: c.to_string(),
            pose,
            confidence,
        }
    }
}

/// One draw from N(0, σ²); 0 when σ is 0.
fn gauss<R: Rng>(rng: &mut R, sigma: f64) -> f64 {
    match Normal::new(0.0, sigma) {
        Ok(n) if sigma > 0.0 => n.sample(rng),
        _ => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_factor_is_one_inside_the_range_and_falls_quadratically_outside() {
        assert_eq!(distance_factor(2.0, [0.5, 4.0], 1.0), 1.0);
        assert!((distance_factor(8.0, [0.5, 4.0], 1.0) - 0.25).abs() < 1e-12);
        assert!((distance_factor(0.25, [0.5, 4.0], 1.0) - 0.25).abs() < 1e-12);
        // Zoom 2 doubles the working interval.
        assert_eq!(distance_factor(8.0, [0.5, 4.0], 2.0), 1.0);
        assert_eq!(distance_factor(f64::NAN, [0.5, 4.0], 1.0), 0.0);
    }

    #[test]
    fn angle_factor_is_one_on_axis_and_one_minus_kappa_at_the_border() {
        assert_eq!(angle_factor(0.0, 0.0, 1.0, 1.0, 0.5), 1.0);
        assert!((angle_factor(0.5, 0.0, 1.0, 1.0, 0.5) - 0.5).abs() < 1e-12);
        assert!((angle_factor(0.0, -0.5, 1.0, 1.0, 0.5) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn config_out_of_range_names_the_field() {
        let c = DetectorConfig {
            distractor_rate: 1.5,
            ..Default::default()
        };
        let e = c.validate().unwrap_err().to_string();
        assert!(e.contains("distractor_rate"), "{e}");
        let c = DetectorConfig {
            bearing_noise: f64::NAN,
            ..Default::default()
        };
        assert!(c
            .validate()
            .unwrap_err()
            .to_string()
            .contains("bearing_noise"));
    }
}
