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

/// `subtgraph validate` on a pipeline text; `Ok(stdout)` or `Err(stderr)` (a refusal, never
/// a panic).
fn validate(dir: &Path, text: &str) -> Result<String, String> {
    let file = write(dir, "p.toml", text);
    let out = subtgraph(&["validate", arg(&file)]);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    match out.status.code() {
        Some(0) => Ok(String::from_utf8_lossy(&out.stdout).into_owned()),
        Some(1) if !stderr.contains("panicked") => Err(stderr),
        code => panic!("{code:?}: {stderr}"),
    }
}

/// The message after `file:line:column: `, so two refusals of the same key compare equal
/// wherever in its line the reader stopped.
fn said(err: &str) -> &str {
    let line = err.lines().next().unwrap_or_default();
    let line = line.strip_prefix("error: ").unwrap_or(line);
    line.splitn(4, ':').nth(3).unwrap_or(line).trim()
}

/// Issue 21 item 20: a placement rule written twice was accepted silently (and drawn twice
/// as often); it is refused as a class written twice is.
#[test]
fn a_placement_rule_written_twice_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let world = "[world]\nseed = 1\nrows = 30\ncols = 30\n\n[artifacts]\n";
    let err = validate(
        tmp.path(),
        &format!("{world}placement = [\"floor\", \"wall\", \"floor\"]\n"),
    )
    .unwrap_err();
    assert!(
        err.contains("p.toml:7:") && err.contains("artifacts.placement"),
        "{err}"
    );
    assert!(err.contains("'floor' twice"), "{err}");
    assert!(
        validate(
            tmp.path(),
            &format!("{world}placement = [\"floor\", \"wall\"]\n")
        )
        .is_ok()
    );
}

/// Issue 21 item 20: `pillars = [-1, 2]` said "must be >= 0" though 0 is refused too. A
/// negative count and zero now get the same message, for pillars and for every `[world]`
/// key with a range (a negative seed, rows or attempts got the reader's "invalid value:
/// integer `-1`, expected u32"; a negative level count or `min_length` ">= 0").
#[test]
fn a_negative_count_is_told_what_zero_is_told() {
    let tmp = tempfile::tempdir().unwrap();
    let block = |pillars: &str| {
        format!(
            "[world]\nrows = 30\ncols = 30\n\n[[topology.structure]]\ntype = \"room-and-pillar\"\n\
             count = 1\npillars = {pillars}\n"
        )
    };
    let zero = validate(tmp.path(), &block("[0, 2]")).unwrap_err();
    assert!(zero.contains("at least 1"), "{zero}");
    for negative in ["[-1, 2]", "[2, -1]", "[2, [-3, 4]]"] {
        let err = validate(tmp.path(), &block(negative)).unwrap_err();
        assert_eq!(said(&err), said(&zero), "pillars = {negative}");
        assert!(err.contains("p.toml:8:"), "at the key's line: {err}");
    }
    // A value of the wrong type inside `pillars` is placed on its line too, in one line.
    let err = validate(tmp.path(), &block("[2.5, 3]")).unwrap_err();
    assert!(
        err.contains("p.toml:8:") && err.lines().count() == 1,
        "{err}"
    );
    for (key, outside, beyond) in [
        ("levels", "-1", "0"),
        ("levels", "[-1, 2]", "[0, 2]"),
        ("levels", "-1", "65"),
        ("min_length", "-5.0", "0.0"),
        ("rows", "-1", "0"),
        ("attempts", "-1", "0"),
        ("seed", "-1", "9223372036854775808"),
    ] {
        let text = |v: &str| {
            let cols = if key == "rows" { "cols = 30\n" } else { "" };
            format!("[world]\n{key} = {v}\n{cols}")
        };
        let a = validate(tmp.path(), &text(outside)).unwrap_err();
        let b = validate(tmp.path(), &text(beyond)).unwrap_err();
        assert_eq!(said(&a), said(&b), "world.{key} = {outside} and = {beyond}");
        assert!(said(&a).starts_with(&format!("world.{key}: ")), "{a}");
        assert!(!a.contains("invalid value") && !a.contains(">= 0"), "{a}");
    }
}

/// Issue 21 item 20: on a cave of 12 m tiles, writing the default `min_clearance = [1.0,
/// 1.0]` was refused while leaving it out was accepted: the default was never checked, and
/// a written value was held to a stricter fit (with half a collision lattice cell of slack)
/// than the passage itself needs. The same value now gives the same answer: a robot's box
/// must fit the unsqueezed passage, written or by default (on 12 m tiles it does; on 8 m
/// tiles, 2.1 m wide at their narrowest, it does not, and the value the refusal suggests is
/// made).
#[test]
fn the_default_min_clearance_is_checked_as_if_written() {
    let tmp = tempfile::tempdir().unwrap();
    let cave = |pitch: &str, extra: &str| {
        format!(
            "[world]\nseed = 1\nrows = 30\ncols = 30\ntile_pitch = {pitch}\n\n[tileset]\n\
             type = \"cave\"\n{extra}"
        )
    };
    let written = "min_clearance = [1.0, 1.0]\n";
    assert!(validate(tmp.path(), &cave("12.0", "")).is_ok());
    assert!(validate(tmp.path(), &cave("12.0", written)).is_ok());
    let left_out = validate(tmp.path(), &cave("8.0", "")).unwrap_err();
    let written = validate(tmp.path(), &cave("8.0", written)).unwrap_err();
    for err in [&left_out, &written] {
        assert!(
            err.contains("min_clearance = [1, 1]") && err.contains("does not fit"),
            "{err}"
        );
    }
    assert!(left_out.contains("its default"), "{left_out}");
    assert_eq!(
        left_out.replace(" (its default: a small ground robot)", ""),
        written
    );
    let fix = written
        .split("set [tileset] min_clearance = ")
        .nth(1)
        .and_then(|s| s.split(" or less").next())
        .unwrap_or_else(|| panic!("a value that fits: {written}"));
    let made = validate(
        tmp.path(),
        &cave("8.0", &format!("min_clearance = {fix}\n")),
    );
    assert!(made.is_ok(), "the suggested {fix}: {made:?}");
}

/// Issue 21 item 16's siblings: computed numbers are shown rounded (the default level height
/// of 12 m tiles, 0.8 x 12, is 9.600000000000001 in binary), and shares written to add up
/// to the whole floor are accepted though their binary sum is a hair above 1.
#[test]
fn computed_numbers_are_shown_rounded_and_whole_shares_accepted() {
    let tmp = tempfile::tempdir().unwrap();
    let mine = "[world]\nseed = 1\nlevels = 2\nrows = 30\ncols = 30\ntile_pitch = 12.0\n\
                connections = \"ramp\"\n\n[tileset]\ntype = \"mine\"\nresolution = 8\n";
    let err = validate(tmp.path(), mine).unwrap_err();
    assert!(err.contains("levels 9.6 m apart"), "{err}");
    assert!(!err.contains("00000"), "{err}");
    let shares = "[world]\nseed = 1\nrows = 30\ncols = 30\n\n[tileset]\ntype = \"cave\"\n\n\
                  [hazards]\nfriction = { mud = 0.34, ice = 0.56, sand = 0.1 }\n";
    assert!(validate(tmp.path(), shares).is_ok());
    let more = shares.replace("sand = 0.1", "sand = 0.11");
    let err = validate(tmp.path(), &more).unwrap_err();
    assert!(
        err.contains("hazards.friction") && err.contains("more than the whole floor"),
        "{err}"
    );
}
