//! Arbitrary bytes through the MCAP reader (`laserlines-foxglove`), and through the ROS 1 and
//! CDR LaserScan and MultiEchoLaserScan decoders on their own: nothing may panic, every record
//! is a valid scan, every error names the input, and a multi-echo message leaves out no more
//! echoes than its bytes could hold.
#![no_main]

use laserlines_foxglove::{McapReadOptions, read, ros};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = ros::decode_cdr(data);
    let _ = ros::decode_ros1(data);
    for decoded in [
        ros::decode_cdr_as(data, ros::ScanMsgType::MultiEcho),
        ros::decode_ros1_as(data, ros::ScanMsgType::MultiEcho),
    ] {
        if let Ok(m) = decoded {
            assert!(m.echoes_left_out <= data.len() / 4);
            assert!(m.ranges.len() <= data.len() / 4);
        }
    }
    // Small record limit: a corrupt length must be an error, not a huge allocation.
    let options = McapReadOptions {
        topic: None,
        max_record_bytes: 1 << 20,
        ..McapReadOptions::default()
    };
    let Ok(reader) = read::from_reader("fuzz", std::io::Cursor::new(data.to_vec()), &options)
    else {
        return;
    };
    for item in reader.take(10_000) {
        match item {
            Ok(record) => assert!(record.scan.validate().is_ok()),
            Err(e) => assert_eq!(e.file(), "fuzz"),
        }
    }
});
