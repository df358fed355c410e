//! What the bindings decide without Python: an extractor by name with parameters laid over
//! its defaults ([`make_extractor`], through the one params path of
//! [`laserlines_io::params`]), and a scan's geometry checked as the core checks it
//! ([`checked_view`]).

use laserlines::registry::{self, Algorithm, BoxedExtractor, Params, Visitor};
use laserlines::{ScanError, ScanView};
use laserlines_io::params::{ParamsFile, ParamsFileError};

/// How errors name the parameters given as keyword arguments.
pub const PARAMS_NAME: &str = "keyword arguments";

/// An extractor built by name and the parameters it runs with (every field, as a table).
pub struct Built {
    /// The extractor.
    pub extractor: BoxedExtractor,
    /// Its parameters, every field (serialized as a params file writes them).
    pub params: toml::Table,
}

/// The extractor `algorithm` with `given` laid over its defaults (a preset by `NAME = true`,
/// nested parameters as tables), as `laserlines extract --params` reads a table.
///
/// # Errors
/// The message of a [`ParamsFileError`]: an unknown algorithm or parameter, a value of the
/// wrong type or out of range, each named.
pub fn make_extractor(algorithm: &str, given: toml::Table) -> Result<Built, String> {
    let mut tables = toml::Table::new();
    if !given.is_empty() {
        tables.insert(algorithm.to_owned(), toml::Value::Table(given));
    }
    let file = match ParamsFile::from_tables(tables, PARAMS_NAME) {
        Ok(file) => file,
        // The only table is the algorithm's: an unknown table is an unknown algorithm.
        Err(ParamsFileError::UnknownTable { .. }) => {
            return Err(ParamsFileError::UnknownAlgorithm(algorithm.to_owned()).to_string());
        }
        Err(e) => return Err(e.to_string()),
    };
    struct Build<'a>(&'a ParamsFile);
    impl Visitor for Build<'_> {
        type Output = Result<Built, String>;
        fn visit<P: Params>(self, entry: &'static Algorithm<P>) -> Self::Output {
            let p = self.0.algorithm_params(entry).map_err(|e| e.to_string())?;
            let params = toml::Table::try_from(&p).map_err(|e| e.to_string())?;
            let extractor = (entry.build)(p).map_err(|e| e.to_string())?;
            Ok(Built { extractor, params })
        }
    }
    registry::visit(algorithm, Build(&file))
        .unwrap_or_else(|| Err(ParamsFileError::UnknownAlgorithm(algorithm.to_owned()).to_string()))
}

/// `range_max` as Python gives it: `inf` (the default) means no upper limit, which the core
/// writes as the largest finite number (every finite range is below it).
#[must_use]
pub fn range_max_of(range_max: f64) -> f64 {
    if range_max == f64::INFINITY {
        f64::MAX
    } else {
        range_max
    }
}

/// A view of `ranges` with the given geometry, checked as [`laserlines::Scan::validate`]
/// checks a scan (`range_max` = `inf` for no limit).
///
/// # Errors
/// The range limits in Python's terms (`inf` as given), else the core's `ScanError` naming the
/// first problem.
pub fn checked_view(
    ranges: &[f64],
    angle_min: f64,
    angle_increment: f64,
    range_min: f64,
    range_max: f64,
) -> Result<ScanView<'_>, String> {
    ScanView::new(
        angle_min,
        angle_increment,
        range_min,
        range_max_of(range_max),
        ranges,
    )
    .map_err(|e| match e {
        // The limits as given: the core's message shows `inf` as the largest finite number.
        ScanError::BadRangeLimits { .. } => format!(
            "range limits must satisfy 0 <= range_min < range_max, range_min finite and \
             range_max finite or inf (no limit), got range_min = {range_min}, range_max = \
             {range_max}"
        ),
        e => e.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> toml::Table {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn parameters_lay_over_the_defaults_and_errors_name_them() {
        let built = make_extractor("hough-split", table("ring_step = 0.05\npaper = true")).unwrap();
        assert_eq!(built.extractor.name(), "hough-split");
        assert_eq!(built.params["ring_step"].as_float(), Some(0.05));
        // The paper preset's range limits, under the key given.
        assert_eq!(
            built.params["range_limits"].as_array().map(Vec::len),
            Some(2)
        );
        let iepf = make_extractor("iepf", table("breakpoints = { noise = 0.02 }")).unwrap();
        assert_eq!(iepf.params["breakpoints"]["noise"].as_float(), Some(0.02));
        assert_eq!(
            make_extractor("hough-split", table("ring_stp = 1.0"))
                .err()
                .unwrap()[..62],
            *"keyword arguments: [hough-split]: unknown field `ring_stp`, ex"
        );
        assert_eq!(
            make_extractor("em", table("inlier_probability = 2.0"))
                .err()
                .unwrap(),
            "keyword arguments: [em] inlier_probability must lie in (0, 1), got 2"
        );
        let e = make_extractor("hough", toml::Table::new()).err().unwrap();
        assert!(
            e.starts_with("unknown algorithm \"hough\": expected one of hough-split"),
            "{e}"
        );
        let e = make_extractor("hough", table("x = 1")).err().unwrap();
        assert!(e.starts_with("unknown algorithm \"hough\""), "{e}");
        for name in registry::ALGORITHMS {
            assert_eq!(
                make_extractor(name, toml::Table::new())
                    .unwrap()
                    .extractor
                    .name(),
                *name
            );
        }
    }

    #[test]
    fn geometry_is_checked_and_inf_is_no_limit() {
        let ranges = [1.0, 1e300];
        let v = checked_view(&ranges, 0.0, 0.1, 0.0, f64::INFINITY).unwrap();
        assert_eq!(v.count_valid(v.range_window(None)), 2);
        assert_eq!(
            checked_view(&ranges, 0.0, 0.0, 0.0, 1.0).unwrap_err(),
            ScanError::BadAngleIncrement(0.0).to_string()
        );
        assert!(checked_view(&ranges, 0.0, 0.1, 2.0, 1.0).is_err());
        assert!(checked_view(&ranges, 0.0, 0.1, 0.0, f64::NAN).is_err());
        // The limits as Python gave them, inf as inf.
        assert_eq!(
            checked_view(&ranges, 0.0, 0.1, f64::NAN, f64::INFINITY).unwrap_err(),
            "range limits must satisfy 0 <= range_min < range_max, range_min finite and \
             range_max finite or inf (no limit), got range_min = NaN, range_max = inf"
        );
        // Reversed scans are scans.
        assert!(checked_view(&ranges, 0.0, -0.1, 0.0, 1.0).is_ok());
    }
}
