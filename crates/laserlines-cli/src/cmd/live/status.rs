//! The figures of a `live` run: scans, lines, extraction time and the time from a scan's
//! last byte to its lines, shown in a status line every second and in the summary.

use std::time::{Duration, Instant};

use laserlines_hokuyo::ScannerStats;

/// Figures of the run shown in the status line.
#[derive(Default)]
pub struct Tally {
    /// Scans extracted.
    pub scans: u64,
    /// Lines extracted.
    pub lines: u64,
    window_start: Option<Instant>,
    window_scans: u64,
    extract_us_max: f64,
    latency_us_max: f64,
    extract_us_sum: f64,
    latency_us_sum: f64,
    /// Scans per second over the last window.
    pub rate: f64,
    last_status: Option<Instant>,
}

impl Tally {
    /// A tally starting now (the first status line comes a second from now).
    pub fn start() -> Self {
        Self {
            last_status: Some(Instant::now()),
            ..Self::default()
        }
    }

    /// Counts a scan whose `lines` lines took `extract_us` to extract, `latency_us` after
    /// its last byte, the extraction done at `done`.
    pub fn add(&mut self, lines: usize, extract_us: f64, latency_us: f64, done: Instant) {
        self.extract_us_sum += extract_us;
        self.latency_us_sum += latency_us;
        self.extract_us_max = self.extract_us_max.max(extract_us);
        self.latency_us_max = self.latency_us_max.max(latency_us);
        self.scans += 1;
        self.lines += lines as u64;
        self.window_scans += 1;
        self.window_start.get_or_insert(done);
    }

    /// Every second: the rate over the window, and the status line on stderr (one line
    /// rewritten on a terminal, one line per second otherwise).
    pub fn report(&mut self, stats: &ScannerStats, done: Instant, tty: bool) {
        let (Some(w0), Some(last)) = (self.window_start, self.last_status) else {
            return;
        };
        if last.elapsed() < Duration::from_secs(1) {
            return;
        }
        let secs = done.duration_since(w0).as_secs_f64();
        if secs > 0.0 {
            self.rate = (self.window_scans - 1) as f64 / secs;
        }
        self.window_start = Some(done);
        self.window_scans = 1;
        let line = self.status_line(stats);
        if tty {
            err!("\r{line}\x1b[K");
        } else {
            errln!("laserlines: {line}");
        }
        self.last_status = Some(Instant::now());
    }

    /// At the end of the run: the rate over the window since the last status line, for a run
    /// shorter than a second or its last part (a window of a second or more counts even
    /// with no scan after its first: a sensor gone at the end shows 0 scans/s, not the rate
    /// from before).
    pub fn close_window(&mut self, now: Instant) {
        let Some(w0) = self.window_start else { return };
        let secs = now.duration_since(w0).as_secs_f64();
        if (self.window_scans > 1 && secs > 0.0) || secs >= 1.0 {
            self.rate = self.window_scans.saturating_sub(1) as f64 / secs;
        }
    }

    /// The status line.
    pub fn status_line(&self, stats: &ScannerStats) -> String {
        let n = self.scans.max(1) as f64;
        format!(
            "{:.1} scans/s, {} scans, dropped: {}, reconnects {}, clock offset {}, drift {:.1} ppm, extraction {:.0} us (max {:.0}), last byte to lines {:.0} us (max {:.0})",
            self.rate,
            self.scans,
            stats.dropped,
            stats.reconnects,
            stats
                .clock_offset_s
                .map_or_else(|| "-".to_owned(), |o| format!("{o:.3} s")),
            stats.drift * 1e6,
            self.extract_us_sum / n,
            self.extract_us_max,
            self.latency_us_sum / n,
            self.latency_us_max,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sensor_gone_at_the_end_shows_no_rate_from_before() {
        let t0 = Instant::now();
        let at = |ms: u64| t0 + Duration::from_millis(ms);
        let mut tally = Tally::start();
        // 40 scans a second for a second: the window's rate is 40.
        for k in 0..=40 {
            tally.add(3, 100.0, 120.0, at(25 * k));
        }
        tally.close_window(at(1000));
        assert!((tally.rate - 40.0).abs() < 1e-9, "{}", tally.rate);
        // A status line opened a window at the last scan; then the sensor was gone 13 s.
        tally.window_start = Some(at(1000));
        tally.window_scans = 1;
        tally.close_window(at(14_000));
        assert_eq!(tally.rate, 0.0);
        // A window shorter than a second with one scan keeps the rate it had.
        tally.rate = 40.0;
        tally.close_window(at(1_300));
        assert_eq!(tally.rate, 40.0);
    }
}
