//! `avs serve` as a process on a loopback port: the Python client of `examples/python/`
//! (standard library only, its own grid-world robot) finds its target through the protocol
//! over real HTTP; an address off loopback without a token is refused.

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// The server process, killed when dropped.
struct Server(Child);

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// A loopback port free now.
fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// `GET path` over plain HTTP/1.0: the status line, or `None` while nothing listens.
fn get(port: u16, path: &str) -> Option<String> {
    let mut s = TcpStream::connect(("127.0.0.1", port)).ok()?;
    s.set_read_timeout(Some(Duration::from_secs(10))).ok()?;
    write!(s, "GET {path} HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n").ok()?;
    let mut out = String::new();
    s.read_to_string(&mut out).ok()?;
    Some(out)
}

/// Start `avs serve` on a free port in an empty folder; the server and its port.
fn serve(extra: &[&str]) -> (Server, u16) {
    let port = free_port();
    let dir = std::env::temp_dir().join(format!("avs-serve-test-{}-{port}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_avs"))
        .args(["serve", "--addr", &format!("127.0.0.1:{port}")])
        .args(extra)
        .current_dir(&dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let server = Server(child);
    let t0 = Instant::now();
    while get(port, "/healthz").is_none_or(|r| !r.contains("\"ok\"")) {
        assert!(
            t0.elapsed() < Duration::from_secs(60),
            "avs serve did not answer /healthz within 60 s"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    (server, port)
}

#[test]
fn the_python_client_finds_its_target_over_http() {
    if Command::new("python3").arg("--version").output().is_err() {
        eprintln!("NOTICE: python3 not found; the Python client test is skipped");
        return;
    }
    let (_server, port) = serve(&[]);
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
fn the_demo_session_finds_the_cereal_box() {
    let (_server, port) = serve(&["--demo"]);
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
    let page = get(port, "/").unwrap();
    assert!(page.starts_with("HTTP/1.0 200") || page.starts_with("HTTP/1.1 200"));
    assert!(page.contains("text/html"), "{page}");
}
