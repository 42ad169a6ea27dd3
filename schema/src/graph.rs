//! `ground_truth/graph.json`: the topological graph with each node on its passage's floor and
//! each edge's polyline along its passage (written by the exporters' `GraphFiles`, read by
//! `preview` for where a node is and which way its passage runs).
//!
//! `S` is the type of the texts (`format`, kinds): `&'static str` where the writer fills
//! them in, `String` (the default) where a file is read.

use serde::{Deserialize, Serialize};

use crate::{Document, SchemaError, finite};

/// `ground_truth/graph.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Graph<S = String> {
    /// [`Graph::FORMAT`](Document::FORMAT).
    pub format: S,
    /// The world's seed.
    pub seed: u64,
    /// The frame, in words.
    pub frame: S,
    /// Units, in words.
    pub units: S,
    /// Where positions are, in words (grid cells, or the passages' own floors).
    pub positions: S,
    /// The start's node id.
    pub start: Option<usize>,
    /// Nodes, by id.
    pub nodes: Vec<GraphNode<S>>,
    /// Edges, by id.
    pub edges: Vec<GraphEdge<S>>,
}

/// A node of `graph.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GraphNode<S = String> {
    /// Its id (its index).
    pub id: usize,
    /// Its tile's kind (`dead-end`, `t-junction`, ...).
    pub kind: S,
    /// Its cell's level.
    pub level: usize,
    /// Its cell's row.
    pub row: usize,
    /// Its cell's column.
    pub col: usize,
    /// On its passage's floor, metres.
    pub position: [f64; 3],
}

/// An edge of `graph.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GraphEdge<S = String> {
    /// Its id (its index).
    pub id: usize,
    /// `corridor`, `shaft` or `ramp`.
    pub kind: S,
    /// One end's node id.
    pub from: usize,
    /// The other end's node id.
    pub to: usize,
    /// Length along the polyline (a ramp's driven length), metres.
    pub length_m: f64,
    /// Steps between its end cells.
    pub length_cells: usize,
    /// From `from` to `to`, on the passage's floor, metres.
    pub polyline: Vec<[f64; 3]>,
    /// The narrowest width of its passage, metres (absent without a mesh).
    pub min_width_m: Option<f64>,
    /// The lowest height of its passage, metres (absent without a mesh).
    pub min_height_m: Option<f64>,
}

impl Document for Graph {
    const PATH: &'static str = "ground_truth/graph.json";
    const FORMAT: &'static str = "subtgraph-graph/1";

    fn format(&self) -> &str {
        &self.format
    }

    fn check(&self) -> Result<(), SchemaError> {
        let bad = |what: String| Err(SchemaError::invalid::<Self>(what));
        for (i, n) in self.nodes.iter().enumerate() {
            if n.id != i {
                return bad(format!("node {i} has id {}: ids must count from 0", n.id));
            }
            finite::<Self>(|| format!("node {i}'s position"), &n.position)?;
        }
        let nodes = self.nodes.len();
        for (i, e) in self.edges.iter().enumerate() {
            if e.id != i {
                return bad(format!("edge {i} has id {}: ids must count from 0", e.id));
            }
            if e.from >= nodes || e.to >= nodes {
                return bad(format!(
                    "edge {i} joins nodes {} and {}, but there are {nodes} nodes",
                    e.from, e.to
                ));
            }
            for p in &e.polyline {
                finite::<Self>(|| format!("a point of edge {i}'s polyline"), p)?;
            }
        }
        if let Some(s) = self.start.filter(|&s| s >= nodes) {
            return bad(format!("start is node {s}, but there are {nodes} nodes"));
        }
        Ok(())
    }
}
