//! [`Snapshot`]: a session as JSON, from which it can be re-created after a restart with
//! nothing lost.
//!
//! **Choice: a replay record, not a memory dump.** The agent's memory (place map, conceptual
//! map with its BP messages, view cones, verifier models, caches) is large, internal and
//! changes shape as the agent improves; serialising it would freeze those internals into a
//! file format. The agent is deterministic given what its robot reports, so a session is fully
//! determined by its inputs (every file's text, seed, robot, start, camera), the goals in
//! order (with the checkpoint at which a cancelled one stopped) and — for a remote robot —
//! every request and answer. Restoring runs the same goals against the same answers (a
//! simulated robot with the same seed, or the recorded answers) and rebuilds the same memory;
//! the replay is checked line by line against the recorded trace, so a snapshot that no longer
//! replays (another avs version, an edited input) is refused instead of restored wrong. The
//! cost is the replay's compute (the agent's planning, not the robot's driving: seconds for
//! a search that drove for minutes). The maps, beliefs and found objects are in the snapshot
//! too, for tools; a restore does not read them.

use crate::api::GoalState;
use crate::live::LiveSummary;
use crate::remote::Exchange;
use crate::spec::Spec;
use avs_agent::Beliefs;
use serde::{Deserialize, Serialize};

/// The format's name and version.
pub const FORMAT: &str = "avs-session-snapshot/1";

/// One goal of a snapshot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GoalRecord {
    /// Its id.
    pub goal_id: String,
    /// The class sought.
    pub class: String,
    /// Classes later goals seek.
    #[serde(default)]
    pub also: Vec<String>,
    /// Where it stood.
    pub state: GoalState,
    /// Its report, if it ended.
    #[serde(default)]
    pub report: Option<serde_json::Value>,
    /// Why it failed.
    #[serde(default)]
    pub error: Option<String>,
    /// The checkpoint at which a cancelled search stopped.
    #[serde(default)]
    pub cancelled_at: Option<u64>,
    /// Its trace, as JSON lines.
    #[serde(default)]
    pub trace: Vec<String>,
}

/// A session as JSON; see the module docs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    /// [`FORMAT`].
    pub format: String,
    /// The avs version that took it.
    pub version: String,
    /// The session's inputs.
    pub spec: Spec,
    /// Every goal, in the order posted.
    pub goals: Vec<GoalRecord>,
    /// Every request to a remote robot and its answer, in order (empty for a simulated one);
    /// a map update's grid as the session keeps it, run-length encoded (`grid.data_rle`,
    /// `[value, count, …]`).
    #[serde(default)]
    pub robot_log: Vec<Exchange>,
    /// The robot's pose, odometry, trail and map as they stood (for tools; not read back).
    #[serde(default)]
    pub live: Option<serde_json::Value>,
    /// The agent's beliefs as they stood: rooms, placeholders, doors, found objects (for
    /// tools; not read back).
    #[serde(default)]
    pub beliefs: Option<serde_json::Value>,
}

impl Snapshot {
    /// A snapshot of these parts.
    pub fn new(
        spec: Spec,
        goals: Vec<GoalRecord>,
        robot_log: Vec<Exchange>,
        live: LiveSummary,
        beliefs: Option<Beliefs>,
    ) -> Self {
        Self {
            format: FORMAT.to_string(),
            version: env!("CARGO_PKG_VERSION").to_string(),
            spec,
            goals,
            robot_log,
            live: serde_json::to_value(live).ok(),
            beliefs: beliefs.and_then(|b| serde_json::to_value(b).ok()),
        }
    }
}
