//! A shaft tile cut in two, so that each end of the shaft faces its own corridor.
//!
//! A shaft tile opens at its foot one way and at its top another (the DARPA vertical shaft
//! opens north at its foot and south at its top, 64 m up: opposite ways). The grid's foot and
//! landing are two dead ends whose corridors leave in any two directions, so no one rotation of
//! the whole tile serves both: turned for the foot, its top opens into whatever lies beside the
//! landing (rock, or another tile), not into the landing's corridor. So the tile is cut at a
//! height (`split`, half its rise unless the manifest says) into the *foot's part*, placed by the
//! foot's tile and turned for the foot's corridor, and the *landing's part*, placed by the
//! landing's tile and turned so its top opening faces the landing's corridor. Both draw the
//! same file (the foot's draw).
//!
//! Where the two turns differ, the shaft's cross-sections at the cut no longer coincide: the
//! *collar*, the flat ring between them at the cut's height, closes the wall there (a ledge
//! facing up where the upper part is the wider, a ceiling facing down where the lower one is).
//! The cross-sections are sampled along [`RAYS`] rays from the tile's vertical axis, so the
//! shaft must surround that axis at the cut (the DARPA shaft does, 11 to 28 m around it).

use std::cmp::Reverse;
use std::collections::HashMap;

use subtgraph_core::mesh::Mesh;

/// Rays from the tile's axis along which the collar samples the cross-sections (a multiple of
/// four, so a quarter turn maps rays onto rays).
const RAYS: usize = 360;

/// The two parts of a shaft tile and the collars that join them.
#[derive(Clone, Debug)]
pub(super) struct ShaftParts {
    /// Below the cut, in the kind's base orientation (the foot opens east), the foot's floor at
    /// z = 0.
    pub foot: Mesh,
    /// Above the cut, turned so that its top opening faces east (the base orientation of a
    /// landing), z from the landing's floor.
    pub landing: Mesh,
    /// `collars[r]`, in the landing part's frame: the ring joining it to the foot's part turned
    /// `r` quarter turns counter-clockwise from that frame (empty for the turn that makes the
    /// two cross-sections coincide).
    pub collars: [Mesh; 4],
}

impl ShaftParts {
    /// Cuts `mesh` (base orientation, metres) at height `split`; the landing's part is lowered
    /// by `rise` and turned `top_turn` quarter turns (those that take its top opening east).
    pub fn new(mesh: &Mesh, split: f32, rise: f32, top_turn: u8) -> ShaftParts {
        let (foot, mut landing, section, material) = cut(mesh, split);
        for p in &mut landing.positions {
            *p = super::prepare::turn([p[0], p[1], p[2] - rise], top_turn);
        }
        for n in &mut landing.normals {
            *n = super::prepare::turn(*n, top_turn);
        }
        let radii = radii(&section);
        let collars = [0u8, 1, 2, 3].map(|r| {
            collar(
                &radii,
                top_turn,
                r,
                split - rise,
                material,
                !mesh.normals.is_empty(),
                !mesh.uvs.is_empty(),
            )
        });
        ShaftParts {
            foot,
            landing,
            collars,
        }
    }
}

/// One side of the cut being built: the source's vertices it uses, and the crossings.
struct Side<'a> {
    src: &'a Mesh,
    out: Mesh,
    kept: HashMap<u32, u32>,
    crossings: HashMap<(u32, u32), u32>,
}

impl<'a> Side<'a> {
    fn new(src: &'a Mesh) -> Self {
        Side {
            src,
            out: Mesh::default(),
            kept: HashMap::new(),
            crossings: HashMap::new(),
        }
    }

    fn push(&mut self, p: [f32; 3], n: Option<[f32; 3]>, uv: Option<[f32; 2]>) -> u32 {
        self.out.positions.push(p);
        if let Some(n) = n {
            self.out.normals.push(n);
        }
        if let Some(uv) = uv {
            self.out.uvs.push(uv);
        }
        self.out.positions.len() as u32 - 1
    }

    fn vertex(&mut self, i: u32) -> u32 {
        if let Some(&k) = self.kept.get(&i) {
            return k;
        }
        let src = self.src;
        let k = self.push(
            src.positions[i as usize],
            src.normals.get(i as usize).copied(),
            src.uvs.get(i as usize).copied(),
        );
        self.kept.insert(i, k);
        k
    }

    /// The point where edge `a`-`b` crosses height `z`, computed from the edge's lower index
    /// first, so both sides and both triangles of the edge get the same bits.
    fn crossing(&mut self, a: u32, b: u32, z: f32) -> u32 {
        let (a, b) = (a.min(b), a.max(b));
        if let Some(&k) = self.crossings.get(&(a, b)) {
            return k;
        }
        let src = self.src;
        let (pa, pb) = (src.positions[a as usize], src.positions[b as usize]);
        let t = (z - pa[2]) / (pb[2] - pa[2]);
        let lerp = |u: f32, v: f32| u + t * (v - u);
        let p = [lerp(pa[0], pb[0]), lerp(pa[1], pb[1]), z];
        let n = (!src.normals.is_empty()).then(|| {
            let (na, nb) = (src.normals[a as usize], src.normals[b as usize]);
            let n = [0, 1, 2].map(|k| lerp(na[k], nb[k]));
            let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt().max(1e-12);
            n.map(|v| v / l)
        });
        let uv = (!src.uvs.is_empty()).then(|| {
            let (ua, ub) = (src.uvs[a as usize], src.uvs[b as usize]);
            [lerp(ua[0], ub[0]), lerp(ua[1], ub[1])]
        });
        let k = self.push(p, n, uv);
        self.crossings.insert((a, b), k);
        k
    }

    fn triangle(&mut self, t: [u32; 3], material: u8) {
        let p = t.map(|i| self.out.positions[i as usize]);
        if p[0] == p[1] || p[1] == p[2] || p[0] == p[2] {
            return;
        }
        self.out.triangles.push(t);
        self.out.materials.push(material);
    }
}

/// The parts of `mesh` below and above height `z` (triangles across it clipped exactly), the
/// cross-section at `z` as segments in the plane, and the material most of the clipped
/// triangles have.
fn cut(mesh: &Mesh, z: f32) -> (Mesh, Mesh, Vec<[[f64; 2]; 2]>, u8) {
    let (mut below, mut above) = (Side::new(mesh), Side::new(mesh));
    let mut section = Vec::new();
    let mut counts = [0usize; 256];
    for (k, &t) in mesh.triangles.iter().enumerate() {
        let material = mesh.materials.get(k).copied().unwrap_or(0);
        let up = t.map(|i| mesh.positions[i as usize][2] >= z);
        let ups = up.iter().filter(|&&u| u).count();
        if ups == 0 || ups == 3 {
            let side = if ups == 0 { &mut below } else { &mut above };
            let v = t.map(|i| side.vertex(i));
            side.triangle(v, material);
            continue;
        }
        counts[material as usize] += 1;
        // The vertex alone on its side first, keeping the winding.
        let lone = (0..3)
            .find(|&i| up[i] != up[(i + 1) % 3] && up[i] != up[(i + 2) % 3])
            .expect("one vertex is alone on its side");
        let (l, m, n) = (t[lone], t[(lone + 1) % 3], t[(lone + 2) % 3]);
        let (alone, pair) = if up[lone] {
            (&mut above, &mut below)
        } else {
            (&mut below, &mut above)
        };
        let (p, q) = (alone.crossing(l, m, z), alone.crossing(l, n, z));
        let lv = alone.vertex(l);
        alone.triangle([lv, p, q], material);
        let (p2, q2) = (pair.crossing(l, m, z), pair.crossing(l, n, z));
        let (mv, nv) = (pair.vertex(m), pair.vertex(n));
        pair.triangle([p2, mv, nv], material);
        pair.triangle([p2, nv, q2], material);
        let (a, b) = (
            alone.out.positions[p as usize],
            alone.out.positions[q as usize],
        );
        if a != b {
            section.push([
                [f64::from(a[0]), f64::from(a[1])],
                [f64::from(b[0]), f64::from(b[1])],
            ]);
        }
    }
    let material = (0..256)
        .max_by_key(|&m| (counts[m], Reverse(m)))
        .unwrap_or(0) as u8;
    (below.out, above.out, section, material)
}

/// Along each of [`RAYS`] rays from the axis (ray `k` at `k` turns of `2 pi / RAYS`
/// counter-clockwise from east), the distance to the nearest segment of the cross-section:
/// the shaft's wall.
fn radii(section: &[[[f64; 2]; 2]]) -> Vec<Option<f64>> {
    (0..RAYS)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / RAYS as f64;
            let u = [a.cos(), a.sin()];
            section
                .iter()
                .filter_map(|&[p, q]| {
                    // t u = p + s (q - p), 0 <= s <= 1, t > 0.
                    let d = [q[0] - p[0], q[1] - p[1]];
                    let den = u[0] * (-d[1]) - u[1] * (-d[0]);
                    if den.abs() < 1e-12 {
                        return None;
                    }
                    let t = (p[0] * (-d[1]) - p[1] * (-d[0])) / den;
                    let s = (u[0] * p[1] - u[1] * p[0]) / den;
                    (t > 0.0 && (0.0..=1.0).contains(&s)).then_some(t)
                })
                .min_by(f64::total_cmp)
        })
        .collect()
}

/// The flat ring at height `z` between the cross-section turned `upper` quarter turns (the
/// landing's part) and turned `lower` (the foot's), facing up where the upper one is the wider
/// (a ledge: free space above it) and down where the lower one is. Where a ray finds no wall
/// the ring is left open there.
fn collar(
    radii: &[Option<f64>],
    upper: u8,
    lower: u8,
    z: f32,
    material: u8,
    normals: bool,
    uvs: bool,
) -> Mesh {
    let quarter = RAYS / 4;
    let at = |k: usize, turns: u8| radii[(k + RAYS * 4 - usize::from(turns % 4) * quarter) % RAYS];
    let point = |k: usize, r: f64| {
        let a = std::f64::consts::TAU * (k % RAYS) as f64 / RAYS as f64;
        [r * a.cos(), r * a.sin()]
    };
    let mut out = Mesh::default();
    let mut emit = |t: [[f64; 2]; 3], up: bool| {
        let area =
            (t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[1][1] - t[0][1]) * (t[2][0] - t[0][0]);
        if area == 0.0 {
            return;
        }
        let t = if (area > 0.0) == up {
            t
        } else {
            [t[0], t[2], t[1]]
        };
        let base = out.positions.len() as u32;
        for p in t {
            out.positions.push([p[0] as f32, p[1] as f32, z]);
            if normals {
                out.normals.push([0.0, 0.0, if up { 1.0 } else { -1.0 }]);
            }
            if uvs {
                out.uvs.push([(p[0] / 8.0) as f32, (p[1] / 8.0) as f32]);
            }
        }
        out.triangles.push([base, base + 1, base + 2]);
        out.materials.push(material);
    };
    for k in 0..RAYS {
        let (Some(b0), Some(b1), Some(a0), Some(a1)) = (
            at(k, upper),
            at(k + 1, upper),
            at(k, lower),
            at(k + 1, lower),
        ) else {
            continue;
        };
        let (d0, d1) = (b0 - a0, b1 - a1);
        let (pa0, pa1, pb0, pb1) = (
            point(k, a0),
            point(k + 1, a1),
            point(k, b0),
            point(k + 1, b1),
        );
        if d0 * d1 >= 0.0 {
            if d0 == 0.0 && d1 == 0.0 {
                continue;
            }
            let up = d0 + d1 > 0.0;
            emit([pa0, pa1, pb1], up);
            emit([pa0, pb1, pb0], up);
        } else {
            // The walls cross between the two rays: where the chords meet.
            let x = meet(pa0, pa1, pb0, pb1).unwrap_or([
                0.25 * (pa0[0] + pa1[0] + pb0[0] + pb1[0]),
                0.25 * (pa0[1] + pa1[1] + pb0[1] + pb1[1]),
            ]);
            emit([pa0, x, pb0], d0 > 0.0);
            emit([x, pa1, pb1], d1 > 0.0);
        }
    }
    out
}

/// Where segment `a0`-`a1` meets segment `b0`-`b1`, if they cross.
fn meet(a0: [f64; 2], a1: [f64; 2], b0: [f64; 2], b1: [f64; 2]) -> Option<[f64; 2]> {
    let (da, db) = (
        [a1[0] - a0[0], a1[1] - a0[1]],
        [b1[0] - b0[0], b1[1] - b0[1]],
    );
    let den = da[0] * db[1] - da[1] * db[0];
    if den.abs() < 1e-12 {
        return None;
    }
    let w = [b0[0] - a0[0], b0[1] - a0[1]];
    let s = (w[0] * db[1] - w[1] * db[0]) / den;
    (0.0..=1.0)
        .contains(&s)
        .then(|| [a0[0] + s * da[0], a0[1] + s * da[1]])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square tube from z = 0 to 10 around the axis, walls facing in, `w` wide in x and `h`
    /// in y (not square, so a quarter turn changes its cross-section).
    fn tube(w: f32, h: f32) -> Mesh {
        let mut m = Mesh::default();
        let c = [[w, -h], [w, h], [-w, h], [-w, -h]];
        for i in 0..4 {
            let (a, b) = (c[i], c[(i + 1) % 4]);
            let base = m.positions.len() as u32;
            for p in [
                [a[0], a[1], 0.0],
                [b[0], b[1], 0.0],
                [b[0], b[1], 10.0],
                [a[0], a[1], 10.0],
            ] {
                m.positions.push(p);
            }
            // Counter-clockwise seen from inside the tube.
            m.triangles
                .extend([[base, base + 2, base + 1], [base, base + 3, base + 2]]);
            m.materials.extend([0, 0]);
        }
        m
    }

    #[test]
    fn the_cut_keeps_every_triangle_on_its_side_and_meets_at_the_split() {
        let m = tube(4.0, 2.0);
        let parts = ShaftParts::new(&m, 4.0, 8.0, 0);
        let zs = |m: &Mesh| {
            m.positions
                .iter()
                .fold((f32::MAX, f32::MIN), |(lo, hi), p| {
                    (lo.min(p[2]), hi.max(p[2]))
                })
        };
        assert_eq!(zs(&parts.foot), (0.0, 4.0));
        // Lowered by the rise: from the cut (4 - 8) to the top (10 - 8).
        assert_eq!(zs(&parts.landing), (-4.0, 2.0));
        // Untouched, the parts' areas add up to the tube's: a wall 10 m high, 24 m round.
        let area = |m: &Mesh| {
            m.triangles
                .iter()
                .map(|t| {
                    let p = t.map(|i| m.positions[i as usize].map(f64::from));
                    let (u, v) = (
                        [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]],
                        [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]],
                    );
                    let n = [
                        u[1] * v[2] - u[2] * v[1],
                        u[2] * v[0] - u[0] * v[2],
                        u[0] * v[1] - u[1] * v[0],
                    ];
                    0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
                })
                .sum::<f64>()
        };
        assert!((area(&parts.foot) + area(&parts.landing) - 240.0).abs() < 1e-3);
        // Same turn for both parts: nothing to close.
        assert!(parts.collars[0].triangles.is_empty());
    }

    #[test]
    fn a_quarter_turn_closes_the_wall_with_a_ledge_and_a_ceiling() {
        // 8 m by 4 m: turned a quarter, the upper part is 4 m by 8 m.
        let m = tube(4.0, 2.0);
        let parts = ShaftParts::new(&m, 4.0, 8.0, 0);
        let ring = &parts.collars[1];
        assert!(!ring.triangles.is_empty());
        // The upper part is the wider in x (a ledge there, facing up), the lower one in y (a
        // ceiling, facing down); all at the cut.
        let (mut up, mut down) = (0.0, 0.0);
        for t in &ring.triangles {
            let p = t.map(|i| ring.positions[i as usize]);
            assert!(p.iter().all(|q| q[2] == -4.0));
            let a = f64::from((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]))
                - f64::from((p[1][1] - p[0][1]) * (p[2][0] - p[0][0]));
            let cx = (p[0][0] + p[1][0] + p[2][0]) / 3.0;
            if a > 0.0 {
                up += a / 2.0;
                assert!(cx.abs() > 1.5, "a ledge lies where the upper part is wider");
            } else {
                down -= a / 2.0;
                assert!(
                    cx.abs() < 2.5,
                    "a ceiling lies where the lower part is wider"
                );
            }
        }
        // Each way, two lobes of 2 m by 4 m (up to the rays' sampling).
        assert!(
            (up - 16.0).abs() < 0.5 && (down - 16.0).abs() < 0.5,
            "{up} {down}"
        );
    }
}
