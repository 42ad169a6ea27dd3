//! What the sensors see of a world: its visual surface (with a mine's services) in a ray
//! caster, what each triangle is (its material, how strongly that reflects a LiDAR's
//! near-infrared light, the tile or fixture it belongs to), and where its floor hazards are.
//!
//! The ray caster is the world survey's ([`WorldSurvey::scan_rays`]): one hierarchy over the
//! surface `mesh/world.obj` and `mesh/services.obj` hold, the one cameras and other
//! simulators' ray casters see, built once per world and shared (an `Arc`). The ground truth
//! is made on the collision surface, within the world's collision budget of this one.

use std::sync::Arc;

use subtgraph_core::mesh::Mesh;
use subtgraph_core::raycast::RayCaster;
use subtgraph_survey::WorldSurvey;

use crate::error::SenseError;
use crate::surface::Surface;

/// A world made ready for sensing: built once, then shared by every scan.
pub struct Scene {
    /// The sensed surface's hierarchy (the survey's, shared).
    pub caster: Arc<RayCaster>,
    /// What each triangle of that surface is: its material and part ([`Surface::hit`]).
    pub surface: Surface,
    /// Each material's reflectivity in `[0, 1]` (index: [`Surface::materials`]' values).
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
        let (caster, _) = survey.scan_rays().ok_or(SenseError::NoMesh)?;
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
        Ok(Scene {
            caster: Arc::clone(caster),
            surface: Surface::of_world(mesh),
            reflectivity,
            hazards,
            tile_pitch: world.resolved.tile_pitch,
        })
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
        Scene {
            caster: Arc::new(RayCaster::new(mesh)),
            surface: Surface::of_materials(&mesh.materials, mesh.triangles.len()),
            reflectivity: reflectivity.to_vec(),
            hazards,
            tile_pitch,
        }
    }

    /// The reflectivity of triangle `t`'s material (0.3 for a material without one).
    pub fn reflectivity_of(&self, t: u32) -> f32 {
        let m = self.surface.material(t) as usize;
        self.reflectivity.get(m).copied().unwrap_or(0.3)
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
