//! Poses and odometry through MCAP: what laserlines writes reads back field for field, and
//! transforms as a ROS system records them (REP 105: `map -> odom -> base_link`) give the
//! pose and the odometry they stand for.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::io::Cursor;

use laserlines::Scan;
use laserlines_foxglove::proto::transform_from_pose;
use laserlines_foxglove::read;
use laserlines_foxglove::write::McapSceneWriter;
use laserlines_io::{Pose2, ScanRecord};

fn record(stamp: f64, pose: Option<Pose2>, odometry: Option<Pose2>) -> ScanRecord {
    let mut r = ScanRecord::new(Scan::new(-0.5, 0.25, 0.1, 8.0, vec![1.0, 2.0, 3.0]).unwrap());
    r.scan.stamp = Some(stamp);
    r.pose = pose;
    r.odometry = odometry;
    r
}

fn read_back(bytes: Vec<u8>) -> Vec<ScanRecord> {
    read::from_reader("memory", Cursor::new(bytes), &Default::default())
        .unwrap()
        .map(Result::unwrap)
        .collect()
}

fn close(a: Option<Pose2>, b: Pose2) -> bool {
    a.is_some_and(|a| {
        (a.x - b.x).abs() < 1e-9
            && (a.y - b.y).abs() < 1e-9
            && laserlines::math::angle_diff(a.theta, b.theta) < 1e-9
    })
}

#[test]
fn pose_and_odometry_survive_a_round_trip() {
    let cases = [
        (
            Some(Pose2::new(1.0, -2.0, 0.3)),
            Some(Pose2::new(5.0, 4.0, -1.2)),
        ),
        (None, Some(Pose2::new(0.5, 0.25, 2.0))),
        (Some(Pose2::new(-3.0, 1.0, 3.0)), None),
        (None, None),
    ];
    let mut w = McapSceneWriter::new(Cursor::new(Vec::new()), "memory").unwrap();
    for (k, &(pose, odometry)) in cases.iter().enumerate() {
        w.write_scan(&record(k as f64, pose, odometry)).unwrap();
    }
    let back = read_back(w.finish().unwrap().into_inner());
    assert_eq!(back.len(), 4);
    // Both given: both back.
    assert!(close(back[0].pose, cases[0].0.unwrap()));
    assert!(close(back[0].odometry, cases[0].1.unwrap()));
    // Odometry alone: it is the pose too (the odometry frame placed at the world's origin).
    assert!(close(back[1].odometry, cases[1].1.unwrap()));
    assert!(close(back[1].pose, cases[1].1.unwrap()));
    // A pose alone: the pose; the odometry is the last one read (a transform holds for
    // the scans that follow it until the next).
    assert!(close(back[2].pose, cases[2].0.unwrap()));
    assert!(close(back[2].odometry, cases[1].1.unwrap()));
}

#[test]
fn a_ros_transform_chain_gives_pose_and_odometry() {
    let mut w = McapSceneWriter::new(Cursor::new(Vec::new()), "memory").unwrap();
    // Only `world -> base_link`: a pose, no odometry.
    w.write_transform(&transform_from_pose(
        "world",
        "base_link",
        Pose2::new(1.0, 2.0, 0.5),
        0.0,
    ))
    .unwrap();
    w.write_scan(&record(0.1, None, None)).unwrap();
    // `map -> odom` and `odom -> base_link`: the odometry, and the pose they compose.
    w.write_transform(&transform_from_pose(
        "map",
        "odom",
        Pose2::new(10.0, 0.0, std::f64::consts::FRAC_PI_2),
        1.0,
    ))
    .unwrap();
    w.write_transform(&transform_from_pose(
        "odom",
        "base_link",
        Pose2::new(1.0, 0.0, 0.0),
        1.0,
    ))
    .unwrap();
    w.write_scan(&record(1.1, None, None)).unwrap();
    let back = read_back(w.finish().unwrap().into_inner());
    assert_eq!(back.len(), 2);
    assert!(close(back[0].pose, Pose2::new(1.0, 2.0, 0.5)));
    assert_eq!(back[0].odometry, None);
    assert!(close(back[1].odometry, Pose2::new(1.0, 0.0, 0.0)));
    assert!(close(
        back[1].pose,
        Pose2::new(10.0, 1.0, std::f64::consts::FRAC_PI_2)
    ));
}
