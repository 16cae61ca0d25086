//! `avs` — active visual object search from the command line.
//!
//! A thin layer over the avs libraries: each subcommand lives in its own module under `cmd/`,
//! parses its flags with clap and reports library errors with context (anyhow).

use clap::{Parser, Subcommand};
use std::process::ExitCode;

mod cmd;

/// The searches allocate many small, short-lived beliefs (the POMDP sessions' look-ahead); an
/// allocator made for that pattern took 0–12 % (about 7 % on average) off `avs run`'s CPU time in
/// interleaved timings (BENCHMARKS.md).
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// Active visual object search: plan where to go, where to look, and when to give up.
#[derive(Parser)]
#[command(name = "avs", version, about, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// The default job: search the shipped office for the cerealbox and print the plan trace.
    Run(cmd::run::Args),
    /// Search a simulated environment for an object class; print the trace and a summary.
    Search(cmd::search::Args),
    /// Write small working example inputs for every command into a folder, and print the
    /// commands that use them.
    Examples(cmd::examples::Args),
    /// Benchmark a search strategy on generated floors (success rate, SPL, path length).
    Bench(cmd::bench::Args),
    /// Run the search agent as a service: sessions, goals, a remote-robot protocol, traces,
    /// beliefs, snapshots and a live web page (docs/SERVICE.md).
    Serve(cmd::serve::Args),
    /// Check avs files (environment, knowledge, domain, scenario) and report every problem.
    Validate(cmd::validate::Args),
    /// Re-enact scenario files and print each expected property with PASS or FAIL.
    Scenario(cmd::scenario::Args),
    /// Print the JSON Schema of an avs file kind.
    Schema(cmd::schema::Args),
    /// Segment a complete map (ROS map_server YAML or avs environment) into rooms by door
    /// detection, and score it against ground truth.
    Segment(cmd::segment::Args),
    /// Draw an environment (fully known, or after some exploration steps) as SVG.
    Render(cmd::render::Args),
    /// Generate an office-like floor environment.
    Generate(cmd::generate::Args),
    /// Marginals of a UAI or libDAI factor graph by belief propagation or exact inference.
    Infer(cmd::infer::Args),
    /// Plan for a PDDL domain and problem.
    Plan(cmd::plan::Args),
    /// Solve or simulate a POMDP in Cassandra's format.
    #[command(subcommand)]
    Pomdp(cmd::pomdp::Command),
    /// Gaussian-process regression (the verification sensor models' GPs).
    #[command(subcommand)]
    Gp(cmd::gp::Command),
    /// Detection verification: train a sensor model for a detector.
    #[command(subcommand)]
    Verify(cmd::verify::Command),
    /// Detection verification over repeated trials of a scenario (precision, recall, path).
    VerifyBench(cmd::verify::BenchArgs),
    /// The view plan of one room for several classes at once (standpoints, images, coverage).
    Views(cmd::views::Args),
    /// Calibrate the simulated camera image against Sjöö et al.'s Figs. 7–10: tables and SVG
    /// charts of hypotheses and distance estimates over distance.
    ZoomBench(cmd::zoom_bench::Args),
}

/// Rust ignores SIGPIPE, so a write to a closed pipe (`avs schema environment | head -c1`) is an
/// error, and `println!` panics on it. A command-line tool whose reader went away should end
/// quietly, as the shell's own tools do: restore the default action (the process ends with
/// the conventional status 141).
fn die_quietly_on_closed_pipe() {
    #[cfg(unix)]
    // SAFETY: `signal` with `SIG_DFL` only resets this process's disposition of SIGPIPE, before
    // any thread is started.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

fn main() -> ExitCode {
    die_quietly_on_closed_pipe();
    // Colours only on a terminal: `RUST_LOG=debug avs … 2> log` writes plain text.
    tracing_subscriber::fmt()
        .with_env_filter(tracing_subscriber::EnvFilter::from_default_env())
        .with_writer(std::io::stderr)
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .init();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(a) => cmd::run::run(a),
        Command::Search(a) => cmd::search::run(a),
        Command::Bench(a) => cmd::bench::run(a),
        Command::Validate(a) => cmd::validate::run(a),
        Command::Serve(a) => cmd::serve::run(a),
        Command::Scenario(a) => cmd::scenario::run(a),
        Command::Schema(a) => cmd::schema::run(a),
        Command::Segment(a) => cmd::segment::run(a),
        Command::Render(a) => cmd::render::run(a),
        Command::Generate(a) => cmd::generate::run(a),
        Command::Infer(a) => cmd::infer::run(a),
        Command::Plan(a) => cmd::plan::run(a),
        Command::Pomdp(c) => cmd::pomdp::run(c),
        Command::Gp(c) => cmd::gp::run(c),
        Command::Verify(c) => cmd::verify::run(c),
        Command::VerifyBench(a) => cmd::verify::bench(a),
        Command::Views(a) => cmd::views::run(a),
        Command::ZoomBench(a) => cmd::zoom_bench::run(a),
        Command::Examples(a) => cmd::examples::run(a),
    };
    // Usage errors (flags clap cannot parse) exit 2 from `Cli::parse`; everything a command
    // reports is about its input: exit 1 (README, "Conventions").
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(1)
        }
    }
}
