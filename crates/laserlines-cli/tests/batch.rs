//! `laserlines extract` as a parallel batch: the output is in input order and the same for
//! any number of threads, across many batches, with bad records skipped in place; CARMEN logs
//! and ROS bags with `--topic`; the summary; bad input.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use serde_json::Value;

mod common;
use common::{bin, io_fixture, run, shared_data, stderr, tmp};

fn jsonl(path: &Path) -> Vec<Value> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

/// A CARMEN log of `scans` FLASER lines, each a room of its own size seen from its own pose
/// (so every scan's lines differ), with a malformed line every 97 scans and other messages
/// between them.
fn synthetic_log(scans: usize) -> String {
    let mut log = String::from("# synthetic CARMEN log\n");
    for k in 0..scans {
        let half_width = 1.5 + (k % 17) as f64 * 0.1;
        let ahead = 3.0 + (k % 11) as f64 * 0.2;
        let mut ranges = String::new();
        for i in 0..181 {
            let a = (-90.0 + i as f64).to_radians();
            let to_side = if a.sin().abs() > 1e-9 {
                half_width / a.sin().abs()
            } else {
                f64::INFINITY
            };
            let to_front = if a.cos() > 1e-9 {
                ahead / a.cos()
            } else {
                f64::INFINITY
            };
            let r = to_side.min(to_front).min(81.91);
            write!(ranges, "{r:.3} ").unwrap();
        }
        let t = k as f64 * 0.1;
        writeln!(log, "FLASER 181 {ranges}{t} 0 0 {t} 0 0 {t} host {t}").unwrap();
        writeln!(log, "ODOM {t} 0 0 0 0 0 {t} host {t}").unwrap();
        if k % 97 == 50 {
            log.push_str("FLASER 181 1 2 3\n");
        }
    }
    log
}

#[test]
fn parallel_output_is_in_input_order_and_equals_the_sequential_one() {
    let input = tmp("synthetic.clf");
    let scans = 1000; // four batches
    std::fs::write(&input, synthetic_log(scans)).unwrap();
    let mut outputs = Vec::new();
    for jobs in ["1", "2", "5"] {
        let out = tmp(&format!("synthetic-{jobs}.jsonl"));
        let o = run(bin()
            .args(["extract", "--skip-bad", "--jobs", jobs, "-o"])
            .arg(&out)
            .arg(&input));
        assert!(o.status.success(), "{}", stderr(&o));
        let err = stderr(&o);
        let bad = (0..scans).filter(|k| k % 97 == 50).count();
        assert!(err.contains(&format!("{scans} scans")), "{err}");
        assert!(
            err.contains(&format!("skipped: {bad} × malformed record")),
            "{err}"
        );
        assert!(err.contains("scans/s") && err.contains("MB/s"), "{err}");
        // Skipped lines are reported in input order, each naming its line.
        let reported: Vec<usize> = err
            .lines()
            .filter_map(|l| l.strip_prefix("laserlines: skipped: "))
            .map(|l| l.split(':').nth(1).unwrap().parse().unwrap())
            .collect();
        assert_eq!(reported.len(), bad);
        assert!(reported.windows(2).all(|w| w[0] < w[1]), "{reported:?}");
        outputs.push(std::fs::read(&out).unwrap());
        let records = jsonl(&out);
        assert_eq!(records.len(), scans);
        for (k, r) in records.iter().enumerate() {
            assert_eq!(r["scan"], k as u64);
            // The stamp of scan k is 0.1 k: file order.
            assert!((r["stamp"].as_f64().unwrap() - k as f64 * 0.1).abs() < 1e-9);
            assert!(!r["lines"].as_array().unwrap().is_empty(), "scan {k}");
        }
    }
    assert!(
        outputs.windows(2).all(|w| w[0] == w[1]),
        "outputs differ with the thread count"
    );
}

#[test]
fn a_bad_record_without_skip_bad_stops_after_the_scans_before_it() {
    let input = tmp("stop.clf");
    std::fs::write(&input, synthetic_log(300)).unwrap();
    let out = tmp("stop.jsonl");
    let o = run(bin().args(["extract", "-o"]).arg(&out).arg(&input));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    // The first bad line follows 51 scans (lines: comment, then FLASER + ODOM per scan).
    assert!(
        err.contains("stop.clf:104: expected 192 tokens for FLASER"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    // Every output keeps the lines of the 51 scans before the bad line, readable: the JSONL,
    // the MCAP and the Parquet table (closed with its footer despite the error).
    assert_eq!(jsonl(&out).len(), 51);
    let lines = jsonl(&out)
        .iter()
        .map(|r| r["lines"].as_array().unwrap().len())
        .sum::<usize>();
    let mcap = tmp("stop.mcap");
    let o = run(bin().args(["extract", "-o"]).arg(&mcap).arg(&input));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let back = run(bin().args(["extract", "-o", "-"]).arg(&mcap));
    assert!(back.status.success(), "{}", stderr(&back));
    assert!(stderr(&back).contains("51 scans"), "{}", stderr(&back));
    let table = tmp("stop.parquet");
    let o = run(bin().args(["extract", "-o"]).arg(&table).arg(&input));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let file = std::fs::File::open(&table).unwrap();
    let rows = ParquetRecordBatchReaderBuilder::try_new(file)
        .expect("a Parquet file with its footer")
        .build()
        .unwrap()
        .map(|b| b.unwrap().num_rows())
        .sum::<usize>();
    assert_eq!(rows, lines, "one row per line of the 51 scans");
}

#[test]
fn carmen_logs_and_bags_with_topics() {
    let out = tmp("front.jsonl");
    let o = run(bin()
        .args(["extract", "-o"])
        .arg(&out)
        .arg(io_fixture("carmen/wall_param.clf")));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("2 scans"), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("1 × RLASER scan (another laser)"),
        "{}",
        stderr(&o)
    );
    let o = run(bin()
        .args(["extract", "--topic", "RLASER", "-o"])
        .arg(&out)
        .arg(io_fixture("carmen/wall_param.clf")));
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(jsonl(&out).len(), 1);

    for bag in ["laserscans.bag", "laserscans_bz2.bag", "laserscans_lz4.bag"] {
        for (topic, scans) in [(None, 6), (Some("/scan_rear"), 3)] {
            let mut cmd = bin();
            cmd.args(["extract", "-o"])
                .arg(&out)
                .arg(io_fixture(&format!("bags/{bag}")));
            if let Some(t) = topic {
                cmd.args(["--topic", t]);
            }
            let o = run(&mut cmd);
            assert!(o.status.success(), "{bag}: {}", stderr(&o));
            let records = jsonl(&out);
            assert_eq!(records.len(), scans, "{bag} {topic:?}");
            assert!(records[0]["stamp"].as_f64().unwrap() > 1.28e9);
        }
    }
}

#[test]
fn bad_topics_and_bags_are_clean_errors() {
    // A topic for a format without topics.
    let o = run(bin()
        .args(["extract", "--topic", "/scan"])
        .arg(io_fixture("scans.jsonl")));
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("cannot read topic `/scan`"),
        "{}",
        stderr(&o)
    );
    // A bag without LaserScan.
    let o = run(bin()
        .args(["extract"])
        .arg(io_fixture("bags/no_laserscan.bag")));
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.contains("no_laserscan.bag: byte 4939: expected a sensor_msgs/LaserScan or sensor_msgs/MultiEchoLaserScan connection"),
        "{err}"
    );
    // A truncated bag: the scans before the cut, then an error naming the offset.
    let bytes = std::fs::read(io_fixture("bags/laserscans.bag")).unwrap();
    let cut = tmp("cut.bag");
    std::fs::write(&cut, &bytes[..9000]).unwrap();
    let out = tmp("cut.jsonl");
    let o = run(bin()
        .args(["extract", "--skip-bad", "-o"])
        .arg(&out)
        .arg(&cut));
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("cut.bag: byte 8827: expected chunk data"),
        "{err}"
    );
    assert!(
        err.contains("3 scans") && err.contains("skipped: "),
        "{err}"
    );
    assert_eq!(jsonl(&out).len(), 3);
    // Without --skip-bad: the same scans, what was written, then the error.
    let o = run(bin().args(["extract", "-o"]).arg(&out).arg(&cut));
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    let written = err.find("3 scans with").expect(&err);
    let error = err
        .find("cut.bag: byte 8827: expected chunk data")
        .expect(&err);
    assert!(
        written < error && err.contains("written before the error"),
        "{err}"
    );
    assert_eq!(jsonl(&out).len(), 3);
    // --jobs 0.
    let o = run(bin()
        .args(["extract", "--jobs", "0"])
        .arg(io_fixture("scans.jsonl")));
    assert_eq!(o.status.code(), Some(2));
}

fn real(path: &str) -> Option<PathBuf> {
    shared_data::available(
        shared_data::path("real").join(path),
        "the real-log batch test",
    )
}

#[test]
fn real_logs_extract_in_order_with_every_thread_count() {
    for (path, scans) in [
        ("mit-csail-clf/mit-csail.clf.gz", 1988),
        ("carmen-radish-corrected/intel-corrected.log.gz", 910),
        ("ccny-scan-tools-urg-bag/demo.bag", 360),
    ] {
        let Some(input) = real(path) else { continue };
        let mut outputs = Vec::new();
        for jobs in ["1", "3"] {
            let out = tmp(&format!("real-{jobs}.jsonl"));
            let o = run(bin()
                .args(["extract", "--jobs", jobs, "-o"])
                .arg(&out)
                .arg(&input));
            assert!(o.status.success(), "{path}: {}", stderr(&o));
            outputs.push(std::fs::read(&out).unwrap());
        }
        assert_eq!(outputs[0], outputs[1], "{path}");
        assert_eq!(
            String::from_utf8_lossy(&outputs[0]).lines().count(),
            scans,
            "{path}"
        );
    }
}

/// The first `n` lines of the bundled excerpt, gzipped, with the stream's CRC-32 (the
/// trailer's first 4 bytes) flipped: every line inflates, then the read fails its check.
fn corrupt_gzip(n: usize) -> Vec<u8> {
    use std::io::{Read as _, Write as _};
    let mut text = String::new();
    flate2::read::GzDecoder::new(std::fs::File::open(common::excerpt()).unwrap())
        .read_to_string(&mut text)
        .unwrap();
    let head: String = text.lines().take(n).map(|l| format!("{l}\n")).collect();
    let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    enc.write_all(head.as_bytes()).unwrap();
    let mut gz = enc.finish().unwrap();
    let crc = gz.len() - 8;
    gz[crc] ^= 0xff;
    gz
}

#[test]
fn a_failed_read_ends_the_run_even_with_skip_bad() {
    let input = tmp("crc.dat.gz");
    std::fs::write(&input, corrupt_gzip(10)).unwrap();
    let out = tmp("crc.jsonl");
    for skip in [&["--skip-bad"][..], &[]] {
        let o = run(bin()
            .arg("extract")
            .args(skip)
            .arg("-o")
            .arg(&out)
            .arg(&input));
        assert_eq!(o.status.code(), Some(2), "{skip:?}: {}", stderr(&o));
        let err = stderr(&o);
        assert!(
            err.contains("crc.dat.gz: 10 scans with")
                && err.contains("written before the error")
                && err.contains("crc.dat.gz:11: read failed: "),
            "{skip:?}: {err}"
        );
        assert!(!err.contains("skipped"), "{skip:?}: {err}");
        // The scans before the failed read stay written.
        assert_eq!(jsonl(&out).len(), 10, "{skip:?}");
    }
    // convert and map stop there too.
    let o = run(bin()
        .arg("convert")
        .arg(&input)
        .arg(tmp("crc-scans.jsonl"))
        .arg("--skip-bad"));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("crc.dat.gz:11: read failed: "),
        "{}",
        stderr(&o)
    );
    let o = run(bin()
        .arg("map")
        .arg(&input)
        .arg("--skip-bad")
        .arg("-o")
        .arg(tmp("crc-map")));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("the map of the 10 scans before it is written")
            && err.contains("crc.dat.gz:11: read failed: "),
        "{err}"
    );
}
