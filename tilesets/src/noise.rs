//! Seeded gradient noise in world coordinates.
//!
//! Wall relief, width changes and rubble all come from this noise evaluated at world
//! positions, so no two tiles look alike (repeated rock is what breaks feature-based SLAM, as
//! the paper notes) while two tiles still agree exactly where they meet. The permutation is
//! drawn from the world seed; the arithmetic is plain `f64`, the same on every machine.

use subtgraph_core::rng::WorldRng;

/// 3D gradient noise (Perlin's improved noise with a seeded permutation), in `[-1, 1]`.
#[derive(Clone, Debug)]
pub struct Noise {
    perm: [u8; 512],
}

const GRADIENTS: [[f64; 3]; 12] = [
    [1., 1., 0.],
    [-1., 1., 0.],
    [1., -1., 0.],
    [-1., -1., 0.],
    [1., 0., 1.],
    [-1., 0., 1.],
    [1., 0., -1.],
    [-1., 0., -1.],
    [0., 1., 1.],
    [0., -1., 1.],
    [0., 1., -1.],
    [0., -1., -1.],
];

impl Noise {
    /// Noise for a seed; `label` separates independent noises of one world.
    pub fn new(seed: u64, label: &str) -> Self {
        let mut rng = WorldRng::new(seed, label, 0);
        let mut p: Vec<u8> = (0..=255).collect();
        rng.shuffle(&mut p);
        let mut perm = [0u8; 512];
        for i in 0..512 {
            perm[i] = p[i & 255];
        }
        Self { perm }
    }

    fn grad(&self, hash: u8, x: f64, y: f64, z: f64) -> f64 {
        let g = GRADIENTS[hash as usize % 12];
        g[0] * x + g[1] * y + g[2] * z
    }

    /// Noise at a point (one unit = one feature size).
    pub fn at(&self, x: f64, y: f64, z: f64) -> f64 {
        let (xf, yf, zf) = (x.floor(), y.floor(), z.floor());
        let (xi, yi, zi) = (
            (xf as i64 & 255) as usize,
            (yf as i64 & 255) as usize,
            (zf as i64 & 255) as usize,
        );
        let (x, y, z) = (x - xf, y - yf, z - zf);
        let fade = |t: f64| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
        let (u, v, w) = (fade(x), fade(y), fade(z));
        let p = &self.perm;
        let a = p[xi] as usize + yi;
        let (aa, ab) = (p[a] as usize + zi, p[a + 1] as usize + zi);
        let b = p[xi + 1] as usize + yi;
        let (ba, bb) = (p[b] as usize + zi, p[b + 1] as usize + zi);
        let lerp = |t: f64, a: f64, b: f64| a + t * (b - a);
        lerp(
            w,
            lerp(
                v,
                lerp(u, self.grad(p[aa], x, y, z), self.grad(p[ba], x - 1., y, z)),
                lerp(
                    u,
                    self.grad(p[ab], x, y - 1., z),
                    self.grad(p[bb], x - 1., y - 1., z),
                ),
            ),
            lerp(
                v,
                lerp(
                    u,
                    self.grad(p[aa + 1], x, y, z - 1.),
                    self.grad(p[ba + 1], x - 1., y, z - 1.),
                ),
                lerp(
                    u,
                    self.grad(p[ab + 1], x, y - 1., z - 1.),
                    self.grad(p[bb + 1], x - 1., y - 1., z - 1.),
                ),
            ),
        )
        .clamp(-1.0, 1.0)
    }

    /// Fractal sum of `octaves` octaves, each half the size and half the amplitude, normalised
    /// to `[-1, 1]`.
    pub fn fbm(&self, x: f64, y: f64, z: f64, octaves: u32) -> f64 {
        let (mut sum, mut amp, mut norm, mut f) = (0.0, 1.0, 0.0, 1.0);
        for _ in 0..octaves {
            sum += amp * self.at(x * f, y * f, z * f);
            norm += amp;
            amp *= 0.5;
            f *= 2.0;
        }
        sum / norm
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_is_seeded_bounded_and_zero_on_the_lattice() {
        let a = Noise::new(1, "walls");
        let b = Noise::new(1, "walls");
        let c = Noise::new(2, "walls");
        let mut differs = false;
        for i in 0..200 {
            let p = (i as f64 * 0.37, i as f64 * 0.11, i as f64 * 0.53);
            let v = a.at(p.0, p.1, p.2);
            assert!((-1.0..=1.0).contains(&v));
            assert_eq!(v, b.at(p.0, p.1, p.2));
            differs |= v != c.at(p.0, p.1, p.2);
        }
        assert!(differs);
        assert_eq!(a.at(3.0, 4.0, 5.0), 0.0);
    }
}
