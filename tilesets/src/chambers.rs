//! Chambers and squeezes: where a passage opens into a room, and where it closes down to a
//! crawl, as the places a robot's autonomy is tested on (planning through a narrow place,
//! localising in a room whose walls are far away).
//!
//! Both are drawn per cell from the world seed (streams `"chambers"` and `"squeezes"`), so
//! whichever tile evaluates the field computes the same ones, and both keep to their own cell:
//!
//! - A **chamber** is a room centred on a junction or dead-end tile, `size` times the passage
//!   width across (a round room in caves and lava tubes, a rectangular one in mines, with the
//!   style's own cross-section: dome, benches or arched back), a little higher than the
//!   passage. It is clamped to fit its cell's block: with its width variation (it follows 30 %
//!   of the passage's) and wall relief its walls stay two lattice cells inside the tile's faces
//!   (on the default 25 m pitch a cave chamber is at most about 18 m across, 2.1 widths of its
//!   8.5 m passage). Its corridors run into it: the field is their union.
//! - A **squeeze** narrows (or lowers) a straight or corner tile's passage about its centre to
//!   `factor` of its size over `length` metres, then widens it back smoothly to its full size
//!   15 % of half a pitch before the tile's faces, so the neighbours meet the nominal passage
//!   and stay seamless.
//!
//! `min_clearance = [width, height]` (metres, a robot's size) bounds every squeeze: a squeeze
//! never makes the passage narrower or lower than a box that wide and high standing on the
//! floor about the axis, with room to spare for the wall relief and for the coarser collision
//! lattice (half a collision cell). Rocks are kept out of that box too. A `min_clearance` that
//! even the unsqueezed passage cannot hold is an error naming the key.

use serde::Deserialize;
use subtgraph_core::grid::Cell;
use subtgraph_core::rng::WorldRng;
use subtgraph_core::tile::TileKind;

use subtgraph_core::Layout;

pub use crate::passage::{DEFAULT_CLEARANCE, Rooms};
use crate::passage::{Levels, Passage, Profile};

/// The chamber and the squeeze of an occupied cell (either, or none), as every tile around it
/// computes them; `lattice` is the visual lattice's spacing.
pub fn of_cell(
    world: &Layout,
    c: Cell,
    kind: TileKind,
    passage: &Passage,
    levels: Levels,
    lattice: f64,
) -> (Option<Chamber>, Option<Squeeze>) {
    let seed = world.resolved.seed;
    let pitch = world.resolved.tile_pitch;
    let rooms = &passage.rooms;
    let chamber = rooms.chamber(
        seed,
        c,
        kind,
        world.cell_position(c),
        passage.width,
        passage.height,
        [passage.width_variation, passage.height_variation],
        passage.roughness,
        Room {
            half: 0.5 * pitch - 2.0 * lattice,
            // Floors rise by up to the slope's amplitude (`tilesets/src/slope.rs`).
            head: levels.head() - passage.floor_roughness - passage.slope.amp,
        },
    );
    (chamber, rooms.squeeze(seed, c, kind, pitch))
}

/// What a tile set tells the ground truth about a cell: `chamber`, `squeeze`, or nothing.
pub fn labels(chamber: &Option<Chamber>, squeeze: &Option<Squeeze>) -> Vec<&'static str> {
    let mut out = Vec::new();
    if chamber.is_some() {
        out.push("chamber");
    }
    if squeeze.is_some() {
        out.push("squeeze");
    }
    out
}

/// `chambers = { rate = 0.3, size = [2.0, 3.0] }` in `[tileset]`.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChamberSettings {
    /// Share of junction and dead-end tiles that get a chamber, 0 to 1.
    pub rate: Option<f64>,
    /// Chamber width as multiples of the passage width, `[low, high]`, each at least 1.
    pub size: Option<[f64; 2]>,
}

/// `squeezes = { rate = 0.15, length = [3.0, 8.0], factor = [0.45, 0.7] }` in `[tileset]`.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SqueezeSettings {
    /// Share of straight and corner tiles that get a squeeze, 0 to 1.
    pub rate: Option<f64>,
    /// Length of the narrowest part, metres, `[low, high]`.
    pub length: Option<[f64; 2]>,
    /// The passage's size there, as a share of its size elsewhere, `[low, high]`, in (0, 1].
    pub factor: Option<[f64; 2]>,
}

/// How much of the passage's width variation a chamber's walls follow: a little, so they are
/// not perfect ellipses, but not all of it, so the room can be larger within its block.
pub const WALL_SHARE: f64 = 0.3;

/// A room about a cell's centre.
#[derive(Clone, Debug, PartialEq)]
pub struct Chamber {
    /// Centre in the plane.
    pub centre: [f64; 2],
    /// Floor height.
    pub floor: f64,
    /// Half-widths along x and y (nominal, before the width variation).
    pub radii: [f64; 2],
    /// Nominal floor-to-ceiling height.
    pub height: f64,
    /// Round or rectangular.
    pub round: bool,
}

impl Chamber {
    /// The section value and height above the floor at `p`, for the column's width and height
    /// scales (the passage's variation, shared with the corridors so the room's walls vary as
    /// theirs do).
    pub fn section(
        &self,
        profile: &dyn Profile,
        p: [f64; 3],
        width_scale: f64,
        height_scale: f64,
        rubble: f64,
    ) -> (f64, f64) {
        let dx = (p[0] - self.centre[0]) / self.radii[0];
        let dy = (p[1] - self.centre[1]) / self.radii[1];
        let n = if self.round {
            (dx * dx + dy * dy).sqrt()
        } else {
            // A rounded rectangle (superellipse of degree 8).
            (dx.powi(8) + dy.powi(8)).powf(0.125)
        };
        let r = self.radii[0];
        let v = p[2] - self.floor - rubble;
        let wide = 1.0 + WALL_SHARE * (width_scale - 1.0);
        (
            profile.section(n * r, v, 2.0 * r * wide, self.height * height_scale),
            v,
        )
    }

    /// Highest point of its ceiling above the floor, with the height variation.
    pub fn top(&self, height_variation: f64) -> f64 {
        self.height * (1.0 + height_variation)
    }
}

/// A narrow or low place about a corridor tile's centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Squeeze {
    /// Half the length of the narrowest part, metres along the axis from the centre.
    pub plateau: f64,
    /// Where the passage is back to its full size, metres from the centre.
    pub end: f64,
    /// Width and height factors at the narrowest part.
    pub factor: [f64; 2],
}

impl Squeeze {
    /// The width and height multipliers `s` metres along the axis from the tile's centre.
    pub fn scale(&self, s: f64) -> [f64; 2] {
        let t = ((s - self.plateau) / (self.end - self.plateau)).clamp(0.0, 1.0);
        let k = t * t * (3.0 - 2.0 * t);
        self.factor.map(|f| f + (1.0 - f) * k)
    }
}

fn cell_key(c: Cell) -> u64 {
    ((c.level as u64) << 40) | ((c.row as u64) << 20) | c.col as u64
}

/// What the room around a chamber has to stay within.
#[derive(Clone, Copy, Debug)]
pub struct Room {
    /// Most metres from the centre to a wall, relief included (half a pitch less a margin).
    pub half: f64,
    /// Most metres from the floor to the ceiling's highest point, relief included.
    pub head: f64,
}

impl Rooms {
    /// The chamber of cell `c` (a junction or dead end), if it has one: `width`, `height` and
    /// the variations and `relief` are the passage's.
    #[allow(clippy::too_many_arguments)]
    pub fn chamber(
        &self,
        seed: u64,
        c: Cell,
        kind: TileKind,
        centre: [f64; 3],
        width: f64,
        height: f64,
        variation: [f64; 2],
        relief: f64,
        room: Room,
    ) -> Option<Chamber> {
        if self.chamber_rate <= 0.0
            || !matches!(
                kind,
                TileKind::DeadEnd | TileKind::TJunction | TileKind::Intersection
            )
        {
            return None;
        }
        let mut rng = WorldRng::new(seed, "chambers", cell_key(c));
        if rng.unit() >= self.chamber_rate {
            return None;
        }
        let [lo, hi] = self.chamber_size;
        let size = if hi > lo { rng.float_in(lo, hi) } else { lo };
        let aspect = rng.float_in(0.85, 1.0);
        let across_x = rng.coin();
        // Clamped so that the widest wall, with its variation and relief, stays inside.
        let most = ((room.half - relief) / (1.0 + WALL_SHARE * variation[0])).max(0.0);
        let r = (0.5 * size * width).min(most);
        if r <= 0.5 * width {
            return None;
        }
        let radii = if across_x {
            [r, r * aspect]
        } else {
            [r * aspect, r]
        };
        // A little higher than the passage (a quarter of the passage height per extra width),
        // up to what the level holds.
        let wanted = height * (1.0 + 0.25 * (size - 1.0));
        let most_h = (room.head - relief) / (1.0 + variation[1]);
        Some(Chamber {
            centre: [centre[0], centre[1]],
            floor: centre[2],
            radii,
            height: wanted.min(most_h).max(height),
            round: self.chamber_round,
        })
    }

    /// The squeeze of cell `c` (a straight or corner tile), if it has one, for a pitch.
    pub fn squeeze(&self, seed: u64, c: Cell, kind: TileKind, pitch: f64) -> Option<Squeeze> {
        if self.squeeze_rate <= 0.0 || !matches!(kind, TileKind::Straight | TileKind::Corner) {
            return None;
        }
        let mut rng = WorldRng::new(seed, "squeezes", cell_key(c));
        if rng.unit() >= self.squeeze_rate {
            return None;
        }
        let low = rng.unit() < self.low_share;
        let [flo, fhi] = self.squeeze_factor;
        let drawn = if fhi > flo {
            rng.float_in(flo, fhi)
        } else {
            flo
        };
        let [llo, lhi] = self.squeeze_length;
        let length = if lhi > llo {
            rng.float_in(llo, lhi)
        } else {
            llo
        };
        let k = usize::from(low);
        let f = drawn.max(self.least_factor[k]);
        if f >= 1.0 {
            return None;
        }
        let end = 0.85 * 0.5 * pitch;
        let mut factor = [1.0, 1.0];
        factor[k] = f;
        Some(Squeeze {
            plateau: (0.5 * length).min(0.5 * end),
            end,
            factor,
        })
    }
}

/// Whether a box `clearance` wide and high, standing on the floor about the axis and grown by
/// `slack` to the sides and above, is inside `profile` of `width` and `height` wherever a wall
/// relief of amplitude `relief` puts the walls (the field adds `relief` times the height above
/// the floor, up to a metre, to the section).
pub fn fits(
    profile: &dyn Profile,
    width: f64,
    height: f64,
    clearance: [f64; 2],
    relief: f64,
    slack: f64,
) -> bool {
    let [cw, ch] = clearance;
    (0..=16).all(|j| {
        let v = 0.02 + (ch + slack - 0.02) * f64::from(j) / 16.0;
        (0..=8).all(|i| {
            let u = (0.5 * cw + slack) * f64::from(i) / 8.0;
            profile.section(u, v, width, height) + relief * v.min(1.0) < 0.0
        })
    })
}

/// The least width and height factors that keep a `clearance` box inside the narrowest
/// passage (`width` and `height` at their smallest), as [`fits`] says: more than 1 when even
/// the full passage cannot.
pub fn least_factors(
    profile: &dyn Profile,
    width: f64,
    height: f64,
    clearance: [f64; 2],
    relief: f64,
    slack: f64,
) -> [f64; 2] {
    let search = |fits_at: &dyn Fn(f64) -> bool| {
        if !fits_at(1.0) {
            return f64::INFINITY;
        }
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..30 {
            let mid = 0.5 * (lo + hi);
            if fits_at(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        hi
    };
    [
        search(&|f| fits(profile, f * width, height, clearance, relief, slack)),
        search(&|f| fits(profile, width, f * height, clearance, relief, slack)),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cave::Gallery;
    use crate::lava_tube::Tube;

    #[test]
    fn a_squeeze_is_back_to_full_size_before_the_faces() {
        let s = Squeeze {
            plateau: 2.0,
            end: 10.0,
            factor: [0.5, 1.0],
        };
        assert_eq!(s.scale(0.0), [0.5, 1.0]);
        assert_eq!(s.scale(2.0), [0.5, 1.0]);
        assert_eq!(s.scale(10.0), [1.0, 1.0]);
        assert_eq!(s.scale(12.5), [1.0, 1.0]);
        let mid = s.scale(6.0)[0];
        assert!(mid > 0.5 && mid < 1.0);
    }

    #[test]
    fn least_factors_keep_the_robot_inside_and_no_more() {
        let (w, h) = (8.0, 7.0);
        for profile in [&Gallery as &dyn Profile, &Tube] {
            let f = least_factors(profile, w, h, [1.5, 1.2], 0.3, 0.5);
            assert!(f[0] < 1.0 && f[1] < 1.0, "{f:?}");
            assert!(fits(profile, f[0] * w, h, [1.5, 1.2], 0.3, 0.5));
            assert!(!fits(profile, (f[0] - 0.01) * w, h, [1.5, 1.2], 0.3, 0.5));
            assert!(!fits(profile, w, (f[1] - 0.01) * h, [1.5, 1.2], 0.3, 0.5));
        }
        // A robot wider than the passage fits no squeeze, not even none.
        assert!(least_factors(&Gallery, w, h, [9.0, 1.0], 0.0, 0.0)[0].is_infinite());
    }

    #[test]
    fn chambers_are_drawn_per_cell_and_fit_their_block() {
        let rooms = Rooms {
            chamber_rate: 1.0,
            chamber_size: [2.0, 3.0],
            ..Rooms::default()
        };
        let room = Room {
            half: 10.0,
            head: 12.0,
        };
        let c = Cell::new(0, 3, 4);
        let at = |cell: Cell| {
            rooms.chamber(
                7,
                cell,
                TileKind::TJunction,
                [0.0, 0.0, 0.0],
                8.0,
                7.0,
                [0.2, 0.2],
                0.7,
                room,
            )
        };
        let a = at(c).expect("rate 1: a chamber");
        assert_eq!(Some(a.clone()), at(c), "seeded per cell");
        assert!(a.radii[0].max(a.radii[1]) * (1.0 + WALL_SHARE * 0.2) + 0.7 <= 10.0 + 1e-9);
        assert!(a.radii[0].max(a.radii[1]) > 4.0);
        assert!(a.top(0.2) + 0.7 <= 12.0 + 1e-9);
        // Corridor tiles get none.
        let none = rooms.chamber(
            7,
            c,
            TileKind::Straight,
            [0.0; 3],
            8.0,
            7.0,
            [0.2, 0.2],
            0.7,
            room,
        );
        assert!(none.is_none());
    }
}
