//! Datasets: many worlds per source (a pipeline file or a preset), made in parallel, one whole
//! world per worker at a time, resumable, and splittable over machines.
//!
//! Every world's seed is `derive_seed(base seed, source name, index)` (the core's
//! [`subtgraph_core::rng::derive_seed`]), so a world depends only on its source, the base seed
//! and its index: not on `--jobs`, not on `--shard`, not on which worlds were made before. Each
//! world is a normal world folder (`cave-0000/`, ...) written atomically by
//! [`crate::pipeline::write_folder`]; its `world.toml` records its seed and resolved configuration and
//! regenerates it on its own.
//!
//! Timings differ between runs, so they are kept out of the world folders (which are
//! byte-identical whatever the run): each world's generation time and triangle counts go to
//! `.index/NAME.json` beside it, and from there into `index.json` and `index.csv`, which are
//! rebuilt from the folders at the end of every run ([`index`]).

mod existing;
pub mod explore;
pub mod index;
mod plan;
mod progress;
mod run;
pub mod sense;
mod shard;

use std::path::PathBuf;

use subtgraph_core::{Components, Pipeline, Registry};
use subtgraph_sensors::SenseRequest;

use crate::pipeline::{self, Adjustments, PipelineSource};
use crate::{Error, Frontend};

pub use existing::recorded_seed;
pub use plan::{Planned, plan, world_seed};
pub use run::run;
pub use shard::Shard;

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
    /// A sensor sequence per world, as this request asks (its `world`, `out` and `force` are
    /// set per world): [`sense::sense_worlds`] after the worlds.
    pub sense: Option<SenseRequest>,
    /// Plugin libraries given besides the pipelines' (`--plugin`): with the pipelines' own,
    /// the ones the worlds may be rebuilt with for sensing.
    pub plugins: Vec<PathBuf>,
    /// A mission per world, run and scored ([`explore::explore_worlds`]) after the worlds.
    pub explore: Option<crate::ExploreRequest>,
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
    /// The sequences of `--sense`.
    pub sensed: Option<sense::Sensed>,
    /// The runs of `--explore`.
    pub explored: Option<explore::Explored>,
}

/// What `dataset` is asked to make.
#[derive(Clone, Debug)]
pub struct DatasetRequest {
    /// Pipeline files (the folder names are their file stems).
    pub pipelines: Vec<PathBuf>,
    /// Built-in presets.
    pub presets: Vec<String>,
    /// Worlds per source.
    pub count: usize,
    /// The base seed every world's seed derives from (0 to 2^63 - 1).
    pub seed: u64,
    /// The dataset folder.
    pub out: PathBuf,
    /// Worker threads (default: the available parallelism).
    pub jobs: Option<usize>,
    /// This machine's share.
    pub shard: Shard,
    /// `--tileset`, `--no-mesh`, `--format`, for every source.
    pub adjust: Adjustments,
    /// Plugin libraries besides the pipelines' `[plugins] paths`.
    pub plugins: Vec<PathBuf>,
    /// `--max-memory` for the whole run (default: 3/4 of physical memory).
    pub max_memory: Option<String>,
    /// Who asks (how options are named in messages).
    pub frontend: Frontend,
    /// A sensor sequence per world (`--sense`), as this request asks; `ground-truth` is added
    /// to every world's formats (the routes follow its graph).
    pub sense: Option<SenseRequest>,
    /// A mission per world (`--explore`), as this request asks, run and scored; `ground-truth`
    /// is added to every world's formats and `[artifacts]` (the defaults) to a pipeline
    /// without one.
    pub explore: Option<crate::ExploreRequest>,
}

impl Default for DatasetRequest {
    fn default() -> Self {
        DatasetRequest {
            pipelines: Vec::new(),
            presets: Vec::new(),
            count: 1,
            seed: 1,
            out: PathBuf::new(),
            jobs: None,
            shard: Shard::ALL,
            adjust: Adjustments::default(),
            plugins: Vec::new(),
            max_memory: None,
            frontend: Frontend::Cli,
            sense: None,
            explore: None,
        }
    }
}

impl DatasetRequest {
    /// The run's options, its numbers checked (the memory budget, the seed, at least one
    /// world, one job and one source) and `--out` checked, before any pipeline is read or any
    /// world made.
    pub fn options(&self) -> Result<Options, Error> {
        let max_memory = crate::memory::budget(self.max_memory.as_deref())?;
        let f = self.frontend;
        let seed = pipeline::check_seed(self.seed, f)?;
        if self.count == 0 {
            return Err(Error::Usage(format!(
                "{} must be at least 1 (worlds per source)",
                f.option("count")
            )));
        }
        if self.jobs == Some(0) {
            return Err(Error::Usage(format!(
                "{} must be at least 1",
                f.option("jobs")
            )));
        }
        if self.pipelines.is_empty() && self.presets.is_empty() {
            return Err(Error::Usage(match f {
                Frontend::Cli => format!(
                    "name at least one source: a pipeline file, or --preset NAME ({})",
                    crate::presets::names()
                ),
                Frontend::Python => format!(
                    "name at least one source: pipelines=[...] or presets=[...] ({})",
                    crate::presets::names()
                ),
            }));
        }
        if let Some(template) = &self.sense {
            if self.adjust.no_mesh {
                return Err(Error::Usage(format!(
                    "{} needs the worlds' geometry (the LiDAR's rays hit the mesh): leave out {}",
                    f.option("sense"),
                    f.option("no-mesh")
                )));
            }
            sense::check(template)?;
        }
        if let Some(template) = &self.explore {
            if self.adjust.no_mesh {
                return Err(Error::Usage(format!(
                    "{} needs the worlds' geometry (robots drive through the mesh): leave out {}",
                    f.option("explore"),
                    f.option("no-mesh")
                )));
            }
            explore::check(template)?;
        }
        let names: Vec<String> = self.chosen().map(|s| s.name()).collect();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        let mut reading: Vec<&std::path::Path> =
            self.pipelines.iter().map(PathBuf::as_path).collect();
        reading.extend(self.plugins.iter().map(PathBuf::as_path));
        run::check_out(&self.out, &plan(&names, self.count, seed), &reading)?;
        Ok(Options {
            count: self.count,
            seed,
            out: self.out.clone(),
            jobs: self.jobs.unwrap_or_else(|| {
                std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
            }),
            shard: self.shard,
            max_memory,
            sense: self.sense.clone(),
            plugins: self.plugins.clone(),
            explore: self.explore.clone(),
        })
    }

    /// Where the sources come from: pipeline files first, then presets.
    fn chosen(&self) -> impl Iterator<Item = PipelineSource> + '_ {
        self.pipelines
            .iter()
            .map(|p| PipelineSource::File(p.clone()))
            .chain(
                self.presets
                    .iter()
                    .map(|n| PipelineSource::Preset(n.clone())),
            )
    }

    /// Every source (pipeline files first, then presets), each with its registry (plus what
    /// `extend` adds: the Python package's components) and components, built once for all its
    /// worlds; and the exporters left out under `--no-mesh`, each named once.
    pub fn sources(
        &self,
        extend: &mut dyn FnMut(&mut Registry) -> Result<(), Error>,
    ) -> Result<(Vec<Source>, Vec<String>), Error> {
        let chosen = self.chosen();
        let mut sources = Vec::new();
        let mut skipped: Vec<String> = Vec::new();
        for from in chosen {
            let (mut p, description) = from.load()?;
            self.adjust.apply(&mut p)?;
            if self.sense.is_some() || self.explore.is_some() {
                pipeline::add_formats(&mut p, &["ground-truth".to_owned()])?;
            }
            if self.explore.is_some() && p.artifacts.is_none() {
                p.artifacts = Some(Default::default());
            }
            let mut registry = crate::registry_with(&p, &self.plugins)?;
            extend(&mut registry)?;
            let (components, left_out) = pipeline::build(&p, &registry, self.adjust.no_mesh)?;
            for name in left_out {
                if !skipped.contains(&name) {
                    skipped.push(name);
                }
            }
            sources.push(Source {
                name: from.name(),
                description,
                pipeline: p,
                components,
                registry,
            });
        }
        Ok((sources, skipped))
    }

    /// Checks the options, builds the sources and makes the worlds (the command line).
    pub fn run(&self) -> Result<(Summary, Vec<String>), Error> {
        let opts = self.options()?;
        let (sources, skipped) = self.sources(&mut |_| Ok(()))?;
        Ok((run(&sources, &opts)?, skipped))
    }
}
