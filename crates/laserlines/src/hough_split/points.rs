//! Step 0: the valid beams of a scan as points, and the beam geometry they are computed from
//! (cached per scan shape).

use crate::math::Point2;

/// One beam's geometry: its direction, its sector and `cos(phi - gamma_sector)`.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Beam {
    pub(crate) cos: f64,
    pub(crate) sin: f64,
    pub(crate) cos_to_sector: f64,
    pub(crate) sector: u32,
}

/// Beam geometry of one scan shape, cached between scans of the same shape.
#[derive(Debug, Default, Clone)]
pub(crate) struct BeamTable {
    key: Option<(u64, u64, usize, u64)>,
    pub(crate) beams: Vec<Beam>,
    /// Per sector: the first beam after it.
    pub(crate) sector_end: Vec<usize>,
    /// True when every beam direction is finite.
    pub(crate) finite: bool,
    /// The angle between beams, rad.
    pub(crate) increment: f64,
    /// The beam a full turn is walked from (0 otherwise): range `i` of the walk is beam
    /// `seam + i` (mod the beam count). Set per scan ([`BeamTable::walk_from`]), not part of
    /// the cached shape.
    seam: usize,
    /// With a seam: per beam of the walk, the direction of its beam and the sector of its
    /// place in the walk.
    turned: Vec<Beam>,
}

impl BeamTable {
    /// Makes sure the table describes beams of `angle_min + i * increment`, `i < n`.
    pub(crate) fn prepare(&mut self, angle_min: f64, increment: f64, n: usize, sector_step: f64) {
        let key = (
            angle_min.to_bits(),
            increment.to_bits(),
            n,
            sector_step.to_bits(),
        );
        if self.key == Some(key) {
            return;
        }
        self.key = Some(key);
        self.increment = increment;
        self.beams.clear();
        self.sector_end.clear();
        self.finite = true;
        let sign = if increment < 0.0 { -1.0 } else { 1.0 };
        let step = increment.abs();
        for i in 0..n {
            let phi = angle_min + i as f64 * increment;
            let (sin, cos) = phi.sin_cos();
            // Sector in the scan's own field of view, counted from the first beam. The tiny
            // epsilon keeps beams that fall exactly on a boundary in the upper sector despite
            // rounding.
            let k_f = ((i as f64 * step) / sector_step + 1e-9).floor();
            let k = if k_f.is_finite() && k_f >= 0.0 {
                (k_f as usize).min(n)
            } else {
                0
            };
            let gamma = angle_min + sign * (k as f64 + 0.5) * sector_step;
            let cos_to_sector = (phi - gamma).cos();
            self.finite &= cos.is_finite() && sin.is_finite();
            // Sectors are non-decreasing along the beams.
            self.sector_end.resize(k + 1, i);
            self.sector_end[k] = i + 1;
            self.beams.push(Beam {
                cos,
                sin,
                cos_to_sector: if cos_to_sector.is_finite() {
                    cos_to_sector
                } else {
                    1.0
                },
                sector: k as u32,
            });
        }
    }
}

impl BeamTable {
    /// Sets the beam the scan is walked from ([`BeamTable::seam`]): beam `i` of the walk
    /// points where beam `seam + i` (mod the beam count) does, and lies in the sector of
    /// the walk's `i`-th beam (sectors count from the walk's first beam).
    pub(crate) fn walk_from(&mut self, seam: usize) {
        let n = self.beams.len();
        self.seam = if seam < n { seam } else { 0 };
        if self.seam == 0 {
            return;
        }
        let turned = self.beams[self.seam..]
            .iter()
            .chain(&self.beams[..self.seam]);
        self.turned.clear();
        self.turned
            .extend(self.beams.iter().zip(turned).map(|(place, dir)| Beam {
                cos: dir.cos,
                sin: dir.sin,
                ..*place
            }));
    }

    /// The beams in the order of the walk ([`BeamTable::walk_from`]).
    pub(crate) fn walk(&self) -> &[Beam] {
        if self.seam == 0 {
            &self.beams
        } else {
            &self.turned
        }
    }
}

/// A valid beam as a point: `(x, y)` in the sensor frame, m, its range, m, and beam index.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Pt {
    pub(crate) x: f64,
    pub(crate) y: f64,
    pub(crate) range: f64,
    pub(crate) idx: usize,
}

/// A run of points (one data segment).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Seg<'a>(pub(crate) &'a [Pt]);

impl Seg<'_> {
    /// Number of points.
    pub(crate) fn len(&self) -> usize {
        self.0.len()
    }

    /// Point `k`.
    #[inline]
    pub(crate) fn point(&self, k: usize) -> Point2 {
        Point2::new(self.0[k].x, self.0[k].y)
    }

    /// Range of point `k`, m.
    #[inline]
    pub(crate) fn range(&self, k: usize) -> f64 {
        self.0[k].range
    }

    /// Beam index of point `k`.
    #[inline]
    pub(crate) fn idx(&self, k: usize) -> usize {
        self.0[k].idx
    }
}

/// The point of beam `idx`, at angle `phi` (rad) and range `r` (m).
#[cfg(test)]
pub(crate) fn on_beam(idx: usize, phi: f64, r: f64) -> Pt {
    Pt {
        x: r * phi.cos(),
        y: r * phi.sin(),
        range: r,
        idx,
    }
}

/// Points at `xy`, beam `k` for the `k`-th, their ranges from the origin.
#[cfg(test)]
pub(crate) fn points_at(xy: &[(f64, f64)]) -> Vec<Pt> {
    xy.iter()
        .enumerate()
        .map(|(i, &(x, y))| Pt {
            x,
            y,
            range: (x * x + y * y).sqrt(),
            idx: i,
        })
        .collect()
}
