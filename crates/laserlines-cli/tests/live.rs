//! `laserlines live` against `laserlines hokuyo-emulator` over TCP, as a user runs them:
//! the emulator's address from its first line, `live --scans N -o lines.jsonl`, one JSON
//! object per scan, a summary naming the scans, no scan dropped, QT at the end.

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

#[test]
fn live_reads_the_emulated_ust10lx_and_writes_lines_per_scan() {
    let bin = env!("CARGO_BIN_EXE_laserlines");
    let mut emulator = Command::new(bin)
        .args([
            "hokuyo-emulator",
            "--model",
            "ust-10lx",
            "--tcp",
            "127.0.0.1:0",
            "--duration",
            "60",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut first = String::new();
    BufReader::new(emulator.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    let addr = first.trim().rsplit(" on ").next().unwrap().to_owned();
    let dir = std::env::temp_dir().join(format!("laserlines-live-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("lines.jsonl");
    let run = Command::new(bin)
        .args(["live", &addr, "--scans", "25", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    let _ = emulator.kill();
    let _ = emulator.wait();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(stderr.contains("UST-10LX"), "{stderr}");
    assert!(
        stderr.contains("25 scans") && stderr.contains("dropped: none"),
        "{stderr}"
    );
    let text = std::fs::read_to_string(&out).unwrap();
    let scans: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(scans.len(), 25);
    let stamps: Vec<f64> = scans.iter().map(|s| s["stamp"].as_f64().unwrap()).collect();
    assert!(stamps.windows(2).all(|w| w[1] > w[0]));
    // The arena's walls give lines.
    assert!(
        scans
            .iter()
            .all(|s| !s["lines"].as_array().unwrap().is_empty())
    );
    let _ = std::fs::remove_dir_all(&dir);
}
