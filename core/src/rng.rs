//! Seeded random streams.
//!
//! Every random choice in a world comes from a [`WorldRng`] derived from the world seed and a
//! fixed label (`"level"`, level index, attempt, ...). Streams never share state, so changing
//! how many numbers one stage draws cannot shift another stage, and a resolved configuration
//! regenerates the same world.
//!
//! Sampling is implemented here on top of the raw ChaCha8 output instead of through `rand`'s
//! distributions, so a future `rand` release that changes its sampling algorithms cannot change
//! the worlds a seed produces.

use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{Rng, SeedableRng};

/// A deterministic random stream (ChaCha8) with the few samplers generation needs.
#[derive(Clone, Debug)]
pub struct WorldRng {
    inner: ChaCha8Rng,
}

/// Mixes a seed with a label into a new 64-bit seed (SplitMix64 finaliser over FNV-1a).
pub fn derive_seed(seed: u64, label: &str, index: u64) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in label.bytes().chain(index.to_le_bytes()) {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    let mut z = seed ^ h;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl WorldRng {
    /// A stream for `seed`, labelled so that different stages get independent streams.
    pub fn new(seed: u64, label: &str, index: u64) -> Self {
        Self {
            inner: ChaCha8Rng::seed_from_u64(derive_seed(seed, label, index)),
        }
    }

    /// A child stream, independent of how much of `self` is consumed later.
    pub fn fork(&mut self, label: &str) -> Self {
        let seed = self.next_u64();
        Self::new(seed, label, 0)
    }

    /// The next raw 64-bit value.
    pub fn next_u64(&mut self) -> u64 {
        self.inner.next_u64()
    }

    /// Uniform integer in `0..n` (Lemire's multiply-shift with rejection). `n` must be > 0.
    pub fn below(&mut self, n: u64) -> u64 {
        assert!(n > 0, "WorldRng::below(0)");
        let threshold = n.wrapping_neg() % n;
        loop {
            let m = u128::from(self.next_u64()) * u128::from(n);
            if (m as u64) >= threshold {
                return (m >> 64) as u64;
            }
        }
    }

    /// Uniform integer in `lo..=hi` (either order).
    pub fn int_in(&mut self, lo: i64, hi: i64) -> i64 {
        let (lo, hi) = if lo <= hi { (lo, hi) } else { (hi, lo) };
        let span = (hi - lo) as u64 + 1;
        lo + self.below(span) as i64
    }

    /// Uniform float in `[0, 1)` with 53 bits of precision.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform float in `[lo, hi]`.
    pub fn float_in(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// `true` with probability one half.
    pub fn coin(&mut self) -> bool {
        self.next_u64() >> 63 == 1
    }

    /// Shuffles a slice in place (Fisher-Yates).
    pub fn shuffle<T>(&mut self, items: &mut [T]) {
        for i in (1..items.len()).rev() {
            let j = self.below(i as u64 + 1) as usize;
            items.swap(i, j);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_and_label_give_the_same_stream() {
        let mut a = WorldRng::new(7, "level", 2);
        let mut b = WorldRng::new(7, "level", 2);
        let xs: Vec<u64> = (0..8).map(|_| a.next_u64()).collect();
        let ys: Vec<u64> = (0..8).map(|_| b.next_u64()).collect();
        assert_eq!(xs, ys);
        let mut c = WorldRng::new(7, "level", 3);
        assert_ne!(xs[0], c.next_u64());
    }

    #[test]
    fn int_in_stays_in_range_and_hits_both_ends() {
        let mut r = WorldRng::new(1, "t", 0);
        let mut seen = [false; 5];
        for _ in 0..1000 {
            let v = r.int_in(3, 7);
            assert!((3..=7).contains(&v));
            seen[(v - 3) as usize] = true;
        }
        assert!(seen.iter().all(|&s| s));
    }

    #[test]
    fn unit_is_in_half_open_interval() {
        let mut r = WorldRng::new(9, "u", 0);
        for _ in 0..1000 {
            let u = r.unit();
            assert!((0.0..1.0).contains(&u));
        }
    }
}
