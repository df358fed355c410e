//! Arbitrary bytes as a Hokuyo's SCIP 2.0 reply stream: the framer, the reply parser, the
//! information and scan decoders and the sensor description must never panic; a scan
//! decoded has exactly the values asked for; a sensor description that parses gives scans
//! the driver can ask for (the command names the very steps of the geometry) and build
//! (a valid `laserlines::Scan`).
#![no_main]

use laserlines::Scan;
use laserlines_hokuyo::codec::Encoding;
use laserlines_hokuyo::reply::{Framer, Reply};
use laserlines_hokuyo::{ScanRequest, SensorInfo};
use libfuzzer_sys::fuzz_target;

/// What the driver does with a description: the whole area and a cluster of three.
fn check_description(vv: &[(String, String)], pp: &[(String, String)], ii: &[(String, String)]) {
    let Ok(info) = SensorInfo::from_pairs(vv, pp, ii) else {
        return;
    };
    let full = info.full_request();
    for request in [full, ScanRequest { cluster: 3, ..full }] {
        let g = info.geometry(&request);
        assert_eq!(g.beams, request.values());
        // MDssssllllcc...: the command asks for the steps the geometry describes.
        let command = request.stream_command(0);
        assert_eq!(command[2..6], format!("{:04}", request.first_step));
        assert_eq!(command[6..10], format!("{:04}", request.last_step));
        let scan = Scan::new(
            g.angle_min,
            g.angle_increment,
            info.range_min_m(),
            info.range_max_m(),
            vec![0.0; g.beams],
        );
        assert!(scan.is_ok(), "{info:?}: {scan:?}");
    }
}

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
    let mut infos = Vec::new();
    for m in &messages {
        let _ = Reply::parse(m);
        let Ok(r) = Reply::parse_unchecked(m) else {
            continue;
        };
        if let Ok(pairs) = r.info() {
            check_description(&pairs, &pairs, &pairs);
            infos.push(pairs);
        }
        for enc in [Encoding::Two, Encoding::Three] {
            for n in [0, 1, 5, 21, 682, 1081] {
                let _ = r.check_scan_layout(enc, n);
                let _ = r.verify_data();
                if r.scan_into(enc, n, &mut values).is_ok() {
                    assert_eq!(values.len(), n);
                }
            }
        }
    }
    // The first three information replies stand for VV, PP and II, as in a start-up.
    if let [vv, pp, ii, ..] = infos.as_slice() {
        check_description(vv, pp, ii);
    }
});
