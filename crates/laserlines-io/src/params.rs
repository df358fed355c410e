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
    #[error(
        "unknown preset {preset:?} of {algorithm}: expected {}",
        known_presets(expected)
    )]
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

/// What a [`ParamsFileError::UnknownPreset`] says was expected.
fn known_presets(expected: &[&str]) -> String {
    if expected.is_empty() {
        "none (it has no presets)".to_owned()
    } else {
        format!("one of {}", expected.join(", "))
    }
}

/// A parsed params file (see the [module docs](self)).
#[derive(Debug, Clone, Default)]
pub struct ParamsFile {
    name: String,
    tables: toml::Table,
}

impl ParamsFile {
    /// [`ParamsFile::load_or_default`], then [`ParamsFile::with_preset`] for `algorithm`
    /// when `preset` is given: how the commands read `--params` and `--preset`.
    ///
    /// # Errors
    /// As those two.
    pub fn load_with_preset(
        path: Option<&Path>,
        algorithm: &str,
        preset: Option<&str>,
    ) -> Result<Self, ParamsFileError> {
        let file = Self::load_or_default(path)?;
        match preset {
            Some(preset) => file.with_preset(algorithm, preset),
            None => Ok(file),
        }
    }

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
    /// table held `preset = true` in place of any preset it names with `true` or `false` (the
    /// table is created when the file has none; what the table sets is still laid over the
    /// preset; a preset key with a value of another type stays, and is an error when read).
    /// The `--preset` option of the commands: see [`ParamsFile::load_with_preset`].
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
                if matches!(t.get(*other), Some(toml::Value::Boolean(_))) {
                    t.remove(*other);
                }
            }
            t.insert(preset.to_owned(), toml::Value::Boolean(true));
        }
        Ok(self)
    }

    /// The keys the file gives in table `table`, in the order of their names (none without
    /// it).
    pub fn keys(&self, table: &str) -> impl Iterator<Item = &str> {
        let given = match self.tables.get(table) {
            Some(toml::Value::Table(t)) => Some(t),
            _ => None,
        };
        given.into_iter().flat_map(|t| t.keys().map(String::as_str))
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
                let mut chosen: Option<&str> = None;
                for (preset, make) in algorithm.presets {
                    match given.remove(*preset) {
                        None => {}
                        Some(toml::Value::Boolean(true)) => {
                            if let Some(first) = chosen {
                                let message = format!(
                                    "a second preset: {first} = true and {preset} = true; \
                                     set at most one preset to true"
                                );
                                return Err(self.key_error(table, preset, message));
                            }
                            chosen = Some(preset);
                            start = make();
                        }
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
mod tests;
