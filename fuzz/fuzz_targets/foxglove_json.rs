//! Arbitrary bytes as a `json` message of `foxglove.LaserScan`, `foxglove.FrameTransform` and
//! `foxglove.FrameTransforms`: no panic; a scan that decodes becomes a `Scan` the way the MCAP
//! reader makes one, and an error names a field.
#![no_main]

use laserlines_foxglove::message::decode_scan;
use laserlines_foxglove::proto::RangeLimits;
use laserlines_foxglove::{ScanEncoding, json};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    match json::laser_scan(data) {
        Ok(msg) => {
            let scan = decode_scan(ScanEncoding::FoxgloveJson, RangeLimits::default(), data, 1.0)
                .expect("a message that decodes once decodes again");
            assert_eq!(scan.ranges.len(), msg.ranges.len());
            // The check of the scan may refuse it (angles, limits), but never panics.
            let _ = scan.validate();
        }
        Err(e) => assert!(!e.field.is_empty()),
    }
    if let Err(e) = json::frame_transform(data) {
        assert!(!e.field.is_empty());
    }
    if let Ok(list) = json::frame_transforms(data) {
        for t in &list.transforms {
            let _ = laserlines_foxglove::proto::pose_from_transform(t);
        }
    }
});
