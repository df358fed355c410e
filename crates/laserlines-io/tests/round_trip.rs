//! Write, read back, compare: scans in every writable format, and the lines JSONL schema.

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::io::Cursor;

use laserlines::math::{Matrix2, Point2};
use laserlines::{Line, Scan};
use laserlines_io::{
    Format, LinesReader, LinesWriter, Pose2, ScanRecord, ScanWriter, WriteError, from_reader, open,
};

/// Floats that are easy to get wrong in text.
const TRICKY: [f64; 9] = [
    0.1 + 0.2,
    1e-300,
    5.6,
    -0.0,
    123_456_789.123_456_78,
    f64::NAN,
    f64::MAX,
    f64::MIN_POSITIVE,
    1.0 / 3.0,
];

fn tricky_record() -> ScanRecord {
    ScanRecord {
        scan: Scan {
            angle_min: -2.086_213_871_836_614_3,
            angle_increment: 0.006_135_923_151_542_565,
            range_min: 0.02,
            range_max: 5.6,
            ranges: TRICKY.to_vec(),
            intensities: Some(vec![1.0, 2.5, f64::NAN, 0.0, 7.0, 1e10, 3.0, 4.0, 0.1]),
            stamp: Some(1_700_000_000.123_456_7),
        },
        pose: Some(Pose2::new(1.0 / 7.0, -2.5, std::f64::consts::PI)),
        odometry: Some(Pose2::new(-0.1, 1.0 / 3.0, -1.25)),
        line: None,
    }
}

fn plain_record(k: usize) -> ScanRecord {
    ScanRecord {
        scan: Scan::new(0.5, -0.25, 0.0, 4.0, vec![k as f64, 1.5, f64::NAN]).unwrap(),
        pose: None,
        odometry: None,
        line: None,
    }
}

fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| (x.is_nan() && y.is_nan()) || x.to_bits() == y.to_bits())
}

fn write_scans(format: Format, records: &[ScanRecord]) -> Vec<u8> {
    let mut w = ScanWriter::new(Vec::new(), format).unwrap();
    for r in records {
        w.write(r).unwrap();
    }
    w.finish().unwrap()
}

fn read_scans(format: Format, bytes: Vec<u8>) -> Vec<ScanRecord> {
    let reader = from_reader("round-trip", Cursor::new(bytes), format).unwrap();
    let records: Result<Vec<_>, _> = reader.collect();
    records.unwrap()
}

fn assert_same_scan(a: &ScanRecord, b: &ScanRecord) {
    let (x, y) = (&a.scan, &b.scan);
    assert_eq!(x.angle_min.to_bits(), y.angle_min.to_bits());
    assert_eq!(x.angle_increment.to_bits(), y.angle_increment.to_bits());
    assert_eq!(x.range_min.to_bits(), y.range_min.to_bits());
    assert_eq!(x.range_max.to_bits(), y.range_max.to_bits());
    assert!(
        same_bits(&x.ranges, &y.ranges),
        "{:?} vs {:?}",
        x.ranges,
        y.ranges
    );
    match (&x.intensities, &y.intensities) {
        (Some(i), Some(j)) => assert!(same_bits(i, j)),
        (None, None) => {}
        other => panic!("intensities differ: {other:?}"),
    }
    assert_eq!(x.stamp.map(f64::to_bits), y.stamp.map(f64::to_bits));
    assert_eq!(a.pose, b.pose);
    assert_eq!(a.odometry, b.odometry);
}

#[test]
fn jsonl_round_trip_is_exact() {
    let records = vec![tricky_record(), plain_record(1), plain_record(2)];
    let back = read_scans(Format::Jsonl, write_scans(Format::Jsonl, &records));
    assert_eq!(back.len(), 3);
    for (a, b) in records.iter().zip(&back) {
        assert_same_scan(a, b);
    }
    assert_eq!(back[2].line, Some(3));
}

#[test]
fn json_round_trip_single_object_array_and_empty() {
    let one = write_scans(Format::Json, &[tricky_record()]);
    assert_eq!(one[0], b'{', "one scan is written as a single object");
    let back = read_scans(Format::Json, one);
    assert_eq!(back.len(), 1);
    assert_same_scan(&tricky_record(), &back[0]);

    let records: Vec<_> = (0..4).map(plain_record).collect();
    let many = write_scans(Format::Json, &records);
    assert!(many.starts_with(b"[\n{"));
    let back = read_scans(Format::Json, many);
    assert_eq!(back.len(), 4);
    for (a, b) in records.iter().zip(&back) {
        assert_same_scan(a, b);
    }
    assert_eq!(back[3].line, Some(5), "one object per line after the `[`");

    let none = write_scans(Format::Json, &[]);
    assert_eq!(none, b"[]\n");
    assert!(read_scans(Format::Json, none).is_empty());
}

#[test]
fn csv_round_trip_keeps_ranges_limits_stamp_pose_and_intensities() {
    let record = tricky_record();
    let bytes = write_scans(Format::Csv, std::slice::from_ref(&record));
    let text = String::from_utf8(bytes.clone()).unwrap();
    assert!(text.starts_with(
        "# angle_min: -2.0862138718366143\n# angle_increment: 0.006135923151542565\n\
         # range_min: 0.02\n# range_max: 5.6\n# stamp: "
    ));
    assert!(text.contains("\nindex,angle_rad,range_m,intensity\n0,"));
    assert!(text.contains("\n5,") && text.contains(",nan,"), "{text}");
    let back = read_scans(Format::Csv, bytes);
    assert_eq!(back.len(), 1);
    assert_same_scan(&record, &back[0]);
}

#[test]
fn csv_round_trip_of_scans_with_no_or_one_beam() {
    for ranges in [vec![], vec![2.5]] {
        let record = ScanRecord::new(Scan::new(0.25, -0.5, 0.0, 3.0, ranges).unwrap());
        let back = read_scans(
            Format::Csv,
            write_scans(Format::Csv, std::slice::from_ref(&record)),
        );
        assert_same_scan(&record, &back[0]);
    }
}

#[test]
fn csv_without_geometry_comments_derives_the_increment() {
    let text = "index,angle_rad,range_m\n0,-0.3,1\n1,-0.1,2\n2,0.1,3\n3,0.3,4\n";
    let back = read_scans(Format::Csv, text.as_bytes().to_vec());
    let s = &back[0].scan;
    assert_eq!(s.angle_min, -0.3);
    assert!((s.angle_increment - 0.2).abs() < 1e-15);
}

#[test]
fn non_finite_beams_read_back_as_they_were() {
    let mut record = plain_record(0);
    record.scan.ranges = vec![f64::INFINITY, f64::NEG_INFINITY, 1.0, f64::NAN];
    record.scan.intensities = Some(vec![f64::INFINITY, 2.0, f64::NAN, f64::NEG_INFINITY]);
    for format in [Format::Json, Format::Jsonl, Format::Csv] {
        let text = write_scans(format, std::slice::from_ref(&record));
        let back = read_scans(format, text.clone());
        let s = &back[0].scan;
        let r = &s.ranges;
        assert!(
            r[0] == f64::INFINITY && r[1] == f64::NEG_INFINITY && r[2] == 1.0 && r[3].is_nan(),
            "{format}: {r:?}"
        );
        let i = s.intensities.as_deref().unwrap();
        assert!(
            i[0] == f64::INFINITY && i[1] == 2.0 && i[2].is_nan() && i[3] == f64::NEG_INFINITY,
            "{format}: {i:?}"
        );
        if format != Format::Csv {
            // As Python's `json.dump` writes them; NaN as JSON's `null`.
            let text = String::from_utf8(text).unwrap();
            assert!(
                text.contains(r#""ranges":[Infinity,-Infinity,1.0,null]"#),
                "{text}"
            );
        }
    }
    // A scan without infinite beams is strict JSON.
    let plain = String::from_utf8(write_scans(Format::Jsonl, &[plain_record(0)])).unwrap();
    let value: serde_json::Value = serde_json::from_str(plain.trim()).unwrap();
    assert!(value["ranges"].is_array());
}

#[test]
fn a_pose_with_a_non_finite_number_is_left_out_of_json() {
    let mut record = plain_record(0);
    record.pose = Some(Pose2::new(f64::NAN, 1.0, 0.0));
    record.odometry = Some(Pose2::new(1.0, 2.0, 0.5));
    for format in [Format::Json, Format::Jsonl] {
        let back = read_scans(format, write_scans(format, std::slice::from_ref(&record)));
        assert_eq!(back[0].pose, None, "{format}");
        assert_eq!(back[0].odometry, record.odometry, "{format}");
    }
}

#[test]
fn dat_excerpt_converts_to_jsonl_and_back_exactly() {
    let records = laserlines_io::demo::urg04lx_excerpt().unwrap();
    let back = read_scans(Format::Jsonl, write_scans(Format::Jsonl, &records));
    assert_eq!(back.len(), records.len());
    for (a, b) in records.iter().zip(&back) {
        assert_same_scan(a, b);
    }
}

#[test]
fn writers_refuse_what_a_format_cannot_hold() {
    let mut w = ScanWriter::new(Vec::new(), Format::Csv).unwrap();
    w.write(&plain_record(0)).unwrap();
    let err = w.write(&plain_record(1)).unwrap_err();
    assert!(matches!(err, WriteError::OneScanPerFile { count: 2, .. }));
    assert_eq!(
        err.to_string(),
        "output: the csv format holds one scan per file; the input has 2 or more"
    );
    let err = ScanWriter::new(Vec::new(), Format::BreezyDat).unwrap_err();
    assert_eq!(
        err.to_string(),
        "output: writing the dat format is not supported"
    );
}

#[test]
fn files_by_name_with_gzip() {
    let dir = std::env::temp_dir().join(format!("laserlines-io-rt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let records: Vec<_> = (0..3).map(plain_record).collect();
    for name in ["s.json", "s.jsonl.gz", "s.json.gz"] {
        let path = dir.join(name);
        let mut w = ScanWriter::create(&path, None).unwrap();
        for r in &records {
            w.write(r).unwrap();
        }
        w.close().unwrap();
        let gz = std::fs::read(&path).unwrap();
        assert_eq!(
            gz.starts_with(&[0x1f, 0x8b]),
            name.ends_with(".gz"),
            "{name}"
        );
        let back: Vec<_> = open(&path, None).unwrap().map(Result::unwrap).collect();
        assert_eq!(back.len(), 3, "{name}");
        for (a, b) in records.iter().zip(&back) {
            assert_same_scan(a, b);
        }
    }
    let err = ScanWriter::create(&dir.join("s.txt"), None).unwrap_err();
    assert!(matches!(err, WriteError::UnknownFormat { .. }));
    std::fs::remove_dir_all(&dir).unwrap();
}

fn sample_lines() -> Vec<Line> {
    vec![
        Line {
            start: Point2::new(1.0, -0.5),
            end: Point2::new(1.0, 0.5),
            r: 1.0,
            alpha: 0.0,
            first: 10,
            last: 40,
            points: 31,
            rms: 0.004,
            covariance: Matrix2::new(1e-6, 2e-7, 2e-7, 1e-5),
        },
        Line {
            start: Point2::new(0.1 + 0.2, 1.0 / 3.0),
            end: Point2::new(-2.718_281_828_459_1, 1e-300),
            r: 2.0_f64.sqrt(),
            alpha: -std::f64::consts::FRAC_PI_3,
            first: 41,
            last: 681,
            points: 600,
            rms: 1.234_567_890_123_456_7e-3,
            covariance: Matrix2::new(4.0e-8, -1.5e-9, -1.5e-9, 3.3e-7),
        },
    ]
}

#[test]
fn lines_jsonl_schema_is_as_documented() {
    let mut w = LinesWriter::new(Vec::new());
    w.write_scan(0, None, None, &[]).unwrap();
    w.write_scan(
        3,
        Some(1.5),
        Some(Pose2::new(1.0, 2.0, 0.5)),
        &sample_lines()[..1],
    )
    .unwrap();
    let text = String::from_utf8(w.finish().unwrap()).unwrap();
    assert_eq!(
        text,
        "{\"scan\":0,\"lines\":[]}\n\
         {\"scan\":3,\"stamp\":1.5,\"pose\":{\"x\":1.0,\"y\":2.0,\"theta\":0.5},\"lines\":[\
         {\"start\":[1.0,-0.5],\"end\":[1.0,0.5],\"r\":1.0,\"alpha\":0.0,\"first\":10,\
         \"last\":40,\"points\":31,\"rms\":0.004,\
         \"covariance\":[[1e-6,2e-7],[2e-7,0.00001]]}]}\n"
    );
}

#[test]
fn lines_round_trip_is_exact() {
    let lines = sample_lines();
    let records: Vec<_> = (0..3).map(plain_record).collect();
    let mut w = LinesWriter::new(Vec::new());
    for (k, r) in records.iter().enumerate() {
        w.write_record(k as u64, r, &lines[..k.min(2)]).unwrap();
    }
    w.write_scan(3, Some(9.75), Some(Pose2::new(0.5, 0.25, -1.0)), &lines)
        .unwrap();
    let bytes = w.finish().unwrap();
    let back: Vec<_> = LinesReader::from_reader("lines.jsonl", Cursor::new(bytes))
        .unwrap()
        .map(Result::unwrap)
        .collect();
    assert_eq!(back.len(), 4);
    for (k, s) in back.iter().enumerate() {
        assert_eq!(s.scan, k as u64);
        let got: Vec<Line> = s.lines.iter().map(|l| l.to_line()).collect();
        assert_eq!(got, lines[..k.min(2)], "scan {k}");
    }
    assert_eq!(back[3].stamp, Some(9.75));
    assert_eq!(back[3].pose, Some(Pose2::new(0.5, 0.25, -1.0)));
    assert_eq!(back[0].stamp, None);
}

#[test]
fn lines_non_finite_numbers_are_null_and_read_back_as_nan() {
    let mut line = sample_lines()[0];
    line.rms = f64::NAN;
    line.covariance[(1, 1)] = f64::INFINITY;
    let mut w = LinesWriter::new(Vec::new());
    w.write_scan(0, None, None, &[line]).unwrap();
    let bytes = w.finish().unwrap();
    let text = String::from_utf8(bytes.clone()).unwrap();
    assert!(
        text.contains("\"rms\":null") && text.contains("[2e-7,null]"),
        "{text}"
    );
    let back = LinesReader::from_reader("l", Cursor::new(bytes))
        .unwrap()
        .next()
        .unwrap()
        .unwrap();
    assert!(back.lines[0].rms.is_nan());
    assert!(back.lines[0].covariance[1][1].is_nan());
}

#[test]
fn lines_reader_reports_bad_lines_with_position() {
    let data = b"{\"scan\":0,\"lines\":[]}\n{\"scan\":1,\"lines\":[{\"start\":[1]}]}\n";
    let items: Vec<_> = LinesReader::from_reader("l.jsonl", Cursor::new(data.to_vec()))
        .unwrap()
        .collect();
    assert!(items[0].is_ok());
    let err = items[1].as_ref().unwrap_err().to_string();
    assert!(err.starts_with("l.jsonl:2:"), "{err}");
}
