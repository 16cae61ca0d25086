//! What a search is asked for ([`Goal`]) and what it returns ([`SearchReport`]: the object,
//! why the search ended, the trace and its figures).

use crate::reason::GiveUpReason;
use crate::trace::Event;
use avs_robot::Point3;
use serde::Serialize;

/// A search goal: find an object of a class and report its position.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Goal {
    /// The object class.
    pub class: String,
}

impl Goal {
    /// Find an object of `class`.
    pub fn find(class: &str) -> Self {
        Self {
            class: class.to_string(),
        }
    }
}

/// The object the agent reported.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FoundObject {
    /// Its name in the plans (`object3`).
    pub name: String,
    /// Its class.
    pub class: String,
    /// Its estimated position.
    pub pose: Point3,
    /// The detector's confidence in the sighting that found it.
    pub confidence: f64,
}

/// Figures of one search.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Metrics {
    /// Odometry during this search, metres.
    pub path_length: f64,
    /// Plans made.
    pub plans: usize,
    /// DT (view-cone POMDP) sessions run.
    pub dt_sessions: usize,
    /// Actions executed (not counting assumptions).
    pub actions: usize,
    /// Wall time of each planning call, ms.
    pub plan_ms: Vec<f64>,
    /// Wall time of each DT decision (next action), ms.
    pub dt_ms: Vec<f64>,
}

/// What a search returned.
#[derive(Debug, Clone, PartialEq)]
pub struct SearchReport {
    /// The reported object, when the goal was reached.
    pub found: Option<FoundObject>,
    /// Why the search ended (goal reached, or why it gave up), as the trace says it.
    pub reason: String,
    /// Why the search gave up, when it did.
    pub gave_up: Option<GiveUpReason>,
    /// The plan trace.
    pub trace: Vec<Event>,
    /// Figures.
    pub metrics: Metrics,
}
