//! Floor hazards (`[hazards] friction`): the patches' friction read back from the MuJoCo
//! export by MuJoCo itself (`tests/readers/hazards_check.py`), their shares as asked, and bad
//! sections refused.

use crate::common;

use common::{arg, fails, ok, read_with_python, small_cave_pipeline};

#[test]
fn friction_patches_read_back_from_mujoco() {
    let dir = tempfile::tempdir().unwrap();
    let p = small_cave_pipeline(
        dir.path(),
        2,
        "[hazards]\nfriction = { mud = 0.2, ice = 0.1, wet-rock = 0.05 }\n",
    );
    let w = dir.path().join("w");
    ok(&["generate", arg(&p), "--format", "mjcf", "--out", arg(&w)]);
    let doc: serde_json::Value =
        serde_json::from_slice(&std::fs::read(w.join("ground_truth/hazards.json")).unwrap())
            .unwrap();
    let patches = doc["patches"].as_array().unwrap();
    assert!(patches.len() > 10, "{doc}");
    let Some(out) = read_with_python(&["numpy", "mujoco"], "hazards_check.py", &[arg(&w)]) else {
        return;
    };
    for m in ["mud", "ice", "wet-rock"] {
        assert!(out.contains(&format!("{m}: ")), "{out}");
    }
    // Without the section: no patches, and the MJCF has no friction of its own.
    let plain = small_cave_pipeline(dir.path(), 2, "");
    let pw = dir.path().join("plain");
    ok(&[
        "generate",
        arg(&plain),
        "--format",
        "mjcf",
        "--out",
        arg(&pw),
    ]);
    assert!(!pw.join("ground_truth/hazards.json").exists());
    let level = std::fs::read_to_string(pw.join("mujoco/level-0.xml")).unwrap();
    assert!(!level.contains("friction="));
}

#[test]
fn bad_hazard_sections_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (section, words) in [
        (
            "[hazards]\nfriction = { mud = 2 }\n",
            ["hazards.friction", "from 0 to 1"],
        ),
        (
            "[hazards]\nfriction = { mud = 0.7, ice = 0.6 }\n",
            ["hazards.friction", "more than the whole floor"],
        ),
        (
            "[hazards]\nfriction = { lava = 0.1 }\n",
            ["unknown variant `lava`", "mud"],
        ),
        (
            "[hazards]\nquicksand = 0.1\n",
            ["hazards.quicksand", "unknown field"],
        ),
    ] {
        let p = small_cave_pipeline(dir.path(), 1, section);
        let err = fails(&["validate", arg(&p)]);
        for w in words {
            assert!(err.contains(w), "{section}: {err}");
        }
    }
}

#[test]
fn friction_patches_read_back_from_sdf_and_usd() {
    let dir = tempfile::tempdir().unwrap();
    let p = small_cave_pipeline(
        dir.path(),
        2,
        "[hazards]\nfriction = { mud = 0.2, ice = 0.1, wet-rock = 0.05 }\n",
    );
    let w = dir.path().join("w");
    ok(&["generate", arg(&p), "--format", "sdf,usd", "--out", arg(&w)]);
    let doc: serde_json::Value =
        serde_json::from_slice(&std::fs::read(w.join("ground_truth/hazards.json")).unwrap())
            .unwrap();
    let patches = doc["patches"].as_array().unwrap();
    assert!(patches.len() > 10, "{doc}");
    // libsdformat: each level model has its rock collision (no <surface>: the default) and a
    // collision per material on it, with that material's friction.
    if let Some(report) = common::sdf_report(dir.path(), &w.join("gazebo/world.sdf")) {
        let frictions: Vec<Vec<&str>> = report
            .lines()
            .filter_map(|l| l.strip_prefix("friction "))
            .map(|l| l.split(' ').collect())
            .collect();
        for m in ["mud", "ice", "wet-rock"] {
            let want = patches.iter().find(|p| p["material"] == m).unwrap()["friction"]
                .as_f64()
                .unwrap();
            let got: Vec<f64> = frictions
                .iter()
                .filter(|f| f[1] == format!("collision-{m}"))
                .map(|f| f[0].parse().unwrap())
                .collect();
            assert!(!got.is_empty(), "{m}: {report}");
            assert!(
                got.iter().all(|&mu| (mu - want).abs() < 1e-9),
                "{m}: {got:?}"
            );
        }
        assert!(
            frictions
                .iter()
                .filter(|f| f[1] == "collision" && f[2].starts_with("subt-"))
                .all(|f| f[0] == "default"),
            "{report}"
        );
    }
    let Some(out) = read_with_python(
        &["numpy", "trimesh", "pxr"],
        "hazards_usd_check.py",
        &[arg(&w)],
    ) else {
        return;
    };
    for m in ["mud", "ice", "wet-rock"] {
        assert!(out.contains(&format!("{m}: ")), "{out}");
    }
    // Without the section no trace of hazards: one collision per part, only the rock.
    let plain = small_cave_pipeline(dir.path(), 2, "");
    let pw = dir.path().join("plain");
    ok(&[
        "generate",
        arg(&plain),
        "--format",
        "sdf,usd",
        "--out",
        arg(&pw),
    ]);
    let sdf = std::fs::read_to_string(pw.join("gazebo/world.sdf")).unwrap();
    assert!(!sdf.contains("<surface>") && !sdf.contains("-collision-"));
    assert!(!pw.join("mesh/hazards").exists());
    let root = std::fs::read_to_string(pw.join("usd/world.usda")).unwrap();
    assert!(!root.contains("subtgraph:hazard"));
}

#[test]
fn patched_tiles_are_labelled_with_their_material() {
    let dir = tempfile::tempdir().unwrap();
    let p = small_cave_pipeline(
        dir.path(),
        2,
        "[hazards]\nfriction = { mud = 0.2, sand = 0.1 }\n",
    );
    let w = dir.path().join("w");
    ok(&[
        "generate",
        arg(&p),
        "--format",
        "ground-truth",
        "--out",
        arg(&w),
    ]);
    let read = |f: &str| -> serde_json::Value {
        serde_json::from_slice(&std::fs::read(w.join("ground_truth").join(f)).unwrap()).unwrap()
    };
    let patched: std::collections::BTreeMap<(u64, u64, u64), String> =
        read("hazards.json")["patches"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| {
                let c = &p["cell"];
                let key = ["level", "row", "col"].map(|k| c[k].as_u64().unwrap());
                (
                    (key[0], key[1], key[2]),
                    p["material"].as_str().unwrap().to_owned(),
                )
            })
            .collect();
    assert!(patched.len() > 10, "{patched:?}");
    let labels = read("semantic_labels.json");
    let tiles = labels["tiles"].as_array().unwrap();
    let csv = std::fs::read_to_string(w.join("ground_truth/semantic_labels.csv")).unwrap();
    let mut lines = csv.lines();
    // `hazard` is the last column (after `start`, and `features` when chambers or squeezes
    // were made).
    let header = lines.next().unwrap();
    assert!(
        header.ends_with(",start,hazard") || header.ends_with(",start,features,hazard"),
        "{header}"
    );
    let mut labelled = 0;
    for (t, line) in tiles.iter().zip(lines) {
        let key = ["level", "row", "col"].map(|k| t[k].as_u64().unwrap());
        let want = patched.get(&(key[0], key[1], key[2]));
        assert_eq!(t["hazard"].as_str(), want.map(String::as_str), "{t}");
        assert_eq!(
            line.rsplit(',').next().unwrap(),
            want.map_or("", |m| m),
            "{line}"
        );
        labelled += usize::from(want.is_some());
    }
    assert_eq!(labelled, patched.len());
    // Without the section: no hazard key and the CSV's columns as before.
    let plain = small_cave_pipeline(dir.path(), 2, "");
    let pw = dir.path().join("plain");
    ok(&[
        "generate",
        arg(&plain),
        "--format",
        "ground-truth",
        "--out",
        arg(&pw),
    ]);
    let csv = std::fs::read_to_string(pw.join("ground_truth/semantic_labels.csv")).unwrap();
    // (A `features` column follows `start` when the tile set made chambers or squeezes.)
    let header = csv.lines().next().unwrap();
    assert!(
        header == "level,row,col,kind,code,rotation,openings,x,y,z,start"
            || header == "level,row,col,kind,code,rotation,openings,x,y,z,start,features",
        "{header}"
    );
    let json = std::fs::read_to_string(pw.join("ground_truth/semantic_labels.json")).unwrap();
    assert!(!json.contains("hazard"));
}

#[test]
fn friction_patches_read_back_from_pybullet() {
    let dir = tempfile::tempdir().unwrap();
    let p = small_cave_pipeline(
        dir.path(),
        2,
        "[hazards]\nfriction = { mud = 0.2, ice = 0.1, wet-rock = 0.05 }\n",
    );
    let w = dir.path().join("w");
    ok(&[
        "generate",
        arg(&p),
        "--format",
        "urdf,ground-truth",
        "--out",
        arg(&w),
    ]);
    let Some(out) = read_with_python(&["pybullet"], "hazards_pybullet_check.py", &[arg(&w)]) else {
        return;
    };
    for m in ["mud", "ice", "wet-rock"] {
        assert!(out.contains(&format!("{m}: ")), "{out}");
    }
    // Without the section: one link for the world, as before.
    let plain = small_cave_pipeline(dir.path(), 2, "");
    let pw = dir.path().join("plain");
    ok(&[
        "generate",
        arg(&plain),
        "--format",
        "urdf",
        "--out",
        arg(&pw),
    ]);
    let urdf = std::fs::read_to_string(pw.join("urdf/world.urdf")).unwrap();
    assert!(!urdf.contains("hazard-") && !urdf.contains("lateral_friction"));
}
