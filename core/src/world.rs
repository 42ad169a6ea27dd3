//! A world: its [`Layout`] (occupancy, tiles, shafts, graph, report) and, when the pipeline
//! has a `[tileset]`, the geometry a tile set made of it.
//!
//! A world is made in one step from its parts ([`World::new`]) and only read afterwards: the
//! layout is reached through `Deref` (`world.occupancy`, `world.cell_position(c)`), the mesh
//! through [`World::mesh`]. Exporters take a `&World` (and its survey, `crate::survey`); tile
//! sets take the `&Layout` alone, since geometry is what they make. What is found in a world
//! after it is made (passages, centrelines, artifact poses) is the survey's, not kept here.

use std::ops::Deref;

use crate::assembly::WorldMesh;
pub use crate::layout::{Counts, Layout, LevelReport, Shaft, fused_blocks, level_components};

/// A layout and its optional geometry.
#[derive(Clone, Debug)]
pub struct World {
    layout: Layout,
    mesh: Option<WorldMesh>,
}

impl World {
    /// A world from its layout and the geometry made of it (`None`: a world without meshes,
    /// as `--no-mesh` or a pipeline without `[tileset]` make).
    pub fn new(layout: Layout, mesh: Option<WorldMesh>) -> World {
        World { layout, mesh }
    }

    /// The layout (also reached through `Deref`).
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The assembled geometry, when the world has one.
    pub fn mesh(&self) -> Option<&WorldMesh> {
        self.mesh.as_ref()
    }

    /// How far the floor of the tile at `cell` stands above its level's floor, metres, lowest
    /// and highest, as the tile set placed it (a hill's tiles; [`WorldMesh::floor_lift`]):
    /// `[0, 0]` without a mesh.
    pub fn floor_lift(&self, cell: crate::grid::Cell) -> [f64; 2] {
        self.mesh
            .as_ref()
            .map_or([0.0, 0.0], |m| m.floor_lift(cell))
    }

    /// The layout and the geometry, taken apart (to mesh an existing layout again, say).
    pub fn into_parts(self) -> (Layout, Option<WorldMesh>) {
        (self.layout, self.mesh)
    }
}

impl From<Layout> for World {
    /// A world without geometry.
    fn from(layout: Layout) -> World {
        World::new(layout, None)
    }
}

impl Deref for World {
    type Target = Layout;

    fn deref(&self) -> &Layout {
        &self.layout
    }
}
