//! Ramps between levels (`world.connections = "ramp"`, the mine's default): the spiral in a
//! shaft's cell column is a graph edge of kind `ramp` whose polyline follows its floor within
//! `world.ramp_grade`; a ball placed on it rolls down and stays inside (MuJoCo, PyBullet);
//! the resolved value is recorded; the same world on every run and thread count; bad values
//! and passages that do not fit name the key to change.

use crate::common;

use std::path::{Path, PathBuf};

use common::{arg, fails, ok, read_with_python};
use subtgraph::core::World;
use subtgraph::core::config::Connections;

/// A small two-level mine (20 m tiles, the preset's drift) with the default MJCF: height
/// fields, and convex slabs in the ramp's two tiles (a height field holds one floor per
/// vertical line, a spiral has several; see README).
pub fn two_level_mine(dir: &Path, seed: u64, extra: &str) -> PathBuf {
    let text = format!(
        "[world]\nseed = {seed}\nlevels = 2\nrows = 12\ncols = 12\ntile_pitch = 20.0\n{extra}\n\
         [topology]\nloops = 0\nt_junctions = 1\nintersections = 0\n\n\
         [route]\ntype = \"linear\"\n\n[tileset]\ntype = \"mine\"\n\n\
         [[export]]\ntype = \"mjcf\"\n"
    );
    let path = dir.join(format!("mine-{seed}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

fn edges(world: &Path) -> Vec<serde_json::Value> {
    let text = std::fs::read_to_string(world.join("ground_truth/graph.json")).unwrap();
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    doc["edges"].as_array().unwrap().clone()
}

#[test]
fn mines_join_their_levels_by_ramps_and_record_it() {
    let mut p = subtgraph::presets::load("mine").unwrap();
    let (resolved, r) = p.resolve().unwrap();
    assert_eq!(r.connections, Connections::Ramp);
    let text = resolved.to_toml();
    assert!(
        text.contains("connections = \"ramp\"") && text.contains("ramp_grade = 8.13"),
        "{text}"
    );
    // Without the key: by the tile set (mine: ramps; the others: shafts, the paper's).
    p.world.connections = None;
    assert_eq!(p.resolve().unwrap().1.connections, Connections::Ramp);
    for preset in ["cave", "lava-tube"] {
        let p = subtgraph::presets::load(preset).unwrap();
        let (resolved, r) = p.resolve().unwrap();
        assert_eq!(r.connections, Connections::Shaft, "{preset}");
        assert!(resolved.to_toml().contains("connections = \"shaft\""));
        assert!(!resolved.to_toml().contains("ramp_grade"));
    }
    // The graph calls the edges ramps; topology.json too.
    let w = World::from(subtgraph::core::layout(&p, &subtgraph::registry()).unwrap());
    let kinds: Vec<_> = w.graph.edges.iter().map(|e| e.kind).collect();
    assert!(kinds.contains(&subtgraph::core::graph::EdgeKind::Ramp));
    assert!(!kinds.contains(&subtgraph::core::graph::EdgeKind::Shaft));
}

/// Over many seeds and levels: every ramp's polyline goes from its foot's level floor to its
/// landing's, climbing all the way (never down, but by the floors' own slope before and after the spiral), never steeper than `world.ramp_grade`, and
/// its nodes and semantic labels say `ramp`.
#[test]
fn ramps_climb_from_floor_to_floor_within_their_grade_over_many_seeds() {
    let tmp = tempfile::tempdir().unwrap();
    let mut ramps = 0;
    let mut steepest: f64 = 0.0;
    for seed in 0..12 {
        let text = format!(
            "[world]\nseed = {seed}\nlevels = 3\nrows = 12\ncols = 12\ntile_pitch = 20.0\n\
             connections = \"ramp\"\n\n[topology]\nloops = 0\nt_junctions = 1\n\
             intersections = 0\n\n[route]\ntype = \"linear\"\n\n[tileset]\ntype = \"mine\"\n"
        );
        let pipeline = tmp.path().join(format!("m{seed}.toml"));
        std::fs::write(&pipeline, text).unwrap();
        let world = tmp.path().join(format!("w{seed}"));
        ok(&[
            "generate",
            arg(&pipeline),
            "--format",
            "graph,semantic-labels",
            "--out",
            arg(&world),
        ]);
        let labels =
            std::fs::read_to_string(world.join("ground_truth/semantic_labels.csv")).unwrap();
        let occupied: Vec<[usize; 3]> = labels
            .lines()
            .skip(1)
            .map(|l| {
                let f: Vec<usize> = l.split(',').take(3).map(|v| v.parse().unwrap()).collect();
                [f[0], f[1], f[2]]
            })
            .collect();
        let topology: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(world.join("topology.json")).unwrap())
                .unwrap();
        let shafts = topology["shafts"].as_array().unwrap();
        let mut seen = 0;
        for e in edges(&world) {
            assert_ne!(e["kind"], "shaft", "seed {seed}: a shaft in a ramp world");
            if e["kind"] != "ramp" {
                continue;
            }
            seen += 1;
            let line: Vec<[f64; 3]> = serde_json::from_value(e["polyline"].clone()).unwrap();
            // Its spiral turns in its block: the foot's cell and three cells beside it, empty in
            // the grid on both levels; every point of its line but the end nodes is over them.
            let cells: Vec<[i64; 2]> = topology["edges"]
                .as_array()
                .unwrap()
                .iter()
                .find(|t| t["id"] == e["id"])
                .unwrap()["cells"]
                .as_array()
                .unwrap()
                .iter()
                .map(|c| [c["row"].as_i64().unwrap(), c["col"].as_i64().unwrap()])
                .collect();
            let shaft = shafts
                .iter()
                .find(|s| s["up"]["row"].as_i64() == Some(cells[0][0]))
                .unwrap();
            let [dr, dc] = [0, 1].map(|i| shaft["block"][i].as_i64().unwrap());
            assert!(dr.abs() == 1 && dc.abs() == 1, "seed {seed}: block {shaft}");
            let [r0, c0] = cells[0];
            let block = [[r0, c0], [r0 + dr, c0], [r0, c0 + dc], [r0 + dr, c0 + dc]];
            for level in [
                shaft["up"]["level"].as_u64().unwrap(),
                shaft["landing"]["level"].as_u64().unwrap(),
            ] {
                for [r, c] in &block[1..] {
                    assert!(
                        !occupied.contains(&[level as usize, *r as usize, *c as usize]),
                        "seed {seed}: block cell ({r}, {c}) of level {level} occupied"
                    );
                }
            }
            for p in &line[1..line.len() - 1] {
                let (r, c) = (
                    11 - (p[1] / 20.0 + 0.5).floor() as i64,
                    (p[0] / 20.0 + 0.5).floor() as i64,
                );
                assert!(
                    block.contains(&[r, c]),
                    "seed {seed}: {p:?} in cell ({r}, {c}), outside {block:?}"
                );
            }
            assert!(line.len() > 20, "seed {seed}: {} points", line.len());
            let (first, last) = (line[0], line[line.len() - 1]);
            // From one level's floor to the next: 16 m apart, and the mine's floors slope by
            // up to a metre or so (`[tileset] grade`, lifting a floor, never lowering it).
            let rise = last[2] - first[2];
            assert!(
                (rise - 16.0).abs() < 1.5,
                "seed {seed}: climbs {rise} m, not 16"
            );
            assert!(
                (0.0..1.5).contains(&(first[2] - (first[2] / 16.0).round() * 16.0 + 0.3)),
                "seed {seed}: starts at {} m, not on a level's floor",
                first[2]
            );
            let mut length = 0.0;
            for w in line.windows(2) {
                let run = ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt();
                let up = w[1][2] - w[0][2];
                length += (run * run + up * up).sqrt();
                // Never down, but where the line runs on a level's own floor between its
                // node and the spiral: the mine's floors slope by up to 3 degrees.
                assert!(
                    up > -0.05 - run * 3.0f64.to_radians().tan(),
                    "seed {seed}: the ramp goes down {up} m over {run} m at {:?}",
                    w[0]
                );
                if run > 0.1 {
                    let grade = (up / run).atan().to_degrees();
                    steepest = steepest.max(grade);
                    assert!(
                        grade <= 8.2,
                        "seed {seed}: {grade:.1} degrees at {:?}",
                        w[0]
                    );
                }
            }
            assert!((e["length_m"].as_f64().unwrap() - length).abs() < 0.01);
            // A spiral: far longer than the climb (a shaft's line would be 16 m).
            assert!(length > 2.0 * rise, "seed {seed}: {length} m");
        }
        assert_eq!(seen, 2, "seed {seed}: two ramps between three levels");
        assert_eq!(labels.matches(",ramp,").count(), 4, "seed {seed}: {labels}");
        ramps += seen;
    }
    eprintln!("{ramps} ramps, steepest {steepest:.1} degrees");
}

/// A ball placed on the ramp's upper part rolls down to its foot inside the spiral, in both
/// engines (`tests/readers/ramp_check.py`), from two places: where its floor has climbed half
/// and nine tenths of the rise (on the climb: a ramp's plan may end in a level stretch before
/// its landing, where a ball rightly stays).
#[test]
fn a_ball_placed_on_a_ramp_rolls_down_it_and_stays_inside() {
    let tmp = tempfile::tempdir().unwrap();
    let pipeline = two_level_mine(tmp.path(), 3, "");
    let world = tmp.path().join("world");
    ok(&[
        "generate",
        arg(&pipeline),
        "--format",
        "urdf,graph",
        "--out",
        arg(&world),
    ]);
    for at in ["0.5", "0.9"] {
        for (engine, module) in [("mujoco", "mujoco"), ("pybullet", "pybullet")] {
            let args = [arg(&world), "--engine", engine, "--at", at];
            if let Some(out) = read_with_python(&[module, "numpy"], "ramp_check.py", &args) {
                assert!(
                    out.contains("OK") && out.contains("inside the ramp"),
                    "{out}"
                );
                eprintln!("{engine} at {at}: {out}");
            }
        }
    }
}

#[test]
fn the_same_ramps_on_every_run_and_thread_count() {
    let tmp = tempfile::tempdir().unwrap();
    let pipeline = two_level_mine(tmp.path(), 4, "");
    common::assert_same_on_one_and_three_threads(tmp.path(), &pipeline, "obj,urdf,ground-truth");
}

#[test]
fn bad_ramp_settings_name_the_key_to_change() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("w");
    for (extra, key, says) in [
        ("connections = \"rmp\"", "world.connections", "ramp"),
        (
            "ramp_grade = 0.5",
            "world.ramp_grade",
            "from 1 to 30 degrees",
        ),
        (
            "ramp_grade = 45",
            "world.ramp_grade",
            "from 1 to 30 degrees",
        ),
        // The spiral round a block of 20 m tiles climbs at about 6 degrees: 3 is refused.
        (
            "ramp_grade = 3",
            "world.ramp_grade",
            "steeper than world.ramp_grade = 3",
        ),
    ] {
        let pipeline = two_level_mine(tmp.path(), 1, extra);
        let e = fails(&["generate", arg(&pipeline), "--out", arg(&out)]);
        assert!(e.contains(key) && e.contains(says), "{extra}: {e}");
        assert!(!out.exists(), "{extra}: nothing written");
    }
}

/// The DARPA tile manifest has no ramp: a world asking for ramps is refused, naming the key.
#[test]
fn tile_manifests_without_ramps_refuse_them() {
    if common::darpa_tiles().is_none() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/darpa-cave.toml");
    let text = std::fs::read_to_string(&example).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    let world_at = lines.iter().position(|l| l.trim() == "[world]").unwrap();
    lines.insert(world_at + 1, "connections = \"ramp\"".into());
    lines.insert(world_at + 2, "levels = 2".into());
    lines.retain(|l| !l.starts_with("levels =") || l == "levels = 2");
    let pipeline = example.with_file_name("darpa-ramp-test.toml");
    let pipeline = tmp.path().join(pipeline.file_name().unwrap());
    // Keep the manifest path valid from the temporary folder.
    let text = lines.join("\n").replace(
        "manifest = \"",
        &format!("manifest = \"{}/", example.parent().unwrap().display()),
    );
    std::fs::write(&pipeline, text).unwrap();
    let out = tmp.path().join("w");
    let e = fails(&["generate", arg(&pipeline), "--out", arg(&out)]);
    assert!(
        e.contains("makes no ramps") && e.contains("world.connections = \"shaft\""),
        "{e}"
    );
}

/// The ground truth of a world with a ramp passes the same independent checks as any other
/// (`tests/readers/ground_truth_check.py`: every node and polyline point, the ramp's spiral
/// included, stands on a floor of the collision surface; labels agree with the grid).
#[test]
fn the_ground_truth_of_a_ramp_world_stands_on_its_floors() {
    let tmp = tempfile::tempdir().unwrap();
    let pipeline = two_level_mine(tmp.path(), 5, "");
    let world = tmp.path().join("world");
    ok(&[
        "generate",
        arg(&pipeline),
        "--format",
        "obj,ground-truth",
        "--out",
        arg(&world),
    ]);
    assert!(edges(&world).iter().any(|e| e["kind"] == "ramp"));
    let readers = ["numpy", "PIL", "yaml", "networkx", "trimesh"];
    if let Some(said) = read_with_python(&readers, "ground_truth_check.py", &[arg(&world), "mesh"])
    {
        eprintln!("{said}");
        assert!(said.contains("spawn poses"), "{said}");
    }
}
