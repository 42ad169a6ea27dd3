//! `--out` is never the current folder nor a folder holding it (issue 37, item 12): `--out .`
//! wrote the world into a new subfolder named after the current folder and said `wrote .`;
//! `--out ..` the same one level up; and with `--force` the user's own folder would be the one
//! checked for replacing. A command writes a new folder of its own, so these are refused,
//! before any work, for every command that writes one (and Python's `World.export`).

use std::path::{Path, PathBuf};

use super::FolderError;

/// Refuses `out` (as given; `resolved` is it with links and `..` resolved) when it is the
/// current folder or holds it.
pub(super) fn not_current(out: &Path, resolved: PathBuf) -> Result<(), FolderError> {
    let Ok(current) = std::env::current_dir().and_then(|d| d.canonicalize()) else {
        return Ok(());
    };
    if !current.starts_with(&resolved) {
        return Ok(());
    }
    Err(FolderError::CurrentFolder {
        out: out.to_owned(),
        how: if current == resolved { "is" } else { "holds" },
        current,
    })
}

/// Refuses `out` when it is the current folder or holds it, for a folder given by its path
/// alone (a dataset's `--out`).
pub fn not_current_folder(out: &Path) -> Result<(), FolderError> {
    not_current(out, resolved(out))
}

/// `path` with its existing part resolved (links, `..`), the rest appended as written.
pub(super) fn resolved(path: &Path) -> PathBuf {
    let mut rest = Vec::new();
    let mut at = path;
    loop {
        if let Ok(real) = at.canonicalize() {
            let mut out = real;
            out.extend(rest.iter().rev());
            return out;
        }
        match (at.file_name(), at.parent()) {
            (Some(name), Some(parent)) => {
                rest.push(name.to_owned());
                at = if parent.as_os_str().is_empty() {
                    Path::new(".")
                } else {
                    parent
                };
            }
            _ => return path.to_owned(),
        }
    }
}
