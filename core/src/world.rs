//! A world: its [`Layout`] (occupancy, tiles, shafts, graph, report) and, when the pipeline
//! has a `[tileset]`, the geometry a tile set made of it.
//!
//! A world is made in one step from its parts ([`World::new`]) and only read afterwards: the
//! layout is reached through `Deref` (`world.occupancy`, `world.cell_position(c)`), the mesh
//! through [`World::mesh`]. Exporters take a `&World`; tile sets take the `&Layout` alone,
//! since geometry is what they make.

use std::any::Any;
use std::ops::Deref;
use std::sync::{Arc, Mutex, PoisonError};

use crate::assembly::WorldMesh;
pub use crate::layout::{Counts, Layout, LevelReport, Shaft, fused_blocks, level_components};

/// A layout and its optional geometry.
#[derive(Clone, Debug)]
pub struct World {
    layout: Layout,
    mesh: Option<WorldMesh>,
    derived: Derived,
}

/// What [`World::derived`] keeps: one value per type, made once.
#[derive(Clone, Default)]
struct Derived(Arc<Mutex<Vec<Arc<dyn Any + Send + Sync>>>>);

impl std::fmt::Debug for Derived {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Derived")
    }
}

impl World {
    /// A world from its layout and the geometry made of it (`None`: a world without meshes,
    /// as `--no-mesh` or a pipeline without `[tileset]` make).
    pub fn new(layout: Layout, mesh: Option<WorldMesh>) -> World {
        World {
            layout,
            mesh,
            derived: Derived::default(),
        }
    }

    /// The value of type `T` derived from this world: made by `make` the first time one is
    /// asked for, shared afterwards (one value per type; a clone of the world shares them).
    /// For what several exporters need and need not each compute again, as the artifacts'
    /// placement, which every simulator format and the ground truth hold. `make` must not
    /// ask for another derived value.
    pub fn derived<T: Any + Send + Sync>(&self, make: impl FnOnce(&World) -> T) -> Arc<T> {
        let mut all = self
            .derived
            .0
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        if let Some(v) = all.iter().find_map(|v| v.clone().downcast::<T>().ok()) {
            return v;
        }
        let v = Arc::new(make(self));
        all.push(v.clone());
        v
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
