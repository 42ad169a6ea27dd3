//! `subtgraph score --segmentation` against an independent numpy recomputation
//! (`tests/readers/segmentation_check.py`): a perfect map drawn from the world's own semantic
//! labels (IoU 1 for every class present, every node found at its place), the same map moved
//! 2 m east, and a corrupted one (noise, an erased junction, a painted dead end), each
//! metric and the confusion matrix compared to 1e-9. Bad input (wrong size, an unknown value,
//! a colour PNG, a float array, a level the world has not, a world without ROS maps) is
//! refused naming the file and what to change, and nothing is written.

use crate::common;

use std::path::{Path, PathBuf};

use common::{arg, fails, ok, read_with_python, small_cave_pipeline};
use serde_json::Value;

const READERS: &[&str] = &["numpy", "PIL", "scipy"];

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("subtgraph-seg-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A two-level world with ground truth (grid: quick, and the maps free exactly over tiles).
fn world(dir: &Path, ground_truth: bool) -> PathBuf {
    world_with(dir, ground_truth, false)
}

/// The same, with its mesh when `mesh` (the maps then free only along the passages).
fn world_with(dir: &Path, ground_truth: bool, mesh: bool) -> PathBuf {
    let p = small_cave_pipeline(dir, 2, "");
    let out = dir.join(if ground_truth { "world" } else { "bare" });
    let mut args = vec!["generate", arg(&p), "--out", arg(&out)];
    if !mesh {
        args.push("--no-mesh");
    }
    if ground_truth {
        args.extend(["--format", "ground-truth"]);
    }
    ok(&args);
    out
}

fn score(world: &Path, map: &Path, out: &Path) -> Value {
    let said = ok(&[
        "score",
        arg(world),
        "--segmentation",
        arg(map),
        "--out",
        arg(out),
    ]);
    assert!(said.contains("mean IoU"), "{said}");
    serde_json::from_slice(&std::fs::read(out.join("segmentation.json")).unwrap()).unwrap()
}

#[test]
fn scores_agree_with_numpy_and_a_perfect_map_scores_one() {
    agree(false);
}

/// The same on the world with its mesh: the ROS maps are free only along the passages, the
/// node positions on them, and a tile's pixels are still those of its square on the grid.
#[test]
fn on_a_meshed_world_too() {
    agree(true);
}

fn agree(mesh: bool) {
    let dir = temp(if mesh { "agree-mesh" } else { "agree" });
    let w = world_with(&dir, true, mesh);
    let maps = dir.join("maps");
    std::fs::create_dir_all(&maps).unwrap();
    for level in ["0", "1"] {
        let Some(said) = read_with_python(
            READERS,
            "segmentation_check.py",
            &["write", arg(&w), level, arg(&maps)],
        ) else {
            return;
        };
        eprintln!("{said}");
        for name in [
            format!("level-{level}.png"),
            format!("shifted-level-{level}.png"),
            format!("corrupt-level-{level}.npy"),
        ] {
            let map = maps.join(&name);
            let out = dir.join(format!("score-{name}"));
            let doc = score(&w, &map, &out);
            let said = read_with_python(
                READERS,
                "segmentation_check.py",
                &["check", arg(&w), level, arg(&map), arg(&out)],
            )
            .unwrap();
            eprintln!("{name}: {said}");
            let iou = |c: &str| doc[format!("iou.{c}")].as_f64();
            if name.starts_with("level-") {
                // Every class the world has on the level is present, each matched exactly.
                for c in [
                    "corridor",
                    "junction",
                    "intersection",
                    "dead_end",
                    "shaft_ramp",
                ] {
                    assert_eq!(iou(c), Some(1.0), "{name} {c}: {doc}");
                }
                assert_eq!(doc["iou_mean"], 1.0);
                assert_eq!(doc["node_recall"], 1.0, "{doc}");
                assert_eq!(doc["node_precision"], 1.0, "{doc}");
                // A node class's region is centred on its tile; with a mesh the node stands
                // on the passage, within the tile (16 m).
                let error = doc["node_error_mean_m"].as_f64().unwrap();
                assert!(if mesh { error < 4.0 } else { error < 1e-9 }, "{doc}");
            } else if name.starts_with("shifted") {
                // 8 pixels of 0.25 m: every node found 2 m off, every class IoU below 1.
                if !mesh {
                    assert!((doc["node_error_mean_m"].as_f64().unwrap() - 2.0).abs() < 1e-9);
                }
                assert!(doc["iou_mean"].as_f64().unwrap() < 0.95, "{doc}");
            } else {
                // The erased junction is missed, the painted dead end a false node.
                assert!(doc["node_recall"].as_f64().unwrap() < 1.0, "{doc}");
                assert!(doc["node_precision"].as_f64().unwrap() < 1.0, "{doc}");
            }
            let csv = std::fs::read_to_string(out.join("confusion.csv")).unwrap();
            assert!(
                csv.starts_with("truth\\predicted,unlabelled,corridor"),
                "{csv}"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn png_file(path: &Path, width: u32, height: u32, color: png::ColorType, data: &[u8]) {
    let f = std::fs::File::create(path).unwrap();
    let mut e = png::Encoder::new(std::io::BufWriter::new(f), width, height);
    e.set_color(color);
    e.set_depth(png::BitDepth::Eight);
    e.write_header().unwrap().write_image_data(data).unwrap();
}

#[test]
fn bad_segmentations_are_refused_naming_the_file_and_nothing_is_written() {
    let dir = temp("bad");
    let w = world(&dir, true);
    let bare = world(&dir, false);
    let (width, height) = (1280usize, 1280usize);
    let header = std::fs::read(w.join("ground_truth/maps/level-0.pgm")).unwrap();
    assert!(
        String::from_utf8_lossy(&header[..200]).contains("1280 1280"),
        "the test's world changed size; update width and height"
    );
    let small = dir.join("small-level-0.png");
    png_file(&small, 100, 80, png::ColorType::Grayscale, &[1; 8000]);
    let rgb = dir.join("rgb-level-0.png");
    png_file(&rgb, 4, 4, png::ColorType::Rgb, &[1; 48]);
    let mut data = vec![0u8; width * height];
    data[3 * width + 7] = 9;
    let unknown = dir.join("unknown-level-0.npy");
    std::fs::write(
        &unknown,
        common::npy_bytes("|u1", &format!("({height}, {width})"), &data),
    )
    .unwrap();
    let floats = dir.join("floats-level-0.npy");
    std::fs::write(&floats, common::npy_bytes("<f8", "(2, 2)", &[0; 32])).unwrap();
    let good = dir.join("level-5.png");
    png_file(
        &good,
        width as u32,
        height as u32,
        png::ColorType::Grayscale,
        &vec![0; width * height],
    );
    let unnamed = dir.join("mine.png");
    std::fs::copy(&good, &unnamed).unwrap();
    let cases: [(&Path, &Path, &[&str]); 7] = [
        (&w, &small, &["100 x 80 pixels", "is 1280 x 1280"]),
        (&w, &rgb, &["Rgb PNG", "8-bit greyscale"]),
        (
            &w,
            &unknown,
            &["row 3, column 7", "value 9", "5 shaft/ramp"],
        ),
        (&w, &floats, &["floats", "2-D integer array"]),
        (&w, &good, &["level 5", "2 level(s)", "--level N"]),
        (&w, &unnamed, &["no level in the file name", "--level N"]),
        (
            &bare,
            &small,
            &["no ground_truth/maps/level-0.pgm", "--format ground-truth"],
        ),
    ];
    for (world, map, says) in cases {
        let out = dir.join("out");
        let err = fails(&[
            "score",
            arg(world),
            "--segmentation",
            arg(map),
            "--out",
            arg(&out),
        ]);
        assert!(err.contains(arg(map)) || err.contains(arg(world)), "{err}");
        for s in says {
            assert!(err.contains(s), "{map:?}: {s:?} not in {err}");
        }
        assert!(!out.exists(), "{map:?}: {out:?} written");
    }
    // --level reads a map whose name does not say.
    let out = dir.join("named");
    ok(&[
        "score",
        arg(&w),
        "--segmentation",
        arg(&unnamed),
        "--level",
        "1",
        "--out",
        arg(&out),
    ]);
    let doc: Value =
        serde_json::from_slice(&std::fs::read(out.join("segmentation.json")).unwrap()).unwrap();
    assert_eq!(doc["options"]["level"], 1);
    assert_eq!(doc["iou.corridor"], 0.0);
    let _ = std::fs::remove_dir_all(&dir);
}
