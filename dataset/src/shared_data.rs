//! Where the real KITTI test data lives: `../shared/data` beside the checkout.

use std::path::PathBuf;

/// The shared real-data folder: `$TRACKD_SHARED_DATA` if set, else `../shared/data` beside the
/// workspace. `None` (and a loud `SKIPPED` line on stderr, naming `what`) when it is absent, so
/// a test that needs it says why it did not run.
pub fn shared_data_dir(what: &str) -> Option<PathBuf> {
    let dir = std::env::var_os("TRACKD_SHARED_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data"));
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!(
            "SKIPPED {what}: real KITTI data not found at {} (set TRACKD_SHARED_DATA)",
            dir.display()
        );
        None
    }
}
