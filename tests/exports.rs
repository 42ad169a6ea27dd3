//! What every export shares, through the command line: formats chosen by `[[export]]` or
//! `--format`, recorded in world.toml; bad names and settings refused before anything is
//! generated; geometry formats without geometry refused (or skipped under `--no-mesh`); an
//! unwritable destination or a full disk leaves nothing behind.

mod common;

use std::path::Path;

use common::{arg, fails, ok, small_cave_pipeline};

/// Everything in a folder, names only (hidden leftovers included).
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn formats_from_the_command_line_are_written_once_and_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let p = small_cave_pipeline(
        dir.path(),
        2,
        "[[export]]\ntype = \"obj\"\nsplit = \"level\"\n",
    );
    let out = dir.path().join("w");
    ok(&["generate", arg(&p), "--out", arg(&out), "--format", "obj"]);
    for l in 0..2 {
        let part = out.join(format!("mesh/parts/level/level-{l}.obj"));
        let text = std::fs::read_to_string(&part).unwrap();
        assert_eq!(text.matches("\no ").count(), 1, "one object per OBJ file");
        assert!(
            out.join(format!("mesh/parts/level/level-{l}-collision.obj"))
                .is_file()
        );
    }
    let toml = std::fs::read_to_string(out.join("world.toml")).unwrap();
    assert_eq!(toml.matches("[[export]]").count(), 1, "obj once:\n{toml}");
    // world.toml makes the same folder again, exports included.
    let again = dir.path().join("again");
    ok(&[
        "generate",
        arg(&out.join("world.toml")),
        "--out",
        arg(&again),
    ]);
    // (world.toml differs only in where the pipeline came from.)
    common::assert_same_files(&out, &again, &["world.toml"]);
}

/// Only what was asked is written: `--format usd` writes USD and no OBJ (gigabytes for a large
/// world); with no format the mesh is OBJ + MTL; `obj` among the formats writes both. world.toml
/// records the formats, so it makes the same files again.
#[test]
fn a_format_writes_only_itself_and_obj_stays_the_default() {
    let dir = tempfile::tempdir().unwrap();
    let p = small_cave_pipeline(dir.path(), 1, "");
    let obj = ["mesh/world.obj", "mesh/world.mtl", "mesh/collision.obj"];
    for (formats, usd, with_obj) in [
        (None, false, true),
        (Some("usd"), true, false),
        (Some("usd,obj"), true, true),
        (Some("obj"), false, true),
    ] {
        let out = dir.path().join(format!("w-{}", formats.unwrap_or("none")));
        let mut args = vec!["generate", arg(&p), "--out", arg(&out)];
        if let Some(f) = formats {
            args.extend(["--format", f]);
        }
        ok(&args);
        assert_eq!(out.join("usd/world.usda").is_file(), usd, "{formats:?}");
        for f in obj {
            assert_eq!(out.join(f).is_file(), with_obj, "{formats:?}: {f}");
        }
        // The same files again from world.toml.
        let again = dir
            .path()
            .join(format!("again-{}", formats.unwrap_or("none")));
        ok(&[
            "generate",
            arg(&out.join("world.toml")),
            "--out",
            arg(&again),
        ]);
        common::assert_same_files(&out, &again, &["world.toml"]);
    }
}

#[test]
fn unknown_formats_and_settings_are_refused_before_generating() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("w");
    let e = fails(&["generate", "--out", arg(&out), "--format", "obj,fbx"]);
    assert!(
        e.contains("unknown exporter 'fbx'") && e.contains("obj"),
        "{e}"
    );
    let e = fails(&["generate", "--out", arg(&out), "--format", "obj,,usd"]);
    assert!(e.contains("separated by commas"), "{e}");

    let p = small_cave_pipeline(
        dir.path(),
        1,
        "[[export]]\ntype = \"obj\"\nsplit = \"levels\"\n",
    );
    let e = fails(&["generate", arg(&p), "--out", arg(&out)]);
    assert!(
        e.contains("small-cave.toml:") && e.contains("export[0].split") && e.contains("\"level\""),
        "{e}"
    );
    assert!(!out.exists());
}

#[test]
fn geometry_formats_need_a_tile_set_and_no_mesh_skips_them() {
    let dir = tempfile::tempdir().unwrap();
    let text = "[world]\nseed = 2\nrows = 20\ncols = 20\n[topology]\nt_junctions = 1\n[route]\ntype = \"linear\"\n[[export]]\ntype = \"obj\"\n";
    let p = dir.path().join("grid-only.toml");
    std::fs::write(&p, text).unwrap();
    let out = dir.path().join("w");
    let e = fails(&["generate", arg(&p), "--out", arg(&out)]);
    assert!(
        e.contains("exporter 'obj' writes geometry") && e.contains("[tileset]"),
        "{e}"
    );
    assert!(!out.exists());

    let p = small_cave_pipeline(
        dir.path(),
        1,
        "[[export]]\ntype = \"obj\"\nsplit = \"whole\"\n",
    );
    let run = common::subtgraph(&["generate", arg(&p), "--out", arg(&out), "--no-mesh"]);
    assert!(run.status.success());
    let note = String::from_utf8_lossy(&run.stderr);
    assert!(note.contains("skipping exporter 'obj'"), "{note}");
    assert!(out.join("occupancy.npy").is_file());
    assert!(!out.join("mesh").exists());
}

#[test]
fn an_unwritable_destination_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("a-file");
    std::fs::write(&file, b"not a folder").unwrap();
    let e = fails(&["generate", "--out", arg(&file.join("w")), "--no-mesh"]);
    assert!(
        e.contains("a-file is a file, not a folder") && e.contains("another --out"),
        "{e}"
    );
    assert_eq!(names(dir.path()), ["a-file"]);
}

/// A disk that fills mid-write (a file size limit, with SIGXFSZ ignored so writes fail with
/// EFBIG as they would with ENOSPC): an error naming the file, and no folder or leftover.
#[test]
fn a_full_disk_leaves_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let p = small_cave_pipeline(
        dir.path(),
        2,
        "[[export]]\ntype = \"obj\"\nsplit = \"level\"\n",
    );
    let out = dir.path().join("worlds").join("w");
    let script = "trap '' XFSZ; ulimit -f 2048; exec \"$0\" \"$@\"";
    let run = std::process::Command::new("sh")
        .args(["-c", script, env!("CARGO_BIN_EXE_subtgraph")])
        .args(["generate", arg(&p), "--out", arg(&out)])
        .output()
        .unwrap();
    assert!(
        !run.status.success(),
        "a 1 MiB file limit must stop a 7 MB mesh"
    );
    let e = String::from_utf8_lossy(&run.stderr);
    assert!(
        e.contains("writing mesh/") && e.contains("too large"),
        "{e}"
    );
    assert_eq!(names(&dir.path().join("worlds")), Vec::<String>::new());
}
