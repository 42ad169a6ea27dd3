//! Datasets: many worlds per source (a pipeline file or a preset), made in parallel, one whole
//! world per worker at a time, resumable, and splittable over machines.
//!
//! Every world's seed is `derive_seed(base seed, source name, index)` (the core's
//! [`subtgraph_core::rng::derive_seed`]), so a world depends only on its source, the base seed
//! and its index: not on `--jobs`, not on `--shard`, not on which worlds were made before. Each
//! world is a normal world folder (`cave-0000/`, ...) written atomically by
//! [`crate::make::write`]; its `world.toml` records its seed and resolved configuration and
//! regenerates it on its own.
//!
//! Timings differ between runs, so they are kept out of the world folders (which are
//! byte-identical whatever the run): each world's generation time and triangle counts go to
//! `.index/NAME.json` beside it, and from there into `index.json` and `index.csv`, which are
//! rebuilt from the folders at the end of every run ([`index`]).

pub mod index;
mod progress;

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};

use subtgraph_core::rng::derive_seed;
use subtgraph_core::{Pipeline, Registry};

use crate::make::{self, NamedExporter};
use index::RunFacts;

/// Where the worlds of a dataset come from: a pipeline file or a preset, ready to generate.
pub struct Source {
    /// Short name: the preset name or the pipeline file's stem. Names the world folders
    /// (`NAME-0000`) and enters each world's seed.
    pub name: String,
    /// Where it came from, for `world.toml` and the index (`preset cave`, a file path).
    pub description: String,
    /// The pipeline (its `world.seed` is replaced by each world's own seed).
    pub pipeline: Pipeline,
    /// The registry with the pipeline's plugins.
    pub registry: Registry,
    /// The exporters to run in every world folder.
    pub exporters: Vec<NamedExporter>,
}

/// This machine's share of a dataset: `I/N` makes every N-th world of the global list,
/// starting with the I-th (1-based).
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

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let help = "write --shard I/N with whole numbers 1 <= I <= N, e.g. --shard 1/4 ... --shard 4/4 \
                    (in a Slurm array: --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT)";
        let (i, n) = s
            .split_once('/')
            .ok_or_else(|| format!("--shard '{s}' has no '/'; {help}"))?;
        let parse = |v: &str| v.trim().parse::<usize>().ok();
        match (parse(i), parse(n)) {
            (Some(i), Some(n)) if n >= 1 && (1..=n).contains(&i) => {
                Ok(Shard { index: i, count: n })
            }
            (Some(i), Some(n)) => Err(format!(
                "--shard {i}/{n} is out of range: I must be between 1 and N (N >= 1); {help}"
            )),
            _ => Err(format!("--shard '{s}' is not two whole numbers; {help}")),
        }
    }
}

/// How to make a dataset.
#[derive(Clone, Debug)]
pub struct Options {
    /// Worlds per source.
    pub count: usize,
    /// The base seed every world's seed derives from.
    pub seed: u64,
    /// The dataset folder.
    pub out: PathBuf,
    /// Worker threads, each making one whole world at a time.
    pub jobs: usize,
    /// This machine's share.
    pub shard: Shard,
    /// Memory the whole run may use; each of the `jobs` workers gets its share.
    pub max_memory: subtgraph_core::Budget,
}

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
    derive_seed(base, name, index as u64) & (i64::MAX as u64)
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

/// What a run did.
#[derive(Debug, Default)]
pub struct Summary {
    /// Worlds made by this run.
    pub made: usize,
    /// Complete worlds found and kept.
    pub skipped: usize,
    /// Worlds in the rebuilt index (all shards' so far).
    pub indexed: usize,
}

/// Makes this shard's worlds of the dataset in `opts.out`, then rebuilds the index.
pub fn run(sources: &[Source], opts: &Options) -> Result<Summary> {
    let names: Vec<&str> = sources.iter().map(|s| s.name.as_str()).collect();
    for (i, a) in names.iter().enumerate() {
        if names[..i].contains(a) {
            bail!(
                "two sources are both named '{a}' (world folders are named after the pipeline file or preset): rename one of the files"
            );
        }
    }
    prepare_out(&opts.out)?;
    let all = plan(&names, opts.count, opts.seed);
    let mine: Vec<&Planned> = all
        .iter()
        .enumerate()
        .filter(|(k, _)| opts.shard.owns(*k))
        .map(|(_, w)| w)
        .collect();

    // Decide what to make before making anything: a folder of another dataset is an error.
    let mut todo = Vec::new();
    let mut skipped = 0;
    for w in &mine {
        match existing(&opts.out, w)? {
            Existing::Complete => skipped += 1,
            Existing::Absent => todo.push(*w),
        }
    }

    let progress = Mutex::new(progress::Progress::new(todo.len(), skipped));
    let next = AtomicUsize::new(0);
    let failures = Mutex::new(Vec::new());
    let jobs = opts.jobs.clamp(1, todo.len().max(1));
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| {
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    let Some(w) = todo.get(k) else { break };
                    let result = make_world(&sources[w.source], w, opts);
                    if let Err(e) = &result {
                        failures
                            .lock()
                            .expect("no worker panics holding it")
                            .push(format!("{}: {e:#}", w.name));
                    }
                    progress
                        .lock()
                        .expect("no worker panics holding it")
                        .finished(&w.name, result.is_ok());
                }
            });
        }
    });
    progress.into_inner().expect("workers are done").close();
    let indexed = index::rebuild(&opts.out)?;
    let failures = failures.into_inner().expect("workers are done");
    if !failures.is_empty() {
        bail!(
            "{} of {} worlds failed (the others are complete; run the same command again to retry):\n  {}",
            failures.len(),
            todo.len(),
            failures.join("\n  ")
        );
    }
    Ok(Summary {
        made: todo.len(),
        skipped,
        indexed,
    })
}

/// Creates the dataset folder and checks it can be written to, before any world is made.
fn prepare_out(out: &Path) -> Result<()> {
    if out.exists() && !out.is_dir() {
        bail!(
            "--out {} is a file; give a folder for the dataset",
            out.display()
        );
    }
    std::fs::create_dir_all(out).with_context(|| {
        format!(
            "cannot create the dataset folder --out {}; choose a folder you can write to",
            out.display()
        )
    })?;
    let probe = out.join(format!(".write-test-{}", std::process::id()));
    std::fs::write(&probe, b"")
        .and_then(|()| std::fs::remove_file(&probe))
        .with_context(|| {
            format!(
                "cannot write into --out {}; choose a folder you can write to",
                out.display()
            )
        })?;
    Ok(())
}

enum Existing {
    Complete,
    Absent,
}

/// Whether a planned world is already complete. Leftovers of an interrupted run (hidden
/// `.NAME.partial-*` folders, a folder without `world.toml`) are removed so it is made again.
fn existing(out: &Path, w: &Planned) -> Result<Existing> {
    let prefix = format!(".{}.partial-", w.name);
    for entry in std::fs::read_dir(out).with_context(|| format!("reading {}", out.display()))? {
        let entry = entry?;
        if entry.file_name().to_string_lossy().starts_with(&prefix) {
            std::fs::remove_dir_all(entry.path())
                .with_context(|| format!("removing the leftover {}", entry.path().display()))?;
        }
    }
    let dir = out.join(&w.name);
    if !dir.exists() {
        return Ok(Existing::Absent);
    }
    let toml_path = dir.join("world.toml");
    if !toml_path.is_file() {
        std::fs::remove_dir_all(&dir)
            .with_context(|| format!("removing the incomplete world {}", dir.display()))?;
        return Ok(Existing::Absent);
    }
    let text = std::fs::read_to_string(&toml_path)
        .with_context(|| format!("reading {}", toml_path.display()))?;
    let seed = recorded_seed(&text);
    if seed == Some(w.seed) {
        return Ok(Existing::Complete);
    }
    bail!(
        "{} holds a world of seed {}, but this dataset's world of that name has seed {}: it belongs to another dataset (other --seed or pipeline); give another --out, or remove it",
        dir.display(),
        seed.map_or("unknown".into(), |s| s.to_string()),
        w.seed
    )
}

/// `world.seed` of a `world.toml`.
pub fn recorded_seed(world_toml: &str) -> Option<u64> {
    let v: toml::Table = toml::from_str(world_toml).ok()?;
    let seed = v.get("world")?.get("seed")?.as_integer()?;
    u64::try_from(seed).ok()
}

/// Generates one world and writes its folder, then its run facts beside it.
fn make_world(source: &Source, w: &Planned, opts: &Options) -> Result<()> {
    let mut p = source.pipeline.clone();
    p.world.seed = w.seed;
    let started = Instant::now();
    let description = format!(
        "{} (dataset world {} of base seed {})",
        source.description, w.index, opts.seed
    );
    let budget = crate::memory::per_world(&opts.max_memory, opts.jobs);
    let world = make::generate(&p, &source.registry, &description, &budget)?;
    let generation_s = started.elapsed().as_secs_f64();
    make::write(&world, &source.exporters, &opts.out.join(&w.name), false)?;
    let facts = RunFacts {
        generation_s,
        total_s: started.elapsed().as_secs_f64(),
        visual_triangles: world.mesh.as_ref().map(|m| m.visual.triangle_count()),
        collision_triangles: world.mesh.as_ref().map(|m| m.collision.triangle_count()),
    };
    index::write_facts(&opts.out, &w.name, &facts).map_err(|e| anyhow!(e))
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
        assert!(small.iter().all(|w| w.seed <= i64::MAX as u64));
    }

    #[test]
    fn shards_split_the_list_round_robin() {
        let s: Shard = "2/3".parse().unwrap();
        let owned: Vec<usize> = (0..7).filter(|&k| s.owns(k)).collect();
        assert_eq!(owned, [1, 4]);
        for bad in ["5/4", "0/2", "a/b", "2", "1/0", "-1/2"] {
            let e = bad.parse::<Shard>().unwrap_err();
            assert!(e.contains("write --shard I/N"), "{bad}: {e}");
        }
    }
}
