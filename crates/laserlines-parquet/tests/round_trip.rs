//! Scans and lines through Parquet and back, on the bundled real URG-04LX excerpt, and what
//! other writers produce (float64 lists, large and fixed-size lists, nullable columns).

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::sync::Arc;

use arrow_array::cast::AsArray;
use arrow_array::types::{Float64Type, Int64Type};
use arrow_array::{
    ArrayRef, FixedSizeListArray, Float32Array, Float64Array, LargeListArray, RecordBatch,
};
use arrow_buffer::OffsetBuffer;
use arrow_schema::{DataType, Field, Schema};
use laserlines::registry;
use laserlines_io::{ReadError, ScanRecord, demo};
use laserlines_parquet::schema::{LINE_BEAMS, LINE_FIT, LINE_GEOMETRY};
use laserlines_parquet::{LinesParquetWriter, ScansParquetWriter, TableWriter, lines_schema, read};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;

/// The errors among `items`, as text.
fn error_texts(items: &[Result<ScanRecord, ReadError>]) -> Vec<String> {
    items
        .iter()
        .filter_map(|r| r.as_ref().err().map(ToString::to_string))
        .collect()
}

fn excerpt() -> Vec<ScanRecord> {
    demo::urg04lx_excerpt().unwrap()
}

fn scans_bytes(records: &[ScanRecord]) -> Vec<u8> {
    let mut w = ScansParquetWriter::new(Vec::new(), "mem").unwrap();
    for r in records {
        w.write(r).unwrap();
    }
    w.finish().unwrap()
}

#[test]
fn scans_read_back_as_written_bit_for_bit() {
    let records = excerpt();
    let bytes = scans_bytes(&records);
    let back: Vec<ScanRecord> = read::from_bytes("mem", bytes.clone())
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    assert_eq!(back.len(), records.len());
    for (a, b) in records.iter().zip(&back) {
        let (s, t) = (&a.scan, &b.scan);
        assert_eq!(
            (s.angle_min, s.angle_increment, s.range_min, s.range_max),
            (t.angle_min, t.angle_increment, t.range_min, t.range_max)
        );
        assert_eq!(s.stamp, t.stamp);
        assert_eq!(a.pose, b.pose);
        assert_eq!(a.odometry, b.odometry);
        assert!(a.pose.is_some() && a.odometry.is_some() && s.stamp.is_some());
        // Ranges keep all 64 bits (the excerpt's millimetres, 1.234 m and the like, are not
        // float32 values).
        let bits = |r: &[f64]| -> Vec<u64> { r.iter().map(|r| r.to_bits()).collect() };
        assert_eq!(bits(&s.ranges), bits(&t.ranges));
    }
    // Written again, the scans read back give the very same bytes.
    assert_eq!(scans_bytes(&back), bytes);
}

#[test]
fn lines_table_holds_every_line_of_every_scan() {
    let records = excerpt();
    let mut hs = registry::by_name("hough-split").unwrap();
    let mut w = LinesParquetWriter::new(Vec::new(), "mem").unwrap();
    let mut expected = Vec::new();
    for (k, r) in records.iter().enumerate() {
        let lines = hs.extract(&r.scan);
        w.write_record(k as u64, r, &lines).unwrap();
        expected.extend(lines.into_iter().map(|l| (k, r.scan.stamp, r.pose, l)));
    }
    let bytes = bytes::Bytes::from(w.finish().unwrap());
    // Given where scans are expected, the file is named for what it is.
    let e = error_of(bytes.to_vec());
    assert!(
        e.starts_with("bad.parquet: row 0: angle_min: expected a column of float64")
            && e.ends_with(
                "; this is a lines file, as `laserlines extract` writes, not a file of scans"
            ),
        "{e}"
    );
    let builder = ParquetRecordBatchReaderBuilder::try_new(bytes).unwrap();
    assert_eq!(builder.schema().fields(), lines_schema().fields());
    let batches: Vec<RecordBatch> = builder.build().unwrap().collect::<Result<_, _>>().unwrap();
    let rows: usize = batches.iter().map(RecordBatch::num_rows).sum();
    assert!(rows > 100, "{rows} lines");
    assert_eq!(rows, expected.len());
    let mut i = 0;
    for b in &batches {
        let f = |name: &str| {
            b.column_by_name(name)
                .unwrap()
                .as_primitive::<Float64Type>()
                .clone()
        };
        let n = |name: &str| {
            b.column_by_name(name)
                .unwrap()
                .as_primitive::<Int64Type>()
                .clone()
        };
        for row in 0..b.num_rows() {
            let (k, stamp, pose, l) = &expected[i];
            i += 1;
            assert_eq!(n("scan").value(row), *k as i64);
            assert_eq!(f("stamp").value(row), stamp.unwrap());
            let pose = pose.unwrap();
            assert_eq!(
                [
                    f("pose_x").value(row),
                    f("pose_y").value(row),
                    f("pose_theta").value(row)
                ],
                [pose.x, pose.y, pose.theta]
            );
            let geometry = [l.start.x, l.start.y, l.end.x, l.end.y, l.r, l.alpha];
            for (name, v) in LINE_GEOMETRY.iter().zip(geometry) {
                assert_eq!(f(name).value(row).to_bits(), v.to_bits(), "{name}");
            }
            for (name, v) in LINE_BEAMS.iter().zip([l.first, l.last, l.points]) {
                assert_eq!(n(name).value(row), v as i64, "{name}");
            }
            let c = l.covariance;
            for (name, v) in LINE_FIT
                .iter()
                .zip([l.rms, c[(0, 0)], c[(0, 1)], c[(1, 1)]])
            {
                assert_eq!(f(name).value(row).to_bits(), v.to_bits(), "{name}");
            }
        }
    }
}

/// Writes one batch of `columns` (all nullable) with the crate's own table writer.
fn table(columns: Vec<(&str, ArrayRef)>) -> Vec<u8> {
    let schema = Arc::new(Schema::new(
        columns
            .iter()
            .map(|(n, a)| Field::new(*n, a.data_type().clone(), true))
            .collect::<Vec<_>>(),
    ));
    let batch =
        RecordBatch::try_new(schema.clone(), columns.into_iter().map(|c| c.1).collect()).unwrap();
    let mut w = TableWriter::new(Vec::new(), "t.parquet", schema, 100).unwrap();
    w.write(&batch).unwrap();
    w.finish().unwrap()
}

fn f64s(v: &[Option<f64>]) -> ArrayRef {
    Arc::new(Float64Array::from(v.to_vec()))
}

#[test]
fn other_writers_shapes_read_the_same() {
    // Two scans of three beams, lists of float64 in three list kinds, limits as float32.
    let values = Float64Array::from(vec![
        Some(1.0),
        None,
        Some(2.0),
        Some(3.0),
        Some(0.5),
        Some(9.0),
    ]);
    let item = Arc::new(Field::new("item", DataType::Float64, true));
    let large: ArrayRef = Arc::new(LargeListArray::new(
        item.clone(),
        OffsetBuffer::from_lengths([3, 3]),
        Arc::new(values.clone()),
        None,
    ));
    let fixed: ArrayRef = Arc::new(FixedSizeListArray::new(item, 3, Arc::new(values), None));
    for ranges in [large, fixed] {
        let bytes = table(vec![
            ("angle_min", f64s(&[Some(-0.1), Some(0.2)])),
            ("angle_increment", f64s(&[Some(0.1), Some(-0.1)])),
            (
                "range_min",
                Arc::new(Float32Array::from(vec![0.25f32, 0.25])),
            ),
            ("range_max", f64s(&[Some(5.0), Some(5.0)])),
            ("ranges", ranges),
            ("pose_x", f64s(&[Some(1.0), Some(2.0)])),
            ("pose_y", f64s(&[Some(1.0), None])),
            ("pose_theta", f64s(&[Some(0.0), Some(0.0)])),
            ("odometry_x", f64s(&[None, Some(4.0)])),
            ("odometry_y", f64s(&[Some(1.0), Some(5.0)])),
            ("odometry_theta", f64s(&[Some(0.5), Some(-0.5)])),
            ("other", f64s(&[None, None])),
        ]);
        let scans: Vec<ScanRecord> = read::from_bytes("t.parquet", bytes)
            .unwrap()
            .collect::<Result<_, _>>()
            .unwrap();
        assert_eq!(scans.len(), 2);
        assert_eq!(scans[0].scan.ranges[0], 1.0);
        assert!(scans[0].scan.ranges[1].is_nan()); // a null item: no return
        assert_eq!(scans[1].scan.ranges, vec![3.0, 0.5, 9.0]);
        assert_eq!(scans[1].scan.angle_increment, -0.1);
        assert_eq!(scans[0].scan.range_min, 0.25);
        assert!(scans[0].pose.is_some() && scans[1].pose.is_none()); // pose_y null
        assert!(scans[0].odometry.is_none()); // odometry_x null
        let odometry = scans[1].odometry.unwrap();
        assert_eq!((odometry.x, odometry.y, odometry.theta), (4.0, 5.0, -0.5));
        assert!(scans[0].scan.stamp.is_none() && scans[0].scan.intensities.is_none());
    }
}

fn error_of(bytes: Vec<u8>) -> String {
    read::from_bytes("bad.parquet", bytes)
        .unwrap_err()
        .to_string()
}

#[test]
fn bad_files_are_errors_naming_the_file_the_row_and_the_column() {
    assert!(
        error_of(b"PAR1 not really".to_vec())
            .starts_with("bad.parquet: byte 0: expected a Parquet file, found"),
    );
    let good = scans_bytes(&excerpt()[..3]);
    let truncated = good[..good.len() / 2].to_vec();
    assert!(error_of(truncated).starts_with("bad.parquet: byte 0: expected a Parquet file"));
    // Nothing, one byte, the gzip magic alone: errors, no panic.
    for short in [&[][..], &[0x1f], &[0x1f, 0x8b]] {
        assert!(error_of(short.to_vec()).contains("expected a Parquet file"));
    }
    // A gzipped file (the gzip magic, then anything): said so.
    let mut gzipped = vec![0x1f, 0x8b, 0x08, 0x00];
    gzipped.extend_from_slice(&good);
    assert!(
        error_of(gzipped).contains("found gzip-compressed data (Parquet compresses its own pages"),
    );
    let e = error_of(table(vec![("angle_min", f64s(&[Some(0.0)]))]));
    assert!(
        e.starts_with(
            "bad.parquet: row 0: angle_increment: expected a column of float64 (or float32), \
             found no such column (columns: angle_min)"
        ),
        "{e}"
    );
    let e = error_of(table(vec![
        ("angle_min", f64s(&[Some(0.0)])),
        ("angle_increment", f64s(&[Some(0.1)])),
        ("range_min", f64s(&[Some(0.0)])),
        ("range_max", f64s(&[Some(1.0)])),
        ("ranges", f64s(&[Some(1.0)])),
    ]));
    assert!(
        e.contains("row 0: ranges: expected a column of list<float64>"),
        "{e}"
    );
    assert!(e.ends_with("found a column of Float64"), "{e}");
}

#[test]
fn a_bad_row_is_an_error_naming_it_and_reading_goes_on() {
    let values = Float32Array::from(vec![1.0f32, 2.0, 1.0, 2.0, 1.0, 2.0]);
    let item = Arc::new(Field::new("item", DataType::Float32, true));
    let ranges: ArrayRef = Arc::new(arrow_array::ListArray::new(
        item,
        OffsetBuffer::from_lengths([2, 2, 2]),
        Arc::new(values),
        None,
    ));
    let bytes = table(vec![
        ("angle_min", f64s(&[Some(0.0), None, Some(0.0)])),
        ("angle_increment", f64s(&[Some(0.1), Some(0.1), Some(0.1)])),
        ("range_min", f64s(&[Some(0.0), Some(0.0), Some(3.0)])),
        ("range_max", f64s(&[Some(4.0), Some(4.0), Some(2.0)])),
        ("ranges", ranges),
    ]);
    let items: Vec<Result<ScanRecord, ReadError>> =
        read::from_bytes("bad.parquet", bytes).unwrap().collect();
    assert_eq!(items.len(), 3);
    assert_eq!(items[0].as_ref().unwrap().scan.ranges, vec![1.0, 2.0]);
    assert_eq!(
        items[1].as_ref().unwrap_err().to_string(),
        "bad.parquet: row 1: angle_min: expected a number, found null"
    );
    assert_eq!(
        items[2].as_ref().unwrap_err().to_string(),
        "bad.parquet: row 2: invalid scan: range limits must satisfy 0 <= range_min < \
         range_max (finite), got 3..2"
    );
}

/// A file the fuzzer made from `laserlines convert crates/laserlines-io/tests/fixtures/two_scans.dat`
/// (`fuzz_targets/parquet.rs`): among its changes, byte 2228 is 0x77 where the writer put
/// 0x76, which makes the `range_min` column chunk's compressed size -60 in the metadata. The
/// decoder panicked on it; it is an error at opening, naming the file and the chunk (files
/// that are fine pass the same check in every other test here).
#[test]
fn a_column_chunk_outside_the_file_is_an_error_not_a_panic() {
    let bytes = std::fs::read("tests/fixtures/negative_chunk_size.parquet").unwrap();
    assert_eq!((bytes.len(), bytes[2228]), (3711, 0x77));
    let Err(e) = read::from_bytes("negative_chunk_size.parquet", bytes) else {
        panic!("a file with a negative chunk size opened");
    };
    let text = e.to_string();
    assert!(text.starts_with("negative_chunk_size.parquet"), "{text}");
    assert!(text.contains("column chunks within the file"), "{text}");
    assert!(
        text.contains("range_min") && text.contains("-60 bytes"),
        "{text}"
    );
}

/// Another file the fuzzer made from the same table: its pages pass the metadata's checks but
/// make the `parquet` crate's decoder panic (definition levels read past the page's end).
/// The reader catches that and gives an error naming the file and the row, then goes on with
/// the next row group (this file has one).
#[test]
fn a_page_the_decoder_panics_on_is_an_error() {
    let bytes = std::fs::read("tests/fixtures/levels_past_the_page.parquet").unwrap();
    let items: Vec<Result<ScanRecord, ReadError>> =
        read::from_bytes("levels_past_the_page.parquet", bytes)
            .unwrap()
            .collect();
    let errors = error_texts(&items);
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].starts_with("levels_past_the_page.parquet: row 0")
            && errors[0].contains("the Parquet decoder failed"),
        "{}",
        errors[0]
    );
}

/// A file the fuzzer made whose dictionary page claims about 1.4 billion doubles in a few
/// hundred bytes: the decoder would allocate for all of them and abort the process. The
/// reader refuses it at opening, naming the file, the offset and the claim.
#[test]
fn a_dictionary_claiming_more_values_than_its_bytes_is_an_error_at_opening() {
    let bytes = std::fs::read("tests/fixtures/dictionary_claims_too_many.parquet").unwrap();
    assert_eq!(bytes.len(), 7277);
    let Err(e) = read::from_bytes("dictionary_claims_too_many.parquet", bytes) else {
        panic!("a file with an impossible dictionary opened");
    };
    let text = e.to_string();
    assert!(
        text.starts_with("dictionary_claims_too_many.parquet: byte "),
        "{text}"
    );
    assert!(
        text.contains("dictionary pages whose values fit in their bytes")
            && text.contains("values of 8 bytes in"),
        "{text}"
    );
    // The tables this project writes open as before: their dictionaries pass the check.
    let written = scans_bytes(&excerpt());
    assert_eq!(read::from_bytes("t.parquet", written).unwrap().count(), 40);
}

/// A table in row groups of 10 scans whose second row group has a damaged data page: the
/// error names that group's first row, its scans are counted as lost, and the other row
/// groups read as written.
#[test]
fn a_damaged_row_group_costs_its_own_scans_only() {
    let records = excerpt();
    assert_eq!(records.len(), 40);
    let mut table =
        TableWriter::new(Vec::new(), "mem", laserlines_parquet::scans_schema(), 10).unwrap();
    let mut columns = laserlines_parquet::ScansColumns::new();
    for (k, r) in records.iter().enumerate() {
        columns.push(k as u64, r).unwrap();
    }
    table.write(&columns.take_batch().unwrap()).unwrap();
    let mut bytes = table.finish().unwrap();
    let meta = ParquetRecordBatchReaderBuilder::try_new(bytes::Bytes::from(bytes.clone()))
        .unwrap()
        .metadata()
        .clone();
    assert_eq!(meta.num_row_groups(), 4);
    // The ranges' column chunk of the second row group: flip bytes in its middle.
    let chunk = meta
        .row_group(1)
        .columns()
        .iter()
        .find(|c| c.column_path().string().starts_with("ranges"))
        .unwrap();
    let start = usize::try_from(chunk.data_page_offset()).unwrap();
    let size = usize::try_from(chunk.compressed_size()).unwrap();
    for b in &mut bytes[start + size / 2..start + size / 2 + 16] {
        *b ^= 0x5a;
    }
    let mut reader = read::from_bytes("groups.parquet", bytes).unwrap();
    let items: Vec<Result<ScanRecord, ReadError>> = reader.by_ref().collect();
    let errors = error_texts(&items);
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].starts_with("groups.parquet: row 10: "),
        "{}",
        errors[0]
    );
    // The error stands for row 10, a bad record; the other 9 are counted lost.
    assert_eq!(reader.skipped().get(read::SKIP_LOST_ROWS), 9);
    let read: Vec<&ScanRecord> = items.iter().filter_map(|r| r.as_ref().ok()).collect();
    let kept: Vec<&ScanRecord> = records[..10].iter().chain(&records[20..]).collect();
    assert_eq!(read.len(), 30);
    for (a, b) in read.iter().zip(&kept) {
        assert_eq!(a.scan.stamp, b.scan.stamp);
        assert_eq!(
            format!("{:?}", a.scan.ranges),
            format!("{:?}", b.scan.ranges)
        );
    }
}
