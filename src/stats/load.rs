//! Reading the worlds to compare: our world folders (alone or in a dataset folder) and the
//! original tool's `.npy` grids in any of its encodings. Every grid goes through the same
//! import (classification, shafts, graph), so ours and the original's are measured alike.
//! Files that are not worlds are skipped with a warning naming them.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Result, anyhow};

use subtgraph_core::graph::EdgeKind;
use subtgraph_core::tile::TileKind;
use subtgraph_core::{Pipeline, World, import, npy};

use super::metrics::Mask;

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
            return Err(anyhow!("{} does not exist", path.display()));
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
                Err(e) => warn(path, &format!("{e:#}")),
            }
        } else if top {
            warn(path, "not a world folder, a dataset folder or a .npy grid");
        }
        return;
    }
    if path.join("occupancy.npy").is_file() {
        match load_world_folder(path, group) {
            Ok(s) => out.push(s),
            Err(e) => warn(path, &format!("{e:#}")),
        }
        return;
    }
    if !top {
        // A folder per world of the original tool's grids: each .npy in it is a world.
        let mut grids: Vec<PathBuf> = std::fs::read_dir(path)
            .map(|d| {
                d.filter_map(|e| e.ok().map(|e| e.path()))
                    .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "npy"))
                    .collect()
            })
            .unwrap_or_default();
        grids.sort();
        if grids.is_empty() {
            warn(
                path,
                "a folder without occupancy.npy or .npy grids is not a world",
            );
        }
        let folder = path
            .file_name()
            .map_or(String::new(), |n| n.to_string_lossy().into_owned());
        for grid in grids {
            match load_npy(&grid, group, None) {
                Ok(mut s) => {
                    s.name = format!("{folder}/{}", s.name);
                    out.push(s);
                }
                Err(e) => warn(&grid, &format!("{e:#}")),
            }
        }
        return;
    }
    let Ok(entries) = std::fs::read_dir(path) else {
        warn(path, "cannot be read");
        return;
    };
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    for p in paths {
        let file = p
            .file_name()
            .map_or(String::new(), |n| n.to_string_lossy().into_owned());
        // Hidden files (run facts, temporary folders) and the dataset's index are ours.
        if file.starts_with('.') || file == "index.json" || file == "index.csv" {
            continue;
        }
        if p.is_dir() || p.extension().is_some_and(|e| e == "npy") {
            collect(&p, group, out, false);
        } else {
            warn(&p, "not a world folder or a .npy grid");
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
        let topo: serde_json::Value = serde_json::from_slice(&bytes)
            .map_err(|e| anyhow!("topology.json is not JSON: {e}"))?;
        let num = |v: &serde_json::Value| v.as_u64().unwrap_or(0);
        sample.constraints = topo["per_level"]
            .as_array()
            .map_or(&[][..], |v| v)
            .iter()
            .map(|l| {
                [
                    ("t-junction", "t_junctions"),
                    ("intersection", "intersections"),
                    ("loop", "loops"),
                ]
                .iter()
                .map(|(shape, key)| {
                    let req = num(&l["requested"][shape]);
                    // Imported worlds have no expectation: what was asked is what is expected.
                    let exp = l["expected"][key].as_u64().unwrap_or(req);
                    ((*shape).to_owned(), (req, exp, num(&l["achieved"][key])))
                })
                .collect()
            })
            .collect();
    }
    Ok(sample)
}

fn load_npy(path: &Path, group: &str, pipeline: Option<&Pipeline>) -> Result<Sample> {
    let bytes = std::fs::read(path).map_err(|e| anyhow!("cannot read it: {e}"))?;
    let array = npy::decode(&bytes).map_err(|e| anyhow!(e))?;
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
pub fn sample_of(world: &World, group: &str, name: String) -> Sample {
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
    }
}
