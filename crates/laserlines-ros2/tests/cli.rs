//! The node's command line as a user meets it: settings it cannot honour are refused before
//! it joins the network.

use std::process::Command;

#[test]
fn discovery_turned_off_is_refused_before_the_node_starts() {
    let o = Command::new(env!("CARGO_BIN_EXE_laserlines-ros2"))
        .env("ROS_AUTOMATIC_DISCOVERY_RANGE", "OFF")
        .args(["--duration", "1"])
        .output()
        .expect("the node runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("ROS_AUTOMATIC_DISCOVERY_RANGE=OFF turns discovery off"),
        "{err}"
    );
}

#[test]
fn a_params_table_the_node_does_not_read_is_said() {
    let params = std::env::temp_dir().join(format!("laserlines-ros2-{}.toml", std::process::id()));
    std::fs::write(&params, "[ransac]\nmax_iterations = 50\n").expect("a temporary file");
    let o = Command::new(env!("CARGO_BIN_EXE_laserlines-ros2"))
        .arg("--params")
        .arg(&params)
        .args(["--localhost-only", "--duration", "0.2"])
        .env_remove("ROS_AUTOMATIC_DISCOVERY_RANGE")
        .output()
        .expect("the node runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("[ransac] is not used by laserlines-ros2 (the algorithm is hough-split)"),
        "{err}"
    );
    let _ = std::fs::remove_file(&params);
}
