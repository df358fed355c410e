//! `laserlines simulate` end to end: outputs and bad input.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_laserlines"))
}

#[test]
fn simulate_writes_metrics_and_pictures() {
    let dir = std::env::temp_dir().join(format!("laserlines-simulate-{}", std::process::id()));
    let o = bin()
        .args([
            "simulate",
            "--arena",
            "inner_explore_test",
            "--duration",
            "25",
            "--snapshot",
            "5",
            "-o",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(dir.join("metrics.json")).unwrap();
    let m: serde_json::Value = serde_json::from_str(&text).unwrap();
    for key in [
        "coverage",
        "collisions",
        "min_clearance_m",
        "path_length_m",
        "sim_time_s",
        "wall_time_s",
        "time_to_90_percent_s",
    ] {
        assert!(m.get(key).is_some(), "{key} missing in {text}");
    }
    assert_eq!(m["collisions"], 0);
    assert!((m["sim_time_s"].as_f64().unwrap() - 25.0).abs() < 0.1);
    let map = std::fs::read_to_string(dir.join("map.svg")).unwrap();
    assert!(map.contains("class=\"wall\"") && map.contains("class=\"path\""));
    let sectors = std::fs::read_to_string(dir.join("sectors.svg")).unwrap();
    assert!(sectors.contains("sector-front") && sectors.contains("selected-object"));
}

#[test]
fn simulate_rejects_bad_input() {
    let o = bin()
        .args([
            "simulate",
            "--arena",
            "inner_explore_test",
            "--start",
            "0.6,0,0",
            "--duration",
            "5",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("start pose") && !err.contains("panicked"),
        "{err}"
    );
    let o = bin()
        .args(["simulate", "--arena", "no_such_arena.raf"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("no_such_arena.raf"), "{err}");
}
