//! Reading the worlds to compare: our world folders (alone or in a dataset folder) and the
//! original tool's `.npy` grids in any of its encodings. Every grid goes through the same
//! import (classification, shafts, graph), so ours and the original's are measured alike.
//! Files that are not worlds are skipped with a warning naming them.
//!
//! The original tool saves every world three times, in its spatial, topological and
//! structural encodings (`<world>/pkl/subtgraph.spatial.pkl`, `.topological`, `.structural`;
//! `.npy` once converted, often renamed `world_12_spatial.npy`, ...). Counting each file as a
//! world would put three copies of every world in the statistics (pairwise IoU 1 between
//! them), so files whose stems differ only by the encoding's name, or that are the only grids
//! of one folder, are one world, measured from its spatial encoding (it alone marks shafts);
//! the report lists each such world and the files left out.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use subtgraph_core::graph::EdgeKind;
use subtgraph_core::tile::TileKind;
use subtgraph_core::{Layout, Pipeline, import, npy};

use super::metrics::Mask;
use crate::Error;

type Result<T> = std::result::Result<T, Error>;

/// One world, reduced to what the statistics need.
#[derive(Clone, Debug)]
pub struct Sample {
    /// Its group (the input it came from).
    pub group: String,
    /// Its name (folder or file stem).
    pub name: String,
    /// Occupancy per level.
    pub levels: Vec<Mask>,
    /// Tiles per kind, in [`TileKind::ALL`] order.
    pub tiles: [usize; 7],
    /// Occupied cells.
    pub cells: usize,
    /// Total passage length in cells (corridor steps; shafts count as none).
    pub length_cells: usize,
    /// Total passage length in metres (corridors and shafts, at the world's pitch; the
    /// original's grids at the default 25 m pitch).
    pub length_m: f64,
    /// Independent cycles, summed over levels.
    pub cycles: u32,
    /// Degree of every graph node (corridors and shafts ending there).
    pub degrees: Vec<usize>,
    /// Length in cells of every corridor.
    pub corridors: Vec<usize>,
    /// Per level and structure (`t-junction`, `intersection`, `loop`): `(requested, expected,
    /// achieved)`; empty for the original's grids, which record no request.
    pub constraints: Vec<BTreeMap<String, (u64, u64, u64)>>,
    /// For a world of the original's found in several files (encodings): the file measured
    /// and the others, left out. Empty otherwise.
    pub encodings: Option<(String, Vec<String>)>,
}

/// One input argument's worlds.
pub struct Group {
    /// Its label: the folder's name.
    pub name: String,
    /// The path given.
    pub path: PathBuf,
    /// Its worlds, by name.
    pub samples: Vec<Sample>,
}

/// Reads every input. Warnings (skipped files) go to standard error.
pub fn load(inputs: &[PathBuf]) -> Result<Vec<Group>> {
    let mut groups: Vec<Group> = Vec::new();
    for path in inputs {
        if !path.exists() {
            return Err(Error::Input(format!("{} does not exist", path.display())));
        }
        let mut name = path
            .canonicalize()
            .ok()
            .and_then(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
            .unwrap_or_else(|| path.display().to_string());
        let base = name.clone();
        let mut k = 2;
        while groups.iter().any(|g| g.name == name) {
            name = format!("{base}-{k}");
            k += 1;
        }
        let mut samples = Vec::new();
        collect(path, &name, &mut samples, true);
        samples.sort_by(|a, b| a.name.cmp(&b.name));
        // A dataset of several sources (`cave-0000`, `mine-0000`, ...) is one group per source.
        let sources: Vec<Option<&str>> = samples.iter().map(|s| source_of(&s.name)).collect();
        let mut distinct: Vec<&str> = sources.iter().flatten().copied().collect();
        distinct.dedup();
        distinct.sort_unstable();
        distinct.dedup();
        if distinct.len() > 1 && sources.iter().all(Option::is_some) {
            for source in distinct {
                let label = format!("{name}:{source}");
                let mut part: Vec<Sample> = samples
                    .iter()
                    .filter(|s| source_of(&s.name) == Some(source))
                    .cloned()
                    .collect();
                for s in &mut part {
                    s.group.clone_from(&label);
                }
                groups.push(Group {
                    name: label,
                    path: path.clone(),
                    samples: part,
                });
            }
            continue;
        }
        groups.push(Group {
            name,
            path: path.clone(),
            samples,
        });
    }
    Ok(groups)
}

/// The source of a dataset world's folder name: `cave` for `cave-0012`.
fn source_of(name: &str) -> Option<&str> {
    name.rsplit_once('-')
        .filter(|(s, i)| !s.is_empty() && !i.is_empty() && i.bytes().all(|b| b.is_ascii_digit()))
        .map(|(s, _)| s)
}

fn warn(path: &Path, why: &str) {
    eprintln!(
        "warning: skipping {}: {}",
        path.display(),
        subtgraph_core::error::shorten(why)
    );
}

/// Adds the worlds at `path`: a world folder, a `.npy` file, or a folder of either (one level
/// down when `top`).
fn collect(path: &Path, group: &str, out: &mut Vec<Sample>, top: bool) {
    if path.is_file() {
        if path.extension().is_some_and(|e| e == "npy") {
            match load_npy(path, group, None) {
                Ok(s) => out.push(s),
                Err(e) => warn(path, &crate::message(&e)),
            }
        } else if top {
            warn(path, "not a world folder, a dataset folder or a .npy grid");
        }
        return;
    }
    if path.join("occupancy.npy").is_file() {
        match load_world_folder(path, group) {
            Ok(s) => out.push(s),
            Err(e) => warn(path, &crate::message(&e)),
        }
        return;
    }
    let Ok(entries) = std::fs::read_dir(path) else {
        warn(path, "cannot be read");
        return;
    };
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    let folder = path
        .file_name()
        .map_or(String::new(), |n| n.to_string_lossy().into_owned());
    let is_npy = |p: &Path| p.is_file() && p.extension().is_some_and(|e| e == "npy");
    if !top {
        // A folder per world of the original tool's grids: its .npy files, or those of its
        // subfolders (the original's `<world>/pkl/`), are that world's encodings; a folder
        // of several worlds' grids names each by its stem.
        let mut grids: Vec<PathBuf> = paths.iter().filter(|p| is_npy(p)).cloned().collect();
        if grids.is_empty() {
            for dir in paths.iter().filter(|p| p.is_dir()) {
                let mut inner: Vec<PathBuf> = std::fs::read_dir(dir)
                    .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
                    .unwrap_or_default();
                inner.retain(|p| is_npy(p));
                inner.sort();
                grids.extend(inner);
            }
        }
        if grids.is_empty() {
            warn(
                path,
                "a folder without occupancy.npy or .npy grids is not a world",
            );
        }
        add_grids(path, &grids, group, out, |key, only| {
            if only || key.is_empty() {
                folder.clone()
            } else {
                format!("{folder}/{key}")
            }
        });
        return;
    }
    let mut grids = Vec::new();
    for p in paths {
        let file = p
            .file_name()
            .map_or(String::new(), |n| n.to_string_lossy().into_owned());
        // Hidden files (run facts, temporary folders) and the dataset's index are ours.
        if file.starts_with('.') || file == "index.json" || file == "index.csv" {
            continue;
        }
        if p.is_dir() {
            collect(&p, group, out, false);
        } else if is_npy(&p) {
            grids.push(p);
        } else {
            warn(&p, "not a world folder or a .npy grid");
        }
    }
    add_grids(path, &grids, group, out, |key, _| {
        if key.is_empty() {
            folder.clone()
        } else {
            key.to_owned()
        }
    });
}

/// The original's encodings, in the order one is preferred to measure a world from: spatial
/// marks shafts and tile kinds; topological marks nodes; structural is plain 0/1 (and wrong
/// for the original's multi-level worlds).
const ENCODINGS: [&str; 3] = ["spatial", "topological", "structural"];

/// A grid file's world and encoding, from its stem: `world_12_spatial` is world `world_12`
/// in encoding 0, `subtgraph.topological` world `subtgraph` in encoding 1, `spatial` the
/// folder's world; any other stem is a world of its own, in an encoding the values tell.
fn world_and_encoding(stem: &str) -> (String, Option<usize>) {
    let lower = stem.to_ascii_lowercase();
    for (rank, name) in ENCODINGS.iter().enumerate() {
        if lower == *name {
            return (String::new(), Some(rank));
        }
        if let Some(base) = lower
            .strip_suffix(name)
            .and_then(|b| b.strip_suffix(['.', '_', '-']))
        {
            return (stem[..base.len()].to_owned(), Some(rank));
        }
    }
    (stem.to_owned(), None)
}

/// Adds the worlds of `grids` (files in `dir` or its subfolders): files of one world (same
/// subfolder and stem but for the encoding) are one world, measured from the first of its
/// files that loads in [`ENCODINGS`] order. `name(world, only)` names it from its stem
/// without the encoding (`only`: it is the only world among `grids`).
fn add_grids(
    dir: &Path,
    grids: &[PathBuf],
    group: &str,
    out: &mut Vec<Sample>,
    name: impl Fn(&str, bool) -> String,
) {
    let mut worlds: BTreeMap<String, Vec<(usize, &PathBuf)>> = BTreeMap::new();
    for grid in grids {
        let stem = grid
            .file_stem()
            .map_or(String::new(), |n| n.to_string_lossy().into_owned());
        let (world, rank) = world_and_encoding(&stem);
        let sub = grid
            .parent()
            .and_then(|p| p.strip_prefix(dir).ok())
            .map(|p| p.to_string_lossy().into_owned())
            .unwrap_or_default();
        let key = match (sub.is_empty(), world.is_empty()) {
            (true, _) => world,
            (false, true) => sub,
            (false, false) => format!("{sub}/{world}"),
        };
        worlds
            .entry(key)
            .or_default()
            .push((rank.unwrap_or(ENCODINGS.len()), grid));
    }
    let only = worlds.len() == 1;
    for (key, mut files) in worlds {
        files.sort();
        let label = |p: &Path| {
            p.strip_prefix(dir)
                .unwrap_or(p)
                .to_string_lossy()
                .into_owned()
        };
        for (k, (_, file)) in files.iter().enumerate() {
            match load_npy(file, group, None) {
                Ok(mut s) => {
                    s.name = name(&key, only);
                    if files.len() > 1 {
                        let others = files
                            .iter()
                            .enumerate()
                            .filter(|&(j, _)| j != k)
                            .map(|(_, (_, f))| label(f))
                            .collect();
                        s.encodings = Some((label(file), others));
                    }
                    out.push(s);
                    break;
                }
                Err(e) => warn(file, &crate::message(&e)),
            }
        }
    }
}

fn load_world_folder(dir: &Path, group: &str) -> Result<Sample> {
    let pipeline = std::fs::read_to_string(dir.join("world.toml"))
        .ok()
        .and_then(|t| Pipeline::parse(&t, "world.toml").ok());
    let name = dir
        .file_name()
        .map_or("world".into(), |n| n.to_string_lossy().into_owned());
    let mut sample = load_npy(&dir.join("occupancy.npy"), group, pipeline.as_ref())?;
    sample.name = name;
    if let Ok(bytes) = std::fs::read(dir.join("topology.json")) {
        let topo: subtgraph_schema::Topology =
            subtgraph_schema::read(&bytes).map_err(|source| Error::WorldFile {
                world: dir.to_owned(),
                source,
            })?;
        sample.constraints = topo
            .per_level
            .iter()
            .map(|l| {
                subtgraph_schema::structure_counts(l)
                    .iter()
                    .map(|c| {
                        // Imported worlds have no expectation: what was asked is expected.
                        let expected = c.expected.unwrap_or(c.requested);
                        (c.structure.to_owned(), (c.requested, expected, c.achieved))
                    })
                    .collect()
            })
            .collect();
    }
    Ok(sample)
}

fn load_npy(path: &Path, group: &str, pipeline: Option<&Pipeline>) -> Result<Sample> {
    let bytes = crate::input::read(path).map_err(|e| match e {
        Error::Io { source, .. } => Error::io("cannot read it")(source),
        e => e,
    })?;
    // The warning that skips the file names it already.
    let array = npy::decode(&bytes).map_err(|e| Error::Input(e.to_string()))?;
    let default = Pipeline::default();
    let name = path.display().to_string();
    let (world, _) = import::import_occupancy(
        &array,
        &name,
        pipeline.unwrap_or(&default),
        env!("CARGO_PKG_VERSION"),
    )?;
    let stem = path
        .file_stem()
        .map_or("world".into(), |n| n.to_string_lossy().into_owned());
    Ok(sample_of(&world, group, stem))
}

/// The statistics' view of a world.
pub fn sample_of(world: &Layout, group: &str, name: String) -> Sample {
    let occ = &world.occupancy;
    let levels = (0..occ.levels())
        .map(|l| {
            Mask::new(
                occ.rows(),
                occ.cols(),
                occ.level_cells(l).map(|c| *occ.get(c)).collect(),
            )
        })
        .collect();
    let mut tiles = [0usize; 7];
    for t in world.tiles.as_slice().iter().flatten() {
        let i = TileKind::ALL
            .iter()
            .position(|k| *k == t.kind)
            .expect("every kind is listed");
        tiles[i] += 1;
    }
    let g = &world.graph;
    let mut degrees = vec![0usize; g.nodes.len()];
    for e in &g.edges {
        degrees[e.from] += 1;
        degrees[e.to] += 1;
    }
    let corridors: Vec<usize> = g
        .edges
        .iter()
        .filter(|e| e.kind == EdgeKind::Corridor)
        .map(|e| e.length_cells)
        .collect();
    Sample {
        group: group.to_owned(),
        name,
        levels,
        tiles,
        cells: occ.occupied_count(),
        length_cells: corridors.iter().sum(),
        length_m: g.edges.iter().map(|e| e.length_m).sum(),
        cycles: world.levels.iter().map(|l| l.achieved.loops).sum(),
        degrees,
        corridors,
        constraints: Vec::new(),
        encodings: None,
    }
}
