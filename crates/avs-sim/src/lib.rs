//! # avs-sim
//!
//! The simulated world of avs: ground truth (map, rooms, doors, objects, distractors), robot
//! motion along collision-free shortest paths, a laser that reveals the map, closed doors that
//! block, ground-truth queries for camera sensor models, and a procedural floor generator.
//! Everything stochastic takes an explicit seed.
//!
//! ```
//! use avs_sim::{World, SimRobot};
//! // One line per string: rustdoc reads a doc line that starts with `##` as `#`, which made
//! // the wall rows one cell short (a ragged map, which `avs validate` rejects).
//! let text = [
//!     "kind: environment",
//!     "name: tiny",
//!     "map:",
//!     "  resolution: 0.5",
//!     "  ascii: |",
//!     "    ##########",
//!     "    #........#",
//!     "    #........#",
//!     "    ##########",
//!     "rooms: [ { name: hall, category: corridor, seed: { x: 1.0, y: 1.0 } } ]",
//!     "robot: { start: { x: 0.75, y: 0.75 }, radius: 0.2 }",
//! ]
//! .join("\n");
//! let env: avs_format::environment::Environment =
//!     avs_format::load_yaml_str("tiny.yaml", &text).unwrap();
//! let world = World::new(env, std::path::Path::new(".")).unwrap();
//! let mut robot = SimRobot::new(&world, 7);
//! let m = robot.move_to([4.25, 1.25]);
//! assert!(m.reached && robot.path_length > 3.0);
//! ```
pub mod check;
pub mod detector;
pub mod explore;
pub mod generate;
pub mod image;
pub mod place_classifier;
pub mod render;
pub mod robot;
pub mod score;
pub mod sensors;
pub mod sim_robot;
pub mod world;
pub mod world_scores;

pub use explore::Explorer;
pub use image::{ImageModel, ImageScene};
pub use robot::{Motion, SimRobot};
pub use world::{load_grid, load_map, CameraView, SimError, ViewedObject, World};
