//! `topology.json`: the topological graph in the world frame, with the requested, expected and
//! achieved counts of every level (written by the exporters' `TopologyJson`, read by `score`,
//! `stats`, `preview` and the dataset index).
//!
//! `S` is the type of the fixed texts (`format`, `frame`): `&'static str` where a writer
//! fills them in, `String` (the default) where a file is read.

use std::borrow::Cow;

use serde::{Deserialize, Serialize};
use subtgraph_core::graph::{Edge, Node};
use subtgraph_core::grid::Cell;
use subtgraph_core::layout::{LevelReport, Shaft};

use crate::{Document, SchemaError, ends_exist, finite, id_in_order};

/// The longest tile pitch and level height a world has, metres (`world.tile_pitch` and
/// `world.level_height` are at most this).
pub const MAX_LENGTH_M: f64 = 1000.0;

/// `topology.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Topology<'a, S = String> {
    /// [`Topology::FORMAT`](Document::FORMAT).
    pub format: S,
    /// The frame, in words.
    pub frame: S,
    /// The world's seed.
    pub seed: u64,
    /// Levels of the grid.
    pub levels: usize,
    /// Rows per level.
    pub rows: usize,
    /// Columns per level.
    pub cols: usize,
    /// Metres between tile centres.
    pub tile_pitch_m: f64,
    /// Metres between levels.
    pub level_height_m: f64,
    /// Occupied cells, every level.
    pub occupied_cells: usize,
    /// Every edge's length, metres.
    pub total_length_m: f64,
    /// Cells reachable from the start.
    pub reachable_cells: usize,
    /// Whether every occupied cell is reachable.
    pub connected: bool,
    /// The start's node id.
    pub start: Option<usize>,
    /// Per level: requested, expected and achieved counts.
    pub per_level: Cow<'a, [LevelReport]>,
    /// Shafts and ramps between levels.
    pub shafts: Cow<'a, [Shaft]>,
    /// The graph's nodes, by id.
    pub nodes: Cow<'a, [Node]>,
    /// The graph's edges, by id.
    pub edges: Cow<'a, [Edge]>,
}

impl<S> Topology<'_, S> {
    /// The frame, as the file states it.
    pub const FRAME: &'static str = "metres; x east (+col), y north (-row), z up (+level); positions are cell centres on the floor";

    /// Cells of the whole grid, `levels x rows x cols` (checked not to overflow by
    /// [`Document::check`]).
    pub fn cells(&self) -> usize {
        self.levels * self.rows * self.cols
    }

    fn check_cell(&self, c: Cell, what: impl FnOnce() -> String) -> Result<(), SchemaError> {
        if c.level < self.levels && c.row < self.rows && c.col < self.cols {
            Ok(())
        } else {
            Err(SchemaError::invalid::<Topology>(format!(
                "{} is cell (level {}, row {}, col {}), outside the grid of {} level(s) of {} x {} cells",
                what(),
                c.level,
                c.row,
                c.col,
                self.levels,
                self.rows,
                self.cols
            )))
        }
    }
}

impl Document for Topology<'_> {
    const PATH: &'static str = "topology.json";
    const FORMAT: &'static str = "subtgraph-topology/1";

    fn format(&self) -> &str {
        &self.format
    }

    fn check(&self) -> Result<(), SchemaError> {
        let bad = |what: String| Err(SchemaError::invalid::<Self>(what));
        if self.levels == 0 || self.rows == 0 || self.cols == 0 {
            return bad(format!(
                "the grid is {} level(s) of {} x {} cells: none may be 0",
                self.levels, self.rows, self.cols
            ));
        }
        if self
            .levels
            .checked_mul(self.rows)
            .and_then(|n| n.checked_mul(self.cols))
            .is_none()
        {
            return bad(format!(
                "a grid of {} level(s) of {} x {} cells has more cells than any machine holds",
                self.levels, self.rows, self.cols
            ));
        }
        for (what, v) in [
            ("tile_pitch_m", self.tile_pitch_m),
            ("level_height_m", self.level_height_m),
        ] {
            // At most what `generate` makes (world.tile_pitch and world.level_height are at
            // most 1000 m): 1e308 made every picture of the world zero pixels wide.
            if !(v.is_finite() && v > 0.0 && v <= MAX_LENGTH_M) {
                return bad(format!(
                    "{what} is {v}: it must be a positive number of metres, at most {MAX_LENGTH_M}"
                ));
            }
        }
        if self.per_level.len() != self.levels {
            return bad(format!(
                "per_level has {} entries for {} level(s)",
                self.per_level.len(),
                self.levels
            ));
        }
        for (i, n) in self.nodes.iter().enumerate() {
            id_in_order::<Self>("node", i, n.id)?;
            self.check_cell(n.cell, || format!("node {i}"))?;
            finite::<Self>(|| format!("node {i}'s position"), &n.position)?;
        }
        let nodes = self.nodes.len();
        for (i, e) in self.edges.iter().enumerate() {
            id_in_order::<Self>("edge", i, e.id)?;
            ends_exist::<Self>(i, [e.from, e.to], nodes)?;
            if e.cells.is_empty() {
                return bad(format!("edge {i} has no cells"));
            }
            for c in &e.cells {
                self.check_cell(*c, || format!("a cell of edge {i}"))?;
            }
            finite::<Self>(|| format!("edge {i}'s length_m"), &[e.length_m])?;
        }
        for (i, s) in self.shafts.iter().enumerate() {
            self.check_cell(s.up, || format!("shaft {i}'s foot"))?;
            self.check_cell(s.landing, || format!("shaft {i}'s landing"))?;
        }
        if let Some(s) = self.start.filter(|&s| s >= nodes) {
            return bad(format!("start is node {s}, but there are {nodes} nodes"));
        }
        Ok(())
    }
}

/// One structure's counts on a level: what was requested, what the requested structures
/// bring (`None` for an imported world, which records no expectation) and what the final grid
/// has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StructureCounts {
    /// `t-junction`, `intersection` or `loop`: the shape's name in `requested`.
    pub structure: &'static str,
    /// Requested.
    pub requested: u64,
    /// Brought by the requested structures.
    pub expected: Option<u64>,
    /// Counted on the final grid.
    pub achieved: u64,
}

/// A level's counts of the three structures the statistics and the dataset index compare
/// (T-junctions, intersections, loops), in that order.
pub fn structure_counts(l: &LevelReport) -> [StructureCounts; 3] {
    let of = |c: &subtgraph_core::topology::Counts, k: usize| {
        u64::from([c.t_junctions, c.intersections, c.loops][k])
    };
    let names = ["t-junction", "intersection", "loop"];
    std::array::from_fn(|k| StructureCounts {
        structure: names[k],
        requested: u64::from(l.requested.get(names[k]).copied().unwrap_or(0)),
        expected: l.expected.as_ref().map(|c| of(c, k)),
        achieved: of(&l.achieved, k),
    })
}
