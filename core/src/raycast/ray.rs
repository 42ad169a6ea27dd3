//! One ray against boxes and triangles: the tests a traversal repeats, with what they need of
//! the ray computed once.

use super::{Node4, WIDEN};

/// A ray with what every box and triangle test needs computed once.
pub(super) struct Prepared {
    origin: [f32; 3],
    inv: [f32; 3],
    /// Whether the direction is negative along each axis (its near plane is the box's high
    /// side).
    negative: [bool; 3],
    /// The axis the ray mostly runs along: the watertight test shears the triangle into a
    /// frame where the ray runs along it.
    kz: usize,
    /// The shear: the other two axes' components over this one's, and its inverse.
    shear: [f32; 3],
}

impl Prepared {
    pub(super) fn new(origin: [f64; 3], dir: [f64; 3]) -> Option<Prepared> {
        let d = [dir[0] as f32, dir[1] as f32, dir[2] as f32];
        let finite = d[0].is_finite()
            && d[1].is_finite()
            && d[2].is_finite()
            && origin[0].is_finite()
            && origin[1].is_finite()
            && origin[2].is_finite();
        let abs = [d[0].abs(), d[1].abs(), d[2].abs()];
        let kz = if abs[0] >= abs[1] && abs[0] >= abs[2] {
            0
        } else if abs[1] >= abs[2] {
            1
        } else {
            2
        };
        if !finite || abs[kz] == 0.0 {
            return None;
        }
        // The watertight test's other two axes follow kz cyclically. Woop et al. swap them
        // when the ray runs down its axis to keep triangles' winding; hits from both sides
        // count here, so the swap (which only flips every edge function's sign) is left out.
        let (kx, ky) = ((kz + 1) % 3, (kz + 2) % 3);
        // A zero component gets a huge but finite inverse of its sign instead, so box tests see
        // huge but finite slab distances (never 0 x infinity).
        let inv = |x: f32| {
            if x.abs() < 1e-30 {
                1e30f32.copysign(x)
            } else {
                1.0 / x
            }
        };
        let inv = [inv(d[0]), inv(d[1]), inv(d[2])];
        let sz = 1.0 / d[kz];
        Some(Prepared {
            origin: [origin[0] as f32, origin[1] as f32, origin[2] as f32],
            negative: [inv[0] < 0.0, inv[1] < 0.0, inv[2] < 0.0],
            inv,
            kz,
            shear: [d[kx] * sz, d[ky] * sz, sz],
        })
    }

    /// Where the ray enters each of the node's four boxes (`f32::INFINITY` for a box it
    /// misses, or enters only beyond `max`).
    ///
    /// Each axis reads the near and far planes the ray's direction picks (no compare and swap
    /// per box), and the loops over the four boxes are what the compiler turns into vector
    /// instructions. Comparisons are plain `<`/`>`, not `f32::min`/`max`, which order NaN and
    /// cost instructions on every box; no NaN can occur, as the inverse direction is finite.
    #[inline(always)]
    pub(super) fn enters4(&self, n: &Node4, max: f32) -> [f32; 4] {
        let pick = |k: usize| {
            if self.negative[k] {
                (&n.hi[k], &n.lo[k])
            } else {
                (&n.lo[k], &n.hi[k])
            }
        };
        let ((nx, fx), (ny, fy), (nz, fz)) = (pick(0), pick(1), pick(2));
        let [ox, oy, oz] = self.origin;
        let [ix, iy, iz] = self.inv;
        let mut out = [0f32; 4];
        for i in 0..4 {
            let near = max2(
                max2((nx[i] - ox) * ix, (ny[i] - oy) * iy),
                max2((nz[i] - oz) * iz, 0.0),
            );
            let far = min2(
                min2((fx[i] - ox) * ix, (fy[i] - oy) * iy),
                min2((fz[i] - oz) * iz, max),
            ) * WIDEN;
            out[i] = if near <= far { near } else { f32::INFINITY };
        }
        out
    }

    /// The watertight ray-triangle test: the distance to the triangle if it is hit before
    /// `max`.
    #[inline(always)]
    pub(super) fn triangle(&self, tri: &[[f32; 3]; 3], max: f32) -> Option<f32> {
        // The axes as constants, so the shear reads fixed coordinates.
        match self.kz {
            0 => self.sheared::<1, 2, 0>(tri, max),
            1 => self.sheared::<2, 0, 1>(tri, max),
            _ => self.sheared::<0, 1, 2>(tri, max),
        }
    }

    #[inline(always)]
    fn sheared<const KX: usize, const KY: usize, const KZ: usize>(
        &self,
        tri: &[[f32; 3]; 3],
        max: f32,
    ) -> Option<f32> {
        let [sx, sy, sz] = self.shear;
        let o = self.origin;
        let rel = |p: &[f32; 3]| {
            let q = [p[0] - o[0], p[1] - o[1], p[2] - o[2]];
            [q[KX] - sx * q[KZ], q[KY] - sy * q[KZ], sz * q[KZ]]
        };
        let (a, b, c) = (rel(&tri[0]), rel(&tri[1]), rel(&tri[2]));
        let mut u = c[0] * b[1] - c[1] * b[0];
        let mut v = a[0] * c[1] - a[1] * c[0];
        let mut w = b[0] * a[1] - b[1] * a[0];
        if u == 0.0 || v == 0.0 || w == 0.0 {
            // Exactly on an edge's line in f32: the products of f32 numbers are exact in f64,
            // so the sign there is the true one.
            let e = |p: [f32; 3], q: [f32; 3]| {
                (f64::from(p[0]) * f64::from(q[1]) - f64::from(p[1]) * f64::from(q[0])) as f32
            };
            u = e(c, b);
            v = e(a, c);
            w = e(b, a);
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let t = u * a[2] + v * b[2] + w * c[2];
        // Signs as det's: behind the origin, or beyond the best hit so far, misses.
        if det > 0.0 {
            if t < 0.0 || t > max * det {
                return None;
            }
        } else if t > 0.0 || t < max * det {
            return None;
        }
        let t = t / det;
        (t >= 0.0 && t <= max).then_some(t)
    }
}

/// The larger of two numbers, as one instruction (`maxps` takes the second when either is NaN,
/// which cannot occur here).
#[inline(always)]
fn max2(a: f32, b: f32) -> f32 {
    if a > b { a } else { b }
}

/// The smaller of two numbers, as one instruction.
#[inline(always)]
fn min2(a: f32, b: f32) -> f32 {
    if a < b { a } else { b }
}

/// Squared distance from `p` to each of the node's four boxes (0 inside; infinite for an
/// empty slot).
pub(super) fn box_distance2(n: &Node4, p: [f64; 3]) -> [f64; 4] {
    let mut d2 = [0.0; 4];
    for (k, &pk) in p.iter().enumerate() {
        for (i, d2) in d2.iter_mut().enumerate() {
            let d = (f64::from(n.lo[k][i]) - pk)
                .max(pk - f64::from(n.hi[k][i]))
                .max(0.0);
            *d2 += d * d;
        }
    }
    d2
}

/// The point of triangle `t` nearest `p` (Ericson, Real-Time Collision Detection, 5.1.5).
#[inline]
pub fn closest_on_triangle(p: [f64; 3], t: [[f64; 3]; 3]) -> [f64; 3] {
    use crate::vec3::{dot, sub};
    let [a, b, c] = t;
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let along =
        |o: [f64; 3], e: [f64; 3], s: f64| [o[0] + s * e[0], o[1] + s * e[1], o[2] + s * e[2]];
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return along(a, ab, d1 / (d1 - d3));
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return along(a, ac, d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return along(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    [
        a[0] + ab[0] * v + ac[0] * w,
        a[1] + ab[1] * v + ac[1] * w,
        a[2] + ab[2] * v + ac[2] * w,
    ]
}
