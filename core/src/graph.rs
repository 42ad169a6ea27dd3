//! The topological graph: junctions, intersections, dead ends and shafts as nodes; corridors
//! (with their cells and length) and shafts as edges.

use serde::{Deserialize, Serialize};

use crate::grid::{Cell, Direction, Grid3, Occupancy, Shaft};
use crate::tile::{Tile, TileKind};

/// A node of the graph.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Node {
    /// Index in [`TopologyGraph::nodes`].
    pub id: usize,
    /// Tile kind at the node (a straight or corner only for a corridor ring with no junction).
    pub kind: TileKind,
    /// Its cell.
    pub cell: Cell,
    /// World-frame position in metres (x east, y north, z up).
    pub position: [f64; 3],
}

/// What an edge is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum EdgeKind {
    /// A passage on one level.
    Corridor,
    /// A vertical shaft between levels.
    Shaft,
    /// A spiral ramp between levels, in the shaft's cells (`world.connections = "ramp"`).
    Ramp,
}

/// An edge: a corridor between two nodes, or a shaft.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Edge {
    /// Index in [`TopologyGraph::edges`].
    pub id: usize,
    /// Corridor or shaft.
    pub kind: EdgeKind,
    /// Node at one end.
    pub from: usize,
    /// Node at the other end.
    pub to: usize,
    /// The cells from `from` to `to`, both included (for a shaft, just the two ends).
    pub cells: Vec<Cell>,
    /// Steps between the two end cells.
    pub length_cells: usize,
    /// Length in metres: steps x tile pitch, or the level height for a shaft or ramp (the
    /// ground truth's graph gives a ramp's driven length).
    pub length_m: f64,
}

/// Nodes and edges of a world.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct TopologyGraph {
    /// Nodes in raster order of their cells.
    pub nodes: Vec<Node>,
    /// Corridors in order of discovery, then shafts.
    pub edges: Vec<Edge>,
}

impl TopologyGraph {
    /// Builds the graph of a layout from its tiles and shafts (what
    /// [`crate::layout::Layout::new`] does): `position` places a cell in the world frame,
    /// `pitch` and `level_height` give corridors and shafts their lengths in metres.
    pub fn build(
        occ: &Occupancy,
        tiles: &Grid3<Option<Tile>>,
        shafts: &[Shaft],
        position: impl Fn(Cell) -> [f64; 3],
        pitch: f64,
        level_height: f64,
    ) -> TopologyGraph {
        let mut node_of = Grid3::filled(occ.levels(), occ.rows(), occ.cols(), usize::MAX);
        let mut graph = TopologyGraph::default();
        let add_node = |graph: &mut TopologyGraph, c: Cell, kind: TileKind| {
            let id = graph.nodes.len();
            graph.nodes.push(Node {
                id,
                kind,
                cell: c,
                position: position(c),
            });
            id
        };
        for c in occ.cells() {
            if let Some(t) = tiles.get(c) {
                if t.kind.is_node() {
                    *node_of.get_mut(c) = add_node(&mut graph, c, t.kind);
                }
            }
        }
        let mut visited = Grid3::filled(occ.levels(), occ.rows(), occ.cols(), false);
        let walk_from = |graph: &mut TopologyGraph,
                         node_of: &Grid3<usize>,
                         visited: &mut Grid3<bool>,
                         start: Cell| {
            let openings = tiles.get(start).map_or(0, |t| t.openings);
            for d in Direction::ALL {
                if openings & d.bit() == 0 {
                    continue;
                }
                let mut cells = vec![start];
                let mut here = start;
                let mut heading = d;
                let end = loop {
                    here = occ
                        .neighbour(here, heading)
                        .expect("openings stay in the grid");
                    cells.push(here);
                    if *node_of.get(here) != usize::MAX {
                        break here;
                    }
                    *visited.get_mut(here) = true;
                    let o = tiles.get(here).map_or(0, |t| t.openings);
                    heading = Direction::ALL
                        .into_iter()
                        .find(|&n| n != heading.opposite() && o & n.bit() != 0)
                        .expect("a corridor cell has two openings");
                };
                // Keep each corridor once: from the smaller (cell, direction) end.
                let back = heading.opposite();
                if (start, d) > (end, back) {
                    continue;
                }
                let id = graph.edges.len();
                let steps = cells.len() - 1;
                graph.edges.push(Edge {
                    id,
                    kind: EdgeKind::Corridor,
                    from: *node_of.get(start),
                    to: *node_of.get(end),
                    cells,
                    length_cells: steps,
                    length_m: steps as f64 * pitch,
                });
            }
        };
        let node_cells: Vec<Cell> = graph.nodes.iter().map(|n| n.cell).collect();
        for c in node_cells {
            walk_from(&mut graph, &node_of, &mut visited, c);
        }
        // Rings of corridor with no junction on them: make their first cell a node.
        for c in occ.cells() {
            if tiles.get(c).is_some() && *node_of.get(c) == usize::MAX && !*visited.get(c) {
                let kind = tiles.get(c).expect("occupied").kind;
                *node_of.get_mut(c) = add_node(&mut graph, c, kind);
                walk_from(&mut graph, &node_of, &mut visited, c);
            }
        }
        for s in shafts {
            let id = graph.edges.len();
            graph.edges.push(Edge {
                id,
                kind: EdgeKind::Shaft,
                from: *node_of.get(s.up),
                to: *node_of.get(s.landing),
                cells: vec![s.up, s.landing],
                length_cells: 0,
                length_m: level_height,
            });
        }
        graph
    }
}
