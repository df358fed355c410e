//! One module per subcommand, plus what they share.

pub mod bench;
pub mod convert;
pub mod demo;
pub mod extract;
pub mod hokuyo_emulator;
pub mod live;
pub mod map;
pub mod map_outputs;
pub mod relations;
pub mod render;
pub mod simulate;
pub mod simulate_world;
pub mod view;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use laserlines::HoughSplit;
use laserlines::registry::{self, BoxedExtractor};
use laserlines_io::params::ParamsFile;
use laserlines_io::{Format, ScanReader};

use crate::InputArgs;

/// The algorithms `--algorithm` accepts.
pub use laserlines::registry::ALGORITHMS;

/// Refuses an output that is the input itself (the same file by another name or link too):
/// writing it would truncate the input before it is read, and a failed conversion would
/// remove it. `-` (stdin, stdout) and an output that does not exist yet pass.
pub fn refuse_same_file(input: &Path, output: &Path) -> Result<()> {
    let dash = |p: &Path| p.as_os_str() == "-";
    if dash(input) || dash(output) {
        return Ok(());
    }
    let (Ok(a), Ok(b)) = (std::fs::metadata(input), std::fs::metadata(output)) else {
        return Ok(());
    };
    if a.is_file() && same_file(input, output, &a, &b) {
        return Err(anyhow!(
            "{}: the output is the input ({}): writing it would destroy the input; give \
             another output file",
            output.display(),
            input.display()
        ));
    }
    Ok(())
}

/// Refuses a recording (`--mcap`) that would overwrite a file the command reads (`inputs`,
/// the same file by any name, or a file inside an input that is a folder, such as a ROS 2
/// bag) or one of the files `names` it writes in its output folder `dir`: the recording is
/// written first or last, and either way one of the two is lost.
pub fn refuse_recording_over(
    mcap: &Path,
    inputs: &[&Path],
    dir: &Path,
    names: &[&str],
) -> Result<()> {
    let place = resolve(mcap);
    for input in inputs {
        refuse_same_file(input, mcap).context("--mcap")?;
        if input.is_dir() && place.starts_with(resolve(input)) {
            bail!(
                "{}: --mcap lies inside the input folder {}: writing it would change the \
                 input; give the recording a place outside it",
                mcap.display(),
                input.display()
            );
        }
    }
    let name = place.file_name().and_then(|n| n.to_str()).unwrap_or("");
    let folder = place.parent().unwrap_or(Path::new(""));
    if names.iter().any(|n| same_name(n, name)) && same_place(folder, &resolve(dir)) {
        bail!(
            "{}: --mcap names a file this command writes in its output folder {}; give the \
             recording another name",
            mcap.display(),
            dir.display()
        );
    }
    Ok(())
}

/// True when paths `a` and `b` (folders or files) name one place, whether or not it exists
/// yet ([`resolve`]).
pub fn same_path(a: &Path, b: &Path) -> bool {
    same_place(&resolve(a), &resolve(b))
}

/// `p` as an absolute path (`""` is `.`), `.` and `name/..` taken out, its longest part that
/// exists resolved (links followed) and the rest appended: two names of one place give one
/// path whether or not the place exists yet.
fn resolve(p: &Path) -> PathBuf {
    use std::path::Component;
    let p = if p.as_os_str().is_empty() {
        Path::new(".")
    } else {
        p
    };
    let abs = std::env::current_dir().map_or_else(|_| p.to_path_buf(), |d| d.join(p));
    let mut plain = PathBuf::new();
    for c in abs.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                plain.pop();
            }
            c => plain.push(c),
        }
    }
    let mut rest = Vec::new();
    let mut head = plain.as_path();
    loop {
        if let Ok(mut out) = std::fs::canonicalize(head) {
            out.extend(rest.iter().rev());
            return out;
        }
        match (head.parent(), head.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name.to_owned());
                head = parent;
            }
            _ => return plain,
        }
    }
}

/// Two resolved paths name one place: the same path, letter case aside where the file
/// systems ignore it by default (Windows, macOS).
fn same_place(a: &Path, b: &Path) -> bool {
    if cfg!(any(windows, target_os = "macos")) {
        a.to_string_lossy().to_lowercase() == b.to_string_lossy().to_lowercase()
    } else {
        a == b
    }
}

/// Two file names name one file, as [`same_place`] compares them.
fn same_name(a: &str, b: &str) -> bool {
    same_place(Path::new(a), Path::new(b))
}

/// Removes the output file of a run that failed or wrote nothing, when it is a regular file:
/// standard output (`-`), a device (`/dev/null`) and a named pipe stay as they are, and so
/// does a symbolic link, with a note that the file it points to holds what was written.
/// True when it was removed.
pub fn remove_own_output(output: &Path) -> bool {
    if output == Path::new("-") {
        return false;
    }
    let Ok(meta) = std::fs::symlink_metadata(output) else {
        return false;
    };
    if meta.file_type().is_symlink() {
        errln!(
            "laserlines: {} is a symbolic link: left as it is, and the file it points to holds \
             what this run wrote before it failed",
            output.display()
        );
        return false;
    }
    meta.file_type().is_file() && std::fs::remove_file(output).is_ok()
}

/// Refuses an output file whose folder does not exist, naming the folder, before anything is
/// read (the commands that write a folder, `map`, `simulate` and `bench -o`, create it).
pub fn output_folder_exists(output: &Path) -> Result<()> {
    if output.as_os_str() == "-" {
        return Ok(());
    }
    match output.parent() {
        Some(dir) if !dir.as_os_str().is_empty() && !dir.is_dir() => Err(anyhow!(
            "{}: cannot write: the folder {} does not exist (create it first)",
            output.display(),
            dir.display()
        )),
        _ => Ok(()),
    }
}

#[cfg(unix)]
fn same_file(_: &Path, _: &Path, a: &std::fs::Metadata, b: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    a.dev() == b.dev() && a.ino() == b.ino()
}

#[cfg(not(unix))]
fn same_file(x: &Path, y: &Path, _: &std::fs::Metadata, _: &std::fs::Metadata) -> bool {
    matches!(
        (std::fs::canonicalize(x), std::fs::canonicalize(y)),
        (Ok(a), Ok(b)) if a == b
    )
}

/// Opens the input of a command (MCAP or any format of `laserlines-io`, chosen by
/// `laserlines_foxglove::open_scans`).
pub fn open_input(input: &InputArgs) -> Result<ScanReader> {
    let format = match &input.format {
        Some(name) => Some(Format::from_name(name).ok_or_else(|| {
            anyhow!(
                "unknown format {name:?}: expected one of {}",
                Format::NAMES.join(", ")
            )
        })?),
        None => None,
    };
    let options = laserlines_io::ReadOptions::format(format).with_topic(input.topic.as_deref());
    Ok(laserlines_foxglove::open_scans(&input.input, &options)?)
}

/// `--params` and `--preset`: where the commands that run one extractor take its parameters.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct ParamsArgs {
    /// TOML file of parameters (one table per algorithm, e.g. `[hough-split]`).
    #[arg(long)]
    pub params: Option<PathBuf>,
    /// Start the extractor from one of its presets instead of its defaults (hough-split:
    /// paper, navigation, walls, complete), in place of any preset its table names; the
    /// table's other keys are laid over it.
    #[arg(long)]
    pub preset: Option<String>,
}

impl ParamsArgs {
    /// The params file, if one is given.
    pub fn file_path(&self) -> Option<&Path> {
        self.params.as_deref()
    }

    /// The params file (empty when none is given) with `--preset` applied to `algorithm`
    /// ([`ParamsFile::load_with_preset`]).
    pub fn file(&self, algorithm: &str) -> Result<ParamsFile> {
        let preset = self.preset.as_deref();
        Ok(ParamsFile::load_with_preset(
            self.file_path(),
            algorithm,
            preset,
        )?)
    }
}

/// The extractor named `algorithm` (one of [`ALGORITHMS`]), with its parameters from
/// `params` ([`ParamsArgs::file`]).
pub fn make_extractor(algorithm: &str, params: &ParamsArgs) -> Result<BoxedExtractor> {
    Ok(params.file(algorithm)?.extractor(algorithm)?)
}

/// A HoughSplit extractor with its parameters from `params` ([`ParamsArgs::file`]).
pub fn make_hough_split(params: &ParamsArgs) -> Result<HoughSplit> {
    let file = params.file(registry::HOUGH_SPLIT.name)?;
    let p = file.algorithm_params(&registry::HOUGH_SPLIT)?;
    HoughSplit::new(p).context("hough-split parameters")
}

/// `n` and the noun, in the singular for one (`1 scan`, `2 scans`, `3 passes`).
pub fn count(n: u64, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else if noun.ends_with('s') || noun.ends_with('x') {
        format!("{n} {noun}es")
    } else {
        format!("{n} {noun}s")
    }
}

/// The values `--algorithm` accepts, listed by `--help` and in its errors.
pub fn algorithm_parser() -> clap::builder::PossibleValuesParser {
    clap::builder::PossibleValuesParser::new(ALGORITHMS)
}

/// Most repetitions `--repeat` takes (`bench`, `demo`).
pub const MAX_REPEAT: usize = 1000;

/// A value parser for repetition counts, 1 to [`MAX_REPEAT`] (`--repeat`).
pub fn repeat_count(s: &str) -> Result<usize, String> {
    match s.trim().parse::<i64>() {
        Ok(n) if (1..=MAX_REPEAT as i64).contains(&n) => {
            usize::try_from(n).map_err(|e| e.to_string())
        }
        Ok(n) => Err(format!("must be from 1 to {MAX_REPEAT}, got {n}")),
        Err(_) => Err(format!(
            "expected a whole number from 1 to {MAX_REPEAT}, got {s:?}"
        )),
    }
}

/// Most seconds a time option takes (about 31.7 years).
pub const MAX_SECONDS: f64 = 1e9;

/// `v` for a message: as written for ordinary magnitudes, in exponent form (`1e300`) for
/// very large or very small ones, so that a message never spells out hundreds of digits.
pub fn compact(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || !a.is_finite() || (1e-4..1e9).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// `value` seconds given to `flag` as a duration: from 0 (more than 0 unless `zero`) up to
/// [`MAX_SECONDS`]; anything else is refused with the allowed range.
pub fn seconds(flag: &str, value: f64, zero: bool) -> Result<std::time::Duration> {
    let low_ok = value > 0.0 || (zero && value == 0.0);
    if low_ok
        && value <= MAX_SECONDS
        && let Ok(d) = std::time::Duration::try_from_secs_f64(value)
    {
        return Ok(d);
    }
    let low = if zero { "from 0" } else { "more than 0" };
    Err(anyhow!(
        "{flag} must be seconds, {low} up to {}, got {}",
        compact(MAX_SECONDS),
        compact(value)
    ))
}

/// `value` milliseconds given to `flag` as a duration: from 0 up to [`MAX_SECONDS`] (1e12
/// ms); anything more is refused with the allowed range.
pub fn milliseconds(flag: &str, value: u64) -> Result<std::time::Duration> {
    let max_ms = MAX_SECONDS * 1e3;
    if value as f64 <= max_ms {
        return Ok(std::time::Duration::from_millis(value));
    }
    Err(anyhow!(
        "{flag} must be milliseconds, from 0 up to {}, got {}",
        compact(max_ms),
        compact(value as f64)
    ))
}

/// Unsigned integer types that options take, with their largest value.
pub trait Whole: TryFrom<i128> + Copy + Send + Sync + 'static {
    /// The largest value of the type.
    const MAX: i128;
}

macro_rules! whole {
    ($($t:ty),*) => {$(
        impl Whole for $t {
            const MAX: i128 = <$t>::MAX as i128;
        }
    )*};
}
whole!(u16, u32, u64, usize);

/// A value parser for whole numbers from `low` to `high` (at most `T`'s largest value), with a
/// message stating the range for anything else, negative numbers included (their options
/// also take `allow_negative_numbers`, so that clap hands them over). A range up to the
/// largest 64-bit value is stated as `low or more`.
pub fn whole_in<T: Whole>(s: &str, low: i128, high: i128) -> Result<T, String> {
    let high = high.min(T::MAX);
    let range = if high >= i128::from(u64::MAX) {
        format!("{low} or more")
    } else {
        format!("from {low} to {high}")
    };
    match s.trim().parse::<i128>() {
        Ok(n) if (low..=high).contains(&n) => {
            T::try_from(n).map_err(|_| format!("must be {range}, got {n}"))
        }
        Ok(n) if n > high => Err(format!("must be from {low} to {high}, got {n}")),
        Ok(n) => Err(format!("must be {range}, got {n}")),
        Err(_) => Err(format!("expected a whole number, {range}, got {s:?}")),
    }
}

/// A value parser for any whole number of `T` from 0 ([`whole_in`]).
pub fn whole<T: Whole>(s: &str) -> Result<T, String> {
    whole_in(s, 0, T::MAX)
}

/// A value parser for 0-based indices (`--scan`), with a plain message for negative ones.
pub fn index(s: &str) -> Result<usize, String> {
    match s.trim().parse::<i64>() {
        Ok(n) if n >= 0 => usize::try_from(n).map_err(|e| e.to_string()),
        Ok(n) => Err(format!("indices count from 0, got {n}")),
        Err(_) => Err(format!("expected a whole number from 0 up, got {s:?}")),
    }
}

/// Says on stderr which tables of the params file `command` does not read (`used` are the
/// tables it reads), so that a table meant for another command or algorithm is not ignored
/// silently; a table of another algorithm that would not build it (an unknown key, a wrong
/// type, a value out of range) is an error.
pub fn note_unused_tables(params: Option<&Path>, used: &[&str], command: &str) -> Result<()> {
    let Some(path) = params else {
        return Ok(());
    };
    let file = ParamsFile::load(path)?;
    if file
        .tables()
        .any(|t| laserlines_io::params::RUN_TABLES.contains(&t) && !used.contains(&t))
    {
        simulate::check_run_tables(&file)
            .map_err(|e| anyhow!("{e:#} (a table {command} does not use, checked all the same)"))?;
    }
    for table in file.tables().filter(|t| !used.contains(t)) {
        // A shared params file: a mistake in another algorithm's table is named now, not on
        // the run that first reads it.
        if ALGORITHMS.contains(&table) {
            file.extractor(table).map_err(|e| {
                anyhow!("{e} (a table {command} does not use, checked all the same)")
            })?;
        }
        let reader = if laserlines_io::params::RUN_TABLES.contains(&table) {
            "read by simulate".to_owned()
        } else if used.len() == 1 {
            format!("the algorithm is {}", used[0])
        } else {
            "not an algorithm this command runs".to_owned()
        };
        errln!(
            "laserlines: {}: [{table}] is not used by {command} ({reader})",
            file.name()
        );
    }
    Ok(())
}

/// True when `--skip-bad` (`skip_bad`) skips `e`: a bad record. A failed read of the input
/// itself ([`laserlines_io::ReadError::is_bad_record`] false: an I/O error, a corrupt gzip
/// stream) is never skipped: nothing after it can be read.
pub fn skips(skip_bad: bool, e: &laserlines_io::ReadError) -> bool {
    skip_bad && e.is_bad_record()
}

/// The error that ends a run at `e`; under `--skip-bad`, a failed read says why it was not
/// skipped.
pub fn read_error(e: laserlines_io::ReadError, skip_bad: bool) -> anyhow::Error {
    if skip_bad && !e.is_bad_record() {
        anyhow!("{e} (a failed read of the input, not a bad record: --skip-bad does not skip it)")
    } else {
        e.into()
    }
}

/// The error of an input that gave no scan: empty, or every record skipped.
pub fn no_scans(name: &str, skipped: &laserlines_io::SkipCounts) -> anyhow::Error {
    if skipped.is_empty() {
        anyhow!("{name}: no scans to read (the input holds none)")
    } else {
        anyhow!("{name}: no scans read: every record was skipped ({skipped})")
    }
}

/// True when the error comes from writing to a closed pipe (standard output closed by its
/// reader, as `| head` does): not an error of ours, and nothing to report.
pub fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// Makes the output folder `dir` (and its parents); an error saying so when a file of that
/// name is in the way.
/// `x,y,yaw_deg` (m, m, deg) of option `flag` as `[x, y, yaw]` (m, m, rad).
pub fn xy_yaw_deg(flag: &str, s: &str) -> Result<[f64; 3]> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .with_context(|| format!("{flag} {s:?}: expected x,y,yaw_deg"))?;
    match v.as_slice() {
        [x, y, yaw] if v.iter().all(|a| a.is_finite()) && yaw.abs() <= 360.0 => {
            Ok([*x, *y, yaw.to_radians()])
        }
        [_, _, yaw] if v.iter().all(|a| a.is_finite()) => Err(anyhow!(
            "{flag} {s:?}: yaw_deg must lie from -360 to 360, got {}",
            compact(*yaw)
        )),
        _ => Err(anyhow!(
            "{flag} {s:?}: expected three finite numbers x,y,yaw_deg"
        )),
    }
}

/// A spinner of scans on standard error when it is a terminal (hidden otherwise): `{pos}
/// scans {what}, N scans/s, elapsed`, the rate in whole scans per second, then the message.
pub fn scan_spinner(what: &str) -> indicatif::ProgressBar {
    use indicatif::{ProgressBar, ProgressDrawTarget, ProgressState, ProgressStyle};
    use std::io::IsTerminal as _;
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let pb = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    let template =
        format!("{{spinner}} {{pos}} scans{what}, {{rate}} scans/s, {{elapsed}} {{msg}}");
    pb.set_style(
        ProgressStyle::with_template(&template)
            .map(|s| {
                s.with_key(
                    "rate",
                    |state: &ProgressState, w: &mut dyn std::fmt::Write| {
                        let _ = w.write_str(&format!("{:.0}", state.per_sec()));
                    },
                )
            })
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    pb
}

pub(crate) fn create_output_dir(dir: &std::path::Path) -> Result<()> {
    if dir.exists() && !dir.is_dir() {
        anyhow::bail!(
            "{} is not a folder (a file of that name exists): -o takes a folder",
            dir.display()
        );
    }
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))
}

#[cfg(test)]
mod tests {
    use super::{whole, whole_in, xy_yaw_deg};

    #[test]
    fn poses_take_a_yaw_of_at_most_a_turn() {
        let [x, y, yaw] = xy_yaw_deg("--start", "1,-2,90").unwrap();
        assert_eq!((x, y), (1.0, -2.0));
        assert!((yaw - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!(xy_yaw_deg("--start", "0,0,-360").is_ok());
        let e = xy_yaw_deg("--start", "0,0,1e30").unwrap_err().to_string();
        assert!(
            e.contains("yaw_deg must lie from -360 to 360, got 1e30"),
            "{e}"
        );
        let e = xy_yaw_deg("--start", "0,nan,0").unwrap_err().to_string();
        assert!(e.contains("expected three finite numbers"), "{e}");
    }

    #[test]
    fn whole_numbers_state_their_range() {
        assert_eq!(whole::<u16>("65535"), Ok(65535));
        assert_eq!(
            whole::<u16>("-1"),
            Err("must be from 0 to 65535, got -1".to_owned())
        );
        assert_eq!(
            whole::<u16>("65536"),
            Err("must be from 0 to 65535, got 65536".to_owned())
        );
        assert_eq!(
            whole::<u64>("-3"),
            Err("must be 0 or more, got -3".to_owned())
        );
        assert_eq!(
            whole::<u64>("18446744073709551616"),
            Err("must be from 0 to 18446744073709551615, got 18446744073709551616".to_owned())
        );
        assert_eq!(whole_in::<u32>(" 7 ", 1, 99), Ok(7));
        assert_eq!(
            whole_in::<u32>("0", 1, 99),
            Err("must be from 1 to 99, got 0".to_owned())
        );
        assert_eq!(
            whole_in::<usize>("x", 1, i128::MAX),
            Err("expected a whole number, 1 or more, got \"x\"".to_owned())
        );
    }
}
