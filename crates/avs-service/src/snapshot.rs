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
use crate::remote::{Exchange, RequestKind};
use crate::spec::Spec;
use avs_agent::Beliefs;
use serde::{Deserialize, Serialize};
use serde_json::Value;

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
    /// Every request to a remote robot and its answer, in order (empty for a simulated one).
    /// A map update's grid is stored run-length encoded ([`compact`]): a floor's grid is long
    /// runs of unknown, free and occupied cells, and a search asks for the map after every
    /// action.
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
            robot_log: robot_log.into_iter().map(compact).collect(),
            live: serde_json::to_value(live).ok(),
            beliefs: beliefs.and_then(|b| serde_json::to_value(b).ok()),
        }
    }
}

/// A map update's answer with its grid's `data` run-length encoded as `data_rle`
/// (`[value, count, value, count, …]`); other exchanges as they are.
pub fn compact(mut e: Exchange) -> Exchange {
    if e.kind != RequestKind::MapUpdate {
        return e;
    }
    if let Some(grid) = e
        .answer
        .result
        .as_mut()
        .and_then(|r| r.get_mut("grid"))
        .and_then(|g| g.as_object_mut())
    {
        if let Some(Value::Array(data)) = grid.remove("data") {
            let mut rle: Vec<Value> = Vec::new();
            let mut run: Option<(Value, u64)> = None;
            for v in data {
                match &mut run {
                    Some((x, n)) if *x == v => *n += 1,
                    _ => {
                        if let Some((x, n)) = run.take() {
                            rle.extend([x, n.into()]);
                        }
                        run = Some((v, 1));
                    }
                }
            }
            if let Some((x, n)) = run {
                rle.extend([x, n.into()]);
            }
            grid.insert("data_rle".into(), Value::Array(rle));
        }
    }
    e
}

/// The inverse of [`compact`]; errors name the exchange.
pub fn expand(mut e: Exchange, index: usize) -> Result<Exchange, String> {
    let Some(grid) = e
        .answer
        .result
        .as_mut()
        .and_then(|r| r.get_mut("grid"))
        .and_then(|g| g.as_object_mut())
    else {
        return Ok(e);
    };
    let Some(rle) = grid.remove("data_rle") else {
        return Ok(e);
    };
    let bad = || {
        format!(
            "snapshot.robot_log[{index}].answer.result.grid.data_rle: expected [value, count, …]"
        )
    };
    let rle = rle.as_array().ok_or_else(bad)?;
    if rle.len() % 2 != 0 {
        return Err(bad());
    }
    let mut data = Vec::new();
    for pair in rle.chunks(2) {
        let n = pair[1].as_u64().ok_or_else(bad)?;
        // A grid holds at most 64 million cells (`OccupancyGrid::new`).
        if data.len() as u64 + n > 64_000_000 {
            return Err(bad());
        }
        data.extend(std::iter::repeat_n(pair[0].clone(), n as usize));
    }
    grid.insert("data".into(), Value::Array(data));
    Ok(e)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::remote::Answer;
    use serde_json::json;

    #[test]
    fn a_map_update_survives_compaction_and_other_exchanges_are_untouched() {
        let grid = json!({ "info": { "resolution": 0.5, "width": 3, "height": 2 },
                           "data": [-1, -1, -1, 0, 0, 100] });
        let e = Exchange {
            kind: RequestKind::MapUpdate,
            args: json!({}),
            answer: Answer {
                result: Some(json!({ "grid": grid, "newly_known": 3 })),
                failure: None,
                pose: None,
                travelled: None,
            },
        };
        let c = compact(e.clone());
        let g = &c.answer.result.as_ref().unwrap()["grid"];
        assert_eq!(g["data_rle"], json!([-1, 3, 0, 2, 100, 1]));
        assert!(g.get("data").is_none());
        assert_eq!(expand(c, 0).unwrap(), e);
        let moved = Exchange {
            kind: RequestKind::MoveTo,
            ..e.clone()
        };
        assert_eq!(compact(moved.clone()), moved);
        // A bad run is named, not expanded into memory.
        let mut bad = compact(e);
        bad.answer.result.as_mut().unwrap()["grid"]["data_rle"] = json!([0, 1e12]);
        assert!(expand(bad, 7).unwrap_err().contains("robot_log[7]"));
    }
}
