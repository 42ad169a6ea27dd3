//! A corridor along its tile set's own passage axis (`tilesets/src/axis.rs`), each point on
//! the collision surface's floor.

use std::collections::BTreeSet;

use subtgraph_core::World;
use subtgraph_core::grid::Cell;

use super::{BAND, columns, floor_near};
use crate::axis::{Axes, towards};
use crate::passages::Passages;

/// The corridor through `cells` along its tile set's axes (see the module's doc), from the
/// first cell's node to the last's; `None` when a tile has no axis, holds a rubble field or a
/// drop, or a point finds no floor near where the tile set laid it.
pub(super) fn tile_set_line(
    world: &World,
    passages: &Passages,
    axes: &Axes,
    cells: &[Cell],
    hazards: &BTreeSet<Cell>,
) -> Option<Vec<[f64; 3]>> {
    let mesh = world.mesh()?;
    if cells.len() < 2 || cells.iter().any(|c| hazards.contains(c)) {
        return None;
    }
    let axis = |c: Cell| mesh.tile(c)?.axis.as_ref();
    let exit = |c: Cell, to: Cell| -> Option<&Vec<[f64; 3]>> {
        let path = &axis(c)?.exits[towards(c, to)? as usize];
        (!path.is_empty()).then_some(path)
    };
    let (first, last) = (cells[0], cells[cells.len() - 1]);
    let mut nominal: Vec<[f64; 3]> = Vec::new();
    let push = |p: [f64; 3], out: &mut Vec<[f64; 3]>| {
        if out
            .last()
            .is_none_or(|q| (q[0] - p[0]).abs() + (q[1] - p[1]).abs() > 1e-6)
        {
            out.push(p);
        }
    };
    // From the first node's anchor onto its tile's path, past the anchor.
    for &p in beyond(
        axes.anchor(first),
        axis(first)?.node,
        exit(first, cells[1])?,
    ) {
        push(p, &mut nominal);
    }
    for (k, &c) in cells.iter().enumerate().take(cells.len() - 1).skip(1) {
        for &p in exit(c, cells[k - 1])?.iter().rev() {
            push(p, &mut nominal);
        }
        push(axis(c)?.node, &mut nominal);
        for &p in exit(c, cells[k + 1])? {
            push(p, &mut nominal);
        }
    }
    let end = beyond(
        axes.anchor(last),
        axis(last)?.node,
        exit(last, cells[cells.len() - 2])?,
    );
    for &p in end.iter().rev() {
        push(p, &mut nominal);
    }
    // Every point on the collision surface's floor nearest where the tile set laid it.
    let xy: Vec<[f64; 2]> = nominal.iter().map(|p| [p[0], p[1]]).collect();
    let mut out = vec![axes.position(first)];
    for (column, p) in columns(passages, &xy, 1).into_iter().zip(&nominal) {
        let floor = floor_near(&column, p[2], BAND)?;
        out.push([p[0], p[1], floor]);
    }
    out.push(axes.position(last));
    Some(out)
}

/// The points of a node tile's `path` (from its `node`, excluded, outward) beyond where the
/// tile's `anchor` projects onto it (the node's position may stand off the tile set's node:
/// a dead end's half way along its passage), so the line leaves the anchor forward.
fn beyond(anchor: [f64; 3], node: [f64; 3], path: &[[f64; 3]]) -> &[[f64; 3]] {
    let mut best = (f64::INFINITY, 0.0);
    let mut along = 0.0;
    let mut prev = node;
    for &p in path {
        let (a, b) = ([prev[0], prev[1]], [p[0], p[1]]);
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        let t = if len > 0.0 {
            (((anchor[0] - a[0]) * (b[0] - a[0]) + (anchor[1] - a[1]) * (b[1] - a[1]))
                / (len * len))
                .clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
        let d = (q[0] - anchor[0]).hypot(q[1] - anchor[1]);
        if d < best.0 {
            best = (d, along + t * len);
        }
        along += len;
        prev = p;
    }
    // Half a metre past the projection, so the first step is not backwards.
    let mut along = 0.0;
    let mut prev = node;
    let start = path
        .iter()
        .position(|&p| {
            along += (p[0] - prev[0]).hypot(p[1] - prev[1]);
            prev = p;
            along > best.1 + 0.5
        })
        .unwrap_or(path.len() - 1);
    &path[start..]
}
