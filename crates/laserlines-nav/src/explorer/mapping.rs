//! The robot's own map: each scan is placed by the tracker of `laserlines-slam` (scan
//! matching onto everything seen so far, held toward the odometry's prediction) and the
//! scans the tracker maps are added to the explorer's grid at the same pose.

use laserlines::Scan;
use laserlines::math::Isometry2;
use laserlines_slam::Se2;

use super::Explorer;

impl Explorer {
    /// Places the scan (scan matching) and adds it to the map when the tracker maps it.
    pub(super) fn localise_and_map(
        &mut self,
        scan: &Scan,
        odom_from_robot: &Isometry2,
        time_s: f64,
    ) {
        // Odometry the tracker refuses (not finite) leaves the pose where it was.
        let Ok(update) = self
            .tracker
            .add_scan(scan, Se2::from_isometry(odom_from_robot))
        else {
            return;
        };
        self.map_from_robot = update.pose.to_isometry();
        if !update.inserted {
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
