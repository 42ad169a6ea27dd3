//! The fixtures (a mine's services, `subtgraph_core::mesh::Fixtures`) as the scene formats
//! with instances store them: each prototype once, each copy a transform. Shared by the glTF
//! writer (a node per copy naming the prototype's mesh) and the USD writer (a
//! `PointInstancer`).

use subtgraph_core::mesh::{Fixtures, Mesh, Placement};

/// Prototype `k`'s mesh with its material on every triangle.
pub(crate) fn prototype_mesh(f: &Fixtures, k: usize) -> Mesh {
    let p = &f.prototypes[k];
    let mut m = p.mesh.clone();
    m.materials = vec![p.material; m.triangles.len()];
    m
}

/// Hamilton product `a * b` of quaternions `[x, y, z, w]`.
fn multiply(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let [ax, ay, az, aw] = a;
    let [bx, by, bz, bw] = b;
    [
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    ]
}

/// A copy's transform in glTF's Y-up frame, for a prototype mesh written Y up too (`(x, y,
/// z)` as `(x, z, -y)`, the turn `C`): translation `C t`, rotation `C R C⁻¹`, scale with its
/// y and z swapped (`C S C⁻¹`).
pub(crate) fn y_up(p: &Placement) -> ([f64; 3], [f64; 4], [f64; 3]) {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let c = [-h, 0.0, 0.0, h];
    let c_inv = [h, 0.0, 0.0, h];
    let [x, y, z] = p.translation;
    let r = multiply(multiply(c, p.rotation), c_inv);
    // One sign per rotation, as `quaternion` writes them.
    let r = if r[3] < 0.0 { r.map(|v| -v) } else { r };
    ([x, z, -y], r, [p.scale[0], p.scale[2], p.scale[1]])
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::grid::Cell;
    use subtgraph_core::mesh::quaternion;

    #[test]
    fn the_y_up_transform_moves_points_as_the_frame_does() {
        let p = Placement {
            prototype: 0,
            cell: Cell {
                level: 0,
                row: 0,
                col: 0,
            },
            translation: [1.0, 2.0, 3.0],
            rotation: quaternion([0.0, 1.0, 0.0], [-0.6, 0.0, 0.8]),
            scale: [2.0, 0.5, 0.25],
        };
        let (t, r, s) = y_up(&p);
        let q = Placement {
            translation: t,
            rotation: r,
            scale: s,
            ..p
        };
        for v in [[1.0f32, 0.0, 0.0], [0.0, 1.0, 0.0], [0.3, -0.2, 0.7]] {
            let a = p.apply(v);
            let b = q.apply([v[0], v[2], -v[1]]);
            let want = [a[0], a[2], -a[1]];
            for k in 0..3 {
                assert!((b[k] - want[k]).abs() < 1e-9, "{v:?}: {b:?} vs {want:?}");
            }
        }
    }
}
