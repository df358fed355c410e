//! Parquet end to end: `convert LOG scans.parquet`, `extract scans.parquet`, `extract LOG -o
//! lines.parquet`, and bad Parquet input ending in a clear error.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::process::{Command, Output};

use arrow_array::RecordBatch;
use arrow_array::cast::AsArray;
use arrow_array::types::{Float64Type, Int64Type};
use laserlines_io::LinesReader;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;

mod common;
use common::{bin, excerpt, tmp};

fn run_ok(cmd: &mut Command) -> Output {
    let o = cmd.output().expect("the laserlines binary runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    o
}

/// `extract scans.parquet` reads the scans `convert` wrote: the same lines as from the same
/// scans written as JSONL (exact decimal text of every range).
#[test]
fn scans_parquet_is_a_scan_source() {
    let scans = tmp("scans.parquet");
    let o = run_ok(bin().arg("convert").arg(excerpt()).arg(&scans));
    assert!(String::from_utf8_lossy(&o.stderr).contains("40 scans written"));
    let jsonl = tmp("scans-from-parquet.jsonl");
    run_ok(bin().arg("convert").arg(&scans).arg(&jsonl));
    let (a, b) = (tmp("a.jsonl"), tmp("b.jsonl"));
    let o = run_ok(bin().arg("extract").arg(&scans).arg("-o").arg(&a));
    assert!(String::from_utf8_lossy(&o.stderr).contains(": 40 scans"));
    run_ok(bin().arg("extract").arg(&jsonl).arg("-o").arg(&b));
    let a = std::fs::read(a).unwrap();
    assert!(a.len() > 10_000);
    assert_eq!(a, std::fs::read(b).unwrap());
    // And back again: the scans of the table convert to the same table.
    let again = tmp("again.parquet");
    run_ok(bin().arg("convert").arg(&scans).arg(&again));
    assert_eq!(
        std::fs::read(&scans).unwrap(),
        std::fs::read(again).unwrap()
    );
}

/// `extract LOG -o lines.parquet` holds the lines of `extract LOG -o lines.jsonl`, row by
/// row, bit for bit.
#[test]
fn lines_parquet_holds_what_lines_jsonl_holds() {
    let (pq, jsonl) = (tmp("lines.parquet"), tmp("lines.jsonl"));
    run_ok(bin().arg("extract").arg(excerpt()).arg("-o").arg(&pq));
    run_ok(bin().arg("extract").arg(excerpt()).arg("-o").arg(&jsonl));
    let mut expected = Vec::new();
    for scan in LinesReader::open(&jsonl).unwrap() {
        let scan = scan.unwrap();
        for l in &scan.lines {
            let pose = scan.pose.unwrap();
            let floats = [
                scan.stamp.unwrap(),
                pose.x,
                pose.y,
                pose.theta,
                l.start[0],
                l.start[1],
                l.end[0],
                l.end[1],
                l.r,
                l.alpha,
                l.rms,
                l.covariance[0][0],
                l.covariance[0][1],
                l.covariance[1][1],
            ];
            let ints = [
                scan.scan as i64,
                l.first as i64,
                l.last as i64,
                l.points as i64,
            ];
            expected.push((floats.map(f64::to_bits), ints));
        }
    }
    let file = std::fs::File::open(&pq).unwrap();
    let batches: Vec<RecordBatch> = ParquetRecordBatchReaderBuilder::try_new(file)
        .unwrap()
        .build()
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    let mut got = Vec::new();
    for b in &batches {
        let f = |n: &str| {
            b.column_by_name(n)
                .unwrap()
                .as_primitive::<Float64Type>()
                .clone()
        };
        let i = |n: &str| {
            b.column_by_name(n)
                .unwrap()
                .as_primitive::<Int64Type>()
                .clone()
        };
        let fs = [
            "stamp",
            "pose_x",
            "pose_y",
            "pose_theta",
            "start_x",
            "start_y",
            "end_x",
            "end_y",
            "r",
            "alpha",
            "rms",
            "cov_rr",
            "cov_ralpha",
            "cov_alphaalpha",
        ]
        .map(f);
        let is = ["scan", "first", "last", "points"].map(i);
        for row in 0..b.num_rows() {
            got.push((
                fs.each_ref().map(|c| c.value(row).to_bits()),
                is.each_ref().map(|c| c.value(row)),
            ));
        }
    }
    assert!(expected.len() > 100);
    assert_eq!(got, expected);
}

#[test]
fn bad_parquet_is_a_clear_error() {
    let bad = tmp("bad.parquet");
    std::fs::write(&bad, b"PAR1 this is not a table PAR1").unwrap();
    let o = bin().arg("extract").arg(&bad).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("bad.parquet: byte 0: expected a Parquet file"),
        "{err}"
    );
    let scans = tmp("topic.parquet");
    run_ok(bin().arg("convert").arg(excerpt()).arg(&scans));
    let o = bin()
        .arg("extract")
        .arg(&scans)
        .args(["--topic", "/scan"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("cannot read topic `/scan`"), "{err}");
}

/// A Parquet table is a file (its footer, written last, says where everything is): `convert
/// LOG - --to parquet` is refused, as MCAP is, and writes no file named `-`.
#[test]
fn parquet_to_standard_output_is_refused() {
    let dir = tmp("parquet-stdout");
    std::fs::create_dir_all(&dir).unwrap();
    let o = bin()
        .current_dir(&dir)
        .arg("convert")
        .arg(excerpt())
        .args(["-", "--to", "parquet"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("Parquet output must be a file, not standard output"),
        "{err}"
    );
    assert!(o.stdout.is_empty());
    assert!(!dir.join("-").exists());
}
