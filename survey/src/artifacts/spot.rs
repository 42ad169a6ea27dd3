//! A spot for one artifact in one tile: the lines of the tile's raster under its footprint
//! flat and free, far enough from the others, rock where its rule wants it, seen or hidden as
//! asked, then cast exactly under its corners and edges (see the module above).

use std::f64::consts::TAU;

use subtgraph_core::World;
use subtgraph_core::artifacts::{Artifact, ArtifactClass, Placement};
use subtgraph_core::grid::Cell;
use subtgraph_core::rng::WorldRng;

use super::lookout::Lookout;
use super::{CLEAR, EXACT, FLAT, GAP, HIDDEN_TRIES, LIFT, OPEN, PROBE_Z, STEP, TRIES, WALL};
use crate::passages::{Columns, Passages, Span};
use crate::sight;
use subtgraph_core::artifacts::PAD;

/// What [`spot_in`] looks for.
pub(super) struct Request<'a> {
    pub cell: Cell,
    pub class: ArtifactClass,
    pub rule: Placement,
    /// Whether the spot must be seen (`true`) or hidden (`false`) from the tile's lookout;
    /// `None`: not looked at.
    pub sight: Option<(bool, &'a Lookout)>,
}

/// A spot [`spot_in`] found: base centre, yaw, and what its sight was checked to be.
pub(super) type Spot = ([f64; 3], f64, Option<(bool, [f64; 3])>);

/// A spot in `request.cell` for an artifact of its class by its rule, at least `min_spacing`
/// from every artifact `placed`: its base centre and yaw. Draws from `rng` in a fixed order
/// (the candidate lines' shuffle, then a yaw per candidate tried).
pub(super) fn spot_in(
    world: &World,
    passages: &Passages,
    request: &Request,
    min_spacing: f64,
    placed: &[Artifact],
    rng: &mut WorldRng,
) -> Option<Spot> {
    let Request {
        cell,
        class,
        rule,
        sight,
    } = *request;
    let size = class.size();
    let half_diag = 0.5 * size[0].hypot(size[1]);
    let reach = half_diag + GAP + WALL.max(OPEN);
    let lines = TileLines::around(world, passages, cell, reach, sight.is_some());
    let mut candidates = lines.candidates(world, cell);
    rng.shuffle(&mut candidates);
    let ring = ring(reach, lines.cols.step, half_diag);
    let look = match rule {
        Placement::Wall => GAP + WALL,
        Placement::Floor => GAP + OPEN,
        Placement::DeadEnd | Placement::Chamber => GAP,
    };
    let tries = match sight {
        Some((false, _)) => HIDDEN_TRIES,
        _ => TRIES,
    };
    for &k in candidates.iter().take(tries) {
        let (x, y) = (
            lines.cols.x(k % lines.cols.nx),
            lines.cols.y(k / lines.cols.nx),
        );
        let yaw = rng.unit() * TAU;
        let Some((lo, hi)) = lines.footing(x, y, yaw, size) else {
            continue;
        };
        if placed.iter().any(|a| {
            let p = a.position;
            (p[0] - x).hypot(p[1] - y).hypot(p[2] - hi) < min_spacing
                || meets(a, [x, y, hi], yaw, size)
        }) {
            continue;
        }
        if !lines.rock_as_ruled(k, hi, rule, &ring[..ring.partition_point(|r| r.0 <= look)]) {
            continue;
        }
        // The line of sight on the raster (each point on its nearest line; a point outside
        // the raster is left to the exact look): a spot that looks the wrong way there is
        // not cast exactly.
        if let Some((seen, lookout)) = sight {
            let target = [x, y, hi + LIFT + 0.5 * size[2]];
            if !sight::as_aimed(seen, &lines.blocked(lookout.eye(target), target)) {
                continue;
            }
        }
        let Some(base) = exact_base(passages, [x, y], yaw, size, (lo, hi)) else {
            continue;
        };
        let mut looked = None;
        if let Some((seen, lookout)) = sight {
            let target = [x, y, base + 0.5 * size[2]];
            let eye = lookout.eye(target);
            let rock = sight::blocked(passages, eye, target);
            if !sight::as_aimed(seen, &rock) {
                continue;
            }
            looked = Some((seen, eye));
        }
        return Some(([x, y, base], yaw, looked));
    }
    None
}

/// Whether an artifact of `size` standing at `base` (its floor: the base may rise by up to
/// `FLAT` once cast exactly) turned by `yaw` would meet artifact `a`: their boxes with their
/// pads (`PAD` wider, reaching `2 PAD` below the base) overlap in height and in the plane
/// (separating axes: two rectangles are apart when one of their four edge directions
/// separates them). Whatever `min_spacing` asks, even 0, artifacts never overlap.
fn meets(a: &Artifact, base: [f64; 3], yaw: f64, size: [f64; 3]) -> bool {
    let (lo, hi) = (base[2] - 2.0 * PAD, base[2] + FLAT + size[2]);
    let (alo, ahi) = (a.position[2] - 2.0 * PAD, a.position[2] + a.size[2]);
    if hi <= alo || ahi <= lo {
        return false;
    }
    let rect = |c: [f64; 3], yaw: f64, size: [f64; 3]| {
        let (sin, cos) = yaw.sin_cos();
        let half = [0.5 * size[0] + PAD, 0.5 * size[1] + PAD];
        ([c[0], c[1]], [[cos, sin], [-sin, cos]], half)
    };
    let rects = [rect(a.position, a.yaw, a.size), rect(base, yaw, size)];
    let d = [rects[1].0[0] - rects[0].0[0], rects[1].0[1] - rects[0].0[1]];
    let dot = |u: [f64; 2], v: [f64; 2]| u[0] * v[0] + u[1] * v[1];
    // Apart along an axis when the centres are farther apart along it than the two
    // rectangles' half extents along it together.
    !rects.iter().flat_map(|r| r.1).any(|axis| {
        let reach: f64 = rects
            .iter()
            .map(|(_, axes, half)| {
                half[0] * dot(axes[0], axis).abs() + half[1] * dot(axes[1], axis).abs()
            })
            .sum();
        dot(d, axis).abs() >= reach
    })
}

/// The vertical lines over one tile and `reach` around it, `STEP` metres apart (finer for
/// small pitches), with what placement reads of each.
struct TileLines {
    cols: Columns,
    /// Each line's stretch of the tile's level: the lowest free stretch reaching 0.3 m above
    /// the nominal floor whose floor is below half the level height (moved up with the tile's
    /// floor on a hill).
    level_span: Vec<Option<[f64; 2]>>,
    /// With a sight to look for, every free stretch of each line: a quick look along a spot's
    /// line of sight before the exact one. Empty otherwise.
    free: Vec<Vec<[f64; 2]>>,
}

impl TileLines {
    fn around(
        world: &World,
        passages: &Passages,
        cell: Cell,
        reach: f64,
        with_free: bool,
    ) -> TileLines {
        let pitch = world.resolved.tile_pitch;
        let lh = world.resolved.level_height;
        let [cx, cy, nominal] = world.cell_position(cell);
        // Where the tile set lifted the tile's floor (a hill's tiles), the band moves up with it.
        let [low, high] = world.floor_lift(cell);
        // Most lines a tile's raster may have: 400 a side (finer for small pitches).
        let step = STEP.max(pitch / 400.0);
        let b = [
            cx - 0.5 * pitch - reach,
            cy - 0.5 * pitch - reach,
            cx + 0.5 * pitch + reach,
            cy + 0.5 * pitch + reach,
        ];
        let cols = Columns {
            x0: b[0],
            y0: b[1],
            step,
            nx: ((b[2] - b[0]) / step).ceil() as usize,
            ny: ((b[3] - b[1]) / step).ceil() as usize,
        };
        let rows = passages
            .raster_within(&cols, b, |_, spans, open| {
                spans
                    .iter()
                    .filter(|s| open.binary_search(&s.i).is_err())
                    .copied()
                    .collect::<Vec<Span>>()
            })
            .rows;
        let nx = cols.nx;
        let mut level_span: Vec<Option<[f64; 2]>> = vec![None; nx * cols.ny];
        for (j, row) in rows.iter().enumerate() {
            for s in row {
                let slot = &mut level_span[j * nx + s.i as usize];
                if slot.is_none()
                    && s.z1 >= nominal + low + 0.3
                    && s.z0 <= nominal + high + 0.5 * lh
                {
                    *slot = Some([s.z0, s.z1]);
                }
            }
        }
        let mut free: Vec<Vec<[f64; 2]>> = Vec::new();
        if with_free {
            free = vec![Vec::new(); nx * cols.ny];
            for (j, row) in rows.iter().enumerate() {
                for s in row {
                    free[j * nx + s.i as usize].push([s.z0, s.z1]);
                }
            }
        }
        TileLines {
            cols,
            level_span,
            free,
        }
    }

    /// The line nearest `(x, y)`, if it is on the raster.
    fn index(&self, x: f64, y: f64) -> Option<usize> {
        let c = &self.cols;
        let i = ((x - c.x0) / c.step).floor();
        let j = ((y - c.y0) / c.step).floor();
        (i >= 0.0 && j >= 0.0 && (i as usize) < c.nx && (j as usize) < c.ny)
            .then(|| j as usize * c.nx + i as usize)
    }

    /// The lines of the tile itself with a stretch of its level: where a spot may be centred.
    fn candidates(&self, world: &World, cell: Cell) -> Vec<usize> {
        let c = &self.cols;
        (0..c.nx * c.ny)
            .filter(|&k| {
                self.level_span[k].is_some()
                    && world.cell_at(cell.level, c.x(k % c.nx), c.y(k / c.nx)) == Some(cell)
            })
            .collect()
    }

    /// The lowest and highest floor under a footprint of `size` centred at `(x, y)` turned by
    /// `yaw`, sampled on lines at most a raster step apart: `None` unless every sample has a
    /// stretch of the level, the floors are within `FLAT` and the box plus `CLEAR` is free.
    fn footing(&self, x: f64, y: f64, yaw: f64, size: [f64; 3]) -> Option<(f64, f64)> {
        let step = self.cols.step;
        let samples = |n: f64| ((n / step).ceil() as usize).max(1) + 1;
        let (su, sv) = (samples(size[0]), samples(size[1]));
        let (sin, cos) = yaw.sin_cos();
        let mut lines = Vec::with_capacity(su * sv);
        for u in 0..su {
            for v in 0..sv {
                let lx = size[0] * (u as f64 / (su - 1) as f64 - 0.5);
                let ly = size[1] * (v as f64 / (sv - 1) as f64 - 0.5);
                match self.index(x + cos * lx - sin * ly, y + sin * lx + cos * ly) {
                    Some(l) if self.level_span[l].is_some() => lines.push(l),
                    _ => return None,
                }
            }
        }
        let span = |l: usize| self.level_span[l].expect("checked");
        let (lo, hi) = lines
            .iter()
            .map(|&l| span(l)[0])
            .fold((f64::MAX, f64::MIN), |(a, b), f| (a.min(f), b.max(f)));
        if hi - lo > FLAT {
            return None;
        }
        let top = hi + size[2] + CLEAR;
        if lines.iter().any(|&l| span(l)[1] < top) {
            return None;
        }
        Some((lo, hi))
    }

    /// Whether the rock around a spot on line `k` standing on `floor` is as its rule wants
    /// it, at the probe height: none within `GAP` of the footprint's circle, and for `wall`
    /// some within `GAP + WALL`, for `floor` none within `GAP + OPEN`. `ring` holds the line
    /// offsets as far as the rule looks, nearest first.
    fn rock_as_ruled(
        &self,
        k: usize,
        floor: f64,
        rule: Placement,
        ring: &[(f64, i64, i64)],
    ) -> bool {
        let (nx, ny) = (self.cols.nx, self.cols.ny);
        let z = floor + PROBE_Z;
        let rock = |l: usize| !self.level_span[l].is_some_and(|s| s[0] <= z && z <= s[1]);
        let (ci, cj) = ((k % nx) as i64, (k / nx) as i64);
        // The nearest rock line, looked for only as far as the rule needs.
        let mut nearest = f64::INFINITY;
        for &(d, di, dj) in ring {
            let (i, j) = (ci + di, cj + dj);
            let outside = i < 0 || j < 0 || i as usize >= nx || j as usize >= ny;
            if outside || rock(j as usize * nx + i as usize) {
                nearest = d;
                break;
            }
        }
        nearest > GAP
            && match rule {
                Placement::Wall => nearest <= GAP + WALL,
                Placement::Floor => nearest > GAP + OPEN,
                Placement::DeadEnd | Placement::Chamber => true,
            }
    }

    /// Whether each point looked at on the line from `eye` to `target` is in rock, by the
    /// raster (each point on its nearest line; a point off the raster counts free).
    fn blocked(&self, eye: [f64; 3], target: [f64; 3]) -> Vec<bool> {
        sight::samples(eye, target)
            .iter()
            .map(|p| {
                self.index(p[0], p[1])
                    .is_some_and(|l| !self.free[l].iter().any(|s| s[0] <= p[2] && p[2] <= s[1]))
            })
            .collect()
    }
}

/// Line offsets around a spot by their distance beyond the footprint's circle (radius
/// `half_diag`), nearest first, as far as any rule looks.
fn ring(reach: f64, step: f64, half_diag: f64) -> Vec<(f64, i64, i64)> {
    let r = (reach / step).ceil() as i64;
    let mut ring: Vec<(f64, i64, i64)> = (-r..=r)
        .flat_map(|dj| (-r..=r).map(move |di| (di, dj)))
        .map(|(di, dj)| {
            (
                ((di * di + dj * dj) as f64).sqrt() * step - half_diag,
                di,
                dj,
            )
        })
        .filter(|o| o.0 <= GAP + WALL.max(OPEN))
        .collect();
    ring.sort_by(|a, b| a.0.total_cmp(&b.0).then((a.1, a.2).cmp(&(b.1, b.2))));
    ring
}

/// The base height of a footprint of `size` centred at `xy` turned by `yaw`, whose raster
/// floors are `(lo, hi)`: the raster's lines are a step apart, and the floor between them,
/// under the footprint's exact corners and edges, may stand a little higher. Cast there every
/// `EXACT` metres at most (quarters of each side included) and stand on the highest, `LIFT`
/// above it; `None` when a cast finds no floor near, the floor varies more than `FLAT`, or the
/// box plus `CLEAR` is not free.
fn exact_base(
    passages: &Passages,
    xy: [f64; 2],
    yaw: f64,
    size: [f64; 3],
    (lo, hi): (f64, f64),
) -> Option<f64> {
    let (sin, cos) = yaw.sin_cos();
    let exact = |n: f64| 4 * ((n / (4.0 * EXACT)).ceil() as usize).max(1) + 1;
    let (eu, ev) = (exact(size[0]), exact(size[1]));
    let mut points = Vec::with_capacity(eu * ev);
    for u in 0..eu {
        for v in 0..ev {
            let lx = size[0] * (u as f64 / (eu - 1) as f64 - 0.5);
            let ly = size[1] * (v as f64 / (ev - 1) as f64 - 0.5);
            points.push([xy[0] + cos * lx - sin * ly, xy[1] + sin * lx + cos * ly]);
        }
    }
    let stretches: Vec<Option<[f64; 2]>> = passages
        .columns_at(&points)
        .into_iter()
        .map(|column| {
            column
                .into_iter()
                .find(|s| s[0] <= hi + FLAT && hi + FLAT <= s[1])
        })
        .collect();
    let (low, exact) = stretches
        .iter()
        .map(|s| s.map(|s| s[0]))
        .try_fold((lo, hi), |(a, b), f| f.map(|f| (a.min(f), b.max(f))))?;
    let base = exact + LIFT;
    if base - low > FLAT
        || stretches
            .iter()
            .flatten()
            .any(|s| s[1] < base + size[2] + CLEAR)
    {
        return None;
    }
    Some(base)
}
