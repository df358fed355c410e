//! Limits and bad input across the commands: option values beyond their bounds, logs whose
//! stamps jump or step back, logs cut short or unreadable given to `render` and to the
//! emulator, and the README's printed examples as the binary prints them.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::io::Read as _;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::{bin, excerpt, fails_with, repo, run, stderr, text, tmp};

/// A CARMEN log of two scans cut in the middle of its third line.
const CUT_CLF: &str =
    "FLASER 3 1 1 1 0 0 0 0 0 0 1.0 h 1.0\nFLASER 3 1 1 1 0 0 0 0 0 0 1.1 h 1.1\nFLASER 3 1 1";

/// Runs `cmd` with stdout and stdin closed, killing it after `deadline`; its exit status
/// (`None` when it had to be killed) and its whole stderr.
fn run_until(cmd: &mut Command, deadline: Duration) -> (Option<std::process::ExitStatus>, String) {
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut pipe = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        pipe.read_to_string(&mut s).unwrap();
        s
    });
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break Some(status);
        }
        if start.elapsed() > deadline {
            child.kill().unwrap();
            child.wait().unwrap();
            break None;
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    (status, reader.join().unwrap())
}

#[test]
fn view_caps_the_wait_at_a_gap_and_does_not_wait_on_a_backward_step() {
    // Stamps: 0.1 s steps, back by 50 s, ahead by 4950 s, and one that is not usable.
    let log = tmp("gaps.jsonl");
    let lines: Vec<String> = [100.0, 100.1, 50.0, 50.1, 5000.0, 5000.1, -1.0]
        .iter()
        .map(|s| {
            format!(
                "{{\"angle_min\": -1.0, \"angle_increment\": 0.1, \"range_min\": 0.02, \
                 \"range_max\": 5.6, \"ranges\": [1.0, 1.0, 1.0, 1.0, 1.0], \"stamp\": {s}}}"
            )
        })
        .collect();
    std::fs::write(&log, lines.join("\n")).unwrap();
    let started = Instant::now();
    let (status, err) = run_until(
        bin()
            .arg("view")
            .arg(&log)
            .args(["--no-wait", "--port", "0"]),
        Duration::from_secs(30),
    );
    assert!(
        status.is_some_and(|s| s.success()),
        "{status:?} after {:?}: {err}",
        started.elapsed()
    );
    // At most 1 s at the gap, 0.1 s at four steps and half a second at the end.
    assert!(started.elapsed() < Duration::from_secs(15), "{err}");
    assert_eq!(err.matches("warning").count(), 1, "{err}");
    assert!(
        err.contains("laserlines: warning: ")
            && err.contains("scan 2 has a stamp that steps backwards"),
        "{err}"
    );
    assert!(err.contains(": 7 scans, "), "{err}");
    assert!(
        err.contains(
            "stamps: 1 gap over 1 s, 1 backward step, 1 unusable stamp (paced 0.1 s apart)"
        ),
        "{err}"
    );
}

#[test]
fn the_emulator_refuses_a_log_it_cannot_read_whole() {
    let dir = tmp("emulator-logs");
    std::fs::create_dir_all(&dir).unwrap();
    let cut = dir.join("cut.clf");
    std::fs::write(&cut, CUT_CLF).unwrap();
    let empty = dir.join("empty.clf");
    std::fs::write(&empty, "").unwrap();
    let noise = dir.join("noise.clf");
    std::fs::write(&noise, [0xf2u8, 0x00, 0x9c, 0xff, 0x13, 0x80, 0xfe, 0x01]).unwrap();
    let missing = dir.join("nonexistent.clf");
    for (log, needles) in [
        (&cut, &["cut.clf:3: expected 14 tokens for FLASER"][..]),
        (&empty, &["empty.clf", "expected laser scans"][..]),
        (&noise, &["noise.clf:1:1: expected UTF-8 text"][..]),
        (&missing, &["nonexistent.clf: cannot open"][..]),
    ] {
        // A log that cannot be read whole is an error, not served as scans of zeros.
        let (status, err) = run_until(
            bin()
                .args(["hokuyo-emulator", "--tcp", "127.0.0.1:0", "--duration", "2"])
                .arg("--log")
                .arg(log),
            Duration::from_secs(30),
        );
        assert_eq!(status.and_then(|s| s.code()), Some(2), "{log:?}: {err}");
        for needle in needles {
            assert!(err.contains(needle), "{log:?}: {err}");
        }
        assert!(!err.contains("panicked"), "{err}");
    }
    // The OS error once, with the file's name.
    let (_, err) = run_until(
        bin()
            .args(["hokuyo-emulator", "--tcp", "127.0.0.1:0", "--log"])
            .arg(&missing),
        Duration::from_secs(30),
    );
    assert_eq!(err.matches("os error").count(), 1, "{err}");
    // A good log is served until --duration.
    let (status, err) = run_until(
        bin()
            .args([
                "hokuyo-emulator",
                "--tcp",
                "127.0.0.1:0",
                "--duration",
                "0.3",
            ])
            .arg("--log")
            .arg(excerpt()),
        Duration::from_secs(30),
    );
    assert!(status.is_some_and(|s| s.success()), "{err}");
    // The URG-04LX's own log is served as it is; a log of another geometry with a note of
    // what serving it as the model changes (a CARMEN scan of 3 beams, 180 deg).
    assert!(!err.contains("note"), "{err}");
    let three = dir.join("three.clf");
    std::fs::write(&three, "FLASER 3 1 1 1 0 0 0 0 0 0 1.0 h 1.0\n").unwrap();
    let (status, err) = run_until(
        bin()
            .args([
                "hokuyo-emulator",
                "--tcp",
                "127.0.0.1:0",
                "--duration",
                "0.3",
            ])
            .arg("--log")
            .arg(&three),
        Duration::from_secs(30),
    );
    assert!(status.is_some_and(|s| s.success()), "{err}");
    assert!(
        err.contains(
            "three.clf: its scans (3 beams of 90.000 deg from -90.0 deg, up to 81.83 m) are served \
             at the urg-04lx's 682 steps of 0.352 deg from -119.5 deg, up to 5.6 m"
        ),
        "{err}"
    );
}

#[test]
fn counts_and_seconds_beyond_their_bounds_are_refused_with_the_range() {
    for (args, needle) in [
        (
            &["extract", "-j", "100000", "-o", "/dev/null", "EXCERPT"][..],
            "--jobs must be from 1 to 256, got 100000",
        ),
        (
            &["extract", "-j", "0", "-o", "/dev/null", "EXCERPT"][..],
            "--jobs must be from 1 to 256, got 0",
        ),
        (
            &["bench", "--repeat", "1001"][..],
            "must be from 1 to 1000, got 1001",
        ),
        (
            &["demo", "--repeat", "100000"][..],
            "must be from 1 to 1000, got 100000",
        ),
        (
            &["live", "x", "--silence", "1e300"][..],
            "--silence must be seconds, more than 0 up to 1e9, got 1e300",
        ),
        (
            &["live", "x", "--duration", "1e300"][..],
            "--duration must be seconds, more than 0 up to 1e9, got 1e300",
        ),
        (
            &["live", "x", "--duration", "-2"][..],
            "--duration must be seconds, more than 0 up to 1e9, got -2",
        ),
        (
            &[
                "hokuyo-emulator",
                "--drop-after",
                "5",
                "--down-for",
                "1e300",
            ][..],
            "--down-for must be seconds, from 0 up to 1e9, got 1e300",
        ),
        (
            &["hokuyo-emulator", "--stall-for", "-0.5"][..],
            "--stall-for must be seconds, from 0 up to 1e9, got -0.5",
        ),
        (
            &["hokuyo-emulator", "--duration", "1e12"][..],
            "--duration must be seconds, more than 0 up to 1e9, got 1e12",
        ),
        (
            &["hokuyo-emulator", "--rate", "1e300"][..],
            "--rate must be scans per second, from 1/60 (one a minute) up to 1000, got 1e300",
        ),
        (
            &["hokuyo-emulator", "--rate", "0.001"][..],
            "--rate must be scans per second, from 1/60 (one a minute) up to 1000, got 0.001",
        ),
        (&["view", "EXCERPT", "--rate", "-1e300"][..], "got -1e300"),
        (
            &["simulate", "--duration", "1e10", "-o", "/nonexistent/s"][..],
            "--duration must be seconds, more than 0 up to 1e9, got 1e10",
        ),
        (
            &["simulate", "--duration", "0", "-o", "/nonexistent/s"][..],
            "--duration must be seconds, more than 0 up to 1e9, got 0",
        ),
        // A run of no time at all is refused by every command that takes one.
        (
            &["live", "127.0.0.1:1", "--duration", "0"][..],
            "--duration must be seconds, more than 0 up to 1e9, got 0",
        ),
        (
            &["hokuyo-emulator", "--duration", "0"][..],
            "--duration must be seconds, more than 0 up to 1e9, got 0",
        ),
        (
            &["hokuyo-emulator", "--reply-delay-ms", "10000000000000"][..],
            "--reply-delay-ms must be milliseconds, from 0 up to 1e12, got 1e13",
        ),
    ] {
        let excerpt = excerpt();
        let args: Vec<&std::ffi::OsStr> = args
            .iter()
            .map(|a| {
                if *a == "EXCERPT" {
                    excerpt.as_os_str()
                } else {
                    a.as_ref()
                }
            })
            .collect();
        let (status, err) = run_until(bin().args(&args), Duration::from_secs(60));
        assert_eq!(status.and_then(|s| s.code()), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!err.contains("0000000000"), "{args:?}: {err}");
    }
}

#[test]
fn negative_numbers_reach_the_range_checks() {
    let excerpt = excerpt();
    let ex = excerpt.to_str().unwrap();
    let out = tmp("negative");
    let out = out.to_str().unwrap();
    for (args, needles) in [
        (
            &["map", ex, "--resolution", "-1", "-o", out][..],
            &["--resolution must lie from 0.005 to 10 m, got -1"][..],
        ),
        (
            &["relations", "a.tum", "b.tum", "--every", "-5"][..],
            &["--every", "must be 1 or more, got -5"][..],
        ),
        (
            &["simulate", "--maze", "-1", "-o", out][..],
            &["--maze", "must be 0 or more, got -1"][..],
        ),
        (
            &["live", "x", "--cluster", "-1"][..],
            &["--cluster", "must be from 1 to 99, got -1"][..],
        ),
        (
            &["view", ex, "--port", "-1"][..],
            &["--port", "must be from 0 to 65535, got -1"][..],
        ),
        (
            &["hokuyo-emulator", "--stall-after", "-2"][..],
            &["--stall-after", "must be 0 or more, got -2"][..],
        ),
    ] {
        let o = run(bin().args(args));
        fails_with(&o, needles);
        assert!(!stderr(&o).contains("unexpected argument"), "{args:?}");
    }
}

#[test]
fn simulate_refuses_more_diagonals_than_the_maze_has_and_its_help_places_odometry() {
    let o = run(bin()
        .args(["simulate", "--maze", "1", "--diagonals", "1000", "-o"])
        .arg(tmp("diagonals")));
    fails_with(
        &o,
        &[
            "--diagonals 1000: maze 1 has 58 turning cells",
            "from 0 to 58",
        ],
    );
    let o = run(bin().args(["simulate", "--help"]));
    assert!(o.status.success());
    let help = text(&o.stdout)
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    assert!(
        help.contains("`[robot]` (footprint, drive limits, wheel base, laser mount)")
            && help.contains("`[simulator]` (odometry noise,"),
        "{help}"
    );
}

#[test]
fn bench_names_every_suite_it_takes() {
    let o = run(bin()
        .args(["bench", "--suite", "foo", "-o"])
        .arg(tmp("bench-foo")));
    fails_with(
        &o,
        &["known suites: rooms, corridors, maze, boxes, clutter, glancing, far, all, arenas"],
    );
}

#[test]
fn render_reports_the_bad_record_that_ends_the_log_before_the_scan() {
    // `render --scan 200` of a log named `name` holding `text`.
    let render_200 = |name: &str, text: &str| {
        let log = tmp(&format!("{name}.clf"));
        std::fs::write(&log, text).unwrap();
        run(bin()
            .arg("render")
            .arg(&log)
            .args(["--scan", "200", "-o"])
            .arg(tmp(&format!("{name}.svg"))))
    };
    let o = render_200("render-cut", CUT_CLF);
    fails_with(&o, &["render-cut.clf:3: expected 14 tokens for FLASER"]);
    assert!(!stderr(&o).contains("has no scan"), "{}", stderr(&o));
    // A log that simply ends before the scan still says how many it holds.
    let o = render_200("render-whole", "FLASER 3 1 1 1 0 0 0 0 0 0 1.0 h 1.0\n");
    fails_with(&o, &["has no scan 200 (it holds 1 scan)"]);
}

#[test]
fn render_skip_bad_numbers_the_scans_as_extract_skip_bad_does() {
    // Ranges of the three records differ: 1.0, a bad one, 1.3 m.
    let good = "FLASER 3 1.0 1.0 1.0 0 0 0 0 0 0 1.0 h 1.0\n";
    let last = "FLASER 3 1.3 1.3 1.3 0 0 0 0 0 0 1.2 h 1.2\n";
    let bad = "FLASER 3 1.1 1.1 0 0 0 0 0 0 1.1 h 1.1\n";
    let (with_bad, without) = (tmp("skip-render-bad.clf"), tmp("skip-render-good.clf"));
    std::fs::write(&with_bad, format!("{good}{bad}{last}")).unwrap();
    std::fs::write(&without, format!("{good}{last}")).unwrap();
    let draw = |log: &std::path::Path, svg: &str, skip: bool| {
        let mut cmd = bin();
        cmd.arg("render").arg(log).args(["--scan", "1", "-o"]);
        cmd.arg(tmp(svg));
        if skip {
            cmd.arg("--skip-bad");
        }
        run(&mut cmd)
    };
    // Without --skip-bad the bad record ends the run, named.
    let o = draw(&with_bad, "skip-render-stop.svg", false);
    fails_with(
        &o,
        &["skip-render-bad.clf:2: expected 14 tokens for FLASER"],
    );
    let o = draw(&with_bad, "skip-render-skip.svg", true);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("skipped: ") && stderr(&o).contains("skip-render-bad.clf:2"),
        "{}",
        stderr(&o)
    );
    let o = draw(&without, "skip-render-ref.svg", false);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let read = |name: &str| std::fs::read_to_string(tmp(name)).unwrap();
    // Scan 1 is the record after the bad one, drawn as from a log without it.
    assert_eq!(read("skip-render-skip.svg"), read("skip-render-ref.svg"));
}

#[test]
fn the_readme_sectors_example_prints_what_the_readme_shows() {
    let readme = std::fs::read_to_string(repo("README.md")).unwrap();
    let mut lines = readme.lines().map(str::trim);
    let command = lines
        .find(|l| l.starts_with("$ laserlines render ") && l.contains("--sectors"))
        .expect("the README shows a render --sectors example");
    let shown: Vec<&str> = lines.take_while(|l| !l.starts_with("```")).collect();
    let args: Vec<&str> = command["$ laserlines ".len()..]
        .split_whitespace()
        .map(|a| if a == "fig.svg" { "-" } else { a })
        .collect();
    let o = run(bin().current_dir(repo("")).args(&args));
    assert!(o.status.success(), "{}", stderr(&o));
    // With `-o -` the SVG goes to stdout and the sector lines to stderr.
    let printed: Vec<String> = stderr(&o).lines().map(str::to_owned).collect();
    assert_eq!(printed, shown, "{command}");
}
