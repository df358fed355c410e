//! Arbitrary bytes through the Parquet scans reader (`laserlines-parquet`): nothing may panic,
//! every record is a valid scan, every error names the input.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(reader) = laserlines_parquet::read::from_bytes("fuzz", data.to_vec()) else {
        return;
    };
    for item in reader.take(10_000) {
        match item {
            Ok(record) => assert!(record.scan.validate().is_ok()),
            Err(e) => assert_eq!(e.file(), "fuzz"),
        }
    }
});
