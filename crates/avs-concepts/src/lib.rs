//! # avs-concepts
//!
//! The conceptual map of avs — its probabilistic memory (Aydemir, Göbelbecker, Pronobis, Sjöö,
//! Jensfelt, *Plan-based object search and exploration using semantic spatial knowledge in the
//! real world*, ECMR 2011, §II-B.4 and §III). It joins common sense from a knowledge file
//! (`knowledge/*.yaml`, see [`avs_format::knowledge`]) with what the robot has seen, and answers
//! the planner's three questions: P_category(room), P_category(placeholder) and
//! P(ObjectAt L).
//!
//! ## Parts
//! * [`factor`]: discrete factors and factor graphs (libDAI's first-variable-fastest tables).
//! * [`bp`]: sum-product loopy BP with libDAI's options, schedules and stopping rule (`updates`
//!   SEQFIX | SEQMAX | PARALL, `damping`, `tol`, `maxiter`, `logdomain`), reporting
//!   iterations, convergence and the last belief change; warm start from given messages; a
//!   zero of BP's told apart from contradictory evidence.
//! * [`exact`]: exact marginals by variable elimination (min-fill order) organised as a
//!   junction tree, with a memory limit.
//! * [`io`]: UAI (`MARKOV`/`BAYES`, evidence, `.MAR`) and libDAI `.fg` readers.
//! * [`map`]: the event-driven [`ConceptualMap`]; [`pairwise`]: its BP engine;
//!   [`placeholder`]: the six structure hypotheses; [`model`]: the knowledge as dense tables.
//!
//! ## The chain graph and our choices where the paper is vague
//! * **Variables.** One category variable per room. Place-property variables (size, shape,
//!   appearance) and object-count variables each hang off exactly one room variable and are
//!   observed, so summing them out is exact: their evidence is multiplied into the room's
//!   node potential — prior P(k) × Π_places Σ_v P(v | k) · L(v) × Π Poisson(n; …) × search
//!   likelihoods. Soft (classifier) evidence L(v) is supported.
//! * **Doors.** Each door multiplies in φ_rc(k_a, k_b) (a symmetric table from the knowledge).
//! * **Object counts.** Objects follow independent Poisson processes over cells (§III-A,
//!   assumptions 1–3). From a place the robot counts n *new* instances of class c, having looked
//!   at a share s of the room; under category k the count is Poisson with rate
//!   s · (p_d · λ_{k,c} · U + λ_fp) — the thinned process plus spurious counts (p_d and λ_fp from
//!   `object_count_observation`) — where U = Π_j (1 − s_j p_d) over the room's earlier counts of
//!   c. Our choice where the paper is vague (it counts from one look): a room's instances are
//!   one Poisson population, and a later look can only add those every earlier look missed.
//!   Each look finding each instance independently with s_j p_d, the instances *first* found
//!   by look i are Poisson with rate s_i p_d λ U_i, independent across looks (Poisson
//!   splitting), so the product of the looks' terms is the exact likelihood of the distinct
//!   instances found; which look re-found which instance does not depend on the category. (Each
//!   look counted as a fresh Poisson draw, a second look around a kitchen from where its
//!   counter is out of sight was as strong evidence against the kitchen as the first look was
//!   for it: P(kitchen) 0.87 → 0.57 on the default office; counting the known instances seen
//!   again as new would count the same counter twice.) The caller counts each instance once, in
//!   the look that first saw it. The instances no look found are what a later search can find:
//!   a room's rate of class c is thinned by U as by a failed search (a look around that saw
//!   no shelf leaves 1 − 0.64 of the rate, not all of it, for a search to hunt).
//! * **P(ObjectAt L)** (eq. 1–2): Σ_k P(k | room) (1 − exp(−λ_{L,c,k})). A room's rate is its own
//!   rate plus the rates of every subordinate location (rates add over the hierarchy, §III-A):
//!   every known landmark location in it, λ(object, relation, landmark class, k), and, with
//!   [`ConceptualMap::set_unfound_landmarks`] (off by default; the agent's
//!   `AgentConfig::unfound_landmarks`), the landmarks not found yet. Those are a Poisson
//!   population too (the landmark class's room
//!   rate μ_k, thinned by the looks that counted the class and by failed searches for it, as
//!   for any object), each holding a Poisson(ν_k) number of the object; the object's count
//!   over them is compound Poisson with P(none) = exp(−μ_k (1 − e^{−ν_k})), so they add
//!   μ_k (1 − e^{−ν_k}) (the paper's μ_k ν_k for small ν). A failed search of the room for the
//!   object thins them as it thins the room's own rate. A room behind a placeholder, with no
//!   landmark known, gets the whole expectation ([`Model::unseen_room_rates`]). Our choice: the
//!   category evidence of a failed search (below) keeps to the room's own rate and the known
//!   landmarks.
//! * **Failed search** of L for c with detection probability q: the Poisson process is thinned,
//!   λ ← (1 − q) λ, and the failure is evidence exp(−q λ_k) for the room's category. Searching a
//!   room searches its landmark locations too. Merging rooms averages their unsearched shares
//!   (rooms of unknown relative size); splitting copies them.
//! * **Placeholders** (§III-A.1): see [`placeholder`] for the six hypotheses' likelihoods
//!   (exponential in the open area and the door distance — the paper names the cues but not the
//!   formula) and for how hypothesised rooms join the graph as a leaf chain without feeding back
//!   into explored rooms. P_category(placeholder) is, per category, the probability that some
//!   hypothesised room has it, summed over hypotheses — not a distribution over categories.
//! * **Inference.** The map uses [`pairwise`], BP on the pairwise MRF, with a residual-gated
//!   sequential schedule: after an event only rooms whose incoming messages changed by more than
//!   `tol` recompute. Its default message tolerance is 1e-7 (beliefs within ~1e-6 of the fixed
//!   point on the 100-room benchmark — far below what the planner distinguishes); it agrees
//!   with the generic factor-graph engine and, on trees, with exact inference (tests). When BP
//!   does not converge and the junction tree is small (≤ [`map::EXACT_FALLBACK_ENTRIES`]
//!   entries), the map answers from exact inference instead.
//! * Loopy BP is approximate: on strongly coupled loopy models (the UAI `Grids` and `DBN`
//!   instances) it may not converge or converge far from the exact marginals — an independent
//!   naive implementation reproduces the same numbers (see `docs/benchmarks/concepts.md`).
//!
//! ## Example
//! ```
//! use avs_concepts::{ConceptualMap, Location, PlaceId, Placeholder, PlaceholderId, Relation, RoomId};
//! let k: avs_format::knowledge::Knowledge = avs_format::load_yaml_str("k.yaml", r#"
//! kind: knowledge
//! name: tiny
//! room_categories: [corridor, kitchen]
//! connectivity: [[1.0, 1.0], [1.0, 0.2]]
//! object_classes:
//!   - { name: table, size: [1.2, 0.8, 0.75], detection_range: [0.5, 6], recognition_range: [0.8, 5], landmark: true }
//!   - { name: cerealbox, size: [0.19, 0.07, 0.28], detection_range: [0.5, 4], recognition_range: [0.5, 2] }
//! object_rates: { table: [0.05, 1.0] }
//! landmark_rates:
//!   - { object: cerealbox, relation: on, landmark: table, rates: [0.01, 0.4] }
//! "#).unwrap();
//! let mut map = ConceptualMap::new("k.yaml", &k).unwrap();
//! let (corridor, room) = (RoomId(0), RoomId(1));
//! map.add_room(corridor).unwrap();
//! map.add_room(room).unwrap();
//! map.add_adjacency(corridor, room).unwrap();
//! map.observe_objects(room, PlaceId(3), "table", 1, 1.0).unwrap();
//! assert!(map.p_category(room, "kitchen").unwrap() > 0.5);
//! let table = map.add_landmark(room, "table").unwrap();
//! let p = map.p_object_at(Location::Landmark(table, Relation::On), "cerealbox").unwrap();
//! map.mark_searched(Location::Landmark(table, Relation::On), "cerealbox", 0.8).unwrap();
//! assert!(map.p_object_at(Location::Landmark(table, Relation::On), "cerealbox").unwrap() < p);
//! map.set_placeholder(PlaceholderId(0), Placeholder {
//!     room: corridor, open_area_m2: 8.0, door_distance_m: Some(0.4) }).unwrap();
//! assert!(map.p_new_room(PlaceholderId(0)).unwrap() > 0.5);
//! ```
pub mod bp;
pub mod exact;
pub mod factor;
pub mod ids;
pub mod io;
pub mod map;
pub mod model;
pub mod pairwise;
pub mod placeholder;

pub use avs_format::knowledge::Relation;
pub use bp::{run_bp, BpOptions, BpResult, Updates};
pub use exact::exact_marginals;
pub use factor::{Factor, FactorGraph};
pub use ids::{LandmarkId, Location, PlaceId, Placeholder, PlaceholderId, RoomId};
pub use map::{ConceptualMap, InferenceStats};
pub use model::Model;
pub use pairwise::MapBpOptions;

/// Errors of the conceptual map.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConceptError {
    /// The knowledge file failed its checks (one diagnostic per line).
    #[error("invalid knowledge:\n{0}")]
    Knowledge(String),
    /// A name not declared in the knowledge.
    #[error("unknown {what} `{name}`; expected one of: {known}")]
    Unknown {
        /// What kind of name.
        what: &'static str,
        /// The name given.
        name: String,
        /// The names known.
        known: String,
    },
    /// A room id not in the map.
    #[error("unknown room {0}")]
    UnknownRoom(u64),
    /// A placeholder id not in the map.
    #[error("unknown placeholder {0}")]
    UnknownPlaceholder(u64),
    /// A landmark id not in the map.
    #[error("unknown landmark {0}")]
    UnknownLandmark(u64),
    /// An id added twice.
    #[error("{0} {1} already exists")]
    Duplicate(&'static str, u64),
    /// A class used as a landmark that is not one.
    #[error("class `{0}` is not a landmark; set `landmark: true` in the knowledge")]
    NotALandmark(String),
    /// A number out of range.
    #[error("{what}: got {value}, expected {expected}")]
    BadNumber {
        /// What the number is.
        what: &'static str,
        /// The value given.
        value: f64,
        /// The range expected.
        expected: &'static str,
    },
    /// Inference failed.
    #[error(transparent)]
    Graph(#[from] GraphError),
}

/// Errors of factor graphs and inference.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GraphError {
    /// A factor or graph is malformed.
    #[error("invalid factor graph: {0}")]
    Invalid(String),
    /// A model file could not be read.
    #[error("{what}: {message}")]
    Parse {
        /// The file or source.
        what: String,
        /// What is wrong and what was expected.
        message: String,
    },
    /// Evidence and factors leave no configuration with positive probability.
    #[error("inconsistent model: {0}")]
    Inconsistent(String),
    /// Loopy BP's message or belief became zero for every value although arc consistency
    /// leaves every variable a value of positive probability: a zero of BP's floating-point
    /// arithmetic (underflow or overflow), not evidence that the model is contradictory (in
    /// exact arithmetic BP keeps every arc-consistent value positive; see [`crate::bp`]).
    #[error(
        "loopy BP: {what} became zero for every value at iteration {iteration}; this is BP's \
         floating-point range, not contradictory evidence (arc consistency leaves every \
         variable a value of positive probability){hint}"
    )]
    BpNumericalZero {
        /// The message or belief, named by factor and variable indices.
        what: String,
        /// The iteration (1-based) in which it happened.
        iteration: usize,
        /// What to try instead (empty when there is nothing to add).
        hint: &'static str,
    },
    /// Exact inference would need too much memory.
    #[error("exact inference needs {needed:.3e} table entries, more than the limit {limit}")]
    TooLarge {
        /// Entries the junction tree would need.
        needed: f64,
        /// The limit given.
        limit: usize,
    },
}
