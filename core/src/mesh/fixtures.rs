//! Fixtures: small closed parts a tile set places many times beside the passage's shell (a
//! mine's rock bolts, ventilation duct, pipes, cable run and lights).
//!
//! A fixture is a prototype mesh in its own frame placed by a rigid transform and a scale per
//! axis, so the scene formats with instances (USD's `PointInstancer`, glTF nodes sharing one
//! mesh) store each prototype once however many bolts a world has, and the others bake them
//! ([`Fixtures::baked`]). They are kept apart from the shell so the shell stays one closed
//! piece; each prototype is closed itself, so a ray's parity over shell and fixtures together
//! still tells rock from passage.

use crate::grid::Cell;

use super::Mesh;

/// A part placed many times: a closed mesh in its own frame, one material.
#[derive(Clone, Debug, PartialEq)]
pub struct Prototype {
    /// Name in files and in the semantic labels (`rock-bolt`, `duct`, `pipe`, `cable`,
    /// `light`).
    pub name: &'static str,
    /// The closed mesh, metres, in the prototype's frame (normals pointing out of the part).
    pub mesh: Mesh,
    /// Index into the world's materials ([`crate::assembly::WorldMesh::materials`]).
    pub material: u8,
}

/// One placed copy of a prototype: `world = translation + rotation * (scale * local)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Index into [`Fixtures::prototypes`].
    pub prototype: u32,
    /// The tile whose passage it serves (for the semantic labels).
    pub cell: Cell,
    /// Where the prototype's origin goes, metres, world frame.
    pub translation: [f64; 3],
    /// Unit quaternion `[x, y, z, w]` (glTF's order).
    pub rotation: [f64; 4],
    /// Scale per axis of the prototype's frame, applied before the rotation.
    pub scale: [f64; 3],
}

impl Placement {
    /// The 3 x 3 matrix `rotation * diag(scale)`, rows.
    pub fn linear(&self) -> [[f64; 3]; 3] {
        let [x, y, z, w] = self.rotation;
        let r = [
            [
                1.0 - 2.0 * (y * y + z * z),
                2.0 * (x * y - z * w),
                2.0 * (x * z + y * w),
            ],
            [
                2.0 * (x * y + z * w),
                1.0 - 2.0 * (x * x + z * z),
                2.0 * (y * z - x * w),
            ],
            [
                2.0 * (x * z - y * w),
                2.0 * (y * z + x * w),
                1.0 - 2.0 * (x * x + y * y),
            ],
        ];
        r.map(|row| [0, 1, 2].map(|k| row[k] * self.scale[k]))
    }

    /// Where the prototype's point `p` lands in the world.
    pub fn apply(&self, p: [f32; 3]) -> [f64; 3] {
        let m = self.linear();
        let p = p.map(f64::from);
        [0, 1, 2].map(|i| self.translation[i] + m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2])
    }
}

/// A unit quaternion `[x, y, z, w]` turning the prototype's axes onto `x`, `y`, `x × y` (`x`
/// and `y` unit and perpendicular).
pub fn quaternion(x: [f64; 3], y: [f64; 3]) -> [f64; 4] {
    let z = crate::vec3::cross(x, y);
    // Columns x, y, z; Shepperd's method.
    let m = [[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]];
    let tr = m[0][0] + m[1][1] + m[2][2];
    let q = if tr > 0.0 {
        let s = (tr + 1.0).sqrt() * 2.0;
        [
            (m[2][1] - m[1][2]) / s,
            (m[0][2] - m[2][0]) / s,
            (m[1][0] - m[0][1]) / s,
            0.25 * s,
        ]
    } else if m[0][0] > m[1][1] && m[0][0] > m[2][2] {
        let s = (1.0 + m[0][0] - m[1][1] - m[2][2]).sqrt() * 2.0;
        [
            0.25 * s,
            (m[0][1] + m[1][0]) / s,
            (m[0][2] + m[2][0]) / s,
            (m[2][1] - m[1][2]) / s,
        ]
    } else if m[1][1] > m[2][2] {
        let s = (1.0 + m[1][1] - m[0][0] - m[2][2]).sqrt() * 2.0;
        [
            (m[0][1] + m[1][0]) / s,
            0.25 * s,
            (m[1][2] + m[2][1]) / s,
            (m[0][2] - m[2][0]) / s,
        ]
    } else {
        let s = (1.0 + m[2][2] - m[0][0] - m[1][1]).sqrt() * 2.0;
        [
            (m[0][2] + m[2][0]) / s,
            (m[1][2] + m[2][1]) / s,
            0.25 * s,
            (m[1][0] - m[0][1]) / s,
        ]
    };
    let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    // One sign for each rotation (w >= 0), so equal rotations write equal numbers.
    let s = if q[3] < 0.0 { -1.0 } else { 1.0 } / n;
    q.map(|v| v * s)
}

/// A world's fixtures: prototypes and where each copy goes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Fixtures {
    /// The parts, each once.
    pub prototypes: Vec<Prototype>,
    /// The copies, in a deterministic order (the tiles' raster order, then along the drift).
    pub placements: Vec<Placement>,
}

impl Fixtures {
    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.placements.is_empty()
    }

    /// Every copy as one mesh in world coordinates (for formats without instances, and for
    /// the ray caster): see [`bake`](Self::bake).
    pub fn baked(&self) -> Mesh {
        self.bake(0..self.placements.len())
    }

    /// The copies `copies` (indices into [`placements`](Self::placements), in that order)
    /// baked into one mesh in world coordinates: each copy's material its prototype's, with
    /// the prototypes' texture coordinates, without vertex normals. Neither user wants
    /// normals: the parts are boxes and cylinders whose averaged corner normals would shade
    /// them round, so the OBJ leaves readers to take face normals, and a ray's hit takes its
    /// triangle's. Working them out for every copy cost the mine's `generate` a fiftieth of
    /// its time.
    pub fn bake(&self, copies: impl IntoIterator<Item = usize>) -> Mesh {
        let mut out = Mesh::default();
        for i in copies {
            let p = &self.placements[i];
            let proto = &self.prototypes[p.prototype as usize];
            let m = &proto.mesh;
            let base = out.positions.len() as u32;
            out.positions
                .extend(m.positions.iter().map(|&v| p.apply(v).map(|c| c as f32)));
            if m.uvs.len() == m.positions.len() {
                out.uvs.extend_from_slice(&m.uvs);
            }
            out.triangles
                .extend(m.triangles.iter().map(|t| t.map(|v| v + base)));
            out.materials
                .extend(std::iter::repeat_n(proto.material, m.triangles.len()));
        }
        if out.uvs.len() != out.positions.len() {
            out.uvs.clear();
        }
        out
    }

    /// How many copies of each prototype.
    pub fn counts(&self) -> Vec<usize> {
        let mut n = vec![0; self.prototypes.len()];
        for p in &self.placements {
            n[p.prototype as usize] += 1;
        }
        n
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quaternion_turns_the_axes_where_asked() {
        let x = [0.0, 1.0, 0.0];
        let y = [-0.6, 0.0, 0.8];
        let p = Placement {
            prototype: 0,
            cell: Cell {
                level: 0,
                row: 0,
                col: 0,
            },
            translation: [1.0, 2.0, 3.0],
            rotation: quaternion(x, y),
            scale: [2.0, 1.0, 1.0],
        };
        let a = p.apply([1.0, 0.0, 0.0]);
        assert!(
            (a[0] - 1.0).abs() < 1e-9 && (a[1] - 4.0).abs() < 1e-9 && (a[2] - 3.0).abs() < 1e-9
        );
        let b = p.apply([0.0, 1.0, 0.0]);
        assert!(
            (b[0] - 0.4).abs() < 1e-9 && (b[2] - 3.8).abs() < 1e-9,
            "{b:?}"
        );
    }
}
