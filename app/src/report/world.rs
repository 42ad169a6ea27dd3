//! A world's parameters, the x of each "metric against the world" plot: read from the world
//! folder's own files (`topology.json`, `ground_truth/hazards.json`,
//! `world.toml`) through the `schema` types.

use std::path::Path;

use subtgraph_core::graph::EdgeKind;
use subtgraph_schema::{Document, Hazards, Topology};

use crate::Error;

/// The parameters, in the order of their columns and plots.
pub const PARAMETERS: [&str; 7] = [
    "loops",
    "t_junctions",
    "intersections",
    "levels",
    "passage_length_m",
    "sloped_share",
    "hazard_patches",
];

/// One world, as the report describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct WorldInfo {
    /// Its folder's name.
    pub name: String,
    /// The preset it was made from (`world.toml`'s `[generated] source = "preset NAME ..."`), else
    /// `custom`.
    pub preset: String,
    /// [`PARAMETERS`]' values: loops, T-junctions and intersections summed over levels (as
    /// counted on the final grid), levels, passage length (m), the share of that length in
    /// shafts and ramps, hazard floor patches.
    pub parameters: [f64; 7],
    /// Its maps, relative to the world folder (`maps/level-N.png`).
    pub maps: Vec<String>,
}

fn document<D: Document>(world: &Path) -> Result<Option<D>, Error> {
    let path = world.join(D::PATH);
    let Ok(bytes) = std::fs::read(&path) else {
        return Ok(None);
    };
    subtgraph_schema::read::<D>(&bytes)
        .map(Some)
        .map_err(|source| Error::WorldFile {
            world: world.to_owned(),
            source,
        })
}

/// Reads a world folder's parameters.
pub fn read(world: &Path) -> Result<WorldInfo, Error> {
    let topology: Topology = document(world)?.ok_or_else(|| {
        Error::Input(format!(
            "{}: no topology.json; is it a world folder written by `subtgraph generate`?",
            world.display()
        ))
    })?;
    let sum = |f: fn(&subtgraph_core::layout::Counts) -> u32| -> f64 {
        topology
            .per_level
            .iter()
            .map(|l| f64::from(f(&l.achieved)))
            .sum()
    };
    // Shafts and ramps: the passages a robot climbs or is carried along.
    let total: f64 = topology.edges.iter().map(|e| e.length_m).sum();
    let sloped: f64 = topology
        .edges
        .iter()
        .filter(|e| e.kind != EdgeKind::Corridor)
        .map(|e| e.length_m)
        // Not `sum`: an empty f64 sum is -0.0, which report.json would print as such.
        .fold(0.0, |a, b| a + b);
    let sloped_share = if total > 0.0 { sloped / total } else { 0.0 };
    let hazards = document::<Hazards>(world)?.map_or(0, |h| h.patches.len());
    let toml_path = world.join("world.toml");
    let text = std::fs::read_to_string(&toml_path)
        .map_err(Error::io(format!("reading {}", toml_path.display())))?;
    let preset = text
        .parse::<toml::Table>()
        .ok()
        .and_then(|t| {
            t.get("generated")?
                .get("source")?
                .as_str()?
                .strip_prefix("preset ")?
                .split_whitespace()
                .next()
                .map(str::to_owned)
        })
        .unwrap_or_else(|| "custom".to_owned());
    let maps = (0..topology.levels)
        .map(|l| format!("maps/level-{l}.png"))
        .filter(|m| world.join(m).is_file())
        .collect();
    Ok(WorldInfo {
        name: world.file_name().map_or_else(
            || world.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        ),
        preset,
        parameters: [
            sum(|c| c.loops),
            sum(|c| c.t_junctions),
            sum(|c| c.intersections),
            topology.levels as f64,
            topology.total_length_m,
            sloped_share,
            hazards as f64,
        ],
        maps,
    })
}
