//! The one error type of the application library: what a request can fail with, each variant
//! saying what to change. The command line prints [`message`] of it; the Python package
//! raises the `subtgraph.Error` subclass its variant belongs to, with the same text.

use std::path::PathBuf;

use subtgraph_core::error::ConfigError;
use subtgraph_schema::SchemaError;

use crate::folder::FolderError;

/// Why a request failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A pipeline file or value is malformed or names something unknown (file, line, column
    /// and key).
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// Generation refused or failed: a constraint that does not fit, a world too large, a
    /// component's failure (the core's message says what to change).
    #[error(transparent)]
    Core(#[from] subtgraph_core::Error),
    /// A plugin library was refused (missing, another API version, another compiler).
    #[error(transparent)]
    Plugin(#[from] subtgraph_plugins::PluginError),
    /// Two components of one kind share a `type` name (a plugin's or a Python one's and
    /// another's).
    #[error(transparent)]
    DuplicateName(#[from] subtgraph_core::registry::DuplicateName),
    /// A loaded plugin failed while it ran (it says what happened).
    #[error("{0}")]
    PluginFailed(String),
    /// A folder could not be written, or `--out` is taken by something `--force` may not
    /// replace.
    #[error(transparent)]
    Folder(#[from] FolderError),
    /// A command-line flag or keyword argument has a value out of range or malformed; the
    /// message names it and what it takes.
    #[error("{0}")]
    Usage(String),
    /// No preset of that name.
    #[error("unknown preset '{name}'; the presets are: {known}")]
    UnknownPreset {
        /// The name asked for (cut to a readable length).
        name: String,
        /// The presets, comma separated.
        known: String,
    },
    /// An exporter that writes geometry in a world without a tile set.
    #[error(
        "exporter '{exporter}' writes geometry, but the pipeline has no [tileset]: add one (e.g. [tileset] type = \"cave\") or pass --tileset NAME"
    )]
    NoTileset {
        /// The exporter's name.
        exporter: String,
    },
    /// The tile set refused the layout or failed to mesh it.
    #[error("tile set '{name}': {source}")]
    TileSet {
        /// The tile set's name.
        name: String,
        /// What it said.
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// The world's survey failed: its artifacts found no room (the message says which key
    /// to relax).
    #[error(transparent)]
    Survey(Box<subtgraph_survey::SurveyError>),
    /// Writing the files every world folder has failed.
    #[error(transparent)]
    WorldFiles(subtgraph_core::export::ExportError),
    /// An exporter failed.
    #[error("exporter '{exporter}': {source}")]
    Export {
        /// The exporter's name.
        exporter: String,
        /// What it said.
        source: subtgraph_core::export::ExportError,
    },
    /// A pipeline that parses but whose world cannot be made (`validate`).
    #[error("{} is well-formed but its world cannot be made: {source}", .pipeline.display())]
    Unmakeable {
        /// The pipeline file.
        pipeline: PathBuf,
        /// Why not (boxed: the core's errors are large, and this one is rare).
        source: Box<subtgraph_core::Error>,
    },
    /// The work would need more memory than `--max-memory` allows: the estimate and what to
    /// change.
    #[error("{0}")]
    TooLarge(String),
    /// A file the user gave (a pipeline, reports, a map, a grid, a world folder) could not be
    /// read or is not what it should be: the message names it, and the row, point or entry.
    #[error("{0}")]
    Input(String),
    /// A `.npy` file is not a readable array.
    #[error("{file}: {source}")]
    Npy {
        /// The file.
        file: String,
        /// What is wrong with it.
        source: subtgraph_core::npy::NpyError,
    },
    /// A sensor sequence was refused or failed (`sense`): the sensors crate's message says what
    /// to change.
    #[error(transparent)]
    Sense(#[from] subtgraph_sensors::SenseError),
    /// An exploration was refused or failed (`explore`, Python's environment): the explore
    /// crate's message says what to change.
    #[error(transparent)]
    Explore(#[from] subtgraph_explore::ExploreError),
    /// A file of a world folder is not what `subtgraph generate` writes (edited, cut short,
    /// another version).
    #[error("{}: {source}", .world.display())]
    WorldFile {
        /// The world folder.
        world: PathBuf,
        /// What is wrong with the file.
        source: SchemaError,
    },
    /// Reading or writing a file failed.
    #[error("{what}: {source}")]
    Io {
        /// What was being done, naming the file.
        what: String,
        /// The system's error.
        source: std::io::Error,
    },
    /// Some worlds of a dataset failed; the others are complete.
    #[error(
        "{} of {total} worlds failed (the others are complete; run the same command again to retry):\n  {}",
        .failures.len(),
        .failures.join("\n  ")
    )]
    DatasetFailures {
        /// `NAME: message` of each failed world.
        failures: Vec<String>,
        /// Worlds this run set out to make.
        total: usize,
    },
    /// `dataset --sense` could not write a world's sequence; the worlds and the sequences
    /// already written are complete.
    #[error(
        "sensing {world}: {source} (the worlds and the sequences finished so far are kept; run the same command again to go on)"
    )]
    Sequence {
        /// The world's folder name.
        world: String,
        /// Why.
        source: Box<Error>,
    },
    /// `dataset --explore` could not run or score a world's mission; the worlds and the runs
    /// already written are complete.
    #[error(
        "exploring {world}: {source} (the worlds and the runs finished so far are kept; run the same command again to go on)"
    )]
    Exploring {
        /// The world's folder name.
        world: String,
        /// Why.
        source: Box<Error>,
    },
}

impl Error {
    /// An [`Error::Io`] doing `what`.
    pub fn io(what: impl Into<String>) -> impl FnOnce(std::io::Error) -> Error {
        let what = what.into();
        move |source| Error::Io { what, source }
    }
}

/// The error and its causes, each cause once: many errors already quote their cause in their
/// own message (`writing mesh/world.obj: File too large`), so a cause already said is skipped.
/// What the command line prints and the Python exceptions carry.
pub fn message(e: &(dyn std::error::Error + 'static)) -> String {
    let mut text = String::new();
    let mut cause = Some(e);
    while let Some(c) = cause {
        let part = c.to_string();
        if text.is_empty() {
            text = part;
        } else if !text.contains(&part) {
            text.push_str(": ");
            text.push_str(&part);
        }
        cause = c.source();
    }
    text
}

impl From<subtgraph_survey::SurveyError> for Error {
    fn from(e: subtgraph_survey::SurveyError) -> Self {
        Error::Survey(Box::new(e))
    }
}
