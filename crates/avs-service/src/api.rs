//! The API's plain data: request and response bodies, serde at the edge, with their OpenAPI
//! schemas. Keys named in the service's contract (`docs/SERVICE.md`) are kept as they are.

use crate::remote::Capability;
use avs_robot::Pose2D;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use utoipa::ToSchema;

/// Where an input file comes from: a path the server can read, or the text itself.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Source {
    /// A file on the server (relative paths from the server's working directory).
    Path(String),
    /// The file's YAML text.
    Inline(String),
}

/// Which robot a session drives.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum RobotKind {
    /// The server's simulated robot in the session's environment.
    #[default]
    Sim,
    /// The client is the robot: it answers the agent's requests (`GET …/robot/next`).
    Remote,
}

/// `POST /v1/sessions`: a new session, or (`snapshot` alone) a restored one.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct CreateSession {
    /// The knowledge file (default: the shipped office knowledge).
    #[serde(default)]
    pub knowledge: Option<Source>,
    /// The planning domain (default: the shipped object-search domain).
    #[serde(default)]
    pub domain: Option<Source>,
    /// The environment: the simulated robot's world; for a remote robot, only its camera and
    /// start (default for `sim`: the shipped office).
    #[serde(default)]
    pub environment: Option<Source>,
    /// `sim` (default) or `remote`.
    #[serde(default)]
    pub robot: Option<RobotKind>,
    /// The simulated robot's seed (default 1).
    #[serde(default)]
    pub seed: Option<u64>,
    /// Looks run the zoom pipeline (default false).
    #[serde(default)]
    pub zoom: Option<bool>,
    /// The robot's start pose (metres, radians); required for a remote robot without an
    /// environment.
    #[serde(default)]
    #[schema(value_type = Option<Object>)]
    pub start: Option<Pose2D>,
    /// The camera as environment files write it (degrees, metres).
    #[serde(default)]
    #[schema(value_type = Option<Object>)]
    pub camera: Option<avs_format::environment::Camera>,
    /// The optional calls a remote robot answers.
    #[serde(default)]
    pub capabilities: Option<Vec<Capability>>,
    /// A snapshot from `GET /v1/sessions/{id}/snapshot` to restore.
    #[serde(default)]
    #[schema(value_type = Option<Object>)]
    pub snapshot: Option<Box<crate::snapshot::Snapshot>>,
}

/// `201` of `POST /v1/sessions`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct Created {
    /// The session's id.
    pub id: String,
}

/// `POST /v1/sessions/{id}/goals`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct GoalRequest {
    /// The object class to find.
    pub class: String,
    /// Classes later goals will seek: every look of this search also runs the detector for
    /// them (`Goal::find_all`).
    #[serde(default)]
    pub also: Vec<String>,
}

/// `202` of `POST /v1/sessions/{id}/goals`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct GoalCreated {
    /// The goal's id within its session.
    pub goal_id: String,
}

/// Where a goal stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum GoalState {
    /// Posted; runs when the goals before it have ended.
    Queued,
    /// The agent is searching.
    Running,
    /// The object was found and reported.
    Found,
    /// The agent gave up.
    NotFound,
    /// Cancelled before it ended.
    Cancelled,
    /// The search stopped with an error (see `error`).
    Failed,
}

impl GoalState {
    /// Whether the goal has ended.
    pub fn ended(self) -> bool {
        !matches!(self, Self::Queued | Self::Running)
    }
}

/// `GET /v1/sessions/{id}/goals/{goal_id}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct GoalStatus {
    /// The goal's id.
    pub goal_id: String,
    /// The class sought.
    pub class: String,
    /// Where it stands.
    pub state: GoalState,
    /// When it ended: the keys of `avs search --json`.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Object>)]
    pub report: Option<Value>,
    /// Why it failed, for `failed`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

/// `GET /v1/sessions/{id}/goals`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct GoalList {
    /// Every goal of the session, in the order posted.
    pub goals: Vec<GoalStatus>,
}

/// One session, as `GET /v1/sessions/{id}` and the session list show it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct SessionInfo {
    /// Its id.
    pub id: String,
    /// `sim` or `remote`.
    pub robot: RobotKind,
    /// The simulated robot's seed.
    pub seed: u64,
    /// `running` while a goal runs, else `idle`.
    pub state: String,
    /// Goals posted.
    pub goals: usize,
    /// The robot's pose as last reported.
    #[schema(value_type = Object)]
    pub pose: Pose2D,
    /// Metres driven since the session began.
    pub odometry: f64,
    /// The pending robot request, for a remote robot.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pending_request: Option<u64>,
    /// Seconds since the last request or robot activity.
    pub idle_s: f64,
}

/// `GET /v1/sessions`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct SessionList {
    /// Every session, oldest first.
    pub sessions: Vec<SessionInfo>,
}

/// `GET /healthz`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct Health {
    /// `ok`.
    pub status: String,
    /// Sessions held.
    pub sessions: usize,
    /// The avs version.
    pub version: String,
}

/// Query of `GET …/robot/next`.
#[derive(Debug, Clone, Copy, Default, Deserialize, utoipa::IntoParams)]
#[serde(deny_unknown_fields)]
pub struct NextQuery {
    /// How long to wait for a request, ms (default 0: answer at once; at most 60000).
    pub timeout_ms: Option<u64>,
}

/// Query of `GET …/trace`.
#[derive(Debug, Clone, Default, Deserialize, utoipa::IntoParams)]
#[serde(deny_unknown_fields)]
pub struct TraceQuery {
    /// Only this goal's lines.
    pub goal: Option<String>,
}

/// Query of `GET …/map.svg`.
#[derive(Debug, Clone, Default, Deserialize, utoipa::IntoParams)]
#[serde(deny_unknown_fields)]
pub struct MapQuery {
    /// List the current plan under the map (default true).
    pub plan: Option<bool>,
}

/// Query of `GET …/beliefs`.
#[derive(Debug, Clone, Default, Deserialize, utoipa::IntoParams)]
#[serde(deny_unknown_fields)]
pub struct BeliefsQuery {
    /// The class whose P(ObjectAt L) to give (default: the current or last goal's class).
    pub class: Option<String>,
}

/// `GET /v1/sessions/{id}/metrics`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct SessionMetrics {
    /// Goals posted.
    pub goals: usize,
    /// Goals found.
    pub found: usize,
    /// Goals ended without the object (not found, cancelled, failed).
    pub not_found: usize,
    /// Metres driven since the session began.
    pub odometry: f64,
    /// Trace lines written.
    pub trace_lines: usize,
    /// Robot requests made (a remote robot's round trips; the simulated robot's calls).
    pub robot_requests: u64,
    /// Per ended goal: its id and the report's figures (`avs search --json` keys).
    #[schema(value_type = Vec<Object>)]
    pub per_goal: Vec<Value>,
}
