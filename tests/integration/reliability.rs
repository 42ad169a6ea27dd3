//! Issue 21, round 2, as a hostile user tried it: nothing lost by `stats` or `score`, `--out`
//! checked before the work, crafted clouds and edited world files refused instead of aborting,
//! no hang on a huge radius, and the readers' silent misreadings. Each test failed on the build
//! before its fix (`SUBTGRAPH_BIN=old/subtgraph cargo test --test integration reliability::`
//! runs them against another build).

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Output;
use std::time::Duration;

use common::{arg, ok, small_cave_pipeline, subtgraph, subtgraph_within};
use serde_json::Value;

/// Far above what any run here needs: only a hang reaches it.
const HANG: Duration = Duration::from_secs(120);

/// A two-level small cave with artifacts and its free space.
fn world(dir: &Path, name: &str) -> PathBuf {
    let p = small_cave_pipeline(
        dir,
        2,
        "[artifacts]\ncount = 6\nmin_distance_from_start = 20\nmin_spacing = 15\n",
    );
    let out = dir.join(name);
    ok(&[
        "generate",
        arg(&p),
        "--format",
        "free-space",
        "--out",
        arg(&out),
    ]);
    out
}

/// A grid-only world of the cave preset (quick).
fn grid_world(dir: &Path, name: &str, seed: &str) -> PathBuf {
    let out = dir.join(name);
    ok(&[
        "generate",
        "--preset",
        "cave",
        "--no-mesh",
        "--seed",
        seed,
        "--out",
        arg(&out),
    ]);
    out
}

fn json(path: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts a clean refusal: exit status 1 (not an abort, 134, or a panic, 101) and a message
/// holding every one of `words`.
fn refused(o: &Output, words: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(1), "a clean error, not a crash: {e}");
    for w in words {
        assert!(e.contains(w), "{w:?} in: {e}");
    }
}

/// Reports 1 m from every artifact (each scores).
fn reports(dir: &Path, world: &Path) -> PathBuf {
    let truth = json(&world.join("ground_truth/artifacts.json"));
    let mut csv = String::from("time,class,x,y,z\n");
    for (k, a) in truth["artifacts"].as_array().unwrap().iter().enumerate() {
        let p = &a["position"];
        csv.push_str(&format!(
            "{k},{},{},{},{}\n",
            a["class"].as_str().unwrap(),
            p[0].as_f64().unwrap() + 1.0,
            p[1].as_f64().unwrap(),
            p[2].as_f64().unwrap()
        ));
    }
    let path = dir.join("reports.csv");
    std::fs::write(&path, csv).unwrap();
    path
}

/// The collision surface's vertices as an ASCII PLY: a map with no map error.
fn surface_map(dir: &Path, world: &Path) -> PathBuf {
    let obj = std::fs::read_to_string(world.join("mesh/collision.obj")).unwrap();
    let verts: Vec<&str> = obj.lines().filter_map(|l| l.strip_prefix("v ")).collect();
    let mut ply = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
        verts.len()
    );
    for v in verts {
        ply.push_str(v);
        ply.push('\n');
    }
    let path = dir.join("surface.ply");
    std::fs::write(&path, ply).unwrap();
    path
}

/// Item 1: `stats` never replaces a world (`world.toml` gone) nor a folder it reads, from the
/// command line or from Python (`python/tests`); it still replaces its own earlier report.
#[test]
fn stats_never_replaces_a_world_or_a_folder_it_reads() {
    let dir = tempfile::tempdir().unwrap();
    let a = grid_world(dir.path(), "a", "1");
    let b = grid_world(dir.path(), "b", "2");
    let o = subtgraph(&["stats", arg(&a), "--out", arg(&b)]);
    refused(&o, &["world folder", "stats report"]);
    assert!(b.join("world.toml").is_file(), "the world is kept");
    let o = subtgraph(&["stats", arg(&a), arg(&b), "--out", arg(&a)]);
    refused(&o, &["reads"]);
    assert!(a.join("world.toml").is_file());
    let o = subtgraph(&["stats", arg(&a), "--out", arg(&a.join("report"))]);
    refused(&o, &["reads"]);
    assert!(!a.join("report").exists());
    let report = dir.path().join("report");
    ok(&["stats", arg(&a), arg(&b), "--out", arg(&report)]);
    ok(&["stats", arg(&a), "--out", arg(&report)]);
    let m = std::fs::read_to_string(report.join(".subtgraph-files")).unwrap();
    assert!(m.contains("\ncomplete stats\n"), "{m}");
}

/// Item 2: `score --force` replaces only a score report: never the world being scored, another
/// world, or a stats report; and `generate --force` never replaces a report.
#[test]
fn score_force_replaces_only_a_score_report_and_never_the_world() {
    let dir = tempfile::tempdir().unwrap();
    let w = world(dir.path(), "w");
    let other = grid_world(dir.path(), "other", "3");
    let r = reports(dir.path(), &w);
    let score = |out: &Path, force: bool| {
        let mut args = vec!["score", arg(&w), "--reports", arg(&r), "--out", arg(out)];
        if force {
            args.push("--force");
        }
        subtgraph(&args)
    };
    refused(&score(&w, true), &["reads"]);
    assert!(w.join("world.toml").is_file() && w.join("topology.json").is_file());
    refused(&score(&other, true), &["world folder", "score report"]);
    assert!(other.join("world.toml").is_file());
    let stats = dir.path().join("stats");
    ok(&["stats", arg(&other), "--out", arg(&stats)]);
    refused(&score(&stats, true), &["stats report", "score report"]);
    assert!(stats.join("stats.json").is_file());
    let s = dir.path().join("s");
    assert!(score(&s, false).status.success());
    refused(&score(&s, false), &["already exists"]);
    assert!(
        score(&s, true).status.success(),
        "its own report is replaced"
    );
    let m = std::fs::read_to_string(s.join(".subtgraph-files")).unwrap();
    assert!(m.contains("\ncomplete score\n"), "{m}");
    let m = std::fs::read_to_string(w.join(".subtgraph-files")).unwrap();
    assert!(m.contains("\ncomplete world\n"), "{m}");
    let o = subtgraph(&[
        "generate",
        "--preset",
        "cave",
        "--no-mesh",
        "--out",
        arg(&s),
        "--force",
    ]);
    refused(&o, &["score report", "world folder"]);
    assert!(s.join("score.json").is_file());
}

/// Item 3: every command that writes a folder checks `--out` before any work: the refusal is
/// about `--out`, not about what the work would have found (memory, a missing input).
#[test]
fn out_is_checked_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let w = grid_world(dir.path(), "w", "4");
    // A world too large for 1 MB of memory: the memory was checked first before the fix.
    let o = subtgraph(&[
        "generate",
        "--preset",
        "lava-tube",
        "--max-memory",
        "1M",
        "--out",
        arg(&w),
    ]);
    refused(&o, &["already exists"]);
    let missing = dir.path().join("missing.toml");
    let o = subtgraph(&["generate", arg(&missing), "--out", arg(&w)]);
    refused(&o, &["already exists"]);
    let file = dir.path().join("notes.txt");
    std::fs::write(&file, "mine").unwrap();
    let o = subtgraph(&[
        "dataset",
        arg(&missing),
        "--count",
        "1",
        "--out",
        arg(&file),
    ]);
    refused(&o, &["is a file"]);
    let o = subtgraph(&["stats", arg(&dir.path().join("nothing")), "--out", arg(&w)]);
    refused(&o, &["world folder"]);
    let o = subtgraph(&[
        "score",
        arg(&w),
        "--reports",
        arg(&dir.path().join("none.csv")),
        "--out",
        arg(&w),
    ]);
    refused(&o, &["reads"]);
    // `w` has no mesh: the picture's --out was checked after reading it before the fix.
    let o = subtgraph(&["preview", arg(&w), "--out", arg(&file)]);
    refused(&o, &["not a picture"]);
    assert_eq!(std::fs::read(&file).unwrap(), b"mine");
}

/// Item 4: a cloud's header promising more than the file holds is refused, never reserved
/// (an abort, exit 134, or a capacity overflow, 101, before the fix; the PCD `COUNT` grew for
/// 44 s first).
#[test]
fn crafted_cloud_headers_are_refused_not_reserved() {
    let dir = tempfile::tempdir().unwrap();
    let w = world(dir.path(), "w");
    let r = reports(dir.path(), &w);
    let head = "property float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n";
    let pcd = |points: &str, count: &str| {
        format!(
            "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT {count}\nWIDTH 1\nHEIGHT 1\nPOINTS {points}\nDATA ascii\n0 0 0\n"
        )
    };
    for (k, (file, text)) in [
        (
            "a.ply",
            format!("ply\nformat ascii 1.0\nelement vertex 1000000000000\n{head}"),
        ),
        (
            "b.ply",
            format!("ply\nformat ascii 1.0\nelement vertex 4611686018427387904\n{head}"),
        ),
        (
            "c.ply",
            format!(
                "ply\nformat binary_little_endian 1.0\nelement vertex 4611686018427387904\n{head}"
            ),
        ),
        ("d.pcd", pcd("5000000000000", "1 1 1")),
        ("e.pcd", pcd("1", "1 1 4000000000")),
        ("f.pcd", pcd("1", "1 1 18446744073709551615")),
    ]
    .into_iter()
    .enumerate()
    {
        let map = dir.path().join(file);
        std::fs::write(&map, text).unwrap();
        let out = dir.path().join(format!("s{k}"));
        let o = subtgraph_within(
            &[
                "score",
                arg(&w),
                "--reports",
                arg(&r),
                "--map",
                arg(&map),
                "--out",
                arg(&out),
            ],
            HANG,
        );
        refused(&o, &[file]);
        assert!(!out.exists());
    }
}

/// Item 5: a `topology.json` edited to ids or sizes out of range is refused naming it (a panic
/// in the coverage, or an abort allocating the grid, before the fix).
#[test]
fn an_edited_topology_is_refused_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let w = world(dir.path(), "w");
    let r = reports(dir.path(), &w);
    let map = surface_map(dir.path(), &w);
    let original = std::fs::read(w.join("topology.json")).unwrap();
    type Edit = (&'static str, fn(&mut Value));
    let edits: [Edit; 4] = [
        ("edge 0 joins nodes", |t| {
            t["edges"][0]["to"] = 100_000.into()
        }),
        ("ids must count from 0", |t| {
            t["nodes"][1]["id"] = 100_000.into()
        }),
        ("outside the grid", |t| {
            t["edges"][0]["cells"][0]["row"] = 100_000.into()
        }),
        ("occupancy.npy has shape", |t| {
            t["rows"] = 100_000.into();
            t["cols"] = 100_000.into();
        }),
    ];
    for (k, (what, edit)) in edits.into_iter().enumerate() {
        let mut t: Value = serde_json::from_slice(&original).unwrap();
        edit(&mut t);
        std::fs::write(w.join("topology.json"), t.to_string()).unwrap();
        let out = dir.path().join(format!("s{k}"));
        let o = subtgraph_within(
            &[
                "score",
                arg(&w),
                "--reports",
                arg(&r),
                "--map",
                arg(&map),
                "--out",
                arg(&out),
            ],
            HANG,
        );
        refused(&o, &["topology.json", what]);
    }
    // A thousand levels: the grid (10^13 cells) is never allocated.
    let mut t: Value = serde_json::from_slice(&original).unwrap();
    t["levels"] = 1000.into();
    t["rows"] = 100_000.into();
    t["cols"] = 100_000.into();
    t["per_level"] = Value::Array(vec![t["per_level"][0].clone(); 1000]);
    std::fs::write(w.join("topology.json"), t.to_string()).unwrap();
    let out = dir.path().join("s-levels");
    let o = subtgraph_within(
        &["score", arg(&w), "--reports", arg(&r), "--out", arg(&out)],
        HANG,
    );
    refused(&o, &["topology.json", "occupancy.npy has shape"]);
}

/// Items 7 and 9: a radius or tolerance beyond the world counts as the world's size: no hang
/// (radius 1e300 ran past 60 s before the fix), every free voxel covered, and no map error
/// with a huge tolerance (1e300 wrapped to 0 and counted every point as an error).
#[test]
fn huge_radius_and_tolerance_end_and_count_the_whole_world() {
    let dir = tempfile::tempdir().unwrap();
    let w = world(dir.path(), "w");
    let r = reports(dir.path(), &w);
    let map = surface_map(dir.path(), &w);
    let run = |k: usize, flag: &str, value: &str| {
        let out = dir.path().join(format!("s{k}"));
        let o = subtgraph_within(
            &[
                "score",
                arg(&w),
                "--reports",
                arg(&r),
                "--map",
                arg(&map),
                flag,
                value,
                "--out",
                arg(&out),
            ],
            HANG,
        );
        assert!(o.status.success(), "{flag} {value}: {}", stderr(&o));
        json(&out.join("score.json"))["map"].clone()
    };
    for (k, radius) in ["100000", "1e300"].into_iter().enumerate() {
        let m = run(k, "--radius", radius);
        assert_eq!(
            m["total"]["coverage"], 1.0,
            "--radius {radius}: {}",
            m["total"]
        );
    }
    for (k, tolerance) in ["100", "1e6", "1e300"].into_iter().enumerate() {
        let m = run(10 + k, "--tolerance", tolerance);
        assert_eq!(m["errors"], 0, "--tolerance {tolerance}");
    }
}

/// An occupancy `.npy` map of the world's free-space grid with one voxel set at `voxel`
/// (`[z, y, x]`), in C or Fortran order, with `trailing` bytes after the array.
fn npy_map(w: &Path, voxel: [usize; 3], dtype: &str, fortran: bool, trailing: &[u8]) -> Vec<u8> {
    let fs = json(&w.join("ground_truth/free_space.json"));
    let shape: Vec<usize> = fs["shape"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap() as usize)
        .collect();
    let size: usize = dtype[2..].parse().unwrap();
    let mut data = vec![0u8; shape.iter().product::<usize>() * size];
    let i = if fortran {
        voxel[0] + shape[0] * (voxel[1] + shape[1] * voxel[2])
    } else {
        (voxel[0] * shape[1] + voxel[1]) * shape[2] + voxel[2]
    };
    data[i * size] = 1;
    let mut bytes = common::npy_bytes(
        dtype,
        &format!("({}, {}, {})", shape[0], shape[1], shape[2]),
        &data,
    );
    if fortran {
        let at = bytes.windows(5).position(|w| w == b"False").unwrap();
        bytes.splice(at..at + 5, b"True ".iter().copied());
    }
    bytes.extend_from_slice(trailing);
    bytes
}

/// Items 10 and 20: an occupancy map is read from just after its header (64 trailing bytes
/// made 65 points of 1 before the fix), in either order, and of any dtype.
#[test]
fn an_npy_map_is_read_from_after_its_header_in_either_order() {
    let dir = tempfile::tempdir().unwrap();
    let w = world(dir.path(), "w");
    let r = reports(dir.path(), &w);
    let voxel = [1, 2, 3];
    for (k, (dtype, fortran, trailing)) in [
        ("|u1", false, vec![1u8; 64]),
        ("|b1", true, vec![]),
        ("|u1", true, vec![7u8; 3]),
        ("<i2", false, vec![]),
        ("<f4", true, vec![]),
    ]
    .into_iter()
    .enumerate()
    {
        let map = dir.path().join(format!("map{k}.npy"));
        std::fs::write(&map, npy_map(&w, voxel, dtype, fortran, &trailing)).unwrap();
        let out = dir.path().join(format!("s{k}"));
        let o = subtgraph(&[
            "score",
            arg(&w),
            "--reports",
            arg(&r),
            "--map",
            arg(&map),
            "--out",
            arg(&out),
        ]);
        assert!(o.status.success(), "{dtype} {fortran}: {}", stderr(&o));
        let m = json(&out.join("score.json"))["map"].clone();
        assert_eq!(
            m["points"],
            1,
            "{dtype}, fortran {fortran}, {} trailing bytes",
            trailing.len()
        );
        assert_eq!(m["outside_grid"], 0);
    }
}

/// Item 11: PLY elements are read in the order the header declares them: a face before the
/// vertices is skipped, in ASCII and binary (its line was read as a point before the fix, and
/// the binary one misread, blaming millimetres).
#[test]
fn ply_elements_are_read_in_the_order_the_header_gives() {
    let dir = tempfile::tempdir().unwrap();
    let w = world(dir.path(), "w");
    let r = reports(dir.path(), &w);
    let fs = json(&w.join("ground_truth/free_space.json"));
    let o: Vec<f32> = (0..3)
        .map(|k| fs["origin"][k].as_f64().unwrap() as f32 + 1.0)
        .collect();
    let verts = [
        [o[0], o[1], o[2]],
        [o[0] + 1.0, o[1], o[2]],
        [o[0], o[1] + 1.0, o[2]],
    ];
    let head = |format: &str| {
        format!(
            "ply\nformat {format} 1.0\ncomment a face first\nelement face 1\nproperty list uchar int vertex_indices\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n"
        )
    };
    let mut ascii = head("ascii");
    ascii.push_str("3 100000 100000 100000\n");
    for v in verts {
        ascii.push_str(&format!("{} {} {}\n", v[0], v[1], v[2]));
    }
    ascii.push_str("0 1\n");
    let mut binary = head("binary_little_endian").into_bytes();
    binary.push(3);
    for i in [100_000i32; 3] {
        binary.extend_from_slice(&i.to_le_bytes());
    }
    for v in verts {
        for c in v {
            binary.extend_from_slice(&c.to_le_bytes());
        }
    }
    binary.extend_from_slice(&[0; 8]);
    for (k, bytes) in [ascii.into_bytes(), binary].into_iter().enumerate() {
        let map = dir.path().join(format!("face-first-{k}.ply"));
        std::fs::write(&map, bytes).unwrap();
        let out = dir.path().join(format!("s{k}"));
        let o = subtgraph(&[
            "score",
            arg(&w),
            "--reports",
            arg(&r),
            "--map",
            arg(&map),
            "--out",
            arg(&out),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let m = json(&out.join("score.json"))["map"].clone();
        assert_eq!(m["points"], 3);
        assert_eq!(m["outside_grid"], 0, "every vertex is in the grid: {m}");
    }
}

/// A tube tile for a mesh-files tile set: a square tube (4 x 4 m) from the centre to each
/// opening, 80 m pitch, Z up.
fn tube(openings: &[(f64, f64)]) -> String {
    let (mut v, mut f) = (Vec::new(), Vec::new());
    for &(ax, ay) in openings {
        let (px, py) = (-ay, ax);
        let base = v.len();
        for t in [0.0, 40.0] {
            for (s, z) in [(-2.0, 0.0), (2.0, 0.0), (2.0, 4.0), (-2.0, 4.0)] {
                v.push(format!("v {} {} {}", ax * t + px * s, ay * t + py * s, z));
            }
        }
        for k in 0..4 {
            let (a, b) = (base + k + 1, base + (k + 1) % 4 + 1);
            f.push(format!("f {a} {b} {}", b + 4));
            f.push(format!("f {a} {} {}", b + 4, a + 4));
        }
    }
    format!("o Tube\n{}\n{}\n", v.join("\n"), f.join("\n"))
}

/// Item 13: `validate` refuses what `generate` refuses before meshing (one check, called by
/// both): rubble from a tile set that makes none, and ramps from one that makes none. It said
/// "valid" before the fix.
#[test]
fn validate_refuses_what_generate_refuses_before_meshing() {
    let dir = tempfile::tempdir().unwrap();
    let (e, n, w, s) = ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0));
    let mut manifest = String::from("pitch = 80.0\nup = \"z\"\n");
    for (kind, file, openings) in [
        ("dead-end", "dead.obj", vec![e]),
        ("straight", "straight.obj", vec![e, w]),
        ("corner", "corner.obj", vec![e, s]),
        ("t-junction", "tee.obj", vec![e, n, s]),
        ("intersection", "cross.obj", vec![e, n, w, s]),
    ] {
        std::fs::write(dir.path().join(file), tube(&openings)).unwrap();
        manifest.push_str(&format!(
            "[[tile]]\nkind = \"{kind}\"\nfiles = [\"{file}\"]\n"
        ));
    }
    std::fs::write(dir.path().join("tiles.toml"), manifest).unwrap();
    let p = dir.path().join("tubes.toml");
    std::fs::write(
        &p,
        "[world]\nseed = 2\ntile_pitch = 80.0\n\n[topology]\nloops = 1\n\n[route]\ntype = \"parabolic\"\n\n[tileset]\ntype = \"mesh-files\"\nmanifest = \"tiles.toml\"\n\n[hazards]\nrubble = 0.3\n",
    )
    .unwrap();
    let o = subtgraph(&["validate", arg(&p)]);
    refused(&o, &["hazards.rubble", "does not make rubble"]);
    let o = subtgraph(&["generate", arg(&p), "--out", arg(&dir.path().join("g"))]);
    refused(&o, &["hazards.rubble", "does not make rubble"]);
    // Ramps between levels: the DARPA tiles have a shaft, and no ramp.
    let Some(tiles) = common::darpa_tiles() else {
        return;
    };
    let levels = common::darpa_levels(dir.path(), &tiles, 15, false);
    let text = std::fs::read_to_string(&levels).unwrap();
    std::fs::write(
        &levels,
        text.replace("[world]\n", "[world]\nconnections = \"ramp\"\n"),
    )
    .unwrap();
    let o = subtgraph(&["validate", arg(&levels)]);
    refused(&o, &["makes no ramps", "world.connections"]);
}

/// Item 17: a CSV with a UTF-8 byte-order mark (spreadsheet programs write one) reads as
/// without it ("no `time` column (it has \ufefftime, ...)" before the fix).
#[test]
fn a_csv_with_a_byte_order_mark_reads_as_without() {
    let dir = tempfile::tempdir().unwrap();
    let w = world(dir.path(), "w");
    let r = reports(dir.path(), &w);
    let mut bom = "\u{feff}".as_bytes().to_vec();
    bom.extend_from_slice(&std::fs::read(&r).unwrap());
    let with_bom = dir.path().join("bom.csv");
    std::fs::write(&with_bom, bom).unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    ok(&["score", arg(&w), "--reports", arg(&r), "--out", arg(&a)]);
    ok(&[
        "score",
        arg(&w),
        "--reports",
        arg(&with_bom),
        "--out",
        arg(&b),
    ]);
    let (a, b) = (json(&a.join("score.json")), json(&b.join("score.json")));
    assert_eq!(a["score"], 6);
    assert_eq!(a["outcomes"], b["outcomes"]);
    assert_eq!(a["artifacts"], b["artifacts"]);
}

/// Item 20: an input that never ends (`/dev/zero`, behind any name) is refused at once, not
/// read until memory runs out; a map, reports, a pipeline and an occupancy grid alike.
#[test]
fn a_stream_without_end_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let w = world(dir.path(), "w");
    let zero = |name: &str| {
        let p = dir.path().join(name);
        std::os::unix::fs::symlink("/dev/zero", &p).unwrap();
        p
    };
    let (map, csv, toml, npy) = (
        zero("zero.ply"),
        zero("zero.csv"),
        zero("zero.toml"),
        zero("zero.npy"),
    );
    let out = dir.path().join("out");
    for args in [
        vec!["score", arg(&w), "--reports", arg(&csv), "--out", arg(&out)],
        vec!["generate", arg(&toml), "--out", arg(&out)],
        vec![
            "generate",
            "--preset",
            "cave",
            "--occupancy",
            arg(&npy),
            "--out",
            arg(&out),
        ],
    ] {
        let o = subtgraph_within(&args, HANG);
        refused(&o, &["device"]);
    }
    let good = dir.path().join("r.csv");
    std::fs::write(&good, "time,class,x,y,z\n").unwrap();
    let o = subtgraph_within(
        &[
            "score",
            arg(&w),
            "--reports",
            arg(&good),
            "--map",
            arg(&map),
            "--out",
            arg(&out),
        ],
        HANG,
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(!out.exists());
}
