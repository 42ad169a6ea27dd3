//! Marching tetrahedra on the world lattice.
//!
//! Each lattice cube is split into six tetrahedra around its main diagonal (the Kuhn
//! triangulation, the same in every cube, so faces split the same way from both sides). A
//! tetrahedron never has an ambiguous case, so the surface is a closed 2-manifold wherever the
//! field is, with no holes between cubes or between tiles. Vertices sit on lattice edges and
//! are computed from the edge's lower end, so a tile and its neighbour place a shared vertex at
//! bit-identical coordinates and assembly welds the seam exactly.
//!
//! Orientation is exact (from the integer corner offsets, not from floating-point normals):
//! triangles are counter-clockwise seen from the void (`field < 0`).

use subtgraph_core::mesh::Mesh;

pub use crate::lattice::Block;

/// Corner bits: x = 1, y = 2, z = 4.
const TETS: [[u8; 4]; 6] = [
    [0, 1, 3, 7],
    [0, 1, 5, 7],
    [0, 2, 3, 7],
    [0, 2, 6, 7],
    [0, 4, 5, 7],
    [0, 4, 6, 7],
];

fn corner(bits: u8) -> [i64; 3] {
    [
        i64::from(bits & 1),
        i64::from((bits >> 1) & 1),
        i64::from((bits >> 2) & 1),
    ]
}

fn det(a: u8, b: u8, c: u8, d: u8) -> i64 {
    let (pa, pb, pc, pd) = (corner(a), corner(b), corner(c), corner(d));
    let u = [pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]];
    let v = [pc[0] - pa[0], pc[1] - pa[1], pc[2] - pa[2]];
    let w = [pd[0] - pa[0], pd[1] - pa[1], pd[2] - pa[2]];
    u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
        + u[2] * (v[0] * w[1] - v[1] * w[0])
}

/// Meshes the zero level set of `field` (negative inside the void) over a block. `field`
/// returns the value and a material index; a triangle takes the material of a solid corner
/// marked `solid_material` if it has one (rocks), else that of its first void corner.
pub fn polygonise(block: Block, solid_material: u8, field: impl Fn([f64; 3]) -> (f64, u8)) -> Mesh {
    let at = |p: [i64; 3]| field(p.map(|i| i as f64 * block.h)).0;
    polygonise_columns(block, solid_material, |_, _| (), |p, _: &()| field(p), at).0
}

/// Like [`polygonise`], for a field with a part that depends only on `(x, y)`: `column` is
/// evaluated once per lattice column and handed to `field` for every point of it. Also returns
/// the vertices on the block's faces (the only ones a neighbouring block can share).
///
/// Small separate pieces of either sign are removed first ([`crate::islands`]); `outside`
/// gives the field at a global lattice point outside the block, as the block that owns the
/// point computes it (for a piece across a face).
pub fn polygonise_columns<C>(
    block: Block,
    solid_material: u8,
    column: impl Fn(f64, f64) -> C,
    field: impl Fn([f64; 3], &C) -> (f64, u8),
    outside: impl Fn([i64; 3]) -> f64,
) -> (Mesh, Vec<u32>) {
    let [nx, ny, nz] = block.cubes;
    let (px, py, pz) = (nx + 1, ny + 1, nz + 1);
    let points = px * py * pz;
    let mut values = vec![0f64; points];
    let mut mats = vec![0u8; points];
    let mut any_in = false;
    let mut any_out = false;
    let index = |i: usize, j: usize, k: usize| (k * py + j) * px + i;
    for j in 0..py {
        for i in 0..px {
            let x = (block.origin[0] + i as i64) as f64 * block.h;
            let y = (block.origin[1] + j as i64) as f64 * block.h;
            let col = column(x, y);
            for k in 0..pz {
                let z = (block.origin[2] + k as i64) as f64 * block.h;
                let (mut v, m) = field([x, y, z], &col);
                if v == 0.0 {
                    v = 1e-12; // exactly on the surface counts as solid, consistently
                }
                any_in |= v < 0.0;
                any_out |= v > 0.0;
                let at = index(i, j, k);
                values[at] = v;
                mats[at] = m;
            }
        }
    }
    let mut mesh = Mesh::default();
    let mut seam = Vec::new();
    if !(any_in && any_out) {
        return (mesh, seam);
    }
    crate::islands::remove(&mut values, block, outside);
    let mut edge_vertex = vec![u32::MAX; points * 7];
    let point_of = |i: usize, j: usize, k: usize, bits: u8| {
        index(
            i + usize::from(bits & 1),
            j + usize::from((bits >> 1) & 1),
            k + usize::from((bits >> 2) & 1),
        )
    };
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let cv: [usize; 8] = std::array::from_fn(|b| point_of(i, j, k, b as u8));
                let inside = cv.map(|p| values[p] < 0.0);
                if inside.iter().all(|&x| x) || inside.iter().all(|&x| !x) {
                    continue;
                }
                for tet in TETS {
                    let ins: Vec<u8> = tet
                        .iter()
                        .copied()
                        .filter(|&b| inside[b as usize])
                        .collect();
                    let outs: Vec<u8> = tet
                        .iter()
                        .copied()
                        .filter(|&b| !inside[b as usize])
                        .collect();
                    if ins.is_empty() || outs.is_empty() {
                        continue;
                    }
                    let material = outs
                        .iter()
                        .find(|&&b| mats[cv[b as usize]] == solid_material)
                        .map(|&b| mats[cv[b as usize]])
                        .unwrap_or(mats[cv[ins[0] as usize]]);
                    let mut vertex = |a: u8, b: u8| -> u32 {
                        // Inclusion order: the lower corner's bits are a subset of the upper's.
                        let (lo, hi) = if a & b == a { (a, b) } else { (b, a) };
                        let key = cv[lo as usize] * 7 + (hi ^ lo) as usize - 1;
                        if edge_vertex[key] != u32::MAX {
                            return edge_vertex[key];
                        }
                        let (fa, fb) = (values[cv[lo as usize]], values[cv[hi as usize]]);
                        let t = (fa / (fa - fb)).clamp(1e-3, 1.0 - 1e-3);
                        let ca = corner(lo);
                        let cb = corner(hi);
                        let pos: [f32; 3] = std::array::from_fn(|d| {
                            let base = [i, j, k][d] as i64 + block.origin[d];
                            let a = (base + ca[d]) as f64 * block.h;
                            let b = (base + cb[d]) as f64 * block.h;
                            (a + t * (b - a)) as f32
                        });
                        let id = mesh.positions.len() as u32;
                        mesh.positions.push(pos);
                        // On the block's boundary when both ends lie on one of its faces.
                        let ends = |c: [i64; 3], d: usize| [i, j, k][d] as i64 + c[d];
                        let on_face = (0..3).any(|d| {
                            let (a, b) = (ends(ca, d), ends(cb, d));
                            a == b && (a == 0 || a == block.cubes[d] as i64)
                        });
                        if on_face {
                            seam.push(id);
                        }
                        edge_vertex[key] = id;
                        id
                    };
                    match (ins.len(), outs.len()) {
                        (1, 3) => {
                            let (i0, [mut j0, mut k0, l0]) = (ins[0], [outs[0], outs[1], outs[2]]);
                            let mut l0 = l0;
                            if det(i0, j0, k0, l0) < 0 {
                                std::mem::swap(&mut k0, &mut l0);
                            }
                            let _ = &mut j0;
                            // (e_ij, e_ik, e_il) faces away from i (the void): reverse it.
                            let t = [vertex(i0, j0), vertex(i0, l0), vertex(i0, k0)];
                            mesh.triangles.push(t);
                            mesh.materials.push(material);
                        }
                        (3, 1) => {
                            let (o0, [j0, mut k0, mut l0]) = (outs[0], [ins[0], ins[1], ins[2]]);
                            if det(o0, j0, k0, l0) < 0 {
                                std::mem::swap(&mut k0, &mut l0);
                            }
                            // (e_oj, e_ok, e_ol) faces away from o (the rock), into the void.
                            let t = [vertex(o0, j0), vertex(o0, k0), vertex(o0, l0)];
                            mesh.triangles.push(t);
                            mesh.materials.push(material);
                        }
                        _ => {
                            let (a, b) = (ins[0], ins[1]);
                            let (mut c, mut d) = (outs[0], outs[1]);
                            if det(a, b, c, d) < 0 {
                                std::mem::swap(&mut c, &mut d);
                            }
                            let (ac, ad, bc, bd) =
                                (vertex(a, c), vertex(a, d), vertex(b, c), vertex(b, d));
                            mesh.triangles.push([ac, bc, bd]);
                            mesh.triangles.push([ac, bd, ad]);
                            mesh.materials.push(material);
                            mesh.materials.push(material);
                        }
                    }
                }
            }
        }
    }
    (mesh, seam)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere_mesh(r: f64, h: f64) -> Mesh {
        let n = (2.0 * (r + 2.0 * h) / h).ceil() as usize;
        let o = -((n / 2) as i64);
        polygonise(
            Block {
                origin: [o, o, o],
                cubes: [n, n, n],
                h,
            },
            9,
            |p| ((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - r, 0),
        )
    }

    #[test]
    fn a_sphere_of_void_is_a_closed_surface_facing_inward() {
        let mut m = sphere_mesh(3.0, 0.37);
        let report = m.edge_report();
        assert!(report.is_closed(), "{report:?}");
        // Normals point into the void: toward the centre.
        m.compute_normals();
        let inward = m
            .positions
            .iter()
            .zip(&m.normals)
            .filter(|(p, n)| p[0] * n[0] + p[1] * n[1] + p[2] * n[2] < 0.0)
            .count();
        assert_eq!(inward, m.positions.len());
    }

    #[test]
    fn two_blocks_meet_vertex_for_vertex() {
        let field = |p: [f64; 3]| ((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 3.0, 0);
        let h = 0.5;
        let left = polygonise(
            Block {
                origin: [-8, -8, -8],
                cubes: [8, 16, 16],
                h,
            },
            9,
            field,
        );
        let right = polygonise(
            Block {
                origin: [0, -8, -8],
                cubes: [8, 16, 16],
                h,
            },
            9,
            field,
        );
        let mut whole = left.clone();
        whole.append(&right);
        assert!(!left.edge_report().is_closed());
        whole.weld();
        assert!(whole.edge_report().is_closed(), "{:?}", whole.edge_report());
    }
}
