//! Arbitrary bytes through the ROS 1 bag reader: it must never panic, and every item is either
//! a valid scan or an error naming the input. The bytes are read as they are (the fuzzer
//! finds the `#ROSBAG V2.0` line from the seeds) and once more after a `#ROSRECORD V1.2` line,
//! so that the records of version 1.2 bags are reached at once.
#![no_main]

use laserlines_io::bag::{BagOptions, MAGIC_V12, from_reader};
use libfuzzer_sys::fuzz_target;

fn read(bytes: Vec<u8>) {
    // A small chunk limit: a corrupt size must be an error, not a huge allocation.
    let options = BagOptions {
        topic: None,
        max_chunk_bytes: 1 << 20,
    };
    let Ok(reader) = from_reader("fuzz", std::io::Cursor::new(bytes), &options) else {
        return;
    };
    for item in reader.take(10_000) {
        match item {
            Ok(record) => assert!(record.scan.validate().is_ok()),
            Err(e) => assert_eq!(e.file(), "fuzz"),
        }
    }
}

fuzz_target!(|data: &[u8]| {
    read(data.to_vec());
    let mut v12 = MAGIC_V12.to_vec();
    v12.extend_from_slice(data);
    read(v12);
});
