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

use crate::error::{from_value, ApiError, ErrorCode};
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

/// The result of a `classify_place` on the wire.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Readings {
    readings: Vec<PlaceReading>,
}

/// Check `result` against the result type of `kind` and its values (finite poses, distances
/// and times not negative, confidences in (0, 1]); errors name the field under `result`.
fn check_result(kind: RequestKind, result: &Value) -> Result<(), ApiError> {
    let at = "result";
    match kind {
        RequestKind::MoveTo => {
            let r: MoveReport = from_value(at, result)?;
            pose_ok("result.pose", r.pose)?;
            metres_ok("result.travelled", r.travelled)
        }
        RequestKind::MapUpdate => {
            let m: MapUpdateWire = from_value(at, result)?;
            m.grid
                .to_grid("result.grid")
                .map_err(|e| ApiError::bad_request(e.field.clone(), e.to_string()))?;
            for (i, d) in m.doors.iter().enumerate() {
                for (f, v) in [("x", d.x), ("y", d.y), ("yaw", d.yaw)] {
                    finite_ok(&format!("result.doors[{i}].{f}"), v)?;
                }
                metres_ok(&format!("result.doors[{i}].width"), d.width)?;
            }
            Ok(())
        }
        RequestKind::ProcessViewCone => {
            let r: ViewReport = from_value(at, result)?;
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
            Ok(())
        }
        RequestKind::ClassifyPlace => {
            let r: Readings = from_value(at, result)?;
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
            Ok(())
        }
        RequestKind::DetectorScores => {
            let r: ScoreReport = from_value(at, result)?;
            pose_ok("result.pose", r.pose)?;
            metres_ok("result.travelled", r.travelled)?;
            metres_ok("result.detector_seconds", r.detector_seconds)?;
            for (i, z) in r.scores.iter().enumerate() {
                if let Some(z) = z {
                    finite_ok(&format!("result.scores[{i}]"), *z)?;
                }
            }
            Ok(())
        }
        RequestKind::Attention => from_value::<AttentionReport>(at, result).map(drop),
        RequestKind::Recognise => from_value::<RecognitionReport>(at, result).map(drop),
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
    pub fn answer(&self, id: u64, answer: Answer) -> Result<(), ApiError> {
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
        if let Some(p) = answer.pose {
            pose_ok("pose", p)?;
        }
        if let Some(t) = answer.travelled {
            metres_ok("travelled", t)?;
        }
        match (&answer.result, &answer.failure) {
            (Some(r), None) => check_result(o.request.kind, r)?,
            (None, Some(_)) => {}
            _ => {
                return Err(ApiError::bad_request(
                    "result",
                    "expected exactly one of `result` and `failure`",
                ))
            }
        }
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

    /// Requests still to be replayed.
    pub fn replay_left(&self) -> usize {
        self.replay.len()
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
        match self.call::<MapUpdateWire>(RequestKind::MapUpdate, json!({})) {
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
