//! The robot side stands on the core crate alone: `laserlines-nav` pulls in the core and
//! the mapping crate `laserlines-slam` and nothing else of ours, never the simulator, not
//! even for its tests; `laserlines-slam` itself builds on the core alone (its tests use the
//! simulator for ground truth, as dev-dependencies); so everything the robot runs runs on a
//! real robot. Checked on the dependency graph cargo itself resolves.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::process::Command;

/// The packages of `cargo tree -p PACKAGE` over the edges `edges`, one name a line.
fn tree(package: &str, edges: &str) -> Vec<String> {
    let out = Command::new(env!("CARGO"))
        .args(["tree", "-p", package, "-e", edges, "--prefix", "none"])
        .args([
            "--manifest-path",
            concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml"),
        ])
        .output()
        .expect("cargo runs");
    assert!(
        out.status.success(),
        "cargo tree failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| l.split_whitespace().next().map(str::to_owned))
        .collect()
}

#[test]
fn nav_depends_on_the_core_and_the_mapping_crate_alone() {
    let names = tree("laserlines-nav", "normal,build,dev");
    assert_eq!(names.first().map(String::as_str), Some("laserlines-nav"));
    let ours: Vec<&String> = names[1..]
        .iter()
        .filter(|n| n.starts_with("laserlines"))
        .collect();
    assert!(ours.iter().any(|n| *n == "laserlines"), "{ours:?}");
    assert!(ours.iter().any(|n| *n == "laserlines-slam"), "{ours:?}");
    assert!(
        ours.iter()
            .all(|n| *n == "laserlines" || *n == "laserlines-slam"),
        "{ours:?}"
    );
    assert!(!names.iter().any(|n| n == "laserlines-sim"));
}

#[test]
fn the_mapping_crate_depends_on_the_core_alone_and_does_no_io() {
    let names = tree("laserlines-slam", "normal,build");
    assert_eq!(names.first().map(String::as_str), Some("laserlines-slam"));
    let ours: Vec<&String> = names[1..]
        .iter()
        .filter(|n| n.starts_with("laserlines"))
        .collect();
    assert!(ours.iter().all(|n| *n == "laserlines"), "{ours:?}");
    assert!(!names.iter().any(|n| n == "laserlines-sim"));
    for io in ["flate2", "serde_json", "toml", "mcap", "bzip2"] {
        assert!(!names.iter().any(|n| n == io), "{io} in {names:?}");
    }
}

#[test]
fn the_core_has_no_laserlines_or_io_dependency() {
    let names = tree("laserlines", "normal");
    let ours: Vec<&String> = names[1..]
        .iter()
        .filter(|n| n.starts_with("laserlines"))
        .collect();
    assert!(ours.is_empty(), "{ours:?}");
    for io in ["flate2", "serde_json", "toml", "mcap", "bzip2"] {
        assert!(!names.iter().any(|n| n == io), "{io} in {names:?}");
    }
}
