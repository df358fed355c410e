//! `laserlines map` on hand-made CARMEN logs: the odometry triple followed and never the
//! laser pose, stamps that do not increase, and odometry that jumps too far for a grid.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;
use common::{assert_clean_error, bin, run, text, tmp, tum_rows};

/// Ranges of 181 beams, 1 deg apart from -90 deg, from `(x, y, theta)` in a 6 m x 4 m room
/// (walls at x = +-3 m, y = +-2 m) with a square pillar (0.8..1.2 m, 0.5..0.9 m).
fn room_ranges(x: f64, y: f64, theta: f64) -> Vec<f64> {
    (0..181)
        .map(|i| {
            let a = theta + f64::from(i - 90).to_radians();
            let (s, c) = a.sin_cos();
            let exit = |p: f64, d: f64, half: f64| {
                if d.abs() < 1e-12 {
                    f64::INFINITY
                } else {
                    (half.copysign(d) - p) / d
                }
            };
            let room = exit(x, c, 3.0).min(exit(y, s, 2.0));
            // The pillar by slabs: entry distance, when the ray meets it.
            let slab = |p: f64, d: f64, lo: f64, hi: f64| {
                if d.abs() < 1e-12 {
                    if p > lo && p < hi {
                        (f64::NEG_INFINITY, f64::INFINITY)
                    } else {
                        (f64::INFINITY, f64::NEG_INFINITY)
                    }
                } else {
                    let (a, b) = ((lo - p) / d, (hi - p) / d);
                    (a.min(b), a.max(b))
                }
            };
            let (ax, bx) = slab(x, c, 0.8, 1.2);
            let (ay, by) = slab(y, s, 0.5, 0.9);
            let (enter, leave) = (ax.max(ay), bx.min(by));
            if enter > 0.0 && enter <= leave {
                room.min(enter)
            } else {
                room
            }
        })
        .collect()
}

/// A `FLASER` line of 181 `ranges` (printed to 0.1 mm) with its laser pose and odometry
/// triples and `time` as both the IPC and the logger time stamp.
fn flaser(
    ranges: &[f64],
    (lx, ly, lt): (f64, f64, f64),
    (ox, oy, ot): (f64, f64, f64),
    time: f64,
) -> String {
    let ranges: Vec<String> = ranges.iter().map(|r| format!("{r:.4}")).collect();
    format!(
        "FLASER 181 {} {lx:.6} {ly:.6} {lt:.6} {ox:.6} {oy:.6} {ot:.6} {time:.3} host {time:.3}\n",
        ranges.join(" ")
    )
}

/// The yaw of a TUM row's quaternion (`qz`, `qw`).
fn tum_yaw(row: &[f64]) -> f64 {
    2.0 * row[6].atan2(row[7])
}

/// A hand-made CARMEN log whose two pose triples differ: the odometry triple is the true
/// motion (in an odometry frame of its own), the laser pose triple is nonsense (metres and
/// radians apart from scan to scan). `map --odometry on` must follow the odometry.
#[test]
fn maps_a_carmen_log_by_its_odometry_triple_never_its_laser_pose() {
    let truth: Vec<(f64, f64, f64)> = (0..40)
        .map(|k| {
            let k = f64::from(k);
            (-1.5 + 0.06 * k, -0.5 + 0.3 * (0.1 * k).sin(), 0.02 * k)
        })
        .collect();
    // The odometry frame: the world turned by 0.5 rad and moved by (2, -1).
    let odom = |&(x, y, t): &(f64, f64, f64)| {
        let (s, c) = 0.5_f64.sin_cos();
        (2.0 + c * x - s * y, -1.0 + s * x + c * y, t + 0.5)
    };
    let laser_pose = |k: usize| {
        let k = k as f64;
        (100.0 + 3.0 * k, -40.0 + 2.0 * k.sin(), 1.1 * k)
    };
    let mut log = String::from("# hand-made: odometry triple true, laser pose triple not\n");
    for (k, t) in truth.iter().enumerate() {
        let time = 10.0 + 0.1 * k as f64;
        log.push_str(&flaser(
            &room_ranges(t.0, t.1, t.2),
            laser_pose(k),
            odom(t),
            time,
        ));
    }
    let path = tmp("two-triples.clf");
    std::fs::write(&path, &log).unwrap();
    let dir = tmp("two-triples");
    let o = run(bin()
        .arg("map")
        .arg(&path)
        .arg("-o")
        .arg(&dir)
        .args(["--loop-closure", "off"]));
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(!text(&o.stderr).contains("stamps"), "{}", text(&o.stderr));
    // The same log with every stamp 0 (as some Radish logs have): mapped alike, the stamps
    // kept as written, and a note says they do not increase.
    let zero = tmp("zero-stamps.clf");
    let zeroed: String = log
        .lines()
        .map(|l| match l.rsplitn(4, ' ').collect::<Vec<_>>()[..] {
            [_, host, _, head] if l.starts_with("FLASER") => format!("{head} 0 {host} 0\n"),
            _ => format!("{l}\n"),
        })
        .collect();
    std::fs::write(&zero, zeroed).unwrap();
    let zero_dir = tmp("zero-stamps");
    let z = run(bin()
        .arg("map")
        .arg(&zero)
        .arg("-o")
        .arg(&zero_dir)
        .args(["--loop-closure", "off"]));
    assert!(z.status.success(), "{}", text(&z.stderr));
    assert!(
        text(&z.stderr).contains(
            "zero-stamps.clf: the scans' stamps do not increase (all are 0 s): the trajectory \
             files keep them as written"
        ),
        "{}",
        text(&z.stderr)
    );
    let zero_traj = tum_rows(&zero_dir.join("trajectory.tum"));
    assert_eq!(zero_traj.len(), 40);
    assert!(zero_traj.iter().all(|row| row[0] == 0.0));
    // The files of the log's own poses hold each triple where it belongs.
    let odometry = tum_rows(&dir.join("odometry.tum"));
    let logged = tum_rows(&dir.join("log-poses.tum"));
    assert_eq!((odometry.len(), logged.len()), (40, 40));
    for (k, (o_row, l_row)) in odometry.iter().zip(&logged).enumerate() {
        let (ox, oy, ot) = odom(&truth[k]);
        let (lx, ly, lt) = laser_pose(k);
        assert!((o_row[1] - ox).abs() < 1e-5 && (o_row[2] - oy).abs() < 1e-5);
        assert!(laserlines::math::angle_diff(tum_yaw(o_row), ot) < 1e-5);
        assert!((l_row[1] - lx).abs() < 1e-5 && (l_row[2] - ly).abs() < 1e-5);
        assert!(laserlines::math::angle_diff(tum_yaw(l_row), lt) < 1e-5);
    }
    // The trajectory (map frame: the first scan's) follows the true motion.
    let traj = tum_rows(&dir.join("trajectory.tum"));
    assert_eq!(traj.len(), 40);
    let (x0, y0, t0) = truth[0];
    for (row, &(x, y, t)) in traj.iter().zip(&truth) {
        let (s, c) = t0.sin_cos();
        let (dx, dy) = (x - x0, y - y0);
        let (ex, ey) = (c * dx + s * dy, -s * dx + c * dy);
        let off = (row[1] - ex).hypot(row[2] - ey);
        assert!(off < 0.01, "{off} m off at {row:?}");
        assert!(
            laserlines::math::angle_diff(tum_yaw(row), t - t0) < 0.005,
            "{row:?}"
        );
    }
    // A RAWLASER log has no odometry triple; without ODOM lines it has no odometry at all.
    let raw = tmp("raw.clf");
    let ranges: Vec<String> = room_ranges(0.0, 0.0, 0.0)
        .iter()
        .map(|r| format!("{r:.4}"))
        .collect();
    std::fs::write(
        &raw,
        format!(
            "RAWLASER1 0 -1.5707963 3.1415927 0.0174533 8.0 0.01 0 181 {} 0 1.0 host 1.0\n",
            ranges.join(" ")
        ),
    )
    .unwrap();
    let o = run(bin()
        .arg("map")
        .arg(&raw)
        .args(["--topic", "RAWLASER1", "--odometry", "on"])
        .arg("-o")
        .arg(tmp("raw")));
    assert_clean_error(
        &o,
        "raw.clf",
        "scan 0 (line 1): no odometry (the log gives none for this scan); map it with --odometry off",
    );
}

/// Odometry that jumps 1.5 km between two scans: the grid would not fit, and `map` says at
/// which cell size it would, after writing the trajectory and the line map.
#[test]
fn a_map_too_large_for_its_grid_names_the_cell_size_that_fits() {
    let mut log = String::from("# hand-made: the odometry jumps 1.5 km\n");
    for (k, x) in [0.0, 0.0, 1500.0].into_iter().enumerate() {
        // Far off, a room of a third the size: nothing like the first.
        let scale = if x > 0.0 { 1.0 / 3.0 } else { 1.0 };
        let ranges: Vec<f64> = room_ranges(0.0, 0.0, 0.0)
            .iter()
            .map(|r| r * scale)
            .collect();
        let time = 10.0 + 0.1 * k as f64;
        log.push_str(&flaser(&ranges, (x, 0.0, 0.0), (x, 0.0, 0.0), time));
    }
    let path = tmp("jump.clf");
    std::fs::write(&path, &log).unwrap();
    let dir = tmp("jump");
    let o = run(bin().arg("map").arg(&path).arg("-o").arg(&dir));
    assert_clean_error(&o, "jump.clf", "occupancy grid: the map would be 30");
    assert!(
        text(&o.stderr).contains("more than 20000 on a side (cells of 0.076 m would fit; the trajectory and lines.json are written in"),
        "{}",
        text(&o.stderr)
    );
    assert_eq!(tum_rows(&dir.join("trajectory.tum")).len(), 3);
    assert!(dir.join("lines.json").is_file());
}
