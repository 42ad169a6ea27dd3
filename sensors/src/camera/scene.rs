//! What a camera sees of a world: its visual surface (`mesh/world.obj`: the rock as the tile
//! set textured it), its services (`mesh/services.obj`: a mine's bolts, duct, pipes, cable and
//! lights) and its artifacts (their boxes in the DARPA classes' colours, with a band of
//! retroreflective tape round the survivor's vest, the helmet and the backpack), in one
//! ray-cast hierarchy (the core's [`RayCaster`]), in that order.
//!
//! The LiDAR casts into the collision surface, the lighter mesh physics uses; a camera needs
//! what is drawn, so it has a hierarchy of its own over the visual surface, built once per
//! sequence. Every triangle knows its material (whose albedo, normal and roughness maps
//! [`texture`](super::texture) samples at the hit's texture coordinates), its semantic class
//! ([`Class`]: the tile's kind and features and the material for rock, the part for a
//! service, the class for an artifact) and its instance (each artifact, each service copy;
//! 0 for rock).

use std::collections::BTreeMap;
use std::sync::Arc;

use serde::Serialize;
use subtgraph_core::World;
use subtgraph_core::artifacts::{Artifact, ArtifactClass};
use subtgraph_core::mesh::{Material, Mesh};
use subtgraph_core::raycast::RayCaster;
use subtgraph_core::vec3::V3;

use super::texture::{Map, Stack, Texture};
use crate::error::SenseError;

/// A semantic class: what the pixels of one id in a label image are.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
pub struct Class {
    /// Its id in the label images (0 is nothing: no surface, or outside a fisheye's circle).
    pub id: u16,
    /// `rock`, `service` or `artifact` (`none` for id 0).
    pub surface: &'static str,
    /// For rock: its tile's kind, as `ground_truth/semantic_labels.json` names it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tile_kind: Option<&'static str>,
    /// For rock: its tile's features (`chamber`, `squeeze`, `mesh-panels`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub features: Vec<&'static str>,
    /// For a service: the part (`rock-bolt`, `duct`, `pipe`, `cable`, `light`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub service: Option<&'static str>,
    /// For an artifact: its class (`survivor`, ...).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub artifact: Option<&'static str>,
    /// The material (empty for id 0).
    pub material: String,
}

/// The instance ids of a scene: artifacts first, then every service copy.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Instances {
    /// Artifact `k` (ground_truth/artifacts.json's id `k`) is instance `k + 1`; its name.
    pub artifacts: Vec<String>,
    /// Service copy `k` (in `mesh/services.obj`'s order) is instance `first_service + k`.
    pub first_service: u32,
    /// Service copies.
    pub services: u32,
}

/// How a material looks to a camera.
pub struct Look {
    /// Name.
    pub name: String,
    /// Linear colour, when it has no albedo image.
    pub colour: [f32; 3],
    /// Its maps, when it has them.
    pub albedo: Option<Texture>,
    /// Tangent-space normals.
    pub normal: Option<Texture>,
    /// Roughness.
    pub roughness_map: Option<Texture>,
    /// The three maps interleaved, when they have one size (then the three above are
    /// `None`: the stack is what is sampled).
    pub stack: Option<Stack>,
    /// Roughness without a map.
    pub roughness: f32,
    /// Peak coefficient of retroreflection (tape), candela per lux per square metre.
    pub retro: f32,
    /// Metres per texture repeat the coordinates stand for (the tile sets' 3 m).
    pub texels_per_metre: f64,
}

/// A world as the cameras see it.
pub struct CameraScene {
    /// The hierarchy over [`mesh`](Self::mesh).
    pub caster: Arc<RayCaster>,
    /// Visual surface, services, artifacts: positions, texture coordinates (zeros where a
    /// part has none), triangles and materials (indices into [`looks`](Self::looks)).
    pub mesh: Mesh,
    /// Vertex normals of the visual surface's vertices (the first of `mesh`'s); the others
    /// shade with their triangles' normals.
    pub vertex_normals: Vec<[f32; 3]>,
    /// Per material.
    pub looks: Vec<Look>,
    /// Per triangle, its class's id.
    pub class: Vec<u16>,
    /// Per triangle, its instance (0 for rock).
    pub instance: Vec<u32>,
    /// Every class, by id.
    pub legend: Vec<Class>,
    /// What the instance ids are.
    pub instances: Instances,
}

/// Metres per texture repeat of the tile sets' coordinates (`[tileset] texture_size` texels
/// per 3 m).
const REPEAT_M: f64 = 3.0;
/// A retroreflective tape's peak coefficient, candela per lux per square metre.
const TAPE_RETRO: f32 = 300.0;

impl CameraScene {
    /// The scene of a world with a mesh, and its artifacts when it has any.
    pub fn of(world: &World, artifacts: &[Artifact]) -> Result<CameraScene, SenseError> {
        let wm = world.mesh().ok_or(SenseError::NoMesh)?;
        let visual = &wm.visual;
        let mut mesh = Mesh {
            positions: visual.positions.clone(),
            uvs: if visual.uvs.len() == visual.positions.len() {
                visual.uvs.clone()
            } else {
                vec![[0.0; 2]; visual.positions.len()]
            },
            triangles: visual.triangles.clone(),
            materials: if visual.materials.len() == visual.triangles.len() {
                visual.materials.clone()
            } else {
                vec![0; visual.triangles.len()]
            },
            normals: Vec::new(),
        };
        let vertex_normals = if visual.normals.len() == visual.positions.len() {
            visual.normals.clone()
        } else {
            Vec::new()
        };
        let mut legend = Legend::default();
        let mut class = Vec::with_capacity(mesh.triangles.len());
        let mut instance = Vec::with_capacity(mesh.triangles.len());
        rock_classes(
            world,
            &wm.materials,
            &mesh.materials,
            &mut legend,
            &mut class,
        );
        instance.resize(class.len(), 0);

        // The services, copy by copy (the order of mesh/services.obj).
        let first_service = artifacts.len() as u32 + 1;
        let f = &wm.fixtures;
        append(&mut mesh, &f.baked());
        let mut end = class.len();
        for (k, p) in f.placements.iter().enumerate() {
            let proto = &f.prototypes[p.prototype as usize];
            let id = legend.id(Class {
                id: 0,
                surface: "service",
                tile_kind: None,
                features: Vec::new(),
                service: Some(proto.name),
                artifact: None,
                material: material_name(&wm.materials, proto.material),
            });
            end += proto.mesh.triangles.len();
            class.resize(end, id);
            instance.resize(end, first_service + k as u32);
        }

        // The artifacts: their own materials after the world's.
        let mut looks = world_looks(&wm.materials, &wm.textures)?;
        let tape = looks.len();
        if tape + ArtifactClass::ALL.len() + 1 > 255 {
            return Err(SenseError::OutOfBounds {
                what: "the tile set's materials".into(),
                value: tape.to_string(),
                bounds: "at most 244 for a camera (the artifacts' 11 come after them)".into(),
            });
        }
        looks.push(Look {
            name: "retroreflective-tape".into(),
            colour: [0.8, 0.8, 0.8],
            albedo: None,
            normal: None,
            roughness_map: None,
            stack: None,
            roughness: 0.4,
            retro: TAPE_RETRO,
            texels_per_metre: 1.0,
        });
        for c in ArtifactClass::ALL {
            looks.push(Look {
                name: format!("artifact-{}", c.name()),
                colour: c.colour(),
                albedo: None,
                normal: None,
                roughness_map: None,
                stack: None,
                roughness: 0.5,
                retro: 0.0,
                texels_per_metre: 1.0,
            });
        }
        for (k, a) in artifacts.iter().enumerate() {
            let body = (tape
                + 1
                + ArtifactClass::ALL
                    .iter()
                    .position(|c| *c == a.class)
                    .unwrap_or(0)) as u8;
            let (part, taped) = artifact_mesh(a, body, tape as u8);
            for (range, m) in [
                (0..part.triangles.len() - taped, body),
                (
                    part.triangles.len() - taped..part.triangles.len(),
                    tape as u8,
                ),
            ] {
                let id = legend.id(Class {
                    id: 0,
                    surface: "artifact",
                    tile_kind: None,
                    features: Vec::new(),
                    service: None,
                    artifact: Some(a.class.name()),
                    material: looks[usize::from(m)].name.clone(),
                });
                class.extend(std::iter::repeat_n(id, range.len()));
            }
            append(&mut mesh, &part);
            instance.resize(mesh.triangles.len(), k as u32 + 1);
        }
        let caster = Arc::new(RayCaster::new(&mesh));
        Ok(CameraScene {
            caster,
            mesh,
            vertex_normals,
            looks,
            class,
            instance,
            legend: legend.classes,
            instances: Instances {
                artifacts: artifacts.iter().map(|a| a.name.clone()).collect(),
                first_service,
                services: f.placements.len() as u32,
            },
        })
    }

    /// Bytes the scene holds beyond the world (its hierarchy, its copy of the mesh, the
    /// classes), for the memory it is said to take.
    pub fn bytes(&self) -> usize {
        self.caster.bytes()
            + self.mesh.positions.len() * 20
            + self.mesh.triangles.len() * (12 + 1 + 2 + 4)
            + self.vertex_normals.len() * 12
    }

    /// A triangle's corners.
    #[inline]
    pub fn corners(&self, t: u32) -> [V3; 3] {
        self.mesh.triangles[t as usize].map(|i| self.mesh.positions[i as usize].map(f64::from))
    }
}

/// The classes met so far, and their ids in order of meeting.
#[derive(Default)]
struct Legend {
    classes: Vec<Class>,
    ids: BTreeMap<Class, u16>,
}

impl Legend {
    fn id(&mut self, c: Class) -> u16 {
        if self.classes.is_empty() {
            self.classes.push(Class {
                id: 0,
                surface: "none",
                tile_kind: None,
                features: Vec::new(),
                service: None,
                artifact: None,
                material: String::new(),
            });
        }
        if let Some(&id) = self.ids.get(&c) {
            return id;
        }
        let id = self.classes.len().min(usize::from(u16::MAX)) as u16;
        self.ids.insert(c.clone(), id);
        self.classes.push(Class { id, ..c });
        id
    }
}

fn material_name(materials: &[Material], m: u8) -> String {
    materials
        .get(usize::from(m))
        .map_or_else(|| format!("material-{m}"), |x| x.name.clone())
}

/// The rock's classes, triangle by triangle: its tile's kind and features, and its material.
fn rock_classes(
    world: &World,
    materials: &[Material],
    per_triangle: &[u8],
    legend: &mut Legend,
    class: &mut Vec<u16>,
) {
    let Some(wm) = world.mesh() else {
        return;
    };
    let ramps = world.resolved.connections == subtgraph_core::config::Connections::Ramp;
    // Each triangle's tile (the tiles' ranges are in order and do not overlap).
    let mut tile_of = vec![usize::MAX; per_triangle.len()];
    for (k, t) in wm.tiles.iter().enumerate() {
        for i in t.visual_triangles.clone() {
            if let Some(slot) = tile_of.get_mut(i) {
                *slot = k;
            }
        }
    }
    let mut cache: BTreeMap<(usize, u8), u16> = BTreeMap::new();
    for (i, &m) in per_triangle.iter().enumerate() {
        let tile = tile_of[i];
        let id = *cache.entry((tile, m)).or_insert_with(|| {
            let (kind, features) = match wm.tiles.get(tile) {
                Some(t) => {
                    let kind = if ramps
                        && world
                            .shafts
                            .iter()
                            .any(|s| s.up == t.cell || s.landing == t.cell)
                    {
                        "ramp"
                    } else {
                        t.kind.name()
                    };
                    (Some(kind), t.labels.clone())
                }
                None => (None, Vec::new()),
            };
            legend.id(Class {
                id: 0,
                surface: "rock",
                tile_kind: kind,
                features,
                service: None,
                artifact: None,
                material: material_name(materials, m),
            })
        });
        class.push(id);
    }
}

/// The looks of the world's materials, their images decoded.
fn world_looks(
    materials: &[Material],
    images: &[subtgraph_core::mesh::ImageFile],
) -> Result<Vec<Look>, SenseError> {
    let find = |path: &Option<String>, map: Map| -> Result<Option<Texture>, SenseError> {
        let Some(p) = path else {
            return Ok(None);
        };
        let Some(file) = images.iter().find(|f| &f.path == p) else {
            return Ok(None);
        };
        Texture::decode(&file.bytes)
            .map(|t| Some(t.with_levels(map)))
            .map_err(|why| SenseError::BadGraph {
                path: format!("mesh/{p}"),
                why: format!("the texture cannot be read ({why})"),
            })
    };
    materials
        .iter()
        .map(|m| {
            let albedo = find(&m.texture, Map::Albedo)?;
            let texels_per_metre = albedo
                .as_ref()
                .map_or(1.0, |t| t.texels_per_repeat() / REPEAT_M);
            let normal = find(&m.normal_map, Map::Normal)?;
            let roughness_map = find(&m.roughness_map, Map::Roughness)?;
            let stack = match (&albedo, &normal, &roughness_map) {
                (Some(a), Some(n), Some(r)) => Stack::of(a, n, r),
                _ => None,
            };
            let (albedo, normal, roughness_map) = if stack.is_some() {
                (None, None, None)
            } else {
                (albedo, normal, roughness_map)
            };
            Ok(Look {
                name: m.name.clone(),
                colour: m.colour,
                albedo,
                normal,
                roughness_map,
                stack,
                roughness: 0.8,
                retro: 0.0,
                texels_per_metre,
            })
        })
        .collect()
}

/// Appends a part (positions, coordinates or zeros, triangles, materials).
fn append(mesh: &mut Mesh, part: &Mesh) {
    let base = mesh.positions.len() as u32;
    mesh.positions.extend_from_slice(&part.positions);
    if part.uvs.len() == part.positions.len() {
        mesh.uvs.extend_from_slice(&part.uvs);
    } else {
        mesh.uvs.resize(mesh.positions.len(), [0.0; 2]);
    }
    mesh.triangles
        .extend(part.triangles.iter().map(|t| t.map(|v| v + base)));
    mesh.materials.extend_from_slice(&part.materials);
    mesh.materials.resize(mesh.triangles.len(), 0);
}

/// Whether an artifact of this class wears retroreflective tape.
fn taped(c: ArtifactClass) -> bool {
    matches!(
        c,
        ArtifactClass::Survivor | ArtifactClass::Helmet | ArtifactClass::Backpack
    )
}

/// An artifact's box (material `body`), and for the taped classes a band round its middle 2 mm
/// proud of its sides (material `tape`): the mesh, and how many triangles at its end are tape.
fn artifact_mesh(a: &Artifact, body: u8, tape: u8) -> (Mesh, usize) {
    let [l, w, h] = a.size;
    let (s, c) = a.yaw.sin_cos();
    let at = |x: f64, y: f64, z: f64| -> [f32; 3] {
        [
            (a.position[0] + c * x - s * y) as f32,
            (a.position[1] + s * x + c * y) as f32,
            (a.position[2] + z) as f32,
        ]
    };
    let mut m = Mesh::default();
    // A box [x0, x1] x [y0, y1] x [z0, z1], faces wound outwards, as quads of two triangles.
    let cuboid = |m: &mut Mesh, lo: [f64; 3], hi: [f64; 3], sides_only: bool, mat: u8| {
        let base = m.positions.len() as u32;
        for k in 0..8 {
            let x = if k & 1 == 0 { lo[0] } else { hi[0] };
            let y = if k & 2 == 0 { lo[1] } else { hi[1] };
            let z = if k & 4 == 0 { lo[2] } else { hi[2] };
            m.positions.push(at(x, y, z));
        }
        let mut quads = vec![[0, 2, 6, 4], [1, 5, 7, 3], [0, 4, 5, 1], [2, 3, 7, 6]];
        if !sides_only {
            quads.extend([[0, 1, 3, 2], [4, 6, 7, 5]]);
        }
        for q in quads {
            let q = q.map(|i: u32| base + i);
            m.triangles.push([q[0], q[1], q[2]]);
            m.triangles.push([q[0], q[2], q[3]]);
            m.materials.extend([mat, mat]);
        }
    };
    cuboid(
        &mut m,
        [-0.5 * l, -0.5 * w, 0.0],
        [0.5 * l, 0.5 * w, h],
        false,
        body,
    );
    let before = m.triangles.len();
    if taped(a.class) {
        let e = 0.002;
        cuboid(
            &mut m,
            [-0.5 * l - e, -0.5 * w - e, 0.45 * h],
            [0.5 * l + e, 0.5 * w + e, 0.6 * h],
            true,
            tape,
        );
    }
    let taped = m.triangles.len() - before;
    m.uvs = vec![[0.0; 2]; m.positions.len()];
    (m, taped)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_artifact_box_is_closed_and_its_tape_rings_its_middle() {
        let a = Artifact {
            id: 0,
            name: "survivor-0".into(),
            class: ArtifactClass::Survivor,
            position: [1.0, 2.0, 3.0],
            yaw: 0.3,
            size: ArtifactClass::Survivor.size(),
            cell: subtgraph_core::grid::Cell::new(0, 0, 0),
            tile_kind: subtgraph_core::tile::TileKind::DeadEnd,
            placement: subtgraph_core::artifacts::Placement::Floor,
            graph: subtgraph_core::artifacts::GraphPlace::Node { node: 0 },
            distance_from_start_m: 0.0,
            visible_from_axis: true,
            sight_from: [0.0; 3],
        };
        let (m, tape) = artifact_mesh(&a, 1, 0);
        assert_eq!(tape, 8);
        let body = Mesh {
            triangles: m.triangles[..12].to_vec(),
            ..m.clone()
        };
        assert!(body.edge_report().is_closed());
        // A ray from outside at the tape's height meets the tape first, from above the box.
        let caster = RayCaster::new(&m);
        let c = a.centre();
        let side = caster
            .cast(
                [
                    c[0] - 3.0 * 0.3f64.cos() + 0.0,
                    c[1] - 3.0 * 0.3f64.sin(),
                    3.0 + 0.52 * 0.7,
                ],
                [0.3f64.cos(), 0.3f64.sin(), 0.0],
                10.0,
            )
            .unwrap();
        assert_eq!(m.materials[side.triangle as usize], 0, "tape");
        let top = caster
            .cast([c[0], c[1], 10.0], [0.0, 0.0, -1.0], 20.0)
            .unwrap();
        assert!((top.t - (10.0 - 3.7)).abs() < 1e-4);
        assert_eq!(m.materials[top.triangle as usize], 1);
    }
}
