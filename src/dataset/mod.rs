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
use subtgraph_core::{Components, Pipeline, Registry};

use crate::folder::{FolderError, manifest};
use crate::make;
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
    /// The pipeline's components, built once for every world of this source (they do not
    /// depend on the seed): a mesh-files tile set reads its meshes once per run, not once
    /// per world. Its exporters run in every world folder.
    pub components: Components,
    /// The registry with the pipeline's plugins.
    pub registry: Registry,
}

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
    pub fn zero_based(index: &str, count: &str) -> Result<Shard, String> {
        let help = "write --shard-index K --shard-count N with whole numbers 0 <= K < N \
                    (in a Kubernetes indexed Job: --shard-index $JOB_COMPLETION_INDEX --shard-count \
                    and its completions), or --shard I/N counted from 1";
        let n = count
            .trim()
            .parse::<usize>()
            .ok()
            .filter(|&n| n >= 1)
            .ok_or_else(|| {
                format!("--shard-count '{count}' is not a whole number of at least 1; {help}")
            })?;
        let k = index
            .trim()
            .parse::<usize>()
            .map_err(|_| format!("--shard-index '{index}' is not a whole number; {help}"))?;
        if k >= n {
            return Err(format!(
                "--shard-index {k} is out of range for --shard-count {n}: the index is 0-based, from 0 to {}; {help}",
                n - 1
            ));
        }
        Ok(Shard {
            index: k + 1,
            count: n,
        })
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
                "--shard {i}/{n} is out of range: I must be between 1 and N (N >= 1); {help}; \
                 for a 0-based index (Kubernetes' JOB_COMPLETION_INDEX) write \
                 --shard-index K --shard-count N"
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
    /// Complete worlds found and kept, also those another process (a shard writing into the
    /// same folder) finished while this run ran.
    pub skipped: usize,
    /// Worlds another process on this machine was still making when this run ended, with its
    /// process id: left to it (its own run indexes them when it ends).
    pub elsewhere: Vec<(String, u32)>,
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
    let all = plan(&names, opts.count, opts.seed);
    prepare_out(&opts.out, &all)?;
    let mine: Vec<&Planned> = all
        .iter()
        .enumerate()
        .filter(|(k, _)| opts.shard.owns(*k))
        .map(|(_, w)| w)
        .collect();

    // Decide what to make before making anything: a folder of another dataset, or made with
    // other options, is an error; a damaged world of this one is made again.
    let mut todo = Vec::new();
    let mut damaged = Vec::new();
    let mut skipped = 0;
    // Worlds another live process on this machine is writing now are left to it.
    let writing = being_written(&opts.out);
    let mut busy = Vec::new();
    for w in &mine {
        if let Some(&pid) = writing.get(&w.name) {
            busy.push((*w, pid));
            continue;
        }
        let expected = expected_world_toml(&sources[w.source], w, opts)?;
        match existing(&opts.out, w, &expected)? {
            Existing::Complete => skipped += 1,
            Existing::Absent => todo.push(*w),
            Existing::Damaged(why) => {
                eprintln!("note: {} is incomplete ({why}); making it again", w.name);
                todo.push(*w);
                damaged.push(w.name.clone());
            }
        }
    }

    let progress = Mutex::new(progress::Progress::new(todo.len(), skipped));
    let next = AtomicUsize::new(0);
    let failures = Mutex::new(Vec::new());
    let meanwhile = AtomicUsize::new(0);
    let jobs = opts.jobs.clamp(1, todo.len().max(1));
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| {
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    let Some(w) = todo.get(k) else { break };
                    let replace = damaged.contains(&w.name);
                    let result = make_world(&sources[w.source], w, opts, replace);
                    match &result {
                        Ok(Made::Here) => {}
                        Ok(Made::Elsewhere) => {
                            meanwhile.fetch_add(1, Ordering::Relaxed);
                        }
                        Err(e) => failures
                            .lock()
                            .expect("no worker panics holding it")
                            .push(format!("{}: {e:#}", w.name)),
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
    let meanwhile = meanwhile.into_inner();
    // The worlds other processes were making: finished by now, or still theirs.
    let mut elsewhere = Vec::new();
    for (w, pid) in busy {
        let expected = expected_world_toml(&sources[w.source], w, opts)?;
        match existing(&opts.out, w, &expected) {
            Ok(Existing::Complete) => skipped += 1,
            _ => elsewhere.push((w.name.clone(), pid)),
        }
    }
    if meanwhile > 0 {
        eprintln!(
            "note: {meanwhile} world(s) were made by another process writing into the same folder (a shard) while this run made them: kept"
        );
    }
    if !elsewhere.is_empty() {
        let list: Vec<String> = elsewhere
            .iter()
            .map(|(name, pid)| format!("{name} (process {pid})"))
            .collect();
        eprintln!(
            "note: {} world(s) are being made by another process writing into the same folder, left to it: {}; that run indexes them when it ends (or run this command again then)",
            elsewhere.len(),
            subtgraph_core::error::excerpt_to(&list.join(", "), 400)
        );
    }
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
        made: todo.len() - meanwhile,
        skipped: skipped + meanwhile,
        elsewhere,
        indexed,
    })
}

/// Creates the dataset folder and checks it can be written to, before any world is made. A
/// folder that is not a dataset's yet must hold nothing but this dataset's worlds: the index
/// files written there would replace a user's files of the same names.
fn prepare_out(out: &Path, all: &[Planned]) -> Result<()> {
    if out.exists() && !out.is_dir() {
        bail!(
            "--out {} is a file; give a folder for the dataset",
            out.display()
        );
    }
    if out.is_dir() && !out.join(index::FACTS_DIR).is_dir() {
        let mut foreign: Vec<String> = std::fs::read_dir(out)
            .with_context(|| format!("reading --out {}", out.display()))?
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| {
                // Another run starting into the same folder at the same time (a shard) may
                // have its write probe there before it marks the folder.
                let temporary = n.starts_with('.')
                    && (n.contains(".partial-") || n.starts_with(".write-test-"));
                !temporary && !all.iter().any(|w| &w.name == n)
            })
            .collect();
        foreign.sort();
        if !foreign.is_empty() {
            bail!(
                "--out {} already holds files that are not this dataset's ({}); give a new or empty folder",
                out.display(),
                subtgraph_core::error::excerpt_to(&foreign.join(", "), 200)
            );
        }
    }
    // The facts folder marks it as a dataset's before anything else is written into it, so
    // shards starting at the same time see each other's files as this dataset's.
    std::fs::create_dir_all(out.join(index::FACTS_DIR)).with_context(|| {
        format!(
            "cannot create the dataset folder --out {}; choose a folder you can write to",
            out.display()
        )
    })?;
    match crate::folder::sweep_stale(out) {
        Ok(0) | Err(_) => {}
        Ok(n) => {
            eprintln!("note: removed {n} unfinished world folder(s) left by runs that were killed")
        }
    }
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

/// The worlds another live process on this machine is writing into `out` now (its hidden
/// `.NAME.partial-*` folder, whose manifest names the process), by name, with the process id.
/// A process on another machine cannot be asked whether it is alive: its worlds are made here
/// too, and whichever process finishes a world second keeps the first one's.
fn being_written(out: &Path) -> std::collections::BTreeMap<String, u32> {
    let here = manifest::Owner::this_process();
    let Ok(entries) = std::fs::read_dir(out) else {
        return Default::default();
    };
    entries
        .flatten()
        .filter_map(|e| {
            let file = e.file_name().to_string_lossy().into_owned();
            let (name, _) = file.strip_prefix('.')?.split_once(".partial-")?;
            match manifest::read(&e.path())? {
                manifest::Manifest::Partial(owner)
                    if owner.host == here.host && owner.pid != here.pid && !owner.is_dead() =>
                {
                    Some((name.to_owned(), owner.pid))
                }
                _ => None,
            }
        })
        .collect()
}

/// What the dataset folder holds for a planned world.
#[derive(Debug, PartialEq)]
enum Existing {
    /// The complete world this run would make.
    Complete,
    /// Nothing.
    Absent,
    /// This world, but with files missing or cut short: made again, replacing only the files
    /// subtgraph wrote.
    Damaged(String),
}

/// The `world.toml` this run writes for world `w`.
fn expected_world_toml(source: &Source, w: &Planned, opts: &Options) -> Result<String> {
    let mut p = source.pipeline.clone();
    p.world.seed = w.seed;
    make::expected_world_toml(&p, &description(source, w, opts))
}

fn description(source: &Source, w: &Planned, opts: &Options) -> String {
    format!(
        "{} (dataset world {} of base seed {})",
        source.description, w.index, opts.seed
    )
}

/// Whether a planned world is already there, complete and made with this run's options
/// (its `world.toml` is byte for byte the one this run would write). A world made with other
/// options (another `--tileset`, `--format`, pipeline or version) or of another dataset is an
/// error naming the difference; nothing is deleted to make room for this run.
fn existing(out: &Path, w: &Planned, expected_toml: &str) -> Result<Existing> {
    let dir = out.join(&w.name);
    if std::fs::symlink_metadata(&dir).is_err() {
        return Ok(Existing::Absent);
    }
    let listed = match manifest::read(&dir) {
        Some(manifest::Manifest::Complete(listed)) => listed,
        _ => {
            let seed = std::fs::read_to_string(dir.join("world.toml"))
                .ok()
                .and_then(|t| recorded_seed(&t));
            match seed {
                Some(seed) if seed != w.seed => bail!(
                    "{} holds a world of seed {seed}, but this dataset's world of that name has seed {}: it belongs to another dataset (other --seed or pipeline); give another --out, or move it away",
                    dir.display(),
                    w.seed
                ),
                _ => bail!(
                    "{} is not a complete world written by subtgraph (no {} list of the files it wrote: made by an older version, or by something else); nothing was changed: move it away to have it made again",
                    dir.display(),
                    manifest::FILE
                ),
            }
        }
    };
    let damage = manifest::damage(&dir, &listed);
    if !damage.is_empty() {
        return Ok(Existing::Damaged(damage.join(", ")));
    }
    let toml = std::fs::read_to_string(dir.join("world.toml"))
        .with_context(|| format!("reading {}/world.toml", dir.display()))?;
    if toml == expected_toml {
        return Ok(Existing::Complete);
    }
    if let Some(seed) = recorded_seed(&toml).filter(|&s| s != w.seed) {
        bail!(
            "{} holds a world of seed {seed}, but this dataset's world of that name has seed {}: it belongs to another dataset (other --seed or pipeline); give another --out, or move it away",
            dir.display(),
            w.seed
        );
    }
    bail!(
        "{} was made with other options than this run's ({}); nothing was changed: run with the options it was made with, give another --out, or move it away to have it made again",
        dir.display(),
        first_difference(&toml, expected_toml)
    )
}

/// The first line where a world's `world.toml` and this run's differ (with the line after
/// it, so a new table shows its first key), for messages.
fn first_difference(on_disk: &str, expected: &str) -> String {
    let a: Vec<&str> = on_disk.lines().collect();
    let b: Vec<&str> = expected.lines().collect();
    let n = (0..a.len().max(b.len()))
        .find(|&i| a.get(i) != b.get(i))
        .unwrap_or(0);
    let show = |v: &[&str]| {
        let shown: Vec<&str> = v.iter().skip(n).take(2).copied().collect();
        if shown.is_empty() {
            "nothing".to_owned()
        } else {
            format!(
                "`{}`",
                subtgraph_core::error::excerpt_to(&shown.join(" / "), 100)
            )
        }
    };
    format!(
        "world.toml line {} is {} there and {} in this run",
        n + 1,
        show(&a),
        show(&b)
    )
}

/// `world.seed` of a `world.toml`.
pub fn recorded_seed(world_toml: &str) -> Option<u64> {
    let v: toml::Table = toml::from_str(world_toml).ok()?;
    let seed = v.get("world")?.get("seed")?.as_integer()?;
    u64::try_from(seed).ok()
}

/// Who made a world this run set out to make.
#[derive(Debug, PartialEq, Eq)]
enum Made {
    /// This run.
    Here,
    /// Another process writing into the same folder (a shard), since this run planned it:
    /// the same world, kept.
    Elsewhere,
}

/// Generates one world and writes its folder, then its run facts beside it. A world another
/// process (a shard) wrote since the plan is kept if it is the same world, and ours discarded.
fn make_world(source: &Source, w: &Planned, opts: &Options, replace: bool) -> Result<Made> {
    let mut p = source.pipeline.clone();
    p.world.seed = w.seed;
    let description = description(source, w, opts);
    // Made by another process since the plan: nothing to do.
    if !replace && std::fs::symlink_metadata(opts.out.join(&w.name)).is_ok() {
        let expected = make::expected_world_toml(&p, &description)?;
        if existing(&opts.out, w, &expected)? == Existing::Complete {
            return Ok(Made::Elsewhere);
        }
    }
    let started = Instant::now();
    let budget = crate::memory::per_world(&opts.max_memory, opts.jobs);
    let world = make::generate(&p, &source.components, &description, &budget)?;
    let generation_s = started.elapsed().as_secs_f64();
    if write_world(&world, source, w, opts, replace)? == Made::Elsewhere {
        return Ok(Made::Elsewhere);
    }
    let facts = RunFacts {
        generation_s,
        total_s: started.elapsed().as_secs_f64(),
        visual_triangles: world.mesh().map(|m| m.visual.triangle_count()),
        collision_triangles: world.mesh().map(|m| m.collision.triangle_count()),
    };
    index::write_facts(&opts.out, &w.name, &facts).map_err(|e| anyhow!(e))?;
    Ok(Made::Here)
}

/// Writes a generated world's folder. When the folder appeared while this run made the world
/// (another process writing into the same folder got there first) and holds the same world,
/// that is no failure: [`Made::Elsewhere`], and our copy is discarded. The folder writer's
/// words about `--force` never reach the user: `dataset` has no such flag.
fn write_world(
    world: &subtgraph_core::World,
    source: &Source,
    w: &Planned,
    opts: &Options,
    replace: bool,
) -> Result<Made> {
    let dest = opts.out.join(&w.name);
    let e = match make::write_folder(world, &source.components.exporters, &dest, replace) {
        Ok(()) => return Ok(Made::Here),
        Err(e) => e,
    };
    if !matches!(
        e,
        FolderError::AppearedMeanwhile { .. } | FolderError::Exists(_)
    ) {
        return Err(e.into());
    }
    let mut p = source.pipeline.clone();
    p.world.seed = w.seed;
    let expected = make::expected_world_toml(&p, &description(source, w, opts))?;
    let there = existing(&opts.out, w, &expected);
    if let FolderError::AppearedMeanwhile { kept, .. } = &e {
        if matches!(there, Ok(Existing::Complete)) {
            crate::folder::remove_listed(kept)
                .with_context(|| format!("removing the duplicate {}", kept.display()))?;
            return Ok(Made::Elsewhere);
        }
        return Err(e.into());
    }
    match there {
        Ok(Existing::Complete) => Ok(Made::Elsewhere),
        // Another dataset's world, or one made with other options: that message says what to do.
        Err(other) => Err(other),
        Ok(_) => bail!(
            "{} appeared while this run was making it, and does not hold this world complete; nothing was changed: run the same command again to make it",
            dest.display()
        ),
    }
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
        assert!(
            "0/2"
                .parse::<Shard>()
                .unwrap_err()
                .contains("--shard-index K --shard-count N")
        );
        // K of N counted from 0 is the same shard as K+1 of N counted from 1.
        for n in 1..5 {
            for k in 0..n {
                let one: Shard = format!("{}/{n}", k + 1).parse().unwrap();
                assert_eq!(Shard::zero_based(&k.to_string(), &n.to_string()), Ok(one));
            }
            let e = Shard::zero_based(&n.to_string(), &n.to_string()).unwrap_err();
            assert!(e.contains("out of range"), "{e}");
        }
    }

    #[test]
    fn a_world_another_process_wrote_since_the_plan_is_kept_not_a_failure() {
        let dir = tempfile::tempdir().unwrap();
        let mut pipeline = crate::presets::load("cave").unwrap();
        pipeline.tileset = None;
        let registry = crate::registry();
        let source = Source {
            name: "cave".into(),
            description: "preset cave".into(),
            components: pipeline.build(&registry).unwrap(),
            pipeline,
            registry,
        };
        let opts = Options {
            count: 1,
            seed: 5,
            out: dir.path().join("d"),
            jobs: 1,
            shard: Shard::ALL,
            max_memory: subtgraph_core::Budget::unlimited(),
        };
        let sources = std::slice::from_ref(&source);
        // This run planned cave-0000; another process then made it.
        run(sources, &opts).unwrap();
        let w = &plan(&["cave"], 1, 5)[0];
        let before = std::fs::read(opts.out.join("cave-0000/topology.json")).unwrap();
        let made = make_world(&source, w, &opts, false);
        assert_eq!(
            made.expect("the same world, made meanwhile, is no failure"),
            Made::Elsewhere
        );
        // The same, when it appears while this run generates it (after the check above).
        let mut p = source.pipeline.clone();
        p.world.seed = w.seed;
        let world = make::generate(
            &p,
            &source.components,
            &description(&source, w, &opts),
            &opts.max_memory,
        )
        .unwrap();
        assert_eq!(
            write_world(&world, &source, w, &opts, false).unwrap(),
            Made::Elsewhere
        );
        assert_eq!(
            std::fs::read(opts.out.join("cave-0000/topology.json")).unwrap(),
            before
        );
        // A folder of another dataset that appears meanwhile is an error naming real flags.
        let other = Planned {
            seed: w.seed + 1,
            ..w.clone()
        };
        let e = write_world(&world, &source, &other, &opts, false).unwrap_err();
        let text = format!("{e:#}");
        assert!(text.contains("belongs to another dataset"), "{text}");
        assert!(!text.contains("--force"), "{text}");
        let leftovers = std::fs::read_dir(&opts.out)
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .file_name()
                    .to_string_lossy()
                    .contains("partial")
            })
            .count();
        assert_eq!(leftovers, 0);
    }
}
