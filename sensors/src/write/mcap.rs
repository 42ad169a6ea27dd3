//! An MCAP writer (the container ROS 2 bags are stored in since Iron): messages grouped into
//! LZ4-compressed chunks, each followed by its message indexes, and a summary section with the
//! schemas, channels, statistics and chunk indexes, so readers can seek.
//!
//! Records follow the MCAP specification (version 0, `ros2` profile). Memory is bounded by one
//! chunk and the chunk indexes (about 100 bytes per chunk of `CHUNK` bytes), whatever the
//! length of the recording. Every checksum the format has is filled in (chunk, data section,
//! summary), so a damaged file is caught by any reader.

use std::collections::BTreeMap;
use std::io::{self, Write};

/// Uncompressed bytes per chunk: about one OS1-32 scan's cloud (the MCAP library's own writers
/// default to 768 KiB). A chunk is compressed in one go by the thread that writes, while the
/// other casts the next scan; chunks of 8 MiB (six scans) left that core idle for most of each
/// compression, and `sense` took 6 % longer by the wall clock.
const CHUNK: usize = 1 << 20;
const MAGIC: &[u8] = b"\x89MCAP0\r\n";

/// Writes and checksums.
struct Out<W: Write> {
    inner: W,
    written: u64,
    crc: crc32fast::Hasher,
}

impl<W: Write> Out<W> {
    fn write(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.inner.write_all(bytes)?;
        self.crc.update(bytes);
        self.written += bytes.len() as u64;
        Ok(())
    }

    fn record(&mut self, op: u8, body: &[u8]) -> io::Result<()> {
        self.write(&[op])?;
        self.write(&(body.len() as u64).to_le_bytes())?;
        self.write(body)
    }
}

fn string(b: &mut Vec<u8>, s: &str) {
    b.extend_from_slice(&(s.len() as u32).to_le_bytes());
    b.extend_from_slice(s.as_bytes());
}

/// A channel's message count and the last sequence number.
#[derive(Default)]
struct Count {
    messages: u64,
}

/// An MCAP file being written.
pub struct Mcap<W: Write> {
    out: Out<W>,
    schemas: Vec<Vec<u8>>,
    channels: Vec<Vec<u8>>,
    counts: BTreeMap<u16, Count>,
    chunk: Vec<u8>,
    /// The last chunk compressed (kept: a new buffer each chunk costs page faults).
    compressed: Vec<u8>,
    chunk_times: (u64, u64),
    chunk_index: BTreeMap<u16, Vec<(u64, u64)>>,
    chunk_indexes: Vec<Vec<u8>>,
    times: (u64, u64),
    metadata: Vec<(String, u64, u64)>,
}

impl<W: Write> Mcap<W> {
    /// Starts a file with the `ros2` profile.
    pub fn new(inner: W) -> io::Result<Mcap<W>> {
        let mut out = Out {
            inner,
            written: 0,
            crc: crc32fast::Hasher::new(),
        };
        out.write(MAGIC)?;
        let mut h = Vec::new();
        string(&mut h, "ros2");
        string(&mut h, concat!("subtgraph ", env!("CARGO_PKG_VERSION")));
        out.record(0x01, &h)?;
        Ok(Mcap {
            out,
            schemas: Vec::new(),
            channels: Vec::new(),
            counts: BTreeMap::new(),
            chunk: Vec::with_capacity(CHUNK + (2 << 20)),
            compressed: Vec::with_capacity(CHUNK + (1 << 20)),
            chunk_times: (u64::MAX, 0),
            chunk_index: BTreeMap::new(),
            chunk_indexes: Vec::new(),
            times: (u64::MAX, 0),
            metadata: Vec::new(),
        })
    }

    /// Adds a `ros2msg` schema; returns its id.
    pub fn schema(&mut self, name: &str, definition: &str) -> io::Result<u16> {
        let id = self.schemas.len() as u16 + 1;
        let mut b = Vec::new();
        b.extend_from_slice(&id.to_le_bytes());
        string(&mut b, name);
        string(&mut b, "ros2msg");
        string(&mut b, definition);
        self.out.record(0x03, &b)?;
        self.schemas.push(b);
        Ok(id)
    }

    /// Adds a CDR channel on `topic` with `schema`, its metadata (rosbag2's
    /// `offered_qos_profiles`); returns its id.
    pub fn channel(
        &mut self,
        schema: u16,
        topic: &str,
        metadata: &[(&str, &str)],
    ) -> io::Result<u16> {
        let id = self.channels.len() as u16 + 1;
        let mut b = Vec::new();
        b.extend_from_slice(&id.to_le_bytes());
        b.extend_from_slice(&schema.to_le_bytes());
        string(&mut b, topic);
        string(&mut b, "cdr");
        let mut m = Vec::new();
        for (k, v) in metadata {
            string(&mut m, k);
            string(&mut m, v);
        }
        b.extend_from_slice(&(m.len() as u32).to_le_bytes());
        b.extend_from_slice(&m);
        self.out.record(0x04, &b)?;
        self.channels.push(b);
        self.counts.insert(id, Count::default());
        Ok(id)
    }

    /// A message on `channel` logged at `log_time` (ns), published at `publish_time`, whose
    /// data `fill` appends.
    pub fn message(
        &mut self,
        channel: u16,
        log_time: u64,
        publish_time: u64,
        fill: impl FnOnce(&mut Vec<u8>),
    ) -> io::Result<()> {
        let count = self
            .counts
            .get_mut(&channel)
            .expect("a channel of this file");
        let sequence = count.messages as u32;
        count.messages += 1;
        let offset = self.chunk.len() as u64;
        self.chunk.push(0x05);
        let len_at = self.chunk.len();
        self.chunk.extend_from_slice(&[0; 8]);
        self.chunk.extend_from_slice(&channel.to_le_bytes());
        self.chunk.extend_from_slice(&sequence.to_le_bytes());
        self.chunk.extend_from_slice(&log_time.to_le_bytes());
        self.chunk.extend_from_slice(&publish_time.to_le_bytes());
        fill(&mut self.chunk);
        let len = (self.chunk.len() - len_at - 8) as u64;
        self.chunk[len_at..len_at + 8].copy_from_slice(&len.to_le_bytes());
        self.chunk_index
            .entry(channel)
            .or_default()
            .push((log_time, offset));
        self.chunk_times = (
            self.chunk_times.0.min(log_time),
            self.chunk_times.1.max(log_time),
        );
        self.times = (self.times.0.min(log_time), self.times.1.max(log_time));
        if self.chunk.len() >= CHUNK {
            self.close_chunk()?;
        }
        Ok(())
    }

    /// Compresses and writes the chunk so far, with its message indexes.
    fn close_chunk(&mut self) -> io::Result<()> {
        if self.chunk.is_empty() {
            return Ok(());
        }
        let crc = crc32fast::hash(&self.chunk);
        self.compressed.clear();
        {
            let mut enc = lz4_flex::frame::FrameEncoder::new(&mut self.compressed);
            enc.write_all(&self.chunk)?;
            enc.finish().map_err(io::Error::other)?;
        }
        // The chunk record's fields, then its compressed records straight from their buffer.
        let mut head = Vec::with_capacity(64);
        head.extend_from_slice(&self.chunk_times.0.to_le_bytes());
        head.extend_from_slice(&self.chunk_times.1.to_le_bytes());
        head.extend_from_slice(&(self.chunk.len() as u64).to_le_bytes());
        head.extend_from_slice(&crc.to_le_bytes());
        string(&mut head, "lz4");
        head.extend_from_slice(&(self.compressed.len() as u64).to_le_bytes());
        let start = self.out.written;
        self.out.write(&[0x06])?;
        self.out
            .write(&((head.len() + self.compressed.len()) as u64).to_le_bytes())?;
        self.out.write(&head)?;
        self.out.write(&self.compressed)?;
        let chunk_length = self.out.written - start;
        let index_start = self.out.written;
        let mut offsets = Vec::new();
        for (channel, entries) in std::mem::take(&mut self.chunk_index) {
            offsets.push((channel, self.out.written));
            let mut m = Vec::with_capacity(6 + entries.len() * 16);
            m.extend_from_slice(&channel.to_le_bytes());
            m.extend_from_slice(&((entries.len() * 16) as u32).to_le_bytes());
            for (t, o) in entries {
                m.extend_from_slice(&t.to_le_bytes());
                m.extend_from_slice(&o.to_le_bytes());
            }
            self.out.record(0x07, &m)?;
        }
        let mut ci = Vec::new();
        ci.extend_from_slice(&self.chunk_times.0.to_le_bytes());
        ci.extend_from_slice(&self.chunk_times.1.to_le_bytes());
        ci.extend_from_slice(&start.to_le_bytes());
        ci.extend_from_slice(&chunk_length.to_le_bytes());
        ci.extend_from_slice(&((offsets.len() * 10) as u32).to_le_bytes());
        for (c, o) in offsets {
            ci.extend_from_slice(&c.to_le_bytes());
            ci.extend_from_slice(&o.to_le_bytes());
        }
        ci.extend_from_slice(&(self.out.written - index_start).to_le_bytes());
        string(&mut ci, "lz4");
        ci.extend_from_slice(&(self.compressed.len() as u64).to_le_bytes());
        ci.extend_from_slice(&(self.chunk.len() as u64).to_le_bytes());
        self.chunk_indexes.push(ci);
        self.chunk.clear();
        self.chunk_times = (u64::MAX, 0);
        Ok(())
    }

    /// A metadata record (rosbag2 keeps its `metadata.yaml` text in one named `rosbag2`).
    pub fn metadata(&mut self, name: &str, entries: &[(&str, &str)]) -> io::Result<()> {
        self.close_chunk()?;
        let mut b = Vec::new();
        string(&mut b, name);
        let mut m = Vec::new();
        for (k, v) in entries {
            string(&mut m, k);
            string(&mut m, v);
        }
        b.extend_from_slice(&(m.len() as u32).to_le_bytes());
        b.extend_from_slice(&m);
        let start = self.out.written;
        self.out.record(0x0C, &b)?;
        self.metadata
            .push((name.to_owned(), start, self.out.written - start));
        Ok(())
    }

    /// Messages written per channel id.
    pub fn counts(&self) -> Vec<(u16, u64)> {
        self.counts.iter().map(|(&c, n)| (c, n.messages)).collect()
    }

    /// The first and last log times (ns), if any message was written.
    pub fn span(&self) -> Option<(u64, u64)> {
        (self.times.0 <= self.times.1).then_some(self.times)
    }

    /// Writes the last chunk, the summary and the footer; returns the writer and the bytes
    /// written.
    pub fn finish(mut self) -> io::Result<(W, u64)> {
        self.close_chunk()?;
        let data_crc = self.out.crc.clone().finalize();
        self.out.record(0x0F, &data_crc.to_le_bytes())?;
        // The summary's checksum starts here.
        self.out.crc = crc32fast::Hasher::new();
        let summary_start = self.out.written;
        let mut groups: Vec<(u8, u64, u64)> = Vec::new();
        let mut group = |out: &mut Out<W>, op: u8, records: &[Vec<u8>]| -> io::Result<()> {
            if records.is_empty() {
                return Ok(());
            }
            let start = out.written;
            for r in records {
                out.record(op, r)?;
            }
            groups.push((op, start, out.written - start));
            Ok(())
        };
        group(&mut self.out, 0x03, &self.schemas)?;
        group(&mut self.out, 0x04, &self.channels)?;
        let message_count: u64 = self.counts.values().map(|c| c.messages).sum();
        let (first, last) = self.span().unwrap_or((0, 0));
        let mut st = Vec::new();
        st.extend_from_slice(&message_count.to_le_bytes());
        st.extend_from_slice(&(self.schemas.len() as u16).to_le_bytes());
        st.extend_from_slice(&(self.channels.len() as u32).to_le_bytes());
        st.extend_from_slice(&0u32.to_le_bytes());
        st.extend_from_slice(&(self.metadata.len() as u32).to_le_bytes());
        st.extend_from_slice(&(self.chunk_indexes.len() as u32).to_le_bytes());
        st.extend_from_slice(&first.to_le_bytes());
        st.extend_from_slice(&last.to_le_bytes());
        st.extend_from_slice(&((self.counts.len() * 10) as u32).to_le_bytes());
        for (c, n) in &self.counts {
            st.extend_from_slice(&c.to_le_bytes());
            st.extend_from_slice(&n.messages.to_le_bytes());
        }
        group(&mut self.out, 0x0B, &[st])?;
        group(&mut self.out, 0x08, &self.chunk_indexes)?;
        let metadata_index: Vec<Vec<u8>> = self
            .metadata
            .iter()
            .map(|(name, offset, length)| {
                let mut b = Vec::new();
                b.extend_from_slice(&offset.to_le_bytes());
                b.extend_from_slice(&length.to_le_bytes());
                string(&mut b, name);
                b
            })
            .collect();
        group(&mut self.out, 0x0D, &metadata_index)?;
        let offsets_start = self.out.written;
        for (op, start, length) in groups {
            let mut b = vec![op];
            b.extend_from_slice(&start.to_le_bytes());
            b.extend_from_slice(&length.to_le_bytes());
            self.out.record(0x0E, &b)?;
        }
        // The footer: its checksum covers the summary up to its own crc field.
        let mut f = Vec::new();
        f.extend_from_slice(&summary_start.to_le_bytes());
        f.extend_from_slice(&offsets_start.to_le_bytes());
        let mut crc = self.out.crc.clone();
        crc.update(&[0x02]);
        crc.update(&20u64.to_le_bytes());
        crc.update(&f);
        f.extend_from_slice(&crc.finalize().to_le_bytes());
        self.out.record(0x02, &f)?;
        self.out.write(MAGIC)?;
        self.out.inner.flush()?;
        Ok((self.out.inner, self.out.written))
    }
}
