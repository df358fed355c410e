//! The paper's extractor: g-weighted Hough transform, grouping into data segments with removal
//! of sparse and cluttered points, and the recursive split `Linseg`.
//!
//! ```
//! use laserlines::{HoughSplit, HoughSplitParams, LineExtractor, Scan};
//! // A wall at x = 2 m seen by 181 beams from -45 to +45 deg.
//! let inc = 0.5_f64.to_radians();
//! let ranges = (0..181)
//!     .map(|i| 2.0 / (-45.0_f64.to_radians() + i as f64 * inc).cos())
//!     .collect();
//! let scan = Scan::new(-45.0_f64.to_radians(), inc, 0.02, 5.6, ranges).unwrap();
//! let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
//! let lines = hs.extract(&scan);
//! assert_eq!(lines.len(), 1);
//! assert!((lines[0].r - 2.0).abs() < 1e-9 && lines[0].alpha.abs() < 1e-9);
//! ```

mod accumulator;
mod arcs;
mod collinear;
mod components;
mod corners;
mod ends;
mod lines;
mod linseg;
mod local_bridge;
mod mixed;
mod opening;
mod params;
mod points;
mod presets;
mod seam;
mod segment;

pub use crate::params::ParamsError;
pub use accumulator::Cell;
pub use lines::SILENT_GAP;
pub use local_bridge::{LOCAL_DROPOUT, LOCAL_MAX_SIN_INCIDENCE, LOCAL_MIN_MISSING, LOCAL_WINDOW};
pub use params::{
    Bridge, GAP_CHANCE, HoughSplitParams, MAX_BRIDGE_GAP, MAX_RING_STEP, MAX_WINDOW_RINGS,
    MIN_RING_STEP, MIN_SPARSE_POINTS, MinPoints, PAPER_SECTOR_BEAMS, Weight,
};

use crate::extractor::LineExtractor;
use crate::line::Line;
use crate::math::Point2;
use crate::noise::{BandEstimate, NOISE_BANDS, NoiseEstimator, NoiseModel, RangeNoise};
use crate::scan::{RangeWindow, ScanPoint, ScanView};
use accumulator::{Accumulator, Valid};
use components::Components;
use linseg::SplitScratch;
use points::{BeamTable, Pt};
use segment::{Breakpoints, Segments};

/// The paper's line extractor (see the module docs). Reuse one value across scans: its
/// working memory is kept, so that steady-state extraction allocates nothing.
#[derive(Debug, Clone)]
pub struct HoughSplit {
    params: HoughSplitParams,
    table: BeamTable,
    estimator: NoiseEstimator,
    /// The estimate one beam apart, for the mixed-pixel test on scans read two beams apart.
    adjacent: NoiseEstimator,
    /// The noise of the last scan: the fixed model, or the estimate.
    noise: RangeNoise,
    /// True when the last scan's noise was estimated from it.
    estimated: bool,
    /// The last scan's dropout rate ([`segment::dropout`]).
    dropout: f64,
    /// The last scan's `angle_min` and `angle_increment`.
    angles: (f64, f64),
    breakpoints: Breakpoints,
    points: Vec<Pt>,
    acc: Accumulator,
    uf: Components,
    /// Per point: its cell (see `Accumulator::build`).
    cell_of: Vec<u32>,
    segments: Segments,
    scratch: SplitScratch,
    /// Split-tree end points of all segments (beam indices), with per-segment ranges.
    split_points: Vec<usize>,
    split_ranges: Vec<(u32, u32)>,
    /// Per line of the last scan before step 7: the sums of its points, and whether it is
    /// certain.
    candidates: Vec<lines::Candidate>,
    /// The pieces of the segment being turned into lines.
    pieces: Vec<lines::Piece>,
    groups: collinear::Groups,
    /// The last scan's beam count, and the beam its walk started from (0 unless it went
    /// once round: [`seam`]); the stages above are in the walk's beam indices.
    turn: (usize, usize),
    /// The ranges of a full turn in the order of its walk.
    walk: Vec<f64>,
    /// A full turn's returns, for [`seam::start`].
    returns: Vec<(usize, f64)>,
    /// The window of valid ranges of the scan being processed ([`ScanView::range_window`]).
    window: RangeWindow,
}

impl HoughSplit {
    /// An extractor with validated parameters.
    ///
    /// # Errors
    /// [`ParamsError`] when a parameter is out of its domain.
    pub fn new(params: HoughSplitParams) -> Result<Self, ParamsError> {
        params.validate()?;
        Ok(Self {
            params,
            table: BeamTable::default(),
            estimator: NoiseEstimator::default(),
            adjacent: NoiseEstimator::default(),
            noise: FALLBACK_NOISE,
            estimated: false,
            dropout: 0.0,
            angles: (0.0, 0.0),
            breakpoints: Breakpoints::default(),
            points: Vec::new(),
            acc: Accumulator::default(),
            uf: Components::default(),
            cell_of: Vec::new(),
            segments: Segments::default(),
            scratch: SplitScratch::default(),
            split_points: Vec::new(),
            split_ranges: Vec::new(),
            candidates: Vec::new(),
            pieces: Vec::new(),
            groups: collinear::Groups::default(),
            turn: (0, 0),
            walk: Vec::new(),
            returns: Vec::new(),
            window: RangeWindow::UNLIMITED,
        })
    }

    /// The parameters in use.
    #[must_use]
    pub fn params(&self) -> &HoughSplitParams {
        &self.params
    }

    /// The range noise of `scan`: the fixed model, or the estimate from the scan itself
    /// ([`FALLBACK_NOISE`] when the scan is too short or sparse to tell, or is no valid
    /// scan), never below `noise_floor`.
    fn noise_of(&mut self, scan: Option<ScanView<'_>>) {
        let p = &self.params;
        let floor = p.noise_floor;
        let (noise, estimated) = match (p.noise, scan) {
            (NoiseModel::Fixed(n), _) => (n, false),
            (NoiseModel::Auto, Some(scan)) => {
                match self.estimator.estimate(scan, self.window, floor) {
                    Some(n) => (n, true),
                    None => (FALLBACK_NOISE, false),
                }
            }
            (NoiseModel::Auto, None) => {
                self.estimator.forget();
                (FALLBACK_NOISE, false)
            }
        };
        self.noise = RangeNoise::new(noise.sigma_min.max(floor), noise.fraction);
        self.estimated = estimated;
    }

    /// The intermediate stages of the last extraction, for pictures and tests.
    #[must_use]
    pub fn stages(&self) -> Stages<'_> {
        Stages { hs: self }
    }
}

impl LineExtractor for HoughSplit {
    fn name(&self) -> &'static str {
        "hough-split"
    }

    fn range_noise(&self) -> Option<RangeNoise> {
        Some(self.noise)
    }

    fn extract_view_into(&mut self, scan: ScanView<'_>, out: &mut Vec<Line>) {
        out.clear();
        self.candidates.clear();
        self.split_points.clear();
        self.split_ranges.clear();
        self.turn = (scan.ranges.len(), 0);
        // Broken geometry (a view built without `ScanView::new`) gives no line.
        if scan.validate().is_err() {
            self.forget_stages();
            return;
        }
        let window = scan.range_window(self.params.range_limits);
        self.window = window;
        let lo = window.min.max(self.params.min_range).max(f64::MIN_POSITIVE);
        if !scan.full_turn() {
            self.run(scan, out);
            return;
        }
        let n = scan.ranges.len();
        let seam = seam::start(
            scan.ranges,
            (lo, window.max),
            scan.angle_increment,
            &mut self.returns,
        );
        // A full turn is walked from `seam`, so that no surface is cut where the scan's
        // beams begin; its lines come back in the scan's own beam indices.
        let mut walk = std::mem::take(&mut self.walk);
        walk.clear();
        walk.extend_from_slice(&scan.ranges[seam..]);
        walk.extend_from_slice(&scan.ranges[..seam]);
        self.turn.1 = seam;
        self.run(
            ScanView {
                ranges: &walk,
                ..scan
            },
            out,
        );
        if let (Some(a), Some(b)) = (self.candidates.last(), self.candidates.first()) {
            seam::join_ends(out, &walk, lo, (a.ends.1, b.ends.0));
        }
        self.walk = walk;
        seam::unwalk(out, &mut self.split_points, seam, n);
    }
}

impl HoughSplit {
    /// Steps 0-7 on `scan` (a full turn in the order of its walk).
    fn run(&mut self, scan: ScanView<'_>, out: &mut Vec<Line>) {
        self.vote(scan);
        self.group(scan);
        self.fit_segments(scan, out);
        // 7. lines of one surface across segments share their joint fit.
        collinear::share_fits(
            out,
            &self.candidates,
            &self.params,
            &self.noise,
            corners::Seen::new(&self.points, &self.breakpoints),
            &mut self.groups,
        );
    }

    /// Empties every stage (for a scan that gives no line).
    fn forget_stages(&mut self) {
        self.points.clear();
        self.cell_of.clear();
        self.acc.clear();
        self.segments.kept.clear();
        self.segments.runs.clear();
        // No estimate: the last scan's would be reported as this one's.
        self.noise_of(None);
        self.dropout = 0.0;
    }

    /// Steps 0-2: the valid beams to points and their noise, the accumulator and its
    /// criterion; then the breakpoints of the scan, and points below the criterion rescued
    /// where the beam bridge would join them.
    fn vote(&mut self, scan: ScanView<'_>) {
        let p = &self.params;
        self.table.prepare(
            scan.angle_min,
            scan.angle_increment,
            scan.ranges.len(),
            p.sector_step,
        );
        self.table.walk_from(self.turn.1);
        self.angles = (scan.angle_min, scan.angle_increment);
        self.noise_of(Some(scan));
        let valid = Valid {
            window: self.window,
            min_range: self.params.min_range,
            mixed: self.params.remove_mixed_pixels.then(|| {
                let limits = (self.window, self.params.noise_floor);
                let noise = (self.noise, self.estimated);
                mixed::between_neighbours(&mut self.adjacent, scan, limits, noise)
            }),
        };
        self.acc.build(
            scan,
            &valid,
            &self.table,
            &self.params,
            &mut self.points,
            &mut self.cell_of,
        );
        self.dropout = segment::dropout(&self.points, scan.ranges.len());
        self.breakpoints.prepare(
            &self.params,
            scan.angle_increment,
            self.noise,
            (self.dropout, valid.window.min, valid.window.max),
        );
        if self.params.bridge_beams && self.acc.loose > 0 {
            segment::rescue_points(
                &self.points,
                &mut self.cell_of,
                &mut self.acc.bins,
                &self.breakpoints,
            );
        }
    }

    /// Steps 3-4: radius grouping and merging of touching groups (and the beam bridge),
    /// then the data segments; everything else is removed.
    fn group(&mut self, scan: ScanView<'_>) {
        components::connect_cells(&self.acc, &self.params, &mut self.uf);
        if self.params.bridge_beams {
            segment::bridge_beams(
                scan.ranges,
                &self.points,
                &self.cell_of,
                &self.breakpoints,
                &mut self.uf,
            );
        }
        let min_points = self.params.min_points_for(self.dropout);
        segment::cut_segments(
            scan.ranges,
            &self.points,
            &self.cell_of,
            &self.acc.bins,
            (&self.params, min_points.segment),
            &self.breakpoints,
            &mut self.uf,
            &mut self.segments,
        );
    }

    /// Steps 5-6: Linseg on each data segment, then the least-squares lines into `out`.
    fn fit_segments(&mut self, scan: ScanView<'_>, out: &mut Vec<Line>) {
        let min_points = self.params.min_points_for(self.dropout);
        let kept = &self.segments.kept;
        let cut_window = lines::cut_window(scan.angle_increment);
        let lone_gap = self.params.lone_gap_for(self.dropout);
        let seen = corners::Seen::new(&self.points, &self.breakpoints);
        let lo = self.window.min.max(self.params.min_range);
        for run in &self.segments.runs {
            let seg = points::Seg(&kept[run.start as usize..run.end as usize]);
            linseg::prefix_sums(seg, &mut self.scratch.prefix);
            linseg::linseg(
                seg,
                &self.params,
                &self.noise,
                min_points.line,
                &mut self.scratch,
            );
            let from = self.split_points.len() as u32;
            self.split_points
                .extend(self.scratch.breaks.iter().map(|&b| seg.idx(b as usize)));
            self.split_ranges
                .push((from, self.split_points.len() as u32));
            let pieces = lines::Pieces {
                seg,
                pre: &self.scratch.prefix,
                p: &self.params,
                noise: &self.noise,
                cut_window,
                min_points: min_points.line,
                lone_gap,
                seen,
            };
            let first = out.len();
            lines::emit_lines(
                &pieces,
                (
                    &mut self.scratch.breaks,
                    &mut self.scratch.openings,
                    &mut self.pieces,
                ),
                out,
                &mut self.candidates,
            );
            if first > 0
                && first < out.len()
                && lines::follows_across_silence(
                    scan.ranges,
                    lo,
                    (&out[first - 1], &out[first]),
                    (
                        self.candidates[first - 1].ends.1,
                        self.candidates[first].ends.0,
                    ),
                )
            {
                self.candidates[first].follows = true;
            }
        }
    }
}

/// The noise assumed when [`NoiseModel::Auto`] finds too few samples in a scan to estimate
/// it: the URG-04LX data sheet's band, `max(10 mm, 1 % of the range)`.
pub const FALLBACK_NOISE: RangeNoise = RangeNoise::new(0.01, 0.01);

/// A data segment: the paper's `SA[t]`, start and end beam of a run of surviving points.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DataSegment {
    /// First beam index (`SA[t][0]`).
    pub first: usize,
    /// Last beam index (`SA[t][1]`).
    pub last: usize,
    /// Number of surviving points in the segment.
    pub points: usize,
}

impl DataSegment {
    /// True when beam `i` lies between `first` and `last` (inclusive), across the seam of a
    /// full turn when `first > last`.
    #[must_use]
    pub fn covers(&self, i: usize) -> bool {
        crate::line::covers(self.first, self.last, i)
    }
}

/// A radius group: a run of kept cells along one ring (paper Fig. 4a).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RadiusGroup {
    /// Ring index (centre distance `ring * ring_step`).
    pub ring: u32,
    /// First sector of the run.
    pub first_sector: u32,
    /// Last sector of the run (inclusive).
    pub last_sector: u32,
}

/// Read-only view of the intermediate stages of the last [`HoughSplit`] extraction.
#[derive(Debug, Clone, Copy)]
pub struct Stages<'a> {
    hs: &'a HoughSplit,
}

impl<'a> Stages<'a> {
    /// The range noise every threshold of the last extraction was a multiple of.
    #[must_use]
    pub fn noise(&self) -> RangeNoise {
        self.hs.noise
    }

    /// True when [`Stages::noise`] was estimated from the scan itself.
    #[must_use]
    pub fn noise_estimated(&self) -> bool {
        self.hs.estimated
    }

    /// The noise-cancelling criterion the last scan's cells were held to
    /// ([`HoughSplitParams::criterion_for`] its beam increment).
    #[must_use]
    pub fn criterion(&self) -> f64 {
        self.hs.params.criterion_for(self.hs.angles.1)
    }

    /// The fraction of the last scan's returns whose next beam returned nothing, which sets
    /// its beam bridge ([`HoughSplitParams::bridge_for`]).
    #[must_use]
    pub fn dropout(&self) -> f64 {
        self.hs.dropout
    }

    /// The fewest points the last scan's data segments and lines needed
    /// ([`HoughSplitParams::min_points_for`] its [`Stages::dropout`]).
    #[must_use]
    pub fn min_points(&self) -> MinPoints {
        self.hs.params.min_points_for(self.hs.dropout)
    }

    /// The range resolution that raised the last estimate's `sigma_min` to `q / sqrt(12)`, m
    /// (see [`NoiseEstimator::quantum`]); `None` with a fixed model.
    #[must_use]
    pub fn range_quantum(&self) -> Option<f64> {
        if self.hs.estimated {
            self.hs.estimator.quantum()
        } else {
            None
        }
    }

    /// The per-band figures of the last estimate (all zero with a fixed model).
    #[must_use]
    pub fn noise_bands(&self) -> &'a [BandEstimate; NOISE_BANDS] {
        self.hs.estimator.bands()
    }

    /// The beam the last scan was walked from: 0, unless it went once round
    /// ([`ScanView::full_turn`]), when the walk starts after the widest gap between its
    /// returns, so that no surface is cut where its beams begin. Every stage below is in the
    /// order of the walk, and names the scan's own beam indices.
    #[must_use]
    pub fn seam(&self) -> usize {
        self.hs.turn.1
    }

    /// The scan's own index of beam `w` of the walk.
    fn beam(&self, w: usize) -> usize {
        let (n, seam) = self.hs.turn;
        if seam == 0 { w } else { (w + seam) % n }
    }

    /// The valid points the pipeline started from, in beam order.
    #[must_use]
    pub fn points(&self) -> Vec<ScanPoint> {
        let pts = &self.hs.points;
        let (angle_min, increment) = self.hs.angles;
        let mut out: Vec<ScanPoint> = (0..pts.len())
            .map(|k| {
                let index = self.beam(pts[k].idx);
                ScanPoint {
                    index,
                    range: pts[k].range,
                    angle: angle_min + index as f64 * increment,
                    point: Point2::new(pts[k].x, pts[k].y),
                }
            })
            .collect();
        // The walk of a full turn passes beam 0 part of the way.
        out.sort_by_key(|p| p.index);
        out
    }

    /// Every accumulator cell that received a vote, sector by sector in ring order.
    #[must_use]
    pub fn cells(&self) -> Vec<Cell> {
        self.hs.acc.cells()
    }

    /// The distance `d` of a ring's centre line, m.
    #[must_use]
    pub fn ring_distance(&self, ring: u32) -> f64 {
        f64::from(ring) * self.hs.params.ring_step
    }

    /// The direction `gamma` of a sector's centre, rad, in the frame of `scan` (a
    /// [`Scan`](crate::Scan) or a [`ScanView`]). Sectors count from the walk's first beam
    /// ([`Stages::seam`]).
    #[must_use]
    pub fn sector_angle<'s>(&self, scan: impl Into<ScanView<'s>>, sector: u32) -> f64 {
        let scan = scan.into();
        let sign = if scan.angle_increment < 0.0 {
            -1.0
        } else {
            1.0
        };
        scan.angle(self.hs.turn.1) + sign * (f64::from(sector) + 0.5) * self.hs.params.sector_step
    }

    /// Radius groups: runs of kept cells along each ring, bridging `group_gap` empty sectors.
    #[must_use]
    pub fn radius_groups(&self) -> Vec<RadiusGroup> {
        let mut kept: Vec<(u32, u32)> = self
            .cells()
            .into_iter()
            .filter(|c| c.kept)
            .map(|c| (c.ring, c.sector))
            .collect();
        kept.sort_unstable();
        let gap = self.hs.params.group_gap as u32;
        let mut out: Vec<RadiusGroup> = Vec::new();
        for (ring, sector) in kept {
            match out.last_mut() {
                Some(g) if g.ring == ring && sector <= g.last_sector + 1 + gap => {
                    g.last_sector = sector;
                }
                _ => out.push(RadiusGroup {
                    ring,
                    first_sector: sector,
                    last_sector: sector,
                }),
            }
        }
        out
    }

    /// The data segments, in beam order (from [`Stages::seam`]; one segment of a full turn
    /// may run across the scan's seam, `first > last`).
    pub fn segments(&self) -> impl Iterator<Item = DataSegment> + 'a {
        let stages = *self;
        let segs = &self.hs.segments;
        segs.runs.iter().map(move |run| DataSegment {
            first: stages.beam(segs.kept[run.start as usize].idx),
            last: stages.beam(segs.kept[run.end as usize - 1].idx),
            points: (run.end - run.start) as usize,
        })
    }

    /// Beam indices of the surviving points (the paper's non-zero `Pm[i]`), in beam order
    /// (from [`Stages::seam`]).
    pub fn kept(&self) -> impl Iterator<Item = usize> + 'a {
        let stages = *self;
        self.hs
            .segments
            .kept
            .iter()
            .map(move |p| stages.beam(p.idx))
    }

    /// Beam indices of valid points removed as sparse or cluttered (the paper's `Pm[i] = 0`),
    /// in beam order (from [`Stages::seam`]).
    #[must_use]
    pub fn removed(&self) -> Vec<usize> {
        let mut keep = self.hs.segments.kept.iter().map(|p| p.idx).peekable();
        let mut out = Vec::new();
        for i in self.hs.points.iter().map(|p| p.idx) {
            if keep.peek().is_some_and(|&x| x == i) {
                keep.next();
            } else {
                out.push(self.beam(i));
            }
        }
        out
    }

    /// The split tree's end points of each data segment (beam indices in beam order, the
    /// segment's first and last beam included; past the last beam of a full turn they go on
    /// from 0, see [`Stages::seam`]), before the collinear merge.
    pub fn split_points(&self) -> impl Iterator<Item = &'a [usize]> + 'a {
        let hs = self.hs;
        hs.split_ranges
            .iter()
            .map(move |&(a, b)| &hs.split_points[a as usize..b as usize])
    }
}
