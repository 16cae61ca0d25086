//! # avs-testdata
//!
//! Tests and benches compare avs against public benchmark files with answers from established
//! tools. Those files are never copied into the project: they are found at `$AVS_REFERENCE_DATA`
//! or at `../shared/data` beside the checkout. When they are absent, [`reference_data`] prints a
//! visible notice and returns `None`, and the test skips itself, so a newcomer's clone passes.
//!
//! ```
//! if let Some(dir) = avs_testdata::reference_data("bp") {
//!     assert!(dir.is_dir());
//! }
//! ```
use std::io::Write;
use std::path::PathBuf;

/// The ten plain maps of `rooms/` (the IPA room segmentation benchmark); each also has a
/// `_furnitures` variant and a `_gt_segmentation.png` ground truth.
pub const ROOM_MAPS: [&str; 10] = [
    "Freiburg52_scan",
    "lab_a_scan",
    "lab_b_scan",
    "lab_c_scan",
    "lab_ipa",
    "office_a",
    "office_b",
    "office_c",
    "office_d",
    "office_e",
];

/// The reference data folder `sub` (e.g. `"bp"`, `"rooms"`), or `None` with a notice on stderr.
pub fn reference_data(sub: &str) -> Option<PathBuf> {
    let root = std::env::var_os("AVS_REFERENCE_DATA")
        .map(PathBuf::from)
        .or_else(|| {
            // CARGO_MANIFEST_DIR is crates/<name>; the checkout is two levels up.
            let here = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
            here.ancestors()
                .nth(3)
                .map(|p| p.join("shared").join("data"))
        });
    match root.map(|r| r.join(sub)) {
        Some(dir) if dir.is_dir() => Some(dir),
        other => {
            // Written straight to the process's stderr, not through `eprintln!`, so the test
            // harness's output capture does not hide it: a skipped check must be visible.
            let _ = writeln!(
                std::io::stderr(),
                "NOTICE: reference data {:?} not found (set AVS_REFERENCE_DATA or place shared/data beside the checkout); skipping",
                other.unwrap_or_else(|| PathBuf::from(sub))
            );
            None
        }
    }
}
