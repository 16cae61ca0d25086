//! # avs
//!
//! Active visual object search — a mobile robot asked to "find the cereal box" in a building
//! it only partly knows. This is the one crate to depend on: it re-exports the libraries, and
//! its [`prelude`] holds what a search needs.
//!
//! | module | crate | what |
//! |---|---|---|
//! | [`agent`] | avs-agent | the search agent ([`Agent`]): the switching planner's executive |
//! | [`robot`] | avs-robot | the [`Robot`] trait a real or simulated robot implements |
//! | [`sim`] | avs-sim | the simulated world ([`World`]) and robot ([`SimAgentRobot`]) |
//! | [`format`] | avs-format | the YAML files: environment, knowledge, scenario; their checks |
//! | [`eval`] | avs-eval | episodes scored against the truth, the bench, the shipped inputs ([`Shipped`]) |
//! | [`plan`] | avs-plan | the planning domain and the continual SAS+ planner |
//! | [`concepts`] | avs-concepts | the conceptual map: room categories by loopy BP |
//! | [`pomdp`] | avs-pomdp | the view-cone POMDP and its solvers |
//! | [`map`] | avs-map | grids, place maps, room segmentation |
//! | [`view`] | avs-view | view planning (CREATEVIEWCONES) |
//!
//! A search of the shipped office for the cereal box, with the simulated robot:
//!
//! ```
//! use avs::prelude::*;
//!
//! let world = Shipped::Environment.input().world().unwrap();
//! let knowledge = Shipped::Knowledge.input().knowledge().unwrap();
//! let domain = Shipped::Domain.input().domain().unwrap();
//! let mut robot =
//!     SimAgentRobot::new(&world, knowledge.clone(), SimRobotConfig::default(), 1).unwrap();
//! let mut agent = Agent::new(domain, knowledge, AgentConfig::default()).unwrap();
//! let report = agent.search(&mut robot, Goal::find("cerealbox")).unwrap();
//! assert!(report.found.is_some(), "{}", report.reason);
//! ```
//!
//! **Build settings for dependents.** avs's searches are numeric and allocation-heavy: in a
//! debug build without optimisation they run tens of times slower. avs's own workspace builds
//! its dependencies at `opt-level = 3` and its crates at 1 in the dev profile; a crate that
//! depends on avs should do the same:
//!
//! ```toml
//! [profile.dev.package."*"]
//! opt-level = 3
//! ```

pub use avs_agent as agent;
pub use avs_concepts as concepts;
pub use avs_eval as eval;
pub use avs_format as format;
pub use avs_map as map;
pub use avs_plan as plan;
pub use avs_pomdp as pomdp;
pub use avs_robot as robot;
pub use avs_sim as sim;
pub use avs_view as view;

pub use avs_agent::{Agent, AgentConfig, Goal, SearchReport};
pub use avs_eval::inputs::{Input, Shipped};
pub use avs_robot::Robot;
pub use avs_sim::sim_robot::{SimAgentRobot, SimRobotConfig};
pub use avs_sim::World;

/// What a search needs: the agent and its settings, the goal and its report, the robot trait,
/// the simulated world and robot, and the shipped inputs.
pub mod prelude {
    pub use crate::{
        Agent, AgentConfig, Goal, Input, Robot, SearchReport, Shipped, SimAgentRobot,
        SimRobotConfig, World,
    };
}
