//! `scripts/doc-commands`, which runs the README's and the book's commands in `scripts/test`,
//! fails when a documented command breaks: a command that exits with an error, a console
//! block whose output is not what the text shows, a link or a path of the checkout that does
//! not exist, a block skipped without a reason. Each is tried on a page of its own, written
//! into a temporary folder, beside a page that passes.

use std::path::Path;
use std::process::{Command, Output};

/// Runs `scripts/doc-commands` on one Markdown page with this build's binary.
fn doc_commands(page: &Path) -> Output {
    let build = Path::new(env!("CARGO_BIN_EXE_subtgraph")).parent().unwrap();
    Command::new("python3")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/doc-commands"))
        .arg(page)
        .env("SUBTGRAPH_BUILD_DIR", build)
        .output()
        .unwrap()
}

fn text(out: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

/// Writes `body` as a page and runs it: (success, everything printed).
fn run(dir: &Path, name: &str, body: &str) -> (bool, String) {
    let page = dir.join(name);
    std::fs::write(&page, body).unwrap();
    let out = doc_commands(&page);
    (out.status.success(), text(&out))
}

#[test]
fn a_page_whose_commands_work_passes() {
    let dir = tempfile::tempdir().unwrap();
    let (ok, said) = run(
        dir.path(),
        "good.md",
        "# Good\n\n```sh\nsubtgraph presets\nsubtgraph validate examples/exact-loops.toml\n```\n\n\
         ```console\n$ printf '[world]\\nlevles = 2\\n' > my.toml\n$ subtgraph validate my.toml\n\
         error: my.toml:2:1: world.levles: unknown field `levles`, expected one of `seed`, `levels`, \
         `min_length`, `rows`, `cols`, `tile_pitch`, `level_height`, `max_width`, `attempts`, \
         `connections`, `ramp_grade`\n```\n\n\
         <!-- not run: a command that would fail, skipped with its reason -->\n```sh\nfalse\n```\n\n\
         ```python\nthis is not run: only sh and console blocks are\n```\n\n\
         [the README](../../README.md) does not exist from a temporary folder, but `examples/cave.toml` does.\n",
    );
    // The relative link is checked from the page's folder: it fails, and is the only problem.
    assert!(!ok && said.contains("README.md"), "{said}");
    let good = said.lines().filter(|l| l.starts_with("ok ")).count();
    assert_eq!(good, 4, "{said}");
    assert!(
        said.contains("doc-commands: 4 passed, 0 failed, 1 skipped"),
        "{said}"
    );
    let (ok, said) = run(
        dir.path(),
        "good.md",
        "# Good\n\n```sh\nsubtgraph presets\n```\n\nSee [Good](#good) and `examples/cave.toml`.\n",
    );
    assert!(ok, "{said}");
}

#[test]
fn a_broken_command_fails_naming_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let (ok, said) = run(
        dir.path(),
        "broken.md",
        "# Broken\n\n```sh\nsubtgraph presets\nsubtgraph generate --preset no-such-preset --out w\n```\n",
    );
    assert!(!ok, "{said}");
    assert!(
        said.contains(
            "broken.md:5: `subtgraph generate --preset no-such-preset --out w`: exit status 1"
        ),
        "{said}"
    );
    assert!(said.contains("1 passed, 1 failed"), "{said}");
}

#[test]
fn console_output_other_than_the_text_shows_fails() {
    let dir = tempfile::tempdir().unwrap();
    let (ok, said) = run(
        dir.path(),
        "stale.md",
        "# Stale\n\n```console\n$ printf '[world]\\nlevles = 2\\n' > my.toml\n$ subtgraph validate my.toml\n\
         error: my.toml:3:1: world.levles: unknown field `levles`\n```\n",
    );
    assert!(!ok, "{said}");
    assert!(
        said.contains("printed other than the text shows")
            && said.contains("  - error: my.toml:3:1")
            && said.contains("  + error: my.toml:2:1"),
        "{said}"
    );
}

#[test]
fn missing_links_paths_and_reasons_fail() {
    let dir = tempfile::tempdir().unwrap();
    for (body, says) in [
        (
            "[a chapter](no-such-chapter.md)\n",
            "no-such-chapter.md, which does not exist",
        ),
        (
            "# Here\n\n[there](#there)\n",
            "no heading of here.md has that anchor",
        ),
        (
            "See `tilesets/src/no_such_file.rs`.\n",
            "names tilesets/src/no_such_file.rs, which does not exist",
        ),
        ("<!-- not run: -->\n```sh\nfalse\n```\n", "needs a reason"),
        ("```sh\nsubtgraph presets\n", "the block never closes"),
    ] {
        let (ok, said) = run(dir.path(), "here.md", body);
        assert!(!ok && said.contains(says), "{body:?}: {said}");
    }
}
