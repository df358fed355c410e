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
