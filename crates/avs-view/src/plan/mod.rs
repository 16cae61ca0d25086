//! View planning for several objects at once (Sjöö et al. `004` §2.1): which images to take in a
//! room so that every object sought would be seen in at least `k` of them wherever it is.
//!
//! The room is a grid of cells (the paper's 0.5 m occupancy cells, §2.1.1); the robot may stand
//! at a set of *standpoints* (the paper's navigation nodes; a place map's places or a lattice);
//! each object class sought has distance limits derived from its size, the image and the zoom
//! (§2.1.3, [`SoughtClass::from_model`]). A *view* is one image: standpoint, camera direction,
//! tilt and the classes to look for in it (§2.1.2). The plan covers every coverable
//! (class, cell) *pair* `k` times (§2.1.4).
//!
//! * [`limits`] — §2.1.3's distance limits from eq. 1 and the vote cell size;
//! * [`candidates`] — the candidate views of every standpoint and direction, with §2.1.5's
//!   tilt rule for near cells;
//! * [`greedy`] — the greedy set (multi-)cover of §2.1.4;
//! * [`optimal`] — the exact minimum number of images (a 0/1 program), to measure the
//!   greedy's gap;
//! * [`execute`] — §2.1.4's execution order (nearest standpoint first) and the removal of a
//!   unique object's pairs once it is found;
//! * [`search`] — a room searched for several objects at once: the plan executed, each view
//!   through the three-step zoom search (§3), found classes dropped (§4.4's experiment).
//!
//! ## Choices where the paper is vague
//! * **Zoom.** A view is (standpoint, direction, tilt, zoom, classes), as the issue has it:
//!   at zoom `z` the fields of view are divided by `z` and every class's distance limits
//!   multiplied by `z` (the same image detail at `z` times the distance). This is what makes
//!   §4.3's cup and robot "not looked for in the same views": the cup needs zoom to be seen
//!   across a room, at which the robot no longer fits the image.
//! * **Visibility.** A cell is in a view when its centre's bearing lies within half the
//!   horizontal field of view of the camera's direction (§2.1.2), its horizontal distance from
//!   the standpoint within the class's limits (§2.1.3), and the caller's line-of-sight
//!   predicate holds (the paper ignores occlusion; pass `|_, _| true` for that).
//! * **Heights.** An object's centre may be anywhere in its class's height band; a pair is
//!   covered by a set of images of one direction when the band above the cell, seen from the
//!   camera, lies within the union of their vertical fields of view.
//! * **Tilt (§2.1.5).** The paper adds extra tilted views for cells nearer than 2 m, using their
//!   average distance. Ours: the near distance is derived, not set — the distance below which
//!   some class's band no longer fits one image's vertical field of view — and the tilts of a
//!   direction are the fewest evenly spaced ones (as little overlap as possible) whose union
//!   spans the bands of the cells they are for, clamped to the camera's tilt limits. A
//!   direction thus has up to two candidate *units*: one for its far cells (usually one image)
//!   and one for its near cells (the tilt rule's images); a unit is chosen whole.
//! * **Greedy criterion.** The paper chooses the view covering most pairs. A near unit takes
//!   several images, so ours chooses the most new pairs *per image* (Chvátal's weighted
//!   greedy); when every unit is one image the two are the same. The greedy alone ends 20–50 %
//!   above the optimum on §4.3's rooms (it takes the widest view first and leaves ragged
//!   remainders), so [`greedy`] also builds the plan that serves the pair the fewest units see
//!   first, follows each with the standard clean-up (drop units later ones made redundant) and a
//!   deterministic local search (remove two to four chosen units, re-cover what they leave
//!   short with fewer images by an exact bounded search or greedily), and keeps the smaller;
//!   [`optimal`] measures the gap left (Table 1: none; random rooms: `tests/plan_gap.rs`).
//! * **Execution (§2.1.4).** "Closest" is the straight-line distance from where the robot
//!   stands, unless the caller gives its own distance (a path length).

pub mod candidates;
pub mod execute;
pub mod greedy;
pub mod limits;
pub mod optimal;
pub mod search;

pub use candidates::{candidate_units, near_distance, tilt_rule, Unit};
pub use execute::{drop_class, nearest_first};
pub use greedy::plan_views;
pub use limits::SoughtClass;
pub use optimal::{optimal_views, OptimalPlan};
pub use search::{search_room, RoomSearch};

use avs_robot::Camera;
use serde::Serialize;

/// A (class, cell) pair: object class `class` (index into the problem's classes) in cell `cell`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub struct Pair {
    /// Index of the class in [`ViewProblem::classes`].
    pub class: usize,
    /// Index of the cell in [`ViewProblem::cells`].
    pub cell: usize,
}

/// Options of the view planner.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PlanOptions {
    /// How many chosen views must cover each coverable pair (§2.1.4's "desired number of views",
    /// ≥ 1; a pair fewer units can see is covered as often as it can be).
    pub k: usize,
    /// Spacing of the candidate camera directions around each standpoint, radians (`None`: the
    /// canonical directions, one per bearing of a seen cell, which lose no plan; see
    /// [`candidates`]).
    pub direction_step: Option<f64>,
    /// The largest zoom views may use (`None`: the camera's). Views are planned at the zoom
    /// levels 1, 2, 4, … up to it ([`crate::view_zooms`]).
    pub max_zoom: Option<f64>,
}

impl Default for PlanOptions {
    fn default() -> Self {
        Self {
            k: 1,
            direction_step: None,
            max_zoom: None,
        }
    }
}

/// A view-planning problem: one room's cells, the standpoints, the classes sought, the camera.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ViewProblem {
    /// Centres of the room's grid cells `[x, y]`, metres.
    pub cells: Vec<[f64; 2]>,
    /// Where the robot may stand `[x, y]`, metres.
    pub standpoints: Vec<[f64; 2]>,
    /// The object classes sought.
    pub classes: Vec<SoughtClass>,
    /// The robot's camera (fields of view at zoom 1, tilt limits, height).
    pub camera: Camera,
    /// Planner options.
    pub options: PlanOptions,
}

/// One planned image (§2.1.2's view): where the robot stands, where the camera looks, what to
/// look for.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct View {
    /// Index of the standpoint.
    pub standpoint: usize,
    /// The standpoint `[x, y]`.
    pub at: [f64; 2],
    /// Direction of the camera in the world, radians (the robot's heading plus the pan).
    pub yaw: f64,
    /// Tilt, radians (negative looks down).
    pub tilt: f64,
    /// Zoom (fields of view divided by it, distance limits multiplied by it).
    pub zoom: f64,
    /// Indices of the classes to look for in this image.
    pub classes: Vec<usize>,
    /// The pairs this image's unit covers (all of them; a near unit's images share them).
    pub pairs: Vec<Pair>,
    /// Index of the candidate unit the image belongs to.
    pub unit: usize,
}

/// A view plan.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ViewPlan {
    /// The images, in the order chosen (see [`nearest_first`] for the order to take them in).
    pub views: Vec<View>,
    /// Pairs no candidate can see (impossible to cover from the given standpoints).
    pub uncoverable: Vec<Pair>,
    /// Per class, the share of its coverable pairs covered `k` times (or as often as they can be).
    pub coverage: Vec<f64>,
}

impl ViewPlan {
    /// The number of images (the paper's *searches*).
    pub fn searches(&self) -> usize {
        self.views.len()
    }

    /// The standpoints the plan uses, ascending.
    pub fn standpoints_used(&self) -> Vec<usize> {
        let mut s: Vec<usize> = self.views.iter().map(|v| v.standpoint).collect();
        s.sort_unstable();
        s.dedup();
        s
    }
}
