//! Large files written around the page cache: the bag and the KITTI scans.
//!
//! A sequence is mostly point clouds, 1.4 MB a scan with both outputs (13 GB for the issue's
//! 1.8 km cave sequence). Written the ordinary way, every byte is first copied into the
//! kernel's page cache, and on this machine that copy costs about 2 s of CPU per GB (`dd
//! bs=4M`: 2.8 s of system time for 1 GB buffered, 0.17 s with `oflag=direct`): more than the
//! bag's LZ4 compression, a quarter of a sequence's CPU. With `O_DIRECT` (Linux) the disk reads
//! the bytes straight from our buffer instead, so [`DirectFile`] gathers them in a buffer
//! aligned to 4 KiB and writes whole multiples of 4 KiB that way; the last partial block is
//! written the ordinary way once the flag is cleared. The bytes on disk are the same.
//!
//! Where the file system refuses `O_DIRECT` (tmpfs, some network and overlay file systems),
//! or on other systems, the file is written the ordinary way, through the same buffer.

use std::fs::File;
use std::io::{self, Write};
use std::path::Path;

/// The alignment `O_DIRECT` asks of buffers, lengths and file offsets (a page, which covers
/// every logical block size in use).
const ALIGN: usize = 4096;
/// Bytes gathered before a write: big enough that a write's fixed cost is small, small enough
/// to stay out of the way of the scans' buffers.
const CAPACITY: usize = 4 << 20;

/// A buffer of 4 MiB starting at a multiple of 4 KiB: a vector a block longer, used from its
/// first aligned byte (no allocator tricks, no unsafe code). Keep one to reuse it from file to
/// file ([`DirectFile::finish`] gives it back).
pub struct Aligned {
    raw: Vec<u8>,
    start: usize,
}

impl Default for Aligned {
    fn default() -> Self {
        let raw = vec![0u8; CAPACITY + ALIGN];
        let start = raw.as_ptr().align_offset(ALIGN);
        Aligned { raw, start }
    }
}

/// A file being written with `O_DIRECT` where the file system allows it (see the module).
/// End it with [`finish`](DirectFile::finish) or `flush`: dropped, it loses what it has
/// gathered (up to 4 MiB).
pub struct DirectFile {
    file: File,
    buf: Aligned,
    /// Bytes in `buf`.
    len: usize,
    /// Whether the file is still open with `O_DIRECT`.
    direct: bool,
}

impl DirectFile {
    /// Creates (or truncates) the file at `path`, gathering its bytes in `buf`.
    pub fn create(path: &Path, buf: Aligned) -> io::Result<DirectFile> {
        let (file, direct) = open(path)?;
        Ok(DirectFile {
            file,
            buf,
            len: 0,
            direct,
        })
    }

    /// Writes what is gathered: with `O_DIRECT`, the whole blocks (the rest stays gathered);
    /// otherwise, or with `all`, everything.
    fn drain(&mut self, all: bool) -> io::Result<()> {
        let len = self.len;
        let whole = if self.direct && !all {
            len / ALIGN * ALIGN
        } else {
            len
        };
        let bytes = &mut self.buf.raw[self.buf.start..self.buf.start + CAPACITY];
        let mut done = 0;
        while done < whole {
            if self.direct && whole - done < ALIGN {
                // The last partial block: the ordinary way.
                clear_direct(&self.file)?;
                self.direct = false;
            }
            let end = if self.direct {
                done + (whole - done) / ALIGN * ALIGN
            } else {
                whole
            };
            match self.file.write(&bytes[done..end]) {
                Ok(0) => return Err(io::ErrorKind::WriteZero.into()),
                Ok(n) => done += n,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                // Refused after all (the file system takes the flag at open but not the
                // writes): the ordinary way from here.
                Err(e) if self.direct && e.kind() == io::ErrorKind::InvalidInput => {
                    clear_direct(&self.file)?;
                    self.direct = false;
                }
                Err(e) => return Err(e),
            }
        }
        bytes.copy_within(whole..len, 0);
        self.len -= whole;
        Ok(())
    }

    /// Writes the rest and closes the file; gives the buffer back for the next.
    pub fn finish(mut self) -> io::Result<Aligned> {
        self.drain(true)?;
        Ok(self.buf)
    }
}

impl Write for DirectFile {
    fn write(&mut self, data: &[u8]) -> io::Result<usize> {
        let n = data.len().min(CAPACITY - self.len);
        let at = self.buf.start + self.len;
        self.buf.raw[at..at + n].copy_from_slice(&data[..n]);
        self.len += n;
        if self.len == CAPACITY {
            self.drain(false)?;
        }
        Ok(n)
    }

    /// Writes everything gathered, the partial last block included (after which the file is
    /// written the ordinary way).
    fn flush(&mut self) -> io::Result<()> {
        self.drain(true)
    }
}

/// `path` created for writing with `O_DIRECT` if the file system takes it (and whether it did).
#[cfg(target_os = "linux")]
fn open(path: &Path) -> io::Result<(File, bool)> {
    use std::os::unix::fs::OpenOptionsExt;
    let mut options = std::fs::OpenOptions::new();
    options.write(true).create(true).truncate(true);
    let flag = rustix::fs::OFlags::DIRECT.bits() as i32;
    match options.clone().custom_flags(flag).open(path) {
        Ok(f) => Ok((f, true)),
        Err(e) if e.kind() == io::ErrorKind::InvalidInput => Ok((options.open(path)?, false)),
        Err(e) => Err(e),
    }
}

#[cfg(not(target_os = "linux"))]
fn open(path: &Path) -> io::Result<(File, bool)> {
    Ok((File::create(path)?, false))
}

#[cfg(target_os = "linux")]
fn clear_direct(file: &File) -> io::Result<()> {
    use rustix::fs::{OFlags, fcntl_getfl, fcntl_setfl};
    let flags = fcntl_getfl(file)?;
    fcntl_setfl(file, flags - OFlags::DIRECT)?;
    Ok(())
}

#[cfg(not(target_os = "linux"))]
fn clear_direct(_: &File) -> io::Result<()> {
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bytes that differ from block to block, so a block written twice or skipped shows.
    fn data(n: usize, seed: u64) -> Vec<u8> {
        (0..n as u64)
            .map(|i| crate::noise::hash(seed, i) as u8)
            .collect()
    }

    fn round_trip(dir: &Path) {
        let mut buf = Aligned::default();
        // Empty, under a block, exactly blocks, over the buffer, many buffers and a tail.
        for (k, n) in [
            0,
            1,
            4095,
            4096,
            8192,
            12_345,
            CAPACITY,
            CAPACITY + 1,
            9_999_999,
        ]
        .into_iter()
        .enumerate()
        {
            let path = dir.join(format!("{k}.bin"));
            let want = data(n, k as u64);
            let mut f = DirectFile::create(&path, buf).unwrap();
            // Pieces of uneven sizes, as the MCAP writer's records come.
            let mut rest = &want[..];
            let mut size = 1;
            while !rest.is_empty() {
                let (piece, tail) = rest.split_at(size.min(rest.len()));
                f.write_all(piece).unwrap();
                rest = tail;
                size = size * 7 % 1_000_003 + 13;
            }
            buf = f.finish().unwrap();
            assert_eq!(std::fs::read(&path).unwrap(), want, "{n} bytes");
        }
        // A flush midway: what follows is written the ordinary way, after the tail.
        let path = dir.join("flushed.bin");
        let (a, b) = (data(10_000, 1), data(20_000, 2));
        let mut f = DirectFile::create(&path, buf).unwrap();
        f.write_all(&a).unwrap();
        f.flush().unwrap();
        f.write_all(&b).unwrap();
        f.finish().unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), [a, b].concat());
    }

    #[test]
    fn files_hold_exactly_the_bytes_written() {
        let dir = tempfile::tempdir().unwrap();
        round_trip(dir.path());
        // A file system that refuses O_DIRECT at open (tmpfs), where there is one.
        let shm = Path::new("/dev/shm");
        if shm.is_dir()
            && let Ok(dir) = tempfile::tempdir_in(shm)
        {
            round_trip(dir.path());
        }
    }
}
