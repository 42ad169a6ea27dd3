//! `ground_truth/artifacts.json`: every artifact's class, pose, tile, graph place and whether it
//! is seen from its passage's axis (written with every world that has `[artifacts]`; `score`
//! matches a team's reports against it).
//!
//! `S` is the type of the fixed texts (`format`, `frame`, ...): `&'static str` where the
//! writer fills them in, `String` (the default) where a file is read.

use std::borrow::Cow;

use serde::{Deserialize, Serialize};
use subtgraph_core::artifacts::{ArtifactClass, Placement};
use subtgraph_core::grid::Cell;
use subtgraph_core::tile::TileKind;

use crate::{Document, SchemaError, finite};

/// `ground_truth/artifacts.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Artifacts<'a, S = String> {
    /// [`Artifacts::FORMAT`](Document::FORMAT).
    pub format: S,
    /// The world's seed.
    pub seed: u64,
    /// The frame, in words.
    pub frame: S,
    /// Units, in words.
    pub units: S,
    /// What `position` is, in words.
    pub position: S,
    /// How many artifacts.
    pub count: usize,
    /// With `[artifacts] hidden`: how many were asked to be out of the axis's sight, and how
    /// many are (fewer when the world has too few hidden spots; absent without the key).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hidden: Option<Hidden>,
    /// The artifacts, by id.
    pub artifacts: Vec<ArtifactEntry<'a>>,
}

/// The hidden artifacts asked for and placed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Hidden {
    /// `[artifacts] hidden`.
    pub share_requested: f64,
    /// Artifacts that share asks for.
    pub requested: usize,
    /// Artifacts out of sight of their axis.
    pub placed: usize,
    /// `placed / count`.
    pub share_placed: f64,
}

/// Where an artifact is on the graph.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GraphPlace {
    /// In the tile of a node.
    Node {
        /// Node id in `topology.json`.
        node: usize,
    },
    /// In a corridor tile between two nodes.
    Edge {
        /// Edge id in `topology.json`.
        edge: usize,
        /// Metres along the edge from its `from` node to the tile's centre.
        along_m: f64,
    },
}

/// One artifact of `artifacts.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ArtifactEntry<'a> {
    /// Index, 0 up.
    pub id: usize,
    /// `class-id`, unique in the world (`survivor-0`).
    pub name: Cow<'a, str>,
    /// What it is.
    pub class: ArtifactClass,
    /// The centre of its base, on the floor (world frame, metres).
    pub position: [f64; 3],
    /// Heading of its length about z, radians counter-clockwise from east.
    pub yaw: f64,
    /// Its box, `[length, width, height]` metres.
    pub size: [f64; 3],
    /// Its tile.
    pub cell: Cell,
    /// The tile's kind.
    pub tile_kind: TileKind,
    /// The rule it was placed by.
    pub placement: Placement,
    /// Node or edge of its tile.
    pub graph: GraphPlace,
    /// From the start tile's centre to its tile's centre along the graph, metres.
    pub distance_from_start_m: f64,
    /// Its orientation, `[x, y, z, w]`.
    pub quaternion_xyzw: [f64; 4],
    /// The centre of its box.
    pub centre: [f64; 3],
    /// Mass, kilograms.
    pub mass_kg: f64,
    /// Colour, linear RGB 0 to 1.
    pub colour_rgb: [f32; 3],
    /// Whether the line from `sight_from` to its centre stays in free space.
    pub visible_from_axis: bool,
    /// The eye the line of sight starts from.
    pub sight_from: [f64; 3],
}

impl Document for Artifacts<'_> {
    const PATH: &'static str = "ground_truth/artifacts.json";
    const FORMAT: &'static str = "subtgraph-artifacts/1";

    fn format(&self) -> &str {
        &self.format
    }

    fn check(&self) -> Result<(), SchemaError> {
        if self.count != self.artifacts.len() {
            return Err(SchemaError::invalid::<Self>(format!(
                "count is {}, but {} artifacts are listed",
                self.count,
                self.artifacts.len()
            )));
        }
        for (i, a) in self.artifacts.iter().enumerate() {
            if a.id != i {
                return Err(SchemaError::invalid::<Self>(format!(
                    "artifact {i} has id {}",
                    a.id
                )));
            }
            finite::<Self>(|| format!("artifact {i}'s position"), &a.position)?;
        }
        Ok(())
    }
}
