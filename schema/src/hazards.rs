//! `ground_truth/hazards.json`: the floor patches of `[hazards]` (tile, material, friction) and
//! the rubble fields and drops the tile set made (written by the ground-truth exporters).

use std::borrow::Cow;

use serde::{Deserialize, Serialize};
use subtgraph_core::grid::Cell;
use subtgraph_core::hazards::{FloorMaterial, HazardRegion};
use subtgraph_core::tile::TileKind;

use crate::Document;

/// `ground_truth/hazards.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Hazards<'a, S = String> {
    /// [`Hazards::FORMAT`](Document::FORMAT).
    pub format: S,
    /// The world's seed.
    pub seed: u64,
    /// The frame, in words.
    pub frame: S,
    /// What the lists hold, in words.
    pub note: S,
    /// Floor patches, in raster order of their tiles.
    pub patches: Cow<'a, [HazardPatch]>,
    /// Rubble fields and drops.
    pub regions: Cow<'a, [HazardRegion]>,
}

/// A floor patch: a whole tile's floor of one material.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct HazardPatch {
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

impl Document for Hazards<'_> {
    const PATH: &'static str = "ground_truth/hazards.json";
    const FORMAT: &'static str = "subtgraph-hazards/1";

    fn format(&self) -> &str {
        &self.format
    }
}
