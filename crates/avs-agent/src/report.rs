//! What a search is asked for ([`Goal`]) and what it returns ([`SearchReport`]: the object,
//! why the search ended, the trace and its figures).

use crate::reason::GiveUpReason;
use crate::trace::Event;
use avs_robot::Point3;
use serde::Serialize;

/// A search goal: find an object of a class and report its position.
#[derive(Debug, Clone, PartialEq)]
pub struct Goal {
    /// The object class.
    pub class: String,
    /// Points (metres, world frame) on the floor of the room that holds the target, for the
    /// [`Strategy::Informed`](crate::Strategy::Informed) reference; empty when not told.
    pub region: Vec<[f64; 2]>,
    /// Classes sought by later goals of the same [`Goal::find_all`]: every look of this
    /// search runs the detector for them too, and what it sees of them is kept for their own
    /// searches (which verify it before they plan). Empty for a goal of its own.
    pub also: Vec<String>,
}

impl Goal {
    /// Find an object of `class`.
    pub fn find(class: &str) -> Self {
        Self {
            class: class.to_string(),
            region: Vec::new(),
            also: Vec::new(),
        }
    }

    /// Find an object of each of `classes` at once (Sjöö et al. `004`'s multi-object search):
    /// one goal per class, in the order given (duplicates dropped), each also seeking the
    /// classes after it. Run them with [`Agent::search_all`](crate::Agent::search_all), or
    /// one by one with [`Agent::search`](crate::Agent::search) on the same agent: every look
    /// of a goal's search runs the detector (and the zoom pipeline, with its windows shared
    /// between the classes) for the classes still sought, and a later goal first verifies
    /// what earlier looks saw of its class, nearest first, before it plans a search of its
    /// own. The switching planner keeps one goal at a time (`002` §II-A plans for one
    /// `reported(label)`); what the classes share is every image, not the plan.
    pub fn find_all<S: AsRef<str>>(classes: impl IntoIterator<Item = S>) -> Vec<Goal> {
        let mut order: Vec<String> = Vec::new();
        for c in classes {
            let c = c.as_ref();
            if !order.iter().any(|o| o == c) {
                order.push(c.to_string());
            }
        }
        (0..order.len())
            .map(|i| Goal {
                class: order[i].clone(),
                region: Vec::new(),
                also: order[i + 1..].to_vec(),
            })
            .collect()
    }

    /// The same goal, told that the target lies in the room whose floor holds `points` (for
    /// the informed reference strategy; the other strategies ignore it).
    pub fn in_region(mut self, points: Vec<[f64; 2]>) -> Self {
        self.region = points;
        self
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

/// What the robot was doing while it drove: each metre of odometry goes to the activity of the
/// motion that drove it (the body is the only caller of motion and keeps the account).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Activity {
    /// The plan's own motions: MOVE to a place, ENTER and EXPLORE a placeholder, looking around.
    #[default]
    Exploration,
    /// Inside a SEARCHFOROBJECT session: to the view cones' poses.
    ViewCones,
    /// A closer look at a sighting before it is reported.
    Verification,
    /// The coverage: after the planner gave up, or the baseline strategies.
    Coverage,
}

/// Metres driven per [`Activity`]; they add up to the search's path length.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct PathBreakdown {
    /// The plan's motions between places, into and beyond placeholders.
    pub exploration: f64,
    /// Travel to view cones within searches.
    pub view_cones: f64,
    /// Detours to verify sightings.
    pub verification: f64,
    /// Coverage after the planner gave up (or a baseline strategy's whole path).
    pub coverage: f64,
}

impl PathBreakdown {
    /// Add `metres` to `activity`.
    pub fn add(&mut self, activity: Activity, metres: f64) {
        let slot = match activity {
            Activity::Exploration => &mut self.exploration,
            Activity::ViewCones => &mut self.view_cones,
            Activity::Verification => &mut self.verification,
            Activity::Coverage => &mut self.coverage,
        };
        *slot += metres;
    }

    /// The sum over the activities, metres.
    pub fn total(&self) -> f64 {
        self.exploration + self.view_cones + self.verification + self.coverage
    }
}

/// Figures of one search.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Metrics {
    /// Odometry during this search, metres.
    pub path_length: f64,
    /// `path_length` by what the robot was doing.
    pub path_by_activity: PathBreakdown,
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
    /// Candidate detections handed to verification.
    pub candidates: usize,
    /// Candidates the verifier accepted.
    pub candidates_accepted: usize,
    /// Candidates the verifier rejected.
    pub candidates_rejected: usize,
    /// Verification looks taken (the detour they drove is `path_by_activity.verification`).
    pub verification_looks: usize,
    /// The detector's processing time of the verifiers' score images, seconds, as the robot
    /// reports it (`ScoreReport::detector_seconds`).
    pub verification_detector_s: f64,
    /// Camera images processed by looks (one per one-shot detector call; every attention and
    /// recognition image of the zoom pipeline).
    pub images: usize,
    /// Of `images`, those the zoom pipeline took after a look's first image (middle and final
    /// steps, recognitions).
    pub zoom_images: usize,
    /// Processing time of the zoom pipeline's images as the robot reports it, seconds.
    pub image_s: f64,
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
