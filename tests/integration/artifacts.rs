//! Artifacts (`[artifacts]`): placed by their rules on the collision surface over many seeds,
//! the same on every run and thread count, in every simulator format where the programs that
//! read them find them (MuJoCo, PyBullet, usd-core, trimesh, libsdformat), and at rest where
//! the ground truth says after a drop. The checks are `tests/readers/artifacts_check.py`.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{arg, fails, folder_bytes, ok, python_with, read_with_python, small_cave_pipeline};

const MODULES: [&str; 2] = ["numpy", "trimesh"];

fn artifacts_section(count: u32) -> String {
    format!("[artifacts]\ncount = {count}\nmin_distance_from_start = 30\nmin_spacing = 6\n")
}

/// A small cave (2 levels) with artifacts, through the command line.
fn world(dir: &Path, seed: u32, count: u32, formats: &str) -> PathBuf {
    let pipeline = small_cave_pipeline(dir, 2, &artifacts_section(count));
    let text = std::fs::read_to_string(&pipeline)
        .unwrap()
        .replace("seed = 5", &format!("seed = {seed}"));
    std::fs::write(&pipeline, text).unwrap();
    let out = dir.join(format!("world-{seed}"));
    let mut args = vec!["generate", arg(&pipeline), "--out", arg(&out), "--force"];
    if !formats.is_empty() {
        args.extend(["--format", formats]);
    }
    ok(&args);
    out
}

fn check(world: &Path, mode: &str, modules: &[&str]) -> Option<String> {
    let out = read_with_python(modules, "artifacts_check.py", &[arg(world), mode])?;
    eprint!("{out}");
    Some(out)
}

#[test]
fn artifacts_stand_on_the_floor_by_their_rules_over_many_seeds() {
    let dir = tempfile::tempdir().unwrap();
    for seed in 1..=8 {
        let w = world(dir.path(), seed, 12, "");
        let doc: serde_json::Value =
            serde_json::from_slice(&std::fs::read(w.join("ground_truth/artifacts.json")).unwrap())
                .unwrap();
        assert_eq!(doc["count"], 12);
        let rules: std::collections::BTreeSet<&str> = doc["artifacts"]
            .as_array()
            .unwrap()
            .iter()
            .map(|a| a["placement"].as_str().unwrap())
            .collect();
        assert!(rules.len() >= 2, "seed {seed}: rules drawn {rules:?}");
        if check(&w, "placement", &MODULES).is_none() {
            return;
        }
    }
}

#[test]
fn a_recorded_pose_inside_the_rock_is_caught() {
    // The negative control of the placement check: the same world with one artifact moved
    // 0.3 m down into the floor, or 0.3 m up off it, must fail.
    let Some(python) = python_with(&MODULES) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let w = world(dir.path(), 3, 6, "");
    let path = w.join("ground_truth/artifacts.json");
    let good = std::fs::read_to_string(&path).unwrap();
    for dz in [-0.3, 0.3] {
        let mut doc: serde_json::Value = serde_json::from_str(&good).unwrap();
        let z = doc["artifacts"][2]["position"][2].as_f64().unwrap();
        doc["artifacts"][2]["position"][2] = (z + dz).into();
        std::fs::write(&path, serde_json::to_string(&doc).unwrap()).unwrap();
        let out = Command::new(&python)
            .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/readers/artifacts_check.py"))
            .args([arg(&w), "placement"])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "moved by {dz} m and still passed");
        assert!(
            err.contains("inside the rock") || err.contains("floats"),
            "{err}"
        );
    }
}

#[test]
fn the_same_artifacts_on_every_run_and_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let pipeline = small_cave_pipeline(dir.path(), 2, &artifacts_section(10));
    common::assert_same_on_one_and_three_threads(
        dir.path(),
        &pipeline,
        "mjcf,sdf,usd,urdf,gltf,ground-truth",
    );
}

#[test]
fn artifacts_draw_from_their_own_stream() {
    // A world with [artifacts] has exactly the grids and meshes of the same world without:
    // only world.toml, the artifact ground truth and the files that hold artifacts differ.
    let dir = tempfile::tempdir().unwrap();
    let with = small_cave_pipeline(dir.path(), 2, &artifacts_section(8));
    let a = dir.path().join("with");
    ok(&["generate", arg(&with), "--out", arg(&a)]);
    let without = small_cave_pipeline(dir.path(), 2, "");
    let b = dir.path().join("without");
    ok(&["generate", arg(&without), "--out", arg(&b)]);
    let names = |d: &Path| {
        folder_bytes(d)
            .into_iter()
            .filter(|(n, _)| !n.starts_with("ground_truth/artifacts"))
            .collect::<Vec<_>>()
    };
    let (fa, fb) = (names(&a), names(&b));
    let differ: Vec<&str> = fa
        .iter()
        .zip(&fb)
        .filter(|(x, y)| x.0 != y.0 || x.1 != y.1)
        .map(|(x, _)| x.0.as_str())
        .collect();
    assert_eq!(fa.len(), fb.len());
    assert_eq!(differ, [".subtgraph-files", "world.toml"]);
    assert!(a.join("ground_truth/artifacts.csv").is_file());
    // The drawn count is written fixed, and world.toml makes the same artifacts again.
    let toml = std::fs::read_to_string(a.join("world.toml")).unwrap();
    assert!(toml.contains("[artifacts]\n"), "{toml}");
    let again = dir.path().join("again");
    ok(&["generate", arg(&a.join("world.toml")), "--out", arg(&again)]);
    assert_eq!(
        std::fs::read(a.join("ground_truth/artifacts.json")).unwrap(),
        std::fs::read(again.join("ground_truth/artifacts.json")).unwrap()
    );
}

#[test]
fn every_simulator_format_has_the_artifacts_and_they_rest_where_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let w = world(dir.path(), 4, 12, "mjcf,urdf,sdf,usd,gltf,obj,ground-truth");
    check(&w, "placement", &MODULES);
    check(&w, "mujoco", &["numpy", "mujoco"]);
    check(&w, "pybullet", &["numpy", "pybullet"]);
    check(&w, "usd", &["numpy", "pxr"]);
    check(&w, "gltf", &MODULES);
    // libsdformat: the world loads with zero errors and has a movable model per artifact.
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
        return;
    };
    let exe = dir.path().join("sdf_check");
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/readers/sdf_check.cc");
    let flags = String::from_utf8(flags.stdout).unwrap();
    let built = Command::new("g++")
        .args(["-std=c++17", "-O0", "-o", arg(&exe), arg(&source)])
        .args(flags.split_whitespace())
        .output()
        .unwrap();
    assert!(built.status.success(), "{built:?}");
    let out = Command::new(&exe)
        .arg(w.join("gazebo/world.sdf"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let text = String::from_utf8(out.stdout).unwrap();
    let dynamic: Vec<&str> = text
        .lines()
        .filter_map(|l| l.strip_prefix("dynamic-model artifact-"))
        .collect();
    assert_eq!(dynamic.len(), 12, "{text}");
}

#[test]
fn bad_artifact_sections_are_refused_saying_what_to_change() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "[artifacts]\nclasses = [\"survivor\", \"phone\"]\n",
            "artifacts.classes",
            "cell-phone",
        ),
        (
            "[artifacts]\nclasses = [\"rope\", \"rope\"]\n",
            "artifacts.classes",
            "twice",
        ),
        (
            "[artifacts]\nplacement = []\n",
            "artifacts.placement",
            "dead-end",
        ),
        ("[artifacts]\ncount = 5000\n", "artifacts.count", "at most"),
        (
            "[artifacts]\nmin_spacing = -1\n",
            "artifacts.min_spacing",
            "metres",
        ),
        (
            "[artifacts]\ncolour = 1\n",
            "artifacts.colour",
            "unknown field",
        ),
    ];
    for (section, key, hint) in cases {
        let p = small_cave_pipeline(dir.path(), 1, section);
        let err = fails(&["validate", arg(&p)]);
        assert!(err.contains(key) && err.contains(hint), "{section}: {err}");
    }
    // More than fit: refused after layout, with the knobs to turn.
    let p = small_cave_pipeline(
        dir.path(),
        1,
        "[artifacts]\ncount = 300\nmin_spacing = 40\n",
    );
    let err = fails(&["generate", arg(&p), "--out", arg(&dir.path().join("x"))]);
    assert!(err.contains("lower artifacts.count"), "{err}");
    assert!(!dir.path().join("x").exists());
}

/// On the DARPA tiles (`examples/darpa-cave.toml` with `[artifacts]`, tiles from `../shared`):
/// every artifact placed, each dropped from 0.5 m in MuJoCo comes to rest at its recorded pose,
/// and each `visible_from_axis` flag is what the collision mesh says (an exact segment-triangle
/// test). `placement`'s own check is not used: its ray parity needs a closed collision surface,
/// and the DARPA tiles' collision copy overlaps itself at the seams.
#[test]
fn artifacts_on_the_darpa_tiles_rest_where_the_ground_truth_says() {
    let Some(_) = common::darpa_tiles() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("examples/darpa-cave.toml")).unwrap();
    let from = "manifest = \"../tilesets/manifests/darpa-cave-type-b.toml\"";
    assert!(text.contains(from), "examples/darpa-cave.toml has {from}");
    let manifest = root.join("tilesets/manifests/darpa-cave-type-b.toml");
    let pipeline = dir.path().join("darpa-artifacts.toml");
    std::fs::write(
        &pipeline,
        text.replacen(
            from,
            &format!("manifest = {:?}", manifest.display().to_string()),
            1,
        ) + "\n"
            + &artifacts_section(12),
    )
    .unwrap();
    let w = dir.path().join("w");
    ok(&[
        "generate",
        arg(&pipeline),
        "--format",
        "obj,mjcf,ground-truth",
        "--out",
        arg(&w),
    ]);
    let doc: serde_json::Value =
        serde_json::from_slice(&std::fs::read(w.join("ground_truth/artifacts.json")).unwrap())
            .unwrap();
    assert_eq!(doc["artifacts"].as_array().unwrap().len(), 12, "{doc}");
    let Some(out) = check(&w, "mujoco", &["numpy", "mujoco"]) else {
        return;
    };
    assert!(out.contains("12 free bodies"), "{out}");
    let out = read_with_python(&MODULES, "visibility_check.py", &[arg(&w)]).unwrap();
    eprint!("{out}");
    assert!(out.contains(" 0 not judged"), "{out}");
}

/// The footprint of an artifact (its box in the plane, turned by its yaw) and its height
/// range, from `artifacts.json`.
fn footprint(a: &serde_json::Value) -> ([[f64; 2]; 4], [f64; 2]) {
    let p: Vec<f64> = a["position"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let s: Vec<f64> = a["size"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let (sin, cos) = a["yaw"].as_f64().unwrap().sin_cos();
    let corner = |u: f64, v: f64| {
        let (lx, ly) = (0.5 * u * s[0], 0.5 * v * s[1]);
        [p[0] + cos * lx - sin * ly, p[1] + sin * lx + cos * ly]
    };
    (
        [
            corner(-1.0, -1.0),
            corner(1.0, -1.0),
            corner(1.0, 1.0),
            corner(-1.0, 1.0),
        ],
        [p[2], p[2] + s[2]],
    )
}

/// Whether two convex quadrilaterals (corners counter-clockwise) overlap: a corner of one
/// strictly inside the other, or two edges crossing.
fn quads_overlap(a: &[[f64; 2]; 4], b: &[[f64; 2]; 4]) -> bool {
    let cross = |o: [f64; 2], p: [f64; 2], q: [f64; 2]| {
        (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0])
    };
    let inside =
        |p: [f64; 2], q: &[[f64; 2]; 4]| (0..4).all(|i| cross(q[i], q[(i + 1) % 4], p) > 1e-9);
    let crossing = |p: [f64; 2], q: [f64; 2], r: [f64; 2], s: [f64; 2]| {
        cross(p, q, r) * cross(p, q, s) < 0.0 && cross(r, s, p) * cross(r, s, q) < 0.0
    };
    a.iter().any(|&p| inside(p, b))
        || b.iter().any(|&p| inside(p, a))
        || (0..4).any(|i| (0..4).any(|j| crossing(a[i], a[(i + 1) % 4], b[j], b[(j + 1) % 4])))
}

/// Issue 21 item 12: `[artifacts] min_spacing = 0` let artifact boxes interpenetrate (2 pairs
/// among 40 dead-end artifacts of the cave preset, seed 1; 79 pairs among 1000). Artifacts
/// never overlap, whatever the spacing asked: checked on the boxes the ground truth records,
/// by a test of its own (corners and edges, not the placement's separating axes).
#[test]
fn artifacts_never_overlap_even_without_spacing() {
    let dir = tempfile::tempdir().unwrap();
    let preset =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/cave.toml"))
            .unwrap();
    for (name, section, seed) in [
        (
            "dead-ends",
            "count = 40\nplacement = [\"dead-end\"]\nmin_spacing = 0\nmin_distance_from_start = 0",
            "1",
        ),
        (
            "many",
            "count = 1000\nmin_spacing = 0\nmin_distance_from_start = 0",
            "1",
        ),
    ] {
        let pipeline = dir.path().join(format!("{name}.toml"));
        std::fs::write(&pipeline, format!("{preset}\n[artifacts]\n{section}\n")).unwrap();
        let out = dir.path().join(name);
        ok(&[
            "generate",
            arg(&pipeline),
            "--seed",
            seed,
            "--out",
            arg(&out),
        ]);
        let doc: serde_json::Value = serde_json::from_slice(
            &std::fs::read(out.join("ground_truth/artifacts.json")).unwrap(),
        )
        .unwrap();
        let boxes: Vec<_> = doc["artifacts"]
            .as_array()
            .unwrap()
            .iter()
            .map(footprint)
            .collect();
        let mut pairs = Vec::new();
        for (i, (a, za)) in boxes.iter().enumerate() {
            for (j, (b, zb)) in boxes.iter().enumerate().take(i) {
                if za[0] < zb[1] && zb[0] < za[1] && quads_overlap(a, b) {
                    pairs.push((j, i));
                }
            }
        }
        assert!(
            pairs.is_empty(),
            "{name}: {} of {} artifacts overlap: {pairs:?}",
            pairs.len(),
            boxes.len()
        );
        eprintln!("{name}: {} artifacts, none overlapping", boxes.len());
    }
}
