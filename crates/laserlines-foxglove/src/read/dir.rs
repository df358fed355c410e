//! A ROS 2 bag directory in MCAP storage: its `.mcap` files read in name order as one
//! input.

use std::collections::VecDeque;
use std::fs::File;
use std::io::{self, BufReader};
use std::path::Path;

use laserlines_io::{Input, ReadError, ScanRecord, ScanSource, SkipCounts};

use super::{McapReadOptions, McapScanSource};

pub(super) fn open_file(path: &Path) -> Result<(String, Input), ReadError> {
    let name = path.display().to_string();
    let file = File::open(path).map_err(|source| ReadError::Open {
        file: name.clone(),
        source,
    })?;
    let gz = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gz"));
    let input =
        laserlines_io::open_input(&name, Box::new(BufReader::with_capacity(1 << 16, file)), gz)?;
    Ok((name, input))
}

/// The `.mcap` files of a ROS 2 bag directory, in name order.
pub(super) fn bag_files(dir: &Path) -> Result<Vec<std::path::PathBuf>, ReadError> {
    let name = dir.display().to_string();
    let open_error = |source| ReadError::Open {
        file: name.clone(),
        source,
    };
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(open_error)? {
        let path = entry.map_err(open_error)?.path();
        let is_mcap = path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("mcap"));
        if is_mcap && path.is_file() {
            files.push(path);
        }
    }
    files.sort();
    if files.is_empty() {
        return Err(open_error(io::Error::new(
            io::ErrorKind::NotFound,
            "a directory is read as a ROS 2 bag with MCAP storage, but this one holds no .mcap \
             file (bags in sqlite3 storage can be converted with `ros2 bag convert`)",
        )));
    }
    Ok(files)
}

/// The files of a ROS 2 bag, read one after the other.
pub(super) struct McapFilesSource {
    pub(super) files: VecDeque<std::path::PathBuf>,
    pub(super) current: Option<McapScanSource>,
    pub(super) options: McapReadOptions,
}

impl ScanSource for McapFilesSource {
    fn next_record(&mut self, skipped: &mut SkipCounts) -> Option<Result<ScanRecord, ReadError>> {
        loop {
            if self.current.is_none() {
                let path = self.files.pop_front()?;
                match open_file(&path) {
                    Ok((name, input)) => {
                        self.current =
                            Some(McapScanSource::new(&name, input, self.options.clone()));
                    }
                    Err(e) => return Some(Err(e)),
                }
            }
            let current = self.current.as_mut()?;
            match current.next_record(skipped) {
                Some(item) => return Some(item),
                None => {
                    // Later files read the topic this one settled.
                    if self.options.topic.is_none() {
                        self.options.topic.clone_from(&current.topic);
                    }
                    self.current = None;
                }
            }
        }
    }
}
