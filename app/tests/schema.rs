//! Every JSON file of a world folder reads back through its schema type (`subtgraph-schema`)
//! and, written again, gives the same bytes: the readers (`score`, `stats`, `preview`, the
//! dataset index) see every field the writers write, in the writers' own types. On a cave with
//! artifacts, floor hazards and rubble, and the whole ground truth.

use subtgraph_core::export::MemoryWriter;
use subtgraph_schema::{
    Artifacts, CollisionBudget, Document, FreeSpace, Graph, Hazards, SemanticLabels, SpawnPoses,
    Topology,
};

fn world_files() -> MemoryWriter {
    let mut text = subtgraph_app::presets::text("cave").unwrap().to_owned();
    text.push_str(
        "\n[artifacts]\ncount = 6\n\n[hazards]\nfriction = { mud = 0.2, ice = 0.1 }\nrubble = 0.2\n",
    );
    let mut p = subtgraph_core::Pipeline::parse(&text, "cave+").unwrap();
    p.world.seed = 3;
    subtgraph_app::pipeline::add_formats(&mut p, &["ground-truth".into()]).unwrap();
    let registry = subtgraph_app::registry();
    let components = p.build(&registry).unwrap();
    let world =
        subtgraph_core::generate_with(&p, &components, &subtgraph_core::Budget::unlimited())
            .unwrap();
    let mut out = MemoryWriter::default();
    let survey = subtgraph_survey::WorldSurvey::new(&world).unwrap();
    subtgraph_exporters::write_world_files(&world, &survey, &mut out, false).unwrap();
    for e in &components.exporters {
        e.exporter.export(&world, &survey, &mut out).unwrap();
    }
    out
}

/// Reads `D`'s file, checks it, writes it again as the exporters write JSON, and compares.
fn round_trip<D: Document + serde::Serialize>(files: &MemoryWriter) -> D {
    let bytes = files
        .get(D::PATH)
        .unwrap_or_else(|| panic!("{} was written", D::PATH));
    let doc: D = subtgraph_schema::read(bytes).unwrap_or_else(|e| panic!("{e}"));
    let mut again = serde_json::to_string_pretty(&doc).unwrap();
    again.push('\n');
    if again.as_bytes() != bytes {
        let was = String::from_utf8_lossy(bytes);
        let line = was
            .lines()
            .zip(again.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(0);
        panic!(
            "{} differs when read and written again, from line {}: {:?} became {:?}",
            D::PATH,
            line + 1,
            was.lines().nth(line),
            again.lines().nth(line)
        );
    }
    doc
}

#[test]
fn every_json_file_of_a_world_reads_back_whole_through_its_schema_type() {
    let files = world_files();
    let t: Topology = round_trip(&files);
    assert!(!t.nodes.is_empty() && !t.edges.is_empty());
    let a: Artifacts = round_trip(&files);
    assert_eq!(a.artifacts.len(), 6);
    let h: Hazards = round_trip(&files);
    assert!(!h.patches.is_empty(), "the friction patches are listed");
    assert!(!h.regions.is_empty(), "the rubble fields are listed");
    let g: Graph = round_trip(&files);
    assert_eq!(g.nodes.len(), t.nodes.len());
    let s: SemanticLabels = round_trip(&files);
    assert_eq!(s.tiles.len(), t.occupied_cells);
    round_trip::<SpawnPoses>(&files);
    let f: FreeSpace = round_trip(&files);
    assert!(f.free_voxels > 0);
    let b: CollisionBudget = round_trip(&files);
    assert!(b.classes.floor_by_routes.count > 0 && b.classes.walls.count > 0);
}

#[test]
fn a_file_edited_out_of_range_is_refused_naming_the_entry() {
    let files = world_files();
    let text = std::str::from_utf8(files.get("topology.json").unwrap()).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(text).unwrap();
    let n = doc["nodes"].as_array().unwrap().len();
    doc["edges"][0]["to"] = n.into();
    let e = subtgraph_schema::read::<Topology>(doc.to_string().as_bytes())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("edge 0 joins nodes") && e.contains(&format!("{n} nodes")),
        "{e}"
    );
    let mut other = serde_json::from_str::<serde_json::Value>(text).unwrap();
    other["format"] = "subtgraph-topology/9".into();
    let e = subtgraph_schema::read::<Topology>(other.to_string().as_bytes())
        .unwrap_err()
        .to_string();
    assert!(e.contains("subtgraph-topology/9"), "{e}");
}
