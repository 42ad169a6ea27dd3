//! Errors of the core library. Each says what went wrong and what to change.

use std::fmt;
use std::sync::Arc;

/// A place in a pipeline file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    /// The file name as the user gave it (or `<preset NAME>`).
    pub file: Arc<str>,
    /// 1-based line.
    pub line: usize,
    /// 1-based column.
    pub column: usize,
}

impl Location {
    /// The location of byte `offset` in `source`.
    pub fn of_offset(file: &Arc<str>, source: &str, offset: usize) -> Location {
        let offset = offset.min(source.len());
        let before = &source[..offset];
        let line = before.bytes().filter(|&b| b == b'\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = source[line_start..offset].chars().count() + 1;
        Location {
            file: file.clone(),
            line,
            column,
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file, self.line, self.column)
    }
}

/// A pipeline configuration that cannot be used as written.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{location}: {key}: {message}")]
pub struct ConfigError {
    /// Where in the file.
    pub location: Location,
    /// The key, dotted from the top (`world.min_length`, `route.amplitude`).
    pub key: String,
    /// What is wrong and what to write instead.
    pub message: String,
}

/// Why a world could not be generated.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The pipeline file is malformed or names something unknown.
    #[error(transparent)]
    Config(#[from] ConfigError),

    /// A requested structure did not fit, or its routes could not be laid, within the retry
    /// bound. Use a larger grid (`world.min_length`, `world.rows`/`world.cols`), fewer
    /// structures, or `exact = false`.
    #[error(
        "level {level}: {what} (after {attempts} attempts with derived seeds on a {rows} x {cols} grid). \
         To fix: {advice}"
    )]
    Unsatisfiable {
        /// Level index.
        level: usize,
        /// Which constraint failed on the last attempt.
        what: String,
        /// How many attempts were made.
        attempts: u32,
        /// Grid rows.
        rows: usize,
        /// Grid columns.
        cols: usize,
        /// What to change.
        advice: String,
    },

    /// An imported occupancy grid has a shape, type or value the tool cannot read.
    #[error("{source_name}: {message}")]
    Import {
        /// The file or array name.
        source_name: String,
        /// What is wrong and what the tool accepts.
        message: String,
    },

    /// A component (route descriptor, shape, tile set, exporter) failed.
    #[error("{component} '{name}': {message}")]
    Component {
        /// What kind of component.
        component: &'static str,
        /// Its `type` name.
        name: String,
        /// What went wrong.
        message: String,
    },
}
