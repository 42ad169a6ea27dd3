//! What a ray met, beyond its distance: the material of the triangle hit and the part of the
//! world it belongs to (a tile, or one placed fixture such as a rock bolt), per triangle of the
//! surface the sensors see ([`crate::scene::Scene`]).
//!
//! A LiDAR needs only the material (its reflectivity sets a return's intensity). A camera also
//! needs the texture at the hit and a semantic label: [`Surface::hit`] gives the material, the
//! part and the hit's barycentric coordinates ([`subtgraph_core::raycast::Hit::barycentric`]),
//! from which the triangle's texture coordinates (`WorldMesh::visual`'s `uvs`, the fixtures'
//! prototypes') and the tile's labels (`WorldMesh::tiles`, the semantic labels' order) follow.
//! The tables cost a byte a triangle and a few bytes a tile or fixture.

use subtgraph_core::assembly::WorldMesh;
use subtgraph_core::raycast::Hit;

/// The part of a world a triangle belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// A tile's surface: the index into `WorldMesh::tiles` (raster order, as the semantic
    /// labels list them).
    Tile(u32),
    /// A placed fixture: the index into `WorldMesh::fixtures.placements` (its prototype names
    /// what it is: `rock-bolt`, `duct`, ...).
    Fixture(u32),
    /// A surface that is not a world's (a mesh given to [`crate::scene::Scene::new`]).
    Unknown,
}

/// A ray's hit with what its triangle is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    /// The hierarchy's hit: distance, triangle, normal, barycentric coordinates.
    pub hit: Hit,
    /// The triangle's material: an index into `WorldMesh::materials`.
    pub material: u8,
    /// Where the triangle belongs.
    pub part: Part,
}

/// Per triangle of the sensed surface: its material, and where it belongs.
#[derive(Clone, Debug, Default)]
pub struct Surface {
    /// Each triangle's material index.
    pub materials: Vec<u8>,
    /// The first triangle of each tile, then one past the last tile's (`WorldMesh::tiles`'
    /// visual ranges, which follow one another).
    tile_starts: Vec<u32>,
    /// The first triangle of each placed fixture, then one past the last's.
    fixture_starts: Vec<u32>,
}

impl Surface {
    /// The surface of a world's visual mesh with its fixtures baked after it, as
    /// `WorldSurvey::scan_rays` lays it out.
    pub fn of_world(mesh: &WorldMesh) -> Surface {
        let visual = mesh.visual.triangles.len();
        let mut materials = mesh.visual.materials.clone();
        materials.resize(visual, 0);
        let mut tile_starts: Vec<u32> = mesh
            .tiles
            .iter()
            .map(|t| t.visual_triangles.start as u32)
            .collect();
        tile_starts.push(visual as u32);
        let f = &mesh.fixtures;
        let mut fixture_starts = Vec::with_capacity(f.placements.len() + 1);
        let mut at = visual as u32;
        for p in &f.placements {
            fixture_starts.push(at);
            let proto = &f.prototypes[p.prototype as usize];
            at += proto.mesh.triangles.len() as u32;
            materials.extend(std::iter::repeat_n(
                proto.material,
                proto.mesh.triangles.len(),
            ));
        }
        fixture_starts.push(at);
        Surface {
            materials,
            tile_starts,
            fixture_starts,
        }
    }

    /// The surface of any mesh's triangles' `materials` (empty: material 0 for all).
    pub fn of_materials(materials: &[u8], triangles: usize) -> Surface {
        let mut materials = materials.to_vec();
        materials.resize(triangles, 0);
        Surface {
            materials,
            ..Surface::default()
        }
    }

    /// The material of triangle `t` (0 past the end).
    pub fn material(&self, t: u32) -> u8 {
        self.materials.get(t as usize).copied().unwrap_or(0)
    }

    /// Where triangle `t` belongs.
    pub fn part(&self, t: u32) -> Part {
        let within = |starts: &[u32]| {
            let (first, last) = (*starts.first()?, *starts.last()?);
            if t < first || t >= last {
                return None;
            }
            Some(starts.partition_point(|&s| s <= t) as u32 - 1)
        };
        if let Some(i) = within(&self.tile_starts) {
            Part::Tile(i)
        } else if let Some(i) = within(&self.fixture_starts) {
            Part::Fixture(i)
        } else {
            Part::Unknown
        }
    }

    /// A hit with its triangle's material and part.
    pub fn hit(&self, hit: Hit) -> SurfaceHit {
        SurfaceHit {
            hit,
            material: self.material(hit.triangle),
            part: self.part(hit.triangle),
        }
    }
}
