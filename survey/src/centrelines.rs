//! Every graph edge's centreline: a corridor's along the middle of its passage through every
//! tile (anchor, path to the opening, the next tile's path from its opening, its anchor, ...;
//! see [`crate::axis`]), a shaft's from its foot's node to its landing's, a ramp's along its
//! spiral's floor (the tile set's own line, `WorldMesh::ramps`). Without a mesh, through the
//! cell centres.

use subtgraph_core::World;
use subtgraph_core::graph::{Edge, EdgeKind};
use subtgraph_core::survey::EdgeLine;

use crate::axis::{Axes, ramp_line};

/// The centreline of every edge of `world`'s graph, in edge order.
pub(crate) fn edges(world: &World, axes: &Axes) -> Vec<EdgeLine> {
    world
        .graph
        .edges
        .iter()
        .map(|e| {
            ramp(world, axes, e).unwrap_or_else(|| EdgeLine {
                points: axes.polyline(&e.cells),
                length_m: e.length_m,
            })
        })
        .collect()
}

/// A ramp's line (its foot's node, the spiral's floor, its landing's node) and the length
/// driven along it, for a ramp edge of a world with a mesh.
fn ramp(world: &World, axes: &Axes, e: &Edge) -> Option<EdgeLine> {
    if e.kind != EdgeKind::Ramp {
        return None;
    }
    let line = ramp_line(world, &e.cells)?;
    let mut p = vec![axes.position(e.cells[0])];
    p.extend_from_slice(line);
    p.push(axes.position(e.cells[e.cells.len() - 1]));
    p.dedup();
    let length_m = p
        .windows(2)
        .map(|w| {
            ((w[1][0] - w[0][0]).powi(2)
                + (w[1][1] - w[0][1]).powi(2)
                + (w[1][2] - w[0][2]).powi(2))
            .sqrt()
        })
        .sum();
    Some(EdgeLine {
        points: p,
        length_m,
    })
}
