//! Where a path built tile by tile jumps across a seam (the tiles either side chose different
//! lines of a wide mouth) or detours, the way is found again: rerouted over a raster of the
//! box around the jump, or cut short by a drivable straight bridge.

use subtgraph_core::World;

use super::{columns, drivable};
use crate::axis::Line;
use crate::passages::Passages;

/// Farthest (metres) two consecutive lines of a path may be apart: where the tiles either side
/// of a seam chose different lines of it (a wide mouth), the way across is found again.
const JUMP: f64 = 1.5;
/// How many lines before a jump, and after the line past it nearest where it starts, the way
/// found again replaces (about 6 m).
const REROUTE_LINES: usize = 15;
/// How far around the lines it joins a way found again may go, metres.
const REROUTE_MARGIN: f64 = 8.0;

/// `lines` with every jump (two consecutive lines more than [`JUMP`] apart) replaced by the
/// way found across it by the same clearance-weighted search as a tile's axis
/// ([`crate::axis`]), over the lines of a box around it: from [`REROUTE_LINES`] before the
/// jump to as many after the line past it nearest where it starts.
pub(super) fn rerouted(world: &World, passages: &Passages, lines: Vec<Line>) -> Vec<Line> {
    let n = lines.len();
    let dist = |a: &Line, b: &Line| (a.point[0] - b.point[0]).hypot(a.point[1] - b.point[1]);
    let mut out: Vec<Line> = Vec::with_capacity(n);
    let mut k = 0;
    while k < n {
        out.push(lines[k]);
        if k + 1 < n && dist(&lines[k], &lines[k + 1]) > JUMP {
            let a = out.len().saturating_sub(REROUTE_LINES + 1);
            let near = (k + 1..n.min(k + 1 + 10 * REROUTE_LINES))
                .min_by(|&i, &j| dist(&lines[i], &lines[k]).total_cmp(&dist(&lines[j], &lines[k])))
                .unwrap_or(k + 1);
            let b = (near + REROUTE_LINES).min(n - 1);
            if let Some(way) = way_between(world, passages, out[a], lines[b]) {
                out.truncate(a + 1);
                out.extend(way);
                // Line b is pushed next, and checked for a jump in its turn.
                k = b;
                continue;
            }
        }
        k += 1;
    }
    out
}

/// The lines of the clearance-weighted way from `a` to `b` (both excluded) over a raster of
/// the box around them, [`REROUTE_MARGIN`] wider, at the tiles' line spacing; `None` when
/// `b` is not reached.
fn way_between(world: &World, passages: &Passages, a: Line, b: Line) -> Option<Vec<Line>> {
    use crate::axis::tile::{clearance, floors_in, lines_per_side, paths, roomy};
    let pitch = world.resolved.tile_pitch;
    let per_side = lines_per_side(pitch);
    let step = pitch / per_side as f64;
    let (p, q) = (a.point, b.point);
    let lo = [
        p[0].min(q[0]) - REROUTE_MARGIN,
        p[1].min(q[1]) - REROUTE_MARGIN,
    ];
    let hi = [
        p[0].max(q[0]) + REROUTE_MARGIN,
        p[1].max(q[1]) + REROUTE_MARGIN,
    ];
    let cols = subtgraph_core::survey::Columns {
        x0: lo[0],
        y0: lo[1],
        step,
        nx: ((hi[0] - lo[0]) / step).ceil() as usize,
        ny: ((hi[1] - lo[1]) / step).ceil() as usize,
    };
    let (nx, ny) = (cols.nx, cols.ny);
    let bounds = [
        lo[0],
        lo[1],
        lo[0] + nx as f64 * step,
        lo[1] + ny as f64 * step,
    ];
    let band = [p[2].min(q[2]), p[2].max(q[2])];
    let floor = floors_in(
        passages,
        &cols,
        bounds,
        band,
        0.45 * world.resolved.level_height,
    );
    let free: Vec<bool> = floor.iter().map(|f| !f.is_nan()).collect();
    let clear = clearance(&roomy(&free, &floor, (nx, ny), step), nx, ny);
    let nearest = |x: [f64; 3]| {
        (0..nx * ny).filter(|&k| free[k]).min_by(|&i, &j| {
            let d = |k: usize| (cols.x(k % nx) - x[0]).hypot(cols.y(k / nx) - x[1]);
            d(i).total_cmp(&d(j))
        })
    };
    let (source, target) = (nearest(p)?, nearest(q)?);
    let (cost, parent) = paths(&free, &floor, &clear, step, (nx, ny), per_side, source);
    if cost[target] == u64::MAX {
        return None;
    }
    let mut way = Vec::new();
    let mut k = target;
    while k != source {
        k = parent[k] as usize;
        if k != source {
            way.push(Line {
                point: [cols.x(k % nx), cols.y(k / nx), floor[k]],
                room: (f64::from(clear[k]) / 3.0 * step).min(0.5 * pitch),
            });
        }
    }
    way.reverse();
    Some(way)
}

/// How many lines ahead a shortcut may reach (about 32 m of path).
const SHORTCUT_LINES: usize = 80;
/// A stretch of path is a detour worth cutting when it is this many times as long as the
/// straight line between its ends, plus [`DETOUR_SLACK`]: more than any zigzag of the raster
/// (at most 1.08) or any bend of a passage (a quarter turn: 1.11).
const DETOUR: f64 = 1.25;
/// See [`DETOUR`], metres.
const DETOUR_SLACK: f64 = 1.0;
/// Shortcuts tried from one line, longest first.
const SHORTCUT_TRIES: usize = 16;

/// `lines` with their detours cut: where the path from a line to one up to
/// [`SHORTCUT_LINES`] ahead is much longer than the straight line between them ([`DETOUR`]),
/// the longest such straight that is a drivable [`bridge`] replaces it. Detours are what the
/// tile-by-tile path leaves at a seam where the tiles either side chose different lines of it
/// (a wide mouth: 21 m apart on the DARPA cave), not bends of the passage.
pub(super) fn shortcuts(passages: &Passages, lines: Vec<Line>) -> Vec<Line> {
    let n = lines.len();
    let mut along = vec![0.0; n];
    for i in 1..n {
        let (a, b) = (lines[i - 1].point, lines[i].point);
        along[i] = along[i - 1] + (a[0] - b[0]).hypot(a[1] - b[1]);
    }
    let mut out: Vec<Line> = Vec::with_capacity(n);
    let mut i = 0;
    while i < n {
        out.push(lines[i]);
        let p = lines[i].point;
        let detours: Vec<usize> = (i + 2..n.min(i + SHORTCUT_LINES + 1))
            .rev()
            .filter(|&j| {
                let q = lines[j].point;
                along[j] - along[i] > DETOUR * (p[0] - q[0]).hypot(p[1] - q[1]) + DETOUR_SLACK
            })
            .take(SHORTCUT_TRIES)
            .collect();
        match detours
            .into_iter()
            .find_map(|j| Some((j, bridge(passages, lines[i], lines[j])?)))
        {
            Some((j, mut b)) => {
                // The bridge ends on line j, which the next step pushes.
                b.pop();
                out.extend(b);
                i = j;
            }
            None => i += 1,
        }
    }
    out
}

/// How far to either side of a bridge its lines are tried for room, metres, widest first.
const BRIDGE_ROOMS: [f64; 6] = [4.0, 3.0, 2.0, 1.5, 1.0, 0.5];

/// The lines strictly between `a` and `b` on the straight bridge joining them, 0.4 m or less
/// apart, each on its floor, with `b` last; `None` when a point of it is not [`drivable`]
/// near the height between `a`'s and `b`'s floors, or two neighbours' floors differ by more
/// than a step a robot drives (a quarter metre). Each line's room is the widest of
/// [`BRIDGE_ROOMS`] with drivable floor that far to either side of it, and half as far (none:
/// 0).
fn bridge(passages: &Passages, a: Line, b: Line) -> Option<Vec<Line>> {
    let (p, q) = (a.point, b.point);
    let len = (q[0] - p[0]).hypot(q[1] - p[1]);
    let n = ((len / 0.4).ceil() as usize).max(1);
    let dir = [(q[0] - p[0]) / len.max(1e-9), (q[1] - p[1]) / len.max(1e-9)];
    let centres: Vec<[f64; 2]> = (1..n)
        .map(|k| {
            let t = k as f64 / n as f64;
            [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]
        })
        .collect();
    let height = |k: usize| p[2] + (k + 1) as f64 / n as f64 * (q[2] - p[2]);
    let mut out = Vec::with_capacity(n);
    let mut last = p[2];
    for (k, column) in columns(passages, &centres, 1).iter().enumerate() {
        let floor = drivable(column, height(k))?;
        if (floor - last).abs() > 0.25 {
            return None;
        }
        last = floor;
        out.push(Line {
            point: [centres[k][0], centres[k][1], floor],
            room: 0.0,
        });
    }
    if (q[2] - last).abs() > 0.25 {
        return None;
    }
    // Each line's room: the widest of BRIDGE_ROOMS with drivable floor that far to either
    // side, and half as far.
    let probes: Vec<[f64; 2]> = centres
        .iter()
        .flat_map(|c| {
            BRIDGE_ROOMS.into_iter().flat_map(move |r| {
                [1.0, -1.0, 0.5, -0.5].map(|f| [c[0] - dir[1] * r * f, c[1] + dir[0] * r * f])
            })
        })
        .collect();
    let columns = columns(passages, &probes, 4 * BRIDGE_ROOMS.len());
    let per = 4 * BRIDGE_ROOMS.len();
    for (k, l) in out.iter_mut().enumerate() {
        l.room = BRIDGE_ROOMS
            .iter()
            .enumerate()
            .find(|&(m, _)| {
                (0..4).all(|f| drivable(&columns[k * per + 4 * m + f], l.point[2]).is_some())
            })
            .map_or(0.0, |(_, &r)| r);
    }
    out.push(b);
    Some(out)
}
