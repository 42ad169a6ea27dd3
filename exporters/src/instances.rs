//! Repeated tiles: tiles whose visual triangles are the same up to a translation (the same
//! mesh file placed with the same rotation, as with the DARPA tiles; procedural tiles never
//! repeat), so a scene format can store the geometry once and place it many times.
//!
//! Two tiles repeat when, walking their triangles in order, every corner lies at the same
//! offset from the tile's first corner (within [`TOLERANCE`]), every triangle has the same
//! material, and their texture coordinates differ by one whole-number shift (so a texture
//! looks the same). Candidates are found by a key of a few numbers rounded to a coarse grid
//! (triangle count, materials, bounding box): exact float bits are not translation-exact
//! (`a + t - t != a`), and a hash of every rounded corner misses repeats, since among a
//! tile's 100 000 coordinates some always fall on either side of a rounding boundary. The key
//! only decides which tiles are compared, never whether they repeat. Everything runs in tile order,
//! so the prototypes and their numbering are deterministic.

use std::collections::BTreeMap;

use subtgraph_core::assembly::WorldMesh;

/// How far a corner may be from where the prototype puts it, in metres.
pub(crate) const TOLERANCE: f32 = 2e-3;

/// The rounding grid of the candidate hash, in metres.
const QUANTUM: f32 = 1.0 / 8.0;

/// A prototype: the geometry of its first tile, with points relative to `origin`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Prototype {
    /// The tile (index into [`WorldMesh::tiles`]) whose triangles are the prototype's.
    pub tile: usize,
    /// The tile's first corner: the prototype's local origin.
    pub origin: [f32; 3],
}

/// Which tiles are placed copies of a prototype.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Instances {
    /// Prototypes, in order of their first tile.
    pub prototypes: Vec<Prototype>,
    /// Per tile: `(prototype, translation)` when the tile is an instance (its first corner).
    pub of_tile: Vec<Option<(usize, [f32; 3])>>,
}

impl Instances {
    /// No instancing: every tile stays in its part's mesh.
    pub(crate) fn none(mesh: &WorldMesh) -> Instances {
        Instances {
            prototypes: Vec::new(),
            of_tile: vec![None; mesh.tiles.len()],
        }
    }
}

/// The corners of a tile's visual triangles, in order, as vertex indices.
fn corners(mesh: &WorldMesh, tile: usize) -> impl Iterator<Item = usize> + '_ {
    mesh.visual.triangles[mesh.tiles[tile].visual_triangles.clone()]
        .iter()
        .flatten()
        .map(|&v| v as usize)
}

fn first_corner(mesh: &WorldMesh, tile: usize) -> Option<[f32; 3]> {
    corners(mesh, tile).next().map(|v| mesh.visual.positions[v])
}

/// The candidate key: triangle count, materials, and the size of the bounding box rounded
/// to [`QUANTUM`]. A few numbers only, so float noise rarely lands two repeats on either side
/// of a rounding boundary (which would only cost an instance, never make a wrong one).
fn key(mesh: &WorldMesh, tile: usize) -> Option<(usize, u64)> {
    let o = first_corner(mesh, tile)?;
    let (mut lo, mut hi) = (o, o);
    for v in corners(mesh, tile) {
        let p = mesh.visual.positions[v];
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut mix = |x: i64| {
        h ^= x as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    };
    for k in 0..3 {
        mix(((hi[k] - lo[k]) / QUANTUM).round() as i64);
        mix(((o[k] - lo[k]) / QUANTUM).round() as i64);
    }
    let r = mesh.tiles[tile].visual_triangles.clone();
    for t in r.clone() {
        mix(i64::from(
            mesh.visual.materials.get(t).copied().unwrap_or(0),
        ));
    }
    Some((r.len(), h))
}

/// Whether tile `b` is tile `a` moved by a translation.
fn repeats(mesh: &WorldMesh, a: usize, b: usize) -> bool {
    let (ra, rb) = (
        mesh.tiles[a].visual_triangles.clone(),
        mesh.tiles[b].visual_triangles.clone(),
    );
    if ra.len() != rb.len() {
        return false;
    }
    let material = |t: usize| mesh.visual.materials.get(t).copied().unwrap_or(0);
    if ra.clone().zip(rb).any(|(x, y)| material(x) != material(y)) {
        return false;
    }
    let (Some(oa), Some(ob)) = (first_corner(mesh, a), first_corner(mesh, b)) else {
        return false;
    };
    let uvs = mesh.visual.uvs.len() == mesh.visual.positions.len();
    let mut shift: Option<[f32; 2]> = None;
    for (va, vb) in corners(mesh, a).zip(corners(mesh, b)) {
        let (pa, pb) = (mesh.visual.positions[va], mesh.visual.positions[vb]);
        if (0..3).any(|k| ((pa[k] - oa[k]) - (pb[k] - ob[k])).abs() > TOLERANCE) {
            return false;
        }
        if uvs {
            let (ua, ub) = (mesh.visual.uvs[va], mesh.visual.uvs[vb]);
            let d = [ub[0] - ua[0], ub[1] - ua[1]];
            match shift {
                None => {
                    if d.iter().any(|x| (x - x.round()).abs() > TOLERANCE) {
                        return false;
                    }
                    shift = Some(d);
                }
                Some(s) => {
                    if (0..2).any(|k| (d[k] - s[k]).abs() > TOLERANCE) {
                        return false;
                    }
                }
            }
        }
    }
    true
}

/// Finds the tiles that repeat an earlier tile's geometry; a geometry used once stays a
/// plain tile.
pub(crate) fn find_instances(mesh: &WorldMesh) -> Instances {
    // Groups of repeating tiles, in order of their first tile (its representative), and
    // per candidate key the groups to compare a new tile with.
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut by_key: BTreeMap<(usize, u64), Vec<usize>> = BTreeMap::new();
    for t in 0..mesh.tiles.len() {
        let Some(k) = key(mesh, t) else { continue };
        let candidates = by_key.entry(k).or_default();
        match candidates.iter().find(|&&g| repeats(mesh, groups[g][0], t)) {
            Some(&g) => groups[g].push(t),
            None => {
                candidates.push(groups.len());
                groups.push(vec![t]);
            }
        }
    }
    let repeated: Vec<Vec<usize>> = groups.into_iter().filter(|m| m.len() > 1).collect();
    let mut out = Instances::none(mesh);
    for members in repeated {
        let k = out.prototypes.len();
        let origin = first_corner(mesh, members[0]).expect("keyed tiles have triangles");
        out.prototypes.push(Prototype {
            tile: members[0],
            origin,
        });
        for t in members {
            out.of_tile[t] = Some((k, first_corner(mesh, t).expect("keyed")));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::mesh::Mesh;

    /// A world mesh of tiles that are one triangle each, at the given offsets.
    fn triangles(at: &[[f32; 3]]) -> WorldMesh {
        let mut mesh = WorldMesh::default();
        for (i, o) in at.iter().enumerate() {
            let m = Mesh {
                positions: vec![
                    [o[0] + 0.1, o[1] + 0.2, o[2]],
                    [o[0] + 1.3, o[1], o[2]],
                    [o[0], o[1] + 1.7, o[2] + 0.5],
                ],
                triangles: vec![[0, 1, 2]],
                materials: vec![0],
                ..Mesh::default()
            };
            mesh.visual.append(&m);
            mesh.tiles.push(subtgraph_core::assembly::PlacedTile {
                cell: subtgraph_core::grid::Cell {
                    level: 0,
                    row: 0,
                    col: i,
                },
                kind: subtgraph_core::tile::TileKind::Straight,
                rotation: 0,
                visual_triangles: i..i + 1,
                collision_triangles: 0..0,
                labels: Vec::new(),
                floor_lift: [0.0, 0.0],
                axis: None,
            });
        }
        mesh
    }

    #[test]
    fn translated_copies_share_a_prototype_and_others_do_not() {
        let mut mesh = triangles(&[[0.0; 3], [80.0, 0.0, 0.0], [1234.5, -80.0, 16.0], [5.0; 3]]);
        // The last tile is different: one corner moved by 1 cm.
        mesh.visual.positions[11][0] += 0.01;
        let inst = find_instances(&mesh);
        assert_eq!(inst.prototypes.len(), 1);
        assert_eq!(inst.prototypes[0].tile, 0);
        assert!(
            inst.of_tile[..3]
                .iter()
                .all(|i| i.is_some_and(|(k, _)| k == 0))
        );
        assert_eq!(inst.of_tile[3], None);
        assert_eq!(inst.of_tile[2].unwrap().1, mesh.visual.positions[6]);
    }
}
