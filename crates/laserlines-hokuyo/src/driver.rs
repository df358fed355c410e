//! One session with a sensor: connection, the start-up urg_node also performs (`QT`, the
//! switch from SCIP 1.1, `VV`, `PP`, `II`, `TM` synchronisation, `BM`), streaming with
//! `MD`/`MS`, single scans with `GD`/`GS`, `RS`/`RT` and `QT`.
//!
//! A [`Session`] does not reconnect and does not count lost scans: [`crate::Scanner`]
//! does, on top of it.

use std::io;
use std::time::{Duration, Instant};

use laserlines::{Scan, ScanError};

use crate::clock::{ClockModel, ClockUnwrap, HostClock, TimeSample};
use crate::codec;
use crate::info::{InfoError, NoReturn, SensorInfo};
use crate::reply::{Reply, ReplyError, Status};
use crate::request::ScanRequest;
use crate::status::StatusError;
use crate::transport::{Connection, Endpoint, Link, PROBE_BAUDS, connect_tcp, open_serial};

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

/// What went wrong talking to a sensor.
#[derive(Debug, thiserror::Error)]
pub enum DriverError {
    /// The transport failed (cannot open the device, connection refused, ...).
    #[error("{endpoint}: {source}")]
    Io {
        /// The endpoint.
        endpoint: String,
        /// The I/O error.
        source: io::Error,
    },
    /// The sensor closed the connection.
    #[error("{endpoint}: the connection was closed")]
    Closed {
        /// The endpoint.
        endpoint: String,
    },
    /// No reply in time.
    #[error("{endpoint}: no reply to {command} within {waited:?}")]
    Timeout {
        /// The endpoint.
        endpoint: String,
        /// The command waited for.
        command: String,
        /// How long.
        waited: Duration,
    },
    /// The sensor answered with an error status.
    #[error("{endpoint}: {source}")]
    Status {
        /// The endpoint.
        endpoint: String,
        /// The status and its meaning.
        source: StatusError,
    },
    /// A reply that does not parse.
    #[error("{endpoint}: reply to {command}: {source}")]
    Reply {
        /// The endpoint.
        endpoint: String,
        /// The command.
        command: String,
        /// What is wrong with it.
        source: ReplyError,
    },
    /// The sensor's parameters do not describe a scan.
    #[error("{endpoint}: {source}")]
    Info {
        /// The endpoint.
        endpoint: String,
        /// What is missing or wrong.
        source: InfoError,
    },
    /// No SCIP 2.0 answer, even after trying to switch from SCIP 1.1.
    #[error("{endpoint}: no SCIP 2.0 reply to QT, also after the SCIP2.0 switch ({detail})")]
    NotScip2 {
        /// The endpoint.
        endpoint: String,
        /// What was tried.
        detail: String,
    },
    /// The scan geometry from the sensor's parameters is not a valid scan.
    #[error("{endpoint}: {source}")]
    Scan {
        /// The endpoint.
        endpoint: String,
        /// The validation error.
        source: ScanError,
    },
}

impl DriverError {
    /// True when the error means the link is gone or silent (reconnecting may help),
    /// rather than the sensor refusing something.
    #[must_use]
    pub fn is_link_failure(&self) -> bool {
        matches!(
            self,
            Self::Io { .. } | Self::Closed { .. } | Self::Timeout { .. } | Self::NotScip2 { .. }
        )
    }
}

/// Why a scan was dropped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DropReason {
    /// A line's check character did not match (or a character outside the encoding).
    Checksum,
    /// The scan was cut short: a short data line, too few characters, or the connection
    /// ended in the middle of it.
    Truncated,
    /// The scan came with an error status (e.g. `0M` unstable, hardware trouble).
    Status,
    /// Missing from the time stamps' sequence without a reply at all (lost on the way or
    /// not sent).
    Gap,
    /// Made by the sensor while the link was down or being re-established.
    Disconnected,
    /// A scan with a time stamp already delivered.
    Duplicate,
}

impl DropReason {
    /// All reasons, in report order.
    pub const ALL: [Self; 6] = [
        Self::Checksum,
        Self::Truncated,
        Self::Status,
        Self::Gap,
        Self::Disconnected,
        Self::Duplicate,
    ];

    /// A short name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Checksum => "checksum",
            Self::Truncated => "truncated",
            Self::Status => "status",
            Self::Gap => "gap",
            Self::Disconnected => "disconnected",
            Self::Duplicate => "duplicate",
        }
    }
}

/// One scan from the sensor.
#[derive(Debug, Clone, PartialEq)]
pub struct HokuyoScan {
    /// The scan: ranges in metres, `range_min`/`range_max` from `DMIN`/`DMAX` (so the error
    /// codes below `DMIN` are not valid ranges), stamp in host time (s since the epoch).
    pub scan: Scan,
    /// The readings as sent, mm (error codes included).
    pub raw_mm: Vec<u32>,
    /// The sensor's time stamp as sent, ms (24 bits).
    pub sensor_raw_ms: u32,
    /// The sensor's time stamp unwrapped, ms.
    pub sensor_ms: u64,
    /// When the scan's last byte was read.
    pub received: Instant,
    /// Remaining scans of a finite `MD`/`MS` request, as the echo said (0 for unlimited).
    pub remaining: u32,
}

impl HokuyoScan {
    /// The beams that are no return, with the reason the sensor gave.
    pub fn no_returns(
        &self,
        dmin_mm: u32,
        dmax_mm: u32,
    ) -> impl Iterator<Item = (usize, NoReturn)> + '_ {
        self.raw_mm
            .iter()
            .enumerate()
            .filter_map(move |(i, &mm)| NoReturn::classify(mm, dmin_mm, dmax_mm).map(|r| (i, r)))
    }
}

/// What [`Session::read_scan`] read.
#[derive(Debug)]
pub enum ScanEvent {
    /// A whole scan.
    Scan(Box<HokuyoScan>),
    /// A scan reply that was dropped, with the reason and what was wrong.
    Dropped(DropReason, String),
    /// Another message (the acknowledgement of `MD`, a late reply), ignored.
    Other,
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

fn io_error(endpoint: &Endpoint, e: io::Error) -> DriverError {
    if e.kind() == io::ErrorKind::UnexpectedEof {
        DriverError::Closed {
            endpoint: endpoint.to_string(),
        }
    } else {
        DriverError::Io {
            endpoint: endpoint.to_string(),
            source: e,
        }
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

    /// `TM0`, `samples` times `TM1`, `TM2`: the sensor clock's offset from the exchange
    /// with the shortest round trip (see [`ClockModel`]).
    ///
    /// # Errors
    /// A [`DriverError`] of the command that failed.
    pub fn sync_time(&mut self, samples: usize) -> Result<ClockModel, DriverError> {
        self.stream = None;
        self.command_ok("TM0", &["00", "02"])?;
        let mut list = Vec::with_capacity(samples);
        for _ in 0..samples.max(1) {
            let host_send_s = self.host.now();
            self.conn
                .send("TM1")
                .map_err(|e| io_error(&self.endpoint, e))?;
            let (m, at) = wait_echo(
                &mut self.conn,
                &self.endpoint,
                "TM1",
                self.options.reply_timeout,
                &mut self.discarded,
            )?;
            let host_recv_s = self.host.at(at);
            let r = Reply::parse(&m).map_err(|source| self.reply_error("TM1", source))?;
            if !r.status.is_ok() {
                return Err(DriverError::Status {
                    endpoint: self.endpoint.to_string(),
                    source: StatusError::new("TM1", &r.status.as_string()),
                });
            }
            let line = r.data_line(0).unwrap_or_default();
            if line.len() != 4 {
                return Err(self.reply_error("TM1", ReplyError::BadTimestamp { found: line.len() }));
            }
            let raw = codec::decode(line).map_err(|source| {
                self.reply_error(
                    "TM1",
                    ReplyError::BadCharacter {
                        line: 3,
                        offset: 0,
                        source,
                    },
                )
            })?;
            list.push(TimeSample {
                host_send_s,
                host_recv_s,
                sensor_ms: self.unwrap.unwrap(raw),
            });
        }
        self.command_ok("TM2", &["00", "03"])?;
        let model = ClockModel::from_samples(&list).ok_or_else(|| DriverError::Timeout {
            endpoint: self.endpoint.to_string(),
            command: "TM1".to_owned(),
            waited: self.options.reply_timeout,
        })?;
        tracing::debug!(
            offset_s = model.offset_s(),
            round_trip_s = model.round_trip_s(),
            "time synchronised"
        );
        self.clock = Some(model.clone());
        Ok(model)
    }

    /// `BM`: switches the laser on (already on is fine).
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

    fn geometry_check(&self, request: &ScanRequest) -> Result<(f64, f64), DriverError> {
        let g = self.info.geometry(request);
        // Validate once here, so that every scan built later is valid.
        Scan::new(
            g.angle_min,
            g.angle_increment,
            self.info.range_min_m(),
            self.info.range_max_m(),
            vec![0.0; g.beams],
        )
        .map_err(|source| DriverError::Scan {
            endpoint: self.endpoint.to_string(),
            source,
        })?;
        Ok((g.angle_min, g.angle_increment))
    }

    /// Starts `MD`/`MS` streaming of `scans` scans (0: until [`Session::stop`]).
    ///
    /// # Errors
    /// [`DriverError::Status`] when the sensor refuses the request.
    pub fn start_stream(&mut self, request: ScanRequest, scans: u32) -> Result<(), DriverError> {
        let (angle_min, angle_increment) = self.geometry_check(&request)?;
        let command = request.stream_command(scans);
        self.command_ok(&command, &["00"])?;
        self.stream = Some(Stream {
            request,
            prefix: command[..command.len() - 2].to_owned(),
            angle_min,
            angle_increment,
        });
        Ok(())
    }

    /// The request being streamed.
    #[must_use]
    pub fn streaming(&self) -> Option<&ScanRequest> {
        self.stream.as_ref().map(|s| &s.request)
    }

    /// The next message of the stream, waiting until `deadline` (`Ok(None)` then).
    ///
    /// # Errors
    /// [`DriverError::Closed`] or [`DriverError::Io`] when the link fails.
    pub fn read_scan(&mut self, deadline: Instant) -> Result<Option<ScanEvent>, DriverError> {
        let Some((m, at)) = self
            .conn
            .read_message(deadline)
            .map_err(|e| io_error(&self.endpoint, e))?
        else {
            return Ok(None);
        };
        let Some(stream) = &self.stream else {
            self.discarded += 1;
            return Ok(Some(ScanEvent::Other));
        };
        let (prefix, request) = (stream.prefix.clone(), stream.request);
        Ok(Some(self.decode(&m, at, &prefix, &request, true)))
    }

    /// One `GD`/`GS` scan (the laser must be on: [`Session::open`] switches it on).
    ///
    /// # Errors
    /// [`DriverError::Status`] when refused, [`DriverError::Reply`] when the reply is
    /// damaged.
    pub fn single_scan(&mut self, request: ScanRequest) -> Result<HokuyoScan, DriverError> {
        self.stream = None;
        self.geometry_check(&request)?;
        let command = request.single_command();
        let (m, at) = self.command(&command)?;
        match self.decode(&m, at, &command, &request, false) {
            ScanEvent::Scan(s) => Ok(*s),
            ScanEvent::Dropped(DropReason::Status, _) => {
                let status = Reply::parse_unchecked(&m)
                    .map(|r| r.status.as_string())
                    .unwrap_or_default();
                Err(DriverError::Status {
                    endpoint: self.endpoint.to_string(),
                    source: StatusError::new(&command, &status),
                })
            }
            ScanEvent::Dropped(_, why) => Err(self.reply_error(
                &command,
                ReplyError::BadStatusLine {
                    offset: 0,
                    text: why,
                },
            )),
            ScanEvent::Other => Err(DriverError::Timeout {
                endpoint: self.endpoint.to_string(),
                command,
                waited: self.options.reply_timeout,
            }),
        }
    }

    /// Decodes one scan reply (`streaming`: `MD`/`MS` with status `99`, else `GD`/`GS`
    /// with status `00`).
    fn decode(
        &mut self,
        m: &[u8],
        at: Instant,
        prefix: &str,
        request: &ScanRequest,
        streaming: bool,
    ) -> ScanEvent {
        let reply = match Reply::parse_unchecked(m) {
            Ok(r) => r,
            Err(e @ ReplyError::Checksum { .. }) => {
                return ScanEvent::Dropped(DropReason::Checksum, e.to_string());
            }
            Err(e) => return ScanEvent::Dropped(DropReason::Truncated, e.to_string()),
        };
        if !reply.echo.starts_with(prefix.as_bytes()) {
            self.discarded += 1;
            return ScanEvent::Other;
        }
        let data_status: [u8; 2] = if streaming { *b"99" } else { *b"00" };
        match reply.status {
            Status::Scip2(s) if s == data_status => {}
            Status::Scip2(s) if streaming && &s == b"00" => return ScanEvent::Other,
            other => {
                let e = StatusError::new(prefix, &other.as_string());
                return ScanEvent::Dropped(DropReason::Status, e.to_string());
            }
        }
        let values = request.values();
        if let Err(e) = reply.check_scan_layout(request.encoding, values) {
            return ScanEvent::Dropped(DropReason::Truncated, e.to_string());
        }
        if let Err(e) = reply.verify_data() {
            return ScanEvent::Dropped(DropReason::Checksum, e.to_string());
        }
        let raw = match reply.scan_into(request.encoding, values, &mut self.values) {
            Ok(t) => t,
            Err(e) => return ScanEvent::Dropped(DropReason::Checksum, e.to_string()),
        };
        let remaining = if streaming {
            std::str::from_utf8(&reply.echo[prefix.len().min(reply.echo.len())..])
                .ok()
                .and_then(|s| s.get(..2))
                .and_then(|s| s.parse().ok())
                .unwrap_or(0)
        } else {
            0
        };
        let sensor_ms = self.unwrap.unwrap(raw);
        let host_recv = self.host.at(at);
        let clock = self.clock.get_or_insert_with(|| {
            // No TM: the first arrival stands for the sensor's offset.
            ClockModel::from_samples(&[TimeSample {
                host_send_s: host_recv,
                host_recv_s: host_recv,
                sensor_ms,
            }])
            .unwrap_or_else(|| ClockModel::from_offset(0.0, sensor_ms))
        });
        clock.observe(sensor_ms, host_recv);
        let stamp = clock.host_time(sensor_ms).min(host_recv);
        let (angle_min, angle_increment) = match &self.stream {
            Some(s) if streaming => (s.angle_min, s.angle_increment),
            _ => {
                let g = self.info.geometry(request);
                (g.angle_min, g.angle_increment)
            }
        };
        let scan = Scan {
            angle_min,
            angle_increment,
            range_min: self.info.range_min_m(),
            range_max: self.info.range_max_m(),
            ranges: self
                .values
                .iter()
                .map(|&mm| f64::from(mm) / 1000.0)
                .collect(),
            intensities: None,
            stamp: Some(stamp),
        };
        ScanEvent::Scan(Box::new(HokuyoScan {
            scan,
            raw_mm: self.values.clone(),
            sensor_raw_ms: raw,
            sensor_ms,
            received: at,
            remaining,
        }))
    }

    /// Sends `QT` without waiting for the reply (for shutting down on a signal).
    pub fn send_quit(&mut self) {
        let _ = self.conn.send("QT");
    }
}

fn wait_echo(
    conn: &mut Connection,
    endpoint: &Endpoint,
    command: &str,
    timeout: Duration,
    discarded: &mut u64,
) -> Result<(Vec<u8>, Instant), DriverError> {
    let deadline = Instant::now() + timeout;
    loop {
        match conn
            .read_message(deadline)
            .map_err(|e| io_error(endpoint, e))?
        {
            Some((m, at)) => {
                let echo_end = m.iter().position(|&b| b == b'\n').unwrap_or(m.len());
                if &m[..echo_end] == command.as_bytes() {
                    return Ok((m, at));
                }
                *discarded += 1;
            }
            None => {
                return Err(DriverError::Timeout {
                    endpoint: endpoint.to_string(),
                    command: command.to_owned(),
                    waited: timeout,
                });
            }
        }
    }
}

/// The first contact: `QT` in SCIP 2.0, or the switch from SCIP 1.1. True when switched.
fn handshake(
    conn: &mut Connection,
    endpoint: &Endpoint,
    timeout: Duration,
) -> Result<bool, DriverError> {
    let mut discarded = 0;
    conn.send("QT").map_err(|e| io_error(endpoint, e))?;
    // A sensor still streaming from an earlier session sends scans before the QT reply.
    let first = match wait_echo(conn, endpoint, "QT", timeout, &mut discarded) {
        Ok((m, _)) => Reply::parse_unchecked(&m).ok().map(|r| r.status),
        Err(DriverError::Timeout { .. }) => None,
        Err(e) => return Err(e),
    };
    if first == Some(Status::Scip2(*b"00")) {
        return Ok(false);
    }
    // SCIP 1.1 answers QT with one status character ("E"), or not at all.
    conn.drain(Duration::from_millis(50), timeout)
        .map_err(|e| io_error(endpoint, e))?;
    conn.send("SCIP2.0").map_err(|e| io_error(endpoint, e))?;
    let switch = wait_echo(conn, endpoint, "SCIP2.0", timeout, &mut discarded);
    match switch {
        Ok(_) | Err(DriverError::Timeout { .. }) => {}
        Err(e) => return Err(e),
    }
    conn.send("QT").map_err(|e| io_error(endpoint, e))?;
    match wait_echo(conn, endpoint, "QT", timeout, &mut discarded) {
        Ok((m, _)) if Reply::parse_unchecked(&m).is_ok_and(|r| r.status.is_ok()) => Ok(true),
        Ok((m, _)) => Err(DriverError::NotScip2 {
            endpoint: endpoint.to_string(),
            detail: format!("QT answered {:?}", String::from_utf8_lossy(&m)),
        }),
        Err(DriverError::Timeout { .. }) => Err(DriverError::NotScip2 {
            endpoint: endpoint.to_string(),
            detail: format!("no reply within {timeout:?}"),
        }),
        Err(e) => Err(e),
    }
}

fn connect(
    endpoint: &Endpoint,
    options: &DriverOptions,
) -> Result<(Connection, Endpoint, bool), DriverError> {
    match endpoint {
        Endpoint::Tcp { host, port } => {
            let stream = connect_tcp(host, *port, options.connect_timeout)
                .map_err(|e| io_error(endpoint, e))?;
            let mut conn = Connection::new(Box::new(stream) as Box<dyn Link>);
            let switched = handshake(&mut conn, endpoint, options.reply_timeout)?;
            Ok((conn, endpoint.clone(), switched))
        }
        Endpoint::Serial { path, baud } => {
            let bauds: Vec<u32> = match baud {
                Some(b) => vec![*b],
                None => PROBE_BAUDS.to_vec(),
            };
            let mut last = None;
            for b in bauds {
                let at = Endpoint::Serial {
                    path: path.clone(),
                    baud: Some(b),
                };
                let link = open_serial(path, b).map_err(|e| io_error(&at, e))?;
                let mut conn = Connection::new(Box::new(link));
                match handshake(&mut conn, &at, options.probe_timeout) {
                    Ok(switched) => return Ok((conn, at, switched)),
                    Err(e) if e.is_link_failure() => {
                        tracing::debug!(baud = b, error = %e, "no SCIP 2.0 answer at this bit rate");
                        last = Some(e);
                    }
                    Err(e) => return Err(e),
                }
            }
            Err(last.unwrap_or_else(|| DriverError::NotScip2 {
                endpoint: endpoint.to_string(),
                detail: "no bit rate to try".to_owned(),
            }))
        }
    }
}
