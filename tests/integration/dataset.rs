//! `subtgraph dataset`: worlds independent of jobs and shards, resumable, refusing bad
//! shard specs and unwritable folders, every world reproducible from its own `world.toml`.

use crate::common;

use std::collections::BTreeSet;
use std::path::Path;

use common::{arg, fails, folder_bytes, ok};

/// Every world folder of a dataset, bytes and all: the index (timings) and the run facts
/// (`.index/`) left out.
fn worlds(dir: &Path) -> Vec<(String, Vec<u8>)> {
    folder_bytes(dir)
        .into_iter()
        .filter(|(p, _)| !p.starts_with("index.") && !p.starts_with(".index"))
        .collect()
}

fn index(dir: &Path) -> Vec<serde_json::Value> {
    let text = std::fs::read_to_string(dir.join("index.json")).unwrap();
    serde_json::from_str::<serde_json::Value>(&text)
        .unwrap()
        .as_array()
        .unwrap()
        .clone()
}

fn dataset(out: &Path, extra: &[&str]) -> String {
    let mut args = vec![
        "dataset",
        "--preset",
        "cave",
        "--preset",
        "mine",
        "--count",
        "3",
        "--seed",
        "11",
        "--no-mesh",
        "--out",
    ];
    args.push(arg(out));
    args.extend_from_slice(extra);
    ok(&args)
}

#[test]
fn jobs_and_shards_do_not_change_the_worlds() {
    let tmp = tempfile::tempdir().unwrap();
    let one = tmp.path().join("one");
    let two = tmp.path().join("two");
    let sharded = tmp.path().join("sharded");
    dataset(&one, &["--jobs", "1"]);
    dataset(&two, &["--jobs", "2"]);
    dataset(&sharded, &["--jobs", "2", "--shard", "2/2"]);
    // The second shard's index lists only its share so far...
    assert_eq!(index(&sharded).len(), 3);
    dataset(&sharded, &["--jobs", "1", "--shard", "1/2"]);
    let a = worlds(&one);
    // world.toml, occupancy.npy, topology.json, the list of written files and a map per
    // level: 3 caves of 1 level, 3 mines of 3.
    assert_eq!(a.len(), 3 * (4 + 1) + 3 * (4 + 3));
    assert!(a == worlds(&two), "--jobs 1 and --jobs 2 differ");
    assert!(
        a == worlds(&sharded),
        "shards 1/2 + 2/2 differ from one run"
    );
    // ...and the last shard's index lists them all, like the unsharded run's.
    let names = |d: &Path| -> Vec<String> {
        index(d)
            .iter()
            .map(|r| r["name"].as_str().unwrap().to_owned())
            .collect()
    };
    assert_eq!(names(&sharded), names(&one));
    assert_eq!(
        names(&one),
        [
            "cave-0000",
            "cave-0001",
            "cave-0002",
            "mine-0000",
            "mine-0001",
            "mine-0002"
        ]
    );
    let csv = std::fs::read_to_string(one.join("index.csv")).unwrap();
    assert_eq!(csv.lines().count(), 7);
    assert!(csv.starts_with("name,source,seed,levels,"));
}

#[test]
fn resuming_redoes_exactly_the_missing_world() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("d");
    dataset(&out, &[]);
    let before = worlds(&out);
    let kept = std::fs::metadata(out.join("mine-0002/occupancy.npy"))
        .unwrap()
        .modified()
        .unwrap();
    std::fs::remove_dir_all(out.join("cave-0001")).unwrap();
    // An interrupted write (hidden temporary folder of a process that is gone) and a world
    // missing a file.
    let mut gone = std::process::Command::new("true").spawn().unwrap();
    let dead_pid = gone.id();
    gone.wait().unwrap();
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap();
    let partial = out.join(format!(".mine-0000.partial-{dead_pid}-1"));
    std::fs::create_dir(&partial).unwrap();
    std::fs::write(partial.join("occupancy.npy"), b"half").unwrap();
    std::fs::write(
        partial.join(".subtgraph-files"),
        format!("partial host={} pid={dead_pid} start=1\n", host.trim()),
    )
    .unwrap();
    // A look-alike without our marker is someone else's: left alone.
    let lookalike = out.join(".notes.partial-1-1");
    std::fs::create_dir(&lookalike).unwrap();
    std::fs::remove_file(out.join("mine-0000/world.toml")).unwrap();
    // An index cut short by a crash is rebuilt.
    std::fs::write(out.join("index.json"), b"[{\"name\": ").unwrap();

    let text = dataset(&out, &[]);
    assert!(
        text.contains("made 2 world(s), kept 4 complete one(s)"),
        "{text}"
    );
    assert!(!partial.exists(), "the leftover is removed");
    assert!(lookalike.exists(), "what is not ours stays");
    assert!(before == worlds(&out), "the redone worlds are the same");
    let again = std::fs::metadata(out.join("mine-0002/occupancy.npy"))
        .unwrap()
        .modified()
        .unwrap();
    assert_eq!(kept, again, "complete worlds are not rewritten");
    assert_eq!(index(&out).len(), 6);
}

#[test]
fn seeds_are_distinct_and_each_world_regenerates_from_its_world_toml() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("d");
    dataset(&out, &[]);
    let rows = index(&out);
    let seeds: BTreeSet<u64> = rows.iter().map(|r| r["seed"].as_u64().unwrap()).collect();
    assert_eq!(seeds.len(), 6, "{seeds:?}");
    for r in &rows {
        let name = r["name"].as_str().unwrap();
        let world = out.join(name);
        let toml = std::fs::read_to_string(world.join("world.toml")).unwrap();
        assert!(toml.contains(&format!("seed = {}", r["seed"])), "{toml}");
        // The index agrees with the folder.
        let topo: serde_json::Value =
            serde_json::from_slice(&std::fs::read(world.join("topology.json")).unwrap()).unwrap();
        assert_eq!(r["occupied_cells"], topo["occupied_cells"]);
        assert_eq!(r["total_length_m"], topo["total_length_m"]);
        let again = tmp.path().join(format!("again-{name}"));
        ok(&[
            "generate",
            arg(&world.join("world.toml")),
            "--no-mesh",
            "--out",
            arg(&again),
        ]);
        for file in ["occupancy.npy", "topology.json", "maps/level-0.png"] {
            assert!(
                std::fs::read(world.join(file)).unwrap()
                    == std::fs::read(again.join(file)).unwrap(),
                "{name}/{file} differs when regenerated from its world.toml"
            );
        }
    }
}

#[test]
fn bad_shards_and_unwritable_folders_are_refused_and_leave_the_index_alone() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("d");
    dataset(&out, &["--shard", "1/3"]);
    let index_before = std::fs::read(out.join("index.json")).unwrap();
    for bad in ["5/4", "0/2", "a/b", "3", "1/0"] {
        let e = fails(&[
            "dataset",
            "--preset",
            "cave",
            "--count",
            "2",
            "--no-mesh",
            "--shard",
            bad,
            "--out",
            arg(&out),
        ]);
        assert!(e.contains("--shard I/N"), "{bad}: {e}");
    }
    assert_eq!(std::fs::read(out.join("index.json")).unwrap(), index_before);

    // --out under a file, and --out a file.
    let file = tmp.path().join("a-file");
    std::fs::write(&file, b"x").unwrap();
    let e = fails(&[
        "dataset",
        "--preset",
        "cave",
        "--count",
        "1",
        "--no-mesh",
        "--out",
        arg(&file.join("d")),
    ]);
    assert!(e.contains("cannot create the dataset folder"), "{e}");
    let e = fails(&[
        "dataset",
        "--preset",
        "cave",
        "--count",
        "1",
        "--out",
        arg(&file),
    ]);
    assert!(e.contains("is a file"), "{e}");
    assert_eq!(std::fs::read(&file).unwrap(), b"x");

    // A folder of another dataset (another base seed) is not mixed in.
    let e = fails(&[
        "dataset",
        "--preset",
        "cave",
        "--count",
        "2",
        "--seed",
        "12",
        "--no-mesh",
        "--out",
        arg(&out),
    ]);
    assert!(e.contains("belongs to another dataset"), "{e}");
    assert_eq!(std::fs::read(out.join("index.json")).unwrap(), index_before);
}

#[test]
fn a_meshed_dataset_records_triangles_and_exports() {
    let tmp = tempfile::tempdir().unwrap();
    let pipeline = common::small_cave_pipeline(tmp.path(), 1, "[[export]]\ntype = \"obj\"\n");
    let out = tmp.path().join("d");
    ok(&[
        "dataset",
        arg(&pipeline),
        "--count",
        "2",
        "--seed",
        "3",
        "--jobs",
        "2",
        "--out",
        arg(&out),
    ]);
    let rows = index(&out);
    assert_eq!(rows.len(), 2);
    for r in &rows {
        assert_eq!(r["source"], "small-cave");
        let name = r["name"].as_str().unwrap();
        let obj = std::fs::read_to_string(out.join(name).join("mesh/world.obj")).unwrap();
        let faces = obj.lines().filter(|l| l.starts_with("f ")).count();
        assert_eq!(r["visual_triangles"].as_u64().unwrap() as usize, faces);
        assert!(r["generation_s"].as_f64().unwrap() > 0.0);
    }
}

#[test]
fn the_paper_configurations_make_worlds_with_the_presets_parameters() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("paper");
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/datasets");
    let files: Vec<String> = ["mine", "cave", "lava-tube"]
        .iter()
        .map(|p| root.join(format!("paper-{p}.toml")).display().to_string())
        .collect();
    let mut args = vec!["dataset"];
    args.extend(files.iter().map(String::as_str));
    args.extend(["--count", "2", "--no-mesh", "--out", arg(&out)]);
    ok(&args);
    for (source, levels, sides) in [
        ("paper-mine", 3, 44..=63),
        ("paper-cave", 1, 31..=44),
        ("paper-lava-tube", 5, 54..=70),
    ] {
        let rows: Vec<serde_json::Value> = index(&out)
            .into_iter()
            .filter(|r| r["source"] == source)
            .collect();
        assert_eq!(rows.len(), 2, "{source}");
        for r in rows {
            assert_eq!(r["levels"], levels, "{source}");
            assert!(
                sides.contains(&r["rows"].as_u64().unwrap()),
                "{source}: {r}"
            );
        }
        // Each configuration asks for a mesh and an OBJ export.
        let text = std::fs::read_to_string(root.join(format!("{source}.toml"))).unwrap();
        assert!(text.contains("[tileset]") && text.contains("type = \"obj\""));
    }
}

/// Resuming compares every kept world with what this run would make: other options are
/// refused naming the difference (nothing deleted), a damaged world is made again, and a
/// folder that holds a user's files is never used as a dataset folder.
#[test]
fn resuming_keeps_only_worlds_this_run_would_make() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("d");
    let base = [
        "dataset", "--preset", "cave", "--count", "2", "--seed", "5", "--out",
    ];
    let run = |extra: &[&'static str]| -> Vec<String> {
        let mut a: Vec<String> = base.iter().map(|s| s.to_string()).collect();
        a.push(arg(&out).to_owned());
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let ok = |a: Vec<String>| ok(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let fails = |a: Vec<String>| fails(&a.iter().map(String::as_str).collect::<Vec<_>>());
    ok(run(&["--no-mesh"]));
    let before = worlds(&out);

    // Another tile set or another format: refused, saying what differs; nothing changed.
    // (The mine tile set also joins levels by ramps: the first line that differs is that.)
    let e = fails(run(&["--tileset", "mine"]));
    assert!(
        e.contains("made with other options")
            && (e.contains("mine") || e.contains("connections = \"ramp\"")),
        "{e}"
    );
    let e = fails(run(&["--no-mesh", "--format", "graph"]));
    assert!(
        e.contains("made with other options") && e.contains("export"),
        "{e}"
    );
    assert!(before == worlds(&out), "a refused run changes nothing");

    // A world missing a file, and one with a file cut short: made again, and the same.
    std::fs::remove_file(out.join("cave-0000/topology.json")).unwrap();
    let npy = out.join("cave-0001/occupancy.npy");
    let bytes = std::fs::read(&npy).unwrap();
    std::fs::write(&npy, &bytes[..bytes.len() / 2]).unwrap();
    let text = ok(run(&["--no-mesh"]));
    assert!(text.contains("made 2 world(s), kept 0"), "{text}");
    assert!(before == worlds(&out), "the redone worlds are the same");
    assert_eq!(index(&out).len(), 2);

    // A damaged world holding a file of the user's is not replaced.
    std::fs::remove_file(out.join("cave-0000/topology.json")).unwrap();
    std::fs::write(out.join("cave-0000/my-notes.txt"), "mine").unwrap();
    let e = fails(run(&["--no-mesh"]));
    assert!(e.contains("my-notes.txt"), "{e}");
    assert!(out.join("cave-0000/my-notes.txt").is_file());

    // A folder of the user's is not a dataset folder.
    let mine = tmp.path().join("mine");
    std::fs::create_dir(&mine).unwrap();
    std::fs::write(mine.join("index.json"), "my index").unwrap();
    let e = common::fails(&[
        "dataset",
        "--preset",
        "cave",
        "--count",
        "1",
        "--no-mesh",
        "--out",
        arg(&mine),
    ]);
    assert!(e.contains("not this dataset's (index.json)"), "{e}");
    assert_eq!(
        std::fs::read_to_string(mine.join("index.json")).unwrap(),
        "my index"
    );
}

/// The id of a process that has ended: a child that has run and been waited for.
fn dead_pid() -> u32 {
    let mut child = std::process::Command::new("true").spawn().unwrap();
    let pid = child.id();
    child.wait().unwrap();
    pid
}

#[test]
fn a_world_another_process_is_writing_is_left_to_it_and_stale_leftovers_are_redone() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("d");
    std::fs::create_dir(&out).unwrap();
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap();
    let partial = |name: &str, pid: u32| {
        let dir = out.join(format!(".{name}.partial-{pid}-1"));
        std::fs::create_dir(&dir).unwrap();
        std::fs::write(dir.join("occupancy.npy"), b"being written").unwrap();
        std::fs::write(
            dir.join(".subtgraph-files"),
            format!("partial host={} pid={pid} start=0\n", host.trim()),
        )
        .unwrap();
        dir
    };
    // Another process on this machine (this test's, which is alive) is writing cave-0001...
    let live = partial("cave-0001", std::process::id());
    // ...and a process that is gone left mine-0002 half written.
    let stale = partial("mine-0002", dead_pid());
    // A shard starting at the same moment has its write probe there.
    std::fs::write(out.join(".write-test-1"), b"").unwrap();

    let run = common::subtgraph(&[
        "dataset",
        "--preset",
        "cave",
        "--preset",
        "mine",
        "--count",
        "3",
        "--seed",
        "11",
        "--no-mesh",
        "--out",
        arg(&out),
    ]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(run.status.success(), "{stderr}");
    assert_eq!(
        std::fs::read(live.join("occupancy.npy")).unwrap(),
        b"being written",
        "another process's partial folder is not touched"
    );
    assert!(
        !out.join("cave-0001").exists(),
        "a world being made elsewhere is left to it"
    );
    assert!(
        stderr.contains("cave-0001") && stderr.contains(&std::process::id().to_string()),
        "the run says which world another process is making: {stderr}"
    );
    assert!(
        !stale.exists(),
        "the leftover of a process that is gone is removed"
    );
    assert!(
        out.join("mine-0002/world.toml").is_file(),
        "and its world made"
    );
    assert!(stdout.contains("made 5 world(s)"), "{stdout}");
    assert!(
        !stderr.contains("--force"),
        "dataset has no --force: {stderr}"
    );
}

#[test]
fn shards_and_an_unsharded_run_filling_one_folder_together_all_succeed() {
    let tmp = tempfile::tempdir().unwrap();
    let one = tmp.path().join("one");
    let shared = tmp.path().join("shared");
    let base = |out: &Path| -> Vec<String> {
        [
            "dataset",
            "--preset",
            "cave",
            "--preset",
            "mine",
            "--count",
            "40",
            "--seed",
            "5",
            "--no-mesh",
            "--jobs",
            "1",
            "--out",
        ]
        .iter()
        .map(|s| (*s).to_owned())
        .chain([arg(out).to_owned()])
        .collect()
    };
    ok(&base(&one).iter().map(String::as_str).collect::<Vec<_>>());
    // Three shards and two unsharded runs at once, into one folder.
    let mut runs = Vec::new();
    for extra in [
        &["--shard", "1/3"][..],
        &["--shard", "2/3"],
        &["--shard-index", "2", "--shard-count", "3"],
        &[],
        &[],
    ] {
        let mut args = base(&shared);
        args.extend(extra.iter().map(|s| (*s).to_owned()));
        runs.push(
            std::process::Command::new(env!("CARGO_BIN_EXE_subtgraph"))
                .args(&args)
                .stdout(std::process::Stdio::piped())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .unwrap(),
        );
    }
    for run in runs {
        let out = run.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{stderr}");
        assert!(!stderr.contains("--force"), "{stderr}");
    }
    // Whatever the interleaving, the folder holds exactly the one-process run's worlds.
    assert!(
        worlds(&one) == worlds(&shared),
        "the worlds differ from one run"
    );
    let leftovers: Vec<String> = std::fs::read_dir(&shared)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".partial-") || n.contains(".tmp-"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[test]
fn shard_index_and_count_are_zero_based_like_kubernetes() {
    let tmp = tempfile::tempdir().unwrap();
    let a = tmp.path().join("a");
    let b = tmp.path().join("b");
    // JOB_COMPLETION_INDEX 0 of 2 is --shard 1/2.
    dataset(&a, &["--shard-index", "0", "--shard-count", "2"]);
    dataset(&b, &["--shard", "1/2"]);
    assert!(worlds(&a) == worlds(&b));
    assert_eq!(index(&a).len(), 3);
    let bad = |extra: &[&str]| {
        let mut args = vec![
            "dataset",
            "--preset",
            "cave",
            "--count",
            "2",
            "--no-mesh",
            "--out",
            arg(&a),
        ];
        args.extend_from_slice(extra);
        fails(&args)
    };
    let e = bad(&["--shard-index", "2", "--shard-count", "2"]);
    assert!(
        e.contains("--shard-index 2 is out of range for --shard-count 2") && e.contains("0-based"),
        "{e}"
    );
    for (extra, says) in [
        (
            &["--shard-index", "-1", "--shard-count", "2"][..],
            "--shard-index '-1'",
        ),
        (
            &["--shard-index", "0", "--shard-count", "0"],
            "--shard-count '0'",
        ),
        (
            &["--shard-index", "x", "--shard-count", "2"],
            "--shard-index 'x'",
        ),
    ] {
        let e = bad(extra);
        assert!(
            e.contains(says) && e.contains("JOB_COMPLETION_INDEX"),
            "{extra:?}: {e}"
        );
    }
    // One spelling at a time, and both halves of the 0-based one.
    let e = bad(&["--shard", "1/2", "--shard-index", "0", "--shard-count", "2"]);
    assert!(e.contains("cannot be used with"), "{e}");
    let e = bad(&["--shard-index", "0"]);
    assert!(e.contains("--shard-count"), "{e}");
    let e = bad(&["--shard-count", "2"]);
    assert!(e.contains("--shard-index"), "{e}");
}

#[test]
fn the_note_about_a_skipped_exporter_is_printed_once() {
    let tmp = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/datasets");
    let files: Vec<String> = ["mine", "cave", "lava-tube"]
        .iter()
        .map(|p| root.join(format!("paper-{p}.toml")).display().to_string())
        .collect();
    let out = tmp.path().join("d");
    let mut args = vec!["dataset"];
    args.extend(files.iter().map(String::as_str));
    args.extend(["--count", "1", "--no-mesh", "--out", arg(&out)]);
    let run = common::subtgraph(&args);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert_eq!(
        stderr.matches("skipping exporter 'obj'").count(),
        1,
        "three sources export obj: one note\n{stderr}"
    );
}
