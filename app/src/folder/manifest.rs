//! `.subtgraph-files`: what subtgraph wrote in a folder, and the proof that it did.
//!
//! Every world folder ends with this file, written last, listing each file the tool wrote with
//! its size in bytes. It serves three purposes:
//! - **ownership**: `--force` and dataset resume delete only the files listed here, so a file a
//!   user put into a world folder (notes, a rosbag, results) is never touched;
//! - **completeness**: a world whose listed files are all present with their sizes is complete
//!   (a truncated OBJ or a missing `topology.json` is seen at once, without parsing them);
//! - **liveness** while the folder is still being written: the hidden temporary folder starts
//!   with a `partial` manifest naming the host, process and its start time, so a later run can
//!   tell a dead run's leftovers (removed) from a live run's work (left alone).
//!
//! - **ownership by command**: its `complete` line names what the folder is (`complete world`,
//!   `complete stats`, `complete score`, `complete sense`, `complete report`), so each command's `--force`
//!   replaces only a folder that command wrote: `stats` never replaces a world, `score` never
//!   replaces a world or a stats report, `generate` never replaces a report or a sensor
//!   sequence, `sense` never replaces a world.
//!
//! The file is plain text, one entry per line, in path order, so it is byte-identical between
//! runs like every other file of the world.

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

/// The manifest's file name inside a folder the tool writes.
pub const FILE: &str = ".subtgraph-files";

/// What a folder the tool writes is, and so which command's `--force` may replace it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A world folder (`generate`, a `dataset`'s worlds, Python's `World.export`).
    World,
    /// A `stats` report.
    Stats,
    /// A `score` report.
    Score,
    /// A `sense` sensor sequence.
    Sense,
    /// A `report` over many score folders.
    Report,
    /// An `explore` run folder.
    Explore,
}

impl Kind {
    /// Every kind.
    pub const ALL: [Kind; 6] = [
        Kind::World,
        Kind::Stats,
        Kind::Score,
        Kind::Sense,
        Kind::Report,
        Kind::Explore,
    ];

    /// Its word on the manifest's `complete` line.
    pub fn token(self) -> &'static str {
        match self {
            Kind::World => "world",
            Kind::Stats => "stats",
            Kind::Score => "score",
            Kind::Sense => "sense",
            Kind::Report => "report",
            Kind::Explore => "explore",
        }
    }

    /// What it is, in messages.
    pub fn what(self) -> &'static str {
        match self {
            Kind::World => "world folder",
            Kind::Stats => "stats report",
            Kind::Score => "score report",
            Kind::Sense => "sensor sequence",
            Kind::Report => "dataset report",
            Kind::Explore => "exploration run",
        }
    }

    /// The command that writes it, in messages.
    pub fn command(self) -> &'static str {
        match self {
            Kind::World => "subtgraph generate",
            Kind::Stats => "subtgraph stats",
            Kind::Score => "subtgraph score",
            Kind::Sense => "subtgraph sense",
            Kind::Report => "subtgraph report",
            Kind::Explore => "subtgraph explore",
        }
    }

    /// The kind of a folder whose manifest predates kinds: told by the file each command
    /// always writes.
    fn of_listed(files: &[(String, u64)]) -> Option<Kind> {
        let has = |f: &str| files.iter().any(|(p, _)| p == f);
        [
            (Kind::World, "world.toml"),
            (Kind::Stats, "stats.json"),
            (Kind::Score, "score.json"),
            (Kind::Sense, "sequence.json"),
            (Kind::Report, "report.json"),
            (Kind::Explore, "run.json"),
        ]
        .into_iter()
        .find(|(_, f)| has(f))
        .map(|(k, _)| k)
    }
}

/// A folder's manifest, as read back.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Manifest {
    /// A finished folder: what it is (told by its files for a manifest written before kinds;
    /// `None` when they do not tell) and every file the tool wrote, with its size, in path
    /// order.
    Complete(Option<Kind>, Vec<(String, u64)>),
    /// A folder being written by a process.
    Partial(Owner),
}

/// The process writing a partial folder.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Owner {
    /// Host name (a shared folder may be written from several machines).
    pub host: String,
    /// Process id on that host.
    pub pid: u32,
    /// The process's start time in clock ticks since boot (Linux), 0 where unknown: tells a
    /// reused pid from the original process.
    pub start: u64,
}

impl Owner {
    /// This process.
    pub fn this_process() -> Owner {
        let pid = std::process::id();
        Owner {
            host: host_name(),
            pid,
            start: process_start(pid).unwrap_or(0),
        }
    }

    /// Whether the process that wrote this is certainly gone: it ran on this host and no
    /// process with its id (and start time, where known) exists. A process on another host is
    /// never presumed dead.
    pub fn is_dead(&self) -> bool {
        if self.host != host_name() || self.pid == 0 {
            return false;
        }
        if self.pid == std::process::id() {
            return false;
        }
        match process_start(self.pid) {
            Some(start) => self.start != 0 && start != self.start,
            None => !process_exists(self.pid),
        }
    }
}

/// Text of a partial manifest for `owner`.
pub fn partial_text(owner: &Owner) -> String {
    format!(
        "# subtgraph: a world folder being written; removed by the next run if its process is gone.\n\
         partial host={} pid={} start={}\n",
        owner.host, owner.pid, owner.start
    )
}

/// Text of a complete manifest of a `kind` folder listing `files` (relative paths with `/`
/// separators, sizes).
pub fn complete_text(kind: Kind, files: &[(String, u64)]) -> String {
    let mut text = match kind {
        Kind::World => "# subtgraph world folder: the files subtgraph wrote here (bytes, path).\n\
             # `--force` and dataset resume delete only these; anything else in this folder is yours and\n\
             # is never touched.\n"
            .to_owned(),
        _ => format!(
            "# subtgraph {}: the files subtgraph wrote here (bytes, path).\n\
             # `{} --force` deletes only these; anything else in this folder is yours and\n\
             # is never touched.\n",
            kind.what(),
            kind.command()
        ),
    };
    text.push_str("complete ");
    text.push_str(kind.token());
    text.push('\n');
    for (path, size) in files {
        writeln!(text, "{size} {path}").expect("writing to a String");
    }
    text
}

/// Reads the manifest of `dir`: `None` when it has none or it is not one of ours.
pub fn read(dir: &Path) -> Option<Manifest> {
    let text = fs::read_to_string(dir.join(FILE)).ok()?;
    parse(&text)
}

/// Parses a manifest's text (`None` when it is not one of ours).
pub fn parse(text: &str) -> Option<Manifest> {
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let head = lines.next()?;
    let kind = match head.strip_prefix("complete") {
        Some("") => Some(None),
        Some(token) => Some(Some(
            Kind::ALL
                .into_iter()
                .find(|k| Some(k.token()) == token.strip_prefix(' '))?,
        )),
        None => None,
    };
    if let Some(kind) = kind {
        let mut files = Vec::new();
        for line in lines {
            let (size, path) = line.split_once(' ')?;
            let path_ok = !path.is_empty()
                && Path::new(path)
                    .components()
                    .all(|c| matches!(c, std::path::Component::Normal(_)));
            if !path_ok {
                return None;
            }
            files.push((path.to_owned(), size.parse().ok()?));
        }
        let kind = kind.or_else(|| Kind::of_listed(&files));
        return Some(Manifest::Complete(kind, files));
    }
    let rest = head.strip_prefix("partial ")?;
    let mut owner = Owner {
        host: String::new(),
        pid: 0,
        start: 0,
    };
    for field in rest.split(' ') {
        match field.split_once('=')? {
            ("host", v) => owner.host = v.to_owned(),
            ("pid", v) => owner.pid = v.parse().ok()?,
            ("start", v) => owner.start = v.parse().ok()?,
            _ => return None,
        }
    }
    Some(Manifest::Partial(owner))
}

/// Every file under `root` (relative, `/`-separated, sorted) with its size; the manifest itself
/// left out.
pub fn list_files(root: &Path) -> std::io::Result<Vec<(String, u64)>> {
    let mut out = Vec::new();
    let mut stack = vec![PathBuf::new()];
    while let Some(rel) = stack.pop() {
        for entry in fs::read_dir(root.join(&rel))? {
            let entry = entry?;
            let name = rel.join(entry.file_name());
            let kind = entry.file_type()?;
            if kind.is_dir() {
                stack.push(name);
            } else if name != Path::new(FILE) {
                let size = entry.metadata()?.len();
                out.push((slash_path(&name), size));
            }
        }
    }
    out.sort();
    Ok(out)
}

/// Every entry under `root` (files, links and folders, relative and `/`-separated) that is
/// not a listed file, not the manifest, and not a folder on the way to a listed file: what the
/// tool did not write.
pub fn foreign_entries(root: &Path, listed: &[(String, u64)]) -> std::io::Result<Vec<String>> {
    let files: std::collections::HashSet<&str> = listed.iter().map(|(p, _)| p.as_str()).collect();
    let dirs: std::collections::HashSet<String> = listed
        .iter()
        .flat_map(|(p, _)| {
            Path::new(p)
                .ancestors()
                .skip(1)
                .filter(|a| !a.as_os_str().is_empty())
                .map(slash_path)
                .collect::<Vec<_>>()
        })
        .collect();
    let mut foreign = Vec::new();
    let mut stack = vec![PathBuf::new()];
    while let Some(rel) = stack.pop() {
        for entry in fs::read_dir(root.join(&rel))? {
            let entry = entry?;
            let name = rel.join(entry.file_name());
            let text = slash_path(&name);
            let kind = entry.file_type()?;
            if kind.is_dir() && dirs.contains(&text) {
                stack.push(name);
            } else if !(kind.is_file() && (files.contains(text.as_str()) || text == FILE)) {
                foreign.push(text);
            }
        }
    }
    foreign.sort();
    Ok(foreign)
}

/// What is wrong with a complete folder: listed files missing or of another size.
pub fn damage(root: &Path, listed: &[(String, u64)]) -> Vec<String> {
    listed
        .iter()
        .filter_map(|(path, size)| match fs::metadata(root.join(path)) {
            Ok(m) if m.is_file() && m.len() == *size => None,
            Ok(m) if m.is_file() => Some(format!("{path} has {} bytes, not {size}", m.len())),
            _ => Some(format!("{path} is missing")),
        })
        .collect()
}

fn slash_path(p: &Path) -> String {
    p.components()
        .map(|c| c.as_os_str().to_string_lossy())
        .collect::<Vec<_>>()
        .join("/")
}

fn host_name() -> String {
    #[cfg(unix)]
    {
        let name = rustix::system::uname();
        let name = name.nodename().to_string_lossy();
        let clean: String = name
            .chars()
            .filter(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '.' | '_'))
            .collect();
        if !clean.is_empty() {
            return clean;
        }
    }
    "localhost".into()
}

/// The start time of process `pid` in clock ticks since boot, from `/proc` (Linux only).
fn process_start(pid: u32) -> Option<u64> {
    let stat = fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The command name (field 2) is in parentheses and may hold spaces: count from its end.
    let after = &stat[stat.rfind(')')? + 1..];
    after.split_whitespace().nth(19)?.parse().ok()
}

fn process_exists(pid: u32) -> bool {
    #[cfg(unix)]
    {
        let Ok(pid) = i32::try_from(pid) else {
            return false;
        };
        let Some(pid) = rustix::process::Pid::from_raw(pid) else {
            return false;
        };
        match rustix::process::test_kill_process(pid) {
            Ok(()) => true,
            Err(e) => e != rustix::io::Errno::SRCH,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = pid;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn manifests_read_back() {
        let files = vec![
            ("maps/level-0.png".to_owned(), 12),
            ("world.toml".into(), 3),
        ];
        for kind in Kind::ALL {
            assert_eq!(
                parse(&complete_text(kind, &files)),
                Some(Manifest::Complete(Some(kind), files.clone()))
            );
        }
        // Written before kinds: told by the files.
        let legacy = "# old\ncomplete\n3 world.toml\n";
        assert_eq!(
            parse(legacy),
            Some(Manifest::Complete(
                Some(Kind::World),
                vec![("world.toml".into(), 3)]
            ))
        );
        assert_eq!(
            parse("complete\n3 notes\n").map(|m| matches!(m, Manifest::Complete(None, _))),
            Some(true)
        );
        let me = Owner::this_process();
        assert_eq!(
            parse(&partial_text(&me)),
            Some(Manifest::Partial(me.clone()))
        );
        assert!(!me.is_dead(), "this process is alive");
        for bad in [
            "",
            "complete planets\n",
            "complete\nx y\n",
            "complete\n3 ../escape\n",
            "partial pid=x\n",
        ] {
            assert_eq!(parse(bad), None, "{bad:?}");
        }
    }

    #[test]
    fn a_dead_process_is_recognised_and_a_foreign_host_never_is() {
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let pid = child.id();
        child.wait().unwrap();
        let gone = Owner {
            host: host_name(),
            pid,
            start: 1,
        };
        assert!(
            gone.is_dead() || process_exists(pid),
            "pid {pid} was reused at once"
        );
        let elsewhere = Owner {
            host: "another-machine".into(),
            ..gone
        };
        assert!(!elsewhere.is_dead());
    }

    #[test]
    fn foreign_entries_are_what_the_list_does_not_hold() {
        let dir = tempfile::tempdir().unwrap();
        fs::create_dir_all(dir.path().join("maps/extra")).unwrap();
        fs::write(dir.path().join("maps/level-0.png"), b"png").unwrap();
        fs::write(dir.path().join("world.toml"), b"x").unwrap();
        fs::write(dir.path().join("data.bin"), b"mine").unwrap();
        fs::write(dir.path().join(FILE), b"").unwrap();
        let listed = vec![("maps/level-0.png".to_owned(), 3), ("world.toml".into(), 1)];
        assert_eq!(
            foreign_entries(dir.path(), &listed).unwrap(),
            ["data.bin", "maps/extra"]
        );
        assert_eq!(list_files(dir.path()).unwrap().len(), 3);
        assert!(damage(dir.path(), &listed).is_empty());
        fs::write(dir.path().join("world.toml"), b"xy").unwrap();
        assert_eq!(
            damage(dir.path(), &listed),
            ["world.toml has 2 bytes, not 1"]
        );
    }
}
