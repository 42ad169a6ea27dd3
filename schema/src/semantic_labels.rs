//! `ground_truth/semantic_labels.json`: every tile's kind, rotation, openings, position and
//! features (written by the exporters' `SemanticLabels`).
//!
//! `S` is the type of the fixed texts (kinds, openings, features): `&'static str` where the
//! writer fills them in, `String` (the default) where a file is read.

use serde::{Deserialize, Serialize};

use crate::Document;

/// `ground_truth/semantic_labels.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SemanticLabels<S = String> {
    /// [`SemanticLabels::FORMAT`](Document::FORMAT).
    pub format: S,
    /// The world's seed.
    pub seed: u64,
    /// The frame, in words.
    pub frame: S,
    /// Units, in words.
    pub units: S,
    /// Metres between tile centres.
    pub tile_pitch_m: f64,
    /// Metres between levels.
    pub level_height_m: f64,
    /// Every kind a label may have.
    pub kinds: [S; 8],
    /// One label per occupied cell, in raster order.
    pub tiles: Vec<TileLabel<S>>,
}

/// One tile's label.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TileLabel<S = String> {
    /// Its level.
    pub level: usize,
    /// Its row.
    pub row: usize,
    /// Its column.
    pub col: usize,
    /// Its kind (one of `kinds`).
    pub kind: S,
    /// The kind's spatial code (as `occupancy.npy`).
    pub code: u8,
    /// Quarter turns counter-clockwise from the kind's base orientation.
    pub rotation: u8,
    /// The directions it opens to (`east`, `north`, `west`, `south`).
    pub openings: Vec<S>,
    /// On its passage's floor, metres.
    pub position: [f64; 3],
    /// Whether it is the start tile.
    pub start: bool,
    /// What the tile set made of the tile beyond its kind (`chamber`, `squeeze`), if anything.
    #[serde(default = "Vec::new", skip_serializing_if = "Vec::is_empty")]
    pub features: Vec<S>,
    /// The floor patch's material (`[hazards] friction`) and `rubble` or `drop`, on those
    /// tiles only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hazard: Option<String>,
    /// The steepest grade along the tile's passage axis, degrees (absent without a mesh).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grade_deg: Option<f64>,
    /// Whether that grade makes the tile a `slope` a robot climbs or descends.
    pub slope: bool,
}

impl Document for SemanticLabels {
    const PATH: &'static str = "ground_truth/semantic_labels.json";
    const FORMAT: &'static str = "subtgraph-semantic-labels/1";

    fn format(&self) -> &str {
        &self.format
    }
}
