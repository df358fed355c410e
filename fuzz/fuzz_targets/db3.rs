//! Arbitrary bytes as a ROS 2 bag in sqlite3 storage (`laserlines-foxglove`'s `.db3` reader,
//! through SQLite): nothing may panic or hang (a damaged page is passed over, never read
//! again), every record is a valid scan, every error names the file. Seed the corpus with
//! whole bags: the mutations then damage their pages.
#![no_main]

use std::path::PathBuf;
use std::sync::OnceLock;

use laserlines_foxglove::{McapReadOptions, read};
use libfuzzer_sys::fuzz_target;

/// The file the input is written to (SQLite reads files only), one per process.
fn path() -> &'static PathBuf {
    static PATH: OnceLock<PathBuf> = OnceLock::new();
    PATH.get_or_init(|| std::env::temp_dir().join(format!("fuzz-db3-{}.db3", std::process::id())))
}

fuzz_target!(|data: &[u8]| {
    let path = path();
    if std::fs::write(path, data).is_err() {
        return;
    }
    let name = path.display().to_string();
    let Ok(reader) = read::open(path, &McapReadOptions::default()) else {
        return;
    };
    for item in reader.take(1_000_000) {
        match item {
            Ok(record) => assert!(record.scan.validate().is_ok()),
            Err(e) => assert_eq!(e.file(), name),
        }
    }
});
