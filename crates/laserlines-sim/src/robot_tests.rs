//! Tests of the simulated robot (`robot.rs`).

use super::*;

fn p(x: f64, y: f64) -> Point2 {
    Point2::new(x, y)
}

#[test]
fn the_robot_stops_at_a_wall_and_counts_one_contact() {
    let mut world = World::new();
    world.add_segment(p(1.0, -2.0), p(1.0, 2.0));
    let params = RobotParams {
        odometry: OdometryNoise { wheel_sigma: 0.0 },
        ..RobotParams::default()
    };
    let mut robot = RobotSim::new(&world, Isometry2::identity(), params, 1).unwrap();
    let mut blocked = 0;
    for _ in 0..300 {
        if robot.step(VelocityCommand::new(0.5, 0.0)).blocked {
            blocked += 1;
        }
    }
    assert!(blocked > 100);
    assert_eq!(robot.collisions(), 1);
    let x = robot.world_from_robot().translation.vector.x;
    assert!(x < 0.75 && x > 0.7, "{x}");
    assert_eq!(robot.min_clearance(), 0.0);
    // Perfect odometry follows the truth.
    assert!((robot.odom_from_robot().translation.vector.x - x).abs() < 1e-12);
}

#[test]
fn limits_hold_and_runs_repeat() {
    let world = World::new();
    let run = |seed| {
        let mut r =
            RobotSim::new(&world, Isometry2::identity(), RobotParams::default(), seed).unwrap();
        let mut max_v: f64 = 0.0;
        for k in 0..500 {
            let w = if k % 100 < 50 { 3.0 } else { -3.0 };
            r.step(VelocityCommand::new(2.0, w));
            max_v = max_v.max(r.velocity().linear_m_s);
            assert!(r.velocity().angular_rad_s.abs() <= 1.5 + 1e-12);
        }
        assert!(max_v <= 0.6 + 1e-12);
        (r.world_from_robot(), r.odom_from_robot())
    };
    let (a_true, a_odom) = run(5);
    let (b_true, b_odom) = run(5);
    let (_, c_odom) = run(6);
    assert_eq!(a_true, b_true);
    assert_eq!(a_odom, b_odom);
    assert_ne!(a_odom, c_odom);
    // Noisy odometry drifts, but not wildly over 10 s.
    let err = (a_true.translation.vector - a_odom.translation.vector).norm();
    assert!(err > 0.0 && err < 0.5, "{err}");
}

#[test]
fn bad_parameters_and_starts_are_errors() {
    let world = World::new();
    let bad = RobotParams {
        physics_dt_s: 0.0,
        ..RobotParams::default()
    };
    assert!(matches!(
        RobotSim::new(&world, Isometry2::identity(), bad, 1),
        Err(RobotError::Params(ParamsError::NotPositive {
            field: "physics_dt_s",
            ..
        }))
    ));
    let slow = RobotParams {
        physics_dt_s: 0.2,
        ..RobotParams::default()
    };
    let e = RobotSim::new(&world, Isometry2::identity(), slow, 1).unwrap_err();
    assert!(
        e.to_string().contains("physics_dt_s must be at most 0.1"),
        "{e}"
    );
    let nan = Isometry2::new(Vector2::new(f64::NAN, 0.0), 0.0);
    assert_eq!(
        RobotSim::new(&world, nan, RobotParams::default(), 1).unwrap_err(),
        RobotError::BadStart
    );
    let mut w = World::new();
    w.add_disc(p(0.3, 0.0), 0.1);
    let e = RobotSim::new(&w, Isometry2::identity(), RobotParams::default(), 1).unwrap_err();
    assert!(e.to_string().contains("disc 0"), "{e}");
}

#[test]
fn a_scan_period_or_top_speed_the_simulation_cannot_follow_is_refused() {
    let ok = RobotParams::default();
    assert!(ok.validate().is_ok());
    // A scan every 100 s.
    let slow = RobotParams {
        scan_period_s: 100.0,
        ..RobotParams::default()
    };
    let e = slow.validate().unwrap_err().to_string();
    assert!(
        e.contains("scan_period_s must be at most 1 (a scan a second at least)"),
        "{e}"
    );
    // 2.5 m/s moves 5 cm in a physics step of 0.02 s; more is refused, as is 1e9 m/s.
    let mut fast = RobotParams::default();
    fast.robot.limits.max_speed = 2.5;
    assert!(fast.validate().is_ok());
    for speed in [2.6, 1e9] {
        fast.robot.limits.max_speed = speed;
        let e = fast.validate().unwrap_err().to_string();
        assert!(
            e.contains("limits.max_speed must be at most 2.5 (5 cm per physics step"),
            "{e}"
        );
    }
    // A finer physics step allows more.
    fast.physics_dt_s = 0.005;
    fast.robot.limits.max_speed = 9.0;
    assert!(fast.validate().is_ok());
}
