//! # avs-eval
//!
//! Experiments over the avs agent in the simulated world: what the agent may never see (the
//! ground truth) is read here, and only to score and judge.
//!
//! * [`episode`] — one scored episode: a world, a simulated robot with faults, an agent, one
//!   search, the result scored against the truth (success, error, SPL);
//! * [`bench`](mod@bench) — the search bench over generated floors (success rate, SPL, path length);
//! * [`faults`] — the fault matrix: floors × faults (action failures, false positives, doors
//!   shutting), judged for crashes, hangs, give-ups that do not name their cause and wrong
//!   reports;
//! * [`inputs`] — input files, and the shipped defaults embedded in the program;
//! * [`edits`] — world edits before a search (start pose, closed doors, removed objects);
//! * [`scenario`] — the scenario runner: a scenario file re-enacted (world edits, searches
//!   before the goal), its expected properties checked and its text trace compared with the
//!   golden file (the plan-trace suite in `tests/plan_traces/`);
//! * [`verification`] — the detection-verification harness and bench (`avs verify-bench`);
//! * [`views`] — a room's view plan for several classes (`avs views`);
//! * [`zoom_calibration`] — the calibration bench of the simulated camera image against Sjöö et
//!   al.'s Figs. 7–10 (`avs zoom-bench`);
//! * [`zoom_sensing`] — the zoom pipeline's detection range, miss and false-alarm rates per
//!   class, measured on the simulated camera for an agent that runs it.
//!
//! The `avs` CLI's `run`, `search` and `bench` are thin layers over this crate.
//!
//! ```
//! use avs_eval::episode::{load_inputs, run_episode, EpisodeSpec, Faults};
//! let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
//! let (world, knowledge, domain) = load_inputs(
//!     &root.join("domains/environments/office.yaml"),
//!     &root.join("knowledge/office.yaml"),
//!     &root.join("domains/object_search.yaml"),
//! )
//! .unwrap();
//! let spec = EpisodeSpec {
//!     knowledge: &knowledge,
//!     domain: &domain,
//!     goal: "cerealbox",
//!     seed: 1,
//!     config: avs_agent::AgentConfig::default(),
//!     faults: Faults::default(),
//!     before: &[],
//!     find_all: false,
//!     place_classifier: false,
//! };
//! let episode = run_episode(&world, &spec, &mut |_| {}).unwrap();
//! assert!(episode.summary.found && episode.summary.spl > 0.0);
//! ```

pub mod bench;
pub mod edits;
pub mod episode;
mod error;
pub mod faults;
pub mod inputs;
pub mod scenario;
pub mod stats;
pub mod verification;
pub mod views;
pub mod zoom_calibration;
pub mod zoom_sensing;

pub use error::EvalError;
