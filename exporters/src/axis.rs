//! The passage axis of every tile, taken from the free space of the collision surface: where a
//! robot drives through a tile, as opposed to where the grid puts the tile's centre.
//!
//! A tile's passage need not pass through its centre: a DARPA cave tile's corner arcs away from
//! it and its straight tiles wind (on `examples/darpa-cave.toml`, 54 % of the corner tiles and
//! 38 % of the dead ends have no surface at all on the vertical line through their centre). So
//! every tile is looked at on a grid of vertical lines (at least [`PIXELS`] x [`PIXELS`], at
//! most [`SPACING`] apart, so a ridge of rock a ball cannot cross lies on a line): a line is
//! drivable where one of its free stretches starts within the level (its floor) and is at least
//! [`BODY`] high. Over the drivable lines, a clearance-weighted shortest path (steps away from
//! the walls and from ledges are cheaper, so paths keep to the middle of the passage; no
//! diagonal step passes between two lines it could not step to) joins each opening of the
//! tile (the widest drivable line of the seam, nearest the seam's middle) to the tile's
//! *anchor*: for a tile with two or more openings the point nearest all of them along the
//! passage (the middle of a corridor tile, the meeting point of a junction), for a dead end
//! the middle of its passage (from the opening to the far end that still has clearance), and
//! for a shaft foot or landing the drivable line nearest the shaft's axis. Paths climb at most
//! 0.6 of the line spacing per line (31 degrees) and pay for every metre up or down.
//!
//! The paths' points are kept every [`KEEP_M`] and wherever the straight line between kept
//! points would stray more than [`CHORD`] from the path (a body is driven point to point).
//! The graph's node positions, its corridor polylines (anchor, path to the opening, the next
//! tile's path from its opening, its anchor, ...), the tiles' positions in the semantic labels and the spawn
//! and goal poses all use these, with the floor's own height. A tile where nothing is drivable
//! or an opening is not reached keeps its grid centre (`fallback` counts them). Without a
//! mesh the passages are the grid's, and the axis is the line through the cell centres.
//!
//! Deterministic: lines come from the exact raster of [`crate::inside`], paths from a Dijkstra
//! with integer costs and ties broken by index, tiles in parallel collected in order.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

use rayon::prelude::*;
use subtgraph_core::World;
use subtgraph_core::grid::{Cell, Direction};
use subtgraph_core::tile::TileKind;

use crate::inside::{Columns, Passages};

/// Least lines per tile side.
pub(crate) const PIXELS: usize = 64;
/// Most metres between neighbouring lines: a ball of 0.3 m (a small robot's wheel) is stopped
/// by a ridge of rock narrower than a coarser spacing could see (the DARPA tiles' 80 m pitch
/// at 64 lines puts them 1.25 m apart, and their floors hold boulders 0.8 m across).
const SPACING: f64 = 0.4;
/// Least free height over a drivable line's floor, metres (a ground robot's body).
pub(crate) const BODY: f64 = 1.0;
/// How deep into a tile an opening's entry is looked for, as a share of the tile's side.
const ENTRY_DEPTH: usize = 8; // of PIXELS lines
/// A path point is kept about every this many metres (and at the ends).
const KEEP_M: f64 = 2.5;
/// ... and wherever the straight line between kept points would stray more than this many
/// metres from the path (round a boulder or a bend: a body driven from point to point in
/// straight lines must stay where the path found room).
const CHORD: f64 = 0.25;
/// Least horizontal run over which [`Axes::grade`] measures a rise, metres.
pub(crate) const GRADE_RUN: f64 = 4.0;
/// What a metre of floor height between neighbouring lines costs, in metres along.
const CLIMB: u64 = 10;
/// How strongly paths keep away from walls: a step next to a wall costs `1 + WALL` times a step
/// far from them.
const WALL: u64 = 8;

/// One tile's axis.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TileAxis {
    /// Where the tile's node stands, on its floor.
    pub anchor: [f64; 3],
    /// Per direction (`Direction as usize`): the path from the anchor (excluded) to the
    /// opening's entry line next to the seam (included), on the floor. The neighbour's path
    /// starts on the line across the seam: the seam itself is not a point (the DARPA tiles'
    /// collision leaves a sliver open along some seams).
    pub exits: [Vec<[f64; 3]>; 4],
}

/// The axes of a world's tiles.
#[derive(Debug, Default)]
pub(crate) struct Axes {
    tiles: HashMap<Cell, TileAxis>,
    /// Tiles that kept their grid centre.
    pub fallback: usize,
}

impl Axes {
    /// Every tile's axis, from the passages (the collision surface, or the grid).
    pub fn of(world: &World, passages: &Passages) -> Axes {
        if matches!(passages, Passages::Grid(_)) {
            return Axes::default();
        }
        let cells: Vec<Cell> = world
            .occupancy
            .cells()
            .filter(|&c| *world.occupancy.get(c))
            .collect();
        let found: Vec<Option<TileAxis>> = cells
            .par_iter()
            .map(|&c| tile_axis(world, passages, c))
            .collect();
        let mut axes = Axes::default();
        for (c, a) in cells.into_iter().zip(found) {
            match a {
                Some(a) => {
                    axes.tiles.insert(c, a);
                }
                None => axes.fallback += 1,
            }
        }
        axes
    }

    /// The axes of `cells` only (the tiles artifacts stand in), as [`of`](Self::of) finds
    /// them.
    pub fn of_cells(world: &World, passages: &Passages, cells: &[Cell]) -> Axes {
        let mut axes = Axes::default();
        if matches!(passages, Passages::Grid(_)) {
            return axes;
        }
        let found: Vec<Option<TileAxis>> = cells
            .par_iter()
            .map(|&c| tile_axis(world, passages, c))
            .collect();
        for (&c, a) in cells.iter().zip(found) {
            match a {
                Some(a) => {
                    axes.tiles.insert(c, a);
                }
                None => axes.fallback += 1,
            }
        }
        axes
    }

    /// Every point of a tile's axis: its anchor and its paths to the openings (the grid
    /// centre alone for a tile without an axis).
    pub fn tile_points(&self, world: &World, c: Cell) -> Vec<[f64; 3]> {
        match self.tiles.get(&c) {
            Some(a) => std::iter::once(a.anchor)
                .chain(a.exits.iter().flatten().copied())
                .collect(),
            None => vec![world.cell_position(c)],
        }
    }

    /// A robot's way through a tile it enters from `from`: that opening's path to the anchor,
    /// the anchor, then the paths to the other openings (east, north, west, south); `None`
    /// for a tile without an axis or without that opening.
    pub fn walk_from(&self, c: Cell, from: Direction) -> Option<Vec<[f64; 3]>> {
        let a = self.tiles.get(&c)?;
        let entry = &a.exits[from as usize];
        if entry.is_empty() {
            return None;
        }
        let mut walk: Vec<[f64; 3]> = entry.iter().rev().copied().collect();
        walk.push(a.anchor);
        for d in Direction::ALL.into_iter().filter(|&d| d != from) {
            walk.extend(a.exits[d as usize].iter().copied());
        }
        Some(walk)
    }

    /// Where a tile's node stands: its anchor, or the grid centre.
    pub fn position(&self, world: &World, c: Cell) -> [f64; 3] {
        self.tiles
            .get(&c)
            .map_or_else(|| world.cell_position(c), |a| a.anchor)
    }

    /// The steepest grade of a tile's floor along its axis, degrees: rise over run from the
    /// anchor along each exit, between points at least [`GRADE_RUN`] metres apart horizontally
    /// (nearer points are merged, so rubble is not a grade). `None` without an axis.
    pub fn grade(&self, c: Cell) -> Option<f64> {
        let a = self.tiles.get(&c)?;
        let mut worst: f64 = 0.0;
        for exit in &a.exits {
            let mut last = a.anchor;
            for &p in exit {
                let run = (p[0] - last[0]).hypot(p[1] - last[1]);
                if run >= GRADE_RUN {
                    worst = worst.max((p[2] - last[2]).abs().atan2(run).to_degrees());
                    last = p;
                }
            }
        }
        Some(worst)
    }

    /// The centreline through `cells` (consecutive cells of one corridor, or a shaft's two
    /// ends): anchors joined by each tile's path to the opening they share.
    pub fn polyline(&self, world: &World, cells: &[Cell]) -> Vec<[f64; 3]> {
        let mut out: Vec<[f64; 3]> = Vec::new();
        let push = |p: [f64; 3], out: &mut Vec<[f64; 3]>| {
            if out.last() != Some(&p) {
                out.push(p);
            }
        };
        for (k, &c) in cells.iter().enumerate() {
            if k > 0 {
                let prev = cells[k - 1];
                if let (Some(d), Some(a)) = (towards(c, prev), self.tiles.get(&c)) {
                    for &p in a.exits[d as usize].iter().rev() {
                        push(p, &mut out);
                    }
                }
            }
            push(self.position(world, c), &mut out);
            if let Some(&next) = cells.get(k + 1) {
                if let (Some(d), Some(a)) = (towards(c, next), self.tiles.get(&c)) {
                    for &p in &a.exits[d as usize] {
                        push(p, &mut out);
                    }
                }
            }
        }
        out
    }
}

/// The floor line of the ramp joining `cells` (a ramp's foot and landing), when the world's
/// mesh has one.
pub(crate) fn ramp_line<'a>(world: &'a World, cells: &[Cell]) -> Option<&'a [[f64; 3]]> {
    let i = world
        .shafts
        .iter()
        .position(|s| cells.first() == Some(&s.up) && cells.last() == Some(&s.landing))?;
    world.mesh()?.ramps.get(i).map(Vec::as_slice)
}

/// Where a ramp's floor line leaves the level of `c`, when `c` is a ramp's foot or landing.
fn ramp_end(world: &World, c: Cell) -> Option<[f64; 2]> {
    let ramps = &world.mesh()?.ramps;
    let (i, s) = world
        .shafts
        .iter()
        .enumerate()
        .find(|(_, s)| s.up == c || s.landing == c)?;
    let line = ramps.get(i)?;
    let p = if s.up == c { line.first() } else { line.last() }?;
    Some([p[0], p[1]])
}

/// The direction of a step from `a` to its neighbour `b` on the same level.
fn towards(a: Cell, b: Cell) -> Option<Direction> {
    if a.level != b.level {
        return None;
    }
    let step = (b.row as i64 - a.row as i64, b.col as i64 - a.col as i64);
    Direction::ALL.into_iter().find(|d| {
        let (dr, dc) = d.step();
        (i64::from(dr), i64::from(dc)) == step
    })
}

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
    let [low, high] = world.floor_lift(c).map(|l| centre[2] + l);
    let off = |z: f64| {
        if z < low {
            low - z
        } else if z > high {
            z - high
        } else {
            0.0
        }
    };
    let bounds = [cols.x0, cols.y0, cols.x0 + pitch, cols.y0 + pitch];
    // Every line's crossings, bottom up, with the facing of their triangles. The surface need
    // not be closed (the DARPA tiles' is not: ray parity would call half their lines open), so
    // floors are read from the facing: a floor is a crossing whose triangle faces into the
    // passage above it. Which winding faces in is taken from the lines' lowest crossings, which
    // are floors wherever a line crosses anything.
    let lines: Vec<Vec<(f64, bool)>> = passages
        .crossings_within(&cols, bounds, |_, hits| {
            let mut row = vec![Vec::new(); n];
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
    if floors.len() != n * n {
        return (cols, vec![f64::NAN; n * n]);
    }
    (cols, floors)
}

/// The most a path climbs (or drops) from one line to the next, metres: 31 degrees.
fn climb_per_line(step: f64) -> f64 {
    (0.6 * step).max(0.25)
}

/// Chamfer distance (3-4) of every drivable line to the nearest undrivable one, in thirds of
/// a line spacing. The tile's border is not a wall: the passage goes on beyond it.
fn clearance(free: &[bool], n: usize) -> Vec<u32> {
    let big = u32::MAX / 4;
    let mut d: Vec<u32> = free.iter().map(|&f| if f { big } else { 0 }).collect();
    let at = |i: i64, j: i64| {
        (i >= 0 && j >= 0 && (i as usize) < n && (j as usize) < n)
            .then(|| j as usize * n + i as usize)
    };
    for j in 0..n as i64 {
        for i in 0..n as i64 {
            let k = j as usize * n + i as usize;
            for (di, dj, w) in [(-1, 0, 3), (0, -1, 3), (-1, -1, 4), (1, -1, 4)] {
                if let Some(m) = at(i + di, j + dj) {
                    d[k] = d[k].min(d[m] + w);
                }
            }
        }
    }
    for j in (0..n as i64).rev() {
        for i in (0..n as i64).rev() {
            let k = j as usize * n + i as usize;
            for (di, dj, w) in [(1, 0, 3), (0, 1, 3), (1, 1, 4), (-1, 1, 4)] {
                if let Some(m) = at(i + di, j + dj) {
                    d[k] = d[k].min(d[m] + w);
                }
            }
        }
    }
    d
}

/// Dijkstra over drivable lines from `source`: costs (integer) and parents.
fn paths(
    free: &[bool],
    floor: &[f64],
    clear: &[u32],
    step: f64,
    n: usize,
    source: usize,
) -> (Vec<u64>, Vec<u32>) {
    let mut dist = vec![u64::MAX; n * n];
    let mut parent = vec![u32::MAX; n * n];
    let mut heap = BinaryHeap::new();
    dist[source] = 0;
    heap.push(Reverse((0u64, source as u32)));
    let climb = climb_per_line(step);
    while let Some(Reverse((d, u))) = heap.pop() {
        let u = u as usize;
        if d > dist[u] {
            continue;
        }
        let (i, j) = ((u % n) as i64, (u / n) as i64);
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
            if a < 0 || b < 0 || a >= n as i64 || b >= n as i64 {
                continue;
            }
            let v = b as usize * n + a as usize;
            let rise = (floor[v] - floor[u]).abs();
            if !free[v] || rise > climb {
                continue;
            }
            // No diagonal step past a line that could not be stepped to itself (rock, or a
            // floor a step up or down): the rock of the two may meet between them (the DARPA
            // tiles' floors hold blocks of rock touching at a corner).
            if di != 0 && dj != 0 {
                let side = [j as usize * n + a as usize, b as usize * n + i as usize];
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
fn tile_axis(world: &World, passages: &Passages, c: Cell) -> Option<TileAxis> {
    let tile = world.tiles.get(c).as_ref()?;
    let n = lines_per_side(world.resolved.tile_pitch);
    let (cols, floor) = floors(world, passages, c, n);
    let free: Vec<bool> = floor.iter().map(|f| !f.is_nan()).collect();
    if !free.iter().any(|&f| f) {
        return None;
    }
    let step = cols.step;
    // Walls are rock, and the edges of a step up or down that no path climbs: a line next to
    // one has no clearance (a body keeps off a ledge as off a wall).
    let climb = climb_per_line(step);
    let roomy: Vec<bool> = (0..n * n)
        .map(|k| {
            let (i, j) = (k % n, k / n);
            free[k]
                && [(1, 0), (-1, 0), (0, 1), (0, -1)].iter().all(|&(di, dj)| {
                    let (a, b) = (i as i64 + di, j as i64 + dj);
                    if a < 0 || b < 0 || a >= n as i64 || b >= n as i64 {
                        return true;
                    }
                    let m = b as usize * n + a as usize;
                    !free[m] || (floor[m] - floor[k]).abs() <= climb
                })
        })
        .collect();
    let clear = clearance(&roomy, n);
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
            let (dist, parent) = paths(&free, &floor, &clear, step, n, e);
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
    let mut exits: [Vec<[f64; 3]>; 4] = Default::default();
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
    }
    // An opening whose drivable lines do not meet the anchor's on the floor (a climb steeper
    // than a robot drives): its entry line, on its floor; the way between is unknown.
    for (d, e, _, _) in &apart {
        exits[*d as usize] = vec![point(*e)];
    }
    Some(TileAxis {
        anchor: point(anchor),
        exits,
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

impl Axes {
    /// Whether no tile has an axis of its own (a world without a mesh).
    pub fn is_empty(&self) -> bool {
        self.tiles.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::graph::EdgeKind;

    #[test]
    fn nodes_and_centrelines_stand_on_the_floor_of_the_passages() {
        let world = crate::ground_truth::tests::world_with_mesh();
        let passages = Passages::of(&world);
        let axes = Axes::of(&world, &passages);
        assert_eq!(axes.fallback, 0, "every tile has an axis");
        let on_floor = |p: [f64; 3]| {
            passages
                .column(p[0], p[1])
                .iter()
                .any(|s| (s[0] - p[2]).abs() < 1e-9 && s[1] - s[0] >= BODY)
        };
        for n in &world.graph.nodes {
            let p = axes.position(&world, n.cell);
            assert!(on_floor(p), "node {} at {p:?}", n.id);
        }
        for e in world
            .graph
            .edges
            .iter()
            .filter(|e| e.kind == EdgeKind::Corridor)
        {
            let line = axes.polyline(&world, &e.cells);
            assert!(
                line.len() > e.cells.len(),
                "the path follows the passage between anchors"
            );
            for p in line {
                // Free half a metre above it, on a floor at most a metre below it (seam
                // points carry the floor of the line next to the seam).
                let free = passages
                    .column(p[0], p[1])
                    .iter()
                    .any(|s| s[0] <= p[2] + 0.5 && p[2] + 0.5 <= s[1] && p[2] - s[0] < 1.0);
                assert!(free, "edge {} point {p:?}", e.id);
            }
        }
        // Without a mesh the axis is the grid's: cell centres.
        let grid = crate::test_world();
        let axes = Axes::of(&grid, &Passages::of(&grid));
        assert!(axes.is_empty());
        let c = grid.start.unwrap();
        assert_eq!(axes.position(&grid, c), grid.cell_position(c));
    }
}
