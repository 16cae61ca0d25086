//! # avs-sim
//!
//! The simulated world of avs: ground truth (map, rooms, doors, objects, distractors), robot
//! motion along collision-free shortest paths, a laser that reveals the map, closed doors that
//! block, ground-truth queries for camera sensor models, and a procedural floor generator.
//! Everything stochastic takes an explicit seed.
#![warn(missing_docs)]

pub mod check;
pub mod world;

pub use world::{load_grid, SimError};
