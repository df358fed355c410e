//! CARMEN logs: the beam angle convention on hand-made logs, bad lines, and every real log of
//! `../shared/data/real` (the 13 corrected Radish logs and the Freiburg benchmark's MIT CSAIL
//! log), checked against counts taken from the files with a plain text scan and against their
//! PROVENANCE.md. The real-data tests are skipped, with a notice, when that folder is absent.

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::collections::HashSet;
use std::f64::consts::PI;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};

use laserlines_io::carmen::{NO_RETURN_BANDS, RANGE_MAX, default_geometry, is_no_return};
use laserlines_io::{Format, ReadOptions, ScanRecord, open, open_with};

#[path = "../../../tests/shared_data.rs"]
mod shared_data;

const FIXTURES: &str = "tests/fixtures/carmen";

fn read_all(path: &Path, topic: Option<&str>) -> (Vec<ScanRecord>, String) {
    let mut reader = open_with(path, &ReadOptions::format(None).with_topic(topic)).unwrap();
    assert_eq!(reader.format(), Format::Carmen);
    let records = reader.by_ref().map(|r| r.unwrap()).collect();
    (records, reader.skipped().to_string())
}

/// Every valid beam of the scan as a point in the laser frame.
fn points(record: &ScanRecord) -> Vec<(usize, f64, f64)> {
    let s = &record.scan;
    let w = s.range_window(None);
    (0..s.len())
        .filter(|&i| w.contains(s.ranges[i]))
        .map(|i| {
            let (r, a) = (s.ranges[i], s.angle(i));
            (i, r * a.cos(), r * a.sin())
        })
        .collect()
}

/// The fixtures' walls: y = 1.5 m on the left, x = 4 m ahead; each valid point lies on the
/// nearer of the two along its beam.
fn assert_on_walls(record: &ScanRecord, expected_valid: usize) {
    let pts = points(record);
    assert_eq!(pts.len(), expected_valid, "line {:?}", record.line);
    for (i, x, y) in pts {
        let on_left = (y - 1.5).abs() < 1e-5 && x < 4.0 + 1e-5;
        let on_ahead = (x - 4.0).abs() < 1e-5 && y < 1.5 + 1e-5;
        assert!(
            on_left || on_ahead,
            "line {:?} beam {i}: ({x}, {y}) is on no wall",
            record.line
        );
    }
}

#[test]
fn flaser_angles_follow_the_documented_convention() {
    let (records, skipped) = read_all(&Path::new(FIXTURES).join("wall_left.clf"), None);
    assert_eq!(records.len(), 4);
    assert_eq!(skipped, "1 × NEFF message (not a scan)");
    let deg = PI / 180.0;
    // 180 beams: -90 deg, 1 deg apart, the last at +89 deg; beams -60..=89 deg see a wall.
    let s = &records[0].scan;
    assert_eq!(
        (s.len(), s.angle_min, s.angle_increment),
        (180, -PI / 2.0, deg)
    );
    assert!((s.angle_max() - 89.0 * deg).abs() < 1e-12);
    assert_on_walls(&records[0], 150);
    // 181 beams: -90..=+90 deg by 1 deg.
    assert_eq!(records[1].scan.angle_increment, deg);
    assert!((records[1].scan.angle_max() - PI / 2.0).abs() < 1e-12);
    assert_on_walls(&records[1], 151);
    // 361 beams: 0.5 deg.
    assert_eq!(records[2].scan.angle_increment, deg / 2.0);
    assert_on_walls(&records[2], 301);
    // 91 beams: spanning 180 deg.
    assert!((records[3].scan.angle_increment - 2.0 * deg).abs() < 1e-15);
    assert_on_walls(&records[3], 76);
    assert_eq!(
        default_geometry(91),
        (records[3].scan.angle_min, records[3].scan.angle_increment)
    );
    // Markers (81.91, 50.0, 32.767) are no returns, never points.
    for r in &records {
        assert!(
            r.scan
                .ranges
                .iter()
                .all(|x| x.is_finite() || *x == f64::INFINITY)
        );
        assert_eq!(r.scan.range_min, 0.0);
        assert_eq!(r.scan.range_max, RANGE_MAX);
    }
    // Stamps (ipc_timestamp), poses (the first triple), lines.
    let stamps: Vec<_> = records.iter().map(|r| r.scan.stamp.unwrap()).collect();
    assert_eq!(stamps, vec![1.0, 2.0, 3.0, 4.0]);
    assert_eq!(records[1].pose.unwrap().x, 1.0);
    assert_eq!(records[1].pose.unwrap().theta, 0.5);
    let lines: Vec<_> = records.iter().map(|r| r.line.unwrap()).collect();
    assert_eq!(lines, vec![3, 6, 8, 9]);
}

#[test]
fn param_lines_set_fov_and_resolution_and_topics_choose_the_laser() {
    let path = Path::new(FIXTURES).join("wall_param.clf");
    let (front, skipped) = read_all(&path, None);
    assert_eq!(front.len(), 2);
    assert_eq!(skipped, "1 × RLASER scan (another laser)");
    let s = &front[0].scan;
    assert_eq!(s.len(), 201);
    assert!((s.angle_min + 50f64.to_radians()).abs() < 1e-12);
    assert!((s.angle_increment - 0.5f64.to_radians()).abs() < 1e-15);
    assert_on_walls(&front[0], 201);
    let (rear, skipped) = read_all(&path, Some("RLASER"));
    assert_eq!(rear.len(), 1);
    assert_eq!(skipped, "2 × FLASER scan (another laser)");
    let s = &rear[0].scan;
    assert_eq!(s.len(), 37);
    assert!((s.angle_min + PI / 2.0).abs() < 1e-12);
    assert!((s.angle_increment - 5f64.to_radians()).abs() < 1e-12);
    assert_on_walls(&rear[0], 31);
}

#[test]
fn a_line_with_too_few_fields_is_an_error_naming_file_and_line() {
    let path = Path::new(FIXTURES).join("bad_short_flaser.clf");
    let mut reader = open(&path, None).unwrap();
    let items: Vec<_> = reader.by_ref().collect();
    assert_eq!(items.len(), 3);
    assert_eq!(items[0].as_ref().unwrap().line, Some(2));
    let e = items[1].as_ref().unwrap_err().to_string();
    assert_eq!(
        e,
        "tests/fixtures/carmen/bad_short_flaser.clf:3: expected 192 tokens for FLASER with \
         181 ranges (the name, n, n ranges, x y theta odom_x odom_y odom_theta ipc_timestamp \
         ipc_hostname logger_timestamp), found 191 tokens"
    );
    assert_eq!(items[2].as_ref().unwrap().line, Some(4));
    assert_eq!(reader.skipped().to_string(), "1 × malformed record");
}

#[test]
fn topics_are_refused_by_single_stream_formats() {
    let e = open_with(
        Path::new("tests/fixtures/scans.jsonl"),
        &ReadOptions::format(None).with_topic(Some("/scan")),
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "tests/fixtures/scans.jsonl: cannot read topic `/scan`: expected no topic: the jsonl \
         format holds one stream of scans"
    );
}

#[test]
fn no_return_bands_are_narrow() {
    // Every band holds its marker; nothing between the bands is a marker.
    for (lo, hi) in NO_RETURN_BANDS {
        assert!(lo < hi);
    }
    for r in [5.0, 25.38, 32.63, 40.0, 49.96, 51.36, 60.0, 79.34, 81.82] {
        assert!(!is_no_return(r), "{r}");
    }
}

// ---- real logs ----

fn real_dir() -> Option<PathBuf> {
    let dir = shared_data::path("real");
    for sub in ["carmen-radish-corrected", "mit-csail-clf"] {
        shared_data::available(dir.join(sub), "the real CARMEN log tests")?;
    }
    Some(dir)
}

/// One log: its path under the real-data folder, the scans and beams PROVENANCE.md states,
/// and the marker it names.
struct Log {
    path: &'static str,
    scans: usize,
    beams: usize,
    /// Valid readings at or above 50 m: genuine long readings beyond the markers' bands (the
    /// Freiburg campus is outdoors; Freiburg 101 and Belgioioso have a few far echoes).
    valid_from_50m: usize,
}

const LOGS: [Log; 14] = [
    Log {
        path: "carmen-radish-corrected/intel-corrected.log.gz",
        scans: 910,
        beams: 180,
        valid_from_50m: 0,
    },
    Log {
        path: "carmen-radish-corrected/aces-corrected.log.gz",
        scans: 440,
        beams: 180,
        valid_from_50m: 0,
    },
    Log {
        path: "carmen-radish-corrected/csail-corrected.log.gz",
        scans: 406,
        beams: 361,
        valid_from_50m: 0,
    },
    Log {
        path: "carmen-radish-corrected/freiburg-079-corrected.log.gz",
        scans: 4791,
        beams: 360,
        valid_from_50m: 0,
    },
    Log {
        path: "carmen-radish-corrected/freiburg-101-corrected.log.gz",
        scans: 292,
        beams: 360,
        valid_from_50m: 11,
    },
    Log {
        path: "carmen-radish-corrected/freiburg-campus-corrected.log.gz",
        scans: 2008,
        beams: 360,
        valid_from_50m: 18210,
    },
    Log {
        path: "carmen-radish-corrected/infinite-corridor-corrected.log.gz",
        scans: 1941,
        beams: 180,
        valid_from_50m: 0,
    },
    Log {
        path: "carmen-radish-corrected/seattle-corrected.log.gz",
        scans: 241,
        beams: 361,
        valid_from_50m: 0,
    },
    Log {
        path: "carmen-radish-corrected/orebro-corrected.log.gz",
        scans: 237,
        beams: 181,
        valid_from_50m: 0,
    },
    Log {
        path: "carmen-radish-corrected/belgioioso-corrected.log.gz",
        scans: 395,
        beams: 361,
        valid_from_50m: 26,
    },
    Log {
        path: "carmen-radish-corrected/fhw-corrected.log.gz",
        scans: 488,
        beams: 180,
        valid_from_50m: 0,
    },
    Log {
        path: "carmen-radish-corrected/edmonton-corrected.log.gz",
        scans: 340,
        beams: 180,
        valid_from_50m: 0,
    },
    Log {
        path: "carmen-radish-corrected/acapulco-corrected.log.gz",
        scans: 861,
        beams: 181,
        valid_from_50m: 0,
    },
    Log {
        path: "mit-csail-clf/mit-csail.clf.gz",
        scans: 1988,
        beams: 361,
        valid_from_50m: 0,
    },
];

/// What a plain text scan of the decompressed file finds: laser lines, the raw range tokens
/// of the first laser line, and every distinct range token of the log.
struct TextCount {
    laser_lines: usize,
    neff_lines: usize,
    first_ranges: Vec<String>,
    marker_tokens: HashSet<String>,
}

fn count_text(path: &Path) -> TextCount {
    let file = std::fs::File::open(path).unwrap();
    let mut text = String::new();
    flate2::read::MultiGzDecoder::new(file)
        .read_to_string(&mut text)
        .unwrap();
    let mut count = TextCount {
        laser_lines: 0,
        neff_lines: 0,
        first_ranges: Vec::new(),
        marker_tokens: HashSet::new(),
    };
    for line in BufReader::new(text.as_bytes()).lines() {
        let line = line.unwrap();
        if line.starts_with("FLASER ") || line.starts_with("ROBOTLASER1 ") {
            count.laser_lines += 1;
            let tokens: Vec<&str> = line.split(' ').filter(|t| !t.is_empty()).collect();
            let n: usize = tokens[1].parse().unwrap();
            if count.first_ranges.is_empty() {
                count.first_ranges = tokens[2..2 + n].iter().map(|t| (*t).to_owned()).collect();
            }
            for t in &tokens[2..2 + n] {
                // The markers PROVENANCE.md names: 81.91 / 81.83 / 81.87..81.89, 50.0, ~51.x,
                // 32.767 and its neighbours.
                if t.starts_with("81.8")
                    || t.starts_with("81.9")
                    || *t == "50"
                    || *t == "50.0"
                    || t.starts_with("51.")
                    || t.starts_with("32.76")
                {
                    count.marker_tokens.insert((*t).to_owned());
                }
            }
        } else if line.starts_with("NEFF ") {
            count.neff_lines += 1;
        }
    }
    count
}

#[test]
fn every_real_log_reads_completely_with_its_markers_as_no_returns() {
    let Some(dir) = real_dir() else { return };
    let mut total = 0;
    for log in &LOGS {
        let path = dir.join(log.path);
        let text = count_text(&path);
        let mut reader = open(&path, None).unwrap();
        let mut records = 0usize;
        let mut valid_from_50m = 0usize;
        let mut last_line = 0;
        let mut markers_seen = 0usize;
        for item in reader.by_ref() {
            let r = item.unwrap_or_else(|e| panic!("{}: {e}", log.path));
            let s = &r.scan;
            assert_eq!(s.len(), log.beams, "{}", log.path);
            assert!(r.pose.unwrap().is_finite());
            assert!(s.stamp.unwrap().is_finite());
            // File order.
            assert!(r.line.unwrap() > last_line);
            last_line = r.line.unwrap();
            if records == 0 {
                // The reader's ranges are the file's numbers, markers turned into +inf.
                for (raw, got) in text.first_ranges.iter().zip(&s.ranges) {
                    let want: f64 = raw.parse().unwrap();
                    if is_no_return(want) {
                        assert_eq!(*got, f64::INFINITY, "{}: {raw}", log.path);
                    } else {
                        assert_eq!(*got, want, "{}: {raw}", log.path);
                    }
                }
            }
            let w = s.range_window(None);
            for &x in &s.ranges {
                if x == f64::INFINITY {
                    markers_seen += 1;
                    continue;
                }
                assert!(w.contains(x), "{}: reading {x} is not valid", log.path);
                assert!(!is_no_return(x));
                if x >= 50.0 {
                    valid_from_50m += 1;
                }
                if log.path.contains("orebro") {
                    assert!(x < 32.759, "orebro reading {x} is a 32.767 marker");
                }
            }
            records += 1;
        }
        let skipped = reader.skipped();
        eprintln!("{}: {records} scans, skipped: {skipped}", log.path);
        assert_eq!(
            records, text.laser_lines,
            "{}: scans vs FLASER lines",
            log.path
        );
        assert_eq!(records, log.scans, "{}: scans vs PROVENANCE.md", log.path);
        assert_eq!(valid_from_50m, log.valid_from_50m, "{}", log.path);
        // Nothing but NEFF is skipped (the MIT CSAIL benchmark log has none).
        assert_eq!(
            skipped.get("NEFF message (not a scan)"),
            text.neff_lines as u64
        );
        assert_eq!(
            skipped.total(),
            text.neff_lines as u64,
            "{}: {skipped}",
            log.path
        );
        // Every marker token of the file is a no return.
        assert!(!text.marker_tokens.is_empty(), "{}", log.path);
        for t in &text.marker_tokens {
            let r: f64 = t.parse().unwrap();
            let marker = r >= 81.83 || (50.0..=51.3).contains(&r) || (32.759..=32.767).contains(&r);
            if marker {
                assert!(
                    is_no_return(r),
                    "{}: marker {t} is read as a wall",
                    log.path
                );
            }
        }
        assert!(markers_seen > 0, "{}", log.path);
        total += records;
    }
    assert_eq!(total, 13_350 + 1_988);
}

#[test]
fn real_log_geometry_and_time_stamps() {
    let Some(dir) = real_dir() else { return };
    let deg = PI / 180.0;
    let first = |path: &str| {
        open(&dir.join(path), None)
            .unwrap()
            .next()
            .unwrap()
            .unwrap()
    };
    // csail: PARAM fov 3.14159 rad and resolution 0.5 deg.
    #[allow(clippy::approx_constant)] // the log's PARAM value as written, not pi
    let fov = 3.14159;
    let s = first("carmen-radish-corrected/csail-corrected.log.gz").scan;
    assert!((s.angle_min + fov / 2.0).abs() < 1e-12);
    assert!((s.angle_increment - deg / 2.0).abs() < 1e-15);
    // Freiburg 079: resolution 0.5 deg, 360 beams from -90 deg.
    let s = first("carmen-radish-corrected/freiburg-079-corrected.log.gz").scan;
    assert_eq!(s.angle_min, -PI / 2.0);
    assert!((s.angle_increment - deg / 2.0).abs() < 1e-15);
    // Intel: no PARAM, 180 beams, 1 deg.
    let r = first("carmen-radish-corrected/intel-corrected.log.gz");
    assert_eq!((r.scan.angle_min, r.scan.angle_increment), (-PI / 2.0, deg));
    assert_eq!(r.scan.stamp, Some(32.9068));
    let p = r.pose.unwrap();
    assert_eq!((p.x, p.y, p.theta), (0.600266, -0.0320327, -0.354665));
    // MIT CSAIL: absolute ipc time stamps, strictly increasing, and every time stamp of the
    // benchmark's ground-truth relations is the stamp of one of its scans.
    let records: Vec<ScanRecord> = open(&dir.join("mit-csail-clf/mit-csail.clf.gz"), None)
        .unwrap()
        .map(|r| r.unwrap())
        .collect();
    assert_eq!(records[0].scan.stamp, Some(1134864629.895182));
    assert_eq!(records.last().unwrap().scan.stamp, Some(1134865053.892206));
    assert!(
        records
            .windows(2)
            .all(|w| w[0].scan.stamp < w[1].scan.stamp)
    );
    assert_eq!(records[0].pose.unwrap().x, 576.536523);
    let relations = dir.join("freiburg-slam-benchmark-relations/mit-csail.relations");
    if relations.is_file() {
        // The relations print stamps to 10 us (five decimals): each must be a scan's stamp
        // rounded, within half of 10 us plus the f64 resolution near 1.1e9 s (0.24 us).
        let stamps: Vec<f64> = records.iter().map(|r| r.scan.stamp.unwrap()).collect();
        let text = std::fs::read_to_string(relations).unwrap();
        let mut checked = 0;
        for line in text.lines().filter(|l| !l.trim().is_empty()) {
            let mut t = line.split_ascii_whitespace();
            for _ in 0..2 {
                let stamp: f64 = t.next().unwrap().parse().unwrap();
                let i = stamps.partition_point(|s| *s < stamp);
                let near = [i.saturating_sub(1), i.min(stamps.len() - 1)]
                    .iter()
                    .any(|&j| (stamps[j] - stamp).abs() <= 5e-6 + 5e-7);
                assert!(near, "relation stamp {stamp} is no scan's stamp");
                checked += 1;
            }
        }
        assert_eq!(checked, 2 * 1172);
    }
    // Broken stamps are kept as written, in file order: Freiburg campus says 0 everywhere.
    let campus: Vec<f64> = open(
        &dir.join("carmen-radish-corrected/freiburg-campus-corrected.log.gz"),
        None,
    )
    .unwrap()
    .take(5)
    .map(|r| r.unwrap().scan.stamp.unwrap())
    .collect();
    assert_eq!(campus, vec![0.0; 5]);
}
