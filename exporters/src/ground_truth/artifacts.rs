//! `ground_truth/artifacts.json` and `.csv`: every artifact's class, pose, level, tile, graph
//! node or edge and distance from the start along the graph, what `subtgraph score` matches
//! a team's reports against. Written with the world folder whenever the pipeline has
//! `[artifacts]` (whatever the formats), so a world with artifacts always has its answers.
//!
//! Each artifact also says whether it is `visible_from_axis`: whether the straight line from
//! half a metre above the nearest point of its tile's passage axis to the artifact's centre
//! stays in free space, as the survey looks (`survey/src/sight.rs`, the computation placement
//! uses to hide some on purpose; `sight_from` is the eye). With `[artifacts] hidden` the eye
//! is instead where a robot on its way from the start first comes within 10 m of the
//! artifact. An artifact around a corner or in a side pocket is not visible. Without a mesh
//! every artifact is visible (from its tile's centre).

use std::fmt::Write as _;

use std::borrow::Cow;

use subtgraph_core::World;
use subtgraph_core::export::{ExportError, WorldWriter, write_file};

use subtgraph_core::artifacts::{GraphPlace, PlacedArtifacts};

use super::FRAME;

type Entry<'a> = subtgraph_schema::ArtifactEntry<'a>;
type Document<'a> = subtgraph_schema::Artifacts<'a, &'static str>;
use subtgraph_schema::Hidden;

/// The CSV's header.
pub const CSV_HEADER: &str = "id,name,class,x,y,z,yaw,level,row,col,tile_kind,graph_node,graph_edge,along_m,distance_from_start_m,placement,visible_from_axis";

/// Writes both files.
pub(crate) fn write(
    world: &World,
    placed: &PlacedArtifacts,
    out: &mut dyn WorldWriter,
) -> Result<(), ExportError> {
    let artifacts = &placed.artifacts;
    let visible: Vec<(bool, [f64; 3])> = artifacts
        .iter()
        .map(|a| (a.visible_from_axis, a.sight_from))
        .collect();
    let doc = Document {
        format: "subtgraph-artifacts/1",
        seed: world.resolved.seed,
        frame: FRAME,
        units: "metres; yaw in radians counter-clockwise from east (x) about z; quaternions x, y, z, w; size is [length along the yaw, width, height]",
        position: "the centre of the artifact's base, on the floor (the collision surface)",
        count: artifacts.len(),
        hidden: placed.hidden.map(|asked| {
            let placed = visible.iter().filter(|v| !v.0).count();
            Hidden {
                share_requested: asked.share,
                requested: asked.count,
                placed,
                share_placed: placed as f64 / artifacts.len().max(1) as f64,
            }
        }),
        artifacts: artifacts
            .iter()
            .zip(&visible)
            .map(|(a, &(visible_from_axis, sight_from))| Entry {
                id: a.id,
                name: Cow::Borrowed(&a.name),
                class: a.class,
                position: a.position,
                yaw: a.yaw,
                size: a.size,
                cell: a.cell,
                tile_kind: a.tile_kind,
                placement: a.placement,
                graph: match a.graph {
                    GraphPlace::Node { node } => subtgraph_schema::GraphPlace::Node { node },
                    GraphPlace::Edge { edge, along_m } => {
                        subtgraph_schema::GraphPlace::Edge { edge, along_m }
                    }
                },
                distance_from_start_m: a.distance_from_start_m,
                quaternion_xyzw: a.quaternion_xyzw(),
                centre: a.centre(),
                mass_kg: a.class.mass(),
                colour_rgb: a.class.colour(),
                visible_from_axis,
                sight_from,
            })
            .collect(),
    };
    crate::write_json(out, "ground_truth/artifacts.json", &doc)?;
    let mut csv = String::from(CSV_HEADER);
    csv.push('\n');
    for (a, &(seen, _)) in artifacts.iter().zip(&visible) {
        let (node, edge, along) = match a.graph {
            GraphPlace::Node { node } => (node.to_string(), String::new(), String::new()),
            GraphPlace::Edge { edge, along_m } => {
                (String::new(), edge.to_string(), format!("{along_m:.3}"))
            }
        };
        let [x, y, z] = a.position;
        let _ = writeln!(
            csv,
            "{},{},{},{x:.4},{y:.4},{z:.4},{:.6},{},{},{},{},{node},{edge},{along},{:.3},{},{}",
            a.id,
            a.name,
            a.class.name(),
            a.yaw,
            a.cell.level,
            a.cell.row,
            a.cell.col,
            a.tile_kind.name(),
            a.distance_from_start_m,
            a.placement.name(),
            u8::from(seen)
        );
    }
    write_file(out, "ground_truth/artifacts.csv", csv.as_bytes())
}
