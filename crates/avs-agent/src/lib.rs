//! # avs-agent
//!
//! The agent of avs. For now this crate holds the boundary between the agent and a robot — the
//! [`Robot`] trait and its plain data types — and the agent's [`world_model`], which keeps the
//! place map and the conceptual map in step (the executive that plans and acts comes next). A real robot implements it with its own drivers;
//! the simulator (`avs-sim`, module `sim_robot`) implements it with the knowledge file's sensor
//! models. The agent never reads ground truth: everything it learns comes through this trait,
//! as a real robot would report it (its pose estimate, the laser map, detections with estimated
//! poses and confidences, and action outcomes, including failures with a reason).
//!
//! ## Design choices
//!
//! * **Camera requests are view cones.** A view cone (Aydemir et al. 2011, §I-A: a sensing
//!   action `s(x_c, y_c, z_c, p, t, f, a)`) is given by the robot pose from which it is taken
//!   and the camera's pan, tilt and zoom ([`ViewCone`]); the camera height is the robot's own
//!   ([`Robot::camera`]). Zoom divides the fields of view and multiplies the detection
//!   distances (Sjöö, Gálvez López et al., §2.1.3 and §3.4 eq. 1).
//! * **Places are the agent's.** The robot moves to metric poses; the agent maps its places to
//!   poses. A robot that cannot reach a pose reports [`FailureReason::Unreachable`].
//! * **Failures are outcomes, not errors.** Every action returns an [`ActionResult`]; a failed
//!   action says why ([`ActionFailure`]) so the agent can monitor and replan.
//! * **Map updates are whole grids.** [`MapUpdate`] carries the robot's current laser map as an
//!   [`OccupancyGrid`](avs_map::grid::OccupancyGrid) plus how many cells became known since
//!   the previous update, so an agent can skip re-segmenting when nothing changed.
//!
//! ```
//! use avs_agent::{Pose2D, ViewCone};
//! let cone = ViewCone::new(Pose2D::new(1.0, 2.0, 0.0), 0.5, -0.2, 2.0);
//! assert!(cone.check(&avs_format::environment::Camera::default()).is_ok());
//! let bad = ViewCone { zoom: f64::NAN, ..cone };
//! assert!(bad.check(&avs_format::environment::Camera::default()).is_err());
//! ```
#![warn(missing_docs)]

pub mod agent;
pub mod robot;
pub mod trace;
pub mod world_model;

pub use agent::{Agent, AgentConfig, AgentError, FoundObject, Goal, Metrics, SearchReport};
pub use trace::{Event, TraceSink};

pub use robot::{
    ActionFailure, ActionResult, Detection, FailureReason, MapUpdate, MoveReport, Point3, Pose2D,
    Robot, ViewCone, ViewReport,
};
