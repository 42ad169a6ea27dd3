//! An exporter plugin: the world's visual mesh as ASCII PLY (`mesh/world.ply`), which
//! MeshLab, CloudCompare, Open3D and trimesh read.
//!
//! ```toml
//! [[export]]
//! type = "ply"
//! ```

use std::fmt::Write;

use subtgraph_core::World;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter, write_file};
use subtgraph_core::survey::Survey;

struct Ply;

impl Exporter for Ply {
    // The mesh is all this format holds: the survey (passages, centrelines, artifacts) is not
    // asked for anything, so nothing of it is computed for this exporter.
    fn export(
        &self,
        world: &World,
        _survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let Some(mesh) = world.mesh() else {
            return Err(ExportError::Unsupported(
                "the ply exporter needs geometry: add a [tileset] to the pipeline".into(),
            ));
        };
        let m = &mesh.visual;
        let mut s = String::with_capacity(m.positions.len() * 40 + m.triangles.len() * 24);
        s.push_str("ply\nformat ascii 1.0\ncomment subtgraph world, metres, z up\n");
        let _ = writeln!(s, "element vertex {}", m.positions.len());
        s.push_str("property float x\nproperty float y\nproperty float z\n");
        let _ = writeln!(s, "element face {}", m.triangles.len());
        s.push_str("property list uchar int vertex_indices\nend_header\n");
        for p in &m.positions {
            let _ = writeln!(s, "{} {} {}", p[0], p[1], p[2]);
        }
        for t in &m.triangles {
            let _ = writeln!(s, "3 {} {} {}", t[0], t[1], t[2]);
        }
        write_file(out, "mesh/world.ply", s.as_bytes())
    }

    fn needs_geometry(&self) -> bool {
        true
    }
}

fn register(r: &mut subtgraph_plugins::Registrar<'_>) {
    r.exporter(
        "ply",
        "the visual mesh as ASCII PLY (mesh/world.ply)",
        |p| {
            p.expect_none()?;
            Ok(Box::new(Ply))
        },
    );
}

subtgraph_plugins::declare_plugin!("ply", register);
