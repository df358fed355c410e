//! Bad input never panics and gives an error naming the file, the line and what was wrong.
//! Where the rest of the input is good (JSONL, `.dat`, JSON arrays), reading goes on.

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::io::Cursor;
use std::path::Path;

use laserlines_io::{Format, ReadError, ScanRecord, from_reader, open};

/// Every item of a fixture, as `ok LINE` or the error message; plus the skip summary.
fn outcome(path: &str) -> (Vec<String>, String) {
    let mut reader = open(Path::new(path), None).unwrap();
    let items = reader.by_ref().map(describe).collect();
    (items, reader.skipped().to_string())
}

fn describe(item: Result<ScanRecord, ReadError>) -> String {
    match item {
        Ok(r) => format!("ok {}", r.line.unwrap_or(0)),
        Err(e) => e.to_string(),
    }
}

fn outcome_of(name: &str, format: Format, data: &[u8]) -> Vec<String> {
    from_reader(name, Cursor::new(data.to_vec()), format)
        .unwrap()
        .map(describe)
        .collect()
}

#[test]
fn malformed_json_names_line_and_column() {
    let (items, skipped) = outcome("tests/fixtures/bad_malformed.json");
    assert_eq!(
        items,
        vec!["tests/fixtures/bad_malformed.json:3:26: malformed JSON: key must be a string"]
    );
    assert_eq!(skipped, "1 × malformed JSON");
}

#[test]
fn ranges_of_the_wrong_type_name_the_field_and_reading_goes_on() {
    let (items, skipped) = outcome("tests/fixtures/bad_ranges_type.jsonl");
    assert_eq!(
        items,
        vec![
            "ok 1",
            "tests/fixtures/bad_ranges_type.jsonl:2:80: ranges: expected an array of numbers \
             or null, found a string (\"1.0 2.0\")",
            "tests/fixtures/bad_ranges_type.jsonl:3:80: ranges[1]: expected a number or null, \
             found a string (\"x\")",
            "ok 4",
        ]
    );
    assert_eq!(skipped, "2 × bad field");
}

#[test]
fn zero_angle_increment_is_an_invalid_scan_at_its_line() {
    let (items, _) = outcome("tests/fixtures/bad_increment_zero.json");
    assert_eq!(
        items,
        vec![
            "tests/fixtures/bad_increment_zero.json:3:3: invalid scan: angle_increment must be \
             finite and non-zero, got 0"
        ]
    );
}

#[test]
fn csv_row_with_a_missing_column_names_the_line() {
    let (items, _) = outcome("tests/fixtures/bad_missing_column.csv");
    assert_eq!(
        items,
        vec![
            "tests/fixtures/bad_missing_column.csv:4: expected 3 columns \
             (index,angle_rad,range_m), found 2 columns: `2,0.2`"
        ]
    );
}

#[test]
fn truncated_dat_line_names_the_line_and_reading_goes_on() {
    let (items, skipped) = outcome("tests/fixtures/bad_truncated.dat");
    assert_eq!(
        items,
        vec![
            "ok 1",
            "tests/fixtures/bad_truncated.dat:2: expected 707 tokens (timestamp, 23 fields, \
             682 ranges, 1 trailing), found 412",
            "ok 3",
        ]
    );
    assert_eq!(skipped, "1 × malformed record");
}

#[test]
fn angle_max_must_agree_with_the_beams() {
    let (items, _) = outcome("tests/fixtures/bad_angle_max.json");
    assert_eq!(
        items,
        vec![
            "tests/fixtures/bad_angle_max.json:1:20: angle_max: expected angle_min + (n - 1) * \
             angle_increment = 0.5 rad for n = 3 ranges (within 0.125 rad), found 1"
        ]
    );
}

#[test]
fn csv_non_uniform_angles_name_the_row() {
    let (items, _) = outcome("tests/fixtures/bad_nonuniform.csv");
    assert_eq!(items.len(), 1);
    assert!(
        items[0].starts_with("tests/fixtures/bad_nonuniform.csv:4: angle_rad: expected uniform"),
        "{}",
        items[0]
    );
    assert!(items[0].ends_with("found 0.25"), "{}", items[0]);
}

#[test]
fn json_framing_errors() {
    let scan =
        r#"{"angle_min": 0, "angle_increment": 0.1, "range_min": 0, "range_max": 1, "ranges": []}"#;
    let cases: Vec<(&str, Vec<u8>, Vec<&str>)> = vec![
        (
            "empty.json",
            vec![],
            vec![
                "empty.json:1:1: expected a JSON scan object `{` or an array `[` of them, found \
                 an empty input",
            ],
        ),
        (
            "scalar.json",
            b"42".to_vec(),
            vec![
                "scalar.json:1:1: expected a JSON scan object `{` or an array `[` of them, \
                 found `4`",
            ],
        ),
        (
            "array.json",
            format!("[1, {scan}, ]").into_bytes(),
            vec![
                "array.json:1:2: expected a scan object `{...}`, found a number (1)",
                "ok 1",
                "array.json:1:93: expected a scan object after `,`, found `]`",
            ],
        ),
        (
            "two.json",
            format!("{scan} {{}}").into_bytes(),
            vec![
                "ok 1",
                "two.json:1:88: expected the end of the input after the scan object (for \
                 several scans use a top-level array, or JSONL with one object per line), found \
                 `{`",
            ],
        ),
        (
            "truncated.json",
            br#"[{"angle_min": 0, "ranges": [1,"#.to_vec(),
            vec!["truncated.json:1:31: malformed JSON: EOF while parsing a value"],
        ),
        (
            "nan.json",
            br#"{"angle_min": 0, "angle_increment": 0.1, "range_min": 0, "range_max": 1, "ranges": [1, nan]}"#.to_vec(),
            vec![
                "nan.json:1:89: malformed JSON: expected ident (`nan` is not JSON; write null \
                 for a beam without return, or Infinity for one that saw nothing within range)",
            ],
        ),
        (
            "nan-increment.json",
            br#"{"angle_min": 0, "angle_increment": NaN, "range_min": 0, "range_max": 1, "ranges": [1]}"#.to_vec(),
            vec![
                "nan-increment.json:1:18: angle_increment: expected a number, found `NaN`",
            ],
        ),
        (
            "inf-increment.json",
            br#"{"angle_min": 0, "angle_increment": Infinity, "range_min": 0, "range_max": 1, "ranges": [1]}"#.to_vec(),
            vec![
                "inf-increment.json:1:18: invalid scan: angle_increment must be finite and \
                 non-zero, got inf",
            ],
        ),
        (
            // An error after a `NaN` on the same line is placed in the text as written.
            "after-nan.json",
            br#"{"angle_min": 0, "angle_increment": 0.1, "range_min": 0, "range_max": 1, "ranges": [NaN, 1,]}"#.to_vec(),
            vec!["after-nan.json:1:92: malformed JSON: trailing comma"],
        ),
        (
            // A stamp or a pose must be finite, as in CSV.
            "inf-stamp.json",
            br#"{"angle_min": 0, "angle_increment": 0.1, "range_min": 0, "range_max": 1, "ranges": [1], "stamp": Infinity}"#.to_vec(),
            vec!["inf-stamp.json:1:89: stamp: expected a finite number or null, found `Infinity`"],
        ),
        (
            "inf-pose.json",
            br#"{"angle_min": 0, "angle_increment": 0.1, "range_min": 0, "range_max": 1, "ranges": [1], "odometry": {"x": -Infinity, "y": 0, "theta": 0}}"#.to_vec(),
            vec!["inf-pose.json:1:89: odometry.x: expected a finite number, found `-Infinity`"],
        ),
        (
            "nan-pose.json",
            br#"{"angle_min": 0, "angle_increment": 0.1, "range_min": 0, "range_max": 1, "ranges": [1], "pose": {"x": NaN, "y": 0, "theta": 0}}"#.to_vec(),
            vec![
                "nan-pose.json:1:89: pose.x: expected a finite number, found null (`NaN` is read \
                 as null)",
            ],
        ),
        (
            // The strings that stand in for Python's infinities are strings in strict JSON.
            "standin.json",
            br#"{"angle_min": 0, "angle_increment": 0.1, "range_min": 0, "range_max": 1, "ranges": [1, "+infin"]}"#.to_vec(),
            vec![
                "standin.json:1:74: ranges[1]: expected a number or null, found a string \
                 (\"+infin\")",
            ],
        ),
        (
            "pose.json",
            br#"{"angle_min": 0, "angle_increment": 0.1, "range_min": 0, "range_max": 1, "ranges": [1], "pose": {"x": 1}}"#.to_vec(),
            vec!["pose.json:1:89: pose.y: expected a finite number, found nothing (the field is missing)"],
        ),
        (
            "limits.json",
            br#"{"angle_min": 0, "angle_increment": 0.1, "range_min": 2, "range_max": 1, "ranges": [1]}"#.to_vec(),
            vec![
                "limits.json:1:42: invalid scan: range limits must satisfy 0 <= range_min < \
                 range_max (finite), got 2..1",
            ],
        ),
    ];
    for (name, data, want) in cases {
        assert_eq!(outcome_of(name, Format::Json, &data), want, "{name}");
    }
}

#[test]
fn jsonl_bad_lines_are_errors_and_reading_goes_on() {
    let data = b"{\"angle_min\": 0}\n[1]\n\xff\xfe\n{\"angle_min\": 0, \"angle_increment\": 0.1, \"range_min\": 0, \"range_max\": 1, \"ranges\": [1]}\n";
    let mut reader = from_reader("x.jsonl", Cursor::new(data.to_vec()), Format::Jsonl).unwrap();
    let items: Vec<String> = reader.by_ref().map(describe).collect();
    assert_eq!(
        items,
        vec![
            "x.jsonl:1:1: angle_increment: expected a number, found nothing (the field is \
             missing)",
            "x.jsonl:2:1: expected a scan object `{...}`, found an array of 1 value",
            "x.jsonl:3:1: expected UTF-8 text, found the byte 0xff",
            "ok 4",
        ]
    );
    assert_eq!(reader.skipped().total(), 3);
    assert_eq!(reader.records(), 1);
}

#[test]
fn csv_errors() {
    let cases: Vec<(&str, &[u8], &str)> = vec![
        (
            "noheader.csv",
            b"0,1,2\n",
            "noheader.csv:1: expected the header `index,angle_rad,range_m` (or \
             `index,angle_rad,range_m,intensity`), or `angle_rad,range_m` for readings at their \
             own bearings (`angle_deg`, `range_mm` in those units), found `0,1,2`",
        ),
        (
            "empty.csv",
            b"",
            "empty.csv:1: expected the header `index,angle_rad,range_m`, found the end of the input",
        ),
        (
            "one.csv",
            b"index,angle_rad,range_m\n0,1,2\n",
            "one.csv:3: expected at least 2 data rows (to derive angle_increment), or the \
             comments `# angle_min:` and `# angle_increment:`, found 1 row and then the end of \
             the input",
        ),
        (
            "gap.csv",
            b"index,angle_rad,range_m\n0,1,2\n2,1.1,2\n",
            "gap.csv:3: index: expected 1 (rows are numbered from 0 without gaps), found `2`",
        ),
        (
            "range.csv",
            b"index,angle_rad,range_m\n0,1,2\n1,1.1,x\n",
            "range.csv:3: range_m: expected a range in metres, or empty or `nan` for no return, \
             found `x`",
        ),
        (
            "angle.csv",
            b"index,angle_rad,range_m\n0,1,2\n1,inf,2\n",
            "angle.csv:3: angle_rad: expected a finite angle in radians, found `inf`",
        ),
        (
            "same.csv",
            b"index,angle_rad,range_m\n0,1,2\n1,1,2\n",
            "same.csv:3: angle_rad: expected angles that change from row to row, found an \
             angle increment of 0 rad",
        ),
        (
            "extra.csv",
            b"index,angle_rad,range_m\n0,1,2\n1,1.1,2,9\n",
            "extra.csv:3: expected 3 columns (index,angle_rad,range_m), found 4 columns: \
             `1,1.1,2,9`",
        ),
        (
            "off.csv",
            b"# angle_increment: 0.1\nindex,angle_rad,range_m\n0,1,2\n1,1.2,2\n",
            "off.csv:4: angle_rad: expected uniform angles: 1.1 (= 1 + 1 * 0.1) within 0.001 \
             (readings at their own bearings: the header `angle_rad,range_m`, without `index`), \
             found 1.2",
        ),
        (
            "amin.csv",
            b"# angle_min: 0.5\nindex,angle_rad,range_m\n0,0,2\n1,0.25,2\n",
            "amin.csv:3: angle_rad: expected uniform angles: 0.5 (= 0.5 + 0 * 0.25) within \
             0.0025 (readings at their own bearings: the header `angle_rad,range_m`, without \
             `index`), found 0",
        ),
        (
            "meta.csv",
            b"# range_max: far\nindex,angle_rad,range_m\n",
            "meta.csv:1: # range_max: expected a finite number, found `far`",
        ),
    ];
    for (name, data, want) in cases {
        assert_eq!(outcome_of(name, Format::Csv, data), vec![want], "{name}");
    }
}

#[test]
fn dat_bad_tokens_name_the_token() {
    let mut tokens = vec!["0"; 707];
    tokens[0] = "12x";
    let line = tokens.join(" ");
    let items = outcome_of("x.dat", Format::BreezyDat, format!("\n{line}\n").as_bytes());
    assert_eq!(
        items,
        vec!["x.dat:2: token 0 (timestamp): expected an integer (microseconds), found `12x`"]
    );
    tokens[0] = "5";
    tokens[30] = "1.5";
    let items = outcome_of("x.dat", Format::BreezyDat, tokens.join(" ").as_bytes());
    assert_eq!(
        items,
        vec![
            "x.dat:1: token 30 (range of beam 6): expected an integer from 0 to 262143 \
             (millimetres, the most a SCIP reading carries), found `1.5`"
        ]
    );
    // Readings no Hokuyo gives are corrupt tokens, not ranges out of the window.
    for (token, shown) in [
        ("-500", "`-500`"),
        ("262144", "`262144`"),
        ("99999999999", "`99999999999`"),
    ] {
        tokens[30] = token;
        let items = outcome_of("x.dat", Format::BreezyDat, tokens.join(" ").as_bytes());
        assert_eq!(
            items,
            vec![format!(
                "x.dat:1: token 30 (range of beam 6): expected an integer from 0 to 262143 \
                 (millimetres, the most a SCIP reading carries), found {shown}"
            )]
        );
    }
    tokens[30] = "262143";
    let items = outcome_of("x.dat", Format::BreezyDat, tokens.join(" ").as_bytes());
    assert_eq!(items, vec!["ok 1"]);
}

#[test]
fn truncated_gzip_is_a_read_error_naming_the_line_and_ends_the_reader() {
    use std::io::Write;
    let text = std::fs::read("tests/fixtures/two_scans.dat").unwrap();
    let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    enc.write_all(&text).unwrap();
    let gz = enc.finish().unwrap();
    let cut = gz[..gz.len() * 2 / 3].to_vec();
    let mut reader = from_reader("cut.dat.gz", Cursor::new(cut), Format::BreezyDat).unwrap();
    let items: Vec<String> = reader.by_ref().map(describe).collect();
    // How much of a cut stream inflates before the error depends on the inflater's buffering:
    // whole lines before the cut come out, then one read error naming the line it stopped in.
    let (last, before) = items.split_last().unwrap();
    assert!(before.iter().all(|i| i.starts_with("ok ")), "{items:?}");
    let line = before.len() + 1;
    assert!(
        last.starts_with(&format!("cut.dat.gz:{line}: read failed: ")),
        "{items:?}"
    );
    assert!(before.len() < 2, "{items:?}");
    // A failed read is no bad record: it ends the reading and is not counted as a skip.
    assert_eq!(reader.skipped().to_string(), "none");
}

#[test]
fn a_corrupt_gzip_stream_is_no_bad_record_and_no_skip() {
    use std::io::Write;
    let text = std::fs::read("tests/fixtures/two_scans.dat").unwrap();
    let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    enc.write_all(&text).unwrap();
    let mut gz = enc.finish().unwrap();
    // The stored CRC-32 of the data (the trailer's first 4 bytes), flipped: every line
    // inflates, then the stream fails its check.
    let crc = gz.len() - 8;
    gz[crc] ^= 0xff;
    let mut reader = from_reader("crc.dat.gz", Cursor::new(gz), Format::BreezyDat).unwrap();
    let items: Vec<Result<_, _>> = reader.by_ref().collect();
    assert_eq!(items.len(), 3, "{items:?}");
    assert!(items[..2].iter().all(Result::is_ok), "{items:?}");
    let e = items[2].as_ref().unwrap_err();
    assert!(!e.is_bad_record(), "{e}");
    assert_eq!(e.reason(), "read failed");
    assert!(
        e.to_string().starts_with("crc.dat.gz:3: read failed: "),
        "{e}"
    );
    assert_eq!(reader.skipped().to_string(), "none");
    assert_eq!(reader.records(), 2);
    let bad = ReadError::Syntax {
        pos: laserlines_io::SourcePos::line("x.dat", 1),
        expected: "707 tokens".to_owned(),
        found: "3".to_owned(),
    };
    assert!(bad.is_bad_record());
}

#[test]
fn open_errors_name_the_file() {
    let e = open(Path::new("scans.txt"), None).unwrap_err();
    assert!(matches!(e, ReadError::UnknownFormat { .. }));
    assert!(e.to_string().starts_with(
        "scans.txt: cannot tell the scan format from the name (found extension .txt)"
    ));
    let e = open(Path::new("-"), None).unwrap_err();
    assert!(e.to_string().starts_with("-: cannot tell the scan format"));
    let e = open(Path::new("tests/fixtures/does-not-exist.json"), None).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("tests/fixtures/does-not-exist.json: cannot open: "),
        "{e}"
    );
    assert_eq!(e.file(), "tests/fixtures/does-not-exist.json");
    assert_eq!(e.line(), None);
}

#[test]
fn errors_expose_file_and_line() {
    let err = from_reader(
        "x.dat",
        Cursor::new(b"\n1 2 3\n".to_vec()),
        Format::BreezyDat,
    )
    .unwrap()
    .next()
    .unwrap()
    .unwrap_err();
    assert_eq!(err.file(), "x.dat");
    assert_eq!(err.line(), Some(2));
    assert_eq!(err.reason(), "malformed record");
}

#[test]
fn an_angle_max_off_a_tiny_increment_reads_in_few_digits() {
    let scan = br#"{"angle_min": 0, "angle_increment": 1e-300, "angle_max": 1.0, "range_min": 0, "range_max": 2, "ranges": [1, 1]}"#;
    let items = outcome_of("tiny.json", Format::Json, scan);
    assert_eq!(items.len(), 1);
    assert!(
        items[0].contains(
            "angle_min + (n - 1) * angle_increment = 1e-300 rad for n = 2 ranges (within 5e-301 rad)"
        ),
        "{}",
        items[0]
    );
    assert!(items[0].len() < 300, "{}", items[0]);
}
