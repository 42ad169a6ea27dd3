//! Where a close-up or inside view is taken: a graph node's cell centre (`topology.json`), its
//! floor and which way its first passage runs (`ground_truth/graph.json`, when the world has
//! it; the grid's cells otherwise).

use std::path::Path;

use subtgraph_core::vec3::{V3, sub};
use subtgraph_schema::{Document, Graph, Topology};

use crate::Error;

/// A graph node's place in the world.
pub(super) struct Place {
    /// Its cell's centre at the level's nominal floor height (`topology.json`).
    pub cell_centre: V3,
    /// On its passage's floor (`ground_truth/graph.json`), when the world has it.
    pub floor: Option<V3>,
    /// The horizontal direction of its first passage (lowest edge id), if it has one.
    pub along: Option<V3>,
    /// The world's tile pitch, metres.
    pub pitch: f64,
    /// The world's level height, metres.
    pub level: f64,
}

/// Reads and checks a file of the world folder.
fn read<D: Document>(world: &Path) -> Result<D, Error> {
    let path = world.join(D::PATH);
    let bytes = std::fs::read(&path).map_err(Error::io(format!("reading {}", path.display())))?;
    subtgraph_schema::read(&bytes).map_err(|source| Error::WorldFile {
        world: world.to_owned(),
        source,
    })
}

/// The tile pitch of a world (`topology.json`; 25 m, the default, without a readable one: the
/// whole world's picture needs no more of the world than its mesh).
pub(super) fn pitch_of(world: &Path) -> f64 {
    read::<Topology>(world).map_or(25.0, |t| t.tile_pitch_m)
}

/// The horizontal direction of `d`, if it has one.
fn horizontal(d: V3) -> Option<V3> {
    let l = (d[0] * d[0] + d[1] * d[1]).sqrt();
    (l > 1e-9).then(|| [d[0] / l, d[1] / l, 0.0])
}

/// Where node `at` (the start when `None`) is: from `topology.json`, and from
/// `ground_truth/graph.json` (each node and passage on its own floor) when the world has it.
pub(super) fn place_of(world: &Path, at: Option<usize>) -> Result<Place, Error> {
    let topo: Topology = read(world)?;
    let node = match at {
        Some(n) => n,
        None => topo.start.ok_or_else(|| {
            Error::Input(format!(
                "{}: topology.json has no start node",
                world.display()
            ))
        })?,
    };
    let Some(entry) = topo.nodes.get(node) else {
        return Err(Error::Usage(format!(
            "--at {node}: {} has nodes 0 to {} (their ids are in topology.json)",
            world.display(),
            topo.nodes.len().saturating_sub(1)
        )));
    };
    let (pitch, level) = (topo.tile_pitch_m, topo.level_height_m);
    if world.join(Graph::PATH).is_file() {
        let g: Graph = read(world)?;
        if let Some(floor) = g.nodes.get(node).map(|n| n.position) {
            let along = g.edges.iter().find_map(|e| {
                let mut line = e.polyline.clone();
                if e.to == node && e.from != node {
                    line.reverse();
                } else if e.from != node {
                    return None;
                }
                // Look at the passage a quarter of a tile on, not at its first wiggle.
                let far = line
                    .iter()
                    .find(|p| {
                        horizontal(sub(**p, floor)).is_some() && {
                            let d = sub(**p, floor);
                            d[0] * d[0] + d[1] * d[1] >= (0.25 * pitch).powi(2)
                        }
                    })
                    .or(line.last())?;
                horizontal(sub(*far, floor))
            });
            return Ok(Place {
                cell_centre: entry.position,
                floor: Some(floor),
                along,
                pitch,
                level,
            });
        }
    }
    let cell = entry.cell;
    let along = topo.edges.iter().find_map(|e| {
        let next = if e.from == node {
            e.cells.get(1)?
        } else if e.to == node {
            e.cells.get(e.cells.len().checked_sub(2)?)?
        } else {
            return None;
        };
        let d = |a: usize, b: usize| a as f64 - b as f64;
        // Columns run east (+x), rows south (-y).
        horizontal([d(next.col, cell.col), -d(next.row, cell.row), 0.0])
    });
    Ok(Place {
        cell_centre: entry.position,
        floor: None,
        along,
        pitch,
        level,
    })
}
