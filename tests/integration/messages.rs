//! Every flag a message or a help text tells the user to pass exists on the command that
//! shows it. The flags of each command are read from its real `--help`; the messages are the
//! string literals of the sources (errors, notes, `#[error]` texts), each checked against the
//! commands that can show it: a message in `src/dataset/` only ever reaches `dataset`, one in
//! `main.rs` the command whose arm it is in, one in `make.rs` both `generate` and `dataset`.
//! A flag written after a command's name (`subtgraph generate --out DIR`, or `cargo build
//! --release`) is checked against that command instead (or not at all, for `cargo`).

use crate::common;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const COMMANDS: [&str; 9] = [
    "generate",
    "dataset",
    "stats",
    "score",
    "validate",
    "preview",
    "presets",
    "plugins list",
    "sense",
];

/// Flags named in a text: `--name` with a lower-case letter after the dashes.
fn mentioned(text: &str) -> Vec<(usize, String)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i + 2 < b.len() {
        let starts = b[i] == b'-'
            && b[i + 1] == b'-'
            && b[i + 2].is_ascii_lowercase()
            && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'-'));
        if starts {
            let end = (i + 2..b.len())
                .find(|&j| !(b[j].is_ascii_lowercase() || b[j].is_ascii_digit() || b[j] == b'-'))
                .unwrap_or(b.len());
            out.push((i, text[i..end].trim_end_matches('-').to_owned()));
            i = end;
        } else {
            i += 1;
        }
    }
    out
}

/// The command a flag at `pos` is written after, in the same clause (`generate --out DIR`),
/// if any: `Some("cargo")` for cargo's own flags.
fn named_command(text: &str, pos: usize) -> Option<String> {
    let clause_start = text[..pos]
        .rfind(['.', ';', ':', ',', '(', ')', '`', '"'])
        .map_or(0, |i| i + 1);
    let words: Vec<&str> = text[clause_start..pos].split_whitespace().collect();
    words.iter().enumerate().rev().find_map(|(k, w)| match *w {
        "cargo" => Some("cargo".to_owned()),
        "plugins" if words.get(k + 1) == Some(&"list") => Some("plugins list".to_owned()),
        w if COMMANDS.contains(&w) => Some(w.to_owned()),
        _ => None,
    })
}

/// Each command's flags, from its `--help`, and the help text itself.
fn commands() -> BTreeMap<&'static str, (BTreeSet<String>, String)> {
    COMMANDS
        .iter()
        .map(|cmd| {
            let mut args: Vec<&str> = cmd.split(' ').collect();
            args.push("--help");
            let help = common::ok(&args);
            let flags = help
                .lines()
                .map(str::trim_start)
                .filter(|l| l.starts_with('-'))
                .filter_map(|l| mentioned(l).into_iter().next().map(|(_, f)| f))
                .collect();
            (*cmd, (flags, help))
        })
        .collect()
}

/// The string literals of Rust source (normal and raw strings), with their byte offsets;
/// comments, char literals and lifetimes are skipped. A `#[cfg(test)]` module ends the scan.
fn literals(src: &str) -> Vec<(usize, String)> {
    let src = src.split("#[cfg(test)]").next().unwrap_or(src);
    let b = src.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'/' if b.get(i + 1) == Some(&b'/') => {
                i = src[i..].find('\n').map_or(b.len(), |n| i + n);
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                i = src[i + 2..].find("*/").map_or(b.len(), |n| i + n + 4);
            }
            b'\'' => {
                // A char literal ('x', '\n', '\'', '\u{..}') or a lifetime ('a).
                if b.get(i + 1) == Some(&b'\\') {
                    i = src[i + 2..].find('\'').map_or(b.len(), |n| i + n + 3);
                } else if b.get(i + 2) == Some(&b'\'') {
                    i += 3;
                } else {
                    let c = src[i + 1..].chars().next().map_or(1, char::len_utf8);
                    if src[i + 1 + c..].starts_with('\'') {
                        i += 2 + c;
                    } else {
                        i += 1;
                    }
                }
            }
            b'r' if (b.get(i + 1) == Some(&b'"') || b.get(i + 1) == Some(&b'#'))
                && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_')) =>
            {
                let hashes = b[i + 1..].iter().take_while(|&&c| c == b'#').count();
                if b.get(i + 1 + hashes) != Some(&b'"') {
                    i += 1;
                    continue;
                }
                let start = i + 2 + hashes;
                let close = format!("\"{}", "#".repeat(hashes));
                let end = src[start..].find(&close).map_or(b.len(), |n| start + n);
                out.push((start, src[start..end].to_owned()));
                i = end + close.len();
            }
            b'"' => {
                let start = i + 1;
                let mut j = start;
                while j < b.len() && b[j] != b'"' {
                    j += if b[j] == b'\\' { 2 } else { 1 };
                }
                out.push((start, src[start..j.min(b.len())].to_owned()));
                i = j + 1;
            }
            _ => i += 1,
        }
    }
    out
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The commands that can show a message of `file` (relative to the repository), at `pos`
/// (for `main.rs`: the `Command::...` arm the literal is in).
fn reached_by(file: &str, src: &str, pos: usize) -> Vec<&'static str> {
    match file {
        "src/main.rs" => {
            let run = src.find("\nfn run(").unwrap();
            let after = src[run + 1..]
                .find("\nfn ")
                .map_or(src.len(), |n| run + 1 + n);
            if pos < run || pos > after {
                return COMMANDS.to_vec();
            }
            let arm = src[run..pos]
                .lines()
                .rev()
                .find_map(|l| {
                    let l = l.trim_start();
                    l.strip_prefix("Command::")
                        .or_else(|| l.strip_prefix("command: PluginsCommand::"))
                })
                .map(|l| l.split(|c: char| !c.is_alphanumeric()).next().unwrap());
            match arm {
                Some("List") => vec!["plugins list"],
                Some(v) => vec![
                    COMMANDS
                        .iter()
                        .find(|c| c.eq_ignore_ascii_case(v))
                        .unwrap_or_else(|| panic!("main.rs arm {v} is not a known command")),
                ],
                None => COMMANDS.to_vec(),
            }
        }
        f if f.starts_with("src/dataset/") => vec!["dataset"],
        f if f.starts_with("src/stats/") => vec!["stats"],
        f if f.starts_with("src/score/") => vec!["score"],
        "src/preview.rs" => vec!["preview"],
        // dataset writes world folders without --force and words its own message when one
        // is in the way (src/dataset/mod.rs, tested in tests/integration/dataset.rs), so the folder
        // writer's messages about --force only reach generate.
        f if f.starts_with("src/folder") => vec!["generate"],
        // A dataset's per-world share of the memory budget: only `dataset` has --jobs.
        "src/memory.rs"
            if src.find("\npub fn per_world(").is_some_and(|start| {
                let end = src[start + 1..]
                    .find("\n}")
                    .map_or(src.len(), |n| start + 1 + n);
                (start..end).contains(&pos)
            }) =>
        {
            vec!["dataset"]
        }
        // Sensor sequences: only `sense` shows the sensors crate's messages and its own.
        f if f.starts_with("sensors/") || f == "src/commands/sense.rs" => vec!["sense"],
        f if f.starts_with("src/") => vec!["generate", "dataset"],
        // Meshing happens only in generate and dataset (validate makes no mesh), and so does
        // writing files (the exporters' and the core's export errors).
        f if f.starts_with("exporters/")
            || f.starts_with("tilesets/")
            || f == "core/src/export.rs"
            || f == "core/src/assembly.rs" =>
        {
            vec!["generate", "dataset"]
        }
        _ => vec!["generate", "dataset", "validate"],
    }
}

#[test]
fn every_flag_a_message_names_exists_on_the_command_that_shows_it() {
    let commands = commands();
    let flags_of = |cmd: &str| &commands[cmd].0;
    assert!(flags_of("dataset").contains("--shard") && !flags_of("dataset").contains("--force"));
    assert!(flags_of("generate").contains("--force"));
    let mut wrong = Vec::new();
    let mut checked = 0;

    // Help texts (the doc comments of main.rs): flags of the command itself.
    for (cmd, (flags, help)) in &commands {
        for line in help.lines().filter(|l| !l.trim_start().starts_with('-')) {
            for (pos, flag) in mentioned(line) {
                let on = named_command(line, pos).unwrap_or_else(|| (*cmd).to_owned());
                checked += 1;
                let known = match on.as_str() {
                    "cargo" => true,
                    other if other == *cmd => flags.contains(&flag),
                    other => flags_of(other).contains(&flag),
                };
                if !known {
                    wrong.push(format!(
                        "`{cmd} --help` names {flag} ({on} has no such flag): {line}"
                    ));
                }
            }
        }
    }

    // Messages in the sources.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in [
        "src",
        "core/src",
        "exporters/src",
        "tilesets/src",
        "descriptors/src",
        "plugins/src",
        "sensors/src",
    ] {
        rust_files(&root.join(dir), &mut files);
    }
    files.sort();
    for path in &files {
        let file = path
            .strip_prefix(root)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        let src = std::fs::read_to_string(path).unwrap();
        for (at, text) in literals(&src) {
            for (pos, flag) in mentioned(&text) {
                checked += 1;
                let on: Vec<String> = match named_command(&text, pos) {
                    Some(c) if c == "cargo" => continue,
                    Some(c) => vec![c],
                    None => reached_by(&file, &src, at)
                        .iter()
                        .map(|c| (*c).to_owned())
                        .collect(),
                };
                let missing: Vec<&String> =
                    on.iter().filter(|c| !flags_of(c).contains(&flag)).collect();
                if !missing.is_empty() {
                    let line = src[..at].lines().count();
                    wrong.push(format!(
                        "{file}:{line}: names {flag}, which {missing:?} do(es) not have: \"{text}\""
                    ));
                }
            }
        }
    }
    assert!(checked > 30, "the scan found the messages ({checked})");
    assert!(
        wrong.is_empty(),
        "messages naming flags that do not exist:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn the_scanner_reads_literals_and_clauses_as_meant() {
    let src = "let c = '\"'; let l: &'a str = \"pass --force\"; // \"--gone\"\n let r = r#\"x \"--raw\" y\"#;";
    let found: Vec<String> = literals(src).into_iter().map(|(_, t)| t).collect();
    assert_eq!(found, ["pass --force", "x \"--raw\" y"]);
    let text = "run `subtgraph generate --preset NAME --out DIR`, or --jobs";
    let at = |f: &str| text.find(f).unwrap();
    assert_eq!(
        named_command(text, at("--out")).as_deref(),
        Some("generate")
    );
    assert_eq!(named_command(text, at("--jobs")), None);
    let cargo = "build it (cargo build --release)";
    assert_eq!(
        named_command(cargo, cargo.find("--release").unwrap()).as_deref(),
        Some("cargo")
    );
}
