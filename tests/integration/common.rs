//! Helpers shared by the integration tests: running the command line, and checking our files
//! with the real programs that read them (Python readers from `.venv`, set up by
//! `scripts/test`).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The binary the tests run: this build's, or the one `SUBTGRAPH_BIN` names, to show that a
/// test fails on a build from before its fix
/// (`SUBTGRAPH_BIN=old/subtgraph cargo test --test integration reliability::`).
pub fn binary() -> PathBuf {
    std::env::var_os("SUBTGRAPH_BIN").map_or_else(
        || PathBuf::from(env!("CARGO_BIN_EXE_subtgraph")),
        PathBuf::from,
    )
}

/// Runs `subtgraph` with arguments, from the repository root.
pub fn subtgraph(args: &[&str]) -> Output {
    Command::new(binary())
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the binary runs")
}

/// Runs `subtgraph` as [`subtgraph`] does, failing the test if it has not ended after `limit`
/// (it is killed): a guard against a hang, far above what the run needs, not a timing.
pub fn subtgraph_within(args: &[&str], limit: std::time::Duration) -> Output {
    let mut child = Command::new(binary())
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the binary runs");
    // Read as it comes, so a full pipe never stops the child.
    let drain = |mut r: Box<dyn std::io::Read + Send>| {
        std::thread::spawn(move || {
            let mut v = Vec::new();
            let _ = r.read_to_end(&mut v);
            v
        })
    };
    let out = drain(Box::new(child.stdout.take().expect("piped")));
    let err = drain(Box::new(child.stderr.take().expect("piped")));
    let started = std::time::Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("waiting works") {
            break status;
        }
        if started.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("subtgraph {args:?} did not end within {limit:?}: it hangs");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    Output {
        status,
        stdout: out.join().expect("read"),
        stderr: err.join().expect("read"),
    }
}

/// Runs `subtgraph`, asserting success; returns standard output.
pub fn ok(args: &[&str]) -> String {
    let out = subtgraph(args);
    assert!(
        out.status.success(),
        "subtgraph {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// Runs `subtgraph`, asserting failure; returns standard error.
pub fn fails(args: &[&str]) -> String {
    let out = subtgraph(args);
    assert!(!out.status.success(), "subtgraph {args:?} should fail");
    String::from_utf8(out.stderr).unwrap()
}

/// A path as a `&str` argument.
pub fn arg(p: &Path) -> &str {
    p.to_str().expect("test paths are UTF-8")
}

/// The Python that has the readers (`SUBTGRAPH_PYTHON`, set by `scripts/test`), if it has
/// every module in `modules`. Without it a test says so and returns `None`, unless
/// `SUBTGRAPH_REQUIRE_PYTHON=1` (as `scripts/test` sets), where a missing reader fails.
pub fn python_with(modules: &[&str]) -> Option<PathBuf> {
    let python =
        PathBuf::from(std::env::var("SUBTGRAPH_PYTHON").unwrap_or_else(|_| "python3".into()));
    let imports = modules
        .iter()
        .map(|m| format!("import {m}"))
        .collect::<Vec<_>>()
        .join("; ");
    let has = Command::new(&python)
        .args(["-c", &imports])
        .output()
        .is_ok_and(|o| o.status.success());
    if has {
        return Some(python);
    }
    assert!(
        std::env::var("SUBTGRAPH_REQUIRE_PYTHON").is_err(),
        "{} cannot import {modules:?}; run scripts/test, which installs the readers",
        python.display()
    );
    eprintln!(
        "skipping: {} cannot import {modules:?} (run scripts/test to install the readers)",
        python.display()
    );
    None
}

/// Runs `tests/readers/<script>` with arguments under a Python that has `modules`, asserting
/// it succeeds; returns its standard output (`None` when skipped, see [`python_with`]).
pub fn read_with_python(modules: &[&str], script: &str, args: &[&str]) -> Option<String> {
    let python = python_with(modules)?;
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/readers")
        .join(script);
    let out = Command::new(python)
        .arg(&path)
        .args(args)
        .output()
        .expect("python runs");
    assert!(
        out.status.success(),
        "{script} {args:?} failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    Some(String::from_utf8(out.stdout).unwrap())
}

/// The DARPA SubT cave tiles beside the checkout (`../shared/darpa-subt-tiles`), or `None`
/// with a message saying the test that needs them is skipped.
pub fn darpa_tiles() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/darpa-subt-tiles/cave-type-b");
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!(
            "skipping: ../shared/darpa-subt-tiles is absent (DARPA tiles are test data kept beside the checkout)"
        );
        None
    }
}

/// `examples/darpa-cave-levels.toml` (two levels of DARPA tiles joined by the vertical shaft)
/// with `seed`, written into `dir`; with `old_shaft`, through the shipped manifest as it
/// was before its shaft faced both corridors (the shaft turned as if its foot opened south, and
/// not cut: whole at the foot, a dead end's tile over its top). `tiles` is [`darpa_tiles`].
pub fn darpa_levels(dir: &Path, tiles: &Path, seed: u64, old_shaft: bool) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let shipped = root.join("tilesets/manifests/darpa-cave-type-b.toml");
    let manifest = if old_shaft {
        let text = std::fs::read_to_string(&shipped).unwrap();
        let old = text
            .lines()
            .map(|l| match l {
                l if l.starts_with("root =") => format!("root = {:?}", tiles.display().to_string()),
                "top = \"west\"" => "top = \"none\"".into(),
                "split = 32.0" => String::new(),
                l => l.to_owned(),
            })
            .collect::<Vec<_>>()
            .join("\n");
        let from = "kind = \"shaft-up\"\nrotation = 1";
        assert!(old.contains(from) && old.contains("top = \"none\""));
        let p = dir.join("old-shaft.toml");
        std::fs::write(&p, old.replace(from, "kind = \"shaft-up\"\nrotation = 3")).unwrap();
        p
    } else {
        shipped
    };
    let text = std::fs::read_to_string(root.join("examples/darpa-cave-levels.toml")).unwrap();
    let pipeline = [
        ("seed = 15", format!("seed = {seed}")),
        (
            "manifest = \"../tilesets/manifests/darpa-cave-type-b.toml\"",
            format!("manifest = {:?}", manifest.display().to_string()),
        ),
    ]
    .iter()
    .fold(text, |t, (from, to)| {
        assert!(
            t.contains(from),
            "examples/darpa-cave-levels.toml has {from}"
        );
        t.replacen(from, to, 1)
    });
    let p = dir.join(format!("darpa-cave-levels-{seed}.toml"));
    std::fs::write(&p, pipeline).unwrap();
    p
}

/// Every file of a folder, relative path and bytes, sorted.
pub fn folder_bytes(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_owned()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let rel = p.strip_prefix(dir).unwrap().to_string_lossy().into_owned();
                out.push((rel, std::fs::read(&p).unwrap()));
            }
        }
    }
    out.sort();
    out
}

/// `generate PIPELINE --format FORMATS` into `dir/t1` and `dir/t3` with `RAYON_NUM_THREADS` 1
/// and 3, and asserts the two folders hold the same files, byte for byte: determinism over
/// thread counts. Returns the two folders.
pub fn assert_same_on_one_and_three_threads(
    dir: &Path,
    pipeline: &Path,
    formats: &str,
) -> Vec<PathBuf> {
    let mut folders = Vec::new();
    for threads in ["1", "3"] {
        let out = dir.join(format!("t{threads}"));
        let status = Command::new(env!("CARGO_BIN_EXE_subtgraph"))
            .args(["generate", arg(pipeline), "--out", arg(&out)])
            .args(["--format", formats])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(status.status.success(), "{status:?}");
        folders.push(out);
    }
    assert_same_files(&folders[0], &folders[1], &[]);
    folders
}

/// Asserts two folders hold the same files with the same bytes, except the files named in
/// `except`; a failure names the files that differ rather than printing their bytes. The
/// list of written files (`.subtgraph-files`, which holds every file's size) is compared only
/// when no file is excepted.
pub fn assert_same_files(a: &Path, b: &Path, except: &[&str]) {
    let names = |dir: &Path| -> Vec<String> {
        folder_files(dir)
            .into_iter()
            .filter(|n| {
                !except.contains(&n.as_str()) && (except.is_empty() || n != ".subtgraph-files")
            })
            .collect()
    };
    let (na, nb) = (names(a), names(b));
    assert_eq!(na, nb, "the same files");
    // A file at a time: a meshed world's folder is hundreds of megabytes.
    let differ: Vec<&str> = na
        .iter()
        .filter(|n| std::fs::read(a.join(n)).unwrap() != std::fs::read(b.join(n)).unwrap())
        .map(String::as_str)
        .collect();
    assert!(differ.is_empty(), "these files differ: {differ:?}");
}

/// The files under `dir`, as paths relative to it, sorted.
pub fn folder_files(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_owned()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push(p.strip_prefix(dir).unwrap().to_string_lossy().into_owned());
            }
        }
    }
    out.sort();
    out
}

/// A small pipeline with a coarse cave tile set: quick to mesh and to load in a simulator.
/// `levels` levels of 20 x 20 cells, 16 m pitch, a loop, junctions and an intersection. The
/// collision lattice (2 m) is as fine as the visual one: at 4 m the 5 m wide passages pinch
/// shut in places and no robot would fit (found by the physics and ground-truth checks).
pub fn small_cave_pipeline(dir: &Path, levels: u32, extra: &str) -> PathBuf {
    let text = format!(
        "[world]\nseed = 5\nlevels = {levels}\nrows = 20\ncols = 20\ntile_pitch = 16.0\nlevel_height = 16.0\n\n\
         [topology]\nloops = 1\nt_junctions = 1\nintersections = 1\n\n\
         [route]\ntype = \"parabolic\"\n\n\
         [tileset]\ntype = \"cave\"\nwidth = 5.0\nheight = 4.0\nresolution = 8\ncollision_resolution = 8\nrocks = 0\n\n{extra}"
    );
    let path = dir.join("small-cave.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// A `.npy` file with any dtype text, shape text and data bytes, as numpy or a crafted file
/// would have them (version 1 header, padded to 64 bytes).
pub fn npy_bytes(descr: &str, shape: &str, data: &[u8]) -> Vec<u8> {
    let mut h = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    while (10 + h.len() + 1) % 64 != 0 {
        h.push(' ');
    }
    h.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend_from_slice(&(h.len() as u16).to_le_bytes());
    out.extend_from_slice(h.as_bytes());
    out.extend_from_slice(data);
    out
}

/// What `tests/readers/sdf_check.cc` (compiled against libsdformat 12 in `dir`) reports on an
/// SDF file, or `None` (skipped with a message) when pkg-config does not know `sdformat12`,
/// unless `SUBTGRAPH_REQUIRE_SDFORMAT=1`. Fails when libsdformat refuses the file.
pub fn sdf_report(dir: &Path, sdf: &Path) -> Option<String> {
    let flags = Command::new("pkg-config")
        .args(["--cflags", "--libs", "sdformat12"])
        .output()
        .ok()
        .filter(|o| o.status.success());
    let Some(flags) = flags else {
        assert!(
            std::env::var("SUBTGRAPH_REQUIRE_SDFORMAT").is_err(),
            "pkg-config cannot find sdformat12; install libsdformat-dev (scripts/test does)"
        );
        eprintln!("skipping the SDF check: pkg-config cannot find sdformat12");
        return None;
    };
    let exe = dir.join("sdf_check");
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/readers/sdf_check.cc");
    let flags = String::from_utf8(flags.stdout).unwrap();
    let built = Command::new("g++")
        .args(["-std=c++17", "-O0", "-o", arg(&exe), arg(&source)])
        .args(flags.split_whitespace())
        .output()
        .expect("g++ runs");
    assert!(
        built.status.success(),
        "compiling sdf_check.cc failed:\n{}",
        String::from_utf8_lossy(&built.stderr)
    );
    let out = Command::new(&exe).arg(sdf).output().unwrap();
    assert!(
        out.status.success(),
        "libsdformat refused {}:\n{}",
        sdf.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    Some(String::from_utf8(out.stdout).unwrap())
}

/// `ground_truth/graph.json` of `world`, as the `graph` exporter writes it (in memory).
pub fn graph_json(world: &subtgraph::core::World) -> serde_json::Value {
    use subtgraph::core::export::{Exporter, MemoryWriter};
    let mut out = MemoryWriter::default();
    let survey = subtgraph::survey::WorldSurvey::new(world).unwrap();
    subtgraph::exporters::GraphFiles
        .export(world, &survey, &mut out)
        .unwrap();
    serde_json::from_slice(out.get("ground_truth/graph.json").unwrap()).unwrap()
}

/// A JSON `[x, y, z]` as numbers.
pub fn json_point(v: &serde_json::Value) -> [f64; 3] {
    [0, 1, 2].map(|k| v[k].as_f64().unwrap())
}

/// A one-level mine of about 25 x 25 cells (seed 3), with `extra` lines in its `[tileset]`,
/// written as `dir/name.toml`.
pub fn small_mine(dir: &Path, name: &str, extra: &str) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(
        &path,
        format!(
            "[world]\nseed = 3\nlevels = 1\nmin_length = [500, 500]\ntile_pitch = 20.0\n\n\
             [route]\ntype = \"linear\"\n\n[tileset]\ntype = \"mine\"\n{extra}\n"
        ),
    )
    .unwrap();
    path
}

/// `subtgraph generate PIPELINE --format FORMATS --out OUT`, which must succeed.
pub fn generate_formats(pipeline: &Path, out: &Path, formats: &str) {
    ok(&[
        "generate",
        arg(pipeline),
        "--format",
        formats,
        "--out",
        arg(out),
    ]);
}
