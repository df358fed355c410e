//! The robot's own map: each scan is placed on it by scan matching (point-to-line ICP pulled
//! toward the odometry's prediction) and every few scans are added to it.

use laserlines::Scan;
use laserlines::math::{Isometry2, Point2, Vector2};

use super::Explorer;
use crate::map::MatchPoint;

impl Explorer {
    /// Places the scan on the map (scan matching) and adds it.
    pub(super) fn localise_and_map(
        &mut self,
        scan: &Scan,
        odom_from_robot: &Isometry2,
        time_s: f64,
    ) {
        let predicted = self.map_from_odom * odom_from_robot;
        // Scan points in the robot frame, at least 5 cm apart along the scan.
        let mut pts = std::mem::take(&mut self.match_points);
        pts.clear();
        let mut outline = std::mem::take(&mut self.scratch_points);
        outline.clear();
        let window = scan.range_window(None);
        let dirs = self
            .beams
            .get(scan.angle_min, scan.angle_increment, scan.ranges.len());
        for (&r, dir) in scan.ranges.iter().zip(dirs).step_by(MATCH_STRIDE) {
            if !window.contains(r) || r > 5.0 {
                continue;
            }
            outline.push(self.robot_from_laser * Point2::from(dir * r));
        }
        // The outline's normal at each point from its neighbours, where they are near
        // (within 15 cm): a point pairs only with map lines of about its direction.
        for (k, &q) in outline.iter().enumerate() {
            let prev = k.checked_sub(1).map(|i| outline[i]);
            let next = outline.get(k + 1).copied();
            let near = |o: Option<Point2>| o.filter(|o| (o - q).norm_squared() < 0.15 * 0.15);
            let tangent = match (near(prev), near(next)) {
                (Some(a), Some(b)) => Some(b - a),
                (Some(a), None) => Some(q - a),
                (None, Some(b)) => Some(b - q),
                (None, None) => None,
            };
            let normal = tangent
                .filter(|t| t.norm_squared() > 1e-8)
                .map(|t| Vector2::new(-t.y, t.x).normalize());
            // The URG-04LX's noise: 5 mm to 1 m, 0.5 % of the range beyond.
            let range = (q - self.robot_from_laser.translation.vector).coords.norm();
            let weight = 1.0 / range.max(1.0).powi(2);
            pts.push(MatchPoint {
                point: q,
                normal,
                weight,
            });
        }
        self.scratch_points = outline;
        let matched = if self.map.scans() > 0 {
            self.map.match_scan(&pts, &predicted, &self.params.matching)
        } else {
            None
        };
        self.match_points = pts;
        if matched.is_none() && self.map.scans() > 0 {
            self.unmatched += 1;
        }
        self.map_from_robot = matched.unwrap_or(predicted);
        self.map_from_odom = self.map_from_robot * odom_from_robot.inverse();
        // Every `map.every`-th scan goes into the map (all are matched against it).
        let every = self.params.map.every.max(1) as u64;
        if !self.scans.is_multiple_of(every) {
            return;
        }
        let newly = self
            .map
            .insert_scan(&(self.map_from_robot * self.robot_from_laser), scan);
        if newly >= self.params.map.new_cells {
            self.last_new = time_s;
        }
        if newly > 0 {
            self.last_gain = time_s;
        }
        self.known += newly as u64;
    }
}

/// Every this many beams give a point to the scan matching (a stride, not a spacing: a
/// choice that depended on the points' noise would bias the match).
const MATCH_STRIDE: usize = 4;
