//! The verb trait every line extractor implements.

use crate::line::Line;
use crate::noise::RangeNoise;
use crate::scan::{Scan, ScanView};

/// A line extraction algorithm.
///
/// Implementations keep their working memory between calls, so that steady-state extraction
/// allocates nothing: call [`LineExtractor::extract_into`] with a buffer you reuse. Any scan is
/// accepted, valid or not: invalid ranges are no returns, and a scan with broken geometry
/// yields no lines rather than a panic. Random algorithms take their seed in their parameters
/// and reseed for every scan, so that the same scan gives the same lines.
pub trait LineExtractor {
    /// The algorithm's name as the command line knows it (e.g. `hough-split`).
    fn name(&self) -> &'static str;

    /// Extracts the lines of `scan` into `out` (cleared first), ordered by first beam. The
    /// ranges are read where they are (a [`Scan`]'s, or any other buffer's), never copied.
    fn extract_view_into(&mut self, scan: ScanView<'_>, out: &mut Vec<Line>);

    /// Extracts the lines of `scan` into `out` (cleared first), ordered by first beam:
    /// [`LineExtractor::extract_view_into`] on [`Scan::view`].
    fn extract_into(&mut self, scan: &Scan, out: &mut Vec<Line>) {
        self.extract_view_into(scan.view(), out);
    }

    /// The range noise the last extraction assumed, for extractors that model it
    /// (`hough-split`: estimated from the scan, or its fixed model; before any extraction,
    /// the model it falls back on); `None` otherwise.
    fn range_noise(&self) -> Option<RangeNoise> {
        None
    }

    /// Allocating convenience wrapper around [`LineExtractor::extract_into`].
    fn extract(&mut self, scan: &Scan) -> Vec<Line> {
        let mut out = Vec::new();
        self.extract_into(scan, &mut out);
        out
    }
}
