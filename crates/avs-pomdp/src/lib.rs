//! # avs-pomdp
//!
//! (Being built; see the crate description.)
#![warn(missing_docs)]
