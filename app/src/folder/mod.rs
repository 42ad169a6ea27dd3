//! World folders, written atomically: every file goes into a hidden temporary folder beside
//! the destination, which is moved into place only when all of them are written. A world
//! folder therefore exists complete or not at all, and a failed run leaves nothing behind.
//!
//! Nothing of the user's is ever deleted or overwritten, whatever the flags or timing:
//! - the move into place never replaces anything (`renameat2(RENAME_NOREPLACE)` on Linux,
//!   `renamex_np(RENAME_EXCL)` on macOS): if a folder appeared at `--out` while the world was
//!   being made, the run fails and keeps its world under a name it reports;
//! - `--force` replaces only a folder this tool wrote, recognised by its manifest
//!   ([`manifest`], written last) and the `[generated]` table of its `world.toml`, and deletes
//!   only the files that manifest lists; a folder holding anything else is refused, naming it;
//! - the old world is swapped out atomically (`RENAME_EXCHANGE`) where the system allows, so
//!   `--out` is never missing for an instant;
//! - an interrupted run removes its temporary folder, and a killed one's is removed by the
//!   next run ([`partial`]).

pub mod manifest;
pub mod partial;

use std::fs;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use subtgraph_core::export::WorldWriter;

pub use partial::{install_signal_handlers, sweep_stale};

/// Writes files under a folder, creating subfolders as needed.
#[derive(Debug)]
pub struct FolderWriter {
    root: PathBuf,
}

impl FolderWriter {
    /// The folder files go to.
    pub fn root(&self) -> &Path {
        &self.root
    }
}

impl FolderWriter {
    fn path_of(&self, path: &str) -> std::io::Result<PathBuf> {
        let rel = Path::new(path);
        if rel.is_absolute()
            || rel
                .components()
                .any(|c| !matches!(c, std::path::Component::Normal(_)))
        {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!("'{path}' is not a plain relative path inside the world folder"),
            ));
        }
        let full = self.root.join(rel);
        if let Some(parent) = full.parent() {
            fs::create_dir_all(parent)?;
        }
        Ok(full)
    }
}

impl WorldWriter for FolderWriter {
    fn write(&mut self, path: &str, bytes: &[u8]) -> std::io::Result<()> {
        fs::write(self.path_of(path)?, bytes)
    }

    fn contains(&self, path: &str) -> bool {
        self.root.join(path).is_file()
    }

    fn stream(
        &mut self,
        path: &str,
        fill: &mut dyn FnMut(&mut dyn std::io::Write) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        let file = fs::File::create(self.path_of(path)?)?;
        let mut w = std::io::BufWriter::with_capacity(1 << 20, file);
        fill(&mut w)?;
        std::io::Write::flush(&mut w)
    }
}

/// Writes one file through a temporary file beside it and a rename, so a reader never sees
/// it half-written (the dataset index, a report's files).
pub fn write_file_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let name = path
        .file_name()
        .map_or("file".into(), |n| n.to_string_lossy());
    // Process id and time: shards on several machines may share the folder.
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let tmp = path.with_file_name(format!(".{name}.tmp-{}-{nanos}", std::process::id()));
    std::fs::write(&tmp, bytes)?;
    std::fs::rename(&tmp, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&tmp);
    })
}

/// Why a world folder could not be written.
#[derive(Debug, thiserror::Error)]
pub enum FolderError {
    /// The destination exists and `--force` was not given.
    #[error("{0} already exists; pass --force to replace it, or choose another --out")]
    Exists(PathBuf),
    /// A file stands where a folder on the way to the destination should be.
    #[error("{0} is a file, not a folder, so --out cannot be made inside it; choose another --out")]
    NotAFolder(PathBuf),
    /// `--force` was given but the destination holds things the tool did not write.
    #[error(
        "{path} holds {} subtgraph did not write ({}); --force replaces only what subtgraph wrote: move {} out, or choose another --out",
        if .foreign.len() == 1 { "something" } else { "things" },
        list(.foreign),
        if .foreign.len() == 1 { "it" } else { "them" }
    )]
    NotOurs {
        /// The destination.
        path: PathBuf,
        /// What is in the way (relative paths).
        foreign: Vec<String>,
    },
    /// `--force` was given but the destination is not a folder written by this tool.
    #[error(
        "{0} exists and is not a folder written by subtgraph ({1}); refusing to replace it even with --force: remove it yourself if nothing in it is yours, or choose another --out"
    )]
    NotAWorld(PathBuf, &'static str),
    /// Something appeared at the destination while the world was being made.
    #[error(
        "{out} appeared while this world was being made (another run or program wrote it); it was left untouched, and this world was kept at {kept}"
    )]
    AppearedMeanwhile {
        /// The destination.
        out: PathBuf,
        /// Where the new world is.
        kept: PathBuf,
    },
    /// A file system operation failed.
    #[error("{what} {path}: {}", describe(.source))]
    Io {
        /// What was being done.
        what: &'static str,
        /// On what.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The content could not be produced (the writer's own error: an exporter's, a full
    /// disk's).
    #[error(transparent)]
    Content(Box<dyn std::error::Error + Send + Sync>),
}

fn list(items: &[String]) -> String {
    let shown: Vec<&str> = items.iter().take(5).map(String::as_str).collect();
    match items.len() {
        n if n > 5 => format!("{} and {} more", shown.join(", "), n - 5),
        _ => shown.join(", "),
    }
}

/// An I/O error, with what to do about the common ones.
fn describe(e: &std::io::Error) -> String {
    format!("{e}{}", subtgraph_core::export::io_hint(e))
}

fn io<'a>(what: &'static str, path: &'a Path) -> impl FnOnce(std::io::Error) -> FolderError + 'a {
    move |source| FolderError::Io {
        what,
        path: path.to_owned(),
        source,
    }
}

/// What stands at the destination before a run.
enum Before {
    /// Nothing.
    Absent,
    /// A folder `--force` may replace: the files its manifest lists (none for an empty folder).
    Ours,
}

/// Where the folder goes: its parent (created if needed) and its own name. `w/.` and `w/..`
/// name real folders, so they are resolved first.
fn destination(out: &Path) -> Result<(PathBuf, std::ffi::OsString), FolderError> {
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
/// [`write_atomically`] writes its temporary folder in, `w/.` resolved); returns that folder
/// and how many were removed, when any were.
pub fn sweep_stale_beside(out: &Path) -> Option<(PathBuf, usize)> {
    let (parent, _) = destination(out).ok()?;
    match sweep_stale(&parent) {
        Ok(n) if n > 0 => Some((parent, n)),
        _ => None,
    }
}

/// Checks what is at `dest` before anything is made.
fn before(dest: &Path, force: bool) -> Result<Before, FolderError> {
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
    ours(dest).map(|_| Before::Ours)
}

/// The files subtgraph wrote in `dir` if everything in it is the tool's (an empty folder
/// counts), or why not.
fn ours(dir: &Path) -> Result<Vec<(String, u64)>, FolderError> {
    let empty = fs::read_dir(dir)
        .map_err(io("reading", dir))?
        .next()
        .is_none();
    if empty {
        return Ok(Vec::new());
    }
    let listed = match manifest::read(dir) {
        Some(manifest::Manifest::Complete(files)) => files,
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

/// Removes from `dir` the files its own manifest lists, then the manifest and every folder
/// left empty, then `dir` itself if it is empty. Anything else stays where it is.
pub(crate) fn remove_listed(dir: &Path) -> std::io::Result<bool> {
    let listed = match manifest::read(dir) {
        Some(manifest::Manifest::Complete(files)) => files,
        _ => Vec::new(),
    };
    let mut dirs = std::collections::BTreeSet::new();
    for (path, _) in &listed {
        let full = dir.join(path);
        if fs::symlink_metadata(&full).is_ok_and(|m| m.is_file()) {
            fs::remove_file(&full)?;
        }
        for a in Path::new(path).ancestors().skip(1) {
            if !a.as_os_str().is_empty() {
                dirs.insert(a.to_owned());
            }
        }
    }
    let _ = fs::remove_file(dir.join(manifest::FILE));
    // Deepest first; a folder that is not empty holds something of the user's and stays.
    let mut dirs: Vec<PathBuf> = dirs.into_iter().collect();
    dirs.sort_by_key(|d| std::cmp::Reverse(d.components().count()));
    for d in dirs {
        let _ = fs::remove_dir(dir.join(d));
    }
    Ok(fs::remove_dir(dir).is_ok())
}

/// Moves `from` to `to` only if nothing is at `to`: atomic where the system allows, and
/// otherwise a check followed by a rename that cannot replace a non-empty folder.
fn rename_noreplace(from: &Path, to: &Path) -> std::io::Result<()> {
    #[cfg(any(target_os = "linux", target_os = "android", target_vendor = "apple"))]
    {
        use rustix::fs::{CWD, RenameFlags, renameat_with};
        match renameat_with(CWD, from, CWD, to, RenameFlags::NOREPLACE) {
            Ok(()) => return Ok(()),
            Err(e) if e == rustix::io::Errno::INVAL || e == rustix::io::Errno::NOSYS => {}
            Err(e) => return Err(e.into()),
        }
    }
    if fs::symlink_metadata(to).is_ok() {
        return Err(std::io::ErrorKind::AlreadyExists.into());
    }
    fs::rename(from, to)
}

/// Swaps `a` and `b` atomically, where the system allows (`Unsupported` elsewhere).
fn exchange(a: &Path, b: &Path) -> std::io::Result<()> {
    #[cfg(any(target_os = "linux", target_os = "android", target_vendor = "apple"))]
    {
        use rustix::fs::{CWD, RenameFlags, renameat_with};
        match renameat_with(CWD, a, CWD, b, RenameFlags::EXCHANGE) {
            Ok(()) => Ok(()),
            Err(e) if e == rustix::io::Errno::INVAL || e == rustix::io::Errno::NOSYS => {
                Err(std::io::ErrorKind::Unsupported.into())
            }
            Err(e) => Err(e.into()),
        }
    }
    #[cfg(not(any(target_os = "linux", target_os = "android", target_vendor = "apple")))]
    {
        let _ = (a, b);
        Err(std::io::ErrorKind::Unsupported.into())
    }
}

fn is_exists(e: &std::io::Error) -> bool {
    e.kind() == std::io::ErrorKind::AlreadyExists
        || e.kind() == std::io::ErrorKind::DirectoryNotEmpty
}

/// A name no other run uses: the first 100 bytes of `name` (file names may be 255 bytes, and
/// the suffix must fit), the process id and the time.
fn temporary_name(name: &str, what: &str) -> String {
    let mut cut = name.len().min(100);
    while !name.is_char_boundary(cut) {
        cut -= 1;
    }
    let stamp = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    format!(".{}.{what}-{}-{stamp}", &name[..cut], std::process::id())
}

/// Keeps a finished world whose destination was taken, under `NAME-new`, `NAME-new-2`, ...
fn keep_elsewhere(tmp: &Path, dest: &Path, name: &str) -> Result<PathBuf, FolderError> {
    for n in 1..1000 {
        // Beside `dest`, named as the user wrote it (`race-new`, not `./race-new`).
        let candidate = if n == 1 {
            dest.with_file_name(format!("{name}-new"))
        } else {
            dest.with_file_name(format!("{name}-new-{n}"))
        };
        match rename_noreplace(tmp, &candidate) {
            Ok(()) => return Ok(candidate),
            Err(e) if is_exists(&e) => continue,
            Err(e) => return Err(io("keeping the new world at", &candidate)(e)),
        }
    }
    Err(FolderError::Io {
        what: "keeping the new world beside",
        path: dest.to_owned(),
        source: std::io::ErrorKind::AlreadyExists.into(),
    })
}

/// Writes a world folder at `out` through `fill`, atomically. With `force`, an existing
/// folder is replaced if subtgraph wrote everything in it (or it is empty); see the module
/// documentation for what is guaranteed.
pub fn write_atomically<E: std::error::Error + Send + Sync + 'static>(
    out: &Path,
    force: bool,
    fill: impl FnOnce(&mut FolderWriter) -> Result<(), E>,
) -> Result<(), FolderError> {
    let (parent, name) = destination(out)?;
    // Named as the user wrote it (`race`, not `./race`) in messages.
    let dest = if out.parent().is_some_and(|p| p.as_os_str().is_empty()) {
        PathBuf::from(&name)
    } else {
        parent.join(&name)
    };
    let name = name.to_string_lossy().into_owned();
    if let Some(file) = parent
        .ancestors()
        .find(|a| a.exists())
        .filter(|a| !a.is_dir())
    {
        return Err(FolderError::NotAFolder(file.to_owned()));
    }
    let was = before(&dest, force)?;
    fs::create_dir_all(&parent).map_err(io("creating", &parent))?;
    let tmp = parent.join(temporary_name(&name, "partial"));
    fs::create_dir(&tmp).map_err(io("creating", &tmp))?;
    let registered = partial::Registered::partial(&tmp);
    let result = fill_and_seal(&tmp, fill);
    if let Err(e) = result {
        let _ = fs::remove_dir_all(&tmp);
        return Err(e);
    }
    let placed = place(&tmp, &dest, &parent, &name, was);
    if placed.is_err() && tmp.exists() {
        // `place` fails only before the new world has left `tmp` (once an old world has been
        // swapped in there, it never fails), so what is at `tmp` is our own new folder.
        let _ = fs::remove_dir_all(&tmp);
    }
    drop(registered);
    placed
}

/// Writes the partial marker, the content, and last the manifest of what was written.
fn fill_and_seal<E: std::error::Error + Send + Sync + 'static>(
    tmp: &Path,
    fill: impl FnOnce(&mut FolderWriter) -> Result<(), E>,
) -> Result<(), FolderError> {
    let marker = tmp.join(manifest::FILE);
    fs::write(
        &marker,
        manifest::partial_text(&manifest::Owner::this_process()),
    )
    .map_err(io("writing", &marker))?;
    let mut writer = FolderWriter {
        root: tmp.to_owned(),
    };
    fill(&mut writer).map_err(|e| FolderError::Content(Box::new(e)))?;
    let files = manifest::list_files(tmp).map_err(io("listing", tmp))?;
    fs::write(&marker, manifest::complete_text(&files)).map_err(io("writing", &marker))?;
    Ok(())
}

/// Moves the finished folder `tmp` to `dest`, replacing only what `before` found replaceable.
/// It fails only while the new world is still at `tmp`: after an old world is swapped out, a
/// failure to remove it is a warning, never an error that would make the caller clean up.
fn place(
    tmp: &Path,
    dest: &Path,
    parent: &Path,
    name: &str,
    was: Before,
) -> Result<(), FolderError> {
    match was {
        Before::Absent => match rename_noreplace(tmp, dest) {
            Ok(()) => Ok(()),
            Err(e) if is_exists(&e) => {
                let kept = keep_elsewhere(tmp, dest, name)?;
                Err(FolderError::AppearedMeanwhile {
                    out: dest.to_owned(),
                    kept,
                })
            }
            Err(e) => Err(io("moving into place", dest)(e)),
        },
        Before::Ours => {
            // Swap atomically where possible; otherwise move the old folder aside first.
            let old = match exchange(tmp, dest) {
                Ok(()) => tmp.to_owned(),
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                    // It was removed meanwhile: an ordinary move.
                    return place(tmp, dest, parent, name, Before::Absent);
                }
                Err(e) if e.kind() == std::io::ErrorKind::Unsupported => {
                    let aside = parent.join(temporary_name(name, "replaced"));
                    fs::rename(dest, &aside).map_err(io("moving aside", dest))?;
                    if let Err(e) = rename_noreplace(tmp, dest) {
                        let _ = rename_noreplace(&aside, dest);
                        return Err(if is_exists(&e) {
                            FolderError::AppearedMeanwhile {
                                out: dest.to_owned(),
                                kept: keep_elsewhere(tmp, dest, name)?,
                            }
                        } else {
                            io("moving into place", dest)(e)
                        });
                    }
                    aside
                }
                Err(e) => return Err(io("replacing", dest)(e)),
            };
            let _registered = partial::Registered::replaced(&old);
            // The new world is in place: from here on nothing fails the run. The old folder is
            // checked again now that it cannot change under us: only the files it lists are
            // removed, and whatever else is in it stays, moved to a visible name.
            let removed = remove_listed(&old).unwrap_or(false);
            if !removed && old.exists() {
                let kept = parent.join(format!("{name}-replaced-leftovers"));
                let kept = match rename_noreplace(&old, &kept) {
                    Ok(()) => Some(kept),
                    Err(_) => keep_elsewhere(&old, dest, &format!("{name}-replaced")).ok(),
                };
                eprintln!(
                    "warning: not everything in the replaced {} could be removed (files subtgraph did not write appeared in it, or a removal failed); it is kept in {}",
                    dest.display(),
                    kept.as_deref().unwrap_or(&old).display()
                );
            }
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const WORLD: &[u8] = b"[generated]\ntool = \"subtgraph\"\n";

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn a_failure_leaves_nothing_and_success_replaces_only_worlds() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("w");
        let e = write_atomically(&out, false, |w| {
            w.write("world.toml", b"x")?;
            Err(std::io::Error::other("disk full"))
        })
        .unwrap_err();
        assert!(e.to_string().contains("disk full"));
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 0, "no leftovers");

        write_atomically(&out, false, |w| w.write("world.toml", WORLD)).unwrap();
        let e = write_atomically(&out, false, |_| Ok::<(), std::io::Error>(())).unwrap_err();
        assert!(matches!(e, FolderError::Exists(_)));
        write_atomically(&out, true, |w| {
            w.write("world.toml", WORLD)?;
            w.write("maps/level-0.png", b"2")
        })
        .unwrap();
        assert_eq!(fs::read(out.join("maps/level-0.png")).unwrap(), b"2");
        assert_eq!(names(dir.path()), ["w"]);
        assert_eq!(names(&out), [manifest::FILE, "maps", "world.toml"]);

        let precious = dir.path().join("home");
        fs::create_dir(&precious).unwrap();
        fs::write(precious.join("thesis.tex"), b"...").unwrap();
        let e = write_atomically(&precious, true, |_| Ok::<(), std::io::Error>(())).unwrap_err();
        assert!(matches!(e, FolderError::NotAWorld(..)), "{e}");
        assert!(precious.join("thesis.tex").exists());
    }

    #[test]
    fn force_refuses_a_world_toml_the_tool_did_not_write_and_files_it_did_not_write() {
        let dir = tempfile::tempdir().unwrap();
        // A folder that merely holds a file named world.toml.
        let fake = dir.path().join("f");
        fs::create_dir(&fake).unwrap();
        fs::write(fake.join("world.toml"), b"mine").unwrap();
        fs::write(fake.join("data.bin"), b"v").unwrap();
        let e = write_atomically(&fake, true, |w| w.write("world.toml", WORLD)).unwrap_err();
        assert!(matches!(e, FolderError::NotAWorld(..)), "{e}");
        assert_eq!(fs::read(fake.join("data.bin")).unwrap(), b"v");
        assert_eq!(fs::read(fake.join("world.toml")).unwrap(), b"mine");

        // A real world folder with a user's file added to it.
        let real = dir.path().join("r");
        write_atomically(&real, false, |w| w.write("world.toml", WORLD)).unwrap();
        fs::write(real.join("data.bin"), b"v").unwrap();
        fs::create_dir(real.join("runs")).unwrap();
        let e = write_atomically(&real, true, |w| w.write("world.toml", WORLD)).unwrap_err();
        let text = e.to_string();
        assert!(matches!(e, FolderError::NotOurs { .. }), "{text}");
        assert!(text.contains("data.bin") && text.contains("runs"), "{text}");
        assert_eq!(fs::read(real.join("data.bin")).unwrap(), b"v");
        assert_eq!(names(dir.path()), ["f", "r"], "no leftovers");
    }

    #[test]
    fn a_folder_that_appears_meanwhile_is_never_replaced() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("race");
        let e = write_atomically(&out, false, |w| {
            w.write("world.toml", WORLD)?;
            // Someone makes the folder while the world is being written.
            fs::create_dir(&out)?;
            fs::write(out.join("thesis.txt"), b"x")?;
            Ok::<(), std::io::Error>(())
        })
        .unwrap_err();
        let FolderError::AppearedMeanwhile { kept, .. } = &e else {
            panic!("{e}")
        };
        assert_eq!(fs::read(out.join("thesis.txt")).unwrap(), b"x");
        assert_eq!(fs::read(kept.join("world.toml")).unwrap(), WORLD);
        assert!(e.to_string().contains("race-new"), "{e}");

        // Even an empty folder that appears is left alone.
        let out2 = dir.path().join("race2");
        let e = write_atomically(&out2, false, |w| {
            fs::create_dir(&out2)?;
            w.write("world.toml", WORLD)
        })
        .unwrap_err();
        assert!(matches!(e, FolderError::AppearedMeanwhile { .. }), "{e}");
    }

    #[test]
    fn two_concurrent_runs_into_one_folder_both_keep_their_world() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("same");
        let barrier = std::sync::Barrier::new(2);
        let results: Vec<Result<(), FolderError>> = std::thread::scope(|s| {
            let runs: Vec<_> = (0..2u8)
                .map(|i| {
                    let (out, barrier) = (&out, &barrier);
                    s.spawn(move || {
                        write_atomically(out, false, |w| {
                            w.write("world.toml", WORLD)?;
                            w.write("which", &[i])?;
                            barrier.wait();
                            Ok::<(), std::io::Error>(())
                        })
                    })
                })
                .collect();
            runs.into_iter().map(|r| r.join().unwrap()).collect()
        });
        assert_eq!(results.iter().filter(|r| r.is_ok()).count(), 1);
        let Some(Err(FolderError::AppearedMeanwhile { kept, .. })) =
            results.iter().find(|r| r.is_err())
        else {
            panic!("the other run says where its world is")
        };
        let a = fs::read(out.join("which")).unwrap();
        let b = fs::read(kept.join("which")).unwrap();
        assert_ne!(a, b, "both worlds exist");
    }

    #[test]
    fn odd_destinations_work() {
        let dir = tempfile::tempdir().unwrap();
        let w = dir.path().join("w");
        write_atomically(&w, false, |x| x.write("world.toml", WORLD)).unwrap();
        // `w/.` is `w`.
        write_atomically(&w.join("."), true, |x| x.write("world.toml", WORLD)).unwrap();
        assert_eq!(names(dir.path()), ["w"]);
        // A long name still leaves room for the temporary folder's suffix.
        let long = dir.path().join("n".repeat(240));
        write_atomically(&long, false, |x| x.write("world.toml", WORLD)).unwrap();
        assert!(long.join("world.toml").is_file());
    }

    #[test]
    fn paths_may_not_leave_the_folder() {
        let dir = tempfile::tempdir().unwrap();
        let mut w = FolderWriter {
            root: dir.path().to_owned(),
        };
        assert!(w.write("../escape", b"").is_err());
        assert!(w.write("/etc/passwd", b"").is_err());
        w.write("maps/level-0.png", b"").unwrap();
    }
}
