//! # avs-service
//!
//! avs as a long-lived HTTP service (`avs serve`): a robot stack keeps one agent per robot
//! alive in a **session**, hands it goals, feeds it what the robot senses and gets back what
//! to do next; a person watches it decide on a live web page. The routes, keys and the
//! remote-robot protocol are the contract of `docs/SERVICE.md`.
//!
//! | module | what it holds |
//! |---|---|
//! | [`api`] | request and response bodies (serde, OpenAPI schemas) |
//! | [`error`] | `{"error": {"code", "message", "field"?}}` and its HTTP statuses |
//! | [`session`] | a session: agent, robot, goals on a worker thread, the stop check, replay |
//! | [`remote`] | the remote-robot protocol: a `Robot` whose calls are long-polled requests |
//! | [`grid`] | occupancy grids in `nav_msgs/OccupancyGrid` conventions |
//! | [`spec`] | a session's inputs, loaded with `avs validate`'s checks |
//! | [`snapshot`] | a session as a replay record, restored with nothing lost |
//! | [`live`] | the live view's state and its SVG picture |
//! | [`routes`] | one handler per route |
//!
//! ```no_run
//! # async fn run() -> Result<(), avs_service::ServiceError> {
//! use avs_service::{serve, ServiceConfig};
//! let config = ServiceConfig::default(); // 127.0.0.1:7878, no token, 16 sessions
//! serve(config).await
//! # }
//! ```
//!
//! In a test or another program, [`router`] gives the routes without a socket:
//!
//! ```
//! # tokio::runtime::Runtime::new().unwrap().block_on(async {
//! use avs_service::{router, AppState, ServiceConfig};
//! use tower::ServiceExt;
//! let app = router(AppState::new(ServiceConfig::default()));
//! let req = axum::http::Request::get("/healthz").body(axum::body::Body::empty()).unwrap();
//! assert_eq!(app.oneshot(req).await.unwrap().status(), 200);
//! # });
//! ```
//!
//! ## Choices
//!
//! * **axum on tokio** (dependencies): the de-facto standard async HTTP stack in Rust, with
//!   server-sent events built in; the agent itself stays synchronous, on one worker thread per
//!   session (a search is one blocking call; running it on the async runtime's threads would
//!   stall every other request).
//! * **utoipa** derives the OpenAPI document from the handlers and types, so it cannot drift
//!   from them; **subtle** compares the bearer token in constant time.
//! * **Long polling** for the remote robot, not a socket: any HTTP client in any language can
//!   be the robot (`examples/python/remote_robot.py` is one in plain Python), and a request not yet
//!   answered is handed again to the next poll, so a client that restarts loses nothing.
//! * **Snapshots are replay records** ([`snapshot`] says why).
//! * **Tokens**: a non-loopback address needs one (`serve` refuses to start without); it is
//!   accepted as `Authorization: Bearer T` or, for browsers' `EventSource` and the page's
//!   first load, as the `access_token` query parameter.

pub mod api;
pub mod error;
pub mod grid;
pub mod live;
pub mod remote;
pub mod routes;
pub mod session;
pub mod snapshot;
pub mod spec;

use axum::extract::{Request, State};
use axum::http::header;
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::Router;
use error::{ApiError, ErrorCode};
use session::Session;
use std::collections::BTreeMap;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;
use utoipa::OpenApi;

/// The largest request body, bytes: a remote robot's map of a large floor or a snapshot.
pub const MAX_BODY: usize = 256 << 20;

/// How the service runs.
#[derive(Debug, Clone)]
pub struct ServiceConfig {
    /// Where to listen.
    pub addr: SocketAddr,
    /// The bearer token every request must carry, if any (required off loopback).
    pub token: Option<String>,
    /// Sessions held at most.
    pub max_sessions: usize,
    /// A session without a running goal and without requests for this long is removed.
    pub idle_timeout: Duration,
    /// How long a remote robot may take to answer one request.
    pub robot_timeout: Duration,
    /// Start a simulated session on the default office searching for a cereal box.
    pub demo: bool,
}

impl Default for ServiceConfig {
    fn default() -> Self {
        Self {
            addr: SocketAddr::from(([127, 0, 0, 1], 7878)),
            token: None,
            max_sessions: 16,
            idle_timeout: Duration::from_secs(3600),
            robot_timeout: Duration::from_secs(300),
            demo: false,
        }
    }
}

/// Why the service cannot start.
#[derive(Debug, thiserror::Error)]
pub enum ServiceError {
    /// A setting is out of range (the flag is named).
    #[error("{flag}: {message}")]
    Config {
        /// The flag.
        flag: &'static str,
        /// What is wrong and what is expected.
        message: String,
    },
    /// Binding or serving failed.
    #[error("{0}")]
    Io(#[from] std::io::Error),
}

impl ServiceConfig {
    /// Check the settings: a non-loopback address needs a token; the limits are positive.
    pub fn check(&self) -> Result<(), ServiceError> {
        if !self.addr.ip().is_loopback() && self.token.as_deref().is_none_or(str::is_empty) {
            return Err(ServiceError::Config {
                flag: "--addr",
                message: format!(
                    "{} is not a loopback address: anyone who reaches it could drive the \
                     robot; give a --token (or AVS_TOKEN) that every request must carry",
                    self.addr
                ),
            });
        }
        if self.max_sessions == 0 {
            return Err(ServiceError::Config {
                flag: "--max-sessions",
                message: "0: expected at least 1".into(),
            });
        }
        for (flag, d) in [
            ("--idle-timeout", self.idle_timeout),
            ("--robot-timeout", self.robot_timeout),
        ] {
            if d.is_zero() {
                return Err(ServiceError::Config {
                    flag,
                    message: "0: expected a positive number of seconds".into(),
                });
            }
        }
        Ok(())
    }
}

/// The service's state: its settings and sessions.
#[derive(Debug, Clone)]
pub struct AppState {
    /// The settings.
    pub config: Arc<ServiceConfig>,
    sessions: Arc<Mutex<BTreeMap<String, Arc<Session>>>>,
    next: Arc<AtomicU64>,
}

impl AppState {
    /// A service with no session yet.
    pub fn new(config: ServiceConfig) -> Self {
        Self {
            config: Arc::new(config),
            sessions: Arc::default(),
            next: Arc::default(),
        }
    }

    /// The sessions, locked (never held across an await).
    pub fn sessions(&self) -> MutexGuard<'_, BTreeMap<String, Arc<Session>>> {
        self.sessions.lock().unwrap_or_else(|p| p.into_inner())
    }

    fn next_id(&self) -> String {
        format!("s{}", self.next.fetch_add(1, Ordering::SeqCst) + 1)
    }

    fn insert(&self, s: Arc<Session>) {
        self.sessions().insert(s.id.clone(), s);
    }

    fn remove(&self, id: &str) -> Option<Arc<Session>> {
        self.sessions().remove(id)
    }

    /// Remove the sessions idle longer than the idle timeout (no goal queued or running);
    /// their ids.
    pub fn expire_idle(&self) -> Vec<String> {
        let limit = self.config.idle_timeout;
        let gone: Vec<Arc<Session>> = {
            let mut map = self.sessions();
            let ids: Vec<String> = map
                .values()
                .filter(|s| !s.busy() && s.info().idle_s >= limit.as_secs_f64())
                .map(|s| s.id.clone())
                .collect();
            ids.iter().filter_map(|id| map.remove(id)).collect()
        };
        for s in &gone {
            tracing::info!(session = %s.id, "session expired after {} s idle", limit.as_secs());
            s.shutdown();
        }
        gone.iter().map(|s| s.id.clone()).collect()
    }
}

/// The OpenAPI document of every route.
#[derive(OpenApi)]
#[openapi(
    info(
        title = "avs serve",
        description = "The avs search agent as a service: sessions, goals, the remote-robot protocol, traces, beliefs, snapshots."
    ),
    paths(
        routes::healthz,
        routes::openapi,
        routes::page,
        routes::list_sessions,
        routes::create_session,
        routes::get_session,
        routes::delete_session,
        routes::post_goal,
        routes::list_goals,
        routes::get_goal,
        routes::cancel_goal,
        routes::robot_next,
        routes::robot_answer,
        routes::trace,
        routes::map_svg,
        routes::beliefs,
        routes::metrics,
        routes::snapshot
    ),
    components(schemas(
        api::CreateSession,
        api::Source,
        api::RobotKind,
        api::Created,
        api::GoalRequest,
        api::GoalCreated,
        api::GoalState,
        api::GoalStatus,
        api::GoalList,
        api::SessionInfo,
        api::SessionList,
        api::Health,
        api::SessionMetrics,
        remote::RobotRequest,
        remote::RequestKind,
        remote::Capability,
        remote::Answer,
        error::ApiError,
        error::ErrorBody,
        error::ErrorCode,
        grid::RosGrid,
        grid::MapInfo,
        grid::RosPose,
        grid::RosPoint,
        grid::RosQuaternion
    ))
)]
pub struct ApiDoc;

/// Every route of the service over `state`, with the token check when it has a token.
pub fn router(state: AppState) -> Router {
    let v1 = Router::new()
        .route(
            "/v1/sessions",
            get(routes::list_sessions).post(routes::create_session),
        )
        .route(
            "/v1/sessions/{id}",
            get(routes::get_session).delete(routes::delete_session),
        )
        .route(
            "/v1/sessions/{id}/goals",
            get(routes::list_goals).post(routes::post_goal),
        )
        .route(
            "/v1/sessions/{id}/goals/{goal_id}",
            get(routes::get_goal).delete(routes::cancel_goal),
        )
        .route("/v1/sessions/{id}/robot/next", get(routes::robot_next))
        .route(
            "/v1/sessions/{id}/robot/{request_id}",
            post(routes::robot_answer),
        )
        .route("/v1/sessions/{id}/trace", get(routes::trace))
        .route("/v1/sessions/{id}/map.svg", get(routes::map_svg))
        .route("/v1/sessions/{id}/beliefs", get(routes::beliefs))
        .route("/v1/sessions/{id}/metrics", get(routes::metrics))
        .route("/v1/sessions/{id}/snapshot", get(routes::snapshot))
        .route("/healthz", get(routes::healthz))
        .route("/openapi.json", get(routes::openapi))
        .route("/", get(routes::page))
        .fallback(|| async {
            ApiError::new(ErrorCode::NotFound, "no such route; see GET /openapi.json")
        });
    v1.layer(axum::middleware::from_fn_with_state(
        state.clone(),
        authorise,
    ))
    // A snapshot or a large map answer is more than the default 2 MB.
    .layer(axum::extract::DefaultBodyLimit::max(MAX_BODY))
    .with_state(state)
}

/// The token check: with a token configured, every request carries it (see the crate docs).
async fn authorise(State(state): State<AppState>, req: Request, next: Next) -> Response {
    let Some(token) = state.config.token.as_deref() else {
        return next.run(req).await;
    };
    let bearer = req
        .headers()
        .get(header::AUTHORIZATION)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.strip_prefix("Bearer "))
        .map(str::to_string);
    let query = req.uri().query().and_then(|q| {
        form_urlencoded::parse(q.as_bytes())
            .find(|(k, _)| k == "access_token")
            .map(|(_, v)| v.into_owned())
    });
    let ok = [bearer, query].into_iter().flatten().any(|t| {
        use subtle::ConstantTimeEq;
        t.len() == token.len() && bool::from(t.as_bytes().ct_eq(token.as_bytes()))
    });
    if ok {
        next.run(req).await
    } else {
        ApiError::new(
            ErrorCode::Unauthorized,
            "this server needs its token: `Authorization: Bearer <token>` (or `?access_token=`)",
        )
        .into_response()
    }
}

/// Run the service until Ctrl-C: check the settings, bind, start the demo session if asked,
/// remove idle sessions every so often.
pub async fn serve(config: ServiceConfig) -> Result<(), ServiceError> {
    config.check()?;
    let state = AppState::new(config.clone());
    let listener = tokio::net::TcpListener::bind(config.addr).await?;
    let addr = listener.local_addr()?;
    tracing::info!("avs serve listening on http://{addr}/");
    if config.demo {
        let id = routes::create(&state, api::CreateSession::default())
            .await
            .map_err(|e| std::io::Error::other(format!("the demo session: {e}")))?;
        if let Some(s) = state.sessions().get(&id) {
            let _ = s.post_goal("cerealbox".into(), Vec::new());
        }
        tracing::info!("demo: session {id} searches the default office for a cerealbox");
    }
    let reaper = state.clone();
    let every =
        (config.idle_timeout / 10).clamp(Duration::from_millis(100), Duration::from_secs(30));
    tokio::spawn(async move {
        let mut tick = tokio::time::interval(every);
        loop {
            tick.tick().await;
            reaper.expire_idle();
        }
    });
    let shutdown_state = state.clone();
    axum::serve(listener, router(state))
        .with_graceful_shutdown(async move {
            let _ = tokio::signal::ctrl_c().await;
            for s in shutdown_state.sessions().values() {
                s.shutdown();
            }
        })
        .await?;
    Ok(())
}
