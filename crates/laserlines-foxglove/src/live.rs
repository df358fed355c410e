//! Live viewing: a Foxglove WebSocket server (the `foxglove` crate's) publishing scans, lines
//! and poses on the channels of [`crate::scene`] and further scenes on channels of their own
//! (the sectors of `laserlines live --sectors`), and a [`Pacer`] that replays a log at a
//! chosen speed.

use std::sync::Arc;
use std::time::{Duration, Instant};

use foxglove::messages::{FrameTransform, LaserScan, SceneUpdate};
use foxglove::{Channel, ChannelBuilder, Context, Encode, WebSocketServer, WebSocketServerHandle};
use laserlines::Line;
use laserlines_io::ScanRecord;

use crate::scene::{log_time_ns, scene_messages};
use crate::{LINES_TOPIC, SCAN_TOPIC, TF_TOPIC};

/// Why the live server could not start.
#[derive(Debug, thiserror::Error)]
pub enum LiveError {
    /// The server could not bind or start (e.g. the port is taken).
    #[error("cannot serve Foxglove WebSocket on {host}:{port}: {message}")]
    Start {
        /// The host asked for.
        host: String,
        /// The port asked for.
        port: u16,
        /// What went wrong.
        message: String,
    },
    /// A channel could not be created.
    #[error("cannot create channel {topic}: {message}")]
    Channel {
        /// The topic.
        topic: String,
        /// What went wrong.
        message: String,
    },
}

/// A Foxglove WebSocket server publishing `/scan`, `/lines` and `/tf`, and the scene topics
/// it was started with ([`LiveServer::start_with_scenes`]).
///
/// The server runs on its own threads (a tokio runtime the `foxglove` crate starts); stop it
/// with [`LiveServer::stop`].
pub struct LiveServer {
    // Keeps the channels' context alive as long as the server.
    _context: Arc<Context>,
    handle: WebSocketServerHandle,
    scan: Channel<LaserScan>,
    lines: Channel<SceneUpdate>,
    tf: Channel<FrameTransform>,
    scenes: Vec<(String, Channel<SceneUpdate>)>,
}

impl std::fmt::Debug for LiveServer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LiveServer")
            .field("port", &self.handle.port())
            .finish_non_exhaustive()
    }
}

fn channel<T: Encode>(ctx: &Arc<Context>, topic: &str) -> Result<Channel<T>, LiveError> {
    let raw = ChannelBuilder::new(topic)
        .context(ctx)
        .schema(T::get_schema())
        .message_encoding(T::get_message_encoding())
        .build_raw()
        .map_err(|e| LiveError::Channel {
            topic: topic.to_owned(),
            message: e.to_string(),
        })?;
    Ok(Channel::from_raw_channel(raw))
}

impl LiveServer {
    /// Starts a server on `host:port` (port 0 picks a free one; see [`LiveServer::port`]).
    ///
    /// # Errors
    /// [`LiveError`] when the server cannot start.
    pub fn start(host: &str, port: u16) -> Result<Self, LiveError> {
        Self::start_with_scenes(host, port, &[])
    }

    /// Starts a server as [`LiveServer::start`] does, with one more `foxglove.SceneUpdate`
    /// channel for each of `scene_topics` (e.g. [`crate::sectors::SECTORS_TOPIC`]), for
    /// [`LiveServer::publish_scene`].
    ///
    /// # Errors
    /// [`LiveError`] when the server cannot start, or [`LiveError::Channel`] for a topic
    /// given twice or one of the server's own (`/scan`, `/lines`, `/tf`).
    pub fn start_with_scenes(
        host: &str,
        port: u16,
        scene_topics: &[&str],
    ) -> Result<Self, LiveError> {
        let context = Context::new();
        let scan = channel::<LaserScan>(&context, SCAN_TOPIC)?;
        let lines = channel::<SceneUpdate>(&context, LINES_TOPIC)?;
        let tf = channel::<FrameTransform>(&context, TF_TOPIC)?;
        let mut scenes: Vec<(String, Channel<SceneUpdate>)> = Vec::new();
        for &topic in scene_topics {
            if [SCAN_TOPIC, LINES_TOPIC, TF_TOPIC].contains(&topic)
                || scenes.iter().any(|(t, _)| t == topic)
            {
                return Err(LiveError::Channel {
                    topic: topic.to_owned(),
                    message: "the topic is already a channel of the server".to_owned(),
                });
            }
            scenes.push((topic.to_owned(), channel::<SceneUpdate>(&context, topic)?));
        }
        let handle = WebSocketServer::new()
            .name("laserlines")
            .context(&context)
            .bind(host, port)
            .start_blocking()
            .map_err(|e| LiveError::Start {
                host: host.to_owned(),
                port,
                message: e.to_string(),
            })?;
        Ok(Self {
            _context: context,
            handle,
            scan,
            lines,
            tf,
            scenes,
        })
    }

    /// The port the server listens on.
    #[must_use]
    pub fn port(&self) -> u16 {
        self.handle.port()
    }

    /// True when a viewer is subscribed to `/scan`.
    #[must_use]
    pub fn has_viewer(&self) -> bool {
        self.scan.has_sinks()
    }

    /// Waits until a viewer subscribes to `/scan`, or `timeout` passes (`None`: forever).
    /// True when a viewer is there.
    pub fn wait_for_viewer(&self, timeout: Option<Duration>) -> bool {
        let start = Instant::now();
        loop {
            if self.has_viewer() {
                return true;
            }
            if timeout.is_some_and(|t| start.elapsed() >= t) {
                return false;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Publishes a scan with its lines and, when it has one, the robot's pose, all at `time`
    /// (s; from a [`crate::scene::SceneClock`], as the MCAP writer does).
    pub fn publish(&self, record: &ScanRecord, lines: &[Line], time: f64) {
        let m = scene_messages(record, Some(lines), time);
        let ns = log_time_ns(time);
        for t in &m.transforms {
            self.tf.log_with_time(t, ns);
        }
        self.scan.log_with_time(&m.scan, ns);
        if let Some(l) = &m.lines {
            self.lines.log_with_time(l, ns);
        }
    }

    /// Publishes a scene update on `topic`, one of the scene topics the server was started
    /// with, at `time` (s; the time of the scan it belongs to).
    ///
    /// # Errors
    /// [`LiveError::Channel`] when the server has no such scene channel.
    pub fn publish_scene(
        &self,
        topic: &str,
        update: &SceneUpdate,
        time: f64,
    ) -> Result<(), LiveError> {
        let (_, channel) = self
            .scenes
            .iter()
            .find(|(t, _)| t == topic)
            .ok_or_else(|| LiveError::Channel {
                topic: topic.to_owned(),
                message: "not a scene channel of this server".to_owned(),
            })?;
        channel.log_with_time(update, log_time_ns(time));
        Ok(())
    }

    /// Stops the server and waits for its tasks to end.
    pub fn stop(self) {
        self.handle.stop().wait_blocking();
    }
}

/// Paces a replay: tells how long to wait before each scan so that scan times (s) pass at
/// `rate` times real time. A time before the previous one (a backward step) is shown at once
/// and restarts the pacing from there; a step of more than [`Pacer::MAX_STEP_S`] (a gap) is
/// waited for as a step of that much, so that no scan waits longer than `MAX_STEP_S / rate`.
/// Both are counted.
#[derive(Debug, Clone)]
pub struct Pacer {
    rate: f64,
    base: Option<(Instant, f64)>,
    last: f64,
    gaps: u64,
    backward_steps: u64,
}

impl Pacer {
    /// The longest step between two scan times that is waited for in full, s; a longer one
    /// (a gap in the log) is waited for as this long, divided by the rate.
    pub const MAX_STEP_S: f64 = 1.0;

    /// A pacer at `rate` (1.0 = real time, 2.0 = twice as fast); `rate` must be positive and
    /// finite, anything else plays as fast as possible.
    #[must_use]
    pub fn new(rate: f64) -> Self {
        Self {
            rate,
            base: None,
            last: f64::NEG_INFINITY,
            gaps: 0,
            backward_steps: 0,
        }
    }

    /// How long to wait from `now` before showing a scan of time `t` (s).
    pub fn delay(&mut self, t: f64, now: Instant) -> Duration {
        if !t.is_finite() {
            return Duration::ZERO;
        }
        let step = t - self.last;
        let (wall, start) = match self.base {
            Some(_) if step < 0.0 => {
                self.backward_steps += 1;
                self.base = Some((now, t));
                (now, t)
            }
            Some((wall, start)) if step > Self::MAX_STEP_S => {
                // The gap counts as a step of MAX_STEP_S: the pacing moves on by the rest.
                self.gaps += 1;
                let moved = start + step - Self::MAX_STEP_S;
                // Stamps near the limits of f64 overflow the sum: the pacing starts afresh,
                // one capped step before this scan.
                let shifted = if moved.is_finite() {
                    (wall, moved)
                } else {
                    (now, t - Self::MAX_STEP_S)
                };
                self.base = Some(shifted);
                shifted
            }
            Some(b) => b,
            None => {
                self.base = Some((now, t));
                (now, t)
            }
        };
        self.last = t;
        if !(self.rate.is_finite() && self.rate > 0.0) {
            return Duration::ZERO;
        }
        let due = Duration::try_from_secs_f64((t - start) / self.rate).unwrap_or(Duration::MAX);
        wall.checked_add(due)
            .map_or(Duration::MAX, |at| at.saturating_duration_since(now))
    }

    /// Steps of more than [`Pacer::MAX_STEP_S`] between two scan times so far.
    #[must_use]
    pub fn gaps(&self) -> u64 {
        self.gaps
    }

    /// Scan times before the previous one so far.
    #[must_use]
    pub fn backward_steps(&self) -> u64 {
        self.backward_steps
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pacer_follows_scan_times_at_the_rate() {
        let t0 = Instant::now();
        let mut p = Pacer::new(2.0);
        assert_eq!(p.delay(10.0, t0), Duration::ZERO);
        assert_eq!(p.delay(11.0, t0), Duration::from_millis(500));
        assert_eq!(
            p.delay(12.0, t0 + Duration::from_millis(600)),
            Duration::from_millis(400)
        );
        // Late: no wait.
        assert_eq!(p.delay(12.5, t0 + Duration::from_secs(5)), Duration::ZERO);
        // Time going backwards restarts the pacing.
        assert_eq!(p.delay(3.0, t0 + Duration::from_secs(6)), Duration::ZERO);
        assert_eq!((p.gaps(), p.backward_steps()), (0, 1));
        assert_eq!(Pacer::new(0.0).delay(100.0, t0), Duration::ZERO);
        assert_eq!(Pacer::new(f64::NAN).delay(100.0, t0), Duration::ZERO);
    }

    #[test]
    fn a_gap_in_the_scan_times_waits_one_step_of_at_most_a_second_over_the_rate() {
        let t0 = Instant::now();
        for rate in [1.0, 4.0] {
            let mut p = Pacer::new(rate);
            assert_eq!(p.delay(10.0, t0), Duration::ZERO);
            // 2^32 s later: one capped step, then the pacing goes on from there.
            let cap = Duration::from_secs_f64(Pacer::MAX_STEP_S / rate);
            let wait = p.delay(10.0 + 4.3e9, t0);
            assert!(wait.abs_diff(cap) < Duration::from_millis(1), "{wait:?}");
            let after = Duration::from_secs_f64((Pacer::MAX_STEP_S + 0.5) / rate);
            let wait = p.delay(10.5 + 4.3e9, t0);
            assert!(wait.abs_diff(after) < Duration::from_millis(1), "{wait:?}");
            // Backwards: no wait.
            assert_eq!(p.delay(5.0, t0 + cap), Duration::ZERO);
            assert_eq!((p.gaps(), p.backward_steps()), (1, 1), "rate {rate}");
        }
        // Stamps at the limits of f64: the wait stays one capped step.
        let mut p = Pacer::new(2.0);
        assert_eq!(p.delay(-1e308, t0), Duration::ZERO);
        let wait = p.delay(1e308, t0);
        assert!(
            wait <= Duration::from_secs_f64(Pacer::MAX_STEP_S / 2.0),
            "{wait:?}"
        );
        // Counted as fast as possible too.
        let mut p = Pacer::new(0.0);
        for t in [1.0, 0.5, 100.0] {
            assert_eq!(p.delay(t, t0), Duration::ZERO);
        }
        assert_eq!((p.gaps(), p.backward_steps()), (1, 1));
    }
}
