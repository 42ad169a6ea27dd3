//! What every export shares, through the command line: formats chosen by `[[export]]` or
//! `--format`, recorded in world.toml; bad names and settings refused before anything is
//! generated; geometry formats without geometry refused (or skipped under `--no-mesh`); an
//! unwritable destination or a full disk leaves nothing behind.

use crate::common;

use std::path::Path;

use common::{arg, fails, ok, small_cave_pipeline, subtgraph};

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

/// A file-size limit (`ulimit -f`) without the signal ignored: SIGXFSZ would end the process
/// silently mid-write; the tool catches it, so this is a clear error with nothing left behind.
#[test]
fn a_file_size_limit_is_an_error_like_a_full_disk() {
    let dir = tempfile::tempdir().unwrap();
    let p = small_cave_pipeline(dir.path(), 2, "");
    let out = dir.path().join("worlds").join("w");
    let run = std::process::Command::new("sh")
        .args(["-c", "ulimit -f 2048; exec \"$0\" \"$@\""])
        .arg(env!("CARGO_BIN_EXE_subtgraph"))
        .args(["generate", arg(&p), "--out", arg(&out)])
        .output()
        .unwrap();
    assert_eq!(
        run.status.code(),
        Some(1),
        "an error exit, not death by a signal: {:?}",
        run.status
    );
    let e = String::from_utf8_lossy(&run.stderr);
    assert!(e.contains("ulimit -f"), "{e}");
    assert_eq!(names(&dir.path().join("worlds")), Vec::<String>::new());
}

/// `--force` replaces only what the tool wrote: a folder that merely holds a file named
/// world.toml is refused, and so is a real world folder with a file of the user's in it.
#[test]
fn force_never_deletes_a_users_files() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("f");
    std::fs::create_dir(&f).unwrap();
    std::fs::write(f.join("world.toml"), "mine\n").unwrap();
    std::fs::write(f.join("data.bin"), "v\n").unwrap();
    let e = fails(&[
        "generate",
        "--preset",
        "cave",
        "--no-mesh",
        "--force",
        "--out",
        arg(&f),
    ]);
    assert!(e.contains("not a folder written by subtgraph"), "{e}");
    assert_eq!(std::fs::read_to_string(f.join("data.bin")).unwrap(), "v\n");
    assert_eq!(
        std::fs::read_to_string(f.join("world.toml")).unwrap(),
        "mine\n"
    );

    let w = dir.path().join("w");
    ok(&[
        "generate",
        "--preset",
        "cave",
        "--no-mesh",
        "--out",
        arg(&w),
    ]);
    std::fs::write(w.join("notes.md"), "my results\n").unwrap();
    let e = fails(&[
        "generate",
        "--preset",
        "cave",
        "--no-mesh",
        "--force",
        "--out",
        arg(&w),
    ]);
    assert!(e.contains("notes.md") && e.contains("did not write"), "{e}");
    assert_eq!(
        std::fs::read_to_string(w.join("notes.md")).unwrap(),
        "my results\n"
    );
    std::fs::remove_file(w.join("notes.md")).unwrap();
    ok(&[
        "generate",
        "--preset",
        "cave",
        "--no-mesh",
        "--force",
        "--seed",
        "3",
        "--out",
        arg(&w),
    ]);
    assert!(
        std::fs::read_to_string(w.join("world.toml"))
            .unwrap()
            .contains("seed = 3")
    );
    assert_eq!(names(dir.path()), ["f", "w"], "no leftovers");
}

/// `--out w/.` is `w`, and a long folder name leaves room for the temporary folder's name.
#[test]
fn odd_but_valid_out_paths_work() {
    let dir = tempfile::tempdir().unwrap();
    let w = dir.path().join("w");
    ok(&[
        "generate",
        "--preset",
        "cave",
        "--no-mesh",
        "--out",
        arg(&w),
    ]);
    ok(&[
        "generate",
        "--preset",
        "cave",
        "--no-mesh",
        "--force",
        "--out",
        arg(&w.join(".")),
    ]);
    let long = dir.path().join("x".repeat(240));
    ok(&[
        "generate",
        "--preset",
        "cave",
        "--no-mesh",
        "--out",
        arg(&long),
    ]);
    assert!(long.join("world.toml").is_file());
    let e = fails(&["plugins", "list", arg(dir.path())]);
    assert!(e.contains("is a folder, not a library"), "{e}");
}

/// Starts a long `generate` into `out`, waits until its hidden temporary folder exists, and
/// sends `signal`; returns the exit status and standard error.
fn interrupt_while_writing(out: &Path, signal: &str) -> (std::process::ExitStatus, String) {
    let parent = out.parent().unwrap();
    std::fs::create_dir_all(parent).unwrap();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_subtgraph"))
        .args([
            "generate",
            "--preset",
            "lava-tube",
            "--format",
            "obj,gltf,usd,sdf",
        ])
        .args(["--out", arg(out)])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    loop {
        let partial = names(parent).iter().any(|n| n.contains(".partial-"));
        if partial {
            break;
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before its folder was seen"
        );
        assert!(
            started.elapsed().as_secs() < 120,
            "no temporary folder appeared"
        );
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    std::thread::sleep(std::time::Duration::from_millis(50));
    let killed = std::process::Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let output = child.wait_with_output().unwrap();
    (
        output.status,
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

/// Ctrl-C or SIGTERM halfway removes the hidden temporary folder; after SIGKILL it stays, and
/// the next run into the same parent removes it.
#[test]
fn interrupted_and_killed_runs_leave_nothing_for_long() {
    use std::os::unix::process::ExitStatusExt;
    let dir = tempfile::tempdir().unwrap();
    let parent = dir.path().join("worlds");
    for (signal, code) in [("-INT", 130), ("-TERM", 143)] {
        let (status, err) = interrupt_while_writing(&parent.join("w"), signal);
        assert_eq!(status.code(), Some(code), "{signal}: {status:?} {err}");
        assert!(err.contains("removed 1 unfinished folder"), "{err}");
        assert_eq!(names(&parent), Vec::<String>::new(), "{signal}");
    }
    let (status, _) = interrupt_while_writing(&parent.join("w"), "-KILL");
    assert_eq!(status.signal(), Some(9));
    let left = names(&parent);
    assert!(
        left.len() == 1 && left[0].starts_with(".w.partial-"),
        "{left:?}"
    );
    // A user's look-alike folder (no manifest of ours) is never removed.
    let lookalike = parent.join(".x.partial-1-1");
    std::fs::create_dir(&lookalike).unwrap();
    let out = subtgraph(&[
        "generate",
        "--preset",
        "cave",
        "--no-mesh",
        "--out",
        arg(&parent.join("next")),
    ]);
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("removed 1 unfinished folder"), "{err}");
    assert_eq!(names(&parent), [".x.partial-1-1", "next"]);
}

/// `preview` and `stats` write where they are told, but never over a user's file: a picture
/// replaces only a picture `preview` drew, a report folder only a report.
#[test]
fn preview_and_stats_never_overwrite_a_users_files() {
    let dir = tempfile::tempdir().unwrap();
    let p = small_cave_pipeline(dir.path(), 1, "");
    let w = dir.path().join("w");
    ok(&["generate", arg(&p), "--out", arg(&w)]);
    let photo = dir.path().join("photo.png");
    std::fs::write(&photo, b"my holiday").unwrap();
    let e = fails(&["preview", arg(&w), "--size", "64x48", "--out", arg(&photo)]);
    assert!(e.contains("not a picture subtgraph preview drew"), "{e}");
    assert_eq!(std::fs::read(&photo).unwrap(), b"my holiday");
    let pic = dir.path().join("pic.png");
    ok(&["preview", arg(&w), "--size", "64x48", "--out", arg(&pic)]);
    ok(&["preview", arg(&w), "--size", "64x40", "--out", arg(&pic)]);

    let report = dir.path().join("report");
    ok(&["stats", arg(&w), "--out", arg(&report)]);
    ok(&["stats", arg(&w), "--out", arg(&report)]);
    std::fs::write(report.join("thesis.tex"), b"...").unwrap();
    let e = fails(&["stats", arg(&w), "--out", arg(&report)]);
    assert!(e.contains("thesis.tex"), "{e}");
    assert!(report.join("thesis.tex").is_file());
    let left: Vec<String> = names(dir.path());
    assert_eq!(
        left,
        ["photo.png", "pic.png", "report", "small-cave.toml", "w"]
    );
}
