//! Arbitrary bytes as the payload of a `sensor_msgs/msg/LaserScan` DDS sample, through what
//! `laserlines-ros2` does with each one: decode (encapsulation header and CDR), turn into a
//! scan, extract and build the outputs. No panic; a decoded message encodes back to bytes
//! that decode to the same encoding; an extracted scan gives one segment and two marker
//! points per line.
#![no_main]

use laserlines_ros2::msg::LaserScan;
use laserlines_ros2::process::{Outputs, Processed, Processor};
use laserlines_ros2::wire::{decode, encode};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(msg) = decode::<LaserScan>(data) else {
        return;
    };
    let bytes = encode(&msg).expect("a decoded scan encodes");
    let again: LaserScan = decode(&bytes).expect("an encoded scan decodes");
    assert_eq!(encode(&again).expect("encodes"), bytes);
    let Some(Ok(extractor)) = laserlines::registry::build("hough-split") else {
        return;
    };
    let mut p = Processor::new(extractor, None, true);
    let mut out = Outputs::default();
    if let Processed::Extracted { lines, .. } = p.process(&msg, &mut out) {
        assert_eq!(out.lines.line_segments.len(), lines);
        assert_eq!(out.marker.points.len(), 2 * lines);
        assert!(out.sectors.is_some());
    }
});
