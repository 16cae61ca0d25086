//! # avs-map
//!
//! What the robot knows of space: an occupancy grid (ROS map_server maps and ASCII grids), what a
//! laser reveals, the place map (places, paths, placeholders on the frontier), door hypotheses
//! and room segmentation by doors (Sjöö et al., `004_eb11ea0b2ea7be93.txt` §2), and the
//! exploration utility of a viewpoint (Masuzawa & Miura, `001_fbcdba3c18be7464.txt` eq. 6).
//!
//! ```
//! use avs_map::grid::{Cell, OccupancyGrid};
//! let g = OccupancyGrid::from_ascii("###\n#.#\n###\n", 0.5, [0.0, 0.0]).unwrap();
//! assert_eq!(g.get(1, 1), Cell::Free);
//! ```
#![warn(missing_docs)]

pub mod doors;
pub mod explore;
pub mod grid;
pub mod metrics;
pub mod nav;
pub mod places;
pub mod raycast;
pub mod segment;
