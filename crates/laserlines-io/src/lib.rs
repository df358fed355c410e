//! # laserlines-io
//!
//! Scan formats for [`laserlines`]: readers that stream scans out of files, and writers for
//! scans and for extracted lines.
//!
//! | format | extension | scans per file | reader | writer |
//! |---|---|---|---|---|
//! | JSON, LaserScan-like object or array of them ([`json`]) | `.json` | 1 or many | yes | yes |
//! | JSONL, one object per line ([`json`]) | `.jsonl`, `.ndjson` | many | yes | yes |
//! | CSV `index,angle_rad,range_m` ([`csv`]) | `.csv` | 1 | yes | yes |
//! | BreezySLAM Hokuyo URG-04LX log ([`breezy`]) | `.dat` | many | yes | no |
//! | CARMEN log: `FLASER`, `RLASER`, `ROBOTLASERk`, `RAWLASERk` ([`carmen`]) | `.clf`, `.log` | many | yes | no |
//! | ROS 1 bag v2.0, `sensor_msgs/LaserScan`, chunks plain, bz2 or lz4 ([`bag`]) | `.bag` | many | yes | no |
//! | lines JSONL ([`lines`]) | `.jsonl` | one object per scan | [`LinesReader`] | [`LinesWriter`] |
//!
//! Any input is decompressed when its name ends in `.gz` or it starts with the gzip magic
//! bytes. [`open`] chooses the format by extension (or takes it explicitly), [`from_reader`]
//! reads any buffered reader (e.g. standard input). Both give a [`ScanReader`]: an iterator of
//! [`ScanRecord`]s (a validated [`laserlines::Scan`], with its stamp, the robot's pose when
//! the source has one, and its line) that reads piece by piece, so memory stays flat on long
//! logs, and counts what it skipped ([`SkipCounts`]).
//!
//! Errors ([`ReadError`]) name the file, the line (or byte offset) and what was expected
//! and found, e.g.
//! `exp1.dat:17: expected 707 tokens (timestamp, 23 fields, 682 ranges, 1 trailing), found 412`.
//! After an error the reader goes on with the next record where the format allows it, so a
//! caller can stop at the first error or count it and go on. A failed read of the input
//! itself (an I/O error, a corrupt or truncated gzip stream) ends the reader and is no bad
//! record to skip ([`ReadError::is_bad_record`]).
//!
//! Units are SI: metres, radians, seconds.
//!
//! ```
//! use laserlines_io::{demo, Format};
//!
//! let mut reader = demo::urg04lx_excerpt_reader()?;
//! assert_eq!(reader.format(), Format::BreezyDat);
//! let first = reader.next().expect("the excerpt has scans")?;
//! assert_eq!(first.scan.len(), 682);
//! assert_eq!(first.scan.stamp, Some(212.387282));
//! assert_eq!(reader.count() + 1, demo::URG04LX_EXCERPT_SCANS);
//! # Ok::<(), laserlines_io::ReadError>(())
//! ```
//!
//! Formats that hold several streams (ROS bag topics, CARMEN lasers) read one, chosen with
//! [`ReadOptions::topic`] in [`open_with`] / [`from_reader_with`], or their default.
//!
//! New formats plug in by implementing [`ScanSource`] and wrapping it with
//! [`ScanReader::from_source`].

pub mod bag;
pub mod breezy;
pub mod carmen;
pub mod csv;
pub mod demo;
pub mod error;
pub mod format;
pub mod gzip;
pub mod json;
pub mod lines;
pub mod params;
pub mod reader;
pub mod record;
pub mod ros;
pub mod skip;
pub mod trajectory;
mod wire;
pub mod writer;

pub use breezy::WheelOdometry;
pub use error::{At, ReadError, SourcePos, WriteError, error_chain};
pub use format::{Format, UnknownFormatName};
pub use lines::{LineRecord, LinesReader, ScanLines};
pub use reader::{
    DeferredParse, Input, Pending, ReadOptions, ScanReader, ScanSource, from_reader,
    from_reader_with, open, open_input, open_with,
};
pub use record::{Pose2, ScanRecord};
pub use ros::LaserScanMsg;
pub use skip::SkipCounts;
pub use wire::DecodeError;
pub use writer::{LinesWriter, Output, ScanWriter, encode_unnumbered};
