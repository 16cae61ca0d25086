//! The detection verifier of a knowledge file: which verifier a class's candidate detections
//! go to, and the trained sensor models they reason with (Velez, Hemann, Huang, Posner & Roy,
//! JAIR 2012; `avs-verify` implements them).
//!
//! ```yaml
//! sensor_models:
//!   - name: generic
//!     model:
//!       max_range: 6.0            # the range the model was trained over, metres
//!       aspect_limit: null        # radians; null: the class is seen from every side
//!       kind: { kind: dynamic, alpha_scale: 0.03 }
//!       object:    { mean: 1.4, kernel: {...}, noise_variance: 0.03, spread: 0.27, points: [...], corr: {...} }
//!       no_object: { ... }
//! object_classes:
//!   - { name: cerealbox, ..., verifier: { strategy: planned, model: generic } }
//! ```
//!
//! `avs verify train` writes a `sensor_models` entry. These are plain data: this module checks
//! that the numbers make sense ([`SensorModelSpec::problems`]); `avs-verify` builds the GP
//! models from them.
//!
//! **A model serves every class whose detector behaves alike, at that class's scale.** A model
//! is stated over its own `max_range`; a class uses it with every range (the range length
//! scales, the training points' ranges, the disc radius) multiplied by
//! `detection_range[1] / max_range` ([`SensorModelSpec::scaled`]), so one model trained on a
//! generic detector verifies a cereal box seen up to 4 m and a marker seen up to 1.5 m.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Which verifier a class's candidates go to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum VerifierStrategy {
    /// Velez et al.'s planned verifier (REPLANONNEWDETECTION, Fig. 7) with the model's own
    /// kind (the dynamic model when trained as such).
    Planned,
    /// The planned verifier with the static disc model (eq. 10–11).
    PlannedDisc,
    /// GREEDY(τ): the best vantage point until the belief passes `threshold`.
    Greedy,
    /// RTBSS: an online POMDP search with the independent model.
    Rtbss,
    /// The fixed rule: a few closer looks, accept on enough detections near the sighting.
    Count,
    /// Closer looks until the Bayes-optimal policy decides: the knowledge's binary detector
    /// (`sensor.false_negative`, `sensor.false_positive`, looks independent given the truth),
    /// the candidate's prior, and a wrong decision priced as a failed search
    /// (`avs_verify::sequential`). With a `model`, each closer look's detector score at the
    /// candidate is weighed by that sensor model instead of its hit or miss (a detector whose
    /// look-alikes fire often, but score lower than objects). The default for a class without
    /// a verifier block (then without a model).
    Sequential,
}

impl VerifierStrategy {
    /// The name as the file writes it.
    pub fn name(self) -> &'static str {
        match self {
            VerifierStrategy::Planned => "planned",
            VerifierStrategy::PlannedDisc => "planned-disc",
            VerifierStrategy::Greedy => "greedy",
            VerifierStrategy::Rtbss => "rtbss",
            VerifierStrategy::Count => "count",
            VerifierStrategy::Sequential => "sequential",
        }
    }

    /// Whether the strategy needs a trained sensor model (`model` in the block): the planned,
    /// greedy and RTBSS verifiers do, `count` and `sequential` do not.
    pub fn uses_model(self) -> bool {
        !matches!(self, VerifierStrategy::Count | VerifierStrategy::Sequential)
    }

    /// Whether the strategy can reason with a trained sensor model: all but `count`
    /// (`sequential` weighs its looks' scores with one when the block names it).
    pub fn accepts_model(self) -> bool {
        self != VerifierStrategy::Count
    }
}

/// A class's verifier block.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VerifierSpec {
    /// Which verifier.
    pub strategy: VerifierStrategy,
    /// The name of the `sensor_models` entry it reasons with; required unless `count`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<String>,
    /// GREEDY's τ: look until the belief that the candidate is (or is not) an object passes
    /// it, in (0.5, 1). Only for `greedy`; default [`DEFAULT_GREEDY_THRESHOLD`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub threshold: Option<f64>,
}

/// GREEDY's τ when a `greedy` block gives none (the paper's best baseline on doors).
pub const DEFAULT_GREEDY_THRESHOLD: f64 = 0.8;

/// Which of the paper's sensor models a trained model is.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum ModelKind {
    /// The static disc model (eq. 10–11) with its radius `d_max`, metres.
    Disc {
        /// d_max of eq. 10, metres (the paper's 3 m).
        d_max: f64,
    },
    /// The dynamic time-varying model (eq. 9, 16, 17) with its scale κ of eq. 17.
    Dynamic {
        /// κ of eq. 17.
        alpha_scale: f64,
    },
    /// The independent model alone (GP_ind; every look a fresh draw) — what RTBSS can use.
    Independent,
}

/// A squared-exponential kernel's parameters: `k(x, x') = σ² exp(−½ Σ_d (x_d − x'_d)² / l_d²)`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct KernelSpec {
    /// σ², the prior variance of the latent function.
    pub signal_variance: f64,
    /// `l_d`, one per input: `[range (m), aspect (rad)]`.
    pub length_scales: Vec<f64>,
}

/// GP_corr's parameters for one hypothesis (eq. 14): the kernel of the per-candidate residual
/// field and the white noise of single scores about it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CorrSpec {
    /// Kernel of the residual field.
    pub kernel: KernelSpec,
    /// Variance of a single score about the residual field.
    pub noise_variance: f64,
}

/// The learned parameters of one hypothesis: GP_ind's mean, kernel, noise, spread and training
/// points, and GP_corr.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HypothesisSpec {
    /// GP_ind's constant prior mean.
    pub mean: f64,
    /// GP_ind's kernel.
    pub kernel: KernelSpec,
    /// Noise variance of GP_ind's training points (bin means).
    pub noise_variance: f64,
    /// Variance of one score about the latent mean.
    pub spread: f64,
    /// GP_ind's training points: `[range m, aspect rad, mean score]`.
    pub points: Vec<[f64; 3]>,
    /// GP_corr.
    pub corr: CorrSpec,
}

/// A trained sensor model in plain data.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SensorModelSpec {
    /// Disc, dynamic or independent.
    pub kind: ModelKind,
    /// Largest range the detector sees from, metres.
    pub max_range: f64,
    /// Largest |aspect| the detector sees from, radians (`None`: all round).
    pub aspect_limit: Option<f64>,
    /// y = object.
    pub object: HypothesisSpec,
    /// y = no object.
    pub no_object: HypothesisSpec,
}

/// A named sensor model of a knowledge file's `sensor_models`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NamedSensorModel {
    /// The name classes refer to (`verifier.model`).
    pub name: String,
    /// The model.
    pub model: SensorModelSpec,
}

/// Most GP_ind training points a hypothesis may hold (the model's cost grows with their
/// square; training bins keep far below).
pub const MAX_POINTS: usize = 2000;

/// Most sensor models a knowledge file may hold.
pub const MAX_MODELS: usize = 64;

impl SensorModelSpec {
    /// Check every parameter; each problem as (field path relative to the model, what is
    /// expected). Empty when the model can be built.
    pub fn problems(&self) -> Vec<(String, String)> {
        let mut out = Vec::new();
        let mut need = |ok: bool, field: String, what: &str| {
            if !ok {
                out.push((field, what.to_string()));
            }
        };
        let pos = |v: f64| v.is_finite() && v > 0.0;
        need(
            pos(self.max_range),
            "max_range".into(),
            "a positive range in metres",
        );
        if let Some(a) = self.aspect_limit {
            need(
                a > 0.0 && a <= std::f64::consts::PI,
                "aspect_limit".into(),
                "an angle in (0, π] radians, or null for a class seen from every side",
            );
        }
        match self.kind {
            ModelKind::Disc { d_max } => need(
                pos(d_max),
                "kind.d_max".into(),
                "a positive distance in metres",
            ),
            ModelKind::Dynamic { alpha_scale } => need(
                pos(alpha_scale),
                "kind.alpha_scale".into(),
                "a positive number",
            ),
            ModelKind::Independent => {}
        }
        for (name, h) in [("object", &self.object), ("no_object", &self.no_object)] {
            let kernel_ok = |k: &KernelSpec| {
                pos(k.signal_variance)
                    && k.length_scales.len() == 2
                    && k.length_scales.iter().all(|&l| pos(l))
            };
            need(
                h.mean.is_finite(),
                format!("{name}.mean"),
                "a finite number",
            );
            need(
                kernel_ok(&h.kernel),
                format!("{name}.kernel"),
                "a positive signal_variance and two positive length_scales [range m, aspect rad]",
            );
            need(
                h.noise_variance.is_finite() && h.noise_variance >= 0.0,
                format!("{name}.noise_variance"),
                "a variance ≥ 0",
            );
            need(
                pos(h.spread),
                format!("{name}.spread"),
                "a positive variance",
            );
            need(
                h.points.iter().all(|p| p.iter().all(|v| v.is_finite())),
                format!("{name}.points"),
                "finite [range, aspect, score] triples",
            );
            need(
                h.points.len() <= MAX_POINTS,
                format!("{name}.points"),
                "at most 2000 training points",
            );
            need(
                kernel_ok(&h.corr.kernel),
                format!("{name}.corr.kernel"),
                "a positive signal_variance and two positive length_scales [range m, aspect rad]",
            );
            need(
                pos(h.corr.noise_variance),
                format!("{name}.corr.noise_variance"),
                "a positive variance",
            );
        }
        out
    }

    /// The model at another scale: every range multiplied by `s` (the range length scales of
    /// both GPs, the training points' ranges, `max_range` and the disc radius). Scores and
    /// aspects are unchanged. `scaled(1.0)` is the model itself.
    pub fn scaled(&self, s: f64) -> SensorModelSpec {
        let kernel = |k: &KernelSpec| {
            let mut k = k.clone();
            if let Some(l) = k.length_scales.first_mut() {
                *l *= s;
            }
            k
        };
        let hyp = |h: &HypothesisSpec| HypothesisSpec {
            kernel: kernel(&h.kernel),
            points: h.points.iter().map(|p| [p[0] * s, p[1], p[2]]).collect(),
            corr: CorrSpec {
                kernel: kernel(&h.corr.kernel),
                noise_variance: h.corr.noise_variance,
            },
            ..h.clone()
        };
        SensorModelSpec {
            kind: match self.kind {
                ModelKind::Disc { d_max } => ModelKind::Disc { d_max: d_max * s },
                k => k,
            },
            max_range: self.max_range * s,
            aspect_limit: self.aspect_limit,
            object: hyp(&self.object),
            no_object: hyp(&self.no_object),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hyp() -> HypothesisSpec {
        let k = KernelSpec {
            signal_variance: 1.0,
            length_scales: vec![1.0, 0.5],
        };
        HypothesisSpec {
            mean: 1.0,
            kernel: k.clone(),
            noise_variance: 0.01,
            spread: 0.2,
            points: vec![[2.0, 0.1, 1.5]],
            corr: CorrSpec {
                kernel: k,
                noise_variance: 0.05,
            },
        }
    }

    fn spec() -> SensorModelSpec {
        SensorModelSpec {
            kind: ModelKind::Disc { d_max: 3.0 },
            max_range: 6.0,
            aspect_limit: None,
            object: hyp(),
            no_object: hyp(),
        }
    }

    #[test]
    fn scaling_multiplies_every_range_and_nothing_else() {
        let s = spec().scaled(0.5);
        assert_eq!(s.max_range, 3.0);
        assert_eq!(s.kind, ModelKind::Disc { d_max: 1.5 });
        assert_eq!(s.object.kernel.length_scales, vec![0.5, 0.5]);
        assert_eq!(s.no_object.corr.kernel.length_scales, vec![0.5, 0.5]);
        assert_eq!(s.object.points, vec![[1.0, 0.1, 1.5]]);
        assert_eq!(s.object.mean, 1.0);
        assert_eq!(spec().scaled(1.0), spec());
    }

    #[test]
    fn a_bad_parameter_is_named_by_its_path() {
        let mut s = spec();
        s.no_object.corr.kernel.length_scales = vec![1.0];
        s.object.spread = -1.0;
        let fields: Vec<String> = s.problems().into_iter().map(|(f, _)| f).collect();
        assert_eq!(fields, vec!["object.spread", "no_object.corr.kernel"]);
        assert!(spec().problems().is_empty());
    }
}
