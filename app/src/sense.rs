//! `sense`: a sensor sequence along a route through a world folder's world. The request itself
//! ([`SenseRequest`]) and everything it makes live in the sensors crate (`subtgraph-sensors`);
//! this module is its host: the world of a folder, rebuilt with every built-in and the plugins
//! the user names (never the ones its `world.toml` names: [`crate::rebuild`]), and the atomic
//! sequence folder of [`crate::folder`], recorded as written by `sense` so that `sense --force`
//! replaces only a sequence folder and never a world.
//!
//! Why rebuild rather than read the folder's `mesh/collision.obj`: the OBJ exists only when
//! the world was exported to OBJ, carries no materials (which set the LiDAR's intensities),
//! and is slower to parse than the world is to make again (docs/src/sensors.md has the
//! numbers); a world records its seed and its whole resolved pipeline, so it comes back
//! exactly, and `sense` checks the rebuilt graph against the folder's.

use std::cell::RefCell;
use std::path::{Path, PathBuf};

use subtgraph_core::World;
pub use subtgraph_sensors::{CameraRequest, SenseError, SenseRequest, Summary};

use crate::Error;
use crate::folder::{self, FolderError, Kind, Out};

/// A written sequence.
#[derive(Debug)]
pub struct Sensed {
    /// What it holds.
    pub summary: Summary,
    /// Unfinished folders of killed runs removed beside the new one: where, and how many.
    pub swept: Option<(PathBuf, usize)>,
}

/// Writes the sequence `request` asks for, atomically; `progress` is told each scan's index
/// and the scan count as it is written (for a progress line). No plugin is loaded: see
/// [`run_with`].
pub fn run(request: &SenseRequest, progress: &dyn Fn(u64, u64)) -> Result<Sensed, Error> {
    run_with(request, &[], progress)
}

/// [`run`], the world rebuilt with the plugin libraries `plugins` (the ones the user named:
/// the world folder's own are never loaded for it, [`crate::rebuild`]). The folder also gets
/// the options it was made with ([`crate::sense_options`]).
pub fn run_with(
    request: &SenseRequest,
    plugins: &[PathBuf],
    progress: &dyn Fn(u64, u64),
) -> Result<Sensed, Error> {
    let host = AppHost {
        reading: [request.world.as_path()],
        plugins,
        options: crate::sense_options::text(request),
        progress,
        folder_error: RefCell::new(None),
        swept: RefCell::new(None),
    };
    match request.run(&host) {
        Ok(summary) => Ok(Sensed {
            summary,
            swept: host.swept.into_inner(),
        }),
        // The folder's own refusal (--out in the way, not ours to replace) keeps its type.
        Err(SenseError::Host(_)) if host.folder_error.borrow().is_some() => Err(Error::Folder(
            host.folder_error.into_inner().expect("checked above"),
        )),
        Err(e) => Err(e.into()),
    }
}

/// The world a world folder was made from: its `world.toml` loaded and generated again (no
/// exporters: only the world is wanted), with the plugins the user named
/// ([`crate::rebuild::world_of`]).
pub fn world_of(folder: &Path, plugins: &[PathBuf]) -> Result<World, Error> {
    crate::rebuild::world_of(folder, plugins)
}

/// The application as the sensors' host.
struct AppHost<'a> {
    reading: [&'a Path; 1],
    plugins: &'a [PathBuf],
    options: String,
    progress: &'a dyn Fn(u64, u64),
    folder_error: RefCell<Option<FolderError>>,
    swept: RefCell<Option<(PathBuf, usize)>>,
}

impl subtgraph_sensors::Host for AppHost<'_> {
    fn world(&self, folder: &Path) -> Result<World, subtgraph_sensors::HostError> {
        world_of(folder, self.plugins).map_err(|e| e.into())
    }

    fn write_folder(
        &self,
        out: &Path,
        force: bool,
        fill: &mut dyn FnMut(&Path) -> Result<(), SenseError>,
    ) -> Result<(), SenseError> {
        let out = Out {
            path: out,
            kind: Kind::Sense,
            force,
            reading: &self.reading,
        };
        out.check().map_err(|e| self.keep(e))?;
        *self.swept.borrow_mut() = folder::sweep_stale_beside(out.path);
        let options = &self.options;
        folder::write_atomically(&out, |w| {
            fill(w.root())?;
            let path = w.root().join(crate::sense_options::FILE);
            std::fs::write(&path, options).map_err(|source| SenseError::Io {
                what: "writing",
                path,
                source,
            })
        })
        .map_err(|e| match e {
            FolderError::Content(inner) => match inner.downcast::<SenseError>() {
                Ok(e) => *e,
                Err(other) => SenseError::Host(other),
            },
            e => self.keep(e),
        })
    }

    fn progress(&self, scan: u64, of: u64) {
        (self.progress)(scan, of);
    }
}

impl AppHost<'_> {
    /// Keeps a folder error for [`run`] to return as it is, and says it to the sensors crate.
    fn keep(&self, e: FolderError) -> SenseError {
        let said = SenseError::Host(e.to_string().into());
        *self.folder_error.borrow_mut() = Some(e);
        said
    }
}
