//! Arbitrary bytes as a Hokuyo's SCIP 2.0 reply stream: the framer, the reply parser, the
//! information and scan decoders and the sensor description must never panic; a scan
//! decoded has exactly the values asked for.
#![no_main]

use laserlines_hokuyo::SensorInfo;
use laserlines_hokuyo::codec::Encoding;
use laserlines_hokuyo::reply::{Framer, Reply};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let mut framer = Framer::new();
    // Push in two pieces, as a transport would.
    let cut = data.first().map_or(0, |&b| usize::from(b)).min(data.len());
    framer.push(&data[..cut]);
    let mut messages = Vec::new();
    while let Some(m) = framer.next_message() {
        messages.push(m);
    }
    framer.push(&data[cut..]);
    while let Some(m) = framer.next_message() {
        messages.push(m);
    }
    let mut values = Vec::new();
    for m in &messages {
        let _ = Reply::parse(m);
        let Ok(r) = Reply::parse_unchecked(m) else {
            continue;
        };
        if let Ok(pairs) = r.info() {
            let _ = SensorInfo::from_pairs(&pairs, &pairs, &pairs);
        }
        for enc in [Encoding::Two, Encoding::Three] {
            for n in [0, 1, 21, 682, 1081] {
                let _ = r.check_scan_layout(enc, n);
                let _ = r.verify_data();
                if r.scan_into(enc, n, &mut values).is_ok() {
                    assert_eq!(values.len(), n);
                }
            }
        }
    }
});
