//! What the command's end-to-end tests share: the binary, the repository's files, a
//! temporary folder per test binary, and the larger data of `../shared`.

#![allow(dead_code, clippy::expect_used, clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

#[path = "../../../../tests/shared_data.rs"]
pub mod shared_data;

/// The `laserlines` binary of this build.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_laserlines"))
}

/// A file of the repository, by its path from the repository's root.
pub fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

/// The bundled URG-04LX excerpt (40 scans of BreezySLAM's `exp1`).
pub fn excerpt() -> PathBuf {
    repo("data/urg04lx-exp1-excerpt.dat.gz")
}

/// A fixture of the readers' tests (`crates/laserlines-io/tests/fixtures`).
pub fn io_fixture(name: &str) -> PathBuf {
    repo("crates/laserlines-io/tests/fixtures").join(name)
}

/// `name` in this test binary's own temporary folder (created).
pub fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "laserlines-{}-test-{}",
        env!("CARGO_CRATE_NAME"),
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Runs the command to its end.
pub fn run(cmd: &mut Command) -> Output {
    cmd.output().expect("the laserlines binary runs")
}

/// Bytes of an output stream as text.
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The command's standard error as text.
pub fn stderr(o: &Output) -> String {
    text(&o.stderr)
}

/// Asserts a clean failure: exit code 2, every one of `needles` in the message, no panic.
pub fn fails_with(o: &Output, needles: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "exit code; stderr: {err}");
    for needle in needles {
        assert!(
            err.contains(needle),
            "stderr does not say {needle:?}: {err}"
        );
    }
    assert!(!err.contains("panicked"), "{err}");
}

/// The Freiburg benchmark's MIT CSAIL log with its ground-truth relations, or `None` (with a
/// notice; a failure when `LASERLINES_REQUIRE_SHARED=1`) when `../shared` is absent.
pub fn mit_csail() -> Option<(PathBuf, PathBuf)> {
    let real = shared_data::path("real");
    let what = "the MIT CSAIL mapping test";
    Some((
        shared_data::available(real.join("mit-csail-clf/mit-csail.clf.gz"), what)?,
        shared_data::available(
            real.join("freiburg-slam-benchmark-relations/mit-csail.relations"),
            what,
        )?,
    ))
}

/// Maps `log` with the defaults into the temporary folder `name` and scores it on the
/// relations file `relations` (both printed): the mean translational (m) and rotational (deg)
/// errors, and the scorer's whole output.
pub fn map_and_score(log: &Path, relations: &Path, name: &str) -> (f64, f64, String) {
    let dir = tmp(name);
    let o = run(bin().arg("map").arg(log).arg("-o").arg(&dir));
    assert!(o.status.success(), "{}", text(&o.stderr));
    eprintln!("{}", text(&o.stderr));
    let o = run(bin()
        .arg("relations")
        .arg(dir.join("trajectory.tum"))
        .arg(relations));
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    eprintln!("{out}");
    let mean = |what: &str| -> f64 {
        let line = out.lines().find(|l| l.starts_with(what)).unwrap();
        line[what.len()..]
            .split_whitespace()
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    (mean("translational error"), mean("rotational error"), out)
}

/// Asserts a clean failure: exit code 2, a message naming `file` and `needle`, no panic.
pub fn assert_clean_error(o: &Output, file: &str, needle: &str) {
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "exit code; stderr: {err}");
    assert!(err.contains(file), "error does not name {file}: {err}");
    assert!(err.contains(needle), "error does not say {needle:?}: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
}

/// The 8 numbers of each non-comment line of a TUM file.
pub fn tum_rows(path: &Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split_whitespace().map(|v| v.parse().unwrap()).collect())
        .collect()
}

/// `extract` of the bundled excerpt to standard output with a params file `name` holding
/// `toml`.
pub fn extract_with_params(name: &str, toml: &str) -> Output {
    let params = tmp(name);
    std::fs::write(&params, toml).unwrap();
    run(bin()
        .arg("extract")
        .arg(excerpt())
        .arg("--params")
        .arg(&params)
        .args(["-o", "-"]))
}

/// The port of the first status line of `view` or `live --view`
/// (`... serving ws://127.0.0.1:PORT ...`).
pub fn served_port(first: &str) -> u16 {
    first
        .split("ws://127.0.0.1:")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no port in {first:?}"))
}
