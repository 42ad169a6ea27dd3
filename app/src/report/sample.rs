//! The statistics of one sample: mean, median, a seeded percentile bootstrap interval of the
//! mean, a Wilson interval of a success rate, a least-squares line, failure rates per bin.
//!
//! The bootstrap is written out so that anyone can redo it: each interval starts SplitMix64
//! at the seed; a resample draws `n` indices, each `(u * n) >> 64` of the next 64-bit `u`;
//! its mean is summed in draw order; the interval is the 2.5th and 97.5th percentiles of the
//! `B` resample means, interpolated linearly between order statistics (numpy's default).

use serde::Serialize;

/// Resamples per bootstrap interval unless asked otherwise.
pub const RESAMPLES: usize = 2000;

/// The 97.5th percentile of the standard normal: a 95 % interval.
pub const Z95: f64 = 1.959_963_984_540_054;

/// SplitMix64 (Steele, Lea and Flood 2014).
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator started at `seed`.
    pub fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    /// The next 64 bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// An index below `n`: `(u * n) >> 64`.
    pub fn below(&mut self, n: usize) -> usize {
        ((u128::from(self.next_u64()) * n as u128) >> 64) as usize
    }
}

/// The mean, summed in order.
pub fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

/// The median (the mean of the two middle values for an even count).
pub fn median(x: &[f64]) -> f64 {
    let mut s = x.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    if n % 2 == 1 {
        s[n / 2]
    } else {
        (s[n / 2 - 1] + s[n / 2]) / 2.0
    }
}

/// The `q`th percentile (0 to 100) of sorted values, linearly interpolated (numpy's
/// default, `method="linear"`).
pub fn percentile(sorted: &[f64], q: f64) -> f64 {
    let pos = q / 100.0 * (sorted.len() - 1) as f64;
    let lo = pos.floor() as usize;
    let hi = (lo + 1).min(sorted.len() - 1);
    let t = pos - lo as f64;
    let (a, b) = (sorted[lo], sorted[hi]);
    // numpy's `_lerp`: from the nearer end.
    if t >= 0.5 {
        b - (b - a) * (1.0 - t)
    } else {
        a + (b - a) * t
    }
}

/// A 95 % percentile bootstrap interval of the mean, `None` below two values.
pub fn bootstrap(x: &[f64], seed: u64, resamples: usize) -> Option<[f64; 2]> {
    let n = x.len();
    if n < 2 || resamples < 2 {
        return None;
    }
    let mut rng = SplitMix64::new(seed);
    let mut means: Vec<f64> = (0..resamples)
        .map(|_| {
            let mut s = 0.0;
            for _ in 0..n {
                s += x[rng.below(n)];
            }
            s / n as f64
        })
        .collect();
    means.sort_by(f64::total_cmp);
    Some([percentile(&means, 2.5), percentile(&means, 97.5)])
}

/// Wilson's 95 % score interval of `k` successes in `n` trials (no continuity correction).
pub fn wilson(k: usize, n: usize) -> Option<[f64; 2]> {
    if n == 0 {
        return None;
    }
    let (n, p) = (n as f64, k as f64 / n as f64);
    let z2 = Z95 * Z95;
    let centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
    let half = Z95 / (1.0 + z2 / n) * (p * (1.0 - p) / n + z2 / (4.0 * n * n)).sqrt();
    Some([(centre - half).max(0.0), (centre + half).min(1.0)])
}

/// A least-squares line `y = slope x + intercept` and Pearson's r.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Line {
    /// Change of the metric per unit of the parameter.
    pub slope: f64,
    /// The metric at parameter 0.
    pub intercept: f64,
    /// Pearson's correlation (`None` when the metric does not vary).
    pub r: Option<f64>,
}

/// The least-squares line through `(x, y)`; `None` below two points or when x is constant.
pub fn fit(x: &[f64], y: &[f64]) -> Option<Line> {
    if x.len() < 2 {
        return None;
    }
    let (mx, my) = (mean(x), mean(y));
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxx += (a - mx) * (a - mx);
        sxy += (a - mx) * (b - my);
        syy += (b - my) * (b - my);
    }
    if sxx <= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    Some(Line {
        slope,
        intercept: my - slope * mx,
        r: (syy > 0.0).then(|| sxy / (sxx * syy).sqrt()),
    })
}

/// One bin of a parameter.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Bin {
    /// Its lower edge (included).
    pub from: f64,
    /// Its upper edge (included for the last bin, else excluded).
    pub to: f64,
    /// Runs in it.
    pub runs: usize,
    /// Of which failed.
    pub failures: usize,
    /// `failures / runs` (`None` when empty).
    pub rate: Option<f64>,
}

/// Bins of the values `all` takes: one per value when there are at most six distinct values,
/// else five of equal width from the smallest to the largest; each with the runs (`x`, one
/// per run) in it and how many of them `failed`.
pub fn bins(all: &[f64], x: &[f64], failed: &[bool]) -> Vec<Bin> {
    let mut values: Vec<f64> = all.to_vec();
    values.sort_by(f64::total_cmp);
    values.dedup();
    let edges: Vec<(f64, f64)> = if values.len() <= 6 {
        values.iter().map(|&v| (v, v)).collect()
    } else {
        let (lo, hi) = (values[0], values[values.len() - 1]);
        let w = (hi - lo) / 5.0;
        (0..5)
            .map(|k| {
                let to = if k == 4 { hi } else { lo + w * (k + 1) as f64 };
                (lo + w * k as f64, to)
            })
            .collect()
    };
    let last = edges.len().saturating_sub(1);
    edges
        .iter()
        .enumerate()
        .map(|(k, &(from, to))| {
            let inside = |v: f64| {
                if from == to {
                    v == from
                } else {
                    v >= from && (v < to || (k == last && v <= to))
                }
            };
            let (mut runs, mut failures) = (0, 0);
            for (v, f) in x.iter().zip(failed) {
                if inside(*v) {
                    runs += 1;
                    failures += usize::from(*f);
                }
            }
            Bin {
                from,
                to,
                runs,
                failures,
                rate: (runs > 0).then(|| failures as f64 / runs as f64),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A normal draw (Box and Muller) from the generator.
    fn normal(rng: &mut SplitMix64) -> f64 {
        let u = |r: &mut SplitMix64| ((r.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
        let (a, b) = (u(rng), u(rng));
        (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
    }

    #[test]
    fn the_bootstrap_interval_covers_the_true_mean_about_95_percent_of_the_time() {
        // 400 samples of 30 from N(3, 2^2): a percentile interval of the mean covers 3 in
        // about 93 to 95 % of them (it is a little narrow at n = 30); the binomial spread of
        // 400 trials is about 1.2 %.
        let mut rng = SplitMix64::new(7);
        let mut covered = 0;
        for k in 0..400 {
            let x: Vec<f64> = (0..30).map(|_| 3.0 + 2.0 * normal(&mut rng)).collect();
            let [lo, hi] = bootstrap(&x, k, 500).unwrap();
            assert!(lo <= mean(&x) && mean(&x) <= hi);
            covered += usize::from(lo <= 3.0 && 3.0 <= hi);
        }
        let share = covered as f64 / 400.0;
        assert!((0.89..=0.98).contains(&share), "coverage {share}");
    }

    #[test]
    fn the_wilson_interval_covers_the_true_rate_about_95_percent_of_the_time() {
        let mut rng = SplitMix64::new(3);
        let mut covered = 0;
        for _ in 0..2000 {
            let k = (0..40)
                .filter(|_| rng.next_u64() < (0.2 * u64::MAX as f64) as u64)
                .count();
            let [lo, hi] = wilson(k, 40).unwrap();
            covered += usize::from(lo <= 0.2 && 0.2 <= hi);
        }
        let share = covered as f64 / 2000.0;
        assert!((0.92..=0.98).contains(&share), "coverage {share}");
    }

    #[test]
    fn bins_hold_every_run_once() {
        let x: Vec<f64> = (0..50).map(|k| f64::from(k % 13) * 1.5).collect();
        let failed: Vec<bool> = (0..50).map(|k| k % 3 == 0).collect();
        let b = bins(&x, &x, &failed);
        assert_eq!(b.len(), 5);
        assert_eq!(b.iter().map(|b| b.runs).sum::<usize>(), 50);
        assert_eq!(b.iter().map(|b| b.failures).sum::<usize>(), 17);
        assert_eq!((b[0].from, b[4].to), (0.0, 18.0));
    }
}
