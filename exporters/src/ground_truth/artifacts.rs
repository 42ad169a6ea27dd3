//! `ground_truth/artifacts.json` and `.csv`: every artifact's class, pose, level, tile, graph
//! node or edge and distance from the start along the graph, what `subtgraph score` matches
//! a team's reports against. Written with the world folder whenever the pipeline has
//! `[artifacts]` (whatever the formats), so a world with artifacts always has its answers.

use std::fmt::Write as _;

use serde::Serialize;
use subtgraph_core::World;
use subtgraph_core::export::{ExportError, WorldWriter, write_file};

use super::FRAME;
use crate::artifacts::{Artifact, GraphPlace};

#[derive(Serialize)]
struct Entry<'a> {
    #[serde(flatten)]
    artifact: &'a Artifact,
    quaternion_xyzw: [f64; 4],
    centre: [f64; 3],
    mass_kg: f64,
    colour_rgb: [f32; 3],
}

#[derive(Serialize)]
struct Document<'a> {
    format: &'static str,
    seed: u64,
    frame: &'static str,
    units: &'static str,
    position: &'static str,
    count: usize,
    artifacts: Vec<Entry<'a>>,
}

/// The CSV's header.
pub const CSV_HEADER: &str = "id,name,class,x,y,z,yaw,level,row,col,tile_kind,graph_node,graph_edge,along_m,distance_from_start_m,placement";

/// Writes both files.
pub(crate) fn write(
    world: &World,
    artifacts: &[Artifact],
    out: &mut dyn WorldWriter,
) -> Result<(), ExportError> {
    let doc = Document {
        format: "subtgraph-artifacts/1",
        seed: world.resolved.seed,
        frame: FRAME,
        units: "metres; yaw in radians counter-clockwise from east (x) about z; quaternions x, y, z, w; size is [length along the yaw, width, height]",
        position: "the centre of the artifact's base, on the floor (the collision surface)",
        count: artifacts.len(),
        artifacts: artifacts
            .iter()
            .map(|a| Entry {
                artifact: a,
                quaternion_xyzw: a.quaternion_xyzw(),
                centre: a.centre(),
                mass_kg: a.class.mass(),
                colour_rgb: a.class.colour(),
            })
            .collect(),
    };
    crate::write_json(out, "ground_truth/artifacts.json", &doc)?;
    let mut csv = String::from(CSV_HEADER);
    csv.push('\n');
    for a in artifacts {
        let (node, edge, along) = match a.graph {
            GraphPlace::Node { node } => (node.to_string(), String::new(), String::new()),
            GraphPlace::Edge { edge, along_m } => {
                (String::new(), edge.to_string(), format!("{along_m:.3}"))
            }
        };
        let [x, y, z] = a.position;
        let _ = writeln!(
            csv,
            "{},{},{},{x:.4},{y:.4},{z:.4},{:.6},{},{},{},{},{node},{edge},{along},{:.3},{}",
            a.id,
            a.name,
            a.class.name(),
            a.yaw,
            a.cell.level,
            a.cell.row,
            a.cell.col,
            a.tile_kind.name(),
            a.distance_from_start_m,
            a.placement.name()
        );
    }
    write_file(out, "ground_truth/artifacts.csv", csv.as_bytes())
}
