//! # laserlines-hokuyo
//!
//! Hokuyo laser scanners speaking SCIP 2.0 (URG-04LX over USB serial, UST/UTM models over
//! Ethernet), from the public protocol specification, with nothing else installed:
//!
//! - [`codec`]: check characters and the 2-, 3- and 4-character encodings;
//! - [`reply`]: framing the byte stream into messages, parsing and verifying them;
//! - [`status`]: status codes as errors that say what went wrong;
//! - [`info`]: `VV`/`PP`/`II` into a [`SensorInfo`], the scan geometry from it, and the
//!   reasons of the error codes below `DMIN` ([`NoReturn`]);
//! - [`request`]: `MD`/`MS`/`GD`/`GS` parameters;
//! - [`clock`]: the 24-bit sensor clock unwrapped, `TM` synchronisation, drift;
//! - [`transport`]: serial devices and TCP;
//! - [`driver`]: one [`Session`]: start-up (`QT`, SCIP 1.1 switch, `VV`, `PP`, `II`, `TM`,
//!   `BM`), streaming, single scans, `RS`/`RT`, `QT`;
//! - [`stream`]: a [`Scanner`] that reconnects with backoff, keeps stamps monotonic and
//!   counts every lost scan by reason;
//! - [`emulator`]: the sensor's side of SCIP 2.0 with fault injection, over TCP or a
//!   pseudo-terminal.
//!
//! Scans come out as [`laserlines::Scan`]s in metres, their geometry from the sensor's own
//! parameters (never from per-model constants), stamped in host time.
//!
//! ```
//! use laserlines_hokuyo::emulator::{Emulator, Faults, Model, ModelName, PatternFeed, ServedLog};
//! use laserlines_hokuyo::{Endpoint, Scanner, ScannerOptions};
//! use std::sync::atomic::AtomicBool;
//!
//! // An emulated UST-10LX on a free local port, and the driver reading one scan from it.
//! let log = ServedLog::in_memory();
//! let emulator = Emulator::new(Model::new(ModelName::Ust10lx), Box::new(PatternFeed::new()), Faults::default(), log)
//!     .serve_tcp("127.0.0.1:0")
//!     .unwrap();
//! let endpoint: Endpoint = emulator.local_addr().unwrap().to_string().parse().unwrap();
//! let mut scanner = Scanner::open(&endpoint, ScannerOptions::default()).unwrap();
//! let scan = scanner.next_scan(&AtomicBool::new(false)).unwrap();
//! assert_eq!(scan.scan.ranges.len(), 1081);
//! assert!((scan.scan.angle_increment.to_degrees() - 0.25).abs() < 1e-12);
//! scanner.close().unwrap();
//! emulator.stop().unwrap();
//! ```

pub mod clock;
pub mod codec;
pub mod driver;
pub mod emulator;
pub mod info;
pub mod reply;
pub mod request;
pub mod status;
pub mod stream;
pub mod transport;

pub use driver::{DriverError, DriverOptions, DropReason, HokuyoScan, ScanEvent, Session};
pub use info::{NoReturn, SensorInfo};
pub use request::ScanRequest;
pub use stream::{DropCounts, Scanner, ScannerOptions, ScannerStats};
pub use transport::{Endpoint, Link};
