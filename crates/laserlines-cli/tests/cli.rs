//! The `laserlines` command end to end: outputs on known inputs, and bad input that must end
//! in a clear error (file, line, what was wrong), exit code 2 and no panic.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::process::Output;

mod common;
use common::{bin, io_fixture, run, stderr, tmp};

/// Asserts a clean failure: exit code 2, a message naming `file` and `needle`, no panic.
fn assert_clean_error(o: &Output, file: &str, needle: &str) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "exit code; stderr: {err}");
    assert!(err.contains(file), "error does not name {file}: {err}");
    assert!(err.contains(needle), "error does not say {needle:?}: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
}

#[test]
fn malformed_json_names_file_and_line() {
    let o = run(bin()
        .args(["extract"])
        .arg(io_fixture("bad_malformed.json")));
    assert_clean_error(&o, "bad_malformed.json", ":3");
}

#[test]
fn ranges_of_the_wrong_type_name_the_field() {
    let o = run(bin()
        .args(["extract"])
        .arg(io_fixture("bad_ranges_type.jsonl")));
    assert_clean_error(&o, "bad_ranges_type.jsonl", "ranges");
}

#[test]
fn zero_angle_increment_is_rejected() {
    let o = run(bin()
        .args(["extract"])
        .arg(io_fixture("bad_increment_zero.json")));
    assert_clean_error(&o, "bad_increment_zero.json", "angle_increment");
}

#[test]
fn csv_row_with_a_missing_column_names_the_line() {
    let o = run(bin()
        .args(["extract"])
        .arg(io_fixture("bad_missing_column.csv")));
    assert_clean_error(&o, "bad_missing_column.csv", "column");
}

#[test]
fn truncated_dat_line_names_the_line() {
    let o = run(bin().args(["extract"]).arg(io_fixture("bad_truncated.dat")));
    assert_clean_error(&o, "bad_truncated.dat", "707 tokens");
}

#[test]
fn unknown_extension_and_algorithm_are_errors() {
    let f = tmp("scan.xyz");
    std::fs::write(&f, "1 2 3").unwrap();
    let o = run(bin().arg("extract").arg(&f));
    assert_clean_error(&o, "scan.xyz", "format");
    let o = run(bin()
        .args(["extract", "--algorithm", "nope"])
        .arg(io_fixture("scans.jsonl")));
    // clap checks the name against the registry's list, and gives the list.
    assert_clean_error(&o, "invalid value 'nope'", "possible values: hough-split");
}

#[test]
fn skip_bad_counts_what_it_skipped() {
    let o = run(bin()
        .args(["extract", "--skip-bad", "-o"])
        .arg(tmp("skip.jsonl"))
        .arg(io_fixture("bad_ranges_type.jsonl")));
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("2 scans"),
        "summary does not count the good scans: {err}"
    );
    assert!(
        err.contains("skipped: 2 × "),
        "summary does not count the skips: {err}"
    );
}

#[test]
fn extract_writes_one_object_per_scan_with_the_schema() {
    let out = tmp("demo-lines.jsonl");
    let dat = tmp("excerpt.dat.gz");
    std::fs::write(&dat, laserlines_io::demo::URG04LX_EXCERPT).unwrap();
    let o = run(bin().args(["extract", "-o"]).arg(&out).arg(&dat));
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    let records = laserlines_io::demo::urg04lx_excerpt().unwrap();
    let rows: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(rows.len(), records.len());
    let mut hs = laserlines::HoughSplit::new(laserlines::HoughSplitParams::default()).unwrap();
    for (k, (row, rec)) in rows.iter().zip(&records).enumerate() {
        assert_eq!(row["scan"], k);
        let lines = laserlines::LineExtractor::extract(&mut hs, &rec.scan);
        let got = row["lines"].as_array().unwrap();
        assert_eq!(got.len(), lines.len());
        for (g, l) in got.iter().zip(&lines) {
            assert_eq!(g["first"], l.first);
            assert_eq!(g["last"], l.last);
            assert_eq!(g["points"], l.points);
            assert_eq!(g["r"].as_f64().unwrap(), l.r);
            assert_eq!(g["alpha"].as_f64().unwrap(), l.alpha);
            assert_eq!(g["start"][0].as_f64().unwrap(), l.start.x);
            assert_eq!(g["end"][1].as_f64().unwrap(), l.end.y);
            assert_eq!(
                g["covariance"][1][1].as_f64().unwrap(),
                l.covariance[(1, 1)]
            );
            assert!(g["rms"].as_f64().unwrap() >= 0.0);
        }
    }
    assert!(stderr(&o).contains(&format!("{} scans", records.len())));
}

#[test]
fn params_file_changes_the_result_and_bad_keys_are_errors() {
    let dat = tmp("excerpt2.dat.gz");
    std::fs::write(&dat, laserlines_io::demo::URG04LX_EXCERPT).unwrap();
    let params = tmp("paper.toml");
    std::fs::write(&params, "[hough-split]\npaper = true\n").unwrap();
    let paper = run(bin().args(["extract", "--params"]).arg(&params).arg(&dat));
    let plain = run(bin().arg("extract").arg(&dat));
    assert!(paper.status.success() && plain.status.success());
    // The paper's 3 m range limit removes the far lines.
    assert_ne!(paper.stdout, plain.stdout);
    let paper_text = String::from_utf8(paper.stdout).unwrap();
    for row in paper_text.lines() {
        let v: serde_json::Value = serde_json::from_str(row).unwrap();
        for l in v["lines"].as_array().unwrap() {
            for end in ["start", "end"] {
                let (x, y) = (l[end][0].as_f64().unwrap(), l[end][1].as_f64().unwrap());
                assert!(
                    (x * x + y * y).sqrt() < 3.1,
                    "line beyond the paper's 3 m: {l}"
                );
            }
        }
    }
    std::fs::write(&params, "[hough-split]\nring_stp = 0.05\n").unwrap();
    let o = run(bin().args(["extract", "--params"]).arg(&params).arg(&dat));
    assert_clean_error(&o, "paper.toml", "ring_stp");
}

#[test]
fn preset_option_starts_from_the_preset_and_names_the_presets_it_knows() {
    let dat = tmp("excerpt-preset.dat.gz");
    std::fs::write(&dat, laserlines_io::demo::URG04LX_EXCERPT).unwrap();
    let params = tmp("paper-preset.toml");
    std::fs::write(&params, "[hough-split]\npaper = true\n").unwrap();
    let by_file = run(bin().args(["extract", "--params"]).arg(&params).arg(&dat));
    let by_option = run(bin().args(["extract", "--preset", "paper"]).arg(&dat));
    assert!(by_file.status.success(), "{}", stderr(&by_file));
    assert!(by_option.status.success(), "{}", stderr(&by_option));
    assert_eq!(by_file.stdout, by_option.stdout);
    // A params table is laid over the preset: the paper's range limits changed back.
    let wide = tmp("wide-preset.toml");
    std::fs::write(&wide, "[hough-split]\nrange_limits = [0.03, 5.0]\n").unwrap();
    let over = run(bin()
        .args(["extract", "--preset", "paper", "--params"])
        .arg(&wide)
        .arg(&dat));
    assert!(over.status.success(), "{}", stderr(&over));
    assert_ne!(over.stdout, by_option.stdout);
    // `complete` keeps more lines than the defaults: also those not known to 6 cm and 3 deg.
    let count = |o: &std::process::Output| {
        String::from_utf8_lossy(&o.stdout)
            .lines()
            .map(|row| {
                let v: serde_json::Value = serde_json::from_str(row).unwrap();
                v["lines"].as_array().unwrap().len()
            })
            .sum::<usize>()
    };
    let plain = run(bin().arg("extract").arg(&dat));
    let complete = run(bin().args(["extract", "--preset", "complete"]).arg(&dat));
    assert!(complete.status.success(), "{}", stderr(&complete));
    let (n_plain, n_complete) = (count(&plain), count(&complete));
    assert!(
        n_plain > 0 && n_complete > n_plain,
        "{n_complete} and {n_plain}"
    );
    // `walls` names the defaults.
    let walls = run(bin().args(["extract", "--preset", "walls"]).arg(&dat));
    assert_eq!(count(&walls), n_plain);
    // render takes the hough-split path with its stages, map the extractor of its own.
    let svg = tmp("walls.svg");
    let o = run(bin()
        .args(["render", "--preset", "walls", "--scan", "5", "-o"])
        .arg(&svg)
        .arg(&dat));
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run(bin().args(["map", "--preset", "wall"]).arg(&dat));
    assert_clean_error(&o, "unknown preset \"wall\" of hough-split", "walls");
    let o = run(bin().args(["extract", "--preset", "wall"]).arg(&dat));
    assert_clean_error(
        &o,
        "unknown preset \"wall\" of hough-split",
        "paper, navigation, walls, complete",
    );
    let o = run(bin()
        .args(["extract", "--algorithm", "iepf", "--preset", "walls"])
        .arg(&dat));
    assert_clean_error(&o, "of iepf", "no presets");
}

#[test]
fn render_draws_four_panels() {
    let dat = tmp("excerpt3.dat.gz");
    std::fs::write(&dat, laserlines_io::demo::URG04LX_EXCERPT).unwrap();
    let svg = tmp("fig.svg");
    let o = run(bin()
        .args(["render", "--scan", "5", "-o"])
        .arg(&svg)
        .arg(&dat));
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg") || text.starts_with("<?xml"));
    for panel in ["(a)", "(b)", "(c)", "(d)"] {
        assert!(text.contains(panel), "panel {panel} missing");
    }
    let o = run(bin()
        .args(["render", "--scan", "999", "-o"])
        .arg(&svg)
        .arg(&dat));
    assert_clean_error(&o, "excerpt3.dat.gz", "no scan 999");
}

#[test]
fn render_sectors_reports_a_wall_ahead() {
    // A straight wall 1 m ahead (x = 1, y from -2 to 2), exact ranges, URG-04LX beams.
    let n = 682;
    let inc = 360.0_f64.to_radians() / 1024.0;
    let angle_min = -inc * (n as f64 - 1.0) / 2.0;
    let ranges: Vec<String> = (0..n)
        .map(|i| {
            let phi = angle_min + inc * i as f64;
            let r = 1.0 / phi.cos();
            if phi.cos() > 0.0 && r * phi.sin().abs() <= 2.0 {
                format!("{r}")
            } else {
                "null".to_owned()
            }
        })
        .collect();
    let json = tmp("wall.json");
    std::fs::write(
        &json,
        format!(
            "{{\"angle_min\": {angle_min}, \"angle_increment\": {inc}, \"range_min\": 0.02, \"range_max\": 5.6, \"ranges\": [{}]}}\n",
            ranges.join(", ")
        ),
    )
    .unwrap();
    let svg = tmp("sectors.svg");
    let o = run(bin()
        .args(["render", "--sectors", "-o"])
        .arg(&svg)
        .arg(&json));
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    let figures = |sector: &str| -> (f64, f64, f64) {
        let line = out
            .lines()
            .find(|l| l.starts_with(&format!("{sector}: ")))
            .unwrap_or_else(|| panic!("no {sector} line in {out}"));
        let nums: Vec<f64> = line
            .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
            .filter_map(|t| t.parse().ok())
            .collect();
        (nums[0], nums[1], nums[2])
    };
    // Front: the wall's nearest point straight ahead, the part between -50 and +50 deg
    // (2 tan 50 deg = 2.384 m) visible, the wall running across the robot (+-90 deg).
    let (d, w, a) = figures("front");
    assert!((d - 1.0).abs() < 0.002, "{out}");
    assert!((w - 2.0 * 50f64.to_radians().tan()).abs() < 0.01, "{out}");
    assert!((a.abs() - 90.0).abs() < 0.2, "{out}");
    // Left: the wall from +50 deg (1.192 m to the left, 1.556 m away) to its end at y = 2
    // (the last beam falls short of the end by up to a beam's spacing there; widths are
    // asked within 5 cm).
    let (d, w, _) = figures("left");
    assert!((d - 1.0 / 50f64.to_radians().cos()).abs() < 0.01, "{out}");
    assert!((w - (2.0 - 50f64.to_radians().tan())).abs() < 0.05, "{out}");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("sector-front") && text.contains("selected-object"));
}

#[test]
fn demo_writes_lines_and_figures() {
    let dir = tmp("demo-out");
    let o = run(bin().args(["demo", "--repeat", "2", "-o"]).arg(&dir));
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8(o.stdout).unwrap();
    assert!(stdout.contains("us per scan"), "{stdout}");
    let lines = std::fs::read_to_string(dir.join("lines.jsonl")).unwrap();
    assert_eq!(
        lines.lines().count(),
        laserlines_io::demo::urg04lx_excerpt().unwrap().len()
    );
    assert!(
        std::fs::read_dir(&dir).unwrap().any(|e| e
            .unwrap()
            .path()
            .extension()
            .is_some_and(|x| x == "svg"))
    );
}

#[test]
fn a_closed_standard_output_ends_quietly() {
    // The reader of the pipe stops at once (as `| head` does): no panic, no error, exit 0.
    let dat = tmp("excerpt-pipe.dat.gz");
    std::fs::write(&dat, laserlines_io::demo::URG04LX_EXCERPT).unwrap();
    let svg = tmp("pipe.svg");
    let runs: [Vec<std::ffi::OsString>; 2] = [
        vec![
            "extract".into(),
            dat.clone().into(),
            "-o".into(),
            "-".into(),
        ],
        vec![
            "render".into(),
            dat.clone().into(),
            "--sectors".into(),
            "-o".into(),
            svg.into(),
        ],
    ];
    for args in runs {
        let mut child = bin()
            .args(&args)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let o = child.wait_with_output().unwrap();
        let err = stderr(&o);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(o.status.success(), "{args:?}: {err}");
        assert!(!err.contains("error"), "{args:?}: {err}");
        if args[0] == "extract" {
            // The summary still says how far it got.
            assert!(
                err.contains("standard output closed by its reader after"),
                "{err}"
            );
        }
    }
}

#[test]
fn a_closed_standard_error_changes_no_exit_code() {
    // `laserlines ... 2>&1 | head` whose reader has gone: the messages are lost, the exit
    // code is what it would have been (0 for a run, 2 for an error), never a panic's 101.
    let dat = tmp("excerpt-closed-stderr.dat.gz");
    std::fs::write(&dat, laserlines_io::demo::URG04LX_EXCERPT).unwrap();
    let missing = tmp("no-such-log.dat");
    let runs: [(Vec<std::ffi::OsString>, i32); 3] = [
        (
            vec![
                "extract".into(),
                dat.clone().into(),
                "-o".into(),
                "-".into(),
            ],
            0,
        ),
        (
            vec![
                "convert".into(),
                dat.clone().into(),
                "-".into(),
                "--to".into(),
                "jsonl".into(),
            ],
            0,
        ),
        (vec!["extract".into(), missing.into()], 2),
    ];
    for (args, code) in runs {
        let mut child = bin()
            .args(&args)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stderr.take());
        let status = child.wait().unwrap();
        assert_eq!(status.code(), Some(code), "{args:?}");
    }
}

#[test]
fn a_spinning_scanners_raw_readings_give_the_rooms_four_walls() {
    // Clockwise degrees and millimetres at uneven bearings (tests/fixtures/readings_room.csv
    // of laserlines-io): the room x = +-2, y = +-1.5 m seen from (0.5, -0.3).
    let o = run(bin()
        .args(["extract", "-o", "-"])
        .arg(common::io_fixture("readings_room.csv")));
    assert!(o.status.success(), "{}", common::stderr(&o));
    let out = common::text(&o.stdout);
    let record: serde_json::Value = serde_json::from_str(out.lines().next().unwrap()).unwrap();
    let lines = record["lines"].as_array().unwrap();
    use std::f64::consts::{FRAC_PI_2, PI, TAU};
    let walls = [(1.5, 0.0), (2.5, PI), (1.8, FRAC_PI_2), (1.2, -FRAC_PI_2)];
    for (r, alpha) in walls {
        let found = lines.iter().any(|l| {
            let (lr, la) = (l["r"].as_f64().unwrap(), l["alpha"].as_f64().unwrap());
            let da = (la - alpha + PI).rem_euclid(TAU) - PI;
            (lr - r).abs() < 0.03 && da.abs() < 0.03
        });
        assert!(found, "wall r {r} alpha {alpha}: {out}");
    }
    let err = common::stderr(&o);
    assert!(
        err.contains(
            "skipped: 38 × reading on a beam that kept a better one (readings put on a grid of beams)"
        ),
        "{err}"
    );
}
