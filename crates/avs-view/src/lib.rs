//! # avs-view
//!
//! View geometry for active visual search, in one place: where to look from and at what.
//!
//! * [`cover`] — CREATEVIEWCONES (Sjöö et al. `004` §2.1): candidate views (pose × pan × tilt,
//!   and zoom levels) and the greedy set cover over a location's points;
//! * [`plan`] — view planning for several classes at once (`004` §2.1: distance limits from
//!   eq. 1, greedy k-coverage of (class, cell) pairs, the tilt rule, the exact optimum,
//!   nearest-first execution);
//! * [`surface`] — the surfaces small objects rest on and the points on a top the laser
//!   never saw;
//! * [`sight`] — 2½-D sight lines over known furniture;
//! * [`heights`] — the heights an object is looked for at;
//! * [`zoom`] — the zoom pipeline of `004` §3 (hypotheses, distance estimates, zoom windows,
//!   the three-step search) and the zoom levels view planning uses.
//!
//! The view-cone POMDP that orders the cones' processing is `avs-pomdp`'s; the agent that asks
//! for the cones and runs them is `avs-agent`'s.
//!
//! ## Choices where the papers are vague
//! * **CREATEVIEWCONES.** Candidate pans/tilts are spaced by half the field of view; visibility is the
//!   cell-centre test of §2.1.2 plus the object's min/max distance (§2.1.3) and a caller-supplied
//!   line-of-sight predicate; views are chosen by greedy set cover (§2.1.4). The points are whatever
//!   the caller samples: a room's cells, or the top / inside of a landmark object; §2.1.5's extra tilt
//!   views for near cells are subsumed by trying every tilt step for every pose and pan.
//! * **Surfaces and sight lines.** The papers' maps are planar: a table's footprint blocks the
//!   line to its own top. A point resting on a known surface counts as seen when the line is
//!   clear up to the disc the footprint may occupy (centre and half the class's diagonal, the
//!   yaw being unknown); a point on the floor behind it stays hidden.
//! * **Search heights.** A small object is looked for at the tops of the surfaces the
//!   knowledge puts it on, the lowest and the highest, merged into their middle when closer
//!   than a step (one view sees both); a coverage that no longer trusts the knowledge adds the
//!   floor and every surface class.
//!
//! ## Example
//! ```
//! use avs_view::{create_view_cones, CameraModel, DetectionRange};
//! // A 4 m × 3 m room at table height, seen from its middle.
//! let mut points = Vec::new();
//! for i in 0..8 {
//!     for j in 0..6 {
//!         points.push([0.25 + 0.5 * i as f64, 0.25 + 0.5 * j as f64, 0.75]);
//!     }
//! }
//! let camera = CameraModel {
//!     hfov: 60f64.to_radians(),
//!     vfov: 45f64.to_radians(),
//!     pan_limits: [-std::f64::consts::PI, std::f64::consts::PI],
//!     tilt_limits: [-0.6, 0.2],
//!     height: 1.2,
//! };
//! let range = DetectionRange { min: 0.3, max: 4.0 };
//! let plan = create_view_cones(&points, &[[2.0, 1.5, 0.0]], &camera, range, |_, _| true).unwrap();
//! assert!(plan.covered_share > 0.9);
//! // Each covered point is covered first by exactly one view, in greedy order.
//! let first: usize = plan.views.iter().map(|v| v.newly_covered.len()).sum();
//! assert!((first as f64 / points.len() as f64 - plan.covered_share).abs() < 1e-12);
//! ```

pub mod cover;
pub mod error;
pub mod heights;
pub mod plan;
pub mod sight;
pub mod surface;
pub mod zoom;

pub use cover::{
    create_view_cones, create_view_cones_at_levels, create_view_cones_costed,
    create_view_cones_zoomed, CameraModel, CoverOptions, DetectionRange, PlannedView, ViewConePlan,
};
pub use error::{Result, ViewError};
pub use heights::search_heights;
pub use sight::{sight_clear, SightLine};
pub use surface::{lattice_step, surface_classes, unseen_tops, Surface};
pub use zoom::{view_zooms, ObjectModel};
