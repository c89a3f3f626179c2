//! Helpers shared by the unit tests.

use std::path::PathBuf;

/// A file of the project's shared reference data, `../shared/reference/NAME` beside the
/// crate (where CI and every checkout of the project have it).
pub(crate) fn shared_reference(name: &str) -> Option<PathBuf> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/reference")
        .join(name);
    path.is_file().then_some(path)
}
