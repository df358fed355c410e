//! Real URG-04LX data bundled with the crate, so the demo runs without any download.
//!
//! The excerpt is the first 40 scans (lines 1..=40) of `examples/exp1.dat` of the BreezySLAM
//! repository (`simondlevy/BreezySLAM`, commit `f9ae4fc0d0f66b2ed379e17f8707dd94fec2198f`,
//! GNU LGPL v3 as the repository states), recorded with a Hokuyo URG-04LX on the Paris Mines
//! Tech robot of CoreSLAM. See `data/README.md` in the repository.

use std::io::Cursor;

use crate::error::ReadError;
use crate::format::Format;
use crate::reader::{ScanReader, from_reader};
use crate::record::ScanRecord;

/// The excerpt, gzipped BreezySLAM `.dat` text ([`crate::breezy`]).
pub const URG04LX_EXCERPT: &[u8] = include_bytes!("../../../data/urg04lx-exp1-excerpt.dat.gz");

/// The excerpt's name, used in messages.
pub const URG04LX_EXCERPT_NAME: &str = "urg04lx-exp1-excerpt.dat.gz";

/// Number of scans in the excerpt.
pub const URG04LX_EXCERPT_SCANS: usize = 40;

/// Reads the whole bundled excerpt ([`URG04LX_EXCERPT_SCANS`] records, with stamps and
/// odometry poses).
///
/// # Errors
/// Never in practice (the data is checked by the tests); the reader's first error otherwise.
pub fn urg04lx_excerpt() -> Result<Vec<ScanRecord>, ReadError> {
    urg04lx_excerpt_reader()?.collect()
}

/// A streaming reader over the bundled excerpt.
///
/// # Errors
/// Never in practice; see [`urg04lx_excerpt`].
pub fn urg04lx_excerpt_reader() -> Result<ScanReader, ReadError> {
    from_reader(
        URG04LX_EXCERPT_NAME,
        Cursor::new(URG04LX_EXCERPT),
        Format::BreezyDat,
    )
}
