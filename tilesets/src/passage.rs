//! What a procedural passage is: its cross-section ([`Profile`]), its knobs ([`Passage`]:
//! sizes, variations, roughness, rocks, bends, slopes, and the chambers and squeezes of
//! [`Rooms`]), the materials it paints ([`material`]) and the vertical layout of a world's
//! levels ([`Levels`]).
//!
//! Plain data shared by everything that lays a passage out (the field, chambers, ramps,
//! rubble); it depends on none of them, so they do not depend on each other through it.

use crate::bends::Bends;
use crate::finish::Finish;
use crate::services::Services;
use crate::slope::Slope;

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
    /// Walls and back under welded mesh panels (from [`Passage::mesh_from`](super::Passage)
    /// up): the tile set's materials are the four above, so this one follows them.
    pub const MESHED: u8 = 4;
}

/// The shape of a passage across its axis.
pub trait Profile: Send + Sync {
    /// Negative inside the passage: `u >= 0` metres sideways from the axis, `v` metres above
    /// the floor, for a passage `width` wide and `height` high here.
    fn section(&self, u: f64, v: f64, width: f64, height: f64) -> f64;

    /// The section without its floor (its walls and back alone), for a profile whose
    /// [`section`](Self::section) is this `.max(-v)`; `None` (the default) when the floor
    /// cannot be told apart. A wall finish ([`crate::finish`]) moves only this part, so the
    /// floor stays where it is at every lattice point, and so in the mesh.
    fn walls(&self, _u: f64, _v: f64, _width: f64, _height: f64) -> Option<f64> {
        None
    }
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
    /// Amplitude of wall relief (with a [`Finish`] other than plain, its peak).
    pub roughness: f64,
    /// How walls and back are finished: the style's relief, blasted rock or shotcrete
    /// (see [`crate::finish`]).
    pub finish: Finish,
    /// Metres of straight drift per refuge bay on average (0: none; see [`crate::refuge`]).
    pub refuge_spacing: f64,
    /// Bolts, duct, pipes, cable and lights (see [`crate::services`]).
    pub services: Services,
    /// Metres above the floor from which welded mesh panels cover the walls and back
    /// (0: none). They are painted, not modelled: see [`crate::finish`] for why.
    pub mesh_from: f64,
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
    /// How passages turn at corner cells (see [`crate::bends`]).
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
            finish: Finish::Plain,
            refuge_spacing: 0.0,
            services: Services::NONE,
            mesh_from: 0.0,
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

/// Chambers and squeezes of one world, resolved to metres (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Rooms {
    /// Share of junction and dead-end tiles with a chamber.
    pub chamber_rate: f64,
    /// Chamber width in passage widths, `[low, high]`.
    pub chamber_size: [f64; 2],
    /// Round rooms (caves, lava tubes) or rectangular ones (mine stopes).
    pub chamber_round: bool,
    /// Share of straight and corner tiles with a squeeze.
    pub squeeze_rate: f64,
    /// Length of a squeeze's narrowest part: in a style, as a share of the pitch; resolved,
    /// metres.
    pub squeeze_length: [f64; 2],
    /// Size factor at a squeeze's narrowest part, `[low, high]`.
    pub squeeze_factor: [f64; 2],
    /// Chance that a squeeze is low (a crawl) rather than narrow.
    pub low_share: f64,
    /// Least width and height a squeeze leaves, metres.
    pub min_clearance: [f64; 2],
    /// The least width and height factors `min_clearance` allows (resolved; 1 or more: no
    /// squeeze of that kind fits).
    pub least_factor: [f64; 2],
}

impl Default for Rooms {
    /// No chambers, no squeezes, a 1 m robot.
    fn default() -> Self {
        Rooms {
            chamber_rate: 0.0,
            chamber_size: [2.0, 3.0],
            chamber_round: true,
            squeeze_rate: 0.0,
            squeeze_length: [0.12, 0.3],
            squeeze_factor: [0.45, 0.7],
            low_share: 0.5,
            min_clearance: [DEFAULT_CLEARANCE, DEFAULT_CLEARANCE],
            least_factor: [0.0, 0.0],
        }
    }
}

/// `min_clearance` when not given: a small ground robot, metres.
pub const DEFAULT_CLEARANCE: f64 = 1.0;
