//! What may stand at `--out`, checked before any work and again when the folder is moved into
//! place: nothing, or (with `--force`) a folder the same command wrote ([`Kind`]); never a
//! folder or file the command is reading, and only where the user can write.

use std::fs;
use std::path::{Path, PathBuf};

use super::here::resolved;
use super::manifest::{self, Kind};
use super::{FolderError, io, sweep_stale};

/// Where a command writes its folder, and what it reads meanwhile.
#[derive(Clone, Copy, Debug)]
pub struct Out<'a> {
    /// The folder to write.
    pub path: &'a Path,
    /// What the command writes there.
    pub kind: Kind,
    /// Whether a folder of the same kind the tool wrote may be replaced.
    pub force: bool,
    /// Every file and folder the command reads: `--out` may not be, hold or lie inside one.
    pub reading: &'a [&'a Path],
}

impl Out<'_> {
    /// Checks `--out` before any work: its parent is a folder (or can be made) the user can
    /// write to; it is none of the inputs, holds none and lies inside none; and nothing stands
    /// there but (with `force`) a folder of the same kind this tool wrote.
    pub fn check(&self) -> Result<(), FolderError> {
        self.checked().map(|_| ())
    }

    /// [`Out::check`], returning the parent folder, the folder's name, its path as the user
    /// wrote it (`race`, not `./race`, in messages) and what stands there now.
    pub(super) fn checked(&self) -> Result<(PathBuf, String, PathBuf, Before), FolderError> {
        super::here::not_current(self.path, resolved(self.path))?;
        let (parent, name) = destination(self.path)?;
        let dest = if self.path.parent().is_some_and(|p| p.as_os_str().is_empty()) {
            PathBuf::from(&name)
        } else {
            parent.join(&name)
        };
        if let Some(file) = parent
            .ancestors()
            .find(|a| a.exists())
            .filter(|a| !a.is_dir())
        {
            return Err(FolderError::NotAFolder(file.to_owned()));
        }
        self.not_read(&dest)?;
        writable(&parent)?;
        let was = before(&dest, self.kind, self.force)?;
        Ok((parent, name.to_string_lossy().into_owned(), dest, was))
    }

    /// Refuses a destination that is an input, holds one, or lies inside an input folder.
    fn not_read(&self, dest: &Path) -> Result<(), FolderError> {
        let dest = resolved(dest);
        for input in self.reading {
            let Ok(input_real) = input.canonicalize() else {
                continue;
            };
            let clash = if dest == input_real {
                Some("is")
            } else if input_real.starts_with(&dest) {
                Some("holds")
            } else if input_real.is_dir() && dest.starts_with(&input_real) {
                Some("is inside")
            } else {
                None
            };
            if let Some(how) = clash {
                return Err(FolderError::BeingRead {
                    out: self.path.to_owned(),
                    how,
                    input: input.to_path_buf(),
                });
            }
        }
        Ok(())
    }
}

/// Refuses a destination whose nearest existing folder the user cannot write to (the folders
/// missing on the way are made there).
fn writable(parent: &Path) -> Result<(), FolderError> {
    #[cfg(unix)]
    {
        let Some(existing) = parent.ancestors().find(|a| a.is_dir()) else {
            return Ok(());
        };
        if let Err(e) = rustix::fs::access(existing, rustix::fs::Access::WRITE_OK) {
            return Err(io("writing into", existing)(e.into()));
        }
    }
    #[cfg(not(unix))]
    let _ = parent;
    Ok(())
}

/// What stands at the destination before a run.
pub(super) enum Before {
    /// Nothing.
    Absent,
    /// A folder `--force` may replace: the files its manifest lists (none for an empty folder).
    Ours,
}

/// Where the folder goes: its parent (created if needed) and its own name. `w/.` and `w/..`
/// name real folders, so they are resolved first.
pub(super) fn destination(out: &Path) -> Result<(PathBuf, std::ffi::OsString), FolderError> {
    let ends_oddly = matches!(
        out.components().next_back(),
        Some(std::path::Component::ParentDir | std::path::Component::CurDir)
    ) || out.file_name().is_none();
    let resolved;
    let out = if ends_oddly {
        resolved = out.canonicalize().map_err(|_| FolderError::Io {
            what: "naming",
            path: out.to_owned(),
            source: std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "--out must name a folder, like worlds/cave-7",
            ),
        })?;
        resolved.as_path()
    } else {
        out
    };
    let name = out.file_name().ok_or_else(|| FolderError::Io {
        what: "naming",
        path: out.to_owned(),
        source: std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "--out must name a folder, like worlds/cave-7, not the root",
        ),
    })?;
    let parent = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_owned(),
        _ => PathBuf::from("."),
    };
    Ok((parent, name.to_owned()))
}

/// Removes what killed runs left in the folder `out` goes into (the same parent
/// [`super::write_atomically`] writes its temporary folder in, `w/.` resolved); returns that folder
/// and how many were removed, when any were.
pub fn sweep_stale_beside(out: &Path) -> Option<(PathBuf, usize)> {
    let (parent, _) = destination(out).ok()?;
    match sweep_stale(&parent) {
        Ok(n) if n > 0 => Some((parent, n)),
        _ => None,
    }
}

/// Checks what is at `dest` before anything is made: nothing, or (with `force`) a folder of
/// `kind` this tool wrote.
fn before(dest: &Path, kind: Kind, force: bool) -> Result<Before, FolderError> {
    let meta = match fs::symlink_metadata(dest) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Before::Absent),
        Err(e) => return Err(io("reading", dest)(e)),
    };
    if !force {
        return Err(FolderError::Exists(dest.to_owned()));
    }
    if !meta.is_dir() {
        return Err(FolderError::NotAWorld(
            dest.to_owned(),
            "it is not a folder",
        ));
    }
    ours(dest, kind).map(|_| Before::Ours)
}

/// The files subtgraph wrote in `dir` if it is a `kind` folder and everything in it is the
/// tool's (an empty folder counts), or why not.
fn ours(dir: &Path, kind: Kind) -> Result<Vec<(String, u64)>, FolderError> {
    let empty = fs::read_dir(dir)
        .map_err(io("reading", dir))?
        .next()
        .is_none();
    if empty {
        return Ok(Vec::new());
    }
    let listed = match manifest::read(dir) {
        Some(manifest::Manifest::Complete(Some(k), files)) if k == kind => files,
        Some(manifest::Manifest::Complete(Some(found), _)) => {
            return Err(FolderError::OtherKind {
                path: dir.to_owned(),
                found,
                wanted: kind,
            });
        }
        Some(manifest::Manifest::Complete(None, _)) => {
            return Err(FolderError::NotAWorld(
                dir.to_owned(),
                "its .subtgraph-files list, written by an older version, does not say which command wrote it",
            ));
        }
        Some(manifest::Manifest::Partial(_)) => {
            return Err(FolderError::NotAWorld(
                dir.to_owned(),
                "another run is still writing it",
            ));
        }
        None if dir.join("world.toml").is_file() => {
            return Err(FolderError::NotAWorld(
                dir.to_owned(),
                "it has a world.toml but no .subtgraph-files list of what subtgraph wrote: made by an older version, or not by subtgraph",
            ));
        }
        None => {
            return Err(FolderError::NotAWorld(
                dir.to_owned(),
                "no world.toml in it",
            ));
        }
    };
    let is_world = listed.iter().any(|(p, _)| p == "world.toml");
    let toml = dir.join("world.toml");
    if is_world && toml.exists() && !generated_by_us(&toml) {
        return Err(FolderError::NotAWorld(
            dir.to_owned(),
            "its world.toml has no [generated] table written by subtgraph",
        ));
    }
    let foreign = manifest::foreign_entries(dir, &listed).map_err(io("reading", dir))?;
    if !foreign.is_empty() {
        return Err(FolderError::NotOurs {
            path: dir.to_owned(),
            foreign,
        });
    }
    Ok(listed)
}

fn generated_by_us(world_toml: &Path) -> bool {
    let Ok(text) = fs::read_to_string(world_toml) else {
        return false;
    };
    let Ok(table) = toml::from_str::<toml::Table>(&text) else {
        return false;
    };
    table
        .get("generated")
        .and_then(|g| g.get("tool"))
        .and_then(|t| t.as_str())
        == Some("subtgraph")
}
