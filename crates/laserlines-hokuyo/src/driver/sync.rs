//! `TM` time synchronisation: the sensor clock's offset from the `TM1` exchange with the
//! shortest round trip.

use crate::clock::{ClockModel, TimeSample};
use crate::codec;
use crate::reply::{Reply, ReplyError};
use crate::status::StatusError;

use super::connect::wait_echo;
use super::error::io_error;
use super::{DriverError, Session};

impl Session {
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
}
