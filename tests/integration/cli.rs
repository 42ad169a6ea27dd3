//! The command line as a user runs it: every example pipeline, the world folder it writes,
//! reproducibility across runs, imports, and the errors bad input gets.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{fails, folder_bytes, ok, subtgraph};

use subtgraph::core::npy;

fn examples() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> =
        std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("examples"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect();
    v.sort();
    assert!(v.len() >= 4, "the presets and at least one more example");
    v
}

/// Checks a world folder's files against each other; returns the topology document.
fn check_folder(dir: &Path) -> serde_json::Value {
    let toml_text = std::fs::read_to_string(dir.join("world.toml")).unwrap();
    let p = subtgraph::core::Pipeline::parse(&toml_text, "world.toml").unwrap();
    let levels = match p.world.levels {
        subtgraph::core::config::IntRange::Fixed(l) => l as usize,
        other => panic!("world.toml must have fixed levels, has {other:?}"),
    };
    let (rows, cols) = (
        p.world.rows.unwrap() as usize,
        p.world.cols.unwrap() as usize,
    );
    let source = p
        .generated
        .as_ref()
        .and_then(|g| g.source.clone())
        .unwrap_or_default();
    if !source.starts_with("import") {
        assert_eq!(
            p.topology.per_level.len(),
            levels,
            "per-level counts recorded"
        );
    }
    assert!(p.generated.is_some(), "tool version recorded");

    let grid = npy::decode(&std::fs::read(dir.join("occupancy.npy")).unwrap()).unwrap();
    assert_eq!(grid.dtype, "|u1");
    assert_eq!(grid.shape, vec![levels, rows, cols]);
    for v in &grid.values {
        assert!(
            [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 11.0, 111.0].contains(v),
            "code {v}"
        );
    }

    let topo: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("topology.json")).unwrap()).unwrap();
    assert_eq!(topo["connected"], true);
    assert_eq!(topo["levels"].as_u64().unwrap() as usize, levels);
    let occupied = grid.values.iter().filter(|&&v| v != 0.0).count();
    assert_eq!(topo["occupied_cells"].as_u64().unwrap() as usize, occupied);
    assert_eq!(topo["per_level"].as_array().unwrap().len(), levels);
    let edge_sum: f64 = topo["edges"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["length_m"].as_f64().unwrap())
        .sum();
    assert!((topo["total_length_m"].as_f64().unwrap() - edge_sum).abs() < 1e-6);
    assert!(edge_sum > 0.0);
    for l in topo["per_level"].as_array().unwrap() {
        let a = &l["achieved"];
        let at_least = |key: &str, shape: &str| {
            a[key].as_u64().unwrap() >= l["requested"][shape].as_u64().unwrap_or(0)
        };
        assert!(at_least("t_junctions", "t-junction"), "{l}");
        assert!(at_least("intersections", "intersection"), "{l}");
        assert!(at_least("loops", "loop"), "{l}");
    }
    // Nodes agree with the grid: every junction cell is a node of that kind.
    let t_cells = grid.values.iter().filter(|&&v| v == 4.0).count();
    let t_nodes = topo["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|n| n["kind"] == "t-junction")
        .count();
    assert_eq!(t_cells, t_nodes);

    for l in 0..levels {
        let png = std::fs::read(dir.join(format!("maps/level-{l}.png"))).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        let w = u32::from_be_bytes(png[16..20].try_into().unwrap()) as usize;
        let h = u32::from_be_bytes(png[20..24].try_into().unwrap()) as usize;
        assert_eq!(w / cols, h / rows, "square cells");
        assert!(w >= cols * 6);
    }
    assert!(!dir.join(format!("maps/level-{levels}.png")).exists());
    topo
}

#[test]
fn every_example_pipeline_makes_a_complete_world_and_regenerates_from_world_toml() {
    let tmp = tempfile::tempdir().unwrap();
    for example in examples() {
        let name = example.file_stem().unwrap().to_string_lossy().into_owned();
        let text = std::fs::read_to_string(&example).unwrap();
        let darpa = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/darpa-subt-tiles");
        if text.contains("darpa-cave-type-b") && !darpa.is_dir() {
            eprintln!("skipping {name}: {} is absent", darpa.display());
            continue;
        }
        let out = tmp.path().join(&name);
        let stdout = ok(&[
            "generate",
            example.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(stdout.contains("wrote"), "{stdout}");
        check_folder(&out);

        // world.toml regenerates the same files (world.toml itself differs only in source).
        let again = tmp.path().join(format!("{name}-again"));
        ok(&[
            "generate",
            out.join("world.toml").to_str().unwrap(),
            "--out",
            again.to_str().unwrap(),
        ]);
        let mut files = vec!["occupancy.npy", "topology.json", "maps/level-0.png"];
        if out.join("mesh").is_dir() {
            files.extend(["mesh/world.obj", "mesh/collision.obj", "mesh/world.mtl"]);
        }
        for f in files {
            assert_eq!(
                std::fs::read(out.join(f)).unwrap(),
                std::fs::read(again.join(f)).unwrap(),
                "{name}: {f} differs when regenerated from world.toml"
            );
        }
    }
}

#[test]
fn the_same_command_twice_gives_byte_identical_folders() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    for out in [&a, &b] {
        ok(&[
            "generate",
            "--preset",
            "lava-tube",
            "--seed",
            "99",
            "--out",
            out.to_str().unwrap(),
        ]);
    }
    common::assert_same_files(&a, &b, &[]);
    // Another seed, another grid (the grid is all this looks at: no mesh).
    let c = tmp.path().join("c");
    ok(&[
        "generate",
        "--preset",
        "lava-tube",
        "--seed",
        "100",
        "--no-mesh",
        "--out",
        c.to_str().unwrap(),
    ]);
    assert_ne!(
        std::fs::read(a.join("occupancy.npy")).unwrap(),
        std::fs::read(c.join("occupancy.npy")).unwrap()
    );
    let toml = std::fs::read_to_string(a.join("world.toml")).unwrap();
    assert!(toml.contains("seed = 99"), "{toml}");
}

#[test]
fn the_built_in_defaults_make_a_world() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("default");
    ok(&["generate", "--out", out.to_str().unwrap()]);
    check_folder(&out);
}

#[test]
fn an_existing_folder_is_refused_without_force_and_replaced_with_it() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("w");
    let o = out.to_str().unwrap();
    ok(&["generate", "--preset", "cave", "--out", o]);
    let before = folder_bytes(&out);
    let err = fails(&["generate", "--preset", "cave", "--seed", "5", "--out", o]);
    assert!(
        err.contains("already exists") && err.contains("--force"),
        "{err}"
    );
    assert_eq!(folder_bytes(&out), before, "untouched");
    ok(&[
        "generate", "--preset", "cave", "--seed", "5", "--out", o, "--force",
    ]);
    assert_ne!(folder_bytes(&out), before);
    assert_eq!(
        std::fs::read_dir(tmp.path()).unwrap().count(),
        1,
        "no leftovers"
    );

    let precious = tmp.path().join("notes");
    std::fs::create_dir(&precious).unwrap();
    std::fs::write(precious.join("a.txt"), "keep me").unwrap();
    let err = fails(&["generate", "--out", precious.to_str().unwrap(), "--force"]);
    assert!(err.contains("not a folder written by subtgraph"), "{err}");
    assert!(precious.join("a.txt").exists());
}

#[test]
fn a_failed_run_leaves_nothing_behind() {
    let tmp = tempfile::tempdir().unwrap();
    let pipeline = tmp.path().join("crowded.toml");
    std::fs::write(
        &pipeline,
        "[world]\nrows = 10\ncols = 10\nattempts = 8\n[topology]\nloops = 2\nt_junctions = 3\nintersections = 3\nexact = true\n",
    )
    .unwrap();
    let out = tmp.path().join("w");
    let err = fails(&[
        "generate",
        pipeline.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        err.contains("level 0") && err.contains("larger grid"),
        "{err}"
    );
    let left: Vec<_> = std::fs::read_dir(tmp.path()).unwrap().collect();
    assert_eq!(left.len(), 1, "only the pipeline file remains");
}

#[test]
fn bad_pipelines_get_errors_naming_file_line_column_and_key() {
    let tmp = tempfile::tempdir().unwrap();
    let cases = [
        ("[world]\nseed = 1\nlevles = 2\n", "3:1", "world.levles"),
        ("[topology]\nloops = [2, 1]\n", "2:9", "topology.loops"),
        (
            "[route]\ntype = \"sine\"\namplitud = 2\n",
            "3:1",
            "route.amplitud",
        ),
        ("[route]\ntype = \"meander\"\n", "1:1", "route.type"),
        ("[world]\nrows = 30\n", "2:1", "world.rows"),
    ];
    for (i, (text, at, key)) in cases.iter().enumerate() {
        let f = tmp.path().join(format!("bad{i}.toml"));
        std::fs::write(&f, text).unwrap();
        let err = fails(&["validate", f.to_str().unwrap()]);
        let want = format!("bad{i}.toml:{at}: {key}");
        assert!(err.contains(&want), "want `{want}` in: {err}");
        let err = fails(&[
            "generate",
            f.to_str().unwrap(),
            "--out",
            tmp.path().join("x").to_str().unwrap(),
        ]);
        assert!(err.contains(&want), "{err}");
    }
    let err = fails(&["validate", tmp.path().join("bad3.toml").to_str().unwrap()]);
    assert!(
        err.contains("known: harmonic, linear, parabolic, sine"),
        "{err}"
    );
    let err = fails(&["generate", "--preset", "ice-cave", "--out", "x"]);
    assert!(err.contains("mine, cave, lava-tube"), "{err}");
    let err = fails(&["validate", "no/such/file.toml"]);
    assert!(err.contains("no/such/file.toml"), "{err}");
}

#[test]
fn validate_and_presets_and_help() {
    let out = ok(&["validate", "examples/exact-loops.toml"]);
    assert!(out.contains("valid"), "{out}");
    let out = ok(&["presets"]);
    for p in ["mine", "cave", "lava-tube"] {
        assert!(out.contains(p), "{out}");
    }
    for cmd in [
        vec!["--help"],
        vec!["generate", "--help"],
        vec!["validate", "--help"],
        vec!["presets", "--help"],
    ] {
        let out = ok(&cmd);
        assert!(out.contains("Usage"), "{out}");
    }
    assert!(ok(&["generate", "--help"]).contains("--occupancy"));
}

fn npy_i64(shape: &[usize], values: &[i64]) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let data: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    common::npy_bytes("<i8", &format!("({})", dims.join(", ")), &data)
}

#[test]
fn imports_reproduce_a_world_and_read_the_originals_encodings() {
    let tmp = tempfile::tempdir().unwrap();
    let made = tmp.path().join("made");
    ok(&[
        "generate",
        "--preset",
        "mine",
        "--out",
        made.to_str().unwrap(),
    ]);
    let imported = tmp.path().join("imported");
    ok(&[
        "generate",
        "--preset",
        "mine",
        "--no-mesh",
        "--occupancy",
        made.join("occupancy.npy").to_str().unwrap(),
        "--out",
        imported.to_str().unwrap(),
    ]);
    assert_eq!(
        std::fs::read(made.join("occupancy.npy")).unwrap(),
        std::fs::read(imported.join("occupancy.npy")).unwrap(),
        "spatial codes survive the round trip"
    );
    let a = check_folder(&made);
    let b = check_folder(&imported);
    for (la, lb) in a["per_level"]
        .as_array()
        .unwrap()
        .iter()
        .zip(b["per_level"].as_array().unwrap())
    {
        assert_eq!(la["achieved"], lb["achieved"]);
    }
    assert_eq!(
        a["edges"].as_array().unwrap().len(),
        b["edges"].as_array().unwrap().len()
    );
    // The imported mine's ramps get spiral blocks too (the grid left them empty).
    for s in b["shafts"].as_array().unwrap() {
        assert!(s["block"].is_array(), "no spiral block: {s}");
    }

    // The original's topological encoding (0 / 1 edge / 10 node), two levels, int64.
    let level = [
        0, 0, 0, 0, 0, //
        0, 10, 1, 10, 0, //
        0, 1, 0, 1, 0, //
        0, 10, 1, 10, 0, //
        0, 0, 10, 0, 0,
    ];
    let mut two = level.to_vec();
    two.extend_from_slice(&[
        0, 0, 0, 0, 0, 0, 10, 1, 10, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    ]);
    let f = tmp.path().join("original.npy");
    std::fs::write(&f, npy_i64(&[2, 5, 5], &two)).unwrap();
    let out = tmp.path().join("orig");
    let o = subtgraph(&[
        "generate",
        "--occupancy",
        f.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("Topological"));
    let topo: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("topology.json")).unwrap()).unwrap();
    assert_eq!(topo["per_level"][0]["achieved"]["loops"], 1);
    assert_eq!(topo["shafts"].as_array().unwrap().len(), 1);

    // Bad input: a value outside every encoding, a wrong shape, not an npy at all.
    let x = tmp.path().join("x");
    let import_fails = |bytes: &[u8]| {
        std::fs::write(&f, bytes).unwrap();
        fails(&[
            "generate",
            "--occupancy",
            f.to_str().unwrap(),
            "--out",
            x.to_str().unwrap(),
        ])
    };
    let err = import_fails(&npy_i64(&[2, 2], &[0, 1, 7, 0]));
    assert!(err.contains("value 7 at [level 0, row 1, col 0]"), "{err}");
    let err = import_fails(&npy_i64(&[2, 2, 2, 2], &[1; 16]));
    assert!(
        err.contains("expected [rows, cols] or [levels, rows, cols]"),
        "{err}"
    );
    let err = import_fails(b"not numpy");
    assert!(err.contains("not a .npy file"), "{err}");
    assert!(!tmp.path().join("x").exists());
}

/// numpy itself reads `occupancy.npy`. The test command installs numpy; run alone without it,
/// this test says so and passes unless `SUBTGRAPH_REQUIRE_PYTHON=1`.
#[test]
fn numpy_reads_the_occupancy_grid() {
    let python = std::env::var("SUBTGRAPH_PYTHON").unwrap_or_else(|_| "python3".into());
    let has_numpy = Command::new(&python)
        .args(["-c", "import numpy"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !has_numpy {
        assert!(
            std::env::var("SUBTGRAPH_REQUIRE_PYTHON").is_err(),
            "{python} cannot import numpy; run scripts/test, which sets up .venv"
        );
        eprintln!("skipping: {python} has no numpy (scripts/test installs it)");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("w");
    // The grid alone (--no-mesh): the lava tube's meshes would add 650 MB nobody reads here.
    ok(&[
        "generate",
        "--preset",
        "lava-tube",
        "--no-mesh",
        "--out",
        out.to_str().unwrap(),
    ]);
    let topo: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("topology.json")).unwrap()).unwrap();
    let script = format!(
        "import numpy as np, json\n\
         a = np.load(r'{}')\n\
         assert a.dtype == np.uint8, a.dtype\n\
         print(json.dumps({{'shape': list(a.shape), 'occupied': int((a > 0).sum()), \
         'up': int((a == 11).sum()), 'landing': int((a == 111).sum()), 't': int((a == 4).sum())}}))",
        out.join("occupancy.npy").display()
    );
    let o = Command::new(&python)
        .args(["-c", &script])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let got: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(
        got["shape"],
        serde_json::json!([topo["levels"], topo["rows"], topo["cols"]])
    );
    assert_eq!(got["occupied"], topo["occupied_cells"]);
    assert_eq!(got["up"], 4);
    assert_eq!(got["landing"], 4);
    let t: u64 = topo["per_level"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["achieved"]["t_junctions"].as_u64().unwrap())
        .sum();
    assert_eq!(got["t"], t);
}
