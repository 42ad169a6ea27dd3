//! How wide and how high each graph edge's passage is at its narrowest, measured on the
//! collision surface (what a robot's body collides with) along the edge's centreline.
//!
//! At every point of a corridor's polyline (a point on the floor, see `axis.rs`): a vertical
//! ray up and one down from half a metre above the point give the floor and the ceiling over
//! it (the *height*: floor to ceiling), and two horizontal rays across the passage, at right
//! angles to the polyline's local direction (from the point before to the point after), a
//! metre above that floor (half the height where the passage is under 2 m), give the *width*
//! (wall to wall). Rocks on the floor count: a rock reaching that height shortens the width
//! at its line, as it does for a robot there. An edge's `min_width_m` and `min_height_m` are
//! the least over its points. A shaft's are measured across the shaft at half way up (width,
//! the lesser of the spans along x and y) and along it (height: the free span there).
//!
//! Rays are cast into the survey's one hierarchy over the collision surface
//! ([`WorldSurvey::rays`](crate::WorldSurvey::rays), `core::raycast`), which finds the
//! triangle each ray meets first; the distance to it is then computed again in `f64` from
//! the ray's own origin (the hierarchy traces in `f32`, a tenth of a millimetre at a
//! kilometre from the origin), so widths are as exact as the surface. A ray finding no
//! surface within a pitch counts a pitch. Deterministic: no parallelism, no hashing order in
//! the results.

use subtgraph_core::World;
use subtgraph_core::graph::EdgeKind;
use subtgraph_core::mesh::Mesh;
use subtgraph_core::raycast::RayCaster;

/// The collision surface's hierarchy, asked across and along the edges' passages.
pub(crate) struct Sections<'a> {
    caster: &'a RayCaster,
    mesh: &'a Mesh,
    reach: f64,
}

/// Height above the floor at which widths are measured, metres.
const WIDTH_AT: f64 = 1.0;

impl<'a> Sections<'a> {
    /// The world's collision surface, if it has one, in `caster` (built over it).
    pub fn of(world: &'a World, caster: &'a RayCaster) -> Option<Self> {
        let pitch = world.resolved.tile_pitch;
        Some(Self::new(caster, &world.mesh()?.collision, pitch))
    }

    /// Rays into `caster` (built over `mesh`) up to `reach` long.
    fn new(caster: &'a RayCaster, mesh: &'a Mesh, reach: f64) -> Self {
        Sections {
            caster,
            mesh,
            reach,
        }
    }

    /// Distance along the unit direction `d` from `o` to the first crossing of the surface, or
    /// [`reach`](Self) when there is none that near.
    pub fn ray(&self, o: [f64; 3], d: [f64; 3]) -> f64 {
        match self.caster.cast(o, d, self.reach) {
            Some(h) => distance(self.mesh, h.triangle, o, d)
                .unwrap_or(h.t)
                .min(self.reach),
            None => self.reach,
        }
    }

    /// `(width, height)` at a floor point `p` of a passage running along the horizontal unit
    /// direction `along`.
    pub fn at(&self, p: [f64; 3], along: [f64; 2]) -> (f64, f64) {
        let o = [p[0], p[1], p[2] + 0.5];
        let up = self.ray(o, [0.0, 0.0, 1.0]);
        let down = self.ray(o, [0.0, 0.0, -1.0]);
        let floor = o[2] - down;
        let height = up + down;
        let z = floor + WIDTH_AT.min(0.5 * height);
        let n = [-along[1], along[0]];
        let w = self.ray([p[0], p[1], z], [n[0], n[1], 0.0])
            + self.ray([p[0], p[1], z], [-n[0], -n[1], 0.0]);
        (w, height)
    }

    /// An edge's `(min_width_m, min_height_m)` along its polyline.
    pub fn edge(&self, kind: EdgeKind, line: &[[f64; 3]]) -> Option<(f64, f64)> {
        match kind {
            // A ramp's spiral is measured like a corridor: across it (pillar to outer wall)
            // and up to the next turn's floor.
            EdgeKind::Corridor | EdgeKind::Ramp => {
                let mut out: Option<(f64, f64)> = None;
                for i in 0..line.len() {
                    let a = line[i.saturating_sub(1)];
                    let b = line[(i + 1).min(line.len() - 1)];
                    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                    let len = (dx * dx + dy * dy).sqrt();
                    if len < 1e-6 {
                        continue;
                    }
                    let (w, h) = self.at(line[i], [dx / len, dy / len]);
                    out = Some(out.map_or((w, h), |(ow, oh)| (ow.min(w), oh.min(h))));
                }
                out
            }
            EdgeKind::Shaft => {
                let (a, b) = (line.first()?, line.last()?);
                let m = [0, 1, 2].map(|k| 0.5 * (a[k] + b[k]));
                let span = |d: [f64; 3]| self.ray(m, d) + self.ray(m, d.map(|v| -v));
                let width = span([1.0, 0.0, 0.0]).min(span([0.0, 1.0, 0.0]));
                Some((width, span([0.0, 0.0, 1.0])))
            }
        }
    }
}

/// The distance along `d` from `o` to the plane of triangle `t` (Möller and Trumbore's, in
/// `f64`), or `None` when the ray runs along it.
fn distance(mesh: &Mesh, t: u32, o: [f64; 3], d: [f64; 3]) -> Option<f64> {
    use subtgraph_core::vec3::{cross, dot, sub};
    let [a, b, c] = mesh.triangles[t as usize].map(|v| mesh.positions[v as usize].map(f64::from));
    let (e1, e2) = (sub(b, a), sub(c, a));
    let h = cross(d, e2);
    let det = dot(e1, h);
    if det.abs() < 1e-12 {
        return None;
    }
    let q = cross(sub(o, a), e1);
    Some(dot(e2, q) / det)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_passage_is_as_wide_and_high_as_the_box() {
        let box_mesh = crate::passages::tests::box_mesh([0.0, 0.0, 0.0], [4.0, 10.0, 3.0]);
        let caster = RayCaster::new(&box_mesh);
        let s = Sections::new(&caster, &box_mesh, 25.0);
        let (w, h) = s.at([1.0, 5.0, 0.0], [0.0, 1.0]);
        assert!((w - 4.0).abs() < 1e-9 && (h - 3.0).abs() < 1e-9, "{w} {h}");
        // Across a diagonal direction the span is longer; the edge's least is the box's.
        let (w, _) = s.at([2.0, 5.0, 0.0], [0.6, 0.8]);
        assert!((w - 4.0 / 0.8).abs() < 1e-9, "{w}");
        let line = [[2.0, 1.0, 0.0], [2.0, 5.0, 0.0], [2.0, 9.0, 0.0]];
        let (w, h) = s.edge(EdgeKind::Corridor, &line).unwrap();
        assert!((w - 4.0).abs() < 1e-9 && (h - 3.0).abs() < 1e-9, "{w} {h}");
    }
}
