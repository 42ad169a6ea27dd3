//! The ground-truth exporters through the command line, checked by the readers their users
//! have (numpy, PIL, yaml, networkx, csv, json) against the grid and against an independent
//! ray parity on the collision surface: `tests/readers/ground_truth_check.py`.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{arg, fails, folder_bytes, ok, read_with_python, small_cave_pipeline};

const READERS: &[&str] = &["numpy", "PIL", "yaml", "networkx", "trimesh"];

/// The small two-level cave.
fn pipeline(dir: &Path, extra: &str) -> PathBuf {
    small_cave_pipeline(dir, 2, extra)
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("subtgraph-gt-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn ground_truth_agrees_with_the_grid_and_the_collision_surface() {
    let dir = temp("mesh");
    let p = pipeline(&dir, "[[export]]\ntype = \"ground-truth\"\n");
    let out = dir.join("world");
    ok(&["generate", arg(&p), "--out", arg(&out)]);
    for f in [
        "graph.json",
        "graph.graphml",
        "maps/level-0.pgm",
        "maps/level-1.yaml",
        "free_space.npy",
        "free_space.json",
        "semantic_labels.json",
        "semantic_labels.csv",
        "spawn_poses.json",
    ] {
        assert!(out.join("ground_truth").join(f).is_file(), "{f}");
    }
    let meta = std::fs::read_to_string(out.join("ground_truth/free_space.json")).unwrap();
    assert!(meta.contains("\"source\": \"collision-mesh\""), "{meta}");
    if let Some(said) = read_with_python(READERS, "ground_truth_check.py", &[arg(&out), "mesh"]) {
        eprintln!("{said}");
        assert!(said.contains("spawn poses: 4 robots"), "{said}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn without_a_mesh_ground_truth_falls_back_to_the_grid_and_says_so() {
    let dir = temp("grid");
    let p = pipeline(&dir, "");
    let out = dir.join("world");
    ok(&[
        "generate",
        arg(&p),
        "--no-mesh",
        "--format",
        "ground-truth",
        "--out",
        arg(&out),
    ]);
    assert!(!out.join("mesh").exists());
    for f in ["free_space.json", "spawn_poses.json"] {
        let text = std::fs::read_to_string(out.join("ground_truth").join(f)).unwrap();
        assert!(text.contains("\"source\": \"grid\""), "{f}: {text}");
    }
    let yaml = std::fs::read_to_string(out.join("ground_truth/maps/level-1.yaml")).unwrap();
    assert!(yaml.contains("computed from: grid"), "{yaml}");
    if let Some(said) = read_with_python(READERS, "ground_truth_check.py", &[arg(&out), "grid"]) {
        assert!(
            said.contains("agrees with every voxel against the cells"),
            "{said}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_ground_truth_keys_are_refused_naming_the_key() {
    let dir = temp("bad");
    let cases = [
        (
            "ground-truth",
            "resolutin = 0.5",
            "export[0].resolutin",
            "this component takes: resolution, height, voxel",
        ),
        (
            "ros-map",
            "resolution = 0",
            "export[0].resolution",
            "positive number of metres per pixel, e.g. resolution = 0.25",
        ),
        (
            "ros-map",
            "voxel = 1.0",
            "export[0].voxel",
            "this component takes: resolution, height",
        ),
        (
            "free-space",
            "voxel = -0.5",
            "export[0].voxel",
            "e.g. voxel = 0.5",
        ),
        (
            "spawn-poses",
            "robots = 0",
            "export[0].robots",
            "e.g. robots = 4",
        ),
        (
            "spawn-poses",
            "clearance = \"wide\"",
            "export[0].clearance",
            "invalid type",
        ),
        (
            "graph",
            "height = 1.0",
            "export[0].height",
            "this component takes no parameters",
        ),
    ];
    for (kind, line, key, says) in cases {
        let p = pipeline(&dir, &format!("[[export]]\ntype = \"{kind}\"\n{line}\n"));
        let err = fails(&["generate", arg(&p), "--out", arg(&dir.join("never"))]);
        assert!(err.contains(key), "{kind} {line}: {err}");
        assert!(err.contains(says), "{kind} {line}: {err}");
        assert!(!dir.join("never").exists());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn ground_truth_is_byte_identical_on_one_and_three_threads() {
    let dir = temp("threads");
    let p = pipeline(&dir, "[[export]]\ntype = \"ground-truth\"\n");
    let run = |threads: &str| {
        let out = dir.join(format!("world-{threads}"));
        let status = Command::new(env!("CARGO_BIN_EXE_subtgraph"))
            .args(["generate", arg(&p), "--out", arg(&out)])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(
            status.status.success(),
            "{}",
            String::from_utf8_lossy(&status.stderr)
        );
        folder_bytes(&out.join("ground_truth"))
    };
    let (one, three) = (run("1"), run("3"));
    assert_eq!(
        one.len(),
        11,
        "{:?}",
        one.iter().map(|f| &f.0).collect::<Vec<_>>()
    );
    for ((a, x), (b, y)) in one.iter().zip(&three) {
        assert_eq!(a, b);
        assert!(x == y, "{a} differs between 1 and 3 threads");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
