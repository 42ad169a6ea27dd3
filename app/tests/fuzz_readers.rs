//! A bounded, seeded fuzz test of every reader (issue 21, "Guard against the next round"):
//! small valid files of each format have their header numbers, counts and bytes mutated, and
//! each reader must answer every case with a clean error or a result: no panic, no abort, no
//! allocation beyond a small multiple of the file's size, no hang.
//!
//! - **Allocation** is measured by a counting global allocator in this test binary: per thread
//!   (the readers are single-threaded), the peak of live bytes above what was live when the
//!   case started. A case may reach [`ALLOWED_PER_BYTE`] times its file's size plus
//!   [`ALLOWED_FLOOR`]: a point read from 6 bytes of ASCII takes 12 (24 while its vector
//!   doubles), a packed free-space byte 8 as 64-bit words, and a few small tables come with
//!   every reader. An allocation over a gigabyte is reported with its case before the
//!   allocator is asked for it (an abort would otherwise name nothing).
//! - **Time** is reported, not asserted (the machine is shared; a time limit would fail
//!   falsely): the slowest cases are printed. A case still running after [`HANG`] stops the
//!   binary, naming the case: only a hang gets there.
//! - **Seeded**: the same cases on every run (`SUBTGRAPH_FUZZ_SEED` picks another seed,
//!   `SUBTGRAPH_FUZZ_CASES` another number of cases per file).
//!
//! Issue 37 added the MCAP (Zstandard, LZ4 and plain chunks), segmentation image (PNG, NPY),
//! trajectory (TUM, KITTI) and runs-CSV readers, each with cases crafted besides the mutated
//! ones ([`fuzz_inputs`]): nesting, sizes in headers, decompression ratios. A reader that
//! decompresses may also hold its decompressor's window ([`ALLOWED_DECOMPRESSING`]).
//!
//! `unsafe` is allowed in this file for the one thing that needs it: a global allocator.
#![allow(unsafe_code)]

mod fuzz_inputs;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use subtgraph_app::score::{cloud, reports, world};
use subtgraph_schema::{Artifacts, FreeSpace, Topology};

/// A case may allocate this many bytes per byte of its file...
const ALLOWED_PER_BYTE: usize = 64;
/// ... plus this many.
const ALLOWED_FLOOR: usize = 4 << 20;
/// A single allocation this large is reported before it is made.
const HUGE: usize = 1 << 30;
/// What a reader that decompresses may hold besides: its decompressor's window (the MCAP
/// reader allows Zstandard windows of up to 8 MiB) and read buffers.
const ALLOWED_DECOMPRESSING: usize = 12 << 20;
/// Crafted cases per crafted reader (`SUBTGRAPH_FUZZ_CASES` scales them too).
const CRAFTED: usize = 150;
/// A case running this long is a hang: the binary stops, naming it.
const HANG: Duration = Duration::from_secs(30);

thread_local! {
    static LIVE: Cell<usize> = const { Cell::new(0) };
    static PEAK: Cell<usize> = const { Cell::new(0) };
}

/// The case being run, for the reports of a huge allocation or a hang.
static CASE: AtomicUsize = AtomicUsize::new(usize::MAX);
/// When it started, in milliseconds since the test began (0: none running).
static STARTED_MS: AtomicU64 = AtomicU64::new(0);

struct Counting;

// SAFETY: every call is forwarded to the system allocator unchanged; the counters are
// thread-local `Cell`s of plain integers (const-initialised, no destructor, no allocation).
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        // SAFETY: forwarded as received.
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        // SAFETY: forwarded as received.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        let _ = LIVE.try_with(|l| l.set(l.get().saturating_sub(layout.size())));
        // SAFETY: forwarded as received.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = LIVE.try_with(|l| l.set(l.get().saturating_sub(layout.size())));
        note(new_size);
        // SAFETY: forwarded as received.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

/// Counts an allocation of `size` bytes on this thread; says so first when it is huge.
fn note(size: usize) {
    if size >= HUGE {
        // Formatted on the stack: the allocator may not allocate here.
        let mut buf = [0u8; 160];
        let mut w = &mut buf[..];
        let case = CASE.load(Ordering::Relaxed);
        let _ = writeln!(w, "fuzz: an allocation of {size} bytes in case {case}");
        let used = 160 - w.len();
        let _ = std::io::stderr().write_all(&buf[..used]);
    }
    let _ = LIVE.try_with(|l| {
        let now = l.get().saturating_add(size);
        l.set(now);
        let _ = PEAK.try_with(|p| p.set(p.get().max(now)));
    });
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// splitmix64: a seeded stream of numbers, the same on every machine.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Numbers a header may be given: zero, one, the edges of every integer width, huge ones,
/// and things that are not numbers.
const NUMBERS: &[&str] = &[
    "0",
    "1",
    "-1",
    "2",
    "3",
    "255",
    "256",
    "65536",
    "2147483647",
    "2147483648",
    "4294967295",
    "4294967296",
    "4000000000",
    "1000000000000",
    "5000000000000",
    "4611686018427387904",
    "9223372036854775807",
    "9223372036854775808",
    "18446744073709551615",
    "18446744073709551616",
    "99999999999999999999999999999",
    "1e300",
    "-1e300",
    "NaN",
    "inf",
    "0.5",
    "abc",
    "",
];

/// Where the ASCII numbers of `bytes` are.
fn numbers(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i].is_ascii_digit() {
            let start = i;
            while i < bytes.len() && (bytes[i].is_ascii_digit() || bytes[i] == b'.') {
                i += 1;
            }
            out.push((start, i));
        } else {
            i += 1;
        }
    }
    out
}

/// One to three mutations of `seed`: a number replaced (mostly in the first kilobyte, where
/// headers are), a byte changed, a line doubled or dropped, bytes cut off or added.
fn mutate(seed: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut b = seed.to_vec();
    for _ in 0..1 + rng.below(3) {
        let spans = numbers(&b[..b.len().min(if rng.below(4) == 0 { b.len() } else { 1024 })]);
        match rng.below(8) {
            0..=3 if !spans.is_empty() => {
                let (s, e) = spans[rng.below(spans.len())];
                let n = NUMBERS[rng.below(NUMBERS.len())];
                b.splice(s..e, n.bytes());
            }
            4 if !b.is_empty() => {
                let i = rng.below(b.len());
                b[i] = rng.next() as u8;
            }
            5 => {
                // A line doubled or dropped.
                let lines: Vec<usize> = std::iter::once(0)
                    .chain(
                        b.iter()
                            .enumerate()
                            .filter(|(_, c)| **c == b'\n')
                            .map(|(i, _)| i + 1),
                    )
                    .filter(|&i| i < b.len())
                    .collect();
                if let Some(&s) = lines.get(rng.below(lines.len())) {
                    let e = b[s..]
                        .iter()
                        .position(|&c| c == b'\n')
                        .map_or(b.len(), |k| s + k + 1);
                    if rng.below(2) == 0 {
                        let line = b[s..e].to_vec();
                        b.splice(s..s, line);
                    } else {
                        b.drain(s..e);
                    }
                }
            }
            6 if !b.is_empty() => {
                let n = rng.below(b.len());
                b.truncate(n);
            }
            _ => {
                let n = 1 + rng.below(64);
                let fill = rng.next() as u8;
                b.extend(std::iter::repeat_n(fill, n));
            }
        }
    }
    b
}

/// A generator of crafted cases.
type Craft = fn(&mut Rng) -> Vec<u8>;

/// A reader under test: its name and how it reads a file's bytes (an error is a fine answer).
type Reader<'a> = (&'a str, Vec<Vec<u8>>, Box<dyn Fn(&[u8]) + 'a>);

/// One case's measurements.
struct Measured {
    reader: String,
    case: usize,
    len: usize,
    allocated: usize,
    took: Duration,
}

fn run_case(
    reader: &str,
    case: usize,
    bytes: &[u8],
    read: &dyn Fn(&[u8]),
    t0: Instant,
) -> Measured {
    CASE.store(case, Ordering::Relaxed);
    STARTED_MS.store(t0.elapsed().as_millis() as u64 + 1, Ordering::Relaxed);
    let base = LIVE.with(Cell::get);
    PEAK.with(|p| p.set(base));
    let started = Instant::now();
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| read(bytes)));
    let took = started.elapsed();
    STARTED_MS.store(0, Ordering::Relaxed);
    let allocated = PEAK.with(Cell::get).saturating_sub(base);
    if result.is_err() {
        let path = std::env::temp_dir().join(format!("subtgraph-fuzz-{reader}-{case}.bin"));
        let _ = std::fs::write(&path, bytes);
        panic!(
            "{reader} case {case} panicked; its file is {}",
            path.display()
        );
    }
    Measured {
        reader: reader.to_owned(),
        case,
        len: bytes.len(),
        allocated,
        took,
    }
}

/// A PLY of four points, ASCII or binary, with a face before the vertices.
fn ply(binary: bool) -> Vec<u8> {
    let pts = [
        [1.0f32, 2.0, 3.0],
        [4.0, 5.0, 6.0],
        [7.5, 8.0, 9.0],
        [0.0, -1.0, 2.0],
    ];
    let format = if binary {
        "binary_little_endian"
    } else {
        "ascii"
    };
    let mut b = format!(
        "ply\nformat {format} 1.0\nelement face 1\nproperty list uchar int vertex_indices\nelement vertex 4\nproperty float x\nproperty double y\nproperty uchar intensity\nproperty float z\nend_header\n"
    )
    .into_bytes();
    if binary {
        b.push(3);
        for i in [0i32, 1, 2] {
            b.extend_from_slice(&i.to_le_bytes());
        }
        for p in pts {
            b.extend_from_slice(&p[0].to_le_bytes());
            b.extend_from_slice(&f64::from(p[1]).to_le_bytes());
            b.push(7);
            b.extend_from_slice(&p[2].to_le_bytes());
        }
    } else {
        b.extend_from_slice(b"3 0 1 2\n");
        for p in pts {
            b.extend_from_slice(format!("{} {} 7 {}\n", p[0], p[1], p[2]).as_bytes());
        }
    }
    b
}

/// A PCD of three points: ASCII, binary or binary_compressed (LZF literal runs).
fn pcd(data: &str) -> Vec<u8> {
    let pts = [[1.0f32, 2.0, 3.0], [4.0, 5.0, 6.0], [7.5, 8.0, 9.0]];
    let mut b = format!(
        "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\nWIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA {data}\n"
    )
    .into_bytes();
    match data {
        "ascii" => {
            for p in pts {
                b.extend_from_slice(format!("{} {} {} 0\n", p[0], p[1], p[2]).as_bytes());
            }
        }
        "binary" => {
            for p in pts {
                for v in p {
                    b.extend_from_slice(&v.to_le_bytes());
                }
                b.extend_from_slice(&0u32.to_le_bytes());
            }
        }
        _ => {
            // Field after field: every x, then every y, z, rgb.
            let mut raw = Vec::new();
            for k in 0..3 {
                for p in pts {
                    raw.extend_from_slice(&p[k].to_le_bytes());
                }
            }
            raw.extend_from_slice(&[0; 12]);
            let mut packed = Vec::new();
            for chunk in raw.chunks(32) {
                packed.push((chunk.len() - 1) as u8);
                packed.extend_from_slice(chunk);
            }
            b.extend_from_slice(&(packed.len() as u32).to_le_bytes());
            b.extend_from_slice(&(raw.len() as u32).to_le_bytes());
            b.extend_from_slice(&packed);
        }
    }
    b
}

/// A small world folder with artifacts and its free space, made once.
/// A small MCAP file as `subtgraph sense` writes them (LZ4 chunks): a topic `/poseK` of each
/// type, 20 stamped poses each.
fn mcap(types: &[&str]) -> Vec<u8> {
    use subtgraph_sensors::write::{cdr::Cdr, mcap::Mcap};
    let mut m = Mcap::new(Vec::new()).unwrap();
    let mut channels = Vec::new();
    for (k, ty) in types.iter().enumerate() {
        let schema = m.schema(ty, "").unwrap();
        let channel = m.channel(schema, &format!("/pose{k}"), &[]).unwrap();
        channels.push((channel, *ty));
    }
    for i in 0..20u64 {
        for &(channel, ty) in &channels {
            let t = 1_000_000_000 + i * 100_000_000;
            m.message(channel, t, t, |buf| {
                let mut c = Cdr::new(buf);
                c.header(t, "map");
                if ty == "nav_msgs/msg/Odometry" {
                    c.string("base_link");
                }
                c.vector([i as f64, 0.5 * i as f64, 0.0]);
                c.quaternion([0.0, 0.0, 0.0, 1.0]);
            })
            .unwrap();
        }
    }
    m.finish().unwrap().0
}

fn world_folder(dir: &Path) -> PathBuf {
    let text = "[world]\nseed = 5\nlevels = 2\nrows = 20\ncols = 20\ntile_pitch = 16.0\nlevel_height = 16.0\n\n\
        [topology]\nloops = 1\nt_junctions = 1\nintersections = 1\n\n[route]\ntype = \"parabolic\"\n\n\
        [tileset]\ntype = \"cave\"\nwidth = 5.0\nheight = 4.0\nresolution = 8\ncollision_resolution = 8\nrocks = 0\n\n\
        [artifacts]\ncount = 4\nmin_distance_from_start = 10\nmin_spacing = 8\n\n\
        [[export]]\ntype = \"free-space\"\nvoxel = 4.0\n";
    let request = subtgraph_app::GenerateRequest {
        source: subtgraph_app::PipelineSource::Given {
            pipeline: Box::new(subtgraph_core::Pipeline::parse(text, "fuzz.toml").unwrap()),
            description: "the fuzz test".into(),
        },
        adjust: subtgraph_app::pipeline::Adjustments {
            formats: vec!["graph".into()],
            ..Default::default()
        },
        ..Default::default()
    };
    let out = dir.join("world");
    request.write(&out, false).unwrap();
    out
}

/// The tube tiles and manifest of a mesh-files tile set.
fn tiles(dir: &Path) -> Vec<u8> {
    let tube = |openings: &[(f64, f64)]| {
        let (mut v, mut f) = (Vec::new(), Vec::new());
        for &(ax, ay) in openings {
            let base = v.len();
            for t in [0.0, 40.0] {
                for (s, z) in [(-2.0, 0.0), (2.0, 0.0), (2.0, 4.0), (-2.0, 4.0)] {
                    v.push(format!("v {} {} {}", ax * t - ay * s, ay * t + ax * s, z));
                }
            }
            for k in 0..4 {
                let (a, b) = (base + k + 1, base + (k + 1) % 4 + 1);
                f.push(format!("f {a} {b} {}", b + 4));
                f.push(format!("f {a} {} {}", b + 4, a + 4));
            }
        }
        format!("o Tube\n{}\n{}\n", v.join("\n"), f.join("\n"))
    };
    let mut manifest = String::from("pitch = 80.0\nup = \"z\"\n");
    for (kind, file, openings) in [
        ("dead-end", "dead.obj", vec![(1.0, 0.0)]),
        ("straight", "straight.obj", vec![(1.0, 0.0), (-1.0, 0.0)]),
        ("corner", "corner.obj", vec![(1.0, 0.0), (0.0, -1.0)]),
        (
            "t-junction",
            "tee.obj",
            vec![(1.0, 0.0), (0.0, 1.0), (0.0, -1.0)],
        ),
        (
            "intersection",
            "cross.obj",
            vec![(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)],
        ),
    ] {
        std::fs::write(dir.join(file), tube(&openings)).unwrap();
        manifest.push_str(&format!(
            "[[tile]]\nkind = \"{kind}\"\nfiles = [\"{file}\"]\n"
        ));
    }
    manifest.into_bytes()
}

/// What a case of `reader` on a file of `len` bytes may allocate.
fn allowance(reader: &str, len: usize) -> usize {
    let decompressing = if reader.contains("mcap") {
        ALLOWED_DECOMPRESSING
    } else {
        0
    };
    ALLOWED_PER_BYTE * len + ALLOWED_FLOOR + decompressing
}

#[test]
fn every_reader_answers_mutated_files_with_a_clean_error_in_bounded_memory() {
    let seed: u64 = std::env::var("SUBTGRAPH_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(21);
    let per_file: usize = std::env::var("SUBTGRAPH_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(150);
    let dir = tempfile::tempdir().unwrap();
    let w = world_folder(dir.path());
    let read = |f: &str| std::fs::read(w.join(f)).unwrap();
    let topology = read("topology.json");
    let shape = subtgraph_core::npy::shape(&read("occupancy.npy")).unwrap();
    let fs_json = read("ground_truth/free_space.json");
    let fs_npy = read("ground_truth/free_space.npy");
    let fs_doc: FreeSpace = subtgraph_schema::read(&fs_json).unwrap();
    let grid = cloud::Grid {
        origin: fs_doc.origin,
        voxel: fs_doc.voxel_m,
        n: [fs_doc.shape[2], fs_doc.shape[1], fs_doc.shape[0]],
    };
    // An occupancy map of the free-space grid: C-order u8, Fortran-order bool, float32.
    let voxels: usize = fs_doc.shape.iter().product();
    let shape_text = format!(
        "({}, {}, {})",
        fs_doc.shape[0], fs_doc.shape[1], fs_doc.shape[2]
    );
    let npy = |descr: &str, fortran: bool, size: usize| {
        let mut data = vec![0u8; voxels * size];
        data[(voxels / 3) * size + size - 1] = 0x3f;
        let mut h = format!(
            "{{'descr': '{descr}', 'fortran_order': {}, 'shape': {shape_text}, }}",
            if fortran { "True" } else { "False" }
        );
        while (10 + h.len() + 1) % 64 != 0 {
            h.push(' ');
        }
        h.push('\n');
        let mut b = b"\x93NUMPY\x01\x00".to_vec();
        b.extend_from_slice(&(h.len() as u16).to_le_bytes());
        b.extend_from_slice(h.as_bytes());
        b.extend_from_slice(&data);
        b
    };
    let manifest = tiles(dir.path());
    let scratch = dir.path().join("scratch");
    std::fs::create_dir_all(&scratch).unwrap();
    // A world folder for preview: the mesh is the mutated file.
    let pw = dir.path().join("pw");
    std::fs::create_dir_all(pw.join("mesh")).unwrap();
    std::fs::copy(w.join("topology.json"), pw.join("topology.json")).unwrap();
    let obj = {
        let text = std::fs::read_to_string(w.join("mesh/world.obj")).unwrap();
        // A piece of the real mesh: a few hundred faces and their vertices.
        let v: Vec<&str> = text
            .lines()
            .filter(|l| l.starts_with("v "))
            .take(400)
            .collect();
        let f: Vec<String> = text
            .lines()
            .filter(|l| l.starts_with("f "))
            .filter(|l| {
                l[2..].split_whitespace().all(|t| {
                    t.split('/')
                        .next()
                        .and_then(|i| i.parse::<usize>().ok())
                        .is_some_and(|i| i <= 400)
                })
            })
            .take(300)
            .map(str::to_owned)
            .collect();
        format!(
            "mtllib world.mtl\nusemtl rock\n{}\n{}\n",
            v.join("\n"),
            f.join("\n")
        )
        .into_bytes()
    };
    let csv = b"time,class,x,y,z,notes\n1.5,survivor,10,20,0,a\n2,backpack,-3.25,4,1e2,\n3,rope,0,0,0,b\n".to_vec();
    let json_reports = br#"{"reports": [{"time": 1, "class": "helmet", "x": 1, "y": "2", "z": 3}, {"time": 2.5, "class": "vent", "x": -1, "y": 0, "z": 0}]}"#.to_vec();
    let readers: Vec<Reader> = vec![
        (
            "ply",
            vec![ply(false), ply(true)],
            Box::new(|b: &[u8]| {
                let _ = cloud::parse(b, cloud::Format::Ply, "fuzz.ply", None);
            }),
        ),
        (
            "pcd",
            vec![pcd("ascii"), pcd("binary"), pcd("binary_compressed")],
            Box::new(|b: &[u8]| {
                let _ = cloud::parse(b, cloud::Format::Pcd, "fuzz.pcd", None);
            }),
        ),
        (
            "npy-map",
            vec![
                npy("|u1", false, 1),
                npy("|b1", true, 1),
                npy("<f4", true, 4),
            ],
            Box::new(|b: &[u8]| {
                let _ = cloud::parse(b, cloud::Format::Npy, "fuzz.npy", Some(&grid));
            }),
        ),
        (
            "reports",
            vec![csv, json_reports],
            Box::new(|b: &[u8]| {
                let _ = reports::parse(b, Path::new("fuzz.csv"));
                let _ = reports::parse(b, Path::new("fuzz.json"));
            }),
        ),
        (
            "topology.json",
            vec![topology],
            Box::new(|b: &[u8]| {
                if let Ok(t) = world::parse_doc::<Topology>(b, Path::new("fuzz")) {
                    let _ = world::cells_of(t, &shape, Path::new("fuzz"));
                }
            }),
        ),
        (
            "artifacts.json",
            vec![read("ground_truth/artifacts.json")],
            Box::new(|b: &[u8]| {
                if let Ok(a) = world::parse_doc::<Artifacts>(b, Path::new("fuzz")) {
                    let _ = world::truth_of(a);
                }
            }),
        ),
        (
            "free_space.json",
            vec![fs_json.clone()],
            Box::new(|b: &[u8]| {
                if let Ok(doc) = world::parse_doc::<FreeSpace>(b, Path::new("fuzz")) {
                    let _ = world::free_space_of(&doc, &fs_npy, Path::new("fuzz.npy"));
                }
            }),
        ),
        (
            "free_space.npy",
            vec![fs_npy.clone()],
            Box::new(|b: &[u8]| {
                let _ = world::free_space_of(&fs_doc, b, Path::new("fuzz.npy"));
            }),
        ),
        (
            "world.toml",
            vec![
                read("world.toml"),
                subtgraph_app::presets::text("mine")
                    .unwrap()
                    .as_bytes()
                    .to_vec(),
            ],
            Box::new(|b: &[u8]| {
                let _ = subtgraph_core::Pipeline::parse(&String::from_utf8_lossy(b), "fuzz.toml");
            }),
        ),
        (
            ".subtgraph-files",
            vec![read(".subtgraph-files")],
            Box::new(|b: &[u8]| {
                let _ = subtgraph_app::folder::manifest::parse(&String::from_utf8_lossy(b));
            }),
        ),
        (
            "tile manifest",
            vec![manifest],
            Box::new(|b: &[u8]| {
                let path = dir.path().join("tiles.toml");
                std::fs::write(&path, b).unwrap();
                let _ = subtgraph_tilesets::mesh_files::MeshFiles::open(&path);
            }),
        ),
        (
            "tile obj",
            vec![std::fs::read(dir.path().join("tee.obj")).unwrap()],
            Box::new(|b: &[u8]| {
                let path = scratch.join("tile.obj");
                std::fs::write(&path, b).unwrap();
                let _ = subtgraph_tilesets::mesh_files::load(&path);
            }),
        ),
        (
            "ros2 bag (mcap)",
            vec![mcap(&[
                "geometry_msgs/msg/PoseStamped",
                "nav_msgs/msg/Odometry",
            ])],
            Box::new(|b: &[u8]| {
                let _ = subtgraph_app::score::trajectory::bag::parse(
                    b,
                    Path::new("fuzz.mcap"),
                    Some("/pose0"),
                );
            }),
        ),
        (
            "mcap (zstd, lz4, plain)",
            fuzz_inputs::mcap_seeds(),
            Box::new(|b: &[u8]| {
                let _ =
                    subtgraph_app::score::trajectory::bag::parse(b, Path::new("fuzz.mcap"), None);
            }),
        ),
        (
            "trajectory (tum)",
            vec![fuzz_inputs::tum_seed()],
            Box::new(|b: &[u8]| {
                let path = scratch.join("fuzz.tum");
                std::fs::write(&path, b).unwrap();
                let _ = subtgraph_app::score::trajectory::read::read(&path, None);
            }),
        ),
        (
            "trajectory (kitti)",
            vec![fuzz_inputs::kitti_seed()],
            Box::new(|b: &[u8]| {
                let path = scratch.join("kitti/poses.txt");
                std::fs::create_dir_all(path.parent().unwrap()).unwrap();
                let times: String = (0..20).map(|k| format!("{}\n", k as f64 * 0.1)).collect();
                std::fs::write(path.with_file_name("times.txt"), times).unwrap();
                std::fs::write(&path, b).unwrap();
                let _ = subtgraph_app::score::trajectory::read::read(&path, None);
            }),
        ),
        (
            "runs.csv",
            vec![fuzz_inputs::runs_seed()],
            Box::new(|b: &[u8]| {
                let path = scratch.join("runs.csv");
                std::fs::write(&path, b).unwrap();
                let _ = subtgraph_app::report::runs::from_csv(&path);
            }),
        ),
        (
            "segmentation png",
            vec![fuzz_inputs::png_seed(64, 48)],
            Box::new(|b: &[u8]| {
                let path = scratch.join("level-0.png");
                std::fs::write(&path, b).unwrap();
                let _ = subtgraph_app::score::segmentation::read::prediction(&path, 64, 48);
            }),
        ),
        (
            "segmentation npy",
            vec![subtgraph_core::npy::encode_u8(
                &[48, 64],
                &(0..48 * 64).map(|k| (k % 6) as u8).collect::<Vec<u8>>(),
            )],
            Box::new(|b: &[u8]| {
                let path = scratch.join("level-0.npy");
                std::fs::write(&path, b).unwrap();
                let _ = subtgraph_app::score::segmentation::read::prediction(&path, 64, 48);
            }),
        ),
        (
            "preview obj",
            vec![obj],
            Box::new(|b: &[u8]| {
                std::fs::write(pw.join("mesh/world.obj"), b).unwrap();
                let _ = subtgraph_app::PreviewRequest {
                    world: pw.clone(),
                    out: scratch.join("p.png"),
                    width: 32,
                    height: 24,
                    view: subtgraph_app::preview::View::Whole,
                    light: subtgraph_app::preview::Light::Sun,
                    at: None,
                }
                .run();
            }),
        ),
    ];

    // The watchdog: a case running past HANG stops the binary, naming it.
    let t0 = Instant::now();
    std::thread::spawn(move || {
        loop {
            std::thread::sleep(Duration::from_millis(200));
            let started = STARTED_MS.load(Ordering::Relaxed);
            if started > 0 && t0.elapsed().as_millis() as u64 > started + HANG.as_millis() as u64 {
                eprintln!(
                    "fuzz: case {} has run for more than {HANG:?}: it hangs",
                    CASE.load(Ordering::Relaxed)
                );
                std::process::abort();
            }
        }
    });

    let mut rng = Rng(seed);
    let results = Mutex::new(Vec::new());
    let mut case = 0;
    for (name, seeds, read) in &readers {
        // The valid files themselves first: they must read.
        for s in seeds {
            results
                .lock()
                .unwrap()
                .push(run_case(name, case, s, read.as_ref(), t0));
            case += 1;
        }
        for k in 0..per_file * seeds.len() {
            let bytes = mutate(&seeds[k % seeds.len()], &mut rng);
            let m = run_case(name, case, &bytes, read.as_ref(), t0);
            let allowed = allowance(name, m.len.max(seeds[k % seeds.len()].len()));
            if m.allocated > allowed {
                let path = std::env::temp_dir().join(format!("subtgraph-fuzz-{name}-{case}.bin"));
                let _ = std::fs::write(&path, &bytes);
                panic!(
                    "{name} case {case}: {} bytes allocated for a file of {} bytes (at most {allowed}); its file is {}",
                    m.allocated,
                    m.len,
                    path.display()
                );
            }
            results.lock().unwrap().push(m);
            case += 1;
        }
    }
    // Crafted cases: structures a mutation rarely reaches (issue 37).
    let crafted: [(&str, Craft); 7] = [
        ("mcap (zstd, lz4, plain)", fuzz_inputs::crafted_mcap),
        ("segmentation png", fuzz_inputs::crafted_png),
        ("segmentation npy", fuzz_inputs::crafted_npy),
        ("trajectory (tum)", fuzz_inputs::crafted_trajectory),
        ("trajectory (kitti)", fuzz_inputs::crafted_trajectory),
        ("runs.csv", fuzz_inputs::crafted_runs),
        ("ros2 bag (mcap)", fuzz_inputs::crafted_mcap),
    ];
    for (name, make) in crafted {
        let (_, _, read) = readers
            .iter()
            .find(|r| r.0 == name)
            .expect("a reader of that name");
        for _ in 0..CRAFTED * per_file / 150 {
            let bytes = make(&mut rng);
            let m = run_case(name, case, &bytes, read.as_ref(), t0);
            let allowed = allowance(name, m.len);
            if m.allocated > allowed {
                let path = std::env::temp_dir().join(format!("subtgraph-fuzz-{name}-{case}.bin"));
                let _ = std::fs::write(&path, &bytes);
                panic!(
                    "{name} crafted case {case}: {} bytes allocated for a file of {} bytes (at most {allowed}); its file is {}",
                    m.allocated,
                    m.len,
                    path.display()
                );
            }
            results.lock().unwrap().push(m);
            case += 1;
        }
    }
    let mut all = results.into_inner().unwrap();
    let total: Duration = all.iter().map(|m| m.took).sum();
    // The most allocated per byte of file, among files large enough for the floor not to
    // count (4 kB).
    let worst_ratio = all
        .iter()
        .filter(|m| m.len >= 4096)
        .map(|m| m.allocated as f64 / m.len as f64)
        .fold(0.0, f64::max);
    all.sort_by_key(|m| std::cmp::Reverse(m.took));
    eprintln!(
        "fuzz: {} cases of {} readers in {:.2} s (seed {seed}); most allocated per byte of a file over 4 kB {worst_ratio:.1} (allowed {ALLOWED_PER_BYTE}); slowest:",
        all.len(),
        readers.len(),
        total.as_secs_f64()
    );
    for m in all.iter().take(5) {
        eprintln!(
            "  {} case {}: {:.1} ms, {} bytes allocated for {} bytes",
            m.reader,
            m.case,
            m.took.as_secs_f64() * 1e3,
            m.allocated,
            m.len
        );
    }
}
