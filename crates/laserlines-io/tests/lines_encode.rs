//! `encode_unnumbered` and `LinesWriter::write_numbered` give the very bytes
//! `LinesWriter::write_record` writes, so that callers may encode scans on other threads
//! before their numbers are known and write them in order.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines::{HoughSplit, HoughSplitParams, LineExtractor, Scan};
use laserlines_io::{LinesWriter, Pose2, ScanRecord, encode_unnumbered};

#[test]
fn encoded_lines_equal_written_lines() {
    let inc = 0.5_f64.to_radians();
    let ranges = (0..181)
        .map(|i| 2.0 / (-45.0_f64.to_radians() + f64::from(i) * inc).cos())
        .collect();
    let scan = Scan::new(-45.0_f64.to_radians(), inc, 0.02, 5.6, ranges).unwrap();
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
    let lines = hs.extract(&scan);
    assert_eq!(lines.len(), 1);
    let mut record = ScanRecord::new(scan);
    let (pose, odometry) = (Pose2::new(1.0, -2.0, 0.5), Pose2::new(1.25, -2.5, 0.75));
    for (k, (stamp, pose, odometry)) in [
        (None, None, None),
        (Some(12.5), Some(pose), None),
        (Some(12.5), Some(pose), Some(odometry)),
    ]
    .into_iter()
    .enumerate()
    {
        record.scan.stamp = stamp;
        record.pose = pose;
        record.odometry = odometry;
        let mut writer = LinesWriter::new(Vec::new());
        writer.write_record(k as u64, &record, &lines).unwrap();
        writer.write_record(k as u64 + 1, &record, &[]).unwrap();
        let written = writer.finish().unwrap();
        let (mut first, mut second) = (Vec::new(), Vec::new());
        encode_unnumbered(&record, &lines, &mut first).unwrap();
        encode_unnumbered(&record, &[], &mut second).unwrap();
        let mut again = LinesWriter::new(Vec::new());
        again.write_numbered(k as u64, &first).unwrap();
        again.write_numbered(k as u64 + 1, &second).unwrap();
        assert!(again.write_numbered(0, b"[1]").is_err());
        assert_eq!(again.finish().unwrap(), written);
        // Read back: the pose and the odometry as the record has them.
        let back =
            laserlines_io::LinesReader::from_reader("l.jsonl", std::io::Cursor::new(written))
                .unwrap()
                .next()
                .unwrap()
                .unwrap();
        assert_eq!((back.pose, back.odometry), (pose, odometry));
    }
}
