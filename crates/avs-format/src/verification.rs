//! `kind: verification` — a detection-verification scenario (Velez et al. 2012 §8): a map, a
//! start and a goal, and the features a detector may respond to — objects of the class and
//! look-alike non-objects — with their positions and facings. The robot drives from the start
//! to the goal, runs the detector on the way, verifies what fires, and is scored by precision,
//! recall and path length (`avs verify-bench`, run by `avs-eval`).
//!
//! [`check`] checks a file's fields (what `avs validate` runs); that features and the start
//! and goal lie on free cells of the map is checked when the map is built (`avs-eval`), which
//! names the field too.

use crate::environment::{MapSource, Point};
use crate::Diagnostic;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A verification scenario file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VerificationScenario {
    /// Must be `verification`.
    pub kind: VerificationKind,
    /// Short name, e.g. `single-door`.
    pub name: String,
    /// What the scenario re-enacts.
    #[serde(default)]
    pub description: String,
    /// The occupancy grid (as in environment files).
    pub map: MapSource,
    /// Where the robot starts, metres.
    pub start: Point,
    /// Where the robot is going, metres.
    pub goal: Point,
    /// Robot radius, metres.
    #[serde(default = "default_radius")]
    pub robot_radius: f64,
    /// The detector: which simulated detector profile scores the features, and which trained
    /// sensor model the verifier uses.
    pub detector: DetectorName,
    /// P(object) of a new candidate before its first score.
    #[serde(default = "default_prior")]
    pub prior: f64,
    /// Metres driven between two detector images on the way to the goal.
    #[serde(default = "default_look_every")]
    pub look_every: f64,
    /// Horizontal field of view of the camera, degrees.
    #[serde(default = "default_fov")]
    pub fov_deg: f64,
    /// The features the detector may respond to.
    pub features: Vec<Feature>,
}

fn default_radius() -> f64 {
    0.25
}
fn default_prior() -> f64 {
    0.5
}
fn default_look_every() -> f64 {
    1.0
}
fn default_fov() -> f64 {
    60.0
}

/// The literal `verification`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum VerificationKind {
    /// `kind: verification`
    Verification,
}

/// The detectors of the verification scenarios (Velez et al. §7): a door detector, a text
/// (sign) detector, and a generic object detector.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum DetectorName {
    /// Doors: two-sided planar features.
    Door,
    /// Text signs: one-sided planar features, unseen beyond 45° of aspect.
    Sign,
    /// Objects that look alike from every side.
    Generic,
}

impl std::str::FromStr for DetectorName {
    type Err = String;

    /// The name as written in files (`door`, `sign`, `generic`).
    fn from_str(s: &str) -> Result<Self, String> {
        [Self::Door, Self::Sign, Self::Generic]
            .into_iter()
            .find(|d| d.as_str() == s)
            .ok_or_else(|| format!("`{s}`: expected door, sign or generic"))
    }
}

impl DetectorName {
    /// The name as written in files.
    pub fn as_str(self) -> &'static str {
        match self {
            DetectorName::Door => "door",
            DetectorName::Sign => "sign",
            DetectorName::Generic => "generic",
        }
    }
}

/// A feature: an object of the detector's class or a look-alike.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Feature {
    /// x, metres.
    pub x: f64,
    /// y, metres.
    pub y: f64,
    /// The direction the feature faces (its normal), degrees counter-clockwise from +x.
    #[serde(default)]
    pub facing_deg: f64,
    /// Whether it is an object of the class (`false`: a look-alike).
    pub object: bool,
}

/// Most features a scenario may hold (the verifier's cost grows with them).
pub const MAX_FEATURES: usize = 200;

impl VerificationScenario {
    /// Check the fields: finite numbers, positive sizes, a probability for the prior, at least
    /// one feature and at most [`MAX_FEATURES`].
    pub fn check_fields(&self, file: &str) -> Vec<Diagnostic> {
        let mut out = Vec::new();
        let mut finite = |path: String, v: f64| {
            if !v.is_finite() {
                out.push(Diagnostic::new(
                    file,
                    path,
                    format!("{v} is not a finite number"),
                    "a finite number",
                ));
            }
        };
        finite("start.x".into(), self.start.x);
        finite("start.y".into(), self.start.y);
        finite("goal.x".into(), self.goal.x);
        finite("goal.y".into(), self.goal.y);
        for (i, f) in self.features.iter().enumerate() {
            finite(format!("features[{i}].x"), f.x);
            finite(format!("features[{i}].y"), f.y);
            finite(format!("features[{i}].facing_deg"), f.facing_deg);
        }
        let mut positive = |path: &str, v: f64, what: &str| {
            if !(v.is_finite() && v > 0.0) {
                out.push(Diagnostic::new(file, path, format!("{v}"), what));
            }
        };
        positive(
            "robot_radius",
            self.robot_radius,
            "a positive radius in metres",
        );
        positive(
            "look_every",
            self.look_every,
            "a positive distance in metres",
        );
        if !(self.fov_deg.is_finite() && self.fov_deg > 0.0 && self.fov_deg <= 360.0) {
            out.push(Diagnostic::new(
                file,
                "fov_deg",
                format!("{}", self.fov_deg),
                "an angle in (0, 360] degrees",
            ));
        }
        if !(self.prior > 0.0 && self.prior < 1.0) {
            out.push(Diagnostic::new(
                file,
                "prior",
                format!("{}", self.prior),
                "a probability strictly between 0 and 1",
            ));
        }
        if self.features.is_empty() {
            out.push(Diagnostic::new(
                file,
                "features",
                "empty",
                "at least one feature (an object or a look-alike)",
            ));
        }
        if self.features.len() > MAX_FEATURES {
            out.push(Diagnostic::new(
                file,
                "features",
                format!("{} features", self.features.len()),
                format!("at most {MAX_FEATURES}"),
            ));
        }
        out
    }
}

/// Parse and check a verification scenario's text: what `avs validate` runs.
pub fn check(file: &str, text: &str) -> Vec<Diagnostic> {
    crate::load::check_with(file, text, VerificationScenario::check_fields)
}

/// Parse and check a verification scenario's text: the scenario, or every problem found.
pub fn parse(file: &str, text: &str) -> Result<VerificationScenario, crate::LoadError> {
    crate::load::parse_checked(file, text, VerificationScenario::check_fields)
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = "kind: verification
name: tiny
map: { ascii: \"######\\n#....#\\n######\", resolution: 0.5 }
start: { x: 0.75, y: 0.75 }
goal: { x: 2.25, y: 0.75 }
detector: door
features:
  - { x: 1.5, y: 1.0, facing_deg: -90, object: true }
";

    #[test]
    fn a_good_file_has_no_diagnostics() {
        assert_eq!(check("v.yaml", GOOD), vec![]);
    }

    #[test]
    fn a_bad_prior_and_a_bad_detector_name_their_fields() {
        let d = check(
            "v.yaml",
            &GOOD.replace("detector: door", "detector: door\nprior: 1.5"),
        );
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].path, "prior");
        assert_eq!(d[0].line, Some(7));
        let d = check("v.yaml", &GOOD.replace("detector: door", "detector: lamp"));
        assert_eq!(d[0].path, "detector", "{d:?}");
        let d = check("v.yaml", &GOOD.replace("x: 1.5", "x: .nan"));
        assert_eq!(d[0].path, "features[0].x", "{d:?}");
    }
}
