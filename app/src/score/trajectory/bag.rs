//! Trajectories from ROS 2 bags: the poses of one topic of a bag in MCAP storage (a bag folder
//! with `metadata.yaml`, or one `.mcap` file), as `ros2 bag record` and `subtgraph sense` write
//! them and as evo reads them (`evo_ape bag2`).
//!
//! - Storage: MCAP, its chunks uncompressed, LZ4 or Zstandard (the three the format allows).
//!   A bag in the older SQLite storage (`.db3`) is refused with how to convert it.
//! - Messages: `nav_msgs/msg/Odometry`, `geometry_msgs/msg/PoseStamped`,
//!   `geometry_msgs/msg/PoseWithCovarianceStamped` and `geometry_msgs/msg/TransformStamped`
//!   (evo's list, less `PointStamped`, which has no orientation), in CDR either byte order.
//! - Times: each message's `header.stamp` (as evo takes them), not the time it was logged;
//!   messages are taken in the order they were logged.
//!
//! Every length is checked against what is left of the file before anything is allocated, so
//! a cut or crafted bag is refused naming the file and the offset, never a panic.

use std::collections::BTreeMap;
use std::io::Read as _;
use std::path::{Path, PathBuf};

use crate::Error;

/// The MCAP magic, at the start and the end of a file.
const MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";

/// The pose message types read (their ROS 2 names).
pub const POSE_TYPES: [&str; 4] = [
    "nav_msgs/msg/Odometry",
    "geometry_msgs/msg/PoseStamped",
    "geometry_msgs/msg/PoseWithCovarianceStamped",
    "geometry_msgs/msg/TransformStamped",
];

/// A chunk larger than this uncompressed is refused (a crafted size, not a bag: rosbag2's
/// chunks are a few megabytes): 256 MiB.
const MAX_CHUNK: u64 = 1 << 28;

/// The chunks of a file may declare at most this many times the file's size uncompressed (and
/// [`INFLATION_FLOOR`] whatever the file's size): compression gives a bag's messages a few
/// times, a crafted file of zeros thousands of times (40 chunks of 256 MiB in 330 kB).
const MAX_INFLATION: u64 = 1000;

/// What the chunks of any file may declare uncompressed, however small the file: 16 MiB.
const INFLATION_FLOOR: u64 = 16 << 20;

/// The largest Zstandard window a chunk may ask for: 8 MiB, what `zstd` levels 1 to 19 use
/// (the decoder sets it aside before it reads a byte).
const MAX_WINDOW: u64 = 8 << 20;

/// Schema and channel records, and the pose messages kept, are read up to this size (a pose
/// message is a few hundred bytes); a longer message is skipped, a longer schema or channel
/// refused.
const MAX_RECORD: u64 = 1 << 20;

/// Whether `path` is a bag: a folder with `metadata.yaml` or `.mcap`/`.db3` files, or an
/// `.mcap` file.
pub fn is_bag(path: &Path) -> bool {
    if path.is_dir() {
        return path.join("metadata.yaml").is_file() || !files_with(path, "mcap").is_empty();
    }
    path.extension().is_some_and(|e| e == "mcap")
}

/// One pose message: its stamp, pose and number in the topic (1-based, for messages).
#[derive(Clone, Debug)]
pub struct Stamped {
    /// `header.stamp`, seconds.
    pub time: f64,
    /// The pose (quaternion as written; checked and normalised by the caller).
    pub position: [f64; 3],
    /// `[x, y, z, w]` as in the message.
    pub orientation: [f64; 4],
    /// The message's number on its topic, 1-based.
    pub number: usize,
}

fn files_with(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    out.sort();
    out
}

/// The `.mcap` files of a bag, in order: `metadata.yaml`'s `relative_file_paths` when it
/// lists them, else every `.mcap` file of the folder by name.
fn mcap_files(bag: &Path) -> Result<Vec<PathBuf>, Error> {
    if !bag.exists() {
        return Err(Error::Input(format!(
            "{}: no such file or folder",
            bag.display()
        )));
    }
    if bag.is_file() {
        return Ok(vec![bag.to_path_buf()]);
    }
    let db3 = files_with(bag, "db3");
    let listed = std::fs::read_to_string(bag.join("metadata.yaml"))
        .map(|text| relative_file_paths(&text))
        .unwrap_or_default();
    let files: Vec<PathBuf> = if listed.is_empty() {
        files_with(bag, "mcap")
    } else {
        listed.iter().map(|f| bag.join(f)).collect()
    };
    if files
        .iter()
        .any(|f| f.extension().is_some_and(|e| e == "db3"))
        || (files.is_empty() && !db3.is_empty())
    {
        return Err(Error::Input(format!(
            "{}: a bag in SQLite storage (.db3): only MCAP storage is read; record with `ros2 bag record -s mcap`, or convert it with `ros2 bag convert -i {} -o out.yaml` where out.yaml says `output_bags: [{{uri: BAG_mcap, storage_id: mcap}}]`",
            bag.display(),
            bag.display()
        )));
    }
    if files.is_empty() {
        return Err(Error::Input(format!(
            "{}: no .mcap file in this bag folder",
            bag.display()
        )));
    }
    Ok(files)
}

/// The entries of `relative_file_paths:` in a rosbag2 `metadata.yaml` (a block list of
/// names, the only part read).
fn relative_file_paths(yaml: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut inside: Option<usize> = None;
    for line in yaml.lines() {
        let indent = line.len() - line.trim_start().len();
        let t = line.trim();
        if let Some(k) = inside {
            if let Some(item) = t.strip_prefix("- ")
                && indent >= k
            {
                out.push(item.trim().trim_matches(['"', '\'']).to_owned());
                continue;
            }
            if !t.is_empty() {
                break;
            }
        }
        if t == "relative_file_paths:" {
            inside = Some(indent);
        }
    }
    out
}

/// A cursor over a record's bytes that refuses to read past its end.
struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Cursor<'a> {
    fn take(&mut self, n: u64) -> Option<&'a [u8]> {
        let n = usize::try_from(n).ok()?;
        let end = self.at.checked_add(n)?;
        let s = self.bytes.get(self.at..end)?;
        self.at = end;
        Some(s)
    }
    fn u16(&mut self) -> Option<u16> {
        Some(u16::from_le_bytes(self.take(2)?.try_into().ok()?))
    }
    fn u32(&mut self) -> Option<u32> {
        Some(u32::from_le_bytes(self.take(4)?.try_into().ok()?))
    }
    fn u64(&mut self) -> Option<u64> {
        Some(u64::from_le_bytes(self.take(8)?.try_into().ok()?))
    }
    fn string(&mut self) -> Option<String> {
        let n = self.u32()?;
        String::from_utf8(self.take(u64::from(n))?.to_vec()).ok()
    }
}

/// A pose message as decoded: `(stamp seconds, position, orientation [x y z w])`, `None`
/// when its bytes are not a readable message of its type.
type Decoded = Option<(f64, [f64; 3], [f64; 4])>;

/// What the records of one file say: schema names by id, channels `(topic, schema id,
/// encoding)` by id, and the pose messages `(log time, channel, decoded)`. Only messages of a
/// pose type in CDR are kept, decoded as they are met (MCAP puts a channel before its
/// messages): a bag's point clouds and images are skipped, not held.
#[derive(Default)]
struct Records {
    schemas: BTreeMap<u16, String>,
    channels: BTreeMap<u16, (String, u16, String)>,
    messages: Vec<(u64, u16, Decoded)>,
}

impl Records {
    /// The pose type of `channel`'s messages, when they are pose messages in CDR.
    fn pose_type(&self, channel: u16) -> Option<&str> {
        let (_, schema, encoding) = self.channels.get(&channel)?;
        let name = self.schemas.get(schema)?;
        (encoding == "cdr" && POSE_TYPES.contains(&name.as_str())).then_some(name.as_str())
    }

    /// Reads a schema (0x03) or channel (0x04) record's body.
    fn definition(&mut self, op: u8, body: &[u8]) -> Result<(), &'static str> {
        let mut r = Cursor { bytes: body, at: 0 };
        if op == 0x03 {
            let id = r.u16().ok_or("a schema record")?;
            let name = r.string().ok_or("a schema's name")?;
            self.schemas.insert(id, name);
        } else {
            let (Some(id), Some(schema), Some(topic), Some(encoding)) =
                (r.u16(), r.u16(), r.string(), r.string())
            else {
                return Err("a channel record");
            };
            self.channels.insert(id, (topic, schema, encoding));
        }
        Ok(())
    }
}

/// A message record's header: channel, sequence, log time, publish time.
const MESSAGE_HEAD: u64 = 22;

/// `(channel, log time)` of a message record's header.
fn message_head(head: &[u8]) -> Option<(u16, u64)> {
    let mut r = Cursor { bytes: head, at: 0 };
    let (Some(channel), Some(_sequence), Some(log_time), Some(_publish)) =
        (r.u16(), r.u32(), r.u64(), r.u64())
    else {
        return None;
    };
    Some((channel, log_time))
}

fn corrupt(file: &Path, offset: usize, what: &str) -> Error {
    Error::Input(format!(
        "{}: not a readable MCAP file at byte {offset}: {what} (cut short or not MCAP?)",
        file.display()
    ))
}

/// Reads the records of a file's data section (`bytes`, starting at byte `base` of the file)
/// into `out`.
fn records(file: &Path, bytes: &[u8], base: usize, out: &mut Records) -> Result<(), Error> {
    let mut c = Cursor { bytes, at: 0 };
    while c.at < bytes.len() {
        let at = base + c.at;
        let bad = |what: &str| corrupt(file, at, what);
        let op = c.take(1).ok_or_else(|| bad("a record's opcode"))?[0];
        let len = c.u64().ok_or_else(|| bad("a record's length"))?;
        let body = c
            .take(len)
            .ok_or_else(|| bad("a record longer than the file"))?;
        match op {
            // Footer: the end of the data.
            0x02 => return Ok(()),
            0x03 | 0x04 => out.definition(op, body).map_err(bad)?,
            0x05 => {
                let head = body
                    .get(..MESSAGE_HEAD as usize)
                    .ok_or_else(|| bad("a message record"))?;
                let (channel, log_time) =
                    message_head(head).ok_or_else(|| bad("a message record"))?;
                if let Some(schema) = out.pose_type(channel) {
                    let decoded = decode(&body[MESSAGE_HEAD as usize..], schema);
                    out.messages.push((log_time, channel, decoded));
                }
            }
            0x06 => {
                let mut r = Cursor { bytes: body, at: 0 };
                chunk(file, &mut r, base + c.at - body.len(), out)?;
            }
            _ => {}
        }
    }
    Ok(())
}

/// The uncompressed bytes the top-level chunk records of a data section declare, summed (the
/// records are walked by their lengths only; a malformed one ends the walk, and is reported
/// when the records are read).
fn declared(bytes: &[u8]) -> u64 {
    let mut c = Cursor { bytes, at: 0 };
    let mut total: u64 = 0;
    while let (Some(op), Some(len)) = (c.take(1), c.u64()) {
        let Some(body) = c.take(len) else { break };
        if op[0] == 0x06 {
            let size = body.get(16..24).map_or(0, |b| {
                u64::from_le_bytes(b.try_into().expect("eight bytes"))
            });
            total = total.saturating_add(size);
        }
    }
    total
}

/// The window a Zstandard frame's header asks for, if `data` starts with one.
fn zstd_window(data: &[u8]) -> Option<u64> {
    if data.get(..4)? != [0x28, 0xb5, 0x2f, 0xfd] {
        return None;
    }
    let descriptor = *data.get(4)?;
    if descriptor & 0x20 == 0 {
        // A window descriptor: exponent and mantissa.
        let w = *data.get(5)?;
        let base = 1u64 << (10 + u32::from(w >> 3));
        return Some(base + (base / 8) * u64::from(w & 7));
    }
    // A single segment: the window is the frame's content size.
    let dictionary = [0, 1, 2, 4][usize::from(descriptor & 3)];
    let size_bytes = [1, 2, 4, 8][usize::from(descriptor >> 6)];
    let at = 5 + dictionary;
    let mut b = [0u8; 8];
    b[..size_bytes].copy_from_slice(data.get(at..at + size_bytes)?);
    let size = u64::from_le_bytes(b);
    Some(if size_bytes == 2 { size + 256 } else { size })
}

/// A chunk record: its records, decompressed as they are read (never the whole chunk at
/// once), and checked as they come: a chunk holds schemas, channels and messages, not chunks.
fn chunk(file: &Path, r: &mut Cursor, at: usize, out: &mut Records) -> Result<(), Error> {
    let bad = |what: &str| corrupt(file, at, what);
    let (Some(_start), Some(_end), Some(size), Some(_crc), Some(compression), Some(n)) =
        (r.u64(), r.u64(), r.u64(), r.u32(), r.string(), r.u64())
    else {
        return Err(bad("a chunk record"));
    };
    let data = r.take(n).ok_or_else(|| bad("a chunk's records"))?;
    if size > MAX_CHUNK {
        return Err(bad(&format!(
            "a chunk of {size} bytes uncompressed (more than the {MAX_CHUNK} read)"
        )));
    }
    let plain: Box<dyn std::io::Read + '_> = match compression.as_str() {
        "" => Box::new(data),
        "lz4" => Box::new(lz4_flex::frame::FrameDecoder::new(data)),
        "zstd" => {
            if let Some(w) = zstd_window(data).filter(|&w| w > MAX_WINDOW) {
                return Err(bad(&format!(
                    "a Zstandard chunk asking for a window of {w} bytes, more than the {MAX_WINDOW} zstd's levels 1 to 19 use: recompress the bag (`mcap compress`)"
                )));
            }
            Box::new(
                ruzstd::decoding::StreamingDecoder::new(data)
                    .map_err(|e| bad(&format!("a Zstandard chunk: {e}")))?,
            )
        }
        other => {
            return Err(bad(&format!(
                "chunk compression '{other}': MCAP allows '', 'lz4' and 'zstd'"
            )));
        }
    };
    let mut plain = std::io::BufReader::with_capacity(1 << 16, plain.take(size));
    chunk_records(&mut plain, size, out).map_err(|what| bad(&what))
}

/// Reads `size` bytes of a chunk's records from `plain` into `out`, keeping only what
/// [`Records`] keeps; `Err` says what is wrong.
fn chunk_records(
    plain: &mut impl std::io::Read,
    size: u64,
    out: &mut Records,
) -> Result<(), String> {
    let short = |e: std::io::Error| match e.kind() {
        std::io::ErrorKind::UnexpectedEof => {
            format!("a chunk that decompresses to fewer bytes than the {size} its record says")
        }
        _ => format!("a chunk that does not decompress: {e}"),
    };
    let mut left = size;
    let skip = |plain: &mut dyn std::io::Read, n: u64| -> Result<(), String> {
        let skipped = std::io::copy(&mut plain.take(n), &mut std::io::sink()).map_err(short)?;
        if skipped < n {
            return Err(short(std::io::ErrorKind::UnexpectedEof.into()));
        }
        Ok(())
    };
    while left > 0 {
        let mut head = [0u8; 9];
        if left < 9 {
            return Err("a record cut at its chunk's end".to_owned());
        }
        plain.read_exact(&mut head).map_err(short)?;
        let op = head[0];
        let len = u64::from_le_bytes(head[1..].try_into().expect("eight bytes"));
        left -= 9;
        if len > left {
            return Err("a record longer than its chunk".to_owned());
        }
        left -= len;
        let body = |plain: &mut dyn std::io::Read, n: u64| -> Result<Vec<u8>, String> {
            let mut v = vec![0; n as usize];
            plain.read_exact(&mut v).map_err(short)?;
            Ok(v)
        };
        match op {
            0x06 => {
                return Err(
                    "a chunk inside a chunk: MCAP chunks hold schema, channel and message records only"
                        .to_owned(),
                );
            }
            0x03 | 0x04 if len > MAX_RECORD => {
                return Err(format!(
                    "a schema or channel record of {len} bytes (more than the {MAX_RECORD} read)"
                ));
            }
            0x03 | 0x04 => {
                let b = body(&mut *plain, len)?;
                out.definition(op, &b).map_err(str::to_owned)?;
            }
            0x05 if len < MESSAGE_HEAD => return Err("a message record".to_owned()),
            0x05 => {
                let head = body(&mut *plain, MESSAGE_HEAD)?;
                let (channel, log_time) = message_head(&head).ok_or("a message record")?;
                let rest = len - MESSAGE_HEAD;
                match out.pose_type(channel) {
                    Some(schema) if rest <= MAX_RECORD => {
                        let data = body(&mut *plain, rest)?;
                        let decoded = decode(&data, schema);
                        out.messages.push((log_time, channel, decoded));
                    }
                    Some(_) => {
                        skip(&mut *plain, rest)?;
                        out.messages.push((log_time, channel, None));
                    }
                    None => skip(&mut *plain, rest)?,
                }
            }
            _ => skip(&mut *plain, len)?,
        }
    }
    Ok(())
}

/// A CDR reader (`ros2msg` messages): alignment counted from after the 4-byte encapsulation
/// header, little- or big-endian as the header says.
struct Cdr<'a> {
    c: Cursor<'a>,
    little: bool,
}

impl Cdr<'_> {
    fn align(&mut self, n: usize) -> Option<()> {
        let pad = (n - (self.c.at - 4) % n) % n;
        self.c.take(pad as u64).map(|_| ())
    }
    fn u32(&mut self) -> Option<u32> {
        self.align(4)?;
        let b: [u8; 4] = self.c.take(4)?.try_into().ok()?;
        Some(if self.little {
            u32::from_le_bytes(b)
        } else {
            u32::from_be_bytes(b)
        })
    }
    fn f64(&mut self) -> Option<f64> {
        self.align(8)?;
        let b: [u8; 8] = self.c.take(8)?.try_into().ok()?;
        Some(if self.little {
            f64::from_le_bytes(b)
        } else {
            f64::from_be_bytes(b)
        })
    }
    fn skip_string(&mut self) -> Option<()> {
        let n = self.u32()?;
        self.c.take(u64::from(n)).map(|_| ())
    }
}

/// `(stamp seconds, position, orientation [x y z w])` of a pose message in CDR.
fn decode(data: &[u8], schema: &str) -> Option<(f64, [f64; 3], [f64; 4])> {
    let little = match data.get(..2)? {
        [0, 1] | [0, 3] => true,
        [0, 0] | [0, 2] => false,
        _ => return None,
    };
    let mut m = Cdr {
        c: Cursor { bytes: data, at: 4 },
        little,
    };
    if data.len() < 4 {
        return None;
    }
    let sec = m.u32()? as i32;
    let nanosec = m.u32()?;
    m.skip_string()?; // header.frame_id
    if matches!(
        schema,
        "nav_msgs/msg/Odometry" | "geometry_msgs/msg/TransformStamped"
    ) {
        m.skip_string()?; // child_frame_id
    }
    let mut v = [0.0; 7];
    for x in &mut v {
        *x = m.f64()?;
    }
    let time = f64::from(sec) + f64::from(nanosec) * 1e-9;
    Some((time, [v[0], v[1], v[2]], [v[3], v[4], v[5], v[6]]))
}

/// The records of one MCAP file's bytes.
fn records_of(file: &Path, bytes: &[u8]) -> Result<Records, Error> {
    if bytes.len() < 8 || &bytes[..8] != MAGIC {
        return Err(Error::Input(format!(
            "{}: not an MCAP file (it does not start with the MCAP magic bytes)",
            file.display()
        )));
    }
    let declared = declared(&bytes[8..]);
    let allowed = (bytes.len() as u64)
        .saturating_mul(MAX_INFLATION)
        .max(INFLATION_FLOOR);
    if declared > allowed {
        return Err(Error::Input(format!(
            "{}: its chunks declare {declared} bytes uncompressed, {} times the file's {} bytes: more than the {MAX_INFLATION} times compression gives a bag (a decompression bomb, or not a bag)",
            file.display(),
            declared / (bytes.len() as u64).max(1),
            bytes.len()
        )));
    }
    let mut one = Records::default();
    records(file, &bytes[8..], 8, &mut one)?;
    Ok(one)
}

/// The pose messages of `topic` in `bag` (any pose topic when `None` and the bag has exactly
/// one), in the order they were logged.
pub fn read(bag: &Path, topic: Option<&str>) -> Result<(String, Vec<Stamped>), Error> {
    let mut by_file = Vec::new();
    for file in mcap_files(bag)? {
        let bytes = crate::input::read(&file)?;
        by_file.push(records_of(&file, &bytes)?);
    }
    select(bag, by_file, topic)
}

/// [`read`] of one MCAP file's bytes, `file` naming it in messages.
pub fn parse(
    bytes: &[u8],
    file: &Path,
    topic: Option<&str>,
) -> Result<(String, Vec<Stamped>), Error> {
    select(file, vec![records_of(file, bytes)?], topic)
}

/// The pose messages of `topic` among the records of a bag's files.
fn select(
    bag: &Path,
    by_file: Vec<Records>,
    topic: Option<&str>,
) -> Result<(String, Vec<Stamped>), Error> {
    // Channel ids are per file: resolve each file's messages to (topic, schema) first.
    let mut topics: BTreeMap<String, String> = BTreeMap::new();
    let mut messages: Vec<(u64, String, String, Decoded)> = Vec::new();
    for f in by_file {
        for (t, schema, _) in f.channels.values() {
            let name = f.schemas.get(schema).cloned().unwrap_or_default();
            topics.insert(t.clone(), name);
        }
        for (time, channel, decoded) in f.messages {
            if let Some((t, schema, _)) = f.channels.get(&channel) {
                let name = f.schemas.get(schema).cloned().unwrap_or_default();
                messages.push((time, t.clone(), name, decoded));
            }
        }
    }
    let poses: Vec<&String> = topics
        .iter()
        .filter(|(_, s)| POSE_TYPES.contains(&s.as_str()))
        .map(|(t, _)| t)
        .collect();
    let listing = || {
        topics
            .iter()
            .map(|(t, s)| format!("{t} ({s})"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let topic = match topic {
        Some(t) => {
            let Some(schema) = topics.get(t) else {
                return Err(Error::Input(format!(
                    "{}: no topic {t}; the bag has: {}",
                    bag.display(),
                    listing()
                )));
            };
            if !POSE_TYPES.contains(&schema.as_str()) {
                return Err(Error::Input(format!(
                    "{}: topic {t} is {schema}, not a pose: give a topic of type {}",
                    bag.display(),
                    POSE_TYPES.join(", ")
                )));
            }
            t.to_owned()
        }
        None if poses.len() == 1 => poses[0].clone(),
        None => {
            return Err(Error::Usage(format!(
                "{}: {} pose topics: name the one to read with --topic (the estimate's) or --reference-topic; the bag has: {}",
                bag.display(),
                poses.len(),
                listing()
            )));
        }
    };
    messages.retain(|m| m.1 == topic);
    messages.sort_by_key(|m| m.0);
    let mut out = Vec::with_capacity(messages.len());
    for (k, (_, _, schema, decoded)) in messages.iter().enumerate() {
        let (time, position, orientation) = decoded.ok_or_else(|| {
            Error::Input(format!(
                "{}: topic {topic}: message {} is not a readable {schema} in CDR",
                bag.display(),
                k + 1
            ))
        })?;
        out.push(Stamped {
            time,
            position,
            orientation,
            number: k + 1,
        });
    }
    Ok((topic, out))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_file_list_of_a_metadata_yaml_is_read() {
        let yaml = "rosbag2_bagfile_information:\n  version: 5\n  relative_file_paths:\n    - run_0.mcap\n    - \"run_1.mcap\"\n  duration:\n    nanoseconds: 5\n";
        assert_eq!(relative_file_paths(yaml), ["run_0.mcap", "run_1.mcap"]);
    }

    #[test]
    fn what_the_sensor_bags_write_is_read_back() {
        use subtgraph_sensors::write::{cdr::Cdr, mcap::Mcap};
        let mut m = Mcap::new(Vec::new()).unwrap();
        let odom = m.schema("nav_msgs/msg/Odometry", "").unwrap();
        let text = m.schema("std_msgs/msg/String", "").unwrap();
        let a = m.channel(odom, "/odom", &[]).unwrap();
        let b = m.channel(text, "/text", &[]).unwrap();
        for i in 0..5u64 {
            let t = 7_000_000_000 + i * 250_000_000;
            m.message(a, t, t, |buf| {
                let mut c = Cdr::new(buf);
                c.header(t, "map");
                c.string("base_link");
                c.vector([i as f64, -1.5, 0.25]);
                c.quaternion([0.0, 0.0, 0.6, 0.8]);
            })
            .unwrap();
            m.message(b, t, t, |buf| Cdr::new(buf).string("x")).unwrap();
        }
        let bytes = m.finish().unwrap().0;
        let (topic, poses) = parse(&bytes, Path::new("t.mcap"), None).unwrap();
        assert_eq!(topic, "/odom");
        assert_eq!(poses.len(), 5);
        assert_eq!(poses[3].time, 7.75);
        assert_eq!(poses[3].position, [3.0, -1.5, 0.25]);
        assert_eq!(poses[3].orientation, [0.0, 0.0, 0.6, 0.8]);
        let e = parse(&bytes, Path::new("t.mcap"), Some("/text")).unwrap_err();
        assert!(e.to_string().contains("not a pose"), "{e}");
    }

    #[test]
    fn a_cut_record_is_an_error_not_a_panic() {
        let mut bytes = MAGIC.to_vec();
        bytes.extend_from_slice(&[0x05, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x7f, 1, 2]);
        let mut r = Records::default();
        let e = records(Path::new("x.mcap"), &bytes[8..], 8, &mut r).unwrap_err();
        assert!(e.to_string().contains("byte 8"), "{e}");
    }
}
