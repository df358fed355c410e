//! Step 6b: neighbouring lines that are chords of one round obstacle are dropped. A barrel
//! or a pillar seen from nearby fills a data segment with an arc, which the split cuts into
//! chords of a few decimetres; each bends from its chord by less than the noise over its
//! width, and so passes every test of a line. The points of two neighbouring chords together
//! show it: a circle of small radius, bulging towards the sensor, explains them as well as
//! the two lines do, for fewer parameters, where the two faces of a box's corner fit two
//! lines and no circle.

use super::lines::{CUT_WINDOW, Candidate, Piece, Pieces};
use super::linseg::{sums, variance_at};
use super::points::Seg;
use crate::line::Line;
use crate::math::{Point2, Vector2};

/// Largest radius of a round obstacle, m: posts, pillars and barrels up to 2 m across. A
/// wall bent more gently is still taken as lines.
pub(crate) const MAX_ARC_RADIUS: f64 = 1.0;

/// Fewest points a circle is fitted to.
const MIN_ARC_POINTS: usize = 8;

/// Fewest points of a piece that gave no line for it to be tried as a chord beside a line
/// ([`drop_arcs`]): as many as a circle is fitted to. With four, the last few points of a
/// straight wall piece that bend away at its end passed for the next chord of a circle of
/// 1 m, and wall pieces of 0.33-0.39 m on the BreezySLAM runs lost their lines.
const MIN_CHORD_POINTS: usize = MIN_ARC_POINTS;

/// A circle fitted to points.
#[derive(Debug, Clone, Copy)]
struct Circle {
    centre: Point2,
    radius: f64,
}

/// The circle through `points` by the algebraic fit (Kasa: least squares of
/// `|p - c|^2 - R^2`), about their centroid; `None` for fewer than three points or points on
/// one line.
fn fit_circle(points: impl Iterator<Item = Point2> + Clone) -> Option<Circle> {
    let (mut n, mut sx, mut sy) = (0.0, 0.0, 0.0);
    for p in points.clone() {
        n += 1.0;
        sx += p.x;
        sy += p.y;
    }
    if n < 3.0 {
        return None;
    }
    let m = Point2::new(sx / n, sy / n);
    let (mut suu, mut suv, mut svv, mut suz, mut svz, mut sz) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for p in points {
        let (u, v) = (p.x - m.x, p.y - m.y);
        let z = u * u + v * v;
        suu += u * u;
        suv += u * v;
        svv += v * v;
        suz += u * z;
        svz += v * z;
        sz += z;
    }
    let det = suu * svv - suv * suv;
    // Points on one line (or one point) give no circle; NaN fails too.
    let scale = suu + svv;
    if det.is_nan() || det <= 1e-12 * scale * scale {
        return None;
    }
    // |p - c|^2 = R^2 as u^2 + v^2 + D u + E v + F = 0: the centre is -(D, E) / 2.
    let d = -(suz * svv - svz * suv) / det;
    let e = -(svz * suu - suz * suv) / det;
    let f = -sz / n;
    let r2 = (d * d + e * e) / 4.0 - f;
    if !(r2 > 0.0 && r2.is_finite()) {
        return None;
    }
    Some(Circle {
        centre: m + Vector2::new(-d / 2.0, -e / 2.0),
        radius: r2.sqrt(),
    })
}

/// Most Gauss-Newton steps of [`refine_circle`].
const REFINE_STEPS: usize = 4;

/// The algebraic circle is refined only when its sum of squared distances is below this
/// many times the two lines' (for a 0.52 m pillar under 1 cm of noise it was 1.14 times;
/// for a box's corner 20 times and more). A gate for speed: refining every pair gave the
/// same lines on 60 scans of each simulated scanner and on the real logs compared, the same
/// figures on the scene suites and the arenas, and cost the bench scan 6 % more
/// instructions (372.9k against 351.0k).
const KASA_MARGIN: f64 = 2.0;

/// The sum of squared distances of `points` from `circle`.
fn circle_sse(circle: &Circle, points: impl Iterator<Item = Point2>) -> f64 {
    points
        .map(|p| {
            let d = (p - circle.centre).norm() - circle.radius;
            d * d
        })
        .sum()
}

/// `circle`, whose sum of squared distances from `points` is `sse`, moved by Gauss-Newton
/// steps towards the least squares of those distances (the geometric fit), each step kept
/// only when it lowers their sum of squares; returns the circle and that sum. The algebraic
/// fit draws a short, noisy arc's circle too small (0.21 m for a 0.26 m pillar under 1 cm of
/// noise) and leaves residuals larger than two chords do, which the geometric fit does not.
fn refine_circle(
    circle: Circle,
    sse: f64,
    points: impl Iterator<Item = Point2> + Clone,
) -> (Circle, f64) {
    let (mut best, mut sse) = (circle, sse);
    for _ in 0..REFINE_STEPS {
        // Normal equations of the residuals `|p - c| - R` in (cx, cy, R).
        let mut jtj = nalgebra::Matrix3::<f64>::zeros();
        let mut jtr = nalgebra::Vector3::<f64>::zeros();
        for p in points.clone() {
            let d = p - best.centre;
            let rho = d.norm();
            if rho <= 0.0 {
                continue;
            }
            let j = nalgebra::Vector3::new(-d.x / rho, -d.y / rho, -1.0);
            jtj += j * j.transpose();
            jtr += j * (rho - best.radius);
        }
        let Some(step) = jtj.cholesky().map(|c| c.solve(&(-jtr))) else {
            break;
        };
        let next = Circle {
            centre: best.centre + Vector2::new(step.x, step.y),
            radius: best.radius + step.z,
        };
        let next_sse = circle_sse(&next, points.clone());
        // NaN fails.
        if !(next.radius > 0.0 && next_sse < sse) {
            break;
        }
        (best, sse) = (next, next_sse);
    }
    (best, sse)
}

/// The quick tests before a circle is fitted to the points `seg[a0..z0]` and `seg[a1..z1]`:
/// their outer ends lie within a circle's diameter of [`MAX_ARC_RADIUS`] (and a tenth of a
/// metre for the noise), and they bend towards the sensor (the last point of the first lies
/// on the sensor's side of the chord between the outer ends). A room's walls, longer or
/// meeting in corners seen from inside, fail them.
fn could_be_chords(seg: Seg<'_>, [(a0, z0), (a1, z1)]: [(usize, usize); 2]) -> bool {
    if z0 <= a0 || z1 <= a1 || z1 > seg.len() {
        return false;
    }
    let (a, j, b) = (seg.point(a0), seg.point(z0 - 1), seg.point(z1 - 1));
    let chord = b - a;
    let reach = 2.0 * MAX_ARC_RADIUS + 0.1;
    let cross = |q: Point2| chord.x * (q.y - a.y) - chord.y * (q.x - a.x);
    // The sensor sits at the origin; NaN fails.
    chord.norm_squared() <= reach * reach && cross(j) * cross(Point2::origin()) > 0.0
}

/// What two lines' extra parameters are charged against one circle, in noise variances:
/// Akaike's 2 for each, and two lines have two more (two each and the break between them,
/// five, against the circle's three). Where the noise hides the bend, two lines tend to leave
/// smaller residuals than the circle's fit (chords of a barrel of 0.58 m seen from 0.8 m
/// under 1.9 cm of noise, each 49 deg of its arc, left 0.0125 m^2 about two lines and
/// 0.0126 m^2 about the circle); charged for the parameters they spend, they no longer beat
/// it. With it, the circle is taken when it leaves at most `4 - arc_significance` noise
/// variances more than the two lines.
const EXTRA_PARAMETERS_CHARGE: f64 = 4.0;

/// Whether the lines of the points `seg[a0..z0]` and `seg[a1..z1]` (whose own squared
/// residuals about their lines sum to `sse_lines`) are chords of one round obstacle: a circle
/// of at most [`MAX_ARC_RADIUS`] through those points, the sensor outside it and its centre
/// beyond their centroid, leaves a sum of squared distances smaller than the two lines (once
/// charged [`EXTRA_PARAMETERS_CHARGE`] variances for their extra parameters) by more than
/// `significance` times the noise variance (`sigma(r)^2` at their centroid, or their scatter
/// about the circle when larger). Unless both pieces gave lines (`both_lines`), the test must
/// also pass with the variance at most the two lines' own residual variance: a piece that
/// gave no line may be a few points that bend off a wall, and a noise model read high
/// (clutter raises it) would let a circle pass through both.
fn chords_of_a_circle(
    pieces: &Pieces<'_>,
    [(a0, z0), (a1, z1)]: [(usize, usize); 2],
    sse_lines: f64,
    (significance, both_lines): (f64, bool),
) -> bool {
    let count = z0.saturating_sub(a0) + z1.saturating_sub(a1);
    if count < MIN_ARC_POINTS {
        return false;
    }
    let points = (a0..z0).chain(a1..z1).map(|k| pieces.seg.point(k));
    let Some(kasa) = fit_circle(points.clone()) else {
        return false;
    };
    let all = sums(pieces.pre, a0, z0).join(&sums(pieces.pre, a1, z1));
    let round = |circle: &Circle| {
        // A positive finite radius (see `fit_circle`). Convex towards the sensor: the sensor
        // outside the circle, its centre beyond the points (from inside a round room, the
        // wall's arc bends away from the sensor).
        let centre2 = circle.centre.coords.norm_squared();
        circle.radius <= MAX_ARC_RADIUS
            && centre2 > circle.radius * circle.radius
            && centre2 > all.centroid_norm_squared()
    };
    let better = |sse_circle: f64| {
        let variance = variance_at(&all, pieces.noise).max(sse_circle / (count - 3) as f64);
        let passes = |variance: f64| {
            sse_lines + EXTRA_PARAMETERS_CHARGE * variance - sse_circle > significance * variance
        };
        // Four parameters of two lines; `count >= MIN_ARC_POINTS`. Both variances must pass,
        // so that the bound is never the looser test (as it would be for a significance
        // above the charge).
        passes(variance) && (both_lines || passes(variance.min(sse_lines / (count - 4) as f64)))
    };
    if !round(&kasa) {
        return false;
    }
    let kasa_sse = circle_sse(&kasa, points.clone());
    if better(kasa_sse) {
        return true;
    }
    // The algebraic circle of a short, noisy arc is too small (see `refine_circle`), and
    // leaves residuals a little above the lines'. Far above (a box's corner, two walls), no
    // circle is better: those are not refined.
    // NaN fails.
    if kasa_sse.partial_cmp(&(KASA_MARGIN * sse_lines)) != Some(std::cmp::Ordering::Less) {
        return false;
    }
    let (circle, sse_circle) = refine_circle(kasa, kasa_sse, points);
    round(&circle) && better(sse_circle)
}

/// Drops the lines from `first_line` on (one segment's, in order, from the segment's pieces
/// `spans`) of which two neighbours are chords of one round obstacle
/// ([`chords_of_a_circle`]).
///
/// Each piece is tried with the piece before it when either gave a line. The other need not
/// have given one: far off, a barrel's next chord is often too short or too uncertain for one
/// (0.14 m against `min_line_length`), and the chord beside it, 0.16 m, passed every test
/// of a line on its own. Such a piece counts with [`MIN_CHORD_POINTS`] points or more, and
/// its pair is judged against the pieces' own scatter too ([`chords_of_a_circle`]); a
/// smaller one is passed over to the piece before it, as the points trimmed between two
/// lines are (at most `2 CUT_WINDOW` points between the pair).
pub(crate) fn drop_arcs(
    pieces: &Pieces<'_>,
    spans: &[Piece],
    out: &mut Vec<Line>,
    candidates: &mut Vec<Candidate>,
    first_line: usize,
) {
    let n = out.len().min(candidates.len());
    let significance = pieces.p.arc_significance;
    // Bit k: line first_line + k is dropped (a segment gives at most a few dozen lines; the
    // lines beyond the 64th are left as they are).
    let mut dropped = 0u64;
    // The line of each piece that gave one, counted from `first_line`.
    let mut line = 0usize;
    let mut before: Option<(Piece, Option<usize>)> = None;
    for &piece in spans {
        let own = piece.line.then_some(line);
        line += usize::from(piece.line);
        let counts = piece.line || piece.len() >= MIN_CHORD_POINTS;
        let Some((prev, prev_line)) = before else {
            before = counts.then_some((piece, own));
            continue;
        };
        let near = piece.a.saturating_sub(prev.z) as usize <= 2 * CUT_WINDOW;
        let both = piece.line && prev_line.is_some();
        if counts && (piece.line || prev_line.is_some()) && near {
            let spans = [prev, piece].map(|q| (q.a as usize, q.z as usize));
            let sse = sums(pieces.pre, spans[0].0, spans[0].1).sse()
                + sums(pieces.pre, spans[1].0, spans[1].1).sse();
            if could_be_chords(pieces.seg, spans)
                && chords_of_a_circle(pieces, spans, sse, (significance, both))
            {
                // Both lines of the pair, or neither (beyond the 64th line).
                let lines = [prev_line, own].into_iter().flatten();
                if lines.clone().all(|k| k < 64) {
                    for k in lines {
                        dropped |= 1 << k;
                    }
                }
            }
        }
        if counts {
            before = Some((piece, own));
        }
    }
    if dropped == 0 || n < first_line {
        return;
    }
    let mut kept = first_line;
    for j in first_line..n {
        let k = j - first_line;
        if k < 64 && dropped & (1 << k) != 0 {
            continue;
        }
        out[kept] = out[j];
        candidates[kept] = candidates[j];
        kept += 1;
    }
    out.truncate(kept);
    candidates.truncate(kept);
}

#[cfg(test)]
mod tests {
    use super::super::linseg::prefix_sums;
    use super::super::params::HoughSplitParams;
    use super::super::points::points_at;
    use super::*;
    use crate::fit::FitSums;
    use crate::noise::RangeNoise;

    /// Points on a circle of `radius` about `centre`, at angles `from + k step`, `k < n`.
    fn arc(centre: (f64, f64), radius: f64, from: f64, step: f64, n: usize) -> Vec<(f64, f64)> {
        (0..n)
            .map(|k| {
                let t = from + step * k as f64;
                (centre.0 + radius * t.cos(), centre.1 + radius * t.sin())
            })
            .collect()
    }

    /// `points` each moved along its beam (from the origin) by range noise of standard
    /// deviation `sigma`: sums of 12 uniform draws of a generator seeded with `seed`.
    fn along_beams(points: impl Iterator<Item = Point2>, sigma: f64, seed: u64) -> Vec<Point2> {
        let mut state = seed;
        let mut uniform = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        points
            .map(|q| {
                let noise = sigma * (0..12).map(|_| uniform()).sum::<f64>();
                q + q.coords.normalize() * noise
            })
            .collect()
    }

    #[test]
    fn the_quick_tests_pass_a_barrel_and_refuse_a_room_seen_from_inside() {
        // The near side of a barrel 1.5 m ahead: two halves of its arc.
        let barrel = points_at(&arc((1.5, 0.0), 0.29, 2.4, 0.05, 30));
        assert!(could_be_chords(Seg(&barrel), [(0, 15), (15, 30)]));
        // A round room's wall seen from inside (the sensor 0.7 m off the centre of a circle
        // of 1 m): it bends away from the sensor.
        let room = points_at(&arc((-0.7, 0.0), 1.0, -0.4, 0.03, 30));
        assert!(!could_be_chords(Seg(&room), [(0, 15), (15, 30)]));
        // Ends 3 m apart: no circle of 1 m.
        let long = points_at(&arc((3.0, 0.0), 2.0, 2.3, 0.06, 30));
        assert!(!could_be_chords(Seg(&long), [(0, 15), (15, 30)]));
        // Empty or out-of-range spans, and NaN points.
        assert!(!could_be_chords(Seg(&barrel), [(5, 5), (5, 30)]));
        assert!(!could_be_chords(Seg(&barrel), [(0, 15), (15, 31)]));
        let mut nan = barrel.clone();
        nan[14].x = f64::NAN;
        assert!(!could_be_chords(Seg(&nan), [(0, 15), (15, 30)]));
    }

    #[test]
    fn a_circle_around_the_sensor_or_too_large_is_no_obstacle() {
        let p = HoughSplitParams::default();
        let noise = RangeNoise::new(0.005, 0.005);
        let check = |pts: &[(f64, f64)], sse_lines: f64| {
            let seg = points_at(pts);
            let mut pre: Vec<FitSums> = Vec::new();
            prefix_sums(Seg(&seg), &mut pre);
            let pieces = Pieces::for_test(Seg(&seg), &pre, &p, &noise);
            let half = pts.len() / 2;
            chords_of_a_circle(
                &pieces,
                [(0, half), (half, pts.len())],
                sse_lines,
                (2.0, true),
            )
        };
        // Exact points, two lines said to leave 1 m^2: a barrel's arc is a round obstacle.
        assert!(check(&arc((1.5, 0.0), 0.29, 2.4, 0.05, 30), 1.0));
        // Points 1 cm off the barrel along their beams: lines said to leave less than the
        // circle by more than their charge less the significance (2 variances) keep them,
        // by less they are chords.
        let pts = along_beams(
            arc((1.5, 0.0), 0.29, 2.4, 0.05, 30)
                .iter()
                .map(|&(x, y)| Point2::new(x, y)),
            0.01,
            5,
        );
        let noisy: Vec<(f64, f64)> = pts.iter().map(|p| (p.x, p.y)).collect();
        let kasa = fit_circle(pts.iter().copied()).unwrap();
        let kasa_sse = circle_sse(&kasa, pts.iter().copied());
        let (_, sse) = refine_circle(kasa, kasa_sse, pts.iter().copied());
        let centroid = pts.iter().fold(Vector2::zeros(), |acc, p| acc + p.coords) / 30.0;
        let variance = noise.sigma(centroid.norm()).powi(2).max(sse / 27.0);
        assert!(check(&noisy, sse - 1.5 * variance), "{sse} {variance}");
        assert!(!check(&noisy, sse - 2.5 * variance), "{sse} {variance}");
        // The sensor inside the circle, its centre still beyond the points' centroid.
        let around = arc((0.5, 0.0), 0.6, std::f64::consts::PI - 0.5, 0.035, 30);
        assert!(!check(&around, 1.0));
        // A radius above 1 m.
        assert!(!check(&arc((3.0, 0.0), 1.2, 2.6, 0.03, 30), 1.0));
        // A wall of 1.05 m radius under 1 cm of range noise: the algebraic circle (0.68 m)
        // passes, the refined one (1.16 m) explains the points better than lines leaving
        // 0.005 m^2 would, but is too large.
        let wall = arc((2.5, 0.0), 1.05, std::f64::consts::PI - 0.3, 0.02, 30);
        let pts = along_beams(wall.iter().map(|&(x, y)| Point2::new(x, y)), 0.01, 2);
        let wide: Vec<(f64, f64)> = pts.iter().map(|p| (p.x, p.y)).collect();
        let kasa = fit_circle(pts.iter().copied()).unwrap();
        let kasa_sse = circle_sse(&kasa, pts.iter().copied());
        let (refined, sse) = refine_circle(kasa, kasa_sse, pts.iter().copied());
        assert!(
            kasa.radius < 0.8 && refined.radius > MAX_ARC_RADIUS,
            "{kasa:?} {refined:?}"
        );
        assert!(0.005 - sse > 2.0 * sse / 27.0, "{sse}");
        assert!(!check(&wide, 0.005));
    }

    /// The line of `seg[a..z]` as `emit_lines` gives it, and its candidate.
    fn line_of(seg: Seg<'_>, pre: &[FitSums], (a, z): (usize, usize)) -> (Line, Candidate) {
        let sums = sums(pre, a, z);
        let fit = sums.fit().unwrap();
        let ends = (seg.point(a), seg.point(z - 1));
        let line = Line::from_fit(&fit, (a, ends.0), (z - 1, ends.1));
        let candidate = Candidate {
            sums,
            ends,
            span: (a as u32, z as u32),
            follows: false,
            certain: true,
        };
        (line, candidate)
    }

    /// Runs `drop_arcs` on the points `pts` cut into `pieces` (`(a, z, gave a line)`) and
    /// returns the first point of each line kept.
    fn kept_lines(pts: &[(f64, f64)], pieces: &[(usize, usize, bool)]) -> Vec<usize> {
        let p = HoughSplitParams::default();
        let noise = RangeNoise::new(0.005, 0.005);
        let seg = points_at(pts);
        let mut pre: Vec<FitSums> = Vec::new();
        prefix_sums(Seg(&seg), &mut pre);
        let spans: Vec<Piece> = pieces
            .iter()
            .map(|&(a, z, line)| Piece {
                a: a as u32,
                z: z as u32,
                line,
            })
            .collect();
        let (mut out, mut candidates): (Vec<Line>, Vec<Candidate>) = pieces
            .iter()
            .filter(|q| q.2)
            .map(|&(a, z, _)| line_of(Seg(&seg), &pre, (a, z)))
            .unzip();
        let pieces = Pieces::for_test(Seg(&seg), &pre, &p, &noise);
        drop_arcs(&pieces, &spans, &mut out, &mut candidates, 0);
        out.iter().map(|l| l.first).collect()
    }

    #[test]
    fn a_chord_beside_a_piece_that_gave_no_line_is_still_a_chord() {
        // The near side of a barrel 1.5 m ahead: a chord that gave a line, beside 8 points
        // that gave none; before, a chord with no line beside it was kept.
        let barrel = arc((1.5, 0.0), 0.29, 2.4, 0.05, 30);
        assert!(kept_lines(&barrel, &[(0, 8, false), (8, 30, true)]).is_empty());
        assert!(kept_lines(&barrel, &[(0, 22, true), (22, 30, false)]).is_empty());
        // Two chords that gave lines, with a piece of two points between them (passed
        // over): both dropped, as before.
        let two = [(0, 14, true), (14, 16, false), (16, 30, true)];
        assert!(kept_lines(&barrel, &two).is_empty());
        // Beside a piece of seven points (too few to count), a chord is kept.
        assert_eq!(kept_lines(&barrel, &[(0, 7, false), (7, 30, true)]), [7]);
        // A straight wall piece of 0.16 m 1 m ahead, then 8 points that bend away from the
        // sensor by up to 1.3 cm (a door frame): a circle explains them within the noise
        // model's 5 mm, not within their own scatter, and the wall keeps its line.
        let mut bent: Vec<(f64, f64)> = (0..14)
            .map(|k| (1.0, -0.2 + 0.012 * f64::from(k)))
            .collect();
        bent.extend((1..=8).map(|k| {
            (
                1.0 + 0.0002 * f64::from(k * k),
                -0.044 + 0.012 * f64::from(k),
            )
        }));
        assert_eq!(kept_lines(&bent, &[(0, 14, true), (14, 22, false)]), [0]);
        // A box's corner 1.3 m ahead, towards the sensor: a face of 0.56 m that gave a line
        // and 10 points of the other face that gave none. Two lines fit it, no circle: the
        // line is kept.
        let mut corner: Vec<(f64, f64)> = (0..20)
            .map(|k| f64::from(20 - k) * 0.02)
            .map(|t| (1.3 + t, -t))
            .collect();
        corner.extend((1..=10).map(|k| (1.3 + 0.02 * f64::from(k), 0.02 * f64::from(k))));
        assert!(could_be_chords(
            Seg(&points_at(&corner)),
            [(0, 20), (20, 30)]
        ));
        assert_eq!(kept_lines(&corner, &[(0, 20, true), (20, 30, false)]), [0]);
    }

    #[test]
    fn the_algebraic_fit_finds_an_exact_circle_and_refuses_a_line() {
        let c = Point2::new(1.5, -0.4);
        let arc = (0..20).map(|k| {
            let t = 2.5 + 0.05 * f64::from(k);
            c + Vector2::new(t.cos(), t.sin()) * 0.29
        });
        let got = fit_circle(arc).unwrap();
        assert!((got.centre - c).norm() < 1e-9, "{got:?}");
        assert!((got.radius - 0.29).abs() < 1e-9);
        let line = (0..20).map(|k| Point2::new(1.0, 0.1 * f64::from(k)));
        assert!(fit_circle(line).is_none());
        assert!(fit_circle([Point2::new(1.0, 1.0); 2].into_iter()).is_none());
        let nan = [
            Point2::new(f64::NAN, 0.0),
            Point2::new(1.0, 0.0),
            Point2::new(0.0, 1.0),
        ];
        assert!(fit_circle(nan.into_iter()).is_none());
    }

    #[test]
    fn the_geometric_fit_mends_the_algebraic_circle_of_a_noisy_arc() {
        // A pillar of 0.26 m radius 1.2 m ahead, 67 points over 85 deg of its near side,
        // each moved along its beam by 1 cm range noise (sums of uniform draws).
        let (c, radius) = (Point2::new(1.2, 0.0), 0.26);
        let near_side = (0..67).map(|k| {
            let t = std::f64::consts::PI - 0.74 + 0.0225 * f64::from(k);
            c + Vector2::new(t.cos(), t.sin()) * radius
        });
        let points = along_beams(near_side, 0.01, 7);
        let kasa = fit_circle(points.iter().copied()).unwrap();
        let kasa_sse = circle_sse(&kasa, points.iter().copied());
        let (geometric, sse) = refine_circle(kasa, kasa_sse, points.iter().copied());
        // Better by more than the arc test's two noise variances (Kasa: 0.212 m).
        assert!(
            kasa_sse - sse > 2.0 * 0.01 * 0.01,
            "{sse} against {kasa_sse}"
        );
        let (off, kasa_off) = (
            (geometric.radius - radius).abs(),
            (kasa.radius - radius).abs(),
        );
        assert!(off < kasa_off, "{geometric:?} against {kasa:?}");
        // Its steps reach the least squares: more steps find nothing lower.
        let (_, again) = refine_circle(geometric, sse, points.iter().copied());
        assert!(again > sse * (1.0 - 1e-9), "{again} after {sse}");
        // An exact circle stays where it is.
        let exact: Vec<Point2> = (0..20)
            .map(|k| c + Vector2::new(f64::from(k).cos(), f64::from(k).sin()) * radius)
            .collect();
        let fit = fit_circle(exact.iter().copied()).unwrap();
        let fit_sse = circle_sse(&fit, exact.iter().copied());
        let (same, sse) = refine_circle(fit, fit_sse, exact.iter().copied());
        assert!(sse < 1e-20 && (same.radius - radius).abs() < 1e-9);
    }
}
