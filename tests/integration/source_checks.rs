//! The source checkers `scripts/test` runs on the workspace, `scripts/module-cycles` and
//! `scripts/long-functions`, each shown to find what it looks for: negative controls, crates
//! written into a temporary folder with a known cycle or a known long function, beside ones
//! without. A checker that cannot fail (as module-cycles could not while a string over two
//! lines hid the code after it) fails here.

use std::path::Path;
use std::process::Command;

/// Writes the files `(path, text)` under `dir`.
fn write(dir: &Path, files: &[(&str, &str)]) {
    for (path, text) in files {
        let path = dir.join(path);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }
}

/// Runs `scripts/NAME` on the crate folder `dir`: (success, everything printed).
fn check(name: &str, dir: &Path, extra: &[&str]) -> (bool, String) {
    let out = Command::new("python3")
        .arg(
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("scripts")
                .join(name),
        )
        .args(extra)
        .arg(dir)
        .output()
        .unwrap();
    let said = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.success(), said)
}

#[test]
fn module_cycles_finds_a_cycle_between_top_level_modules() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        &[
            ("src/lib.rs", "mod a;\nmod b;\nmod c;\n"),
            ("src/a.rs", "use crate::b::B;\npub struct A;\n"),
            ("src/b.rs", "pub struct B(crate::c::C);\n"),
            (
                "src/c.rs",
                "pub struct C;\nfn f() -> crate::a::A { crate::a::A }\n",
            ),
        ],
    );
    let (ok, said) = check("module-cycles", dir.path(), &[]);
    assert!(!ok, "{said}");
    assert!(
        said.contains("module cycle among a, b, c: a -> b -> c -> a"),
        "{said}"
    );
}

#[test]
fn module_cycles_reads_past_strings_over_several_lines_and_other_literals() {
    // The cycle's second edge comes after a string continued over a line, which hid the code
    // after it from the checker's regular expression (issue 40); then after a raw string
    // holding a quote and `//`, a character literal of a quote and lifetimes.
    for b in [
        "pub fn g() {}\nconst S: &str = \"one \\\n two\";\npub fn k() { crate::a::f() }\n\
         const T: &str = \"x\";\n",
        "pub fn g() {}\nconst R: &str = r#\"say \"hi\" // not a comment\"#;\n\
         const Q: char = '\"';\nfn h<'a>(x: &'a str) -> &'a str { x }\n\
         pub fn k() { crate::a::f() }\n",
    ] {
        let dir = tempfile::tempdir().unwrap();
        write(
            dir.path(),
            &[
                ("src/lib.rs", "mod a;\nmod b;\n"),
                ("src/a.rs", "pub fn f() { crate::b::g() }\n"),
                ("src/b.rs", b),
            ],
        );
        let (ok, said) = check("module-cycles", dir.path(), &[]);
        assert!(!ok, "{b}\n{said}");
        assert!(said.contains("module cycle among a, b"), "{said}");
    }
}

#[test]
fn module_cycles_finds_a_cycle_inside_a_folder_module() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        &[
            ("src/lib.rs", "mod score;\n"),
            ("src/score/mod.rs", "mod coverage;\nmod world;\n"),
            (
                "src/score/coverage.rs",
                "use super::world::Cells;\npub struct Bits;\n",
            ),
            (
                "src/score/world.rs",
                "use crate::score::{coverage::Bits};\npub struct Cells;\n",
            ),
        ],
    );
    let (ok, said) = check("module-cycles", dir.path(), &[]);
    assert!(!ok, "{said}");
    assert!(
        said.contains("module cycle in score among coverage, world"),
        "{said}"
    );
}

#[test]
fn module_cycles_passes_a_layered_crate_and_ignores_comments_strings_and_tests() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        &[
            ("src/lib.rs", "mod a;\nmod b;\n"),
            ("src/a.rs", "use crate::b::B;\npub struct A(B);\n"),
            (
                "src/b.rs",
                "/// See [`crate::a::A`].\npub struct B;\n// crate::a::A\n\
                 const S: &str = \"crate::a::A\";\n/* crate::a::A /* nested */ crate::a::A */\n\
                 #[cfg(test)]\nmod tests {\n    use crate::a::A;\n}\n",
            ),
        ],
    );
    let (ok, said) = check("module-cycles", dir.path(), &[]);
    assert!(ok, "{said}");
    assert!(said.contains("no module cycles"), "{said}");
}

/// A function of `lines` lines in all, from its `fn` line to its closing brace.
fn function(name: &str, lines: usize) -> String {
    let mut text = format!("pub fn {name}() -> u32 {{\n    let mut n = 0;\n");
    for _ in 0..lines - 4 {
        text.push_str("    n += 1;\n");
    }
    text.push_str("    n\n}\n");
    text
}

#[test]
fn long_functions_finds_a_function_over_the_limit_and_only_that_one() {
    let dir = tempfile::tempdir().unwrap();
    let long = function("long", 101);
    let fits = function("fits", 100);
    let tested = format!(
        "#[cfg(test)]\nmod tests {{\n{}}}\n",
        function("in_a_test", 150)
    );
    // A string with braces and a `fn` in it changes nothing.
    let lib = format!(
        "#[cfg(test)]\nmod tests;\nconst S: &str = \"fn x() {{ {{\";\n{fits}{long}{tested}"
    );
    write(
        dir.path(),
        &[
            ("src/lib.rs", lib.as_str()),
            ("src/tests.rs", function("a_test_file", 120).as_str()),
        ],
    );
    let (ok, said) = check("long-functions", dir.path(), &[]);
    assert!(!ok, "{said}");
    let flagged: Vec<&str> = said
        .lines()
        .filter(|l| l.contains(" lines (at most"))
        .collect();
    assert_eq!(flagged.len(), 1, "{said}");
    assert!(flagged[0].contains("long is 101 lines"), "{said}");
    let (ok, said) = check("long-functions", dir.path(), &["--max", "101"]);
    assert!(ok, "{said}");
}

/// `scripts/cluster-check` runs the book's cluster examples; it is not in the suite (it installs
/// Slurm and takes minutes), so the suite checks that it still finds them: it once read them
/// from the README, which lost them, and exited 1 without a word.
#[test]
fn cluster_check_finds_the_examples_the_book_gives_and_says_when_it_cannot() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let found = Command::new("bash")
        .arg(root.join("scripts/cluster-check"))
        .arg("--find-only")
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&found.stdout);
    assert!(
        found.status.success(),
        "{out}{}",
        String::from_utf8_lossy(&found.stderr)
    );
    assert!(
        out.contains("#SBATCH --array") && out.contains("subtgraph dataset"),
        "{out}"
    );
    assert!(out.contains("\nparallel "), "{out}");
    // A page without them: refused, saying what is missing and what to do.
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("page.md");
    std::fs::write(&page, "# Datasets\n\nNo cluster here.\n").unwrap();
    let missing = Command::new("bash")
        .arg(root.join("scripts/cluster-check"))
        .arg("--find-only")
        .env("CLUSTER_DOC", &page)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&missing.stderr);
    assert!(!missing.status.success());
    assert!(
        err.contains("no Slurm block") && err.contains("CLUSTER_DOC"),
        "{err}"
    );
}
