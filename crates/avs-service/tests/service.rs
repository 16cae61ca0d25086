//! The service through its routes (in-process, `tower::ServiceExt::oneshot`): the contract's
//! shapes, the sim and remote robots against the library search as the oracle, cancelling,
//! snapshots, tokens, limits.

use avs_agent::AgentConfig;
use avs_eval::episode::{run_episode, EpisodeSpec};
use avs_eval::inputs::Shipped;
use avs_service::remote::{answer_with, RobotRequest};
use avs_service::{router, AppState, ServiceConfig};
use avs_sim::sim_robot::{SimAgentRobot, SimRobotConfig};
use axum::body::Body;
use axum::http::{header, Request, StatusCode};
use axum::Router;
use http_body_util::BodyExt;
use serde_json::{json, Value};
use std::time::Duration;
use tower::ServiceExt;

/// The service's routes over a fresh state.
fn app(config: ServiceConfig) -> (AppState, Router) {
    let state = AppState::new(config);
    (state.clone(), router(state))
}

/// Call `method uri` with an optional JSON body; the status and the body (JSON when it
/// parses, else a string).
async fn call(app: &Router, method: &str, uri: &str, body: Option<Value>) -> (StatusCode, Value) {
    let req = Request::builder().method(method).uri(uri);
    let req = match body {
        Some(b) => req
            .header(header::CONTENT_TYPE, "application/json")
            .body(Body::from(b.to_string())),
        None => req.body(Body::empty()),
    }
    .unwrap();
    let res = app.clone().oneshot(req).await.unwrap();
    let status = res.status();
    let bytes = res.into_body().collect().await.unwrap().to_bytes();
    let text = String::from_utf8_lossy(&bytes).to_string();
    (
        status,
        serde_json::from_str(&text).unwrap_or(Value::String(text)),
    )
}

/// Create a session; its id.
async fn create(app: &Router, body: Value) -> String {
    let (s, v) = call(app, "POST", "/v1/sessions", Some(body)).await;
    assert_eq!(s, StatusCode::CREATED, "{v}");
    v["id"].as_str().unwrap().to_string()
}

/// Post a goal; its id.
async fn goal(app: &Router, sid: &str, class: &str) -> String {
    let (s, v) = call(
        app,
        "POST",
        &format!("/v1/sessions/{sid}/goals"),
        Some(json!({ "class": class })),
    )
    .await;
    assert_eq!(s, StatusCode::ACCEPTED, "{v}");
    v["goal_id"].as_str().unwrap().to_string()
}

/// Wait until goal `gid` of session `sid` has ended; its status.
async fn ended(app: &Router, sid: &str, gid: &str) -> Value {
    for _ in 0..6000 {
        let (_, v) = call(app, "GET", &format!("/v1/sessions/{sid}/goals/{gid}"), None).await;
        if !matches!(v["state"].as_str(), Some("queued" | "running")) {
            return v;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    panic!("goal {gid} of {sid} did not end in 300 s");
}

/// The trace of session `sid` as JSON lines.
async fn trace(app: &Router, sid: &str, query: &str) -> Vec<String> {
    let (s, v) = call(
        app,
        "GET",
        &format!("/v1/sessions/{sid}/trace{query}"),
        None,
    )
    .await;
    assert_eq!(s, StatusCode::OK);
    // A single line parses as JSON; more lines stay text.
    let text = match v {
        Value::String(t) => t,
        other => format!("{other}\n"),
    };
    text.lines().map(str::to_string).collect()
}

/// The library's own search of the shipped office for `class` with seed `seed`: the oracle.
fn library_search(class: &str, seed: u64) -> avs_eval::episode::Episode {
    let world = Shipped::Environment.input().world().unwrap();
    let k = Shipped::Knowledge.input().knowledge().unwrap();
    let d = Shipped::Domain.input().domain().unwrap();
    let spec = EpisodeSpec {
        knowledge: &k,
        domain: &d,
        goal: class,
        seed,
        config: AgentConfig::default(),
        faults: Default::default(),
        before: &[],
        find_all: false,
        place_classifier: false,
    };
    run_episode(&world, &spec, &mut |_| {}).unwrap()
}

fn lines(e: &avs_eval::episode::Episode) -> Vec<String> {
    e.report.trace.iter().map(|e| e.json_line()).collect()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn health_openapi_and_page_answer() {
    let (_, app) = app(ServiceConfig::default());
    let (s, v) = call(&app, "GET", "/healthz", None).await;
    assert_eq!((s, v["status"].as_str()), (StatusCode::OK, Some("ok")));
    let (_, doc) = call(&app, "GET", "/openapi.json", None).await;
    let paths = doc["paths"].as_object().expect("an OpenAPI document");
    for p in [
        "/healthz",
        "/openapi.json",
        "/",
        "/v1/sessions",
        "/v1/sessions/{id}",
        "/v1/sessions/{id}/goals",
        "/v1/sessions/{id}/goals/{goal_id}",
        "/v1/sessions/{id}/robot/next",
        "/v1/sessions/{id}/robot/{request_id}",
        "/v1/sessions/{id}/trace",
        "/v1/sessions/{id}/map.svg",
        "/v1/sessions/{id}/beliefs",
        "/v1/sessions/{id}/metrics",
        "/v1/sessions/{id}/snapshot",
    ] {
        assert!(paths.contains_key(p), "{p} missing from /openapi.json");
    }
    assert!(paths["/v1/sessions/{id}/goals/{goal_id}"]
        .as_object()
        .unwrap()
        .contains_key("delete"));
    let (s, page) = call(&app, "GET", "/", None).await;
    assert_eq!(s, StatusCode::OK);
    let page = page.as_str().unwrap();
    assert!(page.contains("<html") && page.contains("EventSource"));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn errors_have_the_contract_shape_and_name_the_field() {
    let (_, app) = app(ServiceConfig::default());
    let err = |v: &Value| {
        (
            v["error"]["code"].as_str().unwrap_or("?").to_string(),
            v["error"]["field"].as_str().unwrap_or("").to_string(),
        )
    };
    let (s, v) = call(&app, "GET", "/v1/sessions/s99", None).await;
    assert_eq!(s, StatusCode::NOT_FOUND);
    assert_eq!(err(&v).0, "not_found");
    assert!(v["error"]["message"].as_str().unwrap().contains("s99"));
    // Malformed requests: an unknown key, a wrong type.
    let (s, v) = call(
        &app,
        "POST",
        "/v1/sessions",
        Some(json!({ "robto": "sim" })),
    )
    .await;
    assert_eq!(
        (s, err(&v).0.as_str()),
        (StatusCode::BAD_REQUEST, "bad_request")
    );
    let (_, v) = call(&app, "POST", "/v1/sessions", Some(json!({ "seed": "one" }))).await;
    assert_eq!(err(&v), ("bad_request".into(), "seed".into()));
    // Invalid inputs, with the file's own diagnostics.
    let bad = json!({ "knowledge": { "inline": "kind: knowledge\nnot_a_field: 1\n" } });
    let (s, v) = call(&app, "POST", "/v1/sessions", Some(bad)).await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    assert_eq!(err(&v), ("invalid_input".into(), "knowledge".into()));
    assert!(v["error"]["message"]
        .as_str()
        .unwrap()
        .contains("not_a_field"));
    let (_, v) = call(
        &app,
        "POST",
        "/v1/sessions",
        Some(json!({ "knowledge": { "path": "/nonexistent/k.yaml" } })),
    )
    .await;
    assert_eq!(err(&v).1, "knowledge");
    let (_, v) = call(
        &app,
        "POST",
        "/v1/sessions",
        Some(json!({ "robot": "remote" })),
    )
    .await;
    assert_eq!(err(&v), ("invalid_input".into(), "start".into()));
    let (_, v) = call(
        &app,
        "POST",
        "/v1/sessions",
        Some(
            json!({ "robot": "remote", "start": {"x": 0.0, "y": 0.0, "yaw": 0.0},
                     "camera": { "hfov_deg": 0.0, "vfov_deg": 30.0, "pan_deg": [-90.0, 90.0],
                                 "tilt_deg": [-45.0, 30.0], "max_zoom": 4.0, "height": 1.2 } }),
        ),
    )
    .await;
    assert_eq!(err(&v).1, "camera.hfov_deg");
    let (_, v) = call(
        &app,
        "POST",
        "/v1/sessions",
        Some(json!({ "capabilities": ["attention"] })),
    )
    .await;
    assert_eq!(err(&v).1, "capabilities");
    // A goal for a class the knowledge does not have.
    let sid = create(&app, json!({})).await;
    let (s, v) = call(
        &app,
        "POST",
        &format!("/v1/sessions/{sid}/goals"),
        Some(json!({ "class": "unicorn" })),
    )
    .await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    assert_eq!(err(&v), ("invalid_input".into(), "class".into()));
    let (_, v) = call(&app, "GET", &format!("/v1/sessions/{sid}/robot/next"), None).await;
    assert_eq!(err(&v).0, "conflict", "a simulated robot is not polled");
    let (_, v) = call(&app, "GET", "/no/such/route", None).await;
    assert_eq!(err(&v).0, "not_found");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_token_is_required_when_configured() {
    let off_loopback = ServiceConfig {
        addr: "0.0.0.0:7878".parse().unwrap(),
        ..ServiceConfig::default()
    };
    let e = off_loopback.check().unwrap_err().to_string();
    assert!(e.contains("--addr") && e.contains("--token"), "{e}");
    let (_, app) = app(ServiceConfig {
        token: Some("s3cret".into()),
        ..off_loopback
    });
    let get = |auth: Option<&str>, uri: &str| {
        let mut r = Request::get(uri);
        if let Some(a) = auth {
            r = r.header(header::AUTHORIZATION, a);
        }
        r.body(Body::empty()).unwrap()
    };
    let status = |r: Request<Body>| {
        let app = app.clone();
        async move { app.oneshot(r).await.unwrap().status() }
    };
    assert_eq!(
        status(get(None, "/healthz")).await,
        StatusCode::UNAUTHORIZED
    );
    assert_eq!(
        status(get(Some("Bearer wrong!"), "/healthz")).await,
        StatusCode::UNAUTHORIZED
    );
    assert_eq!(
        status(get(Some("Bearer s3cret"), "/healthz")).await,
        StatusCode::OK
    );
    assert_eq!(
        status(get(None, "/v1/sessions?access_token=s3cret")).await,
        StatusCode::OK
    );
    let (_, v) = call(&app, "GET", "/v1/sessions", None).await;
    assert_eq!(v["error"]["code"], "unauthorized");
    // A token with characters a URL escapes is compared decoded.
    let (_, app) = self::app(ServiceConfig {
        token: Some("a+b/c d".into()),
        ..ServiceConfig::default()
    });
    let (s, _) = call(&app, "GET", "/healthz?access_token=a%2Bb%2Fc%20d", None).await;
    assert_eq!(s, StatusCode::OK);
    let (s, _) = call(&app, "GET", "/healthz?access_token=a%2Bb%2Fc", None).await;
    assert_eq!(s, StatusCode::UNAUTHORIZED);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn max_sessions_is_enforced_and_idle_sessions_expire() {
    let (state, app) = app(ServiceConfig {
        max_sessions: 1,
        idle_timeout: Duration::from_millis(20),
        ..ServiceConfig::default()
    });
    let sid = create(&app, json!({})).await;
    let (s, v) = call(&app, "POST", "/v1/sessions", Some(json!({}))).await;
    assert_eq!(s, StatusCode::TOO_MANY_REQUESTS);
    assert_eq!(v["error"]["code"], "too_many_sessions");
    let (s, _) = call(&app, "DELETE", &format!("/v1/sessions/{sid}"), None).await;
    assert_eq!(s, StatusCode::OK);
    let sid = create(&app, json!({})).await;
    tokio::time::sleep(Duration::from_millis(60)).await;
    assert_eq!(state.expire_idle(), vec![sid.clone()]);
    let (s, _) = call(&app, "GET", &format!("/v1/sessions/{sid}"), None).await;
    assert_eq!(s, StatusCode::NOT_FOUND);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_sim_goal_reports_what_the_library_search_reports() {
    let (_, app) = app(ServiceConfig::default());
    let sid = create(&app, json!({ "robot": "sim", "seed": 1 })).await;
    let gid = goal(&app, &sid, "cerealbox").await;
    let status = ended(&app, &sid, &gid).await;
    let oracle = library_search("cerealbox", 1);
    assert_eq!(status["state"], "found");
    let report = &status["report"];
    let expected = serde_json::to_value(&oracle.summary).unwrap();
    // Every key of `avs search --json`, with the same values (the wall-clock figures aside).
    for (k, v) in expected.as_object().unwrap() {
        if matches!(k.as_str(), "compute_s" | "plan_ms_median" | "dt_ms_median") {
            assert!(report.get(k).is_some(), "{k} missing");
            continue;
        }
        assert_eq!(&report[k], v, "report key {k}");
    }
    assert_eq!(trace(&app, &sid, "").await, lines(&oracle));
    assert_eq!(
        trace(&app, &sid, &format!("?goal={gid}")).await,
        lines(&oracle)
    );
    // The picture and the beliefs of what the search left.
    let req = Request::get(format!("/v1/sessions/{sid}/map.svg"))
        .body(Body::empty())
        .unwrap();
    let res = app.clone().oneshot(req).await.unwrap();
    assert_eq!(res.headers()[header::CONTENT_TYPE], "image/svg+xml");
    let svg = res.into_body().collect().await.unwrap().to_bytes();
    let svg = String::from_utf8_lossy(&svg);
    assert!(
        svg.contains("<title>room") && svg.contains("robot at"),
        "{svg}"
    );
    let (_, b) = call(&app, "GET", &format!("/v1/sessions/{sid}/beliefs"), None).await;
    assert_eq!(b["class"], "cerealbox");
    assert!(!b["rooms"].as_array().unwrap().is_empty());
    for r in b["rooms"].as_array().unwrap() {
        let total: f64 = r["categories"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c["p"].as_f64().unwrap())
            .sum();
        assert!((total - 1.0).abs() < 1e-6, "{r}");
    }
    assert!(b["objects"]
        .as_array()
        .unwrap()
        .iter()
        .any(|o| o["class"] == "cerealbox"));
    for p in b["placeholders"].as_array().unwrap() {
        let h: Vec<f64> = serde_json::from_value(p["hypotheses"].clone()).unwrap();
        assert!((h.iter().sum::<f64>() - 1.0).abs() < 1e-9, "{p}");
        let new_room: f64 = h[2..].iter().sum();
        assert!(
            (p["p_new_room"].as_f64().unwrap() - new_room).abs() < 1e-9,
            "{p}"
        );
        assert!(p["p_object"]
            .as_f64()
            .is_some_and(|x| (0.0..=1.0).contains(&x)));
    }
    let (_, m) = call(&app, "GET", &format!("/v1/sessions/{sid}/metrics"), None).await;
    assert_eq!(
        (m["goals"].as_u64(), m["found"].as_u64()),
        (Some(1), Some(1))
    );
    assert!(m["robot_requests"].as_u64().unwrap() > 0);
}

/// A client that answers session `sid`'s robot requests with a simulated robot in the shipped
/// office (seed `seed`), until `stop` resolves; how many it answered.
async fn sim_client(
    app: Router,
    sid: String,
    seed: u64,
    stop: tokio::sync::oneshot::Receiver<()>,
) -> usize {
    let world = Shipped::Environment.input().world().unwrap();
    let k = Shipped::Knowledge.input().knowledge().unwrap();
    let mut robot = SimAgentRobot::new(&world, k, SimRobotConfig::default(), seed).unwrap();
    let mut answered = 0;
    tokio::pin!(stop);
    let poll = format!("/v1/sessions/{sid}/robot/next?timeout_ms=200");
    loop {
        let next = call(&app, "GET", &poll, None);
        let (s, v) = tokio::select! {
            r = next => r,
            _ = &mut stop => return answered,
        };
        if s == StatusCode::NO_CONTENT {
            continue;
        }
        let req: RobotRequest = serde_json::from_value(v).unwrap();
        let answer = answer_with(&mut robot, &req);
        let (s, v) = call(
            &app,
            "POST",
            &format!("/v1/sessions/{sid}/robot/{}", req.request_id),
            Some(serde_json::to_value(answer).unwrap()),
        )
        .await;
        assert_eq!(s, StatusCode::OK, "{v}");
        answered += 1;
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_remote_robot_behind_the_protocol_searches_as_the_same_robot_in_process() {
    let (_, app) = app(ServiceConfig::default());
    let world = Shipped::Environment.input().world().unwrap();
    let s = &world.env.robot.start;
    let sid = create(
        &app,
        json!({
            "robot": "remote",
            "start": { "x": s.x, "y": s.y, "yaw": s.yaw_deg.to_radians() },
            "camera": world.env.camera,
            "capabilities": ["classify_place", "detector_scores", "attention", "recognise"],
        }),
    )
    .await;
    let (stop_tx, stop_rx) = tokio::sync::oneshot::channel();
    let client = tokio::spawn(sim_client(app.clone(), sid.clone(), 1, stop_rx));
    let gid = goal(&app, &sid, "cerealbox").await;
    let status = ended(&app, &sid, &gid).await;
    stop_tx.send(()).unwrap();
    let answered = client.await.unwrap();
    let oracle = library_search("cerealbox", 1);
    assert_eq!(status["state"], "found");
    assert_eq!(
        status["report"]["reported_pose"],
        serde_json::to_value(oracle.summary.reported_pose).unwrap()
    );
    // Without the world the truth-scored keys are empty.
    assert_eq!(status["report"]["spl"], 0.0);
    assert!(status["report"]["shortest_path_length"].is_null());
    assert_eq!(trace(&app, &sid, "").await, lines(&oracle));
    assert!(answered > 10);
    // Every exchange is in the snapshot; a restore replays them without a client.
    let (_, snap) = call(&app, "GET", &format!("/v1/sessions/{sid}/snapshot"), None).await;
    assert_eq!(snap["robot_log"].as_array().unwrap().len(), answered);
    let (_, fresh) = self::app(ServiceConfig::default());
    let rid = create(&fresh, json!({ "snapshot": snap })).await;
    let (_, a) = call(&app, "GET", &format!("/v1/sessions/{sid}/beliefs"), None).await;
    let (_, b) = call(&fresh, "GET", &format!("/v1/sessions/{rid}/beliefs"), None).await;
    assert_eq!(a, b);
    assert_eq!(trace(&fresh, &rid, "").await, lines(&oracle));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_malformed_answer_is_refused_with_the_field_and_the_request_stays_open() {
    let (_, app) = app(ServiceConfig::default());
    let sid = create(
        &app,
        json!({ "robot": "remote", "start": { "x": 1.0, "y": 1.0, "yaw": 0.0 } }),
    )
    .await;
    let gid = goal(&app, &sid, "mug").await;
    let (s, req) = call(
        &app,
        "GET",
        &format!("/v1/sessions/{sid}/robot/next?timeout_ms=10000"),
        None,
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{req}");
    assert_eq!(
        req["kind"], "map_update",
        "the agent's first question is the map"
    );
    let id = req["request_id"].as_u64().unwrap();
    let grid = json!({ "info": { "resolution": 0.5, "width": 2, "height": 1,
        "origin": { "position": { "x": 0.0, "y": 0.0, "z": 0.0 },
                    "orientation": { "x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0 } } },
        "data": [0, 7] });
    let bad = json!({ "result": { "grid": { "info": grid["info"], "data": [0, 101] },
                                  "newly_known": 2 } });
    let (s, v) = call(
        &app,
        "POST",
        &format!("/v1/sessions/{sid}/robot/{id}"),
        Some(bad),
    )
    .await;
    assert_eq!(s, StatusCode::BAD_REQUEST);
    assert_eq!(v["error"]["field"], "result.grid.data[1]");
    let no_count = json!({ "result": { "grid": grid } });
    let (_, v) = call(
        &app,
        "POST",
        &format!("/v1/sessions/{sid}/robot/{id}"),
        Some(no_count),
    )
    .await;
    assert!(
        v["error"]["message"]
            .as_str()
            .unwrap()
            .contains("newly_known"),
        "{v}"
    );
    let (s, _) = call(
        &app,
        "POST",
        &format!("/v1/sessions/{sid}/robot/{}", id + 5),
        Some(json!({ "failure": { "reason": "unsupported", "message": "?" } })),
    )
    .await;
    assert_eq!(s, StatusCode::NOT_FOUND);
    // Still the same request.
    let (_, again) = call(&app, "GET", &format!("/v1/sessions/{sid}/robot/next"), None).await;
    assert_eq!(again["request_id"].as_u64(), Some(id));
    // Cancelling fails the open request; the goal ends cancelled.
    let (s, _) = call(
        &app,
        "DELETE",
        &format!("/v1/sessions/{sid}/goals/{gid}"),
        None,
    )
    .await;
    assert_eq!(s, StatusCode::OK);
    // After the cancel the robot is not asked again: the goal ends at once.
    let status = ended(&app, &sid, &gid).await;
    assert_eq!(status["state"], "cancelled", "{status}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_cancelled_goal_and_the_goals_after_it_survive_a_snapshot() {
    let (_, app) = app(ServiceConfig::default());
    let sid = create(&app, json!({ "seed": 2 })).await;
    let g1 = goal(&app, &sid, "whiteboardmarker").await;
    // Cancel once it has made some progress.
    for _ in 0..6000 {
        let (_, m) = call(&app, "GET", &format!("/v1/sessions/{sid}/metrics"), None).await;
        if m["robot_requests"].as_u64().unwrap_or(0) > 30 {
            break;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    let (_, v) = call(
        &app,
        "DELETE",
        &format!("/v1/sessions/{sid}/goals/{g1}"),
        None,
    )
    .await;
    assert_eq!(v["state"], "running", "the marker's search runs long: {v}");
    let s1 = ended(&app, &sid, &g1).await;
    assert_eq!(s1["state"], "cancelled", "{s1}");
    assert!(s1["report"]["reason"]
        .as_str()
        .unwrap()
        .contains("cancelled"));
    let g2 = goal(&app, &sid, "cerealbox").await;
    let s2 = ended(&app, &sid, &g2).await;
    assert!(matches!(s2["state"].as_str(), Some("found" | "not_found")));
    let (_, snap) = call(&app, "GET", &format!("/v1/sessions/{sid}/snapshot"), None).await;
    assert_eq!(snap["goals"].as_array().unwrap().len(), 2);
    // The restore replays both goals (the cancel at the recorded checkpoint) and checks them
    // line by line against the record.
    let (_, fresh) = self::app(ServiceConfig::default());
    let (s, v) = call(
        &fresh,
        "POST",
        "/v1/sessions",
        Some(json!({ "snapshot": snap })),
    )
    .await;
    assert_eq!(s, StatusCode::CREATED, "{v}");
    let rid = v["id"].as_str().unwrap().to_string();
    assert_eq!(trace(&fresh, &rid, "").await, trace(&app, &sid, "").await);
    let (_, a) = call(&app, "GET", &format!("/v1/sessions/{sid}/beliefs"), None).await;
    let (_, b) = call(&fresh, "GET", &format!("/v1/sessions/{rid}/beliefs"), None).await;
    assert_eq!(a, b);
    let (_, goals) = call(&fresh, "GET", &format!("/v1/sessions/{rid}/goals"), None).await;
    let states: Vec<&str> = goals["goals"]
        .as_array()
        .unwrap()
        .iter()
        .map(|g| g["state"].as_str().unwrap())
        .collect();
    assert_eq!(
        states,
        [s1["state"].as_str().unwrap(), s2["state"].as_str().unwrap()]
    );
    // The next goal goes on from the same memory in both.
    let a3 = goal(&app, &sid, "mug").await;
    let b3 = goal(&fresh, &rid, "mug").await;
    assert_eq!(a3, b3, "goal ids continue");
    ended(&app, &sid, &a3).await;
    ended(&fresh, &rid, &b3).await;
    assert_eq!(
        trace(&app, &sid, &format!("?goal={a3}")).await,
        trace(&fresh, &rid, &format!("?goal={b3}")).await
    );
    // A snapshot whose record was tampered with is refused, not restored wrong.
    let mut bad = snap.clone();
    let line = &mut bad["goals"][1]["trace"][0];
    assert!(
        line.as_str().unwrap().contains("\"goal\":\"cerealbox\""),
        "{line}"
    );
    *line = Value::String(line.as_str().unwrap().replace("cerealbox", "mug"));
    let (s, v) = call(
        &fresh,
        "POST",
        "/v1/sessions",
        Some(json!({ "snapshot": bad })),
    )
    .await;
    assert_eq!(s, StatusCode::BAD_REQUEST, "{v}");
    assert_eq!(v["error"]["field"], "snapshot");
    assert!(v["error"]["message"].as_str().unwrap().contains("differs"));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_event_stream_replays_the_trace_then_follows() {
    let (_, app) = app(ServiceConfig::default());
    let sid = create(&app, json!({})).await;
    let gid = goal(&app, &sid, "cerealbox").await;
    ended(&app, &sid, &gid).await;
    let n = trace(&app, &sid, "").await.len();
    let req = Request::get(format!("/v1/sessions/{sid}/trace"))
        .header(header::ACCEPT, "text/event-stream")
        .body(Body::empty())
        .unwrap();
    let res = app.clone().oneshot(req).await.unwrap();
    assert_eq!(res.headers()[header::CONTENT_TYPE], "text/event-stream");
    let mut body = res.into_body();
    let mut text = String::new();
    while text.matches("event: trace").count() < n {
        let frame = tokio::time::timeout(Duration::from_secs(10), body.frame())
            .await
            .expect("the stream sends what is there at once")
            .unwrap()
            .unwrap();
        if let Ok(d) = frame.into_data() {
            text.push_str(&String::from_utf8_lossy(&d));
        }
    }
    assert!(text.contains("event: goal"));
    assert!(text.contains(&format!("id: {}", n - 1)));
    // Then it follows: a new goal's lines arrive on the same stream.
    let g2 = goal(&app, &sid, "mug").await;
    let mut more = String::new();
    while !more.contains("\"event\":\"started\"") {
        let frame = tokio::time::timeout(Duration::from_secs(60), body.frame())
            .await
            .expect("the new goal's events arrive")
            .unwrap()
            .unwrap();
        if let Ok(d) = frame.into_data() {
            more.push_str(&String::from_utf8_lossy(&d));
        }
    }
    assert!(more.contains(&format!("id: {n}")), "{more}");
    let (_, _) = call(
        &app,
        "DELETE",
        &format!("/v1/sessions/{sid}/goals/{g2}"),
        None,
    )
    .await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_corpus_of_malformed_requests_gets_4xx_naming_the_field_and_the_server_goes_on() {
    let (_, app) = app(ServiceConfig::default());
    let sim = create(&app, json!({})).await;
    let remote = create(
        &app,
        json!({ "robot": "remote", "start": { "x": 1.0, "y": 1.0, "yaw": 0.0 } }),
    )
    .await;
    goal(&app, &remote, "mug").await;
    let (_, req) = call(
        &app,
        "GET",
        &format!("/v1/sessions/{remote}/robot/next?timeout_ms=10000"),
        None,
    )
    .await;
    assert_eq!(req["kind"], "map_update");
    let rid = req["request_id"].as_u64().unwrap();
    let answer = format!("/v1/sessions/{remote}/robot/{rid}");
    let info = json!({ "resolution": 0.5, "width": 2, "height": 1,
        "origin": { "position": { "x": 0.0, "y": 0.0 } } });
    let raw = |s: &str| Value::String(s.to_string());
    // (method, uri, body, the field the error must name); a `Value::String` body is sent raw.
    let corpus: Vec<(&str, String, Option<Value>, &str)> = vec![
        ("POST", "/v1/sessions".into(), Some(raw("")), "body"),
        ("POST", "/v1/sessions".into(), Some(raw("{")), "body"),
        ("POST", "/v1/sessions".into(), Some(raw("[1, 2]")), "body"),
        (
            "POST",
            "/v1/sessions".into(),
            Some(raw("{\"seed\": NaN}")),
            "seed",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(json!({ "robto": "sim" })),
            "robto",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(json!({ "seed": "one" })),
            "seed",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(json!({ "seed": -1 })),
            "seed",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(json!({ "robot": "robotic" })),
            "robot",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(json!({ "zoom": "yes" })),
            "zoom",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(json!({ "knowledge": { "url": "x" } })),
            "knowledge",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(json!({ "knowledge": { "inline": "kind: [" } })),
            "knowledge",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(json!({ "domain": { "inline": "kind: domain\n" } })),
            "domain",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(json!({ "environment": { "inline": "kind: environment\n" } })),
            "environment",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(json!({ "knowledge": { "path": "/no/such.yaml" } })),
            "knowledge",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(json!({ "start": { "x": "1", "y": 0, "yaw": 0 } })),
            "start.x",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(raw(r#"{"start": {"x": 1e999, "y": 0, "yaw": 0}}"#)),
            "start.x",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(json!({ "robot": "remote" })),
            "start",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(
                json!({ "robot": "remote", "start": { "x": 0, "y": 0, "yaw": 0 },
            "camera": { "hfov_deg": 40, "vfov_deg": 30, "pan_deg": [-90, 90], "tilt_deg": [-45, 30],
                        "max_zoom": 0.5, "height": 1.2 } }),
            ),
            "camera.max_zoom",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(json!({ "camera": { "hfov_deg": 40 } })),
            "camera.vfov_deg",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(
                json!({ "robot": "remote", "start": { "x": 0, "y": 0, "yaw": 0 },
            "capabilities": ["teleport"] }),
            ),
            "capabilities[0]",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(json!({ "capabilities": ["attention"] })),
            "capabilities",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(json!({ "snapshot": 5 })),
            "snapshot",
        ),
        (
            "POST",
            "/v1/sessions".into(),
            Some(json!({ "seed": 2, "snapshot": { "format": "x" } })),
            "snapshot.version",
        ),
        (
            "POST",
            format!("/v1/sessions/{sim}/goals"),
            Some(json!({})),
            "class",
        ),
        (
            "POST",
            format!("/v1/sessions/{sim}/goals"),
            Some(json!({ "class": 5 })),
            "class",
        ),
        (
            "POST",
            format!("/v1/sessions/{sim}/goals"),
            Some(json!({ "class": "unicorn" })),
            "class",
        ),
        (
            "POST",
            format!("/v1/sessions/{sim}/goals"),
            Some(json!({ "class": "mug", "also": ["unicorn"] })),
            "also[0]",
        ),
        (
            "POST",
            "/v1/sessions/s404/goals".into(),
            Some(json!({ "class": "mug" })),
            "id",
        ),
        (
            "GET",
            format!("/v1/sessions/{sim}/goals/g404"),
            None,
            "goal_id",
        ),
        (
            "DELETE",
            format!("/v1/sessions/{sim}/goals/g404"),
            None,
            "goal_id",
        ),
        ("DELETE", "/v1/sessions/s404".into(), None, "id"),
        (
            "GET",
            format!("/v1/sessions/{sim}/trace?goal=g404"),
            None,
            "goal",
        ),
        (
            "GET",
            format!("/v1/sessions/{sim}/beliefs?class=unicorn"),
            None,
            "class",
        ),
        (
            "GET",
            format!("/v1/sessions/{sim}/beliefs?klass=mug"),
            None,
            "klass",
        ),
        (
            "GET",
            format!("/v1/sessions/{sim}/map.svg?plan=maybe"),
            None,
            "plan",
        ),
        (
            "GET",
            format!("/v1/sessions/{sim}/robot/next"),
            None,
            "robot",
        ),
        (
            "GET",
            format!("/v1/sessions/{remote}/robot/next?timeout_ms=soon"),
            None,
            "timeout_ms",
        ),
        (
            "POST",
            format!("/v1/sessions/{remote}/robot/first"),
            Some(json!({ "failure": { "reason": "unreachable", "message": "" } })),
            "request_id",
        ),
        (
            "POST",
            format!("/v1/sessions/{remote}/robot/{}", rid + 1),
            Some(json!({ "failure": { "reason": "unreachable", "message": "" } })),
            "request_id",
        ),
        ("POST", answer.clone(), Some(json!({})), "result"),
        (
            "POST",
            answer.clone(),
            Some(json!({ "result": {}, "failure": { "reason": "unreachable", "message": "" } })),
            "result",
        ),
        (
            "POST",
            answer.clone(),
            Some(json!({ "failure": { "reason": "tired", "message": "" } })),
            "failure.reason",
        ),
        (
            "POST",
            answer.clone(),
            Some(json!({ "answer": 1 })),
            "answer",
        ),
        (
            "POST",
            answer.clone(),
            Some(
                json!({ "failure": { "reason": "unreachable", "message": "" },
            "pose": { "x": 0, "y": "0", "yaw": 0 } }),
            ),
            "pose.y",
        ),
        (
            "POST",
            answer.clone(),
            Some(json!({ "result": { "grid": { "info": info, "data": [0] }, "newly_known": 1 } })),
            "result.grid.data",
        ),
        (
            "POST",
            answer.clone(),
            Some(
                json!({ "result": { "grid": { "info": info, "data": [0, -2] }, "newly_known": 1 } }),
            ),
            "result.grid.data[1]",
        ),
        (
            "POST",
            answer.clone(),
            Some(json!({ "result": { "grid": { "info": info, "data": [0, 0] } } })),
            "result.newly_known",
        ),
        (
            "POST",
            answer.clone(),
            Some(
                json!({ "result": { "grid": { "info": { "resolution": -1, "width": 1, "height": 1,
            "origin": { "position": { "x": 0, "y": 0 } } }, "data": [0] }, "newly_known": 1 } }),
            ),
            "result.grid.info",
        ),
        (
            "POST",
            answer.clone(),
            Some(
                json!({ "result": { "grid": { "info": { "resolution": 0.1, "width": 100000, "height": 100000,
            "origin": { "position": { "x": 0, "y": 0 } } }, "data": [0] }, "newly_known": 1 } }),
            ),
            "result.grid.data",
        ),
        (
            "POST",
            answer.clone(),
            Some(
                json!({ "result": { "grid": { "info": info, "data": [0, 0] }, "newly_known": 1,
            "doors": [{ "name": "d", "x": 0, "y": 0, "yaw": 0, "width": -1, "open": true }] } }),
            ),
            "result.doors[0].width",
        ),
    ];
    assert!(corpus.len() >= 30, "{} cases", corpus.len());
    for (method, uri, body, field) in corpus {
        let mut req = Request::builder().method(method).uri(&uri);
        let body = match body {
            Some(Value::String(s)) => Body::from(s),
            Some(v) => {
                req = req.header(header::CONTENT_TYPE, "application/json");
                Body::from(v.to_string())
            }
            None => Body::empty(),
        };
        let res = app.clone().oneshot(req.body(body).unwrap()).await.unwrap();
        let status = res.status();
        let bytes = res.into_body().collect().await.unwrap().to_bytes();
        let v: Value = serde_json::from_slice(&bytes).unwrap_or_else(|_| {
            panic!(
                "{method} {uri}: not JSON: {}",
                String::from_utf8_lossy(&bytes)
            )
        });
        assert!(status.is_client_error(), "{method} {uri}: {status} {v}");
        assert_eq!(v["error"]["field"], field, "{method} {uri}: {v}");
        assert!(!v["error"]["message"].as_str().unwrap().is_empty());
    }
    // The request is still open, and a good answer is taken.
    let good = json!({ "result": { "grid": { "info": info, "data": [0, 0] }, "newly_known": 2 } });
    let (s, v) = call(&app, "POST", &answer, Some(good)).await;
    assert_eq!(s, StatusCode::OK, "{v}");
    let gid = goal(&app, &sim, "cerealbox").await;
    assert_eq!(ended(&app, &sim, &gid).await["state"], "found");
    let (s, _) = call(&app, "DELETE", &format!("/v1/sessions/{remote}"), None).await;
    assert_eq!(s, StatusCode::OK);
}

/// Answer one robot request of session `sid` with `robot`, if one comes within 2 s; whether
/// one did.
async fn answer_one(app: &Router, sid: &str, robot: &mut dyn avs_robot::Robot) -> bool {
    let (s, v) = call(
        app,
        "GET",
        &format!("/v1/sessions/{sid}/robot/next?timeout_ms=2000"),
        None,
    )
    .await;
    if s == StatusCode::NO_CONTENT {
        return false;
    }
    let req: RobotRequest = serde_json::from_value(v).unwrap();
    let answer = answer_with(robot, &req);
    let (s, v) = call(
        app,
        "POST",
        &format!("/v1/sessions/{sid}/robot/{}", req.request_id),
        Some(serde_json::to_value(answer).unwrap()),
    )
    .await;
    assert_eq!(s, StatusCode::OK, "{v}");
    true
}

/// Wait until session `sid`'s agent waits on robot request `id`.
async fn wait_pending(app: &Router, sid: &str, id: u64) {
    for _ in 0..3000 {
        let (_, info) = call(app, "GET", &format!("/v1/sessions/{sid}"), None).await;
        if info["pending_request"].as_u64() == Some(id) {
            return;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    panic!("session {sid} never asked request {id}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_session_restored_mid_goal_continues_its_goal_with_the_maps_it_had() {
    let world = Shipped::Environment.input().world().unwrap();
    let k = Shipped::Knowledge.input().knowledge().unwrap();
    // The physical robot: it goes on existing across the server's restart.
    let mut robot = SimAgentRobot::new(&world, k, SimRobotConfig::default(), 1).unwrap();
    let s = &world.env.robot.start;
    let body = json!({
        "robot": "remote",
        "start": { "x": s.x, "y": s.y, "yaw": s.yaw_deg.to_radians() },
        "camera": world.env.camera,
        "capabilities": ["classify_place", "detector_scores", "attention", "recognise"],
    });
    let (_, app) = app(ServiceConfig::default());
    let sid = create(&app, body).await;
    let gid = goal(&app, &sid, "cerealbox").await;
    // The robot answers until the agent has maps (at least 60 requests; how many the first
    // look-around takes depends on the camera).
    let has_rooms = |b: &Value| b["rooms"].as_array().is_some_and(|r| !r.is_empty());
    let mut answered: u64 = 0;
    loop {
        let (_, b) = call(&app, "GET", &format!("/v1/sessions/{sid}/beliefs"), None).await;
        if answered >= 60 && has_rooms(&b) {
            break;
        }
        assert!(answered < 2000, "no maps after {answered} requests: {b}");
        assert!(
            answer_one(&app, &sid, &mut robot).await,
            "the search asks on"
        );
        answered += 1;
    }
    // The server goes down mid-goal, while the agent waits on the robot: its snapshot is all
    // that is left.
    wait_pending(&app, &sid, answered + 1).await;
    let (_, snap) = call(&app, "GET", &format!("/v1/sessions/{sid}/snapshot"), None).await;
    assert_eq!(snap["goals"][0]["state"], "running");
    assert_eq!(snap["robot_log"].as_array().unwrap().len() as u64, answered);
    let (_, before) = call(&app, "GET", &format!("/v1/sessions/{sid}/beliefs"), None).await;
    call(&app, "DELETE", &format!("/v1/sessions/{sid}"), None).await;
    // A new server re-creates the session; the agent replays the record without asking the
    // robot, then asks what it had not yet been answered.
    let (_, fresh) = self::app(ServiceConfig::default());
    let rid = create(&fresh, json!({ "snapshot": snap })).await;
    // Once the record is replayed the agent waits on the robot with the beliefs it had, for
    // the request it was waiting on (the same number).
    wait_pending(&fresh, &rid, answered + 1).await;
    let (_, restored) = call(&fresh, "GET", &format!("/v1/sessions/{rid}/beliefs"), None).await;
    assert_eq!(restored, before);
    let mut after_restart = 0;
    loop {
        let (_, g) = call(
            &fresh,
            "GET",
            &format!("/v1/sessions/{rid}/goals/{gid}"),
            None,
        )
        .await;
        if g["state"] != "running" && g["state"] != "queued" {
            assert_eq!(g["state"], "found", "{g}");
            break;
        }
        if answer_one(&fresh, &rid, &mut robot).await {
            after_restart += 1;
        }
    }
    assert!(after_restart > 0);
    // The goal's whole trace is the uninterrupted search's: nothing was lost or redone on
    // the robot.
    assert_eq!(
        trace(&fresh, &rid, "").await,
        lines(&library_search("cerealbox", 1))
    );
    assert!(
        has_rooms(&before),
        "the session had maps before the restart: {before}"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_robot_that_never_answers_times_out_and_the_goal_ends() {
    let (_, app) = app(ServiceConfig {
        robot_timeout: Duration::from_millis(20),
        ..ServiceConfig::default()
    });
    let sid = create(
        &app,
        json!({ "robot": "remote", "start": { "x": 1.0, "y": 1.0, "yaw": 0.0 } }),
    )
    .await;
    let gid = goal(&app, &sid, "mug").await;
    let status = ended(&app, &sid, &gid).await;
    assert_eq!(status["state"], "not_found", "{status}");
    let (_, snap) = call(&app, "GET", &format!("/v1/sessions/{sid}/snapshot"), None).await;
    let log = snap["robot_log"].as_array().unwrap();
    assert!(!log.is_empty());
    assert!(log.iter().all(|e| e["answer"]["failure"]["message"]
        .as_str()
        .is_some_and(|m| m.contains("did not answer"))));
}
