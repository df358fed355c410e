//! Where the sensor is and how bytes get there: USB serial (CDC ACM) devices and TCP.

use std::fmt;
use std::io::{self, Read, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::str::FromStr;
use std::time::{Duration, Instant};

use crate::reply::Framer;

/// The TCP port of Hokuyo Ethernet models (UST, UTM, UXM).
pub const DEFAULT_TCP_PORT: u16 = 10940;

/// The bit rate of the URG-04LX's serial interface, and of its USB port's default.
pub const DEFAULT_BAUD: u32 = 115_200;

/// The bit rates tried, in order, when probing a serial sensor (the URG-04LX's RS-232
/// port starts at 19200 and can be set to 38400 or 115200; its USB port ignores the rate).
pub const PROBE_BAUDS: [u32; 3] = [115_200, 19_200, 38_400];

/// Where a sensor is: a serial device or a TCP address.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Endpoint {
    /// A serial device (`/dev/ttyACM0`, `COM3`), optionally at a fixed bit rate (otherwise
    /// [`PROBE_BAUDS`] are tried).
    Serial {
        /// The device path.
        path: String,
        /// The bit rate, when fixed.
        baud: Option<u32>,
    },
    /// A TCP address (`192.168.0.10:10940`).
    Tcp {
        /// Host name or address.
        host: String,
        /// Port.
        port: u16,
    },
}

/// An endpoint that does not parse.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0:?} is neither a serial device path nor HOST:PORT")]
pub struct EndpointError(pub String);

impl FromStr for Endpoint {
    type Err = EndpointError;

    /// `HOST:PORT` or an IP address alone (port 10940) is TCP; anything else is a serial
    /// device path (a path containing `/` or `\`, or a name such as `COM3`).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let s = s.trim();
        if s.is_empty() {
            return Err(EndpointError(s.to_owned()));
        }
        let looks_like_path = s.contains('/') || s.contains('\\');
        if !looks_like_path {
            if let Ok(ip) = s.parse::<std::net::IpAddr>() {
                return Ok(Self::Tcp {
                    host: ip.to_string(),
                    port: DEFAULT_TCP_PORT,
                });
            }
            if let Some((host, port)) = s.rsplit_once(':') {
                let host = host.trim_start_matches('[').trim_end_matches(']');
                return match port.parse::<u16>() {
                    Ok(port) if !host.is_empty() => Ok(Self::Tcp {
                        host: host.to_owned(),
                        port,
                    }),
                    _ => Err(EndpointError(s.to_owned())),
                };
            }
        }
        Ok(Self::Serial {
            path: s.to_owned(),
            baud: None,
        })
    }
}

impl fmt::Display for Endpoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Serial { path, baud: None } => write!(f, "{path}"),
            Self::Serial {
                path,
                baud: Some(b),
            } => write!(f, "{path} at {b} bit/s"),
            Self::Tcp { host, port } => write!(f, "{host}:{port}"),
        }
    }
}

/// A byte link to a sensor (or, for the emulator, to a host).
pub trait Link: Read + Write + Send {
    /// Sets how long a read waits for a first byte.
    ///
    /// # Errors
    /// When the link refuses.
    fn set_read_timeout(&mut self, timeout: Duration) -> io::Result<()>;
}

impl Link for TcpStream {
    fn set_read_timeout(&mut self, timeout: Duration) -> io::Result<()> {
        TcpStream::set_read_timeout(self, Some(timeout.max(Duration::from_millis(1))))
    }
}

/// A serial port as a [`Link`].
pub struct SerialLink(pub Box<dyn serialport::SerialPort>);

impl fmt::Debug for SerialLink {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_tuple("SerialLink").field(&self.0.name()).finish()
    }
}

impl Read for SerialLink {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.0.read(buf)
    }
}

impl Write for SerialLink {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.0.write(buf)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.0.flush()
    }
}

impl Link for SerialLink {
    fn set_read_timeout(&mut self, timeout: Duration) -> io::Result<()> {
        self.0
            .set_timeout(timeout.max(Duration::from_millis(1)))
            .map_err(io::Error::other)
    }
}

#[cfg(unix)]
impl Link for serialport::TTYPort {
    fn set_read_timeout(&mut self, timeout: Duration) -> io::Result<()> {
        serialport::SerialPort::set_timeout(self, timeout.max(Duration::from_millis(1)))
            .map_err(io::Error::other)
    }
}

/// Opens a TCP connection, waiting at most `timeout` for it.
///
/// # Errors
/// The I/O error of resolving or connecting.
pub fn connect_tcp(host: &str, port: u16, timeout: Duration) -> io::Result<TcpStream> {
    let mut last = io::Error::new(io::ErrorKind::NotFound, "no address");
    for addr in (host, port).to_socket_addrs()? {
        match TcpStream::connect_timeout(&addr, timeout) {
            Ok(s) => {
                s.set_nodelay(true)?;
                return Ok(s);
            }
            Err(e) => last = e,
        }
    }
    Err(last)
}

/// Opens a serial device at `baud` (8 data bits, no parity, 1 stop bit).
///
/// # Errors
/// The error of opening the device (missing, or no permission: see the dialout group).
pub fn open_serial(path: &str, baud: u32) -> io::Result<SerialLink> {
    let port = serialport::new(path, baud)
        .timeout(Duration::from_millis(50))
        .open()
        .map_err(|e| match e.kind() {
            serialport::ErrorKind::Io(kind) => io::Error::new(kind, e.description),
            serialport::ErrorKind::NoDevice => {
                io::Error::new(io::ErrorKind::NotFound, e.description)
            }
            _ => io::Error::other(e.description),
        })?;
    Ok(SerialLink(port))
}

/// A link with its framer: sends command lines, reads whole messages.
pub struct Connection {
    link: Box<dyn Link>,
    framer: Framer,
    buf: Vec<u8>,
    bytes_read: u64,
}

impl fmt::Debug for Connection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Connection")
            .field("pending", &self.framer.pending())
            .field("bytes_read", &self.bytes_read)
            .finish_non_exhaustive()
    }
}

impl Connection {
    /// A connection over `link`.
    #[must_use]
    pub fn new(link: Box<dyn Link>) -> Self {
        Self {
            link,
            framer: Framer::new(),
            buf: vec![0; 8192],
            bytes_read: 0,
        }
    }

    /// Sends `command` followed by a line feed.
    ///
    /// # Errors
    /// The link's write error.
    pub fn send(&mut self, command: &str) -> io::Result<()> {
        let mut line = Vec::with_capacity(command.len() + 1);
        line.extend_from_slice(command.as_bytes());
        line.push(b'\n');
        self.link.write_all(&line)?;
        self.link.flush()
    }

    /// The next whole message and when its last byte was read, waiting until `deadline`
    /// (`Ok(None)` then).
    ///
    /// # Errors
    /// [`io::ErrorKind::UnexpectedEof`] when the peer closed the link, or the link's read
    /// error.
    pub fn read_message(&mut self, deadline: Instant) -> io::Result<Option<(Vec<u8>, Instant)>> {
        loop {
            if let Some(m) = self.framer.next_message() {
                return Ok(Some((m, Instant::now())));
            }
            let now = Instant::now();
            if now >= deadline {
                return Ok(None);
            }
            self.link.set_read_timeout(deadline - now)?;
            match self.link.read(&mut self.buf) {
                Ok(0) => {
                    return Err(io::Error::new(
                        io::ErrorKind::UnexpectedEof,
                        "the sensor closed the connection",
                    ));
                }
                Ok(n) => {
                    self.bytes_read += n as u64;
                    self.framer.push(&self.buf[..n]);
                }
                Err(e)
                    if matches!(
                        e.kind(),
                        io::ErrorKind::WouldBlock
                            | io::ErrorKind::TimedOut
                            | io::ErrorKind::Interrupted
                    ) => {}
                Err(e) => return Err(e),
            }
        }
    }

    /// Reads and drops whatever arrives until the link has been quiet for `quiet` (or
    /// `max` has passed); returns the bytes dropped.
    ///
    /// # Errors
    /// As [`Connection::read_message`].
    pub fn drain(&mut self, quiet: Duration, max: Duration) -> io::Result<usize> {
        let start = Instant::now();
        let mut dropped = self.framer.pending();
        self.framer.clear();
        let mut last = Instant::now();
        while start.elapsed() < max && last.elapsed() < quiet {
            self.link.set_read_timeout(quiet)?;
            match self.link.read(&mut self.buf) {
                Ok(0) => {
                    return Err(io::Error::new(
                        io::ErrorKind::UnexpectedEof,
                        "the sensor closed the connection",
                    ));
                }
                Ok(n) => {
                    dropped += n;
                    last = Instant::now();
                }
                Err(e)
                    if matches!(
                        e.kind(),
                        io::ErrorKind::WouldBlock
                            | io::ErrorKind::TimedOut
                            | io::ErrorKind::Interrupted
                    ) => {}
                Err(e) => return Err(e),
            }
        }
        Ok(dropped)
    }

    /// Bytes of an unfinished message buffered.
    #[must_use]
    pub fn pending(&self) -> usize {
        self.framer.pending()
    }

    /// Bytes read so far.
    #[must_use]
    pub fn bytes_read(&self) -> u64 {
        self.bytes_read
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endpoints_parse_as_tcp_or_serial() {
        assert_eq!(
            "192.168.0.10:10940".parse::<Endpoint>(),
            Ok(Endpoint::Tcp {
                host: "192.168.0.10".to_owned(),
                port: 10940
            })
        );
        assert_eq!(
            "192.168.0.10".parse::<Endpoint>(),
            Ok(Endpoint::Tcp {
                host: "192.168.0.10".to_owned(),
                port: DEFAULT_TCP_PORT
            })
        );
        assert_eq!(
            "localhost:4000".parse::<Endpoint>(),
            Ok(Endpoint::Tcp {
                host: "localhost".to_owned(),
                port: 4000
            })
        );
        assert_eq!(
            "/dev/ttyACM0".parse::<Endpoint>(),
            Ok(Endpoint::Serial {
                path: "/dev/ttyACM0".to_owned(),
                baud: None
            })
        );
        assert_eq!(
            "COM3".parse::<Endpoint>(),
            Ok(Endpoint::Serial {
                path: "COM3".to_owned(),
                baud: None
            })
        );
        assert!("host:notaport".parse::<Endpoint>().is_err());
        assert!("".parse::<Endpoint>().is_err());
    }
}
