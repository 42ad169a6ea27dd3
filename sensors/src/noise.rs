//! Random numbers for noise, drawn by hashing: a ray's noise is a function of the seed and the
//! ray's index alone, so rays can be cast in any order, on any number of threads, and come out
//! the same.
//!
//! Normal deviates come from a table of the inverse normal distribution (4,096 intervals,
//! interpolated), so one costs a hash and a lookup instead of a logarithm and a square root:
//! a scan draws tens of thousands. The table reaches 3.7 standard deviations, which sensor
//! noise models need not exceed.

use std::sync::OnceLock;

/// SplitMix64's finaliser: a well-mixed 64-bit hash.
pub fn hash(seed: u64, key: u64) -> u64 {
    let mut z = seed ^ key.wrapping_mul(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A uniform number in `(0, 1)` from `key`.
pub fn uniform(seed: u64, key: u64) -> f64 {
    ((hash(seed, key) >> 11) as f64 + 0.5) * (1.0 / (1u64 << 53) as f64)
}

const CELLS: usize = 4096;

fn table() -> &'static [f64; CELLS + 1] {
    static TABLE: OnceLock<Box<[f64; CELLS + 1]>> = OnceLock::new();
    TABLE.get_or_init(|| {
        let mut t = Box::new([0.0; CELLS + 1]);
        for (i, v) in t.iter_mut().enumerate() {
            // Cell edges at (i + 0.5) / (CELLS + 1), so both ends stay finite.
            *v = inverse_normal((i as f64 + 0.5) / (CELLS + 1) as f64);
        }
        t
    })
}

/// A standard normal deviate from `key`.
pub fn normal(seed: u64, key: u64) -> f64 {
    let x = uniform(seed, key) * CELLS as f64;
    let i = (x as usize).min(CELLS - 1);
    let f = x - i as f64;
    let t = table();
    t[i] + f * (t[i + 1] - t[i])
}

/// The inverse of the standard normal distribution (Acklam's rational approximation,
/// relative error below 1.2e-9).
fn inverse_normal(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969683028665376e1,
        2.209460984245205e2,
        -2.759285104469687e2,
        1.38357751867269e2,
        -3.066479806614716e1,
        2.506628277459239,
    ];
    const B: [f64; 5] = [
        -5.447609879822406e1,
        1.615858368580409e2,
        -1.556989798598866e2,
        6.680131188771972e1,
        -1.328068155288572e1,
    ];
    const C: [f64; 6] = [
        -7.784894002430293e-3,
        -3.223964580411365e-1,
        -2.400758277161838,
        -2.549732539343734,
        4.374664141464968,
        2.938163982698783,
    ];
    const D: [f64; 4] = [
        7.784695709041462e-3,
        3.224671290700398e-1,
        2.445134137142996,
        3.754408661907416,
    ];
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    if p < 0.02425 {
        tail((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - 0.02425 {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_deviates_have_mean_zero_and_unit_variance() {
        let n = 200_000u64;
        let (mut s, mut s2, mut beyond2) = (0.0, 0.0, 0);
        for k in 0..n {
            let x = normal(42, k);
            s += x;
            s2 += x * x;
            beyond2 += usize::from(x.abs() > 2.0);
        }
        let mean = s / n as f64;
        let var = s2 / n as f64 - mean * mean;
        assert!(mean.abs() < 0.01, "{mean}");
        assert!((var - 1.0).abs() < 0.02, "{var}");
        // 4.55 % of a normal lies beyond two standard deviations.
        let share = beyond2 as f64 / n as f64;
        assert!((share - 0.0455).abs() < 0.003, "{share}");
        assert_eq!(normal(42, 7), normal(42, 7));
        assert_ne!(normal(42, 7), normal(43, 7));
    }
}
