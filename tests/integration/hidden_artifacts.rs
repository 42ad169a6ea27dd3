//! Artifacts hidden on purpose (`[artifacts] hidden`): over several seeds of a small cave and
//! the cave preset, the share out of sight of their tile's passage axis is near the one asked
//! for, as the collision mesh says (`tests/readers/visibility_check.py`, an exact
//! segment-triangle test with trimesh), and the ground truth reports it; `hidden = 0` makes
//! the files the section made before the key existed; bad values are refused naming the key.

use crate::common;

use std::path::{Path, PathBuf};

use common::{arg, fails, folder_bytes, ok, read_with_python, small_cave_pipeline};

/// Generates `pipeline` (with its seed set) into `dir/name`.
fn generate(dir: &Path, pipeline: &Path, seed: u32, name: &str) -> PathBuf {
    let text = std::fs::read_to_string(pipeline).unwrap();
    let text = text.replacen("seed = 5", &format!("seed = {seed}"), 1);
    let text = text.replacen("seed = 1\n", &format!("seed = {seed}\n"), 1);
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    let out = dir.join(name);
    ok(&["generate", arg(&path), "--out", arg(&out), "--force"]);
    out
}

fn artifacts_json(world: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(world.join("ground_truth/artifacts.json")).unwrap())
        .unwrap()
}

/// The cave preset's pipeline with `extra` appended.
fn cave_preset(dir: &Path, extra: &str) -> PathBuf {
    let preset = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/cave.toml");
    let text = std::fs::read_to_string(preset).unwrap();
    assert!(text.contains("seed = 1\n"), "the preset's seed line");
    let path = dir.join("cave.toml");
    std::fs::write(&path, format!("{text}\n{extra}")).unwrap();
    path
}

#[test]
fn the_asked_share_of_artifacts_is_out_of_the_axis_sight_as_the_mesh_says() {
    let dir = tempfile::tempdir().unwrap();
    let small = small_cave_pipeline(
        dir.path(),
        2,
        "[artifacts]\ncount = 12\nmin_distance_from_start = 30\nmin_spacing = 6\nhidden = 0.3\n",
    );
    let cave = cave_preset(dir.path(), "[artifacts]\nhidden = 0.3\n");
    let worlds: Vec<(String, PathBuf)> = (1..=4)
        .map(|s| {
            (
                format!("small-{s}"),
                generate(dir.path(), &small, s, &format!("small-{s}")),
            )
        })
        .chain((1..=2).map(|s| {
            (
                format!("cave-{s}"),
                generate(dir.path(), &cave, s, &format!("cave-{s}")),
            )
        }))
        .collect();
    let (mut total, mut flagged, mut by_mesh, mut judged) = (0, 0, 0, 0);
    for (name, w) in &worlds {
        let doc = artifacts_json(w);
        let arts = doc["artifacts"].as_array().unwrap();
        let n = arts.len();
        let hidden = arts
            .iter()
            .filter(|a| !a["visible_from_axis"].as_bool().unwrap())
            .count();
        // The ground truth says how many were asked for and how many are hidden.
        let report = &doc["hidden"];
        assert_eq!(report["share_requested"], 0.3, "{name}");
        let requested = report["requested"].as_u64().unwrap() as usize;
        assert_eq!(requested, (0.3 * n as f64).round() as usize, "{name}");
        assert_eq!(
            report["placed"].as_u64().unwrap() as usize,
            hidden,
            "{name}"
        );
        assert!(
            hidden <= requested,
            "{name}: {hidden} hidden, {requested} asked"
        );
        total += n;
        flagged += hidden;
        // The mesh agrees with every flag, and counts the hidden ones itself.
        let Some(out) = read_with_python(&["numpy", "trimesh"], "visibility_check.py", &[arg(w)])
        else {
            return;
        };
        eprint!("{name}: {hidden} of {n} hidden ({requested} asked); {out}");
        let count = |word: &str| -> usize {
            let at = out.find(word).unwrap_or_else(|| panic!("{out}"));
            out[..at]
                .split_whitespace()
                .last()
                .unwrap()
                .parse()
                .unwrap()
        };
        let (seen, mesh_hidden) = (count(" artifacts seen"), count(" hidden,"));
        // Every rule still holds: on the floor, out of the rock, distance, spacing.
        read_with_python(
            &["numpy", "trimesh"],
            "artifacts_check.py",
            &[arg(w), "placement"],
        )
        .unwrap();
        by_mesh += mesh_hidden;
        judged += seen + mesh_hidden;
    }
    let share = flagged as f64 / total as f64;
    let mesh_share = by_mesh as f64 / judged as f64;
    eprintln!(
        "hidden: {flagged} of {total} ({share:.3}); by the mesh {by_mesh} of {judged} ({mesh_share:.3})"
    );
    assert!((share - 0.3).abs() <= 0.1, "share {share}");
    assert!(
        (mesh_share - 0.3).abs() <= 0.1,
        "share by the mesh {mesh_share}"
    );
}

#[test]
fn a_world_without_hidden_spots_places_every_artifact_and_reports_the_shortfall() {
    // Without a mesh the passages are the grid's open cells: nothing hides anything.
    let dir = tempfile::tempdir().unwrap();
    let p = small_cave_pipeline(
        dir.path(),
        1,
        "[artifacts]\ncount = 10\nmin_distance_from_start = 20\nmin_spacing = 6\nhidden = 0.3\n",
    );
    let w = dir.path().join("grid");
    ok(&["generate", arg(&p), "--no-mesh", "--out", arg(&w)]);
    let doc = artifacts_json(&w);
    let arts = doc["artifacts"].as_array().unwrap();
    assert_eq!(arts.len(), 10, "every artifact placed");
    assert!(arts.iter().all(|a| a["visible_from_axis"] == true));
    assert_eq!(doc["hidden"]["requested"], 3);
    assert_eq!(doc["hidden"]["placed"], 0);
    assert_eq!(doc["hidden"]["share_placed"], 0.0);
}

#[test]
fn hidden_zero_makes_the_files_it_made_before_the_key_existed() {
    // Without the key, placement never looks at sight lines and the ground truth has no
    // `hidden` report; `hidden = 0` is the same world, byte for byte.
    let dir = tempfile::tempdir().unwrap();
    let section = "[artifacts]\ncount = 8\nmin_distance_from_start = 30\nmin_spacing = 6\n";
    let mut folders = Vec::new();
    for (name, extra) in [
        ("absent", ""),
        ("zero", "hidden = 0\n"),
        ("some", "hidden = 0.5\n"),
    ] {
        let p = small_cave_pipeline(dir.path(), 2, &format!("{section}{extra}"));
        let out = dir.path().join(name);
        ok(&[
            "generate",
            arg(&p),
            "--out",
            arg(&out),
            "--format",
            "mjcf,ground-truth",
        ]);
        folders.push(out);
    }
    assert_eq!(folder_bytes(&folders[0]), folder_bytes(&folders[1]));
    let absent = artifacts_json(&folders[0]);
    assert!(absent.get("hidden").is_none(), "{absent}");
    let toml = std::fs::read_to_string(folders[0].join("world.toml")).unwrap();
    assert!(!toml.contains("hidden"), "{toml}");
    // With the key, the same grids and meshes; only the artifacts move.
    let (before, some) = (folder_bytes(&folders[0]), folder_bytes(&folders[2]));
    let differ: Vec<&str> = before
        .iter()
        .zip(&some)
        .filter(|(x, y)| x.0 != y.0 || x.1 != y.1)
        .map(|(x, _)| x.0.as_str())
        .collect();
    assert!(
        differ.contains(&"ground_truth/artifacts.json"),
        "{differ:?}"
    );
    for d in &differ {
        assert!(
            d.starts_with("ground_truth/artifacts")
                || d.starts_with("mujoco/")
                || [".subtgraph-files", "world.toml"].contains(d),
            "{d} changed with hidden"
        );
    }
    let toml = std::fs::read_to_string(folders[2].join("world.toml")).unwrap();
    assert!(toml.contains("hidden = 0.5"), "{toml}");
}

#[test]
fn bad_hidden_shares_are_refused_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    for (value, hint) in [
        ("1.5", "from 0 (none hidden) to 1"),
        ("-0.1", "from 0 (none hidden) to 1"),
        ("\"x\"", "invalid type"),
    ] {
        let p = small_cave_pipeline(dir.path(), 1, &format!("[artifacts]\nhidden = {value}\n"));
        let err = fails(&["validate", arg(&p)]);
        assert!(
            err.contains("artifacts.hidden") && err.contains(hint),
            "hidden = {value}: {err}"
        );
    }
}
