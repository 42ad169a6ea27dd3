//! # subtgraph-tilesets
//!
//! Tile sets turn the classified tiles of a world into geometry. The built-in procedural sets
//! (mine, cave, lava tube) and the mesh-file set come with the tile-set stage; until then this
//! crate registers nothing, and a `[tileset]` section is refused with the list of what is
//! registered.

use subtgraph_core::registry::{DuplicateName, Registry};

/// Adds the built-in tile sets to a registry (none yet).
pub fn register(_registry: &mut Registry) -> Result<(), DuplicateName> {
    Ok(())
}
