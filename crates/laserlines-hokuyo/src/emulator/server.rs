//! Moving the emulated sensor's bytes: one host at a time over TCP (a new connection
//! replaces the old one, as a sensor's single host link), or over a pseudo-terminal; the
//! log of every scan sent.

use std::io::{self, Write};
use std::net::{SocketAddr, TcpListener};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::sensor::{Action, Faults, Sensor};
use super::{Model, ScanFeed};
use crate::transport::Link;

/// The damage done to a scan sent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ServedFault {
    /// One line's check character was wrong.
    Checksum,
    /// One data line was cut short.
    Truncated,
    /// Half of it was sent, then the connection dropped.
    Dropped,
}

impl ServedFault {
    /// A short name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Checksum => "checksum",
            Self::Truncated => "truncated",
            Self::Dropped => "dropped",
        }
    }
}

/// One scan the emulator sent.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Served {
    /// Which connection (1 for the first).
    pub connection: u64,
    /// The time stamp sent, ms (24 bits).
    pub timestamp: u32,
    /// The command echo sent with it.
    pub echo: String,
    /// The readings sent, mm.
    pub values: Vec<u32>,
    /// The damage done to it, if any.
    pub fault: Option<ServedFault>,
}

impl Served {
    /// The scan as one JSON object (for `--served FILE`).
    #[must_use]
    pub fn to_json(&self) -> String {
        let values: Vec<String> = self.values.iter().map(u32::to_string).collect();
        let fault = self
            .fault
            .map_or_else(|| "null".to_owned(), |f| format!("\"{}\"", f.name()));
        format!(
            "{{\"connection\":{},\"timestamp\":{},\"echo\":\"{}\",\"fault\":{},\"values\":[{}]}}",
            self.connection,
            self.timestamp,
            self.echo.replace(['"', '\\'], "_"),
            fault,
            values.join(",")
        )
    }
}

type Sink = Box<dyn Write + Send>;

/// The log of the scans sent: kept in memory (for tests) and/or written as JSON lines.
#[derive(Clone, Default)]
pub struct ServedLog {
    kept: Arc<Mutex<Option<Vec<Served>>>>,
    sink: Arc<Mutex<Option<Sink>>>,
    count: Arc<Mutex<u64>>,
}

impl std::fmt::Debug for ServedLog {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ServedLog")
            .field("count", &self.count())
            .finish_non_exhaustive()
    }
}

impl ServedLog {
    /// A log that keeps every scan in memory.
    #[must_use]
    pub fn in_memory() -> Self {
        Self {
            kept: Arc::new(Mutex::new(Some(Vec::new()))),
            ..Self::default()
        }
    }

    /// A log that writes every scan as one JSON line to `sink` (keeping none in memory).
    #[must_use]
    pub fn to_writer(sink: Box<dyn Write + Send>) -> Self {
        Self {
            sink: Arc::new(Mutex::new(Some(sink))),
            ..Self::default()
        }
    }

    /// Records a scan.
    pub fn push(&self, served: Served) {
        *self.count.lock().unwrap_or_else(PoisonError::into_inner) += 1;
        if let Some(sink) = self
            .sink
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .as_mut()
        {
            // The log is a diagnostic: a failed write must not stop the sensor.
            let _ = writeln!(sink, "{}", served.to_json()).and_then(|()| sink.flush());
        }
        if let Some(kept) = self
            .kept
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .as_mut()
        {
            kept.push(served);
        }
    }

    /// The scans kept so far (empty for a log that keeps none).
    #[must_use]
    pub fn snapshot(&self) -> Vec<Served> {
        self.kept
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .clone()
            .unwrap_or_default()
    }

    /// Scans sent so far.
    #[must_use]
    pub fn count(&self) -> u64 {
        *self.count.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

/// An emulated sensor, ready to serve.
#[derive(Debug)]
pub struct Emulator {
    sensor: Sensor,
    log: ServedLog,
}

/// A running emulator.
#[derive(Debug)]
pub struct EmulatorHandle {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<io::Result<()>>>,
    addr: Option<SocketAddr>,
    pty_path: Option<String>,
    log: ServedLog,
    came_back: Arc<Mutex<Vec<Instant>>>,
}

impl EmulatorHandle {
    /// The TCP address served on.
    #[must_use]
    pub fn local_addr(&self) -> Option<SocketAddr> {
        self.addr
    }

    /// The pseudo-terminal's device path (the host opens it as a serial device).
    #[must_use]
    pub fn pty_path(&self) -> Option<&str> {
        self.pty_path.as_deref()
    }

    /// The log of the scans sent.
    #[must_use]
    pub fn log(&self) -> &ServedLog {
        &self.log
    }

    /// When the emulator listened again after each dropped connection.
    #[must_use]
    pub fn came_back(&self) -> Vec<Instant> {
        self.came_back
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .clone()
    }

    /// True once the serving thread has ended (an error, or [`EmulatorHandle::stop`]).
    #[must_use]
    pub fn is_finished(&self) -> bool {
        self.thread.as_ref().is_none_or(JoinHandle::is_finished)
    }

    /// Stops serving and returns the serving thread's result.
    ///
    /// # Errors
    /// The I/O error that ended the serving thread, if one did.
    pub fn stop(mut self) -> io::Result<()> {
        self.stop.store(true, Ordering::Relaxed);
        match self.thread.take().map(JoinHandle::join) {
            Some(Ok(r)) => r,
            Some(Err(_)) => Err(io::Error::other("the emulator thread panicked")),
            None => Ok(()),
        }
    }
}

impl Drop for EmulatorHandle {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

enum Step {
    Going,
    Closed,
    Dropped,
}

/// Command lines arriving in pieces; a line ends with LF or CR (or both).
#[derive(Default)]
struct Lines {
    buf: Vec<u8>,
}

impl Lines {
    fn push(&mut self, bytes: &[u8]) {
        self.buf.extend_from_slice(bytes);
        if self.buf.len() > 4096 {
            // No command is this long: drop the garbage.
            self.buf.clear();
        }
    }

    fn next_line(&mut self) -> Option<Vec<u8>> {
        loop {
            let end = self.buf.iter().position(|&b| b == b'\n' || b == b'\r')?;
            let line: Vec<u8> = self.buf.drain(..=end).take(end).collect();
            if !line.is_empty() {
                return Some(line);
            }
        }
    }
}

/// Serves one step on `link`: answers the commands that came, sends the scans due.
fn step(sensor: &mut Sensor, link: &mut dyn Link, lines: &mut Lines, buf: &mut [u8]) -> Step {
    let wait = sensor.next_due().map_or(Duration::from_millis(2), |d| {
        d.saturating_duration_since(Instant::now())
            .min(Duration::from_millis(2))
    });
    if link
        .set_read_timeout(wait.max(Duration::from_millis(1)))
        .is_err()
    {
        return Step::Closed;
    }
    match link.read(buf) {
        Ok(0) => return Step::Closed,
        Ok(n) => lines.push(&buf[..n]),
        Err(e)
            if matches!(
                e.kind(),
                io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut | io::ErrorKind::Interrupted
            ) => {}
        Err(_) => return Step::Closed,
    }
    let delay = sensor.faults().reply_delay;
    while let Some(line) = lines.next_line() {
        if !delay.is_zero() {
            std::thread::sleep(delay);
        }
        let reply = sensor.handle(&line, Instant::now());
        if link.write_all(&reply).and_then(|()| link.flush()).is_err() {
            return Step::Closed;
        }
    }
    while let Some(action) = sensor.poll(Instant::now()) {
        let (bytes, drop) = match action {
            Action::Send(b) => (b, false),
            Action::SendAndDrop(b) => (b, true),
        };
        if link.write_all(&bytes).and_then(|()| link.flush()).is_err() {
            return Step::Closed;
        }
        if drop {
            return Step::Dropped;
        }
    }
    Step::Going
}

fn sleep_unless_stopped(d: Duration, stop: &AtomicBool) {
    let until = Instant::now() + d;
    while Instant::now() < until && !stop.load(Ordering::Relaxed) {
        std::thread::sleep(Duration::from_millis(5).min(until - Instant::now()));
    }
}

impl Emulator {
    /// An emulated `model` fed by `feed`, with `faults`, logging to `log`.
    #[must_use]
    pub fn new(model: Model, feed: Box<dyn ScanFeed>, faults: Faults, log: ServedLog) -> Self {
        Self {
            sensor: Sensor::new(model, feed, faults, log.clone()),
            log,
        }
    }

    /// Serves on TCP at `addr` (`127.0.0.1:0` picks a free port: see
    /// [`EmulatorHandle::local_addr`]) on a thread of its own.
    ///
    /// # Errors
    /// The error of binding `addr`.
    pub fn serve_tcp(self, addr: &str) -> io::Result<EmulatorHandle> {
        let listener = TcpListener::bind(addr)?;
        let local = listener.local_addr()?;
        listener.set_nonblocking(true)?;
        let stop = Arc::new(AtomicBool::new(false));
        let came_back = Arc::new(Mutex::new(Vec::new()));
        let (s, c) = (stop.clone(), came_back.clone());
        let log = self.log.clone();
        let mut sensor = self.sensor;
        let thread = std::thread::Builder::new()
            .name("hokuyo-emulator".to_owned())
            .spawn(move || serve_tcp_loop(&mut sensor, listener, local, &s, &c))?;
        Ok(EmulatorHandle {
            stop,
            thread: Some(thread),
            addr: Some(local),
            pty_path: None,
            log,
            came_back,
        })
    }

    /// Serves on a new pseudo-terminal, whose device path
    /// ([`EmulatorHandle::pty_path`]) the host opens as a serial port.
    ///
    /// # Errors
    /// The error of creating the pseudo-terminal.
    #[cfg(unix)]
    pub fn serve_pty(self) -> io::Result<EmulatorHandle> {
        let (mut master, slave) = serialport::TTYPort::pair().map_err(io::Error::other)?;
        let path = serialport::SerialPort::name(&slave)
            .ok_or_else(|| io::Error::other("the pseudo-terminal has no device name"))?;
        let stop = Arc::new(AtomicBool::new(false));
        let s = stop.clone();
        let log = self.log.clone();
        let mut sensor = self.sensor;
        let thread = std::thread::Builder::new()
            .name("hokuyo-emulator-pty".to_owned())
            .spawn(move || {
                // Keep the slave side open, so that the master survives hosts closing it.
                let _slave = slave;
                sensor.new_connection();
                let mut lines = Lines::default();
                let mut buf = vec![0u8; 4096];
                while !s.load(Ordering::Relaxed) {
                    match step(&mut sensor, &mut master, &mut lines, &mut buf) {
                        Step::Going => {}
                        // A pseudo-terminal cannot be dropped and reopened under the same
                        // name: "dropping" it just goes silent for a moment.
                        Step::Dropped | Step::Closed => {
                            std::thread::sleep(Duration::from_millis(10));
                            sensor.new_connection();
                        }
                    }
                }
                Ok(())
            })?;
        Ok(EmulatorHandle {
            stop,
            thread: Some(thread),
            addr: None,
            pty_path: Some(path),
            log,
            came_back: Arc::new(Mutex::new(Vec::new())),
        })
    }
}

fn serve_tcp_loop(
    sensor: &mut Sensor,
    mut listener: TcpListener,
    local: SocketAddr,
    stop: &AtomicBool,
    came_back: &Mutex<Vec<Instant>>,
) -> io::Result<()> {
    let mut link: Option<std::net::TcpStream> = None;
    let mut lines = Lines::default();
    let mut buf = vec![0u8; 4096];
    while !stop.load(Ordering::Relaxed) {
        match listener.accept() {
            Ok((s, _)) => {
                s.set_nonblocking(false)?;
                s.set_nodelay(true)?;
                link = Some(s);
                lines = Lines::default();
                sensor.new_connection();
            }
            Err(e) if e.kind() == io::ErrorKind::WouldBlock => {}
            Err(e) => return Err(e),
        }
        let Some(l) = link.as_mut() else {
            std::thread::sleep(Duration::from_millis(2));
            continue;
        };
        match step(sensor, l, &mut lines, &mut buf) {
            Step::Going => {}
            Step::Closed => link = None,
            Step::Dropped => {
                link = None;
                let down = sensor.faults().down_for;
                if !down.is_zero() {
                    drop(listener);
                    sleep_unless_stopped(down, stop);
                    listener = loop {
                        match TcpListener::bind(local) {
                            Ok(l) => break l,
                            Err(_) if !stop.load(Ordering::Relaxed) => {
                                std::thread::sleep(Duration::from_millis(10));
                            }
                            Err(e) => return Err(e),
                        }
                    };
                    listener.set_nonblocking(true)?;
                    came_back
                        .lock()
                        .unwrap_or_else(PoisonError::into_inner)
                        .push(Instant::now());
                }
            }
        }
    }
    Ok(())
}
