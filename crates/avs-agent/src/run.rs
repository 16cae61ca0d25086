//! [`Run`]: what belongs to one search and not to the agent's memory — the trace as it is
//! written, the figures, and what the coverage has looked at.

use crate::body::Body;
use crate::memory::Memory;
use crate::reason::{FailedActions, GiveUpReason};
use crate::report::{FoundObject, Metrics};
use crate::trace::{Event, Outcome, TraceSink};
use avs_robot::Robot;
use std::collections::BTreeSet;

/// The key of a point in the set of covered points: the point on a grid of `res` metres.
pub(crate) type PointKey = (i64, i64, i64);

/// The key of point `p` on a grid of `res` metres: the one rounding of points to keys.
pub(crate) fn point_key(res: f64, p: [f64; 3]) -> PointKey {
    (
        (p[0] / res).round() as i64,
        (p[1] / res).round() as i64,
        (p[2] / res).round() as i64,
    )
}

/// One search in progress.
pub(crate) struct Run<'s> {
    pub events: Vec<Event>,
    sink: &'s mut dyn TraceSink,
    pub metrics: Metrics,
    /// The goal class's room points inside processed views during this search (keys of
    /// [`Run::key`]): what the coverage phase need not look at again.
    pub covered: BTreeSet<PointKey>,
    /// Where the coverage went to visit known free space outside every room.
    pub visited: Vec<[f64; 2]>,
    /// The resolution of [`Run::key`], metres.
    key_res: f64,
    /// Actions finished, how many of them failed, and the last failure (action and outcome).
    outcomes: (usize, usize, String),
}

impl<'s> Run<'s> {
    /// A search writing its events to `sink`, remembering covered points on a grid of
    /// `key_res` metres.
    pub fn new(sink: &'s mut dyn TraceSink, key_res: f64) -> Self {
        Self {
            events: Vec::new(),
            sink,
            metrics: Metrics::default(),
            covered: BTreeSet::new(),
            visited: Vec::new(),
            key_res,
            outcomes: (0, 0, String::new()),
        }
    }

    /// The key of a point in [`Run::covered`].
    pub fn key(&self, p: [f64; 3]) -> PointKey {
        point_key(self.key_res, p)
    }

    /// Mark `points` covered.
    pub fn cover(&mut self, points: impl IntoIterator<Item = [f64; 3]>) {
        for p in points {
            let k = self.key(p);
            self.covered.insert(k);
        }
    }

    /// Trace the zoom pipeline's images of the last look ([`Body::take_zoom_images`]), one
    /// `ZOOM` line each.
    pub fn zoomed(&mut self, images: Vec<avs_view::zoom::ZoomImage>) {
        for im in images {
            self.emit(Event::Zoom {
                classes: im.classes,
                zoom: im.cone.zoom,
                pan_deg: im.cone.pan.to_degrees(),
                tilt_deg: im.cone.tilt.to_degrees(),
                step: format!("{:?}", im.step).to_lowercase(),
                kind: format!("{:?}", im.kind).to_lowercase(),
            });
        }
    }

    /// Record and hand on one trace event; logged at `info` for the milestones (a plan, a
    /// violated assumption, a door seen closed or opening, the verdict), at `debug` otherwise.
    pub fn emit(&mut self, e: Event) {
        match &e {
            Event::Started { .. }
            | Event::PlanMade { .. }
            | Event::AssumptionViolated { .. }
            | Event::DoorSeen { .. }
            | Event::GoalReached { .. }
            | Event::GaveUp { .. } => tracing::info!("{}", e.text().trim_end()),
            _ => tracing::debug!(event = %e.json_line(), "trace"),
        }
        self.sink.event(&e);
        self.events.push(e);
    }

    /// Emit the end of an action: its outcome, the robot's pose and the odometry; then the
    /// door news the action brought ([`Run::doors`]).
    pub fn finished<R: Robot + ?Sized>(
        &mut self,
        action: String,
        outcome: Outcome,
        body: &Body<R>,
        mem: &mut Memory,
    ) {
        self.outcomes.0 += 1;
        if !outcome.succeeded() {
            self.outcomes.1 += 1;
            self.outcomes.2 = format!("{action}: {outcome}");
        }
        self.emit(Event::ActionFinished {
            action,
            outcome,
            pose: body.pose3(),
            path_length: body.odometry(),
        });
        self.doors(mem);
    }

    /// The actions of this search that failed so far, when any did.
    pub fn failed_actions(&self) -> Option<FailedActions> {
        let (actions, failed, last) = &self.outcomes;
        (*failed > 0).then(|| FailedActions {
            failed: *failed,
            actions: *actions,
            last: last.clone(),
        })
    }

    /// Emit the door sightings not yet in the trace ([`Memory::door_news`]).
    pub fn doors(&mut self, mem: &mut Memory) {
        for d in std::mem::take(&mut mem.door_news) {
            self.emit(Event::DoorSeen {
                door: d.name,
                at: [d.x, d.y],
                open: d.open,
            });
        }
    }

    /// Whether the search's sink asked it to stop ([`TraceSink::stop_requested`]).
    pub fn stop_requested(&mut self) -> bool {
        self.sink.stop_requested()
    }

    /// Hand the beliefs in `mem` (object probabilities for `class`) to the sink, when it
    /// wants them ([`TraceSink::wants_beliefs`]).
    pub fn beliefs(
        &mut self,
        mem: &Memory,
        knowledge: &avs_format::knowledge::Knowledge,
        class: &str,
    ) {
        if self.sink.wants_beliefs() {
            let b = crate::beliefs::beliefs_of(mem, knowledge, Some(class));
            self.sink.beliefs(&b);
        }
    }

    /// Emit an observation.
    pub fn observe(&mut self, what: String) {
        self.emit(Event::Observed { what });
    }

    /// Emit the goal-reached event for `f`; returns the search's ending reason.
    pub fn goal_reached(&mut self, f: &FoundObject) -> String {
        self.emit(Event::GoalReached {
            object: f.name.clone(),
            pose: [f.pose.x, f.pose.y, f.pose.z],
        });
        format!(
            "found {} {} at ({:.2}, {:.2}, {:.2})",
            f.class, f.name, f.pose.x, f.pose.y, f.pose.z
        )
    }

    /// Emit the give-up event.
    pub fn give_up(&mut self, reason: &GiveUpReason) {
        self.emit(Event::GaveUp {
            reason: reason.to_string(),
        });
    }
}

/// How a plan step ended.
pub(crate) enum StepEnd {
    /// Go on with the plan (after monitoring).
    Continue,
    /// Make a new plan, for this reason.
    Replan(crate::reason::ReplanReason),
    /// The goal's object was found (and verified).
    Found(FoundObject),
}
