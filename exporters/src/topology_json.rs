//! `topology.json`: the topological graph in the world frame (metres, x east, y north, z up),
//! with the requested, expected and achieved counts of every level.

use std::borrow::Cow;

use subtgraph_core::World;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter};
use subtgraph_core::survey::Survey;
use subtgraph_schema::{Document as _, Topology};

/// Writes `topology.json`.
#[derive(Clone, Copy, Debug, Default)]
pub struct TopologyJson;

impl Exporter for TopologyJson {
    fn export(
        &self,
        world: &World,
        _survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let occupied = world.occupancy.occupied_count();
        let reachable = world.reachable_from_start();
        let start = world
            .start
            .and_then(|s| world.graph.nodes.iter().find(|n| n.cell == s).map(|n| n.id));
        let doc = Topology {
            format: Topology::FORMAT,
            frame: Topology::<&str>::FRAME,
            seed: world.resolved.seed,
            levels: world.resolved.levels,
            rows: world.resolved.rows,
            cols: world.resolved.cols,
            tile_pitch_m: world.resolved.tile_pitch,
            level_height_m: world.resolved.level_height,
            occupied_cells: occupied,
            total_length_m: world.graph.edges.iter().map(|e| e.length_m).sum(),
            reachable_cells: reachable,
            connected: occupied == reachable,
            start,
            per_level: Cow::Borrowed(&world.levels),
            shafts: Cow::Borrowed(&world.shafts),
            nodes: Cow::Borrowed(&world.graph.nodes),
            edges: Cow::Borrowed(&world.graph.edges),
        };
        crate::write_json(out, Topology::PATH, &doc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::export::MemoryWriter;

    #[test]
    fn the_graph_and_counts_read_back() {
        let world = crate::test_world();
        let mut out = MemoryWriter::default();
        TopologyJson
            .export(&world, &crate::survey_of(&world), &mut out)
            .unwrap();
        let doc: serde_json::Value =
            serde_json::from_slice(out.get("topology.json").unwrap()).unwrap();
        assert_eq!(
            doc["nodes"].as_array().unwrap().len(),
            world.graph.nodes.len()
        );
        assert_eq!(
            doc["edges"].as_array().unwrap().len(),
            world.graph.edges.len()
        );
        assert_eq!(doc["connected"], true);
        assert_eq!(
            doc["per_level"][1]["achieved"]["t_junctions"],
            world.levels[1].achieved.t_junctions
        );
        let shafts = doc["edges"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|e| e["kind"] == "shaft" || e["kind"] == "ramp")
            .count();
        assert_eq!(shafts, world.shafts.len());
    }
}
