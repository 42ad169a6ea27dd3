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

/// What the records of one file say: schema names by id, channels `(topic, schema id,
/// encoding)` by id, and messages `(log time, channel, data)`.
#[derive(Default)]
struct Records {
    schemas: BTreeMap<u16, String>,
    channels: BTreeMap<u16, (String, u16, String)>,
    messages: Vec<(u64, u16, Vec<u8>)>,
}

fn corrupt(file: &Path, offset: usize, what: &str) -> Error {
    Error::Input(format!(
        "{}: not a readable MCAP file at byte {offset}: {what} (cut short or not MCAP?)",
        file.display()
    ))
}

/// Reads the records of `bytes` (a file's data section or a chunk's records) into `out`.
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
        let mut r = Cursor { bytes: body, at: 0 };
        match op {
            // Footer: the end of the data.
            0x02 => return Ok(()),
            0x03 => {
                let id = r.u16().ok_or_else(|| bad("a schema record"))?;
                let name = r.string().ok_or_else(|| bad("a schema's name"))?;
                out.schemas.insert(id, name);
            }
            0x04 => {
                let (Some(id), Some(schema), Some(topic), Some(encoding)) =
                    (r.u16(), r.u16(), r.string(), r.string())
                else {
                    return Err(bad("a channel record"));
                };
                out.channels.insert(id, (topic, schema, encoding));
            }
            0x05 => {
                let (Some(channel), Some(_sequence), Some(log_time), Some(_publish)) =
                    (r.u16(), r.u32(), r.u64(), r.u64())
                else {
                    return Err(bad("a message record"));
                };
                out.messages
                    .push((log_time, channel, body[r.at..].to_vec()));
            }
            0x06 => chunk(file, &mut r, base + c.at - body.len(), out)?,
            _ => {}
        }
    }
    Ok(())
}

/// A chunk record: its records, decompressed.
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
    let plain: Vec<u8> = match compression.as_str() {
        "" => data.to_vec(),
        "lz4" => {
            let mut v = Vec::with_capacity(size.min(16 * data.len() as u64) as usize);
            lz4_flex::frame::FrameDecoder::new(data)
                .take(size)
                .read_to_end(&mut v)
                .map_err(|e| bad(&format!("an LZ4 chunk that does not decompress: {e}")))?;
            v
        }
        "zstd" => {
            let mut v = Vec::with_capacity(size.min(16 * data.len() as u64) as usize);
            ruzstd::decoding::StreamingDecoder::new(data)
                .map_err(|e| bad(&format!("a Zstandard chunk: {e}")))?
                .take(size)
                .read_to_end(&mut v)
                .map_err(|e| bad(&format!("a Zstandard chunk that does not decompress: {e}")))?;
            v
        }
        other => {
            return Err(bad(&format!(
                "chunk compression '{other}': MCAP allows '', 'lz4' and 'zstd'"
            )));
        }
    };
    if plain.len() as u64 != size {
        return Err(bad(&format!(
            "a chunk of {} bytes where its record says {size}",
            plain.len()
        )));
    }
    records(file, &plain, at, out)
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
    let mut one = Records::default();
    records(file, &bytes[8..], 8, &mut one)?;
    Ok(one)
}

/// The pose messages of `topic` in `bag` (any pose topic when `None` and the bag has exactly
/// one), in the order they were logged.
pub fn read(bag: &Path, topic: Option<&str>) -> Result<(String, Vec<Stamped>), Error> {
    let mut by_file = Vec::new();
    for file in mcap_files(bag)? {
        let bytes =
            std::fs::read(&file).map_err(Error::io(format!("reading {}", file.display())))?;
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
    let mut messages: Vec<(u64, String, String, Vec<u8>)> = Vec::new();
    for f in by_file {
        for (t, schema, _) in f.channels.values() {
            let name = f.schemas.get(schema).cloned().unwrap_or_default();
            topics.insert(t.clone(), name);
        }
        for (time, channel, data) in f.messages {
            if let Some((t, schema, encoding)) = f.channels.get(&channel)
                && encoding == "cdr"
            {
                let name = f.schemas.get(schema).cloned().unwrap_or_default();
                messages.push((time, t.clone(), name, data));
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
    for (k, (_, _, schema, data)) in messages.iter().enumerate() {
        let (time, position, orientation) = decode(data, schema).ok_or_else(|| {
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
