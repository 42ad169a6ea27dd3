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

pub mod digest;
mod here;
pub mod manifest;
pub mod out;
pub mod partial;
mod rename;

use std::fs;
use std::path::{Path, PathBuf};

use subtgraph_core::direct_file::{DirectFile, Spool};
use subtgraph_core::export::WorldWriter;

pub use here::not_current_folder;
pub use manifest::Kind;
pub use out::{Out, sweep_stale_beside};
pub use partial::{install_signal_handlers, sweep_stale};

use out::Before;
use rename::{exchange, is_exists, keep_elsewhere, rename_noreplace, temporary_name};

/// Writes files under a folder, creating subfolders as needed.
///
/// Streamed files and large ones (a world's meshes and scene files, most of its bytes) go
/// around the page cache, written by a thread of their own ([`subtgraph_core::direct_file`]):
/// on the development machine the kernel's copy into its cache cost about 2 s of CPU a GB.
/// [`close`](FolderWriter::close) waits for those writes and reports the first that failed;
/// the folder is sealed only after it.
pub struct FolderWriter {
    root: PathBuf,
    /// The thread writing streamed and large files, once there is one.
    spool: Option<Spool>,
}

impl std::fmt::Debug for FolderWriter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FolderWriter")
            .field("root", &self.root)
            .finish_non_exhaustive()
    }
}

/// Files at least this large are written around the page cache (smaller ones the ordinary way:
/// a thread's round trip would cost more than the copy).
const DIRECT_FROM: usize = 1 << 20;

impl FolderWriter {
    /// A writer of files under `root`.
    fn new(root: &Path) -> FolderWriter {
        FolderWriter {
            root: root.to_owned(),
            spool: None,
        }
    }

    /// The folder files go to.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// Writes `path` around the page cache through the spool, `fill` giving its bytes.
    fn direct(
        &mut self,
        path: &Path,
        fill: &mut dyn FnMut(&mut dyn std::io::Write) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        let spool = match self.spool.take() {
            Some(s) => s,
            None => Spool::new()?,
        };
        let mut file = DirectFile::create(path, spool)?;
        fill(&mut file)?;
        self.spool = Some(file.finish()?);
        Ok(())
    }

    /// Waits for every file handed to the writing thread to be written; the first write that
    /// failed is the error.
    pub fn close(&mut self) -> std::io::Result<()> {
        match self.spool.take() {
            Some(spool) => spool.close(),
            None => Ok(()),
        }
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
        let path = self.path_of(path)?;
        if bytes.len() < DIRECT_FROM {
            return fs::write(path, bytes);
        }
        self.direct(&path, &mut |w| w.write_all(bytes))
    }

    fn contains(&self, path: &str) -> bool {
        self.root.join(path).is_file()
    }

    fn stream(
        &mut self,
        path: &str,
        fill: &mut dyn FnMut(&mut dyn std::io::Write) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        let path = self.path_of(path)?;
        self.direct(&path, fill)
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
    /// `--force` was given but the destination is a folder another command wrote (a world
    /// for `stats`, a stats report for `score`, ...).
    #[error(
        "{} is a {} (written by `{}`), not a {}; --force replaces only a {} `{}` wrote: choose another --out",
        .path.display(),
        .found.what(),
        .found.command(),
        .wanted.what(),
        .wanted.what(),
        .wanted.command()
    )]
    OtherKind {
        /// The destination.
        path: PathBuf,
        /// What it is.
        found: Kind,
        /// What the command writes.
        wanted: Kind,
    },
    /// The destination is the current folder or holds it (`--out .`, `--out ..`).
    #[error(
        "--out {} {how} the current folder ({}), which is yours: a command writes a new folder of its own; name one inside it, like --out ./NAME",
        .out.display(),
        .current.display()
    )]
    CurrentFolder {
        /// The destination, as given.
        out: PathBuf,
        /// `is` or `holds`.
        how: &'static str,
        /// The current folder.
        current: PathBuf,
    },
    /// The destination is, holds or lies inside something the command reads.
    #[error(
        "--out {} {how} {}, which this command reads; write the result elsewhere: choose another --out",
        .out.display(),
        .input.display()
    )]
    BeingRead {
        /// The destination, as given.
        out: PathBuf,
        /// `is`, `holds` or `is inside`.
        how: &'static str,
        /// What it clashes with, as given.
        input: PathBuf,
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

pub(super) fn io<'a>(
    what: &'static str,
    path: &'a Path,
) -> impl FnOnce(std::io::Error) -> FolderError + 'a {
    move |source| FolderError::Io {
        what,
        path: path.to_owned(),
        source,
    }
}

/// Removes from `dir` the files its own manifest lists, then the manifest and every folder
/// left empty, then `dir` itself if it is empty. Anything else stays where it is.
pub(crate) fn remove_listed(dir: &Path) -> std::io::Result<bool> {
    let listed = match manifest::read(dir) {
        Some(manifest::Manifest::Complete(_, files)) => files,
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

/// Writes a folder at `out.path` through `fill`, atomically, after checking `--out` once more
/// ([`Out::check`]: what the command reads, and what stands there). With `force`, an existing
/// folder is replaced if it is the same kind and subtgraph wrote everything in it (or it is
/// empty); see the module documentation for what is guaranteed.
pub fn write_atomically<E: std::error::Error + Send + Sync + 'static>(
    out: &Out<'_>,
    fill: impl FnOnce(&mut FolderWriter) -> Result<(), E>,
) -> Result<(), FolderError> {
    let (parent, name, dest, was) = out.checked()?;
    fs::create_dir_all(&parent).map_err(io("creating", &parent))?;
    let tmp = parent.join(temporary_name(&name, "partial"));
    fs::create_dir(&tmp).map_err(io("creating", &tmp))?;
    let registered = partial::Registered::partial(&tmp);
    let result = fill_and_seal(&tmp, out.kind, fill);
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
    kind: Kind,
    fill: impl FnOnce(&mut FolderWriter) -> Result<(), E>,
) -> Result<(), FolderError> {
    let marker = tmp.join(manifest::FILE);
    fs::write(
        &marker,
        manifest::partial_text(&manifest::Owner::this_process()),
    )
    .map_err(io("writing", &marker))?;
    let mut writer = FolderWriter::new(tmp);
    fill(&mut writer).map_err(|e| FolderError::Content(Box::new(e)))?;
    writer.close().map_err(io("writing", tmp))?;
    let files = manifest::list_files(tmp).map_err(io("listing", tmp))?;
    let mut text = manifest::complete_text(kind, &files);
    if kind == Kind::World {
        text.push_str(&digest::lines(tmp, &files).map_err(io("reading", tmp))?);
    }
    fs::write(&marker, text).map_err(io("writing", &marker))?;
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

    /// Writes a world folder at `out`.
    fn write(
        out: &Path,
        force: bool,
        fill: impl FnOnce(&mut FolderWriter) -> std::io::Result<()>,
    ) -> Result<(), FolderError> {
        write_kind(out, Kind::World, force, &[], fill)
    }

    fn write_kind(
        out: &Path,
        kind: Kind,
        force: bool,
        reading: &[&Path],
        fill: impl FnOnce(&mut FolderWriter) -> std::io::Result<()>,
    ) -> Result<(), FolderError> {
        let out = Out {
            path: out,
            kind,
            force,
            reading,
        };
        write_atomically(&out, fill)
    }

    #[test]
    fn force_replaces_only_a_folder_of_the_same_kind_and_never_one_being_read() {
        let dir = tempfile::tempdir().unwrap();
        let report = dir.path().join("report");
        write_kind(&report, Kind::Stats, false, &[], |w| {
            w.write("stats.json", b"{}")
        })
        .unwrap();
        // A world may not replace a stats report, nor a score report a world.
        let e = write(&report, true, |w| w.write("world.toml", WORLD)).unwrap_err();
        assert!(
            matches!(
                e,
                FolderError::OtherKind {
                    found: Kind::Stats,
                    wanted: Kind::World,
                    ..
                }
            ),
            "{e}"
        );
        assert!(e.to_string().contains("stats report"), "{e}");
        let world = dir.path().join("w");
        write(&world, false, |w| w.write("world.toml", WORLD)).unwrap();
        let e = write_kind(&world, Kind::Score, true, &[], |w| {
            w.write("score.json", b"{}")
        })
        .unwrap_err();
        assert!(matches!(e, FolderError::OtherKind { .. }), "{e}");
        assert!(world.join("world.toml").is_file());
        // The same kind is replaced.
        write_kind(&report, Kind::Stats, true, &[], |w| {
            w.write("stats.json", b"[]")
        })
        .unwrap();
        assert_eq!(fs::read(report.join("stats.json")).unwrap(), b"[]");
        // Never the folder being read, one holding it, or one inside it.
        for (out, input) in [
            (world.clone(), world.clone()),
            (dir.path().to_owned(), world.clone()),
            (world.join("scores"), world.clone()),
        ] {
            let e = write_kind(&out, Kind::Score, true, &[&input], |w| {
                w.write("score.json", b"{}")
            })
            .unwrap_err();
            assert!(matches!(e, FolderError::BeingRead { .. }), "{e}");
        }
        assert!(world.join("world.toml").is_file());
        assert!(!world.join("scores").exists());
    }

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
        let e = write(&out, false, |w| {
            w.write("world.toml", b"x")?;
            Err(std::io::Error::other("disk full"))
        })
        .unwrap_err();
        assert!(e.to_string().contains("disk full"));
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 0, "no leftovers");

        write(&out, false, |w| w.write("world.toml", WORLD)).unwrap();
        let e = write(&out, false, |_| Ok::<(), std::io::Error>(())).unwrap_err();
        assert!(matches!(e, FolderError::Exists(_)));
        write(&out, true, |w| {
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
        let e = write(&precious, true, |_| Ok::<(), std::io::Error>(())).unwrap_err();
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
        let e = write(&fake, true, |w| w.write("world.toml", WORLD)).unwrap_err();
        assert!(matches!(e, FolderError::NotAWorld(..)), "{e}");
        assert_eq!(fs::read(fake.join("data.bin")).unwrap(), b"v");
        assert_eq!(fs::read(fake.join("world.toml")).unwrap(), b"mine");

        // A real world folder with a user's file added to it.
        let real = dir.path().join("r");
        write(&real, false, |w| w.write("world.toml", WORLD)).unwrap();
        fs::write(real.join("data.bin"), b"v").unwrap();
        fs::create_dir(real.join("runs")).unwrap();
        let e = write(&real, true, |w| w.write("world.toml", WORLD)).unwrap_err();
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
        let e = write(&out, false, |w| {
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
        let e = write(&out2, false, |w| {
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
                        write(out, false, |w| {
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
        write(&w, false, |x| x.write("world.toml", WORLD)).unwrap();
        // `w/.` is `w`.
        write(&w.join("."), true, |x| x.write("world.toml", WORLD)).unwrap();
        assert_eq!(names(dir.path()), ["w"]);
        // A long name still leaves room for the temporary folder's suffix.
        let long = dir.path().join("n".repeat(240));
        write(&long, false, |x| x.write("world.toml", WORLD)).unwrap();
        assert!(long.join("world.toml").is_file());
    }

    #[test]
    fn paths_may_not_leave_the_folder() {
        let dir = tempfile::tempdir().unwrap();
        let mut w = FolderWriter::new(dir.path());
        assert!(w.write("../escape", b"").is_err());
        assert!(w.write("/etc/passwd", b"").is_err());
        w.write("maps/level-0.png", b"").unwrap();
    }
}
