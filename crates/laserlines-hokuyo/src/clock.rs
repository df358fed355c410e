//! Time: the sensor's 24-bit millisecond clock unwrapped, and its relation to the host's
//! clock (offset from `TM` synchronisation, drift from the scan stream), so that every
//! scan gets a host-time stamp.

use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

/// The sensor clock counts milliseconds in 24 bits: it wraps after 2^24 ms (4 h 40 min).
pub const CLOCK_WRAP_MS: u64 = 1 << 24;

/// The host's clock: seconds since the UNIX epoch, read from a monotonic clock (so it
/// never steps backwards, whatever the system clock does while running).
#[derive(Debug, Clone, Copy)]
pub struct HostClock {
    origin: Instant,
    origin_epoch_s: f64,
}

impl Default for HostClock {
    fn default() -> Self {
        Self::new()
    }
}

impl HostClock {
    /// A clock starting at the system time now.
    #[must_use]
    pub fn new() -> Self {
        let origin_epoch_s = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .unwrap_or(Duration::ZERO)
            .as_secs_f64();
        Self {
            origin: Instant::now(),
            origin_epoch_s,
        }
    }

    /// Seconds since the epoch at `instant`.
    #[must_use]
    pub fn at(&self, instant: Instant) -> f64 {
        let d = instant.saturating_duration_since(self.origin).as_secs_f64();
        self.origin_epoch_s + d
    }

    /// Seconds since the epoch now.
    #[must_use]
    pub fn now(&self) -> f64 {
        self.at(Instant::now())
    }
}

/// Unwraps the sensor's 24-bit clock into a count that does not wrap.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ClockUnwrap {
    last: Option<u32>,
    wraps: u64,
}

impl ClockUnwrap {
    /// A fresh unwrapper.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The unwrapped time of raw reading `raw` (ms, below 2^24). A reading more than half
    /// a wrap below the previous one is taken as the clock having wrapped; a small step
    /// back is kept as it is.
    pub fn unwrap(&mut self, raw: u32) -> u64 {
        let raw = u64::from(raw) % CLOCK_WRAP_MS;
        if let Some(last) = self.last {
            let last = u64::from(last);
            if raw < last && last - raw > CLOCK_WRAP_MS / 2 {
                self.wraps += 1;
            } else if raw > last && raw - last > CLOCK_WRAP_MS / 2 && self.wraps > 0 {
                // A late reading from before the last wrap.
                return (self.wraps - 1) * CLOCK_WRAP_MS + raw;
            }
        }
        self.last = Some(raw as u32);
        self.wraps * CLOCK_WRAP_MS + raw
    }

    /// Times the clock wrapped so far.
    #[must_use]
    pub fn wraps(&self) -> u64 {
        self.wraps
    }
}

/// One `TM1` exchange: host time before sending, host time when the reply's last byte
/// came, and the sensor's time in the reply.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeSample {
    /// Host time when `TM1` was sent, s.
    pub host_send_s: f64,
    /// Host time when its reply was read, s.
    pub host_recv_s: f64,
    /// The sensor's clock, unwrapped, ms.
    pub sensor_ms: u64,
}

impl TimeSample {
    /// The round trip, s.
    #[must_use]
    pub fn round_trip_s(&self) -> f64 {
        self.host_recv_s - self.host_send_s
    }
}

/// How long a window of the scan stream is, in sensor time, for the drift estimate, s.
const DRIFT_WINDOW_S: f64 = 2.0;
/// The drift is estimated only over at least this much sensor time, s.
const DRIFT_MIN_SPAN_S: f64 = 10.0;

/// The sensor clock against the host clock:
/// `host = offset + sensor + drift * (sensor - reference)` (s).
///
/// The offset comes from `TM` synchronisation: of the exchanges, the one with the shortest
/// round trip, taking the sensor's reading to have been made halfway through it. The drift
/// (host seconds gained per sensor second, e.g. 5e-5 for 50 ppm) comes from the scan stream:
/// the least delay between a scan's time stamp and its arrival, per window of
/// [`DRIFT_WINDOW_S`], follows the clocks' difference; its slope between the first window
/// and the latest is the drift.
#[derive(Debug, Clone, PartialEq)]
pub struct ClockModel {
    offset_s: f64,
    reference_s: f64,
    drift: f64,
    best_round_trip_s: f64,
    first_window: Option<(f64, f64)>,
    window: Option<(f64, f64, f64)>,
}

impl ClockModel {
    /// The model from `TM1` exchanges; `None` when there are none.
    #[must_use]
    pub fn from_samples(samples: &[TimeSample]) -> Option<Self> {
        let best = samples
            .iter()
            .filter(|s| s.round_trip_s().is_finite() && s.round_trip_s() >= 0.0)
            .min_by(|a, b| a.round_trip_s().total_cmp(&b.round_trip_s()))?;
        let sensor_s = best.sensor_ms as f64 / 1000.0;
        let mid = 0.5 * (best.host_send_s + best.host_recv_s);
        Some(Self {
            offset_s: mid - sensor_s,
            reference_s: sensor_s,
            drift: 0.0,
            best_round_trip_s: best.round_trip_s(),
            first_window: None,
            window: None,
        })
    }

    /// A model with a known offset (host minus sensor time, s) and no drift, referenced
    /// at sensor time `reference_ms`.
    #[must_use]
    pub fn from_offset(offset_s: f64, reference_ms: u64) -> Self {
        Self {
            offset_s,
            reference_s: reference_ms as f64 / 1000.0,
            drift: 0.0,
            best_round_trip_s: f64::INFINITY,
            first_window: None,
            window: None,
        }
    }

    /// Host time of sensor time `sensor_ms` (unwrapped), s.
    #[must_use]
    pub fn host_time(&self, sensor_ms: u64) -> f64 {
        let s = sensor_ms as f64 / 1000.0;
        self.offset_s + s + self.drift * (s - self.reference_s)
    }

    /// Host minus sensor time at the synchronisation, s.
    #[must_use]
    pub fn offset_s(&self) -> f64 {
        self.offset_s
    }

    /// The drift estimate, s per s (0 until the stream has spanned
    /// [`DRIFT_MIN_SPAN_S`]).
    #[must_use]
    pub fn drift(&self) -> f64 {
        self.drift
    }

    /// The shortest `TM1` round trip, s.
    #[must_use]
    pub fn round_trip_s(&self) -> f64 {
        self.best_round_trip_s
    }

    /// Takes a scan stamped `sensor_ms` (unwrapped) that arrived at `host_recv_s` into
    /// the drift estimate.
    pub fn observe(&mut self, sensor_ms: u64, host_recv_s: f64) {
        let s = sensor_ms as f64 / 1000.0;
        let delay = host_recv_s - s;
        if !delay.is_finite() {
            return;
        }
        match &mut self.window {
            Some((start, at, min)) if s - *start < DRIFT_WINDOW_S && s >= *start => {
                if delay < *min {
                    *at = s;
                    *min = delay;
                }
            }
            Some((_, at, min)) => {
                let done = (*at, *min);
                match self.first_window {
                    None => self.first_window = Some(done),
                    Some((s0, d0)) if done.0 - s0 >= DRIFT_MIN_SPAN_S => {
                        self.drift = (done.1 - d0) / (done.0 - s0);
                    }
                    Some(_) => {}
                }
                self.window = Some((s, s, delay));
            }
            None => self.window = Some((s, s, delay)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_clock_unwraps_at_2_to_the_24() {
        let mut u = ClockUnwrap::new();
        assert_eq!(u.unwrap(16_777_000), 16_777_000);
        assert_eq!(u.unwrap(16_777_215), 16_777_215);
        assert_eq!(u.unwrap(100), CLOCK_WRAP_MS + 100);
        assert_eq!(u.wraps(), 1);
        // A small step back is not a wrap.
        assert_eq!(u.unwrap(90), CLOCK_WRAP_MS + 90);
        // A late reading from before the wrap.
        assert_eq!(u.unwrap(16_777_210), 16_777_210);
        assert_eq!(u.unwrap(200), CLOCK_WRAP_MS + 200);
    }

    #[test]
    fn the_shortest_round_trip_gives_the_offset() {
        // Sensor clock = host - 1000 s; a fast exchange and a slow one.
        let samples = [
            TimeSample {
                host_send_s: 1010.0,
                host_recv_s: 1010.2,
                sensor_ms: 10_150,
            },
            TimeSample {
                host_send_s: 1020.0,
                host_recv_s: 1020.002,
                sensor_ms: 20_001,
            },
        ];
        let m = ClockModel::from_samples(&samples).unwrap();
        assert!((m.offset_s() - 1000.0).abs() < 1e-9);
        assert!((m.host_time(30_000) - 1030.0).abs() < 1e-9);
        assert!((m.round_trip_s() - 0.002).abs() < 1e-9);
        assert!(ClockModel::from_samples(&[]).is_none());
    }

    #[test]
    fn the_stream_reveals_the_drift() {
        // The host clock runs 100 ppm fast against the sensor's; scans every 25 ms arrive
        // 2 to 6 ms after their stamp.
        let sync = TimeSample {
            host_send_s: 500.0,
            host_recv_s: 500.0,
            sensor_ms: 0,
        };
        let mut m = ClockModel::from_samples(&[sync]).unwrap();
        for k in 0..2000u64 {
            let s = k as f64 * 0.025;
            let jitter = 0.002 + 0.004 * ((k * 7919) % 13) as f64 / 12.0;
            m.observe(k * 25, 500.0 + s * (1.0 + 1e-4) + jitter);
        }
        assert!((m.drift() - 1e-4).abs() < 1e-5, "drift {}", m.drift());
    }
}
