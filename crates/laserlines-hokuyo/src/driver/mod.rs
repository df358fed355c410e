//! One session with a sensor: connection, the start-up urg_node also performs (`QT`, the
//! switch from SCIP 1.1, `VV`, `PP`, `II`, `TM` synchronisation, `BM`), streaming with
//! `MD`/`MS`, single scans with `GD`/`GS`, `RS`/`RT` and `QT`.
//!
//! A [`Session`] does not reconnect and does not count lost scans: [`crate::Scanner`]
//! does, on top of it.
//!
//! - this module: the [`Session`], its options and its commands;
//! - `connect`: the first contact (bit rate probe, `QT`, the switch from SCIP 1.1) and
//!   waiting for a command's echo;
//! - `sync`: `TM` time synchronisation;
//! - `scans`: streaming, single scans and the decoding of a scan reply;
//! - `event`: what a scan read gives ([`ScanEvent`], [`HokuyoScan`], [`DropReason`]);
//! - `error`: [`DriverError`].

mod connect;
mod error;
mod event;
mod scans;
mod sync;

use std::time::{Duration, Instant};

use crate::clock::{ClockModel, ClockUnwrap, HostClock};
use crate::info::SensorInfo;
use crate::reply::{Reply, ReplyError};
use crate::request::ScanRequest;
use crate::status::StatusError;
use crate::transport::{Connection, Endpoint};

use connect::{connect, wait_echo};
pub use error::DriverError;
use error::io_error;
pub use event::{DropReason, HokuyoScan, ScanEvent};

/// Settings of a session.
#[derive(Debug, Clone, PartialEq)]
pub struct DriverOptions {
    /// How long to wait for the reply to a command. Default 2 s.
    pub reply_timeout: Duration,
    /// How long to wait for a TCP connection. Default 2 s.
    pub connect_timeout: Duration,
    /// `TM1` exchanges of the time synchronisation (the shortest round trip counts).
    /// Default 10; 0 skips `TM` (stamps then use the host's arrival time of the first
    /// scan as the sensor's offset).
    pub time_samples: usize,
    /// How long the probe of one serial bit rate waits for a reply. Default 0.5 s.
    pub probe_timeout: Duration,
}

impl Default for DriverOptions {
    fn default() -> Self {
        Self {
            reply_timeout: Duration::from_secs(2),
            connect_timeout: Duration::from_secs(2),
            time_samples: 10,
            probe_timeout: Duration::from_millis(500),
        }
    }
}

struct Stream {
    request: ScanRequest,
    /// The echo of a scan reply starts with this (the command less its scan count).
    prefix: String,
    angle_min: f64,
    angle_increment: f64,
}

/// A session with one sensor.
pub struct Session {
    conn: Connection,
    endpoint: Endpoint,
    options: DriverOptions,
    info: SensorInfo,
    host: HostClock,
    clock: Option<ClockModel>,
    unwrap: ClockUnwrap,
    switched_from_scip11: bool,
    stream: Option<Stream>,
    values: Vec<u32>,
    discarded: u64,
}

impl std::fmt::Debug for Session {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Session")
            .field("endpoint", &self.endpoint)
            .field("model", &self.info.model)
            .finish_non_exhaustive()
    }
}

impl Session {
    /// Connects to `endpoint` and runs the start-up: `QT` (switching from SCIP 1.1 with
    /// `SCIP2.0` when the sensor does not answer in SCIP 2.0), `VV`, `PP`, `II`, `TM`
    /// synchronisation and `BM`. A serial device without a fixed bit rate is probed at
    /// [`PROBE_BAUDS`].
    ///
    /// # Errors
    /// [`DriverError`] naming the endpoint and the step that failed.
    pub fn open(
        endpoint: &Endpoint,
        options: &DriverOptions,
        host: HostClock,
    ) -> Result<Self, DriverError> {
        let (conn, endpoint, switched) = connect(endpoint, options)?;
        let mut s = Self {
            conn,
            endpoint,
            options: options.clone(),
            info: SensorInfo::default(),
            host,
            clock: None,
            unwrap: ClockUnwrap::new(),
            switched_from_scip11: switched,
            stream: None,
            values: Vec::new(),
            discarded: 0,
        };
        s.info = s.read_info()?;
        if s.options.time_samples > 0 {
            s.clock = Some(s.sync_time(s.options.time_samples)?);
        }
        s.laser_on()?;
        Ok(s)
    }

    /// The endpoint (with the bit rate found, for serial devices).
    #[must_use]
    pub fn endpoint(&self) -> &Endpoint {
        &self.endpoint
    }

    /// The sensor's description.
    #[must_use]
    pub fn info(&self) -> &SensorInfo {
        &self.info
    }

    /// The clock model of the last synchronisation.
    #[must_use]
    pub fn clock(&self) -> Option<&ClockModel> {
        self.clock.as_ref()
    }

    /// True when the sensor answered in SCIP 1.1 and was switched to SCIP 2.0.
    #[must_use]
    pub fn switched_from_scip11(&self) -> bool {
        self.switched_from_scip11
    }

    /// Messages read and ignored while waiting for replies.
    #[must_use]
    pub fn discarded(&self) -> u64 {
        self.discarded
    }

    /// Bytes of an unfinished message buffered (a scan cut off by a disconnect).
    #[must_use]
    pub fn pending_bytes(&self) -> usize {
        self.conn.pending()
    }

    /// Sends `command` and returns the message that echoes it, waiting at most the reply
    /// timeout; other messages read meanwhile are dropped.
    ///
    /// # Errors
    /// [`DriverError::Timeout`], [`DriverError::Closed`] or [`DriverError::Io`].
    pub fn command(&mut self, command: &str) -> Result<(Vec<u8>, Instant), DriverError> {
        self.conn
            .send(command)
            .map_err(|e| io_error(&self.endpoint, e))?;
        wait_echo(
            &mut self.conn,
            &self.endpoint,
            command,
            self.options.reply_timeout,
            &mut self.discarded,
        )
    }

    /// Sends `command` and checks that its status is one of `ok`.
    fn command_ok(&mut self, command: &str, ok: &[&str]) -> Result<Vec<u8>, DriverError> {
        let (m, _) = self.command(command)?;
        let status = {
            let r =
                Reply::parse_unchecked(&m).map_err(|source| self.reply_error(command, source))?;
            r.status.as_string()
        };
        if !ok.contains(&status.as_str()) {
            return Err(DriverError::Status {
                endpoint: self.endpoint.to_string(),
                source: StatusError::new(command, &status),
            });
        }
        Ok(m)
    }

    fn reply_error(&self, command: &str, source: ReplyError) -> DriverError {
        DriverError::Reply {
            endpoint: self.endpoint.to_string(),
            command: command.to_owned(),
            source,
        }
    }

    fn info_pairs(&mut self, command: &str) -> Result<Vec<(String, String)>, DriverError> {
        let m = self.command_ok(command, &["00"])?;
        let r = Reply::parse_unchecked(&m).map_err(|source| self.reply_error(command, source))?;
        r.info().map_err(|source| self.reply_error(command, source))
    }

    /// Reads `VV`, `PP` and `II` into the sensor's description.
    ///
    /// # Errors
    /// A [`DriverError`] of the first command that failed.
    pub fn read_info(&mut self) -> Result<SensorInfo, DriverError> {
        let vv = self.info_pairs("VV")?;
        let pp = self.info_pairs("PP")?;
        let ii = self.info_pairs("II")?;
        SensorInfo::from_pairs(&vv, &pp, &ii).map_err(|source| DriverError::Info {
            endpoint: self.endpoint.to_string(),
            source,
        })
    }
    ///
    /// # Errors
    /// [`DriverError::Status`] when the laser cannot be switched on.
    pub fn laser_on(&mut self) -> Result<(), DriverError> {
        self.command_ok("BM", &["00", "02"]).map(|_| ())
    }

    /// `QT`: stops streaming and switches the laser off.
    ///
    /// # Errors
    /// A [`DriverError`] when the sensor does not confirm.
    pub fn stop(&mut self) -> Result<(), DriverError> {
        self.stream = None;
        self.command_ok("QT", &["00"]).map(|_| ())
    }

    /// `RS` (all settings) or, with `partial`, `RT` (the laser, the timer and the
    /// sensitivity, not the motor speed and bit rate): the sensor stops, its clock restarts
    /// at 0, so time is synchronised again and the laser switched on again.
    ///
    /// # Errors
    /// A [`DriverError`] of the commands that follow.
    pub fn reset(&mut self, partial: bool) -> Result<(), DriverError> {
        self.stream = None;
        self.command_ok(if partial { "RT" } else { "RS" }, &["00"])?;
        self.unwrap = ClockUnwrap::new();
        if self.options.time_samples > 0 {
            self.clock = Some(self.sync_time(self.options.time_samples)?);
        }
        self.laser_on()
    }

    /// Sends `QT` without waiting for the reply (for shutting down on a signal).
    pub fn send_quit(&mut self) {
        let _ = self.conn.send("QT");
    }
}
