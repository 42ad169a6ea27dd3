//! The world-wide field a procedural tile set meshes: negative in the passages, positive in
//! the rock, the same function of world position whichever tile evaluates it.
//!
//! Every occupied cell contributes its passage's centrelines ([`bends`]: a
//! corner's quarter circle, a straight's meander, or half-corridors from its centre to each
//! opening; a dead end is one half-corridor, rounded at the centre), the foot of a shaft adds a
//! vertical passage to the level above, and rocks are solid blobs on the floor. Floors are
//! lifted by the level's smooth slope ([`slope`](crate::slope)), a function of the horizontal
//! position, so shafts and rocks stand on the lifted floor. Each contribution acts only in
//! its cell's block widened by half a pitch, so a tile needs only its 3 x 3 neighbourhood on
//! its own level and the levels beside it, and two tiles evaluating a point on their shared
//! face compute exactly the same number.

use subtgraph_core::Layout;
use subtgraph_core::grid::{Cell, Direction};
use subtgraph_core::rng::WorldRng;
use subtgraph_core::tile::TileKind;

use crate::bends::{self, Bends, Centreline};
use crate::chambers::{Chamber, Rooms, Squeeze};
use crate::noise::Noise;
use crate::slope::{Slope, Waves};

/// Material indices used by the procedural tile sets.
pub mod material {
    /// Walls and ceiling.
    pub const WALL: u8 = 0;
    /// The floor.
    pub const FLOOR: u8 = 1;
    /// Rock piles and boulders.
    pub const ROCK: u8 = 2;
    /// Striated bands on the walls.
    pub const STRIATED: u8 = 3;
}

/// The shape of a passage across its axis.
pub trait Profile: Send + Sync {
    /// Negative inside the passage: `u >= 0` metres sideways from the axis, `v` metres above
    /// the floor, for a passage `width` wide and `height` high here.
    fn section(&self, u: f64, v: f64, width: f64, height: f64) -> f64;
}

/// The knobs shared by the procedural tile sets, in metres unless said otherwise.
#[derive(Clone, Debug, PartialEq)]
pub struct Passage {
    /// Nominal width.
    pub width: f64,
    /// Nominal floor-to-ceiling height.
    pub height: f64,
    /// Width changes along the passage, as a fraction of the width.
    pub width_variation: f64,
    /// Height changes along the passage, as a fraction of the height.
    pub height_variation: f64,
    /// Distance over which width and height change.
    pub variation_scale: f64,
    /// Amplitude of wall relief.
    pub roughness: f64,
    /// Size of wall relief features.
    pub roughness_scale: f64,
    /// Amplitude of floor rubble.
    pub floor_roughness: f64,
    /// Rocks per tile (fractions are a probability).
    pub rocks: f64,
    /// Typical rock radius.
    pub rock_size: f64,
    /// Shaft radius as a fraction of the width.
    pub shaft_radius: f64,
    /// Whether walls get striated bands.
    pub striations: bool,
    /// Chambers, squeezes and the clearance they keep (see [`crate::chambers`]).
    pub rooms: Rooms,
    /// How passages turn at corner cells (see [`bends`]).
    pub bends: Bends,
    /// Greatest sideways meander of a straight cell's passage, metres.
    pub meander: f64,
    /// Default `[low, high]` range of the floors' steepest grade, degrees (`[tileset] grade`).
    pub grade: [f64; 2],
    /// How floors rise and fall (see [`slope`](crate::slope)); set for a world from `grade`.
    pub slope: Slope,
    /// Spacing of the collision lattice: rubble rocks and pits are never smaller, so the
    /// collision mesh holds them (0: no minimum).
    pub hazard_lattice: f64,
}

impl Default for Passage {
    /// The cave's passage: moderate width and height changes, rough walls, a little floor
    /// rubble, striations. A procedural tile set states only what differs (`..Passage::default()`);
    /// `width` and `height` are 0, taken from the tile set's style and parameters.
    fn default() -> Self {
        Passage {
            width: 0.0,
            height: 0.0,
            width_variation: 0.22,
            height_variation: 0.2,
            variation_scale: 0.9,
            roughness: 0.09,
            roughness_scale: 0.45,
            floor_roughness: 0.03,
            rocks: 0.0,
            rock_size: 0.12,
            shaft_radius: 0.3,
            striations: true,
            rooms: Rooms::default(),
            bends: Bends::Round,
            meander: 0.08,
            grade: [6.0, 12.0],
            slope: Slope::flat(),
            hazard_lattice: 0.0,
        }
    }
}

/// A passage contribution, with the box it acts in.
#[derive(Clone, Debug)]
enum Feature {
    Corridor {
        line: Centreline,
        floor: f64,
        level: usize,
        squeeze: Option<Squeeze>,
    },
    Chamber {
        chamber: Chamber,
        level: usize,
    },
    Shaft {
        c: [f64; 2],
        z0: f64,
        z1: f64,
        r: f64,
    },
    /// A drop's pit (`crate::rubble`).
    Pit(crate::rubble::Pit),
    /// A ramp's spiral (`crate::ramp`).
    Ramp {
        helix: Box<crate::ramp::Helix>,
        /// The slopes' lift at the spiral's foot and top ([`crate::ramp::Helix::lift_at`]).
        lifts: [f64; 2],
    },
}

#[derive(Clone, Debug)]
struct Bounded<T> {
    lo: [f64; 3],
    hi: [f64; 3],
    item: T,
}

impl<T> Bounded<T> {
    fn contains(&self, p: [f64; 3]) -> bool {
        (0..3).all(|d| p[d] >= self.lo[d] && p[d] <= self.hi[d])
    }
}

#[derive(Clone, Debug)]
struct Rock {
    c: [f64; 3],
    r: f64,
}

/// Value of a contribution that does not act at a point: larger than any real value.
const FAR: f64 = 1e9;

/// The field around one tile.
pub struct LocalField<'a> {
    passage: &'a Passage,
    profile: &'a dyn Profile,
    features: Vec<Bounded<Feature>>,
    rocks: Vec<Bounded<Rock>>,
    /// The floor waves of levels `lmin ..= lmin + 2` (flat beyond the world's levels).
    waves: [Waves; 3],
    lmin: usize,
    walls: Noise,
    sizes: Noise,
    rubble: Noise,
    bands: Noise,
}

/// Vertical layout of a world's levels for the lattice.
#[derive(Clone, Copy, Debug)]
pub struct Levels {
    /// Metres between levels.
    pub height: f64,
    /// How far below its floor a level's block starts: the rock under the floor, or under a
    /// drop's pit (`[hazards] drops`) when the world has drops.
    pub below_floor: f64,
    /// The rock kept between a passage's highest ceiling and the top of its level's block
    /// (the next level's `below_floor` starts there): the floor's rock without drops. A pit
    /// sinks into the block of its own level, not into the ceiling of the level below.
    pub above_ceiling: f64,
    /// Metres between the collision lattice's points (ramps keep two of them of rock
    /// between their turns).
    pub coarse: f64,
}

impl Levels {
    /// The height a level's passage may take from its floor to its highest ceiling (floors
    /// lifted by slopes included): the spacing of levels less the rock under the next level's
    /// floor (or pit) and the rock above this level's ceiling.
    pub fn head(&self) -> f64 {
        self.height - (self.below_floor + self.above_ceiling)
    }

    /// The z range `[lo, hi]` of level `l`'s block.
    pub fn block_z(&self, l: usize) -> (f64, f64) {
        let f = l as f64 * self.height;
        (f - self.below_floor, f + self.height - self.below_floor)
    }
}

impl<'a> LocalField<'a> {
    /// The contributions acting on the block of `cell` (its 3 x 3 neighbourhood on levels
    /// `level - 1 ..= level + 1`), for a lattice of spacing `lattice` metres.
    ///
    /// Each contribution acts in a box around it, wide enough that any lattice point within one
    /// lattice edge of a point it makes negative is inside (so edges crossing the surface are
    /// interpolated between true values), and never wider than half a pitch beyond its cell.
    pub fn around(
        world: &Layout,
        cell: Cell,
        passage: &'a Passage,
        profile: &'a dyn Profile,
        levels: Levels,
        lattice: f64,
    ) -> Self {
        let seed = world.resolved.seed;
        let pitch = world.resolved.tile_pitch;
        let half = 0.5 * pitch;
        let mut features = Vec::new();
        let mut rocks = Vec::new();
        let margin = 3.0 * lattice;
        let reach =
            (0.5 * passage.width * (1.0 + passage.width_variation) + passage.roughness + margin)
                .min(half);
        let top = passage.height * (1.0 + passage.height_variation)
            + passage.roughness
            + passage.floor_roughness
            + margin;
        let occ = &world.occupancy;
        let lmin = cell.level.saturating_sub(1);
        let lmax = (cell.level + 1).min(occ.levels() - 1);
        let waves = [0, 1, 2].map(|i| {
            if lmin + i < occ.levels() {
                passage.slope.level(lmin + i)
            } else {
                Waves::FLAT
            }
        });
        let lift = |l: usize, c: [f64; 2]| match waves.get(l - lmin) {
            Some(w) => w.lift(c[0], c[1]),
            // The landing of a shaft from the level above this tile's.
            None => passage.slope.level(l).lift(c[0], c[1]),
        };
        let amp = passage.slope.amp;
        for l in lmin..=lmax {
            for dr in -1i64..=1 {
                for dc in -1i64..=1 {
                    let (r, c) = (cell.row as i64 + dr, cell.col as i64 + dc);
                    if r < 0 || c < 0 || r as usize >= occ.rows() || c as usize >= occ.cols() {
                        continue;
                    }
                    let n = Cell::new(l, r as usize, c as usize);
                    let Some(tile) = world.tiles.get(n) else {
                        continue;
                    };
                    let [x, y, floor] = world.cell_position(n);
                    let (z0, z1) = levels.block_z(l);
                    let (zlo, zhi) = (z0, (floor + amp + top).min(z1));
                    let mut ends: Vec<[f64; 2]> = Direction::ALL
                        .into_iter()
                        .filter(|d| tile.openings & d.bit() != 0)
                        .map(|d| {
                            let (sr, sc) = d.step();
                            [x + f64::from(sc) * half, y - f64::from(sr) * half]
                        })
                        .collect();
                    if ends.is_empty() {
                        ends.push([x, y]);
                    }
                    // A ramp's end: its lead replaces the half-corridor of the ramp's opening.
                    let ramp = crate::ramp::shaft_of(world, n).and_then(|s| {
                        let sizing =
                            crate::ramp::Sizing::of(world, passage, lattice, levels.coarse);
                        crate::ramp::plan(world, s, &sizing)
                            .ok()
                            .map(|h| (s.up == n, h))
                    });
                    let has_ramp = ramp.is_some();
                    let mut leads = Vec::new();
                    if let Some((foot, h)) = &ramp {
                        let (a, b) = h.leads()[usize::from(!*foot)];
                        ends.retain(|e| (e[0] - b[0]).abs() + (e[1] - b[1]).abs() > 1e-6);
                        leads.push(Centreline::Segment { a, b });
                    }
                    let (chamber, squeeze) =
                        crate::chambers::of_cell(world, n, tile.kind, passage, levels, lattice);
                    if let Some(ch) = chamber {
                        let zhi = floor
                            + amp
                            + ch.top(passage.height_variation)
                            + passage.roughness
                            + passage.floor_roughness
                            + margin;
                        features.push(Bounded {
                            lo: [x - half, y - half, zlo],
                            hi: [x + half, y + half, zhi.min(z1)],
                            item: Feature::Chamber {
                                chamber: ch,
                                level: l,
                            },
                        });
                    }
                    let key = ((l as u64) << 40) | ((n.row as u64) << 20) | n.col as u64;
                    let sway = bends::meander(seed, key, passage.meander);
                    // A ramp cell whose only opening is the ramp's has no half-corridor.
                    let mut lines = if ends.is_empty() {
                        Vec::new()
                    } else {
                        bends::centrelines([x, y], &ends, passage.bends, sway)
                    };
                    lines.extend(leads);
                    for &line in &lines {
                        let (lo, hi) = line.bounds();
                        features.push(Bounded {
                            lo: [lo[0] - reach, lo[1] - reach, zlo],
                            hi: [hi[0] + reach, hi[1] + reach, zhi],
                            item: Feature::Corridor {
                                line,
                                floor,
                                level: l,
                                squeeze,
                            },
                        });
                    }
                    if let Some((true, h)) = ramp {
                        let [(a0, _), (a1, _)] = h.leads();
                        let lifts = [lift(l, a0), lift(l + 1, a1)];
                        let (lo, mut hi) = h.bounds(margin + passage.roughness);
                        hi[2] += lifts[0].max(lifts[1]);
                        features.push(Bounded {
                            lo,
                            hi,
                            item: Feature::Ramp {
                                helix: Box::new(h),
                                lifts,
                            },
                        });
                    } else if tile.kind == TileKind::ShaftUp
                        && l + 1 < occ.levels()
                        && crate::ramp::shaft_of(world, n).is_none()
                    {
                        let above = floor + levels.height + lift(l + 1, [x, y]);
                        let foot = floor + lift(l, [x, y]);
                        let r = passage.shaft_radius * passage.width;
                        let w = (r + passage.roughness + margin).min(half);
                        features.push(Bounded {
                            lo: [x - w, y - w, foot],
                            hi: [x + w, y + w, above + 0.5 + margin],
                            item: Feature::Shaft {
                                c: [x, y],
                                z0: foot + 0.5,
                                z1: above + 0.5,
                                r,
                            },
                        });
                    }
                    let mut rng = WorldRng::new(seed, "rocks", key);
                    let count = passage.rocks.floor() as u32
                        + u32::from(rng.unit() < passage.rocks.fract());
                    // No rocks in a squeeze (the passage there is already as tight as allowed)
                    // nor in a ramp's cells.
                    let count = if squeeze.is_some() || has_ramp || lines.is_empty() {
                        0
                    } else {
                        count
                    };
                    for _ in 0..count {
                        let line = lines[rng.below(lines.len() as u64) as usize];
                        let ([ax, ay], [dx, dy]) = line.at(rng.float_in(0.15, 0.85));
                        // Sideways toward a wall, on the floor.
                        let side = if rng.coin() { 1.0 } else { -1.0 };
                        let radius = passage.rock_size * rng.float_in(0.6, 1.2);
                        // Out of the robot's box about the axis (`min_clearance`).
                        let off = rng.float_in(0.15, 0.35).max(
                            (0.5 * passage.rooms.min_clearance[0] + 1.3 * radius + 0.5)
                                / passage.width,
                        ) * passage.width
                            * side;
                        let (cx, cy) = (ax - dy * off, ay + dx * off);
                        let c = [cx, cy, floor + lift(l, [cx, cy]) + 0.15 * radius];
                        let w = radius + passage.roughness + margin;
                        rocks.push(Bounded {
                            lo: [c[0] - w, c[1] - w, c[2] - w],
                            hi: [c[0] + w, c[1] + w, c[2] + w],
                            item: Rock { c, r: radius },
                        });
                    }
                    // `[hazards]` rubble rocks and drops: `crate::rubble`.
                    if let Some(h) = crate::rubble::tile_hazard(world, n, passage, profile) {
                        for (c, r) in h.rocks {
                            let w = r + passage.roughness + margin;
                            rocks.push(Bounded {
                                lo: [c[0] - w, c[1] - w, c[2] - w],
                                hi: [c[0] + w, c[1] + w, c[2] + w],
                                item: Rock { c, r },
                            });
                        }
                        if let Some(pit) = h.pit {
                            let w = pit.r + margin;
                            features.push(Bounded {
                                lo: [pit.c[0] - w, pit.c[1] - w, (pit.bottom - margin).max(z0)],
                                hi: [pit.c[0] + w, pit.c[1] + w, pit.top + margin],
                                item: Feature::Pit(pit),
                            });
                        }
                    }
                }
            }
        }
        LocalField {
            passage,
            profile,
            features,
            rocks,
            waves,
            lmin,
            walls: Noise::new(seed, "walls"),
            sizes: Noise::new(seed, "sizes"),
            rubble: Noise::new(seed, "rubble"),
            bands: Noise::new(seed, "bands"),
        }
    }

    /// What depends only on the horizontal position: width, height and floor rubble.
    pub fn column(&self, x: f64, y: f64) -> Column {
        let ps = self.passage;
        let s = 1.0 / ps.variation_scale;
        Column {
            width: ps.width * (1.0 + ps.width_variation * self.sizes.at(x * s, y * s, 0.5)),
            height: ps.height * (1.0 + ps.height_variation * self.sizes.at(x * s, y * s, 7.5)),
            lift: self.waves.map(|w| w.lift(x, y)),
            rubble: if ps.floor_roughness > 0.0 {
                ps.floor_roughness * (0.5 + 0.5 * self.rubble.fbm(x / 1.5, y / 1.5, 0.0, 2))
            } else {
                0.0
            },
        }
    }

    /// The field and material at a point.
    pub fn at(&self, p: [f64; 3]) -> (f64, u8) {
        self.at_column(p, &self.column(p[0], p[1]))
    }

    /// The field and material at a point whose [`column`](Self::column) is known.
    pub fn at_column(&self, p: [f64; 3], col: &Column) -> (f64, u8) {
        let ps = self.passage;
        // Wall relief is evaluated only where it can matter: it never exceeds `roughness`, so
        // farther from the surface than that (with a margin for the lattice) the sign, and so
        // the surface, does not depend on it.
        let cutoff = 2.0 * ps.roughness + 0.1 * ps.width + 1.0;
        let mut relief: Option<f64> = None;
        let mut relief_at = |p: [f64; 3]| {
            *relief.get_or_insert_with(|| {
                let rs = 1.0 / ps.roughness_scale;
                ps.roughness * self.walls.fbm(p[0] * rs, p[1] * rs, p[2] * rs, 3)
            })
        };
        let mut best = FAR;
        let mut best_v = 0.0;
        for f in &self.features {
            if !f.contains(p) {
                continue;
            }
            let (base, v, wall) = match f.item {
                Feature::Corridor {
                    line,
                    floor,
                    level,
                    squeeze,
                } => {
                    let u = line.distance([p[0], p[1]]);
                    let v = p[2] - floor - col.lift[level - self.lmin] - col.rubble;
                    let wall = v.clamp(0.0, 1.0);
                    let [w, h] =
                        squeeze.map_or([1.0, 1.0], |s| s.scale(line.from_middle([p[0], p[1]])));
                    (
                        self.profile.section(u, v, w * col.width, h * col.height),
                        v,
                        wall,
                    )
                }
                Feature::Chamber { ref chamber, level } => {
                    let q = [p[0], p[1], p[2] - col.lift[level - self.lmin]];
                    let (base, v) = chamber.section(
                        self.profile,
                        q,
                        col.width / ps.width,
                        col.height / ps.height,
                        col.rubble,
                    );
                    (base, v, v.clamp(0.0, 1.0))
                }
                Feature::Shaft { c, z0, z1, r } => {
                    let d = ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2)).sqrt();
                    ((d - r).max(z0 - p[2]).max(p[2] - z1), 10.0, 1.0)
                }
                Feature::Pit(ref pit) => (pit.value(p), 0.0, 0.0),
                Feature::Ramp { ref helix, lifts } => {
                    let q = [p[0], p[1], p[2] - helix.lift_at(lifts, p[2])];
                    let (base, v) = helix.section(q, self.profile, col.rubble);
                    (base, v, v.clamp(0.0, 1.0))
                }
            };
            let value = if base.abs() < cutoff && wall > 0.0 {
                base + wall * relief_at(p)
            } else {
                base
            };
            if value < best {
                best = value;
                best_v = v;
            }
        }
        let mut material = if best_v < 0.35 {
            material::FLOOR
        } else if ps.striations
            && best.abs() < cutoff
            && self.bands.at(p[0] / 9.0, p[1] / 9.0, p[2] / 1.2) > 0.25
        {
            material::STRIATED
        } else {
            material::WALL
        };
        for rock in &self.rocks {
            if !rock.contains(p) {
                continue;
            }
            let r = &rock.item;
            let d = ((p[0] - r.c[0]).powi(2) + (p[1] - r.c[1]).powi(2) + (p[2] - r.c[2]).powi(2))
                .sqrt();
            let base = r.r - d;
            let solid = if base.abs() < cutoff {
                base + 0.3 * relief_at(p)
            } else {
                base
            };
            if solid > best {
                best = solid;
                material = material::ROCK;
            }
        }
        (best, material)
    }
}

/// The parts of the field that depend only on the horizontal position.
#[derive(Clone, Copy, Debug)]
pub struct Column {
    width: f64,
    height: f64,
    rubble: f64,
    /// Floor lift of levels `lmin ..= lmin + 2` here.
    lift: [f64; 3],
}

impl Column {
    /// The floor rubble's height here, metres.
    pub fn rubble(&self) -> f64 {
        self.rubble
    }
}
