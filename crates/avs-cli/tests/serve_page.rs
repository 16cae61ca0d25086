//! The live page of `avs serve` (`GET /`, `crates/avs-service/src/page.html`) in a real headless
//! browser against `avs serve --demo`: the map arrives as inline SVG with the robot and the
//! rooms, the trace pane fills from the event stream, and it keeps growing while a new goal runs.
//!
//! Skipped, with a `NOTICE:` line, when no Chromium or Chrome is on `PATH` (`AVS_BROWSER`
//! names another binary).
//!
//! The browser is driven over the DevTools protocol on a pipe (`--remote-debugging-pipe`), not
//! with `--dump-dom --virtual-time-budget`: the page keeps its trace stream open, and virtual
//! time does not advance while a fetch is pending, so such a dump never comes. Polling the DOM
//! in real time also lets the waits be generous and still end as soon as the page is there.
//!
//! `AVS_PAGE_SCREENSHOT=/abs/path.png` also saves a screenshot of the page once the demo goal
//! is found (how `docs/img/serve.png` is made).

mod common;

use base64::Engine;
use common::serve::{http, serve, Killed};
use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

/// How long the page may take to show the demo's found goal, and then a second goal.
const STAGE: Duration = Duration::from_secs(30);

/// The headless browser to use: `AVS_BROWSER`, else the first of the usual names on `PATH`.
fn find_browser() -> Option<PathBuf> {
    if let Some(b) = std::env::var_os("AVS_BROWSER").filter(|b| !b.is_empty()) {
        return Some(PathBuf::from(b));
    }
    let path = std::env::var_os("PATH")?;
    let names = [
        "chromium",
        "chromium-browser",
        "google-chrome",
        "google-chrome-stable",
    ];
    names.iter().find_map(|n| {
        std::env::split_paths(&path)
            .map(|d| d.join(n))
            .find(|p| p.is_file())
    })
}

/// Whether `browser --version` answers like a Chromium within 20 s (an installer stub, such as
/// Ubuntu's `chromium-browser` without its snap, does not).
fn browser_runs(browser: &Path) -> bool {
    let Ok(child) = Command::new(browser)
        .arg("--version")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
    else {
        return false;
    };
    let mut child = Killed(child);
    let t0 = Instant::now();
    loop {
        match child.0.try_wait() {
            Ok(Some(st)) => {
                let mut out = String::new();
                if let Some(o) = child.0.stdout.as_mut() {
                    let _ = o.read_to_string(&mut out);
                }
                return st.success() && (out.contains("Chrom") || out.contains("chrom"));
            }
            Ok(None) if t0.elapsed() < Duration::from_secs(20) => {
                std::thread::sleep(Duration::from_millis(50));
            }
            _ => return false,
        }
    }
}

/// A headless browser driven over the DevTools protocol on a pipe, with one page attached.
struct Browser {
    /// The browser process (`sh` exec'd into it, so the same process).
    child: Child,
    /// Commands, `\0`-terminated JSON (the browser's fd 3).
    commands: ChildStdin,
    /// Answers and events, one JSON value each (from the browser's fd 4, by a reader thread).
    messages: Receiver<Value>,
    next_id: u64,
    /// The session of the attached page.
    session: Option<String>,
    /// Uncaught exceptions the page threw.
    exceptions: Vec<String>,
    /// Where the browser's stderr goes.
    log: PathBuf,
}

impl Browser {
    /// Start `browser` headless in `dir` and open a blank page.
    fn launch(browser: &Path, dir: &Path) -> Browser {
        let log = dir.join("browser.log");
        // The protocol pipe is fds 3 (in) and 4 (out): give the browser our stdin and stdout
        // pipes there.
        let mut child = Command::new("sh")
            .arg("-c")
            .arg(r#"exec "$0" "$@" 3<&0 4>&1 </dev/null >/dev/null"#)
            .arg(browser)
            .args([
                "--headless=new",
                "--no-sandbox",
                "--disable-gpu",
                "--disable-dev-shm-usage",
                "--no-first-run",
                "--no-default-browser-check",
                "--hide-scrollbars",
                "--window-size=1400,900",
                "--remote-debugging-pipe",
            ])
            .arg(format!("--user-data-dir={}", dir.join("profile").display()))
            .arg("about:blank")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(std::fs::File::create(&log).unwrap())
            .spawn()
            .unwrap_or_else(|e| panic!("starting {}: {e}", browser.display()));
        let commands = child.stdin.take().unwrap();
        let out = child.stdout.take().unwrap();
        let (tx, messages) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let mut out = BufReader::new(out);
            let mut buf = Vec::new();
            while out.read_until(0, &mut buf).is_ok_and(|n| n > 0) {
                if buf.last() == Some(&0) {
                    buf.pop();
                }
                if let Ok(v) = serde_json::from_slice(&buf) {
                    if tx.send(v).is_err() {
                        return;
                    }
                }
                buf.clear();
            }
        });
        let mut b = Browser {
            child,
            commands,
            messages,
            next_id: 0,
            session: None,
            exceptions: Vec::new(),
            log,
        };
        let target = b.call("Target.createTarget", json!({"url": "about:blank"}));
        let target = target["targetId"].as_str().unwrap().to_string();
        let attached = b.call(
            "Target.attachToTarget",
            json!({"targetId": target, "flatten": true}),
        );
        b.session = Some(attached["sessionId"].as_str().unwrap().to_string());
        b.call("Runtime.enable", json!({}));
        b
    }

    /// Send a command (to the page once attached) and wait up to 20 s for its answer.
    fn call(&mut self, method: &str, params: Value) -> Value {
        self.next_id += 1;
        let id = self.next_id;
        let mut msg = json!({"id": id, "method": method, "params": params});
        if let Some(s) = &self.session {
            msg["sessionId"] = json!(s);
        }
        let mut bytes = serde_json::to_vec(&msg).unwrap();
        bytes.push(0);
        if let Err(e) = self
            .commands
            .write_all(&bytes)
            .and_then(|()| self.commands.flush())
        {
            panic!(
                "{method}: the browser closed its pipe ({e}){}",
                self.log_tail()
            );
        }
        let deadline = Instant::now() + Duration::from_secs(20);
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            let m = match self.messages.recv_timeout(left) {
                Ok(m) => m,
                Err(RecvTimeoutError::Timeout) => {
                    panic!("{method}: no answer within 20 s{}", self.log_tail())
                }
                Err(RecvTimeoutError::Disconnected) => {
                    panic!("{method}: the browser exited{}", self.log_tail())
                }
            };
            if m["method"] == "Runtime.exceptionThrown" {
                let d = &m["params"]["exceptionDetails"];
                let text = d["exception"]["description"]
                    .as_str()
                    .or(d["text"].as_str())
                    .unwrap_or("?");
                self.exceptions
                    .push(format!("{text} (line {})", d["lineNumber"]));
            }
            if m["id"] == json!(id) {
                assert!(m["error"].is_null(), "{method}: {}", m["error"]);
                return m["result"].clone();
            }
        }
    }

    /// Evaluate `expr` in the page: its value.
    fn eval(&mut self, expr: &str) -> Value {
        let r = self.call(
            "Runtime.evaluate",
            json!({"expression": expr, "returnByValue": true}),
        );
        assert!(
            r["exceptionDetails"].is_null(),
            "evaluating in the page: {}",
            r["exceptionDetails"]
        );
        r["result"]["value"].clone()
    }

    /// The last lines the browser wrote to stderr, for a failure message.
    fn log_tail(&self) -> String {
        let text = std::fs::read_to_string(&self.log).unwrap_or_default();
        let lines: Vec<&str> = text.lines().collect();
        let tail = lines[lines.len().saturating_sub(15)..].join("\n");
        format!("; the browser's stderr ends:\n{tail}")
    }
}

impl Drop for Browser {
    /// Ask the browser to close, give it 5 s, then kill it.
    fn drop(&mut self) {
        let _ = self
            .commands
            .write_all(b"{\"id\":999999,\"method\":\"Browser.close\"}\0")
            .and_then(|()| self.commands.flush());
        let t0 = Instant::now();
        while t0.elapsed() < Duration::from_secs(5) {
            if !matches!(self.child.try_wait(), Ok(None)) {
                return;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// What the page shows: the map pane's HTML, the trace pane's lines, the status line.
#[derive(Debug)]
struct Shown {
    map: String,
    trace: Vec<String>,
    /// The line under the map: where the robot is.
    robot: String,
    trace_state: String,
    status: String,
    status_is_error: bool,
}

const SHOWN: &str = r"(() => {
  const $ = (id) => document.getElementById(id);
  const text = (id) => ($(id) ? $(id).textContent : '');
  return {
    map: $('map') ? $('map').innerHTML : '',
    trace: $('trace') ? [...$('trace').children].map((d) => d.textContent) : [],
    robot: text('robot'),
    trace_state: text('trace-state'),
    status: text('status'),
    status_is_error: !!$('status') && $('status').classList.contains('err'),
  };
})()";

impl Shown {
    fn of(b: &mut Browser) -> Shown {
        let v = b.eval(SHOWN);
        Shown {
            map: v["map"].as_str().unwrap_or_default().to_string(),
            trace: v["trace"]
                .as_array()
                .map(|a| {
                    a.iter()
                        .map(|l| l.as_str().unwrap_or_default().to_string())
                        .collect()
                })
                .unwrap_or_default(),
            robot: v["robot"].as_str().unwrap_or_default().to_string(),
            trace_state: v["trace_state"].as_str().unwrap_or_default().to_string(),
            status: v["status"].as_str().unwrap_or_default().to_string(),
            status_is_error: v["status_is_error"].as_bool().unwrap_or(false),
        }
    }

    /// The title of the robot's polygon in the inline map.
    fn robot_title(&self) -> Option<&str> {
        let i = self.map.find("<title>robot at")? + "<title>".len();
        let n = self.map[i..].find("</title>")?;
        Some(&self.map[i..i + n])
    }

    fn has_line(&self, from: usize, pred: impl Fn(&str) -> bool) -> bool {
        self.trace.iter().skip(from).any(|l| pred(l))
    }

    /// A summary for a failure message.
    fn describe(&self) -> String {
        let tail = &self.trace[self.trace.len().saturating_sub(8)..];
        format!(
            "map: {} chars, inline svg: {}, robot: {:?}, rooms: {}; under the map {:?}; trace \
             state {:?}; status {:?} (error: {}); {} trace lines, the last:\n  {}",
            self.map.len(),
            self.map.contains("<svg"),
            self.robot_title(),
            self.map.matches("<title>room").count(),
            self.robot,
            self.trace_state,
            self.status,
            self.status_is_error,
            self.trace.len(),
            tail.join("\n  ")
        )
    }
}

/// Poll what the page shows until `done`, for at most `limit`.
fn wait_for(b: &mut Browser, what: &str, limit: Duration, done: impl Fn(&Shown) -> bool) -> Shown {
    let t0 = Instant::now();
    loop {
        let s = Shown::of(b);
        if done(&s) {
            return s;
        }
        if t0.elapsed() > limit {
            panic!(
                "the page did not show {what} within {} s: {}; page exceptions: {:?}",
                limit.as_secs(),
                s.describe(),
                b.exceptions
            );
        }
        std::thread::sleep(Duration::from_millis(250));
    }
}

/// The session's odometry as the server reports it.
fn odometry(port: u16) -> f64 {
    let (_, body) = http(port, "GET", "/v1/sessions/s1", "").expect("GET /v1/sessions/s1");
    let v: Value = serde_json::from_str(&body).expect("session JSON");
    v["odometry"].as_f64().expect("odometry")
}

#[test]
fn the_live_page_shows_the_map_and_follows_the_trace() {
    let t_start = Instant::now();
    let Some(browser) = find_browser().filter(|_| cfg!(unix)) else {
        eprintln!(
            "NOTICE: no headless browser (chromium, chromium-browser or google-chrome) on PATH; \
             the live page test (crates/avs-cli/tests/serve_page.rs) is skipped. Install one \
             (Debian/Ubuntu: apt-get install chromium) or name it in AVS_BROWSER"
        );
        return;
    };
    if !browser_runs(&browser) {
        eprintln!(
            "NOTICE: {} does not run (`--version` failed); the live page test is skipped. \
             Install a working Chromium (Debian: apt-get install chromium) or name one in \
             AVS_BROWSER",
            browser.display()
        );
        return;
    }

    // In a fresh folder, so that nothing of the checkout is picked up.
    let (server, dir, port) = serve(&["--demo"]);
    let mut b = Browser::launch(&browser, &dir.0);
    b.call(
        "Page.navigate",
        json!({"url": format!("http://127.0.0.1:{port}/")}),
    );

    // 1. The demo's goal g1 (cerealbox) is found: the map is inline SVG with the robot and the
    //    rooms, and the trace pane holds the search from its first plan to the goal.
    let first = wait_for(&mut b, "the map and the trace of goal g1", STAGE, |s| {
        s.map.contains("<svg")
            && s.robot_title().is_some()
            && s.map.contains("<title>room")
            && s.robot.starts_with("robot at (")
            && s.has_line(0, |l| l.starts_with("search for cerealbox"))
            && s.has_line(0, |l| l.starts_with("plan 1 "))
            && s.has_line(0, |l| l.starts_with("goal reached"))
    });
    assert_eq!(first.trace_state, "trace: live", "{}", first.describe());
    if let Some(path) = std::env::var_os("AVS_PAGE_SCREENSHOT") {
        std::thread::sleep(Duration::from_millis(1500)); // beliefs and the last map
        let shot = b.call("Page.captureScreenshot", json!({"format": "png"}));
        let png = base64::engine::general_purpose::STANDARD
            .decode(shot["data"].as_str().unwrap())
            .unwrap();
        std::fs::write(&path, png).unwrap();
        eprintln!("screenshot: {}", Path::new(&path).display());
    }

    // 2. A second goal: the trace pane grows with its search (only the event stream brings
    //    those lines: the page never re-reads the trace otherwise), and its end shows as a goal
    //    line.
    let n1 = first.trace.len();
    let odometry_before = odometry(port);
    let (status, body) = http(port, "POST", "/v1/sessions/s1/goals", r#"{"class":"mug"}"#)
        .expect("POST /v1/sessions/s1/goals");
    assert!(
        (200..300).contains(&status),
        "posting goal mug: {status} {body}"
    );
    assert!(body.contains("\"g2\""), "posting goal mug: {body}");
    let second = wait_for(&mut b, "the trace of goal g2 (mug)", STAGE, |s| {
        s.trace.len() > n1
            && s.has_line(n1, |l| l.starts_with("search for mug"))
            && s.has_line(n1, |l| {
                l.starts_with("— goal g2 (mug): ")
                    && ["found", "not_found", "failed", "cancelled"]
                        .iter()
                        .any(|st| l.ends_with(st))
            })
    });
    assert!(
        second.trace.len() > n1,
        "the trace pane did not grow: {n1} lines, then {}",
        second.trace.len()
    );
    // The map follows too: when the robot drove for g2, the robot's title changes.
    if odometry(port) != odometry_before {
        let before = first.robot_title().unwrap_or_default().to_string();
        wait_for(&mut b, "the robot where g2 left it", STAGE, |s| {
            s.robot_title().is_some_and(|t| t != before)
        });
    }
    let last = Shown::of(&mut b);
    assert!(
        !last.status_is_error,
        "the page shows an error: {}",
        last.status
    );
    assert!(
        b.exceptions.is_empty(),
        "the page threw: {:?}",
        b.exceptions
    );
    eprintln!(
        "live page: {n1} trace lines after g1, {} after g2, in {:.1} s",
        second.trace.len(),
        t_start.elapsed().as_secs_f64()
    );
    drop(b);
    drop(server);
}
