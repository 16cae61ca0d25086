//! The remote-robot protocol: [`RemoteRobot`] is a [`Robot`] whose every call becomes a
//! request ([`RobotRequest`]) that a client long-polls (`GET …/robot/next`) and answers
//! (`POST …/robot/{request_id}`); [`RemoteLink`] is the meeting point of the agent's thread,
//! which blocks on the answer, and the HTTP handlers.
//!
//! The agent asks one thing at a time, so at most one request is outstanding; `next` hands the
//! same outstanding request to every poller until it is answered (a client that restarts
//! mid-request gets it again). An answer is checked against its kind's result type before it
//! is accepted: a malformed answer is refused with the field named and the request stays
//! open. Every exchange is kept ([`Exchange`]) for the session's snapshot, and a restored
//! session replays them ([`RemoteRobot::replaying`]).

use crate::error::{from_str, ApiError, ErrorCode};
use crate::grid::RosGrid;
use avs_map::grid::{Cell, OccupancyGrid};
use avs_robot::{
    ActionFailure, ActionResult, AttentionReport, Camera, DoorSighting, FailureReason, MapUpdate,
    MoveReport, PlaceReading, Point3, Pose2D, RecognitionReport, Robot, ScoreReport, ViewCone,
    ViewReport,
};
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};
use std::collections::VecDeque;
use std::sync::{mpsc, Arc, Mutex};
use std::time::Duration;
use utoipa::ToSchema;

/// What the agent asks of the robot: one [`Robot`] method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum RequestKind {
    /// [`Robot::move_to`]: args `{"goal": pose}`, result `{"pose", "travelled"}`.
    MoveTo,
    /// [`Robot::map_update`]: args `{}`, result `{"grid", "newly_known", "doors"}`.
    MapUpdate,
    /// [`Robot::process_view_cone`]: args `{"cone", "classes"}`, result
    /// `{"pose", "detections", "travelled"}`.
    ProcessViewCone,
    /// [`Robot::classify_place`]: args `{}`, result `{"readings"}`.
    ClassifyPlace,
    /// [`Robot::detector_scores`]: args `{"cone", "class", "at"}`, result a `ScoreReport`.
    DetectorScores,
    /// [`Robot::attention`]: args `{"cone", "classes"}`, result an `AttentionReport`.
    Attention,
    /// [`Robot::recognise`]: args `{"cone", "class"}`, result a `RecognitionReport`.
    Recognise,
}

impl RequestKind {
    /// The kind's word on the wire.
    pub fn word(self) -> &'static str {
        match self {
            Self::MoveTo => "move_to",
            Self::MapUpdate => "map_update",
            Self::ProcessViewCone => "process_view_cone",
            Self::ClassifyPlace => "classify_place",
            Self::DetectorScores => "detector_scores",
            Self::Attention => "attention",
            Self::Recognise => "recognise",
        }
    }
}

/// The optional calls a remote robot declares it answers (`capabilities` of a session);
/// the others get the [`Robot`] trait's default (no readings, or `unsupported`) from the
/// server itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum Capability {
    /// Place classifiers (`classify_place`).
    ClassifyPlace,
    /// Detector scores at hypothesised locations (`detector_scores`).
    DetectorScores,
    /// Attention vote matrices (`attention`).
    Attention,
    /// Feature recognition (`recognise`).
    Recognise,
}

/// A request to the robot, as `GET …/robot/next` returns it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct RobotRequest {
    /// Answer with `POST …/robot/{request_id}`.
    pub request_id: u64,
    /// Which call.
    pub kind: RequestKind,
    /// Its arguments (see the kind).
    #[schema(value_type = Object)]
    pub args: Value,
}

/// A robot's answer to a request: exactly one of `result` and `failure`; `pose` may say where
/// a failed action left the robot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct Answer {
    /// The result, of the request kind's type.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Object>)]
    pub result: Option<Value>,
    /// Why the call failed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Object>)]
    pub failure: Option<ActionFailure>,
    /// Where the robot is after a failed call (a motion aborted half-way), when it knows.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Object>)]
    pub pose: Option<Pose2D>,
    /// Metres driven by a failed call before it failed (added to the odometry; the agent
    /// tells a robot that cannot move from one that was stopped on the way by it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub travelled: Option<f64>,
}

impl Answer {
    /// A failure answer made by the server itself.
    fn failed(reason: FailureReason, message: impl Into<String>) -> Self {
        Self {
            result: None,
            failure: Some(ActionFailure::new(reason, message)),
            pose: None,
            travelled: None,
        }
    }
}

/// An answer as the client sent it: [`Answer`] with its `result` unread, to be read typed
/// for the request's kind ([`RemoteLink::answer`]).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnswerWire<'a> {
    /// The result, as sent.
    #[serde(default, borrow)]
    pub result: Option<&'a serde_json::value::RawValue>,
    /// Why the call failed.
    #[serde(default)]
    pub failure: Option<ActionFailure>,
    /// Where a failed call left the robot.
    #[serde(default)]
    pub pose: Option<Pose2D>,
    /// Metres a failed call drove first.
    #[serde(default)]
    pub travelled: Option<f64>,
}

/// One request and the answer the agent got: the remote session's record.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Exchange {
    /// Which call.
    pub kind: RequestKind,
    /// Its arguments.
    pub args: Value,
    /// What the agent got.
    pub answer: Answer,
}

/// The result of a `map_update` on the wire.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct MapUpdateWire {
    grid: RosGrid,
    newly_known: usize,
    #[serde(default)]
    doors: Vec<DoorSighting>,
}

/// A map update's result as the session keeps it: the grid's `data` run-length encoded as
/// `data_rle` (`[value, count, value, count, …]`). A floor's grid is long runs of unknown,
/// free and occupied cells and a search asks for the map after every action: kept as JSON
/// numbers, a 1000 × 1000 grid took 32 MB per update.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct StoredMap {
    grid: StoredGrid,
    newly_known: usize,
    #[serde(default)]
    doors: Vec<DoorSighting>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct StoredGrid {
    info: crate::grid::MapInfo,
    /// The cells as sent (a client's answer read back, an old record).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    data: Option<Vec<i8>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    data_rle: Option<Vec<i64>>,
}

impl MapUpdateWire {
    /// The stored form: `data` run-length encoded.
    fn stored(&self) -> Value {
        let mut rle: Vec<i64> = Vec::new();
        for &v in &self.grid.data {
            match rle.len() {
                n if n >= 2 && rle[n - 2] == i64::from(v) => rle[n - 1] += 1,
                _ => rle.extend([i64::from(v), 1]),
            }
        }
        serde_json::to_value(StoredMap {
            grid: StoredGrid {
                info: self.grid.info,
                data: None,
                data_rle: Some(rle),
            },
            newly_known: self.newly_known,
            doors: self.doors.clone(),
        })
        .unwrap_or(Value::Null)
    }

    /// A map update from its stored (or sent) form; the runs may not add up to more cells
    /// than the grid has.
    fn from_stored(v: &Value) -> Result<Self, String> {
        let m = StoredMap::deserialize(v).map_err(|e| format!("a stored map update: {e}"))?;
        let cells = m.grid.info.width.saturating_mul(m.grid.info.height);
        let data = match (m.grid.data, m.grid.data_rle) {
            (Some(d), None) => d,
            (None, Some(rle)) => {
                if rle.len() % 2 != 0 {
                    return Err("grid.data_rle: expected [value, count, …] pairs".into());
                }
                let mut d = Vec::new();
                for pair in rle.chunks(2) {
                    let (v, n) = (pair[0], pair[1]);
                    let v = i8::try_from(v).map_err(|_| format!("grid.data_rle: value {v}"))?;
                    if n < 0 || d.len() as i64 + n > cells as i64 {
                        return Err(format!(
                            "grid.data_rle: runs of more than info.width × info.height = {cells} cells"
                        ));
                    }
                    d.extend(std::iter::repeat_n(v, n as usize));
                }
                d
            }
            _ => return Err("grid: expected exactly one of data and data_rle".into()),
        };
        Ok(Self {
            grid: RosGrid {
                info: m.grid.info,
                data,
            },
            newly_known: m.newly_known,
            doors: m.doors,
        })
    }
}

/// The result of a `classify_place` on the wire.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Readings {
    readings: Vec<PlaceReading>,
}

/// Check `raw` (the answer's `result`, as sent) against the result type of `kind` and its
/// values (finite poses, distances and times not negative, confidences in (0, 1]); errors name
/// the field under `result`. The result as the session keeps it (a map update's grid
/// run-length encoded): read typed straight from the text, a large grid costs a byte per
/// cell, not a JSON value per cell.
fn check_result(kind: RequestKind, raw: &str) -> Result<Value, ApiError> {
    let at = "result";
    let keep = || {
        serde_json::from_str::<Value>(raw)
            .map_err(|e| ApiError::bad_request(at, format!("result: {e}")))
    };
    match kind {
        RequestKind::MoveTo => {
            let r: MoveReport = from_str(at, raw)?;
            pose_ok("result.pose", r.pose)?;
            metres_ok("result.travelled", r.travelled)?;
            keep()
        }
        RequestKind::MapUpdate => {
            let m: MapUpdateWire = from_str(at, raw)?;
            m.grid
                .to_grid("result.grid")
                .map_err(|e| ApiError::bad_request(e.field.clone(), e.to_string()))?;
            for (i, d) in m.doors.iter().enumerate() {
                for (f, v) in [("x", d.x), ("y", d.y), ("yaw", d.yaw)] {
                    finite_ok(&format!("result.doors[{i}].{f}"), v)?;
                }
                metres_ok(&format!("result.doors[{i}].width"), d.width)?;
            }
            Ok(m.stored())
        }
        RequestKind::ProcessViewCone => {
            let r: ViewReport = from_str(at, raw)?;
            pose_ok("result.pose", r.pose)?;
            metres_ok("result.travelled", r.travelled)?;
            for (i, d) in r.detections.iter().enumerate() {
                let f = format!("result.detections[{i}]");
                for (g, v) in [("x", d.pose.x), ("y", d.pose.y), ("z", d.pose.z)] {
                    finite_ok(&format!("{f}.pose.{g}"), v)?;
                }
                if !(d.confidence > 0.0 && d.confidence <= 1.0) {
                    return Err(ApiError::bad_request(
                        format!("{f}.confidence"),
                        format!("{}: expected a confidence in (0, 1]", d.confidence),
                    ));
                }
            }
            keep()
        }
        RequestKind::ClassifyPlace => {
            let r: Readings = from_str(at, raw)?;
            for (i, p) in r.readings.iter().enumerate() {
                for (j, &l) in p.likelihood.iter().enumerate() {
                    if !(l.is_finite() && l >= 0.0) {
                        return Err(ApiError::bad_request(
                            format!("result.readings[{i}].likelihood[{j}]"),
                            format!("{l}: expected a likelihood ≥ 0"),
                        ));
                    }
                }
            }
            keep()
        }
        RequestKind::DetectorScores => {
            let r: ScoreReport = from_str(at, raw)?;
            pose_ok("result.pose", r.pose)?;
            metres_ok("result.travelled", r.travelled)?;
            metres_ok("result.detector_seconds", r.detector_seconds)?;
            for (i, z) in r.scores.iter().enumerate() {
                if let Some(z) = z {
                    finite_ok(&format!("result.scores[{i}]"), *z)?;
                }
            }
            keep()
        }
        RequestKind::Attention => from_str::<AttentionReport>(at, raw).and_then(|_| keep()),
        RequestKind::Recognise => from_str::<RecognitionReport>(at, raw).and_then(|_| keep()),
    }
}

fn finite_ok(field: &str, v: f64) -> Result<(), ApiError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(ApiError::bad_request(
            field,
            format!("{v}: expected a finite number"),
        ))
    }
}

fn metres_ok(field: &str, v: f64) -> Result<(), ApiError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(ApiError::bad_request(
            field,
            format!("{v}: expected a finite number ≥ 0"),
        ))
    }
}

fn pose_ok(field: &str, p: Pose2D) -> Result<(), ApiError> {
    for (f, v) in [("x", p.x), ("y", p.y), ("yaw", p.yaw)] {
        finite_ok(&format!("{field}.{f}"), v)?;
    }
    Ok(())
}

struct Outstanding {
    request: RobotRequest,
    reply: mpsc::Sender<Answer>,
}

#[derive(Default)]
struct LinkState {
    next_id: u64,
    outstanding: Option<Outstanding>,
    closed: bool,
}

/// Where the agent's thread and the HTTP handlers meet; see the module docs.
///
/// A request ends in exactly one way — the client's answer, a cancel, the session's end or
/// the timeout — and whichever ends it writes the exchange to the record under the same lock
/// that takes the request, so a snapshot never holds an answer the agent did not get, nor
/// misses one it did.
#[derive(Default)]
pub struct RemoteLink {
    state: Mutex<LinkState>,
    notify: tokio::sync::Notify,
    log: Arc<Mutex<Vec<Exchange>>>,
}

impl std::fmt::Debug for RemoteLink {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RemoteLink")
            .field("outstanding", &self.outstanding().map(|r| r.request_id))
            .finish()
    }
}

impl RemoteLink {
    /// A link recording every exchange in `log`, whose first request is numbered `first` (a
    /// restored session continues the numbering of its record, so a request keeps its id
    /// across a restart).
    pub fn new(log: Arc<Mutex<Vec<Exchange>>>, first: u64) -> Self {
        let link = Self {
            log,
            ..Self::default()
        };
        link.lock().next_id = first.saturating_sub(1);
        link
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, LinkState> {
        // A handler that panicked cannot leave the state half-written (each change is one
        // assignment), so a poisoned lock is still good.
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// End outstanding request `o` with `answer`: record it, hand it to the agent.
    fn complete(&self, o: Outstanding, answer: Answer) {
        self.log
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .push(Exchange {
                kind: o.request.kind,
                args: o.request.args,
                answer: answer.clone(),
            });
        // The agent's thread waits on the other end until the request ends.
        let _ = o.reply.send(answer);
    }

    /// The outstanding request, if any.
    pub fn outstanding(&self) -> Option<RobotRequest> {
        self.lock().outstanding.as_ref().map(|o| o.request.clone())
    }

    /// Ask the client (blocking the agent's thread) and wait up to `timeout` for the answer.
    fn ask(&self, kind: RequestKind, args: Value, timeout: Duration) -> Answer {
        let (tx, rx) = mpsc::channel();
        let id = {
            let mut s = self.lock();
            s.next_id += 1;
            let request = RobotRequest {
                request_id: s.next_id,
                kind,
                args,
            };
            let o = Outstanding { request, reply: tx };
            if s.closed {
                drop(s);
                self.complete(
                    o,
                    Answer::failed(FailureReason::ExecutionFailed, "the session ended"),
                );
                return rx.recv().unwrap_or_else(|_| {
                    Answer::failed(FailureReason::ExecutionFailed, "the session ended")
                });
            }
            s.outstanding = Some(o);
            s.next_id
        };
        self.notify.notify_waiters();
        if let Ok(a) = rx.recv_timeout(timeout) {
            return a;
        }
        // Timed out — unless the request ended in the meantime.
        let mut s = self.lock();
        if s.outstanding
            .as_ref()
            .is_some_and(|o| o.request.request_id == id)
        {
            let o = s.outstanding.take().expect("checked");
            drop(s);
            self.complete(
                o,
                Answer::failed(
                    FailureReason::ExecutionFailed,
                    format!(
                        "the robot did not answer {} within {} s",
                        kind.word(),
                        timeout.as_secs_f64()
                    ),
                ),
            );
        } else {
            drop(s);
        }
        rx.recv()
            .unwrap_or_else(|_| Answer::failed(FailureReason::ExecutionFailed, "the session ended"))
    }

    /// The outstanding request, waiting for one up to `timeout` (the long poll).
    pub async fn next(&self, timeout: Duration) -> Option<RobotRequest> {
        let deadline = tokio::time::Instant::now() + timeout;
        loop {
            let notified = self.notify.notified();
            tokio::pin!(notified);
            notified.as_mut().enable();
            if let Some(r) = self.outstanding() {
                return Some(r);
            }
            if self.lock().closed {
                return None;
            }
            if tokio::time::timeout_at(deadline, notified).await.is_err() {
                return None;
            }
        }
    }

    /// Take the client's `answer` to request `id`: checked against the kind's result type
    /// (the request stays open when it does not fit).
    pub fn answer(&self, id: u64, wire: AnswerWire<'_>) -> Result<(), ApiError> {
        let mut s = self.lock();
        let Some(o) = s.outstanding.as_ref() else {
            return Err(ApiError::new(
                ErrorCode::NotFound,
                format!("no robot request {id} is waiting for an answer"),
            )
            .field("request_id"));
        };
        if o.request.request_id != id {
            return Err(ApiError::new(
                ErrorCode::NotFound,
                format!(
                    "no robot request {id} is waiting for an answer (request {} is)",
                    o.request.request_id
                ),
            )
            .field("request_id"));
        }
        if let Some(p) = wire.pose {
            pose_ok("pose", p)?;
        }
        if let Some(t) = wire.travelled {
            metres_ok("travelled", t)?;
        }
        let result = match (wire.result, &wire.failure) {
            (Some(r), None) => Some(check_result(o.request.kind, r.get())?),
            (None, Some(_)) => None,
            _ => {
                return Err(ApiError::bad_request(
                    "result",
                    "expected exactly one of `result` and `failure`",
                ))
            }
        };
        let answer = Answer {
            result,
            failure: wire.failure,
            pose: wire.pose,
            travelled: wire.travelled,
        };
        let o = s.outstanding.take().expect("checked above");
        drop(s);
        self.complete(o, answer);
        Ok(())
    }

    /// Fail the outstanding request (a cancelled goal) with `message`.
    pub fn fail_outstanding(&self, message: &str) {
        let o = self.lock().outstanding.take();
        if let Some(o) = o {
            self.complete(o, Answer::failed(FailureReason::ExecutionFailed, message));
        }
    }

    /// End the link: the outstanding request and every later one fail.
    pub fn close(&self) {
        let o = {
            let mut s = self.lock();
            s.closed = true;
            s.outstanding.take()
        };
        if let Some(o) = o {
            self.complete(
                o,
                Answer::failed(FailureReason::ExecutionFailed, "the session ended"),
            );
        }
        self.notify.notify_waiters();
    }
}

/// A robot on the other side of the protocol; see the module docs.
#[derive(Debug)]
pub struct RemoteRobot {
    link: Arc<RemoteLink>,
    pose: Pose2D,
    odometry: f64,
    camera: Camera,
    capabilities: Vec<Capability>,
    grid: OccupancyGrid,
    doors: Vec<DoorSighting>,
    timeout: Duration,
    /// Every exchange so far (shared with the session, which snapshots it).
    log: Arc<Mutex<Vec<Exchange>>>,
    replay: VecDeque<Exchange>,
    /// Where a replay first asked something the record does not hold.
    pub diverged: Option<String>,
}

impl RemoteRobot {
    /// A robot at `start` with `camera`, answering the optional calls in `capabilities`,
    /// each request waiting at most `timeout`; every exchange is appended to `log`.
    pub fn new(
        link: Arc<RemoteLink>,
        log: Arc<Mutex<Vec<Exchange>>>,
        start: Pose2D,
        camera: Camera,
        capabilities: Vec<Capability>,
        timeout: Duration,
    ) -> Self {
        let grid = OccupancyGrid::new(1, 1, 0.05, [start.x, start.y], Cell::Unknown)
            .expect("a 1×1 grid at a finite start is valid");
        Self {
            link,
            pose: start,
            odometry: 0.0,
            camera,
            capabilities,
            grid,
            doors: Vec::new(),
            timeout,
            log,
            replay: VecDeque::new(),
            diverged: None,
        }
    }

    /// The same robot answering from `record` first (a restored session), then from the
    /// client.
    pub fn replaying(mut self, record: Vec<Exchange>) -> Self {
        self.replay = record.into();
        self
    }

    fn can(&self, c: Capability) -> bool {
        self.capabilities.contains(&c)
    }

    /// Ask `kind` with `args`: from the record while it lasts (checking the question is the
    /// recorded one), else from the client.
    fn ask(&mut self, kind: RequestKind, args: Value) -> Answer {
        let answer = match self.replay.pop_front() {
            Some(e) if e.kind == kind && e.args == args => {
                // A replayed exchange goes into the record again, as it was.
                self.log
                    .lock()
                    .unwrap_or_else(|p| p.into_inner())
                    .push(e.clone());
                e.answer
            }
            Some(e) => {
                self.diverged.get_or_insert(format!(
                    "a recorded request was {} {}; the agent asked {} {}",
                    e.kind.word(),
                    e.args,
                    kind.word(),
                    args
                ));
                self.replay.clear();
                self.link.ask(kind, args, self.timeout)
            }
            None => self.link.ask(kind, args, self.timeout),
        };
        if answer.failure.is_some() {
            if let Some(p) = answer.pose.filter(Pose2D::is_finite) {
                self.pose = p;
            }
            if let Some(t) = answer.travelled.filter(|t| t.is_finite() && *t > 0.0) {
                self.odometry += t;
            }
        }
        answer
    }

    /// Ask and read the result as `T` (the answer was checked when it came).
    fn call<T: serde::de::DeserializeOwned>(
        &mut self,
        kind: RequestKind,
        args: Value,
    ) -> ActionResult<T> {
        let a = self.ask(kind, args);
        match (a.result, a.failure) {
            (_, Some(f)) => Err(f),
            (Some(r), None) => serde_json::from_value(r).map_err(|e| {
                ActionFailure::new(
                    FailureReason::ExecutionFailed,
                    format!("the robot's {} answer: {e}", kind.word()),
                )
            }),
            (None, None) => Err(ActionFailure::new(
                FailureReason::ExecutionFailed,
                format!("the robot's {} answer is empty", kind.word()),
            )),
        }
    }

    fn moved(&mut self, pose: Pose2D, travelled: f64) {
        if pose.is_finite() {
            self.pose = pose;
        }
        if travelled.is_finite() && travelled > 0.0 {
            self.odometry += travelled;
        }
    }
}

impl Robot for RemoteRobot {
    fn pose(&self) -> Pose2D {
        self.pose
    }

    fn camera(&self) -> Camera {
        self.camera
    }

    fn odometry(&self) -> f64 {
        self.odometry
    }

    fn move_to(&mut self, goal: Pose2D) -> ActionResult<MoveReport> {
        let r: MoveReport = self.call(RequestKind::MoveTo, json!({ "goal": goal }))?;
        self.moved(r.pose, r.travelled);
        Ok(r)
    }

    fn map_update(&mut self) -> MapUpdate {
        let a = self.ask(RequestKind::MapUpdate, json!({}));
        let m = match (a.result, a.failure) {
            (_, Some(f)) => Err(f.to_string()),
            (Some(r), None) => MapUpdateWire::from_stored(&r),
            (None, None) => Err("an empty answer".into()),
        };
        match m {
            Ok(m) => match m.grid.to_grid("result.grid") {
                Ok(grid) => {
                    self.grid = grid.clone();
                    self.doors = m.doors.clone();
                    MapUpdate {
                        grid,
                        newly_known: m.newly_known,
                        doors: m.doors,
                    }
                }
                Err(e) => {
                    tracing::warn!("map update: {e}; keeping the last map");
                    self.unchanged_map()
                }
            },
            Err(f) => {
                tracing::warn!("map update failed: {f}; keeping the last map");
                self.unchanged_map()
            }
        }
    }

    fn process_view_cone(
        &mut self,
        cone: &ViewCone,
        classes: &[String],
    ) -> ActionResult<ViewReport> {
        let r: ViewReport = self.call(
            RequestKind::ProcessViewCone,
            json!({ "cone": cone, "classes": classes }),
        )?;
        self.moved(r.pose, r.travelled);
        Ok(r)
    }

    fn classify_place(&mut self) -> ActionResult<Vec<PlaceReading>> {
        if !self.can(Capability::ClassifyPlace) {
            return Ok(Vec::new());
        }
        let r: Readings = self.call(RequestKind::ClassifyPlace, json!({}))?;
        Ok(r.readings)
    }

    fn detector_scores(
        &mut self,
        cone: &ViewCone,
        class: &str,
        at: &[Point3],
    ) -> ActionResult<ScoreReport> {
        if !self.can(Capability::DetectorScores) {
            return Err(unsupported("detector_scores"));
        }
        let r: ScoreReport = self.call(
            RequestKind::DetectorScores,
            json!({ "cone": cone, "class": class, "at": at }),
        )?;
        self.moved(r.pose, r.travelled);
        Ok(r)
    }

    fn attention(&mut self, cone: &ViewCone, classes: &[String]) -> ActionResult<AttentionReport> {
        if !self.can(Capability::Attention) {
            return Err(unsupported("attention"));
        }
        self.call(
            RequestKind::Attention,
            json!({ "cone": cone, "classes": classes }),
        )
    }

    fn recognise(&mut self, cone: &ViewCone, class: &str) -> ActionResult<RecognitionReport> {
        if !self.can(Capability::Recognise) {
            return Err(unsupported("recognise"));
        }
        self.call(
            RequestKind::Recognise,
            json!({ "cone": cone, "class": class }),
        )
    }
}

impl RemoteRobot {
    fn unchanged_map(&self) -> MapUpdate {
        MapUpdate {
            grid: self.grid.clone(),
            newly_known: 0,
            doors: self.doors.clone(),
        }
    }
}

fn unsupported(kind: &str) -> ActionFailure {
    ActionFailure::new(
        FailureReason::Unsupported,
        format!("the remote robot did not declare the `{kind}` capability"),
    )
}

/// The arguments of a request that names a cone and classes.
#[derive(Deserialize)]
struct ConeArgs {
    cone: ViewCone,
    #[serde(default)]
    classes: Vec<String>,
    #[serde(default)]
    class: String,
    #[serde(default)]
    at: Vec<Point3>,
}

/// Answer `request` with `robot`, as a client of the protocol would: the reference client of
/// the remote-robot protocol, for Rust robot stacks (a [`Robot`] on the robot's side answers a
/// server's requests with it) and for tests (a simulated robot behind the protocol must
/// behave as the same robot driven in-process).
pub fn answer_with(robot: &mut dyn Robot, request: &RobotRequest) -> Answer {
    fn reply<T: Serialize>(r: ActionResult<T>) -> Answer {
        match r {
            Ok(v) => Answer {
                result: Some(serde_json::to_value(v).unwrap_or(Value::Null)),
                failure: None,
                pose: None,
                travelled: None,
            },
            Err(f) => Answer {
                result: None,
                failure: Some(f),
                pose: None,
                travelled: None,
            },
        }
    }
    let bad = |e: serde_json::Error| {
        Answer::failed(
            FailureReason::InvalidRequest,
            format!("{} args: {e}", request.kind.word()),
        )
    };
    let cone = || serde_json::from_value::<ConeArgs>(request.args.clone());
    match request.kind {
        RequestKind::MoveTo => {
            #[derive(Deserialize)]
            struct Goal {
                goal: Pose2D,
            }
            match serde_json::from_value::<Goal>(request.args.clone()) {
                Ok(g) => reply(robot.move_to(g.goal)),
                Err(e) => bad(e),
            }
        }
        RequestKind::MapUpdate => {
            let m = robot.map_update();
            reply(Ok(MapUpdateWire {
                grid: RosGrid::from_grid(&m.grid),
                newly_known: m.newly_known,
                doors: m.doors,
            }))
        }
        RequestKind::ProcessViewCone => match cone() {
            Ok(a) => reply(robot.process_view_cone(&a.cone, &a.classes)),
            Err(e) => bad(e),
        },
        RequestKind::ClassifyPlace => {
            reply(robot.classify_place().map(|readings| Readings { readings }))
        }
        RequestKind::DetectorScores => match cone() {
            Ok(a) => reply(robot.detector_scores(&a.cone, &a.class, &a.at)),
            Err(e) => bad(e),
        },
        RequestKind::Attention => match cone() {
            Ok(a) => reply(robot.attention(&a.cone, &a.classes)),
            Err(e) => bad(e),
        },
        RequestKind::Recognise => match cone() {
            Ok(a) => reply(robot.recognise(&a.cone, &a.class)),
            Err(e) => bad(e),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn update(data: Vec<i8>, width: usize, height: usize) -> MapUpdateWire {
        let g =
            avs_map::grid::OccupancyGrid::new(width, height, 0.5, [0.0, 0.0], Cell::Free).unwrap();
        let mut grid = RosGrid::from_grid(&g);
        grid.data = data;
        MapUpdateWire {
            grid,
            newly_known: 4,
            doors: Vec::new(),
        }
    }

    #[test]
    fn a_map_update_is_kept_run_length_encoded_and_read_back_whole() {
        let m = update(vec![-1, -1, -1, 0, 0, 100], 3, 2);
        let stored = m.stored();
        assert_eq!(stored["grid"]["data_rle"], json!([-1, 3, 0, 2, 100, 1]));
        assert!(stored["grid"].get("data").is_none());
        assert_eq!(MapUpdateWire::from_stored(&stored).unwrap(), m);
        // The form a client sends reads the same.
        let sent = serde_json::to_value(&m).unwrap();
        assert_eq!(MapUpdateWire::from_stored(&sent).unwrap(), m);
    }

    #[test]
    fn runs_beyond_the_grid_are_refused_before_they_are_expanded() {
        let mut stored = update(vec![0; 6], 3, 2).stored();
        stored["grid"]["data_rle"] = json!([0, 1_000_000_000_000_i64]);
        let e = MapUpdateWire::from_stored(&stored).unwrap_err();
        assert!(e.contains("more than"), "{e}");
        stored["grid"]["data_rle"] = json!([0, 3, 0]);
        assert!(MapUpdateWire::from_stored(&stored).is_err());
    }
}
