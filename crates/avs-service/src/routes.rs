//! The HTTP routes (the contract of `docs/SERVICE.md`): one handler per route, each a thin
//! layer over [`Session`] that parses, checks, and answers in the API's shapes.

use crate::api::{
    BeliefsQuery, CreateSession, Created, GoalCreated, GoalList, GoalRequest, GoalStatus, Health,
    MapQuery, NextQuery, SessionInfo, SessionList, SessionMetrics, TraceQuery,
};
use crate::error::{parse_json, ApiError, ErrorCode};
use crate::remote::{Answer, AnswerWire, RobotRequest};
use crate::session::Session;
use crate::snapshot::{Snapshot, FORMAT};
use crate::spec::Spec;
use crate::AppState;
use axum::body::Bytes;
use axum::extract::{Path, RawQuery, State};
use axum::http::{header, HeaderMap, StatusCode};
use axum::response::sse::{Event as SseEvent, KeepAlive, Sse};
use axum::response::{Html, IntoResponse, Response};
use axum::Json;
use std::convert::Infallible;
use std::sync::Arc;
use std::time::Duration;
use tokio_stream::wrappers::BroadcastStream;
use tokio_stream::StreamExt;

type Result<T> = std::result::Result<T, ApiError>;

/// The query string read as `T`; errors name the parameter (`access_token` is the token
/// check's and is ignored here).
fn query<T: serde::de::DeserializeOwned>(q: Option<String>) -> Result<T> {
    let q = q.unwrap_or_default();
    let kept: Vec<&str> = q
        .split('&')
        .filter(|kv| !kv.is_empty() && !kv.starts_with("access_token="))
        .collect();
    let joined = kept.join("&");
    let de = serde_urlencoded::Deserializer::new(form_urlencoded::parse(joined.as_bytes()));
    serde_path_to_error::deserialize(de).map_err(|e| {
        let field = e.path().to_string();
        let inner = e.into_inner();
        ApiError::bad_request(field, format!("query: {inner}"))
    })
}

/// The session `id`, marked as used.
fn session(state: &AppState, id: &str) -> Result<Arc<Session>> {
    let s = state
        .sessions()
        .get(id)
        .cloned()
        .ok_or_else(|| ApiError::not_found(format_args!("session {id}")).field("id"))?;
    s.touch();
    Ok(s)
}

/// Whether the service is up.
#[utoipa::path(get, path = "/healthz", responses((status = 200, body = Health)))]
pub async fn healthz(State(state): State<AppState>) -> Json<Health> {
    Json(Health {
        status: "ok".into(),
        sessions: state.sessions().len(),
        version: env!("CARGO_PKG_VERSION").into(),
    })
}

/// The OpenAPI document.
#[utoipa::path(get, path = "/openapi.json", responses((status = 200, description = "OpenAPI 3.1")))]
pub async fn openapi() -> Response {
    let doc = <crate::ApiDoc as utoipa::OpenApi>::openapi();
    (
        [(header::CONTENT_TYPE, "application/json")],
        doc.to_pretty_json().unwrap_or_default(),
    )
        .into_response()
}

/// The live web page.
#[utoipa::path(get, path = "/", responses((status = 200, description = "HTML")))]
pub async fn page() -> Html<&'static str> {
    Html(include_str!("page.html"))
}

/// Every session.
#[utoipa::path(get, path = "/v1/sessions", responses((status = 200, body = SessionList)))]
pub async fn list_sessions(State(state): State<AppState>) -> Json<SessionList> {
    let sessions: Vec<Arc<Session>> = state.sessions().values().cloned().collect();
    let mut list: Vec<SessionInfo> = sessions.iter().map(|s| s.info()).collect();
    list.sort_by_key(|s| {
        s.id.trim_start_matches('s')
            .parse::<u64>()
            .unwrap_or(u64::MAX)
    });
    Json(SessionList { sessions: list })
}

/// Create a session, or restore one from a snapshot.
#[utoipa::path(post, path = "/v1/sessions", request_body = CreateSession,
    responses((status = 201, body = Created), (status = 400, body = ApiError),
              (status = 429, body = ApiError)))]
pub async fn create_session(State(state): State<AppState>, body: Bytes) -> Result<Response> {
    let req: CreateSession = parse_json(&body)?;
    let id = create(&state, req).await?;
    Ok((StatusCode::CREATED, Json(Created { id })).into_response())
}

/// Create the session `req` asks for; its id.
pub async fn create(state: &AppState, req: CreateSession) -> Result<String> {
    if state.sessions().len() >= state.config.max_sessions {
        return Err(ApiError::new(
            ErrorCode::TooManySessions,
            format!(
                "the server holds {} sessions, its --max-sessions; delete one first",
                state.config.max_sessions
            ),
        ));
    }
    let rest = CreateSession {
        snapshot: None,
        ..req.clone()
    };
    let (spec, snapshot) = match req.snapshot {
        Some(snap) => {
            if rest != CreateSession::default() {
                return Err(ApiError::bad_request(
                    "snapshot",
                    "a restore takes the snapshot alone; its inputs are inside it",
                ));
            }
            if snap.format != FORMAT {
                return Err(ApiError::invalid(
                    "snapshot.format",
                    format!("{:?}: expected {FORMAT:?}", snap.format),
                ));
            }
            (snap.spec.clone(), Some(*snap))
        }
        None => (Spec::from_request(&req)?, None),
    };
    let loaded = {
        let spec = spec.clone();
        tokio::task::spawn_blocking(move || spec.load())
            .await
            .map_err(|e| ApiError::new(ErrorCode::Internal, e.to_string()))??
    };
    let id = state.next_id();
    let session = Session::start(
        id.clone(),
        spec,
        loaded,
        snapshot.as_ref(),
        state.config.robot_timeout,
    )
    .await
    .map_err(|e| match (e.field, snapshot.is_some()) {
        ("", _) => ApiError::new(ErrorCode::Internal, e.message),
        // A restore's inputs are inside the snapshot.
        (_, true) => ApiError::invalid("snapshot", e.message),
        (field, false) => ApiError::invalid(field, e.message),
    })?;
    state.insert(session);
    Ok(id)
}

/// One session.
#[utoipa::path(get, path = "/v1/sessions/{id}", responses((status = 200, body = SessionInfo),
    (status = 404, body = ApiError)))]
pub async fn get_session(
    State(state): State<AppState>,
    Path(id): Path<String>,
) -> Result<Json<SessionInfo>> {
    Ok(Json(session(&state, &id)?.info()))
}

/// End a session.
#[utoipa::path(delete, path = "/v1/sessions/{id}", responses((status = 200),
    (status = 404, body = ApiError)))]
pub async fn delete_session(
    State(state): State<AppState>,
    Path(id): Path<String>,
) -> Result<Json<serde_json::Value>> {
    let s = state
        .remove(&id)
        .ok_or_else(|| ApiError::not_found(format_args!("session {id}")).field("id"))?;
    s.shutdown();
    Ok(Json(serde_json::json!({ "deleted": id })))
}

/// Post a goal: it runs when the goals before it have ended.
#[utoipa::path(post, path = "/v1/sessions/{id}/goals", request_body = GoalRequest,
    responses((status = 202, body = GoalCreated), (status = 400, body = ApiError),
              (status = 404, body = ApiError)))]
pub async fn post_goal(
    State(state): State<AppState>,
    Path(id): Path<String>,
    body: Bytes,
) -> Result<Response> {
    let s = session(&state, &id)?;
    let req: GoalRequest = parse_json(&body)?;
    for (field, c) in std::iter::once(("class".to_string(), &req.class)).chain(
        req.also
            .iter()
            .enumerate()
            .map(|(i, c)| (format!("also[{i}]"), c)),
    ) {
        if !s.classes.contains(c) {
            return Err(ApiError::invalid(
                field,
                format!(
                    "{c:?} is not an object class of the session's knowledge; expected one of {}",
                    s.classes.join(", ")
                ),
            ));
        }
    }
    let goal_id = s
        .post_goal(req.class, req.also)
        .map_err(|e| ApiError::new(ErrorCode::Conflict, e))?;
    Ok((StatusCode::ACCEPTED, Json(GoalCreated { goal_id })).into_response())
}

/// Every goal of a session.
#[utoipa::path(get, path = "/v1/sessions/{id}/goals", responses((status = 200, body = GoalList)))]
pub async fn list_goals(
    State(state): State<AppState>,
    Path(id): Path<String>,
) -> Result<Json<GoalList>> {
    let s = session(&state, &id)?;
    let goals = s.shared.state().goals.iter().map(|g| g.status()).collect();
    Ok(Json(GoalList { goals }))
}

/// One goal.
#[utoipa::path(get, path = "/v1/sessions/{id}/goals/{goal_id}",
    responses((status = 200, body = GoalStatus), (status = 404, body = ApiError)))]
pub async fn get_goal(
    State(state): State<AppState>,
    Path((id, goal_id)): Path<(String, String)>,
) -> Result<Json<GoalStatus>> {
    let s = session(&state, &id)?;
    let st = s.shared.state();
    st.goals
        .iter()
        .find(|g| g.id == goal_id)
        .map(|g| Json(g.status()))
        .ok_or_else(|| {
            ApiError::not_found(format_args!("goal {goal_id} in session {id}")).field("goal_id")
        })
}

/// Cancel a goal.
#[utoipa::path(delete, path = "/v1/sessions/{id}/goals/{goal_id}",
    responses((status = 200, body = GoalStatus), (status = 404, body = ApiError)))]
pub async fn cancel_goal(
    State(state): State<AppState>,
    Path((id, goal_id)): Path<(String, String)>,
) -> Result<Json<GoalStatus>> {
    let s = session(&state, &id)?;
    s.cancel(&goal_id).map(Json).ok_or_else(|| {
        ApiError::not_found(format_args!("goal {goal_id} in session {id}")).field("goal_id")
    })
}

/// The link of a remote session (a simulated one is not asked: `409`).
fn remote_link(s: &Session) -> Result<Arc<crate::remote::RemoteLink>> {
    s.shared.link.clone().ok_or_else(|| {
        ApiError::new(
            ErrorCode::Conflict,
            format!(
                "session {} drives a simulated robot; only a remote robot is asked",
                s.id
            ),
        )
        .field("robot")
    })
}

/// The pending robot request (long poll).
#[utoipa::path(get, path = "/v1/sessions/{id}/robot/next", params(NextQuery),
    responses((status = 200, body = RobotRequest), (status = 204, description = "nothing pending"),
              (status = 409, body = ApiError)))]
pub async fn robot_next(
    State(state): State<AppState>,
    Path(id): Path<String>,
    RawQuery(q): RawQuery,
) -> Result<Response> {
    let q: NextQuery = query(q)?;
    let s = session(&state, &id)?;
    let link = remote_link(&s)?;
    let wait = Duration::from_millis(q.timeout_ms.unwrap_or(0).min(60_000));
    let r = link.next(wait).await;
    s.touch();
    Ok(match r {
        Some(r) => Json(r).into_response(),
        None => StatusCode::NO_CONTENT.into_response(),
    })
}

/// Answer a robot request.
#[utoipa::path(post, path = "/v1/sessions/{id}/robot/{request_id}", request_body = Answer,
    responses((status = 200), (status = 400, body = ApiError), (status = 404, body = ApiError)))]
pub async fn robot_answer(
    State(state): State<AppState>,
    Path((id, request_id)): Path<(String, String)>,
    body: Bytes,
) -> Result<Json<serde_json::Value>> {
    let s = session(&state, &id)?;
    let link = remote_link(&s)?;
    let rid: u64 = request_id.parse().map_err(|_| {
        ApiError::bad_request("request_id", format!("{request_id:?}: expected a number"))
    })?;
    let answer: AnswerWire = parse_json(&body)?;
    link.answer(rid, answer)?;
    Ok(Json(serde_json::json!({ "accepted": rid })))
}

/// The plan trace: JSON lines, or a server-sent event stream.
#[utoipa::path(get, path = "/v1/sessions/{id}/trace", params(TraceQuery),
    responses((status = 200, description = "JSON lines, or text/event-stream")))]
pub async fn trace(
    State(state): State<AppState>,
    Path(id): Path<String>,
    RawQuery(q): RawQuery,
    headers: HeaderMap,
) -> Result<Response> {
    let q: TraceQuery = query(q)?;
    let s = session(&state, &id)?;
    let goal = match &q.goal {
        Some(g) => Some(
            s.shared
                .state()
                .goals
                .iter()
                .position(|e| &e.id == g)
                .ok_or_else(|| {
                    ApiError::not_found(format_args!("goal {g} in session {id}")).field("goal")
                })?,
        ),
        None => None,
    };
    let wants_sse = headers
        .get(header::ACCEPT)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.contains("text/event-stream"));
    if !wants_sse {
        let st = s.shared.state();
        let mut body = String::new();
        for (_, line) in st
            .trace
            .iter()
            .filter(|(g, _)| goal.is_none_or(|k| k == *g))
        {
            body.push_str(line);
            body.push('\n');
        }
        return Ok(([(header::CONTENT_TYPE, "application/x-ndjson")], body).into_response());
    }
    // Subscribe first, then send what is already there: lines that arrive in between come
    // through the subscription and are skipped by index.
    let rx = s.shared.tx.subscribe();
    let (old, goals, from) = {
        let st = s.shared.state();
        let old: Vec<(usize, String)> = st
            .trace
            .iter()
            .enumerate()
            .filter(|(_, (g, _))| goal.is_none_or(|k| k == *g))
            .map(|(i, (_, l))| (i, l.clone()))
            .collect();
        let goals: Vec<String> = st
            .goals
            .iter()
            .map(|g| serde_json::to_string(&g.status()).unwrap_or_default())
            .collect();
        (old, goals, st.trace.len())
    };
    let initial = goals
        .into_iter()
        .map(|d| SseEvent::default().event("goal").data(d))
        .chain(
            old.into_iter()
                .map(|(i, l)| SseEvent::default().event("trace").id(i.to_string()).data(l)),
        )
        .map(Ok::<_, Infallible>)
        .collect::<Vec<_>>();
    let live = BroadcastStream::new(rx)
        .map_while(|m| m.ok())
        .filter_map(move |p| match p.line {
            Some((i, _)) if i < from => None,
            Some((_, g)) if goal.is_some_and(|k| k != g) => None,
            Some((i, _)) => Some(
                SseEvent::default()
                    .event(p.event)
                    .id(i.to_string())
                    .data(p.data),
            ),
            None => Some(SseEvent::default().event(p.event).data(p.data)),
        })
        .map(Ok::<_, Infallible>);
    let stream = tokio_stream::iter(initial).chain(live);
    Ok(Sse::new(stream)
        .keep_alive(KeepAlive::default())
        .into_response())
}

/// The map as SVG.
#[utoipa::path(get, path = "/v1/sessions/{id}/map.svg", params(MapQuery),
    responses((status = 200, description = "image/svg+xml")))]
pub async fn map_svg(
    State(state): State<AppState>,
    Path(id): Path<String>,
    RawQuery(q): RawQuery,
) -> Result<Response> {
    let q: MapQuery = query(q)?;
    let s = session(&state, &id)?;
    let live = s.shared.state().live.clone();
    let beliefs = s.beliefs(None);
    let svg = crate::live::render_svg(&live, beliefs.as_ref(), q.plan.unwrap_or(true));
    Ok(([(header::CONTENT_TYPE, "image/svg+xml")], svg).into_response())
}

/// The agent's beliefs.
#[utoipa::path(get, path = "/v1/sessions/{id}/beliefs", params(BeliefsQuery),
    responses((status = 200, description = "rooms, placeholders, doors, objects, locations")))]
pub async fn beliefs(
    State(state): State<AppState>,
    Path(id): Path<String>,
    RawQuery(q): RawQuery,
) -> Result<Json<serde_json::Value>> {
    let q: BeliefsQuery = query(q)?;
    let s = session(&state, &id)?;
    if let Some(c) = q.class.as_ref().filter(|c| !s.classes.contains(c)) {
        return Err(ApiError::invalid(
            "class",
            format!("{c:?} is not an object class of the session's knowledge"),
        ));
    }
    let b = s.beliefs(q.class.as_deref()).unwrap_or_default();
    Ok(Json(serde_json::to_value(b).unwrap_or_default()))
}

/// Figures of the session and its goals.
#[utoipa::path(get, path = "/v1/sessions/{id}/metrics",
    responses((status = 200, body = SessionMetrics)))]
pub async fn metrics(
    State(state): State<AppState>,
    Path(id): Path<String>,
) -> Result<Json<SessionMetrics>> {
    let s = session(&state, &id)?;
    let st = s.shared.state();
    let per_goal = st
        .goals
        .iter()
        .filter_map(|g| {
            let mut r = g.report.clone()?;
            if let Some(o) = r.as_object_mut() {
                o.insert("goal_id".into(), g.id.clone().into());
                o.insert("class".into(), g.class.clone().into());
            }
            Some(r)
        })
        .collect();
    Ok(Json(SessionMetrics {
        goals: st.goals.len(),
        found: st
            .goals
            .iter()
            .filter(|g| g.state == crate::api::GoalState::Found)
            .count(),
        not_found: st
            .goals
            .iter()
            .filter(|g| g.state.ended() && g.state != crate::api::GoalState::Found)
            .count(),
        odometry: st.live.odometry,
        trace_lines: st.trace.len(),
        robot_requests: s.robot_calls(),
        per_goal,
    }))
}

/// The session's snapshot.
#[utoipa::path(get, path = "/v1/sessions/{id}/snapshot",
    responses((status = 200, description = "a snapshot to POST to /v1/sessions as {snapshot}")))]
pub async fn snapshot(
    State(state): State<AppState>,
    Path(id): Path<String>,
) -> Result<Json<Snapshot>> {
    Ok(Json(session(&state, &id)?.snapshot()))
}
