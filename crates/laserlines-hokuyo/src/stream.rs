//! A scan stream that survives its sensor: reconnects with backoff after a disconnect or a
//! silence, resumes streaming, keeps stamps monotonic, drops damaged scans and counts
//! every scan lost, by reason. It tells of the link through `tracing`: a warning when it is
//! lost, another every 5 s while the sensor stays away, and an info event when it is back.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::clock::{CLOCK_WRAP_MS, HostClock};
use crate::driver::{DriverError, DriverOptions, DropReason, HokuyoScan, ScanEvent, Session};
use crate::info::SensorInfo;
use crate::request::ScanRequest;
use crate::transport::Endpoint;

/// Settings of a [`Scanner`].
#[derive(Debug, Clone, PartialEq)]
pub struct ScannerOptions {
    /// The session's settings.
    pub driver: DriverOptions,
    /// What to stream; `None`: every step `AMIN..=AMAX` with `MD`.
    pub request: Option<ScanRequest>,
    /// A link silent this long is taken as lost; `None`: ten scan periods, at least 1 s.
    pub silence: Option<Duration>,
    /// The first wait before reconnecting; doubled per failed attempt. Default 50 ms.
    pub backoff_min: Duration,
    /// The longest wait between attempts. Default 500 ms.
    pub backoff_max: Duration,
}

impl Default for ScannerOptions {
    fn default() -> Self {
        Self {
            driver: DriverOptions::default(),
            request: None,
            silence: None,
            backoff_min: Duration::from_millis(50),
            backoff_max: Duration::from_millis(500),
        }
    }
}

/// Scans lost, by [`DropReason`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct DropCounts([u64; 6]);

impl DropCounts {
    fn index(reason: DropReason) -> usize {
        DropReason::ALL
            .iter()
            .position(|r| *r == reason)
            .unwrap_or(0)
    }

    /// Scans lost for `reason`.
    #[must_use]
    pub fn get(&self, reason: DropReason) -> u64 {
        self.0[Self::index(reason)]
    }

    /// Adds `n` scans lost for `reason`.
    pub fn add(&mut self, reason: DropReason, n: u64) {
        self.0[Self::index(reason)] += n;
    }

    /// All scans lost.
    #[must_use]
    pub fn total(&self) -> u64 {
        self.0.iter().sum()
    }
}

impl std::fmt::Display for DropCounts {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.total() == 0 {
            return write!(f, "none");
        }
        let mut first = true;
        for r in DropReason::ALL {
            let n = self.get(r);
            if n > 0 {
                if !first {
                    write!(f, ", ")?;
                }
                write!(f, "{n} {}", r.name())?;
                first = false;
            }
        }
        Ok(())
    }
}

/// What a [`Scanner`] has seen so far.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ScannerStats {
    /// Scans delivered.
    pub delivered: u64,
    /// Scans lost, by reason.
    pub dropped: DropCounts,
    /// Successful reconnections.
    pub reconnects: u64,
    /// Failed connection attempts.
    pub failed_attempts: u64,
    /// Host minus sensor time of the last synchronisation, s.
    pub clock_offset_s: Option<f64>,
    /// Drift estimate of the current session, s/s.
    pub drift: f64,
    /// The sensor was found in SCIP 1.1 and switched (on the last connection).
    pub switched_from_scip11: bool,
    /// The last link failure, as text.
    pub last_error: Option<String>,
}

/// A stream of scans from one sensor that reconnects by itself; see the module docs.
#[derive(Debug)]
pub struct Scanner {
    endpoint: Endpoint,
    options: ScannerOptions,
    host: HostClock,
    session: Option<Session>,
    info: SensorInfo,
    request: ScanRequest,
    stats: ScannerStats,
    last_raw: Option<u32>,
    /// When the last scan delivered was received (`None` before the first, and after
    /// [`Scanner::count_missed_until_now`]).
    last_good_at: Option<Instant>,
    last_stamp: f64,
    dropped_since_good: u64,
    after_reconnect: bool,
    last_activity: Instant,
    next_attempt: Instant,
    backoff: Duration,
    /// When the link was lost, while it is.
    lost_at: Option<Instant>,
    /// The last warning about the link.
    last_notice: Instant,
}

/// While the sensor is away, a warning this often (each failed attempt is counted in
/// [`ScannerStats::failed_attempts`]).
const NOTICE_EVERY: Duration = Duration::from_secs(5);

impl Scanner {
    /// Connects, runs the start-up and starts streaming. The first connection must succeed
    /// (a wrong path or address is reported at once); later ones are retried.
    ///
    /// # Errors
    /// The [`DriverError`] of the first connection.
    pub fn open(endpoint: &Endpoint, options: ScannerOptions) -> Result<Self, DriverError> {
        let host = HostClock::new();
        let mut session = Session::open(endpoint, &options.driver, host)?;
        let info = session.info().clone();
        let request = options.request.unwrap_or_else(|| info.full_request());
        session.start_stream(request, 0)?;
        let mut stats = ScannerStats {
            switched_from_scip11: session.switched_from_scip11(),
            clock_offset_s: session.clock().map(|c| c.offset_s()),
            ..ScannerStats::default()
        };
        stats.drift = 0.0;
        let backoff = options.backoff_min;
        Ok(Self {
            endpoint: session.endpoint().clone(),
            options,
            host,
            session: Some(session),
            info,
            request,
            stats,
            last_raw: None,
            last_good_at: None,
            last_stamp: f64::NEG_INFINITY,
            dropped_since_good: 0,
            after_reconnect: false,
            last_activity: Instant::now(),
            next_attempt: Instant::now(),
            backoff,
            lost_at: None,
            last_notice: Instant::now(),
        })
    }

    /// The sensor's description (from the first connection).
    #[must_use]
    pub fn info(&self) -> &SensorInfo {
        &self.info
    }

    /// What is streamed.
    #[must_use]
    pub fn request(&self) -> &ScanRequest {
        &self.request
    }

    /// The counts so far.
    #[must_use]
    pub fn stats(&self) -> &ScannerStats {
        &self.stats
    }

    /// True while connected.
    #[must_use]
    pub fn connected(&self) -> bool {
        self.session.is_some()
    }

    fn period_ms(&self) -> f64 {
        self.info.scan_period_s() * 1000.0 * f64::from(self.request.skip + 1)
    }

    fn silence(&self) -> Duration {
        self.options
            .silence
            .unwrap_or_else(|| Duration::from_secs_f64((self.period_ms() / 100.0).max(1.0)))
    }

    /// The next scan, blocking until one comes or `stop` is set (then `None`).
    pub fn next_scan(&mut self, stop: &AtomicBool) -> Option<HokuyoScan> {
        loop {
            if stop.load(Ordering::Relaxed) {
                return None;
            }
            if self.session.is_none() {
                self.try_reconnect(stop);
                continue;
            }
            let silence = self.silence();
            let deadline =
                (Instant::now() + Duration::from_millis(100)).min(self.last_activity + silence);
            let event = match self.session.as_mut().map(|s| s.read_scan(deadline)) {
                Some(Ok(e)) => e,
                Some(Err(e)) => {
                    self.lose_link(e.to_string());
                    continue;
                }
                None => continue,
            };
            match event {
                Some(ScanEvent::Scan(scan)) => {
                    self.last_activity = Instant::now();
                    if let Some(s) = self.accept(*scan) {
                        return Some(s);
                    }
                }
                Some(ScanEvent::Dropped(reason, why)) => {
                    self.last_activity = Instant::now();
                    tracing::debug!(reason = reason.name(), %why, "scan dropped");
                    self.stats.dropped.add(reason, 1);
                    self.dropped_since_good += 1;
                }
                Some(ScanEvent::Other) => self.last_activity = Instant::now(),
                None => {
                    if self.last_activity.elapsed() >= silence {
                        self.lose_link(format!("no data for {silence:?}"));
                    }
                }
            }
        }
    }

    /// Accounts a whole scan: the gap before it, duplicates, a monotonic stamp.
    fn accept(&mut self, mut scan: HokuyoScan) -> Option<HokuyoScan> {
        let raw = scan.sensor_raw_ms;
        if let Some(last) = self.last_raw {
            let dt = (u64::from(raw) + CLOCK_WRAP_MS - u64::from(last)) % CLOCK_WRAP_MS;
            let backwards = dt == 0 || dt > CLOCK_WRAP_MS / 2;
            if backwards && !self.after_reconnect {
                self.stats.dropped.add(DropReason::Duplicate, 1);
                return None;
            }
            if !backwards {
                let slots = (dt as f64 / self.period_ms()).round() as u64;
                let missing = slots
                    .saturating_sub(1)
                    .saturating_sub(self.dropped_since_good);
                let reason = if self.after_reconnect {
                    DropReason::Disconnected
                } else {
                    DropReason::Gap
                };
                self.stats.dropped.add(reason, missing);
            }
        }
        self.last_raw = Some(raw);
        self.last_good_at = Some(scan.received);
        self.dropped_since_good = 0;
        self.after_reconnect = false;
        let host_recv = self.host.at(scan.received);
        let mut stamp = scan.scan.stamp.unwrap_or(host_recv).min(host_recv);
        if stamp <= self.last_stamp {
            stamp = self.last_stamp + 1e-6;
        }
        self.last_stamp = stamp;
        scan.scan.stamp = Some(stamp);
        if let Some(c) = self.session.as_ref().and_then(|s| s.clock()) {
            self.stats.drift = c.drift();
        }
        self.stats.delivered += 1;
        Some(scan)
    }

    /// Counts the scans the sensor made since the last one delivered that never came, for a
    /// run that ends while the sensor is away or silent: [`Scanner::next_scan`] counts such
    /// scans only when the next one arrives, from the gap in the sensor's stamps. Without the
    /// sensor's stamps this count comes from the host clock: the scan periods elapsed since
    /// the last scan was received, less the one that may be on its way and the scans already
    /// counted as dropped, as `disconnected` while the link is down (or was, since that scan)
    /// and as `gap` otherwise. Counts once: a second call adds nothing.
    pub fn count_missed_until_now(&mut self) {
        let Some(at) = self.last_good_at.take() else {
            return;
        };
        let periods = at.elapsed().as_secs_f64() * 1000.0 / self.period_ms();
        // NaN or negative gives 0.
        let slots = if periods >= 1.0 {
            periods.floor() as u64
        } else {
            0
        };
        let missing = slots
            .saturating_sub(1)
            .saturating_sub(self.dropped_since_good);
        let reason = if self.session.is_none() || self.after_reconnect {
            DropReason::Disconnected
        } else {
            DropReason::Gap
        };
        self.stats.dropped.add(reason, missing);
        self.dropped_since_good += missing;
    }

    fn lose_link(&mut self, why: String) {
        if self.session.take().is_some_and(|s| s.pending_bytes() > 0) {
            // A scan cut off by the disconnect.
            self.stats.dropped.add(DropReason::Truncated, 1);
            self.dropped_since_good += 1;
        }
        tracing::warn!(endpoint = %self.endpoint, %why, "sensor link lost; reconnecting");
        let now = Instant::now();
        self.lost_at = Some(now);
        self.last_notice = now;
        self.stats.last_error = Some(why);
        self.after_reconnect = true;
        self.backoff = self.options.backoff_min;
        self.next_attempt = Instant::now() + self.backoff;
    }

    fn try_reconnect(&mut self, stop: &AtomicBool) {
        while Instant::now() < self.next_attempt {
            if stop.load(Ordering::Relaxed) {
                return;
            }
            std::thread::sleep((self.next_attempt - Instant::now()).min(Duration::from_millis(20)));
        }
        let attempt = Session::open(&self.endpoint, &self.options.driver, self.host)
            .and_then(|mut s| s.start_stream(self.request, 0).map(|()| s));
        match attempt {
            Ok(s) => {
                if let Some(t) = self.lost_at.take() {
                    let away = t.elapsed().as_secs_f64();
                    tracing::info!(endpoint = %self.endpoint, "sensor link back after {away:.1} s");
                }
                self.stats.reconnects += 1;
                self.stats.switched_from_scip11 = s.switched_from_scip11();
                self.stats.clock_offset_s = s.clock().map(|c| c.offset_s());
                self.session = Some(s);
                self.last_activity = Instant::now();
                self.backoff = self.options.backoff_min;
            }
            Err(e) => {
                let now = Instant::now();
                if now.duration_since(self.last_notice) >= NOTICE_EVERY {
                    self.last_notice = now;
                    let away = self
                        .lost_at
                        .map_or(0.0, |t| now.duration_since(t).as_secs_f64());
                    tracing::warn!(
                        endpoint = %self.endpoint,
                        error = %e,
                        failed_attempts = self.stats.failed_attempts + 1,
                        "sensor still away after {away:.0} s; reconnecting"
                    );
                }
                self.stats.failed_attempts += 1;
                self.stats.last_error = Some(e.to_string());
                self.backoff = (self.backoff * 2).min(self.options.backoff_max);
                self.next_attempt = Instant::now() + self.backoff;
            }
        }
    }

    /// Stops the sensor (`QT`, waiting for its reply) and closes the link.
    ///
    /// # Errors
    /// The [`DriverError`] of `QT`.
    pub fn close(mut self) -> Result<(), DriverError> {
        match self.session.take() {
            Some(mut s) => s.stop(),
            None => Ok(()),
        }
    }
}
