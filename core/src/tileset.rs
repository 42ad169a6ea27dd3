//! Tile sets turn classified tiles into geometry.
//!
//! This is the trait's home; the geometry methods (visual and collision meshes, opening
//! cross-sections) arrive with the tile-set stage. What a tile set needs to know about a tile
//! is already here: its [`Tile`](crate::tile::Tile) (kind and rotation), its cell, and its
//! world position from [`World::cell_position`](crate::world::World::cell_position).

/// Turns tiles into 3D geometry for a world.
pub trait TileSet: Send + Sync {
    /// Metres between opposite openings of a tile, when the tile set fixes it (mesh tiles do;
    /// procedural ones follow `world.tile_pitch`).
    fn pitch(&self) -> Option<f64> {
        None
    }
}
