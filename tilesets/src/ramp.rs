//! Ramps between levels (`world.connections = "ramp"`): a spiral decline beside a shaft's
//! foot, as real mines join their levels, so a wheeled robot can drive from one level to the
//! next.
//!
//! The spiral turns in its *block*: the 2 x 2 cells made of the foot and three empty cells
//! beside it, on both levels (the grid keeps them empty: [`Shaft::block`]), so its circle is
//! nearly a pitch in radius. One cell is too small for a drivable grade: each turn's drop must
//! hold the passage and rock above it, and a turn round a circle inside one 20 m cell is about
//! 31 m long, so the mine's spiral climbed at 19 to 25 degrees; round the block a turn is about
//! 94 m and the same climb is about 6 degrees, within a real decline's 1 in 7.
//!
//! The foot's passage leaves its opening in a straight *lead* tangent to a circle about the
//! block's centre, climbs round a rock pillar along that circle (a helix whose floor is flat
//! across the passage), and leaves in a second lead tangent to the circle towards the
//! landing's opening, on the landing's floor. The helix turns as often as the level height
//! allows with the passage and enough rock between one turn and the next (the passage's
//! highest point plus one and a half collision lattice cells, so the coarse collision surface
//! keeps the turns apart: no lattice edge spans the rock), which makes it as gentle as the
//! block allows: each turn is one circumference long (the circle is as large as the block takes
//! with the passage's half-width), so the grade is at least the rock and passage per turn over
//! that circumference. The climb starts and ends with short blends (no kink at the foot or the
//! top), and, when the openings leave part of a turn over, stretches flat on the floors. A ramp
//! steeper than `world.ramp_grade` is refused, naming what to change. A ramp without a block
//! (an imported grid with no three empty cells beside its foot) turns inside its own cell.
//!
//! Everything here is a function of the world (pitch, level height, openings) and the passage
//! knobs, so every tile evaluating the ramp's field computes the same numbers.

use std::collections::BTreeMap;
use std::f64::consts::TAU;
use std::sync::Mutex;

use subtgraph_core::Layout;
use subtgraph_core::grid::{Cell, Direction, Shaft};
use subtgraph_core::tile::TileKind;

use crate::passage::{Passage, Profile};
use crate::winding::{Span, Winding};

/// A point of the floor line is kept every this many metres along it.
const SAMPLE: f64 = 0.5;
/// Two stretches of floor side by side closer than this in height are one floor, metres.
const STEP: f64 = 0.25;
/// The helix's passage is at most this share of the level height high: each turn's drop must
/// hold it and the rock above it.
const HEADROOM: f64 = 0.25;
/// Length of the blends at both ends of the climb, at most, metres.
const BLEND: f64 = 2.0;

/// What sizes a ramp: the passage and the lattice.
#[derive(Clone, Copy, Debug)]
pub struct Sizing {
    /// Half the passage's width with its relief, metres.
    pub half_width: f64,
    /// The passage's nominal width and height (the helix keeps them, without variation).
    pub width: f64,
    /// See `width`.
    pub height: f64,
    /// Vertical room a turn of the helix needs: its passage's highest point plus rock, metres.
    pub per_turn: f64,
    /// The same for the leads (the tile set's full passage height).
    pub per_lead: f64,
    /// Horizontal rock needed between two passages, metres.
    pub rock: f64,
    /// How far from a cell's centre a passage's side may reach, metres (a spiral block's reaches
    /// half a pitch further from its centre).
    pub room: f64,
    /// The steepest grade allowed, degrees.
    pub max_grade: f64,
}

impl Sizing {
    /// The sizing for a procedural passage with lattices `fine` (visual) and `coarse`
    /// (collision) metres apart.
    pub fn of(world: &Layout, p: &Passage, fine: f64, coarse: f64) -> Sizing {
        let rock = 1.2 * coarse;
        let height = p.height.min(HEADROOM * world.resolved.level_height);
        let extra = 2.0 * p.roughness + p.floor_roughness + rock;
        Sizing {
            half_width: 0.5 * p.width + p.roughness,
            width: p.width,
            height,
            per_turn: height + extra,
            per_lead: p.height * (1.0 + p.height_variation) + extra,
            rock,
            room: 0.5 * world.resolved.tile_pitch - 2.0 * fine,
            max_grade: world.resolved.ramp_grade,
        }
    }
}

/// One ramp, planned.
#[derive(Clone, Debug, PartialEq)]
pub struct Helix {
    /// The cell's centre.
    pub centre: [f64; 2],
    /// The circle's radius.
    pub radius: f64,
    /// +1 counter-clockwise, -1 clockwise (seen from above, going up).
    pub sense: f64,
    /// Angle at the foot's tangent point.
    pub start: f64,
    /// Arc length of the helix, metres.
    pub length: f64,
    /// Flat stretches at the foot and the top, metres along.
    pub flat: [f64; 2],
    /// Blend length at both ends of the climb, metres.
    pub blend: f64,
    /// Floors of the foot's and the landing's levels.
    pub floors: [f64; 2],
    /// The foot's opening (on the cell's edge) and the landing's.
    pub openings: [[f64; 2]; 2],
    /// Passage width and height.
    pub size: [f64; 2],
    /// How the ramp winds from the exact helix ([`crate::winding`]).
    pub winding: Winding,
}

/// Why a ramp cannot be made.
#[derive(Clone, Debug, PartialEq)]
pub enum Unfit {
    /// No pillar is left inside the spiral.
    Narrow {
        /// The passage's width with relief, metres.
        width: f64,
        /// Room in the cell, metres from its centre.
        room: f64,
    },
    /// The gentlest ramp the cell holds is steeper than allowed.
    Steep {
        /// Its grade, degrees.
        grade: f64,
    },
}

impl Helix {
    /// Plans the ramp round `centre` from the foot's opening `openings[0]` on floor
    /// `floors[0]` to the landing's `openings[1]` on `floors[1]`, its passage's side at most
    /// `room` metres from `centre`.
    pub fn plan(
        centre: [f64; 2],
        floors: [f64; 2],
        openings: [[f64; 2]; 2],
        room: f64,
        s: &Sizing,
    ) -> Result<Helix, Unfit> {
        let radius = room - s.half_width;
        if radius - s.half_width < s.rock / 2.0 {
            return Err(Unfit::Narrow {
                width: 2.0 * s.half_width,
                room,
            });
        }
        let angle = |p: [f64; 2]| (p[1] - centre[1]).atan2(p[0] - centre[0]);
        // The angle at the centre between an opening and the tangent point of its lead.
        let beta = |p: [f64; 2]| (radius / (p[0] - centre[0]).hypot(p[1] - centre[1])).acos();
        let rise = floors[1] - floors[0];
        let step = SAMPLE.max(radius * TAU / 64.0);
        let mut best: Option<Helix> = None;
        for sense in [1.0, -1.0] {
            let start = angle(openings[0]) + sense * beta(openings[0]);
            let end = angle(openings[1]) - sense * beta(openings[1]);
            let base = (sense * (end - start)).rem_euclid(TAU);
            for k in 0..8 {
                let length = radius * (base + TAU * f64::from(k));
                if length > radius * TAU * (rise / s.per_turn + 2.0) {
                    break;
                }
                // Flat stretches, shortest in all first (the gentlest climb), split every
                // way between the foot and the top, in steps of half a metre (a 64th of a
                // turn round a spiral block: as fine a grade, in a search 8 times shorter).
                let mut total = 0;
                let mut overlaps = None;
                'flats: while f64::from(total) * step < length - 1.0 {
                    let climb = length - f64::from(total) * step;
                    for a in 0..=total {
                        let h = Helix {
                            centre,
                            radius,
                            sense,
                            start,
                            length,
                            flat: [f64::from(a) * step, f64::from(total - a) * step],
                            blend: BLEND.min(0.25 * climb),
                            floors,
                            openings,
                            size: [s.width, s.height],
                            winding: Winding::NONE,
                        };
                        if best.as_ref().is_some_and(|b| b.grade() <= h.grade()) {
                            break 'flats;
                        }
                        let o = overlaps.get_or_insert_with(|| Overlaps::of(&h, s));
                        if h.separated_over(o, s) {
                            best = Some(h);
                            break 'flats;
                        }
                    }
                    total += 1;
                }
            }
        }
        let best = best.ok_or(Unfit::Steep { grade: 90.0 })?;
        if best.grade() > s.max_grade {
            return Err(Unfit::Steep {
                grade: best.grade(),
            });
        }
        Ok(best)
    }

    /// The steepest grade along the climb, degrees.
    pub fn grade(&self) -> f64 {
        self.slope().atan().to_degrees()
    }

    fn slope(&self) -> f64 {
        let climb = self.length - self.flat[0] - self.flat[1];
        (self.floors[1] - self.floors[0]) / (climb - self.blend)
    }

    /// Where the winding acts: the steady climb between the blends.
    fn span(&self) -> Span {
        Span {
            radius: self.radius,
            climb: [
                self.flat[0] + self.blend,
                self.length - self.flat[1] - self.blend,
            ],
            slope: self.slope(),
        }
    }

    /// The floor's height `s` metres along the helix (metres along the planned circle: the
    /// winding's line is a little shorter where it comes in).
    pub fn floor(&self, s: f64) -> f64 {
        self.planned_floor(s) + self.winding.rise_at(&self.span(), s)
    }

    /// The passage's axis's distance from the centre `s` metres along.
    pub fn radius_at(&self, s: f64) -> f64 {
        self.radius - self.winding.inset_at(&self.span(), s)
    }

    /// The planned (exact helix's) floor `s` metres along.
    fn planned_floor(&self, s: f64) -> f64 {
        let g = self.slope();
        let climb = self.length - self.flat[0] - self.flat[1];
        let e = self.blend;
        let t = (s - self.flat[0]).clamp(0.0, climb);
        // Slope from 0 up to g over e, g, then down to 0 over e.
        let up = if t < e {
            0.5 * g * t * t / e
        } else if t <= climb - e {
            g * (t - 0.5 * e)
        } else {
            let r = climb - t;
            g * (climb - e) - 0.5 * g * r * r / e
        };
        self.floors[0] + up
    }

    /// The horizontal point `s` metres along the helix.
    pub fn at(&self, s: f64) -> [f64; 2] {
        let a = self.start + self.sense * s / self.radius;
        let r = self.radius_at(s);
        [self.centre[0] + r * a.cos(), self.centre[1] + r * a.sin()]
    }

    /// The steepest grade along the drawn floor line (the winding's included), degrees,
    /// measured every quarter metre.
    pub fn steepest(&self) -> f64 {
        let n = (self.length / (0.5 * SAMPLE)).ceil().max(1.0) as usize;
        let point = |i: usize| {
            let s = self.length * i as f64 / n as f64;
            let [x, y] = self.at(s);
            [x, y, self.floor(s)]
        };
        let mut last = point(0);
        let mut most: f64 = 0.0;
        for i in 1..=n {
            let p = point(i);
            let run = (p[0] - last[0]).hypot(p[1] - last[1]);
            most = most.max((p[2] - last[2]).atan2(run).to_degrees().abs());
            last = p;
        }
        most
    }

    /// The radii (least, greatest) the passage's axis takes along the steady climb, and the
    /// grades (least, steepest) there, degrees: how far the ramp departs from a helix.
    pub fn ranges(&self) -> ([f64; 2], [f64; 2]) {
        let span = self.span();
        let n = ((span.climb[1] - span.climb[0]) / (0.5 * SAMPLE))
            .ceil()
            .max(1.0) as usize;
        let mut radius = [f64::INFINITY, 0.0f64];
        let mut grade = [f64::INFINITY, 0.0f64];
        let at = |i: usize| span.climb[0] + (span.climb[1] - span.climb[0]) * i as f64 / n as f64;
        for i in 0..n {
            let (s, t) = (at(i), at(i + 1));
            let r = self.radius_at(s);
            radius = [radius[0].min(r), radius[1].max(r)];
            let (p, q) = (self.at(s), self.at(t));
            let run = (q[0] - p[0]).hypot(q[1] - p[1]);
            let g = (self.floor(t) - self.floor(s)).atan2(run).to_degrees();
            grade = [grade[0].min(g), grade[1].max(g)];
        }
        (radius, grade)
    }

    /// Winds the helix as `w` says, at the largest of its amplitudes tried (both waves full,
    /// the grade's halved, both halved, the radius's alone full or halved) whose steepest grade
    /// is within `max_grade` degrees and whose turns keep their rock apart; exact when none is.
    pub fn wind(&mut self, w: Winding, sizing: &Sizing) {
        // A swing beyond what the grade allows would be halved anyway: start from the most
        // the planned grade leaves, with the inset's steepening (the line is shorter by
        // r / R where it comes in).
        let room = sizing.max_grade.to_radians().tan() / self.slope().max(1e-9);
        let shorter = (self.radius - w.inset) / self.radius;
        let w = Winding {
            swing: w.swing.min((0.97 * room * shorter - 1.0).max(0.0)),
            ..w
        };
        // Both waves at full, then half, amplitude; then the radius's alone.
        for (inset, swing) in [(1.0, 1.0), (1.0, 0.5), (0.5, 0.5), (1.0, 0.0), (0.5, 0.0)] {
            self.winding = Winding {
                inset: w.inset * inset,
                swing: w.swing * swing,
                ..w
            };
            if self.steepest() <= sizing.max_grade && self.separated(sizing) {
                return;
            }
        }
        self.winding = Winding::NONE;
    }

    /// The floor line from the foot's tangent point to the landing's, a point every
    /// half a metre or closer.
    pub fn floor_line(&self) -> Vec<[f64; 3]> {
        let n = (self.length / SAMPLE).ceil().max(1.0) as usize;
        (0..=n)
            .map(|i| {
                let s = self.length * i as f64 / n as f64;
                let [x, y] = self.at(s);
                [x, y, self.floor(s)]
            })
            .collect()
    }

    /// How far the floors' slopes ([`crate::slope`]) lift the spiral at height `z`: by
    /// `lifts[0]` (the foot's lift where the spiral leaves the lower level) at the foot's floor,
    /// by `lifts[1]` (the landing's) at the landing's, in proportion to the climb in between, so
    /// the spiral meets both lifted corridors.
    pub fn lift_at(&self, lifts: [f64; 2], z: f64) -> f64 {
        let f = ((z - self.floors[0]) / (self.floors[1] - self.floors[0])).clamp(0.0, 1.0);
        lifts[0] + (lifts[1] - lifts[0]) * f
    }

    /// The leads: foot opening to the helix's start, helix's end to the landing's opening.
    pub fn leads(&self) -> [([f64; 2], [f64; 2]); 2] {
        [
            (self.at(0.0), self.openings[0]),
            (self.at(self.length), self.openings[1]),
        ]
    }

    /// What covers the horizontal point `p` (a passage with `reach` metres beside it): calls
    /// `turn` with where along the helix each turn covering it is, in order, and returns
    /// which of the two `leads` (see [`leads`](Self::leads)) cover it.
    fn covering(
        &self,
        p: [f64; 2],
        reach: f64,
        leads: &[([f64; 2], [f64; 2]); 2],
        mut turn: impl FnMut(f64),
    ) -> [bool; 2] {
        let (dx, dy) = (p[0] - self.centre[0], p[1] - self.centre[1]);
        let rho = (dx * dx + dy * dy).sqrt();
        if rho > self.radius - self.winding.inset - reach && rho < self.radius + reach {
            let phi = dy.atan2(dx);
            let mut s = self.radius * (self.sense * (phi - self.start)).rem_euclid(TAU);
            while s <= self.length {
                if (rho - self.radius_at(s)).abs() < reach {
                    turn(s);
                }
                s += self.radius * TAU;
            }
        }
        // A lead's body, not its round end at the helix: there lead and helix are one
        // passage, the lead's floor merging into the helix's.
        leads.map(|(a, b)| beside_segment(p, a, b) < reach)
    }

    /// The points [`separated`](Self::separated) looks at, row by row: a square grid every
    /// [`SAMPLE`] metres or closer over the spiral and `reach` metres round it.
    fn grid(&self, reach: f64) -> impl Iterator<Item = [f64; 2]> + '_ {
        let extent = self.radius + reach;
        let n = (2.0 * extent / SAMPLE).ceil() as usize;
        (0..=n).flat_map(move |j| {
            (0..=n).map(move |i| {
                [
                    self.centre[0] - extent + 2.0 * extent * i as f64 / n as f64,
                    self.centre[1] - extent + 2.0 * extent * j as f64 / n as f64,
                ]
            })
        })
    }

    /// Appends to `floors` the floors of the leads `covered` says cover a point.
    fn push_leads(&self, covered: [bool; 2], floors: &mut Vec<(f64, bool)>) {
        for (lead, z) in covered.into_iter().zip(self.floors) {
            if lead {
                floors.push((z, true));
            }
        }
    }

    /// Whether, over every point of the cell, the floors of the passages that cover it (with
    /// half the rock beside them) are a turn's room apart in height, or one floor (within
    /// [`STEP`]: the passages merge into a wider one there).
    fn separated(&self, s: &Sizing) -> bool {
        let reach = s.half_width + 0.5 * s.rock;
        let leads = self.leads();
        let mut floors = Vec::new();
        for p in self.grid(reach) {
            floors.clear();
            let covered = self.covering(p, reach, &leads, |t| floors.push((self.floor(t), false)));
            self.push_leads(covered, &mut floors);
            if !apart(&floors, s) {
                return false;
            }
        }
        true
    }

    /// [`separated`](Self::separated) for an unwound helix, over the points `o` found
    /// covered twice or more (for a helix of the same centre, radius, sense, start and length):
    /// the same answer, with only the floors' heights computed.
    fn separated_over(&self, o: &Overlaps, s: &Sizing) -> bool {
        let mut floors = Vec::new();
        for point in &o.points {
            floors.clear();
            floors.extend(
                o.turns[point.turns.clone()]
                    .iter()
                    .map(|&t| (self.floor(t), false)),
            );
            self.push_leads(point.leads, &mut floors);
            if !apart(&floors, s) {
                return false;
            }
        }
        true
    }

    /// The box the helix acts in, with `margin` around the passage.
    pub fn bounds(&self, margin: f64) -> ([f64; 3], [f64; 3]) {
        let r = self.radius + 0.5 * self.size[0] + margin;
        (
            [
                self.centre[0] - r,
                self.centre[1] - r,
                self.floors[0] - margin,
            ],
            [
                self.centre[0] + r,
                self.centre[1] + r,
                self.floors[1] + 1.5 * self.size[1] + margin,
            ],
        )
    }

    /// The helix's field at `p` (negative in the passage) and the height above its floor
    /// there, for floor rubble `rubble`.
    pub fn section(&self, p: [f64; 3], profile: &dyn Profile, rubble: f64) -> (f64, f64) {
        let (dx, dy) = (p[0] - self.centre[0], p[1] - self.centre[1]);
        let rho = (dx * dx + dy * dy).sqrt();
        let phi = dy.atan2(dx);
        let first = self.radius * (self.sense * (phi - self.start)).rem_euclid(TAU);
        let turn = self.radius * TAU;
        let mut best = (f64::INFINITY, 0.0);
        let mut s = first;
        while s <= self.length {
            let u = (rho - self.radius_at(s)).abs();
            let v = p[2] - self.floor(s) - rubble;
            let f = profile.section(u, v, self.size[0], self.size[1]);
            if f < best.0 {
                best = (f, v);
            }
            s += turn;
        }
        best
    }
}

/// Distance from `p` to the segment `a`-`b` in the plane, infinite for points beyond `a`.
fn beside_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2
    } else {
        0.0
    };
    if t < 0.0 {
        return f64::INFINITY;
    }
    let t = t.min(1.0);
    ((a[0] + t * dx - p[0]).powi(2) + (a[1] + t * dy - p[1]).powi(2)).sqrt()
}

/// The ramp ends of a world: for a foot or a landing cell, its shaft.
pub fn shaft_of(world: &Layout, cell: Cell) -> Option<&Shaft> {
    if world.resolved.connections != subtgraph_core::config::Connections::Ramp {
        return None;
    }
    let kind = world.tiles.get(cell).as_ref()?.kind;
    if !matches!(kind, TileKind::ShaftUp | TileKind::ShaftLanding) {
        return None;
    }
    world
        .shafts
        .iter()
        .find(|s| s.up == cell || s.landing == cell)
}

/// The first opening of a cell, in [`Direction::ALL`] order.
fn first_opening(world: &Layout, cell: Cell) -> Option<Direction> {
    let t = world.tiles.get(cell).as_ref()?;
    Direction::ALL
        .into_iter()
        .find(|d| t.openings & d.bit() != 0)
}

/// Whether the floors over one point (height, and whether it is a lead's) are each a turn's
/// room apart in height (a lead's room above a lead), or one floor within [`STEP`].
fn apart(floors: &[(f64, bool)], s: &Sizing) -> bool {
    for (k, a) in floors.iter().enumerate() {
        for b in &floors[k + 1..] {
            let (low, high) = if a.0 < b.0 { (a, b) } else { (b, a) };
            let need = if low.1 { s.per_lead } else { s.per_turn };
            let dz = high.0 - low.0;
            if dz > STEP && dz < need {
                return false;
            }
        }
    }
    true
}

/// The points of [`Helix::separated`]'s grid that two or more passages cover, with what covers
/// them: which turns (where along the helix) and which leads. For an unwound helix this
/// depends on its centre, radius, sense, start and length alone, not on its flat stretches,
/// so [`Helix::plan`]'s search over the flats finds it once per length (the search spent
/// most of a mine's generate time recomputing it).
struct Overlaps {
    points: Vec<Overlap>,
    /// The covering turns' distances along the helix, [`Overlap::turns`] ranges into it.
    turns: Vec<f64>,
}

struct Overlap {
    turns: std::ops::Range<usize>,
    /// Whether the foot's and the landing's lead cover the point.
    leads: [bool; 2],
}

impl Overlaps {
    /// What covers each point of `h`'s grid, as [`Helix::covering`] finds it (`h` unwound).
    fn of(h: &Helix, s: &Sizing) -> Overlaps {
        debug_assert!(h.winding == Winding::NONE);
        let reach = s.half_width + 0.5 * s.rock;
        let leads = h.leads();
        let mut out = Overlaps {
            points: Vec::new(),
            turns: Vec::new(),
        };
        for p in h.grid(reach) {
            let first = out.turns.len();
            let covered = h.covering(p, reach, &leads, |t| out.turns.push(t));
            let count = out.turns.len() - first + covered.iter().filter(|c| **c).count();
            if count >= 2 {
                out.points.push(Overlap {
                    turns: first..out.turns.len(),
                    leads: covered,
                });
            } else {
                out.turns.truncate(first);
            }
        }
        out
    }
}

/// A ramp's shape (centred on the origin, from floor 0) by what it depends on: its openings and
/// the bits of its sizes. The search for the gentlest ramp is the same for every tile around
/// it, so it is made once.
type Key = (u8, u8, Option<[i8; 2]>, [u64; 10]);

static PLANS: Mutex<BTreeMap<Key, Result<Helix, Unfit>>> = Mutex::new(BTreeMap::new());

/// The wound ramps (still centred on the origin) by their shape's key, the world's seed and the
/// foot cell: winding tries up to five amplitudes, each checking the turns' rock over the
/// whole spiral block, and every tile around the ramp (and the world's check) asks for it.
static WOUND: Mutex<BTreeMap<(Key, u64, u64), Helix>> = Mutex::new(BTreeMap::new());

/// Plans the ramp of `shaft`: round the centre of its spiral block (see
/// [`Shaft::block`]; a ramp without one turns round its foot cell's centre).
pub fn plan(world: &Layout, shaft: &Shaft, s: &Sizing) -> Result<Helix, Unfit> {
    let [x, y, z0] = world.cell_position(shaft.up);
    let z1 = world.cell_position(shaft.landing)[2];
    let entry = first_opening(world, shaft.up).unwrap_or(Direction::ALL[0]);
    let exit = first_opening(world, shaft.landing).unwrap_or(Direction::ALL[0]);
    let pitch = world.resolved.tile_pitch;
    let half = 0.5 * pitch;
    let [cx, cy] = block_centre(shaft, half);
    let (centre, room) = (
        [x + cx, y + cy],
        s.room + if shaft.block.is_some() { half } else { 0.0 },
    );
    // The openings on the foot's and the landing's cell edges, from the block's centre.
    let opening = |d: Direction| {
        let (sr, sc) = d.step();
        [f64::from(sc) * half - cx, -f64::from(sr) * half - cy]
    };
    let key: Key = (
        entry as u8,
        exit as u8,
        shaft.block,
        [
            pitch,
            z1 - z0,
            s.half_width,
            s.width,
            s.height,
            s.per_turn,
            s.per_lead,
            s.rock,
            s.room,
            s.max_grade,
        ]
        .map(f64::to_bits),
    );
    let found = PLANS.lock().ok().and_then(|m| m.get(&key).cloned());
    let shape = match found {
        Some(p) => p,
        None => {
            let p = Helix::plan(
                [0.0, 0.0],
                [0.0, z1 - z0],
                [opening(entry), opening(exit)],
                room,
                s,
            );
            if let Ok(mut m) = PLANS.lock() {
                m.insert(key, p.clone());
            }
            p
        }
    };
    let mut h = shape?;
    if h.grade() > s.max_grade {
        return Err(Unfit::Steep { grade: h.grade() });
    }
    // Seeded by the world and the foot alone: the same winding for every tile around it.
    let foot =
        ((shaft.up.level as u64) << 40) | ((shaft.up.row as u64) << 20) | shaft.up.col as u64;
    let wound_key = (key, world.resolved.seed, foot);
    match WOUND.lock().ok().and_then(|m| m.get(&wound_key).cloned()) {
        Some(w) => h = w,
        None => {
            let pillar = s.half_width + 0.5 * s.rock;
            h.wind(
                Winding::draw(world.resolved.seed, foot, h.radius, pillar),
                s,
            );
            if let Ok(mut m) = WOUND.lock() {
                m.insert(wound_key, h.clone());
            }
        }
    }
    h.centre = centre;
    h.floors = [z0, z1];
    for o in &mut h.openings {
        *o = [o[0] + centre[0], o[1] + centre[1]];
    }
    Ok(h)
}

/// The centre of a ramp's spiral block from its foot cell's centre, metres east and north.
pub fn block_centre(shaft: &Shaft, half_pitch: f64) -> [f64; 2] {
    shaft.block.map_or([0.0, 0.0], |[dr, dc]| {
        [f64::from(dc) * half_pitch, -f64::from(dr) * half_pitch]
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sizing() -> Sizing {
        // The mine preset's: 20 m pitch, 6.4 x 5.6 m drift, collision lattice 1.67 m.
        Sizing {
            half_width: 3.3,
            width: 6.4,
            height: 4.0,
            per_turn: 4.0 + 0.2 + 2.0,
            per_lead: 5.7 + 0.2 + 2.0,
            rock: 2.0,
            room: 10.0 - 1.67,
            max_grade: 30.0,
        }
    }

    /// The opening of a cell centred `cell` metres from the spiral's centre, `pitch` wide.
    fn opening(cell: [f64; 2], d: Direction, pitch: f64) -> [f64; 2] {
        let (sr, sc) = d.step();
        [
            cell[0] + f64::from(sc) * 0.5 * pitch,
            cell[1] - f64::from(sr) * 0.5 * pitch,
        ]
    }

    /// Every way a one-cell spiral's openings face, and every way a 2 x 2 block's (its foot
    /// in the block's north-west cell, openings leaving the block).
    fn cases() -> Vec<([[f64; 2]; 2], f64, f64)> {
        let s = sizing();
        let pairs = Direction::ALL
            .into_iter()
            .flat_map(|a| Direction::ALL.map(|b| (a, b)));
        let mut out = Vec::new();
        for (a, b) in pairs {
            let at = |d| {
                [
                    100.0 + opening([0.0; 2], d, 20.0)[0],
                    40.0 + opening([0.0; 2], d, 20.0)[1],
                ]
            };
            out.push(([at(a), at(b)], s.room, 26.0));
        }
        let outward = [Direction::North, Direction::West];
        for a in outward {
            for b in outward {
                let at = |d| {
                    let o = opening([-10.0, 10.0], d, 20.0);
                    [100.0 + o[0], 40.0 + o[1]]
                };
                out.push(([at(a), at(b)], s.room + 10.0, 8.13));
            }
        }
        out
    }

    #[test]
    fn the_helix_joins_both_openings_tangentially_on_their_floors() {
        for (openings, room, steepest) in cases() {
            let h = Helix::plan([100.0, 40.0], [0.0, 16.0], openings, room, &sizing());
            eprintln!(
                "{openings:?} {room} {:?}",
                h.as_ref().map(|h| (h.grade(), h.flat, h.length, h.sense))
            );
            let h = h.unwrap();
            let line = h.floor_line();
            assert_eq!(line[0][2], 0.0);
            assert!((line.last().unwrap()[2] - 16.0).abs() < 1e-9);
            // Each lead continues the helix's direction at its end.
            for (end, (p, q), dir) in [(0, h.leads()[0], -1.0), (1, h.leads()[1], 1.0)] {
                let s = if end == 0 { 0.0 } else { h.length };
                let (t0, t1) = (h.at(s), h.at(s + 0.01 * dir));
                let tangent = [t1[0] - t0[0], t1[1] - t0[1]];
                let lead = [q[0] - p[0], q[1] - p[1]];
                let cross = tangent[0] * lead[1] - tangent[1] * lead[0];
                let dot = tangent[0] * lead[0] + tangent[1] * lead[1];
                assert!(dot > 0.0 && cross.abs() < 1e-3 * dot.abs(), "{cross} {dot}");
            }
            // Grade within its bound along the whole line, and turns a turn's room apart.
            let g = h.slope();
            for w in line.windows(2) {
                let run = ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt();
                assert!((w[1][2] - w[0][2]) / run <= g * 1.01 + 1e-9);
                assert!(w[1][2] >= w[0][2] - 1e-9);
            }
            assert!(h.separated(&sizing()));
            assert!(h.grade() < steepest, "{}", h.grade());
            // The passage keeps within `room` of the centre.
            assert!(h.radius + sizing().half_width <= room + 1e-9);
        }
    }

    /// Over many seeds and both spiral blocks' ways out, a wound ramp keeps the planned ends,
    /// its grade within its bound and its turns apart, and mostly winds: its radius and
    /// grade vary by 0.3 m and a quarter degree or more (most by far more).
    #[test]
    fn a_wound_ramp_varies_within_its_bounds() {
        let s = sizing();
        let (mut wound, mut all) = (0, 0);
        for (openings, room, _) in cases().into_iter().filter(|c| c.1 > s.room) {
            let planned = Helix::plan([100.0, 40.0], [0.0, 16.0], openings, room, &s).unwrap();
            for seed in 0..12 {
                let mut h = planned.clone();
                let pillar = s.half_width + 0.5 * s.rock;
                h.wind(Winding::draw(seed, 5, h.radius, pillar), &s);
                assert_eq!(h.leads(), planned.leads());
                assert!(h.steepest() <= s.max_grade, "{}", h.steepest());
                assert!(h.separated(&s));
                let line = h.floor_line();
                assert!((line.last().unwrap()[2] - 16.0).abs() < 1e-9);
                let (radius, grade) = h.ranges();
                eprintln!("{seed}: {:?} radius {radius:?} grade {grade:?}", h.winding);
                all += 1;
                if radius[1] - radius[0] > 0.3 && grade[1] - grade[0] > 0.25 {
                    wound += 1;
                }
            }
        }
        assert!(wound * 5 >= all * 4, "{wound} of {all} wound");
    }

    #[test]
    fn a_passage_too_tall_or_too_wide_is_refused() {
        let mut s = sizing();
        s.max_grade = 5.0;
        let east = opening([0.0; 2], Direction::East, 20.0);
        let e = Helix::plan([0.0; 2], [0.0, 16.0], [east, east], s.room, &s);
        assert!(matches!(e, Err(Unfit::Steep { .. })), "{e:?}");
        let mut s = sizing();
        s.half_width = 4.5;
        let e = Helix::plan([0.0; 2], [0.0, 16.0], [east, east], s.room, &s);
        assert!(matches!(e, Err(Unfit::Narrow { .. })), "{e:?}");
    }
}
