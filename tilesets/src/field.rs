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

use crate::bends::{self, Centreline};
use crate::chambers::{Chamber, Squeeze};
use crate::finish::FinishNoise;
use crate::noise::Noise;
use crate::passage::{Levels, Passage, Profile, material};
use crate::slope::Waves;

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
    /// A refuge bay beside a straight drift (`crate::refuge`).
    Bay {
        bay: crate::refuge::Bay,
        floor: f64,
        level: usize,
    },
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

/// How far a shaft's radius swells or narrows with its relief, as a share of the radius: its
/// walls are not a lattice's flat facets round a cylinder, but rock broken a few decimetres
/// either way (about 0.3 m in a lava tube's 2.9 m shaft).
pub const SHAFT_SWELL: f64 = 0.12;

/// How much faster a shaft's relief changes upward than round it (a shaft is sunk in rounds:
/// its walls change more from one round to the next than round one round).
const SHAFT_STRETCH: f64 = 1.6;

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
    shaft_walls: Noise,
    finish: FinishNoise,
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
        let mut gather = Gather::new(world, passage, profile, levels, lattice, &waves, lmin);
        for l in lmin..=lmax {
            for dr in -1i64..=1 {
                for dc in -1i64..=1 {
                    let (r, c) = (cell.row as i64 + dr, cell.col as i64 + dc);
                    if r < 0 || c < 0 || r as usize >= occ.rows() || c as usize >= occ.cols() {
                        continue;
                    }
                    gather.cell(Cell::new(l, r as usize, c as usize));
                }
            }
        }
        LocalField {
            passage,
            profile,
            features: gather.features,
            rocks: gather.rocks,
            waves,
            lmin,
            walls: Noise::new(seed, "walls"),
            sizes: Noise::new(seed, "sizes"),
            rubble: Noise::new(seed, "rubble"),
            bands: Noise::new(seed, "bands"),
            shaft_walls: Noise::new(seed, "shaft-walls"),
            finish: FinishNoise::new(seed),
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
        let finish = ps.finish;
        // The direction-free part of the relief: the style's, or the finish's texture
        // (`crate::finish`), to which a corridor adds its blast rounds' overbreak.
        let mut relief_at = |p: [f64; 3]| {
            *relief.get_or_insert_with(|| {
                if finish.is_plain() {
                    let rs = 1.0 / ps.roughness_scale;
                    ps.roughness * self.walls.fbm(p[0] * rs, p[1] * rs, p[2] * rs, 3)
                } else {
                    finish.texture(&self.finish, p)
                }
            })
        };
        let mut best = FAR;
        let mut best_v = 0.0;
        for f in &self.features {
            if !f.contains(p) {
                continue;
            }
            let s = self.shape(&f.item, p, col, None);
            let value = if s.base.abs() < cutoff && s.wall > 0.0 {
                let r = relief_at(p);
                if finish.is_plain() {
                    s.base + s.wall * r
                } else {
                    // A finish moves the walls and back, never the floor: the feature is
                    // evaluated again with the relief inside its profile ([`Relieved`]).
                    let relief = finish.relief(r, &self.finish, p, s.along);
                    match s.section {
                        // A corridor's section again, where `p` stands in it already known
                        // (its distance from the centreline is most of a corridor's cost).
                        Some([u, v, w, h]) => Relieved {
                            profile: self.profile,
                            relief,
                        }
                        .section(u, v, w, h),
                        None => self.shape(&f.item, p, col, Some(relief)).base,
                    }
                }
            } else {
                s.base
            };
            if value < best {
                best = value;
                best_v = s.v;
            }
        }
        let mut material = if best_v < 0.35 {
            material::FLOOR
        } else if ps.mesh_from > 0.0 && best_v >= ps.mesh_from {
            material::MESHED
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

    /// One contribution's value at `p` (over the column `col`), with a finish's `relief` (metres,
    /// positive into the passage) on its walls and back when given, and what the relief
    /// depends on: the height above its floor, the relief's share there and the drift's
    /// direction (a corridor's or a refuge bay's).
    fn shape(&self, item: &Feature, p: [f64; 3], col: &Column, relief: Option<f64>) -> Shape {
        let relieved = relief.map(|relief| Relieved {
            profile: self.profile,
            relief,
        });
        let profile: &dyn Profile = match &relieved {
            Some(r) => r,
            None => self.profile,
        };
        let ps = self.passage;
        let mut section = None;
        let (base, v, wall, along) = match *item {
            Feature::Corridor {
                line,
                floor,
                level,
                squeeze,
            } => {
                let u = line.distance([p[0], p[1]]);
                let v = p[2] - floor - col.lift[level - self.lmin] - col.rubble;
                let [w, h] =
                    squeeze.map_or([1.0, 1.0], |s| s.scale(line.from_middle([p[0], p[1]])));
                let (w, h) = (w * col.width, h * col.height);
                section = Some([u, v, w, h]);
                (
                    profile.section(u, v, w, h),
                    v,
                    v.clamp(0.0, 1.0),
                    line.direction(),
                )
            }
            Feature::Chamber { ref chamber, level } => {
                let q = [p[0], p[1], p[2] - col.lift[level - self.lmin]];
                let (base, v) = chamber.section(
                    profile,
                    q,
                    col.width / ps.width,
                    col.height / ps.height,
                    col.rubble,
                );
                (base, v, v.clamp(0.0, 1.0), None)
            }
            Feature::Shaft { c, z0, z1, r } => {
                let d = ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2)).sqrt();
                // The shaft's own relief: its radius swells and narrows over features
                // about its radius across, which the lattice holds (the wall relief
                // below is finer than a lattice cell).
                let s = 1.0 / r;
                let swell = SHAFT_SWELL
                    * r
                    * self
                        .shaft_walls
                        .fbm(p[0] * s, p[1] * s, p[2] * s * SHAFT_STRETCH, 2);
                let base = (d - r - swell).max(z0 - p[2]).max(p[2] - z1);
                // No floor: the relief moves all of it.
                (relief.map_or(base, |r| base + r), 10.0, 1.0, None)
            }
            Feature::Pit(ref pit) => (pit.value(p), 0.0, 0.0, None),
            Feature::Bay { bay, floor, level } => {
                let v = p[2] - floor - col.lift[level - self.lmin] - col.rubble;
                let wall = v.clamp(0.0, 1.0);
                let base = match relief {
                    Some(r) => (bay.walls(p, v) + wall * r).max(-v),
                    None => bay.value(p, v),
                };
                (base, v, wall, Some(bay.along))
            }
            Feature::Ramp { ref helix, lifts } => {
                let q = [p[0], p[1], p[2] - helix.lift_at(lifts, p[2])];
                let (base, v) = helix.section(q, profile, col.rubble);
                (base, v, v.clamp(0.0, 1.0), None)
            }
        };
        Shape {
            base,
            v,
            wall,
            along,
            section,
        }
    }
}

/// What [`LocalField::around`] collects, cell by cell: every contribution of one occupied
/// neighbour (its passage's centrelines, chamber, ramp or shaft, rocks, rubble field or drop).
struct Gather<'g> {
    world: &'g Layout,
    passage: &'g Passage,
    profile: &'g dyn Profile,
    levels: Levels,
    lattice: f64,
    waves: &'g [Waves; 3],
    lmin: usize,
    /// Half the pitch.
    half: f64,
    /// How far a contribution's box reaches beyond what it makes negative.
    margin: f64,
    /// How far a corridor's box reaches sideways from its centreline.
    reach: f64,
    /// How high a corridor's box reaches above its floor.
    top: f64,
    features: Vec<Bounded<Feature>>,
    rocks: Vec<Bounded<Rock>>,
}

impl<'g> Gather<'g> {
    fn new(
        world: &'g Layout,
        passage: &'g Passage,
        profile: &'g dyn Profile,
        levels: Levels,
        lattice: f64,
        waves: &'g [Waves; 3],
        lmin: usize,
    ) -> Self {
        let half = 0.5 * world.resolved.tile_pitch;
        let margin = 3.0 * lattice;
        Gather {
            world,
            passage,
            profile,
            levels,
            lattice,
            waves,
            lmin,
            half,
            margin,
            reach: (0.5 * passage.width * (1.0 + passage.width_variation)
                + passage.roughness
                + margin)
                .min(half),
            top: passage.height * (1.0 + passage.height_variation)
                + passage.roughness
                + passage.floor_roughness
                + margin,
            features: Vec::new(),
            rocks: Vec::new(),
        }
    }

    /// The floor's lift on level `l` at `c`.
    fn lift(&self, l: usize, c: [f64; 2]) -> f64 {
        match self.waves.get(l - self.lmin) {
            Some(w) => w.lift(c[0], c[1]),
            // The landing of a shaft from the level above this tile's.
            None => self.passage.slope.level(l).lift(c[0], c[1]),
        }
    }

    /// Every contribution of the cell `n`, if it is occupied.
    fn cell(&mut self, n: Cell) {
        let world = self.world;
        let Some(tile) = world.tiles.get(n) else {
            return;
        };
        let passage = self.passage;
        let l = n.level;
        let [x, y, floor] = world.cell_position(n);
        let (z0, z1) = self.levels.block_z(l);
        let zspan = (z0, (floor + passage.slope.amp + self.top).min(z1));
        let mut ends: Vec<[f64; 2]> = Direction::ALL
            .into_iter()
            .filter(|d| tile.openings & d.bit() != 0)
            .map(|d| {
                let (sr, sc) = d.step();
                [x + f64::from(sc) * self.half, y - f64::from(sr) * self.half]
            })
            .collect();
        if ends.is_empty() {
            ends.push([x, y]);
        }
        // A ramp's end: its lead replaces the half-corridor of the ramp's opening.
        let ramp = crate::ramp::shaft_of(world, n).and_then(|s| {
            let sizing = crate::ramp::Sizing::of(world, passage, self.lattice, self.levels.coarse);
            crate::ramp::plan(world, s, &sizing)
                .ok()
                .map(|h| (s.up == n, h))
        });
        let mut leads = Vec::new();
        if let Some((foot, h)) = &ramp {
            let (a, b) = h.leads()[usize::from(!*foot)];
            ends.retain(|e| (e[0] - b[0]).abs() + (e[1] - b[1]).abs() > 1e-6);
            leads.push(Centreline::Segment { a, b });
        }
        let (chamber, squeeze) =
            crate::chambers::of_cell(world, n, tile.kind, passage, self.levels, self.lattice);
        if let Some(ch) = chamber {
            self.chamber(ch, [x, y, floor], l, zspan.0, z1);
        }
        let key = ((l as u64) << 40) | ((n.row as u64) << 20) | n.col as u64;
        let sway = bends::meander(world.resolved.seed, key, passage.meander);
        // A ramp cell whose only opening is the ramp's has no half-corridor.
        let mut lines = if ends.is_empty() {
            Vec::new()
        } else {
            bends::centrelines([x, y], &ends, passage.bends, sway)
        };
        lines.extend(leads);
        for &line in &lines {
            let (lo, hi) = line.bounds();
            self.features.push(Bounded {
                lo: [lo[0] - self.reach, lo[1] - self.reach, zspan.0],
                hi: [hi[0] + self.reach, hi[1] + self.reach, zspan.1],
                item: Feature::Corridor {
                    line,
                    floor,
                    level: l,
                    squeeze,
                },
            });
        }
        if let Some(bay) = crate::refuge::of_cell(
            world,
            n,
            tile.kind,
            tile.openings,
            passage,
            squeeze.is_some(),
        ) {
            let grow = passage.roughness + self.margin;
            let (lo, hi) = bay.bounds(grow);
            self.features.push(Bounded {
                lo: [lo[0], lo[1], zspan.0],
                hi: [hi[0], hi[1], zspan.1],
                item: Feature::Bay {
                    bay,
                    floor,
                    level: l,
                },
            });
        }
        let has_ramp = ramp.is_some();
        if let Some((true, h)) = ramp {
            self.ramp(h, l);
        } else if tile.kind == TileKind::ShaftUp
            && l + 1 < world.occupancy.levels()
            && crate::ramp::shaft_of(world, n).is_none()
        {
            self.shaft([x, y, floor], l);
        }
        // No rocks in a squeeze (the passage there is already as tight as allowed) nor in a
        // ramp's cells.
        let rocky = squeeze.is_none() && !has_ramp && !lines.is_empty();
        self.rocks_of(key, &lines, floor, l, rocky);
        // `[hazards]` rubble rocks and drops: `crate::rubble`.
        if let Some(h) = crate::rubble::tile_hazard(world, n, passage, self.profile) {
            self.hazard(h, z0);
        }
    }

    /// A chamber centred at `at` (on its floor) on level `level`, in a box from `zlo` up to
    /// at most `z1`.
    fn chamber(&mut self, ch: Chamber, at: [f64; 3], level: usize, zlo: f64, z1: f64) {
        let ps = self.passage;
        let zhi = at[2]
            + ps.slope.amp
            + ch.top(ps.height_variation)
            + ps.roughness
            + ps.floor_roughness
            + self.margin;
        self.features.push(Bounded {
            lo: [at[0] - self.half, at[1] - self.half, zlo],
            hi: [at[0] + self.half, at[1] + self.half, zhi.min(z1)],
            item: Feature::Chamber { chamber: ch, level },
        });
    }

    /// The spiral of a ramp whose foot is on level `l`.
    fn ramp(&mut self, h: crate::ramp::Helix, l: usize) {
        let [(a0, _), (a1, _)] = h.leads();
        let lifts = [self.lift(l, a0), self.lift(l + 1, a1)];
        let (lo, mut hi) = h.bounds(self.margin + self.passage.roughness);
        hi[2] += lifts[0].max(lifts[1]);
        self.features.push(Bounded {
            lo,
            hi,
            item: Feature::Ramp {
                helix: Box::new(h),
                lifts,
            },
        });
    }

    /// The vertical shaft from the foot at `at` (on level `l`) to the level above.
    fn shaft(&mut self, at: [f64; 3], l: usize) {
        let ps = self.passage;
        let [x, y, floor] = at;
        let above = floor + self.levels.height + self.lift(l + 1, [x, y]);
        let foot = floor + self.lift(l, [x, y]);
        let r = ps.shaft_radius * ps.width;
        let w = (r * (1.0 + SHAFT_SWELL) + ps.roughness + self.margin).min(self.half);
        self.features.push(Bounded {
            lo: [x - w, y - w, foot],
            hi: [x + w, y + w, above + 0.5 + self.margin],
            item: Feature::Shaft {
                c: [x, y],
                z0: foot + 0.5,
                z1: above + 0.5,
                r,
            },
        });
    }

    /// The rocks on the floor beside the cell's `lines` (drawn whether `rocky` or not, from
    /// the cell's own stream, so the draws do not depend on what else the cell has).
    fn rocks_of(&mut self, key: u64, lines: &[Centreline], floor: f64, l: usize, rocky: bool) {
        let ps = self.passage;
        let mut rng = WorldRng::new(self.world.resolved.seed, "rocks", key);
        let count = ps.rocks.floor() as u32 + u32::from(rng.unit() < ps.rocks.fract());
        let count = if rocky { count } else { 0 };
        for _ in 0..count {
            let line = lines[rng.below(lines.len() as u64) as usize];
            let ([ax, ay], [dx, dy]) = line.at(rng.float_in(0.15, 0.85));
            // Sideways toward a wall, on the floor.
            let side = if rng.coin() { 1.0 } else { -1.0 };
            let radius = ps.rock_size * rng.float_in(0.6, 1.2);
            // Out of the robot's box about the axis (`min_clearance`).
            let off = rng
                .float_in(0.15, 0.35)
                .max((0.5 * ps.rooms.min_clearance[0] + 1.3 * radius + 0.5) / ps.width)
                * ps.width
                * side;
            let (cx, cy) = (ax - dy * off, ay + dx * off);
            let c = [cx, cy, floor + self.lift(l, [cx, cy]) + 0.15 * radius];
            self.rock(c, radius, ps.roughness + self.margin);
        }
    }

    /// A rock of radius `r` at `c`, in a box `grow` wider than the rock.
    fn rock(&mut self, c: [f64; 3], r: f64, grow: f64) {
        let w = r + grow;
        self.rocks.push(Bounded {
            lo: [c[0] - w, c[1] - w, c[2] - w],
            hi: [c[0] + w, c[1] + w, c[2] + w],
            item: Rock { c, r },
        });
    }

    /// A tile's rubble field or drop; `z0` is the bottom of its level's block.
    fn hazard(&mut self, h: crate::rubble::TileHazard, z0: f64) {
        for (c, r) in h.rocks {
            self.rock(c, r, self.passage.roughness + self.margin);
        }
        if let Some(pit) = h.pit {
            let w = pit.r + self.margin;
            self.features.push(Bounded {
                lo: [
                    pit.c[0] - w,
                    pit.c[1] - w,
                    (pit.bottom - self.margin).max(z0),
                ],
                hi: [pit.c[0] + w, pit.c[1] + w, pit.top + self.margin],
                item: Feature::Pit(pit),
            });
        }
    }
}

/// One contribution's value at a point and what its relief depends on
/// ([`LocalField::shape`]).
struct Shape {
    /// The field, negative in the passage.
    base: f64,
    /// Metres above the contribution's floor.
    v: f64,
    /// The share of the wall relief acting here: none on the floor, all of it from a metre up.
    wall: f64,
    /// The drift's direction, for a blast round's overbreak.
    along: Option<[f64; 2]>,
    /// A corridor's section at the point: across from its centreline, up from its floor, its
    /// width and height there (what its profile was asked).
    section: Option<[f64; 4]>,
}

/// A profile with a finish's relief on its walls and back: `relief` metres into the passage,
/// faded in over the first metre above the floor as every tile set's relief is.
///
/// **Why not on the section as a whole.** The mesh's floor vertices are interpolated along
/// lattice edges from lattice points up to a lattice cell (0.83 m visual, 1.67 m collision)
/// above the floor, where the fade lets most of the relief act: decimetres of blasted relief
/// added to the whole section moved the floor up or down by several centimetres from one
/// lattice cell to the next (a 15-degree step at a ramp's foot, a ball stopped on a ramp).
/// Moved inside `max(walls, floor)`, the relief leaves every point where the floor is nearer
/// than the walls exactly as it was, so the floor a robot drives on is the plain one.
struct Relieved<'p> {
    profile: &'p dyn Profile,
    relief: f64,
}

impl Profile for Relieved<'_> {
    fn section(&self, u: f64, v: f64, width: f64, height: f64) -> f64 {
        let r = v.clamp(0.0, 1.0) * self.relief;
        match self.profile.walls(u, v, width, height) {
            Some(walls) => (walls + r).max(-v),
            None => self.profile.section(u, v, width, height) + r,
        }
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
