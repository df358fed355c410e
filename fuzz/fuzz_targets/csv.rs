//! Arbitrary bytes through the csv reader: it must never panic, and every item is either a
//! valid scan or an error naming the input.
#![no_main]

use libfuzzer_sys::fuzz_target;
use laserlines_io::{Format, from_reader};

fuzz_target!(|data: &[u8]| {
    let Ok(reader) = from_reader("fuzz", std::io::Cursor::new(data.to_vec()), Format::Csv) else {
        return;
    };
    for item in reader.take(10_000) {
        match item {
            Ok(record) => assert!(record.scan.validate().is_ok()),
            Err(e) => assert_eq!(e.file(), "fuzz"),
        }
    }
});
