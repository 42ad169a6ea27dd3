//! One tile's passage axis (see the module above): its drivable lines, their clearance, the
//! shortest paths from each opening, the anchor where they meet, and the points kept.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use subtgraph_core::World;
use subtgraph_core::grid::{Cell, Direction};
use subtgraph_core::tile::TileKind;

use super::{Line, TileAxis, ramp_end};
use crate::passages::{Columns, Passages};

/// Least lines per tile side.
const PIXELS: usize = 64;
/// Most metres between neighbouring lines: a ball of 0.3 m (a small robot's wheel) is stopped
/// by a ridge of rock narrower than a coarser spacing could see (the DARPA tiles' 80 m pitch
/// at 64 lines puts them 1.25 m apart, and their floors hold boulders 0.8 m across).
const SPACING: f64 = 0.4;
/// Least free height over a drivable line's floor, metres (a ground robot's body).
pub(super) const BODY: f64 = 1.0;
/// How deep into a tile an opening's entry is looked for, as a share of the tile's side.
const ENTRY_DEPTH: usize = 8; // of PIXELS lines
/// A path point is kept about every this many metres (and at the ends).
const KEEP_M: f64 = 2.5;
/// ... and wherever the straight line between kept points would stray more than this many
/// metres from the path (round a boulder or a bend: a body driven from point to point in
/// straight lines must stay where the path found room).
const CHORD: f64 = 0.25;
/// What a metre of floor height between neighbouring lines costs, in metres along.
const CLIMB: u64 = 10;
/// How strongly paths keep away from walls: a step next to a wall costs `1 + WALL` times a step
/// far from them.
const WALL: u64 = 8;

/// Lines per tile side for a tile pitch: [`PIXELS`], or more where that would put them more
/// than [`SPACING`] apart.
pub(crate) fn lines_per_side(pitch: f64) -> usize {
    PIXELS.max((pitch / SPACING).ceil() as usize)
}

/// The lines of one tile: per line its floor (NaN where not drivable).
fn floors(world: &World, passages: &Passages, c: Cell, n: usize) -> (Columns, Vec<f64>) {
    let pitch = world.resolved.tile_pitch;
    let centre = world.cell_position(c);
    let step = pitch / n as f64;
    let cols = Columns {
        x0: centre[0] - 0.5 * pitch,
        y0: centre[1] - 0.5 * pitch,
        step,
        nx: n,
        ny: n,
    };
    // The floor is looked for within 0.45 level heights of the level's floor, or of the
    // heights the tile set lifted this tile's floor to (a hill's tiles: `floor_lift`).
    let half = 0.45 * world.resolved.level_height;
    let band = world.floor_lift(c).map(|l| centre[2] + l);
    let bounds = [cols.x0, cols.y0, cols.x0 + pitch, cols.y0 + pitch];
    let floors = floors_in(passages, &cols, bounds, band, half);
    (cols, floors)
}

/// Per line of `cols` (rows south to north, each west to east; all within `bounds`) the floor a
/// body stands on (NaN where none): the floor of a free stretch at least [`BODY`] high,
/// nearest the heights `band` (`[low, high]`), at most `half` from them.
pub(crate) fn floors_in(
    passages: &Passages,
    cols: &Columns,
    bounds: [f64; 4],
    band: [f64; 2],
    half: f64,
) -> Vec<f64> {
    let [low, high] = band;
    let (nx, ny) = (cols.nx, cols.ny);
    let off = |z: f64| {
        if z < low {
            low - z
        } else if z > high {
            z - high
        } else {
            0.0
        }
    };
    // Every line's crossings, bottom up, with the facing of their triangles. The surface need
    // not be closed (the DARPA tiles' is not: ray parity would call half their lines open), so
    // floors are read from the facing: a floor is a crossing whose triangle faces into the
    // passage above it. Which winding faces in is taken from the lines' lowest crossings, which
    // are floors wherever a line crosses anything.
    let lines: Vec<Vec<(f64, bool)>> = passages
        .crossings_within(cols, bounds, |_, hits| {
            let mut row = vec![Vec::new(); nx];
            for h in hits {
                row[h.i as usize].push((h.z, h.up));
            }
            row
        })
        .unwrap_or_default()
        .concat();
    let lowest_up = lines.iter().filter(|l| l.len() >= 2 && l[0].1).count();
    let lowest_down = lines.iter().filter(|l| l.len() >= 2 && !l[0].1).count();
    let floor_faces_up = lowest_up >= lowest_down;
    let floors = lines
        .iter()
        .map(|l| {
            let mut best = f64::NAN;
            for w in l.windows(2) {
                // A floor is the top of the rock below it: the next crossing up must be a
                // ceiling. Two floors in a row (the DARPA tiles' flat plate under a mound of
                // their rock) have rock between them, not a passage the ball could enter.
                let ((z0, up), (z1, next_up)) = (w[0], w[1]);
                if up != floor_faces_up
                    || next_up == floor_faces_up
                    || z1 - z0 < BODY
                    || off(z0) > half
                {
                    continue;
                }
                if best.is_nan() || off(z0) < off(best) {
                    best = z0;
                }
            }
            best
        })
        .collect::<Vec<f64>>();
    if floors.len() != nx * ny {
        return vec![f64::NAN; nx * ny];
    }
    floors
}

/// The most a path climbs (or drops) from one line to the next, metres: 31 degrees.
pub(crate) fn climb_per_line(step: f64) -> f64 {
    (0.6 * step).max(0.25)
}

/// Which drivable lines have room about them: walls are rock, and so are the edges of a step
/// up or down that no path climbs (a body keeps off a ledge as off a wall). The raster's
/// border is not a wall.
pub(crate) fn roomy(
    free: &[bool],
    floor: &[f64],
    (nx, ny): (usize, usize),
    step: f64,
) -> Vec<bool> {
    let climb = climb_per_line(step);
    (0..nx * ny)
        .map(|k| {
            let (i, j) = (k % nx, k / nx);
            free[k]
                && [(1, 0), (-1, 0), (0, 1), (0, -1)].iter().all(|&(di, dj)| {
                    let (a, b) = (i as i64 + di, j as i64 + dj);
                    if a < 0 || b < 0 || a >= nx as i64 || b >= ny as i64 {
                        return true;
                    }
                    let m = b as usize * nx + a as usize;
                    !free[m] || (floor[m] - floor[k]).abs() <= climb
                })
        })
        .collect()
}

/// Chamfer distance (3-4) of every drivable line to the nearest undrivable one, in thirds of
/// a line spacing. The tile's border is not a wall: the passage goes on beyond it.
pub(crate) fn clearance(free: &[bool], nx: usize, ny: usize) -> Vec<u32> {
    let big = u32::MAX / 4;
    let mut d: Vec<u32> = free.iter().map(|&f| if f { big } else { 0 }).collect();
    let at = |i: i64, j: i64| {
        (i >= 0 && j >= 0 && (i as usize) < nx && (j as usize) < ny)
            .then(|| j as usize * nx + i as usize)
    };
    for j in 0..ny as i64 {
        for i in 0..nx as i64 {
            let k = j as usize * nx + i as usize;
            for (di, dj, w) in [(-1, 0, 3), (0, -1, 3), (-1, -1, 4), (1, -1, 4)] {
                if let Some(m) = at(i + di, j + dj) {
                    d[k] = d[k].min(d[m] + w);
                }
            }
        }
    }
    for j in (0..ny as i64).rev() {
        for i in (0..nx as i64).rev() {
            let k = j as usize * nx + i as usize;
            for (di, dj, w) in [(1, 0, 3), (0, 1, 3), (1, 1, 4), (-1, 1, 4)] {
                if let Some(m) = at(i + di, j + dj) {
                    d[k] = d[k].min(d[m] + w);
                }
            }
        }
    }
    d
}

/// Dijkstra over drivable lines from `source`: costs (integer) and parents. The raster is
/// `nx` x `ny` lines, `n` of them to a tile's side.
#[allow(clippy::too_many_arguments)]
pub(crate) fn paths(
    free: &[bool],
    floor: &[f64],
    clear: &[u32],
    step: f64,
    (nx, ny): (usize, usize),
    n: usize,
    source: usize,
) -> (Vec<u64>, Vec<u32>) {
    let mut dist = vec![u64::MAX; nx * ny];
    let mut parent = vec![u32::MAX; nx * ny];
    let mut heap = BinaryHeap::new();
    dist[source] = 0;
    heap.push(Reverse((0u64, source as u32)));
    let climb = climb_per_line(step);
    while let Some(Reverse((d, u))) = heap.pop() {
        let u = u as usize;
        if d > dist[u] {
            continue;
        }
        let (i, j) = ((u % nx) as i64, (u / nx) as i64);
        for (di, dj, len) in [
            (1, 0, 1000u64),
            (-1, 0, 1000),
            (0, 1, 1000),
            (0, -1, 1000),
            (1, 1, 1414),
            (1, -1, 1414),
            (-1, 1, 1414),
            (-1, -1, 1414),
        ] {
            let (a, b) = (i + di, j + dj);
            if a < 0 || b < 0 || a >= nx as i64 || b >= ny as i64 {
                continue;
            }
            let v = b as usize * nx + a as usize;
            let rise = (floor[v] - floor[u]).abs();
            if !free[v] || rise > climb {
                continue;
            }
            // No diagonal step past a line that could not be stepped to itself (rock, or a
            // floor a step up or down): the rock of the two may meet between them (the DARPA
            // tiles' floors hold blocks of rock touching at a corner).
            if di != 0 && dj != 0 {
                let side = [j as usize * nx + a as usize, b as usize * nx + i as usize];
                if side
                    .iter()
                    .any(|&m| !free[m] || (floor[m] - floor[u]).abs() > climb)
                {
                    continue;
                }
            }
            // Clearance in thirds of a tile's side over [`PIXELS`] (as with the coarsest
            // lines), so paths keep as far from the walls in metres at any line count.
            let c = u64::from(clear[v].min(3 * n as u32)) * PIXELS as u64 / n as u64 + 3;
            // Rough floor costs too: a metre up or down is worth [`CLIMB`] metres along.
            let rough = (rise / step * CLIMB as f64 * len as f64) as u64;
            let nd = d + len * (c + 3 * WALL) / c + rough;
            if nd < dist[v] {
                dist[v] = nd;
                parent[v] = u as u32;
                heap.push(Reverse((nd, v as u32)));
            }
        }
    }
    (dist, parent)
}

/// The axis of one tile, or `None` when it has no drivable line or an opening is not reached.
pub(super) fn tile_axis(world: &World, passages: &Passages, c: Cell) -> Option<TileAxis> {
    let tile = world.tiles.get(c).as_ref()?;
    let n = lines_per_side(world.resolved.tile_pitch);
    let (cols, floor) = floors(world, passages, c, n);
    let free: Vec<bool> = floor.iter().map(|f| !f.is_nan()).collect();
    if !free.iter().any(|&f| f) {
        return None;
    }
    let step = cols.step;
    let clear = clearance(&roomy(&free, &floor, (n, n), step), n, n);
    let entry_depth = ENTRY_DEPTH * n / PIXELS;
    // Each opening's entry: the widest drivable line on that seam, nearest its middle; where
    // the seam's own lines are not drivable (a tile whose passage ends short of its border),
    // the nearest drivable line within [`ENTRY_DEPTH`] lines of it.
    let mut entries: Vec<(Direction, usize)> = Vec::new();
    for d in Direction::ALL {
        if tile.openings & d.bit() == 0 {
            continue;
        }
        // Rows run south to north (j), lines west to east (i); North is +y, the last row.
        let line = |depth: usize, t: usize| match d {
            Direction::East => t * n + (n - 1 - depth),
            Direction::West => t * n + depth,
            Direction::North => (n - 1 - depth) * n + t,
            Direction::South => depth * n + t,
        };
        let found = (0..entry_depth).find_map(|depth| {
            (0..n)
                .filter(|&t| free[line(depth, t)])
                .min_by_key(|&t| (Reverse(clear[line(depth, t)]), (2 * t).abs_diff(n - 1), t))
                .map(|t| line(depth, t))
        });
        if let Some(e) = found {
            entries.push((d, e));
        }
    }
    if entries.is_empty() {
        return None;
    }
    let runs: Vec<(Direction, usize, Vec<u64>, Vec<u32>)> = entries
        .iter()
        .map(|&(d, e)| {
            let (dist, parent) = paths(&free, &floor, &clear, step, (n, n), n, e);
            (d, e, dist, parent)
        })
        .collect();
    // The anchor is reached from as many openings as any line is (all of them, unless the
    // tile's passages do not meet on its floor).
    let reach: Vec<usize> = (0..n * n)
        .map(|k| runs.iter().filter(|r| r.2[k] != u64::MAX).count())
        .collect();
    let most = (0..n * n).filter(|&k| free[k]).map(|k| reach[k]).max()?;
    let first = (0..n * n).find(|&k| free[k] && reach[k] == most)?;
    let (runs, apart): (Vec<_>, Vec<_>) = runs.into_iter().partition(|r| r.2[first] != u64::MAX);
    let reached = |k: usize| runs.iter().all(|r| r.2[k] != u64::MAX);
    // A shaft's foot or landing stands nearest the shaft's axis; a ramp's where its floor
    // line leaves the level (the spiral's axis is a rock pillar).
    let centre = ramp_end(world, c).unwrap_or([
        cols.x0 + 0.5 * n as f64 * step,
        cols.y0 + 0.5 * n as f64 * step,
    ]);
    let xy = |k: usize| [cols.x(k % n), cols.y(k / n)];
    let from_centre = |k: usize| {
        let p = xy(k);
        (((p[0] - centre[0]).powi(2) + (p[1] - centre[1]).powi(2)) * 1e6) as u64
    };
    let candidates = (0..n * n).filter(|&k| free[k] && reached(k));
    let anchor = match (tile.kind, runs.len()) {
        (TileKind::ShaftUp | TileKind::ShaftLanding, _) => {
            candidates.min_by_key(|&k| (from_centre(k), k))?
        }
        (_, 1) => {
            // A dead end: half way along its passage from the opening to the far end that
            // still has clearance (the far end itself can be up a slope of rubble).
            let run = &runs[0];
            let widest = (0..n * n)
                .filter(|&k| run.2[k] != u64::MAX)
                .map(|k| clear[k])
                .max()?;
            let enough = (widest / 2).max(3);
            let roomy: Vec<usize> = candidates.filter(|&k| clear[k] >= enough).collect();
            let far = roomy.iter().map(|&k| run.2[k]).max()?;
            roomy
                .into_iter()
                .min_by_key(|&k| (run.2[k].abs_diff(far / 2), k))?
        }
        _ => candidates.min_by_key(|&k| {
            let ds: Vec<u64> = runs.iter().map(|r| r.2[k]).collect();
            let lo = ds.iter().min().copied().unwrap_or(0);
            let hi = ds.iter().max().copied().unwrap_or(0);
            (ds.iter().sum::<u64>() + (hi - lo), k)
        })?,
    };
    let point = |k: usize| {
        let [x, y] = xy(k);
        [x, y, floor[k]]
    };
    let keep = ((KEEP_M / step).round() as usize).max(1);
    // Metres from a line to the nearest one a body cannot stand on (the chamfer distance is
    // in thirds of a line spacing; a tile without any such line counts half a pitch).
    let pitch = world.resolved.tile_pitch;
    let room = |k: usize| (f64::from(clear[k]) / 3.0 * step).min(0.5 * pitch);
    let line_at = |k: usize| Line {
        point: point(k),
        room: room(k),
    };
    let mut exits: [Vec<[f64; 3]>; 4] = Default::default();
    let mut lines: [Vec<Line>; 4] = Default::default();
    for (d, e, _, parent) in &runs {
        // From the anchor back along the parents to the entry.
        let mut path = vec![anchor];
        let mut k = anchor;
        while k != *e {
            k = parent[k] as usize;
            path.push(k);
        }
        let line: Vec<[f64; 2]> = path.iter().map(|&k| xy(k)).collect();
        exits[*d as usize] = kept(&line, keep)
            .into_iter()
            .map(|i| point(path[i]))
            .collect();
        lines[*d as usize] = path[1..].iter().map(|&k| line_at(k)).collect();
    }
    // An opening whose drivable lines do not meet the anchor's on the floor (a climb steeper
    // than a robot drives): its entry line, on its floor; the way between is unknown.
    for (d, e, _, _) in &apart {
        exits[*d as usize] = vec![point(*e)];
        lines[*d as usize] = vec![line_at(*e)];
    }
    Some(TileAxis {
        anchor: point(anchor),
        exits,
        anchor_room: room(anchor),
        lines,
    })
}

/// The indices of `line`'s points to keep (the first excluded, the last included): every
/// `keep`-th point since the last kept one, and the point before any point whose straight line
/// from the last kept one strays more than [`CHORD`] from the points between.
fn kept(line: &[[f64; 2]], keep: usize) -> Vec<usize> {
    let strays = |a: [f64; 2], b: [f64; 2], p: [f64; 2]| {
        subtgraph_core::vec3::segment_distance_squared(p, a, b) > CHORD * CHORD
    };
    let mut out = Vec::new();
    let mut last = 0;
    for i in 1..line.len() {
        let next = i + 1;
        let cut =
            next < line.len() && (last + 1..=i).any(|j| strays(line[last], line[next], line[j]));
        if i + 1 == line.len() || i - last >= keep || cut {
            out.push(i);
            last = i;
        }
    }
    out
}
