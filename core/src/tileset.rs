//! Tile sets turn classified tiles into geometry.
//!
//! A tile set is asked for one tile at a time, with everything it may need in a
//! [`TileContext`]: the tile (kind and rotation), its cell and world position, its
//! neighbours, the world's [`Layout`], and a seed of its own. It answers with a visual mesh
//! (materials, UVs) and a lighter collision mesh, in world coordinates. Assembly
//! ([`crate::assembly`]) asks for every occupied cell in parallel and welds the result.
//!
//! Openings must match: two adjacent tiles meet on exactly the same cross-section, vertex for
//! vertex, so the world is one closed surface. Procedural tile sets get this by evaluating
//! one world-wide field; mesh tiles by sharing an opening profile.

use crate::budget::TileTriangles;
use crate::grid::Cell;
use crate::layout::Layout;
use crate::mesh::{Material, Mesh};
use crate::tile::{Tile, TileKind};

/// What a tile set knows about the tile it is asked for.
#[derive(Clone, Copy, Debug)]
pub struct TileContext<'a> {
    /// The whole layout (grid, tiles, shafts, graph, resolved numbers).
    pub layout: &'a Layout,
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
    /// The seed the tile at `cell` of this world gets as its own `seed`: a tile that must agree
    /// with another draws from that tile's seed (a shaft's landing the file its foot drew).
    pub fn seed_of(&self, cell: Cell) -> u64 {
        tile_seed(self.layout.resolved.seed, cell)
    }

    /// The neighbouring tiles on the same level, east, north, west, south.
    pub fn neighbours(&self) -> [Option<Tile>; 4] {
        crate::grid::Direction::ALL.map(|d| {
            self.layout
                .occupancy
                .neighbour(self.cell, d)
                .and_then(|n| *self.layout.tiles.get(n))
        })
    }
}

/// A tile's own seed (its [`TileContext::seed`]), from the world's seed and its cell.
pub fn tile_seed(world_seed: u64, cell: Cell) -> u64 {
    crate::rng::derive_seed(
        world_seed,
        "tile",
        ((cell.level as u64) << 40) | ((cell.row as u64) << 20) | cell.col as u64,
    )
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
    /// What the tile set made of this tile beyond its kind, for the ground truth's semantic
    /// labels (the procedural sets say `chamber` or `squeeze`); usually empty.
    pub labels: Vec<&'static str>,
    /// The rubble field or drop the tile set made in this tile (`[hazards]`; only tile sets
    /// whose [`TileSet::makes_hazards`] is true make them).
    pub hazards: Vec<crate::hazards::HazardRegion>,
    /// The tile's passage axis as the tile set laid it, when it knows one (the procedural
    /// sets do: their passages are swept along it); `None` for meshes whose passage is only
    /// known from its surface. The ground truth's centrelines follow it.
    pub axis: Option<PassageAxis>,
}

/// A tile's passage axis as its tile set laid it: the middle of the passage, on its floor
/// (world frame, metres), from where the tile's node stands to the middle of each opening's
/// face. A smooth line: a robot can follow it from point to point.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PassageAxis {
    /// Where the tile's node stands: where its passage meets its openings (a junction's
    /// centre, a dead end's far end, the middle of a straight or corner's way through).
    pub node: [f64; 3],
    /// Per direction (`Direction as usize`): points from the node (excluded) to the middle of
    /// that opening's face (included), at most a metre apart; empty for a side without an
    /// opening. Two neighbouring tiles' paths meet at the same face point.
    pub exits: [Vec<[f64; 3]>; 4],
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

/// Why a tile set cannot make a world's tiles. Each message says what to change.
///
/// It crosses the plugin boundary (a plugin's tile set returns it), so a new variant is a
/// plugin API change; [`TileSetError::Other`] is there for what fits no other variant.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum TileSetError {
    /// The layout does not suit the tile set. `what` says what does not fit (`"cave:
    /// passages up to 9.1 m wide ... do not fit tiles 8 m apart"`), `fix` what to change in
    /// the pipeline (`"use a smaller [tileset] width"`).
    #[error("{what}; {fix}")]
    Unsuited {
        /// What does not fit, naming the tile set.
        what: String,
        /// What to change.
        fix: String,
    },
    /// The tile set has no tile for these kinds (`"dead-end"`, ...), which the layout needs:
    /// add tiles of those kinds to the tile set. `tileset` names it (a manifest's path).
    #[error(
        "{tileset} has no tile for {} but the world needs them; add [[tile]] entries with those kinds",
        kinds.join(", ")
    )]
    MissingKinds {
        /// The tile set, as users know it (a manifest's path).
        tileset: String,
        /// The kinds' names, in the order the layout first needs them.
        kinds: Vec<String>,
    },
    /// The world's meshes would need more memory than the budget allows
    /// ([`crate::budget::Budget::check`]): how much, and what to make smaller or raise.
    #[error("{0}")]
    TooLarge(crate::budget::OverBudget),
    /// Making one tile failed: where, and why.
    #[error(
        "tile at level {}, row {}, column {} ({}): {source}",
        cell.level,
        cell.row,
        cell.col,
        kind.name()
    )]
    Tile {
        /// The tile's cell.
        cell: Cell,
        /// Its kind.
        kind: TileKind,
        /// Why the tile set could not make it.
        source: Box<TileSetError>,
    },
    /// A plugin's tile set panicked, now or on an earlier call: the message names the plugin
    /// and the call (fix or remove the plugin).
    #[error("{0}")]
    Plugin(String),
    /// Any other reason, in a message that says what to change.
    #[error("{0}")]
    Other(String),
}

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
///         let h = 0.5 * ctx.layout.resolved.tile_pitch as f32;
///         let plate = Mesh {
///             positions: vec![[x - h, y - h, z], [x + h, y - h, z], [x + h, y + h, z], [x - h, y + h, z]],
///             triangles: vec![[0, 1, 2], [0, 2, 3]],
///             ..Mesh::default()
///         };
///         Ok(TileGeometry { visual: plate.clone(), collision: plate, ..TileGeometry::default() })
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
    fn opening(&self, _layout: &Layout) -> Option<CrossSection> {
        None
    }

    /// Checks that the layout suits the tile set (pitch, level height) before any tile is
    /// made ([`TileSetError::Unsuited`], [`TileSetError::MissingKinds`]).
    fn check(&self, _layout: &Layout) -> Result<(), TileSetError> {
        Ok(())
    }

    /// Triangles of one tile of `kind` in this world, estimated without meshing, so that a
    /// world too large for the memory budget is refused before any tile is made (see
    /// [`crate::budget`]). Keep it cheap: it is called once per kind. `None` (the default):
    /// assembly measures the first tiles it makes and extrapolates instead.
    fn estimate(&self, _layout: &Layout, _kind: TileKind) -> Option<TileTriangles> {
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

    /// The image files [`materials`](TileSet::materials) name (albedo, normal and roughness
    /// maps), made for the world with this seed; assembly keeps them on the world's mesh and
    /// the exporters write them under `mesh/`. The default: none (plain colours).
    fn textures(&self, _seed: u64) -> Result<Vec<crate::mesh::ImageFile>, TileSetError> {
        Ok(Vec::new())
    }

    /// Whether the tile set makes `[hazards]` rubble fields and drops (in the tiles
    /// [`crate::hazards::HazardsSection::floor_hazard`] names). Assembly refuses a pipeline
    /// asking for them from a tile set that does not, rather than leaving them out silently.
    fn makes_hazards(&self) -> bool {
        false
    }

    /// The floor line of the ramp this tile set makes for `shaft` (world frame, metres, from
    /// the foot's level floor to the landing's) when the world's levels are joined by ramps
    /// (`world.connections = "ramp"`). `None` (the default): the tile set makes no ramps, and
    /// assembly refuses such a world, naming `world.connections`.
    fn ramp(&self, _layout: &Layout, _shaft: &crate::grid::Shaft) -> Option<Vec<[f64; 3]>> {
        None
    }

    /// How far the floor of the tile at `cell` stands above its level's floor, metres, as
    /// `[lowest, highest]`: `[0, 0]` (the default) for a tile on its level's floor, `[h, h]`
    /// for one the tile set lifts by `h` (the top of a hill), `[0, h]` for one whose floor
    /// climbs `h` across it. Assembly keeps it per tile ([`crate::assembly::PlacedTile`]); the
    /// ground truth looks for the tile's floor in its level's height band moved up by it.
    fn floor_lift(&self, _layout: &Layout, _cell: Cell) -> [f64; 2] {
        [0.0, 0.0]
    }

    /// The small closed parts this tile set places beside the passages once every tile is
    /// made and welded (a mine's rock bolts, duct, pipes, cable run and lights; see
    /// [`crate::mesh::Fixtures`]), given the world's welded visual surface and each tile's
    /// passage axis ([`TileGeometry::axis`], raster order). Placed in world coordinates along
    /// the axes, so they run on across tile joins. The default: none.
    fn fixtures(
        &self,
        _layout: &Layout,
        _visual: &Mesh,
        _axes: &[(Cell, &PassageAxis)],
    ) -> Result<crate::mesh::Fixtures, TileSetError> {
        Ok(crate::mesh::Fixtures::default())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_say_what_to_change_and_where() {
        let unsuited = TileSetError::Unsuited {
            what: "cave: the shaft does not fit the tile".into(),
            fix: "use a smaller [tileset] width".into(),
        };
        assert_eq!(
            unsuited.to_string(),
            "cave: the shaft does not fit the tile; use a smaller [tileset] width"
        );
        let missing = TileSetError::MissingKinds {
            tileset: "tiles/manifest.toml".into(),
            kinds: vec!["corner".into(), "dead-end".into()],
        };
        assert_eq!(
            missing.to_string(),
            "tiles/manifest.toml has no tile for corner, dead-end but the world needs them; add \
             [[tile]] entries with those kinds"
        );
        let at = TileSetError::Tile {
            cell: Cell::new(1, 2, 3),
            kind: TileKind::Corner,
            source: Box::new(TileSetError::Other("no geometry".into())),
        };
        assert_eq!(
            at.to_string(),
            "tile at level 1, row 2, column 3 (corner): no geometry"
        );
        assert_eq!(
            std::error::Error::source(&at).map(ToString::to_string),
            Some("no geometry".to_owned())
        );
    }
}
