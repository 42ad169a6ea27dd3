//! Tileable noise on the unit square: every function here takes texture coordinates
//! `(u, v)` in `[0, 1)` and wraps around at the edges (its lattices have a whole number of
//! cells per repeat), so a texture made of it repeats without a seam.
//!
//! Integer hashing only (SplitMix64) and plain `f64` arithmetic: the same on every machine
//! and thread count.

/// A seeded source of tileable noise.
#[derive(Clone, Copy, Debug)]
pub struct Tileable {
    seed: u64,
}

fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

fn smooth(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

impl Tileable {
    /// Noise for a seed (each material draws its own).
    pub fn new(seed: u64) -> Self {
        Self { seed }
    }

    /// A hash of lattice point `(x, y)` of layer `layer`, uniform in `[0, 1)`.
    pub fn hash(&self, layer: u64, x: i64, y: i64) -> f64 {
        let h = mix(self
            .seed
            .wrapping_add(layer.wrapping_mul(0x9e37_79b9_7f4a_7c15))
            .wrapping_add((x as u64).wrapping_mul(0xd1b5_4a32_d192_ed03))
            .wrapping_add((y as u64).wrapping_mul(0x8cb9_2ba7_2f3d_8dd7)));
        (h >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Value noise with `period` cells per repeat, in `[0, 1]`.
    pub fn value(&self, layer: u64, period: i64, u: f64, v: f64) -> f64 {
        let (x, y) = (u * period as f64, v * period as f64);
        let (x0, y0) = (x.floor(), y.floor());
        let (tx, ty) = (smooth(x - x0), smooth(y - y0));
        // The lattice corners wrapped once (an integer division each), their neighbours by a
        // compare: a quarter of the divisions, the same corners.
        let wrap = |i: i64| i.rem_euclid(period);
        let next = |i: i64| if i + 1 == period { 0 } else { i + 1 };
        let (x0, y0) = (wrap(x0 as i64), wrap(y0 as i64));
        let (x1, y1) = (next(x0), next(y0));
        let (h00, h10) = (self.hash(layer, x0, y0), self.hash(layer, x1, y0));
        let (h01, h11) = (self.hash(layer, x0, y1), self.hash(layer, x1, y1));
        let a = h00 + (h10 - h00) * tx;
        let b = h01 + (h11 - h01) * tx;
        a + (b - a) * ty
    }

    /// Fractal sum of `octaves` value noises from `period` cells per repeat, each twice as
    /// fine and `gain` times as strong as the last, normalised to `[0, 1]`.
    pub fn fbm(&self, layer: u64, period: i64, octaves: u32, gain: f64, u: f64, v: f64) -> f64 {
        let (mut sum, mut weight, mut amp, mut p) = (0.0, 0.0, 1.0, period);
        for o in 0..octaves {
            sum += amp * self.value(layer * 16 + u64::from(o), p, u, v);
            weight += amp;
            amp *= gain;
            p *= 2;
        }
        sum / weight
    }

    /// Cellular noise with `period` cells per repeat, one feature point per cell: the
    /// distances to the nearest and second-nearest points, in cells.
    pub fn cells(&self, layer: u64, period: i64, u: f64, v: f64) -> (f64, f64) {
        let (x, y) = (u * period as f64, v * period as f64);
        let (ix, iy) = (x.floor() as i64, y.floor() as i64);
        let (mut f1, mut f2) = (f64::MAX, f64::MAX);
        for dy in -1..=1 {
            for dx in -1..=1 {
                let (cx, cy) = (ix + dx, iy + dy);
                let (wx, wy) = (cx.rem_euclid(period), cy.rem_euclid(period));
                let px = cx as f64 + self.hash(layer, wx, wy);
                let py = cy as f64 + self.hash(layer + 1, wx, wy);
                let d = ((px - x).powi(2) + (py - y).powi(2)).sqrt();
                if d < f1 {
                    f2 = f1;
                    f1 = d;
                } else if d < f2 {
                    f2 = d;
                }
            }
        }
        (f1, f2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_wraps_around_the_repeat() {
        let n = Tileable::new(7);
        for &(u, v) in &[(0.0, 0.3), (0.25, 0.0), (0.0, 0.0), (0.6, 0.9)] {
            let a = n.fbm(3, 4, 5, 0.5, u, v);
            let b = n.fbm(3, 4, 5, 0.5, u + 1.0, v + 1.0);
            assert!((a - b).abs() < 1e-12, "{a} {b}");
            let (c, d) = (n.cells(5, 6, u, v), n.cells(5, 6, u + 1.0, v));
            assert!((c.0 - d.0).abs() < 1e-9 && (c.1 - d.1).abs() < 1e-9);
        }
        // And it varies: not a constant.
        assert!((n.value(1, 8, 0.1, 0.1) - n.value(1, 8, 0.55, 0.4)).abs() > 1e-6);
    }
}
