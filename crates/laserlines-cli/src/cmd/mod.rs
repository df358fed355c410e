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
pub mod view;

use std::path::Path;

use anyhow::{Context, Result, anyhow};
use laserlines::HoughSplit;
use laserlines::registry::{self, BoxedExtractor};
use laserlines_io::params::ParamsFile;
use laserlines_io::{Format, ScanReader};

use crate::InputArgs;

/// The algorithms `--algorithm` accepts.
pub use laserlines::registry::ALGORITHMS;

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

/// The extractor named `algorithm` (one of [`ALGORITHMS`]), with parameters from its table
/// in `params` when given.
pub fn make_extractor(algorithm: &str, params: Option<&Path>) -> Result<BoxedExtractor> {
    Ok(ParamsFile::load_or_default(params)?.extractor(algorithm)?)
}

/// A HoughSplit extractor with parameters from `params` when given.
pub fn make_hough_split(params: Option<&Path>) -> Result<HoughSplit> {
    let file = ParamsFile::load_or_default(params)?;
    let p = file.algorithm_params(&registry::HOUGH_SPLIT)?;
    HoughSplit::new(p).context("hough-split parameters")
}
