//! The first contact with a sensor: the serial bit rate probe, `QT`, the switch from SCIP
//! 1.1; and waiting for the reply that echoes a command.

use std::time::{Duration, Instant};

use crate::reply::{Reply, Status};
use crate::transport::{Connection, Endpoint, Link, PROBE_BAUDS, connect_tcp, open_serial};

use super::error::io_error;
use super::{DriverError, DriverOptions};

pub(super) fn wait_echo(
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

pub(super) fn connect(
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
