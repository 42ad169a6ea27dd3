//! Issue 24 item 2: ramps that wind and shafts whose landing is on their axis, checked from
//! the files by independent readers (trimesh in Python).
//!
//! A mine's decline varies its radius and grade within `world.ramp_grade` (not an exact
//! helix): `tests/readers/decline_check.py` measures the ground truth's centreline and the
//! exported mesh's floor. A vertical shaft's landing node stands on the shaft's axis, and the
//! straight line from its foot's node to it keeps clear of the collision mesh:
//! `tests/readers/shaft_landing_check.py`.

use crate::common;

use std::path::{Path, PathBuf};

use common::{arg, ok, read_with_python};

/// A two-level world of tile set `tileset`, joined by `connections`, with the ground truth's
/// graph and the OBJ meshes.
fn two_levels(dir: &Path, tileset: &str, connections: &str, pitch: f64, seed: u64) -> PathBuf {
    let text = format!(
        "[world]\nseed = {seed}\nlevels = 2\nrows = 10\ncols = 10\ntile_pitch = {pitch:.1}\n\
         connections = \"{connections}\"\n\n\
         [topology]\nloops = 0\nt_junctions = 1\nintersections = 0\n\n\
         [route]\ntype = \"linear\"\n\n[tileset]\ntype = \"{tileset}\"\n"
    );
    let pipeline = dir.join(format!("{tileset}-{seed}.toml"));
    std::fs::write(&pipeline, text).unwrap();
    let world = dir.join(format!("{tileset}-{seed}"));
    ok(&[
        "generate",
        arg(&pipeline),
        "--format",
        "graph,obj",
        "--out",
        arg(&world),
    ]);
    world
}

/// Over 6 seeds: every ramp's centreline and the mesh's floor under it stay within
/// `world.ramp_grade` (the mine's 8.13 degrees: the reader fails otherwise), and the ramps
/// wind: on most the radius varies by 0.2 m or more and the grade by a degree or more, and
/// on none is either the same all along (an exact helix's would be).
#[test]
fn declines_wind_within_their_grade() {
    let tmp = tempfile::tempdir().unwrap();
    let (mut ramps, mut wound) = (0, 0);
    for seed in 0..6 {
        let world = two_levels(tmp.path(), "mine", "ramp", 20.0, seed);
        let Some(out) = read_with_python(
            &["numpy", "trimesh"],
            "decline_check.py",
            &[arg(&world), "8.13"],
        ) else {
            return;
        };
        assert!(out.contains("OK"), "{out}");
        for line in out.lines().filter(|l| l.starts_with('{')) {
            let m: serde_json::Value = serde_json::from_str(line).unwrap();
            let range = |k: &str| m[k][1].as_f64().unwrap() - m[k][0].as_f64().unwrap();
            let (radius, grade) = (range("radius"), range("grade"));
            eprintln!("seed {seed}: {line}");
            assert!(
                radius > 0.05 || grade > 0.1,
                "seed {seed}: an exact helix: {line}"
            );
            ramps += 1;
            if radius >= 0.2 && grade >= 1.0 {
                wound += 1;
            }
        }
    }
    assert!(ramps >= 6, "{ramps} ramps");
    assert!(wound * 3 >= ramps * 2, "only {wound} of {ramps} ramps wind");
}

/// On the cave and the lava tube (the presets with shafts), over 3 seeds each: every shaft's
/// landing node is on the shaft's axis, and the straight line from 1.5 m above the foot's
/// node to it is at least 1 m from the collision mesh all the way (the robot's default
/// clearance), with nothing across the shaft below the landing.
#[test]
fn shaft_landings_stand_on_the_axis_with_clearance() {
    let tmp = tempfile::tempdir().unwrap();
    let mut shafts = 0;
    for (tileset, pitch) in [("cave", 20.0), ("lava-tube", 25.0)] {
        for seed in 0..3 {
            let world = two_levels(tmp.path(), tileset, "shaft", pitch, seed);
            let Some(out) = read_with_python(
                &["numpy", "trimesh"],
                "shaft_landing_check.py",
                &[arg(&world), "1.0"],
            ) else {
                return;
            };
            assert!(out.contains("OK"), "{out}");
            eprintln!("{tileset} {seed}: {out}");
            shafts += out.lines().filter(|l| l.starts_with('{')).count();
        }
    }
    assert!(shafts >= 6, "{shafts} shafts");
}
