//! The scene exporters (Gazebo SDF, USD, glTF binary), each checked by the program that reads
//! it: libsdformat (what gz-sim parses worlds with), usd-core (Isaac Sim's USD) and trimesh
//! (what the OBJ and GLB look like to a mesh library). A missing reader skips its test with a
//! message, unless `scripts/test` asked for every reader.

use crate::common;

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
pub(crate) fn sdf_checker(dir: &Path) -> Option<PathBuf> {
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
pub(crate) fn check_sdf(checker: &Path, sdf: &Path) -> Vec<String> {
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

pub(crate) fn count(report: &[String], key: &str) -> usize {
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

/// The pkg-config modules the Gazebo physics checker is built with (Debian's
/// libignition-physics-dev, -sdf-dev, -mesh-dev, libignition-common-dev, libsdformat-dev).
const GAZEBO_PHYSICS: [&str; 7] = [
    "ignition-physics5",
    "ignition-physics5-sdf",
    "ignition-physics5-mesh",
    "ignition-plugin1-loader",
    "ignition-common4-graphics",
    "ignition-math6-eigen3",
    "sdformat12",
];

/// `tests/readers/gazebo_physics_check.cc` compiled against ign-physics 5 (Gazebo Fortress),
/// or `None` (skipped with a message) when pkg-config or the dartsim plugin is missing, unless
/// `SUBTGRAPH_REQUIRE_GAZEBO_PHYSICS=1` (as `scripts/test` sets after installing them).
fn gazebo_physics_checker(dir: &Path) -> Option<PathBuf> {
    let flags = Command::new("pkg-config")
        .arg("--cflags")
        .arg("--libs")
        .args(GAZEBO_PHYSICS)
        .output()
        .ok()
        .filter(|o| o.status.success());
    let plugin = Path::new(
        "/usr/lib/x86_64-linux-gnu/ign-physics-5/engine-plugins/libignition-physics5-dartsim-plugin.so",
    );
    let (Some(flags), true) = (flags, plugin.exists()) else {
        let hint = "apt install libignition-physics-dev libignition-physics5-dartsim-plugin5 \
                    libignition-physics-sdf-dev libignition-physics-mesh-dev libignition-common-dev";
        assert!(
            std::env::var("SUBTGRAPH_REQUIRE_GAZEBO_PHYSICS").is_err(),
            "ign-physics 5 with its dartsim plugin is missing; {hint} (scripts/test does)"
        );
        eprintln!("skipping: ign-physics 5 with its dartsim plugin is missing ({hint})");
        return None;
    };
    let exe = dir.join("gazebo_physics_check");
    let source =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/readers/gazebo_physics_check.cc");
    let flags = String::from_utf8(flags.stdout).unwrap();
    let out = Command::new("g++")
        .args(["-std=c++17", "-O1", "-o", arg(&exe), arg(&source)])
        .args(flags.split_whitespace())
        .output()
        .expect("g++ runs");
    assert!(
        out.status.success(),
        "compiling gazebo_physics_check.cc failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    Some(exe)
}

/// Where a ball ended: (x, y, z) after "end" in a `ball I start ... end X Y Z ...` line.
fn ball_end(line: &str) -> [f64; 3] {
    let words: Vec<&str> = line.split_whitespace().collect();
    let at = words.iter().position(|w| *w == "end").unwrap();
    [1, 2, 3].map(|k| words[at + k].parse().unwrap())
}

/// Gazebo's own physics: the world built in ign-physics' dartsim engine as gz-sim builds it;
/// a 0.2 m ball dropped 0.5 m above each spawn pose rests on the floor after 3 s, and one
/// dropped inside the rock (the centre of a cell no passage crosses) falls through the
/// surface, as it must, since a surface holds only from the passage's side (the negative
/// control). Also what gz-sim expects of the file: one static <model> per part (gz-sim's
/// levels load and unload whole models), every collision mesh URI found from the world's
/// folder and, from another working directory, through `GZ_SIM_RESOURCE_PATH` (and not
/// without it), and the world's one directional light.
#[test]
fn gazebo_physics_holds_balls_on_the_floor_in_dartsim() {
    let dir = tempfile::tempdir().unwrap();
    let Some(checker) = gazebo_physics_checker(dir.path()) else {
        return;
    };
    // Level floors: a ball rests only there (on a sloping floor it rolls).
    let pipeline = small_cave_pipeline(dir.path(), 2, "grade = [0, 0]\n");
    let w = dir.path().join("world");
    ok(&[
        "generate",
        arg(&pipeline),
        "--format",
        "sdf,spawn-poses",
        "--out",
        arg(&w),
    ]);
    let json = |f: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(w.join(f)).unwrap()).unwrap()
    };
    let poses = json("ground_truth/spawn_poses.json");
    let topology = json("topology.json");
    let mut drops: Vec<[f64; 3]> = poses["robots"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| crate::common::json_point(&r["spawn"]["position"]))
        .collect();
    assert!(drops.len() >= 2, "{poses}");
    // A cell of level 0 no passage crosses: solid rock at its centre.
    let mut used = BTreeSet::new();
    for e in topology["edges"].as_array().unwrap() {
        for c in e["cells"].as_array().unwrap() {
            used.insert((c["level"].as_u64(), c["row"].as_u64(), c["col"].as_u64()));
        }
    }
    let (rows, pitch) = (
        topology["rows"].as_u64().unwrap(),
        topology["tile_pitch_m"].as_f64().unwrap(),
    );
    let (row, col) = (0..rows)
        .flat_map(|r| (0..topology["cols"].as_u64().unwrap()).map(move |c| (r, c)))
        .find(|&(r, c)| {
            (r.saturating_sub(1)..=r + 1).all(|rr| {
                (c.saturating_sub(1)..=c + 1)
                    .all(|cc| !used.contains(&(Some(0), Some(rr), Some(cc))))
            })
        })
        .expect("a rock cell with rock around it");
    let rock = [col as f64 * pitch, (rows - 1 - row) as f64 * pitch, 1.5];
    let mut args: Vec<String> = vec![
        w.join("gazebo/world.sdf").display().to_string(),
        "0.2".into(),
    ];
    for d in &mut drops {
        d[2] += 0.5;
    }
    drops.push(rock);
    args.extend(drops.iter().map(|d| format!("{},{},{}", d[0], d[1], d[2])));
    let run = |resources: Option<&Path>| -> Vec<String> {
        let mut cmd = Command::new(&checker);
        cmd.args(&args)
            .current_dir(dir.path())
            .env_remove("GZ_SIM_RESOURCE_PATH");
        if let Some(r) = resources {
            cmd.env("GZ_SIM_RESOURCE_PATH", r);
        }
        let out = cmd.output().unwrap();
        assert!(
            out.status.success(),
            "gazebo_physics_check failed:\n{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8(out.stdout)
            .unwrap()
            .lines()
            .map(str::to_owned)
            .collect()
    };
    let report = run(Some(&w.join("gazebo")));
    let text = report.join("\n");
    // One static model per part, each with its collision mesh, found both ways.
    let parts = level_parts(&w);
    let models: Vec<&String> = report.iter().filter(|l| l.starts_with("model ")).collect();
    assert_eq!(models.len(), parts.len(), "{text}");
    assert!(
        models.iter().all(|l| l.ends_with(" collisions 1")),
        "{text}"
    );
    let meshes: Vec<&String> = report.iter().filter(|l| l.starts_with("mesh ")).collect();
    assert_eq!(meshes.len(), parts.len(), "{text}");
    for m in &meshes {
        let words: Vec<&str> = m.split_whitespace().collect();
        assert!(words[2] != "-" && words[2] == words[3], "{m}");
    }
    assert_eq!(
        report.iter().filter(|l| l.starts_with("light ")).count(),
        1,
        "{text}"
    );
    assert!(text.contains("light sun directional"), "{text}");
    // The balls: each on the floor near where it was dropped; the one in the rock far below.
    let balls: Vec<&String> = report.iter().filter(|l| l.starts_with("ball ")).collect();
    assert_eq!(balls.len(), drops.len(), "{text}");
    for (line, drop) in balls.iter().zip(&drops).take(drops.len() - 1) {
        let end = ball_end(line);
        let floor = drop[2] - 0.5;
        assert!(
            (end[2] - (floor + 0.2)).abs() < 0.6,
            "a ball fell through or hangs: {line}\n{text}"
        );
        assert!(
            (end[0] - drop[0]).hypot(end[1] - drop[1]) < 4.0,
            "a ball rolled away: {line}"
        );
    }
    let fell = ball_end(balls.last().unwrap());
    assert!(
        fell[2] < rock[2] - 10.0,
        "the ball in the rock did not fall: {text}"
    );
    // Without GZ_SIM_RESOURCE_PATH the URIs are found from the world's folder only.
    let without = run(None);
    for m in without.iter().filter(|l| l.starts_with("mesh ")) {
        assert!(m.ends_with(" -") && !m.contains(" - "), "{m}");
    }
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

/// The Isaac Sim checks can fail: a copy of the world whose collider lost its physics material
/// binding, or its `PhysicsCollisionAPI`, or whose root layer lost its physics materials, is
/// refused by `usd_check.py`, naming what is missing.
#[test]
fn usd_checks_refuse_a_collider_without_its_physics_schemas() {
    let dir = tempfile::tempdir().unwrap();
    let w = world(
        dir.path(),
        "[[export]]\ntype = \"usd\"\n\n[[export]]\ntype = \"obj\"\n",
    );
    if check_usd(&w, &[]).is_none() {
        return;
    }
    let part = w.join("usd/parts/level-0.usda");
    let root = w.join("usd/world.usda");
    let (part_text, root_text) = (
        std::fs::read_to_string(&part).unwrap(),
        std::fs::read_to_string(&root).unwrap(),
    );
    let python = common::python_with(&["pxr", "numpy"]).unwrap();
    for (file, text, from, to, says) in [
        (
            &part,
            &part_text,
            "rel material:binding:physics",
            "rel unbound",
            "no physics material bound",
        ),
        (
            &part,
            &part_text,
            "\"PhysicsCollisionAPI\", ",
            "",
            "lacks PhysicsCollisionAPI",
        ),
        (
            &root,
            &root_text,
            "\"PhysicsMaterialAPI\"",
            "\"MaterialBindingAPI\"",
            "no physics material",
        ),
        (
            &root,
            &root_text,
            "kilogramsPerUnit = 1\n",
            "",
            "kilogramsPerUnit",
        ),
    ] {
        assert!(text.contains(from), "{from} in {}", file.display());
        std::fs::write(file, text.replace(from, to)).unwrap();
        let out = Command::new(&python)
            .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/readers/usd_check.py"))
            .arg(&w)
            .output()
            .unwrap();
        let report = String::from_utf8_lossy(&out.stdout);
        assert!(
            !out.status.success() && report.contains("FAIL") && report.contains(says),
            "without {from}: {report}{}",
            String::from_utf8_lossy(&out.stderr)
        );
        std::fs::write(file, text).unwrap();
    }
    assert!(check_usd(&w, &[]).is_some());
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

/// Runs Blender headless on a mesh file with `tests/readers/blender_check.py`; its report.
/// `None` (skipped with a message) without a `blender` on the PATH, unless
/// `SUBTGRAPH_REQUIRE_BLENDER=1` (as `scripts/test` sets after installing it).
fn blender_import(file: &Path) -> Option<serde_json::Value> {
    let has = Command::new("blender")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !has {
        assert!(
            std::env::var("SUBTGRAPH_REQUIRE_BLENDER").is_err(),
            "blender is missing; apt-get install --no-install-recommends blender python3-numpy (scripts/test does)"
        );
        eprintln!(
            "skipping: no blender (apt-get install --no-install-recommends blender python3-numpy)"
        );
        return None;
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/readers/blender_check.py");
    let out = Command::new("blender")
        .args([
            "-b",
            "--factory-startup",
            "--python-exit-code",
            "1",
            "--python",
        ])
        .arg(&script)
        .arg("--")
        .arg(file)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "blender could not import {}:\n{text}{}",
        file.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    let line = text
        .lines()
        .find_map(|l| l.strip_prefix("RESULT "))
        .unwrap_or_else(|| panic!("no RESULT from blender:\n{text}"));
    Some(serde_json::from_str(line).unwrap())
}

/// Blender (Debian's 3.4, headless) imports `mesh/world.glb` and `mesh/world.obj` with its own
/// importers: as many faces as `world.obj` has triangles, a mesh object per part from the GLB
/// (per `o` from the OBJ), and the materials the OBJ uses, by name.
#[test]
fn blender_imports_the_glb_and_the_obj() {
    let dir = tempfile::tempdir().unwrap();
    let w = world(dir.path(), SCENES);
    let obj = std::fs::read_to_string(w.join("mesh/world.obj")).unwrap();
    let faces = obj.lines().filter(|l| l.starts_with("f ")).count() as u64;
    let objects = obj.lines().filter(|l| l.starts_with("o ")).count();
    let materials: BTreeSet<&str> = obj
        .lines()
        .filter_map(|l| l.strip_prefix("usemtl "))
        .collect();
    let parts = level_parts(&w);
    for (file, count) in [("mesh/world.glb", parts.len()), ("mesh/world.obj", objects)] {
        let Some(report) = blender_import(&w.join(file)) else {
            return;
        };
        assert_eq!(report["faces"].as_u64(), Some(faces), "{file}: {report}");
        assert_eq!(
            report["objects"].as_array().unwrap().len(),
            count,
            "{file}: {report}"
        );
        let names: BTreeSet<&str> = report["materials"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m.as_str().unwrap())
            .collect();
        assert_eq!(names, materials, "{file}: {report}");
    }
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
