//! Exporters write a world's files.
//!
//! An exporter formats a finished world: its [`World`] (layout and geometry) and what the
//! world's survey found in it ([`Survey`]: passages, node positions, centrelines, artifacts,
//! floor patches). It computes nothing a second exporter would need again, and reads the
//! survey's answers rather than the pipeline's sections.
//!
//! The core does no file I/O: an exporter writes through a [`WorldWriter`], which the command
//! line implements over a temporary folder that is renamed into place only when every exporter
//! has succeeded, so a world folder is complete or absent.

use crate::survey::Survey;
use crate::world::World;

/// Where an exporter puts its files: paths are relative to the world folder and use `/`.
pub trait WorldWriter {
    /// Writes one whole file.
    fn write(&mut self, path: &str, bytes: &[u8]) -> std::io::Result<()>;

    /// Whether a file was already written in this world folder: exporters that share files
    /// (the per-part meshes that SDF, URDF and MJCF all reference) write them once.
    fn contains(&self, _path: &str) -> bool {
        false
    }

    /// Writes one file through a stream, for files too large to hold in memory. The default
    /// collects the stream and calls [`write`](WorldWriter::write).
    fn stream(
        &mut self,
        path: &str,
        fill: &mut dyn FnMut(&mut dyn std::io::Write) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        let mut buf = Vec::new();
        fill(&mut buf)?;
        self.write(path, &buf)
    }
}

/// An in-memory writer, for tests and for callers that post-process files.
#[derive(Debug, Default, Clone)]
pub struct MemoryWriter {
    /// Files by relative path, in the order written.
    pub files: Vec<(String, Vec<u8>)>,
}

impl WorldWriter for MemoryWriter {
    fn write(&mut self, path: &str, bytes: &[u8]) -> std::io::Result<()> {
        self.files.push((path.to_owned(), bytes.to_vec()));
        Ok(())
    }

    fn contains(&self, path: &str) -> bool {
        self.get(path).is_some()
    }
}

impl MemoryWriter {
    /// The contents of a written file.
    pub fn get(&self, path: &str) -> Option<&[u8]> {
        self.files
            .iter()
            .find(|(p, _)| p == path)
            .map(|(_, b)| b.as_slice())
    }
}

/// Why an export failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExportError {
    /// Writing a file failed (disk full, permissions). Free space or choose another `--out`.
    #[error("writing {path}: {source}{}", io_hint(source))]
    Io {
        /// The file.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// The exporter cannot represent this world; the message says what it needs.
    #[error("{0}")]
    Unsupported(String),
    /// A plugin's exporter panicked, now or on an earlier call: the message names the plugin
    /// and the call (fix or remove the plugin).
    #[error("{0}")]
    Plugin(String),
}

/// What to do about an I/O error a user can fix (a full disk, a file-size limit), as a
/// clause to append to the message; empty for other errors.
pub fn io_hint(e: &std::io::Error) -> &'static str {
    match e.kind() {
        std::io::ErrorKind::StorageFull => "; the disk is full: free space or choose another --out",
        std::io::ErrorKind::FileTooLarge => {
            "; the file-size limit (ulimit -f) was reached: raise it, or export fewer or smaller formats"
        }
        std::io::ErrorKind::QuotaExceeded => {
            "; the disk quota is exhausted: free space or choose another --out"
        }
        std::io::ErrorKind::PermissionDenied => "; choose an --out you can write to",
        _ => "",
    }
}

/// Writes some of a world's files.
///
/// # Example
///
/// ```
/// use subtgraph_core::export::{Exporter, ExportError, WorldWriter};
/// use subtgraph_core::survey::Survey;
/// use subtgraph_core::world::World;
///
/// /// Writes the number of occupied cells, and how many artifacts the survey placed.
/// struct CellCount;
///
/// impl Exporter for CellCount {
///     fn export(
///         &self,
///         world: &World,
///         survey: &dyn Survey,
///         out: &mut dyn WorldWriter,
///     ) -> Result<(), ExportError> {
///         let artifacts = survey.artifacts().map_or(0, |a| a.artifacts.len());
///         let text = format!("{} {artifacts}", world.occupancy.occupied_count());
///         out.write("cells.txt", text.as_bytes())
///             .map_err(|source| ExportError::Io { path: "cells.txt".into(), source })
///     }
/// }
/// ```
pub trait Exporter: Send + Sync {
    /// Writes the files of `world`, from what its `survey` found where a format needs more
    /// than the layout and the meshes.
    fn export(
        &self,
        world: &World,
        survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError>;

    /// Whether this exporter writes geometry and so needs the pipeline's `[tileset]`. The
    /// command line refuses such an exporter in a pipeline without one before generating
    /// anything, and skips it (saying so) under `--no-mesh`.
    fn needs_geometry(&self) -> bool {
        false
    }
}

/// Streams a file, turning an I/O failure into an [`ExportError`] naming the file.
pub fn stream_file(
    out: &mut dyn WorldWriter,
    path: &str,
    mut fill: impl FnMut(&mut dyn std::io::Write) -> std::io::Result<()>,
) -> Result<(), ExportError> {
    out.stream(path, &mut fill)
        .map_err(|source| ExportError::Io {
            path: path.to_owned(),
            source,
        })
}

/// Writes `bytes` to `path`, turning an I/O failure into an [`ExportError`] naming the file.
pub fn write_file(out: &mut dyn WorldWriter, path: &str, bytes: &[u8]) -> Result<(), ExportError> {
    out.write(path, bytes).map_err(|source| ExportError::Io {
        path: path.to_owned(),
        source,
    })
}
