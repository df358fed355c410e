//! The emulated sensor's protocol state: commands in, replies and scans out, faults
//! applied. Transport-free: [`super::Emulator`] moves the bytes.

use std::time::{Duration, Instant};

use super::encode::{corrupt_check, cut_line, data_reply, info_reply, scan_message, simple_reply};
use super::server::{Served, ServedFault, ServedLog};
use super::{Model, ScanFeed};
use crate::clock::CLOCK_WRAP_MS;
use crate::codec::{Encoding, encode_into};
use crate::request::ScanRequest;

/// Faults to inject. The default injects none.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Faults {
    /// Every so many scans sent, one gets a wrong check character (0: never).
    pub bad_checksum_every: u64,
    /// Every so many scans sent, one has a data line cut short (0: never).
    pub truncate_every: u64,
    /// After so many scans on a connection, the next is sent half and the connection
    /// dropped (0: never).
    pub drop_after: u64,
    /// How long the emulator stays unreachable after dropping a connection (TCP: it stops
    /// listening).
    pub down_for: Duration,
    /// Start in SCIP 1.1: answer nothing but `SCIP2.0` until switched (as URG-04LX units
    /// shipped with SCIP 1.1 as default do).
    pub start_in_scip11: bool,
    /// Wait this long before answering each command.
    pub reply_delay: Duration,
    /// After so many scans on a connection, fall silent (0: never) ...
    pub stall_after: u64,
    /// ... for this long.
    pub stall_for: Duration,
    /// The sensor clock at start, ms (e.g. 2^24 - 2000 to see it wrap after 2 s).
    pub clock_start_ms: u32,
}

/// What the server should do after a step of the sensor.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Action {
    /// Send these bytes.
    Send(Vec<u8>),
    /// Send these bytes, then drop the connection.
    SendAndDrop(Vec<u8>),
}

struct Stream {
    echo_head: Vec<u8>,
    tag: Vec<u8>,
    request: ScanRequest,
    remaining: Option<u32>,
    next_due: Instant,
    next_stamp_ms: u64,
    every_ms: u64,
}

/// The emulated sensor.
pub struct Sensor {
    model: Model,
    feed: Box<dyn ScanFeed>,
    faults: Faults,
    scip2: bool,
    laser: bool,
    adjust: bool,
    clock_base: Instant,
    clock_at_base_ms: u64,
    stream: Option<Stream>,
    connection: u64,
    scans_this_connection: u64,
    scans_sent: u64,
    stall_until: Option<Instant>,
    stalled_this_connection: bool,
    log: ServedLog,
}

impl std::fmt::Debug for Sensor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Sensor")
            .field("model", &self.model.name)
            .field("scip2", &self.scip2)
            .field("laser", &self.laser)
            .finish_non_exhaustive()
    }
}

/// A parse failure of a command's parameters: the status to answer.
type Refusal = &'static [u8; 2];

fn digits(p: &[u8], range: std::ops::Range<usize>, status: Refusal) -> Result<u32, Refusal> {
    let s = p.get(range).ok_or(b"0C")?;
    if s.is_empty() || !s.iter().all(u8::is_ascii_digit) {
        return Err(status);
    }
    std::str::from_utf8(s)
        .ok()
        .and_then(|s| s.parse().ok())
        .ok_or(status)
}

impl Sensor {
    /// A sensor of `model` fed by `feed`, with `faults`, logging what it sends to `log`.
    #[must_use]
    pub fn new(model: Model, feed: Box<dyn ScanFeed>, faults: Faults, log: ServedLog) -> Self {
        Self {
            scip2: !faults.start_in_scip11,
            clock_at_base_ms: u64::from(faults.clock_start_ms) % CLOCK_WRAP_MS,
            model,
            feed,
            faults,
            laser: false,
            adjust: false,
            clock_base: Instant::now(),
            stream: None,
            connection: 0,
            scans_this_connection: 0,
            scans_sent: 0,
            stall_until: None,
            stalled_this_connection: false,
            log,
        }
    }

    /// The model.
    #[must_use]
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The faults.
    #[must_use]
    pub fn faults(&self) -> &Faults {
        &self.faults
    }

    /// A new host connected: streaming stops and the laser goes off (the clock runs on;
    /// the protocol version stays as it was).
    pub fn new_connection(&mut self) {
        self.connection += 1;
        self.stream = None;
        self.laser = false;
        self.adjust = false;
        self.scans_this_connection = 0;
        self.stalled_this_connection = false;
        self.stall_until = None;
    }

    /// The sensor clock now, ms (unwrapped; sent modulo 2^24).
    fn clock_ms(&self, now: Instant) -> u64 {
        self.clock_at_base_ms + now.saturating_duration_since(self.clock_base).as_millis() as u64
    }

    /// When the next scan is due, if streaming.
    #[must_use]
    pub fn next_due(&self) -> Option<Instant> {
        let due = self.stream.as_ref().map(|s| s.next_due)?;
        Some(self.stall_until.map_or(due, |u| u.max(due)))
    }

    /// Answers one command line (without its line ending).
    pub fn handle(&mut self, line: &[u8], now: Instant) -> Vec<u8> {
        if !self.scip2 {
            // SCIP 1.1: only the switch is understood here.
            if line == b"SCIP2.0" {
                self.scip2 = true;
                let mut out = line.to_vec();
                out.extend_from_slice(b"\n0\n\n");
                return out;
            }
            let mut out = line.to_vec();
            out.extend_from_slice(b"\nE\n\n");
            return out;
        }
        if line == b"SCIP2.0" {
            return simple_reply(line, b"0E");
        }
        let (body, tag) = match line.iter().position(|&b| b == b';') {
            Some(i) => (&line[..i], &line[i..]),
            None => (line, &line[..0]),
        };
        if tag.len() > 17 {
            return simple_reply(line, b"0G");
        }
        if body.len() < 2 {
            return simple_reply(line, b"0D");
        }
        let (code, params) = body.split_at(if body[0] == b'%' { 3 } else { 2 });
        match code {
            b"VV" => info_reply(line, &self.vv()),
            b"PP" => info_reply(line, &self.pp()),
            b"II" => info_reply(line, &self.ii(now)),
            b"%ST" => {
                let state: &[u8] = match (&self.stream, self.adjust, self.laser) {
                    (_, true, _) => b"002",
                    (Some(_), _, _) => b"004",
                    (None, _, true) => b"003",
                    _ => b"000",
                };
                data_reply(line, b"00", &[state])
            }
            b"BM" => {
                let s = if self.laser { b"02" } else { b"00" };
                self.laser = true;
                simple_reply(line, s)
            }
            b"QT" => {
                self.stream = None;
                self.laser = false;
                simple_reply(line, b"00")
            }
            b"RS" | b"RT" => {
                self.stream = None;
                self.laser = false;
                self.adjust = false;
                self.clock_base = now;
                self.clock_at_base_ms = 0;
                simple_reply(line, b"00")
            }
            b"TM" => self.time(line, params, now),
            b"MD" | b"MS" | b"GD" | b"GS" => self.scan_command(line, code, params, tag, now),
            _ => simple_reply(line, b"0E"),
        }
    }

    fn time(&mut self, line: &[u8], params: &[u8], now: Instant) -> Vec<u8> {
        match params {
            b"0" => {
                let s = if self.adjust { b"02" } else { b"00" };
                self.adjust = true;
                self.stream = None;
                simple_reply(line, s)
            }
            b"1" if self.adjust => {
                let mut t = Vec::with_capacity(4);
                encode_into(
                    (self.clock_ms(now) % CLOCK_WRAP_MS) as u32,
                    Encoding::Four,
                    &mut t,
                );
                data_reply(line, b"00", &[&t])
            }
            b"1" => simple_reply(line, b"04"),
            b"2" => {
                let s = if self.adjust { b"00" } else { b"03" };
                self.adjust = false;
                simple_reply(line, s)
            }
            _ => simple_reply(line, b"01"),
        }
    }

    fn parse_request(
        &self,
        code: &[u8],
        params: &[u8],
    ) -> Result<(ScanRequest, u32, u32), Refusal> {
        let streaming = code[0] == b'M';
        let need = if streaming { 13 } else { 10 };
        if params.len() < need {
            return Err(b"0C");
        }
        if params.len() > need {
            return Err(b"0F");
        }
        let first = digits(params, 0..4, b"01")?;
        let last = digits(params, 4..8, b"02")?;
        let cluster = digits(params, 8..10, b"03")?;
        let (skip, scans) = if streaming {
            (
                digits(params, 10..11, b"06")?,
                digits(params, 11..13, b"07")?,
            )
        } else {
            (0, 0)
        };
        if last > self.model.amax || first < self.model.amin {
            return Err(b"04");
        }
        if last < first {
            return Err(b"05");
        }
        let encoding = if code[1] == b'S' {
            Encoding::Two
        } else {
            Encoding::Three
        };
        Ok((
            ScanRequest {
                first_step: first,
                last_step: last,
                cluster,
                skip,
                encoding,
            },
            skip,
            scans,
        ))
    }

    fn scan_command(
        &mut self,
        line: &[u8],
        code: &[u8],
        params: &[u8],
        tag: &[u8],
        now: Instant,
    ) -> Vec<u8> {
        let (request, skip, scans) = match self.parse_request(code, params) {
            Ok(r) => r,
            Err(status) => return simple_reply(line, status),
        };
        if code[0] == b'G' {
            if !self.laser {
                return simple_reply(line, b"10");
            }
            let stamp = (self.clock_ms(now) % CLOCK_WRAP_MS) as u32;
            let values = self.values(&request);
            let msg = scan_message(line, b"00", stamp, &values, request.encoding);
            self.log_scan(stamp, values, line, None);
            return msg;
        }
        self.laser = true;
        let every_ms = self.model.period_ms() * u64::from(skip + 1);
        let mut echo_head = code.to_vec();
        echo_head.extend_from_slice(&params[..11]);
        self.stream = Some(Stream {
            echo_head,
            tag: tag.to_vec(),
            request,
            remaining: (scans > 0).then_some(scans),
            next_due: now + Duration::from_millis(every_ms),
            next_stamp_ms: self.clock_ms(now) + every_ms,
            every_ms,
        });
        simple_reply(line, b"00")
    }

    /// The readings of one scan for `request`: the feed's steps, grouped by the cluster
    /// count (smallest valid reading of the group, else its smallest error code), clamped
    /// to the encoding (a reading `MS`/`GS` cannot carry is sent as 0, no echo).
    fn values(&mut self, request: &ScanRequest) -> Vec<u32> {
        let mut steps = self.feed.next_scan(&self.model);
        steps.resize(self.model.steps(), 0);
        let from = (request.first_step - self.model.amin) as usize;
        let to = (request.last_step - self.model.amin) as usize;
        let c = request.cluster_steps() as usize;
        let dmin = self.model.dmin_mm;
        steps[from..=to]
            .chunks(c)
            .map(|g| {
                let v = g
                    .iter()
                    .copied()
                    .filter(|&v| v >= dmin)
                    .min()
                    .unwrap_or_else(|| g.iter().copied().min().unwrap_or(0));
                if v > request.encoding.max_value() {
                    0
                } else {
                    v
                }
            })
            .collect()
    }

    fn log_scan(&self, timestamp: u32, values: Vec<u32>, echo: &[u8], fault: Option<ServedFault>) {
        self.log.push(Served {
            connection: self.connection,
            timestamp,
            echo: String::from_utf8_lossy(echo).into_owned(),
            values,
            fault,
        });
    }

    /// The scan due at `now`, if any, with the faults applied.
    pub fn poll(&mut self, now: Instant) -> Option<Action> {
        if let Some(u) = self.stall_until {
            if now < u {
                return None;
            }
            self.stall_until = None;
        }
        let due = self.stream.as_ref()?.next_due;
        if now < due {
            return None;
        }
        let f = self.faults.clone();
        if f.stall_after > 0
            && !self.stalled_this_connection
            && self.scans_this_connection >= f.stall_after
        {
            self.stalled_this_connection = true;
            self.stall_until = Some(now + f.stall_for);
            return None;
        }
        let request = self.stream.as_ref()?.request;
        let values = self.values(&request);
        let s = self.stream.as_mut()?;
        let stamp = (s.next_stamp_ms % CLOCK_WRAP_MS) as u32;
        s.next_stamp_ms += s.every_ms;
        s.next_due += Duration::from_millis(s.every_ms);
        let remaining = match &mut s.remaining {
            Some(r) => {
                *r -= 1;
                *r
            }
            None => 0,
        };
        let mut echo = s.echo_head.clone();
        echo.extend_from_slice(format!("{remaining:02}").as_bytes());
        echo.extend_from_slice(&s.tag);
        if s.remaining == Some(0) {
            self.stream = None;
        }
        let mut msg = scan_message(&echo, b"99", stamp, &values, request.encoding);
        self.scans_sent += 1;
        self.scans_this_connection += 1;
        let n = self.scans_sent;
        if f.drop_after > 0 && self.scans_this_connection > f.drop_after {
            msg.truncate(msg.len() / 2);
            self.log_scan(stamp, values, &echo, Some(ServedFault::Dropped));
            return Some(Action::SendAndDrop(msg));
        }
        let fault = if f.bad_checksum_every > 0 && n.is_multiple_of(f.bad_checksum_every) {
            corrupt_check(&mut msg);
            Some(ServedFault::Checksum)
        } else if f.truncate_every > 0 && n.is_multiple_of(f.truncate_every) {
            cut_line(&mut msg);
            Some(ServedFault::Truncated)
        } else {
            None
        };
        self.log_scan(stamp, values, &echo, fault);
        Some(Action::Send(msg))
    }

    fn vv(&self) -> Vec<(&'static str, String)> {
        let m = &self.model;
        vec![
            ("VEND", m.vendor.clone()),
            ("PROD", m.product.clone()),
            ("FIRM", m.firmware.clone()),
            ("PROT", m.protocol.clone()),
            ("SERI", m.serial.clone()),
        ]
    }

    fn pp(&self) -> Vec<(&'static str, String)> {
        let m = &self.model;
        vec![
            ("MODL", m.model.clone()),
            ("DMIN", m.dmin_mm.to_string()),
            ("DMAX", m.dmax_mm.to_string()),
            ("ARES", m.ares.to_string()),
            ("AMIN", m.amin.to_string()),
            ("AMAX", m.amax.to_string()),
            ("AFRT", m.afrt.to_string()),
            ("SCAN", m.scan_rpm.to_string()),
        ]
    }

    fn ii(&self, now: Instant) -> Vec<(&'static str, String)> {
        let m = &self.model;
        vec![
            ("MODL", m.model.clone()),
            ("LASR", if self.laser { "ON" } else { "OFF" }.to_owned()),
            ("SCSP", format!("Initial({}[rpm])", m.scan_rpm)),
            ("MESM", "Measuring by Normal Mode".to_owned()),
            ("SBPS", format!("{}[bps]", m.bit_rate)),
            (
                "TIME",
                format!("{:06X}", self.clock_ms(now) % CLOCK_WRAP_MS),
            ),
            ("STAT", "Sensor works well.".to_owned()),
        ]
    }
}
