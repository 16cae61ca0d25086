//! # avs-fuzz
//!
//! Fuzz targets for the avs readers: one public function per input format, each taking the raw
//! bytes of one input. The afl binaries in `fuzz/` (a separate cargo project, outside the
//! workspace) call them, and so does the corpus replay test (`tests/corpus.rs`), which runs every
//! seed in `fuzz/corpus/<target>/` on every `cargo test`.
//!
//! Each target feeds its bytes to the reader the way the `avs` CLI does (`avs validate`,
//! `segment`, `plan`, `pomdp`, `infer`, `search`), and ignores `Err` results: a clean error is
//! the right answer to a malformed file. What a target finds is a panic, an abort (out of
//! memory, stack overflow) or a run that does not end.
//!
//! Bytes that are not UTF-8 are dropped at once where the CLI reads text (`read_to_string`, or
//! avs-format's `read_text`, both refuse such a file before any parser sees it).
//!
//! ## Targets
//!
//! | function | input | what it covers |
//! | --- | --- | --- |
//! | [`environment`] | environment YAML, optionally `NUL` + map image | avs-format's loader ([`avs_format::check_env::load_environment`]), avs-sim's checks ([`avs_sim::check::check_environment`]), the diagnostics' positions ([`avs_format::positions::locate`]); when the checks pass, [`World::named`] must build the world (the checks are the one gate: a panic here means they let through a world that cannot be built) |
//! | [`knowledge`] | knowledge YAML | [`avs_format::knowledge::check`] (parse and meaning checks), positions |
//! | [`domain`] | planning domain YAML | [`avs_plan::check_domain`] ([`avs_plan::domain::Domain::from_yaml`]: parse and compile), positions |
//! | [`scenario`] | scenario YAML | [`avs_format::scenario::check`], positions |
//! | [`map`] | ROS map_server descriptor YAML + `NUL` + image (PGM/PNG) | [`OccupancyGrid::from_map_server_yaml`] (descriptor and image decoding within avs-map's limits), then `avs segment`'s [`segment_rooms`] on grids of at most [`MAX_SEGMENT_CELLS`] cells |
//! | [`pddl`] | PDDL domain + `NUL` + PDDL problem | avs-plan's PDDL reader ([`avs_plan::pddl::parse_domain`], [`avs_plan::pddl::parse_problem`]), grounding within [`pddl_limits`], and `avs plan`'s two searches (A* with LM-cut, greedy with h^FF) for at most [`PDDL_MAX_EXPANSIONS`] expansions each |
//! | [`pomdp`] | Cassandra `.pomdp` text | [`avs_pomdp::parse_pomdp`], then the default horizon ([`avs_pomdp::horizon_for`]) |
//! | [`uai`] | UAI `MARKOV`/`BAYES` model | [`avs_concepts::io::parse_uai`], then `avs infer`'s BP and exact marginals on small models ([`infer_small`]) |
//! | [`fg`] | libDAI `.fg` factor graph | [`avs_concepts::io::parse_fg`], then the same inference as [`uai`] |
//! | [`search`] | environment YAML, optionally `NUL` + map image | "validate then run one step": the checks of [`environment`] against the shipped office knowledge; a world that passes is built, a simulated robot put in it, and the agent searches it for a target with the budgets of [`search_budgets`] (one plan, one action) |
//!
//! Two-part inputs are split at the first [`SEPARATOR`] byte (NUL, which no text format here
//! uses). Where a reader only takes a path (the map_server descriptor, and an environment whose
//! map is an image relative to its file), the parts are written to a private temporary folder
//! of the calling thread: the descriptor as `map.yaml`, the image as `map.pgm` (the decoder
//! guesses the format from the content, so a PNG works under that name too). A descriptor or
//! environment in the corpus therefore names its image `map.pgm`. Without an image part, no
//! `map.pgm` exists, so no input sees a file an earlier one left.
//!
//! ## Dependencies
//!
//! - `avs-format`, `avs-sim`, `avs-map`, `avs-plan`, `avs-pomdp`, `avs-concepts`: the readers
//!   under test (and avs-sim's world and simulated robot for [`search`]).
//! - `avs-agent`: the agent whose search [`search`] starts.
//! - `avs-eval`: the shipped knowledge and domain ([`Shipped`]) that [`search`] uses.
//! - `tempfile` (already in the tree through proptest): the private folder for readers that
//!   only take a path, removed when the thread ends.
//!
//! The `afl` crate is a dependency of `fuzz/` only, not of this crate, so the workspace builds
//! and tests without the afl toolchain.

use avs_agent::{Agent, AgentConfig, Goal};
use avs_concepts::bp::{run_bp, BpOptions};
use avs_concepts::exact::exact_marginals;
use avs_concepts::factor::FactorGraph;
use avs_eval::inputs::Shipped;
use avs_format::environment::{Environment, ObjectRole};
use avs_format::knowledge::Knowledge;
use avs_map::grid::OccupancyGrid;
use avs_map::segment::{segment_rooms, SegmentParams};
use avs_plan::limits::GroundingLimits;
use avs_plan::{Mode, SearchOptions};
use avs_sim::sim_robot::{SimAgentRobot, SimRobotConfig};
use avs_sim::World;
use std::path::{Path, PathBuf};

/// The byte that splits a two-part input (NUL).
pub const SEPARATOR: u8 = 0;

/// The name the targets give their input in diagnostics.
const FILE: &str = "fuzz.yaml";

/// The image file name a two-part input's image is written to (see the crate docs).
pub const IMAGE_NAME: &str = "map.pgm";

/// Largest grid (cells) that [`map`] segments: segmentation is linear in the cells, and a
/// 64 × 64 grid keeps one input well under a millisecond while reaching every code path.
pub const MAX_SEGMENT_CELLS: usize = 64 * 64;

/// Expansions each of [`pddl`]'s two searches may make.
pub const PDDL_MAX_EXPANSIONS: u64 = 64;

/// Largest model (table entries over all factors, and variables) on which [`uai`] and [`fg`]
/// run inference.
pub const MAX_INFER_ENTRIES: usize = 4096;

/// The office knowledge shipped with avs: the class names [`search`]'s environments are
/// checked against and the agent's priors.
const OFFICE_KNOWLEDGE: &str = Shipped::Knowledge.text();

/// The object-search planning domain shipped with avs, the agent's domain in [`search`].
const OBJECT_SEARCH_DOMAIN: &str = Shipped::Domain.text();

/// What a target made of one input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// The reader took the input: an environment that passed the checks and built, a file
    /// without diagnostics, a map, model or task that was read (and for [`search`], a search
    /// that returned a report).
    Accepted,
    /// The reader refused the input with an error (or, for [`search`], the agent stopped with
    /// an error): a clean refusal, not a bug.
    Refused,
}

impl Verdict {
    fn of(accepted: bool) -> Self {
        if accepted {
            Verdict::Accepted
        } else {
            Verdict::Refused
        }
    }
}

/// The fuzz targets, for code that runs all of them (the corpus replay test).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// [`environment`].
    Environment,
    /// [`knowledge`].
    Knowledge,
    /// [`domain`].
    Domain,
    /// [`scenario`].
    Scenario,
    /// [`map`].
    Map,
    /// [`pddl`].
    Pddl,
    /// [`pomdp`].
    Pomdp,
    /// [`uai`].
    Uai,
    /// [`fg`].
    Fg,
    /// [`search`].
    Search,
}

impl Target {
    /// Every target, the fast readers first and the slow [`search`] last.
    pub const ALL: [Target; 10] = [
        Target::Environment,
        Target::Knowledge,
        Target::Domain,
        Target::Scenario,
        Target::Map,
        Target::Pddl,
        Target::Pomdp,
        Target::Uai,
        Target::Fg,
        Target::Search,
    ];

    /// The target's name: its function, its afl binary in `fuzz/`, and its corpus folder
    /// `fuzz/corpus/<name>/`.
    pub fn name(self) -> &'static str {
        match self {
            Target::Environment => "environment",
            Target::Knowledge => "knowledge",
            Target::Domain => "domain",
            Target::Scenario => "scenario",
            Target::Map => "map",
            Target::Pddl => "pddl",
            Target::Pomdp => "pomdp",
            Target::Uai => "uai",
            Target::Fg => "fg",
            Target::Search => "search",
        }
    }

    /// Run the target on one input and say whether the reader accepted it.
    pub fn run(self, data: &[u8]) -> Verdict {
        Verdict::of(match self {
            Target::Environment => run_environment(data),
            Target::Knowledge => run_knowledge(data),
            Target::Domain => run_domain(data),
            Target::Scenario => run_scenario(data),
            Target::Map => run_map(data),
            Target::Pddl => run_pddl(data),
            Target::Pomdp => run_pomdp(data),
            Target::Uai => run_uai(data),
            Target::Fg => run_fg(data),
            Target::Search => run_search(data),
        })
    }
}

/// `data` split at the first [`SEPARATOR`]: the part before it, and the part after it if there
/// is one.
pub fn split(data: &[u8]) -> (&[u8], Option<&[u8]>) {
    match data.iter().position(|&b| b == SEPARATOR) {
        Some(i) => (&data[..i], Some(&data[i + 1..])),
        None => (data, None),
    }
}

thread_local! {
    /// The calling thread's private folder (threads of one test process must not share files).
    static SCRATCH: tempfile::TempDir = tempfile::Builder::new()
        .prefix("avs-fuzz-")
        .tempdir()
        .expect("a temporary folder for the fuzz targets");
}

/// The sub-folder `name` of the calling thread's private folder, created if needed.
fn scratch(name: &str) -> PathBuf {
    let dir = SCRATCH.with(|d| d.path().join(name));
    std::fs::create_dir_all(&dir).expect("a sub-folder of the fuzz targets' temporary folder");
    dir
}

/// Write `image` as [`IMAGE_NAME`] in `dir`, or remove that file when there is no image.
fn put_image(dir: &Path, image: Option<&[u8]>) {
    let path = dir.join(IMAGE_NAME);
    match image {
        Some(bytes) => std::fs::write(&path, bytes).expect("writing the fuzz image"),
        None => {
            let _ = std::fs::remove_file(&path);
        }
    }
}

/// An environment read from `text` (its image in `base`), checked as `avs validate` checks it
/// (against `knowledge` when given); the environment when the checks pass.
fn checked_environment(
    text: &str,
    base: &Path,
    knowledge: Option<&Knowledge>,
) -> Option<Environment> {
    let env = avs_format::check_env::load_environment(FILE, text).ok()?;
    let mut problems = avs_sim::check::check_environment(FILE, &env, base, knowledge);
    avs_format::positions::locate(&mut problems, text);
    problems.is_empty().then_some(env)
}

/// Build the world of an environment that passed the checks. The checks are the gate every
/// command relies on ([`World::new`]'s docs): one that passes them must build, so a failure here
/// is a bug, reported as a panic.
fn build_world(env: Environment, base: &Path) -> World {
    match World::named(FILE, env, base) {
        Ok(w) => w,
        Err(e) => panic!("the environment passed the checks, yet its world does not build: {e}"),
    }
}

/// Environment YAML, optionally followed by [`SEPARATOR`] and the map image the environment
/// names as [`IMAGE_NAME`]: loaded, checked, and built into a [`World`] when the checks pass.
pub fn environment(data: &[u8]) {
    Target::Environment.run(data);
}

fn run_environment(data: &[u8]) -> bool {
    let (yaml, image) = split(data);
    let Ok(text) = std::str::from_utf8(yaml) else {
        return false;
    };
    let base = scratch("environment");
    put_image(&base, image);
    match checked_environment(text, &base, None) {
        Some(env) => {
            build_world(env, &base);
            true
        }
        None => false,
    }
}

/// Knowledge YAML, checked as `avs validate` checks it.
pub fn knowledge(data: &[u8]) {
    Target::Knowledge.run(data);
}

fn run_knowledge(data: &[u8]) -> bool {
    let Ok(text) = std::str::from_utf8(data) else {
        return false;
    };
    let mut problems = avs_format::knowledge::check(FILE, text);
    avs_format::positions::locate(&mut problems, text);
    problems.is_empty()
}

/// Planning-domain YAML (avs-plan's `Domain`), parsed, compiled and checked as `avs validate`
/// checks it.
pub fn domain(data: &[u8]) {
    Target::Domain.run(data);
}

fn run_domain(data: &[u8]) -> bool {
    let Ok(text) = std::str::from_utf8(data) else {
        return false;
    };
    let mut problems = avs_plan::check_domain(FILE, text);
    avs_format::positions::locate(&mut problems, text);
    problems.is_empty()
}

/// Scenario YAML, checked as `avs validate` checks it.
pub fn scenario(data: &[u8]) {
    Target::Scenario.run(data);
}

fn run_scenario(data: &[u8]) -> bool {
    let Ok(text) = std::str::from_utf8(data) else {
        return false;
    };
    let mut problems = avs_format::scenario::check(FILE, text);
    avs_format::positions::locate(&mut problems, text);
    problems.is_empty()
}

/// A ROS map_server descriptor (YAML), [`SEPARATOR`], and the image it names as
/// [`IMAGE_NAME`]: read as `avs segment` reads a map, and segmented into rooms when the grid
/// has at most [`MAX_SEGMENT_CELLS`] cells.
pub fn map(data: &[u8]) {
    Target::Map.run(data);
}

fn run_map(data: &[u8]) -> bool {
    let (descriptor, image) = split(data);
    let dir = scratch("map");
    let path = dir.join("map.yaml");
    std::fs::write(&path, descriptor).expect("writing the fuzz descriptor");
    put_image(&dir, image);
    let Ok(grid) = OccupancyGrid::from_map_server_yaml(&path) else {
        return false;
    };
    if grid.cells().len() <= MAX_SEGMENT_CELLS {
        let _ = segment_rooms(&grid, &SegmentParams::default());
    }
    true
}

/// The grounding limits of [`pddl`]: the CLI's defaults allow seconds of legitimate work (a
/// million operators), far too slow per input; these smaller ones reach the same limit checks.
pub fn pddl_limits() -> GroundingLimits {
    GroundingLimits {
        max_operators: 10_000,
        max_facts: 10_000,
        max_bytes: 16 << 20,
        max_bindings: 100_000,
    }
}

/// A PDDL domain, [`SEPARATOR`], and a PDDL problem: parsed, grounded (within
/// [`pddl_limits`]) and searched as `avs plan` does, in both modes, for at most
/// [`PDDL_MAX_EXPANSIONS`] expansions each.
pub fn pddl(data: &[u8]) {
    Target::Pddl.run(data);
}

fn run_pddl(data: &[u8]) -> bool {
    let (d, p) = split(data);
    let (Ok(dtext), Ok(ptext)) = (
        std::str::from_utf8(d),
        std::str::from_utf8(p.unwrap_or(&[])),
    ) else {
        return false;
    };
    let Ok(domain) = avs_plan::pddl::parse_domain("domain.pddl", dtext) else {
        return false;
    };
    let Ok(problem) = avs_plan::pddl::parse_problem("problem.pddl", ptext) else {
        return false;
    };
    let Ok(task) = avs_plan::pddl::ground_with("domain.pddl", &domain, &problem, &pddl_limits())
    else {
        return false;
    };
    for mode in [Mode::Optimal, Mode::Fast] {
        let opts = SearchOptions {
            mode,
            max_expansions: PDDL_MAX_EXPANSIONS,
            ..SearchOptions::default()
        };
        let _ = avs_plan::search(&task, &opts);
    }
    true
}

/// A Cassandra `.pomdp` file, parsed as `avs pomdp` reads it; for a model that parses, the
/// horizon `avs pomdp simulate` uses by default.
pub fn pomdp(data: &[u8]) {
    Target::Pomdp.run(data);
}

fn run_pomdp(data: &[u8]) -> bool {
    let Ok(text) = std::str::from_utf8(data) else {
        return false;
    };
    match avs_pomdp::parse_pomdp(text, "fuzz.pomdp") {
        Ok(model) => {
            let _ = avs_pomdp::horizon_for(&model, 1e-3);
            true
        }
        Err(_) => false,
    }
}

/// Inference as `avs infer` runs it (BP with the default schedule, and exact marginals), on a
/// model of at most [`MAX_INFER_ENTRIES`] table entries and variables; BP stops after 20
/// iterations.
pub fn infer_small(graph: &FactorGraph) {
    let entries: usize = graph.factors().iter().map(|f| f.values().len()).sum();
    if entries > MAX_INFER_ENTRIES || graph.num_vars() > MAX_INFER_ENTRIES {
        return;
    }
    let opts = BpOptions {
        maxiter: 20,
        ..BpOptions::default()
    };
    let _ = run_bp(graph, &opts, None);
    let _ = exact_marginals(graph, MAX_INFER_ENTRIES);
}

/// A UAI model (`MARKOV` or `BAYES`), read as `avs infer` reads it, then [`infer_small`].
pub fn uai(data: &[u8]) {
    Target::Uai.run(data);
}

fn run_uai(data: &[u8]) -> bool {
    let Ok(text) = std::str::from_utf8(data) else {
        return false;
    };
    match avs_concepts::io::parse_uai(text, "fuzz.uai") {
        Ok(graph) => {
            infer_small(&graph);
            true
        }
        Err(_) => false,
    }
}

/// A libDAI `.fg` factor graph, read as `avs infer` reads it, then [`infer_small`].
pub fn fg(data: &[u8]) {
    Target::Fg.run(data);
}

fn run_fg(data: &[u8]) -> bool {
    let Ok(text) = std::str::from_utf8(data) else {
        return false;
    };
    match avs_concepts::io::parse_fg(text, "fuzz.fg") {
        Ok(lg) => {
            infer_small(&lg.graph);
            true
        }
        Err(_) => false,
    }
}

/// The agent's budgets in [`search`]: one plan and one action (each of the plan's and the
/// coverage's), so that one input runs in well under a second.
pub fn search_budgets() -> AgentConfig {
    AgentConfig {
        max_plans: 1,
        max_actions: 1,
        max_cover_actions: 1,
        ..AgentConfig::default()
    }
}

/// "Validate then run one step": environment YAML (optionally [`SEPARATOR`] and its image, as
/// in [`environment`]) checked against the shipped office knowledge; a world that passes is
/// built, a simulated robot (seed 0) is put in it, and the agent searches for the class of the
/// environment's first target object (`cerealbox` when it has none) with [`search_budgets`].
/// A search that ends, with a report or an error, is fine; a panic or a search that does not
/// end is a bug.
pub fn search(data: &[u8]) {
    Target::Search.run(data);
}

fn run_search(data: &[u8]) -> bool {
    let (yaml, image) = split(data);
    let Ok(text) = std::str::from_utf8(yaml) else {
        return false;
    };
    let knowledge: Knowledge = avs_format::load_yaml_str("office.yaml", OFFICE_KNOWLEDGE)
        .expect("the shipped office knowledge loads");
    let base = scratch("search");
    put_image(&base, image);
    let Some(env) = checked_environment(text, &base, Some(&knowledge)) else {
        return false;
    };
    let goal = env
        .objects
        .iter()
        .find(|o| o.role == ObjectRole::Target)
        .map_or_else(|| "cerealbox".to_string(), |o| o.class.clone());
    let world = build_world(env, &base);
    let domain = avs_plan::domain::Domain::from_yaml("object_search.yaml", OBJECT_SEARCH_DOMAIN)
        .expect("the shipped object-search domain loads");
    // As in crates/avs-eval/tests/validate_then_run.rs: a world that validates takes a robot.
    let mut robot =
        match SimAgentRobot::new(&world, knowledge.clone(), SimRobotConfig::default(), 0) {
            Ok(r) => r,
            Err(e) => panic!("the environment passed the checks, yet the robot: {e}"),
        };
    let mut agent = Agent::new(domain, knowledge, search_budgets())
        .expect("the agent takes the shipped domain and knowledge");
    agent.search(&mut robot, Goal::find(&goal)).is_ok()
}
