//! The zoom pipeline of PROCESSVIEWCONE (Sjöö et al. `004` §3): from a wide image's vote
//! matrices to hypotheses, distance estimates, zoom windows shared between classes, and the
//! three-step search that ends in recognition — plus the zoom levels view planning uses.
//!
//! * [`levels`] — the zoom levels a view plan may use;
//! * [`model`] — what the pipeline knows of a class: its front face, its training image, and
//!   the geometry of eq. 1 and §3.3 (distance from a vote area or a scale ratio, zoom to fill
//!   the image);
//! * [`hypotheses`](mod@hypotheses) — the local maxima of a vote matrix above the class's
//!   threshold and the bounding box of their associated cells (§3.2, §3.3.1);
//! * [`distance`] — the distance from the strongest hypothesis's vote area (§3.3.1) and the
//!   median distance of matched features (§3.3.2);
//! * [`windows`] — hypothesis grouping into zoom windows and their reduction (§3.4.1);
//! * [`sharing`] — zoom window sharing between classes within the middle-step magnification
//!   range (§3.4.2);
//! * [`search`] — the three-step search (initial, middle, final; §3.1, Fig. 3) with the
//!   recognition and placement of §3.5, on a [`avs_robot::Robot`]'s attention and recogniser;
//! * [`error`] — [`ZoomError`].

pub mod distance;
pub mod error;
pub mod hypotheses;
pub mod levels;
pub mod model;
pub mod search;
pub mod sharing;
pub mod windows;

#[cfg(test)]
pub(crate) mod testbed;

pub use distance::{distance_from_matches, distance_from_votes, MIN_MATCHES_FOR_DISTANCE};
pub use error::ZoomError;
pub use hypotheses::{hypotheses, Hypothesis};
pub use levels::view_zooms;
pub use model::{ObjectModel, DEFAULT_VOTE_THRESHOLD, RECOGNITION_SHARE};
pub use search::{
    three_step_search, ImageKind, Recognised, Skipped, Step, ZoomConfig, ZoomImage, ZoomOutcome,
    MAX_MIDDLE_ROUNDS,
};
pub use sharing::{share, MIDDLE_MAX, MIDDLE_MIN};
pub use windows::{group_into_windows, reduce, ZoomWindow, REDUCE_OVERLAP, REDUCE_RICHER};
