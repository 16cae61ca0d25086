//! The one home of the `avs serve` tests' process handling: a free loopback port, the server
//! started in a fresh folder and killed when dropped, plain HTTP/1.0 requests (no client crate
//! for a handful of calls).

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A folder removed when dropped.
pub struct TempDir(pub PathBuf);

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A child process killed (and reaped) when dropped.
pub struct Killed(pub Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// A loopback port free now.
pub fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// One request over plain HTTP/1.0: the status and the body, or `None` while nothing listens.
pub fn http(port: u16, method: &str, path: &str, body: &str) -> Option<(u16, String)> {
    let mut s = TcpStream::connect(("127.0.0.1", port)).ok()?;
    s.set_read_timeout(Some(Duration::from_secs(10))).ok()?;
    s.set_write_timeout(Some(Duration::from_secs(10))).ok()?;
    write!(
        s,
        "{method} {path} HTTP/1.0\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n\
         Content-Length: {}\r\n\r\n{body}",
        body.len()
    )
    .ok()?;
    let mut out = String::new();
    s.read_to_string(&mut out).ok()?;
    let (head, body) = out.split_once("\r\n\r\n")?;
    let status = head.split_whitespace().nth(1)?.parse().ok()?;
    Some((status, body.to_string()))
}

/// `avs serve --addr 127.0.0.1:PORT extra…` started in a fresh folder (so nothing of the
/// checkout is picked up) and answering `/healthz`: the server, its folder and its port.
pub fn serve(extra: &[&str]) -> (Killed, TempDir, u16) {
    let port = free_port();
    let dir =
        TempDir(std::env::temp_dir().join(format!("avs-serve-test-{}-{port}", std::process::id())));
    std::fs::create_dir_all(&dir.0).unwrap();
    let server = Killed(
        Command::new(env!("CARGO_BIN_EXE_avs"))
            .args(["serve", "--addr", &format!("127.0.0.1:{port}")])
            .args(extra)
            .current_dir(&dir.0)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap(),
    );
    let t0 = Instant::now();
    while http(port, "GET", "/healthz", "").is_none_or(|(_, b)| !b.contains("\"ok\"")) {
        assert!(
            t0.elapsed() < Duration::from_secs(60),
            "avs serve did not answer /healthz within 60 s"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    (server, dir, port)
}
