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
    let mesh = world.join("mesh/world.obj");
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
    let mesh = world.join("mesh/world.obj");
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
    // The bag's wheel odometry scored against its ground-truth odometry (LZ4 chunks, two
    // Odometry topics of one bag), the numbers checked against `evo_ape bag2` on the bag.
    let bag = dir.path().join("loop/bag");
    let score = dir.path().join("wheel-score");
    let said = ok(&[
        "score",
        arg(&bag),
        "--reference-topic",
        "/ground_truth/odom",
        "--trajectory",
        arg(&bag),
        "--topic",
        "/wheel/odom",
        "--out",
        arg(&score),
    ]);
    assert!(said.contains("pose pairs"), "{said}");
    let j = json(&score.join("trajectory.json"));
    assert!(j["associated_poses"].as_u64().unwrap() > 100, "{j}");
    read_with_python(&["evo"], "trajectory_check.py", &[arg(&score)]);
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
    // Its manifest says `sense` wrote it: `generate --force` does not replace a sequence, and
    // `sense --force` does not replace a world.
    let manifest = std::fs::read_to_string(seq.join(".subtgraph-files")).unwrap();
    assert!(manifest.contains("complete sense"), "{manifest}");
    let e = fails(&["generate", arg(&pipeline), "--out", arg(&seq), "--force"]);
    assert!(e.contains("sensor sequence"), "{e}");
    assert_eq!(json(&seq.join("sequence.json"))["scan_count"], 20);
    let e = fails(&[
        "sense",
        w,
        "--out",
        arg(&bare),
        "--duration",
        "1",
        "--force",
    ]);
    assert!(e.contains("world folder"), "{e}");
    assert!(bare.join("world.toml").is_file());
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

/// A straight tube along x, `length` metres long and `radius` across, closed at both ends, its
/// triangles wound to face the inside: a passage with nothing along it to register against.
fn tube(radius: f64, length: f64) -> subtgraph::core::mesh::Mesh {
    let segments = 48usize;
    let rings = (length / 0.5).round() as usize;
    let mut m = subtgraph::core::mesh::Mesh::default();
    for k in 0..=rings {
        let x = length * k as f64 / rings as f64;
        for j in 0..segments {
            let a = std::f64::consts::TAU * j as f64 / segments as f64;
            m.positions.push([
                x as f32,
                (radius * a.cos()) as f32,
                (radius * a.sin()) as f32,
            ]);
        }
    }
    let at = |k: usize, j: usize| (k * segments + j % segments) as u32;
    for k in 0..rings {
        for j in 0..segments {
            // Counter-clockwise seen from the axis.
            m.triangles.push([at(k, j), at(k + 1, j), at(k + 1, j + 1)]);
            m.triangles.push([at(k, j), at(k + 1, j + 1), at(k, j + 1)]);
        }
    }
    for (k, x) in [(0, 0.0), (rings, length)] {
        let centre = m.positions.len() as u32;
        m.positions.push([x as f32, 0.0, 0.0]);
        for j in 0..segments {
            let t = [centre, at(k, j), at(k, j + 1)];
            m.triangles
                .push(if k == 0 { t } else { [t[0], t[2], t[1]] });
        }
    }
    m
}

/// Writes a sequence of the tube with the sensors' library, as a dataset worker would.
fn tube_sequence(out: &Path, seconds: f64) {
    use subtgraph_sensors::graph::RouteGraph;
    use subtgraph_sensors::{Options, Scene, Sequence};
    // Long enough that neither end is in range (120 m) of where the sequence drives: an end
    // wall would pin the motion along the tube.
    let (radius, length) = (2.5, 400.0);
    let mesh = tube(radius, length);
    assert!(mesh.edge_report().is_closed());
    // Facing the inside: a ray from the axis meets a triangle whose normal points back.
    let caster = subtgraph::core::raycast::RayCaster::new(&mesh);
    let hit = caster
        .cast([150.0, 0.0, 0.0], [0.0, 1.0, 0.0], 10.0)
        .unwrap();
    assert!(hit.normal[1] < -0.9, "{hit:?}");
    let floor = -radius;
    let polyline: Vec<String> = (0..=120)
        .map(|i| format!("[{}, 0, {floor}]", 140.0 + i as f64))
        .collect();
    let graph = format!(
        r#"{{"format": "subtgraph-graph/1", "start": 0,
            "nodes": [{{"id": 0, "kind": "dead-end", "level": 0, "position": [140, 0, {floor}]}},
                      {{"id": 1, "kind": "dead-end", "level": 0, "position": [260, 0, {floor}]}}],
            "edges": [{{"id": 0, "kind": "corridor", "from": 0, "to": 1, "length_m": 120,
                        "polyline": [{}]}}]}}"#,
        polyline.join(", ")
    );
    let graph = RouteGraph::from_json(&graph, "tube").unwrap();
    let scene = Scene::new(&mesh, &[0.3], Vec::new(), 20.0);
    let request = subtgraph_sensors::SenseRequest {
        duration: Some(seconds),
        lidar: "os1-64".into(),
        ..Default::default()
    };
    let options: Options = subtgraph_sensors::request::options(&request, 1).unwrap();
    let sequence = Sequence::plan(&scene, &graph, options).unwrap();
    std::fs::create_dir_all(out).unwrap();
    sequence
        .write(
            out,
            serde_json::json!({"folder": "a uniform tube"}),
            &mut |_| {},
        )
        .unwrap();
}

#[test]
fn odometry_tracks_the_control_route_and_loses_itself_in_a_uniform_tube() {
    // KISS-ICP and GenZ-LIO, on the bag and on the KITTI folder, with their own tools; evo
    // scores them: translation drift over 20 m of path, as a share of it.
    let Some(_) = common::python_with(&["kiss_icp", "genz_lio", "evo", "rosbags"]) else {
        return;
    };
    // The control: the cave preset's start, rocky and winding, seen by an OS1-64.
    let dir = tempfile::tempdir().unwrap();
    let world = dir.path().join("cave-7");
    ok(&[
        "generate",
        "--preset",
        "cave",
        "--seed",
        "7",
        "--format",
        "ground-truth",
        "--out",
        arg(&world),
    ]);
    let control = dir.path().join("control");
    sense(&world, &control, &["--duration", "30", "--lidar", "os1-64"]);
    let tube = dir.path().join("tube");
    tube_sequence(&tube, 30.0);
    let score = |seq: &Path, work: &str| -> serde_json::Value {
        let out = read_with_python(
            &["kiss_icp", "genz_lio", "evo", "rosbags", "yaml"],
            "odometry_check.py",
            &[arg(seq), arg(&dir.path().join(work)), "--delta", "20"],
        )
        .unwrap();
        eprintln!("{work}: {out}");
        serde_json::from_str(out.trim()).unwrap()
    };
    let runs = ["kiss-bag", "kiss-kitti", "genz-bag", "genz-kitti"];
    let good = score(&control, "odometry-control");
    for run in runs {
        // Tracking: a few percent at most (KISS-ICP drifts 1.5-2.3 % on the visual surface,
        // GenZ-LIO under 1 %), against more than 10 % in the tube.
        let drift = good[run]["drift_percent"].as_f64();
        assert!(
            drift.is_some_and(|d| d < 3.0),
            "{run} on the control route: {}",
            good[run]
        );
    }
    let bad = score(&tube, "odometry-tube");
    for run in runs {
        // Lost: the drift is many times the control's, or the method gave up.
        let drift = bad[run]["drift_percent"].as_f64();
        assert!(
            drift.is_none_or(|d| d > 10.0),
            "{run} in the tube: {}",
            bad[run]
        );
    }
}

/// `dataset --sense`: a sequence per world in `sequences/NAME`, the same bytes `sense` writes
/// for that world on its own (whose files the tests above check with rosbags, trimesh and the
/// odometry programs); run again, complete sequences are kept and a damaged one is made again;
/// a user's folder in a sequence's place is refused and kept; bad sensor options are refused
/// before any world is made.
#[test]
fn a_dataset_with_sense_writes_what_sense_writes_for_each_world() {
    let dir = tempfile::tempdir().unwrap();
    let pipeline = small_cave_pipeline(dir.path(), 1, "");
    let data = dir.path().join("data");
    let dataset = |extra: &[&str]| {
        let mut args = vec![
            "dataset",
            arg(&pipeline),
            "--count",
            "2",
            "--seed",
            "9",
            "--sense",
            "--sense-duration",
            "2",
            "--out",
            arg(&data),
        ];
        args.extend_from_slice(extra);
        args.iter().map(|s| s.to_string()).collect::<Vec<String>>()
    };
    let run = |extra: &[&str]| {
        let args = dataset(extra);
        ok(&args.iter().map(String::as_str).collect::<Vec<_>>())
    };
    let said = run(&[]);
    assert!(
        said.contains("wrote 2 sensor sequence(s) (40 scans"),
        "{said}"
    );
    let names = ["small-cave-0000", "small-cave-0001"];
    for name in names {
        let world = data.join(name);
        assert!(
            world.join("ground_truth/graph.json").is_file(),
            "--sense adds the ground truth"
        );
        let alone = dir.path().join(format!("alone-{name}"));
        sense(&world, &alone, &["--duration", "2"]);
        let seq = data.join("sequences").join(name);
        // sequence.json names the world folder it was made from: the same world, two paths.
        common::assert_same_files(&alone, &seq, &["sequence.json", ".subtgraph-files"]);
        let (a, b) = (
            json(&alone.join("sequence.json")),
            json(&seq.join("sequence.json")),
        );
        assert_eq!(a["scans"], b["scans"]);
        assert_eq!(a["seed"], b["seed"]);
    }

    // Again: nothing to do.
    let said = run(&[]);
    assert!(said.contains("wrote 0 sensor sequence(s)"), "{said}");
    assert!(said.contains("kept 2 complete one(s)"), "{said}");

    // A damaged sequence (ours) is made again; a user's folder in a sequence's place is not.
    let damaged = data
        .join("sequences")
        .join(names[0])
        .join("ground_truth.tum");
    let good = std::fs::read(&damaged).unwrap();
    std::fs::write(&damaged, b"0 0 0 0 0 0 0 1\n").unwrap();
    let said = run(&[]);
    assert!(said.contains("wrote 1 sensor sequence(s)"), "{said}");
    assert_eq!(std::fs::read(&damaged).unwrap(), good);
    let theirs = data.join("sequences").join(names[1]);
    std::fs::remove_dir_all(&theirs).unwrap();
    std::fs::create_dir_all(&theirs).unwrap();
    std::fs::write(theirs.join("notes.txt"), b"mine").unwrap();
    let args = dataset(&[]);
    let err = fails(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(err.contains("sensing small-cave-0001"), "{err}");
    assert_eq!(std::fs::read(theirs.join("notes.txt")).unwrap(), b"mine");

    // Refused before any world is made.
    for (extra, expect) in [
        (
            &["--sense-lidar", "hdl-64"][..],
            "unknown LiDAR model 'hdl-64'",
        ),
        (&["--no-mesh"][..], "leave out --no-mesh"),
    ] {
        let fresh = dir.path().join("fresh");
        let mut args: Vec<&str> = vec![
            "dataset",
            arg(&pipeline),
            "--count",
            "1",
            "--sense",
            "--out",
            arg(&fresh),
        ];
        args.extend_from_slice(extra);
        let err = fails(&args);
        assert!(err.contains(expect), "{err}");
        assert!(!fresh.exists(), "nothing made");
    }
}
