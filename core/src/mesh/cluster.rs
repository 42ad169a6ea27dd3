//! One mesh simplifier, vertex clustering: every vertex in one cell of a grid becomes one, and
//! the triangles that collapse are dropped. Snapping to fixed grid points (not to averages)
//! keeps the seams between pieces, parts and tiles closed: two meshes that share a border
//! snap its vertices to the same points. MuJoCo's coarse visual meshes (`visual = "coarse"`)
//! and the mesh-file tile set's collision copies use it.

use std::collections::{HashMap, HashSet};

use super::{BuildFastHash, Mesh};

/// Where [`Mesh::clustered`] moves each vertex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Grid {
    /// To the centre of its cube: cubes of side `cell` from the world's origin.
    CubeCentres {
        /// The cube's side, metres.
        cell: f32,
    },
    /// To the nearest point of a lattice `cell` apart through `origin` (a tile's corner, so
    /// its lines fall on the tile's edges).
    Points {
        /// The spacing, metres.
        cell: f32,
        /// A lattice point.
        origin: [f32; 3],
    },
}

impl Grid {
    /// The cell a position falls in.
    fn key(self, p: [f32; 3]) -> [i32; 3] {
        match self {
            Grid::CubeCentres { cell } => p.map(|v| (v / cell).floor() as i32),
            Grid::Points { cell, origin } => {
                [0, 1, 2].map(|a| ((p[a] - origin[a]) / cell).round() as i32)
            }
        }
    }

    /// The position the vertices of cell `key` move to.
    fn point(self, key: [i32; 3]) -> [f32; 3] {
        match self {
            Grid::CubeCentres { cell } => key.map(|c| (c as f32 + 0.5) * cell),
            Grid::Points { cell, origin } => [0, 1, 2].map(|a| origin[a] + key[a] as f32 * cell),
        }
    }
}

/// How to cluster a mesh's vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clustering {
    /// Where the vertices go.
    pub grid: Grid,
    /// Whether the result keeps normals (the average of the merged vertices', renormalised),
    /// texture coordinates (the first merged vertex's) and each kept triangle's material;
    /// `false` keeps positions and triangles only (a collision surface).
    pub attributes: bool,
    /// Whether a triangle with the same three vertices as one already kept (in any order) is
    /// dropped too.
    pub distinct: bool,
}

impl Mesh {
    /// This mesh with its vertices clustered (see the module doc): vertices numbered in order
    /// of first use, so the result is deterministic.
    pub fn clustered(&self, how: &Clustering) -> Mesh {
        let mut index: HashMap<[i32; 3], u32, BuildFastHash> =
            HashMap::with_capacity_and_hasher(self.positions.len() / 4, BuildFastHash::default());
        let mut out = Mesh::default();
        let has_normals = how.attributes && self.normals.len() == self.positions.len();
        let has_uvs = how.attributes && self.uvs.len() == self.positions.len();
        let mut normal_sums: Vec<[f32; 3]> = Vec::new();
        let remap: Vec<u32> = self
            .positions
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                let key = how.grid.key(p);
                let next = out.positions.len() as u32;
                let k = *index.entry(key).or_insert(next);
                if k == next {
                    out.positions.push(how.grid.point(key));
                    if has_normals {
                        normal_sums.push([0.0; 3]);
                    }
                    if has_uvs {
                        out.uvs.push(self.uvs[i]);
                    }
                }
                if has_normals {
                    let s = &mut normal_sums[k as usize];
                    for (s, n) in s.iter_mut().zip(self.normals[i]) {
                        *s += n;
                    }
                }
                k
            })
            .collect();
        if has_normals {
            out.normals = normal_sums
                .into_iter()
                .map(|n| {
                    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                    if l > 0.0 {
                        n.map(|v| v / l)
                    } else {
                        [0.0, 0.0, 1.0]
                    }
                })
                .collect();
        }
        // Sized as the mesh-file tile set's copies need (about a quarter of the triangles
        // survive), so the set rarely grows.
        let mut seen: HashSet<[u32; 3], BuildFastHash> = HashSet::with_capacity_and_hasher(
            if how.distinct {
                self.triangles.len() / 4
            } else {
                0
            },
            BuildFastHash::default(),
        );
        for (t, tri) in self.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|v| remap[v as usize]);
            if a == b || b == c || a == c {
                continue;
            }
            if how.distinct {
                let mut key = [a, b, c];
                key.sort_unstable();
                if !seen.insert(key) {
                    continue;
                }
            }
            out.triangles.push([a, b, c]);
            if how.attributes {
                out.materials
                    .push(self.materials.get(t).copied().unwrap_or(0));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two triangles sharing an edge, and a sliver that collapses, with normals and UVs.
    fn strip() -> Mesh {
        Mesh {
            positions: vec![
                [0.1, 0.1, 0.0],
                [1.9, 0.2, 0.0],
                [0.2, 1.8, 0.0],
                [1.8, 1.9, 0.1],
                [0.15, 0.12, 0.02],
            ],
            normals: vec![[0.0, 0.0, 1.0]; 5],
            uvs: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [0.5, 0.5]],
            triangles: vec![[0, 1, 2], [1, 3, 2], [0, 4, 1], [2, 1, 0]],
            materials: vec![1, 2, 3, 4],
        }
    }

    #[test]
    fn vertices_go_to_cube_centres_or_lattice_points_and_collapsed_triangles_go() {
        let m = strip();
        let coarse = m.clustered(&Clustering {
            grid: Grid::CubeCentres { cell: 1.0 },
            attributes: true,
            distinct: false,
        });
        // Vertices 0 and 4 share a cube; the sliver collapses, the reversed copy stays.
        assert_eq!(coarse.positions.len(), 4);
        assert_eq!(coarse.positions[0], [0.5, 0.5, 0.5]);
        assert_eq!(coarse.triangles.len(), 3);
        assert_eq!(coarse.materials, vec![1, 2, 4]);
        assert_eq!(coarse.uvs[0], [0.0, 0.0], "the first merged vertex's");
        assert_eq!(coarse.normals.len(), coarse.positions.len());
        let lattice = m.clustered(&Clustering {
            grid: Grid::Points {
                cell: 2.0,
                origin: [0.0, 0.0, 0.0],
            },
            attributes: false,
            distinct: true,
        });
        assert!(lattice.positions.iter().flatten().all(|v| v % 2.0 == 0.0));
        assert_eq!(lattice.triangles.len(), 2, "the reversed copy is dropped");
        assert!(lattice.normals.is_empty() && lattice.uvs.is_empty());
        assert!(lattice.materials.is_empty());
    }
}
