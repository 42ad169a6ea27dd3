//! # subtgraph-exporters
//!
//! Writers for a world's files. The world folder's own files are always written:
//!
//! | file | what |
//! |---|---|
//! | `world.toml` | the resolved pipeline (seed, every drawn value, tool version): regenerates the world |
//! | `occupancy.npy` | `uint8 [levels, rows, cols]` with the original's spatial codes |
//! | `topology.json` | the graph, and requested against achieved counts per level |
//! | `maps/level-N.png` | a top-down picture per level, tile kinds in distinct colours |
//! | `mesh/world.obj`, `mesh/world.mtl`, `mesh/collision.obj` | the geometry, when the pipeline has a `[tileset]` |
//!
//! Simulator formats (`[[export]]`) come with the exporters stage and register here.

use subtgraph_core::World;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter};
use subtgraph_core::registry::{DuplicateName, Registry};

mod level_maps;
mod obj;
mod occupancy_npy;
mod topology_json;
mod world_toml;

pub use level_maps::{LevelMaps, kind_colour};
pub use obj::Obj;
pub use occupancy_npy::OccupancyNpy;
pub use topology_json::TopologyJson;
pub use world_toml::WorldToml;

/// Adds the built-in `[[export]]` exporters to a registry (none yet: the world folder's own
/// files are always written by [`write_world_folder`]).
pub fn register(_registry: &mut Registry) -> Result<(), DuplicateName> {
    Ok(())
}

/// Writes the files every world folder has.
pub fn write_world_folder(world: &World, out: &mut dyn WorldWriter) -> Result<(), ExportError> {
    let always: [&dyn Exporter; 4] = [&WorldToml, &OccupancyNpy, &TopologyJson, &LevelMaps];
    for e in always {
        e.export(world, out)?;
    }
    if world.mesh.is_some() {
        Obj.export(world, out)?;
    }
    Ok(())
}

/// A small two-level world for the exporters' tests.
#[cfg(test)]
fn test_world() -> World {
    let text = "[world]\nseed = 3\nlevels = 2\nrows = 24\ncols = 24\n[topology]\nloops = 1\nt_junctions = 1\nintersections = 1\n";
    let p = subtgraph_core::Pipeline::parse(text, "test.toml").unwrap();
    let mut registry = Registry::with_core_shapes();
    registry
        .route_descriptors
        .register(
            "parabolic",
            "test",
            "",
            std::sync::Arc::new(|_| {
                Ok(Box::new(Straight) as Box<dyn subtgraph_core::route::RouteDescriptor>)
            }),
        )
        .unwrap();
    subtgraph_core::layout(&p, &registry).unwrap()
}

#[cfg(test)]
struct Straight;

#[cfg(test)]
impl subtgraph_core::route::RouteDescriptor for Straight {
    fn offset(&self, _t: f64, _s: &subtgraph_core::route::Segment) -> f64 {
        0.0
    }
}
