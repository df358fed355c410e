//! Params files: TOML with one table per extractor of the registry
//! ([`laserlines::registry`]: `[hough-split]`, `[iepf]`, ...), whose keys are the fields of
//! the extractor's params struct (nested structs as dotted keys, `breakpoints.noise = 0.02`,
//! or sub-tables, `[iepf.breakpoints]`), SI units, angles in radians. A key left out keeps
//! the default; a table may start from a preset instead (`paper = true` in `[hough-split]`).
//! Unknown tables and keys, values of the wrong type and values out of range are errors
//! naming the file, the table and the key as written.
//!
//! `laserlines simulate` also reads [`RUN_TABLES`]: `[robot]`, `[simulator]` and
//! `[explorer]`, through [`ParamsFile::read`]; other commands leave them alone.
//!
//! Values are read with serde: a table is laid over the serialized defaults (or the preset)
//! and the result deserialized into the params struct, so that every field of the struct is
//! a key, and a field added to a struct is a key at once.
//!
//! ```
//! use laserlines::registry;
//! use laserlines_io::params::ParamsFile;
//! let file = ParamsFile::parse(
//!     "[hough-split]\npaper = true\nring_step = 0.05\n[iepf]\nbreakpoints.noise = 0.02\n",
//!     "my.toml",
//! )?;
//! let hs = file.algorithm_params(&registry::HOUGH_SPLIT)?;
//! assert_eq!(hs.ring_step, 0.05);
//! assert_eq!(hs.range_limits, Some(laserlines::RangeWindow::PAPER));
//! assert_eq!(file.extractor("iepf")?.name(), "iepf");
//! let bad = ParamsFile::parse("[iepf]\nsplit_distance = -1.0\n", "bad.toml")?;
//! let e = bad.extractor("iepf").err().unwrap().to_string();
//! assert_eq!(e, "bad.toml: [iepf] split_distance must be finite and >= 0, got -1");
//! # Ok::<(), laserlines_io::params::ParamsFileError>(())
//! ```

use std::path::Path;

use laserlines::ParamsError;
use laserlines::registry::{self, Algorithm, BoxedExtractor, Params, Visitor};
use serde::Serialize;
use serde::de::DeserializeOwned;

/// The tables of a params file that are not extractors, read by `laserlines simulate`.
pub const RUN_TABLES: &[&str] = &["robot", "simulator", "explorer"];

/// An error of a params file, naming the file (and the table and key).
#[derive(Debug, thiserror::Error)]
pub enum ParamsFileError {
    /// The file cannot be read.
    #[error("cannot read params file {file}: {source}")]
    Read {
        /// the file
        file: String,
        /// why
        source: std::io::Error,
    },
    /// The file is not TOML.
    #[error("{file}: invalid params file: {message}")]
    Syntax {
        /// the file
        file: String,
        /// the TOML parser's message, with line and column
        message: String,
    },
    /// A table that no extractor and no command reads.
    #[error("{file}: unknown table [{table}]: expected one of {expected}")]
    UnknownTable {
        /// the file
        file: String,
        /// the table
        table: String,
        /// the tables there may be
        expected: String,
    },
    /// A key that is not a field, or a value of the wrong type.
    #[error("{file}: [{table}]{}: {message}", if key.is_empty() { String::new() } else { format!(" {key}") })]
    Key {
        /// the file
        file: String,
        /// the table
        table: String,
        /// the key as written (empty when the problem is the table itself)
        key: String,
        /// what is wrong
        message: String,
    },
    /// A value out of its range.
    #[error("{file}: [{table}] {problem}")]
    Invalid {
        /// the file
        file: String,
        /// the table
        table: String,
        /// the field and its range
        problem: ParamsError,
    },
    /// A preset the algorithm does not have (`--preset`).
    #[error("unknown preset {preset:?} of {algorithm}: expected {}", if expected.is_empty() { "none (it has no presets)".to_owned() } else { format!("one of {}", expected.join(", ")) })]
    UnknownPreset {
        /// the algorithm
        algorithm: String,
        /// the preset asked for
        preset: String,
        /// the presets it has
        expected: Vec<&'static str>,
    },
    /// An algorithm the registry does not have.
    #[error("unknown algorithm {0:?}: expected one of {list}", list = registry::ALGORITHMS.join(", "))]
    UnknownAlgorithm(String),
}

/// A parsed params file (see the [module docs](self)).
#[derive(Debug, Clone, Default)]
pub struct ParamsFile {
    name: String,
    tables: toml::Table,
}

impl ParamsFile {
    /// Reads and parses `path`.
    ///
    /// # Errors
    /// [`ParamsFileError::Read`], [`ParamsFileError::Syntax`], or
    /// [`ParamsFileError::UnknownTable`] for a table that is neither an algorithm nor one of
    /// [`RUN_TABLES`].
    pub fn load(path: &Path) -> Result<Self, ParamsFileError> {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| ParamsFileError::Read {
            file: name.clone(),
            source,
        })?;
        Self::parse(&text, &name)
    }

    /// [`ParamsFile::load`] of `path` when given, else an empty file (every default).
    ///
    /// # Errors
    /// As [`ParamsFile::load`].
    pub fn load_or_default(path: Option<&Path>) -> Result<Self, ParamsFileError> {
        path.map_or_else(|| Ok(Self::default()), Self::load)
    }

    /// Parses `text`, naming it `name` in errors.
    ///
    /// # Errors
    /// As [`ParamsFile::load`], but for reading.
    pub fn parse(text: &str, name: &str) -> Result<Self, ParamsFileError> {
        let tables: toml::Table = toml::from_str(text).map_err(|e| ParamsFileError::Syntax {
            file: name.to_owned(),
            message: e.to_string().trim_end().to_owned(),
        })?;
        Self::from_tables(tables, name)
    }

    /// The tables of a params file given as values rather than text (keyword arguments of
    /// another language's binding), named `name` in errors.
    ///
    /// # Errors
    /// As [`ParamsFile::parse`], but for the syntax.
    pub fn from_tables(tables: toml::Table, name: &str) -> Result<Self, ParamsFileError> {
        let file = Self {
            name: name.to_owned(),
            tables,
        };
        for (table, value) in &file.tables {
            let known = registry::ALGORITHMS.contains(&table.as_str())
                || RUN_TABLES.contains(&table.as_str());
            if !known {
                let expected = registry::ALGORITHMS
                    .iter()
                    .chain(RUN_TABLES)
                    .map(|t| format!("[{t}]"))
                    .collect::<Vec<_>>()
                    .join(", ");
                return Err(ParamsFileError::UnknownTable {
                    file: file.name.clone(),
                    table: table.clone(),
                    expected,
                });
            }
            if !value.is_table() {
                return Err(file.key_error(table, "", "expected a table".to_owned()));
            }
        }
        Ok(file)
    }

    /// The file's name, as errors give it.
    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The names of the file's tables, in name order.
    pub fn tables(&self) -> impl Iterator<Item = &str> {
        self.tables.keys().map(String::as_str)
    }

    /// True when the file has the table `table`.
    #[must_use]
    pub fn has(&self, table: &str) -> bool {
        self.tables.contains_key(table)
    }

    /// The file with `algorithm`'s table starting from its preset called `preset`, as if the
    /// table held `preset = true` in place of any preset it names (the table is created when
    /// the file has none; what the table sets is still laid over the preset). The `--preset`
    /// option of the commands.
    ///
    /// # Errors
    /// [`ParamsFileError::UnknownAlgorithm`], or [`ParamsFileError::UnknownPreset`] naming
    /// the algorithm's presets.
    pub fn with_preset(mut self, algorithm: &str, preset: &str) -> Result<Self, ParamsFileError> {
        let known = registry::presets(algorithm)
            .ok_or_else(|| ParamsFileError::UnknownAlgorithm(algorithm.to_owned()))?;
        if !known.contains(&preset) {
            return Err(ParamsFileError::UnknownPreset {
                algorithm: algorithm.to_owned(),
                preset: preset.to_owned(),
                expected: known,
            });
        }
        let table = self
            .tables
            .entry(algorithm)
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        if let toml::Value::Table(t) = table {
            for other in known.iter().filter(|&&n| n != preset) {
                t.remove(*other);
            }
            t.insert(preset.to_owned(), toml::Value::Boolean(true));
        }
        Ok(self)
    }

    /// The table `table` laid over `preset` (see the [module docs](self)); `preset` itself
    /// when the file has no such table. Not validated: see [`ParamsFile::invalid`].
    ///
    /// # Errors
    /// [`ParamsFileError::Key`] for an unknown key or a value of the wrong type.
    pub fn read<P: Serialize + DeserializeOwned>(
        &self,
        table: &str,
        preset: P,
    ) -> Result<P, ParamsFileError> {
        let Some(toml::Value::Table(given)) = self.tables.get(table) else {
            return Ok(preset);
        };
        self.overlay(table, preset, given)
    }

    /// [`ParamsFile::read`], then `check` on the result.
    ///
    /// # Errors
    /// As [`ParamsFile::read`], and [`ParamsFileError::Invalid`] with `check`'s error.
    pub fn read_valid<P: Serialize + DeserializeOwned>(
        &self,
        table: &str,
        preset: P,
        check: impl FnOnce(&P) -> Result<(), ParamsError>,
    ) -> Result<P, ParamsFileError> {
        let p = self.read(table, preset)?;
        check(&p).map_err(|e| self.invalid(table, e))?;
        Ok(p)
    }

    /// The error of a value of table `table` out of its range.
    #[must_use]
    pub fn invalid(&self, table: &str, problem: ParamsError) -> ParamsFileError {
        ParamsFileError::Invalid {
            file: self.name.clone(),
            table: table.to_owned(),
            problem,
        }
    }

    /// The parameters of `algorithm`: its defaults, or the preset the table names, with the
    /// table laid over them, validated.
    ///
    /// # Errors
    /// [`ParamsFileError::Key`] for an unknown key, a value of the wrong type or an unknown
    /// preset; [`ParamsFileError::Invalid`] for a value out of range.
    pub fn algorithm_params<P: Params>(
        &self,
        algorithm: &'static Algorithm<P>,
    ) -> Result<P, ParamsFileError> {
        self.algorithm_params_over(algorithm, (algorithm.defaults)())
    }

    /// [`ParamsFile::algorithm_params`] starting from `base` instead of the defaults (a
    /// preset the table names still replaces it), e.g. the navigation preset of
    /// `hough-split` for `simulate`.
    ///
    /// # Errors
    /// As [`ParamsFile::algorithm_params`].
    pub fn algorithm_params_over<P: Params>(
        &self,
        algorithm: &'static Algorithm<P>,
        base: P,
    ) -> Result<P, ParamsFileError> {
        let table = algorithm.name;
        let p = match self.tables.get(table) {
            Some(toml::Value::Table(given)) => {
                let mut given = given.clone();
                let mut start = base;
                for (preset, make) in algorithm.presets {
                    match given.remove(*preset) {
                        None => {}
                        Some(toml::Value::Boolean(true)) => start = make(),
                        Some(toml::Value::Boolean(false)) => {}
                        Some(other) => {
                            let message = format!("expected true or false, found {other}");
                            return Err(self.key_error(table, preset, message));
                        }
                    }
                }
                self.overlay(table, start, &given)?
            }
            _ => base,
        };
        (algorithm.build)(p.clone()).map_err(|e| self.invalid(table, e))?;
        Ok(p)
    }

    /// The extractor called `algorithm`, with the parameters of its table
    /// ([`ParamsFile::algorithm_params`]).
    ///
    /// # Errors
    /// As [`ParamsFile::algorithm_params`], and [`ParamsFileError::UnknownAlgorithm`].
    pub fn extractor(&self, algorithm: &str) -> Result<BoxedExtractor, ParamsFileError> {
        self.extractor_for_noise(algorithm, 1.0)
    }

    /// [`ParamsFile::extractor`] with the thresholds that stand for the sensor's noise
    /// multiplied by `noise_scale` ([`Algorithm::scale_noise`]; `laserlines bench` gives
    /// every extractor the noise of the simulated sensor this way).
    ///
    /// # Errors
    /// As [`ParamsFile::extractor`].
    pub fn extractor_for_noise(
        &self,
        algorithm: &str,
        noise_scale: f64,
    ) -> Result<BoxedExtractor, ParamsFileError> {
        struct Build<'a>(&'a ParamsFile, f64);
        impl Visitor for Build<'_> {
            type Output = Result<BoxedExtractor, ParamsFileError>;
            fn visit<P: Params>(self, entry: &'static Algorithm<P>) -> Self::Output {
                let mut p = self.0.algorithm_params(entry)?;
                if self.1 != 1.0 {
                    (entry.scale_noise)(&mut p, self.1);
                }
                (entry.build)(p).map_err(|e| self.0.invalid(entry.name, e))
            }
        }
        registry::visit(algorithm, Build(self, noise_scale))
            .unwrap_or_else(|| Err(ParamsFileError::UnknownAlgorithm(algorithm.to_owned())))
    }

    fn key_error(&self, table: &str, key: &str, message: String) -> ParamsFileError {
        ParamsFileError::Key {
            file: self.name.clone(),
            table: table.to_owned(),
            key: key.to_owned(),
            message,
        }
    }

    /// `given` laid over the serialized `start`, deserialized.
    fn overlay<P: Serialize + DeserializeOwned>(
        &self,
        table: &str,
        start: P,
        given: &toml::Table,
    ) -> Result<P, ParamsFileError> {
        let mut base = toml::Table::try_from(&start)
            .map_err(|e| self.key_error(table, "", format!("cannot write the defaults: {e}")))?;
        merge(&mut base, given);
        P::deserialize(toml::Value::Table(base)).map_err(|e| {
            // The message, then "in `key.path`" when a key is to blame.
            let message = e.message().to_owned();
            let shown = e.to_string();
            let key = shown
                .strip_prefix(message.as_str())
                .and_then(|rest| rest.trim().strip_prefix("in `"))
                .and_then(|rest| rest.strip_suffix('`'))
                .unwrap_or("");
            self.key_error(table, key, message)
        })
    }
}

/// Lays `over` onto `base`, table into table.
fn merge(base: &mut toml::Table, over: &toml::Table) {
    for (key, value) in over {
        match (base.get_mut(key), value) {
            (Some(toml::Value::Table(b)), toml::Value::Table(o)) => merge(b, o),
            _ => {
                base.insert(key.clone(), value.clone());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use laserlines::extractors::SplitMergeParams;
    use laserlines::{HoughSplitParams, RangeWindow, Weight};

    fn file(text: &str) -> ParamsFile {
        ParamsFile::parse(text, "p.toml").unwrap()
    }

    fn error(text: &str, algorithm: &str) -> String {
        match ParamsFile::parse(text, "p.toml") {
            Ok(f) => f.extractor(algorithm).err().unwrap().to_string(),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn hough_split_noise_is_auto_a_preset_or_a_model() {
        use laserlines::{NoiseModel, RangeNoise};
        let p = |text: &str| file(text).algorithm_params(&registry::HOUGH_SPLIT);
        assert_eq!(p("").unwrap().noise, NoiseModel::Auto);
        assert_eq!(
            p("[hough-split]\nnoise = \"ydlidar-x4\"\n").unwrap().noise,
            NoiseModel::Fixed(RangeNoise::preset("ydlidar-x4").unwrap())
        );
        assert_eq!(
            p("[hough-split]\nnoise = { sigma_min = 0.004, fraction = 0.002 }\n")
                .unwrap()
                .noise,
            NoiseModel::Fixed(RangeNoise::new(0.004, 0.002))
        );
        assert_eq!(
            p("[hough-split]\nnoise = \"auto\"\n").unwrap().noise,
            NoiseModel::Auto
        );
        let e = p("[hough-split]\nnoise = \"cheap\"\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("unknown noise \"cheap\"") && e.contains("urg-04lx"),
            "{e}"
        );
        let e = p("[hough-split]\nnoise = { sigma_min = -0.01, fraction = 0.0 }\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("noise.sigma_min"), "{e}");
    }

    #[test]
    fn a_preset_by_option_replaces_the_tables_preset_and_keeps_its_keys() {
        let none = ParamsFile::default()
            .with_preset("hough-split", "walls")
            .unwrap();
        assert_eq!(
            none.algorithm_params(&registry::HOUGH_SPLIT).unwrap(),
            HoughSplitParams::walls()
        );
        let f = file("[hough-split]\npaper = true\nmin_range = 0.3\n")
            .with_preset("hough-split", "walls")
            .unwrap();
        let p = f.algorithm_params(&registry::HOUGH_SPLIT).unwrap();
        assert_eq!(
            p,
            HoughSplitParams {
                min_range: 0.3,
                ..HoughSplitParams::walls()
            }
        );
        let e = ParamsFile::default()
            .with_preset("hough-split", "wall")
            .unwrap_err();
        assert_eq!(
            e.to_string(),
            "unknown preset \"wall\" of hough-split: expected one of paper, navigation, walls"
        );
        let e = ParamsFile::default()
            .with_preset("iepf", "walls")
            .unwrap_err();
        assert_eq!(
            e.to_string(),
            "unknown preset \"walls\" of iepf: expected none (it has no presets)"
        );
        assert!(matches!(
            ParamsFile::default().with_preset("nope", "walls"),
            Err(ParamsFileError::UnknownAlgorithm(_))
        ));
    }

    #[test]
    fn tables_lay_over_defaults_and_presets() {
        let f =
            file("[hough-split]\nring_step = 0.05\nweight = \"one\"\nrange_limits = [0.1, 2.0]\n");
        let p = f.algorithm_params(&registry::HOUGH_SPLIT).unwrap();
        assert_eq!(p.ring_step, 0.05);
        assert_eq!(p.weight, Weight::One);
        assert_eq!(p.range_limits, Some(RangeWindow::new(0.1, 2.0)));
        assert_eq!(p.criterion, HoughSplitParams::default().criterion);
        // No table: the defaults; the paper preset.
        let none = ParamsFile::default();
        assert_eq!(
            none.algorithm_params(&registry::HOUGH_SPLIT).unwrap(),
            HoughSplitParams::default()
        );
        let paper = file("[hough-split]\npaper = true\n");
        assert_eq!(
            paper.algorithm_params(&registry::HOUGH_SPLIT).unwrap(),
            HoughSplitParams::paper()
        );
        // iepf and split-and-merge start from their own defaults.
        let f = file("[iepf]\nsplit_distance = 0.02\n[split-and-merge]\nmin_cluster_points = 5\n");
        let iepf = f.algorithm_params(&registry::IEPF).unwrap();
        assert_eq!(iepf.split_distance, 0.02);
        assert_eq!(iepf.breakpoints.noise, 0.01);
        let sam = f.algorithm_params(&registry::SPLIT_AND_MERGE).unwrap();
        assert_eq!(sam.min_cluster_points, 5);
        assert_eq!(
            sam.breakpoints,
            SplitMergeParams::split_and_merge().breakpoints
        );
        // Nested keys, dotted or as a sub-table.
        let dotted = file("[iepf]\nbreakpoints.max_gap = 4\nfilter.min_length = 0.3\n");
        let table = file("[iepf.breakpoints]\nmax_gap = 4\n[iepf.filter]\nmin_length = 0.3\n");
        for f in [dotted, table] {
            let p = f.algorithm_params(&registry::IEPF).unwrap();
            assert_eq!((p.breakpoints.max_gap, p.filter.min_length), (4, 0.3));
            assert_eq!(p.breakpoints.incidence, 10f64.to_radians());
        }
    }

    #[test]
    fn every_field_of_every_params_struct_is_a_key() {
        // The defaults written out as a table read back as the defaults.
        struct RoundTrip;
        impl Visitor for RoundTrip {
            type Output = ();
            fn visit<P: Params>(self, entry: &'static Algorithm<P>) {
                let start = (entry.defaults)();
                let mut tables = toml::Table::new();
                tables.insert(
                    entry.name.to_owned(),
                    toml::Value::Table(toml::Table::try_from(&start).unwrap()),
                );
                let text = toml::to_string(&tables).unwrap();
                let f = ParamsFile::parse(&text, "all.toml").unwrap();
                assert_eq!(f.algorithm_params(entry).unwrap(), start, "{text}");
                let bad = format!("[{}]\nno_such_key = 1\n", entry.name);
                let e = ParamsFile::parse(&bad, "bad.toml")
                    .unwrap()
                    .extractor(entry.name)
                    .err()
                    .unwrap()
                    .to_string();
                assert!(e.contains("no_such_key") && e.contains(entry.name), "{e}");
            }
        }
        for name in registry::ALGORITHMS {
            registry::visit(name, RoundTrip);
        }
    }

    #[test]
    fn errors_name_the_file_the_table_and_the_key() {
        assert_eq!(
            error("[em]\ninlier_probability = 2.0\n", "em"),
            "p.toml: [em] inlier_probability must lie in (0, 1), got 2"
        );
        assert_eq!(
            error("[hough-split]\nring_stp = 1.0\n", "hough-split"),
            "p.toml: [hough-split]: unknown field `ring_stp`, expected one of `ring_step`, \
             `sector_step`, `window`, `weight`, `criterion`, `group_gap`, `noise`, \
             `noise_floor`, `bridge_beams`, `bridge_incidence`, `bridge_sigmas`, \
             `bridge_max_gap`, `min_segment_points`, `split_sigmas`, `split_significance`, \
             `merge_collinear`, `refine_ends`, `min_line_points`, `min_line_length`, \
             `max_rms_sigmas`, `max_alpha_sd`, `max_r_sd`, `remove_mixed_pixels`, `min_range`, \
             `range_limits`"
        );
        assert_eq!(
            error("[iepf]\nbreakpoints.noise = \"x\"\n", "iepf"),
            "p.toml: [iepf] breakpoints.noise: invalid type: string \"x\", expected f64"
        );
        assert_eq!(
            error("[iepf]\nbreakpoints.incidence = 2\n", "iepf"),
            "p.toml: [iepf] breakpoints.incidence must lie in (0, 1.5707963267948966), got 2"
        );
        assert_eq!(
            error("[hough-split]\nweight = \"square\"\n", "hough-split"),
            "p.toml: [hough-split] weight: unknown variant `square`, expected `one` or `range`"
        );
        assert_eq!(
            error("[hough-split]\npaper = 1\n", "hough-split"),
            "p.toml: [hough-split] paper: expected true or false, found 1"
        );
        assert!(error("[no-such-algorithm]\n", "iepf").starts_with("p.toml: unknown table"));
        assert!(error("[iepf\n", "iepf").starts_with("p.toml: invalid params file"));
        assert_eq!(
            ParamsFile::default()
                .extractor("nope")
                .err()
                .unwrap()
                .to_string(),
            "unknown algorithm \"nope\": expected one of hough-split, iterative-hough, \
             split-and-merge, iepf, incremental, line-regression, ransac, em"
        );
        // The tables of the simulator are accepted and left alone.
        let f = file("[robot]\nwhatever = 1\n[hough-split]\n");
        assert!(f.has("robot") && f.extractor("hough-split").is_ok());
    }
}
