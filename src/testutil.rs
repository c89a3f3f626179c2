//! Helpers shared by the unit tests.

use std::path::PathBuf;

/// A published reference file: `tests/data/NAME` (its source and licence in
/// `tests/data/README.md`), `None` when it is absent.
pub(crate) fn shared_reference(name: &str) -> Option<PathBuf> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name);
    path.is_file().then_some(path)
}
