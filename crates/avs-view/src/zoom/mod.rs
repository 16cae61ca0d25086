//! The zoom pipeline of PROCESSVIEWCONE (Sjöö et al. `004` §3): from a wide image's vote
//! matrices to hypotheses, distance estimates, zoom windows shared between classes, and the
//! three-step search that ends in recognition — plus the zoom levels view planning uses.
//!
//! * [`levels`] — the zoom levels a view plan may use;
//! * [`model`] — what the pipeline knows of a class: its front face, its training image, and
//!   the geometry of eq. 1 and §3.3 (distance from a vote area or a scale ratio, zoom to fill
//!   the image).

pub mod levels;
pub mod model;

pub use levels::view_zooms;
pub use model::{ObjectModel, DEFAULT_VOTE_THRESHOLD, RECOGNITION_SHARE};
