//! A corridor along the passage axis found in the free space ([`crate::axis`]), smoothed
//! within the room of its lines and relaxed where it still bends sharply.

use subtgraph_core::World;
use subtgraph_core::grid::Cell;

use super::detours::{rerouted, shortcuts};
use super::{MARGIN, PASSES, SPACING, columns, drivable, floor_near, resample};
use crate::axis::{Axes, Line, towards};
use crate::passages::Passages;

/// The corridor through `cells` along the passage axis found in the free space, smoothed
/// within the room of its lines (see the module's doc).
pub(super) fn smoothed(
    passages: &Passages,
    axes: &Axes,
    world: &World,
    cells: &[Cell],
) -> Vec<[f64; 3]> {
    let lines = shortcuts(
        passages,
        rerouted(
            world,
            passages,
            without_loops(axis_lines(axes, world, cells)),
        ),
    );
    if lines.len() < 3 {
        return lines.iter().map(|l| l.point).collect();
    }
    let n = lines.len();
    // How far each line may move: none for the two nodes.
    let room: Vec<f64> = lines
        .iter()
        .enumerate()
        .map(|(i, l)| {
            if i == 0 || i == n - 1 {
                0.0
            } else {
                (l.room - MARGIN).max(0.0)
            }
        })
        .collect();
    let mut s: Vec<[f64; 2]> = lines.iter().map(|l| [l.point[0], l.point[1]]).collect();
    let mut next = s.clone();
    for _ in 0..PASSES {
        for i in 1..n - 1 {
            let q = lines[i].point;
            let f = [
                0.25 * (s[i - 1][0] + 2.0 * s[i][0] + s[i + 1][0]),
                0.25 * (s[i - 1][1] + 2.0 * s[i][1] + s[i + 1][1]),
            ];
            let (dx, dy) = (f[0] - q[0], f[1] - q[1]);
            let d = dx.hypot(dy);
            next[i] = if d > room[i] {
                let k = room[i] / d;
                [q[0] + dx * k, q[1] + dy * k]
            } else {
                f
            };
        }
        std::mem::swap(&mut s, &mut next);
        next[0] = s[0];
        next[n - 1] = s[n - 1];
    }
    // Points SPACING apart along the smoothed path, each on the floor found by an exact cast
    // nearest the floor of the lines it lies between. Where that cast finds no floor (a
    // feature finer than the lines, which are 0.4 m apart), the point is tried again on its
    // way back to the path the lines made, and left out if none is found.
    let picked = resample(&s, SPACING);
    let place = |(p, i): ([f64; 2], f64)| -> [[f64; 2]; 5] {
        let l = lines[(i.round() as usize).min(n - 1)].point;
        [0.0, 0.25, 0.5, 0.75, 1.0].map(|t| [p[0] + t * (l[0] - p[0]), p[1] + t * (l[1] - p[1])])
    };
    let tries: Vec<[f64; 2]> = picked.iter().flat_map(|&x| place(x)).collect();
    let columns = columns(passages, &tries, 5);
    let mut out = vec![lines[0].point];
    for (k, &(_, i)) in picked.iter().enumerate().take(picked.len() - 1).skip(1) {
        let (a, b) = (
            lines[i.floor() as usize],
            lines[(i.ceil() as usize).min(n - 1)],
        );
        let z = a.point[2] + i.fract() * (b.point[2] - a.point[2]);
        if let Some((p, f)) = (0..5).find_map(|t| {
            let at = 5 * k + t;
            Some((tries[at], floor_near(&columns[at], z, [1.0, 1.0])?))
        }) {
            out.push([p[0], p[1], f]);
        }
    }
    out.push(lines[n - 1].point);
    out.dedup();
    relaxed(passages, out)
}

/// Turn (degrees between one step and the next, the steps [`SPACING`] long) above which a
/// smoothed path is relaxed further where it bends.
const RELAX_ABOVE: f64 = 16.0;
/// Most a relaxed point's floor may differ from where it was, or from the point before it,
/// metres (half a metre a metre: 27 degrees).
const RELAX_RISE: f64 = 0.5;
/// Points either side of a sharp bend that its relaxation moves.
const RELAX_REACH: usize = 7;

/// `points` (a path [`SPACING`] apart) relaxed where they still bend sharply: the lines' room
/// is measured to the nearest undrivable line of a raster 0.4 m apart, which is cautious
/// where the path rounds a boulder or a ledge. About each bend sharper than [`RELAX_ABOVE`],
/// the [`RELAX_REACH`] points either side are smoothed further, and the new ones are kept if
/// every one of them is [`drivable`] within [`RELAX_RISE`] of where it was and of the point
/// before it, and so is the floor 0.15 m to either side of it, within 0.3 m. A few rounds, the
/// same on every run.
fn relaxed(passages: &Passages, mut points: Vec<[f64; 3]>) -> Vec<[f64; 3]> {
    let turn = |p: &[[f64; 3]], i: usize| {
        let h = |a: [f64; 3], b: [f64; 3]| (b[1] - a[1]).atan2(b[0] - a[0]);
        let t = (h(p[i], p[i + 1]) - h(p[i - 1], p[i])).abs();
        t.min(std::f64::consts::TAU - t).to_degrees()
    };
    for _ in 0..4 {
        let n = points.len();
        if n < 2 * RELAX_REACH + 3 {
            return points;
        }
        let mut changed = false;
        let mut i = 1;
        while i + 1 < n {
            if turn(&points, i) <= RELAX_ABOVE {
                i += 1;
                continue;
            }
            let (lo, hi) = (
                i.saturating_sub(RELAX_REACH).max(1),
                (i + RELAX_REACH).min(n - 2),
            );
            let mut tried = points.clone();
            for _ in 0..12 {
                let before = tried.clone();
                for k in lo..=hi {
                    for a in 0..2 {
                        tried[k][a] =
                            0.25 * (before[k - 1][a] + 2.0 * before[k][a] + before[k + 1][a]);
                    }
                }
            }
            let mut probes = Vec::with_capacity(3 * (hi - lo + 1));
            for k in lo..=hi {
                let (a, b) = (tried[k - 1], tried[k + 1]);
                let len = (b[0] - a[0]).hypot(b[1] - a[1]).max(1e-9);
                let side = [-(b[1] - a[1]) / len * 0.15, (b[0] - a[0]) / len * 0.15];
                let c = tried[k];
                probes.extend([
                    [c[0], c[1]],
                    [c[0] + side[0], c[1] + side[1]],
                    [c[0] - side[0], c[1] - side[1]],
                ]);
            }
            let columns = columns(passages, &probes, 3);
            let ok = (lo..=hi).all(|k| {
                let at = 3 * (k - lo);
                let z = points[k][2];
                match drivable(&columns[at], z) {
                    Some(f) if (f - z).abs() <= RELAX_RISE => {
                        tried[k][2] = f;
                        (1..3).all(|s| {
                            drivable(&columns[at + s], f).is_some_and(|g| (g - f).abs() <= 0.3)
                        })
                    }
                    _ => false,
                }
            }) && (lo..=hi + 1)
                .all(|k| (tried[k][2] - tried[k - 1][2]).abs() <= RELAX_RISE);
            if ok {
                points = tried;
                changed = true;
            }
            i = hi + 1;
        }
        if !changed {
            break;
        }
    }
    points
}

/// The lines of the passage axis through `cells`: each tile's path from the previous tile's
/// opening to its anchor and on to the next's (a tile without an axis: its centre, which may
/// not move), from the first node's anchor to the last's.
fn axis_lines(axes: &Axes, world: &World, cells: &[Cell]) -> Vec<Line> {
    let mut out: Vec<Line> = Vec::new();
    let push = |l: Line, out: &mut Vec<Line>| {
        if out.last().is_none_or(|m| m.point != l.point) {
            out.push(l);
        }
    };
    for (k, &c) in cells.iter().enumerate() {
        let Some(a) = axes.get(c) else {
            push(
                Line {
                    point: world.cell_position(c),
                    room: 0.0,
                },
                &mut out,
            );
            continue;
        };
        if k > 0 {
            if let Some(d) = towards(c, cells[k - 1]) {
                for &l in a.lines[d as usize].iter().rev() {
                    push(l, &mut out);
                }
            }
        }
        push(
            Line {
                point: a.anchor,
                room: a.anchor_room,
            },
            &mut out,
        );
        if let Some(&next) = cells.get(k + 1) {
            if let Some(d) = towards(c, next) {
                for &l in &a.lines[d as usize] {
                    push(l, &mut out);
                }
            }
        }
    }
    out
}

/// How near (metres) a later line of a path must come to an earlier one for the lines between
/// to be a loop (or a spur: the way into a tile's anchor and out again along the same lines).
const LOOP: f64 = 0.6;
/// How many lines back a loop is looked for (about 16 m).
const LOOP_LINES: usize = 40;

/// `lines` without the loops and spurs of a path built tile by tile: a tile's anchor need not
/// lie on the way through it (its paths to two openings may share their first lines), and the
/// way in and out would retrace them. A line that comes back within [`LOOP`] of one of the
/// last [`LOOP_LINES`] cuts everything since that one.
fn without_loops(lines: Vec<Line>) -> Vec<Line> {
    let mut out: Vec<Line> = Vec::with_capacity(lines.len());
    for l in lines {
        let from = out.len().saturating_sub(LOOP_LINES);
        let back = (from..out.len().saturating_sub(1)).find(|&j| {
            let q = out[j].point;
            (q[0] - l.point[0]).hypot(q[1] - l.point[1]) < LOOP
        });
        if let Some(j) = back {
            // Keep the first line (a node) and the newer one.
            out.truncate(j.max(1));
        }
        out.push(l);
    }
    out
}
