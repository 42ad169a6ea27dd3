//! The collision copy of a procedural tile: its visual surface simplified within a bound
//! (`[tileset] collision_tolerance`), not a second marching on a coarser lattice.
//!
//! Why: physics and the ground truth (free space, widths, the drive) work on the collision
//! surface, sensors and cameras on the visual one, and the two must agree. A coarse lattice
//! (pitch / 12, 1.7-2.1 m on the presets) put the collision floor a median 2 cm and up to 37 cm
//! from the visual one beside the routes, and walls up to 0.9 m (issue 39's table: 48-59 cm at
//! the 99th percentile). Simplifying the visual surface instead
//! ([`crate::simplify`]) keeps every collision vertex exactly on it and every
//! visual vertex within a tolerance of the collision surface: a tight one on floors (what a
//! wheel stands on), a looser one on walls and roofs, where a few centimetres change nothing a
//! robot or the ground truth measures. Flat floors and smooth tubes lose most of their
//! triangles; rough rock keeps more.
//!
//! A vertex is a floor's when its normal (area weighted, into the passage) is within 60 degrees
//! of up: more than the 45 degrees the budget's check calls a floor, so a floor's edge is held
//! tight too. Seam vertices (on the tile's block faces) stay, so neighbouring tiles' copies weld
//! as their visual surfaces do.

use crate::simplify::simplify;
use subtgraph_core::mesh::Mesh;

/// Metres the visual surface may lie from the collision surface: `[floors, the rest]`.
pub const DEFAULT_TOLERANCE: [f64; 2] = [0.02, 0.10];

/// A vertex whose normal's z is at least this is a floor's (60 degrees from up).
const FLOOR_NORMAL_Z: f64 = 0.5;

/// The collision copy of a tile's `visual` mesh, and its seam (indices into it) from the
/// visual's `seam`; `tolerance` is `[floors, the rest]`, metres.
pub fn collision_of(visual: &Mesh, seam: &[u32], tolerance: [f64; 2]) -> (Mesh, Vec<u32>) {
    let normals = vertex_normals(visual);
    let per_vertex: Vec<f32> = normals
        .iter()
        .map(|n| {
            let t = if n[2] >= FLOOR_NORMAL_Z {
                tolerance[0]
            } else {
                tolerance[1]
            };
            t as f32
        })
        .collect();
    let s = simplify(visual, seam, &per_vertex);
    let seam = seam.iter().map(|&v| s.kept[v as usize]).collect();
    let mut mesh = s.mesh;
    mesh.materials.clear();
    (mesh, seam)
}

/// Area-weighted vertex normals (the z of a unit normal is all the classing reads).
fn vertex_normals(m: &Mesh) -> Vec<[f64; 3]> {
    use subtgraph_core::vec3::{cross, sub, unit};
    let mut acc = vec![[0.0f64; 3]; m.positions.len()];
    for t in &m.triangles {
        let [a, b, c] = t.map(|v| m.positions[v as usize].map(f64::from));
        let n = cross(sub(b, a), sub(c, a));
        for &v in t {
            for k in 0..3 {
                acc[v as usize][k] += n[k];
            }
        }
    }
    acc.into_iter()
        .map(|n| unit(n).unwrap_or([0.0; 3]))
        .collect()
}
