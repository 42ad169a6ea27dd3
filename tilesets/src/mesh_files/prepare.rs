//! Turning a mesh file's parts into a tile's mesh: metres, z up, materials matched by part
//! name, vertices shared, and which sides of the tile square it opens on.

use subtgraph_core::grid::{Direction, Openings};
use subtgraph_core::mesh::Mesh;
use subtgraph_core::tile::TileKind;

use super::load::Part;
use super::manifest::Manifest;

/// Rotates `(x, y)` by `q` quarter turns counter-clockwise.
pub(super) fn turn(p: [f32; 3], q: u8) -> [f32; 3] {
    (0..q % 4).fold(p, |[x, y, z], _| [-y, x, z])
}

pub(super) fn materials_of(m: &Manifest) -> Vec<(String, u8)> {
    m.materials
        .iter()
        .enumerate()
        .filter_map(|(i, mat)| mat.matches.clone().map(|p| (p, i as u8)))
        .collect()
}

/// The parts of a file as one mesh in metres, z up, materials matched by part name.
pub(super) fn to_metres(parts: &[Part], manifest: &Manifest, matchers: &[(String, u8)]) -> Mesh {
    let s = manifest.scale as f32;
    let y_up = manifest.up == "y";
    let convert = |p: [f32; 3]| {
        if y_up {
            [p[0] * s, -p[2] * s, p[1] * s]
        } else {
            [p[0] * s, p[1] * s, p[2] * s]
        }
    };
    let mut mesh = Mesh::default();
    for part in parts {
        let material = matchers
            .iter()
            .find(|(prefix, _)| part.name.starts_with(prefix.as_str()))
            .map_or(0, |(_, i)| *i);
        let base = mesh.positions.len() as u32;
        mesh.positions
            .extend(part.positions.iter().map(|&p| convert(p)));
        let unit = |n: [f32; 3]| {
            let n = convert(n);
            let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt().max(1e-12);
            [n[0] / l, n[1] / l, n[2] / l]
        };
        if part.normals.len() == part.positions.len() {
            mesh.normals.extend(part.normals.iter().map(|&n| unit(n)));
        }
        if part.uvs.len() == part.positions.len() {
            mesh.uvs.extend_from_slice(&part.uvs);
        }
        mesh.triangles
            .extend(part.triangles.iter().map(|t| t.map(|i| i + base)));
        mesh.materials.resize(mesh.triangles.len(), material);
    }
    if mesh.normals.len() != mesh.positions.len() {
        mesh.normals.clear();
    }
    if mesh.uvs.len() != mesh.positions.len() {
        mesh.uvs.clear();
    }
    reindex(mesh)
}

/// Shares vertices that are identical in position, normal and texture coordinate (loaders
/// hand out one vertex per triangle corner; a tile is copied hundreds of times, so this
/// matters).
fn reindex(mesh: Mesh) -> Mesh {
    use std::collections::HashMap;
    use subtgraph_core::mesh::BuildFastHash;
    type Key = ([u32; 3], [u32; 3], [u32; 2]);
    let mut map: HashMap<Key, u32, BuildFastHash> =
        HashMap::with_capacity_and_hasher(mesh.positions.len() / 2, BuildFastHash::default());
    let mut out = Mesh {
        materials: mesh.materials.clone(),
        ..Mesh::default()
    };
    let has_n = !mesh.normals.is_empty();
    let has_uv = !mesh.uvs.is_empty();
    let remap: Vec<u32> = (0..mesh.positions.len())
        .map(|i| {
            let key = (
                mesh.positions[i].map(f32::to_bits),
                if has_n {
                    mesh.normals[i].map(f32::to_bits)
                } else {
                    [0; 3]
                },
                if has_uv {
                    mesh.uvs[i].map(f32::to_bits)
                } else {
                    [0; 2]
                },
            );
            *map.entry(key).or_insert_with(|| {
                out.positions.push(mesh.positions[i]);
                if has_n {
                    out.normals.push(mesh.normals[i]);
                }
                if has_uv {
                    out.uvs.push(mesh.uvs[i]);
                }
                out.positions.len() as u32 - 1
            })
        })
        .collect();
    out.triangles = mesh
        .triangles
        .iter()
        .map(|t| t.map(|i| remap[i as usize]))
        .collect();
    out
}

/// Which sides of the tile square (side `pitch`) the mesh crosses: the sides with vertices at
/// the tile boundary. A shaft is read on its lower half.
pub(super) fn openings(mesh: &Mesh, pitch: f64, kind: TileKind) -> Openings {
    let half = (0.5 * pitch) as f32;
    let tol = (0.04 * pitch) as f32;
    let zmax = mesh
        .bounds()
        .map_or(0.0, |(lo, hi)| lo[2] + 0.4 * (hi[2] - lo[2]));
    let low = |p: &&[f32; 3]| kind != TileKind::ShaftUp || p[2] <= zmax;
    let mut counts = [0usize; 4];
    let mut total = 0usize;
    for p in mesh.positions.iter().filter(low) {
        total += 1;
        for d in Direction::ALL {
            let (r, c) = d.step();
            let along = p[0] * c as f32 - p[1] * r as f32;
            if (along - half).abs() <= tol {
                counts[d as usize] += 1;
            }
        }
    }
    let threshold = (total / 200).max(3);
    Direction::ALL
        .into_iter()
        .filter(|d| counts[*d as usize] >= threshold)
        .fold(0, |m, d| m | d.bit())
}

pub(super) fn describe(o: Openings) -> String {
    let names: Vec<&str> = Direction::ALL
        .into_iter()
        .filter(|d| o & d.bit() != 0)
        .map(|d| match d {
            Direction::East => "east",
            Direction::North => "north",
            Direction::West => "west",
            Direction::South => "south",
        })
        .collect();
    if names.is_empty() {
        "nowhere".into()
    } else {
        names.join(" and ")
    }
}
