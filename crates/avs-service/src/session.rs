//! A session: one agent and one robot, with the goals posted to it run one at a time on a
//! worker thread of its own, everything they do written where the handlers can read it
//! ([`Shared`]), and a record from which the session can be re-created ([`Snapshot`]).
//!
//! The agent is synchronous (a search is one call that drives the robot until it ends), so
//! each session has one worker thread that owns the robot and runs the goals in the order
//! posted; the handlers never wait on it. What a search does reaches the handlers through
//! the trace sink ([`avs_agent::TraceSink`]: events, beliefs before every plan, the stop
//! check) and through a robot wrapper that records every call (`Watched`).
//!
//! **Cancelling** sets a flag the agent asks about before every plan and action (and the
//! wrapper fails robot calls from then on; a remote robot's outstanding request fails at
//! once), so a search ends within one action. **Determinism**: the agent is deterministic
//! given what its robot reports; the stop checks and robot calls of a goal are counted
//! (checkpoints), and the checkpoint at which a cancel was first seen is recorded, so a
//! replay cancels at the same point and a snapshot restores a cancelled goal exactly.

use crate::api::{GoalState, GoalStatus, RobotKind, SessionInfo};
use crate::live::Live;
use crate::remote::{Capability, Exchange, RemoteLink, RemoteRobot};
use crate::snapshot::{GoalRecord, Snapshot};
use crate::spec::Spec;
use avs_agent::{Agent, AgentConfig, Beliefs, Event, Goal, TraceSink};
use avs_format::knowledge::Knowledge;
use avs_robot::{
    ActionFailure, ActionResult, AttentionReport, Camera, FailureReason, MapUpdate, MoveReport,
    PlaceReading, Point3, Pose2D, RecognitionReport, Robot, ScoreReport, ViewCone, ViewReport,
};
use avs_sim::sim_robot::{SimAgentRobot, SimRobotConfig};
use avs_sim::World;
use std::cell::Cell;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{mpsc, Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};
use tokio::sync::{broadcast, oneshot};

/// A message for the server-sent event stream: its event name and JSON data.
#[derive(Debug, Clone)]
pub struct Push {
    /// `trace`, `goal`, `robot` or `beliefs`.
    pub event: &'static str,
    /// The JSON data.
    pub data: String,
    /// For a trace line: its index in the session's trace and its goal's index.
    pub line: Option<(usize, usize)>,
}

/// One goal of a session.
#[derive(Debug, Clone)]
pub struct GoalEntry {
    /// `g<N>`.
    pub id: String,
    /// The class sought.
    pub class: String,
    /// Classes later goals seek (every look also detects them).
    pub also: Vec<String>,
    /// Where it stands.
    pub state: GoalState,
    /// The `avs search --json` summary, once it ended.
    pub report: Option<serde_json::Value>,
    /// Why it failed.
    pub error: Option<String>,
    /// The checkpoint at which the search saw it was cancelled.
    pub cancelled_at: Option<u64>,
    /// For a replayed goal: the trace it must reproduce and the checkpoint to cancel at.
    pub replay: Option<(Vec<String>, Option<u64>)>,
}

impl GoalEntry {
    /// The goal's status as the API gives it.
    pub fn status(&self) -> GoalStatus {
        GoalStatus {
            goal_id: self.id.clone(),
            class: self.class.clone(),
            state: self.state,
            report: self.report.clone(),
            error: self.error.clone(),
        }
    }
}

/// What the handlers read and the worker writes.
#[derive(Debug)]
pub struct State {
    /// Every goal, in the order posted.
    pub goals: Vec<GoalEntry>,
    /// Every trace line: the goal (index) and the JSON line.
    pub trace: Vec<(usize, String)>,
    /// What the live view shows.
    pub live: Live,
    /// The beliefs as the agent last handed them.
    pub beliefs: Option<Beliefs>,
    /// When the session was last asked or did something.
    pub last_active: Instant,
}

/// The part of a session the handlers and the worker share.
#[derive(Debug)]
pub struct Shared {
    state: Mutex<State>,
    /// The event stream.
    pub tx: broadcast::Sender<Push>,
    /// Set to cancel the running goal.
    cancel: AtomicBool,
    /// The agent; the worker holds the lock while a goal runs.
    pub agent: Mutex<Agent>,
    /// The remote robot's link, for a remote session.
    pub link: Option<Arc<RemoteLink>>,
    /// Every exchange with a remote robot.
    pub robot_log: Arc<Mutex<Vec<Exchange>>>,
    /// Robot calls made (for the metrics, without taking the state lock).
    calls: AtomicU64,
}

fn relock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    // Every change under these locks is complete when the lock is released (no handler
    // holds one across an await or a panic point that leaves a half-written value).
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl Shared {
    /// The state, locked.
    pub fn state(&self) -> MutexGuard<'_, State> {
        relock(&self.state)
    }

    /// Send `data` as event `event` to every stream (none listening is fine).
    pub fn push(&self, event: &'static str, data: String) {
        let _ = self.tx.send(Push {
            event,
            data,
            line: None,
        });
    }

    fn push_goal(&self, g: &GoalEntry) {
        self.push(
            "goal",
            serde_json::to_string(&g.status()).unwrap_or_default(),
        );
    }
}

/// The inputs of a session, loaded and checked.
#[derive(Debug, Clone)]
pub struct Loaded {
    /// The knowledge.
    pub knowledge: Knowledge,
    /// The planning domain.
    pub domain: avs_plan::domain::Domain,
    /// The simulated robot's world (sim sessions).
    pub world: Option<World>,
    /// The robot's start.
    pub start: Pose2D,
    /// The robot's camera.
    pub camera: Camera,
    /// The agent's settings.
    pub config: AgentConfig,
}

/// A session; see the module docs.
#[derive(Debug)]
pub struct Session {
    /// Its id.
    pub id: String,
    /// Its inputs as given (for snapshots).
    pub spec: Spec,
    /// What the handlers read.
    pub shared: Arc<Shared>,
    /// The knowledge's object classes (goals name one).
    pub classes: Vec<String>,
    jobs: Mutex<Option<mpsc::Sender<usize>>>,
}

/// Why a session could not start: the request key at fault (empty for a fault of the
/// server) and what is wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct StartError {
    /// The request key: `knowledge` (the agent refused it), `environment` (the simulated
    /// robot did), `snapshot` (it does not replay); empty for the server's own fault.
    pub field: &'static str,
    /// What is wrong.
    pub message: String,
}

impl StartError {
    fn new(field: &'static str, message: impl Into<String>) -> Self {
        Self {
            field,
            message: message.into(),
        }
    }
}

/// A goal the worker runs first, before any posted one: a restored session's record.
struct Start {
    goals: Vec<usize>,
    ready: oneshot::Sender<Result<(), StartError>>,
}

impl Session {
    /// Start a session `id` from `spec` (already loaded into `loaded`), running the goals of
    /// `restore` (a snapshot's) first. Resolves when the robot is set up and every ended goal
    /// of the snapshot has been replayed and found to reproduce its trace.
    pub async fn start(
        id: String,
        spec: Spec,
        loaded: Loaded,
        restore: Option<&Snapshot>,
        robot_timeout: Duration,
    ) -> Result<Arc<Session>, StartError> {
        let agent = Agent::new(
            loaded.domain.clone(),
            loaded.knowledge.clone(),
            loaded.config.clone(),
        )
        .map_err(|e| StartError::new("knowledge", e.to_string()))?;
        let classes = loaded
            .knowledge
            .object_classes
            .iter()
            .map(|c| c.name.clone())
            .collect();
        let (tx, _) = broadcast::channel(1024);
        let mut goals = Vec::new();
        let mut replay_log = Vec::new();
        let mut to_run = Vec::new();
        if let Some(s) = restore {
            for (i, g) in s.goals.iter().enumerate() {
                // Ended goals are replayed (a cancelled one to its recorded checkpoint), queued
                // and running ones run again, one cancelled before it ran stays cancelled.
                let replayed = match g.state {
                    GoalState::Queued | GoalState::Running => false,
                    GoalState::Cancelled => g.cancelled_at.is_some(),
                    GoalState::Found | GoalState::NotFound | GoalState::Failed => true,
                };
                let runs = replayed || !g.state.ended();
                goals.push(GoalEntry {
                    id: g.goal_id.clone(),
                    class: g.class.clone(),
                    also: g.also.clone(),
                    state: if runs { GoalState::Queued } else { g.state },
                    report: None,
                    error: None,
                    cancelled_at: None,
                    replay: replayed.then(|| (g.trace.clone(), g.cancelled_at)),
                });
                if runs {
                    to_run.push(i);
                }
            }
            replay_log = s.robot_log.clone();
        }
        let robot_log = Arc::new(Mutex::new(Vec::new()));
        let link = (spec.robot == RobotKind::Remote).then(|| {
            Arc::new(RemoteLink::new(
                robot_log.clone(),
                replay_log.len() as u64 + 1,
            ))
        });
        let shared = Arc::new(Shared {
            state: Mutex::new(State {
                goals,
                trace: Vec::new(),
                live: Live::new(loaded.start, loaded.camera.hfov),
                beliefs: None,
                last_active: Instant::now(),
            }),
            tx,
            cancel: AtomicBool::new(false),
            agent: Mutex::new(agent),
            link,
            robot_log,
            calls: AtomicU64::new(0),
        });
        let (jobs_tx, jobs_rx) = mpsc::channel();
        let (ready_tx, ready_rx) = oneshot::channel();
        let worker_shared = shared.clone();
        let robot = spec.robot;
        let capabilities = spec.capabilities.clone();
        let seed = spec.seed;
        std::thread::Builder::new()
            .name(format!("avs-session-{id}"))
            .spawn(move || {
                let start = Start {
                    goals: to_run,
                    ready: ready_tx,
                };
                worker(
                    worker_shared,
                    loaded,
                    robot,
                    seed,
                    capabilities,
                    robot_timeout,
                    replay_log,
                    start,
                    jobs_rx,
                )
            })
            .map_err(|e| StartError::new("", format!("starting the session's thread: {e}")))?;
        ready_rx
            .await
            .map_err(|_| StartError::new("", "the session's thread stopped while starting"))??;
        Ok(Arc::new(Session {
            id,
            spec,
            shared,
            classes,
            jobs: Mutex::new(Some(jobs_tx)),
        }))
    }

    /// Post a goal; its id.
    pub fn post_goal(&self, class: String, also: Vec<String>) -> Result<String, String> {
        let (id, index) = {
            let mut st = self.shared.state();
            // Goal ids count up from g1 (a restored session's goals keep theirs).
            let n = st
                .goals
                .iter()
                .filter_map(|g| g.id.strip_prefix('g')?.parse::<u64>().ok())
                .max()
                .unwrap_or(0);
            let id = format!("g{}", n + 1);
            st.goals.push(GoalEntry {
                id: id.clone(),
                class,
                also,
                state: GoalState::Queued,
                report: None,
                error: None,
                cancelled_at: None,
                replay: None,
            });
            st.last_active = Instant::now();
            let g = st.goals.len() - 1;
            self.shared.push_goal(&st.goals[g]);
            (id, g)
        };
        let jobs = relock(&self.jobs);
        match jobs.as_ref().map(|j| j.send(index)) {
            Some(Ok(())) => Ok(id),
            _ => Err("the session has ended".into()),
        }
    }

    /// Cancel goal `goal_id`: a queued goal is dropped, a running one stopped (its state
    /// becomes `cancelled` when the search has stopped). `None` when there is no such goal.
    pub fn cancel(&self, goal_id: &str) -> Option<GoalStatus> {
        let mut st = self.shared.state();
        st.last_active = Instant::now();
        let g = st.goals.iter_mut().find(|g| g.id == goal_id)?;
        match g.state {
            GoalState::Queued => {
                g.state = GoalState::Cancelled;
                let s = g.status();
                self.shared.push_goal(g);
                Some(s)
            }
            GoalState::Running => {
                self.shared.cancel.store(true, Ordering::SeqCst);
                if let Some(l) = &self.shared.link {
                    l.fail_outstanding("the goal was cancelled");
                }
                Some(g.status())
            }
            _ => Some(g.status()),
        }
    }

    /// End the session: the running goal is cancelled, the worker stops after it.
    pub fn shutdown(&self) {
        relock(&self.jobs).take();
        self.shared.cancel.store(true, Ordering::SeqCst);
        if let Some(l) = &self.shared.link {
            l.close();
        }
    }

    /// Mark the session as used now.
    pub fn touch(&self) {
        self.shared.state().last_active = Instant::now();
    }

    /// Whether a goal is queued or running.
    pub fn busy(&self) -> bool {
        self.shared.state().goals.iter().any(|g| !g.state.ended())
    }

    /// The session as the API lists it.
    pub fn info(&self) -> SessionInfo {
        let st = self.shared.state();
        SessionInfo {
            id: self.id.clone(),
            robot: self.spec.robot,
            seed: self.spec.seed,
            state: if st.goals.iter().any(|g| g.state == GoalState::Running) {
                "running".into()
            } else {
                "idle".into()
            },
            goals: st.goals.len(),
            pose: st.live.pose,
            odometry: st.live.odometry,
            pending_request: self
                .shared
                .link
                .as_ref()
                .and_then(|l| l.outstanding())
                .map(|r| r.request_id),
            idle_s: st.last_active.elapsed().as_secs_f64(),
        }
    }

    /// Robot calls made so far.
    pub fn robot_calls(&self) -> u64 {
        self.shared.calls.load(Ordering::Relaxed)
    }

    /// The agent's beliefs with object probabilities for `class` (default: the last goal's):
    /// between goals asked of the agent; while a goal runs (the agent is busy), as it handed
    /// them over before its last plan (for that goal's class). `None` before the first search.
    pub fn beliefs(&self, class: Option<&str>) -> Option<Beliefs> {
        let (last_class, pushed) = {
            let st = self.shared.state();
            (st.goals.last().map(|g| g.class.clone()), st.beliefs.clone())
        };
        match self.shared.agent.try_lock() {
            Ok(agent) => agent.beliefs(class.or(last_class.as_deref())).or(pushed),
            Err(_) => pushed,
        }
    }

    /// The session's snapshot; see [`Snapshot`].
    pub fn snapshot(&self) -> Snapshot {
        let (goals, live) = {
            let st = self.shared.state();
            let goals = st
                .goals
                .iter()
                .enumerate()
                .map(|(i, g)| GoalRecord {
                    goal_id: g.id.clone(),
                    class: g.class.clone(),
                    also: g.also.clone(),
                    state: g.state,
                    report: g.report.clone(),
                    error: g.error.clone(),
                    cancelled_at: g.cancelled_at,
                    trace: st
                        .trace
                        .iter()
                        .filter(|(k, _)| *k == i)
                        .map(|(_, l)| l.clone())
                        .collect(),
                })
                .collect();
            (goals, st.live.summary())
        };
        let beliefs = self.beliefs(None);
        Snapshot::new(
            self.spec.clone(),
            goals,
            relock(&self.shared.robot_log).clone(),
            live,
            beliefs,
        )
    }
}

/// The robot a session drives.
enum Body<'w> {
    Sim(Box<SimAgentRobot<'w>>),
    Remote(Box<RemoteRobot>),
}

impl Body<'_> {
    fn robot(&mut self) -> &mut dyn Robot {
        match self {
            Body::Sim(r) => r.as_mut(),
            Body::Remote(r) => r.as_mut(),
        }
    }

    fn diverged(&self) -> Option<String> {
        match self {
            Body::Sim(_) => None,
            Body::Remote(r) => r.diverged.clone(),
        }
    }
}

/// The worker: set up the robot, replay the restored goals, then run goals as they come.
#[expect(
    clippy::too_many_arguments,
    reason = "the session's parts, handed over once"
)]
fn worker(
    shared: Arc<Shared>,
    loaded: Loaded,
    robot: RobotKind,
    seed: u64,
    capabilities: Vec<Capability>,
    robot_timeout: Duration,
    replay_log: Vec<Exchange>,
    start: Start,
    jobs: mpsc::Receiver<usize>,
) {
    let world = loaded.world.clone();
    let mut body = match (robot, &world, &shared.link) {
        (RobotKind::Sim, Some(w), _) => {
            match SimAgentRobot::new(w, loaded.knowledge.clone(), SimRobotConfig::default(), seed) {
                Ok(r) => Body::Sim(Box::new(r)),
                Err(e) => {
                    let _ = start.ready.send(Err(StartError::new(
                        "environment",
                        format!("the simulated robot: {e}"),
                    )));
                    return;
                }
            }
        }
        (RobotKind::Remote, _, Some(link)) => Body::Remote(Box::new(
            RemoteRobot::new(
                link.clone(),
                shared.robot_log.clone(),
                loaded.start,
                loaded.camera,
                capabilities,
                robot_timeout,
            )
            .replaying(replay_log),
        )),
        _ => {
            let _ = start.ready.send(Err(StartError::new(
                "environment",
                "a simulated robot needs an environment",
            )));
            return;
        }
    };
    let mut replayed = Ok(());
    for &g in &start.goals {
        let is_replay = shared.state().goals[g].replay.is_some();
        if !is_replay {
            continue;
        }
        run_goal(&shared, &mut body, world.as_ref(), g);
        if let Some(e) = replay_mismatch(&shared, &body, g) {
            replayed = Err(StartError::new("snapshot", e));
            break;
        }
    }
    let ok = replayed.is_ok();
    let _ = start.ready.send(replayed);
    if !ok {
        return;
    }
    // Goals that were queued or running when the snapshot was taken run again, live.
    for &g in &start.goals {
        if shared.state().goals[g].replay.is_none() {
            run_goal(&shared, &mut body, world.as_ref(), g);
        }
    }
    while let Ok(g) = jobs.recv() {
        run_goal(&shared, &mut body, world.as_ref(), g);
    }
}

/// Why replayed goal `g` is not what was recorded, if it is not.
fn replay_mismatch(shared: &Shared, body: &Body, g: usize) -> Option<String> {
    let st = shared.state();
    let goal = &st.goals[g];
    let (expected, _) = goal.replay.as_ref()?;
    let got: Vec<&String> = st
        .trace
        .iter()
        .filter(|(k, _)| *k == g)
        .map(|(_, l)| l)
        .collect();
    if let Some(d) = body.diverged() {
        return Some(format!(
            "goal {}: the robot record does not replay: {d}",
            goal.id
        ));
    }
    let first = expected
        .iter()
        .zip(&got)
        .position(|(a, b)| a != *b)
        .or((expected.len() != got.len()).then(|| expected.len().min(got.len())));
    first.map(|i| {
        format!(
            "goal {}: the replay differs from the recorded trace at line {} (recorded {:?}, \
             replayed {:?}); the snapshot was taken by a different avs or from a different input",
            goal.id,
            i + 1,
            expected.get(i).map(String::as_str).unwrap_or("(end)"),
            got.get(i).map(|s| s.as_str()).unwrap_or("(end)")
        )
    })
}

/// Run goal `g` to its end and file its report.
fn run_goal(shared: &Arc<Shared>, body: &mut Body, world: Option<&World>, g: usize) {
    let (goal, replay_at) = {
        let mut st = shared.state();
        let entry = &mut st.goals[g];
        if entry.state != GoalState::Queued {
            return;
        }
        entry.state = GoalState::Running;
        let goal = Goal {
            class: entry.class.clone(),
            region: Vec::new(),
            also: entry.also.clone(),
        };
        let replay_at = entry.replay.as_ref().and_then(|r| r.1);
        shared.cancel.store(false, Ordering::SeqCst);
        shared.push_goal(&st.goals[g]);
        (goal, replay_at)
    };
    let class = goal.class.clone();
    let checks = Checkpoints {
        n: Cell::new(0),
        seen_at: Cell::new(None),
        cancel: &shared.cancel,
        replay_at,
    };
    let start = body.robot().pose();
    let trail_from = match body {
        Body::Sim(r) => r.trail().len().saturating_sub(1),
        Body::Remote(_) => 0,
    };
    let clock = Instant::now();
    let result = {
        let mut agent = relock(&shared.agent);
        let mut sink = Sink {
            shared,
            goal: g,
            checks: &checks,
        };
        let mut watched = Watched {
            inner: body.robot(),
            shared,
            checks: &checks,
        };
        // A fault in the agent fails this goal, not the server: the other sessions and the
        // next goal go on (the agent's memory is whatever the search left).
        match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            agent.search_with(&mut watched, goal, &mut sink)
        })) {
            Ok(r) => r.map_err(|e| e.to_string()),
            Err(p) => {
                let what = p
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| p.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "no message".into());
                tracing::error!("goal {}: the agent panicked: {what}", goal_id(shared, g));
                Err(format!("internal error: the agent panicked: {what}"))
            }
        }
    };
    let compute_s = clock.elapsed().as_secs_f64();
    // The truth to score against and the robot's path over it: the simulated world and its
    // trail; a remote robot's world is not the environment file (only its camera and start are
    // used), so nothing is scored against a truth the server does not have.
    let (truth, trail): (Option<&World>, Vec<[f64; 2]>) = match body {
        Body::Sim(r) => (
            world,
            r.trail().get(trail_from..).unwrap_or_default().to_vec(),
        ),
        Body::Remote(_) => (None, Vec::new()),
    };
    let mut st = shared.state();
    let entry = &mut st.goals[g];
    entry.cancelled_at = checks.seen_at.get();
    match result {
        Ok(report) => {
            let summary = avs_eval::episode::summarize(
                truth,
                &class,
                [start.x, start.y],
                &report,
                &trail,
                compute_s,
            );
            entry.state = if entry.cancelled_at.is_some() {
                GoalState::Cancelled
            } else if report.found.is_some() {
                GoalState::Found
            } else {
                GoalState::NotFound
            };
            entry.report = serde_json::to_value(&summary).ok();
        }
        Err(e) => {
            entry.state = GoalState::Failed;
            entry.error = Some(e);
        }
    }
    st.last_active = Instant::now();
    shared.push_goal(&st.goals[g]);
}

/// The id of goal `g`.
fn goal_id(shared: &Shared, g: usize) -> String {
    shared.state().goals[g].id.clone()
}

/// The stop checks and robot calls of one goal, counted; see the module docs.
struct Checkpoints<'a> {
    n: Cell<u64>,
    seen_at: Cell<Option<u64>>,
    cancel: &'a AtomicBool,
    /// In a replay: cancel at this checkpoint (the live flag is not looked at).
    replay_at: Option<u64>,
}

impl Checkpoints<'_> {
    /// Pass a checkpoint: whether the goal is cancelled.
    fn stop(&self) -> bool {
        let n = self.n.get();
        self.n.set(n + 1);
        let stop = match self.replay_at {
            Some(k) => n >= k,
            None => self.cancel.load(Ordering::SeqCst),
        };
        if stop && self.seen_at.get().is_none() {
            self.seen_at.set(Some(n));
        }
        stop
    }
}

/// The trace sink of a goal: trace lines, beliefs, the live view, the stop check.
struct Sink<'a> {
    shared: &'a Shared,
    goal: usize,
    checks: &'a Checkpoints<'a>,
}

impl TraceSink for Sink<'_> {
    fn event(&mut self, e: &Event) {
        let line = e.json_line();
        let index = {
            let mut st = self.shared.state();
            st.live.event(e);
            st.trace.push((self.goal, line.clone()));
            st.trace.len() - 1
        };
        let _ = self.shared.tx.send(Push {
            event: "trace",
            data: line,
            line: Some((index, self.goal)),
        });
    }

    fn wants_beliefs(&self) -> bool {
        true
    }

    fn beliefs(&mut self, b: &Beliefs) {
        let data = serde_json::to_string(b).unwrap_or_default();
        self.shared.state().beliefs = Some(b.clone());
        self.shared.push("beliefs", data);
    }

    fn stop_requested(&mut self) -> bool {
        self.checks.stop()
    }
}

/// The session's robot as the agent drives it: every call counted as a checkpoint (failed
/// once the goal is cancelled), and its outcome written to the live view.
struct Watched<'a> {
    inner: &'a mut dyn Robot,
    shared: &'a Shared,
    checks: &'a Checkpoints<'a>,
}

impl Watched<'_> {
    /// Whether the call may go ahead (else the goal was cancelled).
    fn go(&self) -> ActionResult<()> {
        if self.checks.stop() {
            Err(ActionFailure::new(
                FailureReason::ExecutionFailed,
                "the goal was cancelled",
            ))
        } else {
            Ok(())
        }
    }

    /// Note a finished call of `kind` in the live view and the stream.
    fn done(&self, kind: &str, grid: Option<&avs_map::grid::OccupancyGrid>) {
        let (pose, odometry) = (self.inner.pose(), self.inner.odometry());
        self.shared.calls.fetch_add(1, Ordering::Relaxed);
        {
            let mut st = self.shared.state();
            st.last_active = Instant::now();
            st.live.robot_at(pose, odometry);
            if let Some(g) = grid {
                st.live.grid = Some(g.clone());
            }
        }
        let data = serde_json::json!({ "kind": kind, "pose": pose, "odometry": odometry });
        self.shared.push("robot", data.to_string());
    }
}

impl Robot for Watched<'_> {
    fn pose(&self) -> Pose2D {
        self.inner.pose()
    }

    fn camera(&self) -> Camera {
        self.inner.camera()
    }

    fn odometry(&self) -> f64 {
        self.inner.odometry()
    }

    fn move_to(&mut self, goal: Pose2D) -> ActionResult<MoveReport> {
        self.go()?;
        let r = self.inner.move_to(goal);
        self.done("move_to", None);
        r
    }

    fn map_update(&mut self) -> MapUpdate {
        // After a cancel the robot is not asked again (a remote robot whose client has gone
        // would hold the search for the robot timeout): the last map stands.
        if self.checks.stop() {
            let st = self.shared.state();
            if let Some(grid) = st.live.grid.clone() {
                return MapUpdate {
                    grid,
                    newly_known: 0,
                    doors: st.live.doors.clone(),
                };
            }
        }
        let m = self.inner.map_update();
        self.shared.state().live.doors = m.doors.clone();
        self.done("map_update", Some(&m.grid));
        m
    }

    fn process_view_cone(
        &mut self,
        cone: &ViewCone,
        classes: &[String],
    ) -> ActionResult<ViewReport> {
        self.go()?;
        let r = self.inner.process_view_cone(cone, classes);
        self.done("process_view_cone", None);
        r
    }

    fn classify_place(&mut self) -> ActionResult<Vec<PlaceReading>> {
        self.go()?;
        let r = self.inner.classify_place();
        self.done("classify_place", None);
        r
    }

    fn detector_scores(
        &mut self,
        cone: &ViewCone,
        class: &str,
        at: &[Point3],
    ) -> ActionResult<ScoreReport> {
        self.go()?;
        let r = self.inner.detector_scores(cone, class, at);
        self.done("detector_scores", None);
        r
    }

    fn attention(&mut self, cone: &ViewCone, classes: &[String]) -> ActionResult<AttentionReport> {
        self.go()?;
        let r = self.inner.attention(cone, classes);
        self.done("attention", None);
        r
    }

    fn recognise(&mut self, cone: &ViewCone, class: &str) -> ActionResult<RecognitionReport> {
        self.go()?;
        let r = self.inner.recognise(cone, class);
        self.done("recognise", None);
        r
    }
}
