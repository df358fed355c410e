//! One module per subcommand, plus what they share.

pub mod bench;
pub mod convert;
pub mod demo;
pub mod extract;
pub mod map;
pub mod map_outputs;
pub mod relations;
pub mod render;
pub mod simulate;
pub mod simulate_mcap;
pub mod view;

use std::path::Path;

use anyhow::{Context, Result, anyhow};
use laserlines::{HoughSplit, LineExtractor};
use laserlines_io::{Format, ScanReader};

use crate::InputArgs;
use crate::params::ParamsFile;

/// The algorithms `--algorithm` accepts.
pub use laserlines::extractors::ALGORITHMS;

/// Opens the input of a command.
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
    // MCAP files, and directories (ROS 2 bags in MCAP storage), are read by laserlines-foxglove.
    let mcap = match format {
        Some(f) => f == Format::Mcap,
        None => input.input.is_dir() || Format::from_path(&input.input) == Some(Format::Mcap),
    };
    if mcap {
        let options = laserlines_foxglove::McapReadOptions::topic(input.topic.as_deref());
        return Ok(laserlines_foxglove::read::open(&input.input, &options)?);
    }
    let options = laserlines_io::ReadOptions::format(format).with_topic(input.topic.as_deref());
    Ok(laserlines_io::open_with(&input.input, &options)?)
}

/// The extractor named `algorithm` (one of [`ALGORITHMS`]), with parameters from its table
/// in `params` when given.
pub fn make_extractor(
    algorithm: &str,
    params: Option<&Path>,
) -> Result<Box<dyn LineExtractor + Send>> {
    let file = match params {
        Some(p) => ParamsFile::load(p)?,
        None => ParamsFile::default(),
    };
    file.extractor(algorithm)
}

/// A HoughSplit extractor with parameters from `params` when given.
pub fn make_hough_split(params: Option<&Path>) -> Result<HoughSplit> {
    let file = match params {
        Some(p) => ParamsFile::load(p)?,
        None => ParamsFile::default(),
    };
    HoughSplit::new(file.hough_split()?).context("hough-split parameters")
}
