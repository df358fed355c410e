//! Arbitrary bytes through the CARMEN reader, with the default laser and with a chosen one:
//! it must never panic, every item is either a valid scan or an error naming the input, and
//! records left to parse later (`next_pending`) parse to the very items `next` gives.
#![no_main]

use laserlines_io::{Format, from_reader_with};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // The first byte chooses the laser read, so that every message kind gets parsed.
    let topic = match data.first().map(|b| b % 4) {
        Some(1) => Some("RLASER"),
        Some(2) => Some("RAWLASER1"),
        Some(3) => Some("ROBOTLASER2"),
        _ => None,
    };
    let open = || {
        from_reader_with(
            "fuzz",
            std::io::Cursor::new(data.to_vec()),
            Format::Carmen,
            topic,
        )
    };
    let (Ok(reader), Ok(mut pending)) = (open(), open()) else {
        return;
    };
    for item in reader.take(10_000) {
        let later = pending.next_pending().map(|p| p.parse());
        assert_eq!(
            format!("{:?}", Some(&item)),
            format!("{:?}", later.as_ref())
        );
        match item {
            Ok(record) => {
                assert!(record.scan.validate().is_ok());
                assert!(record.pose.is_none_or(|p| p.is_finite()));
                assert!(record.odometry.is_none_or(|p| p.is_finite()));
            }
            Err(e) => assert_eq!(e.file(), "fuzz"),
        }
    }
});
