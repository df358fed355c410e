//! What a new user runs into, end to end: empty inputs, names the command cannot write,
//! values out of range (negative ones too), files given to the wrong command, the formats of
//! old ROS bags and ROS 2 bags in sqlite3 storage. Each error must exit with code 2 and say
//! what was wrong, never panic nor clamp silently.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::io::Write as _;
use std::path::Path;
use std::process::Output;

mod common;
use common::{bin, excerpt, extract_with_params, repo, run, stderr, tmp};

/// Exit code 2, `needle` in the message, no panic.
fn fails_with(o: &Output, needle: &str) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "exit code; stderr: {err}");
    assert!(
        err.contains(needle),
        "stderr does not say {needle:?}: {err}"
    );
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn an_input_without_scans_fails_whatever_its_format() {
    for name in ["empty.jsonl", "empty.dat", "empty.json", "empty.csv"] {
        let path = tmp(name);
        std::fs::write(&path, b"").unwrap();
        let o = run(bin().arg("extract").arg(&path).args(["-o", "-"]));
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
        let o = run(bin().arg("convert").arg(&path).arg(tmp("out.jsonl")));
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
    }
    let o = run(bin().arg("extract").arg(tmp("empty.jsonl")));
    fails_with(&o, "no scans to read");
    // No output file is left beside the error, whatever its format.
    let extract_to = |out: &Path| {
        let o = run(bin()
            .arg("extract")
            .arg(tmp("empty.jsonl"))
            .arg("-o")
            .arg(out));
        fails_with(&o, "no scans to read");
    };
    for out in ["none.jsonl", "none.parquet", "none.mcap"] {
        let out = tmp(out);
        extract_to(&out);
        assert!(!out.exists(), "{} was left", out.display());
    }
    // A device or a link given as the output stays: only a file of this run goes.
    extract_to(Path::new("/dev/null"));
    assert!(Path::new("/dev/null").exists());
    #[cfg(unix)]
    {
        let target = tmp("kept-target.jsonl");
        std::fs::write(&target, b"keep").unwrap();
        let link = tmp("link.jsonl");
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink(&target, &link).unwrap();
        extract_to(&link);
        assert!(
            std::fs::symlink_metadata(&link).is_ok(),
            "the link was removed"
        );
    }
}

#[test]
fn skip_bad_with_every_record_bad_fails() {
    let path = tmp("all_bad.jsonl");
    std::fs::write(&path, b"{\"angle_min\": 1}\nnot json\n").unwrap();
    let o = run(bin().arg("extract").arg(&path).arg("--skip-bad"));
    fails_with(&o, "no scans read: every record was skipped");
}

#[test]
fn a_lines_file_given_as_scans_is_named_as_such() {
    let lines = tmp("lines.jsonl");
    let o = run(bin().arg("extract").arg(excerpt()).arg("-o").arg(&lines));
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run(bin().arg("extract").arg(&lines));
    fails_with(&o, "this is a lines file");
}

#[test]
fn outputs_are_what_their_names_say() {
    // render: SVG to a .svg file or to standard output, nothing else.
    let png = tmp("fig.png");
    let o = run(bin().arg("render").arg(excerpt()).arg("-o").arg(&png));
    fails_with(&o, "render writes SVG");
    assert!(!png.exists());
    // A folder is named as one.
    let folder = tmp("figures");
    std::fs::create_dir_all(&folder).unwrap();
    let o = run(bin().arg("render").arg(excerpt()).arg("-o").arg(&folder));
    fails_with(&o, "is a folder; render writes one SVG file: name it");
    let o = run(bin().arg("render").arg(excerpt()).args(["-o", "-"]));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(o.stdout.starts_with(b"<?xml"));
    assert!(o.stdout.ends_with(b"</svg>\n"));
    assert!(!Path::new("-").exists());
    // extract: lines JSONL or MCAP.
    let o = run(bin()
        .arg("extract")
        .arg(excerpt())
        .arg("-o")
        .arg(tmp("lines.txt")));
    fails_with(
        &o,
        "expected lines JSONL (.jsonl, .jsonl.gz, or - for standard output)",
    );
    // A device or a pipe has no extension: lines JSONL.
    #[cfg(unix)]
    {
        let o = run(bin()
            .arg("extract")
            .arg(excerpt())
            .args(["-o", "/dev/null"]));
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(stderr(&o).contains("40 scans"), "{}", stderr(&o));
    }
    // .mcap.gz is read, never written.
    for cmd in ["extract", "convert"] {
        let mut c = bin();
        c.arg(cmd).arg(excerpt());
        if cmd == "extract" {
            c.arg("-o");
        }
        let o = run(c.arg(tmp(&format!("{cmd}.mcap.gz"))));
        fails_with(&o, "MCAP compresses its own chunks");
    }
}

#[test]
fn a_gzipped_mcap_reads_back() {
    let mcap = tmp("round.mcap");
    let o = run(bin().arg("convert").arg(excerpt()).arg(&mcap));
    assert!(o.status.success(), "{}", stderr(&o));
    let gz = tmp("round.mcap.gz");
    let mut enc = flate2::write::GzEncoder::new(
        std::fs::File::create(&gz).unwrap(),
        flate2::Compression::fast(),
    );
    enc.write_all(&std::fs::read(&mcap).unwrap()).unwrap();
    enc.finish().unwrap();
    let plain = run(bin().arg("extract").arg(&mcap));
    let zipped = run(bin().arg("extract").arg(&gz));
    assert!(zipped.status.success(), "{}", stderr(&zipped));
    assert_eq!(plain.stdout, zipped.stdout);
    assert_eq!(String::from_utf8_lossy(&zipped.stdout).lines().count(), 40);
}

#[test]
fn convert_names_what_it_writes_and_leaves_no_partial_file() {
    let o = run(bin().arg("convert").arg(excerpt()).arg(tmp("out.txt")));
    fails_with(&o, ".mcap");
    fails_with(&o, "--to FORMAT");
    let csv = tmp("many.csv");
    let o = run(bin().arg("convert").arg(excerpt()).arg(&csv));
    fails_with(&o, "one scan per file");
    fails_with(&o, "(--scan K converts one scan of the log");
    assert!(!csv.exists(), "the partial CSV is left behind");
    // One scan of the log, as the same scan written alone: the CSV reads back as scan 5.
    let o = run(bin()
        .arg("convert")
        .arg(excerpt())
        .arg(&csv)
        .args(["--scan", "5"]));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("1 scan written"), "{}", stderr(&o));
    let back: Vec<_> = laserlines_io::reader::open(&csv, None)
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    let want = laserlines_io::demo::urg04lx_excerpt().unwrap();
    assert_eq!(back.len(), 1);
    assert_eq!(back[0].scan.ranges, want[5].scan.ranges);
    assert_eq!(back[0].scan.stamp, want[5].scan.stamp);
    // A scan the log does not hold.
    let o = run(bin()
        .arg("convert")
        .arg(excerpt())
        .arg(&csv)
        .args(["--scan", "40"]));
    fails_with(&o, "has no scan 40 (it holds 40 scans)");
    assert!(!csv.exists(), "a CSV is left behind");
}

/// A failed run removes the output file it made, never a device, a pipe or a symbolic link
/// named as its output (a run as root once took `/dev/full` with it): each output here is a
/// link to a file of the user's; the link stays, and a note says that its file holds what
/// the run wrote.
#[cfg(unix)]
#[test]
fn a_failed_run_leaves_an_output_that_is_no_regular_file_alone() {
    let bad = tmp("bad-third.jsonl");
    let good = r#"{"angle_min": -1.0, "angle_increment": 0.01, "range_min": 0.02, "range_max": 5.6, "ranges": [2.0, 2.0, 2.0, 2.0]}"#;
    std::fs::write(&bad, format!("{good}\n{good}\n{{\"ranges\": oops}}\n")).unwrap();
    let keep = tmp("users-file.jsonl");
    let link = |name: &str| {
        std::fs::write(&keep, b"the user's own\n").unwrap();
        let l = tmp(name);
        let _ = std::fs::remove_file(&l);
        std::os::unix::fs::symlink(&keep, &l).unwrap();
        l
    };
    let survived = |l: &Path, what: &str, o: &Output| {
        let meta = std::fs::symlink_metadata(l);
        assert!(
            meta.is_ok_and(|m| m.file_type().is_symlink()),
            "{what}: the link was removed"
        );
        assert!(keep.exists(), "{what}: the file it points to was removed");
        // The run wrote through the link: the file holds its output now, and a note says so.
        let err = stderr(o);
        assert!(
            err.contains("is a symbolic link: left as it is, and the file it points to holds"),
            "{what}: {err}"
        );
        let held = std::fs::read(&keep).unwrap();
        let mine: &[u8] = b"the user's own";
        assert!(
            !held.windows(mine.len()).any(|w| w == mine),
            "{what}: unchanged"
        );
    };
    let out = link("convert-out.jsonl");
    let o = run(bin().arg("convert").arg(&bad).arg(&out));
    fails_with(&o, "bad-third.jsonl:3");
    survived(&out, "convert", &o);
    let empty = tmp("nothing.jsonl");
    std::fs::write(&empty, b"").unwrap();
    let out = link("extract-out.jsonl");
    let o = run(bin().arg("extract").arg(&empty).arg("-o").arg(&out));
    fails_with(&o, "no scans to read");
    survived(&out, "extract", &o);
    let mcap = link("map-out.mcap");
    let o = run(bin()
        .arg("map")
        .arg(&empty)
        .arg("-o")
        .arg(tmp("map-dir"))
        .arg("--mcap")
        .arg(&mcap));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    survived(&mcap, "map --mcap", &o);
    // A regular file the run made is still removed.
    let plain = tmp("convert-plain.jsonl");
    let o = run(bin().arg("convert").arg(&bad).arg(&plain));
    fails_with(&o, "removed the partial");
    assert!(!plain.exists());
}

/// An output that fails part way (a full disk: `/dev/full`) is reported as such: the summary
/// counts the scans extracted, never as written; so does one that fails only as its buffers
/// are flushed at the end (a short run).
#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_is_not_reported_as_scans_written() {
    if !Path::new("/dev/full").exists() {
        eprintln!("SKIPPED: no /dev/full on this machine");
        return;
    }
    // Enough scans that the output's buffer is written before the end.
    let scan = format!(
        r#"{{"angle_min": -2.0, "angle_increment": 0.006, "range_min": 0.02, "range_max": 5.6, "ranges": [{}]}}"#,
        vec!["2.5"; 682].join(", ")
    );
    for (name, count) in [("many.jsonl", 400), ("few.jsonl", 3)] {
        let input = tmp(name);
        std::fs::write(&input, format!("{scan}\n").repeat(count)).unwrap();
        let o = run(bin().arg("extract").arg(&input).args(["-o", "/dev/full"]));
        fails_with(&o, "No space left on device");
        let err = stderr(&o);
        assert!(
            err.contains("extracted before the output failed") && !err.contains("written"),
            "a full disk reported as written ({count} scans): {err}"
        );
    }
}

/// `live` names an output in a missing folder before it opens the sensor (port 1 of the
/// loopback would refuse the connection).
#[test]
fn live_names_a_missing_output_folder_before_the_sensor() {
    for flag in ["-o", "--record"] {
        let o = run(bin()
            .args(["live", "127.0.0.1:1", flag])
            .arg(tmp("no-such-folder").join("x.mcap")));
        fails_with(&o, "no-such-folder does not exist");
        assert!(!stderr(&o).contains("refused"), "{}", stderr(&o));
    }
}

#[test]
fn values_out_of_range_are_errors_not_clamped() {
    for (args, needle) in [
        (
            &["demo", "--figure-scan", "40"][..],
            "--figure-scan must be less than 40",
        ),
        (
            &["demo", "--repeat", "0"][..],
            "must be from 1 to 1000, got 0",
        ),
        (
            &["bench", "--repeat", "0"][..],
            "must be from 1 to 1000, got 0",
        ),
        (
            &["bench", "--scans", "10000000", "--algorithms", "iepf"][..],
            "--scans must be from 1 to 20000 per simulated suite, got 10000000",
        ),
        (
            &[
                "bench",
                "--scans",
                "0",
                "--data",
                "../../data/urg04lx-exp1-excerpt.dat.gz",
            ][..],
            "--scans must be at least 1 (at most this many scans of each log), got 0",
        ),
        (
            &["live", "127.0.0.1:9", "--scans", "0"][..],
            "must be 1 or more, got 0",
        ),
        (
            &["simulate", "--duration", "-5"][..],
            "--duration must be seconds, more than 0 up to 1e9, got -5",
        ),
        (
            &["simulate", "--snapshot", "-1"][..],
            "--snapshot must lie within the run",
        ),
        (
            &["simulate", "--duration", "10", "--snapshot", "10"][..],
            "from 0 to its last scan at 9.900 s (--duration 10 s), got 10",
        ),
        (
            &["simulate", "--duration", "10", "--snapshot", "10.01"][..],
            "from 0 to its last scan at 9.900 s (--duration 10 s), got 10.01",
        ),
        (
            &["simulate", "--duration", "1.005", "--snapshot", "0.905"][..],
            "from 0 to its last scan at 0.900 s (--duration 1.005 s), got 0.905",
        ),
        (
            &["simulate", "--arena", "inner_explore_test", "--islands"][..],
            "'--arena <ARENA>' cannot be used with '--islands'",
        ),
        (
            &["simulate", "--maze", "3", "--mesh-walls"][..],
            "'--maze <SEED>' cannot be used with '--mesh-walls'",
        ),
    ] {
        let mut c = bin();
        c.args(args).arg("-o").arg(tmp("out-dir"));
        let o = run(&mut c);
        fails_with(&o, needle);
    }
    for (args, needle) in [
        (&["--width", "10"][..], "--width must lie from 400 to 8000"),
        (&["--width", "-3"][..], "--width must lie from 400 to 8000"),
        (&["--scan", "-1"][..], "indices count from 0, got -1"),
    ] {
        let o = run(bin()
            .arg("render")
            .arg(excerpt())
            .args(args)
            .arg("-o")
            .arg(tmp("w.svg")));
        fails_with(&o, needle);
    }
    let o = run(bin().arg("view").arg(excerpt()).args(["--rate", "-1"]));
    fails_with(&o, "--rate must be a number >= 0");
}

#[test]
fn simulate_refuses_a_start_outside_the_arena_and_a_short_run_still_draws_its_sectors() {
    let dir = tmp("sim-outside");
    let o = run(bin()
        .args([
            "simulate",
            "--arena",
            "inner_explore_test",
            "--start",
            "100,100,0",
        ])
        .arg("-o")
        .arg(&dir));
    fails_with(&o, "--start (100, 100): outside inner_explore_test");
    // Text of another kind with a `<` in it is no arena, rather than one cut short.
    let text = tmp("le.raf");
    std::fs::write(&text, "x <= 3\n").unwrap();
    let o = run(bin()
        .args(["simulate", "--arena"])
        .arg(&text)
        .arg("-o")
        .arg(tmp("sim-le")));
    fails_with(
        &o,
        "le.raf:1: unclosed tag before any <elements> or <element> tag: not an arena layout",
    );
    let dir = tmp("sim-short");
    let o = run(bin()
        .args([
            "simulate",
            "--arena",
            "inner_explore_test",
            "--duration",
            "3",
        ])
        .arg("-o")
        .arg(&dir));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("sectors.svg").is_file(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(!out.contains("at never"), "{out}");
}

#[test]
fn help_lists_the_algorithms_and_summaries_count_in_the_singular() {
    let o = run(bin().args(["extract", "--help"]));
    let help = String::from_utf8_lossy(&o.stdout);
    assert!(
        help.contains("[possible values: hough-split, iterative-hough"),
        "{help}"
    );
    let one = repo("crates/laserlines-io/tests/fixtures/three_beams.json");
    let o = run(bin().arg("extract").arg(&one));
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains(": 1 scan, "), "{err}");
    let o = run(bin()
        .args(["demo", "--repeat", "1"])
        .arg("-o")
        .arg(tmp("demo1")));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("(median of 1 pass, one thread)"), "{out}");
}

#[test]
fn old_ros_bags_and_ros2_sqlite_bags_extract() {
    let v12 = repo("crates/laserlines-io/tests/fixtures/bags/laserscans_v12.bag");
    let o = run(bin().arg("extract").arg(&v12));
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(String::from_utf8_lossy(&o.stdout).lines().count(), 6);
    let db3 = repo("crates/laserlines-foxglove/tests/fixtures/ros2_laserscan_sqlite3");
    for topic in ["/scan", "/scan_rear"] {
        let o = run(bin().arg("extract").arg(&db3).args(["--topic", topic]));
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(String::from_utf8_lossy(&o.stdout).lines().count(), 3);
    }
}

#[test]
fn a_long_input_name_wraps_in_the_sectors_title() {
    let long = tmp(&format!(
        "{}_scans.dat.gz",
        "a_very_long_log_name".repeat(8)
    ));
    std::fs::copy(excerpt(), &long).unwrap();
    let o = run(bin()
        .arg("render")
        .arg(&long)
        .args(["--sectors", "-o", "-"]));
    assert!(o.status.success(), "{}", stderr(&o));
    let svg = String::from_utf8_lossy(&o.stdout);
    let title: Vec<&str> = svg
        .split("class=\"panel-title\"")
        .skip(1)
        .filter_map(|t| t.split_once('>').and_then(|(_, r)| r.split('<').next()))
        .collect();
    assert!(title.len() >= 3, "{title:?}");
    // The plot is 560 px wide; 13.5 px bold letters are about 8 px wide.
    for line in &title {
        assert!(line.chars().count() <= 75, "{line:?} in {title:?}");
    }
    assert!(
        !svg.contains(&std::env::temp_dir().display().to_string()),
        "the whole path"
    );
}

/// An output that is the input, by its name or through a hard link, is refused before
/// anything is written: the input stays as it was.
#[test]
fn the_input_is_never_its_own_output() {
    let scans = tmp("same.jsonl");
    let o = run(bin().arg("convert").arg(excerpt()).arg(&scans));
    assert!(o.status.success(), "{}", stderr(&o));
    let before = std::fs::read(&scans).unwrap();
    let link = tmp("same-link.jsonl");
    std::fs::hard_link(&scans, &link).unwrap();
    for output in [&scans, &link] {
        let o = run(bin().arg("extract").arg(&scans).arg("-o").arg(output));
        fails_with(&o, "the output is the input");
        let o = run(bin().arg("convert").arg(&scans).arg(output));
        fails_with(&o, "writing it would destroy the input");
        assert_eq!(std::fs::read(&scans).unwrap(), before);
    }
    // Another file of the same content is no problem.
    let copy = tmp("same-copy.jsonl");
    std::fs::copy(&scans, &copy).unwrap();
    let o = run(bin().arg("convert").arg(&scans).arg(&copy));
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn an_output_in_a_missing_folder_names_the_folder() {
    let missing = tmp("no-such-folder");
    let _ = std::fs::remove_dir_all(&missing);
    for (args, file) in [
        (&["extract", "IN", "-o", "OUT"][..], "lines.jsonl"),
        (&["convert", "IN", "OUT"][..], "scans.mcap"),
        (&["render", "IN", "-o", "OUT"][..], "scan.svg"),
    ] {
        let out = missing.join(file);
        let o = run(bin().args(args.iter().map(|a| match *a {
            "IN" => excerpt().into_os_string(),
            "OUT" => out.clone().into_os_string(),
            a => a.into(),
        })));
        fails_with(&o, "cannot write: the folder");
        assert!(stderr(&o).contains(&format!("{} does not exist", missing.display())));
        assert!(!missing.exists(), "{args:?} made the folder");
    }
}

/// Parameters that leave no line anywhere (a criterion no cell reaches) are legal, but the
/// summary says that no scan gave a line; a normal run says nothing of the kind.
#[test]
fn a_run_without_any_line_says_so() {
    let o = extract_with_params("no-lines.toml", "[hough-split]\ncriterion = 1e300\n");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("note: no line in any of the 40 scans; if the scans see walls"),
        "{}",
        stderr(&o)
    );
    let o = run(bin().arg("extract").arg(excerpt()).args(["-o", "-"]));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("no line in"), "{}", stderr(&o));
}

/// A single scan in millimetres (a URG-04LX's raw readings) with limits in metres gives no
/// line, and the summary says where to look.
#[test]
fn a_single_scan_in_millimetres_says_so() {
    let input = tmp("mm.json");
    let ranges: Vec<String> = (0..682).map(|i| format!("{}", 1500 + i % 7)).collect();
    std::fs::write(
        &input,
        format!(
            "{{\"angle_min\": -2.08, \"angle_increment\": 0.006136, \"range_min\": 0.02, \
             \"range_max\": 5.6, \"ranges\": [{}]}}",
            ranges.join(", ")
        ),
    )
    .unwrap();
    let o = run(bin().arg("extract").arg(&input).args(["-o", "-"]));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("note: no line in the scan;")
            && stderr(&o).contains("the ranges are in metres"),
        "{}",
        stderr(&o)
    );
}
