//! # avs-format
//!
//! The files avs users write, as plain serde types, and one safe way to read them.
//!
//! Every avs file is YAML and starts with `kind:` — `environment`, `knowledge`, `domain` or
//! `scenario`. This crate owns the types of environments and knowledge files, the
//! [`Diagnostic`] every checker reports (`FILE:LINE:COLUMN: field.path: what is wrong; what is
//! expected`), and [`load_yaml`], which reads a file with bounded size, nesting and alias
//! expansion and turns serde errors into diagnostics.
//!
//! Domain files belong to `avs-plan` (which uses this crate's loader); semantic checks that need
//! the occupancy grid live in `avs-sim`.
//!
//! ```
//! use avs_format::{environment::Environment, load_yaml_str};
//! let env: Environment = load_yaml_str("inline.yaml", r#"
//! kind: environment
//! name: tiny
//! map: { ascii: "#####\n#...#\n#####\n", resolution: 0.5 }
//! robot: { start: { x: 1.0, y: 0.75 } }
//! "#).unwrap();
//! assert_eq!(env.name, "tiny");
//! ```
#![warn(missing_docs)]

pub mod diag;
pub mod environment;
pub mod knowledge;
pub mod load;

pub use diag::{Diagnostic, Diagnostics};
pub use load::{load_yaml, load_yaml_str, read_kind, FileKind, LoadError};
