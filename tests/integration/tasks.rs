//! The `tasks` exporter (MovingAI planning benchmarks) through the command line, checked by an
//! independent A* written from MovingAI's definition (`tests/readers/tasks_check.py`) and by
//! ray parity on the collision surface.

use crate::common;

use std::path::{Path, PathBuf};

use common::{arg, assert_same_on_one_and_three_threads, fails, ok, read_with_python};

const READERS: &[&str] = &["numpy", "trimesh"];

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("subtgraph-tasks-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A preset's pipeline with a `tasks` export of small counts (the Python A* is slow) and the
/// collision surface the check reads (no visual OBJ: a lava tube's is about 500 MB).
fn preset_with_tasks(dir: &Path, preset: &str, seed: u64, keys: &str) -> PathBuf {
    let text = subtgraph::presets::text(preset).unwrap();
    let path = dir.join(format!("{preset}.toml"));
    let text = text.replacen("seed = ", &format!("seed = {seed} # was "), 1);
    std::fs::write(
        &path,
        format!(
            "{text}\n[[export]]\ntype = \"obj\"\nvisual = \"none\"\n\n[[export]]\ntype = \"tasks\"\n{keys}"
        ),
    )
    .unwrap();
    path
}

#[test]
fn every_presets_optimal_lengths_agree_with_an_independent_astar_and_cells_are_free() {
    let dir = temp("presets");
    for (preset, seed) in [("mine", 3), ("cave", 4), ("lava-tube", 5)] {
        let p = preset_with_tasks(
            &dir,
            preset,
            seed,
            "problems = 12\nagents = 6\ninstances = 2\n",
        );
        let out = dir.join(preset);
        ok(&["generate", arg(&p), "--format", "tasks", "--out", arg(&out)]);
        assert!(out.join("mesh/collision.obj").is_file());
        let meta = std::fs::read_to_string(out.join("tasks/tasks.json")).unwrap();
        assert!(meta.contains(&format!("\"seed\": {seed},")), "{meta}");
        assert!(meta.contains("\"source\": \"collision-mesh\""), "{meta}");
        if let Some(said) = read_with_python(READERS, "tasks_check.py", &[arg(&out), "mesh"]) {
            eprintln!("{preset}:\n{said}");
            assert!(said.contains("12 problems and 2 x 6 agents"), "{said}");
            assert!(
                said.contains("300 passable cells inside the collision surface and 300 rock cells beside them outside"),
                "{said}"
            );
        }
        let _ = std::fs::remove_dir_all(&out);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn grid_worlds_get_tasks_too_and_the_files_repeat_on_any_thread_count() {
    let dir = temp("grid");
    let p = common::small_cave_pipeline(
        &dir,
        2,
        "[[export]]\ntype = \"tasks\"\nresolution = 2.0\nproblems = 40\nagents = 20\ninstances = 3\n",
    );
    let folders = assert_same_on_one_and_three_threads(&dir, &p, "tasks");
    let meta = std::fs::read_to_string(folders[0].join("tasks/tasks.json")).unwrap();
    assert!(meta.contains("\"resolution_m\": 2.0"), "{meta}");
    assert!(folders[0].join("tasks/level-1-random-3.scen").is_file());
    assert!(!folders[0].join("tasks/level-1-random-4.scen").exists());
    if let Some(said) = read_with_python(READERS, "tasks_check.py", &[arg(&folders[0]), "mesh"]) {
        assert!(said.contains("40 problems and 3 x 20 agents"), "{said}");
    }
    // Without geometry the map is the grid's cells.
    let out = dir.join("no-mesh");
    ok(&["generate", arg(&p), "--no-mesh", "--out", arg(&out)]);
    let meta = std::fs::read_to_string(out.join("tasks/tasks.json")).unwrap();
    assert!(meta.contains("\"source\": \"grid\""), "{meta}");
    if let Some(said) = read_with_python(READERS, "tasks_check.py", &[arg(&out), "grid"]) {
        assert!(said.contains("optimal lengths reproduced"), "{said}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_knobs_and_huge_maps_are_refused_naming_the_key_and_nothing_is_written() {
    let dir = temp("bad");
    for (keys, says) in [
        (
            "resolution = 0.0\n",
            "export[0].resolution: must be a positive number",
        ),
        (
            "problems = 1000000\n",
            "export[0].problems: must be from 0 to 100000",
        ),
        ("agents = -1\n", "export[0].agents"),
        (
            "instances = 1000\n",
            "export[0].instances: must be from 0 to 100",
        ),
        (
            "robots = 3\n",
            "this component takes: resolution, problems, agents, instances",
        ),
        (
            "resolution = 0.01\n",
            "resolution = 0.01 makes maps of 1024.0 million cells per level (at most 16 million); use a larger resolution",
        ),
    ] {
        let p =
            common::small_cave_pipeline(&dir, 1, &format!("[[export]]\ntype = \"tasks\"\n{keys}"));
        let out = dir.join("world");
        let err = fails(&["generate", arg(&p), "--no-mesh", "--out", arg(&out)]);
        assert!(err.contains(says), "{keys}: {err}");
        assert!(!out.exists(), "{keys}: nothing written");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
