//! The larger recorded data of `../shared/data` (beside the repository in development and
//! CI, absent on a user's machine), as the tests of every crate find it. Each test crate
//! includes this file: `#[path = "../../../tests/shared_data.rs"] mod shared_data;`.
//!
//! A test whose data is absent skips with a notice that shows on the terminal even when the
//! test passes; in CI (`LASERLINES_REQUIRE_SHARED=1`, where `../shared` is there) the absence
//! fails instead.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// `../shared/data/<rel>` as seen from the crate being tested (every crate sits two folders
/// below the repository).
pub fn path(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data")
        .join(rel)
}

/// `path` when it exists, else `None` after [`skip_notice`] for `what`.
pub fn available(path: PathBuf, what: &str) -> Option<PathBuf> {
    if path.exists() {
        Some(path)
    } else {
        skip_notice(&path, what);
        None
    }
}

/// Says that `what` is skipped because `path` is absent, on the terminal even when the test
/// passes (libtest captures only `print!` and `eprint!`, not writes to the stream itself);
/// with `LASERLINES_REQUIRE_SHARED=1` the absence fails instead.
pub fn skip_notice(path: &Path, what: &str) {
    use std::io::Write as _;
    let required = std::env::var_os("LASERLINES_REQUIRE_SHARED").is_some_and(|v| v == "1");
    assert!(
        !required,
        "{} is absent, and LASERLINES_REQUIRE_SHARED=1 requires it",
        path.display()
    );
    let _ = writeln!(
        std::io::stderr(),
        "notice: {} is absent; skipping {what}",
        path.display()
    );
}
