//! Arbitrary bytes through the lines JSONL reader: it must never panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use laserlines_io::LinesReader;

fuzz_target!(|data: &[u8]| {
    let Ok(reader) = LinesReader::from_reader("fuzz", std::io::Cursor::new(data.to_vec())) else {
        return;
    };
    for item in reader.take(10_000) {
        if let Err(e) = item {
            assert_eq!(e.file(), "fuzz");
        }
    }
});
