//! What went wrong talking to a sensor.

use std::io;
use std::time::Duration;

use laserlines::ScanError;

use crate::info::InfoError;
use crate::reply::ReplyError;
use crate::status::StatusError;
use crate::transport::Endpoint;

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

pub(super) fn io_error(endpoint: &Endpoint, e: io::Error) -> DriverError {
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
