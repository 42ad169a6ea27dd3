//! `graph`: the topological graph as `ground_truth/graph.json` and `ground_truth/graph.graphml`.
//!
//! Nodes are the junctions, intersections, dead ends and shaft ends (kind, cell, level, world
//! position on the floor of the tile's own passage); edges are corridors and shafts with their
//! length in metres (along the grid), the corridor's centreline along the middle of its
//! passage, in the world frame (the survey's, `survey/src/centrelines/`; without a mesh,
//! through the cell centres), and its least width and height measured on the collision
//! surface (`min_width_m`, `min_height_m`, `survey/src/sections.rs`; `null` without a mesh). The GraphML declares a
//! typed `<key>` for every attribute, so `networkx.read_graphml` gives numbers as numbers; it is
//! an undirected graph, and a multigraph when two corridors join the same two nodes.

use subtgraph_core::World;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter, write_file};
use subtgraph_core::graph::EdgeKind;
use subtgraph_core::survey::Survey;

use super::FRAME;
use crate::text::{push_fixed, push_uint};

/// Writes `ground_truth/graph.json` and `ground_truth/graph.graphml`.
#[derive(Clone, Copy, Debug, Default)]
pub struct GraphFiles;

type Document = subtgraph_schema::Graph<&'static str>;
type NodeOut = subtgraph_schema::GraphNode<&'static str>;
type EdgeOut = subtgraph_schema::GraphEdge<&'static str>;

fn edge_kind(k: EdgeKind) -> &'static str {
    match k {
        EdgeKind::Corridor => "corridor",
        EdgeKind::Shaft => "shaft",
        EdgeKind::Ramp => "ramp",
    }
}

fn document(world: &World, survey: &dyn Survey) -> Document {
    let g = &world.graph;
    Document {
        format: "subtgraph-graph/1",
        seed: world.resolved.seed,
        frame: FRAME,
        units: "metres",
        positions: if !survey.has_axes() {
            "tile centres on their level's nominal floor; a polyline runs through the cell centres of its corridor, a shaft's from the foot to the landing"
        } else {
            "on the floor of each tile's own passage (its axis, from the collision surface's free space): a node where its tile's passage meets its openings (a dead end where its passage ends), a corridor's polyline along the middle of its passage through every tile, a shaft's from the foot to the landing, a ramp's along its spiral's floor"
        },
        start: world
            .start
            .and_then(|s| g.nodes.iter().find(|n| n.cell == s).map(|n| n.id)),
        nodes: g
            .nodes
            .iter()
            .map(|n| NodeOut {
                id: n.id,
                kind: n.kind.name(),
                level: n.cell.level,
                row: n.cell.row,
                col: n.cell.col,
                position: survey.position(n.cell),
            })
            .collect(),
        edges: g
            .edges
            .iter()
            .zip(survey.edges())
            .zip(survey.sections())
            .map(|((e, line), least)| {
                EdgeOut {
                    id: e.id,
                    kind: edge_kind(e.kind),
                    from: e.from,
                    to: e.to,
                    length_m: line.length_m,
                    length_cells: e.length_cells,
                    polyline: line.points.clone(),
                    // Centimetres are what the surface is good for (and keep the files stable).
                    min_width_m: least.map(|l| round_cm(l.0)),
                    min_height_m: least.map(|l| round_cm(l.1)),
                }
            })
            .collect(),
    }
}

fn round_cm(v: f64) -> f64 {
    (v * 100.0).round() / 100.0
}

/// Appends a GraphML `<data>` element.
fn data(s: &mut Vec<u8>, key: &str, value: impl FnOnce(&mut Vec<u8>)) {
    s.extend_from_slice(b"<data key=\"");
    s.extend_from_slice(key.as_bytes());
    s.extend_from_slice(b"\">");
    value(s);
    s.extend_from_slice(b"</data>");
}

fn graphml(doc: &Document) -> Vec<u8> {
    let mut s = Vec::new();
    s.extend_from_slice(
        b"<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
<graphml xmlns=\"http://graphml.graphdrawing.org/xmlns\" \
xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\" \
xsi:schemaLocation=\"http://graphml.graphdrawing.org/xmlns http://graphml.graphdrawing.org/xmlns/1.0/graphml.xsd\">\n",
    );
    let keys: [(&str, &str, &str, &str); 18] = [
        ("g_seed", "graph", "seed", "long"),
        ("g_frame", "graph", "frame", "string"),
        ("g_start", "graph", "start", "string"),
        ("n_kind", "node", "kind", "string"),
        ("n_level", "node", "level", "int"),
        ("n_row", "node", "row", "int"),
        ("n_col", "node", "col", "int"),
        ("n_x", "node", "x", "double"),
        ("n_y", "node", "y", "double"),
        ("n_z", "node", "z", "double"),
        ("e_id", "edge", "edge_id", "int"),
        ("e_kind", "edge", "kind", "string"),
        ("e_length", "edge", "length_m", "double"),
        ("e_cells", "edge", "length_cells", "int"),
        ("e_polyline", "edge", "polyline", "string"),
        ("e_weight", "edge", "weight", "double"),
        ("e_min_width", "edge", "min_width_m", "double"),
        ("e_min_height", "edge", "min_height_m", "double"),
    ];
    for (id, on, name, ty) in keys {
        s.extend_from_slice(
            format!("  <key id=\"{id}\" for=\"{on}\" attr.name=\"{name}\" attr.type=\"{ty}\"/>\n")
                .as_bytes(),
        );
    }
    s.extend_from_slice(b"  <graph id=\"topology\" edgedefault=\"undirected\">\n    ");
    data(&mut s, "g_seed", |s| push_uint(s, doc.seed));
    data(&mut s, "g_frame", |s| {
        s.extend_from_slice(doc.frame.as_bytes())
    });
    if let Some(start) = doc.start {
        data(&mut s, "g_start", |s| {
            s.push(b'n');
            push_uint(s, start as u64);
        });
    }
    s.push(b'\n');
    for n in &doc.nodes {
        s.extend_from_slice(b"    <node id=\"n");
        push_uint(&mut s, n.id as u64);
        s.extend_from_slice(b"\">");
        data(&mut s, "n_kind", |s| s.extend_from_slice(n.kind.as_bytes()));
        for (key, v) in [("n_level", n.level), ("n_row", n.row), ("n_col", n.col)] {
            data(&mut s, key, |s| push_uint(s, v as u64));
        }
        for (key, v) in ["n_x", "n_y", "n_z"].into_iter().zip(n.position) {
            data(&mut s, key, |s| push_fixed(s, v as f32));
        }
        s.extend_from_slice(b"</node>\n");
    }
    for e in &doc.edges {
        s.extend_from_slice(b"    <edge id=\"e");
        push_uint(&mut s, e.id as u64);
        s.extend_from_slice(b"\" source=\"n");
        push_uint(&mut s, e.from as u64);
        s.extend_from_slice(b"\" target=\"n");
        push_uint(&mut s, e.to as u64);
        s.extend_from_slice(b"\">");
        data(&mut s, "e_id", |s| push_uint(s, e.id as u64));
        data(&mut s, "e_kind", |s| s.extend_from_slice(e.kind.as_bytes()));
        data(&mut s, "e_length", |s| push_fixed(s, e.length_m as f32));
        data(&mut s, "e_weight", |s| push_fixed(s, e.length_m as f32));
        data(&mut s, "e_cells", |s| push_uint(s, e.length_cells as u64));
        for (key, v) in [
            ("e_min_width", e.min_width_m),
            ("e_min_height", e.min_height_m),
        ] {
            if let Some(v) = v {
                data(&mut s, key, |s| push_fixed(s, v as f32));
            }
        }
        // The centreline as JSON text: `json.loads` gives [[x, y, z], ...].
        data(&mut s, "e_polyline", |s| {
            s.push(b'[');
            for (k, p) in e.polyline.iter().enumerate() {
                if k > 0 {
                    s.push(b',');
                }
                s.push(b'[');
                for (d, v) in p.iter().enumerate() {
                    if d > 0 {
                        s.push(b',');
                    }
                    push_fixed(s, *v as f32);
                }
                s.push(b']');
            }
            s.push(b']');
        });
        s.extend_from_slice(b"</edge>\n");
    }
    s.extend_from_slice(b"  </graph>\n</graphml>\n");
    s
}

impl Exporter for GraphFiles {
    fn export(
        &self,
        world: &World,
        survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let doc = document(world, survey);
        crate::write_json(out, "ground_truth/graph.json", &doc)?;
        write_file(out, "ground_truth/graph.graphml", &graphml(&doc))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::export::MemoryWriter;

    #[test]
    fn every_node_and_edge_is_written_once_with_its_centreline() {
        let world = crate::test_world();
        let mut out = MemoryWriter::default();
        GraphFiles
            .export(&world, &crate::survey_of(&world), &mut out)
            .unwrap();
        let doc: serde_json::Value =
            serde_json::from_slice(out.get("ground_truth/graph.json").unwrap()).unwrap();
        assert_eq!(
            doc["nodes"].as_array().unwrap().len(),
            world.graph.nodes.len()
        );
        let edges = doc["edges"].as_array().unwrap();
        assert_eq!(edges.len(), world.graph.edges.len());
        for (e, g) in edges.iter().zip(&world.graph.edges) {
            let line = e["polyline"].as_array().unwrap();
            assert_eq!(line.len(), g.cells.len());
            // Consecutive corridor points are one pitch apart.
            if g.kind == EdgeKind::Corridor {
                let p = |k: usize| -> Vec<f64> {
                    line[k]
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|v| v.as_f64().unwrap())
                        .collect()
                };
                for k in 1..line.len() {
                    let (a, b) = (p(k - 1), p(k));
                    let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
                    assert!((d - world.resolved.tile_pitch).abs() < 1e-9);
                }
            }
        }
        let xml =
            String::from_utf8(out.get("ground_truth/graph.graphml").unwrap().to_vec()).unwrap();
        assert_eq!(xml.matches("<node ").count(), world.graph.nodes.len());
        assert_eq!(xml.matches("<edge ").count(), world.graph.edges.len());
    }
}
