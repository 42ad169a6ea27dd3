//! `ground_truth/artifacts.json` and `.csv`: every artifact's class, pose, level, tile, graph
//! node or edge and distance from the start along the graph, what `subtgraph score` matches
//! a team's reports against. Written with the world folder whenever the pipeline has
//! `[artifacts]` (whatever the formats), so a world with artifacts always has its answers.
//!
//! Each artifact also says whether it is `visible_from_axis`: whether the straight line from
//! [`EYE`] above the nearest point of its tile's passage axis (`axis.rs`) to the artifact's
//! centre stays in free space (every [`SIGHT_STEP`] along it, the point lies in a free
//! stretch of the collision surface's vertical line; the last [`SIGHT_END`] before the
//! artifact, where it touches a wall or the floor, is not looked at; `sight_from` is the
//! eye). An artifact around a corner or in a side pocket is not. Without a mesh every
//! artifact is visible (from its tile's centre).

use std::fmt::Write as _;

use serde::Serialize;
use subtgraph_core::World;
use subtgraph_core::export::{ExportError, WorldWriter, write_file};

use super::FRAME;
use super::axis::Axes;
use crate::artifacts::{Artifact, GraphPlace};
use crate::inside::Passages;

/// Height of the eye above the passage axis's floor, metres (a robot's sensor).
pub const EYE: f64 = 0.5;
/// Spacing of the points looked at along a line of sight, metres.
pub const SIGHT_STEP: f64 = 0.2;
/// How far from the artifact's centre the line of sight stops being looked at, metres.
pub const SIGHT_END: f64 = 0.3;

/// Whether each artifact is seen from its tile's passage axis (see the module's docs).
fn visible_from_axis(world: &World, artifacts: &[Artifact]) -> Vec<(bool, [f64; 3])> {
    let passages = Passages::of(world);
    if matches!(passages, Passages::Grid(_)) {
        return artifacts
            .iter()
            .map(|a| (true, world.cell_position(a.cell)))
            .collect();
    }
    let mut cells: Vec<_> = artifacts.iter().map(|a| a.cell).collect();
    cells.sort();
    cells.dedup();
    let axes = Axes::of_cells(world, &passages, &cells);
    artifacts
        .iter()
        .map(|a| {
            let target = a.centre();
            let points = axes.tile_points(world, a.cell);
            // The nearest point of the axis's polyline pieces (anchor to each path).
            let mut eye = points[0];
            let mut best = f64::MAX;
            for w in points.windows(2) {
                let q = nearest_on_segment(target, w[0], w[1]);
                let d = dist2(q, target);
                if d < best {
                    (best, eye) = (d, q);
                }
            }
            if points.len() == 1 {
                eye = points[0];
            }
            let eye = [eye[0], eye[1], eye[2] + EYE];
            let len = dist2(eye, target).sqrt();
            let n = ((len - SIGHT_END).max(0.0) / SIGHT_STEP).floor() as usize;
            let samples: Vec<[f64; 3]> = (0..=n)
                .map(|k| {
                    let t = (k as f64 * SIGHT_STEP / len.max(1e-9)).min(1.0);
                    [
                        eye[0] + (target[0] - eye[0]) * t,
                        eye[1] + (target[1] - eye[1]) * t,
                        eye[2] + (target[2] - eye[2]) * t,
                    ]
                })
                .collect();
            let xy: Vec<[f64; 2]> = samples.iter().map(|p| [p[0], p[1]]).collect();
            let columns = passages.columns_at(&xy);
            let seen = samples
                .iter()
                .zip(&columns)
                .all(|(p, spans)| spans.iter().any(|s| s[0] <= p[2] && p[2] <= s[1]));
            (seen, eye)
        })
        .collect()
}

fn dist2(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).powi(2)).sum()
}

fn nearest_on_segment(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let l2 = ab.iter().map(|v| v * v).sum::<f64>();
    let t = if l2 > 0.0 {
        (((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1] + (p[2] - a[2]) * ab[2]) / l2)
            .clamp(0.0, 1.0)
    } else {
        0.0
    };
    [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]]
}

#[derive(Serialize)]
struct Entry<'a> {
    #[serde(flatten)]
    artifact: &'a Artifact,
    quaternion_xyzw: [f64; 4],
    centre: [f64; 3],
    mass_kg: f64,
    colour_rgb: [f32; 3],
    visible_from_axis: bool,
    /// The eye the line of sight starts from.
    sight_from: [f64; 3],
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
pub const CSV_HEADER: &str = "id,name,class,x,y,z,yaw,level,row,col,tile_kind,graph_node,graph_edge,along_m,distance_from_start_m,placement,visible_from_axis";

/// Writes both files.
pub(crate) fn write(
    world: &World,
    artifacts: &[Artifact],
    out: &mut dyn WorldWriter,
) -> Result<(), ExportError> {
    let visible = visible_from_axis(world, artifacts);
    let doc = Document {
        format: "subtgraph-artifacts/1",
        seed: world.resolved.seed,
        frame: FRAME,
        units: "metres; yaw in radians counter-clockwise from east (x) about z; quaternions x, y, z, w; size is [length along the yaw, width, height]",
        position: "the centre of the artifact's base, on the floor (the collision surface)",
        count: artifacts.len(),
        artifacts: artifacts
            .iter()
            .zip(&visible)
            .map(|(a, &(visible_from_axis, sight_from))| Entry {
                artifact: a,
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
