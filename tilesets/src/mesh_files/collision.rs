//! The collision copy of a mesh tile: lighter (snapped to a coarse grid from the tile's
//! corner, so neighbouring tiles meet on their seams) and without the *fins* snapping leaves;
//! and the vertical-line crossings the fin probe and the elevation tile's floors read.

use subtgraph_core::mesh::{Clustering, Grid, Mesh};

/// A lighter copy for collision: vertices snapped to a grid of `cell` metres from `origin` and
/// merged, triangles that collapse dropped, and so are the *fins* the snapping leaves: a bump
/// of the floor whose top snaps down onto the floor keeps its front as a vertical triangle up to
/// a cell high, standing in the passage with free space on both sides. Rays cast down do not
/// see it, but it stops a body (PyBullet's ball on the DARPA cave, at 1842.6, 382.4).
pub fn simplify(mesh: &Mesh, cell: f32, origin: [f32; 3]) -> Mesh {
    // Vertices snapped to a grid of `cell` metres from `origin` and merged, triangles that
    // collapse (or repeat) dropped: positions only.
    let mut out = mesh.clustered(&Clustering {
        grid: Grid::Points { cell, origin },
        attributes: false,
        distinct: true,
    });
    let flat = Flat::new(&out, cell);
    let fins: Vec<bool> = out
        .triangles
        .iter()
        .map(|&t| is_fin(&out, &flat, t, cell))
        .collect();
    let mut k = 0;
    out.triangles.retain(|_| {
        k += 1;
        !fins[k - 1]
    });
    out
}

/// `mesh`'s surface (positions and triangles, as [`simplify`] gives them) with every vertex
/// within `near` metres of a line of the tile's edges (the square of side `pitch` from
/// `origin`, its south-west corner) moved onto it.
pub(super) fn onto_edges(mesh: &Mesh, near: f32, origin: [f32; 3], pitch: f32) -> Mesh {
    let mut out = Mesh {
        positions: mesh.positions.clone(),
        triangles: mesh.triangles.clone(),
        ..Mesh::default()
    };
    for p in &mut out.positions {
        for a in 0..2 {
            for edge in [origin[a], origin[a] + pitch] {
                if (p[a] - edge).abs() <= near {
                    p[a] = edge;
                }
            }
        }
    }
    out
}

/// Whether triangle `t` of `mesh` stands vertical with free space on both sides of it half way
/// up (free: between a floor below and a ceiling above, by the facing of the triangles crossed
/// along the vertical line; normals point into the passage).
fn is_fin(mesh: &Mesh, flat: &Flat, t: [u32; 3], cell: f32) -> bool {
    let p = t.map(|i| mesh.positions[i as usize].map(f64::from));
    use subtgraph_core::vec3::{cross, sub};
    let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    let h = (n[0] * n[0] + n[1] * n[1]).sqrt();
    if h == 0.0 || n[2].abs() > 1e-6 * h {
        return false;
    }
    let c = [0, 1, 2].map(|a| (p[0][a] + p[1][a] + p[2][a]) / 3.0);
    // Off the grid's lines and diagonals, so the probe lines cross the floor inside triangles.
    let (off, along) = (0.2371 * f64::from(cell), 0.0137 * f64::from(cell));
    let (nx, ny) = (n[0] / h, n[1] / h);
    [1.0, -1.0].iter().all(|&side| {
        let q = [
            c[0] + side * off * nx - along * ny,
            c[1] + side * off * ny + along * nx,
        ];
        flat.free_at(q, c[2])
    })
}

/// The triangles of a mesh that a vertical line can cross (not vertical), bucketed by squares
/// of the snapping grid for the probes of [`is_fin`].
struct Flat {
    cell: f64,
    triangles: Vec<[[f64; 3]; 3]>,
    buckets: std::collections::HashMap<[i64; 2], Vec<u32>>,
}

impl Flat {
    fn new(mesh: &Mesh, cell: f32) -> Flat {
        let cell = f64::from(cell);
        let mut flat = Flat {
            cell,
            triangles: Vec::new(),
            buckets: std::collections::HashMap::new(),
        };
        for t in &mesh.triangles {
            let p = t.map(|i| mesh.positions[i as usize].map(f64::from));
            if area(&p) == 0.0 {
                continue;
            }
            let k = flat.triangles.len() as u32;
            let lo = [0, 1].map(|a| (p[0][a].min(p[1][a]).min(p[2][a]) / cell).floor() as i64);
            let hi = [0, 1].map(|a| (p[0][a].max(p[1][a]).max(p[2][a]) / cell).floor() as i64);
            for bx in lo[0]..=hi[0] {
                for by in lo[1]..=hi[1] {
                    flat.buckets.entry([bx, by]).or_default().push(k);
                }
            }
            flat.triangles.push(p);
        }
        flat
    }

    /// Whether height `z` on the vertical line through `q` lies between a floor and a ceiling.
    fn free_at(&self, q: [f64; 2], z: f64) -> bool {
        let key = [0, 1].map(|a| (q[a] / self.cell).floor() as i64);
        let Some(bucket) = self.buckets.get(&key) else {
            return false;
        };
        let hits = line_crossings(bucket.iter().map(|&k| &self.triangles[k as usize]), q);
        let mut floor = None;
        for (h, up) in hits {
            if up {
                floor = Some(h);
            } else if let Some(f) = floor.take() {
                if f < z && z < h {
                    return true;
                }
            }
        }
        false
    }
}

/// Where the vertical line through `q` crosses `triangles` (none of them vertical): each
/// crossing's height and whether its triangle faces up (a floor) or down (a ceiling), from the
/// bottom up, a ceiling before a floor at the same height.
pub(super) fn line_crossings<'a>(
    triangles: impl IntoIterator<Item = &'a [[f64; 3]; 3]>,
    q: [f64; 2],
) -> Vec<(f64, bool)> {
    let mut hits: Vec<(f64, bool)> = Vec::new();
    for p in triangles {
        let a = area(p);
        let w = [
            ((p[1][0] - q[0]) * (p[2][1] - q[1]) - (p[1][1] - q[1]) * (p[2][0] - q[0])) / a,
            ((p[2][0] - q[0]) * (p[0][1] - q[1]) - (p[2][1] - q[1]) * (p[0][0] - q[0])) / a,
        ];
        let w = [w[0], w[1], 1.0 - w[0] - w[1]];
        if w.iter().all(|&b| b >= 0.0) {
            hits.push((w[0] * p[0][2] + w[1] * p[1][2] + w[2] * p[2][2], a > 0.0));
        }
    }
    hits.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    hits
}

/// Twice the signed area of a triangle seen from above (positive: its normal points up).
pub(super) fn area(p: &[[f64; 3]; 3]) -> f64 {
    (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A floor (facing up) and a ceiling 4 m above it (facing down) over `[x0, x1] x [0, 8]`.
    fn slab(m: &mut Mesh, x0: f32, x1: f32) {
        let b = m.positions.len() as u32;
        for z in [0.0, 4.0] {
            for p in [[x0, 0.0], [x1, 0.0], [x1, 8.0], [x0, 8.0]] {
                m.positions.push([p[0], p[1], z]);
            }
        }
        m.triangles.extend([[b, b + 1, b + 2], [b, b + 2, b + 3]]);
        m.triangles
            .extend([[b + 4, b + 6, b + 5], [b + 4, b + 7, b + 6]]);
    }

    fn vertical(m: &mut Mesh, tri: [[f32; 3]; 3]) -> [f32; 3] {
        let b = m.positions.len() as u32;
        m.positions.extend(tri);
        m.triangles.push([b, b + 1, b + 2]);
        tri[2]
    }

    #[test]
    fn the_collision_copy_drops_fins_and_keeps_walls() {
        let mut m = Mesh::default();
        slab(&mut m, 0.0, 8.0);
        // A bump's front snapped vertical, standing in the room; a wall on the room's edge.
        let fin = vertical(&mut m, [[4.0, 2.0, 0.0], [4.0, 6.0, 0.0], [4.1, 4.0, 1.2]]);
        let wall = vertical(&mut m, [[0.0, 2.0, 0.0], [0.0, 6.0, 0.0], [0.1, 4.0, 2.1]]);
        let out = simplify(&m, 1.0, [0.0; 3]);
        let apexes: Vec<[f32; 3]> = out
            .triangles
            .iter()
            .filter_map(|t| {
                let p = t.map(|i| out.positions[i as usize]);
                (p[0][0] == p[1][0] && p[1][0] == p[2][0]).then_some(p[2])
            })
            .collect();
        assert_eq!(
            apexes,
            vec![[0.0, 4.0, 2.0]],
            "{fin:?} dropped, {wall:?} kept"
        );
        assert_eq!(out.triangles.len(), 5);
    }

    #[test]
    fn tiles_snapped_from_their_corners_meet_at_the_seam() {
        // Two tiles 4 m wide whose seam is at x = 4.5, half way between the lines of a grid
        // from the origin; their edges carry rounding noise either side of it.
        let (mut a, mut b) = (Mesh::default(), Mesh::default());
        slab(&mut a, 0.5, 4.4999);
        slab(&mut b, 4.5001, 8.5);
        let edge = |m: &Mesh, max: bool| {
            let xs = m.positions.iter().map(|p| p[0]);
            if max {
                xs.fold(f32::MIN, f32::max)
            } else {
                xs.fold(f32::MAX, f32::min)
            }
        };
        let (sa, sb) = (
            simplify(&a, 1.0, [0.5, 0.0, 0.0]),
            simplify(&b, 1.0, [4.5, 0.0, 0.0]),
        );
        assert_eq!((edge(&sa, true), edge(&sb, false)), (4.5, 4.5));
        // From the world's origin the seam opens a cell wide.
        let (sa, sb) = (simplify(&a, 1.0, [0.0; 3]), simplify(&b, 1.0, [0.0; 3]));
        assert_eq!((edge(&sa, true), edge(&sb, false)), (4.0, 5.0));
    }
}
