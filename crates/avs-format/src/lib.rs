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
//! ## Choices made for validation
//! - **Bounds before building.** serde_yaml stops at 128 levels of recursion and at
//!   100 × (number of events) alias jumps, which still lets a 16 MB file expand quadratically.
//!   [`load_yaml_str`] therefore first walks the text with the `yaml-rust2` event parser (which
//!   never expands aliases): at most [`positions::MAX_DEPTH`] levels of nesting and
//!   [`positions::MAX_ALIAS_NODES`] nodes added by aliases, counted without expanding (an
//!   alias counts the expanded size of its anchor). Files are at most [`load::MAX_FILE_BYTES`].
//! - **Positions for semantic errors.** Checkers report dotted field paths
//!   (`objects[2].room`, the notation of `serde_path_to_error`); [`positions::locate`] maps
//!   them back to line and column with the same event walk, falling back to the longest written
//!   prefix (a field left at its default is reported at its parent).
//! - **Environment rules** ([`check_env`]): every number finite; sizes, widths, resolution,
//!   radius, speed positive; thresholds in [0, 1]; laser range at most
//!   [`check_env::MAX_LASER_RANGE_M`] (a unit slip; the simulator clips rays to the map anyway); names unique per kind (rooms, doors,
//!   objects); references (`room`, `on`, `in`, door `rooms`) resolve; a supporting object is a
//!   landmark in the same room, under the object (footprint + 5 cm), with no support cycles,
//!   and at its height (an object `on` a landmark stands at its top, one `in` it between its
//!   base and top, within 5 cm); no door is narrower than the robot; an ASCII map's rows are
//!   equally long, and its doors sit across gaps of its walls no narrower than them
//!   ([`check_doors`]); with a knowledge file, categories and classes are known ones and
//!   landmarks have landmark classes. A room needs a `seed` or a `polygon`, since without
//!   either it has no extent. A missing field is reported with the fields of its section
//!   ([`load::explain_missing_fields`]).
//!   Every check is linear (or n log n) in the file, so a large file cannot make it hang.
//! - **Scenarios** ([`scenario`]): a search re-enacted for a test or an experiment (world
//!   edits, goal, seed, expected properties), run by `avs-eval`. [`schema::schema_json`] prints
//!   the schemas of environments, knowledge and scenario files generated from the types
//!   (schemars).
//!
//! ```
//! use avs_format::{environment::Environment, load_yaml_str};
//! // One line per string: rustdoc would read a line that starts with `##` as `#`.
//! let text = [
//!     "kind: environment",
//!     "name: tiny",
//!     "map:",
//!     "  ascii: |",
//!     "    #####",
//!     "    #...#",
//!     "    #####",
//!     "  resolution: 0.5",
//!     "robot: { start: { x: 1.0, y: 0.75 } }",
//! ]
//! .join("\n");
//! let env: Environment = load_yaml_str("inline.yaml", &text).unwrap();
//! assert_eq!(env.name, "tiny");
//! assert_eq!(avs_format::check_env::check_environment("inline.yaml", &env, None), vec![]);
//!
//! // A wrong type is reported with its field path, line and column.
//! let err = load_yaml_str::<Environment>("bad.yaml", "kind: environment\nname: [1]\n").unwrap_err();
//! assert_eq!(err.diagnostics[0].path, "name");
//! assert_eq!(err.diagnostics[0].line, Some(2));
//! ```
pub mod check_doors;
pub mod check_env;
pub mod diag;
pub mod environment;
pub mod knowledge;
pub mod load;
pub mod positions;
pub mod scenario;
pub mod schema;
pub mod verification;
pub mod verifier;

pub use diag::{Diagnostic, Diagnostics};
pub use load::{load_yaml, load_yaml_str, read_kind, read_text, FileKind, LoadError};
