//! What a view can contain, for a rasteriser: the triangles of the leaves whose boxes are not
//! wholly outside a convex volume (a camera's or a lamp's view frustum), and one ray against
//! one of those triangles, so a pixel a rasteriser assigned a triangle gets the hit a cast
//! would give it, to the bit.
//!
//! Why here: a camera that draws its first hits by rasterising still needs the hierarchy to
//! skip the world outside its view (a cave's visual surface is a million triangles, a view
//! holds a few per cent of them), and its hits must be the ray cast's own numbers (the same
//! watertight test, the same `f32` distance) so depth and shading do not depend on which of
//! the two found them.
//!
//! Triangles are named here by their **slot**, their place in the hierarchy's order (what
//! [`RayCaster::slot_corners`] and [`RayCaster::hit_slot`] take); [`RayCaster::slot_triangle`]
//! gives the mesh's index.

use super::{Entry, Hit, RayCaster, STACK, ray::Prepared};

/// A half-space `[a, b, c, d]`: the points with `a x + b y + c z + d >= 0`.
pub type Plane = [f64; 4];

impl RayCaster {
    /// Appends to `out` the slots of every triangle in a leaf whose box is not wholly outside
    /// one of `planes` (a conservative test: a triangle of such a leaf may still lie outside),
    /// in the hierarchy's order.
    pub fn slots_within(&self, planes: &[Plane], out: &mut Vec<u32>) {
        if self.nodes.is_empty() {
            return;
        }
        let planes: Vec<[f32; 4]> = planes
            .iter()
            .map(|p| [p[0] as f32, p[1] as f32, p[2] as f32, p[3] as f32])
            .collect();
        let mut stack = [Entry::default(); STACK];
        let mut top = 1usize;
        while top > 0 {
            top -= 1;
            let at = stack[top];
            if at.count > 0 {
                out.extend(at.child..at.child + at.count);
                continue;
            }
            let n = &self.nodes[at.child as usize];
            for i in 0..4 {
                if n.lo[0][i] > n.hi[0][i] {
                    continue;
                }
                let inside = planes.iter().all(|p| {
                    // The box's corner farthest along the plane's normal, widened by a
                    // hair so rounding never culls a box that touches the volume.
                    let far = |k: usize| if p[k] >= 0.0 { n.hi[k][i] } else { n.lo[k][i] };
                    let s = p[0] * far(0) + p[1] * far(1) + p[2] * far(2) + p[3];
                    let scale = p[0].abs() + p[1].abs() + p[2].abs();
                    s >= -1e-4 * scale * (1.0 + far(0).abs() + far(1).abs() + far(2).abs())
                });
                if inside {
                    stack[top] = Entry {
                        child: n.child[i],
                        count: n.count[i],
                        t: 0.0,
                    };
                    top += 1;
                }
            }
        }
    }

    /// The corners of the triangle in slot `slot`.
    #[inline]
    pub fn slot_corners(&self, slot: u32) -> [[f32; 3]; 3] {
        self.vertices[slot as usize]
    }

    /// The mesh's index of the triangle in slot `slot`.
    #[inline]
    pub fn slot_triangle(&self, slot: u32) -> u32 {
        self.ids[slot as usize]
    }

    /// The ray from `origin` along `dir` against the triangle in slot `slot` alone: its hit
    /// within `max` (in multiples of `dir`), with the distance and normal a
    /// [`cast`](RayCaster::cast) reports when that triangle is the first it meets.
    #[inline]
    pub fn hit_slot(&self, origin: [f64; 3], dir: [f64; 3], slot: u32, max: f64) -> Option<Hit> {
        self.hit_slots(origin, dir, &[slot], max)
    }

    /// The ray against the triangles in `slots` alone: the nearest hit within `max`, the
    /// last listed of those at the same distance.
    #[inline]
    pub fn hit_slots(
        &self,
        origin: [f64; 3],
        dir: [f64; 3],
        slots: &[u32],
        max: f64,
    ) -> Option<Hit> {
        if max.is_nan() || max <= 0.0 {
            return None;
        }
        let ray = Prepared::new(origin, dir)?;
        let mut best = max as f32;
        let mut found = None;
        for &s in slots {
            if let Some(t) = ray.triangle(&self.vertices[s as usize], best) {
                best = t;
                found = Some(s as usize);
            }
        }
        found.map(|k| self.hit(k, best, origin, dir))
    }
}

#[cfg(test)]
mod tests {
    use crate::mesh::Mesh;
    use crate::raycast::RayCaster;

    /// A grid of unit squares on the plane z = 0, `n` by `n`, two triangles each.
    fn floor(n: u32) -> Mesh {
        let mut m = Mesh::default();
        for j in 0..=n {
            for i in 0..=n {
                m.positions.push([i as f32, j as f32, 0.0]);
            }
        }
        for j in 0..n {
            for i in 0..n {
                let a = j * (n + 1) + i;
                m.triangles.push([a, a + 1, a + n + 2]);
                m.triangles.push([a, a + n + 2, a + n + 1]);
            }
        }
        m.materials = vec![0; m.triangles.len()];
        m
    }

    #[test]
    fn a_volume_keeps_the_triangles_it_holds_and_a_slot_hits_as_a_cast_does() {
        let mesh = floor(32);
        let caster = RayCaster::new(&mesh);
        // Everything, then the squares with x in [4, 8] and y in [10, 12].
        let mut all = Vec::new();
        caster.slots_within(&[], &mut all);
        assert_eq!(all.len(), mesh.triangles.len());
        let box_planes = [
            [1.0, 0.0, 0.0, -4.0],
            [-1.0, 0.0, 0.0, 8.0],
            [0.0, 1.0, 0.0, -10.0],
            [0.0, -1.0, 0.0, 12.0],
        ];
        let mut some = Vec::new();
        caster.slots_within(&box_planes, &mut some);
        assert!(some.len() < all.len() / 4, "{}", some.len());
        // Every triangle wholly inside the box is kept (the test is conservative).
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let inside = tri.iter().all(|&v| {
                let p = mesh.positions[v as usize];
                (4.0..=8.0).contains(&p[0]) && (10.0..=12.0).contains(&p[1])
            });
            if inside {
                assert!(
                    some.iter().any(|&s| caster.slot_triangle(s) as usize == t),
                    "triangle {t} culled"
                );
            }
        }
        // A slot's hit is the cast's, to the bit, when it is that triangle.
        for (o, d) in [
            ([5.3, 11.7, 3.0], [0.1, -0.2, -1.0]),
            ([20.25, 3.5, 1.0], [0.0, 0.0, -1.0]),
        ] {
            let cast = caster.cast(o, d, 100.0).unwrap();
            let slot = all
                .iter()
                .copied()
                .find(|&s| caster.slot_triangle(s) == cast.triangle)
                .unwrap();
            assert_eq!(caster.hit_slot(o, d, slot, 100.0), Some(cast));
            assert_eq!(caster.hit_slot(o, d, slot, 0.5 * cast.t), None);
            let other = all.iter().copied().find(|&s| s != slot).unwrap();
            let corners = caster.slot_corners(other);
            let centre =
                [0, 1, 2].map(|k| f64::from(corners[0][k] + corners[1][k] + corners[2][k]) / 3.0);
            // A ray at another triangle's centre misses this slot's triangle.
            let to = [0, 1, 2].map(|k| centre[k] - o[k]);
            if caster.slot_triangle(other) != cast.triangle {
                assert!(caster.hit_slot(o, to, slot, 10.0).is_none());
            }
        }
    }
}
