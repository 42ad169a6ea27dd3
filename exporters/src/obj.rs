//! `mesh/world.obj` + `mesh/world.mtl` (visual, grouped by material) and
//! `mesh/collision.obj` (the lighter collision surface), metres, Z up as in the world frame.
//! A world with fixtures (a mine's services: `subtgraph_core::mesh::Fixtures`) has them
//! baked into `mesh/services.obj` (materials from `world.mtl`), one closed part per copy:
//! `world.obj` stays the passage's one closed surface, as every reader of it expects.
//!
//! Numbers are written with a fixed four decimals (0.1 mm) by a small formatter of our own:
//! `format!` would dominate the export time of a multi-million-triangle world.

use subtgraph_core::World;
use subtgraph_core::error::ConfigError;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter, stream_file};
use subtgraph_core::params::Params;
use subtgraph_core::survey::Survey;

use crate::parts::{Split, parts, write_part_meshes};
use crate::text::write_obj;

/// Writes the world's meshes as Wavefront OBJ: `mesh/world.obj` (visual, one object, grouped
/// by material), `mesh/world.mtl` and `mesh/collision.obj`. Every world folder with geometry
/// has these; as an `[[export]]` with a `split`, it also writes one OBJ pair per part under
/// `mesh/parts/<split>/`, and with `visual = "none"` only the collision surface.
#[derive(Clone, Copy, Debug)]
pub struct Obj {
    /// Also write per-part meshes cut this way.
    pub split: Option<Split>,
    /// Write `mesh/world.obj` and its `.mtl` (`visual = "full"`, the default); without, only
    /// `mesh/collision.obj`: what ray casting, planning and physics read, a quarter of the
    /// bytes (a lava tube's visual OBJ is about 500 MB).
    pub visual: bool,
}

impl Default for Obj {
    fn default() -> Self {
        Obj {
            split: None,
            visual: true,
        }
    }
}

impl Obj {
    /// From an `[[export]] type = "obj"` table: an optional `split` (and `region_tiles`) and
    /// `visual` (`"full"` or `"none"`).
    pub fn from_params(params: &Params) -> Result<Obj, ConfigError> {
        params.expect_known(&[Split::KEYS[0], Split::KEYS[1], "visual"])?;
        let visual = match params.raw("visual") {
            None => true,
            Some(toml::Value::String(s)) if s == "full" => true,
            Some(toml::Value::String(s)) if s == "none" => false,
            Some(_) => {
                return Err(params.error(
                    "visual",
                    "visual must be \"full\" (mesh/world.obj and its .mtl beside mesh/collision.obj) or \"none\" (mesh/collision.obj alone: a quarter of the bytes, for ray casting, planning and physics)",
                ));
            }
        };
        Ok(Obj {
            visual,
            split: match params.raw("split") {
                Some(_) => Some(Split::from_params(params)?),
                None => None,
            },
        })
    }
}

impl Exporter for Obj {
    fn export(
        &self,
        world: &World,
        _survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let Some(mesh) = world.mesh() else {
            return Err(ExportError::Unsupported(
                "the OBJ exporter needs geometry: add a [tileset] to the pipeline (or drop --no-mesh)".into(),
            ));
        };
        if self.visual && !out.contains("mesh/world.obj") {
            crate::text::write_world_mtl(out, mesh)?;
            stream_file(out, "mesh/world.obj", |w| {
                write_obj(
                    w,
                    &mesh.visual,
                    "world",
                    Some((&mesh.materials, "world.mtl")),
                )
            })?;
            crate::services::write_services_obj(out, mesh)?;
        }
        if !out.contains("mesh/collision.obj") {
            stream_file(out, "mesh/collision.obj", |w| {
                write_obj(w, &mesh.collision, "collision", None)
            })?;
        }
        if let Some(split) = self.split {
            write_part_meshes(out, mesh, split, &parts(world, mesh, split))?;
        }
        Ok(())
    }

    fn needs_geometry(&self) -> bool {
        true
    }
}
