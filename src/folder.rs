//! World folders, written atomically: every file goes into a hidden temporary folder beside
//! the destination, which is renamed into place only when all of them are written. A world
//! folder therefore exists complete or not at all, and a failed run leaves nothing behind.

use std::fs;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use subtgraph_core::export::WorldWriter;

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

/// Why a world folder could not be written.
#[derive(Debug, thiserror::Error)]
pub enum FolderError {
    /// The destination exists and `--force` was not given.
    #[error("{0} already exists; pass --force to replace it, or choose another --out")]
    Exists(PathBuf),
    /// A file stands where a folder on the way to the destination should be.
    #[error("{0} is a file, not a folder, so --out cannot be made inside it; choose another --out")]
    NotAFolder(PathBuf),
    /// `--force` was given but the destination is not a world folder.
    #[error(
        "{0} exists and is not a subtgraph world folder (no world.toml in it); refusing to replace it even with --force"
    )]
    NotAWorld(PathBuf),
    /// A file system operation failed.
    #[error("{what} {path}: {source}")]
    Io {
        /// What was being done.
        what: &'static str,
        /// On what.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The content could not be produced.
    #[error(transparent)]
    Content(#[from] anyhow::Error),
}

fn io<'a>(what: &'static str, path: &'a Path) -> impl FnOnce(std::io::Error) -> FolderError + 'a {
    move |source| FolderError::Io {
        what,
        path: path.to_owned(),
        source,
    }
}

/// Writes a world folder at `out` through `fill`, atomically. With `force`, an existing world
/// folder (one holding `world.toml`) or an empty folder is replaced.
pub fn write_atomically(
    out: &Path,
    force: bool,
    fill: impl FnOnce(&mut FolderWriter) -> anyhow::Result<()>,
) -> Result<(), FolderError> {
    if out.exists() {
        if !force {
            return Err(FolderError::Exists(out.to_owned()));
        }
        let is_world = out.join("world.toml").is_file();
        let is_empty = out.is_dir()
            && fs::read_dir(out)
                .map_err(io("reading", out))?
                .next()
                .is_none();
        if !(is_world || is_empty) {
            return Err(FolderError::NotAWorld(out.to_owned()));
        }
    }
    let name = out
        .file_name()
        .ok_or_else(|| FolderError::Io {
            what: "naming",
            path: out.to_owned(),
            source: std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "--out must name a folder, like worlds/cave-7",
            ),
        })?
        .to_string_lossy()
        .into_owned();
    let parent = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_owned(),
        _ => PathBuf::from("."),
    };
    if let Some(file) = parent
        .ancestors()
        .find(|a| a.exists())
        .filter(|a| !a.is_dir())
    {
        return Err(FolderError::NotAFolder(file.to_owned()));
    }
    fs::create_dir_all(&parent).map_err(io("creating", &parent))?;
    let stamp = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let tmp = parent.join(format!(".{name}.partial-{}-{stamp}", std::process::id()));
    fs::create_dir(&tmp).map_err(io("creating", &tmp))?;
    let mut writer = FolderWriter { root: tmp.clone() };
    if let Err(e) = fill(&mut writer) {
        let _ = fs::remove_dir_all(&tmp);
        return Err(FolderError::Content(e));
    }
    if out.exists() {
        let old = parent.join(format!(".{name}.replaced-{}-{stamp}", std::process::id()));
        if let Err(e) = fs::rename(out, &old) {
            let _ = fs::remove_dir_all(&tmp);
            return Err(io("moving aside", out)(e));
        }
        if let Err(e) = fs::rename(&tmp, out) {
            let _ = fs::rename(&old, out);
            let _ = fs::remove_dir_all(&tmp);
            return Err(io("renaming into place", out)(e));
        }
        let _ = fs::remove_dir_all(&old);
    } else if let Err(e) = fs::rename(&tmp, out) {
        let _ = fs::remove_dir_all(&tmp);
        return Err(io("renaming into place", out)(e));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failure_leaves_nothing_and_success_replaces_only_worlds() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("w");
        let e = write_atomically(&out, false, |w| {
            w.write("world.toml", b"x")?;
            anyhow::bail!("disk full")
        })
        .unwrap_err();
        assert!(e.to_string().contains("disk full"));
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 0, "no leftovers");

        write_atomically(&out, false, |w| Ok(w.write("world.toml", b"1")?)).unwrap();
        let e = write_atomically(&out, false, |_| Ok(())).unwrap_err();
        assert!(matches!(e, FolderError::Exists(_)));
        write_atomically(&out, true, |w| Ok(w.write("world.toml", b"2")?)).unwrap();
        assert_eq!(fs::read(out.join("world.toml")).unwrap(), b"2");
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 1);

        let precious = dir.path().join("home");
        fs::create_dir(&precious).unwrap();
        fs::write(precious.join("thesis.tex"), b"...").unwrap();
        let e = write_atomically(&precious, true, |_| Ok(())).unwrap_err();
        assert!(matches!(e, FolderError::NotAWorld(_)));
        assert!(precious.join("thesis.tex").exists());
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
