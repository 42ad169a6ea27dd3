//! Triangle meshes: what tile sets produce and exporters write.

mod cluster;
mod fixtures;

use serde::{Deserialize, Serialize};

pub use cluster::{Clustering, Grid};
pub use fixtures::{Fixtures, Placement, Prototype, quaternion};

use crate::vec3::{cross, sub};

/// A surface material a tile set paints triangles with.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// Name used in files (`cave-wall`, `rock-pile`, ...).
    pub name: String,
    /// Diffuse colour, linear RGB in `[0, 1]`.
    pub colour: [f32; 3],
    /// An image file for the colour (the albedo), relative to the world folder's `mesh/`, if
    /// any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture: Option<String>,
    /// A tangent-space normal map (OpenGL convention: green up), relative to `mesh/`, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_map: Option<String>,
    /// A roughness map (grey: black smooth, white rough), relative to `mesh/`, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roughness_map: Option<String>,
}

impl Material {
    /// A plain coloured material.
    pub fn coloured(name: &str, colour: [f32; 3]) -> Self {
        Self {
            name: name.to_owned(),
            colour,
            texture: None,
            normal_map: None,
            roughness_map: None,
        }
    }

    /// Its image files (albedo, normal, roughness), those it has.
    pub fn maps(&self) -> impl Iterator<Item = &str> {
        [&self.texture, &self.normal_map, &self.roughness_map]
            .into_iter()
            .filter_map(|m| m.as_deref())
    }
}

/// An image file a tile set writes into the world folder for its materials (a texture).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ImageFile {
    /// Where, relative to the world folder's `mesh/` (`textures/mine-wall-albedo.png`).
    pub path: String,
    /// The file's bytes (PNG).
    pub bytes: Vec<u8>,
}

/// An indexed triangle mesh in world coordinates (metres, x east, y north, z up).
///
/// `normals` and `uvs` are per vertex and may be left empty by a tile set: assembly then
/// computes area-weighted normals and box-projected UVs. `materials` holds one index into the
/// tile set's material list per triangle (empty means material 0 everywhere).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Unit normals per vertex, pointing into the passage (the side a robot sees).
    pub normals: Vec<[f32; 3]>,
    /// Texture coordinates per vertex.
    pub uvs: Vec<[f32; 2]>,
    /// Triangles, counter-clockwise seen from the passage.
    pub triangles: Vec<[u32; 3]>,
    /// Material index per triangle.
    pub materials: Vec<u8>,
}

impl Mesh {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Appends another mesh.
    pub fn append(&mut self, other: &Mesh) {
        let base = self.positions.len() as u32;
        self.materials.resize(self.triangles.len(), 0);
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.uvs.extend_from_slice(&other.uvs);
        self.triangles.extend(
            other
                .triangles
                .iter()
                .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
        );
        if other.materials.len() == other.triangles.len() {
            self.materials.extend_from_slice(&other.materials);
        } else {
            self.materials.resize(self.triangles.len(), 0);
        }
    }

    /// Area-weighted vertex normals from the triangles' winding.
    pub fn compute_normals(&mut self) {
        let mut acc = vec![[0f64; 3]; self.positions.len()];
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| self.positions[i as usize].map(f64::from));
            let n = cross(sub(b, a), sub(c, a));
            for &i in t {
                for k in 0..3 {
                    acc[i as usize][k] += n[k];
                }
            }
        }
        self.normals = acc
            .into_iter()
            .map(|n| {
                let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                if len > 0.0 {
                    [
                        (n[0] / len) as f32,
                        (n[1] / len) as f32,
                        (n[2] / len) as f32,
                    ]
                } else {
                    [0.0, 0.0, 1.0]
                }
            })
            .collect();
    }

    /// Box-projected texture coordinates, `metres_per_repeat` metres per texture repeat: each
    /// vertex is projected along the axis its normal is closest to.
    pub fn compute_box_uvs(&mut self, metres_per_repeat: f32) {
        let s = 1.0 / metres_per_repeat;
        self.uvs = self
            .positions
            .iter()
            .zip(&self.normals)
            .map(|(p, n)| {
                let (ax, ay, az) = (n[0].abs(), n[1].abs(), n[2].abs());
                if az >= ax && az >= ay {
                    [p[0] * s, p[1] * s]
                } else if ax >= ay {
                    [p[1] * s, p[2] * s]
                } else {
                    [p[0] * s, p[2] * s]
                }
            })
            .collect();
    }

    /// The axis-aligned bounds `(min, max)`, or `None` for an empty mesh.
    pub fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        let mut it = self.positions.iter();
        let first = *it.next()?;
        Some(it.fold((first, first), |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])],
                [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])],
            )
        }))
    }
}

/// Edge statistics of a closed-surface check: how many edges are shared by one, two, or more
/// triangles, and how many shared edges are traversed the same way by both (inconsistent
/// winding).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EdgeReport {
    /// Distinct undirected edges.
    pub edges: usize,
    /// Edges with one triangle: holes.
    pub boundary: usize,
    /// Edges with three or more triangles: non-manifold.
    pub non_manifold: usize,
    /// Edges whose two triangles run it in the same direction.
    pub flipped: usize,
}

impl EdgeReport {
    /// Whether the surface is closed, manifold and consistently wound.
    pub fn is_closed(&self) -> bool {
        self.boundary == 0 && self.non_manifold == 0 && self.flipped == 0
    }
}

impl Mesh {
    /// Checks that every edge is shared by exactly two triangles running it in opposite
    /// directions.
    pub fn edge_report(&self) -> EdgeReport {
        let mut edges: Vec<(u32, u32, bool)> = Vec::with_capacity(self.triangles.len() * 3);
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                edges.push(if a < b { (a, b, true) } else { (b, a, false) });
            }
        }
        edges.sort_unstable();
        let mut r = EdgeReport::default();
        let mut i = 0;
        while i < edges.len() {
            let mut j = i;
            while j < edges.len() && edges[j].0 == edges[i].0 && edges[j].1 == edges[i].1 {
                j += 1;
            }
            r.edges += 1;
            match j - i {
                1 => r.boundary += 1,
                2 => r.flipped += usize::from(edges[i].2 == edges[i + 1].2),
                _ => r.non_manifold += 1,
            }
            i = j;
        }
        r
    }

    /// Merges vertices with bit-identical positions (tiles compute their shared openings from
    /// the same numbers, so the seams weld exactly), dropping triangles that collapse.
    /// Returns where the old triangles went, as [`weld_among`](Self::weld_among) does.
    pub fn weld(&mut self) -> Vec<usize> {
        let all: Vec<u32> = (0..self.positions.len() as u32).collect();
        self.weld_among(&all)
    }

    /// Like [`weld`](Self::weld), considering only the listed vertices (sorted ascending):
    /// the others are known to be unique.
    ///
    /// Returns, for every old triangle index `i` (and one past the last), how many triangles
    /// before it were kept: old range `a..b` is new range `kept[a]..kept[b]`. That keeps
    /// per-tile triangle ranges exact when welding drops collapsed triangles.
    pub fn weld_among(&mut self, candidates: &[u32]) -> Vec<usize> {
        if candidates.is_empty() {
            return (0..=self.triangles.len()).collect();
        }
        use std::collections::HashMap;
        let mut map: HashMap<[u32; 3], u32, BuildFastHash> =
            HashMap::with_capacity_and_hasher(candidates.len(), BuildFastHash::default());
        let n = self.positions.len();
        let mut target: Vec<u32> = (0..n as u32).collect();
        for &c in candidates {
            let key = self.positions[c as usize].map(f32::to_bits);
            let first = *map.entry(key).or_insert(c);
            target[c as usize] = first;
        }
        // Compact: keep first occurrences in order.
        let mut remap = vec![0u32; n];
        let mut positions = Vec::with_capacity(n);
        let mut normals = Vec::new();
        let mut uvs = Vec::new();
        for i in 0..n {
            if target[i] as usize == i {
                remap[i] = positions.len() as u32;
                positions.push(self.positions[i]);
                if let Some(v) = self.normals.get(i) {
                    normals.push(*v);
                }
                if let Some(v) = self.uvs.get(i) {
                    uvs.push(*v);
                }
            } else {
                remap[i] = remap[target[i] as usize];
            }
        }
        let mut triangles = Vec::with_capacity(self.triangles.len());
        let mut materials = Vec::with_capacity(self.materials.len());
        let mut kept = Vec::with_capacity(self.triangles.len() + 1);
        for (k, t) in self.triangles.iter().enumerate() {
            kept.push(triangles.len());
            let t = t.map(|i| remap[i as usize]);
            if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                triangles.push(t);
                if let Some(m) = self.materials.get(k) {
                    materials.push(*m);
                }
            }
        }
        self.positions = positions;
        self.normals = normals;
        self.uvs = uvs;
        kept.push(triangles.len());
        self.triangles = triangles;
        self.materials = materials;
        kept
    }

    /// A mesh of the triangles in `ranges` only, with just the vertices they use (in order of
    /// first use), keeping normals, UVs and materials. For writing a part of a world, or one
    /// tile, without copying the rest.
    pub fn extract(&self, ranges: &[std::ops::Range<usize>]) -> Mesh {
        let count: usize = ranges.iter().map(|r| r.len()).sum();
        let mut out = Mesh::default();
        out.triangles.reserve(count);
        let with_n = self.normals.len() == self.positions.len();
        let with_uv = self.uvs.len() == self.positions.len();
        let with_m = self.materials.len() == self.triangles.len();
        // Vertex map sized to the span the ranges touch, not to the whole mesh.
        let (mut lo, mut hi) = (u32::MAX, 0u32);
        for r in ranges {
            for t in &self.triangles[r.clone()] {
                for &v in t {
                    lo = lo.min(v);
                    hi = hi.max(v);
                }
            }
        }
        if count == 0 {
            return out;
        }
        let mut map = vec![u32::MAX; (hi - lo + 1) as usize];
        for r in ranges {
            for k in r.clone() {
                let t = self.triangles[k].map(|v| {
                    let slot = &mut map[(v - lo) as usize];
                    if *slot == u32::MAX {
                        *slot = out.positions.len() as u32;
                        out.positions.push(self.positions[v as usize]);
                        if with_n {
                            out.normals.push(self.normals[v as usize]);
                        }
                        if with_uv {
                            out.uvs.push(self.uvs[v as usize]);
                        }
                    }
                    *slot
                });
                out.triangles.push(t);
                if with_m {
                    out.materials.push(self.materials[k]);
                }
            }
        }
        out
    }
}

/// The hasher for hash maps keyed by vertex positions or lattice cells: `rustc-hash`'s Fx
/// hash, fast and non-cryptographic (positions are not adversarial input). Every map keyed
/// this way is only probed and filled, never iterated, so the hash function cannot change an
/// output.
pub type BuildFastHash = rustc_hash::FxBuildHasher;

#[cfg(test)]
mod tests {
    use super::*;

    fn tetrahedron() -> Mesh {
        Mesh {
            positions: vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]],
            triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
            ..Mesh::default()
        }
    }

    #[test]
    fn a_tetrahedron_is_closed_and_losing_a_face_opens_it() {
        let t = tetrahedron();
        assert!(t.edge_report().is_closed());
        let mut open = t.clone();
        open.triangles.pop();
        assert_eq!(open.edge_report().boundary, 3);
        let mut flipped = t;
        flipped.triangles[0] = [0, 1, 2];
        assert_eq!(flipped.edge_report().flipped, 3);
    }

    #[test]
    fn welding_merges_identical_positions() {
        let mut m = tetrahedron();
        // Split vertex 3 into a copy used by one face.
        m.positions.push([0., 0., 1.]);
        m.triangles[3] = [1, 2, 4];
        assert!(!m.edge_report().is_closed());
        m.weld();
        assert_eq!(m.positions.len(), 4);
        assert!(m.edge_report().is_closed());
    }
}
