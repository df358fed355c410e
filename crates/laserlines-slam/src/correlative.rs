//! Branch-and-bound correlative scan matching (Olson 2009; Hess et al. 2016): the pose in a
//! search window whose scan points fall on the most likely cells of a likelihood grid, found
//! exactly (at the grid's resolution and an angular step that moves the farthest point by
//! about one cell) without scoring every pose.
//!
//! The grid holds, per cell, how likely a surface is there (a Gaussian of the distance to
//! the nearest reference point). Coarser grids hold, per cell, the largest value of the
//! `2^h x 2^h` cells starting at it, so that a score on them bounds the score of every pose in
//! that block from above; blocks whose bound is below the best found are never opened.

use laserlines::math::{Point2, floor_i64};

use crate::se2::Se2;

/// Where to look, around a guess.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchWindow {
    /// Half width of the square of translations, m.
    pub linear_m: f64,
    /// Half width of the range of headings, rad.
    pub angular_rad: f64,
}

/// The best pose found and its score.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CorrelativeMatch {
    /// `grid_from_scan`.
    pub pose: Se2,
    /// Mean cell value under the scan points, 0..1.
    pub score: f64,
}

/// A likelihood grid with its max-pooled levels, ready for branch-and-bound search.
#[derive(Debug, Clone)]
pub struct CorrelativeGrid {
    origin: Point2,
    resolution: f64,
    width: usize,
    height: usize,
    /// `levels[h]`: each cell the maximum of the `2^h x 2^h` block of level 0 starting there.
    levels: Vec<Vec<u8>>,
}

impl CorrelativeGrid {
    /// A grid of cells of side `resolution_m` over the points, each cell holding
    /// `exp(-d^2 / (2 sigma^2))` for the distance `d` to the nearest point (cut at 3 sigma),
    /// with `levels` max-pooled levels (`levels` = 1 + the deepest `h`). `None` without points.
    #[must_use]
    pub fn new(points: &[Point2], resolution_m: f64, sigma_m: f64, levels: usize) -> Option<Self> {
        let finite: Vec<Point2> = points
            .iter()
            .copied()
            .filter(|p| p.x.is_finite() && p.y.is_finite())
            .collect();
        let first = finite.first()?;
        let (mut lo, mut hi) = (*first, *first);
        for p in &finite {
            lo = Point2::new(lo.x.min(p.x), lo.y.min(p.y));
            hi = Point2::new(hi.x.max(p.x), hi.y.max(p.y));
        }
        let res = resolution_m.max(1e-3);
        let pad = 3.0 * sigma_m + res;
        let origin = Point2::new(lo.x - pad, lo.y - pad);
        let width = (((hi.x - lo.x + 2.0 * pad) / res).ceil() as usize).max(1);
        let height = (((hi.y - lo.y + 2.0 * pad) / res).ceil() as usize).max(1);
        if width.saturating_mul(height) > 64_000_000 {
            return None;
        }
        let mut base = vec![0u8; width * height];
        let reach = (3.0 * sigma_m / res).ceil() as i64;
        let inv = 1.0 / (2.0 * sigma_m * sigma_m).max(1e-12);
        for p in &finite {
            let cx = floor_i64((p.x - origin.x) / res);
            let cy = floor_i64((p.y - origin.y) / res);
            for dy in -reach..=reach {
                for dx in -reach..=reach {
                    let (x, y) = (cx + dx, cy + dy);
                    if x < 0 || y < 0 || x >= width as i64 || y >= height as i64 {
                        continue;
                    }
                    let centre = Point2::new(
                        origin.x + (x as f64 + 0.5) * res,
                        origin.y + (y as f64 + 0.5) * res,
                    );
                    let d2 = (centre - p).norm_squared();
                    let v = (255.0 * (-d2 * inv).exp()).round() as u8;
                    let cell = &mut base[y as usize * width + x as usize];
                    *cell = (*cell).max(v);
                }
            }
        }
        let mut all = vec![base];
        for h in 1..levels.max(1) {
            let prev = &all[h - 1];
            let step = 1usize << (h - 1);
            let mut next = vec![0u8; width * height];
            for y in 0..height {
                for x in 0..width {
                    let mut m = prev[y * width + x];
                    if x + step < width {
                        m = m.max(prev[y * width + x + step]);
                    }
                    if y + step < height {
                        m = m.max(prev[(y + step) * width + x]);
                        if x + step < width {
                            m = m.max(prev[(y + step) * width + x + step]);
                        }
                    }
                    next[y * width + x] = m;
                }
            }
            all.push(next);
        }
        Some(Self {
            origin,
            resolution: res,
            width,
            height,
            levels: all,
        })
    }

    /// Side of a cell, m.
    #[must_use]
    pub fn resolution(&self) -> f64 {
        self.resolution
    }

    /// Finds the pose within `window` around `guess` (`grid_from_scan`) with the best score
    /// of `points` (scan frame), if that score reaches `min_score`.
    #[must_use]
    pub fn search(
        &self,
        points: &[Point2],
        guess: Se2,
        window: SearchWindow,
        min_score: f64,
    ) -> Option<CorrelativeMatch> {
        if points.is_empty() {
            return None;
        }
        let res = self.resolution;
        let far = points
            .iter()
            .map(|p| p.coords.norm())
            .fold(0.0, f64::max)
            .max(res);
        let angle_step = (1.0 - res * res / (2.0 * far * far))
            .clamp(-1.0, 1.0)
            .acos()
            .max(1e-4);
        let n_angles = (window.angular_rad / angle_step).ceil() as i64;
        let wx = (window.linear_m / res).ceil() as i64;
        let top = self.levels.len() - 1;
        let block = 1i64 << top;
        let n = points.len() as f64;
        // Rotated point sets, in cells relative to the guess's translation.
        let mut rotations: Vec<(f64, Vec<(i64, i64)>)> =
            Vec::with_capacity((2 * n_angles + 1) as usize);
        for k in -n_angles..=n_angles {
            let theta = guess.theta + k as f64 * angle_step;
            let pose = Se2::new(guess.x, guess.y, theta);
            let cells = points
                .iter()
                .map(|p| {
                    let q = pose.transform(*p);
                    (
                        floor_i64((q.x - self.origin.x) / res),
                        floor_i64((q.y - self.origin.y) / res),
                    )
                })
                .collect();
            rotations.push((theta, cells));
        }
        let mut best_score = (min_score * 255.0 * n).max(0.0);
        let mut best: Option<(usize, i64, i64)> = None;
        let mut candidates = Vec::new();
        for (r, (_, cells)) in rotations.iter().enumerate() {
            let mut ox = -wx;
            while ox <= wx {
                let mut oy = -wx;
                while oy <= wx {
                    let s = self.score(top, cells, ox, oy);
                    candidates.push((s, r, ox, oy));
                    oy += block;
                }
                ox += block;
            }
        }
        candidates.sort_by_key(|c| std::cmp::Reverse(c.0));
        for (s, r, ox, oy) in candidates {
            if (s as f64) <= best_score {
                break;
            }
            self.branch(
                top,
                &rotations[r].1,
                r,
                ox,
                oy,
                wx,
                &mut best_score,
                &mut best,
            );
        }
        let (r, ox, oy) = best?;
        Some(CorrelativeMatch {
            pose: Se2::new(
                guess.x + ox as f64 * res,
                guess.y + oy as f64 * res,
                rotations[r].0,
            ),
            score: best_score / (255.0 * n),
        })
    }

    /// Depth-first search below the block `(ox, oy)` of level `h`.
    #[allow(clippy::too_many_arguments)]
    fn branch(
        &self,
        h: usize,
        cells: &[(i64, i64)],
        r: usize,
        ox: i64,
        oy: i64,
        wx: i64,
        best_score: &mut f64,
        best: &mut Option<(usize, i64, i64)>,
    ) {
        if h == 0 {
            let s = self.score(0, cells, ox, oy) as f64;
            if s > *best_score {
                *best_score = s;
                *best = Some((r, ox, oy));
            }
            return;
        }
        let half = 1i64 << (h - 1);
        let mut children = [(0u64, 0i64, 0i64); 4];
        let mut count = 0;
        for (dx, dy) in [(0, 0), (half, 0), (0, half), (half, half)] {
            let (cx, cy) = (ox + dx, oy + dy);
            if cx > wx || cy > wx {
                continue;
            }
            children[count] = (self.score(h - 1, cells, cx, cy), cx, cy);
            count += 1;
        }
        let children = &mut children[..count];
        children.sort_by_key(|c| std::cmp::Reverse(c.0));
        for &(s, cx, cy) in children.iter() {
            if (s as f64) <= *best_score {
                break;
            }
            self.branch(h - 1, cells, r, cx, cy, wx, best_score, best);
        }
    }

    /// Sum of level `h` under the cells shifted by `(ox, oy)`.
    fn score(&self, h: usize, cells: &[(i64, i64)], ox: i64, oy: i64) -> u64 {
        let grid = &self.levels[h];
        let (w, hgt) = (self.width as i64, self.height as i64);
        cells
            .iter()
            .map(|&(x, y)| {
                let (x, y) = (x + ox, y + oy);
                if x < 0 || y < 0 || x >= w || y >= hgt {
                    0
                } else {
                    u64::from(grid[(y * w + x) as usize])
                }
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An L-shaped room corner and a rectangle's walls, as points every 2 cm.
    fn walls() -> Vec<Point2> {
        let mut pts = Vec::new();
        for k in 0..300 {
            let t = f64::from(k) * 0.02;
            pts.push(Point2::new(t - 1.0, 3.0));
            pts.push(Point2::new(4.0, t - 2.0));
            if k < 100 {
                pts.push(Point2::new(1.0 + t, -1.0 + 0.5 * t));
            }
        }
        pts
    }

    #[test]
    fn finds_a_known_offset_exactly_and_refuses_a_poor_score() {
        let reference = walls();
        let grid = CorrelativeGrid::new(&reference, 0.05, 0.05, 6).unwrap();
        let truth = Se2::new(0.7, -0.45, 0.2);
        let scan: Vec<Point2> = reference
            .iter()
            .map(|p| truth.inverse().transform(*p))
            .step_by(3)
            .collect();
        let window = SearchWindow {
            linear_m: 1.0,
            angular_rad: 0.35,
        };
        let m = grid.search(&scan, Se2::IDENTITY, window, 0.5).unwrap();
        assert!(m.pose.distance(&truth) < 0.05, "{m:?}");
        assert!((m.pose.theta - truth.theta).abs() < 0.01, "{m:?}");
        assert!(m.score > 0.8);
        // Outside the window: the true pose cannot be found and nothing scores high.
        let far = Se2::new(2.5, 0.0, 0.0);
        assert!(
            grid.search(
                &scan,
                far,
                SearchWindow {
                    linear_m: 0.3,
                    angular_rad: 0.05
                },
                0.8
            )
            .is_none()
        );
    }

    #[test]
    fn branch_and_bound_agrees_with_exhaustive_search() {
        let reference = walls();
        let grid = CorrelativeGrid::new(&reference, 0.1, 0.1, 4).unwrap();
        let truth = Se2::new(-0.33, 0.21, -0.1);
        let scan: Vec<Point2> = reference
            .iter()
            .map(|p| truth.inverse().transform(*p))
            .step_by(7)
            .collect();
        let window = SearchWindow {
            linear_m: 0.6,
            angular_rad: 0.15,
        };
        let m = grid.search(&scan, Se2::IDENTITY, window, 0.0).unwrap();
        // Exhaustive: every cell offset at level 0, same angles.
        let res = grid.resolution;
        let far = scan.iter().map(|p| p.coords.norm()).fold(0.0, f64::max);
        let step = (1.0 - res * res / (2.0 * far * far)).acos();
        let na = (window.angular_rad / step).ceil() as i64;
        let wx = (window.linear_m / res).ceil() as i64;
        let mut best = 0u64;
        for k in -na..=na {
            let pose = Se2::new(0.0, 0.0, k as f64 * step);
            let cells: Vec<(i64, i64)> = scan
                .iter()
                .map(|p| {
                    let q = pose.transform(*p);
                    (
                        floor_i64((q.x - grid.origin.x) / res),
                        floor_i64((q.y - grid.origin.y) / res),
                    )
                })
                .collect();
            for ox in -wx..=wx {
                for oy in -wx..=wx {
                    best = best.max(grid.score(0, &cells, ox, oy));
                }
            }
        }
        let exhaustive = best as f64 / (255.0 * scan.len() as f64);
        assert!(
            (m.score - exhaustive).abs() < 1e-12,
            "{} vs {exhaustive}",
            m.score
        );
    }
}
