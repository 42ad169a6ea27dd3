//! The scene exporters (Gazebo SDF, USD, glTF binary), each checked by the program that reads
//! it: libsdformat (what gz-sim parses worlds with), usd-core (Isaac Sim's USD) and trimesh
//! (what the OBJ and GLB look like to a mesh library). A missing reader skips its test with a
//! message, unless `scripts/test` asked for every reader.

mod common;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

use common::{arg, fails, folder_bytes, ok, read_with_python, small_cave_pipeline};

/// The three scene exporters with their defaults.
const SCENES: &str = "[[export]]\ntype = \"sdf\"\n\n[[export]]\ntype = \"usd\"\n\n[[export]]\ntype = \"gltf\"\n\n[[export]]\ntype = \"obj\"\n";

/// A two-level small cave world with `exports`, generated through the command line.
fn world(dir: &Path, exports: &str) -> PathBuf {
    let pipeline = small_cave_pipeline(dir, 2, exports);
    let out = dir.join("world");
    ok(&["generate", arg(&pipeline), "--out", arg(&out), "--force"]);
    out
}

/// The part names of the shared per-level meshes the world folder holds.
fn level_parts(world: &Path) -> BTreeSet<String> {
    std::fs::read_dir(world.join("mesh/parts/level"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter_map(|n| n.strip_suffix(".obj").map(str::to_owned))
        .filter(|n| !n.ends_with("-collision"))
        .collect()
}

/// `tests/readers/sdf_check.cc` compiled against libsdformat 12, or `None` (skipped with a
/// message) when pkg-config does not know `sdformat12`, unless `SUBTGRAPH_REQUIRE_SDFORMAT=1`.
fn sdf_checker(dir: &Path) -> Option<PathBuf> {
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
        eprintln!("skipping: pkg-config cannot find sdformat12 (apt install libsdformat-dev)");
        return None;
    };
    let exe = dir.join("sdf_check");
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/readers/sdf_check.cc");
    let flags = String::from_utf8(flags.stdout).unwrap();
    let out = Command::new("g++")
        .args(["-std=c++17", "-O0", "-o", arg(&exe), arg(&source)])
        .args(flags.split_whitespace())
        .output()
        .expect("g++ runs");
    assert!(
        out.status.success(),
        "compiling sdf_check.cc failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    Some(exe)
}

/// Runs the SDF checker on a world; returns its report lines.
fn check_sdf(checker: &Path, sdf: &Path) -> Vec<String> {
    let out = Command::new(checker).arg(sdf).output().unwrap();
    assert!(
        out.status.success(),
        "libsdformat refused {}:\n{}",
        sdf.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(str::to_owned)
        .collect()
}

fn count(report: &[String], key: &str) -> usize {
    report
        .iter()
        .find_map(|l| l.strip_prefix(&format!("{key} ")))
        .unwrap_or_else(|| panic!("no `{key}` in {report:?}"))
        .parse()
        .unwrap()
}

#[test]
fn gazebo_sdf_loads_in_libsdformat_with_a_static_model_per_level() {
    let dir = tempfile::tempdir().unwrap();
    let Some(checker) = sdf_checker(dir.path()) else {
        return;
    };
    let w = world(dir.path(), "[[export]]\ntype = \"sdf\"\n");
    let report = check_sdf(&checker, &w.join("gazebo/world.sdf"));
    let parts = level_parts(&w);
    assert_eq!(parts.len(), 2, "a part per level: {parts:?}");
    for key in ["models", "links", "visuals", "collisions"] {
        assert_eq!(count(&report, key), parts.len(), "{key}: {report:?}");
    }
    assert_eq!(count(&report, "missing"), 0, "{report:?}");
    assert!(!report.iter().any(|l| l.starts_with("dynamic-model")));
    // Each model shows its own level's visual mesh and collides with its collision mesh.
    let canonical = |p: PathBuf| p.canonicalize().unwrap().to_string_lossy().into_owned();
    let meshes: BTreeSet<String> = report
        .iter()
        .filter(|l| l.starts_with("visual ") || l.starts_with("collision "))
        .cloned()
        .collect();
    let expected: BTreeSet<String> = parts
        .iter()
        .flat_map(|p| {
            let dir = w.join("mesh/parts/level");
            [
                format!("visual {}", canonical(dir.join(format!("{p}.obj")))),
                format!(
                    "collision {}",
                    canonical(dir.join(format!("{p}-collision.obj")))
                ),
            ]
        })
        .collect();
    assert_eq!(meshes, expected);
    // Default lighting: only the faint sun.
    assert_eq!(count(&report, "lights"), 1);
    assert_eq!(count(&report, "point-lights"), 0);

    // Dark: no light at all; lamps: point lights along every corridor.
    let dark = dir.path().join("dark");
    std::fs::create_dir(&dark).unwrap();
    let w = world(&dark, "[[export]]\ntype = \"sdf\"\nlights = \"dark\"\n");
    assert_eq!(
        count(&check_sdf(&checker, &w.join("gazebo/world.sdf")), "lights"),
        0
    );
    let lamps = dir.path().join("lamps");
    std::fs::create_dir(&lamps).unwrap();
    let w = world(
        &lamps,
        "[[export]]\ntype = \"sdf\"\nlights = \"lamps\"\nlamps_every = 3\nsplit = \"whole\"\n",
    );
    let report = check_sdf(&checker, &w.join("gazebo/world.sdf"));
    assert_eq!(count(&report, "models"), 1, "split = whole");
    let topology: serde_json::Value =
        serde_json::from_slice(&std::fs::read(w.join("topology.json")).unwrap()).unwrap();
    let corridors = topology["edges"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["kind"] == "corridor")
        .count();
    let points = count(&report, "point-lights");
    assert!(
        corridors > 0 && points >= corridors,
        "{points} lamps, {corridors} corridors"
    );
    assert_eq!(count(&report, "lights"), points);
}

#[test]
fn bad_scene_settings_are_refused_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    for (exports, key, hint) in [
        (
            "type = \"sdf\"\nlights = \"bright\"",
            "export[0].lights",
            "\"lamps\"",
        ),
        ("type = \"sdf\"\nlamp = 2", "export[0].lamp", "lamp_height"),
        (
            "type = \"sdf\"\nlamps_every = 0",
            "export[0].lamps_every",
            "1 to 1000",
        ),
    ] {
        let pipeline = small_cave_pipeline(dir.path(), 1, &format!("[[export]]\n{exports}\n"));
        let out = dir.path().join("never");
        let err = fails(&["generate", arg(&pipeline), "--out", arg(&out)]);
        assert!(err.contains(key) && err.contains(hint), "{exports}: {err}");
        assert!(!out.exists(), "nothing written for a bad table");
    }
}

#[test]
fn scene_files_do_not_depend_on_the_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let pipeline = small_cave_pipeline(dir.path(), 2, SCENES);
    let mut folders = Vec::new();
    for threads in ["1", "3"] {
        let out = dir.path().join(format!("t{threads}"));
        let status = Command::new(env!("CARGO_BIN_EXE_subtgraph"))
            .args(["generate", arg(&pipeline), "--out", arg(&out)])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(status.status.success(), "{status:?}");
        folders.push(folder_bytes(&out));
    }
    let names: Vec<&str> = folders[0].iter().map(|(n, _)| n.as_str()).collect();
    for f in ["gazebo/world.sdf", "usd/world.usda", "mesh/world.glb"] {
        assert!(names.contains(&f), "{f} in {names:?}");
    }
    assert!(
        folders[0] == folders[1],
        "files differ between 1 and 3 threads"
    );
}

/// Runs `usd_check.py` on a world folder with extra arguments; returns its JSON summary.
fn check_usd(world: &Path, extra: &[&str]) -> Option<serde_json::Value> {
    let mut args = vec![arg(world)];
    args.extend_from_slice(extra);
    let out = read_with_python(&["pxr", "numpy"], "usd_check.py", &args)?;
    Some(serde_json::from_str(out.trim()).unwrap())
}

#[test]
fn usd_opens_in_usd_core_with_triangle_mesh_colliders() {
    let dir = tempfile::tempdir().unwrap();
    // With the SDF exporter, which writes the per-level OBJs the USD meshes are compared to.
    let w = world(
        dir.path(),
        "[[export]]\ntype = \"sdf\"\n\n[[export]]\ntype = \"usd\"\n\n[[export]]\ntype = \"obj\"\n",
    );
    let parts = w.join("mesh/parts/level");
    let Some(summary) = check_usd(&w, &["--parts", arg(&parts)]) else {
        return;
    };
    // A layer, a visual mesh and a collider per level; procedural tiles never repeat.
    assert_eq!(summary["parts"], 2, "{summary}");
    assert_eq!(summary["colliders"], 2, "{summary}");
    assert_eq!(summary["instances"], 0, "{summary}");
    for p in level_parts(&w) {
        assert!(w.join(format!("usd/parts/{p}.usda")).is_file(), "{p}");
    }
}

#[test]
fn usd_of_darpa_tiles_instances_repeated_tiles() {
    let Some(_) = common::darpa_tiles() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let manifest =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tilesets/manifests/darpa-cave-type-b.toml");
    let pipeline = dir.path().join("darpa.toml");
    std::fs::write(
        &pipeline,
        format!(
            "[world]\nseed = 2\nlevels = 1\nrows = 16\ncols = 16\ntile_pitch = 80.0\n\n\
             [topology]\nloops = 0\nt_junctions = 1\nintersections = 1\n\n\
             [route]\ntype = \"parabolic\"\n\n\
             [tileset]\ntype = \"mesh-files\"\nmanifest = {manifest:?}\n\n\
             [[export]]\ntype = \"usd\"\n\n[[export]]\ntype = \"obj\"\n"
        ),
    )
    .unwrap();
    let w = dir.path().join("world");
    ok(&["generate", arg(&pipeline), "--out", arg(&w)]);
    let Some(summary) = check_usd(&w, &["--min-instances", "2"]) else {
        return;
    };
    // The check above counted every face once, through the instances, against world.obj.
    let instances = summary["instances"].as_u64().unwrap();
    assert!(instances >= 10, "{summary}");
    let prototypes = std::fs::read_to_string(w.join("usd/parts/prototypes.usda")).unwrap();
    let count = prototypes.matches("def Xform \"tile_").count() as u64;
    assert!(
        count > 0 && count < instances,
        "{count} prototypes for {instances} instances"
    );
}

#[test]
fn obj_and_glb_are_the_same_closed_surface_in_trimesh() {
    let dir = tempfile::tempdir().unwrap();
    let w = world(dir.path(), SCENES);
    let Some(out) = read_with_python(&["trimesh", "numpy"], "trimesh_check.py", &[arg(&w)]) else {
        return;
    };
    let summary: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    // The script checked watertightness of all three, and that the GLB (turned back to Z up)
    // has the OBJ's triangles, bounds and enclosed volume.
    assert!(summary["triangles"].as_u64().unwrap() > 10_000, "{summary}");
    // A node per level, each split by trimesh into a geometry per material primitive.
    assert!(summary["glb_nodes"].as_u64().unwrap() >= 2, "{summary}");
    let glb = std::fs::read(w.join("mesh/world.glb")).unwrap();
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let doc: serde_json::Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
    let nodes: Vec<&str> = doc["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n["name"].as_str().unwrap())
        .collect();
    let parts: Vec<String> = level_parts(&w).into_iter().collect();
    assert_eq!(nodes, parts);
    assert!(
        doc["asset"]["generator"]
            .as_str()
            .unwrap()
            .starts_with("subtgraph")
    );
}
