//! Arbitrary bytes through the Parquet scans reader (`laserlines-parquet`): nothing may panic,
//! every record is a valid scan, every error names the input.
#![no_main]

use libfuzzer_sys::fuzz_target;

/// Installs, once, a panic hook that prints without aborting (libfuzzer-sys's aborts at
/// once): the reader catches the panics of the `parquet` crate's decoder on malformed pages
/// and reports them as errors. A panic anywhere else still ends the run: libfuzzer-sys
/// aborts when one leaves this closure.
static HOOK: std::sync::Once = std::sync::Once::new();

fuzz_target!(|data: &[u8]| {
    HOOK.call_once(|| std::panic::set_hook(Box::new(|info| eprintln!("{info}"))));
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
