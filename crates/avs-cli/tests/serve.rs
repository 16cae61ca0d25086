//! `avs serve` as a process on a loopback port: the Python client of `examples/python/`
//! (standard library only, its own grid-world robot) finds its target through the protocol
//! over real HTTP; an address off loopback without a token is refused.

mod common;

use common::serve::{http, serve};
use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

/// `GET path`: the body, or `None` while nothing listens.
fn get(port: u16, path: &str) -> Option<String> {
    http(port, "GET", path, "").map(|(_, b)| b)
}

#[test]
fn the_python_client_finds_its_target_over_http() {
    if Command::new("python3").arg("--version").output().is_err() {
        eprintln!("NOTICE: python3 not found; the Python client test is skipped");
        return;
    }
    let (_server, _dir, port) = serve(&[]);
    let script =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/python/remote_robot.py");
    let out = Command::new("python3")
        .arg(&script)
        .args([
            "--server",
            &format!("http://127.0.0.1:{port}"),
            "--timeout-s",
            "240",
        ])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "exit {:?}\n{stdout}\n{stderr}",
        out.status
    );
    let last = stdout.lines().last().unwrap_or_default();
    let v: serde_json::Value = serde_json::from_str(last).unwrap();
    assert_eq!(v["state"], "found", "{stdout}");
    // The client's own world puts the cereal box at (4.1, 3.1).
    let at: Vec<f64> = serde_json::from_value(v["found_at"].clone()).unwrap();
    assert!(
        (at[0] - 4.1).hypot(at[1] - 3.1) < 0.3,
        "reported at {at:?}: {stdout}"
    );
    // The server is still up and lists the session.
    let sessions = get(port, "/v1/sessions").unwrap();
    assert!(sessions.contains("\"robot\":\"remote\""), "{sessions}");
}

#[test]
fn an_address_off_loopback_needs_a_token() {
    let out = Command::new(env!("CARGO_BIN_EXE_avs"))
        .args(["serve", "--addr", "0.0.0.0:0"])
        .env_remove("AVS_TOKEN")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--token") && err.contains("0.0.0.0"), "{err}");
}

#[test]
fn the_demo_session_finds_the_cereal_box_with_the_trace_of_avs_search() {
    let (_server, dir, port) = serve(&["--demo"]);
    let t0 = Instant::now();
    loop {
        let r = get(port, "/v1/sessions/s1/goals/g1").unwrap_or_default();
        if r.contains("\"state\":\"found\"") {
            break;
        }
        assert!(
            !r.contains("\"state\":\"not_found\"") && !r.contains("\"state\":\"failed\""),
            "{r}"
        );
        assert!(t0.elapsed() < Duration::from_secs(120), "{r}");
        std::thread::sleep(Duration::from_millis(200));
    }
    // The same trace, line for line, as `avs search` with the same inputs and seed.
    let (_, served) = http(port, "GET", "/v1/sessions/s1/trace", "").unwrap();
    let file = dir.0.join("search.jsonl");
    let out = Command::new(env!("CARGO_BIN_EXE_avs"))
        .args([
            "search",
            "--goal",
            "cerealbox",
            "--seed",
            "1",
            "--json",
            "--trace-json",
        ])
        .arg(&file)
        .current_dir(&dir.0)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let searched = std::fs::read_to_string(&file).unwrap();
    assert!(searched.lines().count() > 10);
    assert_eq!(served, searched);
    let (status, page) = http(port, "GET", "/", "").unwrap();
    assert_eq!(status, 200);
    assert!(page.contains("<html"), "{page}");
}
