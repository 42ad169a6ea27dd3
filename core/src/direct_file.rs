//! Large files written around the page cache: a world's meshes and scene files, a sensor
//! sequence's bag and KITTI scans.
//!
//! A mine's world folder with every format is close to a gigabyte, a sensor sequence 1.4 MB a
//! scan (13 GB for 9,300 OS1-32 scans). Written the ordinary way, every byte is first copied
//! into the kernel's page cache, and on the development machine that copy costs about 2 s of
//! CPU per GB (`dd bs=4M`: 2.8 s of system time for 1 GB buffered, 0.17 s with
//! `oflag=direct`): more than a sequence's LZ4 compression. With `O_DIRECT` (Linux) the disk
//! reads the bytes straight from our buffer instead, so [`DirectFile`] gathers them in a
//! buffer aligned to 4 KiB and writes whole multiples of 4 KiB that way; the last partial
//! block is written the ordinary way once the flag is cleared. The bytes on disk are the same.
//!
//! Where the file system refuses `O_DIRECT` (tmpfs, some network and overlay file systems),
//! or on other systems, the file is written the ordinary way, through the same buffer.
//!
//! A write with `O_DIRECT` returns once the disk has the bytes (about a millisecond a sensor
//! scan on that machine's disk), in which the thread that wrote would stand idle. So the
//! writes themselves are done by a thread of their own, a [`Spool`]: a full buffer is handed
//! to it and filling goes on in a second one. The files are written in the order their
//! buffers were handed over, and a write's error comes back with its buffer, so it is reported
//! at the next buffer handed over, or by [`Spool::close`].

use std::fs::File;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

/// The alignment `O_DIRECT` asks of buffers, lengths and file offsets (a page, which covers
/// every logical block size in use).
const ALIGN: usize = 4096;
/// Bytes gathered before a write: big enough that a write's fixed cost is small, small enough
/// to stay out of the way of the scans' buffers.
const CAPACITY: usize = 4 << 20;
/// Buffers a spool has: one being filled while the other is written.
const BUFFERS: usize = 2;

/// A buffer of 4 MiB starting at a multiple of 4 KiB: a vector a block longer, used from its
/// first aligned byte (no allocator tricks, no unsafe code).
struct Aligned {
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

impl Aligned {
    fn bytes(&self) -> &[u8] {
        &self.raw[self.start..self.start + CAPACITY]
    }

    fn bytes_mut(&mut self) -> &mut [u8] {
        &mut self.raw[self.start..self.start + CAPACITY]
    }
}

/// An open file as the spool's thread writes it.
struct Open {
    file: File,
    path: PathBuf,
    /// Whether the file is still open with `O_DIRECT`.
    direct: bool,
}

impl Open {
    /// From here on, the ordinary way (`O_DIRECT` cleared).
    fn plain(&mut self) -> io::Result<()> {
        clear_direct(&self.file)?;
        self.direct = false;
        Ok(())
    }
}

/// A buffer to write: its first `len` bytes go to the end of `open`; with `last`, the partial
/// block at the end too (written the ordinary way, as is all that follows it).
struct Job {
    open: Arc<Mutex<Open>>,
    buf: Aligned,
    len: usize,
    last: bool,
}

/// A thread that writes [`DirectFile`]s' buffers, so the threads that fill them never wait
/// for the disk (see the module). Keep one for many files in a row ([`DirectFile::finish`]
/// gives it back), and end it with [`close`](Spool::close), which waits for every write and
/// reports the first that failed.
pub struct Spool {
    jobs: Option<SyncSender<Job>>,
    back: Receiver<(Aligned, io::Result<()>)>,
    thread: Option<JoinHandle<()>>,
    /// Buffers at hand.
    free: Vec<Aligned>,
    /// Buffers with the thread.
    lent: usize,
}

impl Spool {
    /// Starts the thread, with two buffers.
    pub fn new() -> io::Result<Spool> {
        let (jobs, todo) = sync_channel::<Job>(BUFFERS);
        let (done, back) = sync_channel(BUFFERS);
        let thread = std::thread::Builder::new()
            .name("subtgraph-spool".into())
            .spawn(move || {
                for job in todo {
                    let result = {
                        let mut open = job.open.lock().unwrap_or_else(|e| e.into_inner());
                        write_out(&mut open, &job.buf.bytes()[..job.len], job.last)
                    };
                    if done.send((job.buf, result)).is_err() {
                        break;
                    }
                }
            })?;
        Ok(Spool {
            jobs: Some(jobs),
            back,
            thread: Some(thread),
            free: (0..BUFFERS).map(|_| Aligned::default()).collect(),
            lent: 0,
        })
    }

    /// A buffer to fill: one at hand, or the next the thread gives back (an error of the
    /// write it was used for comes out here).
    fn take(&mut self) -> io::Result<Aligned> {
        if let Some(buf) = self.free.pop() {
            return Ok(buf);
        }
        if self.lent == 0 {
            return Ok(Aligned::default());
        }
        let (buf, result) = self.back.recv().map_err(|_| stopped())?;
        self.lent -= 1;
        match result {
            Ok(()) => Ok(buf),
            Err(e) => {
                self.free.push(buf);
                Err(e)
            }
        }
    }

    fn send(&mut self, job: Job) -> io::Result<()> {
        let jobs = self.jobs.as_ref().ok_or_else(stopped)?;
        jobs.send(job).map_err(|_| stopped())?;
        self.lent += 1;
        Ok(())
    }

    /// Waits for every buffer handed over to be written; the first write that failed is the
    /// error.
    fn wait(&mut self) -> io::Result<()> {
        let mut first = Ok(());
        while self.lent > 0 {
            let (buf, result) = self.back.recv().map_err(|_| stopped())?;
            self.lent -= 1;
            self.free.push(buf);
            if first.is_ok() {
                first = result;
            }
        }
        first
    }

    /// Waits for every write, stops the thread, and reports the first write that failed.
    pub fn close(mut self) -> io::Result<()> {
        let result = self.wait();
        self.stop();
        result
    }

    fn stop(&mut self) {
        self.jobs = None;
        if let Some(thread) = self.thread.take() {
            // The thread only writes; a panic there (none is expected) loses nothing more.
            let _ = thread.join();
        }
    }
}

impl Drop for Spool {
    /// Lets the writes handed over finish (the files are whole or the error was reported)
    /// before the thread ends.
    fn drop(&mut self) {
        self.stop();
    }
}

/// The spool's thread has stopped (it only does after a panic).
fn stopped() -> io::Error {
    io::Error::other("the spool's writing thread stopped")
}

/// Writes `bytes` at the end of `open`: with `O_DIRECT`, whole blocks (the caller gives whole
/// blocks unless `last`), the last partial block the ordinary way.
fn write_out(open: &mut Open, bytes: &[u8], last: bool) -> io::Result<()> {
    let with_path =
        |path: &Path, e: io::Error| io::Error::new(e.kind(), format!("{}: {e}", path.display()));
    let mut done = 0;
    while done < bytes.len() {
        if open.direct && bytes.len() - done < ALIGN {
            debug_assert!(
                last,
                "only the last buffer of a file ends in a partial block"
            );
            // The last partial block: the ordinary way.
            open.plain().map_err(|e| with_path(&open.path, e))?;
        }
        let end = if open.direct {
            done + (bytes.len() - done) / ALIGN * ALIGN
        } else {
            bytes.len()
        };
        match open.file.write(&bytes[done..end]) {
            Ok(0) => return Err(with_path(&open.path, io::ErrorKind::WriteZero.into())),
            Ok(n) => done += n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            // Refused after all (the file system takes the flag at open but not the
            // writes): the ordinary way from here.
            Err(e) if open.direct && e.kind() == io::ErrorKind::InvalidInput => {
                open.plain().map_err(|e| with_path(&open.path, e))?;
            }
            Err(e) => return Err(with_path(&open.path, e)),
        }
    }
    Ok(())
}

/// A file being written with `O_DIRECT` where the file system allows it, by a [`Spool`]'s
/// thread (see the module). End it with [`finish`](DirectFile::finish), or `flush` to have
/// everything on disk: dropped, it loses what it has gathered (up to 4 MiB).
pub struct DirectFile {
    open: Arc<Mutex<Open>>,
    spool: Spool,
    buf: Aligned,
    /// Bytes in `buf`.
    len: usize,
}

impl DirectFile {
    /// Creates (or truncates) the file at `path`, to be written by `spool`.
    pub fn create(path: &Path, mut spool: Spool) -> io::Result<DirectFile> {
        let (file, direct) = open(path)?;
        let buf = spool.take()?;
        Ok(DirectFile {
            open: Arc::new(Mutex::new(Open {
                file,
                path: path.to_owned(),
                direct,
            })),
            spool,
            buf,
            len: 0,
        })
    }

    /// Hands the gathered bytes to the spool and takes a fresh buffer.
    fn hand_over(&mut self, last: bool) -> io::Result<()> {
        let fresh = self.spool.take()?;
        let buf = std::mem::replace(&mut self.buf, fresh);
        let len = std::mem::take(&mut self.len);
        self.spool.send(Job {
            open: Arc::clone(&self.open),
            buf,
            len,
            last,
        })
    }

    /// Hands the rest to the spool and gives the spool back for the next file (without
    /// waiting for the writes: [`Spool::close`] does).
    pub fn finish(mut self) -> io::Result<Spool> {
        self.hand_over(true)?;
        let DirectFile { mut spool, buf, .. } = self;
        spool.free.push(buf);
        Ok(spool)
    }
}

impl Write for DirectFile {
    fn write(&mut self, data: &[u8]) -> io::Result<usize> {
        let n = data.len().min(CAPACITY - self.len);
        let at = self.len;
        self.buf.bytes_mut()[at..at + n].copy_from_slice(&data[..n]);
        self.len += n;
        if self.len == CAPACITY {
            self.hand_over(false)?;
        }
        Ok(n)
    }

    /// Writes everything gathered, a partial last block included (that block, and all that
    /// follows it, the ordinary way), and waits until it is written.
    fn flush(&mut self) -> io::Result<()> {
        self.hand_over(true)?;
        self.spool.wait()
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
        // SplitMix64 of the seed and the index.
        (0..n as u64)
            .map(|i| {
                let mut z = (seed << 32 ^ i).wrapping_add(0x9e37_79b9_7f4a_7c15);
                z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
                z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
                (z ^ (z >> 31)) as u8
            })
            .collect()
    }

    fn round_trip(dir: &Path) {
        let mut spool = Spool::new().unwrap();
        // Empty, under a block, exactly blocks, over the buffer, many buffers and a tail.
        let mut files = Vec::new();
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
            let mut f = DirectFile::create(&path, spool).unwrap();
            // Pieces of uneven sizes, as the MCAP writer's records come.
            let mut rest = &want[..];
            let mut size = 1;
            while !rest.is_empty() {
                let (piece, tail) = rest.split_at(size.min(rest.len()));
                f.write_all(piece).unwrap();
                rest = tail;
                size = size * 7 % 1_000_003 + 13;
            }
            spool = f.finish().unwrap();
            files.push((path, want));
        }
        // A flush midway: it waits for the writes, and what follows is written the ordinary
        // way, after the tail.
        let path = dir.join("flushed.bin");
        let (a, b) = (data(10_000, 1), data(20_000, 2));
        let mut f = DirectFile::create(&path, spool).unwrap();
        f.write_all(&a).unwrap();
        f.flush().unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), a);
        f.write_all(&b).unwrap();
        f.finish().unwrap().close().unwrap();
        files.push((path, [a, b].concat()));
        // Every file whole once the spool is closed.
        for (path, want) in files {
            assert_eq!(std::fs::read(&path).unwrap(), want, "{}", path.display());
        }
    }

    #[test]
    fn a_failed_write_is_reported() {
        // A file opened read-only cannot be written: the error comes back from the spool's
        // thread, at the next buffer handed over or when the spool closes.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("ro.bin");
        std::fs::write(&path, b"").unwrap();
        let mut f = DirectFile::create(&path, Spool::new().unwrap()).unwrap();
        f.open = Arc::new(Mutex::new(Open {
            file: File::open(&path).unwrap(),
            path: path.clone(),
            direct: false,
        }));
        f.write_all(&data(100, 3)).unwrap();
        let err = f.finish().unwrap().close().unwrap_err();
        assert!(err.to_string().contains("ro.bin"), "{err}");
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
