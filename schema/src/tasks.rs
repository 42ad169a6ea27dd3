//! `tasks/tasks.json`: what the MovingAI planning benchmark files beside it hold (their grid's
//! resolution and origin in the world frame, the seed, each level's files and counts), written
//! by the exporters' `Tasks`.
//!
//! `S` is the type of the fixed texts: `&'static str` where the writer fills them in,
//! `String` (the default) where a file is read.

use serde::{Deserialize, Serialize};

use crate::{Document, SchemaError, finite};

/// `tasks/tasks.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Tasks<S = String> {
    /// [`Tasks::FORMAT`](Document::FORMAT).
    pub format: S,
    /// The world's seed; the problems are drawn from streams derived from it.
    pub seed: u64,
    /// The world frame, in words.
    pub frame: S,
    /// Where the free space came from (`collision-mesh` or `grid`).
    pub source: S,
    /// A map cell's edge, metres.
    pub resolution_m: f64,
    /// World `[x, y]` of the south-west corner of the map's south-west cell (row `height - 1`,
    /// column 0), metres: the ROS map's `origin` convention.
    pub origin: [f64; 2],
    /// How cell `(x, y)` of a `.map` maps to world metres, in words.
    pub cell_centre: S,
    /// Metres above each level's floor where free space is sliced (a cell is free where the
    /// slice is inside a passage at its centre).
    pub slice_height_m: f64,
    /// The moves and costs the optimal lengths assume, in words.
    pub movement: S,
    /// How problems are drawn, in words.
    pub sampling: S,
    /// Single-agent problems asked for per level.
    pub problems_requested: u32,
    /// Agents asked for per multi-agent instance.
    pub agents_requested: u32,
    /// Multi-agent instances per level.
    pub instances: u32,
    /// One entry per level.
    pub levels: Vec<TaskLevel>,
}

/// One level's benchmark files and what they hold.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TaskLevel {
    /// The level, 0 at the bottom.
    pub level: usize,
    /// The map's file name, beside `tasks.json`.
    pub map: String,
    /// The single-agent scenario file's name.
    pub scen: String,
    /// The multi-agent scenario files' names (`level-N-random-K.scen`, K from 1).
    pub instances: Vec<String>,
    /// Map columns.
    pub width: usize,
    /// Map rows.
    pub height: usize,
    /// World z of the slice, metres (over the level's nominal floor).
    pub z_m: f64,
    /// Free (`.`) cells.
    pub free_cells: u64,
    /// Connected groups of free cells under the moves of [`Tasks::movement`].
    pub components: u64,
    /// Cells of the largest group.
    pub largest_component: u64,
    /// Single-agent problems written (0 when no group has two cells).
    pub problems: u32,
    /// Agents in each multi-agent instance (fewer than asked when the level has too few free
    /// cells for distinct starts and goals).
    pub agents: u32,
}

impl Document for Tasks {
    const PATH: &'static str = "tasks/tasks.json";
    const FORMAT: &'static str = "subtgraph-tasks/1";

    fn format(&self) -> &str {
        &self.format
    }

    fn check(&self) -> Result<(), SchemaError> {
        finite::<Self>(|| "resolution_m".into(), &[self.resolution_m])?;
        finite::<Self>(|| "origin".into(), &self.origin)?;
        if self.resolution_m <= 0.0 {
            return Err(SchemaError::invalid::<Self>(format!(
                "resolution_m {} is not positive",
                self.resolution_m
            )));
        }
        Ok(())
    }
}
