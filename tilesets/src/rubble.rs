//! Rubble fields and drops (`[hazards] rubble`, `drops`) in the procedural tile sets: more
//! solid rock blobs and a pit in the world field ([`crate::field`]), so they are part of the
//! one closed surface, visual and collision alike, and seamless across tiles.
//!
//! Which tiles get one, and on which arm (the half-corridor from the tile's centre toward one
//! opening), the layout says ([`Layout::floor_hazards`], resolved from `[hazards]` when the
//! layout was made: a tile set never reads the pipeline); the rest is drawn here from the
//! world's `"rubble"` stream keyed by the cell, so every tile evaluating a neighbour's field
//! places the same rocks. With `w` the passage's nominal width, `p` the tile pitch and `h` the
//! collision lattice's spacing (pitch / `collision_resolution`):
//!
//! - **Rubble**: rocks (spheres with their centre half a radius above the floor, roughened by
//!   a third of the wall relief) over the arm from `0.08 p` to `0.42 p` from the centre and
//!   across the whole width `w`, on the columns of the collision lattice (every `k`-th, `k h`
//!   closest to `1.6 r0`, at most 64 rocks a field), one rock a column, so neighbouring rocks
//!   touch or nearly and a robot drives around a field, not through it. Radii are
//!   `r0 x [0.8, 1.25]` with `r0 = max(0.08 w, 0.5 h)`, and at least enough for a rock's top
//!   to pass the first lattice plane above the floor (`(plane - floor + relief + 0.15) / 1.5`):
//!   a rock between the collision lattice's points would flatten to a bump. The collision
//!   lattice thus sets the smallest rock: on the cave preset (25 m tiles, `h` = 2.1 m) rocks
//!   are boulders of 1.6-1.7 m radius, up to 2.5 m high; a finer `collision_resolution`
//!   makes smaller rocks (1 m lattice: 0.9 m). Rocks whose centre is not on the passage's
//!   floor (they would be buried in the wall) are left out. With `rubble_passable = true`
//!   (the default) a lane `rubble_gap` wide runs the whole field, free of rocks (with their
//!   relief), centred `max(0, 0.25 w - gap / 2)` to one side of the axis (the side drawn per
//!   tile); with `false` the rocks cover the whole floor. A field with no room for a rock
//!   beside the lane (a passage too narrow for the gap and a rock) is not made, nor listed.
//! - **Drop**: a pit with vertical walls, a disc of radius `R = min(0.3 w, max(0.2 w, 0.75 h))`
//!   centred `0.25 p` along the arm and `0.3 w - R` to one side, `D = clamp(0.3 x height, 0.5,
//!   3)` metres deep, leaving the rest of the floor beside it. The levels' blocks reach `D`
//!   plus two lattice cells below the floor in worlds with drops, so the pit stays closed.
//!
//! The ground truth gets each as a [`HazardRegion`] (rocks' centres and radii, the lane, the
//! pit's rim and depth), which the tile reports in `TileGeometry::hazards`.

use subtgraph_core::Layout;
use subtgraph_core::grid::Cell;
use subtgraph_core::hazards::{FloorHazard, HazardRegion};
use subtgraph_core::rng::WorldRng;

use crate::noise::Noise;
use crate::passage::{Passage, Profile};

/// Most rocks in one rubble field; a wider passage gets its rocks spaced wider.
pub const MAX_FIELD_ROCKS: usize = 64;

/// A pit: solid rock outside the vertical cylinder of radius `r` around `c` from `bottom` to
/// `top` (above the floor, where it joins the passage).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pit {
    /// Centre in the plane.
    pub c: [f64; 2],
    /// Radius.
    pub r: f64,
    /// The pit's floor.
    pub bottom: f64,
    /// Where the pit's cylinder ends, above the passage's floor.
    pub top: f64,
}

impl Pit {
    /// The field of the pit alone: negative inside.
    pub fn value(&self, p: [f64; 3]) -> f64 {
        let d = ((p[0] - self.c[0]).powi(2) + (p[1] - self.c[1]).powi(2)).sqrt();
        (d - self.r).max(self.bottom - p[2]).max(p[2] - self.top)
    }
}

/// One tile's rubble field or drop: what the field adds, and what the ground truth says.
#[derive(Clone, Debug, PartialEq)]
pub struct TileHazard {
    /// Rubble rocks: centre and radius.
    pub rocks: Vec<([f64; 3], f64)>,
    /// The pit of a drop.
    pub pit: Option<Pit>,
    /// The region, as the ground truth has it.
    pub region: HazardRegion,
}

/// How deep a drop's pit is for a passage `height` metres high (the passage's nominal height,
/// known before the rest of [`Passage`]: the levels' blocks are sized from it).
pub fn pit_depth(height: f64) -> f64 {
    (0.3 * height).clamp(0.5, 3.0)
}

/// Whether the world asks for drops (its levels' blocks then reach deeper).
pub fn has_drops(world: &Layout) -> bool {
    world.floor_hazards.drops
}

/// The rubble field or drop of `cell`, if it has one.
///
/// Rubble rocks whose centre is not on the passage's floor (the profile, at the local width,
/// not free 0.3 m above the floor there) are left out: they would be buried in the wall.
pub fn tile_hazard(
    world: &Layout,
    cell: Cell,
    passage: &Passage,
    profile: &dyn Profile,
) -> Option<TileHazard> {
    let (kind, arm) = world.floor_hazards.at(cell)?;
    let tile = world.tiles.get(cell).as_ref()?;
    let pitch = world.resolved.tile_pitch;
    // A squeeze is already as tight as `min_clearance` allows: no rubble or drop there.
    if passage
        .rooms
        .squeeze(world.resolved.seed, cell, tile.kind, pitch)
        .is_some()
    {
        return None;
    }
    let key = ((cell.level as u64) << 40) | ((cell.row as u64) << 20) | cell.col as u64;
    let mut rng = WorldRng::new(world.resolved.seed, "rubble", key);
    let side = if rng.coin() { 1.0 } else { -1.0 };
    let site = Site {
        world,
        cell,
        passage,
        // The arm's stretch of the passage's own centreline (bent or meandering, as the field
        // has it: `crate::bends`).
        arm_line: ArmLine::new(world, cell, tile.openings, passage, arm, key),
        floor: world.cell_position(cell)[2],
        waves: passage.slope.level(cell.level),
        side,
    };
    match kind {
        FloorHazard::Rubble => rubble_field(&site, profile, &mut rng),
        FloorHazard::Drop => Some(drop_pit(&site)),
    }
}

/// Where a tile's rubble field or drop goes: its passage, the arm's centreline, and the side
/// of the axis drawn for it.
struct Site<'a> {
    world: &'a Layout,
    cell: Cell,
    passage: &'a Passage,
    arm_line: ArmLine,
    /// The level's nominal floor.
    floor: f64,
    /// How the level's floor rises and falls (`crate::slope`).
    waves: crate::slope::Waves,
    /// `1` or `-1`: which side of the axis the lane (rubble) or the pit (drop) is on.
    side: f64,
}

impl Site<'_> {
    /// The floor under a point: the nominal floor lifted by the level's slope.
    fn floor_at(&self, px: f64, py: f64) -> f64 {
        self.floor + self.waves.lift(px, py)
    }
}

/// A rubble field on the site's arm (see the module's doc), drawing its rocks' radii from
/// `rng`; `None` when no rock fits beside the lane.
fn rubble_field(site: &Site, profile: &dyn Profile, rng: &mut WorldRng) -> Option<TileHazard> {
    let Site {
        world,
        cell,
        passage,
        ref arm_line,
        side,
        ..
    } = *site;
    let hazards = &world.floor_hazards;
    let kind = FloorHazard::Rubble;
    let pitch = world.resolved.tile_pitch;
    let floor_at = |px: f64, py: f64| site.floor_at(px, py);
    let w = passage.width;
    let h = passage.hazard_lattice;
    let r0 = (0.08 * w).max(0.5 * h);
    let relief = 0.3 * passage.roughness;
    // The first collision lattice plane above the floor (with its rubble): a rock
    // whose centre column is solid there is in the collision mesh at its height.
    let r_min = |floor: f64| {
        if h > 0.0 {
            let plane = (((floor + passage.floor_roughness) / h).floor() + 1.0) * h;
            (plane - floor + relief + 0.15) / 1.5
        } else {
            0.0
        }
    };
    let (s0, s1) = (0.08 * pitch, 0.42 * pitch);
    let samples = arm_line.samples(s0, s1, 48);
    let gap = hazards.rubble_passable.then(|| {
        let c = side * (0.25 * w - 0.5 * hazards.rubble_gap).max(0.0);
        (c - 0.5 * hazards.rubble_gap, c + 0.5 * hazards.rubble_gap)
    });
    // The local width, as `LocalField::column` has it.
    let sizes = Noise::new(world.resolved.seed, "sizes");
    let vs = 1.0 / passage.variation_scale;
    let on_floor = |px: f64, py: f64, l: f64| {
        let width = w * (1.0 + passage.width_variation * sizes.at(px * vs, py * vs, 0.5));
        profile.section(l.abs(), 0.3, width, passage.height) < 0.0
    };
    // Candidate centres: a grid about `1.6 r0` apart; on lattice columns (every
    // `k`-th, from the world's origin) when the tile set has a collision lattice, so
    // the field has no hole where a column was skipped.
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(q, _) in &samples {
        x0 = x0.min(q[0] - 0.5 * w);
        x1 = x1.max(q[0] + 0.5 * w);
        y0 = y0.min(q[1] - 0.5 * w);
        y1 = y1.max(q[1] + 0.5 * w);
    }
    let unit = if h > 0.0 { h } else { 0.25 * r0 };
    let mut k = ((1.6 * r0 / unit).round() as i64).max(1);
    let columns = |k: i64| {
        let span = |a: f64, b: f64| {
            let (i0, i1) = ((a / unit).ceil() as i64, (b / unit).floor() as i64);
            (i0..=i1).filter(move |i| i.rem_euclid(k) == 0)
        };
        span(x0, x1)
            .flat_map(|i| span(y0, y1).map(move |j| (i, j)))
            .collect::<Vec<_>>()
    };
    let mut grid = columns(k);
    while grid.len() > MAX_FIELD_ROCKS {
        k += 1;
        grid = columns(k);
    }
    let mut rocks = Vec::new();
    for (i, j) in grid {
        // Every draw is made whether the rock is kept or not, so the lane does not
        // change the other rocks.
        let drawn = r0 * rng.float_in(0.8, 1.25);
        let (px, py) = (i as f64 * unit, j as f64 * unit);
        let Some(l) = offset(&samples, [px, py]) else {
            continue;
        };
        let here = floor_at(px, py);
        let r = drawn.max(r_min(here));
        if let Some((g0, g1)) = gap {
            if l + r + relief > g0 && l - r - relief < g1 {
                continue;
            }
        }
        if !on_floor(px, py, l) {
            continue;
        }
        rocks.push(([px, py, here + 0.5 * r], r));
    }
    let mut bounds = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
    let mut top = f64::MIN;
    let mut low = f64::MAX;
    for &(c, r) in &rocks {
        low = low.min(c[2] - 0.5 * r);
        bounds = [
            bounds[0].min(c[0] - r),
            bounds[1].min(c[1] - r),
            bounds[2].max(c[0] + r),
            bounds[3].max(c[1] + r),
        ];
        top = top.max(c[2] + r);
    }
    if rocks.is_empty() {
        // No room for a rock beside the lane: no field.
        return None;
    }
    let gap = gap.map(|(g0, g1)| {
        let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
        for &(q, d) in &samples {
            for g in [g0, g1] {
                let e = [q[0] - d[1] * g, q[1] + d[0] * g];
                b = [
                    b[0].min(e[0]),
                    b[1].min(e[1]),
                    b[2].max(e[0]),
                    b[3].max(e[1]),
                ];
            }
        }
        b
    });
    Some(TileHazard {
        region: HazardRegion {
            kind,
            cell,
            bounds,
            floor_z: low,
            z: [low, top],
            gap,
            rocks: rocks.iter().map(|&(c, r)| [c[0], c[1], c[2], r]).collect(),
        },
        rocks,
        pit: None,
    })
}

/// A drop's pit on the site's arm (see the module's doc).
fn drop_pit(site: &Site) -> TileHazard {
    let Site {
        world,
        cell,
        passage,
        ref arm_line,
        side,
        ..
    } = *site;
    let kind = FloorHazard::Drop;
    let pitch = world.resolved.tile_pitch;
    let floor_at = |px: f64, py: f64| site.floor_at(px, py);
    let w = passage.width;
    let h = passage.hazard_lattice;
    let r = (0.2 * w).max(0.75 * h).min(0.3 * w);
    let (q, d) = arm_line.samples(0.25 * pitch, 0.25 * pitch, 1)[0];
    let off = side * (0.3 * w - r).max(0.0);
    let c = [q[0] - d[1] * off, q[1] + d[0] * off];
    let depth = pit_depth(passage.height);
    let floor = floor_at(c[0], c[1]);
    let pit = Pit {
        c,
        r,
        bottom: floor - depth,
        top: floor + passage.floor_roughness + 0.3,
    };
    TileHazard {
        rocks: Vec::new(),
        pit: Some(pit),
        region: HazardRegion {
            kind,
            cell,
            bounds: [c[0] - r, c[1] - r, c[0] + r, c[1] + r],
            floor_z: floor,
            z: [floor - depth, floor],
            gap: None,
            rocks: Vec::new(),
        },
    }
}

/// The stretch of a tile's centreline from its middle toward one opening (`arm`), as the
/// field lays it ([`crate::bends::centrelines`]): a half-corridor, or half of a corner's arc or
/// a straight's meander.
struct ArmLine {
    line: crate::bends::Centreline,
    /// The centreline parameter at the tile's middle and at the arm's face.
    t: [f64; 2],
    /// Metres from the middle to the face.
    half: f64,
}

impl ArmLine {
    fn new(
        world: &Layout,
        cell: Cell,
        openings: u8,
        passage: &Passage,
        arm: subtgraph_core::grid::Direction,
        key: u64,
    ) -> Self {
        use subtgraph_core::grid::Direction;
        let half = 0.5 * world.resolved.tile_pitch;
        let [x, y, _] = world.cell_position(cell);
        let face = |d: Direction| {
            let (sr, sc) = d.step();
            [x + f64::from(sc) * half, y - f64::from(sr) * half]
        };
        let ends: Vec<[f64; 2]> = Direction::ALL
            .into_iter()
            .filter(|d| openings & d.bit() != 0)
            .map(face)
            .collect();
        let amp = crate::bends::meander(world.resolved.seed, key, passage.meander);
        let lines = crate::bends::centrelines([x, y], &ends, passage.bends, amp);
        let f = face(arm);
        let near = |p: [f64; 2]| (p[0] - f[0]).abs() + (p[1] - f[1]).abs() < 1e-6;
        for &line in &lines {
            let (start, _) = line.at(0.0);
            let (end, _) = line.at(1.0);
            let t = match line {
                crate::bends::Centreline::Segment { .. } if near(end) => [0.0, 1.0],
                crate::bends::Centreline::Segment { .. } => continue,
                _ if near(end) => [0.5, 1.0],
                _ if near(start) => [0.5, 0.0],
                _ => continue,
            };
            return ArmLine { line, t, half };
        }
        // Not reached for straight and corner tiles; a straight half-corridor otherwise.
        ArmLine {
            line: crate::bends::Centreline::Segment { a: [x, y], b: f },
            t: [0.0, 1.0],
            half,
        }
    }

    /// `n` points from `s0` to `s1` metres from the middle, each with the unit direction
    /// away from the middle.
    fn samples(&self, s0: f64, s1: f64, n: usize) -> Vec<([f64; 2], [f64; 2])> {
        (0..n)
            .map(|i| {
                let s = if n > 1 {
                    s0 + (s1 - s0) * i as f64 / (n - 1) as f64
                } else {
                    s0
                };
                let t = self.t[0] + (self.t[1] - self.t[0]) * (s / self.half).clamp(0.0, 1.0);
                let (q, d) = self.line.at(t);
                let sign = if self.t[1] >= self.t[0] { 1.0 } else { -1.0 };
                (q, [d[0] * sign, d[1] * sign])
            })
            .collect()
    }
}

/// Signed metres of `p` to the left of the sampled centreline (`None` beyond its ends).
fn offset(samples: &[([f64; 2], [f64; 2])], p: [f64; 2]) -> Option<f64> {
    let (j, &(q, d)) = samples.iter().enumerate().min_by(|a, b| {
        let da = (a.1.0[0] - p[0]).powi(2) + (a.1.0[1] - p[1]).powi(2);
        let db = (b.1.0[0] - p[0]).powi(2) + (b.1.0[1] - p[1]).powi(2);
        da.total_cmp(&db)
    })?;
    let v = [p[0] - q[0], p[1] - q[1]];
    let along = v[0] * d[0] + v[1] * d[1];
    if (j == 0 && along < 0.0) || (j + 1 == samples.len() && along > 0.0) {
        return None;
    }
    Some(-v[0] * d[1] + v[1] * d[0])
}
