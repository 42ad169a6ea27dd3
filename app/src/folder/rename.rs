//! Moving folders into place without ever replacing what is there: `RENAME_NOREPLACE` and
//! `RENAME_EXCHANGE` where the system has them, and names no other run uses.

use std::fs;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use super::{FolderError, io};

/// Moves `from` to `to` only if nothing is at `to`: atomic where the system allows, and
/// otherwise a check followed by a rename that cannot replace a non-empty folder.
pub(super) fn rename_noreplace(from: &Path, to: &Path) -> std::io::Result<()> {
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
pub(super) fn exchange(a: &Path, b: &Path) -> std::io::Result<()> {
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

pub(super) fn is_exists(e: &std::io::Error) -> bool {
    e.kind() == std::io::ErrorKind::AlreadyExists
        || e.kind() == std::io::ErrorKind::DirectoryNotEmpty
}

/// A name no other run uses: the first 100 bytes of `name` (file names may be 255 bytes, and
/// the suffix must fit), the process id and the time.
pub(super) fn temporary_name(name: &str, what: &str) -> String {
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
pub(super) fn keep_elsewhere(tmp: &Path, dest: &Path, name: &str) -> Result<PathBuf, FolderError> {
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
