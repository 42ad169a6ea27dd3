//! A world's layout: occupancy, tiles, shafts, the topological graph and the report of what
//! was asked against what was achieved, with the resolved numbers they were made from.
//!
//! A [`Layout`] is made in one step ([`Layout::new`], by the generator or an import) and not
//! changed afterwards: tile sets receive it (`&Layout`) to make geometry, and a
//! [`crate::world::World`] is a layout plus, optionally, that geometry. Nothing here knows
//! about meshes or tile sets, so the model does not depend on the steps that use it (no
//! layout -> assembly -> tile set -> layout cycle).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::config::{Pipeline, Resolved};
use crate::graph::TopologyGraph;
pub use crate::grid::Shaft;
use crate::grid::{Cell, Direction, Grid3, Occupancy};
use crate::hazards::FloorHazards;
use crate::tile::{Tile, TileKind, classify_cell};
use crate::topology;

pub use crate::topology::Counts;

/// What one level asked for and what it has.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LevelReport {
    /// Level index.
    pub level: usize,
    /// Structures requested, by shape name.
    pub requested: BTreeMap<String, u32>,
    /// Junction tiles and cycles the requested structures bring (a loop's arms meet its ring at
    /// T-junctions of its own). `None` for imported worlds.
    pub expected: Option<Counts>,
    /// Counted on the final grid.
    pub achieved: Counts,
    /// Occupied cells.
    pub cells: u32,
    /// 4-connected pieces of this level alone (shafts not counted).
    pub components: u32,
    /// Attempts the generator needed (1 = first try). 0 for imported worlds.
    pub attempts: u32,
}

/// A world without geometry, made once and then only read.
///
/// The fields are public to read; a layout comes only from [`Layout::new`] (it is
/// `#[non_exhaustive]`), which classifies the tiles, builds the graph and counts the report from
/// the occupancy and shafts, so they always agree.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Layout {
    /// The resolved pipeline: every range drawn, every level's counts written out.
    pub pipeline: Pipeline,
    /// The same numbers, typed.
    pub resolved: Resolved,
    /// Which cells are passages.
    pub occupancy: Occupancy,
    /// The tile of each occupied cell.
    pub tiles: Grid3<Option<Tile>>,
    /// Shafts between consecutive levels.
    pub shafts: Vec<Shaft>,
    /// Where a robot starts: a dead end of level 0 that is not a shaft.
    pub start: Option<Cell>,
    /// Per level, the `[row, col]` offset that places it over the level below (non-zero only
    /// for imported worlds whose shafts are not stacked).
    pub level_offsets: Vec<[i64; 2]>,
    /// Per-level requested and achieved counts.
    pub levels: Vec<LevelReport>,
    /// Nodes and corridors.
    pub graph: TopologyGraph,
    /// The `[hazards]` rubble fields and drops: which tiles get one (empty without the
    /// section). Tile sets read this, not the pipeline.
    pub floor_hazards: FloorHazards,
}

impl Layout {
    /// Sums a tile set's per-kind triangle estimate over this layout's tiles
    /// ([`crate::budget::mesh_estimate`]); `None` when `per_kind` has no estimate for a kind
    /// the layout has.
    pub fn mesh_estimate(
        &self,
        per_kind: impl FnMut(TileKind) -> Option<crate::budget::TileTriangles>,
    ) -> Option<crate::budget::MeshEstimate> {
        crate::budget::mesh_estimate(
            self.tiles.as_slice().iter().flatten().map(|t| t.kind),
            per_kind,
        )
    }

    /// Classifies tiles, marks shafts, builds the graph and counts the topology of a grid.
    /// Used for generated and imported worlds alike.
    pub fn new(
        pipeline: Pipeline,
        resolved: Resolved,
        occupancy: Occupancy,
        shafts: Vec<Shaft>,
        requested: Vec<BTreeMap<String, u32>>,
        expected: Vec<Option<Counts>>,
        attempts: Vec<u32>,
    ) -> Layout {
        let mut tiles = Grid3::filled(occupancy.levels(), occupancy.rows(), occupancy.cols(), None);
        for c in occupancy.cells() {
            if *occupancy.get(c) {
                *tiles.get_mut(c) = Some(classify_cell(&occupancy, c));
            }
        }
        for s in &shafts {
            if let Some(t) = tiles.get_mut(s.up) {
                t.kind = TileKind::ShaftUp;
            }
            if let Some(t) = tiles.get_mut(s.landing) {
                t.kind = TileKind::ShaftLanding;
            }
        }
        let start = occupancy
            .level_cells(0)
            .find(|&c| tiles.get(c).is_some_and(|t| t.kind == TileKind::DeadEnd))
            .or_else(|| occupancy.level_cells(0).find(|&c| *occupancy.get(c)));
        let mut level_offsets = vec![[0i64, 0i64]; occupancy.levels()];
        for s in &shafts {
            let below = level_offsets[s.up.level];
            level_offsets[s.landing.level] = [
                below[0] + s.up.row as i64 - s.landing.row as i64,
                below[1] + s.up.col as i64 - s.landing.col as i64,
            ];
        }
        let levels = (0..occupancy.levels())
            .map(|l| {
                let (achieved, cells, components) = count_level(&occupancy, &tiles, l);
                LevelReport {
                    level: l,
                    requested: requested.get(l).cloned().unwrap_or_default(),
                    expected: expected.get(l).copied().flatten(),
                    achieved,
                    cells,
                    components,
                    attempts: attempts.get(l).copied().unwrap_or(0),
                }
            })
            .collect();
        let position = |c: Cell| {
            cell_position(
                &level_offsets,
                occupancy.rows(),
                resolved.tile_pitch,
                resolved.level_height,
                c,
            )
        };
        let mut graph = TopologyGraph::build(
            &occupancy,
            &tiles,
            &shafts,
            position,
            resolved.tile_pitch,
            resolved.level_height,
        );
        if resolved.connections == crate::config::Connections::Ramp {
            for e in &mut graph.edges {
                if e.kind == crate::graph::EdgeKind::Shaft {
                    e.kind = crate::graph::EdgeKind::Ramp;
                }
            }
        }
        let floor_hazards = FloorHazards::resolve(
            pipeline.hazards.as_ref(),
            resolved.seed,
            occupancy
                .cells()
                .filter_map(|c| Some((c, (*tiles.get(c))?))),
            start,
        );
        Layout {
            pipeline,
            resolved,
            occupancy,
            tiles,
            shafts,
            start,
            level_offsets,
            levels,
            graph,
            floor_hazards,
        }
    }

    /// World-frame position in metres of a cell's centre on its floor: x east, y north, z up,
    /// origin at the centre of cell (row `rows - 1`, column 0) of level 0.
    pub fn cell_position(&self, c: Cell) -> [f64; 3] {
        cell_position(
            &self.level_offsets,
            self.occupancy.rows(),
            self.resolved.tile_pitch,
            self.resolved.level_height,
            c,
        )
    }

    /// The cell of `level` whose square holds `(x, y)` (world frame, metres), if it is in the
    /// grid: the inverse of [`cell_position`](Self::cell_position) in the plane.
    pub fn cell_at(&self, level: usize, x: f64, y: f64) -> Option<Cell> {
        let pitch = self.resolved.tile_pitch;
        let off = self.level_offsets[level];
        let rows = self.occupancy.rows() as i64;
        let col = (x / pitch + 0.5).floor() as i64 - off[1];
        let row = rows - 1 - (y / pitch + 0.5).floor() as i64 - off[0];
        (col >= 0 && row >= 0 && row < rows && (col as usize) < self.occupancy.cols())
            .then(|| Cell::new(level, row as usize, col as usize))
    }

    /// The cells reachable from the start through corridors and shafts.
    pub fn reachable_from_start(&self) -> usize {
        let Some(start) = self.start else { return 0 };
        let occ = &self.occupancy;
        let mut seen = Grid3::filled(occ.levels(), occ.rows(), occ.cols(), false);
        let mut stack = vec![start];
        *seen.get_mut(start) = true;
        let mut count = 0;
        while let Some(c) = stack.pop() {
            count += 1;
            let mut next: Vec<Cell> = Direction::ALL
                .iter()
                .filter_map(|&d| occ.neighbour(c, d))
                .filter(|&n| *occ.get(n))
                .collect();
            for s in &self.shafts {
                if s.up == c {
                    next.push(s.landing);
                }
                if s.landing == c {
                    next.push(s.up);
                }
            }
            for n in next {
                if !*seen.get(n) {
                    *seen.get_mut(n) = true;
                    stack.push(n);
                }
            }
        }
        count
    }

    /// The spatial-code grid of the original (0 empty, 1 dead end, ..., 11 shaft up, 111 shaft
    /// landing), level-major, row-major.
    pub fn spatial_codes(&self) -> Vec<u8> {
        self.tiles
            .as_slice()
            .iter()
            .map(|t| t.map_or(0, |t| t.kind.spatial_code()))
            .collect()
    }
}

/// [`Layout::cell_position`] before the layout exists (the graph's node positions).
fn cell_position(
    level_offsets: &[[i64; 2]],
    rows: usize,
    pitch: f64,
    level_height: f64,
    c: Cell,
) -> [f64; 3] {
    let off = level_offsets[c.level];
    let row = c.row as f64 + off[0] as f64;
    let col = c.col as f64 + off[1] as f64;
    [
        col * pitch,
        (rows as f64 - 1.0 - row) * pitch,
        c.level as f64 * level_height,
    ]
}

/// Counts one level: junctions, intersections, dead ends, independent cycles, cells and
/// 4-connected components, through [`crate::topology`] as the generator does. A shaft's foot
/// or landing is reported as a shaft, not as a junction, when it has three or four openings
/// (only imported grids place shafts there).
fn count_level(occ: &Occupancy, tiles: &Grid3<Option<Tile>>, level: usize) -> (Counts, u32, u32) {
    let view = topology::level(occ, level);
    let mut counts = view.counts();
    for c in occ.level_cells(level) {
        let Some(t) = tiles.get(c) else { continue };
        if matches!(t.kind, TileKind::ShaftUp | TileKind::ShaftLanding) {
            match t.openings.count_ones() {
                3 => counts.t_junctions -= 1,
                4 => counts.intersections -= 1,
                _ => {}
            }
        }
    }
    (counts, view.cell_count(), view.component_count())
}

/// Number of 4-connected pieces of occupied cells on one level.
pub fn level_components(occ: &Occupancy, level: usize) -> u32 {
    topology::level(occ, level).component_count()
}

/// The top-left cells of 2 x 2 blocks of occupied cells: side-by-side corridors fused into a
/// ladder of junctions, which the generator never makes.
pub fn fused_blocks(occ: &Occupancy) -> Vec<Cell> {
    (0..occ.levels())
        .flat_map(|l| {
            topology::level(occ, l)
                .fused_blocks()
                .map(move |(r, c)| Cell::new(l, r, c))
                .collect::<Vec<_>>()
        })
        .collect()
}
