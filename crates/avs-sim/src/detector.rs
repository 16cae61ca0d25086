//! A simulated object detector whose scores are correlated across nearby vantage points.
//!
//! Velez, Hemann, Huang, Posner & Roy (JAIR 44, 2012, "Modelling observation correlations for
//! active exploration and robust object detection") observe that a real detector looked at twice
//! from nearly the same spot gives nearly the same confidence: what drives its errors (lighting,
//! clutter, the view of the object) changes smoothly with the vantage point. This module is the
//! ground-truth side of that observation: a detector whose scores carry a hidden, smooth,
//! per-feature nuisance field. (The verifier's GP models live elsewhere; this crate does not
//! depend on them: the simulator is the truth, the verifier is a model of it.)
//!
//! ```
//! use avs_sim::detector::{CorrelatedDetector, Feature, ScoreProfile};
//! let door = Feature { position: [0.0, 0.0], facing: 0.0, is_object: true };
//! let mut det = CorrelatedDetector::new(ScoreProfile::door(), vec![door], 7);
//! // 4 m straight in front of the door: range 4, aspect 0.
//! let (r, phi) = det.vantage(0, [4.0, 0.0]);
//! assert!((r - 4.0).abs() < 1e-12 && phi.abs() < 1e-12);
//! // Two nearby vantage points (0.7° of aspect apart) share the nuisance field: their latent
//! // scores nearly agree.
//! let near = det.latent(0, 4.0, 0.0) - det.latent(0, 4.0, 0.0125);
//! assert!(near.abs() < 0.05);
//! // A door is two-sided: seen from behind, but not edge-on (90° > its 80° limit).
//! assert!(det.score(0, [-4.0, 0.0]).is_some());
//! assert!(det.score(0, [0.0, 4.0]).is_none());
//! // One image, looking back at the door from 4 m: one score, 4.5 s of processing.
//! let seen = det.look([4.0, 0.0], std::f64::consts::PI, 0.5);
//! assert_eq!(seen.len(), 1);
//! assert_eq!((det.images(), det.processing_seconds()), (1, 4.5));
//! ```
//!
//! # Model
//!
//! A [`Feature`] is a thing in the world the detector may respond to: an object of the class
//! (`y = object`) or a look-alike non-object (`y = no-object`), with a planar position, a facing
//! (radians) and a hidden nuisance field drawn once per feature. The robot's vantage point
//! relative to a feature is `v = (r, φ)`: range `r` in metres, and aspect `φ`, the angle between
//! the feature's facing normal and the direction from the feature to the robot (0 = straight in
//! front), wrapped to `(−π, π]`.
//!
//! The score of one look at feature `f` of class `y` from `v` is
//!
//! `z = m_y(r, φ) + g_f(r, φ) + ε`, with `ε ~ N(0, σ_n,y²)` white noise independent per look,
//!
//! * mean `m_y(r, φ) = base_y + gain_y · exp(−½ ((r − r_best)/r_width)²) · a(φ)`, with
//!   `a(φ) = max(cos φ, 0)^k` for a one-sided planar class (signs), `|cos φ|^k` for a two-sided
//!   planar class (doors, seen from both sides) and `1` for a non-planar class
//!   ([`ScoreProfile::mean`]);
//! * nuisance field `g_f`: a zero-mean Gaussian-process sample with the squared-exponential kernel
//!   `σ_g,y² exp(−½ (Δr²/l_r² + Δφ²/l_φ²))` (Δφ the wrapped aspect difference), drawn by random
//!   Fourier features (Rahimi & Recht 2007):
//!   `g(v) = σ_g √(2/D) Σ_{k=1..D} cos(ω_k · (r, φ) + b_k)` with `b_k ~ U[0, 2π)`,
//!   `ω_k,r ~ N(0, 1/l_r²)` and `D =` [`DEFAULT_FOURIER_FEATURES`] unless chosen otherwise
//!   ([`CorrelatedDetector::with_fourier_features`]).
//!
//! A planar class has an aspect limit (signs 45°, doors 80°); beyond it, or beyond `max_range`,
//! the detector cannot see the feature and a look returns no score (`None`). The detector fires
//! (reports a detection) when `z > fire_threshold`. Each image costs the profile's processing
//! time (the paper: the door detector needs about 4.5 s per image, the text detector 8 s); the
//! detector counts the images it processed and their simulated seconds.
//!
//! # Choices where the paper is vague
//!
//! * **Truth, not the paper's model.** The paper learns GP sensor models from real detector
//!   outputs; it never states a generative model of the scores. Ours is mean + per-feature GP
//!   field + white noise. The mean's shape (a Gaussian bump in range times a power of the cosine
//!   of the aspect) and all profile numbers are ours: the paper's Table 1 scales (e.g. a
//!   no-object σ of 9303) belong to its detectors' raw score units and are not usable here.
//! * **The correlation lives in the feature, for the detector's lifetime.** Each feature's field
//!   is drawn once, from a `ChaCha8Rng` seeded with the detector seed on stream `index + 1`, so
//!   the field of feature `i` depends on neither the number of other features nor the order of
//!   looks. [`CorrelatedDetector::add_feature`] adds a feature on a stream the caller names, for
//!   a world whose features are found as the robot looks (the simulated robot keys them by the
//!   object's index in the environment, or by a cell for clutter): its field is then fixed by
//!   the seed and that key alone. Two looks from the same vantage point differ only by white noise, so the correlation
//!   of two looks' scores (over features of one class) is
//!   `σ_g² k(Δ) / (σ_g² + σ_n²)`, which falls with the vantage distance `Δ` as the field's length
//!   scales say. The white noise comes from the detector's own `ChaCha8Rng` (stream 0 of the
//!   same seed), so scores (not latent values) depend on the order of calls.
//! * **Each class has its own field parameters.** Objects and no-objects have different `σ_g`,
//!   length scales and noise (as the paper's Table 1 has separate object / no-object kernels).
//! * **The aspect kernel is periodic, with no seam at ±π.** Random Fourier features on raw `φ`
//!   would make two views just either side of `φ = ±π` (behind an all-round object) nearly
//!   uncorrelated. Instead the aspect frequencies are integers drawn from the discrete Gaussian
//!   `P(ω_φ = m) ∝ exp(−½ m² l_φ²)`: by Poisson summation the field then has the wrapped
//!   Gaussian kernel `Σ_n exp(−½ (Δφ + 2πn)²/l_φ²)` (normalised), which equals
//!   `exp(−½ Δφ²/l_φ²)` for the wrapped difference `Δφ ∈ (−π, π]` up to `2 exp(−π²/(2 l_φ²))`
//!   (below 2·10⁻⁴ for `l_φ ≤ 0.73` rad; every built-in profile has `l_φ ≤ 0.6`). For absurdly
//!   short aspect length scales (`l_φ < 10⁻³` rad) the integers are a rounded continuous normal.
//!   Range is not periodic: `ω_r` is continuous.
//! * **Visibility.** A look beyond `max_range` or beyond the aspect limit returns `None` (no
//!   score at all, rather than a low one), and draws no white noise. A two-sided class's limit
//!   applies to the folded aspect `min(|φ|, π − |φ|)`; one-sided and all-round classes compare
//!   `|φ|` with the limit. There is no occlusion model: callers filter by line of sight.
//! * **Images.** [`CorrelatedDetector::look`] is one image: it counts one image's processing time
//!   and scores every visible feature within the horizontal field of view, each as if the robot
//!   faced it (the paper only models vantage points facing the object; the position of a feature
//!   within the image does not change its score). [`CorrelatedDetector::score`] is one feature's
//!   score and counts no image.

use rand::Rng;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};

/// Number of random Fourier features per nuisance field unless chosen otherwise.
pub const DEFAULT_FOURIER_FEATURES: usize = 256;

/// Wraps an angle to `(−π, π]`.
pub fn wrap_angle(a: f64) -> f64 {
    let w = a.rem_euclid(TAU);
    if w > PI {
        w - TAU
    } else {
        w
    }
}

/// From which sides a class of feature can be seen, and how its mean score falls with aspect.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Sidedness {
    /// A planar feature seen from the front only (a sign): `a(φ) = max(cos φ, 0)^k`.
    OneSided,
    /// A planar feature seen from both sides (a door): `a(φ) = |cos φ|^k`.
    TwoSided,
    /// A non-planar feature, the same from every side: `a(φ) = 1`.
    AllRound,
}

/// The score distribution of one class of feature (object or no-object).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScoreParams {
    /// Mean score far from the best vantage point.
    pub base: f64,
    /// Mean score added at the best range, straight in front.
    pub gain: f64,
    /// Standard deviation `σ_g` of the nuisance field.
    pub field_std: f64,
    /// Length scales of the nuisance field: `[range (m), aspect (rad)]`.
    pub field_length: [f64; 2],
    /// Standard deviation `σ_n` of the white noise of each look.
    pub noise_std: f64,
}

/// How a detector's scores depend on the vantage point, for objects and no-objects.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScoreProfile {
    /// From which sides the class is seen.
    pub sidedness: Sidedness,
    /// Largest aspect (radians) at which the detector sees the feature; `None` = all round.
    pub aspect_limit: Option<f64>,
    /// Largest range (metres) at which the detector sees the feature.
    pub max_range: f64,
    /// Range (metres) of the best mean score.
    pub r_best: f64,
    /// Width (metres) of the Gaussian bump of the mean score around `r_best`.
    pub r_width: f64,
    /// Power `k` of the cosine of the aspect in the mean score.
    pub aspect_power: f64,
    /// Scores of objects of the class.
    pub object: ScoreParams,
    /// Scores of look-alike non-objects.
    pub no_object: ScoreParams,
    /// The detector fires when a score exceeds this.
    pub fire_threshold: f64,
    /// Simulated processing time of one image, seconds.
    pub processing_seconds: f64,
}

impl ScoreProfile {
    /// A door detector: two-sided, aspect limit 80°, 10 m range, 4.5 s per image.
    pub fn door() -> Self {
        ScoreProfile {
            sidedness: Sidedness::TwoSided,
            aspect_limit: Some(80f64.to_radians()),
            max_range: 10.0,
            r_best: 4.0,
            r_width: 3.0,
            aspect_power: 1.0,
            object: ScoreParams {
                base: 0.0,
                gain: 2.0,
                field_std: 0.5,
                field_length: [1.5, 0.4],
                noise_std: 0.25,
            },
            no_object: ScoreParams {
                base: 0.0,
                gain: 0.9,
                field_std: 0.7,
                field_length: [1.2, 0.3],
                noise_std: 0.25,
            },
            fire_threshold: 1.0,
            processing_seconds: 4.5,
        }
    }

    /// A sign (text) detector: one-sided, aspect limit 45°, 8 m range, 8 s per image.
    pub fn sign() -> Self {
        ScoreProfile {
            sidedness: Sidedness::OneSided,
            aspect_limit: Some(PI / 4.0),
            max_range: 8.0,
            r_best: 2.5,
            r_width: 2.0,
            aspect_power: 2.0,
            object: ScoreParams {
                base: 0.0,
                gain: 2.2,
                field_std: 0.6,
                field_length: [1.0, 0.25],
                noise_std: 0.3,
            },
            no_object: ScoreParams {
                base: 0.0,
                gain: 1.0,
                field_std: 0.8,
                field_length: [0.8, 0.2],
                noise_std: 0.3,
            },
            fire_threshold: 1.0,
            processing_seconds: 8.0,
        }
    }

    /// A generic object detector: all round, 6 m range, 1 s per image.
    pub fn generic() -> Self {
        ScoreProfile {
            sidedness: Sidedness::AllRound,
            aspect_limit: None,
            max_range: 6.0,
            r_best: 2.0,
            r_width: 2.5,
            aspect_power: 0.0,
            object: ScoreParams {
                base: 0.0,
                gain: 2.0,
                field_std: 0.5,
                field_length: [1.5, 0.6],
                noise_std: 0.25,
            },
            no_object: ScoreParams {
                base: 0.0,
                gain: 0.8,
                field_std: 0.7,
                field_length: [1.2, 0.5],
                noise_std: 0.25,
            },
            fire_threshold: 1.0,
            processing_seconds: 1.0,
        }
    }

    /// This profile with every range-like quantity multiplied by `s`: `max_range`, `r_best`,
    /// `r_width` and both classes' range length scale `field_length[0]`. Scores, aspects, noise
    /// and processing time are unchanged, so the scaled detector at range `s·r` behaves exactly
    /// as this one at range `r`: same mean, and (from the same seed and stream) the very same
    /// nuisance field, the range frequencies of its random Fourier features being drawn as
    /// `N(0, 1)/l_r`.
    ///
    /// ```
    /// use avs_sim::detector::ScoreProfile;
    /// let g = ScoreProfile::generic();
    /// let half = g.scaled(0.5);
    /// assert_eq!(half.max_range, 3.0);
    /// assert!((half.mean(true, 1.3, 0.2) - g.mean(true, 2.6, 0.2)).abs() < 1e-12);
    /// ```
    pub fn scaled(&self, s: f64) -> ScoreProfile {
        let mut p = self.clone();
        p.max_range *= s;
        p.r_best *= s;
        p.r_width *= s;
        p.object.field_length[0] *= s;
        p.no_object.field_length[0] *= s;
        p
    }

    /// The profile of a knowledge-file object class with detection range `detection_range`
    /// (`[min, max]` metres at zoom 1): [`ScoreProfile::generic`] scaled
    /// ([`ScoreProfile::scaled`]) by `s = detection_range[1] / generic().max_range`, so that the
    /// correlated detector of the class works out to the class's maximum detection distance.
    /// The minimum distance is not used (the mean score already falls off close in).
    ///
    /// This is the profile [`crate::sim_robot::SimAgentRobot`] scores every knowledge class with
    /// (its correlated detections of non-landmark classes and every
    /// [`avs_robot::Robot::detector_scores`]). A verifier's sensor model trained on
    /// [`ScoreProfile::generic`] applies to such a class after scaling its range inputs (range
    /// and range length scales) by the same `s`: a score at range `r` of the class is
    /// distributed as a generic score at range `r / s`.
    ///
    /// A non-finite or non-positive `detection_range[1]` gives a profile that fails
    /// [`ScoreProfile::check`].
    ///
    /// ```
    /// use avs_sim::detector::ScoreProfile;
    /// // A cereal box is detected out to 4 m: two thirds of the generic 6 m.
    /// let p = ScoreProfile::for_class([0.5, 4.0]);
    /// assert_eq!(p.max_range, 4.0);
    /// assert!((p.r_best - 2.0 * 4.0 / 6.0).abs() < 1e-12);
    /// assert_eq!(p.processing_seconds, ScoreProfile::generic().processing_seconds);
    /// ```
    pub fn for_class(detection_range: [f64; 2]) -> ScoreProfile {
        let g = Self::generic();
        let s = detection_range[1] / g.max_range;
        g.scaled(s)
    }

    /// The score parameters of objects (`true`) or no-objects (`false`).
    pub fn params(&self, is_object: bool) -> &ScoreParams {
        if is_object {
            &self.object
        } else {
            &self.no_object
        }
    }

    /// The mean score `m_y(r, φ)` of an object (`true`) or no-object (`false`) at range `range`
    /// (metres) and aspect `aspect` (radians).
    pub fn mean(&self, is_object: bool, range: f64, aspect: f64) -> f64 {
        let p = self.params(is_object);
        let a = match self.sidedness {
            Sidedness::OneSided => aspect.cos().max(0.0).powf(self.aspect_power),
            Sidedness::TwoSided => aspect.cos().abs().powf(self.aspect_power),
            Sidedness::AllRound => 1.0,
        };
        let u = (range - self.r_best) / self.r_width;
        p.base + p.gain * (-0.5 * u * u).exp() * a
    }

    /// Whether the detector sees a feature at range `range` (metres) and aspect `aspect`
    /// (radians): within `[0, max_range]` and within the aspect limit (for a two-sided class, of the
    /// folded aspect `min(|φ|, π − |φ|)`).
    pub fn sees(&self, range: f64, aspect: f64) -> bool {
        if !((0.0..=self.max_range).contains(&range) && aspect.is_finite()) {
            return false;
        }
        let Some(limit) = self.aspect_limit else {
            return true;
        };
        let a = wrap_angle(aspect).abs();
        let a = match self.sidedness {
            Sidedness::TwoSided => a.min(PI - a),
            Sidedness::OneSided | Sidedness::AllRound => a,
        };
        a <= limit
    }

    /// Checks the profile: every number finite; `max_range`, `r_width`, the field standard
    /// deviations, length scales and noise standard deviations positive; `aspect_power` and
    /// `processing_seconds` non-negative; the aspect limit in `(0, π]`. The message names the
    /// field and what is expected.
    pub fn check(&self) -> Result<(), String> {
        fn finite(name: &str, v: f64) -> Result<(), String> {
            if v.is_finite() {
                Ok(())
            } else {
                Err(format!("{name} must be a finite number, got {v}"))
            }
        }
        fn positive(name: &str, v: f64) -> Result<(), String> {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(format!("{name} must be a finite number > 0, got {v}"))
            }
        }
        fn non_negative(name: &str, v: f64) -> Result<(), String> {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(format!("{name} must be a finite number >= 0, got {v}"))
            }
        }
        if let Some(limit) = self.aspect_limit {
            if !(limit.is_finite() && limit > 0.0 && limit <= PI) {
                return Err(format!(
                    "aspect_limit must be in (0, π] radians (or absent for all round), got {limit}"
                ));
            }
        }
        positive("max_range (metres)", self.max_range)?;
        finite("r_best (metres)", self.r_best)?;
        positive("r_width (metres)", self.r_width)?;
        non_negative("aspect_power", self.aspect_power)?;
        finite("fire_threshold", self.fire_threshold)?;
        non_negative("processing_seconds", self.processing_seconds)?;
        for (class, p) in [("object", &self.object), ("no_object", &self.no_object)] {
            finite(&format!("{class}.base"), p.base)?;
            finite(&format!("{class}.gain"), p.gain)?;
            positive(&format!("{class}.field_std"), p.field_std)?;
            positive(
                &format!("{class}.field_length[0] (range length scale, metres)"),
                p.field_length[0],
            )?;
            positive(
                &format!("{class}.field_length[1] (aspect length scale, radians)"),
                p.field_length[1],
            )?;
            positive(&format!("{class}.noise_std"), p.noise_std)?;
        }
        Ok(())
    }
}

/// A thing in the world the detector may respond to: an object of the class or a look-alike.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Feature {
    /// Planar position `[x, y]`, metres.
    pub position: [f64; 2],
    /// Direction of the feature's facing normal, radians (aspect 0 is straight in front).
    pub facing: f64,
    /// Whether this is an object of the class (`true`) or a look-alike non-object (`false`).
    pub is_object: bool,
}

/// One feature's nuisance field: `g(r, φ) = amplitude · Σ_k cos(ω_k,r r + ω_k,φ φ + b_k)`.
#[derive(Debug, Clone)]
struct Field {
    /// `σ_g √(2/D)`.
    amplitude: f64,
    /// `[ω_r, ω_φ, b]` per Fourier feature; `ω_φ` is an integer (the aspect kernel is periodic).
    waves: Vec<[f64; 3]>,
}

impl Field {
    fn at(&self, range: f64, aspect: f64) -> f64 {
        let aspect = wrap_angle(aspect);
        self.amplitude
            * self
                .waves
                .iter()
                .map(|[wr, wa, b]| (wr * range + wa * aspect + b).cos())
                .sum::<f64>()
    }
}

/// Sampler of integer aspect frequencies `m` with `P(m) ∝ exp(−½ m² l²)` (the spectral measure
/// of the wrapped Gaussian kernel of length scale `l` on the circle).
#[derive(Debug, Clone)]
enum AspectFrequencies {
    /// Cumulative weights of `m = −half..=half`.
    Table { half: i64, cumulative: Vec<f64> },
    /// `round(N(0, 1/l²))`, for length scales so short that a table would be huge.
    Rounded { std: f64 },
}

impl AspectFrequencies {
    fn new(length: f64) -> Self {
        let std = 1.0 / length;
        // Beyond 9 standard deviations the weights (e^-40.5) are lost in the cumulative sum.
        let half = (9.0 * std).ceil();
        if half > 10_000.0 {
            return AspectFrequencies::Rounded { std };
        }
        let half = half as i64;
        let mut total = 0.0;
        let cumulative = (-half..=half)
            .map(|m| {
                let m = m as f64;
                total += (-0.5 * m * m * length * length).exp();
                total
            })
            .collect();
        AspectFrequencies::Table { half, cumulative }
    }

    fn sample(&self, rng: &mut impl Rng) -> f64 {
        match self {
            AspectFrequencies::Table { half, cumulative } => {
                let u = rng.gen::<f64>() * cumulative[cumulative.len() - 1];
                let i = cumulative
                    .partition_point(|&c| c <= u)
                    .min(cumulative.len() - 1);
                (i as i64 - half) as f64
            }
            AspectFrequencies::Rounded { std } => {
                (std * rng.sample::<f64, _>(StandardNormal)).round()
            }
        }
    }
}

/// Draws a nuisance field from stream `stream` of `seed` (the constructors' feature `i` uses
/// stream `i + 1`).
fn draw_field(
    p: &ScoreParams,
    aspect: &AspectFrequencies,
    seed: u64,
    stream: u64,
    d: usize,
) -> Field {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream);
    let waves = (0..d)
        .map(|_| {
            let wr = rng.sample::<f64, _>(StandardNormal) / p.field_length[0];
            let wa = aspect.sample(&mut rng);
            let b = rng.gen::<f64>() * TAU;
            [wr, wa, b]
        })
        .collect();
    Field {
        amplitude: p.field_std * (2.0 / d as f64).sqrt(),
        waves,
    }
}

/// A simulated detector whose scores are correlated across nearby vantage points (see the
/// [module documentation](self)).
#[derive(Debug, Clone)]
pub struct CorrelatedDetector {
    profile: ScoreProfile,
    features: Vec<Feature>,
    fields: Vec<Field>,
    noise: ChaCha8Rng,
    images: usize,
    seconds: f64,
    /// The seed of every field and of the white noise.
    seed: u64,
    /// Random Fourier features per field.
    fourier_features: usize,
    /// Aspect-frequency samplers of objects and no-objects.
    aspect_object: AspectFrequencies,
    aspect_no_object: AspectFrequencies,
}

impl CorrelatedDetector {
    /// A detector of `profile` over `features`, with [`DEFAULT_FOURIER_FEATURES`] Fourier
    /// features per nuisance field; `seed` seeds every field and the white noise.
    ///
    /// # Panics
    /// When `profile` fails [`ScoreProfile::check`].
    pub fn new(profile: ScoreProfile, features: Vec<Feature>, seed: u64) -> Self {
        Self::with_fourier_features(profile, features, seed, DEFAULT_FOURIER_FEATURES)
    }

    /// As [`CorrelatedDetector::new`], with `fourier_features` random Fourier features per field
    /// (more = closer to a Gaussian process, slower scores).
    ///
    /// # Panics
    /// When `profile` fails [`ScoreProfile::check`] or `fourier_features` is 0.
    pub fn with_fourier_features(
        profile: ScoreProfile,
        features: Vec<Feature>,
        seed: u64,
        fourier_features: usize,
    ) -> Self {
        if let Err(e) = profile.check() {
            panic!("invalid detector score profile: {e}");
        }
        assert!(
            fourier_features > 0,
            "a nuisance field needs at least one Fourier feature"
        );
        let object = AspectFrequencies::new(profile.object.field_length[1]);
        let no_object = AspectFrequencies::new(profile.no_object.field_length[1]);
        let fields = features
            .iter()
            .enumerate()
            .map(|(i, f)| {
                let aspect = if f.is_object { &object } else { &no_object };
                draw_field(
                    profile.params(f.is_object),
                    aspect,
                    seed,
                    i as u64 + 1,
                    fourier_features,
                )
            })
            .collect();
        let mut noise = ChaCha8Rng::seed_from_u64(seed);
        noise.set_stream(0);
        CorrelatedDetector {
            profile,
            features,
            fields,
            noise,
            images: 0,
            seconds: 0.0,
            seed,
            fourier_features,
            aspect_object: object,
            aspect_no_object: no_object,
        }
    }

    /// Adds `feature` with its nuisance field drawn from stream `stream` of the detector seed,
    /// and returns its index (the number of features before it). The field depends only on the
    /// seed, the stream, the feature's class (object or no-object) and the profile, not on the
    /// other features or the order of additions and looks: a caller that names each thing in
    /// its world by a stable stream (e.g. an object's index in an environment plus 1, as the
    /// constructors do for feature `i`) gets the same field for it whenever it adds it. A
    /// feature added on the stream of another of the same class shares that feature's field
    /// exactly.
    ///
    /// ```
    /// use avs_sim::detector::{CorrelatedDetector, Feature, ScoreProfile};
    /// let f = Feature { position: [0.0, 0.0], facing: 0.0, is_object: true };
    /// let built = CorrelatedDetector::new(ScoreProfile::door(), vec![f.clone(); 3], 7);
    /// let mut grown = CorrelatedDetector::new(ScoreProfile::door(), Vec::new(), 7);
    /// // Feature 2 of the constructor has stream 3; added first, it has the same field.
    /// assert_eq!(grown.add_feature(f, 3), 0);
    /// assert_eq!(grown.latent(0, 3.0, 0.2), built.latent(2, 3.0, 0.2));
    /// ```
    ///
    /// # Panics
    /// When `stream` is 0: that stream is the white noise's.
    pub fn add_feature(&mut self, feature: Feature, stream: u64) -> usize {
        assert!(
            stream != 0,
            "stream 0 is the detector's white noise; a feature's field needs another stream"
        );
        let aspect = if feature.is_object {
            &self.aspect_object
        } else {
            &self.aspect_no_object
        };
        let field = draw_field(
            self.profile.params(feature.is_object),
            aspect,
            self.seed,
            stream,
            self.fourier_features,
        );
        self.features.push(feature);
        self.fields.push(field);
        self.features.len() - 1
    }

    /// The features, in the order their indices refer to.
    pub fn features(&self) -> &[Feature] {
        &self.features
    }

    /// The score profile.
    pub fn profile(&self) -> &ScoreProfile {
        &self.profile
    }

    /// The vantage point `(range in metres, aspect in radians wrapped to (−π, π])` of a robot at
    /// `waypoint` facing feature `feature`. A robot on the feature's position has range 0 and an
    /// aspect as if it stood on the +x side.
    ///
    /// # Panics
    /// When `feature` is out of range.
    pub fn vantage(&self, feature: usize, waypoint: [f64; 2]) -> (f64, f64) {
        let f = &self.features[feature];
        let dx = waypoint[0] - f.position[0];
        let dy = waypoint[1] - f.position[1];
        (dx.hypot(dy), wrap_angle(dy.atan2(dx) - f.facing))
    }

    /// The latent score `m_y(r, φ) + g_f(r, φ)` of feature `feature` at vantage point
    /// `(range, aspect)`, without white noise (whether or not the detector sees it there).
    ///
    /// # Panics
    /// When `feature` is out of range.
    pub fn latent(&self, feature: usize, range: f64, aspect: f64) -> f64 {
        let is_object = self.features[feature].is_object;
        self.profile.mean(is_object, range, aspect) + self.fields[feature].at(range, aspect)
    }

    /// One look's score at feature `feature` from a robot at `waypoint` facing it: the latent
    /// score plus white noise from the detector's own seeded stream; `None` (and no noise drawn)
    /// when the detector does not see the feature from there. Counts no image: see
    /// [`CorrelatedDetector::look`].
    ///
    /// # Panics
    /// When `feature` is out of range.
    pub fn score(&mut self, feature: usize, waypoint: [f64; 2]) -> Option<f64> {
        let (r, phi) = self.vantage(feature, waypoint);
        self.score_from(feature, r, phi)
    }

    /// One look's score at feature `feature` from vantage point `(range, aspect)` (metres,
    /// radians), for a caller that computes the vantage itself (e.g. a zoomed image, which sees
    /// as from nearer): the latent score plus white noise; `None` (and no noise drawn) when the
    /// detector does not see the feature from there ([`ScoreProfile::sees`]). Counts no image.
    /// [`CorrelatedDetector::score`] is this at [`CorrelatedDetector::vantage`].
    ///
    /// # Panics
    /// When `feature` is out of range.
    pub fn score_from(&mut self, feature: usize, range: f64, aspect: f64) -> Option<f64> {
        if !self.profile.sees(range, aspect) {
            return None;
        }
        let sigma = self
            .profile
            .params(self.features[feature].is_object)
            .noise_std;
        let eps: f64 = self.noise.sample(StandardNormal);
        Some(self.latent(feature, range, aspect) + sigma * eps)
    }

    /// One image from a robot at `waypoint` with camera heading `heading` (radians) and
    /// horizontal half field of view `half_fov` (radians): counts one image's processing time and
    /// returns `(feature index, score)` of every feature with `|bearing − heading| ≤ half_fov`
    /// that the detector sees, in index order. No occlusion model: the caller filters by line
    /// of sight.
    pub fn look(&mut self, waypoint: [f64; 2], heading: f64, half_fov: f64) -> Vec<(usize, f64)> {
        self.images += 1;
        self.seconds += self.profile.processing_seconds;
        (0..self.features.len())
            .filter_map(|i| {
                let p = self.features[i].position;
                let bearing = (p[1] - waypoint[1]).atan2(p[0] - waypoint[0]);
                if wrap_angle(bearing - heading).abs() > half_fov {
                    return None;
                }
                self.score(i, waypoint).map(|z| (i, z))
            })
            .collect()
    }

    /// Whether the detector fires (reports a detection) on `score`: `score > fire_threshold`.
    pub fn fires(&self, score: f64) -> bool {
        score > self.profile.fire_threshold
    }

    /// Number of images processed by [`CorrelatedDetector::look`].
    pub fn images(&self) -> usize {
        self.images
    }

    /// Total simulated processing time of those images, seconds.
    pub fn processing_seconds(&self) -> f64 {
        self.seconds
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` features of one class, all at the origin facing +x.
    fn detector(profile: ScoreProfile, is_object: bool, n: usize, seed: u64) -> CorrelatedDetector {
        let f = Feature {
            position: [0.0, 0.0],
            facing: 0.0,
            is_object,
        };
        CorrelatedDetector::new(profile, vec![f; n], seed)
    }

    fn mean_var(x: &[f64]) -> (f64, f64) {
        let n = x.len() as f64;
        let m = x.iter().sum::<f64>() / n;
        (
            m,
            x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0),
        )
    }

    fn correlation(a: &[f64], b: &[f64]) -> f64 {
        let (ma, va) = mean_var(a);
        let (mb, vb) = mean_var(b);
        let n = a.len() as f64;
        let c = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x - ma) * (y - mb))
            .sum::<f64>()
            / (n - 1.0);
        c / (va * vb).sqrt()
    }

    #[test]
    fn wrap_angle_maps_to_minus_pi_exclusive_pi_inclusive() {
        assert_eq!(wrap_angle(PI), PI);
        assert_eq!(wrap_angle(-PI), PI);
        assert!((wrap_angle(3.0 * PI / 2.0) + PI / 2.0).abs() < 1e-12);
        assert!((wrap_angle(-0.25) + 0.25).abs() < 1e-15);
    }

    #[test]
    fn fourier_field_has_the_kernels_variance_and_correlation() {
        let n = 4000;
        for (case, (profile, is_object)) in [
            (ScoreProfile::door(), true),
            (ScoreProfile::sign(), false),
            (ScoreProfile::generic(), true),
        ]
        .into_iter()
        .enumerate()
        {
            let p = profile.params(is_object).clone();
            let det = detector(profile, is_object, n, 11 + case as u64);
            let at = |r: f64, phi: f64| -> Vec<f64> {
                (0..n).map(|i| det.fields[i].at(r, phi)).collect()
            };
            let (r0, a0) = (3.0, 0.1);
            let g0 = at(r0, a0);
            let (_, var) = mean_var(&g0);
            let want = p.field_std.powi(2);
            eprintln!("variance {var:.4} vs σ_g² {want:.4}");
            assert!(
                (var / want - 1.0).abs() < 0.10,
                "variance {var} vs σ_g² {want}"
            );
            for axis in 0..2 {
                let l = p.field_length[axis];
                for t in [0.5, 1.0, 2.0] {
                    let d = t * l;
                    let g1 = if axis == 0 {
                        at(r0 + d, a0)
                    } else {
                        at(r0, a0 + d)
                    };
                    let rho = correlation(&g0, &g1);
                    let want = (-0.5 * t * t).exp();
                    eprintln!("axis {axis}, Δ = {t} l: correlation {rho:.3} vs kernel {want:.3}");
                    assert!(
                        (rho - want).abs() < 0.05,
                        "axis {axis}, Δ = {t} l: correlation {rho} vs kernel {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn aspect_field_is_continuous_across_the_seam_behind_an_all_round_object() {
        let det = detector(ScoreProfile::generic(), true, 50, 5);
        for i in 0..50 {
            let a = det.latent(i, 2.0, PI - 1e-6);
            let b = det.latent(i, 2.0, -PI + 1e-6);
            assert!((a - b).abs() < 1e-3, "feature {i}: {a} vs {b}");
        }
        // And the correlation across the seam is the wrapped kernel's: 0.2 rad apart.
        let n = 4000;
        let det = detector(ScoreProfile::generic(), true, n, 9);
        let a: Vec<f64> = (0..n).map(|i| det.fields[i].at(2.0, PI - 0.1)).collect();
        let b: Vec<f64> = (0..n).map(|i| det.fields[i].at(2.0, -PI + 0.1)).collect();
        let want = (-0.5f64 * (0.2f64 / 0.6).powi(2)).exp();
        let rho = correlation(&a, &b);
        assert!((rho - want).abs() < 0.05, "{rho} vs {want}");
    }

    #[test]
    fn aspect_frequencies_follow_the_discrete_gaussian() {
        let l = 0.4;
        let s = AspectFrequencies::new(l);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let n = 200_000;
        let m: Vec<f64> = (0..n).map(|_| s.sample(&mut rng)).collect();
        assert!(m.iter().all(|v| v.fract() == 0.0));
        let (mean, var) = mean_var(&m);
        // Discrete Gaussian variance Σ m² w_m / Σ w_m ≈ 1/l² for l well below π.
        assert!(mean.abs() < 0.05, "{mean}");
        assert!((var * l * l - 1.0).abs() < 0.02, "{var}");
        // A very short length scale falls back to rounding.
        assert!(matches!(
            AspectFrequencies::new(1e-4),
            AspectFrequencies::Rounded { .. }
        ));
    }

    #[test]
    fn mean_falls_with_range_and_aspect() {
        let s = ScoreProfile::sign();
        assert!((s.mean(true, 2.5, 0.0) - 2.2).abs() < 1e-12);
        assert!(s.mean(true, 2.5, 0.0) > s.mean(true, 4.5, 0.0));
        assert!(s.mean(true, 2.5, 0.0) > s.mean(true, 2.5, 0.5));
        assert_eq!(s.mean(true, 2.5, 2.0), 0.0);
        let d = ScoreProfile::door();
        assert!((d.mean(true, 4.0, PI) - 2.0).abs() < 1e-12);
        let g = ScoreProfile::generic();
        assert_eq!(g.mean(false, 2.0, 2.5), g.mean(false, 2.0, 0.0));
    }

    #[test]
    fn a_scaled_profile_scores_at_s_times_the_range_as_the_unscaled_at_the_range() {
        let f = Feature {
            position: [1.0, -2.0],
            facing: 0.3,
            is_object: true,
        };
        let g = Feature {
            is_object: false,
            ..f.clone()
        };
        let s = 0.4;
        let plain = CorrelatedDetector::new(ScoreProfile::generic(), vec![f.clone(), g.clone()], 8);
        let scaled = CorrelatedDetector::new(ScoreProfile::generic().scaled(s), vec![f, g], 8);
        for i in 0..2 {
            for (r, phi) in [(0.5, 0.0), (2.0, 1.0), (4.5, -2.5), (7.0, 3.0)] {
                let (a, b) = (plain.latent(i, r, phi), scaled.latent(i, s * r, phi));
                assert!(
                    (a - b).abs() < 1e-9,
                    "feature {i} at ({r}, {phi}): {a} vs {b}"
                );
                assert_eq!(
                    plain.profile().sees(r, phi),
                    scaled.profile().sees(s * r, phi)
                );
            }
        }
    }

    #[test]
    fn for_class_scales_every_range_quantity_by_the_max_detection_range() {
        let g = ScoreProfile::generic();
        let p = ScoreProfile::for_class([0.3, 1.5]);
        let s = 1.5 / g.max_range;
        assert_eq!(p.check(), Ok(()));
        assert!((p.max_range - 1.5).abs() < 1e-12);
        assert!((p.r_best - s * g.r_best).abs() < 1e-12);
        assert!((p.r_width - s * g.r_width).abs() < 1e-12);
        for (a, b) in [(&p.object, &g.object), (&p.no_object, &g.no_object)] {
            assert!((a.field_length[0] - s * b.field_length[0]).abs() < 1e-12);
            assert_eq!(a.field_length[1], b.field_length[1]);
            assert_eq!((a.base, a.gain, a.field_std), (b.base, b.gain, b.field_std));
            assert_eq!(a.noise_std, b.noise_std);
        }
        assert_eq!(
            (p.fire_threshold, p.processing_seconds, p.sidedness),
            (g.fire_threshold, g.processing_seconds, g.sidedness)
        );
        // The generic detector's own range gives the generic profile.
        assert_eq!(ScoreProfile::for_class([0.5, 6.0]), g);
        // A class detected nowhere has no usable profile.
        assert!(ScoreProfile::for_class([0.0, 0.0])
            .check()
            .unwrap_err()
            .contains("max_range"));
    }

    #[test]
    fn score_from_the_vantage_is_the_score_from_the_waypoint() {
        let f = Feature {
            position: [2.0, 1.0],
            facing: 1.0,
            is_object: true,
        };
        let mut a = CorrelatedDetector::new(ScoreProfile::sign(), vec![f.clone()], 4);
        let mut b = a.clone();
        for wp in [[4.0, 3.0], [2.0, 4.0], [-5.0, 1.0], [2.5, 1.5]] {
            let (r, phi) = b.vantage(0, wp);
            assert_eq!(a.score(0, wp), b.score_from(0, r, phi), "{wp:?}");
        }
    }

    #[test]
    fn added_features_get_their_streams_field_whatever_came_before() {
        let f = |is_object| Feature {
            position: [0.0, 0.0],
            facing: 0.0,
            is_object,
        };
        let mut a = CorrelatedDetector::new(ScoreProfile::door(), Vec::new(), 21);
        let mut b = a.clone();
        let ia = a.add_feature(f(true), 77);
        b.add_feature(f(false), 5);
        b.add_feature(f(true), 1 << 63);
        let ib = b.add_feature(f(true), 77);
        assert_eq!((ia, ib), (0, 2));
        assert_eq!(a.latent(ia, 3.0, 0.4), b.latent(ib, 3.0, 0.4));
        assert_ne!(b.latent(1, 3.0, 0.4), b.latent(ib, 3.0, 0.4));
    }

    #[test]
    #[should_panic(expected = "white noise")]
    fn a_feature_on_the_noise_stream_is_refused() {
        let mut d = CorrelatedDetector::new(ScoreProfile::door(), Vec::new(), 1);
        d.add_feature(
            Feature {
                position: [0.0, 0.0],
                facing: 0.0,
                is_object: true,
            },
            0,
        );
    }

    #[test]
    fn built_in_profiles_pass_their_check_and_bad_ones_are_named() {
        for p in [
            ScoreProfile::door(),
            ScoreProfile::sign(),
            ScoreProfile::generic(),
        ] {
            assert_eq!(p.check(), Ok(()));
        }
        let mut bad = ScoreProfile::door();
        bad.aspect_limit = Some(4.0);
        assert!(bad.check().unwrap_err().contains("aspect_limit"));
        let mut bad = ScoreProfile::sign();
        bad.no_object.noise_std = f64::NAN;
        assert!(bad.check().unwrap_err().contains("no_object.noise_std"));
    }
}
