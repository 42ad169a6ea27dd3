//! Wilcoxon's signed-rank test of paired differences, two-sided, as `scipy.stats.wilcoxon`
//! computes it with its defaults (`zero_method="wilcox"`, `correction=False`,
//! `method="auto"`, scipy 1.13 and later):
//! - zero differences are dropped; the others ranked by size, ties given their mean rank;
//! - no ties and no zeros: the exact null distribution of the positive rank sum `T+`, with
//!   `p = 2 min(P(T+ <= t), P(T+ >= t))`, at most 1;
//! - ties or zeros among at most 13 differences: every one of the `2^n` sign flips counted
//!   (scipy's permutation test, exact at this size);
//! - otherwise the normal approximation `z = (T+ - n(n+1)/4) / sd`, the variance corrected
//!   for ties (`n(n+1)(2n+1)/24 - sum(t^3 - t)/48`), without continuity correction.

use serde::Serialize;

/// The test's result.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Wilcoxon {
    /// Non-zero differences ranked.
    pub n: usize,
    /// Zero differences dropped.
    pub zeros: usize,
    /// `min(T+, T-)`, scipy's `statistic` for a two-sided test.
    pub statistic: f64,
    /// The two-sided p-value.
    pub p: f64,
    /// `exact`, `permutation` or `normal`.
    pub method: &'static str,
}

/// `erfc(x)` to about 1e-15 relative: a positive series for small `x`, Laplace's continued
/// fraction for large.
pub fn erfc(x: f64) -> f64 {
    if x < 0.0 {
        return 2.0 - erfc(-x);
    }
    if x < 2.5 {
        let (mut term, mut sum, mut k) = (x, x, 0.0);
        while term > sum * 1e-17 {
            k += 1.0;
            term *= 2.0 * x * x / (2.0 * k + 1.0);
            sum += term;
        }
        return 1.0 - 2.0 / std::f64::consts::PI.sqrt() * (-x * x).exp() * sum;
    }
    let mut f = x;
    for k in (1..=120).rev() {
        f = x + (f64::from(k) / 2.0) / f;
    }
    (-x * x).exp() / (std::f64::consts::PI.sqrt() * f)
}

/// Mean ranks of `a` (1-based) and `sum(t^3 - t)` over groups of ties.
fn ranks(a: &[f64]) -> (Vec<f64>, f64, bool) {
    let mut order: Vec<usize> = (0..a.len()).collect();
    order.sort_by(|&i, &j| a[i].total_cmp(&a[j]));
    let mut r = vec![0.0; a.len()];
    let (mut tie, mut ties) = (0.0, false);
    let mut i = 0;
    while i < order.len() {
        let mut j = i;
        while j + 1 < order.len() && a[order[j + 1]] == a[order[i]] {
            j += 1;
        }
        let t = (j - i + 1) as f64;
        for &k in &order[i..=j] {
            r[k] = (i + j) as f64 / 2.0 + 1.0;
        }
        if j > i {
            ties = true;
            tie += t * t * t - t;
        }
        i = j + 1;
    }
    (r, tie, ties)
}

/// `P(T+ = k)` for `n` untied ranks, `k = 0 ..= n(n+1)/2`.
fn null_pmf(n: usize) -> Vec<f64> {
    let top = n * (n + 1) / 2;
    let mut pmf = vec![0.0; top + 1];
    pmf[0] = 1.0;
    for r in 1..=n {
        for k in (0..=top).rev() {
            let with = if k >= r { pmf[k - r] } else { 0.0 };
            pmf[k] = (pmf[k] + with) / 2.0;
        }
    }
    pmf
}

/// The two-sided test of the differences `d` (`None` when every difference is 0).
pub fn test(d: &[f64]) -> Option<Wilcoxon> {
    let nonzero: Vec<f64> = d.iter().copied().filter(|&x| x != 0.0).collect();
    let zeros = d.len() - nonzero.len();
    let n = nonzero.len();
    if n == 0 {
        return None;
    }
    let abs: Vec<f64> = nonzero.iter().map(|x| x.abs()).collect();
    let (r, tie, ties) = ranks(&abs);
    let plus: f64 = nonzero
        .iter()
        .zip(&r)
        .filter(|(x, _)| **x > 0.0)
        .map(|(_, r)| r)
        .sum();
    let total = (n * (n + 1)) as f64 / 2.0;
    let statistic = plus.min(total - plus);
    let (p, method) = if !ties && zeros == 0 {
        let pmf = null_pmf(n);
        let t = plus as usize;
        let below: f64 = pmf[..=t].iter().sum();
        let above: f64 = pmf[t..].iter().sum();
        ((2.0 * below.min(above)).min(1.0), "exact")
    } else if d.len() <= 13 {
        let gamma = plus.abs() * 1e-12;
        let (mut less, mut more) = (0u64, 0u64);
        for signs in 0u32..(1 << n) {
            let s: f64 = (0..n).filter(|k| signs >> k & 1 == 1).map(|k| r[k]).sum();
            less += u64::from(s <= plus + gamma);
            more += u64::from(s >= plus - gamma);
        }
        let all = (1u64 << n) as f64;
        ((2.0 * less.min(more) as f64 / all).min(1.0), "permutation")
    } else {
        let nf = n as f64;
        let sd = ((nf * (nf + 1.0) * (2.0 * nf + 1.0) - tie / 2.0) / 24.0).sqrt();
        let z = (plus - nf * (nf + 1.0) / 4.0) / sd;
        (erfc(z.abs() / std::f64::consts::SQRT_2), "normal")
    };
    Some(Wilcoxon {
        n,
        zeros,
        statistic,
        p,
        method,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erfc_meets_known_values() {
        // Abramowitz and Stegun, table 7.1, and erfc(0) = 1.
        assert_eq!(erfc(0.0), 1.0);
        assert!((erfc(1.0) - 0.157_299_207_050_285_13).abs() < 1e-15);
        assert!((erfc(3.0) / 2.209_049_699_858_544e-5 - 1.0).abs() < 1e-13);
        assert!((erfc(-1.0) - 1.842_700_792_949_715).abs() < 1e-15);
    }

    #[test]
    fn the_null_distribution_sums_to_one_and_is_symmetric() {
        let pmf = null_pmf(10);
        assert!((pmf.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        assert_eq!(pmf[3], pmf[55 - 3]);
        // T+ = 0 only when every sign is negative.
        assert_eq!(pmf[0], 1.0 / 1024.0);
    }

    #[test]
    fn counting_sign_flips_gives_the_exact_distribution_without_ties() {
        // Untied differences: the exact null distribution and the 2^n sign flips are the same
        // count, so the two ways must give the same p-value.
        for n in 2..=12usize {
            let d: Vec<f64> = (1..=n)
                .map(|k| {
                    (k as f64 + 0.37 * k as f64 * k as f64) * if k % 3 == 0 { -1.0 } else { 1.0 }
                })
                .collect();
            let exact = test(&d).unwrap();
            assert_eq!(exact.method, "exact");
            let mut with_zero = d.clone();
            with_zero.push(0.0);
            let flips = test(&with_zero).unwrap();
            assert_eq!(flips.method, "permutation");
            assert!(
                (exact.p - flips.p).abs() < 1e-12,
                "n {n}: {} {}",
                exact.p,
                flips.p
            );
        }
    }
}
