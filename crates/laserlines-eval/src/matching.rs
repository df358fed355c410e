//! Matching extracted lines to ground-truth wall pieces, one to one.
//!
//! A line `l` and a piece `p` are **compatible** when all of these hold:
//!
//! 1. **beam overlap**: `shared / union >= min_overlap` (default 1/2), where `shared` is the
//!    number of beams in both `l.first..=l.last` and `p.first..=p.last` and `union` the number
//!    in either (the intersection over union of the two beam ranges; either may run across
//!    the seam of a full turn);
//! 2. **distance**: `|l.r - p.r| <= max(r_tolerance, sigmas * p.sigma_r)`
//!    (default `max(1 cm, 4 sigma_r)`);
//! 3. **direction**: the angle between `l.alpha` and `p.alpha` is at most
//!    `max(alpha_tolerance, sigmas * p.sigma_alpha)` (default `max(0.5 deg, 4 sigma_alpha)`).
//!
//! `sigma_r` and `sigma_alpha` are the standard errors an ideal least-squares fit of the
//! piece's own beams has under the simulated noise ([`crate::truth::ideal_fit_errors`]): they
//! widen the fixed tolerances only where the noise makes them unreachable for any fit (short or
//! far pieces). These are the tolerances of the round-trip tests of `HoughSplit`.
//!
//! **Assignment.** Compatible pairs are taken in order of decreasing overlap (ties: smaller
//! normalised error `|dr| / tol_r + |dalpha| / tol_alpha`, then lower line and piece index);
//! a pair is kept when neither its line nor its piece is taken yet. With `min_overlap > 1/2`
//! no line and no piece can have two compatible partners among beam-disjoint pieces and lines,
//! so this greedy assignment is then the only one; at exactly 1/2 it breaks the rare tie.
//!
//! **Counts.** A significant piece with a line assigned is *found*; a line with no piece
//! assigned is *false*. Lines assigned to pieces that are not significant (too short or too
//! few beams to be required) count neither as found nor as false.
//!
//! A false line is also counted as *on a wall* when it still lies on a real wall: at least
//! half of its beams fall on pieces of one wall, and its `r` and `alpha` are within the
//! tolerances of the piece of that wall it shares most beams with. These are the second line
//! of a split wall, fragments too short to overlap their piece by half, and lines that bridge a
//! small obstacle in front of a wall (covering two visible pieces of it, neither by half).
//! They stay false: a visible piece is found only by a line that covers it and ends where it
//! ends; the count says how many false lines are of that kind.

use laserlines::Line;
use laserlines::math::angle_diff;
use serde::Serialize;

use crate::truth::{ExpectedPiece, beam_span, beams_shared};

/// Which lines count as right (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Criteria {
    /// Lines and visible pieces one to one: a line must cover its piece by an intersection
    /// over union of the beams of `min_overlap`, within tolerances widened to `sigmas`
    /// standard errors of an ideal fit; every other line is false.
    #[default]
    Strict,
    /// As a user judges each line on its own: a line is right when at least `min_overlap` of
    /// its beams fall on pieces of one wall and its `r` and angle are within `r_tolerance`
    /// and `alpha_tolerance` of that wall's (5 cm and 3 deg by [`MatchParams::field`]); a
    /// significant piece is found when a right line of its wall covers at least half of its
    /// beams. A wall behind a cable may so be one line, and a wall cut by a leg two; a
    /// fragment off the wall, a line on a leg, or one across a corner is false.
    Field,
}

/// Tolerances of [`match_lines`] (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MatchParams {
    /// Fixed tolerance on `r`, m. Default 0.01.
    pub r_tolerance: f64,
    /// Fixed tolerance on `alpha`, rad. Default 0.5 deg.
    pub alpha_tolerance: f64,
    /// Standard errors of an ideal fit that the tolerances are widened to. Default 4.
    pub sigmas: f64,
    /// Smallest intersection over union of the beam ranges of a line and its piece, in
    /// `(0, 1]` (with [`Criteria::Field`]: the fraction of the line's beams on its target).
    /// Default 0.5.
    pub min_overlap: f64,
    /// Which lines count as right. Default [`Criteria::Strict`].
    pub criteria: Criteria,
}

impl Default for MatchParams {
    fn default() -> Self {
        Self {
            r_tolerance: 0.01,
            alpha_tolerance: 0.5_f64.to_radians(),
            sigmas: 4.0,
            min_overlap: 0.5,
            criteria: Criteria::Strict,
        }
    }
}

impl MatchParams {
    /// The field criteria: `|dr| <= 5 cm`, angle within 3 deg, half of the line on its
    /// target ([`Criteria::Field`]).
    #[must_use]
    pub fn field() -> Self {
        Self {
            r_tolerance: 0.05,
            alpha_tolerance: 3f64.to_radians(),
            sigmas: 0.0,
            min_overlap: 0.5,
            criteria: Criteria::Field,
        }
    }

    /// Tolerances `(r in m, alpha in rad)` for `piece`.
    #[must_use]
    pub fn tolerances(&self, piece: &ExpectedPiece) -> (f64, f64) {
        (
            self.r_tolerance.max(self.sigmas * piece.sigma_r),
            self.alpha_tolerance.max(self.sigmas * piece.sigma_alpha),
        )
    }
}

/// A line assigned to a piece.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Pair {
    /// Index of the line.
    pub line: usize,
    /// Index of the piece.
    pub piece: usize,
    /// True when the piece is significant (the pair counts as found).
    pub significant: bool,
    /// `l.r - p.r`, m.
    pub dr: f64,
    /// Absolute angle between `l.alpha` and `p.alpha`, rad.
    pub dalpha: f64,
    /// Distance between the line's start and the piece's first seen hit, m.
    pub start_error: f64,
    /// Distance between the line's end and the piece's last seen hit, m.
    pub end_error: f64,
    /// Intersection over union of the beam ranges.
    pub overlap: f64,
}

/// The outcome of matching the lines of one scan to its pieces.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct ScanMatch {
    /// Assigned pairs, in order of line index.
    pub pairs: Vec<Pair>,
    /// Number of significant pieces (the pieces to find).
    pub significant_pieces: usize,
    /// Significant pieces with a line assigned.
    pub found: usize,
    /// Number of lines.
    pub lines: usize,
    /// Indices of lines with no piece assigned.
    pub false_lines: Vec<usize>,
    /// Indices of the false lines that still lie on a wall (see the module docs).
    pub on_wall_lines: Vec<usize>,
}

/// Beams shared by line `l` and piece `p` (either may run across the seam of a full turn).
fn shared(l: &Line, p: &ExpectedPiece) -> usize {
    beams_shared((l.first, l.last), (p.first, p.last), p.scan_beams)
}

/// Beams of line `l`, in a scan of `n` beams.
fn line_beams(l: &Line, n: usize) -> usize {
    beam_span(l.first, l.last, n)
}

/// The number of beams of the scan `pieces` were seen in (0 without pieces).
fn scan_beams(pieces: &[ExpectedPiece]) -> usize {
    pieces.iter().map(|p| p.scan_beams).max().unwrap_or(0)
}

/// `(overlap, line fraction, dr, dalpha)` of `l` against `p`.
fn compare(l: &Line, p: &ExpectedPiece) -> (f64, f64, f64, f64) {
    let s = shared(l, p);
    let (nl, np) = (line_beams(l, p.scan_beams), p.beams());
    let union = (nl + np).saturating_sub(s);
    let iou = if union > 0 {
        s as f64 / union as f64
    } else {
        0.0
    };
    let on = if nl > 0 { s as f64 / nl as f64 } else { 0.0 };
    (iou, on, l.r - p.r, angle_diff(l.alpha, p.alpha))
}

/// Matches `lines` to `pieces` by `params.criteria` (see the module docs). Never panics; a
/// line with non-finite fields matches nothing.
#[must_use]
pub fn match_lines(lines: &[Line], pieces: &[ExpectedPiece], params: &MatchParams) -> ScanMatch {
    match params.criteria {
        Criteria::Strict => match_one_to_one(lines, pieces, params),
        Criteria::Field => match_each(lines, pieces, params),
    }
}

/// [`Criteria::Field`]: each line on its own.
fn match_each(lines: &[Line], pieces: &[ExpectedPiece], params: &MatchParams) -> ScanMatch {
    // The wall each line is right for, if any: the wall holding most of its beams.
    let n = scan_beams(pieces);
    let right: Vec<Option<usize>> = lines
        .iter()
        .map(|l| {
            let nl = line_beams(l, n);
            let on_wall = |w: usize| -> usize {
                pieces
                    .iter()
                    .filter(|p| p.wall == w)
                    .map(|p| shared(l, p))
                    .sum()
            };
            let p = pieces
                .iter()
                .max_by_key(|p| (on_wall(p.wall), std::cmp::Reverse(p.wall)))?;
            let (_, _, dr, da) = compare(l, p);
            let (tr, ta) = params.tolerances(p);
            let enough = nl > 0 && on_wall(p.wall) as f64 >= params.min_overlap * nl as f64;
            (enough && dr.abs() <= tr && da <= ta).then_some(p.wall)
        })
        .collect();
    let mut pairs = Vec::new();
    for (pi, p) in pieces.iter().enumerate() {
        let covering = (0..lines.len())
            .filter(|&li| right[li] == Some(p.wall))
            .map(|li| (li, shared(&lines[li], p)))
            .filter(|&(_, s)| 2 * s >= p.beams())
            .max_by_key(|&(li, s)| (s, std::cmp::Reverse(li)));
        if let Some((li, s)) = covering {
            let l = &lines[li];
            let union = (line_beams(l, n) + p.beams()).saturating_sub(s);
            pairs.push(Pair {
                line: li,
                piece: pi,
                significant: p.significant,
                dr: l.r - p.r,
                dalpha: angle_diff(l.alpha, p.alpha),
                start_error: (l.start - p.start).norm(),
                end_error: (l.end - p.end).norm(),
                overlap: s as f64 / union.max(1) as f64,
            });
        }
    }
    let false_lines: Vec<usize> = (0..lines.len()).filter(|&i| right[i].is_none()).collect();
    ScanMatch {
        significant_pieces: pieces.iter().filter(|p| p.significant).count(),
        found: pairs.iter().filter(|p| p.significant).count(),
        lines: lines.len(),
        pairs,
        false_lines,
        on_wall_lines: Vec::new(),
    }
}

/// [`Criteria::Strict`]: one to one.
fn match_one_to_one(lines: &[Line], pieces: &[ExpectedPiece], params: &MatchParams) -> ScanMatch {
    // (overlap, cost, line, piece)
    let mut candidates: Vec<(f64, f64, usize, usize)> = Vec::new();
    for (li, l) in lines.iter().enumerate() {
        for (pi, p) in pieces.iter().enumerate() {
            let (iou, _, dr, da) = compare(l, p);
            let (tr, ta) = params.tolerances(p);
            if iou >= params.min_overlap && dr.abs() <= tr && da <= ta {
                let cost = dr.abs() / tr.max(f64::MIN_POSITIVE) + da / ta.max(f64::MIN_POSITIVE);
                candidates.push((iou, cost, li, pi));
            }
        }
    }
    candidates.sort_by(|a, b| {
        b.0.total_cmp(&a.0)
            .then(a.1.total_cmp(&b.1))
            .then(a.2.cmp(&b.2))
            .then(a.3.cmp(&b.3))
    });
    let mut line_taken = vec![false; lines.len()];
    let mut piece_taken = vec![false; pieces.len()];
    let mut pairs = Vec::new();
    for (iou, _, li, pi) in candidates {
        if line_taken[li] || piece_taken[pi] {
            continue;
        }
        line_taken[li] = true;
        piece_taken[pi] = true;
        let (l, p) = (&lines[li], &pieces[pi]);
        pairs.push(Pair {
            line: li,
            piece: pi,
            significant: p.significant,
            dr: l.r - p.r,
            dalpha: angle_diff(l.alpha, p.alpha),
            start_error: (l.start - p.start).norm(),
            end_error: (l.end - p.end).norm(),
            overlap: iou,
        });
    }
    pairs.sort_by_key(|p| p.line);
    let false_lines: Vec<usize> = (0..lines.len()).filter(|&i| !line_taken[i]).collect();
    let on_wall_lines = false_lines
        .iter()
        .copied()
        .filter(|&li| on_a_wall(&lines[li], pieces, params))
        .collect();
    ScanMatch {
        significant_pieces: pieces.iter().filter(|p| p.significant).count(),
        found: pairs.iter().filter(|p| p.significant).count(),
        lines: lines.len(),
        pairs,
        false_lines,
        on_wall_lines,
    }
}

/// True when at least half of the beams of `l` fall on pieces of one wall, and `l` is within
/// the tolerances of the piece of that wall it shares most beams with.
fn on_a_wall(l: &Line, pieces: &[ExpectedPiece], params: &MatchParams) -> bool {
    let nl = line_beams(l, scan_beams(pieces));
    if nl == 0 {
        return false;
    }
    pieces.iter().any(|p| {
        let same_wall = pieces.iter().filter(|q| q.wall == p.wall);
        let on: usize = same_wall.clone().map(|q| shared(l, q)).sum();
        let mine = shared(l, p);
        let best = same_wall.map(|q| shared(l, q)).max().unwrap_or(0);
        if mine == 0 || mine < best || 2 * on < nl {
            return false;
        }
        let (_, _, dr, da) = compare(l, p);
        let (tr, ta) = params.tolerances(p);
        dr.abs() <= tr && da <= ta
    })
}
