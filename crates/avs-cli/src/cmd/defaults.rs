//! The checkout the binary was built from: where scenario files' relative paths resolve when
//! neither the file's folder nor the current directory has them. The shipped default inputs
//! themselves are built into the binary (`avs_eval::inputs`), so no command needs this path.

use std::path::PathBuf;

/// The checkout the binary was built from.
pub fn built_checkout() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}
