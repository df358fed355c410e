//! The pose graph: a loop closure corrects drift, a false closure does not bend the map.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines_slam::Se2;
use laserlines_slam::graph::{Edge, OptimizeParams, PoseGraph, RobustKernel};
use nalgebra::Matrix3;

/// The true poses of a square loop of 4 m sides, one pose every 0.5 m, turning 90 deg at
/// each corner; returns to the start.
fn square() -> Vec<Se2> {
    let mut poses = vec![Se2::IDENTITY];
    for side in 0..4 {
        for k in 0..8 {
            let last = *poses.last().unwrap();
            let turn = if k == 7 && side < 3 {
                std::f64::consts::FRAC_PI_2
            } else {
                0.0
            };
            poses.push(last * Se2::new(0.5, 0.0, turn));
        }
    }
    poses
}

fn info(sigma_xy: f64, sigma_theta: f64) -> Matrix3<f64> {
    Matrix3::from_diagonal(&nalgebra::Vector3::new(
        1.0 / (sigma_xy * sigma_xy),
        1.0 / (sigma_xy * sigma_xy),
        1.0 / (sigma_theta * sigma_theta),
    ))
}

/// A graph of the square with odometry edges that under-measure every turn by 2 deg (so the
/// chained poses drift), poses seeded by chaining those edges.
fn drifting_graph(truth: &[Se2]) -> PoseGraph {
    let mut g = PoseGraph::new();
    let mut pose = truth[0];
    g.add_node(pose);
    for i in 1..truth.len() {
        let true_delta = truth[i - 1].between(&truth[i]);
        let measured = Se2::new(true_delta.x, true_delta.y, true_delta.theta - 0.035);
        pose = pose * measured;
        g.add_node(pose);
        g.add_edge(Edge {
            from: i - 1,
            to: i,
            measurement: measured,
            information: info(0.05, 0.05),
            kernel: RobustKernel::None,
        })
        .unwrap();
    }
    g
}

fn max_error(g: &PoseGraph, truth: &[Se2]) -> f64 {
    g.nodes()
        .iter()
        .zip(truth)
        .map(|(a, b)| a.distance(b))
        .fold(0.0, f64::max)
}

#[test]
fn a_loop_closure_corrects_the_drift() {
    let truth = square();
    let last = truth.len() - 1;
    let mut g = drifting_graph(&truth);
    let before = max_error(&g, &truth);
    assert!(before > 1.0, "the odometry should drift: {before}");
    // The closure: the last pose seen from the first, exactly as it is.
    g.add_edge(Edge {
        from: 0,
        to: last,
        measurement: truth[0].between(&truth[last]),
        information: info(0.01, 0.005),
        kernel: RobustKernel::Cauchy(3.0),
    })
    .unwrap();
    let report = g.optimize(&OptimizeParams::default()).unwrap();
    assert!(report.final_cost < report.initial_cost);
    let after = max_error(&g, &truth);
    // The remaining error is the spread of 2 deg per corner over the loop: well under the drift.
    assert!(after < 0.25, "before {before:.3} m, after {after:.3} m");
    assert!(g.nodes()[last].distance(&truth[last]) < 0.05);
}

#[test]
fn one_false_closure_does_not_bend_the_map() {
    let truth = square();
    let last = truth.len() - 1;
    let mut g = drifting_graph(&truth);
    let good = Edge {
        from: 0,
        to: last,
        measurement: truth[0].between(&truth[last]),
        information: info(0.01, 0.005),
        kernel: RobustKernel::Cauchy(3.0),
    };
    g.add_edge(good).unwrap();
    let mut reference = g.clone();
    reference.optimize(&OptimizeParams::default()).unwrap();
    // A false closure: pose 12 (on the second side) claimed to be 2 m from where it is.
    let wrong = truth[4].between(&truth[12]) * Se2::new(2.0, 1.0, 0.5);
    g.add_edge(Edge {
        from: 4,
        to: 12,
        measurement: wrong,
        information: info(0.01, 0.005),
        kernel: RobustKernel::Cauchy(3.0),
    })
    .unwrap();
    g.optimize(&OptimizeParams::default()).unwrap();
    let shift = g
        .nodes()
        .iter()
        .zip(reference.nodes())
        .map(|(a, b)| a.distance(b))
        .fold(0.0, f64::max);
    // The Cauchy kernel leaves it a pull of about its scale, not its 2 m: a few centimetres.
    assert!(
        shift < 0.15,
        "the false closure moved a pose by {shift:.3} m"
    );
    // Without the kernel the same closure bends the map by metres.
    let mut plain = reference.clone();
    plain
        .add_edge(Edge {
            from: 4,
            to: 12,
            measurement: wrong,
            information: info(0.01, 0.005),
            kernel: RobustKernel::None,
        })
        .unwrap();
    plain.optimize(&OptimizeParams::default()).unwrap();
    let bent = plain
        .nodes()
        .iter()
        .zip(reference.nodes())
        .map(|(a, b)| a.distance(b))
        .fold(0.0, f64::max);
    assert!(bent > 0.5, "{bent}");
}

#[test]
fn bad_edges_are_refused() {
    let mut g = PoseGraph::new();
    g.add_node(Se2::IDENTITY);
    let e = Edge {
        from: 0,
        to: 1,
        measurement: Se2::IDENTITY,
        information: Matrix3::identity(),
        kernel: RobustKernel::None,
    };
    assert!(g.add_edge(e).is_err());
    g.add_node(Se2::IDENTITY);
    assert!(g.add_edge(Edge { to: 0, ..e }).is_err());
    assert!(
        g.add_edge(Edge {
            measurement: Se2 {
                x: f64::NAN,
                y: 0.0,
                theta: 0.0
            },
            ..e
        })
        .is_err()
    );
    assert!(g.add_edge(e).is_ok());
}
