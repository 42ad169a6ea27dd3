//! The physics exporters, checked by the simulators themselves: MuJoCo loads `mujoco/world.xml`
//! and PyBullet `urdf/world.urdf` (from another working directory), a ball dropped in a
//! corridor rests on its floor, and the naive exports (one convex mesh) are shown to fail the
//! same checks. Plus determinism across thread counts and errors naming bad keys.

use crate::common;

use std::path::Path;
use std::process::Command;

use common::{arg, fails, folder_bytes, ok, read_with_python, small_cave_pipeline};

/// MuJoCo and PyBullet, and the OBJ the naive exports are made from.
const BOTH: &str =
    "[[export]]\ntype = \"mjcf\"\n\n[[export]]\ntype = \"urdf\"\n\n[[export]]\ntype = \"obj\"\n";

/// A `[tileset]` key for `small_cave_pipeline`'s `extra`: level floors, for the resting drops.
const FLAT: &str = "grade = [0, 0]\n";

/// The small two-level cave (its collision lattice holds the 5 m tunnels open: see
/// `small_cave_pipeline`), made through the command line.
///
/// Flat floors (`grade = [0, 0]`): a ball comes to rest only where the floor is level (on a
/// sloping floor it rolls; `drive.rs` drives a ball along the route on sloping floors).
fn physics_world(dir: &Path) -> std::path::PathBuf {
    let path = small_cave_pipeline(dir, 2, &format!("{FLAT}{BOTH}"));
    let out = dir.join("world");
    ok(&["generate", arg(&path), "--out", arg(&out)]);
    out
}

#[test]
fn a_ball_rests_on_a_corridor_floor_in_mujoco_and_pybullet() {
    let tmp = tempfile::tempdir().unwrap();
    let world = physics_world(tmp.path());
    for f in [
        "mujoco/world.xml",
        "mujoco/level-0.xml",
        "mujoco/level-1.xml",
        "urdf/world.urdf",
    ] {
        assert!(world.join(f).is_file(), "{f} written");
    }
    let xml = std::fs::read_to_string(world.join("mujoco/world.xml")).unwrap();
    assert!(xml.contains("<include file=\"level-1.xml\"/>"), "{xml}");
    // The default collision: a floor and a roof height field per tile, no convex slab.
    let part = std::fs::read_to_string(world.join("mujoco/level-0.xml")).unwrap();
    assert!(part.contains("type=\"hfield\"") && !part.contains("-rock-"));
    // The visual mesh, in pieces MuJoCo compiles in parallel.
    assert!(part.contains("mesh=\"level-0-visual-0\""), "visual geom");
    assert!(world.join("mujoco/meshes/level-0-0.msh").is_file());
    if let Some(out) = read_with_python(&["mujoco", "numpy"], "mujoco_check.py", &[arg(&world)]) {
        assert!(out.contains("OK"), "{out}");
    }
    if let Some(out) = read_with_python(&["pybullet"], "pybullet_check.py", &[arg(&world)]) {
        assert!(out.contains("OK"), "{out}");
    }
}

/// The older collision export, convex slabs in the rock, still holds the ball too.
#[test]
fn a_ball_rests_on_convex_slabs_in_mujoco() {
    let tmp = tempfile::tempdir().unwrap();
    let path = small_cave_pipeline(
        tmp.path(),
        1,
        &format!("{FLAT}[[export]]\ntype = \"mjcf\"\ncollision = \"slabs\"\n"),
    );
    let out = tmp.path().join("world");
    ok(&["generate", arg(&path), "--out", arg(&out)]);
    let part = std::fs::read_to_string(out.join("mujoco/level-0.xml")).unwrap();
    assert!(part.contains("-rock-") && !part.contains("hfield"), "slabs");
    if let Some(out) = read_with_python(&["mujoco", "numpy"], "mujoco_check.py", &[arg(&out)]) {
        assert!(out.contains("OK"), "{out}");
    }
}

/// `visual = "none"` leaves the visual meshes out (MuJoCo's load is mostly their bounding
/// volume hierarchies) and the ball still rests on the height fields.
#[test]
fn a_ball_rests_in_mujoco_without_visual_meshes() {
    let tmp = tempfile::tempdir().unwrap();
    let path = small_cave_pipeline(
        tmp.path(),
        1,
        &format!("{FLAT}[[export]]\ntype = \"mjcf\"\nvisual = \"none\"\n"),
    );
    let out = tmp.path().join("world");
    ok(&["generate", arg(&path), "--out", arg(&out)]);
    let part = std::fs::read_to_string(out.join("mujoco/level-0.xml")).unwrap();
    assert!(
        part.contains("type=\"hfield\"") && !part.contains("-visual"),
        "{part}"
    );
    assert!(!out.join("mujoco/meshes").exists(), "no .msh written");
    if let Some(out) = read_with_python(&["mujoco", "numpy"], "mujoco_check.py", &[arg(&out)]) {
        assert!(out.contains("OK"), "{out}");
    }
}

/// The checks can fail: the same drops against the naive exports (the whole collision surface
/// as one MuJoCo mesh geom; the URDF without `concave="yes"`) find the passage filled.
#[test]
fn naive_convex_exports_fail_the_same_drop() {
    let tmp = tempfile::tempdir().unwrap();
    let world = physics_world(tmp.path());
    let python = std::env::var("SUBTGRAPH_PYTHON").unwrap_or_else(|_| "python3".into());
    for (modules, script, flag) in [
        (&["mujoco", "numpy"][..], "mujoco_check.py", "--one-mesh"),
        (&["pybullet"][..], "pybullet_check.py", "--convex"),
    ] {
        if common::python_with(modules).is_none() {
            continue;
        }
        let out = Command::new(&python)
            .arg(
                Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("tests/readers")
                    .join(script),
            )
            .args([arg(&world), flag])
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && text.contains("FAIL"),
            "{script} {flag} should fail:\n{}\n{text}",
            String::from_utf8_lossy(&out.stdout)
        );
    }
}

#[test]
fn physics_files_are_identical_on_one_and_three_threads() {
    let tmp = tempfile::tempdir().unwrap();
    let pipeline = small_cave_pipeline(tmp.path(), 2, BOTH);
    let mut folders = Vec::new();
    for threads in ["1", "3"] {
        let out = tmp.path().join(format!("world-{threads}"));
        let run = Command::new(env!("CARGO_BIN_EXE_subtgraph"))
            .args(["generate", arg(&pipeline), "--out", arg(&out)])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let files: Vec<_> = folder_bytes(&out)
            .into_iter()
            .filter(|(p, _)| {
                p.starts_with("mujoco") || p.starts_with("urdf") || p.starts_with("mesh")
            })
            .collect();
        assert!(files.iter().any(|(p, _)| p == "mujoco/level-0.xml"));
        folders.push(files);
    }
    assert!(folders[0] == folders[1], "thread count changed the files");
}

#[test]
fn bad_physics_settings_name_the_key() {
    let tmp = tempfile::tempdir().unwrap();
    for (table, key, hint) in [
        (
            "type = \"mjcf\"\nthicknes = 0.5",
            "export[0].thicknes",
            "thickness",
        ),
        (
            "type = \"mjcf\"\ntolerance = -0.1",
            "export[0].tolerance",
            "tolerance = 0.1",
        ),
        (
            "type = \"mjcf\"\ncollision = \"boxes\"",
            "export[0].collision",
            "heightfields",
        ),
        ("type = \"mjcf\"\nstep = 0", "export[0].step", "step = 0.5"),
        (
            "type = \"mjcf\"\nvisual = \"rough\"",
            "export[0].visual",
            "\"none\"",
        ),
        (
            "type = \"mjcf\"\nthickness = \"deep\"",
            "export[0].thickness",
            "thickness = 0.5",
        ),
        (
            "type = \"urdf\"\nconcave = true",
            "export[0].concave",
            "split",
        ),
    ] {
        let pipeline = small_cave_pipeline(tmp.path(), 1, &format!("[[export]]\n{table}\n"));
        let out = tmp.path().join("never");
        let err = fails(&["generate", arg(&pipeline), "--out", arg(&out)]);
        assert!(err.contains(key) && err.contains(hint), "{table}: {err}");
        assert!(!out.exists());
    }
}
