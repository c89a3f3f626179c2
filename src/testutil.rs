//! Helpers shared by the unit tests.

use std::path::PathBuf;

/// A published reference file: `../shared/reference/NAME` beside the crate (where CI and the
/// project's checkouts have it), else the cited copy in `tests/data/NAME`.
pub(crate) fn shared_reference(name: &str) -> Option<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    [
        root.join("../shared/reference").join(name),
        root.join("tests/data").join(name),
    ]
    .into_iter()
    .find(|p| p.is_file())
}
