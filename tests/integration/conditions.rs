//! `sense --conditions`: dust, fog, wet rock and drips, checked ray by ray against the model by
//! numpy (tests/readers/conditions_check.py), the same bytes on one and three threads and with
//! `--conditions none` as without; bad condition tables refused before anything is cast; and
//! the routes that go straight to a study's target (`shaft`, `edge:N`, `node:N`, `--start`),
//! checked against the ground-truth graph by an independent reader (networkx,
//! tests/readers/route_target_check.py).

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::{self, arg, fails, ok, read_with_python, small_cave_pipeline};

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

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

#[test]
fn dust_and_fog_returns_are_labelled_and_match_the_model() {
    let dir = tempfile::tempdir().unwrap();
    let world = cave_world(dir.path(), 1);
    let clean = dir.path().join("clean");
    let base = ["--duration", "2.5", "--noiseless", "--format", "bag"];
    let mut args = vec!["sense", arg(&world), "--out", arg(&clean)];
    args.extend_from_slice(&base);
    ok(&args);
    for (name, text) in [
        (
            "dust",
            "[[conditions]]\ntype = \"dust\"\nat = \"route\"\ndensity_mg_m3 = 400\n",
        ),
        (
            "fog",
            "[[conditions]]\ntype = \"fog\"\nat = \"route\"\ndensity_mg_m3 = 3000\n",
        ),
    ] {
        let file = write(dir.path(), &format!("{name}.toml"), text);
        let seq = dir.path().join(name);
        let mut args = vec!["sense", arg(&world), "--out", arg(&seq), "--conditions"];
        args.push(arg(&file));
        args.extend_from_slice(&base);
        ok(&args);
        let meta = json(&seq.join("sequence.json"));
        let label = &meta["scans"][10]["conditions"];
        assert_eq!(label["inside"], serde_json::json!([0]), "{label}");
        assert!(label[name].as_u64().unwrap() > 100, "{label}");
        if let Some(out) = read_with_python(
            &["rosbags", "numpy"],
            "conditions_check.py",
            &[arg(&clean), arg(&seq)],
        ) {
            eprintln!("{name}: {out}");
        }
    }
}

#[test]
fn conditions_none_is_clear_air_and_conditions_are_the_same_on_one_and_three_threads() {
    let dir = tempfile::tempdir().unwrap();
    let world = cave_world(dir.path(), 1);
    let plain = dir.path().join("plain");
    let none = dir.path().join("none");
    ok(&[
        "sense",
        arg(&world),
        "--out",
        arg(&plain),
        "--duration",
        "3",
    ]);
    ok(&[
        "sense",
        arg(&world),
        "--out",
        arg(&none),
        "--duration",
        "3",
        "--conditions",
        "none",
    ]);
    common::assert_same_files(&plain, &none, &[]);
    // Every condition at once, on 1 and 3 threads.
    let file = write(
        dir.path(),
        "all.toml",
        "[[conditions]]\ntype = \"dust\"\nat = \"platform\"\ndensity_mg_m3 = 3000\n\n\
         [[conditions]]\ntype = \"mist\"\nat = \"node 1\"\nradius_m = 10\ndensity_mg_m3 = 500\n\n\
         [[conditions]]\ntype = \"wet-rock\"\nat = \"route\"\npuddles = 0.5\n\n\
         [[conditions]]\ntype = \"drips\"\nat = \"route\"\nlines_per_10m = 20\ninterval_s = 0.1\n",
    );
    let mut folders = Vec::new();
    for threads in ["1", "3"] {
        let out = dir.path().join(format!("t{threads}"));
        let status = Command::new(env!("CARGO_BIN_EXE_subtgraph"))
            .args(["sense", arg(&world), "--out", arg(&out), "--duration", "6"])
            .args(["--conditions", arg(&file)])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(status.status.success(), "{status:?}");
        folders.push(out);
    }
    common::assert_same_files(&folders[0], &folders[1], &[]);
    // Each kind of return is there and labelled, in the labels and beside each KITTI scan.
    let meta = json(&folders[0].join("sequence.json"));
    let total = |k: &str| -> u64 {
        meta["scans"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s["conditions"][k].as_u64().unwrap())
            .sum()
    };
    for k in ["dust", "wet", "puddle", "drip"] {
        assert!(total(k) > 0, "no {k} returns");
    }
    let labels = std::fs::read(folders[0].join("kitti/labels/000030.label")).unwrap();
    let points = std::fs::metadata(folders[0].join("kitti/velodyne/000030.bin"))
        .unwrap()
        .len();
    assert_eq!(labels.len() as u64 * 4, points, "a label per point");
}

#[test]
fn bad_condition_tables_are_refused_before_anything_is_cast() {
    let dir = tempfile::tempdir().unwrap();
    let world = cave_world(dir.path(), 1);
    let out = dir.path().join("seq");
    let cases = [
        (
            "[[conditions]]\ntype = \"dust\"\nat = \"route\"\ndensity_mg_m3 = -1\n",
            "density_mg_m3 = -1 is out of bounds",
        ),
        (
            "[[conditions]]\ntype = \"fog\"\nat = \"edge 9999\"\ndensity_mg_m3 = 10\n",
            "edge 9999 does not exist",
        ),
        (
            "[[conditions]]\ntype = \"fog\"\nat = \"node 9999\"\ndensity_mg_m3 = 10\n",
            "node 9999 does not exist",
        ),
        (
            "[[conditions]]\ntype = \"dust\"\nat = \"route\"\ndensity_mg_m3 = 10\nspeed = 3\n",
            "unknown key 'speed'",
        ),
        (
            "[[conditions]]\ntype = \"sand\"\nat = \"route\"\n",
            "'sand'",
        ),
        (
            "[[conditions]]\ntype = \"drips\"\nat = \"level 7\"\n",
            "level 7 does not exist",
        ),
        ("wind = 3\n", "unknown key 'wind'"),
    ];
    for (text, says) in cases {
        let file = write(dir.path(), "bad.toml", text);
        let e = fails(&[
            "sense",
            arg(&world),
            "--out",
            arg(&out),
            "--conditions",
            arg(&file),
        ]);
        assert!(e.contains(says) && e.contains("bad.toml"), "{text}: {e}");
        assert!(!out.exists(), "{text} wrote {}", out.display());
    }
    let e = fails(&[
        "sense",
        arg(&world),
        "--out",
        arg(&out),
        "--conditions",
        "missing.toml",
    ]);
    assert!(
        e.contains("missing.toml") && e.contains("cannot be read"),
        "{e}"
    );
}

#[test]
fn routes_go_straight_to_a_shaft_an_edge_and_a_node() {
    let dir = tempfile::tempdir().unwrap();
    let world = cave_world(dir.path(), 2);
    let graph = world.join("ground_truth/graph.json");
    let shaft = dir.path().join("shaft");
    ok(&[
        "sense",
        arg(&world),
        "--out",
        arg(&shaft),
        "--platform",
        "aerial",
        "--route",
        "shaft",
        "--duration",
        "25",
        "--format",
        "kitti",
    ]);
    if let Some(out) = read_with_python(
        &["networkx", "numpy"],
        "route_target_check.py",
        &[arg(&graph), arg(&shaft), "shaft"],
    ) {
        eprintln!("shaft: {out}");
    }
    // An edge and a node far from the start, and a window of the edge's route.
    let g = json(&graph);
    let last_edge = g["edges"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["kind"] == "corridor")
        .map(|e| e["id"].as_u64().unwrap())
        .max()
        .unwrap();
    let target = format!("edge:{last_edge}");
    let edge = dir.path().join("edge");
    ok(&[
        "sense",
        arg(&world),
        "--out",
        arg(&edge),
        "--route",
        &target,
        "--duration",
        "8",
        "--format",
        "kitti",
    ]);
    read_with_python(
        &["networkx", "numpy"],
        "route_target_check.py",
        &[arg(&graph), arg(&edge), &target],
    );
    // The junction on level 0 with the shortest edge (its route reaches it soonest).
    let junction = g["edges"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["kind"] == "corridor")
        .flat_map(|e| {
            [
                (e["from"].clone(), e["length_m"].as_f64().unwrap()),
                (e["to"].clone(), e["length_m"].as_f64().unwrap()),
            ]
        })
        .filter(|(n, _)| {
            let node = &g["nodes"][n.as_u64().unwrap() as usize];
            node["kind"] != "dead-end" && node["level"] == 0
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(n, _)| n.as_u64().unwrap())
        .unwrap();
    let target = format!("node:{junction}");
    let node = dir.path().join("node");
    ok(&[
        "sense",
        arg(&world),
        "--out",
        arg(&node),
        "--route",
        &target,
        "--duration",
        "30",
        "--format",
        "kitti",
    ]);
    read_with_python(
        &["networkx", "numpy"],
        "route_target_check.py",
        &[arg(&graph), arg(&node), &target],
    );
    // A window: the same route from 3 s on is the same poses, 30 scans later.
    let window = dir.path().join("window");
    ok(&[
        "sense",
        arg(&world),
        "--out",
        arg(&window),
        "--route",
        &target,
        "--start",
        "3",
        "--duration",
        "5",
        "--format",
        "kitti",
    ]);
    let tum = |p: &Path| std::fs::read_to_string(p.join("ground_truth.tum")).unwrap();
    let (whole, part) = (tum(&node), tum(&window));
    let whole: Vec<&str> = whole.lines().skip(1).collect();
    let part: Vec<&str> = part.lines().skip(1).collect();
    assert_eq!(part.len(), 50);
    assert_eq!(part[..], whole[30..80]);
    let e = fails(&[
        "sense",
        arg(&world),
        "--out",
        arg(&dir.path().join("no")),
        "--route",
        "shaft",
    ]);
    assert!(e.contains("--platform aerial"), "{e}");
    let e = fails(&[
        "sense",
        arg(&world),
        "--out",
        arg(&dir.path().join("no")),
        "--route",
        "edge:99999",
    ]);
    assert!(e.contains("edge 99999 does not exist"), "{e}");
    let e = fails(&[
        "sense",
        arg(&world),
        "--out",
        arg(&dir.path().join("no")),
        "--start",
        "99999",
    ]);
    assert!(e.contains("--start 99999 s is out of bounds"), "{e}");
}
