//! The mine's services (issue 24 item 1): rock bolts, a ventilation duct, pipes, a cable run
//! and lights, placed along the drifts and instanced. An independent reader
//! (tests/readers/services_check.py: trimesh over the OBJ and GLB, usd-core over the USD)
//! finds the same copies of each part in the three formats, each part's mesh stored once in
//! the GLB and the USD, the bolt plates on the rock, the duct under the back and above a
//! robot, and the labels; SDF, URDF and MJCF carry them as visual geometry only (libsdformat,
//! MuJoCo and PyBullet against services.obj: tests/readers/services_formats_check.py); the
//! services leave the rock's own files as they were; the same bytes on 1 and 3 threads; bad
//! keys refused with what to change.

use crate::common::{self, arg, generate_formats as generate, small_mine};

#[test]
fn services_are_instanced_on_the_rock_and_labelled() {
    let dir = tempfile::tempdir().unwrap();
    let w = dir.path().join("world");
    generate(
        &small_mine(dir.path(), "on", ""),
        &w,
        "obj,gltf,usd,ground-truth",
    );
    let Some(out) = common::read_with_python(
        &["trimesh", "numpy", "scipy", "pxr"],
        "services_check.py",
        &[arg(&w), "--sample", "100"],
    ) else {
        return;
    };
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    // The reader found the same copies in OBJ, GLB and USD; each part's mesh is stored once.
    assert_eq!(v["prototypes"], 5, "{v}");
    assert_eq!(v["glb_meshes"], 5, "{v}");
    let n = |k: &str| v["instances"][k].as_u64().unwrap();
    // About 125 tiles of 20 m: a bolt ring every 1.2 m, a light every 20 m.
    assert!(n("rock-bolt") > 5_000, "{v}");
    assert!(n("light") > 50, "{v}");
    assert_eq!(n("pipe"), 2 * n("cable"), "two pipes and a cable run: {v}");
    assert!(n("duct") > n("cable"), "the duct's couplings: {v}");
    assert!(
        v["bolt_rock_distance_max_m"].as_f64().unwrap() <= 0.05,
        "{v}"
    );
    assert!(
        v["duct_floor_clearance_min_m"].as_f64().unwrap() >= 1.7,
        "{v}"
    );
    assert!(v["duct_back_gap_min_m"].as_f64().unwrap() > 0.0, "{v}");
    // Instances, not copies: the USD and the GLB stay far smaller than the baked OBJ.
    let size = |f: &str| std::fs::metadata(w.join(f)).unwrap().len();
    assert!(
        size("usd/parts/services.usda") * 2 < size("mesh/services.obj"),
        "USD {} vs OBJ {}",
        size("usd/parts/services.usda"),
        size("mesh/services.obj")
    );
}

#[test]
fn services_leave_the_rock_as_it_was_and_off_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let (on, off) = on_and_off(dir.path(), "obj,gltf,usd,ground-truth");
    // The rock's meshes and every ground truth file but the labels are the same bytes.
    for f in [
        "mesh/world.obj",
        "mesh/collision.obj",
        "ground_truth/graph.json",
        "ground_truth/free_space.npy",
        "usd/parts/level-0.usda",
    ] {
        if !on.join(f).exists() {
            continue;
        }
        assert!(
            std::fs::read(on.join(f)).unwrap() == std::fs::read(off.join(f)).unwrap(),
            "{f} changed with the services"
        );
    }
    for f in ["mesh/services.obj", "usd/parts/services.usda"] {
        assert!(on.join(f).is_file(), "{f}");
        assert!(!off.join(f).exists(), "{f} with services = false");
    }
    let labels = std::fs::read_to_string(off.join("ground_truth/semantic_labels.json")).unwrap();
    assert!(!labels.contains("rock-bolt"), "no services, no labels");
    let mtl = std::fs::read_to_string(off.join("mesh/world.mtl")).unwrap();
    assert!(!mtl.contains("mine-bolt"), "no services, no materials");
    // Each kind off by its own key: no bolts, the rest kept.
    let no_bolts = dir.path().join("no-bolts");
    generate(
        &small_mine(dir.path(), "no-bolts", "bolt_spacing = 0"),
        &no_bolts,
        "usd",
    );
    let usd = std::fs::read_to_string(no_bolts.join("usd/parts/services.usda")).unwrap();
    assert!(
        !usd.contains("rock_bolt") && usd.contains("duct"),
        "bolts off"
    );
}

#[test]
fn services_are_the_same_on_one_and_three_threads() {
    let dir = tempfile::tempdir().unwrap();
    common::assert_same_on_one_and_three_threads(
        dir.path(),
        &small_mine(dir.path(), "threads", ""),
        "obj,gltf,usd,sdf,urdf,mjcf",
    );
}

#[test]
fn bad_service_keys_say_what_to_change() {
    let dir = tempfile::tempdir().unwrap();
    for (extra, says) in [
        ("bolt_spacing = -1", "bolt_spacing"),
        ("bolt_spacing = 0.1", "from 0.5 to 5 metres"),
        ("duct_diameter = 4", "duct_diameter"),
        ("pipes = 9", "from 0 to 4 pipes"),
        ("light_spacing = 1", "light_spacing"),
    ] {
        let err = common::fails(&["validate", arg(&small_mine(dir.path(), "bad", extra))]);
        assert!(err.contains(says), "{extra}: {err}");
    }
    let cave = common::small_cave_pipeline(dir.path(), 1, "");
    let text = std::fs::read_to_string(&cave)
        .unwrap()
        .replace("type = \"cave\"", "type = \"cave\"\nbolt_spacing = 1.2");
    std::fs::write(&cave, text).unwrap();
    let err = common::fails(&["validate", arg(&cave)]);
    assert!(err.contains("has no services"), "{err}");
}

/// SDF, URDF and MJCF carry the services as visual geometry only (they are mounted above a
/// robot), each format standing alone: `--format sdf,urdf,mjcf` without the OBJ. Read by
/// libsdformat (tests/readers/sdf_check.cc), MuJoCo and PyBullet
/// (tests/readers/services_formats_check.py), each against services.obj read apart.
#[test]
fn services_are_visual_only_in_sdf_urdf_and_mjcf() {
    let dir = tempfile::tempdir().unwrap();
    let w = dir.path().join("world");
    generate(&small_mine(dir.path(), "on", ""), &w, "sdf,urdf,mjcf");
    assert!(!w.join("mesh/world.obj").exists(), "no OBJ asked for");
    for f in ["mesh/services.obj", "mesh/world.mtl"] {
        assert!(w.join(f).is_file(), "{f}: the SDF names it");
    }
    if let Some(checker) = crate::export_scenes::sdf_checker(dir.path()) {
        let report = crate::export_scenes::check_sdf(&checker, &w.join("gazebo/world.sdf"));
        let services = w.join("mesh/services.obj").canonicalize().unwrap();
        let visual = format!("visual {}", services.display());
        assert!(report.contains(&visual), "{visual} in {report:?}");
        assert_eq!(crate::export_scenes::count(&report, "missing"), 0);
        // One more visual than collisions (the services' model), and none of its collisions.
        let count = |k| crate::export_scenes::count(&report, k);
        assert_eq!(count("visuals"), count("collisions") + 1, "{report:?}");
        assert!(
            !report
                .iter()
                .any(|l| l.starts_with("collision ") && l.contains("services"))
        );
        assert!(
            !report.iter().any(|l| l.ends_with(" subt-services")),
            "{report:?}"
        );
    }
    let Some(out) = common::read_with_python(
        &["mujoco", "pybullet", "trimesh", "numpy"],
        "services_formats_check.py",
        &[arg(&w), "--mujoco", "--pybullet"],
    ) else {
        return;
    };
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    let obj = &v["services_obj_faces"];
    assert_eq!(obj.as_object().unwrap().len(), 5, "five materials: {v}");
    assert_eq!(v["mujoco_faces"], *obj, "{v}");
    assert_eq!(v["pybullet_faces"], *obj, "{v}");
}

/// Off, SDF, URDF and MJCF name no services and write no file for them; the rock's files are
/// the same bytes with them on or off, and MJCF's `visual = "none"` leaves them out.
#[test]
fn services_off_leave_sdf_urdf_and_mjcf_without_them() {
    let dir = tempfile::tempdir().unwrap();
    let (on, off) = on_and_off(dir.path(), "sdf,urdf,mjcf");
    for f in ["gazebo/world.sdf", "urdf/world.urdf", "mujoco/level-0.xml"] {
        let text = std::fs::read_to_string(off.join(f)).unwrap();
        assert!(!text.contains("services"), "{f} names services when off");
        let text = std::fs::read_to_string(on.join(f)).unwrap();
        assert!(text.contains("services"), "{f} names no services when on");
    }
    for f in ["mesh/services.obj", "mesh/services", "mesh/world.mtl"] {
        assert!(!off.join(f).exists(), "{f} with services = false");
    }
    let msh = |w: &std::path::Path| {
        std::fs::read_dir(w.join("mujoco/meshes"))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.contains("services"))
            .count()
    };
    assert_eq!(msh(&off), 0);
    assert!(msh(&on) >= 5, "a mesh per material at least");
    for f in [
        "mesh/parts/level/level-0.obj",
        "mesh/parts/level/level-0-collision.obj",
        "mujoco/meshes/level-0-0.msh",
        "mujoco/world.xml",
    ] {
        assert!(
            std::fs::read(on.join(f)).unwrap() == std::fs::read(off.join(f)).unwrap(),
            "{f} changed with the services"
        );
    }
    let none = dir.path().join("none");
    let pipeline = small_mine(dir.path(), "none", "");
    let text = std::fs::read_to_string(&pipeline).unwrap()
        + "\n[[export]]\ntype = \"mjcf\"\nvisual = \"none\"\n";
    std::fs::write(&pipeline, text).unwrap();
    common::ok(&["generate", arg(&pipeline), "--out", arg(&none)]);
    let part = std::fs::read_to_string(none.join("mujoco/level-0.xml")).unwrap();
    assert!(!part.contains("services"), "visual = \"none\": no services");
}

/// The small mine written in `formats` with its services (`on`) and without (`off`), in
/// folders of those names under `dir`.
fn on_and_off(dir: &std::path::Path, formats: &str) -> (std::path::PathBuf, std::path::PathBuf) {
    let (on, off) = (dir.join("on"), dir.join("off"));
    generate(&small_mine(dir, "on", ""), &on, formats);
    generate(&small_mine(dir, "off", "services = false"), &off, formats);
    (on, off)
}
