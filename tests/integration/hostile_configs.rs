//! Hostile and careless pipeline files (issue 21 items 16, 19 and 20): keys nested past the
//! TOML reader's limit, values that say one thing and are refused for another, keys written
//! twice. Each message must name the key and line at fault, say what is accepted, and give
//! the same answer for the same value whether it is written out or left to its default.

use crate::common;

use std::path::{Path, PathBuf};

use common::{arg, subtgraph};

/// Asserts `subtgraph ARGS` failed with a message (exit 1), not a panic or a signal; returns
/// standard error.
fn refused(args: &[&str]) -> String {
    let out = subtgraph(args);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
    err
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// Issue 21 item 19: a 100,000-name dotted key under `[extra]` was reported as
/// "1:1: world: recursion limit" (the file's first table, its first line, and the reader's
/// words). Now the key's own line and name, the limit, and what to do; for a table header
/// and for a tile-set manifest too.
#[test]
fn a_key_nested_past_the_readers_limit_is_named_where_it_is() {
    let tmp = tempfile::tempdir().unwrap();
    let deep = vec!["a"; 100_000].join(".");
    let file = write(
        tmp.path(),
        "deep.toml",
        &format!("[world]\nseed = 1\nlevels = 1\n\n[extra]\n{deep} = 1\n"),
    );
    let out = tmp.path().join("w");
    for args in [
        vec!["validate", arg(&file)],
        vec!["generate", arg(&file), "--out", arg(&out)],
    ] {
        let err = refused(&args);
        assert!(
            err.contains("deep.toml:6:1: extra.a.a.a"),
            "the key and its line: {err}"
        );
        assert!(err.contains("100000 names") && err.contains("80"), "{err}");
        assert!(!err.contains("world"), "not the first table: {err}");
        assert!(err.len() < 600, "the key is cut: {} bytes", err.len());
    }
    assert!(!out.exists());
    // A table header, after other tables.
    let header = write(
        tmp.path(),
        "header.toml",
        &format!(
            "[world]\nseed = 1\n[route]\ntype = \"sine\"\n[{}]\nx = 1\n",
            vec!["t"; 90].join(".")
        ),
    );
    let err = refused(&["validate", arg(&header)]);
    assert!(
        err.contains("header.toml:5:2: t.t.t") && err.contains("90 names"),
        "{err}"
    );
    // Values nested past the limit were already placed; they are explained the same way.
    let value = write(
        tmp.path(),
        "value.toml",
        &format!(
            "[world]\nseed = 1\n[route]\ntype = \"sine\"\nx = {}1{}\n",
            "[".repeat(200),
            "]".repeat(200)
        ),
    );
    let err = refused(&["validate", arg(&value)]);
    assert!(
        err.contains("value.toml:5:") && err.contains("route.x"),
        "{err}"
    );
    assert!(err.contains("nest more than 80 deep"), "{err}");
    // A tile-set manifest read by the mesh-files tile set.
    let manifest = write(
        tmp.path(),
        "tiles.toml",
        &format!(
            "pitch = 80.0\nup = \"z\"\n\n{} = 1\n",
            vec!["m"; 500].join(".")
        ),
    );
    let err = subtgraph::tilesets::mesh_files::MeshFiles::open(&manifest)
        .err()
        .expect("refused")
        .to_string();
    assert!(
        err.contains("tiles.toml: line 4:") && err.contains("500 names"),
        "{err}"
    );
}
