//! `avs serve [--addr 127.0.0.1:7878] [--max-sessions N] [--idle-timeout S] [--robot-timeout S]
//! [--token T] [--demo]` — the search agent as a service (crate `avs-service`; routes and the
//! remote-robot protocol in `docs/SERVICE.md`). Logs go to stderr (`RUST_LOG=info` shows the
//! address and each session's milestones).

use std::net::SocketAddr;
use std::process::ExitCode;
use std::time::Duration;

/// Flags.
#[derive(clap::Args)]
pub struct Args {
    /// Where to listen. Loopback by default; any other address needs --token.
    #[arg(long, default_value = "127.0.0.1:7878")]
    pub addr: SocketAddr,
    /// Sessions held at most (each is one agent and one robot).
    #[arg(long, default_value_t = 16)]
    pub max_sessions: usize,
    /// Seconds a session without a running goal and without requests lives.
    #[arg(long, default_value_t = 3600.0)]
    pub idle_timeout: f64,
    /// Seconds a remote robot may take to answer one request.
    #[arg(long, default_value_t = 300.0)]
    pub robot_timeout: f64,
    /// The bearer token every request must carry (`Authorization: Bearer T`).
    #[arg(long, env = "AVS_TOKEN", hide_env_values = true)]
    pub token: Option<String>,
    /// Start a simulated session on the shipped office that searches for the cereal box, so
    /// the page at / shows a search at once.
    #[arg(long)]
    pub demo: bool,
}

/// Seconds from a flag, checked.
fn seconds(flag: &str, s: f64) -> anyhow::Result<Duration> {
    anyhow::ensure!(
        s.is_finite() && s > 0.0 && s <= 1e9,
        "{flag} {s}: expected a positive number of seconds"
    );
    Ok(Duration::from_secs_f64(s))
}

/// Run the subcommand until Ctrl-C.
pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    let config = avs_service::ServiceConfig {
        addr: a.addr,
        token: a.token.filter(|t| !t.is_empty()),
        max_sessions: a.max_sessions,
        idle_timeout: seconds("--idle-timeout", a.idle_timeout)?,
        robot_timeout: seconds("--robot-timeout", a.robot_timeout)?,
        demo: a.demo,
    };
    config.check()?;
    eprintln!(
        "avs serve: http://{}/ (the live page; API in docs/SERVICE.md, GET /openapi.json); Ctrl-C stops",
        config.addr
    );
    let rt = tokio::runtime::Runtime::new()?;
    rt.block_on(avs_service::serve(config))?;
    Ok(ExitCode::SUCCESS)
}
