//! `subtgraph explore`, `score --run` and `dataset --explore`: the closed loop's run folders
//! checked by an independent reader (tests/readers/explore_check.py: trimesh for the poses'
//! clearance and the radio's lines of sight, numpy for the artifacts found over a link and the
//! explored share), the same bytes on one and three threads, `report` over the scores, and bad
//! input refused with what to change and nothing written.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::{self, arg, fails, folder_bytes, ok, read_with_python};

/// A small cave with artifacts and ground truth, in `dir`.
fn small_world(dir: &Path, name: &str) -> PathBuf {
    let pipeline = common::small_cave_pipeline(
        dir,
        1,
        "[artifacts]\ncount = 8\nmin_distance_from_start = 10\nmin_spacing = 5\n",
    );
    let out = dir.join(name);
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

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

/// `explore` with `RAYON_NUM_THREADS` set.
fn explore_threads(threads: &str, args: &[&str]) {
    let out = Command::new(common::binary())
        .env("RAYON_NUM_THREADS", threads)
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_run_is_scored_as_darpa_scored_and_checked_by_trimesh_and_numpy() {
    let dir = tempfile::tempdir().unwrap();
    let world = small_world(dir.path(), "w");
    let run = dir.path().join("run");
    let said = ok(&[
        "explore",
        arg(&world),
        "--robots",
        "2",
        "--duration",
        "120",
        "--out",
        arg(&run),
    ]);
    assert!(said.contains("explored 120 simulated s"), "{said}");
    let meta = json(&run.join("run.json"));
    assert_eq!(meta["robots"], 2);
    assert_eq!(meta["policy"], "frontier");
    assert!(
        meta["radio"]["source"]
            .as_str()
            .unwrap()
            .contains("osrf/subt")
    );
    let driven: f64 = meta["per_robot"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["distance_m"].as_f64().unwrap())
        .sum();
    // Two robots for two minutes at up to 2 m/s: they go somewhere, within their limits.
    assert!(
        driven > 40.0 && driven < 2.0 * 2.0 * 120.0 + 1.0,
        "{driven}"
    );
    for f in [
        "robot-0.tum",
        "robot-1.tum",
        "map.ply",
        "explored.npy",
        "reports.csv",
        "radio.csv",
        "connectivity.csv",
    ] {
        assert!(run.join(f).is_file(), "{f}");
    }
    let scored = dir.path().join("scored");
    let said = ok(&[
        "score",
        arg(&world),
        "--run",
        arg(&run),
        "--out",
        arg(&scored),
    ]);
    assert!(
        said.contains("explored:") && said.contains("radio:"),
        "{said}"
    );
    let r = json(&scored.join("run.json"));
    let explored = r["explored"]["coverage"].as_f64().unwrap();
    assert!(explored > 0.01 && explored <= 1.0, "{r}");
    if let Some(out) = read_with_python(
        &["numpy", "trimesh", "rtree"],
        "explore_check.py",
        &[arg(&world), arg(&run), arg(&scored)],
    ) {
        let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
        assert!(v["poses_checked"].as_u64().unwrap() > 100, "{v}");
        assert!(v["links_checked"].as_u64().unwrap() > 0, "{v}");
    }
}

#[test]
fn the_same_run_on_one_and_three_threads_and_bad_input_refused() {
    let dir = tempfile::tempdir().unwrap();
    let world = small_world(dir.path(), "w");
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    for (threads, out) in [("1", &a), ("3", &b)] {
        explore_threads(
            threads,
            &[
                "explore",
                arg(&world),
                "--robots",
                "3",
                "--duration",
                "40",
                "--out",
                arg(out),
            ],
        );
    }
    assert_eq!(folder_bytes(&a), folder_bytes(&b));
    // The random policy writes a run too.
    let random = dir.path().join("random");
    ok(&[
        "explore",
        arg(&world),
        "--planner",
        "random",
        "--duration",
        "20",
        "--out",
        arg(&random),
    ]);
    assert_eq!(json(&random.join("run.json"))["policy"], "random");
    // A world without ground truth: refused, saying how to make it.
    let bare = dir.path().join("bare");
    let pipeline = common::small_cave_pipeline(dir.path(), 1, "");
    ok(&["generate", arg(&pipeline), "--out", arg(&bare)]);
    let no = dir.path().join("no");
    let e = fails(&["explore", arg(&bare), "--out", arg(&no)]);
    assert!(
        e.contains("ground truth") && e.contains("--format ground-truth"),
        "{e}"
    );
    assert!(!no.exists());
    for (flag, value, said) in [
        ("--planner", "greedy", "frontier, random"),
        ("--platform", "submarine", "ground, aerial"),
        ("--lidar", "os9", "vlp-16"),
        ("--robots", "0", "1 to 16"),
        ("--duration", "NaN", "--duration"),
        ("--lidar-columns", "7", "16 to 1800"),
    ] {
        let e = fails(&["explore", arg(&world), flag, value, "--out", arg(&no)]);
        assert!(e.contains(said), "{flag} {value}: {e}");
        assert!(!no.exists());
    }
    // An existing run is replaced only with --force.
    let e = fails(&["explore", arg(&world), "--duration", "5", "--out", arg(&a)]);
    assert!(e.contains("--force"), "{e}");
    // A run folder without its radio log cannot be scored as one.
    std::fs::remove_file(random.join("connectivity.csv")).unwrap();
    let e = fails(&[
        "score",
        arg(&world),
        "--run",
        arg(&random),
        "--out",
        arg(&dir.path().join("s")),
    ]);
    assert!(e.contains("connectivity.csv"), "{e}");
}

#[test]
fn a_dataset_is_explored_scored_and_reported() {
    let dir = tempfile::tempdir().unwrap();
    let pipeline = common::small_cave_pipeline(
        dir.path(),
        1,
        "[artifacts]\ncount = 6\nmin_distance_from_start = 10\nmin_spacing = 5\n",
    );
    let data = dir.path().join("data");
    let said = ok(&[
        "dataset",
        arg(&pipeline),
        "--count",
        "2",
        "--seed",
        "3",
        "--explore",
        "--robots",
        "2",
        "--explore-duration",
        "60",
        "--out",
        arg(&data),
    ]);
    assert!(said.contains("explored 2 world(s)"), "{said}");
    let names = ["small-cave-0000", "small-cave-0001"];
    for name in names {
        let (world, run, score) = (
            data.join(name),
            data.join("runs").join(name),
            data.join("scores").join(name),
        );
        assert!(world.join("ground_truth/artifacts.json").is_file());
        read_with_python(
            &["numpy", "trimesh", "rtree"],
            "explore_check.py",
            &[arg(&world), arg(&run), arg(&score)],
        );
    }
    // Again: everything is kept.
    let said = ok(&[
        "dataset",
        arg(&pipeline),
        "--count",
        "2",
        "--seed",
        "3",
        "--explore",
        "--robots",
        "2",
        "--explore-duration",
        "60",
        "--out",
        arg(&data),
    ]);
    assert!(
        said.contains("explored 0 world(s)") && said.contains("kept 2"),
        "{said}"
    );
    let report = dir.path().join("report");
    let said = ok(&[
        "report",
        &format!("frontier={}", arg(&data.join("scores"))),
        "--out",
        arg(&report),
    ]);
    assert!(said.contains("2 world(s)"), "{said}");
    let r = std::fs::read_to_string(report.join("report.json")).unwrap();
    assert!(
        r.contains("run.explored.coverage"),
        "the report has the explored share"
    );
}
