//! `cargo bench -p avs-service --bench sessions`: `avs serve` on a loopback port, driven over
//! real TCP as robot stacks would drive it. 16 simulated sessions search the shipped office at
//! once (seeds 1–16) while one remote session's client answers its robot requests with a
//! simulated robot; prints how many searches completed, the wall time, the robot-request
//! round trip (a pending request fetched with `GET …/robot/next` plus its answer `POST`ed,
//! seen from the client) at p50 and p99, and the process's peak resident memory (server and
//! clients together). Figures go to BENCHMARKS.md; nothing here asserts a time.

use avs_eval::inputs::Shipped;
use avs_service::remote::{answer_with, RobotRequest};
use avs_service::{serve, ServiceConfig};
use avs_sim::sim_robot::{SimAgentRobot, SimRobotConfig};
use serde_json::{json, Value};
use std::time::{Duration, Instant};

const SESSIONS: u64 = 16;

fn post(base: &str, path: &str, body: &Value) -> Value {
    let r = ureq::post(&format!("{base}{path}"))
        .set("Content-Type", "application/json")
        .send_string(&body.to_string())
        .unwrap_or_else(|e| panic!("POST {path}: {e}"));
    serde_json::from_str(&r.into_string().unwrap()).unwrap()
}

fn get(base: &str, path: &str) -> (u16, String) {
    let r = ureq::get(&format!("{base}{path}"))
        .call()
        .unwrap_or_else(|e| panic!("GET {path}: {e}"));
    (r.status(), r.into_string().unwrap())
}

fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

fn peak_rss_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map(|kib| kib / 1024.0)
        .unwrap_or(f64::NAN)
}

fn main() {
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let config = ServiceConfig {
        addr: ([127, 0, 0, 1], port).into(),
        max_sessions: SESSIONS as usize + 1,
        ..ServiceConfig::default()
    };
    let rt = tokio::runtime::Runtime::new().unwrap();
    rt.spawn(async move { serve(config).await.unwrap() });
    let base = format!("http://127.0.0.1:{port}");
    while ureq::get(&format!("{base}/healthz")).call().is_err() {
        std::thread::sleep(Duration::from_millis(20));
    }
    let t0 = Instant::now();
    let mut goals = Vec::new();
    for seed in 1..=SESSIONS {
        let id = post(&base, "/v1/sessions", &json!({ "seed": seed }))["id"]
            .as_str()
            .unwrap()
            .to_string();
        let g = post(
            &base,
            &format!("/v1/sessions/{id}/goals"),
            &json!({ "class": "cerealbox" }),
        );
        goals.push((id, g["goal_id"].as_str().unwrap().to_string()));
    }
    // The remote session, answered by a simulated robot in this process.
    let world = Shipped::Environment.input().world().unwrap();
    let k = Shipped::Knowledge.input().knowledge().unwrap();
    let mut robot = SimAgentRobot::new(&world, k, SimRobotConfig::default(), 1).unwrap();
    let s = &world.env.robot.start;
    let rid = post(
        &base,
        "/v1/sessions",
        &json!({ "robot": "remote", "start": { "x": s.x, "y": s.y, "yaw": s.yaw_deg.to_radians() },
                 "camera": world.env.camera,
                 "capabilities": ["classify_place", "detector_scores", "attention", "recognise"] }),
    )["id"]
        .as_str()
        .unwrap()
        .to_string();
    let rg = post(
        &base,
        &format!("/v1/sessions/{rid}/goals"),
        &json!({ "class": "cerealbox" }),
    )["goal_id"]
        .as_str()
        .unwrap()
        .to_string();
    let mut round_trips_ms = Vec::new();
    loop {
        let (_, g) = get(&base, &format!("/v1/sessions/{rid}/goals/{rg}"));
        if !g.contains("\"queued\"") && !g.contains("\"running\"") {
            break;
        }
        // Wait (outside the timing) until a request is pending, then time fetch + answer.
        let (_, info) = get(&base, &format!("/v1/sessions/{rid}"));
        if !info.contains("pending_request") {
            std::thread::sleep(Duration::from_micros(200));
            continue;
        }
        let t = Instant::now();
        let (status, body) = get(&base, &format!("/v1/sessions/{rid}/robot/next"));
        if status != 200 {
            continue;
        }
        let req: RobotRequest = serde_json::from_str(&body).unwrap();
        let think = Instant::now();
        let answer = answer_with(&mut robot, &req);
        let thinking = think.elapsed();
        post(
            &base,
            &format!("/v1/sessions/{rid}/robot/{}", req.request_id),
            &serde_json::to_value(answer).unwrap(),
        );
        round_trips_ms.push((t.elapsed() - thinking).as_secs_f64() * 1e3);
    }
    let mut found = 0;
    for (id, g) in &goals {
        loop {
            let (_, body) = get(&base, &format!("/v1/sessions/{id}/goals/{g}"));
            if body.contains("\"found\"") {
                found += 1;
                break;
            }
            if !body.contains("\"queued\"") && !body.contains("\"running\"") {
                break;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }
    let wall = t0.elapsed().as_secs_f64();
    round_trips_ms.sort_by(f64::total_cmp);
    println!(
        "{SESSIONS} simulated sessions at once: {found} of {SESSIONS} found the cerealbox; all ended in {wall:.1} s"
    );
    println!(
        "remote session under that load: {} robot requests; round trip (GET next + POST answer, \
         the robot's own time excluded) p50 {:.2} ms, p99 {:.2} ms",
        round_trips_ms.len(),
        percentile(&round_trips_ms, 0.5),
        percentile(&round_trips_ms, 0.99)
    );
    println!(
        "peak resident memory of the process (server and clients): {:.0} MiB",
        peak_rss_mib()
    );
}
