//! Tile sets turn classified tiles into geometry.
//!
//! A tile set is asked for one tile at a time, with everything it may need in a
//! [`TileContext`]: the tile (kind and rotation), its cell and world position, its
//! neighbours, the world itself, and a seed of its own. It answers with a visual mesh
//! (materials, UVs) and a lighter collision mesh, in world coordinates. Assembly
//! ([`crate::assembly`]) asks for every occupied cell in parallel and welds the result.
//!
//! Openings must match: two adjacent tiles meet on exactly the same cross-section, vertex for
//! vertex, so the world is one closed surface. Procedural tile sets get this by evaluating
//! one world-wide field; mesh tiles by sharing an opening profile.

use crate::budget::TileTriangles;
use crate::grid::Cell;
use crate::mesh::{Material, Mesh};
use crate::tile::{Tile, TileKind};
use crate::world::World;

/// What a tile set knows about the tile it is asked for.
#[derive(Clone, Copy, Debug)]
pub struct TileContext<'a> {
    /// The whole world (grid, shafts, resolved pipeline).
    pub world: &'a World,
    /// The tile's cell.
    pub cell: Cell,
    /// Kind, rotation and openings.
    pub tile: Tile,
    /// Centre of the tile on its floor, world frame, metres.
    pub position: [f64; 3],
    /// A seed of the tile's own, derived from the world seed and the cell.
    pub seed: u64,
}

impl TileContext<'_> {
    /// The neighbouring tiles on the same level, east, north, west, south.
    pub fn neighbours(&self) -> [Option<Tile>; 4] {
        crate::grid::Direction::ALL.map(|d| {
            self.world
                .occupancy
                .neighbour(self.cell, d)
                .and_then(|n| *self.world.tiles.get(n))
        })
    }
}

/// The geometry of one tile.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TileGeometry {
    /// What is rendered.
    pub visual: Mesh,
    /// What physics collides with: lighter, same passages.
    pub collision: Mesh,
    /// Which vertices assembly welds to a neighbour's.
    pub seams: Seams,
}

/// Which vertices of a tile may coincide with a neighbour's, so that assembly welds them.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Seams {
    /// The tile set does not know: every vertex of the world that coincides with another is
    /// welded (the safe default, and the slowest).
    #[default]
    All,
    /// None: the tile's meshes are whole and share no vertex with a neighbour.
    None,
    /// Only these vertices (those on the tile's boundary), by index into `visual` and
    /// `collision`.
    Listed {
        /// Indices into the visual mesh's positions.
        visual: Vec<u32>,
        /// Indices into the collision mesh's positions.
        collision: Vec<u32>,
    },
}

/// The cross-section at a tile opening, metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrossSection {
    /// Widest extent across the passage.
    pub width: f64,
    /// Floor to ceiling.
    pub height: f64,
}

/// Why a tile set cannot make a world's tiles. The message says what to change.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct TileSetError(pub String);

/// Turns tiles into 3D geometry.
///
/// Only [`tile`](TileSet::tile) is required.
///
/// # Example
///
/// A tile set that marks each tile with a flat square on its floor (not closed; just the
/// shape of the trait):
///
/// ```
/// use subtgraph_core::mesh::Mesh;
/// use subtgraph_core::tileset::{Seams, TileContext, TileGeometry, TileSet, TileSetError};
///
/// struct FloorPlates;
///
/// impl TileSet for FloorPlates {
///     fn tile(&self, ctx: &TileContext<'_>) -> Result<TileGeometry, TileSetError> {
///         let [x, y, z] = ctx.position.map(|v| v as f32);
///         let h = 0.5 * ctx.world.resolved.tile_pitch as f32;
///         let plate = Mesh {
///             positions: vec![[x - h, y - h, z], [x + h, y - h, z], [x + h, y + h, z], [x - h, y + h, z]],
///             triangles: vec![[0, 1, 2], [0, 2, 3]],
///             ..Mesh::default()
///         };
///         Ok(TileGeometry { visual: plate.clone(), collision: plate, seams: Seams::All })
///     }
/// }
/// ```
pub trait TileSet: Send + Sync {
    /// The geometry of one tile, in world coordinates.
    fn tile(&self, ctx: &TileContext<'_>) -> Result<TileGeometry, TileSetError>;

    /// The materials triangles refer to by index.
    fn materials(&self) -> Vec<Material> {
        vec![Material::coloured("rock", [0.45, 0.42, 0.38])]
    }

    /// Metres between opposite openings, when the tile set fixes it (mesh tiles do;
    /// procedural ones follow `world.tile_pitch`).
    fn pitch(&self) -> Option<f64> {
        None
    }

    /// The cross-section at every opening in this world, when the tile set has one shape
    /// for all of them (procedural sets vary it along the passage around this nominal size).
    fn opening(&self, _world: &World) -> Option<CrossSection> {
        None
    }

    /// Checks that the world suits the tile set (pitch, level height) before any tile is made.
    fn check(&self, _world: &World) -> Result<(), TileSetError> {
        Ok(())
    }

    /// Triangles of one tile of `kind` in this world, estimated without meshing, so that a
    /// world too large for the memory budget is refused before any tile is made (see
    /// [`crate::budget`]). Keep it cheap: it is called once per kind. `None` (the default):
    /// assembly measures the first tiles it makes and extrapolates instead.
    fn estimate(&self, _world: &World, _kind: TileKind) -> Option<TileTriangles> {
        None
    }

    /// What to change in this tile set for lighter meshes, named when a world's meshes are
    /// too large (`lower [tileset] resolution`). `None`: only the world's size is named.
    fn detail_advice(&self) -> Option<String> {
        None
    }

    /// Metres per texture repeat for UVs computed by assembly.
    fn texture_scale(&self) -> f32 {
        4.0
    }
}
