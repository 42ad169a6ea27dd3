//! Rays against a triangle mesh: a bounding volume hierarchy built once over a world's collision
//! surface, then cast into by LiDAR models, line-of-sight checks and clearance queries.
//!
//! Why a hierarchy of our own, not a crate or Embree: the measured need is about 10 M rays a
//! second on two cores against worlds of 0.2 to 1.4 M triangles (an OS1-32 scan is 32,768 rays,
//! ten scans a second). A binary tree built by the binned surface area heuristic and collapsed
//! into a four-wide one (four child boxes tested at once, nearest first) does that in a few
//! hundred lines, builds in about a second on the largest preset, and brings no dependency into
//! `core`; the numbers and the alternatives measured are in `docs/src/sensors.md`.
//!
//! Two properties matter more than speed:
//! - **Watertight**: a ray from inside a closed surface always hits it. Rays are tested with
//!   the watertight algorithm of Woop, Benthin and Wald (JCGT 2013): vertices are moved into a
//!   frame where the ray runs along an axis, and the three edge functions of two triangles that
//!   share an edge are computed from the same numbers with opposite signs, so a ray through the
//!   edge is inside one of them; edge functions that come out exactly zero are computed again
//!   in `f64`, where the products of `f32` coordinates are exact. Box tests widen the far
//!   distance by `1 + 2 gamma(3)` (Ize, "Robust BVH ray traversal", JCGT 2013) so rounding
//!   cannot cull a box the ray enters.
//! - **Deterministic**: the hierarchy is built by one thread in a fixed order and each ray is
//!   traced alone, so results do not depend on the thread count ([`RayCaster::cast_all`] uses
//!   rayon over independent rays).
//!
//! Triangles are hit from either side; [`Hit::normal`] is the triangle's normal as wound
//! (counter-clockwise seen from the passage, so it points into the passage).

mod build;
mod frustum;
mod morton;
mod ray;

use rayon::prelude::*;

use crate::mesh::Mesh;
pub use frustum::Plane;
pub use ray::closest_on_triangle;
use ray::{Prepared, box_distance2};

/// Triangles a leaf holds at most (more only where the heuristic finds no cheaper split, up to
/// four times this).
const LEAF_SIZE: usize = 4;
/// `1 + 2 gamma(3)` with `gamma(n) = n u / (1 - n u)`, `u = 2^-24`: the far distance of a box
/// test is widened by this factor so a box the ray truly enters is never culled by rounding.
const WIDEN: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);
/// Entries of a traversal stack: up to three per level of a four-wide tree at most
/// ([`build::MEDIAN_DEPTH`] + 32) / 2 deep.
const STACK: usize = 3 * (build::MEDIAN_DEPTH + 32) / 2 + 4;

/// A ray's first hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the direction, metres for a unit direction (in multiples of its length
    /// otherwise).
    pub t: f64,
    /// The triangle's index in the mesh the caster was built from.
    pub triangle: u32,
    /// The triangle's unit normal as wound (pointing into the passage).
    pub normal: [f32; 3],
    /// Where on the triangle: the weights of its second and third vertex (as the mesh lists
    /// them; the first's is `1 - u - v`), for what is interpolated across it (texture
    /// coordinates, vertex normals, colours).
    pub barycentric: [f32; 2],
}

/// A ray: where it starts and where it goes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Start, metres, world frame.
    pub origin: [f64; 3],
    /// Direction (need not be unit: [`Hit::t`] is in multiples of it).
    pub dir: [f64; 3],
}

/// The point of a surface nearest a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nearest {
    /// Distance, metres.
    pub distance: f64,
    /// The point on the surface.
    pub point: [f64; 3],
    /// The triangle's index in the mesh.
    pub triangle: u32,
}

/// A node of the four-wide tree: its children's boxes, axis by axis, and what each child is.
#[derive(Clone, Copy, Debug)]
struct Node4 {
    /// Low corners: `lo[axis][child]`.
    lo: [[f32; 4]; 3],
    /// High corners: `hi[axis][child]`.
    hi: [[f32; 4]; 3],
    /// A node's index (count 0), or a leaf's first triangle.
    child: [u32; 4],
    /// A leaf's triangles; 0 for a node. An empty slot has an empty box (low above high).
    count: [u32; 4],
}

impl Node4 {
    const EMPTY: Node4 = Node4 {
        lo: [[f32::INFINITY; 4]; 3],
        hi: [[f32::NEG_INFINITY; 4]; 3],
        child: [0; 4],
        count: [0; 4],
    };

    fn set(&mut self, slot: usize, b: &impl build::Boxed, child: u32, count: u32) {
        let (lo, hi) = b.corners();
        for k in 0..3 {
            self.lo[k][slot] = lo[k];
            self.hi[k][slot] = hi[k];
        }
        self.child[slot] = child;
        self.count[slot] = count;
    }
}

/// A bounding volume hierarchy over a mesh's triangles, for ray casts and nearest-point
/// queries. Build it once per world ([`RayCaster::new`]) and share it between threads.
#[derive(Clone, Debug)]
pub struct RayCaster {
    nodes: Vec<Node4>,
    /// Each triangle's vertices, in hierarchy order.
    vertices: Vec<[[f32; 3]; 3]>,
    /// Each triangle's index in the mesh, in hierarchy order.
    ids: Vec<u32>,
    /// Each triangle's unit normal as wound, in hierarchy order (worked out once: a hit's
    /// square root and division cost a twentieth of a cast). Empty in a quick hierarchy,
    /// whose few hits work theirs out.
    normals: Vec<[f32; 3]>,
}

/// A traversal stack entry: a child and the distance at which the ray enters its box.
#[derive(Clone, Copy, Default)]
struct Entry {
    child: u32,
    count: u32,
    t: f32,
}

impl RayCaster {
    /// Builds the hierarchy over every triangle of `mesh` (about half a second for the 1.2 M
    /// collision triangles of the lava-tube preset, on two cores; the same hierarchy on any
    /// number of threads).
    pub fn new(mesh: &Mesh) -> RayCaster {
        Self::from_tree(mesh, build::tree(mesh))
    }

    /// Builds a hierarchy over every triangle of `mesh` in the order of a Morton curve, split
    /// by the bits of its keys rather than by the surface area heuristic: built in linear
    /// time after one radix sort, in a sixth of the heuristic's time (26 against 165 ms over
    /// the mine preset's collision surface on a quiet machine, `cargo bench --bench raycast
    /// -- raycast-build`; the earlier tree split in halves took 79), slower to cast into, for
    /// a few rays per thousand triangles (a mine's bolt plates on its visual surface). The same
    /// hits as [`RayCaster::new`]'s, except at an edge two triangles share, where either may be
    /// the one reported (their distances differ in the last bits).
    pub fn quick(mesh: &Mesh) -> RayCaster {
        morton::quick(mesh)
    }

    fn from_tree(mesh: &Mesh, (nodes, ids): (Vec<Node4>, Vec<u32>)) -> RayCaster {
        let vertices = ids
            .par_iter()
            .map(|&i| mesh.triangles[i as usize].map(|v| mesh.positions[v as usize]))
            .collect::<Vec<_>>();
        let normals = vertices.par_iter().map(normal).collect();
        RayCaster {
            nodes,
            vertices,
            ids,
            normals,
        }
    }

    /// Triangles in the hierarchy.
    pub fn triangle_count(&self) -> usize {
        self.ids.len()
    }

    /// Bytes the hierarchy holds (its nodes, its copy of the vertices, the triangle ids).
    pub fn bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node4>()
            + self.vertices.len() * std::mem::size_of::<[[f32; 3]; 3]>()
            + self.ids.len() * 4
            + self.normals.len() * 12
    }

    /// The first triangle the ray from `origin` along `dir` meets within `max` (in multiples of
    /// `dir`), or `None`.
    pub fn cast(&self, origin: [f64; 3], dir: [f64; 3], max: f64) -> Option<Hit> {
        self.cast_in(origin, dir, max, &mut [Entry::default(); STACK])
    }

    /// [`cast`](Self::cast) with a stack the caller keeps (batches reuse one: zeroing a
    /// fresh one for every ray costs a tenth of a cast).
    ///
    /// On a processor with AVX2 the traversal runs as compiled for it (see [`wide`]): the same
    /// arithmetic, so the same hits to the bit, in less time.
    fn cast_in(
        &self,
        origin: [f64; 3],
        dir: [f64; 3],
        max: f64,
        stack: &mut [Entry; STACK],
    ) -> Option<Hit> {
        #[cfg(target_arch = "x86_64")]
        if wide::available() {
            #[allow(unsafe_code)]
            // SAFETY: `wide::cast` only needs the processor to have AVX2, which `available`
            // has just said it does.
            return unsafe { wide::cast(self, origin, dir, max, stack) };
        }
        self.traverse(origin, dir, max, stack)
    }

    /// The traversal itself, inlined into each build of [`cast_in`](Self::cast_in).
    #[inline(always)]
    fn traverse(
        &self,
        origin: [f64; 3],
        dir: [f64; 3],
        max: f64,
        stack: &mut [Entry; STACK],
    ) -> Option<Hit> {
        if self.nodes.is_empty() || max.is_nan() || max <= 0.0 {
            return None;
        }
        let ray = Prepared::new(origin, dir)?;
        let mut best = max as f32;
        let mut hit = None;
        let mut top = 0usize;
        let mut at = Entry::default();
        loop {
            if at.count == 0 {
                let n = &self.nodes[at.child as usize];
                let t = ray.enters4(n, best);
                {
                    // The children entered, nearest first (an insertion sort of at most four).
                    let mut order = [0usize; 4];
                    let mut k = 0;
                    for i in 0..4 {
                        if t[i] < f32::INFINITY {
                            let mut j = k;
                            while j > 0 && t[order[j - 1]] > t[i] {
                                order[j] = order[j - 1];
                                j -= 1;
                            }
                            order[j] = i;
                            k += 1;
                        }
                    }
                    if k > 0 {
                        for &i in order[1..k].iter().rev() {
                            stack[top] = Entry {
                                child: n.child[i],
                                count: n.count[i],
                                t: t[i],
                            };
                            top += 1;
                        }
                        let i = order[0];
                        at = Entry {
                            child: n.child[i],
                            count: n.count[i],
                            t: t[i],
                        };
                        continue;
                    }
                }
            } else {
                let first = at.child as usize;
                for k in first..first + at.count as usize {
                    if let Some(t) = ray.triangle(&self.vertices[k], best) {
                        best = t;
                        hit = Some(k);
                    }
                }
            }
            // The next child whose box the ray enters before the best hit so far.
            loop {
                if top == 0 {
                    return hit.map(|k| self.hit(k, best, origin, dir));
                }
                top -= 1;
                if stack[top].t <= best {
                    at = stack[top];
                    break;
                }
            }
        }
    }

    fn hit(&self, k: usize, t: f32, origin: [f64; 3], dir: [f64; 3]) -> Hit {
        let t = f64::from(t);
        let p = [0, 1, 2].map(|i| origin[i] + t * dir[i]);
        Hit {
            t,
            triangle: self.ids[k],
            normal: match self.normals.get(k) {
                Some(&n) => n,
                None => normal(&self.vertices[k]),
            },
            barycentric: barycentric(&self.vertices[k], p),
        }
    }

    /// Every ray's first hit within `max`, in order, the rays shared among rayon's threads
    /// (the results do not depend on how many).
    pub fn cast_all(&self, rays: &[Ray], max: f64) -> Vec<Option<Hit>> {
        let mut out = vec![None; rays.len()];
        out.par_chunks_mut(1024)
            .zip(rays.par_chunks(1024))
            .for_each(|(out, rays)| {
                let mut tracer = self.tracer();
                for (o, r) in out.iter_mut().zip(rays) {
                    *o = tracer.cast(r.origin, r.dir, max);
                }
            });
        out
    }

    /// A tracer: [`cast`](Self::cast) for many rays in a row on one thread, reusing its
    /// traversal stack (a fresh one for every ray costs a tenth of a cast).
    pub fn tracer(&self) -> Tracer<'_> {
        Tracer {
            caster: self,
            stack: Box::new([Entry::default(); STACK]),
        }
    }

    /// The point of the surface nearest `p` within `max` metres, or `None` when there is none
    /// that close.
    pub fn nearest(&self, p: [f64; 3], max: f64) -> Option<Nearest> {
        if self.nodes.is_empty() {
            return None;
        }
        let mut best2 = max * max;
        let mut found: Option<(usize, [f64; 3])> = None;
        let mut stack = [Entry::default(); STACK];
        let mut top = 1usize;
        while top > 0 {
            top -= 1;
            let at = stack[top];
            if f64::from(at.t) > best2 {
                continue;
            }
            if at.count > 0 {
                let first = at.child as usize;
                for k in first..first + at.count as usize {
                    let tri = self.vertices[k].map(|v| v.map(f64::from));
                    let q = closest_on_triangle(p, tri);
                    let d = crate::vec3::sub(q, p);
                    let d2 = crate::vec3::dot(d, d);
                    if d2 <= best2 {
                        best2 = d2;
                        found = Some((k, q));
                    }
                }
                continue;
            }
            let n = &self.nodes[at.child as usize];
            let d2 = box_distance2(n, p);
            // Farthest pushed first, so the nearest is visited next.
            let mut order = [0usize, 1, 2, 3];
            order.sort_by(|&a, &b| d2[b].total_cmp(&d2[a]));
            for i in order {
                // An empty slot is child 0 with count 0 (no node points at the root).
                let empty = n.child[i] == 0 && n.count[i] == 0;
                if !empty && d2[i] <= best2 {
                    stack[top] = Entry {
                        child: n.child[i],
                        count: n.count[i],
                        // Rounded down, so the f32 never prunes a box the f64 would visit.
                        t: next_down(d2[i] as f32),
                    };
                    top += 1;
                }
            }
        }
        found.map(|(k, point)| Nearest {
            distance: best2.sqrt(),
            point,
            triangle: self.ids[k],
        })
    }
}

/// The traversal compiled for AVX2 and chosen at run time, for builds made without the
/// workspace's `.cargo/config.toml` (which builds everything for x86-64-v3, AVX2 included, so
/// the check below is settled when compiling): a `RUSTFLAGS` of one's own replaces that
/// file's flags, and the ray cast, the half of `sense`'s time, should not lose its speed then.
///
/// Why AVX2: the baseline x86-64 build (SSE2) spends instructions moving operands (two-operand
/// encodings) and blending that AVX2's three-operand forms do without; on the development
/// machine the cast took about a fifth less CPU built this way (`perf record` on `sense`, 1,200
/// cave scans). Rust never fuses a multiply and an add on its own (LLVM is not given leave to
/// contract), so no result changes: the sequences written are the same to the byte with
/// either build.
#[cfg(target_arch = "x86_64")]
mod wide {
    use super::{Entry, Hit, RayCaster, STACK};

    /// Whether this processor has AVX2 (the standard library detects it once and caches it;
    /// a constant where the build enables AVX2).
    #[inline]
    pub(super) fn available() -> bool {
        std::is_x86_feature_detected!("avx2")
    }

    /// [`RayCaster::traverse`] compiled with AVX2.
    ///
    /// # Safety
    ///
    /// The processor must have AVX2 ([`available`]).
    #[target_feature(enable = "avx2")]
    #[allow(unsafe_code)]
    pub(super) unsafe fn cast(
        caster: &RayCaster,
        origin: [f64; 3],
        dir: [f64; 3],
        max: f64,
        stack: &mut [Entry; STACK],
    ) -> Option<Hit> {
        caster.traverse(origin, dir, max, stack)
    }
}

/// Casts rays one after another with one traversal stack: see [`RayCaster::tracer`].
pub struct Tracer<'a> {
    caster: &'a RayCaster,
    stack: Box<[Entry; STACK]>,
}

impl Tracer<'_> {
    /// The first triangle the ray meets within `max`, as [`RayCaster::cast`] finds it.
    pub fn cast(&mut self, origin: [f64; 3], dir: [f64; 3], max: f64) -> Option<Hit> {
        self.caster.cast_in(origin, dir, max, &mut self.stack)
    }
}

/// A triangle's unit normal as wound (up for a degenerate one), worked out in `f64`.
fn normal(v: &[[f32; 3]; 3]) -> [f32; 3] {
    let [a, b, c] = v.map(|p| p.map(f64::from));
    let n = crate::vec3::cross(crate::vec3::sub(b, a), crate::vec3::sub(c, a));
    let normal = crate::vec3::unit(n).unwrap_or([0.0, 0.0, 1.0]);
    normal.map(|x| x as f32)
}

/// The weights of `v`'s second and third vertex at `p` (projected onto its plane), clamped to
/// the triangle: one square root-free solve in `f64`, once per hit.
fn barycentric(v: &[[f32; 3]; 3], p: [f64; 3]) -> [f32; 2] {
    use crate::vec3::{dot, sub};
    let [a, b, c] = v.map(|q| q.map(f64::from));
    let (e1, e2, d) = (sub(b, a), sub(c, a), sub(p, a));
    let (d11, d12, d22) = (dot(e1, e1), dot(e1, e2), dot(e2, e2));
    let (p1, p2) = (dot(d, e1), dot(d, e2));
    let det = d11 * d22 - d12 * d12;
    if det <= 0.0 {
        return [0.0; 2];
    }
    let u = ((d22 * p1 - d12 * p2) / det).clamp(0.0, 1.0);
    let w = ((d11 * p2 - d12 * p1) / det).clamp(0.0, 1.0 - u);
    [u as f32, w as f32]
}

/// The largest `f32` below `x` (for positive, finite `x`; 0 stays 0).
fn next_down(x: f32) -> f32 {
    if x > 0.0 && x.is_finite() {
        f32::from_bits(x.to_bits() - 1)
    } else {
        x
    }
}

#[cfg(test)]
mod tests;
