//! The route graph: the world folder's `ground_truth/graph.json`, what routes are planned on.
//!
//! Its nodes are where passages meet or end, its edges the corridors, ramps and shafts between
//! them, each with a polyline along the middle of its passage, on its floor (see the graph
//! exporter). Routes follow those polylines; the labels of a sequence name its ids, so a scan
//! can be traced to the edge or junction it was taken in.

use serde::Deserialize;

use crate::error::SenseError;

/// A node of the graph.
#[derive(Clone, Debug, Deserialize, PartialEq)]
pub struct Node {
    /// Its id (`graph.json`'s).
    pub id: usize,
    /// `dead-end`, `t-junction`, `intersection`, `corner`, `shaft-up`, `shaft-landing`, ...
    pub kind: String,
    /// Its level.
    pub level: usize,
    /// Where it is, on the floor, metres.
    pub position: [f64; 3],
}

/// What kind of passage an edge is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeKind {
    /// A passage within a level.
    Corridor,
    /// A drivable spiral ramp between levels.
    Ramp,
    /// A vertical shaft between levels: only a flying platform takes it.
    Shaft,
}

/// An edge of the graph.
#[derive(Clone, Debug, PartialEq)]
pub struct Edge {
    /// Its id (`graph.json`'s).
    pub id: usize,
    /// Corridor, ramp or shaft.
    pub kind: EdgeKind,
    /// One end node's id.
    pub from: usize,
    /// The other end node's id.
    pub to: usize,
    /// Length, metres.
    pub length: f64,
    /// From `from` to `to`, along the middle of the passage on its floor (a shaft's from its
    /// foot to its landing).
    pub polyline: Vec<[f64; 3]>,
}

/// The graph of a world.
#[derive(Clone, Debug, PartialEq)]
pub struct RouteGraph {
    /// Nodes, indexed by id.
    pub nodes: Vec<Node>,
    /// Edges, indexed by id.
    pub edges: Vec<Edge>,
    /// The node a route starts from (the world's start).
    pub start: usize,
}

#[derive(Deserialize)]
struct EdgeJson {
    id: usize,
    kind: String,
    from: usize,
    to: usize,
    length_m: f64,
    polyline: Vec<[f64; 3]>,
}

#[derive(Deserialize)]
struct GraphJson {
    format: String,
    start: Option<usize>,
    nodes: Vec<Node>,
    edges: Vec<EdgeJson>,
}

impl RouteGraph {
    /// Reads `graph.json` text (`source` names it in errors).
    pub fn from_json(text: &str, source: &str) -> Result<RouteGraph, SenseError> {
        let bad = |why: String| SenseError::BadGraph {
            path: source.to_owned(),
            why,
        };
        let g: GraphJson = serde_json::from_str(text).map_err(|e| bad(e.to_string()))?;
        if !g.format.starts_with("subtgraph-graph/") {
            return Err(bad(format!("format '{}' is not subtgraph-graph", g.format)));
        }
        let mut nodes = g.nodes;
        nodes.sort_by_key(|n| n.id);
        if nodes.iter().enumerate().any(|(i, n)| n.id != i) {
            return Err(bad("node ids are not 0, 1, 2, ...".into()));
        }
        let mut edges = Vec::with_capacity(g.edges.len());
        for e in g.edges {
            let kind = match e.kind.as_str() {
                "corridor" => EdgeKind::Corridor,
                "ramp" => EdgeKind::Ramp,
                "shaft" => EdgeKind::Shaft,
                other => return Err(bad(format!("edge {} has an unknown kind '{other}'", e.id))),
            };
            if e.from >= nodes.len() || e.to >= nodes.len() {
                return Err(bad(format!(
                    "edge {} joins a node that does not exist",
                    e.id
                )));
            }
            if e.polyline.len() < 2 || e.polyline.iter().flatten().any(|x| !x.is_finite()) {
                return Err(bad(format!("edge {} has no usable polyline", e.id)));
            }
            edges.push(Edge {
                id: e.id,
                kind,
                from: e.from,
                to: e.to,
                length: e.length_m,
                polyline: e.polyline,
            });
        }
        edges.sort_by_key(|e| e.id);
        if edges.iter().enumerate().any(|(i, e)| e.id != i) {
            return Err(bad("edge ids are not 0, 1, 2, ...".into()));
        }
        let start = g.start.unwrap_or(0);
        if start >= nodes.len() {
            return Err(bad("the graph has no start node".into()));
        }
        Ok(RouteGraph {
            nodes,
            edges,
            start,
        })
    }

    /// The first node position or polyline point farther than `reach` from every triangle of
    /// `caster`, if any: a point a route cannot be at (a graph edited, or another world's; a
    /// point moved 10,000 km once made the route ask for 4 GB).
    pub fn stray(
        &self,
        caster: &subtgraph_core::raycast::RayCaster,
        reach: f64,
    ) -> Option<[f64; 3]> {
        self.nodes
            .iter()
            .map(|n| n.position)
            .chain(self.edges.iter().flat_map(|e| e.polyline.iter().copied()))
            .find(|&p| caster.nearest(p, reach).is_none())
    }

    /// The edges at a node, as `(edge id, the node at its other end)`, in id order.
    pub fn neighbours(&self, node: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.edges.iter().filter_map(move |e| {
            if e.from == node {
                Some((e.id, e.to))
            } else if e.to == node {
                Some((e.id, e.from))
            } else {
                None
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_graph_reads_and_bad_ones_are_refused_with_the_reason() {
        let text = r#"{"format": "subtgraph-graph/1", "start": 0,
            "nodes": [{"id": 0, "kind": "dead-end", "level": 0, "position": [0, 0, 0]},
                      {"id": 1, "kind": "dead-end", "level": 0, "position": [10, 0, 0]}],
            "edges": [{"id": 0, "kind": "corridor", "from": 0, "to": 1, "length_m": 10,
                       "polyline": [[0, 0, 0], [10, 0, 0]]}]}"#;
        let g = RouteGraph::from_json(text, "g.json").unwrap();
        assert_eq!(g.neighbours(1).collect::<Vec<_>>(), [(0, 0)]);
        let bad = text.replace("corridor", "tunnel");
        let e = RouteGraph::from_json(&bad, "g.json")
            .unwrap_err()
            .to_string();
        assert!(e.contains("g.json") && e.contains("tunnel"), "{e}");
        let e = RouteGraph::from_json("{}", "g.json")
            .unwrap_err()
            .to_string();
        assert!(e.contains("g.json"), "{e}");
    }
}
