//! `laserlines simulate` end to end: outputs and bad input.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::ffi::OsStr;
use std::path::Path;

mod common;
use common::{bin, tum_rows};

/// Runs `laserlines simulate` in the bundled `inner_explore_test` for `duration` seconds into
/// `dir`, with `extra` arguments; asserts that it succeeds and returns its `metrics.json`
/// (and the file's text).
fn simulate_ok(dir: &Path, duration: &str, extra: &[&OsStr]) -> (serde_json::Value, String) {
    let o = bin()
        .args([
            "simulate",
            "--arena",
            "inner_explore_test",
            "--duration",
            duration,
            "-o",
        ])
        .arg(dir)
        .args(extra)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(dir.join("metrics.json")).unwrap();
    (serde_json::from_str(&text).unwrap(), text)
}

#[test]
fn simulate_writes_metrics_and_pictures() {
    let dir = std::env::temp_dir().join(format!("laserlines-simulate-{}", std::process::id()));
    let (m, text) = simulate_ok(&dir, "25", &["--snapshot".as_ref(), "5".as_ref()]);
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

/// The output folder of [`simulate_args`] for `tag`.
fn tagged_dir(tag: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("laserlines-{tag}-{}", std::process::id()))
}

/// Runs `laserlines simulate` with `args` into a fresh folder named after `tag`; its
/// `metrics.json`.
fn simulate_args(tag: &str, args: &[&str]) -> serde_json::Value {
    let dir = tagged_dir(tag);
    let o = bin()
        .arg("simulate")
        .args(args)
        .arg("-o")
        .arg(&dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(dir.join("metrics.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

#[test]
fn simulate_reports_the_arena_and_a_robot_out_of_it() {
    let m = simulate_args("go2011", &["--arena", "go2011_arena", "--duration", "3"]);
    let arena = &m["arena"];
    assert_eq!(arena["elements"], 178);
    assert_eq!(arena["in_plane"]["wall_diag_120"], 6);
    assert_eq!(arena["out_of_plane"]["half_ramp"], 40);
    assert_eq!(arena["skipped_count"], 0);
    assert_eq!(arena["laser_height_m"], 0.45);
    assert_eq!(m["coverage_region"], "enclosed");
    assert_eq!(m["left_arena"], false);
    assert!(
        m["wall_time_includes"]
            .as_str()
            .unwrap()
            .contains("closed loop")
    );
    for key in [
        "setup_time_s",
        "load_time_s",
        "arena_area_m2",
        "reachable_coverage",
    ] {
        assert!(m[key].as_f64().is_some(), "{key}");
    }
    // A start in the corner of inner_explore_test's bounds, outside the walls that enclose
    // it: the robot is in the arena's bounds (not left), but coverage is taken over the
    // bounds, of which it sees little. A start beyond the bounds is refused (tests/edges.rs).
    let out = simulate_args(
        "outside",
        &[
            "--arena",
            "inner_explore_test",
            "--start=-4.1,-6.5,0",
            "--duration",
            "1",
        ],
    );
    assert_eq!(out["left_arena"], false);
    assert_eq!(out["coverage_region"], "bounds");
    assert!(out["coverage"].as_f64().unwrap() < 0.25, "{out}");
    // --fence: the arena's bounds as the explorer's fence (its effect: tests of
    // laserlines-harness, fence.rs).
    let fenced = simulate_args(
        "fence",
        &["--arena", "rc_2015_arena_big", "--fence", "--duration", "5"],
    );
    assert_eq!(fenced["collisions"], 0);
    assert_eq!(fenced["left_arena"], false);
    // Its bounds, x -9.0..9.0 and y -0.6..16.2 m, seen from the start at the origin.
    let fence = &fenced["fence"];
    assert_eq!(
        fence["half_extent"],
        serde_json::json!([9.0, 8.4]),
        "{fence}"
    );
    assert_eq!(fence["centre"], serde_json::json!([0.0, 7.8]), "{fence}");
    assert_eq!(m.get("fence"), Some(&serde_json::Value::Null));
    // The map picture draws it (and only when there is one).
    let picture = |tag: &str| std::fs::read_to_string(tagged_dir(tag).join("map.svg")).unwrap();
    assert!(picture("fence").contains("class=\"fence\""));
    assert!(!picture("go2011").contains("class=\"fence\""));
}

#[test]
fn simulate_rejects_bad_input() {
    // A start on a wall: refused before any folder is made, with no warning before it.
    let dir = std::env::temp_dir().join(format!("laserlines-on-wall-{}", std::process::id()));
    let o = bin()
        .args([
            "simulate",
            "--arena",
            "inner_explore_test",
            "--start",
            "0.6,0,0",
            "--duration",
            "5",
            "-o",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains(
            "start pose (x 0.600 m, y 0.000 m, yaw 0.0 deg) puts the robot's footprint on wall 23"
        ) && !err.contains("warning")
            && !err.contains("panicked"),
        "{err}"
    );
    assert!(!dir.exists());
    let o = bin()
        .args(["simulate", "--arena", "no_such_arena.raf"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("no_such_arena.raf"), "{err}");
    // A laser mounted 5 m from the robot: refused, naming the field.
    let params =
        std::env::temp_dir().join(format!("laserlines-far-laser-{}.toml", std::process::id()));
    std::fs::write(
        &params,
        "[robot]\nlaser = { x = 5.0, y = 0.0, yaw = 0.0 }\n",
    )
    .unwrap();
    let o = bin()
        .args(["simulate", "--duration", "1", "--params"])
        .arg(&params)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("laser.x, laser.y") && err.contains("got 5"),
        "{err}"
    );
}

#[test]
fn an_arena_without_a_floor_or_room_for_the_robot_is_refused() {
    let dir = std::env::temp_dir().join(format!("laserlines-nofloor-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let wall = |rotation: u32| {
        format!(r#"<element type="small_wall" rotation="{rotation}" x="0" y="0"/>"#)
    };
    // One wall, and a 1.2 m cell whose two half barrels leave no place 0.32 m from all.
    let one = format!("<elements>\n{}\n</elements>\n", wall(0));
    let cell = format!(
        "<elements>\n{}\n{}\n{}\n{}\n\
         <element type=\"red_barrel\" rotation=\"0\" x=\"0\" y=\"0\"/>\n\
         <element type=\"red_barrel\" rotation=\"180\" x=\"0\" y=\"0\"/>\n</elements>\n",
        wall(0),
        wall(90),
        wall(180),
        wall(270)
    );
    let cases = [
        (
            "one_wall.raf",
            one,
            "one_wall.raf: its walls enclose no floor: their largest group spans 1.20 m x 0.00 m",
        ),
        (
            "no_room.raf",
            cell,
            "no_room.raf: no place among its walls where the robot fits, 0.32 m from every \
             obstacle; give a start with --start",
        ),
    ];
    for (name, text, says) in cases {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let o = bin()
            .args(["simulate", "--duration", "2", "-o"])
            .arg(dir.join("out"))
            .arg("--arena")
            .arg(&path)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains(says), "{err}");
        assert!(!dir.join("out").join("metrics.json").exists(), "{name}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_start_within_the_turning_radius_is_warned_of_and_a_robot_that_never_moved_named() {
    // 0.30 m from the nearest wall of the default arena: the robot needs 0.32 m to turn.
    let out = std::env::temp_dir().join(format!("laserlines-cramped-{}", std::process::id()));
    let o = bin()
        .args(["simulate", "--duration", "2", "--start", "0.3,0.3,0", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains(
            "lies 0.30 m from the nearest obstacle, within the robot's turning radius of 0.32 m"
        ),
        "{err}"
    );
    // The area it can reach is the arena's.
    let metrics = std::fs::read_to_string(out.join("metrics.json")).unwrap();
    let m: serde_json::Value = serde_json::from_str(&metrics).unwrap();
    assert!(m["reachable_area_m2"].as_f64().unwrap() > 50.0, "{metrics}");
    // In inner_explore_test the same start leaves the planner no way out: the run ends
    // "explored" where it began, and the summary says why.
    let o = bin()
        .args([
            "simulate",
            "--arena",
            "inner_explore_test",
            "--start",
            "0.3,0.3,0",
            "-o",
        ])
        .arg(&out)
        .output()
        .unwrap();
    let (text, err) = (
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr),
    );
    assert!(o.status.success(), "{err}");
    let metrics = std::fs::read_to_string(out.join("metrics.json")).unwrap();
    let m: serde_json::Value = serde_json::from_str(&metrics).unwrap();
    assert!(m["path_length_m"].as_f64().unwrap() < 0.05, "{metrics}");
    assert_eq!(m["stop"], "explored", "{metrics}");
    assert!(
        text.contains("the robot did not move from its start"),
        "{text}"
    );
}

#[test]
fn simulate_records_the_run_as_mcap() {
    use foxglove::messages::{FrameTransform, SceneUpdate};
    use prost::Message as _;

    let dir = std::env::temp_dir().join(format!("laserlines-simulate-mcap-{}", std::process::id()));
    let mcap_path = dir.join("run.mcap");
    let (m, _) = simulate_ok(
        &dir,
        "3",
        &["--mcap".as_ref(), mcap_path.as_os_str(), "--fence".as_ref()],
    );
    let scans = m["scans"].as_u64().unwrap();
    assert_eq!(scans, 30, "3 s at 10 Hz");

    // The scans as laserlines reads them back: the URG-04LX's 682 beams each.
    let records: Vec<_> = laserlines_foxglove::read::open(
        &mcap_path,
        &laserlines_foxglove::McapReadOptions::default(),
    )
    .unwrap()
    .collect::<Result<_, _>>()
    .unwrap();
    assert_eq!(records.len() as u64, scans);
    assert!(records.iter().all(|r| r.scan.ranges.len() == 682));
    // Each with the true pose and the wheel odometry: both start at the origin, and the
    // odometry drifts from the truth by its noise only (3 s of driving: centimetres).
    let (first, last) = (&records[0], &records[records.len() - 1]);
    let (p, o) = (first.pose.unwrap(), first.odometry.unwrap());
    assert!(
        p.x.abs() < 1e-12 && p.y.abs() < 1e-12 && p.theta.abs() < 1e-12,
        "{p:?}"
    );
    assert!(
        o.x.abs() < 1e-12 && o.y.abs() < 1e-12 && o.theta.abs() < 1e-12,
        "{o:?}"
    );
    let (p, o) = (last.pose.unwrap(), last.odometry.unwrap());
    let drift = (p.x - o.x).hypot(p.y - o.y);
    assert!(p.x.hypot(p.y) > 0.3, "the robot moved: {p:?}");
    assert!(drift < 0.05 && drift > 0.0, "odometry {o:?}, truth {p:?}");

    // `map` takes the run back with its odometry (the default) and follows the truth.
    let map_dir = dir.join("map");
    let o = bin()
        .arg("map")
        .arg(&mcap_path)
        .arg("-o")
        .arg(&map_dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let traj = tum_rows(&map_dir.join("trajectory.tum"));
    let end = traj.last().unwrap();
    // The map frame is the first scan's laser frame, 0.15 m ahead of the robot's start.
    let (s, c) = p.theta.sin_cos();
    let (lx, ly) = (p.x + 0.15 * c - 0.15, p.y + 0.15 * s);
    let off = (end[1] - lx).hypot(end[2] - ly);
    assert!(
        off < 0.05,
        "mapped end ({}, {}), true ({lx}, {ly})",
        end[1],
        end[2]
    );

    // Every message by topic, with the stock reader of the `mcap` crate.
    let bytes = std::fs::read(&mcap_path).unwrap();
    let mut by_topic: std::collections::HashMap<String, Vec<Vec<u8>>> = Default::default();
    for msg in mcap::MessageStream::new(&bytes).unwrap() {
        let msg = msg.unwrap();
        by_topic
            .entry(msg.channel.topic.clone())
            .or_default()
            .push(msg.data.into_owned());
    }
    for topic in ["/lines", "/sectors", "/explorer"] {
        assert_eq!(by_topic[topic].len() as u64, scans, "{topic}");
    }
    // The arena once, with every wall of the bundled arena.
    let arena = laserlines_harness::arenas::bundled("inner_explore_test", &Default::default())
        .unwrap()
        .unwrap();
    let walls = SceneUpdate::decode(by_topic["/arena"][0].as_slice()).unwrap();
    assert_eq!(by_topic["/arena"].len(), 2);
    // Then the fence (--fence): the arena's bounds as a closed line of four sides.
    let fence = SceneUpdate::decode(by_topic["/arena"][1].as_slice()).unwrap();
    assert_eq!(fence.entities[0].id, "fence");
    let corners = &fence.entities[0].lines[0].points;
    assert_eq!(corners.len(), 8);
    let (lo, hi) = laserlines_sim::arena::ArenaOutline::new(&arena.world)
        .bounds()
        .unwrap();
    for p in corners {
        let on_x = (p.x - lo.x).abs() < 1e-9 || (p.x - hi.x).abs() < 1e-9;
        let on_y = (p.y - lo.y).abs() < 1e-9 || (p.y - hi.y).abs() < 1e-9;
        assert!(on_x && on_y, "{p:?}");
    }
    assert_eq!(
        walls.entities[0].lines[0].points.len(),
        2 * arena.world.walls.len()
    );
    // Four transforms per scan, a tree (REP 105): `world -> odom -> base_link -> laser` and
    // the estimate; the first two place the robot at the start (the origin, facing +x) and
    // the laser 0.15 m ahead of the axle.
    let tf = &by_topic["/tf"];
    assert_eq!(tf.len() as u64, 4 * scans);
    let frames: Vec<FrameTransform> = tf[..4]
        .iter()
        .map(|d| FrameTransform::decode(d.as_slice()).unwrap())
        .collect();
    let pairs: Vec<(&str, &str)> = frames
        .iter()
        .map(|f| (f.parent_frame_id.as_str(), f.child_frame_id.as_str()))
        .collect();
    assert_eq!(
        pairs,
        [
            ("world", "odom"),
            ("odom", "base_link"),
            ("base_link", "laser"),
            ("world", "base_link_estimate")
        ]
    );
    for f in &frames[..2] {
        let t = f.translation.as_ref().unwrap();
        assert_eq!((t.x, t.y), (0.0, 0.0));
    }
    let (laser, estimate) = (&frames[2], &frames[3]);
    assert_eq!(laser.child_frame_id, "laser");
    assert!((laser.translation.unwrap().x - 0.15).abs() < 1e-12);
    assert_eq!(estimate.child_frame_id, "base_link_estimate");
    // The sector objects: every object's label gives the distance of its nearest point.
    let mut objects = 0;
    for data in &by_topic["/sectors"] {
        let e = &SceneUpdate::decode(data.as_slice()).unwrap().entities[0];
        assert_eq!(e.frame_id, "base_link");
        for (s, label) in e.spheres.iter().zip(&e.texts) {
            let p = s.pose.as_ref().unwrap().position.as_ref().unwrap();
            let d: f64 = label
                .text
                .split(": ")
                .nth(1)
                .unwrap()
                .split(" m")
                .next()
                .unwrap()
                .parse()
                .unwrap();
            assert!((p.x.hypot(p.y) - d).abs() <= 0.005 + 1e-9, "{}", label.text);
            objects += 1;
        }
    }
    assert!(objects > 0);
}

#[test]
fn simulate_takes_robot_and_explorer_settings_from_a_params_file() {
    let dir =
        std::env::temp_dir().join(format!("laserlines-simulate-params-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let params = dir.join("robot.toml");
    std::fs::write(
        &params,
        "[robot]\nlimits.max_speed = 0.2\nfootprint.width = 0.35\nlaser.x = 0.1\n\n[explorer]\nside = \"right\"\nfollow.cruise_speed = 0.2\n",
    )
    .unwrap();
    let (m, text) = simulate_ok(&dir, "20", &["--params".as_ref(), params.as_os_str()]);
    // At most 0.2 m/s for 20 s (the default robot drives up to 0.6 m/s).
    let path = m["path_length_m"].as_f64().unwrap();
    assert!(path > 0.5 && path <= 0.2 * 20.0 + 1e-9, "{text}");
    assert_eq!(m["collisions"], 0);
    assert!(m["params"].as_str().unwrap().ends_with("robot.toml"));

    // Bad settings: a clear error naming the table and the key, exit code 2.
    for (body, needle) in [
        ("[robot]\nfootprint.width = -1\n", "[robot] footprint.width"),
        ("[robot]\nwheels = 3\n", "wheels"),
        (
            "[explorer]\nfollow.distance = 0\n",
            "[explorer] follow.distance",
        ),
        ("[explorer]\nside = \"up\"\n", "[explorer] side"),
        (
            "[simulator]\nphysics_dt_s = 0.5\n",
            "[simulator] physics_dt_s",
        ),
        ("[robot]\nfootprint_width = 0.4\n", "footprint_width"),
        (
            "[explorer.fence]\ncentre = [0.0, 0.0]\nhalf_extent = [0.0, 3.0]\nyaw = 0.0\n",
            "fence.half_extent",
        ),
        (
            "[explorer]\nsafety.turn_margin = -0.01\n",
            "[explorer] safety.turn_margin",
        ),
    ] {
        std::fs::write(&params, body).unwrap();
        let o = bin()
            .args(["simulate", "--duration", "1", "-o"])
            .arg(&dir)
            .arg("--params")
            .arg(&params)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{body}: {err}");
        assert!(
            err.contains(needle) && !err.contains("panicked"),
            "{body}: {err}"
        );
    }
}
