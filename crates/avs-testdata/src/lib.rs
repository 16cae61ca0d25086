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
use std::path::{Path, PathBuf};

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

/// Environment variable naming a file to which every skipped reference check appends one line
/// (`sub`, a tab, the test binary's name): `scripts/test`, the README's test command, sets it
/// and ends with a summary line counting them.
pub const SKIP_LOG_VAR: &str = "AVS_SKIP_LOG";

/// The reference data folder `sub` (e.g. `"bp"`, `"rooms"`), or `None` with a notice on stderr
/// (and a line in the file named by [`SKIP_LOG_VAR`], when it is set).
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
    let log = std::env::var_os(SKIP_LOG_VAR).map(PathBuf::from);
    lookup(root, sub, log.as_deref())
}

/// [`reference_data`] with its inputs explicit: the data root, the folder, the skip log.
fn lookup(root: Option<PathBuf>, sub: &str, skip_log: Option<&Path>) -> Option<PathBuf> {
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
            if let Some(path) = skip_log {
                let binary = std::env::current_exe()
                    .ok()
                    .and_then(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
                    .unwrap_or_default();
                // One short append per skip, in a single write so that test binaries running
                // at once do not interleave their lines; a failure to log must not fail the
                // test. The whole data folder is named `.`.
                let what = if sub.is_empty() { "." } else { sub };
                let line = format!("{what}\t{binary}\n");
                let _ = std::fs::OpenOptions::new()
                    .create(true)
                    .append(true)
                    .open(path)
                    .and_then(|mut f| f.write_all(line.as_bytes()));
            }
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_folder_is_skipped_with_a_line_in_the_skip_log() {
        let dir = std::env::temp_dir().join(format!("avs-testdata-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let log = dir.join("skips.log");
        let _ = std::fs::remove_file(&log);
        let absent = dir.join("no-such-root");
        assert_eq!(lookup(Some(absent.clone()), "bp", Some(&log)), None);
        assert_eq!(lookup(Some(absent), "rooms", Some(&log)), None);
        let text = std::fs::read_to_string(&log).unwrap();
        let subs: Vec<&str> = text.lines().filter_map(|l| l.split('\t').next()).collect();
        assert_eq!(subs, ["bp", "rooms"]);
        // A folder that exists is found, and nothing is logged.
        std::fs::create_dir_all(dir.join("root/bp")).unwrap();
        assert_eq!(
            lookup(Some(dir.join("root")), "bp", Some(&log)),
            Some(dir.join("root/bp"))
        );
        assert_eq!(std::fs::read_to_string(&log).unwrap().lines().count(), 2);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
