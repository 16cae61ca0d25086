//! # avs-concepts
//!
//! (Being built; see the crate description.)
#![warn(missing_docs)]
