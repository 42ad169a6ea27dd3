//! Reading the files a user gives (pipelines, reports, maps, grids) and the files of a world
//! folder: a regular file whole, after checking its size against the memory budget; a pipe
//! (`--map <(zcat map.ply.gz)`) up to that budget; a device or anything else that is not a
//! file refused by name. `/dev/zero` or a terminal would otherwise be read until memory ran
//! out.

use std::io::Read;
use std::path::Path;

use crate::Error;

/// The most bytes one input may have: three quarters of the machine's memory (the default
/// memory budget), as nothing read can be used without holding it in memory.
pub fn limit() -> u64 {
    crate::memory::budget(None).map_or(u64::MAX, |b| b.bytes)
}

/// Reads `path` whole (at most [`limit`] bytes).
pub fn read(path: &Path) -> Result<Vec<u8>, Error> {
    read_within(path, limit())
}

/// Reads `path` whole, refusing more than `limit` bytes and anything but a file or a pipe.
pub fn read_within(path: &Path, limit: u64) -> Result<Vec<u8>, Error> {
    let reading = || Error::io(format!("reading {}", path.display()));
    let meta = std::fs::metadata(path).map_err(reading())?;
    let too_large = |size: String| {
        Error::TooLarge(format!(
            "{} holds {size}, more than this machine's memory allows (--max-memory: {}); give a smaller file",
            path.display(),
            subtgraph_core::budget::Bytes(limit)
        ))
    };
    if meta.is_file() {
        if meta.len() > limit {
            return Err(too_large(format!("{} bytes", meta.len())));
        }
        return std::fs::read(path).map_err(reading());
    }
    if meta.is_dir() {
        return Err(Error::Input(format!(
            "{} is a folder; give a file",
            path.display()
        )));
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if !meta.file_type().is_fifo() {
            return Err(Error::Input(format!(
                "{} is a device or socket, not a file: it may never end; give a file (or a pipe)",
                path.display()
            )));
        }
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(limit.saturating_add(1)).read_to_end(&mut bytes))
        .map_err(reading())?;
    if bytes.len() as u64 > limit {
        return Err(too_large(format!("more than {limit} bytes")));
    }
    Ok(bytes)
}

/// Opens `path` to be read as a stream (by a reader that checks what it reads as it goes, and
/// so needs no size limit): a file or a pipe; a folder, a device or a socket is refused as
/// [`read_within`] refuses it.
pub fn open(path: &Path) -> Result<std::fs::File, Error> {
    let reading = || Error::io(format!("reading {}", path.display()));
    let meta = std::fs::metadata(path).map_err(reading())?;
    if meta.is_dir() {
        return Err(Error::Input(format!(
            "{} is a folder; give a file",
            path.display()
        )));
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if !meta.is_file() && !meta.file_type().is_fifo() {
            return Err(Error::Input(format!(
                "{} is a device or socket, not a file: it may never end; give a file (or a pipe)",
                path.display()
            )));
        }
    }
    std::fs::File::open(path).map_err(reading())
}

/// Reads `path` as UTF-8 text (see [`read`]).
pub fn read_text(path: &Path) -> Result<String, Error> {
    String::from_utf8(read(path)?)
        .map_err(|_| Error::Input(format!("{} is not UTF-8 text", path.display())))
}
