//! Arbitrary bytes through the ROS 1 bag reader: it must never panic, and every item is either
//! a valid scan or an error naming the input.
#![no_main]

use laserlines_io::bag::{BagOptions, from_reader};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // A small chunk limit: a corrupt size must be an error, not a huge allocation.
    let options = BagOptions {
        topic: None,
        max_chunk_bytes: 1 << 20,
    };
    let Ok(reader) = from_reader("fuzz", std::io::Cursor::new(data.to_vec()), &options) else {
        return;
    };
    for item in reader.take(10_000) {
        match item {
            Ok(record) => assert!(record.scan.validate().is_ok()),
            Err(e) => assert_eq!(e.file(), "fuzz"),
        }
    }
});
