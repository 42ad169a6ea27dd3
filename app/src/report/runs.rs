//! The runs a report is made of: which score folders, of which method, on which world; and
//! each folder's numbers, read generically so that a new kind of score needs no code here.
//!
//! Runs are named in either of two ways (both may be mixed):
//! - `METHOD=FOLDER`: `FOLDER` is a score folder, or a folder whose subfolders are all score
//!   folders (hidden ones skipped), each one run of `METHOD`;
//! - `--runs runs.csv` with the header `world,method,score_folder` (comma-separated, a field
//!   with a comma or a quote between double quotes as RFC 4180 has it, a byte-order mark
//!   allowed; paths relative to the CSV's folder; `world` may be empty, then the score
//!   folder's own record is used; a world given here wins over the record, so a trajectory
//!   scored against a bare reference file can still be placed in its world).
//!
//! Each score folder records the world it graded (`world` in `score.json`,
//! `world_or_sequence` in `trajectory.json`, a sensor sequence's `world` in its
//! `sequence.json`): a relative path is looked for from the current folder, then from the
//! score folder's parent.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::Error;
use crate::folder::{Kind, manifest};

/// Keys whose subtrees are a score's inputs and settings, not its results.
pub const NOT_METRICS: [&str; 3] = ["options", "reference", "estimate"];

/// One score folder of one method on one world.
#[derive(Clone, Debug)]
pub struct Run {
    /// The method's name.
    pub method: String,
    /// The score folders (several when they are of different kinds: a trajectory score and
    /// an artifact score of the same run).
    pub folders: Vec<PathBuf>,
    /// The world folder graded.
    pub world: PathBuf,
    /// The world folder, canonical: the key runs are paired on.
    pub key: PathBuf,
    /// Every number of the folders' summary files, `file-stem.path.to.field`.
    pub metrics: BTreeMap<String, f64>,
    /// `true` when a summary says `"failed": true`; `None` when none has the flag.
    pub failed: Option<bool>,
    /// Where it was named: `argument 2`, `runs.csv row 5`.
    pub source: String,
}

fn input(msg: String) -> Error {
    Error::Input(msg)
}

/// Whether `dir` is a folder `subtgraph score` wrote.
fn is_score(dir: &Path) -> bool {
    matches!(
        manifest::read(dir),
        Some(manifest::Manifest::Complete(Some(Kind::Score), _))
    )
}

/// The top-level JSON files a score folder's manifest lists: its summaries.
fn summaries(dir: &Path) -> Vec<String> {
    match manifest::read(dir) {
        Some(manifest::Manifest::Complete(_, files)) => files
            .into_iter()
            .map(|(p, _)| p)
            .filter(|p| !p.contains('/') && p.ends_with(".json"))
            .collect(),
        _ => Vec::new(),
    }
}

/// Adds every number under `v` to `out` as `prefix.key.key`; arrays (per-item tables, which
/// the score's CSV files hold) and [`NOT_METRICS`] are left out.
fn flatten(prefix: &str, v: &Value, top: bool, out: &mut BTreeMap<String, f64>) {
    match v {
        Value::Number(n) => {
            if let Some(x) = n.as_f64() {
                out.insert(prefix.to_owned(), x);
            }
        }
        Value::Object(map) => {
            for (k, x) in map {
                if top && NOT_METRICS.contains(&k.as_str()) {
                    continue;
                }
                flatten(&format!("{prefix}.{k}"), x, false, out);
            }
        }
        _ => {}
    }
}

/// Looks for a recorded path from the current folder, then from the score folder's parent.
fn locate(recorded: &str, score: &Path) -> Option<PathBuf> {
    let p = PathBuf::from(recorded);
    if p.exists() {
        return Some(p);
    }
    let beside = score.parent()?.join(&p);
    beside.exists().then_some(beside)
}

/// The world a summary records; a sensor sequence is followed to its world.
fn recorded_world(doc: &Value, score: &Path, file: &str) -> Result<Option<PathBuf>, Error> {
    let Some(rec) = ["world", "world_or_sequence"]
        .iter()
        .find_map(|k| doc.get(*k).and_then(Value::as_str))
    else {
        return Ok(None);
    };
    let Some(found) = locate(rec, score) else {
        return Err(input(format!(
            "{}: {file} records the world {rec}, which is not found from here nor beside the score folder; give the world in a --runs CSV (world,method,score_folder)",
            score.display()
        )));
    };
    if found.join("world.toml").is_file() {
        return Ok(Some(found));
    }
    let seq = found.join("sequence.json");
    if let Ok(bytes) = std::fs::read(&seq) {
        let v: Value =
            serde_json::from_slice(&bytes).map_err(|e| input(format!("{}: {e}", seq.display())))?;
        // `sense` records its world as `{"folder": ..., "seed": ...}`.
        let world = v.get("world").and_then(|w| {
            w.as_str()
                .or_else(|| w.get("folder").and_then(Value::as_str))
        });
        if let Some(w) = world.and_then(|w| locate(w, &found)) {
            if w.join("world.toml").is_file() {
                return Ok(Some(w));
            }
        }
    }
    Err(input(format!(
        "{}: {file} records {rec}, which is not a world folder (no world.toml) nor a sensor sequence of one; give the world in a --runs CSV (world,method,score_folder)",
        score.display()
    )))
}

/// Reads one score folder as a run of `method` (`world` given by a CSV, else recorded).
pub fn read(
    method: &str,
    folder: &Path,
    world: Option<PathBuf>,
    source: String,
) -> Result<Run, Error> {
    if !is_score(folder) {
        return Err(input(format!(
            "{source}: {} is not a score folder (its .subtgraph-files does not say `complete score`); name folders written by `subtgraph score`",
            folder.display()
        )));
    }
    let mut metrics = BTreeMap::new();
    let mut failed = None;
    let mut recorded = None;
    for file in summaries(folder) {
        let path = folder.join(&file);
        let bytes =
            std::fs::read(&path).map_err(Error::io(format!("reading {}", path.display())))?;
        let doc: Value = serde_json::from_slice(&bytes)
            .map_err(|e| input(format!("{}: {e}", path.display())))?;
        let stem = file.trim_end_matches(".json");
        flatten(stem, &doc, true, &mut metrics);
        if let Some(f) = doc.get("failed").and_then(Value::as_bool) {
            failed = Some(failed.unwrap_or(false) || f);
        }
        if world.is_none() && recorded.is_none() {
            recorded = recorded_world(&doc, folder, &file)?;
        }
    }
    let world = match (world, recorded) {
        (Some(w), _) | (None, Some(w)) => w,
        (None, None) => {
            return Err(input(format!(
                "{source}: {} records no world; give it in a --runs CSV (world,method,score_folder)",
                folder.display()
            )));
        }
    };
    if !world.join("world.toml").is_file() {
        return Err(input(format!(
            "{source}: {} is not a world folder (no world.toml)",
            world.display()
        )));
    }
    let key = world
        .canonicalize()
        .map_err(Error::io(format!("reading {}", world.display())))?;
    Ok(Run {
        method: method.to_owned(),
        folders: vec![folder.to_owned()],
        world,
        key,
        metrics,
        failed,
        source,
    })
}

/// The runs of `METHOD=FOLDER` arguments.
pub fn from_argument(k: usize, arg: &str) -> Result<Vec<Run>, Error> {
    let Some((method, folder)) = arg
        .split_once('=')
        .filter(|(m, f)| !m.is_empty() && !f.is_empty())
    else {
        return Err(Error::Usage(format!(
            "argument {k} `{arg}` is not METHOD=FOLDER (a method's name, `=`, a score folder or a folder of them)"
        )));
    };
    let source = format!("argument {k} ({method})");
    let folder = Path::new(folder);
    if is_score(folder) {
        return Ok(vec![read(method, folder, None, source)?]);
    }
    let entries = std::fs::read_dir(folder)
        .map_err(Error::io(format!("{source}: reading {}", folder.display())))?;
    let mut dirs: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.is_dir())
        .filter(|p| {
            !p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with('.'))
        })
        .collect();
    dirs.sort();
    if dirs.is_empty() {
        return Err(input(format!(
            "{source}: {} is neither a score folder nor a folder of score folders",
            folder.display()
        )));
    }
    dirs.iter()
        .map(|d| read(method, d, None, source.clone()))
        .collect()
}

/// The runs of a `world,method,score_folder` CSV.
pub fn from_csv(csv: &Path) -> Result<Vec<Run>, Error> {
    let text = crate::input::read_text(csv)?;
    // A spreadsheet saves a byte-order mark first.
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    let base = csv.parent().unwrap_or(Path::new(""));
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let header = lines.next().map(|(_, l)| l.trim());
    if header != Some("world,method,score_folder") {
        return Err(input(format!(
            "{}: line 1 must be the header `world,method,score_folder`",
            csv.display()
        )));
    }
    let mut runs = Vec::new();
    for (i, line) in lines {
        let source = format!("{} line {}", csv.display(), i + 1);
        let cols =
            super::csv::split(line).map_err(|why| input(format!("{source}: `{line}`: {why}")))?;
        let cols: Vec<&str> = cols.iter().map(|c| c.trim()).collect();
        let [world, method, folder] = cols[..] else {
            return Err(input(format!(
                "{source}: `{line}` has {} columns; rows are world,method,score_folder",
                cols.len()
            )));
        };
        if method.is_empty() || folder.is_empty() {
            return Err(input(format!(
                "{source}: the method and the score folder must not be empty"
            )));
        }
        let world = (!world.is_empty()).then(|| base.join(world));
        runs.push(read(method, &base.join(folder), world, source)?);
    }
    Ok(runs)
}

/// Merges each method's runs on one world: folders of different kinds add their numbers; the
/// same number twice (the same world scored twice alike) is refused, naming both.
pub fn merge(runs: Vec<Run>) -> Result<Vec<Run>, Error> {
    let mut by: BTreeMap<(String, PathBuf), Run> = BTreeMap::new();
    for r in runs {
        let k = (r.method.clone(), r.key.clone());
        match by.get_mut(&k) {
            None => {
                by.insert(k, r);
            }
            Some(have) => {
                if let Some(m) = r.metrics.keys().find(|m| have.metrics.contains_key(*m)) {
                    return Err(input(format!(
                        "method {} has world {} twice: {} ({}) and {} ({}) both give {m}; keep one score folder per world and method (or name another method)",
                        r.method,
                        r.world.display(),
                        have.folders[0].display(),
                        have.source,
                        r.folders[0].display(),
                        r.source
                    )));
                }
                have.metrics.extend(r.metrics);
                have.folders.extend(r.folders);
                have.failed = match (have.failed, r.failed) {
                    (None, f) | (f, None) => f,
                    (Some(a), Some(b)) => Some(a || b),
                };
            }
        }
    }
    Ok(by.into_values().collect())
}
