//! A session's inputs: [`Spec`] (what the client asked for, with every file's text, so a
//! snapshot needs no file) and its loading into checked values ([`Spec::load`]) with the same
//! checks as `avs validate`.

use crate::api::{CreateSession, RobotKind, Source};
use crate::error::ApiError;
use crate::remote::Capability;
use crate::session::Loaded;
use avs_agent::AgentConfig;
use avs_eval::edits::{Start, WorldEdits};
use avs_eval::inputs::{Input, Shipped};
use avs_robot::{Camera, Pose2D};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// One input file: its name in messages, its text and the folder its relative paths (a map
/// image) resolve against.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Text {
    /// The name messages use (the path, `inline`, or a shipped default's).
    pub name: String,
    /// The YAML text.
    pub text: String,
    /// The folder relative paths inside it resolve against.
    pub base_dir: PathBuf,
}

impl Text {
    fn input(&self) -> Input {
        Input {
            name: self.name.clone(),
            text: self.text.clone(),
            base_dir: self.base_dir.clone(),
        }
    }

    /// The text of `source` (the request key `field`), or the shipped default.
    fn read(source: Option<&Source>, field: &str, default: Shipped) -> Result<Self, ApiError> {
        let input = match source {
            None => default.input(),
            Some(Source::Path(p)) => Input::read(std::path::Path::new(p))
                .map_err(|e| ApiError::invalid(field, e.to_string()))?,
            Some(Source::Inline(text)) => Input {
                name: format!("{field} (inline)"),
                text: text.clone(),
                base_dir: PathBuf::from("."),
            },
        };
        Ok(Self {
            name: input.name,
            text: input.text,
            base_dir: input.base_dir,
        })
    }
}

/// What a session was created from; see the module docs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Spec {
    /// The knowledge file.
    pub knowledge: Text,
    /// The planning domain.
    pub domain: Text,
    /// The environment, when there is one.
    pub environment: Option<Text>,
    /// Which robot.
    pub robot: RobotKind,
    /// The simulated robot's seed.
    pub seed: u64,
    /// Looks run the zoom pipeline.
    pub zoom: bool,
    /// The start pose given (else the environment's).
    pub start: Option<Pose2D>,
    /// The camera given (else the environment's, else the default).
    pub camera: Option<avs_format::environment::Camera>,
    /// What a remote robot answers beyond motion, maps and views.
    pub capabilities: Vec<Capability>,
}

impl Spec {
    /// The spec of a creation request (reading the files it names).
    pub fn from_request(r: &CreateSession) -> Result<Self, ApiError> {
        let robot = r.robot.unwrap_or_default();
        let environment = match (&r.environment, robot) {
            (None, RobotKind::Remote) => None,
            (e, _) => Some(Text::read(e.as_ref(), "environment", Shipped::Environment)?),
        };
        Ok(Self {
            knowledge: Text::read(r.knowledge.as_ref(), "knowledge", Shipped::Knowledge)?,
            domain: Text::read(r.domain.as_ref(), "domain", Shipped::Domain)?,
            environment,
            robot,
            seed: r.seed.unwrap_or(1),
            zoom: r.zoom.unwrap_or(false),
            start: r.start,
            camera: r.camera.clone(),
            capabilities: r.capabilities.clone().unwrap_or_default(),
        })
    }

    /// Load and check every input as `avs validate` does; errors name the request key and,
    /// through the file's diagnostics, the file and field.
    pub fn load(&self) -> Result<Loaded, ApiError> {
        let knowledge = self
            .knowledge
            .input()
            .knowledge()
            .map_err(|e| ApiError::invalid("knowledge", e.to_string()))?;
        let domain = self
            .domain
            .input()
            .domain()
            .map_err(|e| ApiError::invalid("domain", e.to_string()))?;
        if let Some(s) = self.start.filter(|s| !s.is_finite()) {
            return Err(ApiError::invalid(
                "start",
                format!(
                    "({}, {}, {}): expected finite metres and radians",
                    s.x, s.y, s.yaw
                ),
            ));
        }
        let edits = WorldEdits {
            start: self.start.map(|s| Start {
                x: s.x,
                y: s.y,
                yaw_deg: s.yaw.to_degrees(),
            }),
            ..WorldEdits::default()
        };
        let world = match &self.environment {
            Some(t) => Some(
                t.input()
                    .edited_world(Some(&knowledge), &edits, |_| "start".to_string())
                    .map_err(|e| ApiError::invalid("environment", e.to_string()))?,
            ),
            None => None,
        };
        let camera_spec = match (&self.camera, &world) {
            (Some(c), _) => c.clone(),
            (None, Some(w)) => w.env.camera.clone(),
            (None, None) => avs_format::environment::Camera::default(),
        };
        check_camera(&camera_spec)?;
        let camera = Camera::from(&camera_spec);
        let start = match (self.start, &world) {
            (Some(s), _) => s,
            (None, Some(w)) => {
                let s = &w.env.robot.start;
                Pose2D::new(s.x, s.y, s.yaw_deg.to_radians())
            }
            (None, None) => {
                return Err(ApiError::invalid(
                    "start",
                    "a remote robot without an environment needs its start pose: \
                     {\"x\", \"y\", \"yaw\"} in metres and radians",
                ))
            }
        };
        if self.robot == RobotKind::Sim && !self.capabilities.is_empty() {
            return Err(ApiError::invalid(
                "capabilities",
                "only a remote robot declares capabilities; the simulated robot has them all",
            ));
        }
        let mut config = AgentConfig {
            zoom_pipeline: self.zoom,
            ..AgentConfig::default()
        };
        if self.zoom {
            // The pipeline's ranges and rates, measured on this camera (as `avs search --zoom`).
            config.measured_sensing =
                avs_eval::zoom_sensing::measured_sensing(&knowledge, &camera, &config.zoom)
                    .map_err(|e| ApiError::invalid("zoom", e.to_string()))?;
        }
        Ok(Loaded {
            knowledge,
            domain,
            world,
            start,
            camera,
            config,
        })
    }
}

/// The camera's values as the environment checks read them: positive finite fields of view
/// under 180°, ordered limits, zoom ≥ 1, a positive height.
fn check_camera(c: &avs_format::environment::Camera) -> Result<(), ApiError> {
    let bad =
        |field: &str, message: String| Err(ApiError::invalid(format!("camera.{field}"), message));
    for (field, v) in [("hfov_deg", c.hfov_deg), ("vfov_deg", c.vfov_deg)] {
        if !(v.is_finite() && v > 0.0 && v < 180.0) {
            return bad(field, format!("{v}: expected degrees in (0, 180)"));
        }
    }
    for (field, [a, b]) in [("pan_deg", c.pan_deg), ("tilt_deg", c.tilt_deg)] {
        if !(a.is_finite() && b.is_finite() && a <= b) {
            return bad(
                field,
                format!("[{a}, {b}]: expected finite degrees [min, max]"),
            );
        }
    }
    if !(c.max_zoom.is_finite() && c.max_zoom >= 1.0) {
        return bad("max_zoom", format!("{}: expected a number ≥ 1", c.max_zoom));
    }
    if !(c.height.is_finite() && c.height > 0.0) {
        return bad("height", format!("{}: expected metres > 0", c.height));
    }
    Ok(())
}
