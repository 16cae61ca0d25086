//! The plan trace: every decision of the agent as an [`Event`], rendered as text in the style of
//! the papers' listings (Aydemir et al. 2011, `002` Fig. 3: `ASSUME-LEADS-TO-ROOM place1
//! kitchen`, `SEARCHFOROBJECT cerealbox ON new-object1 new-object2`) and as JSON lines.
//!
//! Events carry no wall-clock times, so the same seed gives byte-identical JSON lines; timings
//! are kept in the search metrics instead. Outcomes are enums ([`Outcome`], [`SessionOutcome`])
//! written as the same words in text and JSON; a camera action carries its view ([`View`]) as
//! numbers, so tools need not read them back out of the listing line.

use avs_concepts::RoomId;
use schemars::gen::SchemaGenerator;
use schemars::schema::Schema;
use schemars::JsonSchema;
use serde::{Serialize, Serializer};
use std::fmt;

/// How an action ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// It did what it was for.
    Ok,
    /// A coverage view saw the goal's class and a closer look confirmed it.
    DetectedAndConfirmed,
    /// It failed; the failure as the trace says it.
    Failed(String),
}

impl Outcome {
    /// Whether the action did not fail.
    pub fn succeeded(&self) -> bool {
        !matches!(self, Self::Failed(_))
    }
}

impl fmt::Display for Outcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Ok => f.write_str("ok"),
            Self::DetectedAndConfirmed => f.write_str("detected and confirmed"),
            Self::Failed(e) => f.write_str(e),
        }
    }
}

impl Serialize for Outcome {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// In JSON an outcome is its text: `ok`, `detected and confirmed`, or the failure.
impl JsonSchema for Outcome {
    fn schema_name() -> String {
        "Outcome".into()
    }

    fn json_schema(gen: &mut SchemaGenerator) -> Schema {
        String::json_schema(gen)
    }
}

/// How a view-cone POMDP session ended.
#[derive(Debug, Clone, PartialEq)]
pub enum SessionOutcome {
    /// It declared the object found, and verification confirmed it.
    Found,
    /// It declared the object found, and verification did not confirm it.
    FalseAlarm,
    /// It declared the object absent (or stopped without a declaration).
    Absent,
    /// The session could not be set up.
    Failed(String),
}

impl fmt::Display for SessionOutcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Found => f.write_str("found"),
            Self::FalseAlarm => f.write_str("false alarm"),
            Self::Absent => f.write_str("absent"),
            Self::Failed(e) => write!(f, "failed: {e}"),
        }
    }
}

impl Serialize for SessionOutcome {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// In JSON a session outcome is its text: `found`, `false alarm`, `absent` or `failed: …`.
impl JsonSchema for SessionOutcome {
    fn schema_name() -> String {
        "SessionOutcome".into()
    }

    fn json_schema(gen: &mut SchemaGenerator) -> Schema {
        String::json_schema(gen)
    }
}

/// A camera view: where the robot stood and how the camera pointed (degrees, as every file of
/// avs writes angles; the `Robot` trait takes radians).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, JsonSchema)]
pub struct View {
    /// x of the robot, metres.
    pub x: f64,
    /// y of the robot, metres.
    pub y: f64,
    /// Pan, degrees relative to the robot's heading.
    pub pan_deg: f64,
    /// Tilt, degrees (negative looks down).
    pub tilt_deg: f64,
    /// Zoom factor.
    pub zoom: f64,
}

impl View {
    /// The view from `(x, y)` at `pan` and `tilt` (radians) through `zoom`.
    pub fn new([x, y]: [f64; 2], pan: f64, tilt: f64, zoom: f64) -> Self {
        Self {
            x,
            y,
            pan_deg: pan.to_degrees(),
            tilt_deg: tilt.to_degrees(),
            zoom,
        }
    }
}

/// How many landmarks of a class a look around saw.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct LandmarkCount {
    /// The landmark class.
    pub class: String,
    /// How many were seen (at least one).
    pub count: u32,
}

/// One room category's probability.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct CategoryBelief {
    /// The room category (as the knowledge file names it).
    pub category: String,
    /// P(the room is of this category).
    pub p: f64,
}

/// One event of the plan trace.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
#[serde(tag = "event", rename_all = "snake_case")]
pub enum Event {
    /// The search for a goal started.
    Started {
        /// The object class searched for.
        goal: String,
        /// Robot pose `[x, y, yaw]`.
        pose: [f64; 3],
    },
    /// The continual planner made a plan.
    PlanMade {
        /// 1-based plan number within this search.
        plan: usize,
        /// Why a (new) plan was needed.
        reason: String,
        /// The plan's steps in listing form, assumptions first.
        steps: Vec<String>,
        /// Σ cost of the plan.
        cost: f64,
        /// Π p of the plan.
        probability: f64,
    },
    /// An action of the plan started.
    ActionStarted {
        /// The listing line.
        action: String,
    },
    /// An action of the plan finished.
    ActionFinished {
        /// The listing line.
        action: String,
        /// `ok`, or the failure.
        outcome: Outcome,
        /// Robot pose `[x, y, yaw]` afterwards.
        pose: [f64; 3],
        /// Odometry so far, metres.
        path_length: f64,
    },
    /// What the robot learned (e.g. landmarks seen on entering a room and the room's category).
    Observed {
        /// A description.
        what: String,
    },
    /// The robot looked around on entering a room: the landmarks it saw there and the room's
    /// category distribution afterwards (`002` §III-A, eq. 1).
    LookedAround {
        /// The agent's room id (the `roomN` of plans).
        room: u64,
        /// Where the robot stood `[x, y]`, metres (so that a simulation can name the true room).
        at: [f64; 2],
        /// Landmarks seen, by class (classes seen at least once, in name order).
        landmarks: Vec<LandmarkCount>,
        /// Views of the pan that failed.
        failed_views: usize,
        /// The room's category distribution, in the knowledge file's order.
        categories: Vec<CategoryBelief>,
    },
    /// An assumption of the plan held.
    AssumptionConfirmed {
        /// The assumption's listing line.
        assumption: String,
        /// What confirmed it.
        evidence: String,
    },
    /// An assumption of the plan was contradicted or became too unlikely.
    AssumptionViolated {
        /// The assumption's listing line (or the monitor's description).
        assumption: String,
        /// Why.
        reason: String,
    },
    /// A decision-theoretic (view-cone POMDP) session started.
    DtSessionStarted {
        /// The SEARCHFOROBJECT line that started it.
        search: String,
        /// Number of view cones.
        cones: usize,
        /// P(ObjectAt L) spread over the cones.
        p_location: f64,
    },
    /// One action of the DT session.
    DtAction {
        /// `PROCESSVIEWCONE k` with the view's pose and pan.
        action: String,
        /// Whether the target class was detected (for processed cones).
        detected: Option<bool>,
        /// The view, for a look (PROCESSVIEWCONE, VERIFY).
        #[serde(skip_serializing_if = "Option::is_none")]
        view: Option<View>,
        /// For a VERIFY look, the sighting it looks at `[x, y]`, metres.
        #[serde(skip_serializing_if = "Option::is_none")]
        target: Option<[f64; 2]>,
    },
    /// A DT session ended.
    DtSessionEnded {
        /// How it ended.
        outcome: SessionOutcome,
        /// Cones processed.
        steps: usize,
    },
    /// A sighting became a candidate for verification.
    CandidateCreated {
        /// The object class.
        class: String,
        /// Where the sighting is `[x, y]`, metres.
        at: [f64; 2],
        /// P(it is an object of the class) before any verification look: the conceptual map's
        /// P(ObjectAt L) for its room.
        prior: f64,
        /// The verifier it goes to (`planned`, `planned-disc`, `greedy`, `rtbss`, `count`).
        verifier: String,
    },
    /// A candidate was decided.
    VerificationDecision {
        /// The object class.
        class: String,
        /// Where the sighting is `[x, y]`, metres.
        at: [f64; 2],
        /// Whether it was accepted (and is reported).
        accepted: bool,
        /// The final belief that it is an object (the model verifiers; none for `count`).
        belief: Option<f64>,
        /// Verification looks taken.
        looks: usize,
        /// Metres driven for the verification.
        detour_m: f64,
        /// Why, in words.
        reason: String,
    },
    /// The zoom pipeline took an image after a look's first one (Sjöö et al. `004` §3.1: a
    /// middle-step window, a final zoom, a recognition).
    Zoom {
        /// The classes the image was for.
        classes: Vec<String>,
        /// Zoom factor.
        zoom: f64,
        /// Pan relative to the robot's heading, degrees.
        pan_deg: f64,
        /// Tilt, degrees.
        tilt_deg: f64,
        /// The step of the three-step search: `initial`, `middle` or `final`.
        step: String,
        /// `attention` (vote matrices) or `recognition` (matched features).
        kind: String,
    },
    /// The robot saw a door closed for the first time, or saw a known door open or close
    /// ([`avs_robot::MapUpdate::doors`]; doors first seen open are not news).
    DoorSeen {
        /// The door's name as the robot reports it.
        door: String,
        /// Centre of its opening `[x, y]`, metres.
        at: [f64; 2],
        /// Whether it stands open.
        open: bool,
    },
    /// The goal was reached: the object's position was reported.
    GoalReached {
        /// The reported object.
        object: String,
        /// Its estimated position `[x, y, z]`.
        pose: [f64; 3],
    },
    /// The agent gave up.
    GaveUp {
        /// Why.
        reason: String,
    },
}

fn xy(p: &[f64]) -> String {
    let v: Vec<String> = p.iter().map(|x| format!("{x:.2}")).collect();
    format!("({})", v.join(", "))
}

impl Event {
    /// The event as one JSON line (no trailing newline).
    pub fn json_line(&self) -> String {
        // Serialising plain data with finite or non-finite floats cannot fail with serde_json
        // (non-finite numbers become null).
        serde_json::to_string(self)
            .unwrap_or_else(|e| format!("{{\"event\":\"error\",\"message\":\"{e}\"}}"))
    }

    /// The event as text in the papers' listing style (one or more lines, each ending in `\n`).
    pub fn text(&self) -> String {
        match self {
            Event::Started { goal, pose } => {
                format!("search for {goal} from {}\n", xy(&pose[..2]))
            }
            Event::PlanMade {
                plan,
                reason,
                steps,
                cost,
                probability,
            } => {
                let mut s = format!(
                    "plan {plan} ({reason}; cost {cost:.1}, success probability {probability:.4}):\n"
                );
                for st in steps {
                    s.push_str("    ");
                    s.push_str(st);
                    s.push('\n');
                }
                s
            }
            Event::ActionStarted { action } => format!("  > {action}\n"),
            Event::ActionFinished {
                action,
                outcome,
                pose,
                path_length,
            } => format!(
                "  < {action}: {outcome}; robot at {}, path {path_length:.1} m\n",
                xy(&pose[..2])
            ),
            Event::Observed { what } => format!("  * {what}\n"),
            Event::LookedAround {
                room,
                landmarks,
                failed_views,
                categories,
                ..
            } => {
                let seen = if landmarks.is_empty() {
                    "no landmarks".to_string()
                } else {
                    let v: Vec<String> = landmarks
                        .iter()
                        .map(|l| format!("{} x{}", l.class, l.count))
                        .collect();
                    v.join(", ")
                };
                let failed = if *failed_views > 0 {
                    format!(" ({failed_views} views failed)")
                } else {
                    String::new()
                };
                let beliefs: Vec<String> = categories
                    .iter()
                    .map(|c| format!("P({}) = {:.3}", c.category, c.p))
                    .collect();
                format!(
                    "  * looked around in {}: {seen}{failed}; {}\n",
                    crate::binding::names::room(RoomId(*room)),
                    beliefs.join(", ")
                )
            }
            Event::AssumptionConfirmed {
                assumption,
                evidence,
            } => format!("  + assumption confirmed: {assumption} ({evidence})\n"),
            Event::AssumptionViolated { assumption, reason } => {
                format!("  ! assumption violated: {assumption}: {reason}\n")
            }
            Event::DtSessionStarted {
                search,
                cones,
                p_location,
            } => format!(
                "  DT session started: {search}, {cones} view cones, P(ObjectAt L) = {p_location:.3}\n"
            ),
            Event::DtAction {
                action, detected, ..
            } => match detected {
                Some(true) => format!("      {action}: detected\n"),
                Some(false) => format!("      {action}: not detected\n"),
                None => format!("      {action}\n"),
            },
            Event::DtSessionEnded { outcome, steps } => {
                format!("  DT session ended: {outcome} after {steps} view cones\n")
            }
            Event::CandidateCreated {
                class,
                at,
                prior,
                verifier,
            } => format!(
                "  ? candidate created: {class} at {}, prior {prior:.3}, verifier {verifier}\n",
                xy(at)
            ),
            Event::VerificationDecision {
                class,
                at,
                accepted,
                looks,
                detour_m,
                reason,
                ..
            } => format!(
                "  ? verification decision: {class} at {} {} ({reason}; {looks} looks, detour {detour_m:.1} m)\n",
                xy(at),
                if *accepted { "accepted" } else { "rejected" }
            ),
            Event::Zoom {
                classes,
                zoom,
                pan_deg,
                tilt_deg,
                step,
                kind,
            } => format!(
                "        ZOOM {} x{zoom:.1} at {pan_deg:.1},{tilt_deg:.1} ({step} {kind})\n",
                classes.join(",")
            ),
            Event::DoorSeen { door, at, open } => {
                let state = if *open { "open" } else { "closed" };
                format!("  * door {door} at {} is {state}\n", xy(at))
            }
            Event::GoalReached { object, pose } => {
                format!("goal reached: REPORTPOSITION {object} at {}\n", xy(pose))
            }
            Event::GaveUp { reason } => format!("gave up: {reason}\n"),
        }
    }
}

/// The observer of a search: receives its trace events as they happen (e.g. a printer that
/// flushes each line) and, when it asks for them, the agent's beliefs before every plan; it
/// may ask the search to stop (a service cancelling a goal). A closure `FnMut(&Event)` is a
/// sink that only receives events.
pub trait TraceSink {
    /// Called once per event, in order.
    fn event(&mut self, e: &Event);

    /// Whether [`TraceSink::beliefs`] should be called: building the beliefs costs a pass over
    /// the conceptual map, so a sink that does not show them is not handed any.
    fn wants_beliefs(&self) -> bool {
        false
    }

    /// The agent's beliefs as they stand before each plan and at the end of the search
    /// (called only when [`TraceSink::wants_beliefs`]).
    fn beliefs(&mut self, b: &crate::beliefs::Beliefs) {
        let _ = b;
    }

    /// Asked before every plan and every action of the plan or the coverage: `true` ends the
    /// search at once with [`GiveUpReason::Cancelled`](crate::GiveUpReason::Cancelled). An
    /// action already under way is the robot's to end (a service fails its outstanding
    /// requests).
    fn stop_requested(&mut self) -> bool {
        false
    }
}

impl<F: FnMut(&Event)> TraceSink for F {
    fn event(&mut self, e: &Event) {
        self(e)
    }
}

/// Render a whole trace as text.
pub fn render_text(events: &[Event]) -> String {
    events.iter().map(Event::text).collect()
}

/// Render a whole trace as JSON lines (each ending in `\n`).
pub fn render_json_lines(events: &[Event]) -> String {
    events
        .iter()
        .map(|e| {
            let mut s = e.json_line();
            s.push('\n');
            s
        })
        .collect()
}

/// The JSON Schema of one line of a JSON-lines trace (one [`Event`]; `avs schema trace`).
pub fn schema_json() -> String {
    let schema = schemars::schema_for!(Event);
    // Serialising a schema (plain maps, strings and numbers) cannot fail.
    serde_json::to_string_pretty(&schema).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plan_event_renders_one_listing_line_per_step_and_valid_json() {
        let e = Event::PlanMade {
            plan: 1,
            reason: "initial".into(),
            steps: vec![
                "ASSUME-LEADS-TO-ROOM placeholder0 kitchen".into(),
                "MOVE placeholder0".into(),
            ],
            cost: 3.0,
            probability: 0.25,
        };
        let t = e.text();
        assert!(t.contains("\n    ASSUME-LEADS-TO-ROOM placeholder0 kitchen\n"));
        assert_eq!(t.lines().count(), 3);
        let v: serde_json::Value = serde_json::from_str(&e.json_line()).unwrap();
        assert_eq!(v["event"], "plan_made");
        assert_eq!(v["steps"][1], "MOVE placeholder0");
    }
}
