//! What a finished world's survey says, as exporters read it: where the passages are, where
//! each tile's node stands, each edge's centreline and narrowest section, where the artifacts
//! and the floor patches are.
//!
//! The survey runs once per world, after the mesh and before any exporter (crate
//! `subtgraph-survey`, which implements [`Survey`]); exporters only format what it answers.
//! The trait is here, not in that crate, because [`crate::export::Exporter`] names it and
//! the survey crate depends on this one; a plugin's exporter sees the survey through it too.
//! Its answers are plain data: the centrelines of [`Survey::edges`], the
//! [`PlacedArtifacts`] and [`Patch`]es are the same for every exporter of a world, computed
//! once (the artifacts and patches when the survey is made, the rest when first asked for, so
//! a world exported only as OBJ never finds its passage axes).
//!
//! The passages are asked about along vertical lines ([`Columns`]): which stretches of each
//! line are free, from the collision surface by exact ray parity (or the grid's cells without
//! a mesh), what the ground truth's maps, free-space grid and spawn poses are made of.

use std::sync::Mutex;

use crate::artifacts::PlacedArtifacts;
use crate::config::Pipeline;
use crate::grid::Cell;
use crate::hazards::Patch;
use crate::layout::Layout;

/// A regular grid of vertical lines: line `(i, j)` stands at
/// `(x0 + (i + ½) step, y0 + (j + ½) step)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Columns {
    /// West edge, metres.
    pub x0: f64,
    /// South edge, metres.
    pub y0: f64,
    /// Spacing, metres.
    pub step: f64,
    /// Lines west to east.
    pub nx: usize,
    /// Lines south to north.
    pub ny: usize,
}

impl Columns {
    /// x of line column `i`.
    pub fn x(&self, i: usize) -> f64 {
        self.x0 + (i as f64 + 0.5) * self.step
    }

    /// y of line row `j`.
    pub fn y(&self, j: usize) -> f64 {
        self.y0 + (j as f64 + 0.5) * self.step
    }
}

/// A stretch of passage along line `i` of a row: free from `z0` to `z1` (metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    /// The line's column index.
    pub i: u32,
    /// Bottom: a floor.
    pub z0: f64,
    /// Top: a ceiling.
    pub z1: f64,
}

/// A raster's rows (one value per row, south to north) and how many of its lines crossed the
/// surface an odd number of times (0 for a closed surface).
#[derive(Clone, Debug, PartialEq)]
pub struct Raster<T> {
    /// One value per row, south to north.
    pub rows: Vec<T>,
    /// Lines whose crossings do not close (an open surface): their spans are unreliable.
    pub open_lines: usize,
}

/// What the passages were found from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// Inside the world's closed collision surface.
    CollisionMesh,
    /// The grid's cells (a world without a mesh): each occupied cell's square, from its floor
    /// up [`grid_clear_height`].
    Grid,
}

impl Source {
    /// `"collision-mesh"` or `"grid"`, as the ground truth's files say it.
    pub const fn name(self) -> &'static str {
        match self {
            Source::CollisionMesh => "collision-mesh",
            Source::Grid => "grid",
        }
    }
}

/// The clear height of a grid world's passages: half the level height (the other half is the
/// rock between levels).
pub fn grid_clear_height(layout: &Layout) -> f64 {
    0.5 * layout.resolved.level_height
}

/// What [`Survey::visit_rows`] calls for each row of a raster: the row's index (south to
/// north), its free stretches sorted by line then height, and its open lines.
pub type RowVisitor<'a> = dyn Fn(usize, &[Span], &[u32]) + Sync + 'a;

/// One graph edge's centreline, as the ground truth writes it.
#[derive(Clone, Debug, PartialEq)]
pub struct EdgeLine {
    /// From the `from` node's position to the `to` node's, on the floor (world frame, metres):
    /// a corridor along the middle of its passage, a shaft from its foot to its landing, a
    /// ramp along its spiral's floor.
    pub points: Vec<[f64; 3]>,
    /// The length a robot drives, metres: the graph's (along the grid) for corridors and
    /// shafts, along the spiral for a ramp.
    pub length_m: f64,
}

/// What an exporter may ask of a surveyed world. Implemented by `subtgraph-survey`; an
/// exporter receives it beside the [`crate::World`] it writes.
///
/// The generic conveniences (`raster`, `floor`, ...) are inherent
/// methods of `dyn Survey`.
pub trait Survey: Send + Sync {
    /// The resolved pipeline the world was made from (every range drawn): the record
    /// `world.toml` writes. Exporters read the survey's answers, not the pipeline's sections.
    fn record(&self) -> &Pipeline;

    /// What the passages were found from.
    fn source(&self) -> Source;

    /// Every line of `cols` that the triangles meeting `bounds` (`[x0, y0, x1, y1]`, which
    /// must hold every line) can cross: `row(j, spans, open)` once for each row `j`, in
    /// parallel, spans sorted by line then height; `open` lists the lines of the row that
    /// crossed the surface an odd number of times. Returns how many lines were open. The
    /// object-safe form of `dyn Survey::raster_within`.
    fn visit_rows(&self, cols: &Columns, bounds: [f64; 4], row: &RowVisitor<'_>) -> usize;

    /// The free stretches along the vertical line through `(x, y)`, bottom up.
    fn column(&self, x: f64, y: f64) -> Vec<[f64; 2]>;

    /// Where the node of the tile at `cell` stands, on its floor: where its passage meets its
    /// openings (a dead end's half way along its passage, a shaft's foot nearest the shaft),
    /// the tile's centre without a mesh or where the tile has no drivable floor. A vertical
    /// shaft's landing in a procedural tile set stands over the shaft's axis at its floor's
    /// height (the shaft's collar: no floor under it), so the line up the shaft is straight.
    fn position(&self, cell: Cell) -> [f64; 3];

    /// The steepest grade along the tile's passage, degrees (`None` without a mesh).
    fn grade(&self, cell: Cell) -> Option<f64>;

    /// Whether any tile's passage was found on the surface (false without a mesh): the
    /// positions are then the passages' own, not the grid's.
    fn has_axes(&self) -> bool;

    /// Every graph edge's centreline, in edge order.
    fn edges(&self) -> &[EdgeLine];

    /// Every edge's least `(width, height)` along its centreline, metres, measured on the
    /// collision surface (`None` without a mesh), in edge order.
    fn sections(&self) -> &[Option<(f64, f64)>];

    /// The artifacts and whether each is seen from its tile's passage; `None` without
    /// `[artifacts]`.
    fn artifacts(&self) -> Option<&PlacedArtifacts>;

    /// The floor patches of `[hazards] friction`, in raster order of their cells; `None`
    /// without `[hazards]`.
    fn patches(&self) -> Option<&[Patch]>;

    /// What a ray hits: the one hierarchy over the collision surface the survey holds, built
    /// on first use; `None` without a mesh (or from a survey that keeps none: the caller then
    /// builds its own).
    fn ray_caster(&self) -> Option<&crate::raycast::RayCaster> {
        None
    }
}

impl dyn Survey + '_ {
    /// Every line of `cols`: `row(j, spans, open)` for each row `j`, south to north (see
    /// [`Survey::visit_rows`]), collected in row order.
    pub fn raster<T: Send>(
        &self,
        cols: &Columns,
        row: impl Fn(usize, &[Span], &[u32]) -> T + Sync,
    ) -> Raster<T> {
        let all = [f64::MIN, f64::MIN, f64::MAX, f64::MAX];
        self.raster_within(cols, all, row)
    }

    /// `raster`, using only the surface's triangles near `bounds`
    /// (`[x0, y0, x1, y1]`), which must hold every line of `cols`.
    pub fn raster_within<T: Send>(
        &self,
        cols: &Columns,
        bounds: [f64; 4],
        row: impl Fn(usize, &[Span], &[u32]) -> T + Sync,
    ) -> Raster<T> {
        let slots: Vec<Mutex<Option<T>>> = (0..cols.ny).map(|_| Mutex::new(None)).collect();
        let open_lines = self.visit_rows(cols, bounds, &|j, spans, open| {
            let value = row(j, spans, open);
            *slots[j].lock().unwrap_or_else(|e| e.into_inner()) = Some(value);
        });
        let rows = slots
            .into_iter()
            .map(|s| {
                s.into_inner()
                    .unwrap_or_else(|e| e.into_inner())
                    .expect("every row is visited once")
            })
            .collect();
        Raster { rows, open_lines }
    }

    /// The floor under `(x, y)` for a level whose nominal floor is at `nominal` metres: the
    /// bottom of the free stretch holding `nominal + probe` (a downward cast from that height).
    pub fn floor(&self, x: f64, y: f64, nominal: f64, probe: f64) -> Option<f64> {
        floor_in(&self.column(x, y), nominal + probe)
    }
}

/// The bottom of the stretch holding height `z`.
pub fn floor_in(stretches: &[[f64; 2]], z: f64) -> Option<f64> {
    stretches
        .iter()
        .find(|s| s[0] <= z && z <= s[1])
        .map(|s| s[0])
}
