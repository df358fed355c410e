//! The scan formats, told from a file name or chosen by name.

use std::fmt;
use std::path::Path;
use std::str::FromStr;

/// A scan format this crate reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Format {
    /// One LaserScan-like JSON object per file, or a top-level array of them (`.json`).
    Json,
    /// One LaserScan-like JSON object per line (`.jsonl`, `.ndjson`).
    Jsonl,
    /// `index,angle_rad,range_m` with a header, one scan per file (`.csv`).
    Csv,
    /// BreezySLAM / Paris Mines Tech Hokuyo URG-04LX log, 707 tokens per line (`.dat`).
    BreezyDat,
    /// MCAP (`.mcap`). Named here so that paths and `--format` can choose it; the
    /// `laserlines-foxglove` crate reads and writes it (plugging in through
    /// [`crate::ScanReader::from_source`]), this crate does not.
    Mcap,
    /// CARMEN log (`.clf`, `.log`): FLASER, RLASER, ROBOTLASER, RAWLASER lines; see
    /// [`crate::carmen`].
    Carmen,
    /// ROS 1 bag, version 2.0 or 1.2 (`.bag`): `sensor_msgs/LaserScan` messages; see
    /// [`crate::bag`].
    Bag,
    /// ROS 2 bag in sqlite3 storage (`.db3`, or a bag directory holding `.db3` files). Named
    /// here so that paths and `--format` can choose it; `laserlines-foxglove` reads it.
    Db3,
    /// Apache Parquet (`.parquet`), one scan per row. Named here so that paths and
    /// `--format` can choose it; the `laserlines-parquet` crate reads and writes it, this
    /// crate does not.
    Parquet,
}

impl Format {
    /// Every format, in the order of [`Format::NAMES`].
    pub const ALL: [Self; 9] = [
        Self::Json,
        Self::Jsonl,
        Self::Csv,
        Self::BreezyDat,
        Self::Mcap,
        Self::Carmen,
        Self::Bag,
        Self::Db3,
        Self::Parquet,
    ];

    /// The canonical names accepted by [`Format::from_name`] (e.g. for `--format`).
    pub const NAMES: &'static [&'static str] = &[
        "json", "jsonl", "csv", "dat", "mcap", "carmen", "bag", "db3", "parquet",
    ];

    /// Tells the format from a path's extension, ignoring a trailing `.gz` (case-insensitive):
    /// `.json`, `.jsonl` / `.ndjson`, `.csv`, `.dat`, `.mcap`, `.clf` / `.log` (CARMEN), `.bag`,
    /// `.db3`, `.parquet`.
    /// `None` for anything else.
    #[must_use]
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = inner_extension(path)?;
        Self::from_extension(&ext)
    }

    /// Chooses a format by name: a canonical name of [`Format::NAMES`] or an alias
    /// (`ndjson`, `breezy`, `breezyslam`, `clf`, `log`, `rosbag`, `sqlite3`), case-insensitive.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        match name.to_ascii_lowercase().as_str() {
            "json" => Some(Self::Json),
            "jsonl" | "ndjson" => Some(Self::Jsonl),
            "csv" => Some(Self::Csv),
            "dat" | "breezy" | "breezyslam" => Some(Self::BreezyDat),
            "mcap" => Some(Self::Mcap),
            "carmen" | "clf" | "log" => Some(Self::Carmen),
            "bag" | "rosbag" => Some(Self::Bag),
            "db3" | "sqlite3" => Some(Self::Db3),
            "parquet" | "pq" => Some(Self::Parquet),
            _ => None,
        }
    }

    fn from_extension(ext: &str) -> Option<Self> {
        match ext {
            "json" => Some(Self::Json),
            "jsonl" | "ndjson" => Some(Self::Jsonl),
            "csv" => Some(Self::Csv),
            "dat" => Some(Self::BreezyDat),
            "mcap" => Some(Self::Mcap),
            "clf" | "log" => Some(Self::Carmen),
            "bag" => Some(Self::Bag),
            "db3" => Some(Self::Db3),
            "parquet" | "pq" => Some(Self::Parquet),
            _ => None,
        }
    }

    /// The canonical name (`json`, `jsonl`, `csv`, `dat`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Json => "json",
            Self::Jsonl => "jsonl",
            Self::Csv => "csv",
            Self::BreezyDat => "dat",
            Self::Mcap => "mcap",
            Self::Carmen => "carmen",
            Self::Bag => "bag",
            Self::Db3 => "db3",
            Self::Parquet => "parquet",
        }
    }

    /// The usual file extension, without the dot.
    #[must_use]
    pub fn extension(self) -> &'static str {
        match self {
            Self::Carmen => "clf",
            other => other.name(),
        }
    }

    /// True when the format holds several streams of scans, one of which is read
    /// ([`crate::ReadOptions::topic`]): ROS bag topics, CARMEN laser messages, MCAP topics.
    #[must_use]
    pub fn has_topics(self) -> bool {
        matches!(self, Self::Bag | Self::Carmen | Self::Mcap | Self::Db3)
    }

    /// True when [`crate::ScanWriter`] can write this format.
    #[must_use]
    pub fn is_writable(self) -> bool {
        !matches!(
            self,
            Self::BreezyDat | Self::Mcap | Self::Carmen | Self::Bag | Self::Db3 | Self::Parquet
        )
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The error of parsing a [`Format`] from an unknown name.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "unknown scan format `{0}`; expected one of: json, jsonl, csv, dat, mcap, carmen, bag, db3, \
     parquet"
)]
pub struct UnknownFormatName(pub String);

impl FromStr for Format {
    type Err = UnknownFormatName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::from_name(s).ok_or_else(|| UnknownFormatName(s.to_owned()))
    }
}

/// The lower-case extension of `path` after removing one trailing `.gz`.
fn inner_extension(path: &Path) -> Option<String> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    if ext == "gz" {
        let stem = Path::new(path.file_stem()?);
        Some(stem.extension()?.to_str()?.to_ascii_lowercase())
    } else {
        Some(ext)
    }
}

/// What a path ends with, for error messages (`extension .txt`, `no extension`).
pub(crate) fn describe_extension(path: &Path) -> String {
    match inner_extension(path) {
        Some(ext) => format!("extension .{ext}"),
        None => "no extension".to_owned(),
    }
}

/// True when the path names a gzip file (`.gz`, case-insensitive).
pub(crate) fn has_gz_extension(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gz"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn format_from_path_ignores_gz_and_case() {
        let cases = [
            ("a.json", Some(Format::Json)),
            ("a.JSON.gz", Some(Format::Json)),
            ("dir.v2/a.jsonl", Some(Format::Jsonl)),
            ("a.ndjson.gz", Some(Format::Jsonl)),
            ("a.csv", Some(Format::Csv)),
            ("exp1.dat.gz", Some(Format::BreezyDat)),
            ("exp1.dat", Some(Format::BreezyDat)),
            ("log.MCAP", Some(Format::Mcap)),
            ("intel-corrected.log.gz", Some(Format::Carmen)),
            ("mit-csail.clf.gz", Some(Format::Carmen)),
            ("a.CLF", Some(Format::Carmen)),
            ("demo.bag", Some(Format::Bag)),
            ("demo.bag.gz", Some(Format::Bag)),
            ("rosbag2_0.db3", Some(Format::Db3)),
            ("scans.parquet", Some(Format::Parquet)),
            ("a.gz", None),
            ("a.txt", None),
            ("noext", None),
            ("a.tar.gz", None),
        ];
        for (p, want) in cases {
            assert_eq!(Format::from_path(Path::new(p)), want, "{p}");
        }
    }

    #[test]
    fn names_round_trip() {
        for (f, n) in Format::ALL.iter().zip(Format::NAMES) {
            assert_eq!(f.name(), *n);
            assert_eq!(Format::from_name(n), Some(*f));
            assert_eq!(n.parse::<Format>(), Ok(*f));
        }
        assert_eq!(Format::from_name("NDJSON"), Some(Format::Jsonl));
        assert_eq!(Format::from_name("breezyslam"), Some(Format::BreezyDat));
        assert!("xml".parse::<Format>().is_err());
    }
}
