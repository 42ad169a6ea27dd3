//! `subtgraph sense`: sensor sequences along a world's routes, checked by the programs that read
//! them (rosbags, trimesh, KISS-ICP, GenZ-LIO, evo; tests/readers/sense_check.py and
//! odometry_check.py), the same on one and three threads, and refused with a clear error and
//! nothing written when the input is wrong.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::{self, arg, fails, ok, read_with_python, small_cave_pipeline};

/// A small cave world folder with ground truth (and the OBJ meshes `generate` writes by
/// default), in `dir`.
fn cave_world(dir: &Path, levels: u32) -> PathBuf {
    let pipeline = small_cave_pipeline(dir, levels, "");
    let out = dir.join(format!("cave-{levels}"));
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

fn sense(world: &Path, out: &Path, extra: &[&str]) -> String {
    let mut args = vec!["sense", arg(world), "--out", arg(out)];
    args.extend_from_slice(extra);
    ok(&args)
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

#[test]
fn a_sequence_is_what_rosbags_and_trimesh_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let world = cave_world(dir.path(), 1);
    let mesh = world.join("mesh/collision.obj");
    let seq = dir.path().join("seq");
    let said = sense(&world, &seq, &["--duration", "15"]);
    assert!(said.contains("150 scans"), "{said}");
    let meta = json(&seq.join("sequence.json"));
    assert_eq!(meta["scan_count"], 150);
    assert_eq!(meta["scans"].as_array().unwrap().len(), 150);
    assert_eq!(meta["lidar"]["name"], "os1-32");
    assert_eq!(meta["platform"]["name"], "ground");
    // The first scans stand still (IMU initialisation), then the platform drives an edge.
    assert_eq!(meta["scans"][0]["phase"], "still");
    assert!(
        meta["scans"][149]["edge"].is_number(),
        "{}",
        meta["scans"][149]
    );
    let out = read_with_python(
        &["rosbags", "trimesh", "rtree"],
        "sense_check.py",
        &[arg(&seq), arg(&mesh)],
    );
    if let Some(out) = out {
        eprintln!("{out}");
    }
    // Noiseless: the returns lie on the mesh to the OBJ's 0.1 mm, and the IMU is the ground
    // truth differentiated.
    let quiet = dir.path().join("quiet");
    sense(&world, &quiet, &["--duration", "8", "--noiseless"]);
    if let Some(out) = read_with_python(
        &["rosbags", "trimesh", "rtree"],
        "sense_check.py",
        &[arg(&quiet), arg(&mesh), "--noiseless"],
    ) {
        let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
        assert!(v["max_distance_m"].as_f64().unwrap() < 1e-3, "{v}");
    }
}

#[test]
fn other_sensors_platforms_and_routes_are_read_back_too() {
    let dir = tempfile::tempdir().unwrap();
    let world = cave_world(dir.path(), 2);
    let mesh = world.join("mesh/collision.obj");
    for (name, extra) in [
        ("vlp", &["--lidar", "vlp-16", "--duration", "6"][..]),
        ("livox", &["--lidar", "mid-360", "--duration", "6"][..]),
        (
            "aerial",
            &[
                "--platform",
                "aerial",
                "--route",
                "levels",
                "--duration",
                "40",
            ][..],
        ),
        (
            "loop",
            &["--route", "loop", "--wheel-odometry", "--duration", "6"][..],
        ),
    ] {
        let seq = dir.path().join(name);
        sense(&world, &seq, extra);
        read_with_python(
            &["rosbags", "trimesh", "rtree"],
            "sense_check.py",
            &[arg(&seq), arg(&mesh)],
        );
    }
    // The aerial route climbs a shaft within its 40 seconds... or is labelled on its way there.
    let meta = json(&dir.path().join("aerial/sequence.json"));
    assert_eq!(meta["route"]["kind"], "levels");
    let phases: Vec<&str> = meta["scans"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["phase"].as_str().unwrap())
        .collect();
    assert!(phases.contains(&"drive"), "{phases:?}");
    let meta = json(&dir.path().join("loop/sequence.json"));
    assert!(meta["wheel_odometry"].as_bool().unwrap());
}

#[test]
fn a_sequence_is_the_same_on_one_and_three_threads() {
    let dir = tempfile::tempdir().unwrap();
    let world = cave_world(dir.path(), 1);
    let mut folders = Vec::new();
    for threads in ["1", "3"] {
        let out = dir.path().join(format!("t{threads}"));
        let status = Command::new(env!("CARGO_BIN_EXE_subtgraph"))
            .args(["sense", arg(&world), "--out", arg(&out), "--duration", "5"])
            .args(["--wheel-odometry"])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(status.status.success(), "{status:?}");
        folders.push(out);
    }
    common::assert_same_files(&folders[0], &folders[1], &[]);
}

#[test]
fn bad_input_is_refused_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let world = cave_world(dir.path(), 1);
    let out = dir.path().join("seq");
    let w = arg(&world);
    let o = arg(&out);
    let cases: &[(&[&str], &str)] = &[
        (&["--lidar", "os2-9"], "unknown LiDAR model 'os2-9'"),
        (&["--platform", "boat"], "unknown platform 'boat'"),
        (&["--route", "spiral"], "unknown route 'spiral'"),
        (&["--format", "pcap"], "unknown output format 'pcap'"),
        (
            &["--imu-rate", "100000"],
            "--imu-rate 100000 Hz is out of bounds",
        ),
        (
            &["--lidar-rate", "400"],
            "rate_hz of LiDAR 'os1-32' 400 is out of bounds",
        ),
        (&["--max-range", "0"], "range_m of LiDAR 'os1-32'"),
        (&["--imu-time-offset", "5"], "--imu-time-offset"),
        (&["--duration", "0"], "--duration"),
        (
            &["--platform", "aerial", "--wheel-odometry"],
            "--wheel-odometry",
        ),
        (&["--route", "levels"], "the world has one level"),
        (&["--max-disk", "10M"], "--max-disk allows 10.0 MB"),
    ];
    for (extra, says) in cases {
        let mut args = vec!["sense", w, "--out", o];
        args.extend_from_slice(extra);
        let e = fails(&args);
        assert!(e.contains(says), "{extra:?}: {e}");
        assert!(!out.exists(), "{extra:?} wrote {}", out.display());
    }
    // A route the platform cannot take: the ground robot does not fly shafts.
    let two = cave_world(dir.path(), 2);
    let e = fails(&["sense", arg(&two), "--out", o, "--route", "levels"]);
    assert!(e.contains("--platform aerial"), "{e}");
    // A world without ground truth.
    let bare = dir.path().join("bare");
    let pipeline = small_cave_pipeline(dir.path(), 1, "");
    ok(&["generate", arg(&pipeline), "--out", arg(&bare)]);
    let e = fails(&["sense", arg(&bare), "--out", o]);
    assert!(e.contains("--format ground-truth"), "{e}");
    let e = fails(&["sense", arg(&dir.path().join("nowhere")), "--out", o]);
    assert!(e.contains("no such folder"), "{e}");
    // An output folder in the way, and --force on a folder subtgraph did not write.
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("notes.txt"), b"mine").unwrap();
    let e = fails(&["sense", w, "--out", o, "--duration", "1"]);
    assert!(e.contains("already exists"), "{e}");
    let e = fails(&["sense", w, "--out", o, "--duration", "1", "--force"]);
    assert!(e.contains("refusing to replace it"), "{e}");
    assert_eq!(std::fs::read(out.join("notes.txt")).unwrap(), b"mine");
    // Nothing half-written beside it either.
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(names.is_empty(), "{names:?}");
    // A sequence subtgraph wrote is replaced with --force.
    let seq = dir.path().join("again");
    sense(&world, &seq, &["--duration", "1"]);
    sense(&world, &seq, &["--duration", "2", "--force"]);
    assert_eq!(json(&seq.join("sequence.json"))["scan_count"], 20);
}

#[test]
fn no_ray_escapes_a_closed_world() {
    // A LiDAR table with no range limit worth the name and no grazing cut-off: in a world whose
    // collision surface is closed, every ray returns.
    let dir = tempfile::tempdir().unwrap();
    let world = cave_world(dir.path(), 1);
    let table = dir.path().join("all.toml");
    std::fs::write(
        &table,
        "name = \"all\"\ndriver = \"ouster\"\nrate_hz = 10\ncolumns = 512\n\
         elevations_deg = [89.0, 60.0, 30.0, 10.0, 0.0, -10.0, -30.0, -60.0, -89.0]\n\
         range_m = [0.0, 500.0]\nrange_noise_m = 0.0\ngrazing_deg = 90\n",
    )
    .unwrap();
    let seq = dir.path().join("seq");
    let said = sense(&world, &seq, &["--lidar", arg(&table), "--duration", "20"]);
    let rays = 512 * 9 * 200;
    assert!(
        said.contains(&format!("{rays} of {rays} rays returned")),
        "{said}"
    );
    // The surface is closed, as trimesh sees it.
    if let Some(python) = common::python_with(&["trimesh"]) {
        let out = Command::new(python)
            .args([
                "-c",
                "import sys, trimesh; m = trimesh.load(sys.argv[1], force='mesh', process=False); \
                 m.merge_vertices(); print(m.is_watertight)",
                arg(&world.join("mesh/collision.obj")),
            ])
            .output()
            .unwrap();
        assert_eq!(
            String::from_utf8_lossy(&out.stdout).trim(),
            "True",
            "{out:?}"
        );
    }
}
