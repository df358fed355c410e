//! The full Hough accumulator of the iterative Hough baseline against eq. (1) evaluated cell
//! by cell, a slow and obviously right implementation.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines::hough::{HoughAccumulator, HoughGrid};
use laserlines::math::Point2;
use laserlines::{ScanPoint, Weight};
use proptest::prelude::*;

// ---------------------------------------------------------------------------------------------
// The full Hough accumulator against eq. (1) evaluated cell by cell.

/// `C(d_j, gamma_k) = sum_i w(r_i cos(phi_i - gamma_k) - d_j) g_i` with window half-width `a`.
fn slow_hough(acc: &HoughAccumulator, points: &[ScanPoint], a: f64, weight: Weight) -> Vec<f64> {
    let mut out = vec![0.0; acc.rows() * acc.columns()];
    for k in 0..acc.columns() {
        let gamma = acc.angle(k);
        for j in 0..acc.rows() {
            let d = acc.distance(j);
            for sp in points {
                if (sp.range * (sp.angle - gamma).cos() - d).abs() <= a {
                    out[k * acc.rows() + j] += match weight {
                        Weight::One => 1.0,
                        Weight::Range => sp.range,
                    };
                }
            }
        }
    }
    out
}

fn polar_points() -> impl Strategy<Value = Vec<ScanPoint>> {
    prop::collection::vec((0.05f64..7.0, -3.2f64..3.2), 0..25).prop_map(|v| {
        v.into_iter()
            .enumerate()
            .map(|(index, (range, angle))| ScanPoint {
                index,
                range,
                angle,
                point: Point2::new(range * angle.cos(), range * angle.sin()),
            })
            .collect()
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn full_hough_matches_eq_1_cell_by_cell(
        points in polar_points(),
        distance_step in 0.05f64..0.5,
        max_distance in 0.5f64..8.0,
        angle_step_deg in 3.0f64..20.0,
        window_steps in 0.3f64..2.0,
        range_weight in prop::bool::ANY,
    ) {
        let grid = HoughGrid {
            distance_step,
            max_distance,
            angle_step: angle_step_deg.to_radians(),
            window: window_steps * distance_step,
        };
        let weight = if range_weight { Weight::Range } else { Weight::One };
        let mut acc = HoughAccumulator::new(grid).unwrap();
        acc.build(points.iter(), weight);
        // Rounding may move a point sitting exactly on a window edge: bound the fast values by
        // the slow ones with the window shrunk and grown by a hair.
        let eps = 1e-9;
        let lo = slow_hough(&acc, &points, grid.window - eps, weight);
        let hi = slow_hough(&acc, &points, grid.window + eps, weight);
        for (i, &v) in acc.values().iter().enumerate() {
            prop_assert!(lo[i] - 1e-9 <= v && v <= hi[i] + 1e-9,
                "cell {} (row {}, column {}): fast {} slow {}..{}",
                i, i % acc.rows(), i / acc.rows(), v, lo[i], hi[i]);
        }
        // Every point votes in every column where its projection is on the grid.
        if weight == Weight::One && window_steps >= 0.5 {
            for k in 0..acc.columns() {
                let column: f64 = (0..acc.rows()).map(|j| acc.value(j, k)).sum();
                let inside = points.iter().filter(|sp| {
                    let x = sp.point.x * acc.angle(k).cos() + sp.point.y * acc.angle(k).sin();
                    x.abs() + grid.window + eps < acc.distance(acc.rows() - 1)
                }).count() as f64;
                prop_assert!(column >= inside);
            }
        }
        // The peak is the maximum.
        let max = acc.values().iter().cloned().fold(0.0, f64::max);
        match acc.peak() {
            Some(peak) => {
                prop_assert_eq!(peak.value, max);
                prop_assert_eq!(acc.value(peak.row, peak.column), max);
            }
            None => prop_assert_eq!(max, 0.0),
        }
    }
}
