//! Every graph edge's centreline, what the ground truth's `graph.json` writes and robots follow
//! as waypoints: smooth (at most 20 degrees of turn per metre away from the nodes), on the
//! floor and inside the free space.
//!
//! - A corridor through tiles whose tile set laid their passage along an axis of its own (the
//!   procedural sets: a corner's arc, a straight's meander, square corners rounded; see
//!   `tilesets/src/axis.rs`) follows that axis, from the node where the edge starts to the one
//!   where it ends, every point's height found on the collision surface's floor. This is the
//!   passage's own centreline, not a path found again in the mesh.
//! - Elsewhere (mesh tiles such as the DARPA manifest's, and a corridor whose tile-set axis
//!   crosses a rubble field or a drop, or finds no floor under a point), the passage axis found
//!   in the free space ([`crate::axis`]: a clearance-weighted path over a raster of lines
//!   0.4 m apart, which zigzags from line to line) is smoothed: every line of the path may
//!   move within its *room* (its distance to the nearest line a body cannot stand on, less
//!   [`MARGIN`]), and a few hundred passes of a [1 2 1] filter, each followed by moving every
//!   point back into its room, leave a smooth path that never leaves the drivable floor.
//!   Points a metre apart are then kept, each on the floor found by an exact vertical cast.
//! - A shaft runs from its foot's node to its landing's, a ramp along its spiral's floor (the
//!   tile set's own line, `WorldMesh::ramps`). Without a mesh, corridors run through the cell
//!   centres.
//!
//! Node positions are the tiles' anchors ([`crate::axis`]), whichever way the line between
//! them was found. Each edge alone, in parallel, collected in order: deterministic.

mod detours;
mod smooth;
mod tile_set;

use std::collections::BTreeSet;

use rayon::prelude::*;
use subtgraph_core::World;
use subtgraph_core::graph::{Edge, EdgeKind};
use subtgraph_core::grid::Cell;
use subtgraph_core::survey::EdgeLine;

use crate::axis::{Axes, ramp_line};
use crate::passages::Passages;
use smooth::smoothed;
use tile_set::tile_set_line;

/// How far inside its room (metres) a smoothed point stays from the nearest undrivable line.
pub const MARGIN: f64 = 0.25;
/// Passes of the smoothing filter: about a Gaussian of 4 m on lines 0.4 m apart.
pub(crate) const PASSES: usize = 200;
/// Spacing of the points written, metres (a path's curves are followed this closely).
pub(crate) const SPACING: f64 = 1.0;
/// Least free height over a centreline point's floor, metres.
const HEADROOM: f64 = 0.6;
/// How far below and above its tile set's nominal floor a point's floor may be found, metres
/// (the collision surface is a coarser lattice than the passage it approximates).
pub(crate) const BAND: [f64; 2] = [2.0, 1.5];

/// Points of a path cast together: [`Passages::columns_at`] tests every point against the
/// triangles near all of them, so a few metres of path at a time keep that set small.
const CAST_RUN: usize = 4;

/// The free stretches over each of `points`, in order, cast [`CAST_RUN`] groups of `per`
/// neighbouring points at a time (a group: a point and its side probes).
pub(crate) fn columns(passages: &Passages, points: &[[f64; 2]], per: usize) -> Vec<Vec<[f64; 2]>> {
    points
        .chunks(CAST_RUN * per.max(1))
        .flat_map(|run| passages.columns_at(run))
        .collect()
}

/// The centreline of every edge of `world`'s graph, in edge order.
pub(crate) fn edges(world: &World, passages: &Passages, axes: &Axes) -> Vec<EdgeLine> {
    let hazards: BTreeSet<Cell> = world
        .mesh()
        .map(|m| m.hazards.iter().map(|h| h.cell).collect())
        .unwrap_or_default();
    world
        .graph
        .edges
        .par_iter()
        .map(|e| {
            if let Some(line) = ramp(world, axes, e) {
                return line;
            }
            let points = match e.kind {
                EdgeKind::Corridor if world.mesh().is_some() => {
                    tile_set_line(world, passages, axes, &e.cells, &hazards)
                        .unwrap_or_else(|| smoothed(passages, axes, world, &e.cells))
                }
                _ => axes.polyline(&e.cells),
            };
            EdgeLine {
                points,
                length_m: e.length_m,
            }
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

/// The floor of the free stretch (at least [`HEADROOM`] high) nearest `z`, if one lies
/// within `band` (below, above) of it.
pub(crate) fn floor_near(column: &[[f64; 2]], z: f64, band: [f64; 2]) -> Option<f64> {
    column
        .iter()
        .filter(|s| s[1] - s[0] >= HEADROOM && s[0] >= z - band[0] && s[0] <= z + band[1])
        .map(|s| s[0])
        .min_by(|a, b| (a - z).abs().total_cmp(&(b - z).abs()))
}

/// The floor of a free stretch of `column` a body stands in (at least a metre high) within a
/// metre of `z`, if there is one.
pub(crate) fn drivable(column: &[[f64; 2]], z: f64) -> Option<f64> {
    column
        .iter()
        .filter(|s| s[1] - s[0] >= 1.0 && (s[0] - z).abs() <= 1.0)
        .map(|s| s[0])
        .min_by(|a, b| (a - z).abs().total_cmp(&(b - z).abs()))
}

/// Points `spacing` apart (and the last) along the polyline `s`, each with its fractional
/// index into `s` (the segment it lies on and how far along).
pub(crate) fn resample(s: &[[f64; 2]], spacing: f64) -> Vec<([f64; 2], f64)> {
    let mut out = vec![(s[0], 0.0)];
    let mut left = spacing;
    for i in 0..s.len() - 1 {
        let (a, b) = (s[i], s[i + 1]);
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        let mut at = 0.0;
        while len - at >= left {
            at += left;
            let t = at / len;
            out.push((
                [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])],
                i as f64 + t,
            ));
            left = spacing;
        }
        left -= len - at;
    }
    let last = s.len() - 1;
    if out.last().is_none_or(|p| p.1 < last as f64 - 1e-9) {
        out.push((s[last], last as f64));
    }
    out
}
