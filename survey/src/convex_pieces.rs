//! Convex pieces of a world's collision surface, for simulators that collide every mesh as its
//! convex hull (MuJoCo always, PyBullet for moving bodies).
//!
//! A cave exported as one mesh is, to such a simulator, a solid block: the robot spawns inside
//! rock and is pushed out. Generic convex decomposition (V-HACD, CoACD) splits a *volume*; our
//! collision surface encloses the passage, and what must be solid is the rock around it, which
//! has no outer boundary. So the pieces are grown on the surface instead:
//!
//! 1. Adjacent triangles are gathered into near-planar **patches**: each triangle's normal is
//!    within about 45 degrees of the patch plane's, every vertex lies within `tolerance`
//!    metres of the plane and within [`MAX_EXTENT`] metres of the seed triangle. The patch
//!    stays a disc (a triangle closing a ring around an opening is refused), covers at least
//!    [`MIN_FILL`] of its own convex hull in the plane and leaves at most [`MAX_GAP`] of it
//!    uncovered, so a slab never bridges an opening such as a shaft or a side passage. The
//!    plane is the seed triangle's, then refitted to the first patch and grown again.
//! 2. Each patch becomes a thin **slab**: the patch's outline (the vertices of its hull in
//!    the plane, at their own heights), plus the same outline pushed `thickness` metres into
//!    the rock (against the normal, which points into the passage). The slab's hull rises at
//!    most `tolerance` above the plane, so at most twice that above the real surface (in a
//!    dip of a rough floor), and otherwise lies in rock: the passage stays hollow.
//!
//! The number of pieces follows the surface's roughness at the scale of `tolerance`: on the
//! cave preset's walls, most candidate triangles are refused for leaving the band, not for
//! the other limits, so a coarser `tolerance` is the one knob that makes fewer pieces.
//!
//! Every triangle belongs to exactly one patch, so the slabs cover the whole surface (but for
//! slivers narrower than [`MIN_WIDTH`], which have no volume to collide with). The
//! result depends only on the mesh (triangles are visited in order), not on thread count.

use std::collections::VecDeque;

use subtgraph_core::mesh::Mesh;
use subtgraph_core::vec3::{V3, cross, dot, sub, unit};

/// How far a patch may spread from its seed triangle, in metres: keeps slabs small enough that
/// a simulator's broad phase culls them well, and bounds the hull checks.
pub const MAX_EXTENT: f64 = 4.0;

/// The least fraction of its in-plane convex hull a patch must cover (an L-shaped patch, whose
/// hull would cover the inside of a bend, is about 0.75).
pub const MIN_FILL: f64 = 0.85;

/// The most area (m²) of its in-plane hull a patch may leave uncovered: far smaller than any
/// opening a robot could pass, a jagged outline of marching-cubes triangles well within it.
pub const MAX_GAP: f64 = 0.25;

/// Patches narrower than this (m, area over length) get no slab.
pub const MIN_WIDTH: f64 = 0.01;

/// At most this many triangles per patch.
const MAX_TRIANGLES: usize = 96;

/// Cosine of the largest angle between a triangle's normal and its patch's.
const MIN_COS: f64 = 0.7;

/// How to cut the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PieceSettings {
    /// How far (m) a patch's vertices may stray from its plane: a slab stands at most this
    /// above the plane, at most twice this above the real surface.
    pub tolerance: f64,
    /// How deep (m) each slab reaches into the rock.
    pub thickness: f64,
}

impl Default for PieceSettings {
    /// 10 cm (cave walls are rough at that scale: a finer tolerance multiplies the pieces) and 0.5 m (far thicker than a time step's
    /// travel, far thinner than the rock between two passages of any preset).
    fn default() -> Self {
        PieceSettings {
            tolerance: 0.1,
            thickness: 0.5,
        }
    }
}

/// One convex piece: a patch of the surface and its slab.
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    /// The mesh triangles of the patch.
    pub triangles: Vec<u32>,
    /// A point on the patch plane (the seed triangle's centroid).
    pub origin: [f64; 3],
    /// The plane's unit normal, pointing into the passage.
    pub normal: [f64; 3],
    /// How many of `points` are on the surface (the patch's outline); as many follow,
    /// `thickness` below the plane. 0 for a sliver narrower than [`MIN_WIDTH`], which gets
    /// no slab.
    pub surface: usize,
    /// The slab's corners: the patch's outline on the surface, then the same outline pushed
    /// into the rock. A simulator takes their convex hull.
    pub points: Vec<[f32; 3]>,
}

/// Triangles sharing an edge with each triangle (compressed rows).
struct Neighbours {
    start: Vec<u32>,
    list: Vec<u32>,
}

impl Neighbours {
    fn new(mesh: &Mesh) -> Neighbours {
        let mut edges: Vec<(u32, u32, u32)> = Vec::with_capacity(mesh.triangles.len() * 3);
        for (i, t) in mesh.triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                edges.push((a.min(b), a.max(b), i as u32));
            }
        }
        edges.sort_unstable();
        let mut pairs: Vec<(u32, u32)> = Vec::with_capacity(edges.len() * 2);
        let mut i = 0;
        while i < edges.len() {
            let mut j = i;
            while j < edges.len() && edges[j].0 == edges[i].0 && edges[j].1 == edges[i].1 {
                j += 1;
            }
            for a in i..j {
                for b in i..j {
                    if a != b {
                        pairs.push((edges[a].2, edges[b].2));
                    }
                }
            }
            i = j;
        }
        pairs.sort_unstable();
        pairs.dedup();
        let mut start = vec![0u32; mesh.triangles.len() + 1];
        for &(a, _) in &pairs {
            start[a as usize + 1] += 1;
        }
        for k in 1..start.len() {
            start[k] += start[k - 1];
        }
        Neighbours {
            start,
            list: pairs.into_iter().map(|p| p.1).collect(),
        }
    }

    fn of(&self, t: u32) -> &[u32] {
        &self.list[self.start[t as usize] as usize..self.start[t as usize + 1] as usize]
    }
}

/// The convex hull of 2D points (Andrew's monotone chain), as indices in counter-clockwise
/// order, and twice its area.
fn hull(points: &[[f64; 2]]) -> (Vec<usize>, f64) {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| {
        let (a, b) = (points[a], points[b]);
        a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1]))
    });
    let turn = |o: usize, a: usize, b: usize| {
        let (o, a, b) = (points[o], points[a], points[b]);
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut h: Vec<usize> = Vec::with_capacity(points.len() * 2);
    for pass in 0..2 {
        let floor = h.len();
        for k in 0..order.len() {
            let p = order[if pass == 0 { k } else { order.len() - 1 - k }];
            while h.len() >= floor + 2 && turn(h[h.len() - 2], h[h.len() - 1], p) <= 0.0 {
                h.pop();
            }
            h.push(p);
        }
        h.pop();
    }
    let n = h.len();
    let area2 = (0..n)
        .map(|i| {
            let (a, b) = (points[h[i]], points[h[(i + 1) % n]]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f64>()
        .abs();
    (h, area2)
}

/// A plane with an in-plane basis.
#[derive(Clone, Copy)]
struct Plane {
    origin: V3,
    normal: V3,
    u: V3,
    w: V3,
}

impl Plane {
    fn new(origin: V3, normal: V3) -> Plane {
        let helper = if normal[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let u = unit(cross(normal, helper)).unwrap_or([1.0, 0.0, 0.0]);
        Plane {
            origin,
            normal,
            u,
            w: cross(normal, u),
        }
    }

    fn flat(&self, p: V3) -> [f64; 2] {
        let d = sub(p, self.origin);
        [dot(d, self.u), dot(d, self.w)]
    }
}

/// What growing works on: the mesh, its triangle normals and adjacency, and who owns what.
struct Surface<'a> {
    mesh: &'a Mesh,
    normals: Vec<Option<V3>>,
    neighbours: Neighbours,
    owner: Vec<u32>,
    tolerance: f64,
}

impl Surface<'_> {
    fn pos(&self, v: u32) -> V3 {
        self.mesh.positions[v as usize].map(f64::from)
    }

    /// Grows a patch from `seed` within `plane`: its triangles and vertices. Claims nothing.
    fn grow(&self, seed: u32, plane: &Plane) -> (Vec<u32>, Vec<u32>) {
        let mesh = self.mesh;
        let fits = |t: u32| {
            self.normals[t as usize].is_none_or(|n| dot(n, plane.normal) >= MIN_COS)
                && mesh.triangles[t as usize].iter().all(|&v| {
                    let d = sub(self.pos(v), plane.origin);
                    let h = dot(d, plane.normal);
                    h.abs() <= self.tolerance && dot(d, d) - h * h <= MAX_EXTENT * MAX_EXTENT
                })
        };
        let area2_of = |t: u32| {
            let [a, b, c] = mesh.triangles[t as usize].map(|v| plane.flat(self.pos(v)));
            ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs()
        };
        let edge = |a: u32, b: u32| (a.min(b), a.max(b));
        let tri = mesh.triangles[seed as usize];
        let mut members = vec![seed];
        let mut vertices: Vec<u32> = tri.to_vec();
        let mut edges: Vec<(u32, u32)> = (0..3).map(|k| edge(tri[k], tri[(k + 1) % 3])).collect();
        let mut area2 = area2_of(seed);
        let mut queue: VecDeque<u32> = self.neighbours.of(seed).iter().copied().collect();
        let mut flat: Vec<[f64; 2]> = Vec::new();
        while let Some(t) = queue.pop_front() {
            if members.len() >= MAX_TRIANGLES {
                break;
            }
            if self.owner[t as usize] != u32::MAX || members.contains(&t) || !fits(t) {
                continue;
            }
            let t3 = mesh.triangles[t as usize];
            let fresh: Vec<u32> = t3
                .iter()
                .copied()
                .filter(|v| !vertices.contains(v))
                .collect();
            // The patch stays a disc (vertices - edges + faces = 1): a triangle that would
            // close a ring around an opening is left for another patch.
            let new_edges: Vec<(u32, u32)> = (0..3)
                .map(|k| edge(t3[k], t3[(k + 1) % 3]))
                .filter(|e| !edges.contains(e))
                .collect();
            if fresh.len() + 1 != new_edges.len() {
                continue;
            }
            let area = area2 + area2_of(t);
            if !fresh.is_empty() {
                flat.clear();
                flat.extend(
                    vertices
                        .iter()
                        .chain(&fresh)
                        .map(|&v| plane.flat(self.pos(v))),
                );
                let hull_area2 = hull(&flat).1;
                if area < MIN_FILL * hull_area2 || hull_area2 - area > 2.0 * MAX_GAP {
                    continue;
                }
            }
            members.push(t);
            vertices.extend(fresh);
            edges.extend(new_edges);
            area2 = area;
            queue.extend(
                self.neighbours
                    .of(t)
                    .iter()
                    .filter(|&&n| self.owner[n as usize] == u32::MAX),
            );
        }
        (members, vertices)
    }
}

/// Cuts a closed collision surface into convex slabs that keep the passage hollow.
pub fn convex_pieces(mesh: &Mesh, settings: &PieceSettings) -> Vec<Piece> {
    let mut s = Surface {
        mesh,
        normals: mesh
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| mesh.positions[v as usize].map(f64::from));
                unit(cross(sub(b, a), sub(c, a)))
            })
            .collect(),
        neighbours: Neighbours::new(mesh),
        owner: vec![u32::MAX; mesh.triangles.len()],
        tolerance: settings.tolerance,
    };
    let mut pieces = Vec::new();
    for seed in 0..mesh.triangles.len() as u32 {
        if s.owner[seed as usize] != u32::MAX {
            continue;
        }
        let tri = mesh.triangles[seed as usize];
        let corners = tri.map(|v| s.pos(v));
        let origin = [0, 1, 2].map(|k| (corners[0][k] + corners[1][k] + corners[2][k]) / 3.0);
        let normal = s.normals[seed as usize]
            .or_else(|| {
                let n = tri
                    .iter()
                    .filter_map(|&v| mesh.normals.get(v as usize))
                    .fold([0.0; 3], |s, n| [0, 1, 2].map(|k| s[k] + f64::from(n[k])));
                unit(n)
            })
            .unwrap_or([0.0, 0.0, 1.0]);
        let mut plane = Plane::new(origin, normal);
        let (mut members, mut vertices) = s.grow(seed, &plane);
        // The seed is usually at the patch's edge (its neighbours were taken), where its
        // tangent plane soon leaves a curved wall. Refit the plane to the patch (area-weighted
        // normal and centroid) and grow again: on a tunnel wall this about doubles the width.
        let mut weighted = ([0.0; 3], [0.0; 3], 0.0);
        for &t in &members {
            let [a, b, c] = mesh.triangles[t as usize].map(|v| s.pos(v));
            let n = cross(sub(b, a), sub(c, a));
            let area = dot(n, n).sqrt();
            for k in 0..3 {
                weighted.0[k] += n[k];
                weighted.1[k] += area * (a[k] + b[k] + c[k]) / 3.0;
            }
            weighted.2 += area;
        }
        if let Some(n) = unit(weighted.0).filter(|_| weighted.2 > 0.0) {
            let fitted = Plane::new(weighted.1.map(|c| c / weighted.2), n);
            let again = s.grow(seed, &fitted);
            if again.0.len() > members.len() {
                (members, vertices) = again;
                plane = fitted;
            }
        }
        let id = pieces.len() as u32;
        for &t in &members {
            s.owner[t as usize] = id;
        }
        // The slab's corners: the patch's outline in the plane, at the vertices' own heights
        // (interior vertices lie under the hull of these, within the band), and the same
        // outline `thickness` below the plane, in the rock.
        let flat: Vec<[f64; 2]> = vertices.iter().map(|&v| plane.flat(s.pos(v))).collect();
        let (mut outline, area2) = hull(&flat);
        let [lo, hi] = outline
            .iter()
            .fold([[f64::MAX; 2], [f64::MIN; 2]], |[lo, hi], &i| {
                let [x, y] = flat[i];
                [[lo[0].min(x), lo[1].min(y)], [hi[0].max(x), hi[1].max(y)]]
            });
        let length = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
        if outline.len() < 3 || area2 / 2.0 < MIN_WIDTH * length {
            // A sliver (degenerate triangles of a user's mesh): a hull of it would have no
            // volume, which simulators refuse, and it holds nothing up.
            outline.clear();
        }
        let mut points: Vec<[f32; 3]> = outline
            .iter()
            .map(|&i| mesh.positions[vertices[i] as usize])
            .collect();
        points.extend(outline.iter().map(|&i| {
            let [x, y] = flat[i];
            [0, 1, 2].map(|k| {
                (plane.origin[k] + x * plane.u[k] + y * plane.w[k]
                    - settings.thickness * plane.normal[k]) as f32
            })
        }));
        pieces.push(Piece {
            triangles: members,
            origin: plane.origin,
            normal: plane.normal,
            surface: outline.len(),
            points,
        });
    }
    pieces
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed box-shaped tunnel, `n` x `n` quads per face, normals pointing inwards.
    fn box_tunnel(size: [f32; 3], n: u32) -> Mesh {
        let mut m = Mesh::default();
        // Each face: origin corner and two edge vectors; the cross product points out of the box,
        // so the triangles are wound the other way (CCW seen from inside).
        let [x, y, z] = size;
        let faces: [([f32; 3], [f32; 3], [f32; 3]); 6] = [
            ([0., 0., 0.], [0., y, 0.], [x, 0., 0.]), // floor, normal +z
            ([0., 0., z], [x, 0., 0.], [0., y, 0.]),  // roof, normal -z
            ([0., 0., 0.], [x, 0., 0.], [0., 0., z]), // south wall, +y
            ([0., y, 0.], [0., 0., z], [x, 0., 0.]),  // north wall, -y
            ([0., 0., 0.], [0., 0., z], [0., y, 0.]), // west wall, +x
            ([x, 0., 0.], [0., y, 0.], [0., 0., z]),  // east wall, -x
        ];
        for (o, a, b) in faces {
            let base = m.positions.len() as u32;
            for i in 0..=n {
                for j in 0..=n {
                    let (s, t) = (i as f32 / n as f32, j as f32 / n as f32);
                    m.positions
                        .push([0, 1, 2].map(|k| o[k] + a[k] * s + b[k] * t));
                }
            }
            let at = |i: u32, j: u32| base + i * (n + 1) + j;
            for i in 0..n {
                for j in 0..n {
                    m.triangles.push([at(i, j), at(i + 1, j + 1), at(i + 1, j)]);
                    m.triangles.push([at(i, j), at(i, j + 1), at(i + 1, j + 1)]);
                }
            }
        }
        m.weld();
        m
    }

    #[test]
    fn slabs_cover_a_box_tunnel_once_and_stay_in_the_rock() {
        let size = [12.0f32, 3.0, 2.5];
        let mesh = box_tunnel(size, 6);
        assert!(mesh.edge_report().is_closed());
        let s = PieceSettings::default();
        let pieces = convex_pieces(&mesh, &s);
        let mut seen = vec![0; mesh.triangles.len()];
        for p in &pieces {
            for &t in &p.triangles {
                seen[t as usize] += 1;
            }
        }
        assert!(
            seen.iter().all(|&c| c == 1),
            "every triangle in exactly one patch"
        );
        // A box's faces are flat: patches follow them, bounded by their extent.
        assert!(
            pieces.len() >= 6 && pieces.len() < mesh.triangles.len() / 4,
            "{}",
            pieces.len()
        );
        let inside =
            |p: [f32; 3], margin: f32| (0..3).all(|k| p[k] > margin && p[k] < size[k] - margin);
        for p in &pieces {
            // The patch's vertices, then its outline `thickness` below the plane, in the rock.
            assert!(p.surface >= 3 && p.points.len() == 2 * p.surface);
            for (k, q) in p.points.iter().enumerate() {
                let h = dot(sub(q.map(f64::from), p.origin), p.normal);
                if k >= p.surface {
                    assert!((h + s.thickness).abs() < 1e-4, "{h}");
                }
                assert!(!inside(*q, s.tolerance as f32));
            }
            // The slab lies behind its plane (offset by the tolerance), and the passage shrunk
            // by twice the tolerance lies wholly in front of it: the hull cannot intrude.
            for q in &p.points {
                let h = dot(sub(q.map(f64::from), p.origin), p.normal);
                assert!(h <= s.tolerance + 1e-6, "slab point {h} m into the passage");
            }
            let m = 2.0 * s.tolerance + 1e-3;
            for corner in 0..8 {
                let c: V3 = [0, 1, 2].map(|k| {
                    if corner >> k & 1 == 1 {
                        f64::from(size[k]) - m
                    } else {
                        m
                    }
                });
                assert!(dot(sub(c, p.origin), p.normal) > s.tolerance);
            }
        }
    }

    #[test]
    fn a_patch_does_not_close_an_opening() {
        // A flat floor, 5 x 5 quads of 0.5 m, with the middle quad cut out (a shaft).
        let mut m = Mesh::default();
        for i in 0..=5 {
            for j in 0..=5 {
                m.positions.push([i as f32 * 0.5, j as f32 * 0.5, 0.0]);
            }
        }
        for i in 0..5u32 {
            for j in 0..5u32 {
                if (i, j) == (2, 2) {
                    continue;
                }
                let at = |i: u32, j: u32| i * 6 + j;
                m.triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                m.triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        let pieces = convex_pieces(&m, &PieceSettings::default());
        assert!(pieces.len() > 1, "one convex slab would cover the opening");
        let hole = [1.25f64, 1.25];
        for p in &pieces {
            // The opening's centre is outside every slab's footprint.
            let mut pts: Vec<[f64; 2]> = p
                .points
                .iter()
                .map(|q| [f64::from(q[0]), f64::from(q[1])])
                .collect();
            let a = hull(&pts).1;
            pts.push(hole);
            assert!(hull(&pts).1 > a + 1e-9, "a slab covers the opening");
        }
    }
}
