//! # subtgraph-tilesets
//!
//! Tile sets turn the classified tiles of a world into geometry. The built-in procedural sets
//! are one file each:
//!
//! - [`mine`]: an operational drift (flat floor, straight walls, arched back);
//! - [`cave`]: a natural cave (irregular, rough, rubble and rock piles, varying size);
//! - [`lava_tube`]: a wide, smooth elliptical tube with a flat floor and side benches.
//!
//! They share one design: the passages of the whole world are one implicit field
//! ([`field`]), built from each tile's half-corridors, shafts and rocks plus seeded noise in
//! world coordinates, and each tile meshes its own block of a world-wide lattice with marching
//! tetrahedra ([`marching`]). Adjacent tiles therefore meet on exactly the same opening,
//! vertex for vertex, the assembled world is one closed surface, and no two tiles are alike.
//! Each tile's collision copy is its visual surface simplified within a bound ([`collision`]).
//! A new cave type needs only a [`passage::Profile`] and a [`procedural::Style`].
//!
//! [`mesh_files`] places meshes of your own (the DARPA SubT tiles, scans) from a manifest.

use subtgraph_core::registry::{DuplicateName, Registry};
use subtgraph_core::tileset::TileSet;

pub mod axis;
pub mod bends;
pub mod cave;
pub mod chambers;
pub mod collision;
pub mod field;
pub mod finish;
pub mod islands;
pub mod lattice;
pub mod lava_tube;
pub mod marching;
pub mod mesh_files;
pub mod mine;
pub mod noise;
pub mod owner;
pub mod passage;
pub mod procedural;
pub mod ramp;
pub mod refuge;
pub mod rubble;
pub mod services;
pub mod simplify;
pub mod slope;
pub mod textures;
pub mod winding;

/// Adds the built-in tile sets to a registry.
pub fn register(registry: &mut Registry) -> Result<(), DuplicateName> {
    let t = &mut registry.tilesets;
    t.add(
        "mine",
        "operational drifts: flat floor, straight walls, arched back",
        |p| Ok(Box::new(mine::from_params(p)?) as Box<dyn TileSet>),
    )?;
    t.add(
        "cave",
        "natural cave: rough irregular walls, rubble and rock piles",
        |p| Ok(Box::new(cave::from_params(p)?) as Box<dyn TileSet>),
    )?;
    t.add(
        "lava-tube",
        "wide smooth elliptical tube, flat floor, side benches",
        |p| Ok(Box::new(lava_tube::from_params(p)?) as Box<dyn TileSet>),
    )?;
    t.add(
        "mesh-files",
        "your own tile meshes (OBJ, Collada, STL, glTF) mapped to tile kinds by a manifest",
        |p| Ok(Box::new(mesh_files::MeshFiles::from_params(p)?) as Box<dyn TileSet>),
    )?;
    Ok(())
}
