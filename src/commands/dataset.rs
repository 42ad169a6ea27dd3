//! `subtgraph dataset`.

use std::path::PathBuf;
use std::time::Instant;

use subtgraph::app::dataset::Shard;
use subtgraph::app::pipeline::Adjustments;
use subtgraph::app::{DatasetRequest, Error, ExploreRequest, SenseRequest};

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
    /// Also write a sensor sequence of every world (LiDAR, IMU and poses, as `subtgraph
    /// sense` writes it) to OUT/sequences/NAME; adds ground-truth to every world's formats.
    #[arg(long)]
    sense: bool,
    /// With --sense: seconds of each world's route (default: the whole route; a cave's
    /// out-and-back is about 15 minutes and 13 GB).
    #[arg(long, value_name = "SECONDS", requires = "sense")]
    sense_duration: Option<f64>,
    /// With --sense: out-and-back, loop, levels or coverage.
    #[arg(
        long,
        value_name = "ROUTE",
        default_value = "out-and-back",
        requires = "sense"
    )]
    sense_route: String,
    /// With --sense: ground or aerial.
    #[arg(long, value_name = "P", default_value = "ground", requires = "sense")]
    sense_platform: String,
    /// With --sense: the LiDAR (what `sense --lidar` takes).
    #[arg(
        long,
        value_name = "MODEL",
        default_value = subtgraph_sensors::lidar::DEFAULT,
        requires = "sense"
    )]
    sense_lidar: String,
    /// With --sense: the outputs besides sequence.json and ground_truth.tum: bag, kitti
    /// (default both).
    #[arg(long, value_name = "LIST", requires = "sense")]
    sense_format: Vec<String>,
    /// With --sense: cameras too: mono, stereo, fisheye-stereo, d435i, or a camera table
    /// FILE.toml.
    #[arg(long, value_name = "MODEL", requires = "sense")]
    sense_camera: Option<String>,
    /// Also explore every world as `subtgraph explore` does (the frontier baseline by
    /// default) and score each run: OUT/runs/NAME and OUT/scores/NAME (then `subtgraph report
    /// frontier=OUT/scores`); adds ground-truth to every world's formats and [artifacts] to a
    /// pipeline without one.
    #[arg(long)]
    explore: bool,
    /// With --explore: robots per world.
    #[arg(long, value_name = "N", default_value_t = 1, requires = "explore")]
    robots: usize,
    /// With --explore: simulated seconds per world.
    #[arg(
        long,
        value_name = "SECONDS",
        default_value_t = 600.0,
        requires = "explore"
    )]
    explore_duration: f64,
    /// With --explore: frontier or random.
    #[arg(
        long,
        value_name = "NAME",
        default_value = "frontier",
        requires = "explore"
    )]
    planner: String,
    /// With --explore: ground or aerial.
    #[arg(long, value_name = "P", default_value = "ground", requires = "explore")]
    explore_platform: String,
    /// With --explore: columns a turn of each scan (default 180).
    #[arg(long, value_name = "N", requires = "explore")]
    explore_lidar_columns: Option<usize>,
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
        sense: a.sense.then(|| SenseRequest {
            platform: a.sense_platform,
            route: a.sense_route,
            lidar: a.sense_lidar,
            formats: a.sense_format,
            duration: a.sense_duration,
            camera: a.sense_camera.map(|model| subtgraph::app::CameraRequest {
                model,
                ..Default::default()
            }),
            ..SenseRequest::default()
        }),
        explore: a.explore.then(|| ExploreRequest {
            robots: a.robots,
            duration: a.explore_duration,
            planner: a.planner,
            platform: a.explore_platform,
            lidar_columns: a.explore_lidar_columns,
            ..ExploreRequest::default()
        }),
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
    if let Some(s) = &summary.sensed {
        super::print(&format!(
            "wrote {} sensor sequence(s) ({} scans, {:.1} MB), kept {} complete one(s), in {}\n",
            s.made,
            s.scans,
            s.bytes as f64 / 1e6,
            s.kept,
            a.out
                .join(subtgraph::app::dataset::sense::SEQUENCES_DIR)
                .display()
        ));
    }
    if let Some(e) = &summary.explored {
        super::print(&format!(
            "explored {} world(s) ({:.0} simulated s in {:.1} s), kept {} complete run(s), in {} and scored in {}\n",
            e.made,
            e.simulated_s,
            e.run_s,
            e.kept,
            a.out
                .join(subtgraph::app::dataset::explore::RUNS_DIR)
                .display(),
            a.out
                .join(subtgraph::app::dataset::explore::SCORES_DIR)
                .display()
        ));
    }
    Ok(())
}
