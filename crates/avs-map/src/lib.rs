//! # avs-map
//!
//! What the robot knows of space.
//!
//! * [`grid`]: occupancy grids from ROS map_server maps (through the `image` crate) and ASCII;
//!   [`image_io`]: the one image reader, with a pixel limit checked before decoding and a
//!   decoder memory limit (map images and ground-truth images alike);
//! * [`raycast`]: walking grid cells along a segment, line of sight, what a laser scan reveals;
//! * [`nav`]: traversability for a robot radius, A* shortest paths, Dijkstra distance fields;
//! * [`doors`]: door hypotheses — critical points of the free space's Voronoi diagram whose
//!   opening lies in the door width range (Sjöö et al., `004_eb11ea0b2ea7be93.txt` §2; method
//!   and choices in the module docs), and the exact clearance transform;
//! * [`segment`]: room segmentation of a complete map by cutting doors; [`metrics`]: scoring
//!   against ground truth (per-room and per-pixel precision / recall, MCC);
//! * [`places`]: the place map — places, paths, confirmed doors, placeholders with their open
//!   area and door distance, rooms as the components left when door places are cut
//!   (Aydemir et al., `002_ff7a0884d9f6f2df.txt` §II-B); [`pockets`]: the unknown insides of
//!   furniture the laser saw only the rim of, each inside one room;
//! * [`explore`]: the exploration utility of a viewpoint, newly seen area / travel cost
//!   (Masuzawa & Miura, `001_fbcdba3c18be7464.txt` eq. 6).
//!
//! ```
//! use avs_map::grid::{Cell, OccupancyGrid};
//! let g = OccupancyGrid::from_ascii("###\n#.#\n###\n", 0.5, [0.0, 0.0]).unwrap();
//! assert_eq!(g.get(1, 1), Cell::Free);
//! ```
pub mod doors;
pub mod explore;
pub mod geometry;
pub mod grid;
pub mod image_io;
pub mod memo;
pub mod metrics;
pub mod nav;
pub mod places;
pub mod pockets;
pub mod raycast;
pub mod segment;
