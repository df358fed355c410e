//! What a horizontal laser at a given height sees of an element: its solids cut by the
//! laser's plane, placed in the arena, and gathered into a [`World`] (duplicate segments
//! merged, two half barrels back to back made one disc).

use laserlines::math::{Isometry2, Point2, Vector2};

use super::elements::{Hole, Solid};
use crate::world::World;

/// Segments of a lone half barrel's round side.
const ARC_SEGMENTS: usize = 8;

/// Largest distance between the centres of two half barrels made one disc, m (back to back
/// on one cell edge their flat sides are 2 cm apart).
const PAIR_GAP: f64 = 0.03;

/// What the laser's plane cuts out of an element, element frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Piece {
    /// A wall segment.
    Segment(Point2, Point2),
    /// Half a disc: its flat side through `centre` across `inward`, the round side towards
    /// `inward` (a unit vector).
    HalfDisc {
        centre: Point2,
        radius: f64,
        inward: Vector2,
    },
}

fn p(v: [f64; 2]) -> Point2 {
    Point2::new(v[0], v[1])
}

fn within(h: f64, z: [f64; 2]) -> bool {
    z[0] <= h && h <= z[1]
}

/// The outline of an axis-aligned box as four segments.
fn outline(min: [f64; 2], max: [f64; 2], out: &mut Vec<Piece>) {
    let c = [
        Point2::new(min[0], min[1]),
        Point2::new(max[0], min[1]),
        Point2::new(max[0], max[1]),
        Point2::new(min[0], max[1]),
    ];
    for k in 0..4 {
        out.push(Piece::Segment(c[k], c[(k + 1) % 4]));
    }
}

/// Cuts `solid`, raised by `dz` m, at height `h`: the pieces it leaves in the plane.
pub(crate) fn cut_solid(solid: &Solid, dz: f64, h: f64, out: &mut Vec<Piece>) {
    let h = h - dz;
    match *solid {
        Solid::Plate { a, b, z } => {
            if within(h, z) {
                out.push(Piece::Segment(p(a), p(b)));
            }
        }
        Solid::Block { min, max, z } => {
            if within(h, z) {
                outline(min, max, out);
            }
        }
        Solid::HalfBarrel { centre, radius, z } => {
            if within(h, z) {
                out.push(Piece::HalfDisc {
                    centre: p(centre),
                    radius,
                    inward: Vector2::new(0.0, -1.0),
                });
            }
        }
        Solid::Wedge { x, y0, y1, top } => {
            // Solid between the surface's contour at h and the vertical face at y1.
            if h >= 0.0 && h < top {
                let y = y0 + (h / top) * (y1 - y0);
                outline([x[0], y.min(y1)], [x[1], y.max(y1)], out);
            }
        }
        Solid::Board {
            x,
            y0,
            y1,
            top,
            thickness,
        } => {
            // The board crosses the plane where its underside lies within a thickness
            // below h: a strip that thin is one segment at its middle.
            let mid = h - 0.5 * thickness;
            if mid >= -0.5 * thickness && mid <= top + 0.5 * thickness {
                let y = y0 + (mid.clamp(0.0, top) / top) * (y1 - y0);
                out.push(Piece::Segment(Point2::new(x[0], y), Point2::new(x[1], y)));
            }
        }
    }
}

/// Cuts a wall plate on the `+y` edge, `length` m long and centred on it, with `holes`, at
/// height `h` (walls stand from the floor to at least 1.2 m; above that nothing).
pub(crate) fn cut_wall(length: f64, holes: &[Hole], h: f64, out: &mut Vec<Piece>) {
    if !(0.0..=1.2).contains(&h) {
        return;
    }
    let half = 0.5 * length;
    let y = 0.5 * super::ARENA_GRID;
    // The gaps the holes leave at this height, in order along the wall.
    let mut gaps: Vec<(f64, f64)> = holes
        .iter()
        .filter_map(|hole| {
            let dz = h - hole.z;
            (dz.abs() < hole.radius).then(|| {
                let w = (hole.radius * hole.radius - dz * dz).sqrt();
                (hole.x[0] - w, hole.x[1] + w)
            })
        })
        .collect();
    gaps.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut from = -half;
    for (lo, hi) in gaps {
        if lo > from + 1e-9 {
            out.push(Piece::Segment(
                Point2::new(from, y),
                Point2::new(lo.min(half), y),
            ));
        }
        from = from.max(hi);
    }
    if half > from + 1e-9 {
        out.push(Piece::Segment(Point2::new(from, y), Point2::new(half, y)));
    }
}

/// Gathers the placed pieces of all elements into a world: segments once each (both ends
/// to the millimetre), half barrels back to back on one edge as one disc, a lone half
/// barrel as its outline.
#[derive(Debug, Default)]
pub(crate) struct Builder {
    world: World,
    placed: std::collections::HashSet<[i64; 4]>,
    halves: Vec<(Point2, f64, Vector2)>,
    /// Segments that repeated one already placed.
    pub(crate) duplicates: usize,
}

fn mm(v: f64) -> i64 {
    (v * 1000.0).round() as i64
}

impl Builder {
    /// Adds `pieces`, element frame, placed by `world_from_element`; the number of pieces
    /// that were new.
    pub(crate) fn add(&mut self, world_from_element: &Isometry2, pieces: &[Piece]) -> usize {
        let mut added = 0;
        for piece in pieces {
            match *piece {
                Piece::Segment(a, b) => {
                    let (a, b) = (world_from_element * a, world_from_element * b);
                    if self.segment(a, b) {
                        added += 1;
                    }
                }
                Piece::HalfDisc {
                    centre,
                    radius,
                    inward,
                } => {
                    let c = world_from_element * centre;
                    let d = world_from_element * inward;
                    self.halves.push((c, radius, d));
                    added += 1;
                }
            }
        }
        added
    }

    /// Adds a segment unless it is there already; true when it was added.
    fn segment(&mut self, a: Point2, b: Point2) -> bool {
        if !(a.x.is_finite() && a.y.is_finite() && b.x.is_finite() && b.y.is_finite()) {
            return false;
        }
        let (ka, kb) = ([mm(a.x), mm(a.y)], [mm(b.x), mm(b.y)]);
        let (lo, hi) = if ka <= kb { (ka, kb) } else { (kb, ka) };
        if self.placed.insert([lo[0], lo[1], hi[0], hi[1]]) {
            self.world.add_segment(a, b);
            true
        } else {
            self.duplicates += 1;
            false
        }
    }

    /// The world: the segments, then the half barrels: two back to back on one edge
    /// (centres less than [`PAIR_GAP`] apart, facing away from each other) as one disc
    /// around both, a lone one as its outline. Also the number of such discs.
    pub(crate) fn finish(mut self) -> (World, usize) {
        let halves = std::mem::take(&mut self.halves);
        let mut used = vec![false; halves.len()];
        let mut discs = 0;
        for (i, &(c, r, d)) in halves.iter().enumerate() {
            if used[i] {
                continue;
            }
            used[i] = true;
            let partner = (i + 1..halves.len()).find(|&j| {
                let (cj, rj, dj) = halves[j];
                !used[j]
                    && (cj - c).norm() < PAIR_GAP
                    && (rj - r).abs() < 1e-9
                    && dj.dot(&d) < -0.99
            });
            if let Some(j) = partner {
                used[j] = true;
                let gap = (halves[j].0 - c).norm();
                self.world.add_disc(
                    Point2::from(0.5 * (c.coords + halves[j].0.coords)),
                    r + 0.5 * gap,
                );
                discs += 1;
            } else {
                self.half_outline(c, r, d);
            }
        }
        (self.world, discs)
    }

    /// The outline of a lone half barrel: the flat side and the round side in
    /// [`ARC_SEGMENTS`] chords.
    fn half_outline(&mut self, c: Point2, r: f64, inward: Vector2) {
        let across = Vector2::new(-inward.y, inward.x);
        let at = |k: usize| {
            let t = std::f64::consts::PI * k as f64 / ARC_SEGMENTS as f64;
            c + across * (r * t.cos()) + inward * (r * t.sin())
        };
        self.segment(at(0), at(ARC_SEGMENTS));
        for k in 0..ARC_SEGMENTS {
            self.segment(at(k), at(k + 1));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn segments(out: &[Piece]) -> Vec<(Point2, Point2)> {
        out.iter()
            .filter_map(|p| match *p {
                Piece::Segment(a, b) => Some((a, b)),
                Piece::HalfDisc { .. } => None,
            })
            .collect()
    }

    #[test]
    fn holes_open_the_wall_only_at_their_height() {
        let holes = [Hole {
            x: [-0.3, -0.3],
            z: 0.3,
            radius: 0.075,
        }];
        let mut out = Vec::new();
        cut_wall(1.2, &holes, 0.5, &mut out);
        assert_eq!(segments(&out).len(), 1);
        out.clear();
        // Through the hole's centre: a gap of 0.15 m at x = -0.3.
        cut_wall(1.2, &holes, 0.3, &mut out);
        let s = segments(&out);
        assert_eq!(s.len(), 2);
        assert!((s[0].0.x + 0.6).abs() < 1e-12 && (s[0].1.x + 0.375).abs() < 1e-12);
        assert!((s[1].0.x + 0.225).abs() < 1e-12 && (s[1].1.x - 0.6).abs() < 1e-12);
        assert!(s.iter().all(|(a, b)| a.y == 0.6 && b.y == 0.6));
    }

    #[test]
    fn ramps_are_cut_where_their_surface_meets_the_plane() {
        let wedge = Solid::Wedge {
            x: [-0.5, 0.5],
            y0: 0.5,
            y1: -0.5,
            top: 0.4,
        };
        let mut out = Vec::new();
        cut_solid(&wedge, 0.0, 0.1, &mut out);
        // The contour at 0.1 m lies a quarter of the way up: y = 0.25; the solid runs to
        // the vertical face at y = -0.5.
        let s = segments(&out);
        assert_eq!(s.len(), 4);
        let ys: Vec<f64> = s.iter().flat_map(|(a, b)| [a.y, b.y]).collect();
        assert!(
            ys.iter()
                .all(|y| (y - 0.25).abs() < 1e-12 || (y + 0.5).abs() < 1e-12)
        );
        out.clear();
        cut_solid(&wedge, 0.0, 0.4, &mut out);
        assert!(out.is_empty(), "above the top");
        let board = Solid::Board {
            x: [-0.5, 0.5],
            y0: -0.5,
            y1: 0.5,
            top: 1.0,
            thickness: 0.02,
        };
        cut_solid(&board, 0.0, 0.51, &mut out);
        let s = segments(&out);
        assert_eq!(s.len(), 1);
        assert!((s[0].0.y - 0.0).abs() < 1e-12, "{s:?}");
        // Raised items: a block from -0.2 to 0.2 raised by 0.6 is cut at 0.5 but not 0.3.
        out.clear();
        let b = Solid::Block {
            min: [0.0, 0.0],
            max: [1.0, 1.0],
            z: [-0.2, 0.2],
        };
        cut_solid(&b, 0.6, 0.3, &mut out);
        assert!(out.is_empty());
        cut_solid(&b, 0.6, 0.5, &mut out);
        assert_eq!(out.len(), 4);
    }

    #[test]
    fn half_barrels_back_to_back_make_one_disc() {
        let half = [Piece::HalfDisc {
            centre: Point2::new(0.0, 0.59),
            radius: 0.29,
            inward: Vector2::new(0.0, -1.0),
        }];
        let mut b = Builder::default();
        // Cell (0, 0) at rotation 0 and the cell above at rotation 180: the same edge,
        // flat sides 2 cm apart.
        b.add(&Isometry2::new(Vector2::new(0.0, 0.0), 0.0), &half);
        b.add(
            &Isometry2::new(Vector2::new(0.0, 1.2), std::f64::consts::PI),
            &half,
        );
        // A lone one elsewhere.
        b.add(&Isometry2::new(Vector2::new(5.0, 0.0), 0.0), &half);
        let (world, discs) = b.finish();
        assert_eq!(discs, 1);
        assert_eq!(world.discs.len(), 1);
        assert!((world.discs[0].centre - Point2::new(0.0, 0.6)).norm() < 1e-9);
        assert!((world.discs[0].radius - 0.30).abs() < 1e-9);
        assert_eq!(world.walls.len(), ARC_SEGMENTS + 1);
        // The lone half bulges into its cell (towards -y) from the edge at y = 0.59.
        assert!(
            world
                .walls
                .iter()
                .all(|w| w.a.y <= 0.59 + 1e-9 && w.a.y >= 0.3 - 1e-9)
        );
    }

    #[test]
    fn duplicate_segments_are_merged() {
        let mut b = Builder::default();
        let s = [Piece::Segment(Point2::new(0.0, 0.6), Point2::new(1.0, 0.6))];
        let r = [Piece::Segment(Point2::new(1.0, 0.6), Point2::new(0.0, 0.6))];
        assert_eq!(b.add(&Isometry2::identity(), &s), 1);
        assert_eq!(b.add(&Isometry2::identity(), &r), 0);
        assert_eq!(b.duplicates, 1);
        let (world, _) = b.finish();
        assert_eq!(world.walls.len(), 1);
    }
}
