//! Inserting a scan into the map: the fan it sweeps frees cells, the ends of its beams
//! mark them occupied.

use laserlines::Scan;
use laserlines::math::{Isometry2, Point2, Vector2};

use super::{FREE_STEP, HIT_STEP, MAP_STRIDE, NEUTRAL, NO_RETURN_FREE, RobotMap};

impl RobotMap {
    /// Inserts a scan taken with the laser at `map_from_laser` (see the [module
    /// docs](self)); returns how many knowledge cells it made known.
    pub fn insert_scan(&mut self, map_from_laser: &Isometry2, scan: &Scan) -> usize {
        let o = Point2::from(map_from_laser.translation.vector);
        let yaw = map_from_laser.rotation.angle();
        if !(o.x.is_finite() && o.y.is_finite() && yaw.is_finite()) {
            return 0;
        }
        let reach = if scan.range_max.is_finite() {
            scan.range_max.clamp(0.0, 20.0)
        } else {
            20.0
        } + 0.5;
        let r = Vector2::new(reach, reach);
        self.knowledge.ensure(o - r, o + r);
        self.centroids.ensure(o - r, o + r);
        if self.knowledge.cols == 0 {
            return 0;
        }
        self.scans += 1;
        let before = self.known;
        self.trace_fan(o, yaw, scan);
        self.mark_free();
        self.grow_extent(o);
        self.mark_hits();
        self.known - before
    }

    /// The scan's fan in knowledge-grid cell units (the laser, then every
    /// [`MAP_STRIDE`]-th beam's end, and the last) into `poly`, and the ends of the beams
    /// with a return into `ends`.
    fn trace_fan(&mut self, o: Point2, yaw: f64, scan: &Scan) {
        let window = scan.range_window(None);
        let mut poly = std::mem::take(&mut self.poly);
        poly.clear();
        poly.push(self.knowledge.to_cells(o));
        let (s_yaw, c_yaw) = yaw.sin_cos();
        let n = scan.ranges.len();
        let mut ends = std::mem::take(&mut self.ends);
        ends.clear();
        let mut beams = std::mem::take(&mut self.beams);
        let dirs = beams.get(scan.angle_min, scan.angle_increment, n);
        for (i, (&range, d)) in scan.ranges.iter().zip(dirs).enumerate() {
            // Every MAP_STRIDE-th beam, and the last (so that the fan keeps its span).
            if i % MAP_STRIDE != 0 && i + 1 != n {
                continue;
            }
            let dir = Vector2::new(c_yaw * d.x - s_yaw * d.y, s_yaw * d.x + c_yaw * d.y);
            if window.contains(range) {
                let p = o + dir * range;
                poly.push(self.knowledge.to_cells(p));
                ends.push(p);
            } else {
                let free = NO_RETURN_FREE.min(scan.range_max.max(0.0));
                poly.push(self.knowledge.to_cells(o + dir * free));
            }
        }
        self.beams = beams;
        self.poly = poly;
        self.ends = ends;
    }

    /// Moves every knowledge cell the fan covers toward free.
    fn mark_free(&mut self) {
        let mut raster = std::mem::take(&mut self.raster);
        let (cells, cols, known) = (
            &mut self.knowledge.cells,
            self.knowledge.cols,
            &mut self.known,
        );
        raster.fill(&self.poly, cols, self.knowledge.rows, |row, first, last| {
            for v in &mut cells[row * cols + first..=row * cols + last] {
                if *v == 0 {
                    *v = NEUTRAL;
                    *known += 1;
                }
                *v = v.saturating_sub(FREE_STEP).max(1);
            }
        });
        self.raster = raster;
    }

    /// Grows the extent to hold the whole fan from `o` (the ends of beams without a return
    /// too).
    fn grow_extent(&mut self, o: Point2) {
        let (mut lo, mut hi) = self.extent.unwrap_or((o, o));
        for &(u, v) in &self.poly {
            let p = Point2::new(
                self.knowledge.origin.x + u * self.knowledge.cell,
                self.knowledge.origin.y + v * self.knowledge.cell,
            );
            lo = Point2::new(lo.x.min(p.x), lo.y.min(p.y));
            hi = Point2::new(hi.x.max(p.x), hi.y.max(p.y));
        }
        self.extent = Some((lo, hi));
    }

    /// Moves the knowledge cells the beams end in toward occupied (with their centroids).
    fn mark_hits(&mut self) {
        for &p in &self.ends {
            if let Some(c) = self.knowledge.index(p) {
                let v = &mut self.knowledge.cells[c];
                if *v == 0 {
                    *v = NEUTRAL;
                    self.known += 1;
                }
                *v = v.saturating_add(HIT_STEP);
                let centre = self.knowledge.centre(c);
                let sum = &mut self.centroids.cells[c];
                if sum[2] < 1000.0 {
                    sum[0] += (p.x - centre.x) as f32;
                    sum[1] += (p.y - centre.y) as f32;
                    sum[2] += 1.0;
                }
            }
        }
    }
}
