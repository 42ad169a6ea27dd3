//! The readers issue 37 added to the fuzz: MCAP bags (Zstandard, LZ4 and plain chunks),
//! segmentation images (PNG and NPY), trajectories (TUM and KITTI) and a report's runs CSV.
//! Their seeds are mutated as every reader's are; besides, [`crafted`] makes cases a random
//! mutation rarely reaches: chunks nested deep, sizes in headers from every edge, Zstandard
//! frames of RLE blocks that decompress thousands of times their size, windows of every size,
//! PNG and NPY headers claiming huge images, lines without end.

use super::Rng;

/// Sizes a header may claim.
const SIZES: &[u64] = &[
    0,
    1,
    8,
    9,
    22,
    255,
    4096,
    65536,
    1 << 20,
    16 << 20,
    1 << 28,
    (1 << 28) + 1,
    1 << 32,
    u64::MAX / 2,
    u64::MAX,
];

/// An MCAP record.
pub fn record(op: u8, body: &[u8]) -> Vec<u8> {
    let mut r = vec![op];
    r.extend_from_slice(&(body.len() as u64).to_le_bytes());
    r.extend_from_slice(body);
    r
}

fn string(out: &mut Vec<u8>, s: &str) {
    out.extend_from_slice(&(s.len() as u32).to_le_bytes());
    out.extend_from_slice(s.as_bytes());
}

/// An MCAP chunk record declaring `size` bytes uncompressed, holding `data`.
pub fn chunk(size: u64, compression: &str, data: &[u8]) -> Vec<u8> {
    let mut b = Vec::new();
    b.extend_from_slice(&[0; 16]);
    b.extend_from_slice(&size.to_le_bytes());
    b.extend_from_slice(&0u32.to_le_bytes());
    string(&mut b, compression);
    b.extend_from_slice(&(data.len() as u64).to_le_bytes());
    b.extend_from_slice(data);
    record(0x06, &b)
}

pub const MAGIC: &[u8] = b"\x89MCAP0\r\n";

/// The uncompressed records of a PoseStamped topic `/pose0` of 20 poses: a schema, a channel,
/// the messages (CDR, little-endian).
pub fn pose_records() -> Vec<u8> {
    let mut out = Vec::new();
    let mut schema = 1u16.to_le_bytes().to_vec();
    string(&mut schema, "geometry_msgs/msg/PoseStamped");
    string(&mut schema, "ros2msg");
    string(&mut schema, "");
    out.extend(record(0x03, &schema));
    let mut channel = 1u16.to_le_bytes().to_vec();
    channel.extend_from_slice(&1u16.to_le_bytes());
    string(&mut channel, "/pose0");
    string(&mut channel, "cdr");
    channel.extend_from_slice(&0u32.to_le_bytes());
    out.extend(record(0x04, &channel));
    for i in 0..20u32 {
        let mut m = 1u16.to_le_bytes().to_vec();
        m.extend_from_slice(&i.to_le_bytes());
        let t = 1_000_000_000u64 + u64::from(i) * 100_000_000;
        m.extend_from_slice(&t.to_le_bytes());
        m.extend_from_slice(&t.to_le_bytes());
        // CDR: encapsulation, stamp, frame_id "map", padding to 8, pose.
        let mut cdr = vec![0, 1, 0, 0];
        cdr.extend_from_slice(&((t / 1_000_000_000) as u32).to_le_bytes());
        cdr.extend_from_slice(&((t % 1_000_000_000) as u32).to_le_bytes());
        cdr.extend_from_slice(&4u32.to_le_bytes());
        cdr.extend_from_slice(b"map\0");
        cdr.extend_from_slice(&[0; 4]);
        for v in [f64::from(i), 0.5 * f64::from(i), 0.0, 0.0, 0.0, 0.0, 1.0] {
            cdr.extend_from_slice(&v.to_le_bytes());
        }
        m.extend_from_slice(&cdr);
        out.extend(record(0x05, &m));
    }
    out
}

/// A Zstandard frame of `plain` in raw blocks (valid, uncompressed), window exponent `w`.
pub fn zstd_raw(plain: &[u8], w: u8) -> Vec<u8> {
    let mut f = vec![0x28, 0xb5, 0x2f, 0xfd, 0x00, w << 3];
    let blocks: Vec<&[u8]> = plain.chunks(1 << 16).collect();
    if blocks.is_empty() {
        f.extend_from_slice(&[1, 0, 0]);
    }
    for (k, b) in blocks.iter().enumerate() {
        let h = u32::from(k + 1 == blocks.len()) | ((b.len() as u32) << 3);
        f.extend_from_slice(&h.to_le_bytes()[..3]);
        f.extend_from_slice(b);
    }
    f
}

/// A Zstandard frame of `n` zero bytes in RLE blocks of `block` bytes, window descriptor `wd`
/// (or, with `single`, a single-segment frame claiming `fcs` bytes of content).
fn zstd_rle(n: u64, block: u64, wd: u8, single: Option<u64>) -> Vec<u8> {
    let mut f = vec![0x28, 0xb5, 0x2f, 0xfd];
    match single {
        Some(fcs) => {
            f.push(0xe0);
            f.extend_from_slice(&fcs.to_le_bytes());
        }
        None => f.extend_from_slice(&[0x00, wd]),
    }
    let block = block.clamp(1, (1 << 21) - 1);
    let mut left = n;
    loop {
        let k = left.min(block);
        left -= k;
        let h = u32::from(left == 0) | (1 << 1) | ((k as u32) << 3);
        f.extend_from_slice(&h.to_le_bytes()[..3]);
        f.push(0);
        if left == 0 {
            break;
        }
    }
    f
}

/// A seed bag: the pose records in one chunk of each compression, and bare.
pub fn mcap_seeds() -> Vec<Vec<u8>> {
    let plain = pose_records();
    let mut seeds = Vec::new();
    for (compression, data) in [
        ("", plain.clone()),
        ("zstd", zstd_raw(&plain, 7)),
        ("lz4", lz4(&plain)),
    ] {
        let mut b = MAGIC.to_vec();
        b.extend(chunk(plain.len() as u64, compression, &data));
        b.extend(record(0x02, &[0; 20]));
        b.extend_from_slice(MAGIC);
        seeds.push(b);
    }
    let mut bare = MAGIC.to_vec();
    bare.extend(&plain);
    seeds.push(bare);
    seeds
}

fn lz4(plain: &[u8]) -> Vec<u8> {
    use std::io::Write as _;
    let mut e = lz4_flex::frame::FrameEncoder::new(Vec::new());
    e.write_all(plain).unwrap();
    e.finish().unwrap()
}

/// A crafted MCAP file: nesting, declared sizes, decompression ratios, windows.
pub fn crafted_mcap(rng: &mut Rng) -> Vec<u8> {
    let mut b = MAGIC.to_vec();
    match rng.below(4) {
        0 => {
            // Chunks nested 1 to 20,000 deep around the pose records.
            let depth = [1, 2, 3, 50, 1000, 20_000][rng.below(6)];
            let mut inner = pose_records();
            for _ in 0..depth {
                inner = chunk(inner.len() as u64, "", &inner);
            }
            b.extend(inner);
        }
        1 => {
            // A chunk whose declared size is any edge, its data of any compression.
            let plain = pose_records();
            let size = SIZES[rng.below(SIZES.len())];
            let (compression, data) = match rng.below(4) {
                0 => ("", plain.clone()),
                1 => ("zstd", zstd_raw(&plain, rng.below(32) as u8)),
                2 => ("lz4", lz4(&plain)),
                _ => ("brotli", plain.clone()),
            };
            b.extend(chunk(size, compression, &data));
        }
        2 => {
            // Zstandard bombs: RLE blocks of zeros, one to fifty chunks, of up to 256 MiB
            // each (mostly small: a big one takes a second to decompress).
            let n = match rng.below(8) {
                0 => 1 << 28,
                1 => 16 << 20,
                _ => 1 << rng.below(20),
            };
            let single = (rng.below(4) == 0).then(|| SIZES[rng.below(SIZES.len())]);
            let wd = rng.next() as u8;
            // Blocks of at least n / 4096 bytes: the frame stays a few kilobytes.
            let block = (1u64 << rng.below(18)).max(n / 4096);
            let frame = zstd_rle(n, block, wd, single);
            let declared = if rng.below(2) == 0 {
                n
            } else {
                SIZES[rng.below(SIZES.len())]
            };
            for _ in 0..1 + rng.below(50) {
                b.extend(chunk(declared, "zstd", &frame));
            }
        }
        _ => {
            // A record whose length runs past its chunk or the file.
            let mut inner = pose_records();
            let at = rng.below(inner.len().saturating_sub(8).max(1));
            let len = SIZES[rng.below(SIZES.len())];
            inner.splice(at..(at + 8).min(inner.len()), len.to_le_bytes());
            b.extend(chunk(inner.len() as u64, "", &inner));
        }
    }
    b
}

/// A `w` x `h` 8-bit grey PNG of labels 0 to 5 (valid), as the segmentation seeds.
pub fn png_seed(w: u32, h: u32) -> Vec<u8> {
    let mut bytes = Vec::new();
    {
        let mut e = png::Encoder::new(&mut bytes, w, h);
        e.set_color(png::ColorType::Grayscale);
        e.set_depth(png::BitDepth::Eight);
        let mut wr = e.write_header().unwrap();
        let data: Vec<u8> = (0..w * h).map(|k| (k % 6) as u8).collect();
        wr.write_image_data(&data).unwrap();
    }
    bytes
}

fn crc32(bytes: &[u8]) -> u32 {
    crc32fast::hash(bytes)
}

/// A PNG whose header says anything: sizes from every edge, every colour type and depth, and
/// a little data.
pub fn crafted_png(rng: &mut Rng) -> Vec<u8> {
    let sides: [u32; 9] = [0, 1, 47, 48, 64, 65, 200_000, i32::MAX as u32, u32::MAX];
    let chunk = |out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]| {
        out.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let mut body = kind.to_vec();
        body.extend_from_slice(data);
        out.extend_from_slice(&body);
        out.extend_from_slice(&crc32(&body).to_be_bytes());
    };
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&sides[rng.below(sides.len())].to_be_bytes());
    ihdr.extend_from_slice(&sides[rng.below(sides.len())].to_be_bytes());
    ihdr.push([1, 2, 4, 8, 16, 3][rng.below(6)]);
    ihdr.push([0, 2, 3, 4, 6, 7][rng.below(6)]);
    ihdr.extend_from_slice(&[0, 0, rng.below(3) as u8]);
    chunk(&mut png, b"IHDR", &ihdr);
    let n = rng.below(2000);
    let mut idat = vec![0x78, 0x01, 0x00];
    idat.extend_from_slice(&(n as u16).to_le_bytes());
    idat.extend_from_slice(&(!(n as u16)).to_le_bytes());
    idat.extend(std::iter::repeat_n(rng.next() as u8, n));
    chunk(&mut png, b"IDAT", &idat);
    if rng.below(4) != 0 {
        chunk(&mut png, b"IEND", &[]);
    }
    png
}

/// A `.npy` whose header says any shape and dtype, with a little data.
pub fn crafted_npy(rng: &mut Rng) -> Vec<u8> {
    let dims = [
        "0",
        "1",
        "48",
        "64",
        "200000",
        "4294967296",
        "18446744073709551615",
    ];
    let shape = match rng.below(3) {
        0 => format!("({},)", dims[rng.below(dims.len())]),
        1 => format!(
            "({}, {})",
            dims[rng.below(dims.len())],
            dims[rng.below(dims.len())]
        ),
        _ => format!(
            "({}, {}, {})",
            dims[rng.below(dims.len())],
            dims[rng.below(dims.len())],
            dims[rng.below(dims.len())]
        ),
    };
    let dtype = ["|u1", "<i8", "<f4", "|b1", "<u8", ">i2", "<c16"][rng.below(7)];
    let mut h = format!("{{'descr': '{dtype}', 'fortran_order': False, 'shape': {shape}, }}");
    while (10 + h.len() + 1) % 64 != 0 {
        h.push(' ');
    }
    h.push('\n');
    let mut b = b"\x93NUMPY\x01\x00".to_vec();
    b.extend_from_slice(&(h.len() as u16).to_le_bytes());
    b.extend_from_slice(h.as_bytes());
    b.extend(std::iter::repeat_n(2u8, rng.below(64 * 48 * 9)));
    b
}

/// A valid TUM trajectory of 20 poses.
pub fn tum_seed() -> Vec<u8> {
    let mut s = String::from("# t x y z qx qy qz qw\n");
    for k in 0..20 {
        s.push_str(&format!(
            "{} {} {} 0.5 0 0 0.6 0.8\n",
            k as f64 * 0.1,
            k as f64 * 0.25,
            -(k as f64)
        ));
    }
    s.into_bytes()
}

/// A valid KITTI trajectory of 20 poses (its times.txt is written beside it by the reader).
pub fn kitti_seed() -> Vec<u8> {
    let mut s = String::new();
    for k in 0..20 {
        s.push_str(&format!("1 0 0 {} 0 1 0 0 0 0 1 {}\n", k as f64 * 0.5, k));
    }
    s.into_bytes()
}

/// A trajectory file of crafted lines: any count of numbers, huge values, lines without end.
pub fn crafted_trajectory(rng: &mut Rng) -> Vec<u8> {
    let values = [
        "0", "1", "-1", "0.5", "1e308", "-1e308", "1e-320", "nan", "inf", "x",
    ];
    let mut s = String::new();
    if rng.below(4) == 0 {
        s.push('\u{feff}');
    }
    for _ in 0..1 + rng.below(30) {
        match rng.below(10) {
            0 => s.push_str(&"7".repeat(1 + rng.below(10_000))),
            1 => s.push('\r'),
            _ => {
                let n = [1, 5, 7, 8, 9, 11, 12, 13, 40][rng.below(9)];
                let line: Vec<&str> = (0..n).map(|_| values[rng.below(values.len())]).collect();
                s.push_str(&line.join(if rng.below(3) == 0 { "," } else { " " }));
            }
        }
        if rng.below(8) != 0 {
            s.push('\n');
        }
    }
    s.into_bytes()
}

/// A runs CSV naming score folders that do not exist (every row is refused, after its fields
/// are read), quoted and not.
pub fn runs_seed() -> Vec<u8> {
    b"world,method,score_folder\nw1,lio,s1\n,\"lio (v2, tuned)\",\"s 2\"\nw3,\"say \"\"hi\"\"\",s3\n"
        .to_vec()
}

/// A runs CSV of crafted rows: quotes unclosed or doubled, fields of any count, a byte-order
/// mark, a line of any length.
pub fn crafted_runs(rng: &mut Rng) -> Vec<u8> {
    let fields = [
        "", "a", "\"a,b\"", "\"", "\"\"", "\"x\"y", "a\"b", "\u{feff}", "w,m",
    ];
    let mut s = String::new();
    if rng.below(3) == 0 {
        s.push('\u{feff}');
    }
    s.push_str(if rng.below(4) == 0 {
        "world,method\n"
    } else {
        "world,method,score_folder\n"
    });
    for _ in 0..rng.below(20) {
        let n = 1 + rng.below(5);
        let row: Vec<&str> = (0..n).map(|_| fields[rng.below(fields.len())]).collect();
        s.push_str(&row.join(","));
        if rng.below(10) == 0 {
            s.push_str(&"z".repeat(rng.below(100_000)));
        }
        s.push('\n');
    }
    s.into_bytes()
}
