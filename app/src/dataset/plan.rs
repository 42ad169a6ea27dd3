//! The global list of a dataset's worlds: every source's worlds in order, each with its seed
//! and folder name, whatever the shard or the number of jobs.

use subtgraph_core::rng::derive_seed;

/// One world of the global list.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Planned {
    /// Index of its source.
    pub source: usize,
    /// Index within its source.
    pub index: usize,
    /// Its seed.
    pub seed: u64,
    /// Its folder name, `NAME-0000`.
    pub name: String,
}

/// The seed of world `index` of source `name` in a dataset with base seed `base`: below 2^63,
/// as `world.seed` must be.
pub fn world_seed(base: u64, name: &str, index: usize) -> u64 {
    derive_seed(base, name, index as u64) & subtgraph_core::config::MAX_SEED
}

/// Every world of the dataset, source by source, in the order shards share them out.
pub fn plan(names: &[&str], count: usize, base: u64) -> Vec<Planned> {
    let width = count.saturating_sub(1).to_string().len().max(4);
    names
        .iter()
        .enumerate()
        .flat_map(|(s, name)| {
            (0..count).map(move |i| Planned {
                source: s,
                index: i,
                seed: world_seed(base, name, i),
                name: format!("{name}-{i:0width$}"),
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_world_seed_depends_on_its_source_base_and_index_only() {
        let small = plan(&["cave", "mine"], 3, 7);
        let large = plan(&["mine", "cave"], 50, 7);
        for w in &small {
            let same = large.iter().find(|l| l.name == w.name).unwrap();
            assert_eq!(same.seed, w.seed, "{}", w.name);
        }
        assert_eq!(small[0].name, "cave-0000");
        assert_eq!(plan(&["cave"], 12_000, 7)[11_999].name, "cave-11999");
        assert_ne!(world_seed(7, "cave", 0), world_seed(8, "cave", 0));
        assert_ne!(world_seed(7, "cave", 0), world_seed(7, "mine", 0));
        assert!(
            small
                .iter()
                .all(|w| w.seed <= subtgraph_core::config::MAX_SEED)
        );
    }
}
