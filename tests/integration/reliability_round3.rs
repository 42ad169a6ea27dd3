//! Issue 37, round 3, as a hostile user tried it: a world folder never runs code, no crafted
//! bag, image or CSV takes the machine down, `--out .` and changed options never fool the user.
//! One test per numbered item of the issue (`itemNN_...`); each failed on the build before its
//! fix (`SUBTGRAPH_BIN=old/subtgraph cargo test --test integration reliability_round3::` runs
//! them against another build). Item 17 is Python's: `python/tests/test_sense.py`.
//!
//! Crafted inputs are made here, small: a header that claims a huge size, chunks nested deep,
//! a stream without end through a pipe. Where the old behaviour took gigabytes, the command
//! runs under an address-space limit ([`limited`]): the old build aborts there (exit 134 or a
//! signal), the fixed one refuses cleanly long before it.

use crate::common;

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::Duration;

use common::{arg, binary, ok, small_cave_pipeline, subtgraph, subtgraph_within};
use serde_json::Value;

/// Far above what any run here needs: only a hang reaches it.
const HANG: Duration = Duration::from_secs(120);

/// The address space a crafted input's command may use: a few times what the fixed build
/// needs, a fraction of what the old one asked for.
const LIMIT_KIB: u64 = 3 << 20;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts a clean refusal: exit status 1 (not an abort, 134, a panic, 101, or a signal) and
/// a message holding every one of `words`.
fn refused(o: &Output, words: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(1), "a clean error, not a crash: {e}");
    for w in words {
        assert!(e.contains(w), "{w:?} in: {e}");
    }
}

fn json(path: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

/// Runs `subtgraph` from `cwd`.
fn run_in(cwd: &Path, args: &[&str]) -> Output {
    Command::new(binary())
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the binary runs")
}

/// Runs `subtgraph` (from the repository root, as `common::subtgraph` does) with its address
/// space limited to [`LIMIT_KIB`] (bash's `ulimit -v`), and extra environment variables.
fn limited(args: &[&str], env: &[(&str, &Path)]) -> Output {
    let mut c = Command::new("bash");
    c.arg("-c")
        .arg(format!("ulimit -v {LIMIT_KIB} && exec \"$0\" \"$@\""))
        .arg(binary())
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"));
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("bash runs")
}

/// A one-level small cave with its ground truth and OBJ meshes: what `sense` and
/// `score --segmentation` read.
fn cave_world(dir: &Path, name: &str) -> PathBuf {
    let pipeline = small_cave_pipeline(dir, 1, "");
    let out = dir.join(name);
    ok(&[
        "generate",
        arg(&pipeline),
        "--out",
        arg(&out),
        "--format",
        "ground-truth",
    ]);
    out
}

/// A TUM file of `n` poses along x, a pose every 0.1 s.
fn tum(path: &Path, n: usize) {
    let mut s = String::new();
    for k in 0..n {
        s.push_str(&format!(
            "{} {} 0 0 0 0 0 1\n",
            k as f64 * 0.1,
            k as f64 * 0.5
        ));
    }
    std::fs::write(path, s).unwrap();
}

/// CRC-32 (IEEE), as PNG chunks carry it.
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                (c >> 1) ^ 0xedb8_8320
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// A PNG of 900 bytes whose header claims `width` x `height` 8-bit grey pixels (its data is
/// a few hundred bytes of a zlib stream, far from what the header promises).
fn png_claiming(width: u32, height: u32) -> Vec<u8> {
    let chunk = |out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]| {
        out.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let mut body = kind.to_vec();
        body.extend_from_slice(data);
        out.extend_from_slice(&body);
        out.extend_from_slice(&crc32(&body).to_be_bytes());
    };
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&width.to_be_bytes());
    ihdr.extend_from_slice(&height.to_be_bytes());
    ihdr.extend_from_slice(&[8, 0, 0, 0, 0]);
    chunk(&mut png, b"IHDR", &ihdr);
    // A zlib stream of one stored block (800 zero bytes), not the last.
    let mut idat = vec![0x78, 0x01, 0x00];
    idat.extend_from_slice(&800u16.to_le_bytes());
    idat.extend_from_slice(&(!800u16).to_le_bytes());
    idat.extend(std::iter::repeat_n(0u8, 800));
    chunk(&mut png, b"IDAT", &idat);
    chunk(&mut png, b"IEND", &[]);
    png
}

/// An MCAP record: opcode, length, body.
fn record(op: u8, body: &[u8]) -> Vec<u8> {
    let mut r = vec![op];
    r.extend_from_slice(&(body.len() as u64).to_le_bytes());
    r.extend_from_slice(body);
    r
}

/// An MCAP chunk record holding `data` (compressed as `compression` says) that declares
/// `size` bytes of records uncompressed.
fn chunk_record(size: u64, compression: &str, data: &[u8]) -> Vec<u8> {
    let mut b = Vec::new();
    b.extend_from_slice(&0u64.to_le_bytes());
    b.extend_from_slice(&0u64.to_le_bytes());
    b.extend_from_slice(&size.to_le_bytes());
    b.extend_from_slice(&0u32.to_le_bytes());
    b.extend_from_slice(&(compression.len() as u32).to_le_bytes());
    b.extend_from_slice(compression.as_bytes());
    b.extend_from_slice(&(data.len() as u64).to_le_bytes());
    b.extend_from_slice(data);
    record(0x06, &b)
}

const MCAP_MAGIC: &[u8] = b"\x89MCAP0\r\n";

/// A Zstandard frame of `size` bytes: `head` raw, then zeros in RLE blocks of 128 KiB (4
/// bytes each), as a crafted bag packs 256 MiB into 8 kB.
fn zstd_zeros(head: &[u8], size: usize) -> Vec<u8> {
    // Magic, a frame header with a window of 128 KiB (exponent 7), no content size.
    let mut f = vec![0x28, 0xb5, 0x2f, 0xfd, 0x00, 7 << 3];
    let block = |f: &mut Vec<u8>, last: bool, kind: u32, n: usize| {
        let h = u32::from(last) | (kind << 1) | ((n as u32) << 3);
        f.extend_from_slice(&h.to_le_bytes()[..3]);
    };
    let mut left = size - head.len();
    block(&mut f, left == 0, 0, head.len());
    f.extend_from_slice(head);
    while left > 0 {
        let n = left.min(128 << 10);
        left -= n;
        block(&mut f, left == 0, 1, n);
        f.push(0);
    }
    f
}

/// Item 1: sensing a world folder never loads a plugin its `world.toml` names: not one it was
/// made with, not one a received folder puts beside it; the refusal names the plugin and how
/// to allow it (`--plugin`), and the library's constructor never runs (it did, loading the
/// library while the world was rebuilt, before the fix). Named on the command line, it loads.
#[test]
fn item01_sense_never_loads_a_plugin_named_only_in_the_world_folder() {
    let dir = tempfile::tempdir().unwrap();
    let built = Path::new(&binary())
        .parent()
        .unwrap()
        .join("libsubtgraph_test_plugin_runs_at_load.so");
    let built = if built.is_file() {
        built
    } else {
        // The plugin is built by this build (scripts/build), beside this build's binary.
        Path::new(env!("CARGO_BIN_EXE_subtgraph"))
            .parent()
            .unwrap()
            .join("libsubtgraph_test_plugin_runs_at_load.so")
    };
    assert!(
        built.is_file(),
        "{} is missing: build the workspace first with scripts/build",
        built.display()
    );
    let lib = dir.path().join("libworld.so");
    std::fs::copy(&built, &lib).unwrap();
    // The world is made with the plugin (its maker's own pipeline names it).
    let pipeline = small_cave_pipeline(dir.path(), 1, "[plugins]\npaths = [\"libworld.so\"]\n");
    let w = dir.path().join("w");
    let made = dir.path().join("made-marker");
    let o = Command::new(binary())
        .args(["generate", arg(&pipeline), "--format", "ground-truth"])
        .args(["--out", arg(&w)])
        .env("SUBTGRAPH_TEST_MARKER", &made)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        made.is_file(),
        "generate loads the plugins of the pipeline it is given"
    );
    let toml = std::fs::read_to_string(w.join("world.toml")).unwrap();
    assert!(toml.contains("libworld.so"), "{toml}");
    let marker = dir.path().join("sense-marker");
    let sense = |world: &Path, out: &str, extra: &[&str]| {
        let mut args = vec!["sense", arg(world), "--duration", "1"];
        args.extend_from_slice(extra);
        let out = dir.path().join(out);
        args.extend(["--out", arg(&out)]);
        let o = Command::new(binary())
            .args(&args)
            .env("SUBTGRAPH_TEST_MARKER", &marker)
            .output()
            .unwrap();
        (o, out)
    };
    let (o, out) = sense(&w, "s1", &[]);
    assert!(!marker.exists(), "the plugin's code ran: {}", stderr(&o));
    refused(&o, &["libworld.so", "--plugin"]);
    assert!(!out.exists(), "nothing written");
    // A received folder: the library beside its world.toml, named relative to it.
    let received = dir.path().join("received");
    std::fs::create_dir(&received).unwrap();
    for f in common::folder_files(&w) {
        let to = received.join(&f);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(w.join(&f), to).unwrap();
    }
    std::fs::copy(&built, received.join("libworld.so")).unwrap();
    let toml = toml
        .lines()
        .map(|l| {
            if l.contains("libworld.so") {
                "paths = [\"libworld.so\"]"
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    std::fs::write(received.join("world.toml"), toml + "\n").unwrap();
    let (o, out) = sense(&received, "s2", &[]);
    assert!(!marker.exists(), "the plugin's code ran: {}", stderr(&o));
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("libworld.so"), "{}", stderr(&o));
    assert!(!out.exists());
    // Named by the user, it loads, and the world is sensed.
    let (o, out) = sense(&w, "s3", &["--plugin", arg(&lib)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(marker.is_file() && out.join("sequence.json").is_file());
}

/// Item 2: a trajectory whose positions span -1e308 to 1e308, and a world whose topology.json
/// says `tile_pitch_m: 1e308`, are refused naming the value (a panic drawing a picture of
/// zero width before the fix).
#[test]
fn item02_extreme_positions_and_pitches_are_refused_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let reference = dir.path().join("ref.tum");
    tum(&reference, 50);
    let wild = dir.path().join("wild.tum");
    let mut s = String::new();
    for k in 0..50 {
        let x = if k % 2 == 0 { 1e308 } else { -1e308 };
        s.push_str(&format!("{} {x} 0 0 0 0 0 1\n", k as f64 * 0.1));
    }
    std::fs::write(&wild, s).unwrap();
    for (k, (a, b)) in [(&reference, &wild), (&wild, &reference)]
        .into_iter()
        .enumerate()
    {
        let out = dir.path().join(format!("s{k}"));
        let o = subtgraph_within(
            &["score", arg(a), "--trajectory", arg(b), "--out", arg(&out)],
            HANG,
        );
        refused(&o, &["wild.tum", "line 1"]);
        assert!(!out.exists());
    }
    // A world folder whose tile pitch was edited to 1e308.
    let w = dir.path().join("w");
    ok(&[
        "generate",
        "--preset",
        "cave",
        "--no-mesh",
        "--seed",
        "3",
        "--out",
        arg(&w),
    ]);
    let mut t = json(&w.join("topology.json"));
    t["tile_pitch_m"] = 1e308.into();
    std::fs::write(w.join("topology.json"), t.to_string()).unwrap();
    let out = dir.path().join("s-world");
    let o = subtgraph_within(
        &[
            "score",
            arg(&w),
            "--trajectory",
            arg(&reference),
            "--reference",
            arg(&reference),
            "--out",
            arg(&out),
        ],
        HANG,
    );
    refused(&o, &["topology.json", "tile_pitch_m"]);
}

/// Item 3: an MCAP bag of 300 kB whose chunks nest 6,000 deep is refused at the second chunk
/// (a stack overflow before the fix): MCAP chunks hold schemas, channels and messages only.
#[test]
fn item03_nested_mcap_chunks_are_refused_not_a_stack_overflow() {
    let dir = tempfile::tempdir().unwrap();
    let mut inner = Vec::new();
    for _ in 0..6000 {
        inner = chunk_record(inner.len() as u64, "", &inner);
    }
    let mut bag = MCAP_MAGIC.to_vec();
    bag.extend_from_slice(&inner);
    assert!(bag.len() < 320_000, "{} bytes", bag.len());
    let file = dir.path().join("nested.mcap");
    std::fs::write(&file, bag).unwrap();
    let reference = dir.path().join("ref.tum");
    tum(&reference, 20);
    let out = dir.path().join("s");
    let o = limited(
        &[
            "score",
            arg(&reference),
            "--trajectory",
            arg(&file),
            "--out",
            arg(&out),
        ],
        &[],
    );
    refused(&o, &["nested.mcap", "chunk inside a chunk"]);
    assert!(!out.exists());
}

/// Item 4: an MCAP bag of 330 kB holding 40 Zstandard chunks of 256 MiB each (RLE blocks of
/// zeros behind a message header) is refused before anything is decompressed: its chunks
/// declare 32,000 times its size. Before the fix every chunk's message was kept (10 GB).
#[test]
fn item04_a_decompression_bomb_is_refused_within_bounded_memory() {
    let dir = tempfile::tempdir().unwrap();
    let size = 256usize << 20;
    // A message record that fills the chunk: opcode, length, channel, sequence, two times.
    let mut head = vec![0x05];
    head.extend_from_slice(&((size - 9) as u64).to_le_bytes());
    head.extend_from_slice(&1u16.to_le_bytes());
    head.extend_from_slice(&0u32.to_le_bytes());
    head.extend_from_slice(&[0; 16]);
    let frame = zstd_zeros(&head, size);
    let mut bag = MCAP_MAGIC.to_vec();
    for _ in 0..40 {
        bag.extend_from_slice(&chunk_record(size as u64, "zstd", &frame));
    }
    assert!(bag.len() < 340_000, "{} bytes", bag.len());
    let file = dir.path().join("bomb.mcap");
    std::fs::write(&file, bag).unwrap();
    let reference = dir.path().join("ref.tum");
    tum(&reference, 20);
    let out = dir.path().join("s");
    let o = limited(
        &[
            "score",
            arg(&reference),
            "--trajectory",
            arg(&file),
            "--out",
            arg(&out),
        ],
        &[],
    );
    refused(&o, &["bomb.mcap", "uncompressed"]);
    assert!(!out.exists());
}

/// Item 5: a segmentation PNG of 900 bytes whose header claims 200,000 x 200,000 pixels is
/// refused from its header, against the level map's known size (a 40 GB buffer was allocated
/// before decoding before the fix).
#[test]
fn item05_a_segmentation_header_is_checked_before_the_pixels_are_allocated() {
    let dir = tempfile::tempdir().unwrap();
    let w = cave_world(dir.path(), "w");
    let png = dir.path().join("level-0.png");
    std::fs::write(&png, png_claiming(200_000, 200_000)).unwrap();
    assert!(std::fs::metadata(&png).unwrap().len() < 1000);
    let out = dir.path().join("s");
    let o = limited(
        &[
            "score",
            arg(&w),
            "--segmentation",
            arg(&png),
            "--out",
            arg(&out),
        ],
        &[],
    );
    refused(&o, &["level-0.png", "200000 x 200000"]);
    assert!(!out.exists());
}

/// Item 6: a user texture whose header claims 200,000 x 200,000 pixels is refused by
/// `generate` (it was accepted and copied into the world, and `preview` then aborted asking
/// for 120 GB); and `preview` refuses such an image found in a world folder.
#[test]
fn item06_texture_headers_are_checked_when_the_world_is_made_and_drawn() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("huge.png"), png_claiming(200_000, 200_000)).unwrap();
    let pipeline = small_cave_pipeline(
        dir.path(),
        1,
        "[tileset.textures]\ncave-wall = \"huge.png\"\n",
    );
    let out = dir.path().join("w");
    let o = limited(&["generate", arg(&pipeline), "--out", arg(&out)], &[]);
    refused(&o, &["huge.png", "200000 x 200000"]);
    assert!(!out.exists());
    // A world whose albedo image was replaced afterwards.
    let plain = small_cave_pipeline(dir.path(), 1, "");
    let w = dir.path().join("plain");
    ok(&["generate", arg(&plain), "--out", arg(&w)]);
    let albedo = common::folder_files(&w)
        .into_iter()
        .find(|f| f.ends_with("-albedo.png"))
        .expect("a procedural albedo");
    std::fs::write(w.join(&albedo), png_claiming(200_000, 200_000)).unwrap();
    let picture = dir.path().join("p.png");
    let o = limited(
        &[
            "preview",
            arg(&w),
            "--size",
            "64x48",
            "--out",
            arg(&picture),
        ],
        &[],
    );
    refused(&o, &["200000 x 200000"]);
    assert!(!picture.exists());
}

/// Item 7: a `graph.json` with one polyline point moved 10,000 km is refused before the route
/// is planned (sense aborted allocating 4 GB before the fix): the file is not the one the world
/// was made with.
#[test]
fn item07_an_edited_graph_is_refused_before_the_route_is_planned() {
    let dir = tempfile::tempdir().unwrap();
    let w = cave_world(dir.path(), "w");
    let path = w.join("ground_truth/graph.json");
    let mut g = json(&path);
    let x = g["edges"][0]["polyline"][1][0].as_f64().unwrap();
    g["edges"][0]["polyline"][1][0] = (x + 1e7).into();
    std::fs::write(&path, serde_json::to_string_pretty(&g).unwrap()).unwrap();
    let out = dir.path().join("s");
    let o = limited(&["sense", arg(&w), "--out", arg(&out)], &[]);
    refused(&o, &["graph.json"]);
    assert!(!out.exists());
}

/// A report's input: one grid world, and `methods` score folders of one metric (`a.value`
/// differing between methods) on it, in the form `score` writes them.
fn report_runs(dir: &Path, methods: usize, doc: impl Fn(usize) -> Value) -> (PathBuf, PathBuf) {
    let w = dir.join("world");
    if !w.exists() {
        ok(&[
            "generate",
            "--preset",
            "cave",
            "--no-mesh",
            "--seed",
            "2",
            "--out",
            arg(&w),
        ]);
    }
    let mut csv = String::from("world,method,score_folder\n");
    for m in 0..methods {
        let folder = dir.join(format!("score-{m}"));
        std::fs::create_dir_all(&folder).unwrap();
        let mut d = doc(m);
        d["world"] = Value::from(arg(&w));
        let text = serde_json::to_string_pretty(&d).unwrap() + "\n";
        std::fs::write(folder.join("a.json"), &text).unwrap();
        std::fs::write(
            folder.join(".subtgraph-files"),
            format!("complete score\n{} a.json\n", text.len()),
        )
        .unwrap();
        csv.push_str(&format!("world,method {m},score-{m}\n"));
    }
    let runs = dir.join("runs.csv");
    std::fs::write(&runs, csv).unwrap();
    (w, runs)
}

/// Item 8: `report --resamples` is bounded, and the bound said, before anything is read (a
/// capacity overflow, an abort or minutes of work before the fix).
#[test]
fn item08_report_resamples_are_bounded() {
    let dir = tempfile::tempdir().unwrap();
    // Two worlds scored by one method, so the bootstrap runs.
    let (_, runs) = report_runs(dir.path(), 1, |_| serde_json::json!({"value": 1.0}));
    let w2 = dir.path().join("world2");
    ok(&[
        "generate",
        "--preset",
        "cave",
        "--no-mesh",
        "--seed",
        "4",
        "--out",
        arg(&w2),
    ]);
    let mut csv = std::fs::read_to_string(&runs).unwrap();
    std::fs::create_dir_all(dir.path().join("score-b")).unwrap();
    let text = format!("{{\"world\": \"{}\", \"value\": 2.0}}\n", arg(&w2));
    std::fs::write(dir.path().join("score-b/a.json"), &text).unwrap();
    std::fs::write(
        dir.path().join("score-b/.subtgraph-files"),
        format!("complete score\n{} a.json\n", text.len()),
    )
    .unwrap();
    csv.push_str("world2,method 0,score-b\n");
    std::fs::write(&runs, csv).unwrap();
    for (k, n) in ["18446744073709551615", "1000000000000", "100000000"]
        .into_iter()
        .enumerate()
    {
        let out = dir.path().join(format!("r{k}"));
        let o = limited(
            &[
                "report",
                "--runs",
                arg(&runs),
                "--resamples",
                n,
                "--out",
                arg(&out),
            ],
            &[],
        );
        refused(&o, &["--resamples", "at most 100000"]);
        assert!(!out.exists());
    }
    let out = dir.path().join("fine");
    ok(&[
        "report",
        "--runs",
        arg(&runs),
        "--resamples",
        "100000",
        "--out",
        arg(&out),
    ]);
    assert_eq!(json(&out.join("report.json"))["resamples"], 100_000);
}

/// Item 9: a trajectory file is read a line at a time and its first line's columns are
/// checked before the rest is read: an endless stream of lines `1` through a pipe is refused
/// at line 1 (it was read whole into memory first, 70 bytes a byte, before the fix).
#[test]
fn item09_a_trajectory_is_checked_at_its_first_line_not_read_whole_first() {
    let dir = tempfile::tempdir().unwrap();
    let reference = dir.path().join("ref.tum");
    tum(&reference, 20);
    let fifo = dir.path().join("endless.tum");
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    // The writer: lines "1" until the reader closes the pipe.
    let writer = {
        let fifo = fifo.clone();
        std::thread::spawn(move || {
            let Ok(mut f) = std::fs::OpenOptions::new().write(true).open(&fifo) else {
                return;
            };
            let block = "1\n".repeat(1 << 16);
            while f.write_all(block.as_bytes()).is_ok() {}
        })
    };
    let out = dir.path().join("s");
    let o = limited(
        &[
            "score",
            arg(&reference),
            "--trajectory",
            arg(&fifo),
            "--out",
            arg(&out),
        ],
        &[],
    );
    // Unblock the writer if the reader never opened the pipe (without blocking here:
    // O_NONBLOCK opens a pipe's reading end at once).
    if !writer.is_finished() {
        use std::os::unix::fs::OpenOptionsExt as _;
        let _ = std::fs::OpenOptions::new()
            .read(true)
            .custom_flags(0o4000)
            .open(&fifo);
    }
    writer.join().unwrap();
    refused(&o, &["endless.tum", "line 1", "1 number"]);
    assert!(!out.exists());
}

/// A `width` x `height` 8-bit grey PNG whose pixels alternate junction (2) and dead end (4)
/// in a checkerboard: every pixel its own detected node.
fn checkerboard(width: u32, height: u32) -> Vec<u8> {
    let mut bytes = Vec::new();
    {
        let mut e = png::Encoder::new(&mut bytes, width, height);
        e.set_color(png::ColorType::Grayscale);
        e.set_depth(png::BitDepth::Eight);
        let mut w = e.write_header().unwrap();
        let data: Vec<u8> = (0..height)
            .flat_map(|r| (0..width).map(move |c| if (r + c) % 2 == 0 { 2 } else { 4 }))
            .collect();
        w.write_image_data(&data).unwrap();
    }
    bytes
}

/// Item 10: `score --segmentation --node-radius 2000` on the cave preset with a map where every
/// pixel is a detected node (12 million) keeps only the candidate pairs the matching can use
/// (every pair of detection and graph node was stored before the fix: an abort under 3 GB).
#[test]
fn item10_node_matching_does_not_store_every_pair() {
    let dir = tempfile::tempdir().unwrap();
    let w = dir.path().join("cave");
    ok(&[
        "generate",
        "--preset",
        "cave",
        "--format",
        "ground-truth",
        "--out",
        arg(&w),
    ]);
    // The PGM header: P5, width, height, each after white space or a `#` comment line.
    let pgm = std::fs::read(w.join("ground_truth/maps/level-0.pgm")).unwrap();
    let head = String::from_utf8_lossy(&pgm[..pgm.len().min(1024)]).into_owned();
    let fields: Vec<u32> = head
        .lines()
        .filter(|l| !l.starts_with('#'))
        .flat_map(str::split_whitespace)
        .skip(1)
        .take(2)
        .map(|s| s.parse().unwrap())
        .collect();
    let (width, height) = (fields[0], fields[1]);
    assert!(
        u64::from(width) * u64::from(height) > 10_000_000,
        "{width} x {height}"
    );
    let png = dir.path().join("level-0.png");
    std::fs::write(&png, checkerboard(width, height)).unwrap();
    let out = dir.path().join("s");
    let o = limited(
        &[
            "score",
            arg(&w),
            "--segmentation",
            arg(&png),
            "--node-radius",
            "2000",
            "--out",
            arg(&out),
        ],
        &[],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&out.join("segmentation.json"));
    assert_eq!(
        s["nodes_detected"].as_u64().unwrap(),
        u64::from(width) * u64::from(height)
    );
    // Every graph node is matched: the radius covers the level, and there are detections to
    // spare.
    assert_eq!(s["nodes_matched"], s["nodes_truth"]);
}

/// Item 11: `report` with 1,000 methods compares half a million pairs: refused at once with
/// the estimate and what to change (before the fix it ran for minutes and aborted); 30 methods
/// make every pair.
#[test]
fn item11_pairwise_comparisons_are_bounded_with_the_estimate() {
    let dir = tempfile::tempdir().unwrap();
    let (_, runs) = report_runs(
        dir.path(),
        1000,
        |m| serde_json::json!({"value": m as f64, "other": (m * m) as f64}),
    );
    let out = dir.path().join("r");
    let o = subtgraph_within(&["report", "--runs", arg(&runs), "--out", arg(&out)], HANG);
    refused(&o, &["1000 methods", "499500 pairs", "fewer methods"]);
    assert!(!out.exists());
    // 30 methods: 435 pairs of each of the two metrics.
    let few = dir.path().join("few");
    std::fs::create_dir(&few).unwrap();
    let (_, runs) = report_runs(
        &few,
        30,
        |m| serde_json::json!({"value": m as f64, "other": (m * m) as f64}),
    );
    let out = dir.path().join("r30");
    ok(&["report", "--runs", arg(&runs), "--out", arg(&out)]);
    let paired = std::fs::read_to_string(out.join("paired.csv")).unwrap();
    assert_eq!(paired.lines().count(), 1 + 2 * 30 * 29 / 2);
}

/// Item 12: `--out .`, `--out ..` and a folder holding the current one are refused by
/// `generate`, `sense` and `dataset` (the world went into a new subfolder named after the
/// current folder, and `wrote .` was printed, before the fix). Python's `World.export(".")`
/// is in `python/tests/test_world.py`.
#[test]
fn item12_out_is_never_the_current_folder_or_one_holding_it() {
    let dir = tempfile::tempdir().unwrap();
    let w = cave_world(dir.path(), "w");
    let here = dir.path().join("a/b");
    std::fs::create_dir_all(&here).unwrap();
    std::fs::write(here.join("notes.txt"), b"mine").unwrap();
    let before = common::folder_files(dir.path());
    let a = dir.path().join("a");
    for out in [".", "..", "./", "../", arg(&a), arg(&here)] {
        let cases: [&[&str]; 4] = [
            &["generate", "--preset", "cave", "--no-mesh", "--out", out],
            &[
                "generate",
                "--preset",
                "cave",
                "--no-mesh",
                "--out",
                out,
                "--force",
            ],
            &["sense", arg(&w), "--out", out],
            &[
                "dataset",
                "--preset",
                "cave",
                "--no-mesh",
                "--count",
                "1",
                "--out",
                out,
            ],
        ];
        for args in cases {
            let o = run_in(&here, args);
            refused(&o, &["--out", "current folder"]);
        }
    }
    assert_eq!(common::folder_files(dir.path()), before, "nothing written");
}

/// Item 13: a world folder whose `world.toml` was edited (the cave's width, 5 m to 5.5 m: the
/// same number of bytes, the same graph) is refused by `sense`: it would rebuild another world
/// than the folder's meshes and ground truth (only the graph's node and edge counts were
/// compared before the fix, and the wider world was sensed).
#[test]
fn item13_sense_refuses_a_world_toml_edited_after_the_world_was_made() {
    let dir = tempfile::tempdir().unwrap();
    let w = cave_world(dir.path(), "w");
    let toml = std::fs::read_to_string(w.join("world.toml")).unwrap();
    assert!(toml.contains("width = 5.0"), "{toml}");
    std::fs::write(
        w.join("world.toml"),
        toml.replace("width = 5.0", "width = 5.5"),
    )
    .unwrap();
    let out = dir.path().join("s");
    let o = subtgraph_within(
        &["sense", arg(&w), "--duration", "1", "--out", arg(&out)],
        HANG,
    );
    refused(&o, &["world.toml", "changed", "generate"]);
    assert!(!out.exists());
    // Put back, it senses; so it does with its meshes removed to save room (the world is
    // made again from world.toml: the meshes are not read).
    std::fs::write(w.join("world.toml"), &toml).unwrap();
    std::fs::remove_dir_all(w.join("mesh")).unwrap();
    ok(&["sense", arg(&w), "--duration", "1", "--out", arg(&out)]);
}

/// Item 14: `dataset --sense` run again with other sensor options does not keep the old
/// sequences as if they were this run's: it refuses, naming the options that differ, and
/// changes nothing (it said "kept 1 complete one(s)" before the fix); the same options keep
/// them.
#[test]
fn item14_dataset_sense_with_other_options_is_refused_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let pipeline = small_cave_pipeline(dir.path(), 1, "");
    let data = dir.path().join("data");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "dataset",
            arg(&pipeline),
            "--count",
            "1",
            "--sense",
            "--sense-duration",
            "1",
            "--out",
            arg(&data),
        ];
        args.extend_from_slice(extra);
        subtgraph(&args)
    };
    let o = run(&[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let seq = data.join("sequences/small-cave-0000");
    let before = common::folder_bytes(&seq);
    let o = run(&["--sense-lidar", "vlp-16"]);
    refused(&o, &["small-cave-0000", "lidar", "os1-32", "vlp-16"]);
    assert_eq!(common::folder_bytes(&seq), before, "nothing changed");
    let o = run(&[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        String::from_utf8_lossy(&o.stdout).contains("kept 1 complete one(s)"),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
}

/// Items 15 and 16: a method named `lio (v2, tuned)` is quoted in every CSV of the report as
/// RFC 4180 says (rows had a column more than their header before the fix), as Python's csv
/// module reads them; and metrics `zz.y` and `zz-y` get a picture each (they shared one).
#[test]
fn item15_16_report_csvs_are_quoted_and_metrics_get_distinct_pictures() {
    let dir = tempfile::tempdir().unwrap();
    report_runs(
        dir.path(),
        2,
        |m| serde_json::json!({"zz": {"y": m as f64}, "zz-y": (10 * m) as f64, "failed": m == 1}),
    );
    // The methods named on the command line, as METHOD=FOLDER.
    let (a, b) = (
        format!("lio (v2, tuned)={}", arg(&dir.path().join("score-0"))),
        format!("say \"hi\"={}", arg(&dir.path().join("score-1"))),
    );
    let out = dir.path().join("r");
    ok(&["report", &a, &b, "--out", arg(&out)]);
    let Some(python) = common::python_with(&["csv", "json"]) else {
        return;
    };
    let script = r#"
import csv, json, sys, pathlib
out = {}
for p in sorted(pathlib.Path(sys.argv[1]).glob("*.csv")):
    with open(p, newline="") as f:
        rows = list(csv.reader(f))
    out[p.name] = {"widths": sorted({len(r) for r in rows}), "first": [r[0] for r in rows[1:]]}
print(json.dumps(out))
"#;
    let o = Command::new(python)
        .args(["-c", script, arg(&out)])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let read: Value = serde_json::from_slice(&o.stdout).unwrap();
    let files = read.as_object().unwrap();
    assert!(files.len() >= 5, "{read}");
    for (name, f) in files {
        assert_eq!(f["widths"].as_array().unwrap().len(), 1, "{name}: {f}");
    }
    let methods: Vec<&str> = files["summary.csv"]["first"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert!(methods.contains(&"lio (v2, tuned)"), "{methods:?}");
    assert!(methods.contains(&"say \"hi\""), "{methods:?}");
    // Item 16: one picture per metric, each named in the page.
    let report = json(&out.join("report.json"));
    let metrics: Vec<&str> = report["metrics"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert!(
        metrics.contains(&"a.zz.y") && metrics.contains(&"a.zz-y"),
        "{metrics:?}"
    );
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    let pictures: std::collections::BTreeSet<&str> = html
        .split("src=\"")
        .skip(1)
        .filter_map(|s| s.split('"').next())
        .filter(|s| s.starts_with("plots/") && !s.contains("failure"))
        .collect();
    assert_eq!(pictures.len(), metrics.len(), "{pictures:?}");
    for p in &pictures {
        assert!(out.join(p).is_file(), "{p}");
    }
}

/// Item 18: an imported world (`generate --occupancy`) is sensed from its own grid, which its
/// folder holds (`sense` rebuilt another world from the pipeline alone, and refused it, before
/// the fix). The grid imported again with the recorded pipeline makes the folder's files byte
/// for byte, and the sequence's returns lie on the folder's own collision mesh (trimesh, by
/// `tests/readers/sense_check.py`).
#[test]
fn item18_an_imported_world_is_sensed_from_its_own_grid() {
    let dir = tempfile::tempdir().unwrap();
    let pipeline = small_cave_pipeline(dir.path(), 1, "");
    let source = dir.path().join("source");
    ok(&[
        "generate",
        arg(&pipeline),
        "--no-mesh",
        "--seed",
        "7",
        "--out",
        arg(&source),
    ]);
    let w = dir.path().join("imported");
    ok(&[
        "generate",
        arg(&pipeline),
        "--occupancy",
        arg(&source.join("occupancy.npy")),
        "--format",
        "ground-truth",
        "--out",
        arg(&w),
    ]);
    // What sense rebuilds: the folder's grid imported again with its world.toml.
    let again = dir.path().join("again");
    ok(&[
        "generate",
        arg(&w.join("world.toml")),
        "--occupancy",
        arg(&w.join("occupancy.npy")),
        "--out",
        arg(&again),
    ]);
    common::assert_same_files(&w, &again, &["world.toml", ".subtgraph-files"]);
    let out = dir.path().join("s");
    let o = subtgraph_within(
        &[
            "sense",
            arg(&w),
            "--duration",
            "6",
            "--noiseless",
            "--out",
            arg(&out),
        ],
        HANG,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let seq = json(&out.join("sequence.json"));
    let graph = json(&w.join("ground_truth/graph.json"));
    assert_eq!(seq["route"]["nodes"][0], graph["start"], "{}", seq["route"]);
    if let Some(said) = common::read_with_python(
        &["rosbags", "trimesh", "rtree"],
        "sense_check.py",
        &[arg(&out), arg(&w.join("mesh/world.obj")), "--noiseless"],
    ) {
        let v: Value = serde_json::from_str(said.trim()).unwrap();
        // The world the grid makes (another world is metres off): within millimetres of its
        // visual surface, as the OBJ's text keeps it (1.07 mm at most, 0.04 mm RMS, here).
        assert!(v["max_distance_m"].as_f64().unwrap() < 5e-3, "{v}");
    }
}

/// Item 19: `dataset --sense --sense-duration 0` is refused before any world is made (the
/// worlds were made first before the fix).
#[test]
fn item19_sense_options_are_checked_before_any_world_is_made() {
    let dir = tempfile::tempdir().unwrap();
    let pipeline = small_cave_pipeline(dir.path(), 1, "");
    for bad in ["0", "-1", "nan", "inf"] {
        let fresh = dir.path().join(format!("fresh{bad}"));
        let o = subtgraph(&[
            "dataset",
            arg(&pipeline),
            "--count",
            "1",
            "--sense",
            &format!("--sense-duration={bad}"),
            "--out",
            arg(&fresh),
        ]);
        refused(&o, &["--sense-duration"]);
        assert!(!fresh.exists(), "nothing made");
    }
}

/// Item 20: a TUM file of five-number lines is told its lines have five numbers where TUM has
/// eight and KITTI twelve (it was told its first line had 8).
#[test]
fn item20_a_first_line_of_the_wrong_width_is_named_as_it_is() {
    let dir = tempfile::tempdir().unwrap();
    let reference = dir.path().join("ref.tum");
    tum(&reference, 20);
    let five = dir.path().join("five.tum");
    std::fs::write(&five, "0 1 2 3 4\n0.1 1 2 3 4\n").unwrap();
    let out = dir.path().join("s");
    let o = subtgraph(&[
        "score",
        arg(&reference),
        "--trajectory",
        arg(&five),
        "--out",
        arg(&out),
    ]);
    refused(&o, &["five.tum", "line 1", "5 numbers", "(8)", "(12)"]);
    assert!(!stderr(&o).contains("first line has 8"), "{}", stderr(&o));
}

/// Item 21: a `runs.csv` saved with a byte-order mark (as spreadsheets save it) reads as
/// without it (it was told its header was missing); and its fields may be quoted as
/// spreadsheets quote them (a method named `lio (v2, tuned)`).
#[test]
fn item21_a_runs_csv_with_a_byte_order_mark_reads_as_without() {
    let dir = tempfile::tempdir().unwrap();
    let (_, runs) = report_runs(dir.path(), 3, |m| serde_json::json!({"value": m as f64}));
    let with_bom = |from: &Path, to: &Path| {
        let mut bytes = "\u{feff}".as_bytes().to_vec();
        bytes.extend_from_slice(&std::fs::read(from).unwrap());
        std::fs::write(to, bytes).unwrap();
    };
    let report = |csv: &Path, out: &str| {
        let out = dir.path().join(out);
        ok(&["report", "--runs", arg(csv), "--out", arg(&out)]);
        json(&out.join("report.json"))
    };
    let bom = dir.path().join("bom.csv");
    with_bom(&runs, &bom);
    let (a, b) = (report(&runs, "a"), report(&bom, "b"));
    assert_eq!(a["summary"], b["summary"]);
    assert_eq!(a["paired"], b["paired"]);
    // Quoted as a spreadsheet quotes a name with a comma or a quote.
    let quoted = dir.path().join("quoted.csv");
    let text = std::fs::read_to_string(&runs)
        .unwrap()
        .replace("method 0", "\"lio (v2, tuned)\"")
        .replace("method 1", "\"say \"\"hi\"\"\"");
    std::fs::write(&quoted, text).unwrap();
    let quoted_bom = dir.path().join("quoted-bom.csv");
    with_bom(&quoted, &quoted_bom);
    let (c, d) = (report(&quoted, "c"), report(&quoted_bom, "d"));
    assert_eq!(
        c["methods"],
        serde_json::json!(["lio (v2, tuned)", "method 2", "say \"hi\""])
    );
    assert_eq!(c["summary"], d["summary"]);
}

/// Item 22: a `--max-disk` or `--max-memory` past 64 bits is told it is too large and what the
/// largest is (it was told "give a size of at least 1M").
#[test]
fn item22_a_size_past_64_bits_is_told_it_is_too_large() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s");
    let o = subtgraph(&[
        "sense",
        arg(&dir.path().join("no-world")),
        "--max-disk",
        "20000000000G",
        "--out",
        arg(&out),
    ]);
    refused(&o, &["--max-disk 20000000000G", "too large", "at most"]);
    assert!(!stderr(&o).contains("at least 1M"), "{}", stderr(&o));
    let o = subtgraph(&[
        "generate",
        "--preset",
        "cave",
        "--max-memory",
        "20000000000G",
        "--out",
        arg(&out),
    ]);
    refused(&o, &["--max-memory 20000000000G", "too large", "at most"]);
    // Small and unreadable sizes keep their own messages.
    let o = subtgraph(&[
        "sense",
        arg(&dir.path().join("no-world")),
        "--max-disk",
        "10k",
        "--out",
        arg(&out),
    ]);
    refused(&o, &["--max-disk 10k", "at least 1M"]);
    let o = subtgraph(&[
        "sense",
        arg(&dir.path().join("no-world")),
        "--max-disk",
        "lots",
        "--out",
        arg(&out),
    ]);
    refused(&o, &["--max-disk lots", "like 20G"]);
}
