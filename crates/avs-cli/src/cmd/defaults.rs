//! Where the shipped default files are: relative to the current directory (a checkout), else
//! in the checkout the binary was built from.

use std::path::PathBuf;

/// The shipped default knowledge.
pub const KNOWLEDGE: &str = "knowledge/office.yaml";

/// The checkout the binary was built from.
pub fn built_checkout() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Resolve a shipped file's path.
pub fn shipped(rel: &str) -> PathBuf {
    let here = PathBuf::from(rel);
    if here.exists() {
        return here;
    }
    let built = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel);
    if built.exists() {
        built
    } else {
        here
    }
}
