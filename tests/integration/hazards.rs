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
            "[hazards]\nrubble = 0.1\n",
            ["hazards.rubble", "unknown field"],
        ),
    ] {
        let p = small_cave_pipeline(dir.path(), 1, section);
        let err = fails(&["validate", arg(&p)]);
        for w in words {
            assert!(err.contains(w), "{section}: {err}");
        }
    }
}
