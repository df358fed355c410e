//! Scans: `MD`/`MS` streaming, `GD`/`GS` single scans, and the decoding of a scan reply
//! into a [`HokuyoScan`] stamped in host time (or a drop and its reason).

use std::time::Instant;

use laserlines::Scan;

use crate::clock::{ClockModel, TimeSample};
use crate::reply::{Reply, ReplyError, Status};
use crate::request::ScanRequest;
use crate::status::StatusError;

use super::error::io_error;
use super::{DriverError, DropReason, HokuyoScan, ScanEvent, Session, Stream};

impl Session {
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
        let (raw, remaining) = match self.check_and_read(m, prefix, request, streaming) {
            Ok(read) => read,
            Err(event) => return event,
        };
        let (sensor_ms, stamp) = self.stamp(raw, at);
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

    /// Parses a scan reply, checks its echo, status, layout and check characters, and reads
    /// its values into `self.values`: the raw time stamp and the scans remaining, or the
    /// event to return instead (a drop, or another message).
    fn check_and_read(
        &mut self,
        m: &[u8],
        prefix: &str,
        request: &ScanRequest,
        streaming: bool,
    ) -> Result<(u32, u32), ScanEvent> {
        let reply = match Reply::parse_unchecked(m) {
            Ok(r) => r,
            Err(e @ ReplyError::Checksum { .. }) => {
                return Err(ScanEvent::Dropped(DropReason::Checksum, e.to_string()));
            }
            Err(e) => return Err(ScanEvent::Dropped(DropReason::Truncated, e.to_string())),
        };
        if !reply.echo.starts_with(prefix.as_bytes()) {
            self.discarded += 1;
            return Err(ScanEvent::Other);
        }
        let data_status: [u8; 2] = if streaming { *b"99" } else { *b"00" };
        match reply.status {
            Status::Scip2(s) if s == data_status => {}
            Status::Scip2(s) if streaming && &s == b"00" => return Err(ScanEvent::Other),
            other => {
                let e = StatusError::new(prefix, &other.as_string());
                return Err(ScanEvent::Dropped(DropReason::Status, e.to_string()));
            }
        }
        let values = request.values();
        if let Err(e) = reply.check_scan_layout(request.encoding, values) {
            return Err(ScanEvent::Dropped(DropReason::Truncated, e.to_string()));
        }
        if let Err(e) = reply.verify_data() {
            return Err(ScanEvent::Dropped(DropReason::Checksum, e.to_string()));
        }
        let raw = match reply.scan_into(request.encoding, values, &mut self.values) {
            Ok(t) => t,
            Err(e) => return Err(ScanEvent::Dropped(DropReason::Checksum, e.to_string())),
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
        Ok((raw, remaining))
    }

    /// The unwrapped sensor time of raw stamp `raw` and the scan's host stamp: the clock
    /// model's time of it (the first arrival stands for the offset when there was no `TM`),
    /// never later than the arrival `at`.
    fn stamp(&mut self, raw: u32, at: Instant) -> (u64, f64) {
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
        (sensor_ms, clock.host_time(sensor_ms).min(host_recv))
    }
}
