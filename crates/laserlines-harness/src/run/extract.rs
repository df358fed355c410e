//! Line extraction in the loop: in line by default, or, with
//! [`crate::RunConfig::extraction_thread`] on a machine with two cores or more, on a second
//! thread while the robot side matches the same scan onto its map
//! ([`laserlines_nav::Explorer::sense`]) and the ground truth marks it. The lines are the
//! same either way: the extractor keeps no state from scan to scan but its working memory.

use std::sync::mpsc::{Receiver, Sender, channel};

use laserlines::{HoughSplit, Line, LineExtractor, Scan};

/// Where the lines of a scan are extracted: [`Extraction::start`] hands the scan over,
/// [`Extraction::finish`] gives its lines.
pub(super) trait Extraction {
    /// Starts extracting the lines of `scan`.
    fn start(&mut self, scan: &Scan);
    /// The lines of `scan`, the scan last started, into `lines`.
    fn finish(&mut self, scan: &Scan, lines: &mut Vec<Line>);
}

/// Extraction in line, at [`Extraction::start`].
pub(super) struct Inline {
    extractor: HoughSplit,
    lines: Vec<Line>,
}

impl Inline {
    pub(super) fn new(extractor: HoughSplit) -> Self {
        Self {
            extractor,
            lines: Vec::new(),
        }
    }
}

impl Extraction for Inline {
    fn start(&mut self, scan: &Scan) {
        self.extractor.extract_into(scan, &mut self.lines);
    }

    fn finish(&mut self, _scan: &Scan, lines: &mut Vec<Line>) {
        std::mem::swap(lines, &mut self.lines);
    }
}

/// A scan and the buffer for its lines, travelling between the threads.
type Job = (Scan, Vec<Line>);

/// Extraction on a second thread (see the [module docs](self)); should that thread be
/// gone, in line with a fresh extractor of the same parameters.
pub(super) struct Worker {
    to_worker: Option<Sender<Job>>,
    from_worker: Receiver<Job>,
    /// The buffers not travelling.
    spare: Job,
    fallback: Inline,
    /// True while a scan is with the worker.
    pending: bool,
}

impl Worker {
    /// Starts the thread on `scope`, extracting with `extractor`.
    pub(super) fn spawn<'scope>(
        scope: &'scope std::thread::Scope<'scope, '_>,
        extractor: HoughSplit,
    ) -> Self {
        let fallback = Inline::new(extractor.clone());
        let (to_worker, jobs) = channel::<Job>();
        let (done, from_worker) = channel::<Job>();
        scope.spawn(move || {
            let mut extractor = extractor;
            for (scan, mut lines) in jobs {
                extractor.extract_into(&scan, &mut lines);
                if done.send((scan, lines)).is_err() {
                    break;
                }
            }
        });
        Self {
            to_worker: Some(to_worker),
            from_worker,
            spare: (Scan::default(), Vec::new()),
            fallback,
            pending: false,
        }
    }
}

impl Extraction for Worker {
    fn start(&mut self, scan: &Scan) {
        let (mut copy, lines) = std::mem::take(&mut self.spare);
        copy_scan(&mut copy, scan);
        self.pending = match &self.to_worker {
            Some(to) => match to.send((copy, lines)) {
                Ok(()) => true,
                Err(back) => {
                    self.spare = back.0;
                    false
                }
            },
            None => false,
        };
        if !self.pending {
            self.to_worker = None;
            self.fallback.start(scan);
        }
    }

    fn finish(&mut self, scan: &Scan, lines: &mut Vec<Line>) {
        if !std::mem::take(&mut self.pending) {
            self.fallback.finish(scan, lines);
            return;
        }
        match self.from_worker.recv() {
            Ok((copy, mut got)) => {
                std::mem::swap(lines, &mut got);
                self.spare = (copy, got);
            }
            Err(_) => {
                // The thread is gone: extract the scan in line.
                self.to_worker = None;
                self.fallback.start(scan);
                self.fallback.finish(scan, lines);
            }
        }
    }
}

/// `dst` becomes a copy of `src`, reusing `dst`'s buffers.
fn copy_scan(dst: &mut Scan, src: &Scan) {
    dst.angle_min = src.angle_min;
    dst.angle_increment = src.angle_increment;
    dst.range_min = src.range_min;
    dst.range_max = src.range_max;
    dst.ranges.clear();
    dst.ranges.extend_from_slice(&src.ranges);
    match (&mut dst.intensities, &src.intensities) {
        (Some(d), Some(s)) => {
            d.clear();
            d.extend_from_slice(s);
        }
        (d, s) => *d = s.clone(),
    }
    dst.stamp = src.stamp;
}
