//! `subtgraph dataset`.

use std::path::PathBuf;
use std::time::Instant;

use subtgraph::app::dataset::Shard;
use subtgraph::app::pipeline::Adjustments;
use subtgraph::app::{DatasetRequest, Error};

/// `dataset`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    /// Pipeline TOML files (the folder names are their file stems).
    pipelines: Vec<PathBuf>,
    /// Built-in presets (repeatable): mine, cave, lava-tube.
    #[arg(long = "preset", value_name = "P")]
    presets: Vec<String>,
    /// Worlds per source.
    #[arg(long, value_name = "N")]
    count: usize,
    /// The base seed every world's seed derives from (0 to 2^63 - 1).
    #[arg(long, value_name = "S", default_value_t = 1)]
    seed: u64,
    /// The dataset folder (created; may already hold this dataset's worlds).
    #[arg(long)]
    out: PathBuf,
    /// Worker threads, each making one whole world at a time (default: the available
    /// parallelism). Memory grows with J, not with N; the worlds do not depend on it.
    #[arg(long, value_name = "J")]
    jobs: Option<usize>,
    /// Make only this machine's share, I/N (1-based, like a Slurm array's task id): every
    /// N-th world of the global list from the I-th. The worlds are exactly those of an
    /// unsharded run.
    #[arg(long, value_name = "I/N")]
    shard: Option<String>,
    /// The same share counted from 0, like a Kubernetes indexed Job's
    /// JOB_COMPLETION_INDEX: shard K (0 <= K < N) of --shard-count N.
    #[arg(
        long,
        value_name = "K",
        requires = "shard_count",
        conflicts_with = "shard",
        allow_hyphen_values = true
    )]
    shard_index: Option<String>,
    /// The number of shards, with --shard-index.
    #[arg(
        long,
        value_name = "N",
        requires = "shard_index",
        conflicts_with = "shard",
        allow_hyphen_values = true
    )]
    shard_count: Option<String>,
    /// Grids, graph, maps and non-geometry exports only.
    #[arg(long, conflicts_with = "tileset")]
    no_mesh: bool,
    /// The tile set giving every world its geometry, overriding the pipelines' `[tileset]`.
    #[arg(long, value_name = "T")]
    tileset: Option<String>,
    /// Formats to export in every world besides the pipelines' `[[export]]`s (comma list).
    #[arg(long, value_name = "LIST")]
    format: Vec<String>,
    /// A plugin library to load (repeatable), besides the pipelines' `[plugins] paths`.
    #[arg(long = "plugin", value_name = "PATH")]
    plugins: Vec<PathBuf>,
    /// Memory the whole run may use, like 16G (default: 3/4 of physical memory); each of
    /// the --jobs workers gets its share.
    #[arg(long, value_name = "SIZE")]
    max_memory: Option<String>,
}

/// Makes the dataset and prints what was made.
pub fn run(a: Args) -> Result<(), Error> {
    let shard = match (&a.shard, &a.shard_index, &a.shard_count) {
        (Some(s), _, _) => s.parse::<Shard>()?,
        (None, Some(k), Some(n)) => Shard::zero_based(k, n)?,
        _ => Shard::ALL,
    };
    let request = DatasetRequest {
        pipelines: a.pipelines,
        presets: a.presets,
        count: a.count,
        seed: a.seed,
        out: a.out.clone(),
        jobs: a.jobs,
        shard,
        adjust: Adjustments {
            tileset: a.tileset,
            no_mesh: a.no_mesh,
            formats: a.format,
        },
        plugins: a.plugins,
        max_memory: a.max_memory,
        ..DatasetRequest::default()
    };
    let opts = request.options()?;
    let (sources, skipped) = request.sources(&mut |_| Ok(()))?;
    super::note_skipped(&skipped);
    let started = Instant::now();
    let summary = subtgraph::app::dataset::run(&sources, &opts)?;
    super::print(&format!(
        "made {} world(s), kept {} complete one(s), in {:.1} s; {} lists {} world(s)\n",
        summary.made,
        summary.skipped,
        started.elapsed().as_secs_f64(),
        a.out.join("index.json").display(),
        summary.indexed
    ));
    Ok(())
}
