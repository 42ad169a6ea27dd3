//! Issue 15 item 7: hills from the DARPA elevation tile (`[[tile]] kind = "elevation"` in
//! `tilesets/manifests/darpa-cave-type-b.toml`). On the real tiles (skipped with a message when
//! `../shared/darpa-subt-tiles` is absent): hills are placed, the ground truth follows their
//! floors and bodies rest on them (`tests/readers/elevation_check.py`, trimesh, PyBullet and
//! MuJoCo), the files are the same on 1 and 3 threads, a rate of 0 makes the world of a
//! manifest without the tile, on two levels hills stand only under free cells, and bad values
//! are refused naming the key.

use crate::common;

use std::path::{Path, PathBuf};

use common::{arg, fails, ok, read_with_python};

/// The elevation tile's climb in the shipped manifest, metres.
const RISE: f64 = 32.0;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn shipped_manifest() -> PathBuf {
    root().join("tilesets/manifests/darpa-cave-type-b.toml")
}

/// `examples/<example>.toml` with `seed`, its manifest `manifest` and `extra` lines at the end
/// of its `[tileset]`, written into `dir`. The level is a third of the example's size
/// (`min_length = [400, 500]`, 20 to 22 tiles a side, as `darpa-cave-levels` has): every check
/// here looks at each hill on its own, and a smaller world still has several per seed, at a
/// third of the cost of the 80 m tiles' millions of triangles.
fn pipeline(dir: &Path, example: &str, seed: u64, manifest: &Path, extra: &str) -> PathBuf {
    let text = std::fs::read_to_string(root().join(format!("examples/{example}.toml"))).unwrap();
    let mut seeded = false;
    let text: String = text
        .lines()
        .map(|l| {
            if l.starts_with("seed = ") {
                seeded = true;
                format!("seed = {seed}")
            } else if l.starts_with("min_length = ") {
                "min_length = [400, 500]".to_owned()
            } else if l.starts_with("manifest = ") {
                format!("manifest = {:?}\n{extra}", manifest.display().to_string())
            } else {
                l.to_owned()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    assert!(seeded && text.contains("manifest = "));
    let path = dir.join(format!("{example}-{seed}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// The shipped manifest with its `root` made absolute and `edit` applied, written into `dir`.
fn manifest_with(dir: &Path, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let tiles = common::darpa_tiles().expect("checked by the caller");
    let text = std::fs::read_to_string(shipped_manifest()).unwrap();
    let text = text
        .lines()
        .map(|l| {
            if l.starts_with("root = ") {
                format!("root = {:?}", tiles.display().to_string())
            } else {
                l.to_owned()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let path = dir.join(name);
    std::fs::write(&path, edit(text)).unwrap();
    path
}

/// The tiles of a world folder labelled `feature` in `ground_truth/semantic_labels.json`.
fn labelled(world: &Path, feature: &str) -> usize {
    let doc: serde_json::Value = serde_json::from_slice(
        &std::fs::read(world.join("ground_truth/semantic_labels.json")).unwrap(),
    )
    .unwrap();
    doc["tiles"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|t| {
            t["features"]
                .as_array()
                .is_some_and(|f| f.iter().any(|v| v == feature))
        })
        .count()
}

/// Over three seeds of `examples/darpa-cave.toml` with every eligible run a hill: hills are
/// placed, every node and polyline point stands on a floor, the polylines climb the rise over
/// each end and stay up over the raised tiles, no steeper than the tile's own floor, and a ball
/// rests on each raised tile in PyBullet (the URDF's mesh) and MuJoCo (the height fields).
#[test]
fn hills_climb_and_descend_and_the_ground_truth_follows_their_floors() {
    if common::darpa_tiles().is_none() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let tile = common::darpa_tiles()
        .unwrap()
        .join("cave_elevation_type_b/caveelevation.obj");
    let mut hills = Vec::new();
    for seed in [1, 2, 3] {
        let p = pipeline(
            tmp.path(),
            "darpa-cave",
            seed,
            &shipped_manifest(),
            "elevation_rate = 1.0",
        );
        let world = tmp.path().join(format!("world-{seed}"));
        ok(&[
            "generate",
            arg(&p),
            "--format",
            "obj,urdf,mjcf,graph,semantic-labels",
            "--out",
            arg(&world),
        ]);
        let ends = labelled(&world, "elevation");
        assert_eq!(ends % 2, 0, "seed {seed}: two ends a hill");
        hills.push(ends / 2);
        let rise = RISE.to_string();
        let args = [arg(&world), rise.as_str(), arg(&tile)];
        if let Some(said) = read_with_python(
            &["trimesh", "pybullet", "mujoco", "numpy"],
            "elevation_check.py",
            &args,
        ) {
            assert!(said.contains("OK"), "{said}");
            eprintln!("seed {seed}:\n{said}");
        }
        std::fs::remove_dir_all(&world).unwrap();
    }
    eprintln!("hills per seed: {hills:?}");
    assert!(hills.iter().all(|&h| h > 0), "{hills:?}");
    assert!(hills.iter().sum::<usize>() >= 6, "{hills:?}");
}

#[test]
fn hills_are_the_same_on_one_and_three_threads() {
    if common::darpa_tiles().is_none() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let p = pipeline(
        tmp.path(),
        "darpa-cave",
        2,
        &shipped_manifest(),
        "elevation_rate = 1.0",
    );
    let folders = common::assert_same_on_one_and_three_threads(
        tmp.path(),
        &p,
        "urdf,mjcf,graph,semantic-labels,spawn-poses",
    );
    assert!(labelled(&folders[0], "raised") > 0);
}

/// A rate of 0 makes, byte for byte, the world of the manifest without its elevation tile
/// (only `world.toml`, which repeats the pipeline, differs).
#[test]
fn a_rate_of_zero_makes_the_world_without_hills() {
    if common::darpa_tiles().is_none() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let without = manifest_with(tmp.path(), "without.toml", |t| {
        let cut = t.find("# Hills:").expect("the manifest's hills");
        t[..cut].to_owned()
    });
    let mut folders = Vec::new();
    for (name, manifest, extra) in [
        ("zero", shipped_manifest(), "elevation_rate = 0.0"),
        ("without", without, ""),
    ] {
        let dir = tmp.path().join(name);
        std::fs::create_dir(&dir).unwrap();
        let p = pipeline(&dir, "darpa-cave", 1, &manifest, extra);
        let out = tmp.path().join(format!("world-{name}"));
        ok(&[
            "generate",
            arg(&p),
            "--format",
            "urdf,mjcf,graph,semantic-labels,spawn-poses",
            "--out",
            arg(&out),
        ]);
        folders.push(out);
    }
    common::assert_same_files(&folders[0], &folders[1], &["world.toml"]);
}

/// On two levels 64 m apart (`examples/darpa-cave-levels.toml`), with every eligible run a
/// hill: no hill tile has an occupied cell of the level above over it or beside it, and
/// level-0 straights under such cells exist and stay flat.
#[test]
fn on_two_levels_hills_stand_only_under_free_cells() {
    use subtgraph::core::grid::Cell;
    if common::darpa_tiles().is_none() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let (mut hill_tiles, mut kept_flat) = (0, 0);
    for seed in [15, 16, 17, 18] {
        let p = pipeline(
            tmp.path(),
            "darpa-cave-levels",
            seed,
            &shipped_manifest(),
            "elevation_rate = 1.0",
        );
        let text = std::fs::read_to_string(&p).unwrap();
        let pipeline = subtgraph::core::Pipeline::parse(&text, p.to_str().unwrap()).unwrap();
        let world = subtgraph::core::generate(&pipeline, &subtgraph::registry()).unwrap();
        let mesh = world.mesh().unwrap();
        let crowded = |c: Cell| {
            let up = c.level + 1;
            if up >= world.occupancy.levels() {
                return false;
            }
            let (a, b) = (world.level_offsets[c.level], world.level_offsets[up]);
            (-1i64..=1).any(|dr| {
                (-1i64..=1).any(|dc| {
                    let r = c.row as i64 + dr + a[0] - b[0];
                    let k = c.col as i64 + dc + a[1] - b[1];
                    r >= 0
                        && k >= 0
                        && (r as usize) < world.occupancy.rows()
                        && (k as usize) < world.occupancy.cols()
                        && *world.occupancy.get(Cell::new(up, r as usize, k as usize))
                })
            })
        };
        for t in &mesh.tiles {
            let hill = t.labels.contains(&"elevation") || t.labels.contains(&"raised");
            assert_eq!(
                hill,
                t.floor_lift[1] > 0.0,
                "seed {seed}: {:?} labels and lift agree",
                t.cell
            );
            if hill {
                assert!(!crowded(t.cell), "seed {seed}: a hill under {:?}", t.cell);
                hill_tiles += 1;
            } else if t.kind == subtgraph::core::tile::TileKind::Straight
                && t.cell.level == 0
                && crowded(t.cell)
            {
                kept_flat += 1;
            }
        }
    }
    eprintln!(
        "{hill_tiles} hill tiles; {kept_flat} level-0 straights under the level above kept flat"
    );
    assert!(hill_tiles > 0 && kept_flat > 0, "{hill_tiles} {kept_flat}");
}

#[test]
fn bad_elevation_values_are_refused_naming_the_key() {
    if common::darpa_tiles().is_none() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let refused = |name: &str, manifest: &Path, extra: &str| {
        let dir = tmp.path().join(name);
        std::fs::create_dir(&dir).unwrap();
        let p = pipeline(&dir, "darpa-cave", 1, manifest, extra);
        fails(&["generate", arg(&p), "--out", arg(&dir.join("world"))])
    };
    let edited = |name: &str, from: &str, to: &str| {
        manifest_with(tmp.path(), &format!("{name}.toml"), |t| {
            assert!(t.contains(from), "{from}");
            t.replace(from, to)
        })
    };
    for (name, from, to, says) in [
        (
            "rate",
            "rate = 0.3",
            "rate = 1.5",
            "rate = 1.5: give the share",
        ),
        (
            "negative-rise",
            "rise = 32.0",
            "rise = -1.0",
            "rise = -1: give the climb",
        ),
        (
            "nan-rise",
            "rise = 32.0",
            "rise = nan",
            "rise = NaN: give the climb",
        ),
        ("no-rise", "rise = 32.0", "", "give rise"),
        (
            "wrong-rise",
            "rise = 32.0",
            "rise = 10.0",
            "rise = 10: cave_elevation_type_b/caveelevation.obj's floor climbs 3",
        ),
        (
            "turned",
            "rotation = 3\nfiles = [\"cave_elevation",
            "rotation = 1\nfiles = [\"cave_elevation",
            "rotation = 1 puts",
        ),
        (
            "missing",
            "cave_elevation_type_b/caveelevation.obj",
            "cave_elevation_type_b/nothing.obj",
            "nothing.obj does not exist",
        ),
    ] {
        let err = refused(name, &edited(name, from, to), "");
        assert!(
            err.contains("manifest") && err.contains(says),
            "{name}: {err}"
        );
    }
    // The measured orientation: without `rotation` the same tile climbs the same way.
    let measured = edited(
        "measured",
        "rotation = 3\nfiles = [\"cave_elevation",
        "files = [\"cave_elevation",
    );
    let dir = tmp.path().join("measured");
    std::fs::create_dir(&dir).unwrap();
    let p = pipeline(&dir, "darpa-cave", 1, &measured, "");
    ok(&["generate", arg(&p), "--out", arg(&dir.join("w"))]);
    // The world's override.
    let err = refused("override", &shipped_manifest(), "elevation_rate = 2.0");
    assert!(
        err.contains("elevation_rate") && err.contains("from 0 to 1"),
        "{err}"
    );
    let without = manifest_with(tmp.path(), "without.toml", |t| {
        t[..t.find("# Hills:").unwrap()].to_owned()
    });
    let err = refused("nothing-to-override", &without, "elevation_rate = 0.5");
    assert!(
        err.contains("elevation_rate") && err.contains("no [[tile]] kind = \"elevation\""),
        "{err}"
    );
}
