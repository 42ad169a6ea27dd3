//! `[hazards]`: what makes a world's floor hard to cross.
//!
//! ```toml
//! [hazards]
//! friction = { mud = 0.05, ice = 0.02 }   # share of the floor (whole tiles) per material
//! rubble = 0.1                            # share of corridor tiles with a rubble field
//! rubble_passable = true                  # keep a lane free of rocks (default true)
//! rubble_gap = 2.0                        # the lane's width, metres (a robot's width)
//! drops = 0.05                            # share of corridor tiles with a pit in the floor
//! ```
//!
//! Floor patches ([`Patch`]) are placed by the survey (`survey/src/hazards.rs`). Rubble fields and
//! drops are geometry: which tiles get one is decided here ([`HazardsSection::floor_hazard`],
//! per tile from the world's seed, so a tile set meshing one tile knows its neighbours'), and
//! the tile set that makes the geometry describes it ([`HazardRegion`], gathered in
//! `WorldMesh::hazards`) for the ground truth. Optional: a pipeline without the section makes
//! the files it always made.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::grid::{Cell, Direction};
use crate::rng::WorldRng;
use crate::tile::{Tile, TileKind};

/// A floor material with its own friction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FloorMaterial {
    /// Wet clay: sticky for feet, slippery for wheels.
    Mud,
    /// Frozen seepage.
    Ice,
    /// Loose sand.
    Sand,
    /// Rock under running water.
    WetRock,
}

impl FloorMaterial {
    /// Every material.
    pub const ALL: [FloorMaterial; 4] = [
        FloorMaterial::Mud,
        FloorMaterial::Ice,
        FloorMaterial::Sand,
        FloorMaterial::WetRock,
    ];

    /// The name in pipeline files and ground truth.
    pub const fn name(self) -> &'static str {
        match self {
            FloorMaterial::Mud => "mud",
            FloorMaterial::Ice => "ice",
            FloorMaterial::Sand => "sand",
            FloorMaterial::WetRock => "wet-rock",
        }
    }

    /// Coulomb friction coefficient (sliding), against rock's 0.8 in USD and 1.0 in MuJoCo.
    pub const fn friction(self) -> f64 {
        match self {
            FloorMaterial::Mud => 0.3,
            FloorMaterial::Ice => 0.05,
            FloorMaterial::Sand => 0.5,
            FloorMaterial::WetRock => 0.4,
        }
    }
}

/// A floor patch of `[hazards] friction`: a whole tile's floor of another material.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Patch {
    /// Its tile.
    pub cell: Cell,
    /// The tile's kind.
    pub tile_kind: TileKind,
    /// Its material.
    pub material: FloorMaterial,
    /// Its friction coefficient.
    pub friction: f64,
    /// The tile's square in the plane, `[x0, y0, x1, y1]`, metres.
    pub bounds: [f64; 4],
    /// The level's nominal floor, metres.
    pub floor_z: f64,
}

/// `[hazards]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HazardsSection {
    /// Share of the floor per material, whole tiles.
    #[serde(default)]
    pub friction: BTreeMap<FloorMaterial, f64>,
    /// Share of corridor tiles with a rubble field.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub rubble: f64,
    /// Whether a rubble field keeps a lane [`rubble_gap`](Self::rubble_gap) wide free of rocks.
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub rubble_passable: bool,
    /// Width of the lane a passable rubble field keeps, metres.
    #[serde(default = "default_gap", skip_serializing_if = "is_default_gap")]
    pub rubble_gap: f64,
    /// Share of corridor tiles with a drop (a pit) in the floor.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub drops: f64,
}

fn yes() -> bool {
    true
}

// `world.toml` leaves out what is as by default, so a world with only `friction` writes the
// section it always wrote.
fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

fn is_true(v: &bool) -> bool {
    *v
}

fn is_default_gap(v: &f64) -> bool {
    *v == default_gap()
}

fn default_gap() -> f64 {
    2.0
}

impl Default for HazardsSection {
    fn default() -> Self {
        HazardsSection {
            friction: BTreeMap::new(),
            rubble: 0.0,
            rubble_passable: true,
            rubble_gap: default_gap(),
            drops: 0.0,
        }
    }
}

/// A hazard that is geometry: the tile set makes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FloorHazard {
    /// Rocks on the floor, part of the collision surface.
    Rubble,
    /// A pit: the floor lowered over a region.
    Drop,
}

impl FloorHazard {
    /// The name in ground truth and semantic labels.
    pub const fn name(self) -> &'static str {
        match self {
            FloorHazard::Rubble => "rubble",
            FloorHazard::Drop => "drop",
        }
    }
}

/// Where a tile set put a rubble field or a drop, in world metres, for the ground truth.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HazardRegion {
    /// Rubble or drop.
    pub kind: FloorHazard,
    /// Its tile.
    pub cell: Cell,
    /// The region in the plane, `[x0, y0, x1, y1]`: every rock (rubble) or the pit's rim
    /// (drop) is inside.
    pub bounds: [f64; 4],
    /// The level's nominal floor.
    pub floor_z: f64,
    /// Lowest and highest point: the floor and the highest rock top (rubble), the pit's
    /// bottom and the floor (drop).
    pub z: [f64; 2],
    /// A passable rubble field's lane free of rocks, `[x0, y0, x1, y1]` (it runs along the
    /// whole field).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap: Option<[f64; 4]>,
    /// Rubble: each rock as `[x, y, z, radius]` (a sphere, roughened by the wall relief).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rocks: Vec<[f64; 4]>,
}

/// A layout's rubble fields and drops, resolved from `[hazards]` when the layout is made
/// ([`crate::layout::Layout::floor_hazards`]): which corridor tiles get one and on which arm,
/// and the knobs the tile set that makes them needs. Plain data: a tile set reads this, never
/// the pipeline.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FloorHazards {
    /// Whether the pipeline asks for rubble fields (`hazards.rubble` above 0).
    pub rubble: bool,
    /// Whether it asks for drops (`hazards.drops` above 0): the levels' blocks then reach
    /// deeper, whether or not a tile drew one.
    pub drops: bool,
    /// Whether a rubble field keeps a lane `rubble_gap` wide free of rocks.
    pub rubble_passable: bool,
    /// Width of that lane, metres.
    pub rubble_gap: f64,
    /// Each tile with a rubble field or a drop, and the arm (toward which opening) it lies on
    /// ([`HazardsSection::floor_hazard`]).
    pub tiles: BTreeMap<Cell, (FloorHazard, Direction)>,
}

impl FloorHazards {
    /// The hazards `section` asks of the tiles in `cells` (with their tiles), `start` the
    /// start tile; none without a section.
    pub fn resolve(
        section: Option<&HazardsSection>,
        seed: u64,
        cells: impl IntoIterator<Item = (Cell, Tile)>,
        start: Option<Cell>,
    ) -> FloorHazards {
        let Some(h) = section else {
            return FloorHazards::default();
        };
        FloorHazards {
            rubble: h.rubble > 0.0,
            drops: h.drops > 0.0,
            rubble_passable: h.rubble_passable,
            rubble_gap: h.rubble_gap,
            tiles: cells
                .into_iter()
                .filter_map(|(c, t)| Some((c, h.floor_hazard(seed, c, &t, start == Some(c))?)))
                .collect(),
        }
    }

    /// Whether the pipeline asks for hazards a tile set must make (rubble, drops).
    pub fn asked(&self) -> bool {
        self.rubble || self.drops
    }

    /// The rubble field or drop of the tile at `cell`, and its arm.
    pub fn at(&self, cell: Cell) -> Option<(FloorHazard, Direction)> {
        self.tiles.get(&cell).copied()
    }
}

impl HazardsSection {
    /// Whether the section asks for hazards a tile set must make (rubble, drops).
    pub fn has_geometry(&self) -> bool {
        self.rubble > 0.0 || self.drops > 0.0
    }

    /// The geometric hazard of a tile, if any, and the arm (toward which opening) it lies on.
    ///
    /// Only corridor tiles (straight and corner tiles, not the start) get one, each with
    /// probability `rubble` (a rubble field) or `drops` (a drop), drawn from the world's
    /// `"floor-hazards"` stream keyed by the cell: the same answer whichever tile asks.
    pub fn floor_hazard(
        &self,
        seed: u64,
        cell: Cell,
        tile: &Tile,
        start: bool,
    ) -> Option<(FloorHazard, Direction)> {
        if !self.has_geometry() || start {
            return None;
        }
        if !matches!(tile.kind, TileKind::Straight | TileKind::Corner) {
            return None;
        }
        let key = ((cell.level as u64) << 40) | ((cell.row as u64) << 20) | cell.col as u64;
        let mut rng = WorldRng::new(seed, "floor-hazards", key);
        let u = rng.unit();
        let kind = if u < self.rubble {
            FloorHazard::Rubble
        } else if u < self.rubble + self.drops {
            FloorHazard::Drop
        } else {
            return None;
        };
        let arms: Vec<Direction> = Direction::ALL
            .into_iter()
            .filter(|d| tile.openings & d.bit() != 0)
            .collect();
        let arm = *arms.get(rng.below(arms.len().max(1) as u64) as usize)?;
        Some((kind, arm))
    }

    /// What is wrong with the section, as `(key, message)`.
    pub fn problem(&self) -> Option<(&'static str, String)> {
        for (key, v) in [
            ("hazards.rubble", self.rubble),
            ("hazards.drops", self.drops),
        ] {
            if !(v.is_finite() && (0.0..=1.0).contains(&v)) {
                return Some((
                    key,
                    format!("{v} is not a share: give a number from 0 to 1, e.g. 0.1"),
                ));
            }
        }
        // Shares written to add up to 1 may sum to a hair above it in binary (mud = 0.34,
        // ice = 0.56, sand = 0.1 sum to 1.0000000000000002): the whole floor is allowed.
        const WHOLE: f64 = 1.0 + 1e-9;
        if self.rubble + self.drops > WHOLE {
            return Some((
                "hazards.drops",
                "rubble and drops together are more than every corridor tile (1); lower them"
                    .into(),
            ));
        }
        if !(self.rubble_gap.is_finite() && (0.5..=20.0).contains(&self.rubble_gap)) {
            return Some((
                "hazards.rubble_gap",
                format!(
                    "{} m: give the width of the lane kept free of rocks, from 0.5 to 20 metres",
                    self.rubble_gap
                ),
            ));
        }
        if self
            .friction
            .values()
            .any(|s| !(s.is_finite() && (0.0..=1.0).contains(s)))
        {
            return Some((
                "hazards.friction",
                "each share is a number from 0 to 1, e.g. friction = { mud = 0.05 }".into(),
            ));
        }
        if self.friction.values().sum::<f64>() > WHOLE {
            return Some((
                "hazards.friction",
                "the shares add up to more than the whole floor (1); lower them".into(),
            ));
        }
        None
    }

    /// Which tiles get which material: `tiles` (the candidates, in a fixed order) shuffled by
    /// the world's `"hazards"` stream, then `round(share x count)` for each material in name
    /// order.
    pub fn assign<T: Copy>(&self, seed: u64, tiles: &[T]) -> Vec<(T, FloorMaterial)> {
        let mut order: Vec<T> = tiles.to_vec();
        WorldRng::new(seed, "hazards", 0).shuffle(&mut order);
        let mut out = Vec::new();
        let mut next = 0;
        for (&m, &share) in &self.friction {
            let n = (share * tiles.len() as f64).round() as usize;
            let n = n.min(order.len() - next);
            out.extend(order[next..next + n].iter().map(|&t| (t, m)));
            next += n;
        }
        out
    }
}
