//! What the sensors see of a world: its collision surface in a ray caster, how strongly each
//! triangle reflects a LiDAR's near-infrared light, and where its floor hazards are.
//!
//! The ray caster is the world survey's ([`WorldSurvey::rays`]): one hierarchy over the
//! collision surface, built once per world and shared (an `Arc`) by every question about
//! what a ray hits, the survey's own widths and heights as well as the sensors' rays.

use std::sync::Arc;

use subtgraph_core::mesh::Mesh;
use subtgraph_core::raycast::RayCaster;
use subtgraph_survey::WorldSurvey;

use crate::error::SenseError;

/// A world made ready for sensing: built once, then shared by every scan.
pub struct Scene {
    /// The collision surface's hierarchy (the survey's, shared).
    pub caster: Arc<RayCaster>,
    /// Each triangle's reflectivity in `[0, 1]` (index: the mesh's triangle).
    pub reflectivity: Vec<f32>,
    /// Floor hazards (rubble fields, drops) as `[x0, y0, x1, y1, z0, z1]`.
    pub hazards: Vec<[f64; 6]>,
    /// The grid's tile pitch, metres (how near a node a scan counts as at it).
    pub tile_pitch: f64,
}

impl Scene {
    /// The scene of a surveyed world with geometry: its ray caster is the survey's.
    pub fn of_survey(survey: &WorldSurvey<'_>) -> Result<Scene, SenseError> {
        let world = survey.world();
        let mesh = world.mesh().ok_or(SenseError::NoMesh)?;
        // The rock and, in a mine, its services (bolts, duct, pipes, cable, lights).
        let (caster, surface) = survey.scan_rays().ok_or(SenseError::NoMesh)?;
        let reflectivity: Vec<f32> = mesh.materials.iter().map(material_reflectivity).collect();
        let hazards = mesh
            .hazards
            .iter()
            .map(|h| {
                [
                    h.bounds[0],
                    h.bounds[1],
                    h.bounds[2],
                    h.bounds[3],
                    h.z[0],
                    h.z[1],
                ]
            })
            .collect();
        Ok(Scene::with_caster(
            Arc::clone(caster),
            surface,
            &reflectivity,
            hazards,
            world.resolved.tile_pitch,
        ))
    }

    /// A scene of any mesh, not a world's (tests, a mesh read from elsewhere): builds a
    /// hierarchy over it. `reflectivity` per material index (the triangles' `materials`; 0.3
    /// for an index without one).
    pub fn new(
        mesh: &Mesh,
        reflectivity: &[f32],
        hazards: Vec<[f64; 6]>,
        tile_pitch: f64,
    ) -> Scene {
        let caster = Arc::new(RayCaster::new(mesh));
        Scene::with_caster(caster, mesh, reflectivity, hazards, tile_pitch)
    }

    /// A scene of `mesh` whose hierarchy `caster` is already built (over that mesh).
    fn with_caster(
        caster: Arc<RayCaster>,
        mesh: &Mesh,
        reflectivity: &[f32],
        hazards: Vec<[f64; 6]>,
        tile_pitch: f64,
    ) -> Scene {
        let per_triangle = (0..mesh.triangles.len())
            .map(|i| {
                let m = mesh.materials.get(i).copied().unwrap_or(0) as usize;
                reflectivity.get(m).copied().unwrap_or(0.3)
            })
            .collect();
        Scene {
            caster,
            reflectivity: per_triangle,
            hazards,
            tile_pitch,
        }
    }

    /// Whether a point is over a floor hazard (within 1 m of its region in the plane).
    pub fn at_hazard(&self, p: [f64; 3]) -> bool {
        self.hazards.iter().any(|h| {
            p[0] >= h[0] - 1.0
                && p[0] <= h[2] + 1.0
                && p[1] >= h[1] - 1.0
                && p[1] <= h[3] + 1.0
                && p[2] >= h[4] - 2.0
                && p[2] <= h[5] + 3.0
        })
    }
}

/// A material's reflectivity at a LiDAR's wavelength (about 850 nm): the luminance of its
/// diffuse colour, a stand-in for a measured near-infrared reflectance (dark basalt about
/// 0.2, pale limestone about 0.5).
pub fn material_reflectivity(m: &subtgraph_core::mesh::Material) -> f32 {
    let [r, g, b] = m.colour;
    (0.2126 * r + 0.7152 * g + 0.0722 * b).clamp(0.02, 1.0)
}
