//! Simplifying a closed surface within a bound: the lighter copy of a surface that physics
//! collides with, no farther from the original than each of its vertices allows.
//!
//! Edges are collapsed one end onto the other (a *half-edge* collapse: the kept vertex does not
//! move, so every vertex of the result is a vertex of the original, exactly), cheapest first by
//! Garland and Heckbert's quadric error (SIGGRAPH 1997: the squared distances to the planes of
//! the original triangles merged into a vertex, weighted by their areas). What makes the result
//! a *bounded* copy is a check on every collapse, after Klein, Liebich and Strasser's
//! Hausdorff-bounded simplification (1996) and Cohen et al.'s simplification envelopes: each
//! original vertex removed is kept with the triangle of the simplified surface nearest it, and
//! a collapse is taken only if every such vertex of the triangles it changes stays within its
//! own tolerance of the triangles it makes (and on a triangle facing the same side it faced:
//! a collapse cannot fold the surface across a thin wall). Collapses that would break the
//! surface are refused too: the link condition (Dey et al., 1999) keeps it a 2-manifold, so a
//! closed surface stays closed, and no triangle may turn over.
//!
//! Locked vertices (a tile's seam: its vertices on the block's faces) never go, and the edges
//! between them stay, so two pieces simplified apart still weld vertex for vertex. The work is
//! serial and its order fixed (ties broken by vertex indices), so the result does not depend
//! on the thread count.

use subtgraph_core::mesh::Mesh;
use subtgraph_core::raycast::closest_on_triangle;
use subtgraph_core::vec3::{V3, unit};

/// The surface a [`simplify`] made: its mesh, and where each original vertex went.
#[derive(Clone, Debug, Default)]
pub struct Simplified {
    /// The simplified surface: the original's kept vertices in their order, its remaining
    /// triangles in their order (with their materials), no normals or texture coordinates.
    pub mesh: Mesh,
    /// For every vertex of the original, its index in [`mesh`](Self::mesh), or `u32::MAX`
    /// when it was removed (never for a locked one).
    pub kept: Vec<u32>,
}

/// Simplifies `mesh` (a 2-manifold, closed or open along locked vertices) so that every one of
/// its vertices stays within `tolerance[v]` metres of the result, keeping the vertices
/// `locked` (and every vertex on an open edge). A tolerance of 0 keeps a vertex where it is.
pub fn simplify(mesh: &Mesh, locked: &[u32], tolerance: &[f32]) -> Simplified {
    if mesh.positions.len() as u64 > INDEX_MASK {
        // Beyond what a pass's sort key holds (16 M vertices, far more than a tile has): the
        // surface as it is, which is within any tolerance.
        let tolerance = vec![0.0; mesh.positions.len()];
        return Simplifier::new(mesh, locked, &tolerance).finish(mesh);
    }
    let mut s = Simplifier::new(mesh, locked, tolerance);
    s.run();
    s.finish(mesh)
}

/// A symmetric 4 x 4 quadric `[a², ab, ac, ad, b², bc, bd, c², cd, d²]` of planes
/// `ax + by + cz + d = 0`: the sum of squared distances to them.
#[derive(Clone, Copy, Default)]
struct Quadric([f64; 10]);

impl Quadric {
    fn plane(n: V3, d: f64, weight: f64) -> Quadric {
        let [a, b, c] = n;
        Quadric(
            [
                a * a,
                a * b,
                a * c,
                a * d,
                b * b,
                b * c,
                b * d,
                c * c,
                c * d,
                d * d,
            ]
            .map(|x| x * weight),
        )
    }

    fn add(&mut self, o: &Quadric) {
        for (a, b) in self.0.iter_mut().zip(o.0) {
            *a += b;
        }
    }

    fn at(&self, p: V3, other: &Quadric) -> f64 {
        let q: [f64; 10] = std::array::from_fn(|i| self.0[i] + other.0[i]);
        let [x, y, z] = p;
        let e = q[0] * x * x
            + 2.0 * q[1] * x * y
            + 2.0 * q[2] * x * z
            + 2.0 * q[3] * x
            + q[4] * y * y
            + 2.0 * q[5] * y * z
            + 2.0 * q[6] * y
            + q[7] * z * z
            + 2.0 * q[8] * z
            + q[9];
        e.max(0.0)
    }
}

/// Bits of a pass's sort key that hold the vertex (so at most 2^24 vertices a call).
const INDEX_BITS: u32 = 24;
const INDEX_MASK: u64 = (1 << INDEX_BITS) - 1;
/// No vertex: the end of a list.
const NONE: u32 = u32::MAX;
/// How many of a vertex's cheapest collapses a pass tries before it leaves the vertex be.
const TRIES: usize = 2;
/// Below this a new triangle's doubled area counts as none, square metres.
const DEGENERATE: f64 = 1e-10;
/// The least cosine between a changed triangle's normal and its normal before: a collapse
/// turning a triangle further than this (about 78 degrees) is refused.
const TURN: f64 = 0.2;

struct Simplifier {
    pos: Vec<V3>,
    tris: Vec<[u32; 3]>,
    alive: Vec<bool>,
    /// Each vertex's living triangles.
    fans: Vec<Vec<u32>>,
    quadric: Vec<Quadric>,
    locked: Vec<bool>,
    removed: Vec<bool>,
    /// Bumped whenever a vertex's neighbourhood changes.
    version: Vec<u32>,
    /// The version at which a vertex was last found to have no allowed collapse.
    stuck: Vec<u32>,
    /// Each triangle's original vertices that are gone, kept with it: the first, then each
    /// one's next in `next` (a list threaded through the vertices: no allocation a triangle).
    first: Vec<u32>,
    next: Vec<u32>,
    /// Each original vertex's unit normal (area weighted, as wound).
    normal: Vec<V3>,
    tol2: Vec<f64>,
    /// Each vertex's cheapest collapse, cost and target, as last worked out (kept low where a
    /// neighbour's collapse made a cheaper one: stale only in the order it gives the next pass
    /// and in the first target tried).
    best: Vec<(f64, u32)>,
    /// Marks of the vertices around one vertex ([`Simplifier::neighbours`]).
    mark: Vec<u32>,
    stamp: u32,
    // Scratch, reused by every check.
    targets: Vec<(f64, u32)>,
    around: Vec<u32>,
    points: Vec<u32>,
    made: Vec<(u32, [V3; 3], V3)>,
    /// How many of `made` the collapse changes (the rest are v's others).
    changed: usize,
    /// The vertex whose other triangles `made` may still take.
    more: Option<u32>,
    /// The collapse being checked: the vertex that goes.
    going: u32,
    homes: Vec<u32>,
}

impl Simplifier {
    fn new(mesh: &Mesh, locked: &[u32], tolerance: &[f32]) -> Simplifier {
        let n = mesh.positions.len();
        let pos: Vec<V3> = mesh.positions.iter().map(|p| p.map(f64::from)).collect();
        let mut valence = vec![0u32; n];
        for tri in &mesh.triangles {
            for &v in tri {
                valence[v as usize] += 1;
            }
        }
        // Room for a few more: a vertex gains the triangles of those collapsed onto it.
        let mut fans: Vec<Vec<u32>> = valence
            .iter()
            .map(|&k| Vec::with_capacity(k as usize + 4))
            .collect();
        let mut quadric = vec![Quadric::default(); n];
        let mut normal = vec![[0.0; 3]; n];
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let c = tri.map(|v| pos[v as usize]);
            let nn = cross(sub(c[1], c[0]), sub(c[2], c[0]));
            let len = dot(nn, nn).sqrt();
            for &v in tri {
                fans[v as usize].push(t as u32);
                for k in 0..3 {
                    normal[v as usize][k] += nn[k];
                }
            }
            if len > 0.0 {
                let unit = nn.map(|x| x / len);
                let q = Quadric::plane(unit, -dot(unit, c[0]), 0.5 * len);
                for &v in tri {
                    quadric[v as usize].add(&q);
                }
            }
        }
        for nv in &mut normal {
            *nv = unit(*nv).unwrap_or([0.0; 3]);
        }
        let mut is_locked = vec![false; n];
        for &v in locked {
            is_locked[v as usize] = true;
        }
        for v in open_edge_vertices(&mesh.triangles, &fans) {
            is_locked[v as usize] = true;
        }
        let tol2 = (0..n)
            .map(|v| f64::from(tolerance.get(v).copied().unwrap_or(0.0)).powi(2))
            .collect();
        Simplifier {
            pos,
            tris: mesh.triangles.clone(),
            alive: vec![true; mesh.triangles.len()],
            fans,
            quadric,
            locked: is_locked,
            removed: vec![false; n],
            version: vec![0; n],
            stuck: vec![u32::MAX; n],
            first: vec![NONE; mesh.triangles.len()],
            next: vec![NONE; n],
            normal,
            tol2,
            best: vec![(f64::INFINITY, u32::MAX); n],
            mark: vec![0; n],
            stamp: 0,
            targets: Vec::new(),
            around: Vec::new(),
            points: Vec::new(),
            made: Vec::new(),
            changed: 0,
            more: None,
            going: NONE,
            homes: Vec::new(),
        }
    }

    /// The vertices next to `u` into `around`, each once, in the order its triangles list
    /// them; they are left marked with the current `stamp`.
    fn neighbours(&mut self, u: u32) {
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.mark.fill(0);
            self.stamp = 1;
        }
        self.around.clear();
        for &t in &self.fans[u as usize] {
            for w in self.tris[t as usize] {
                if w != u && self.mark[w as usize] != self.stamp {
                    self.mark[w as usize] = self.stamp;
                    self.around.push(w);
                }
            }
        }
    }

    /// The cost of collapsing `u` onto `v`: the quadric error, and among equal errors (a flat
    /// floor) the shorter edge first, for rounder triangles.
    fn cost(&self, u: u32, v: u32) -> f64 {
        let (ui, vi) = (u as usize, v as usize);
        let d = sub(self.pos[ui], self.pos[vi]);
        self.quadric[ui].at(self.pos[vi], &self.quadric[vi]) + 1e-6 * dot(d, d)
    }

    /// Works out `u`'s cheapest collapse from `around` (its neighbours).
    fn cost_best(&mut self, u: u32) {
        let mut least = (f64::INFINITY, u32::MAX);
        for k in 0..self.around.len() {
            let v = self.around[k];
            let c = self.cost(u, v);
            if c < least.0 {
                least = (c, v);
            }
        }
        self.best[u as usize] = least;
    }

    /// Collapses `u` onto the cheapest neighbour the checks allow among its [`TRIES`]
    /// cheapest, if any: `true` when it did.
    fn try_collapse(&mut self, u: u32) -> bool {
        // `neighbours` leaves u's neighbours marked, for the link condition.
        self.neighbours(u);
        let stamp = self.stamp;
        let (_, first) = self.best[u as usize];
        let known = first != u32::MAX && self.mark[first as usize] == stamp;
        if known && self.allowed(u, first, stamp) {
            self.collapse(u, first);
            return true;
        }
        if TRIES == 1 && known {
            return false;
        }
        self.targets.clear();
        for k in 0..self.around.len() {
            let v = self.around[k];
            if !known || v != first {
                self.targets.push((self.cost(u, v), v));
            }
        }
        self.targets
            .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let tries = if known { TRIES - 1 } else { TRIES };
        for k in 0..tries.min(self.targets.len()) {
            let v = self.targets[k].1;
            if self.allowed(u, v, stamp) {
                self.collapse(u, v);
                return true;
            }
        }
        false
    }

    /// Collapses in passes (as meshoptimizer's simplifier does, rather than with a priority
    /// queue kept exact after every collapse, which cost three times as long here): each pass
    /// sorts the vertices that may go by their cheapest collapse as last worked out, then tries
    /// each onto that neighbour and, failing that, onto its next cheapest ([`TRIES`] in all).
    /// A collapse works out the costs around it again, so an order made at the pass's start
    /// is a little stale by the time a vertex is reached; the checks are always made on the
    /// surface as it is then. A vertex with no allowed collapse is not tried again until its
    /// neighbourhood changes. Passes end when one collapses nothing.
    fn run(&mut self) {
        let n = self.pos.len();
        for u in 0..n as u32 {
            self.neighbours(u);
            self.cost_best(u);
        }
        // Keys: the cost's bits above the lowest INDEX_BITS (costs are never negative, so they
        // order as numbers), then the vertex: one integer sort a pass, the same order on any
        // machine.
        let mut order: Vec<u64> = Vec::with_capacity(n);
        loop {
            order.clear();
            for u in 0..n as u32 {
                let ui = u as usize;
                if self.locked[ui]
                    || self.removed[ui]
                    || self.tol2[ui] == 0.0
                    || self.stuck[ui] == self.version[ui]
                {
                    continue;
                }
                let cost = self.best[ui].0;
                if cost.is_finite() {
                    order.push((cost.to_bits() & !INDEX_MASK) | u64::from(u));
                }
            }
            order.sort_unstable();
            let mut collapsed = 0;
            for &key in &order {
                let u = (key & INDEX_MASK) as u32;
                let ui = u as usize;
                if self.removed[ui] {
                    continue;
                }
                if self.try_collapse(u) {
                    collapsed += 1;
                } else {
                    self.stuck[ui] = self.version[ui];
                }
            }
            if collapsed == 0 {
                break;
            }
        }
    }

    /// Whether collapsing `u` onto `v` keeps the surface a 2-manifold, turns no triangle over,
    /// and keeps every removed vertex within its tolerance; on success `made` holds the
    /// changed triangles and `points`/`homes` where each removed vertex goes.
    /// `u`'s neighbours carry the mark `stamp`.
    fn allowed(&mut self, u: u32, v: u32, stamp: u32) -> bool {
        let ui = u as usize;
        let mut shared = [u32::MAX; 2];
        let mut count = 0;
        for &t in &self.fans[ui] {
            if self.tris[t as usize].contains(&v) {
                if count == 2 {
                    return false;
                }
                shared[count] = t;
                count += 1;
            }
        }
        if count != 2 || !self.link_holds(u, v, shared, stamp) {
            return false;
        }
        if self.locked[v as usize] && self.makes_seam_chord(u, v) {
            return false;
        }
        self.made.clear();
        self.going = u;
        for &t in &self.fans[ui] {
            if shared.contains(&t) {
                continue;
            }
            let old = self.corners(self.tris[t as usize]);
            let tri = self.tris[t as usize].map(|w| if w == u { v } else { w });
            let new = self.corners(tri);
            let (n0, n1) = (tri_normal(&old), tri_normal(&new));
            let (l0, l1) = (dot(n0, n0).sqrt(), dot(n1, n1).sqrt());
            if l1 < DEGENERATE || dot(n0, n1) < TURN * l0 * l1 {
                return false;
            }
            self.made.push((t, new, n1.map(|x| x / l1)));
        }
        self.changed = self.made.len();
        self.more = Some(v);
        self.points.clear();
        self.homes.clear();
        if !self.place(u, None) {
            return false;
        }
        for k in 0..self.fans[ui].len() {
            let t = self.fans[ui][k];
            // A changed triangle's vertices try its new shape first.
            let own = self.made[..self.changed].iter().position(|m| m.0 == t);
            let mut p = self.first[t as usize];
            while p != NONE {
                if !self.place(p, own) {
                    return false;
                }
                p = self.next[p as usize];
            }
        }
        true
    }

    /// Whether collapsing `u` onto the locked `v` would join `v` to another locked vertex it
    /// is not joined to yet. Such an edge runs between two seam vertices, and the piece on the
    /// seam's other side may make the very same edge from its side: the welded surface would
    /// then have four triangles on one edge (two sheets touching along it), no longer a
    /// closed 2-manifold.
    fn makes_seam_chord(&self, u: u32, v: u32) -> bool {
        let joined = |a: u32, b: u32| {
            self.fans[a as usize]
                .iter()
                .any(|&t| self.tris[t as usize].contains(&b))
        };
        self.fans[u as usize].iter().any(|&t| {
            self.tris[t as usize]
                .iter()
                .any(|&w| w != u && w != v && self.locked[w as usize] && !joined(v, w))
        })
    }

    /// Adds `v`'s triangles other than the changed ones to `made`: where a removed vertex may
    /// also go (worked out only when one fits none of the changed triangles).
    fn add_more(&mut self) {
        let Some(v) = self.more.take() else {
            return;
        };
        for k in 0..self.fans[v as usize].len() {
            let t = self.fans[v as usize][k];
            let tri = self.tris[t as usize];
            // The two triangles the collapse removes have u; the changed ones are listed.
            if self.made[..self.changed].iter().any(|m| m.0 == t)
                || tri.iter().any(|w| self.removed_now(*w))
            {
                continue;
            }
            let c = self.corners(tri);
            let n = tri_normal(&c);
            let l = dot(n, n).sqrt().max(DEGENERATE);
            self.made.push((t, c, n.map(|x| x / l)));
        }
    }

    /// Finds a triangle of `made` within point `p`'s tolerance, facing its way (`first` tried
    /// first), and notes it in `points`/`homes`; `false` when there is none.
    fn place(&mut self, p: u32, first: Option<usize>) -> bool {
        let (q, facing, tol2) = (
            self.pos[p as usize],
            self.normal[p as usize],
            self.tol2[p as usize],
        );
        let fits = |m: &(u32, [V3; 3], V3)| {
            if dot(m.2, facing) <= 0.0 {
                return false;
            }
            let plane = dot(sub(q, m.1[0]), m.2);
            if plane * plane > tol2 {
                return false;
            }
            let d = sub(closest_on_triangle(q, m.1), q);
            dot(d, d) <= tol2
        };
        let mut home = first.filter(|&i| fits(&self.made[i]));
        if home.is_none() {
            home = self.made.iter().position(fits);
        }
        if home.is_none() && self.more.is_some() {
            let from = self.made.len();
            self.add_more();
            home = self.made[from..].iter().position(fits).map(|i| i + from);
        }
        match home {
            Some(i) => {
                self.points.push(p);
                self.homes.push(self.made[i].0);
                true
            }
            None => false,
        }
    }

    /// The link condition: the vertices next to both `u` and `v` are exactly the two
    /// triangles' third corners.
    fn link_holds(&self, u: u32, v: u32, shared: [u32; 2], stamp: u32) -> bool {
        let third = |t: u32| {
            let tri = self.tris[t as usize];
            tri.into_iter().find(|&w| w != u && w != v).unwrap_or(u)
        };
        let (a, b) = (third(shared[0]), third(shared[1]));
        if a == b {
            return false;
        }
        self.fans[v as usize].iter().all(|&t| {
            self.tris[t as usize]
                .into_iter()
                .all(|w| w == u || w == v || w == a || w == b || self.mark[w as usize] != stamp)
        })
    }

    fn collapse(&mut self, u: u32, v: u32) {
        let (ui, vi) = (u as usize, v as usize);
        let fan = std::mem::take(&mut self.fans[ui]);
        for &t in &fan {
            let ti = t as usize;
            self.first[ti] = NONE;
            if self.tris[ti].contains(&v) {
                self.alive[ti] = false;
                for w in self.tris[ti] {
                    if w != u {
                        let fan = &mut self.fans[w as usize];
                        if let Some(i) = fan.iter().position(|&x| x == t) {
                            fan.swap_remove(i);
                        }
                    }
                }
            } else {
                for w in &mut self.tris[ti] {
                    if *w == u {
                        *w = v;
                    }
                }
                self.fans[vi].push(t);
            }
        }
        for k in 0..self.points.len() {
            let (p, home) = (self.points[k], self.homes[k]);
            self.next[p as usize] = self.first[home as usize];
            self.first[home as usize] = p;
        }
        self.removed[ui] = true;
        let q = self.quadric[ui];
        self.quadric[vi].add(&q);
        // v and every vertex next to it see a new neighbourhood; their collapses onto v cost
        // anew (v's quadric grew), and v's own.
        self.neighbours(v);
        self.cost_best(v);
        for k in 0..self.around.len() {
            let w = self.around[k];
            let wi = w as usize;
            self.version[wi] += 1;
            let c = self.cost(w, v);
            if c < self.best[wi].0 {
                self.best[wi] = (c, v);
            }
        }
        self.version[vi] += 1;
    }

    /// Whether `w` is the vertex the collapse being checked removes.
    fn removed_now(&self, w: u32) -> bool {
        w == self.going
    }

    fn corners(&self, tri: [u32; 3]) -> [V3; 3] {
        tri.map(|w| self.pos[w as usize])
    }

    fn finish(self, mesh: &Mesh) -> Simplified {
        let mut kept = vec![u32::MAX; self.pos.len()];
        let mut out = Mesh::default();
        for (v, &gone) in self.removed.iter().enumerate() {
            if !gone {
                kept[v] = out.positions.len() as u32;
                out.positions.push(mesh.positions[v]);
            }
        }
        for (t, tri) in self.tris.iter().enumerate() {
            if self.alive[t] {
                out.triangles.push(tri.map(|w| kept[w as usize]));
                if let Some(&m) = mesh.materials.get(t) {
                    out.materials.push(m);
                }
            }
        }
        Simplified { mesh: out, kept }
    }
}

// The vector arithmetic of the inner loops, inlined (the core's own are not, across crates).
#[inline(always)]
fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// A triangle's normal as wound, twice its area long.
fn tri_normal(c: &[V3; 3]) -> V3 {
    cross(sub(c[1], c[0]), sub(c[2], c[0]))
}

/// The vertices of edges only one triangle has (an open surface's rim), in order: around a
/// vertex inside a surface every neighbour is met by two of its triangles (`fans`, each
/// vertex's triangles).
fn open_edge_vertices(triangles: &[[u32; 3]], fans: &[Vec<u32>]) -> Vec<u32> {
    let mut out = Vec::new();
    let mut met: Vec<(u32, u8)> = Vec::new();
    for (v, fan) in fans.iter().enumerate() {
        met.clear();
        for &t in fan {
            for w in triangles[t as usize] {
                if w as usize == v {
                    continue;
                }
                match met.iter_mut().find(|m| m.0 == w) {
                    Some(m) => m.1 += 1,
                    None => met.push((w, 1)),
                }
            }
        }
        if met.iter().any(|m| m.1 == 1) {
            out.push(v as u32);
        }
    }
    out
}

#[cfg(test)]
mod tests;
