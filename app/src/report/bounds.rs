//! What a report refuses to compute, said before the work (issue 37, items 8 and 11): more
//! bootstrap resamples than an interval needs, and more paired comparisons than a report can
//! show. Everything else a report computes grows with its runs (linearly, or as their sort).

use crate::Error;

/// The most bootstrap resamples per interval: 100,000. An interval's percentiles are stable to
/// a few parts in a thousand from 10,000; more only costs time (each resample draws every
/// world) and memory (8 bytes a resample).
pub const MAX_RESAMPLES: usize = 100_000;

/// The most paired comparisons (pairs of methods times metrics) a report makes: 250,000,
/// about 100 methods on 50 metrics. Each is a Wilcoxon test and a row of `paired.csv`,
/// `report.json` and `index.html` (about 1 kB in all).
pub const MAX_COMPARISONS: u64 = 250_000;

/// Bytes a paired comparison takes in the report's files, for the estimate.
const BYTES_PER_COMPARISON: u64 = 1000;

/// Refuses `--resamples` outside 100 to [`MAX_RESAMPLES`].
pub fn resamples(n: usize) -> Result<(), Error> {
    if n < 100 {
        return Err(Error::Usage(format!(
            "--resamples {n} is too few for a 95 % interval: give 100 or more (1000 to 10000 is usual)"
        )));
    }
    if n > MAX_RESAMPLES {
        return Err(Error::Usage(format!(
            "--resamples {n}: at most {MAX_RESAMPLES} resamples per interval (1000 to 10000 is usual; the interval does not change past 10000)"
        )));
    }
    Ok(())
}

/// Refuses `methods` methods compared pairwise on `metrics` metrics when that makes more than
/// [`MAX_COMPARISONS`] comparisons, with the estimate and what to change.
pub fn comparisons(methods: usize, metrics: usize) -> Result<(), Error> {
    let m = methods as u64;
    let pairs = m.saturating_mul(m.saturating_sub(1)) / 2;
    let total = pairs.saturating_mul(metrics as u64);
    if total <= MAX_COMPARISONS {
        return Ok(());
    }
    Err(Error::TooLarge(format!(
        "{methods} methods make {pairs} pairs; on {metrics} metric(s) that is {total} paired comparisons, each a Wilcoxon test and a row of paired.csv, report.json and index.html (about {} in all), more than the {MAX_COMPARISONS} a report makes: compare fewer methods at once (a report per group of methods: name their runs in separate --runs files), or fewer metrics",
        subtgraph_core::budget::Bytes(total.saturating_mul(BYTES_PER_COMPARISON))
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bounds_are_inclusive_and_say_the_numbers() {
        assert!(resamples(100).is_ok() && resamples(MAX_RESAMPLES).is_ok());
        let e = resamples(MAX_RESAMPLES + 1).unwrap_err().to_string();
        assert!(e.contains("at most 100000"), "{e}");
        assert!(resamples(usize::MAX).is_err() && resamples(99).is_err());
        assert!(comparisons(100, 50).is_ok());
        assert!(comparisons(usize::MAX, usize::MAX).is_err());
        let e = comparisons(1000, 2).unwrap_err().to_string();
        assert!(e.contains("499500 pairs") && e.contains("999000"), "{e}");
    }
}
