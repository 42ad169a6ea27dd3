//! The mine's wall finish (issue 24 item 1): blasted drifts (the default) have decimetres of
//! relief against a passage fitted apart from our code (tests/readers/wall_relief_check.py,
//! numpy over the exported OBJ), shotcrete less, `finish = "none"` the plain walls of before,
//! and the floor between the walls stays smooth (tests/readers/floor_flatness_check.py); the
//! relief holds a LiDAR's scan
//! registration along the drift (the sensor's degeneracy labels); the same bytes on 1 and 3
//! threads; refuge bays are recesses in the mesh exactly where the semantic labels say; mesh
//! panels cover the back and the walls from `mesh_from` up, with the wire grid and the
//! half-barrel marks in their textures (tests/readers/mesh_panels_check.py), and off change
//! no geometry; bad keys refused with what to change.

use std::path::Path;

use crate::common::{self, arg, generate_formats as generate, small_mine};

/// The wall relief RMS (cm) the independent reader measures on `world`, or `None` when the
/// readers are not installed.
fn relief_cm(world: &Path) -> Option<f64> {
    let out = common::read_with_python(&["numpy"], "wall_relief_check.py", &[arg(world)])?;
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert!(
        v["sides"].as_u64().unwrap() >= 20,
        "enough straight walls: {v}"
    );
    Some(v["relief_rms_cm"].as_f64().unwrap())
}

#[test]
fn blasted_walls_have_decimetres_of_relief_shotcrete_less_and_none_least() {
    let dir = tempfile::tempdir().unwrap();
    let mut rms = Vec::new();
    for (name, extra) in [
        // The default finish is blasted.
        ("blasted", ""),
        ("shotcrete", "finish = \"shotcrete\""),
        ("none", "finish = \"none\""),
        ("rougher", "relief = 25"),
    ] {
        let out = dir.path().join(name);
        // Ground truth too: the reader leaves out the cells labelled with a refuge bay.
        generate(
            &small_mine(dir.path(), name, extra),
            &out,
            "obj,ground-truth",
        );
        let Some(r) = relief_cm(&out) else { return };
        std::fs::remove_dir_all(&out).unwrap();
        rms.push(r);
    }
    let [blasted, shotcrete, none, rougher] = rms[..] else {
        unreachable!()
    };
    // The default relief is 15 cm RMS of the field; the lattice smooths a little of it.
    assert!(blasted >= 10.0, "blasted walls: {blasted:.1} cm RMS");
    assert!(
        none < 0.5 * blasted,
        "none {none:.1} vs blasted {blasted:.1}"
    );
    assert!(
        shotcrete < 0.6 * blasted && shotcrete > none,
        "shotcrete {shotcrete:.1} between none {none:.1} and blasted {blasted:.1}"
    );
    assert!(rougher > 1.3 * blasted, "relief = 25: {rougher:.1} cm");
}

/// The blasted relief moves the walls and the back, never the floor: in the default mine, 95 %
/// of the floor's vertices within 2 m of a straight drift's axis (where a robot drives) are
/// within a centimetre of a smooth floor fitted apart from our code, while the same drifts'
/// walls have a decimetre of relief or more. (Added to the whole section, as it was first, the
/// relief reached the floor through the lattice's interpolation: 5 % of it 4.4 cm off, and a
/// ramp's foot stepped by 15 degrees.)
#[test]
fn blasted_relief_leaves_the_floor_smooth() {
    let dir = tempfile::tempdir().unwrap();
    let world = dir.path().join("blasted");
    generate(
        &small_mine(dir.path(), "blasted", ""),
        &world,
        "obj,ground-truth",
    );
    let Some(relief) = relief_cm(&world) else {
        return;
    };
    assert!(relief >= 10.0, "blasted walls: {relief:.1} cm RMS");
    let out = common::read_with_python(
        &["numpy"],
        "floor_flatness_check.py",
        &[arg(&world), "--max-cm", "1.0"],
    )
    .unwrap();
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert!(
        v["cells"].as_u64().unwrap() >= 10,
        "enough straight floors: {v}"
    );
    eprintln!("walls {relief:.1} cm RMS; floor {v}");
}

#[test]
fn blasted_drifts_hold_a_lidars_registration() {
    let dir = tempfile::tempdir().unwrap();
    let mut shares = Vec::new();
    // The walls alone (blasted is the default finish): the services (bolts,
    // duct...) hold registration too (tests/integration/mine_services.rs,
    // scripts/measure-mine-services).
    for (name, extra) in [
        ("blasted", "services = false"),
        ("none", "finish = \"none\"\nservices = false"),
    ] {
        let world = dir.path().join(name);
        generate(&small_mine(dir.path(), name, extra), &world, "ground-truth");
        let seq = dir.path().join(format!("{name}-seq"));
        common::ok(&[
            "sense",
            arg(&world),
            "--out",
            arg(&seq),
            "--format",
            "kitti",
            "--duration",
            "30",
        ]);
        let v: serde_json::Value =
            serde_json::from_slice(&std::fs::read(seq.join("sequence.json")).unwrap()).unwrap();
        let scans = v["scans"].as_array().unwrap();
        // Scans the label calls sliding (issue 39: the translation least constrained along
        // the platform's travel, calibrated against KISS-ICP), since the LiDAR casts on the
        // visual surface, where neither wall is degenerate by the older score: blasted 16 %
        // and smooth 56 % on this mine.
        let bad = scans
            .iter()
            .filter(|s| s["degeneracy"]["slides"].as_bool() == Some(true))
            .count();
        shares.push(bad as f64 / scans.len() as f64);
        std::fs::remove_dir_all(&seq).unwrap();
    }
    assert!(
        shares[0] < 0.3,
        "blasted: {:.0} % sliding",
        100.0 * shares[0]
    );
    assert!(
        shares[1] > 2.0 * shares[0],
        "smooth walls should slide far more often: {shares:?}"
    );
}

#[test]
fn refuge_bays_are_recesses_where_the_labels_say() {
    let dir = tempfile::tempdir().unwrap();
    let world = dir.path().join("bays");
    generate(
        &small_mine(dir.path(), "bays", "refuge_spacing = 60"),
        &world,
        "obj,ground-truth",
    );
    // The reader finds the recesses in the mesh and fails when they and the labels differ.
    let Some(out) = common::read_with_python(&["numpy"], "refuge_bay_check.py", &[arg(&world)])
    else {
        return;
    };
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    let (bays, straight) = (
        v["recesses"].as_array().unwrap().len() as f64,
        v["straight_cells"].as_f64().unwrap(),
    );
    // One bay per 60 m of straight drift: a third of the 20 m straight tiles, drawn.
    assert!(
        (0.15..0.55).contains(&(bays / straight)),
        "{bays} bays in {straight} straight tiles"
    );
    // Off, none: the reader finds no recess either.
    let none = dir.path().join("none");
    generate(
        &small_mine(dir.path(), "none", "refuge_spacing = 0"),
        &none,
        "obj,ground-truth",
    );
    let out = common::read_with_python(&["numpy"], "refuge_bay_check.py", &[arg(&none)]).unwrap();
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(v["recesses"].as_array().unwrap().len(), 0, "{v}");
}

#[test]
fn mesh_panels_cover_the_back_from_mesh_from_up_and_off_change_no_geometry() {
    let dir = tempfile::tempdir().unwrap();
    let (on, off) = (dir.path().join("on"), dir.path().join("off"));
    generate(
        &small_mine(dir.path(), "on", "mesh_from = 2.5"),
        &on,
        "obj,ground-truth",
    );
    generate(
        &small_mine(dir.path(), "off", "mesh_from = 0"),
        &off,
        "obj,ground-truth",
    );
    // Off, the ground truth is the same: the panels are paint on the same rock.
    for f in [
        "mesh/collision.obj",
        "ground_truth/graph.json",
        "ground_truth/free_space.npy",
    ] {
        assert!(
            std::fs::read(on.join(f)).unwrap() == std::fs::read(off.join(f)).unwrap(),
            "{f} changed with the mesh panels"
        );
    }
    let labels = |w: &Path| std::fs::read_to_string(w.join("ground_truth/semantic_labels.json"));
    assert!(labels(&on).unwrap().contains("\"mesh-panels\""));
    assert!(!labels(&off).unwrap().contains("mesh-panels"));
    assert!(!off.join("mesh/textures/meshed-wall-albedo.png").exists());
    let Some(out) = common::read_with_python(
        &["numpy", "PIL"],
        "mesh_panels_check.py",
        &[arg(&on), "--mesh-from", "2.5", "--plain", arg(&off)],
    ) else {
        return;
    };
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    let f = |k: &str| v[k].as_f64().unwrap();
    // The mesh ends 2.5 m up, within a lattice cell (0.83 m) and the relief.
    assert!(f("meshed_low_m") > 2.5 - 1.0, "{v}");
    assert!(f("wall_high_m") < 2.5 + 1.0, "{v}");
    assert!(f("meshed_low_m") < f("wall_high_m"), "the two meet: {v}");
    // The whole back is under mesh.
    assert!(f("back_meshed_share") > 0.95, "{v}");
    // Its texture is a grid of 100 mm cells (30 per 3 m repeat) both ways; the rock below
    // carries half-barrel marks along the drift, which the rock of a world without mesh
    // (whose back would show them across a drift running north) does not.
    assert_eq!(v["grid_cycles"], serde_json::json!([30, 30]), "{v}");
    assert!(f("mark_correlation") > 0.15, "{v}");
    assert!(f("plain_mark_correlation").abs() < 0.08, "{v}");
    // The same triangles, only their materials changed.
    assert_eq!(v["same_geometry"], true, "{v}");
    assert_eq!(v["plain_meshed"], 0, "{v}");
}

#[test]
fn blasted_mine_is_the_same_on_one_and_three_threads() {
    let dir = tempfile::tempdir().unwrap();
    // The default (blasted) finish with its own round length.
    let pipeline = small_mine(dir.path(), "mine", "round_length = 3.0");
    common::assert_same_on_one_and_three_threads(dir.path(), &pipeline, "obj,ground-truth");
}

#[test]
fn finish_keys_are_checked_with_what_to_change() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    for (extra, said) in [
        (
            "finish = \"granite\"",
            "\"blasted\", \"shotcrete\" or \"none\"",
        ),
        ("relief = 80", "centimetres RMS"),
        ("round_length = 0.1", "advance of one blast round"),
        ("roughness = 0.1\nfinish = \"blasted\"", "set relief"),
        ("refuge_spacing = 5", "metres of straight drift per bay"),
        (
            "mesh_from = 0.1",
            "where the mesh over the walls and back begins",
        ),
        (
            "mesh_from = -2",
            "where the mesh over the walls and back begins",
        ),
    ] {
        let p = small_mine(dir.path(), "bad", extra);
        let err = common::fails(&["generate", arg(&p), "--out", arg(&out)]);
        assert!(err.contains(said), "{extra}: {err}");
        assert!(!out.exists(), "nothing written for {extra}");
    }
    let cave = dir.path().join("cave.toml");
    std::fs::write(
        &cave,
        "[tileset]\ntype = \"cave\"\nfinish = \"shotcrete\"\n",
    )
    .unwrap();
    let err = common::fails(&["generate", arg(&cave), "--out", arg(&out)]);
    assert!(err.contains("only mine has"), "{err}");
    std::fs::write(&cave, "[tileset]\ntype = \"cave\"\nmesh_from = 2\n").unwrap();
    let err = common::fails(&["generate", arg(&cave), "--out", arg(&out)]);
    assert!(
        err.contains("mesh panels") && err.contains("mesh_from"),
        "{err}"
    );
}
