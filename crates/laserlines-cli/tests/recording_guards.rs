//! What `map` and `simulate` refuse to overwrite with their `--mcap` recording (their input,
//! their params file, the files of their output folder), what `map` keeps when a scan has
//! no odometry under `--odometry on`, and a run refused for its settings before it makes any
//! file.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};

mod common;
use common::{assert_clean_error, bin, excerpt, repo, run, text, tmp, tum_rows};

/// The bundled excerpt as JSONL (40 scans with odometry), in the test's folder.
fn excerpt_jsonl(name: &str) -> PathBuf {
    let path = tmp(name);
    let o = run(bin()
        .arg("convert")
        .arg(excerpt())
        .arg(&path)
        .args(["--to", "jsonl"]));
    assert!(o.status.success(), "{}", text(&o.stderr));
    path
}

/// `path`'s JSONL with the odometry of the scans `without` taken out.
fn drop_odometry(path: &Path, without: &[usize]) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut out = String::new();
    for (k, line) in text.lines().enumerate() {
        let mut v: serde_json::Value = serde_json::from_str(line).unwrap();
        if without.contains(&k) {
            assert!(v.as_object_mut().unwrap().remove("odometry").is_some());
        }
        out.push_str(&v.to_string());
        out.push('\n');
    }
    std::fs::write(path, out).unwrap();
}

#[test]
fn map_refuses_a_recording_over_its_input_or_its_outputs() {
    let log = tmp("own.dat.gz");
    std::fs::copy(excerpt(), &log).unwrap();
    let before = std::fs::read(&log).unwrap();
    let out = tmp("own-map");
    let _ = std::fs::remove_dir_all(&out);
    // `map LOG -o OUT`, then `extra`.
    let map = |extra: &[&std::ffi::OsStr]| {
        run(bin().arg("map").arg(&log).arg("-o").arg(&out).args(extra))
    };
    // The log itself: refused before anything is written, the log as it was.
    let o = map(&["--mcap".as_ref(), log.as_os_str()]);
    assert_clean_error(&o, "own.dat.gz", "the output is the input");
    assert_eq!(std::fs::read(&log).unwrap(), before);
    assert!(!out.exists(), "the output folder was made");
    // The params file too.
    let params = tmp("own.toml");
    std::fs::write(&params, "[hough-split]\n").unwrap();
    let o = map(&[
        "--params".as_ref(),
        params.as_os_str(),
        "--mcap".as_ref(),
        params.as_os_str(),
    ]);
    assert_clean_error(&o, "own.toml", "the output is the input");
    assert_eq!(std::fs::read_to_string(&params).unwrap(), "[hough-split]\n");
    // A file the command writes in its output folder, also by a roundabout path to a
    // folder that does not exist yet, and by an absolute name for an output folder named
    // relative to the working folder.
    let relative = run(bin()
        .current_dir(out.parent().unwrap())
        .arg("map")
        .arg(&log)
        .args(["-o", "own-map", "--mcap"])
        .arg(out.join("trajectory.tum")));
    for o in [
        map(&["--mcap".as_ref(), out.join("map.svg").as_os_str()]),
        map(&[
            "--mcap".as_ref(),
            out.join("../own-map/./lines.json").as_os_str(),
        ]),
        relative,
    ] {
        assert_clean_error(
            &o,
            "own-map",
            "a file this command writes in its output folder",
        );
        assert!(!out.exists(), "the output folder was made");
    }
    // A recording inside an input that is a folder (a ROS 2 bag).
    let bag = tmp("own-bag");
    std::fs::create_dir_all(&bag).unwrap();
    let fixture = repo("crates/laserlines-foxglove/tests/fixtures/ros2_laserscan_sqlite3");
    for entry in std::fs::read_dir(&fixture).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), bag.join(entry.file_name())).unwrap();
    }
    let o = run(bin()
        .arg("map")
        .arg(&bag)
        .arg("-o")
        .arg(tmp("own-bag-map"))
        .arg("--mcap")
        .arg(bag.join("run.mcap")));
    assert_clean_error(&o, "own-bag", "--mcap lies inside the input folder");
    assert!(!bag.join("run.mcap").exists());
    // Another name in the same folder is a recording like any other.
    let o = map(&["--mcap".as_ref(), out.join("run.mcap").as_os_str()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        std::fs::read(out.join("run.mcap"))
            .unwrap()
            .starts_with(b"\x89MCAP0\r\n")
    );
    assert!(
        std::fs::read_to_string(out.join("map.svg"))
            .unwrap()
            .contains("<svg")
    );
}

#[test]
fn simulate_refuses_a_recording_over_its_arena_or_its_outputs() {
    let arena = tmp("own.raf");
    std::fs::copy(repo("data/arenas/inner_explore_test.raf"), &arena).unwrap();
    let before = std::fs::read(&arena).unwrap();
    let out = tmp("own-run");
    let simulate = |mcap: &Path| {
        run(bin()
            .arg("simulate")
            .arg("--arena")
            .arg(&arena)
            .args(["--duration", "2", "-o"])
            .arg(&out)
            .arg("--mcap")
            .arg(mcap))
    };
    let o = simulate(&arena);
    assert_clean_error(&o, "own.raf", "the output is the input");
    assert_eq!(std::fs::read(&arena).unwrap(), before);
    for name in ["map.svg", "metrics.json", "sectors.svg"] {
        let o = simulate(&out.join(name));
        assert_clean_error(&o, name, "a file this command writes in its output folder");
    }
    assert!(!out.exists(), "the output folder was made");
}

#[test]
fn a_scan_without_odometry_keeps_the_map_of_the_scans_before_it() {
    // The last of 40 scans without odometry: the 39 before it mapped and written.
    let log = excerpt_jsonl("no-odometry-last.jsonl");
    drop_odometry(&log, &[39]);
    let out = tmp("no-odometry-last");
    let _ = std::fs::remove_dir_all(&out);
    let o = run(bin().arg("map").arg(&log).arg("-o").arg(&out));
    assert_clean_error(
        &o,
        "scan 39 (line 40)",
        "stopped at a scan without odometry",
    );
    let err = text(&o.stderr);
    assert!(
        err.contains("the map of the 39 scans before it is written"),
        "{err}"
    );
    assert_eq!(tum_rows(&out.join("trajectory.tum")).len(), 39);
    // With --skip-bad, a scan in the middle is skipped, counted and named by its index in
    // the log; the scans after it are mapped.
    let log = excerpt_jsonl("no-odometry-middle.jsonl");
    drop_odometry(&log, &[20, 39]);
    let out = tmp("no-odometry-middle");
    let o = run(bin()
        .arg("map")
        .arg(&log)
        .arg("--skip-bad")
        .arg("-o")
        .arg(&out));
    let err = text(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("scan 20 (line 21): no odometry"), "{err}");
    assert!(err.contains("scan 39 (line 40): no odometry"), "{err}");
    assert!(
        err.contains("2 × scan without odometry (--odometry on)"),
        "{err}"
    );
    assert_eq!(tum_rows(&out.join("trajectory.tum")).len(), 38);
}

#[test]
fn a_log_without_any_odometry_skipped_whole_says_so() {
    let log = excerpt_jsonl("no-odometry-at-all.jsonl");
    drop_odometry(&log, &(0..40).collect::<Vec<_>>());
    let o = run(bin()
        .arg("map")
        .arg(&log)
        .args(["--odometry", "on", "--skip-bad", "-o"])
        .arg(tmp("no-odometry-at-all")));
    assert_clean_error(
        &o,
        "no-odometry-at-all.jsonl",
        "40 × scan without odometry (--odometry on)",
    );
}

#[test]
fn a_run_refused_for_its_settings_makes_no_files() {
    // A followed wall beyond the laser's 5.6 m, and a top speed the physics step cannot
    // follow: refused before the output folder or the recording is made.
    for (name, toml, needle) in [
        (
            "far-wall",
            "[explorer]\nfollow.distance = 100\n",
            "follow.distance must be at most 5.6 (the laser's range_max), got 100",
        ),
        (
            "fast",
            "[robot]\nlimits.max_speed = 3\n",
            "[robot] limits.max_speed must be at most 2.5 (5 cm per physics step",
        ),
        (
            "reverse",
            "[robot]\nlimits.max_reverse = 50\n",
            "[robot] limits.max_reverse must be at most 2.5",
        ),
    ] {
        let params = tmp(&format!("{name}.toml"));
        std::fs::write(&params, toml).unwrap();
        let out = tmp(&format!("{name}-run"));
        let o = run(bin()
            .arg("simulate")
            .args(["--duration", "2", "--params"])
            .arg(&params)
            .arg("-o")
            .arg(&out)
            .arg("--mcap")
            .arg(out.join("run.mcap")));
        assert_clean_error(&o, &format!("{name}.toml"), needle);
        assert!(!out.exists(), "{name}: the output folder was made");
    }
    // A slower robot may take a coarser physics step: 0.3 m/s at 0.1 s is 3 cm a step.
    let params = tmp("slow.toml");
    std::fs::write(
        &params,
        "[robot]\nlimits.max_speed = 0.3\nlimits.max_reverse = 0.2\n\n[simulator]\nphysics_dt_s = 0.1\n",
    )
    .unwrap();
    let o = run(bin()
        .arg("simulate")
        .args(["--duration", "2", "--params"])
        .arg(&params)
        .arg("-o")
        .arg(tmp("slow-run")));
    assert!(o.status.success(), "{}", text(&o.stderr));
}
