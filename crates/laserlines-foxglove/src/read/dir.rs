//! A ROS 2 bag directory: its `.mcap` files (MCAP storage) or its `.db3` files (sqlite3
//! storage) read in order (`bag_0`, `bag_1`, ..., `bag_10`: numbers compared as numbers) as
//! one input.

use std::cmp::Ordering;
use std::collections::VecDeque;
use std::fs::File;
use std::io::{self, BufReader};
use std::path::{Path, PathBuf};

use laserlines_io::{ReadError, ScanRecord, ScanSource, SkipCounts};

use super::definitions::SummaryDefinitions;
use super::{McapReadOptions, McapScanSource};

/// A source reading the MCAP file at `path` (gzipped or not), with its summary's
/// definitions at hand ([`SummaryDefinitions`]).
pub(super) fn open_file(
    path: &Path,
    options: &McapReadOptions,
) -> Result<McapScanSource, ReadError> {
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
    let mut source = McapScanSource::new(&name, input, options.clone());
    source.summary = SummaryDefinitions::read(path);
    Ok(source)
}

/// The storage of a ROS 2 bag directory.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Storage {
    Mcap,
    Sqlite,
}

/// The storage of a ROS 2 bag directory and its files, in order.
pub(super) fn bag_files(dir: &Path) -> Result<(Storage, Vec<PathBuf>), ReadError> {
    let name = dir.display().to_string();
    let open_error = |source| ReadError::Open {
        file: name.clone(),
        source,
    };
    let (mut mcap, mut db3, mut compressed) = (Vec::new(), Vec::new(), Vec::new());
    for entry in std::fs::read_dir(dir).map_err(open_error)? {
        let path = entry.map_err(open_error)?.path();
        if !path.is_file() {
            continue;
        }
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("mcap") => mcap.push(path),
            Some("db3") => db3.push(path),
            Some("zstd") => compressed.push(path),
            _ => {}
        }
    }
    let (storage, mut files) = match (mcap.is_empty(), db3.is_empty()) {
        (false, true) => (Storage::Mcap, mcap),
        (true, false) => (Storage::Sqlite, db3),
        (false, false) => {
            return Err(open_error(io::Error::new(
                io::ErrorKind::InvalidData,
                "a ROS 2 bag holds .mcap or .db3 files, and this directory holds both: give \
                 one of the files",
            )));
        }
        (true, true) => {
            let why = if compressed.is_empty() {
                "a directory is read as a ROS 2 bag, but this one holds no .mcap or .db3 file"
            } else {
                "a directory is read as a ROS 2 bag, but its files are compressed (.zstd): \
                 decompress them first (`ros2 bag decompress`, or `zstd -d` on each file)"
            };
            return Err(open_error(io::Error::new(io::ErrorKind::NotFound, why)));
        }
    };
    files.sort_by(|a, b| natural_cmp(&a.to_string_lossy(), &b.to_string_lossy()));
    if !dir.join("metadata.yaml").is_file()
        && let Some(odd) = not_one_split_set(&files)
    {
        return Err(open_error(io::Error::new(
            io::ErrorKind::InvalidData,
            format!(
                "a directory is read as a ROS 2 bag, but this one has no metadata.yaml and its \
                 files are not one bag's split files (NAME_0, NAME_1, ...: {odd} is not): give \
                 the file itself, or restore the bag's metadata (`ros2 bag reindex`)"
            ),
        )));
    }
    Ok((storage, files))
}

/// Without `metadata.yaml` (a recording cut off before rosbag2 wrote it), the directory's
/// files must be named as one bag's split files are, `NAME_N` with one `NAME`: the first file
/// that is not, by its name. A folder of unrelated `.mcap` files is not read as one input;
/// a folder of one file is that file, whatever its name.
fn not_one_split_set(files: &[PathBuf]) -> Option<String> {
    if files.len() < 2 {
        return None;
    }
    let stem_of = |p: &PathBuf| -> Option<String> {
        let stem = p.file_stem()?.to_str()?;
        let (name, n) = stem.rsplit_once('_')?;
        (!n.is_empty() && n.bytes().all(|b| b.is_ascii_digit())).then(|| name.to_owned())
    };
    let first = files.first().and_then(stem_of);
    files
        .iter()
        .find(|p| first.is_none() || stem_of(p) != first)
        .map(|p| {
            p.file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
        })
}

/// Compares names with runs of digits compared as numbers (`bag_2` before `bag_10`).
fn natural_cmp(a: &str, b: &str) -> Ordering {
    let (mut a, mut b) = (a.as_bytes(), b.as_bytes());
    loop {
        match (a.first(), b.first()) {
            (None, None) => return Ordering::Equal,
            (None, Some(_)) => return Ordering::Less,
            (Some(_), None) => return Ordering::Greater,
            (Some(x), Some(y)) if x.is_ascii_digit() && y.is_ascii_digit() => {
                let da = a.iter().take_while(|c| c.is_ascii_digit()).count();
                let db = b.iter().take_while(|c| c.is_ascii_digit()).count();
                let (na, nb) = (trim_zeros(&a[..da]), trim_zeros(&b[..db]));
                let order = na.len().cmp(&nb.len()).then_with(|| na.cmp(nb));
                if order != Ordering::Equal {
                    return order;
                }
                (a, b) = (&a[da..], &b[db..]);
            }
            (Some(x), Some(y)) => {
                if x != y {
                    return x.cmp(y);
                }
                (a, b) = (&a[1..], &b[1..]);
            }
        }
    }
}

fn trim_zeros(digits: &[u8]) -> &[u8] {
    let zeros = digits.iter().take_while(|c| **c == b'0').count();
    &digits[zeros.min(digits.len().saturating_sub(1))..]
}

/// The files of a ROS 2 bag, read one after the other.
pub(super) struct McapFilesSource {
    pub(super) files: VecDeque<PathBuf>,
    pub(super) current: Option<McapScanSource>,
    pub(super) options: McapReadOptions,
}

impl ScanSource for McapFilesSource {
    fn next_record(&mut self, skipped: &mut SkipCounts) -> Option<Result<ScanRecord, ReadError>> {
        loop {
            if self.current.is_none() {
                let path = self.files.pop_front()?;
                match open_file(&path, &self.options) {
                    Ok(source) => self.current = Some(source),
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

#[cfg(test)]
mod tests {
    use super::{natural_cmp, not_one_split_set};
    use std::cmp::Ordering;
    use std::path::PathBuf;

    #[test]
    fn without_metadata_only_one_bags_split_files_make_a_bag() {
        let files = |names: &[&str]| -> Vec<PathBuf> { names.iter().map(PathBuf::from).collect() };
        assert_eq!(
            not_one_split_set(&files(&["run_0.mcap", "run_1.mcap"])),
            None
        );
        assert_eq!(not_one_split_set(&files(&["d/my_bag_0.db3"])), None);
        assert_eq!(not_one_split_set(&files(&["d/recording.mcap"])), None);
        assert_eq!(
            not_one_split_set(&files(&["a.mcap", "b.mcap"])).as_deref(),
            Some("a.mcap")
        );
        assert_eq!(
            not_one_split_set(&files(&["run_0.mcap", "other_1.mcap"])).as_deref(),
            Some("other_1.mcap")
        );
        assert_eq!(
            not_one_split_set(&files(&["run_0.mcap", "run_x.mcap"])).as_deref(),
            Some("run_x.mcap")
        );
    }

    #[test]
    fn numbers_in_names_compare_as_numbers() {
        let mut names = vec![
            "bag_10.db3",
            "bag_2.db3",
            "bag_0.db3",
            "bag_1.db3",
            "bag_01.db3",
        ];
        names.sort_by(|a, b| natural_cmp(a, b));
        assert_eq!(
            names,
            [
                "bag_0.db3",
                "bag_1.db3",
                "bag_01.db3",
                "bag_2.db3",
                "bag_10.db3"
            ]
        );
        assert_eq!(natural_cmp("a", "b"), Ordering::Less);
        assert_eq!(natural_cmp("x9", "x9"), Ordering::Equal);
    }
}
