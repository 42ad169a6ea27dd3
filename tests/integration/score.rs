//! `subtgraph score` on synthetic runs with known answers (`tests/readers/score_inputs.py`):
//! reports with noise below and above 5 m, duplicates and wrong classes, in CSV and JSON;
//! maps sampled from the free space of some graph edges only, in every cloud format, which
//! must give exactly those edges' coverage; and bad input refused naming the row or point.

use crate::common;

use std::path::{Path, PathBuf};

use common::{arg, fails, ok, read_with_python, small_cave_pipeline};
use serde_json::Value;

/// A two-level small cave with 12 artifacts 15 m apart and its free space.
fn world(dir: &Path) -> PathBuf {
    let p = small_cave_pipeline(
        dir,
        2,
        "[artifacts]\ncount = 12\nmin_distance_from_start = 20\nmin_spacing = 15\n",
    );
    let out = dir.join("world");
    ok(&[
        "generate",
        arg(&p),
        "--format",
        "free-space",
        "--out",
        arg(&out),
    ]);
    out
}

fn json(path: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

#[test]
fn reports_and_maps_with_known_answers_score_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let w = world(dir.path());
    let inputs = dir.path().join("inputs");
    if read_with_python(&["numpy"], "score_inputs.py", &[arg(&w), arg(&inputs)]).is_none() {
        return;
    }
    let expected = json(&inputs.join("expected.json"));
    for (k, (reports, map)) in [
        ("reports.csv", "map-binary.ply"),
        ("reports.json", "map-ascii.ply"),
        ("reports.csv", "map-binary.pcd"),
        ("reports.csv", "map-ascii.pcd"),
        ("reports.csv", "map-compressed.pcd"),
        ("reports.csv", "map.npy"),
    ]
    .into_iter()
    .enumerate()
    {
        let out = dir.path().join(format!("score-{k}"));
        // radius 0: a voxel is covered when it holds a point; with 1 m the covered edges'
        // neighbours are nodes, so the edges' shares are the same.
        for radius in ["0", "1"] {
            let summary = ok(&[
                "score",
                arg(&w),
                "--reports",
                arg(&inputs.join(reports)),
                "--map",
                arg(&inputs.join(map)),
                "--radius",
                radius,
                "--out",
                arg(&out),
                "--force",
            ]);
            assert!(summary.contains("score "), "{summary}");
            let s = json(&out.join("score.json"));
            for key in ["scored", "duplicate", "wrong_class", "false_reports"] {
                assert_eq!(
                    s["outcomes"][key], expected["reports"][key],
                    "{reports}: {key}"
                );
            }
            assert_eq!(s["score"], expected["reports"]["scored"]);
            let found: Vec<u64> = s["artifacts"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|a| a["found"] == true)
                .map(|a| a["id"].as_u64().unwrap())
                .collect();
            let want: Vec<u64> = expected["found"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_u64().unwrap())
                .collect();
            assert_eq!(found, want, "{reports}");
            let map = &s["map"];
            assert_eq!(map["points"], expected["points"], "{map}");
            let edges = map["edges"].as_array().unwrap();
            for id in expected["covered_edges"].as_array().unwrap() {
                let e = &edges[id.as_u64().unwrap() as usize];
                assert_eq!(e["coverage"], 1.0, "{map} edge {id}");
            }
            for id in expected["uncovered_edges"].as_array().unwrap() {
                let e = &edges[id.as_u64().unwrap() as usize];
                assert_eq!(e["covered_voxels"], 0, "{map} edge {id}: {e}");
            }
            if radius == "0" {
                for (l, want) in expected["level_shares"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .enumerate()
                {
                    let got = map["levels"][l]["coverage"].as_f64().unwrap();
                    assert!(
                        (got - want.as_f64().unwrap()).abs() < 1e-12,
                        "level {l}: {got} vs {want}"
                    );
                }
            }
            // Voxel centres deep in the passages are far from the surface: map errors.
            assert!(map["errors"].as_u64().unwrap() > 0);
            for f in [
                "reports.csv",
                "artifacts.csv",
                "coverage.csv",
                "level-0.png",
                "level-1.png",
            ] {
                assert!(out.join(f).is_file(), "{f}");
            }
        }
    }
}

#[test]
fn a_map_of_the_surface_has_no_map_errors() {
    // Points on the collision surface (the collision mesh's vertices) are all within the
    // tolerance: the negative control of the map error above.
    let dir = tempfile::tempdir().unwrap();
    let w = world(dir.path());
    let obj = std::fs::read_to_string(w.join("mesh/collision.obj")).unwrap();
    let mut ply = String::new();
    let verts: Vec<&str> = obj.lines().filter_map(|l| l.strip_prefix("v ")).collect();
    ply.push_str(&format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
        verts.len()
    ));
    for v in &verts {
        ply.push_str(v);
        ply.push('\n');
    }
    let cloud = dir.path().join("surface.ply");
    std::fs::write(&cloud, ply).unwrap();
    let reports = dir.path().join("none.csv");
    std::fs::write(&reports, "time,class,x,y,z\n").unwrap();
    let out = dir.path().join("s");
    ok(&[
        "score",
        arg(&w),
        "--reports",
        arg(&reports),
        "--map",
        arg(&cloud),
        "--out",
        arg(&out),
    ]);
    let s = json(&out.join("score.json"));
    assert_eq!(s["map"]["errors"], 0, "{}", s["map"]);
    assert_eq!(s["score"], 0);
    let cov = s["map"]["total"]["coverage"].as_f64().unwrap();
    assert!(
        cov > 0.2 && cov < 1.0,
        "the surface's points cover the free space near it: {cov}"
    );
}

#[test]
fn bad_input_is_refused_naming_the_row_or_point() {
    let dir = tempfile::tempdir().unwrap();
    let w = world(dir.path());
    let out = dir.path().join("s");
    let write = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let good = write("good.csv", "time,class,x,y,z\n1,rope,10,10,0\n");
    let cases = [
        (
            write(
                "class.csv",
                "time,class,x,y,z\n1,rope,10,10,0\n2,phone,1,2,3\n",
            ),
            None,
            vec!["row 3", "unknown artifact class 'phone'", "cell-phone"],
        ),
        (
            write("nan.csv", "time,class,x,y,z\n1,rope,NaN,10,0\n"),
            None,
            vec!["row 2", "finite"],
        ),
        (
            write("empty.csv", ""),
            None,
            vec!["empty", "time,class,x,y,z"],
        ),
        (
            write("header.csv", "t,class,x,y,z\n"),
            None,
            vec!["no `time` column"],
        ),
        (
            write("mm.csv", "time,class,x,y,z\n1,rope,100000,200000,0\n"),
            None,
            vec!["row 2", "outside the world", "world frame in metres"],
        ),
        (
            good.clone(),
            Some(write(
                "mm.ply",
                "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n10 10 1\n10000 20000 1000\n",
            )),
            vec!["point 1", "outside the world", "millimetres"],
        ),
        (
            good.clone(),
            Some(write(
                "nan.ply",
                "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n10 10 1\n1 nan 1\n",
            )),
            vec!["point 1", "finite"],
        ),
        (good.clone(), Some(write("empty.pcd", "")), vec!["empty"]),
    ];
    for (reports, map, words) in cases {
        let mut args = vec![
            "score",
            arg(&w),
            "--reports",
            arg(&reports),
            "--out",
            arg(&out),
        ];
        if let Some(m) = &map {
            args.extend(["--map", arg(m)]);
        }
        let err = fails(&args);
        for word in words {
            assert!(err.contains(word), "{reports:?} {map:?}: {err}");
        }
        assert!(!out.exists(), "nothing written on bad input");
    }
    // A world without artifacts says how to get them; an existing folder is not replaced.
    let plain = small_cave_pipeline(dir.path(), 1, "");
    let pw = dir.path().join("plain");
    ok(&["generate", arg(&plain), "--no-mesh", "--out", arg(&pw)]);
    let err = fails(&[
        "score",
        arg(&pw),
        "--reports",
        arg(&good),
        "--out",
        arg(&out),
    ]);
    assert!(err.contains("[artifacts]"), "{err}");
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("notes.md"), "mine").unwrap();
    let err = fails(&[
        "score",
        arg(&w),
        "--reports",
        arg(&good),
        "--out",
        arg(&out),
        "--force",
    ]);
    assert!(err.contains("refusing"), "{err}");
    assert_eq!(
        std::fs::read_to_string(out.join("notes.md")).unwrap(),
        "mine"
    );
}
