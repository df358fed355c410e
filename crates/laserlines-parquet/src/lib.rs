//! # laserlines-parquet
//!
//! Apache Parquet for [`laserlines`], with the `arrow` and `parquet` crates: the tables a
//! notebook, a data frame library or a distributed engine (Ray Data, Spark, DuckDB) reads.
//!
//! - [`schema`]: the two tables, lines (one row per line) and scans (one row per scan), and
//!   their columns.
//! - [`LinesColumns`] / [`LinesParquetWriter`]: `laserlines extract LOG -o lines.parquet`.
//! - [`ScansColumns`] / [`ScansParquetWriter`]: `laserlines convert LOG scans.parquet`.
//! - [`read`]: a scans table read back as a [`laserlines_io::ScanReader`], like every other
//!   format.
//!
//! Files are written with zstd pages, in bounded row groups; the reader takes what pyarrow
//! and Ray write (snappy, zstd, LZ4, gzip; `float32` or `float64`; nullable columns).
//!
//! ```
//! use laserlines::{LineExtractor, Scan};
//! use laserlines_io::{Pose2, ScanRecord};
//! use laserlines_parquet::{ScansParquetWriter, read};
//!
//! let mut record = ScanRecord::new(Scan::new(-0.5, 0.25, 0.1, 8.0, vec![1.234, 2.5, f64::NAN])?);
//! record.scan.stamp = Some(12.5);
//! record.pose = Some(Pose2::new(1.0, -2.0, 0.3));
//! let mut writer = ScansParquetWriter::new(Vec::new(), "memory")?;
//! writer.write(&record)?;
//! let bytes = writer.finish()?;
//!
//! let mut reader = read::from_bytes("memory", bytes)?;
//! let back = reader.next().expect("one scan")?;
//! assert_eq!(back.scan.stamp, Some(12.5));
//! assert_eq!(back.scan.ranges[..2], [1.234, 2.5]); // float64: every bit kept
//! assert!(back.scan.ranges[2].is_nan());
//! assert_eq!(back.pose, record.pose);
//! assert!(reader.next().is_none());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod columns;
pub mod dictionary;
mod lines;
pub mod read;
mod scans;
pub mod schema;
mod table;

pub use lines::{LinesColumns, LinesParquetWriter};
pub use scans::{ScansColumns, ScansParquetWriter};
pub use schema::{lines_schema, scans_schema};
pub use table::TableWriter;
