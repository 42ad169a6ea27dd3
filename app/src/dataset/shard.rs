//! This machine's share of a dataset (`--shard I/N`, or `--shard-index K --shard-count N`).

use crate::Error;

/// This machine's share of a dataset: `I/N` makes every N-th world of the global list,
/// starting with the I-th (1-based). Written `--shard I/N` (1-based, as Slurm numbers array
/// tasks) or `--shard-index K --shard-count N` (0-based, as Kubernetes numbers the pods of an
/// indexed Job): two spellings, so neither needs arithmetic in a job script.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// 1-based index of this shard.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl Shard {
    /// The whole dataset.
    pub const ALL: Shard = Shard { index: 1, count: 1 };

    /// Whether this shard makes the world at `position` of the global list.
    pub fn owns(&self, position: usize) -> bool {
        position % self.count == self.index - 1
    }
}

impl Shard {
    /// `--shard-index K --shard-count N`: the K-th of N shards counted from 0
    /// (`JOB_COMPLETION_INDEX` of a Kubernetes indexed Job). Takes the flags' text, so a
    /// negative or missing number gets the same message as one out of range.
    pub fn zero_based(index: &str, count: &str) -> Result<Shard, Error> {
        let help = "write --shard-index K --shard-count N with whole numbers 0 <= K < N \
                    (in a Kubernetes indexed Job: --shard-index $JOB_COMPLETION_INDEX --shard-count \
                    and its completions), or --shard I/N counted from 1";
        let n = count
            .trim()
            .parse::<usize>()
            .ok()
            .filter(|&n| n >= 1)
            .ok_or_else(|| {
                Error::Usage(format!(
                    "--shard-count '{count}' is not a whole number of at least 1; {help}"
                ))
            })?;
        let k = index.trim().parse::<usize>().map_err(|_| {
            Error::Usage(format!(
                "--shard-index '{index}' is not a whole number; {help}"
            ))
        })?;
        if k >= n {
            return Err(Error::Usage(format!(
                "--shard-index {k} is out of range for --shard-count {n}: the index is 0-based, from 0 to {}; {help}",
                n - 1
            )));
        }
        Ok(Shard {
            index: k + 1,
            count: n,
        })
    }
}

impl std::str::FromStr for Shard {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        let help = "write --shard I/N with whole numbers 1 <= I <= N, e.g. --shard 1/4 ... --shard 4/4 \
                    (in a Slurm array: --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT)";
        let (i, n) = s
            .split_once('/')
            .ok_or_else(|| Error::Usage(format!("--shard '{s}' has no '/'; {help}")))?;
        let parse = |v: &str| v.trim().parse::<usize>().ok();
        match (parse(i), parse(n)) {
            (Some(i), Some(n)) if n >= 1 && (1..=n).contains(&i) => {
                Ok(Shard { index: i, count: n })
            }
            (Some(i), Some(n)) => Err(Error::Usage(format!(
                "--shard {i}/{n} is out of range: I must be between 1 and N (N >= 1); {help}; \
                 for a 0-based index (Kubernetes' JOB_COMPLETION_INDEX) write \
                 --shard-index K --shard-count N"
            ))),
            _ => Err(Error::Usage(format!(
                "--shard '{s}' is not two whole numbers; {help}"
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_split_the_list_round_robin() {
        let s: Shard = "2/3".parse().unwrap();
        let owned: Vec<usize> = (0..7).filter(|&k| s.owns(k)).collect();
        assert_eq!(owned, [1, 4]);
        for bad in ["5/4", "0/2", "a/b", "2", "1/0", "-1/2"] {
            let e = bad.parse::<Shard>().unwrap_err().to_string();
            assert!(e.contains("write --shard I/N"), "{bad}: {e}");
        }
        assert!(
            "0/2"
                .parse::<Shard>()
                .unwrap_err()
                .to_string()
                .contains("--shard-index K --shard-count N")
        );
        // K of N counted from 0 is the same shard as K+1 of N counted from 1.
        for n in 1..5 {
            for k in 0..n {
                let one: Shard = format!("{}/{n}", k + 1).parse().unwrap();
                assert_eq!(
                    Shard::zero_based(&k.to_string(), &n.to_string()).unwrap(),
                    one
                );
            }
            let e = Shard::zero_based(&n.to_string(), &n.to_string())
                .unwrap_err()
                .to_string();
            assert!(e.contains("out of range"), "{e}");
        }
    }
}
