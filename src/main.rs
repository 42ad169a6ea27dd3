//! The `subtgraph` command line.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use clap::{Parser, Subcommand};

use subtgraph::core::{Layout, Pipeline, World, import, npy};
use subtgraph::presets;

/// Procedural subterranean worlds with controlled topology, for robot simulation.
#[derive(Parser)]
#[command(name = "subtgraph", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Generate a world folder from a pipeline file, a preset, or the built-in defaults.
    ///
    /// Writes world.toml (resolved pipeline), occupancy.npy, topology.json and
    /// maps/level-N.png into --out, atomically: the folder appears complete or not at all.
    Generate {
        /// A pipeline TOML file (see examples/). Without it and without --preset, the built-in
        /// defaults are used: the cave preset.
        pipeline: Option<PathBuf>,
        /// A built-in preset: mine, cave or lava-tube.
        #[arg(long, conflicts_with = "pipeline")]
        preset: Option<String>,
        /// Seed, overriding the pipeline's `world.seed` (0 to 2^63 - 1).
        #[arg(long)]
        seed: Option<u64>,
        /// The world folder to write.
        #[arg(long)]
        out: PathBuf,
        /// Replace --out if it is an existing world folder.
        #[arg(long)]
        force: bool,
        /// The tile set giving the world its geometry (mine, cave, lava-tube), overriding the
        /// pipeline's `[tileset]`.
        #[arg(long, value_name = "NAME")]
        tileset: Option<String>,
        /// Grids, graph and maps only: no geometry even if the pipeline has a `[tileset]`
        /// (exporters that write geometry are skipped, with a note).
        #[arg(long, conflicts_with = "tileset")]
        no_mesh: bool,
        /// Formats to export besides the pipeline's `[[export]]`s, separated by commas:
        /// obj, gltf, sdf, urdf, mjcf, usd, and the ground-truth files (see `plugins list`).
        #[arg(long, value_name = "LIST")]
        format: Vec<String>,
        /// A plugin library to load (repeatable), besides the pipeline's `[plugins] paths`.
        #[arg(long = "plugin", value_name = "PATH")]
        plugins: Vec<PathBuf>,
        /// Instead of generating, import an occupancy grid (.npy; the original's spatial,
        /// topological or structural encodings, or plain 0/1). The pipeline or preset still
        /// sets the scale (tile pitch, level height).
        #[arg(long, value_name = "FILE.npy")]
        occupancy: Option<PathBuf>,
        /// Memory the run may use, like 16G or 512M (default: 3/4 of physical memory). A world
        /// whose grid or meshes would need more is refused before it is made, with its estimate.
        #[arg(long, value_name = "SIZE")]
        max_memory: Option<String>,
    },
    /// Make a dataset: COUNT worlds per source (pipeline files and presets), in parallel.
    ///
    /// World i of source NAME gets the seed derive_seed(--seed, NAME, i) and the folder
    /// OUT/NAME-000i, written atomically. Complete worlds are kept, so an interrupted run
    /// resumes where it stopped. OUT/index.json and OUT/index.csv list every world folder.
    Dataset {
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
    },
    /// Variability statistics of worlds (the paper's "Topological Analysis"): IoU, mirror
    /// asymmetry, tile mix, sizes, constraint satisfaction, graph statistics; JSON, CSV and
    /// plots (SVG and PNG).
    Stats {
        /// World folders, dataset folders (holding world folders), or folders of the original
        /// tool's .npy grids. Each argument is one group in the report.
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        /// The report folder (created; files in it are replaced).
        #[arg(long)]
        out: PathBuf,
        /// How pairwise IoU treats grids of different sizes: `common` crops both to the rows
        /// and columns they share (the top-left corner), `pad` pads the smaller with empty
        /// cells (the union counts everything).
        #[arg(long, default_value = "common", value_name = "common|pad")]
        crop: String,
    },
    /// Check a pipeline file: syntax, keys, component names, that its layout can be made and
    /// that the tile set can build it. No mesh is made (`generate` makes it), so this is quick
    /// even for large worlds.
    Validate {
        /// The pipeline TOML file.
        pipeline: PathBuf,
        /// A plugin library to load (repeatable), besides the pipeline's `[plugins] paths`.
        #[arg(long = "plugin", value_name = "PATH")]
        plugins: Vec<PathBuf>,
    },
    /// Plugins: list what plugin libraries register.
    Plugins {
        #[command(subcommand)]
        command: PluginsCommand,
    },
    /// List the built-in presets.
    Presets,
    /// Grade a robot's run against a world's ground truth: artifact reports by the DARPA
    /// rule (same class within 5 m, each artifact once), and a map's coverage of the free
    /// space (per level and graph edge) and error. JSON, CSV, a picture per level.
    Score {
        /// A world folder generated with [artifacts] (and free-space ground truth for --map).
        world: PathBuf,
        /// The team's reports: CSV with columns time,class,x,y,z, or a JSON list of them.
        #[arg(long)]
        reports: PathBuf,
        /// The robot's map in the world frame: a PLY or PCD point cloud, or an occupancy .npy
        /// on the grid of ground_truth/free_space.npy.
        #[arg(long, value_name = "CLOUD")]
        map: Option<PathBuf>,
        /// A free voxel within this many metres of a mapped point counts as covered.
        #[arg(long, default_value_t = 1.0, value_name = "METRES")]
        radius: f64,
        /// A mapped point farther than this many metres from the surface is a map error.
        #[arg(long, default_value_t = 0.5, value_name = "METRES")]
        tolerance: f64,
        /// The score folder (must not exist, unless --force and the tool wrote it).
        #[arg(long)]
        out: PathBuf,
        /// Replace a score folder written earlier.
        #[arg(long)]
        force: bool,
    },
    /// Draw a shaded perspective picture of a world's mesh (no GPU needed).
    Preview {
        /// A world folder generated with a tile set.
        world: PathBuf,
        /// The PNG to write.
        #[arg(long)]
        out: PathBuf,
        /// Picture size, WIDTHxHEIGHT pixels.
        #[arg(long, default_value = "1280x800")]
        size: String,
        /// Draw the few tiles around the start (or --at NODE) instead of the whole world.
        #[arg(long, conflicts_with = "inside")]
        close_up: bool,
        /// Draw what a robot sees from inside the passage at the start (or --at NODE), 1.5 m
        /// above its floor, looking along its first passage.
        #[arg(long)]
        inside: bool,
        /// The graph node (an id of topology.json) a --close-up or --inside picture is taken at.
        #[arg(long, value_name = "NODE")]
        at: Option<usize>,
        /// lamp: a light just above the camera that falls off with distance, as a robot's lamp
        /// shows a passage (the default with --inside); sun: a fixed light from above, the same
        /// at every distance (the default from outside, where a lamp at the far camera lights
        /// every face alike).
        #[arg(long, value_name = "lamp|sun")]
        light: Option<String>,
    },
    /// Record a sensor sequence along a route through a world: a LiDAR, an IMU and ground-truth
    /// poses, as a ROS 2 bag (bag/), a KITTI folder (kitti/), ground_truth.tum and
    /// sequence.json (models, extrinsics, route, a label per scan). No simulator needed.
    Sense(Box<SenseArgs>),
}

/// `subtgraph sense`'s arguments (see `subtgraph_sensors::SenseRequest`).
#[derive(clap::Args)]
struct SenseArgs {
    /// A world folder made with ground truth (`generate --format ground-truth`).
    world: PathBuf,
    /// The sequence folder to write (must not exist, unless --force and subtgraph wrote it).
    #[arg(long)]
    out: PathBuf,
    /// ground (a wheeled robot: corridors and ramps) or aerial (a quadrotor: shafts too).
    #[arg(long, default_value = "ground")]
    platform: String,
    /// out-and-back (to the farthest dead end and back), loop, levels or coverage.
    #[arg(long, default_value = "out-and-back")]
    route: String,
    /// os1-32, os1-64, os1-128, vlp-16, mid-360, or a LiDAR table FILE.toml.
    #[arg(long, default_value = "os1-32", value_name = "MODEL")]
    lidar: String,
    /// Scans a second, instead of the model's (1 to 50).
    #[arg(long, value_name = "HZ")]
    lidar_rate: Option<f64>,
    /// Farthest return in metres, instead of the model's.
    #[arg(long, value_name = "METRES")]
    max_range: Option<f64>,
    /// IMU samples a second (10 to 4000).
    #[arg(long, default_value_t = 200.0, value_name = "HZ")]
    imu_rate: f64,
    /// Seconds added to the IMU's time stamps (a clock offset, -1 to 1).
    #[arg(
        long,
        default_value_t = 0.0,
        value_name = "SECONDS",
        allow_hyphen_values = true
    )]
    imu_time_offset: f64,
    /// Outputs besides sequence.json and ground_truth.tum: bag, kitti (default both).
    #[arg(long, value_name = "LIST")]
    format: Vec<String>,
    /// Also publish wheel odometry on /wheel/odom (ground platform).
    #[arg(long)]
    wheel_odometry: bool,
    /// No range noise, no IMU noise or drift.
    #[arg(long)]
    noiseless: bool,
    /// Stop after this many seconds of the route.
    #[arg(long, value_name = "SECONDS")]
    duration: Option<f64>,
    /// Seed of the route's choices and the noise (default: the world's seed).
    #[arg(long)]
    seed: Option<u64>,
    /// The most disk the folder may take, like 20G (default: the free space less 1 GB).
    #[arg(long, value_name = "SIZE")]
    max_disk: Option<String>,
    /// Replace --out if it is a folder subtgraph wrote.
    #[arg(long)]
    force: bool,
}

#[derive(Subcommand)]
enum PluginsCommand {
    /// Load plugin libraries and list the components each registers (without PATH: the
    /// built-in components).
    List {
        /// Plugin libraries (.so, .dylib, .dll).
        paths: Vec<PathBuf>,
    },
}

use subtgraph::make::{self, registry_with};

/// The layout of a pipeline's world, checked by its tile set (passages that fit the tiles and
/// the levels), without meshing. Every component is built once, exporters included.
fn validate_layout(
    p: &Pipeline,
    registry: &subtgraph::core::Registry,
) -> Result<Layout, subtgraph::core::Error> {
    let components = p.build(registry)?;
    let layout =
        subtgraph::core::layout_with(p, &components, &subtgraph::core::Budget::unlimited())?;
    if let Some(t) = &components.tileset {
        t.tileset
            .check(&layout)
            .map_err(|e| subtgraph::core::Error::Component {
                component: "tile set",
                name: t.name.clone(),
                message: e.to_string(),
            })?;
    }
    Ok(layout)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    subtgraph::folder::install_signal_handlers();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // Every message passes through `shorten`, so no path that echoes a user's value can
            // print a huge one whole.
            eprintln!(
                "error: {}",
                subtgraph::core::error::shorten(&make::message(&e))
            );
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Generate {
            pipeline,
            preset,
            seed,
            out,
            force,
            tileset,
            no_mesh,
            format,
            plugins,
            occupancy,
            max_memory,
        } => {
            let budget = subtgraph::memory::budget(max_memory.as_deref())?;
            let (mut p, source) = make::load_pipeline(pipeline.as_deref(), preset.as_deref())?;
            if let Some(name) = tileset {
                p.tileset = Some(subtgraph::core::params::ComponentSpec::named(&name));
            }
            if no_mesh {
                p.tileset = None;
            }
            if let Some(seed) = seed {
                if seed > i64::MAX as u64 {
                    bail!("--seed must be at most 2^63 - 1 (9223372036854775807)");
                }
                p.world.seed = seed;
            }
            make::add_formats(&mut p, &format)?;
            let registry = registry_with(&p, &plugins)?;
            let components = make::build(&p, &registry, no_mesh)?;
            let started = Instant::now();
            let world = match occupancy {
                Some(npy_path) => {
                    let layout = import_world(&npy_path, &p, &budget)?;
                    let mesh = match &components.tileset {
                        Some(t) => Some(
                            subtgraph::core::assembly::assemble_within(
                                &layout,
                                t.tileset.as_ref(),
                                &budget,
                            )
                            .map_err(|e| anyhow!("tile set '{}': {e}", t.name))?,
                        ),
                        None => None,
                    };
                    World::new(layout, mesh)
                }
                None => make::generate(&p, &components, &source, &budget)?,
            };
            let generated_in = started.elapsed();
            subtgraph_plugins::check_failures().map_err(|e| anyhow!(e))?;
            let writing = Instant::now();
            make::write(&world, &components.exporters, &out, force)?;
            print_summary(&world, &out, generated_in);
            print_written(&out, writing.elapsed());
            Ok(())
        }
        Command::Dataset {
            pipelines,
            presets: preset_names,
            count,
            seed,
            out,
            jobs,
            shard,
            shard_index,
            shard_count,
            no_mesh,
            tileset,
            format,
            plugins,
            max_memory,
        } => {
            use subtgraph::dataset;
            let max_memory = subtgraph::memory::budget(max_memory.as_deref())?;
            let shard = match (shard, shard_index, shard_count) {
                (Some(s), _, _) => s.parse::<dataset::Shard>().map_err(|e| anyhow!(e))?,
                (None, Some(k), Some(n)) => {
                    dataset::Shard::zero_based(&k, &n).map_err(|e| anyhow!(e))?
                }
                _ => dataset::Shard::ALL,
            };
            if seed > i64::MAX as u64 {
                bail!("--seed must be at most 2^63 - 1 (9223372036854775807)");
            }
            if count == 0 {
                bail!("--count must be at least 1 (worlds per source)");
            }
            if jobs == Some(0) {
                bail!("--jobs must be at least 1");
            }
            if pipelines.is_empty() && preset_names.is_empty() {
                bail!(
                    "name at least one source: a pipeline file, or --preset NAME ({})",
                    presets::names()
                );
            }
            let chosen = pipelines
                .iter()
                .map(|p| (Some(p.as_path()), None))
                .chain(preset_names.iter().map(|n| (None, Some(n.as_str()))));
            let mut sources = Vec::new();
            let mut skipped_exporters: Vec<String> = Vec::new();
            for (file, preset) in chosen {
                let (source, skipped) = make::dataset_source(
                    file,
                    preset,
                    &make::SourceOptions {
                        tileset: tileset.as_deref(),
                        no_mesh,
                        formats: &format,
                        plugins: &plugins,
                    },
                    &mut |_| Ok(()),
                )?;
                for name in skipped {
                    if !skipped_exporters.contains(&name) {
                        skipped_exporters.push(name);
                    }
                }
                sources.push(source);
            }
            make::note_skipped(&skipped_exporters);
            let opts = dataset::Options {
                count,
                seed,
                out: out.clone(),
                jobs: jobs.unwrap_or_else(|| {
                    std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
                }),
                shard,
                max_memory,
            };
            let started = Instant::now();
            let summary = dataset::run(&sources, &opts)?;
            println!(
                "made {} world(s), kept {} complete one(s), in {:.1} s; {} lists {} world(s)",
                summary.made,
                summary.skipped,
                started.elapsed().as_secs_f64(),
                out.join("index.json").display(),
                summary.indexed
            );
            Ok(())
        }
        Command::Stats { inputs, out, crop } => {
            let crop = crop
                .parse::<subtgraph::stats::Crop>()
                .map_err(|e| anyhow!(e))?;
            let report = subtgraph::stats::run(&inputs, &out, crop)?;
            println!("{report}");
            Ok(())
        }
        Command::Validate { pipeline, plugins } => {
            let (p, _) = make::load_pipeline(Some(&pipeline), None)?;
            let registry = registry_with(&p, &plugins)?;
            let world = match validate_layout(&p, &registry) {
                Ok(w) => w,
                Err(e @ subtgraph::core::Error::Config(_)) => return Err(e.into()),
                Err(e) => {
                    return Err(anyhow!(e).context(format!(
                        "{} is well-formed but its world cannot be made",
                        pipeline.display()
                    )));
                }
            };
            subtgraph_plugins::check_failures().map_err(|e| anyhow!(e))?;
            println!(
                "{}: valid; seed {} makes {} level(s) of {} x {} cells, {} occupied",
                pipeline.display(),
                world.resolved.seed,
                world.resolved.levels,
                world.resolved.rows,
                world.resolved.cols,
                world.occupancy.occupied_count()
            );
            Ok(())
        }
        Command::Score {
            world,
            reports,
            map,
            radius,
            tolerance,
            out,
            force,
        } => {
            let summary = subtgraph::score::run(&subtgraph::score::Options {
                world,
                reports,
                map,
                radius,
                tolerance,
                out,
                force,
            })?;
            println!("{summary}");
            Ok(())
        }
        Command::Preview {
            world,
            out,
            size,
            close_up,
            inside,
            at,
            light,
        } => {
            let (w, h) = size
                .split_once('x')
                .and_then(|(w, h)| Some((w.parse::<usize>().ok()?, h.parse::<usize>().ok()?)))
                .filter(|&(w, h)| (16..=8192).contains(&w) && (16..=8192).contains(&h))
                .ok_or_else(|| {
                    anyhow!("--size must be WIDTHxHEIGHT, 16 to 8192 pixels each, like 1280x800")
                })?;
            let view = if inside {
                subtgraph::preview::View::Inside
            } else if close_up {
                subtgraph::preview::View::CloseUp
            } else {
                subtgraph::preview::View::Whole
            };
            let options = subtgraph::preview::Options {
                width: w,
                height: h,
                view,
                light: match light {
                    Some(name) => name.parse()?,
                    None if inside => subtgraph::preview::Light::Lamp,
                    None => subtgraph::preview::Light::Sun,
                },
                at,
            };
            let drawn = subtgraph::preview::render(&world, &out, &options)?;
            println!(
                "wrote {} ({w} x {h}, {drawn} triangles drawn)",
                out.display()
            );
            Ok(())
        }
        Command::Plugins {
            command: PluginsCommand::List { paths },
        } => {
            if paths.is_empty() {
                let r = subtgraph::registry();
                println!("built-in components:");
                list(&r);
                return Ok(());
            }
            let mut registry = subtgraph::registry();
            for path in &paths {
                let plugin = subtgraph_plugins::load(path, &mut registry)?;
                println!("{} ({})", plugin.info.name, plugin.info.path);
                for (kind, name, summary) in &plugin.components {
                    println!("  {kind:<17} {name:<16} {summary}");
                }
            }
            Ok(())
        }
        Command::Sense(a) => {
            let max_disk = match a.max_disk.as_deref() {
                // The sizes --max-memory takes, said of the disk.
                Some(s) => Some(subtgraph::memory::parse_size(s).map_err(|e| {
                    anyhow!(
                        "{}",
                        e.replace("--max-memory", "--max-disk")
                            .replace("any world", "any sequence")
                    )
                })?),
                None => None,
            };
            let request = subtgraph_sensors::SenseRequest {
                world: a.world,
                out: a.out,
                platform: a.platform,
                route: a.route,
                lidar: a.lidar,
                lidar_rate: a.lidar_rate,
                max_range: a.max_range,
                imu_rate: a.imu_rate,
                imu_time_offset: a.imu_time_offset,
                formats: a.format,
                wheel_odometry: a.wheel_odometry,
                noiseless: a.noiseless,
                duration: a.duration,
                seed: a.seed,
                max_disk,
                force: a.force,
            };
            let started = Instant::now();
            let s = request.run(&subtgraph::sense::CommandLine)?;
            let took = started.elapsed().as_secs_f64();
            println!(
                "wrote {} ({} scans, {:.1} s of sensor time, {:.0} m driven, {} of {} rays returned, {:.1} MB, {} degenerate scans) in {took:.1} s (world rebuilt, ray caster built and route planned in {:.1} s): {:.1} M rays/s, {:.0} scans/s",
                request.out.display(),
                s.scans,
                s.duration_s,
                s.route_length_m,
                s.returns,
                s.rays,
                s.bytes as f64 / 1e6,
                s.degenerate_scans,
                s.prepare_s,
                s.rays as f64 / took / 1e6,
                s.scans as f64 / took
            );
            Ok(())
        }
        Command::Presets => {
            for (name, _) in presets::PRESETS {
                println!("{name:<10} {}", presets::summary(name));
            }
            println!(
                "\nUse one with `subtgraph generate --preset NAME --out DIR`; their files are in examples/."
            );
            Ok(())
        }
    }
}

fn list(r: &subtgraph::core::Registry) {
    fn rows<T: ?Sized>(c: &subtgraph::core::registry::Catalogue<T>) {
        for (name, e) in c.entries() {
            println!("  {:<17} {name:<16} {}", c.kind(), e.summary);
        }
    }
    rows(&r.route_descriptors);
    rows(&r.constraint_shapes);
    rows(&r.tilesets);
    rows(&r.exporters);
}

fn import_world(path: &Path, p: &Pipeline, budget: &subtgraph::core::Budget) -> Result<Layout> {
    use subtgraph::core::budget;
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    let name = path.display().to_string();
    // Sized from the header before any value is decoded: the values as f64, the codes, and the
    // world's grids.
    let shape = npy::shape(&bytes).map_err(|m| anyhow!("{name}: {m}"))?;
    let cells: usize = shape.iter().product();
    let (levels, per_level) = match shape[..] {
        [l, r, c] => (l, r * c),
        _ => (1, cells),
    };
    let needed = budget::layout_bytes(levels, 1, per_level)
        .saturating_add((cells as u64).saturating_mul(budget::BYTES_PER_IMPORTED_CELL))
        .saturating_add(bytes.len() as u64);
    budget
        .check(
            needed,
            &format!("importing {name} ({cells} cells, shape {shape:?})"),
            "import a smaller grid (crop or split it with numpy)",
        )
        .map_err(|e| anyhow!(e))?;
    let array = npy::decode(&bytes).map_err(|m| anyhow!("{name}: {m}"))?;
    let (world, encoding) = import::import_occupancy(&array, &name, p, env!("CARGO_PKG_VERSION"))?;
    eprintln!("imported {name}: {encoding:?} encoding");
    Ok(world)
}

/// Prints how many files and bytes the world folder holds and how long writing them (every
/// exporter included) took: what `scripts/bench-exports` reads.
fn print_written(out: &Path, took: std::time::Duration) {
    let (mut files, mut bytes) = (0u64, 0u64);
    let mut stack = vec![out.to_owned()];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            match e.metadata() {
                Ok(m) if m.is_dir() => stack.push(e.path()),
                Ok(m) => {
                    files += 1;
                    bytes += m.len();
                }
                Err(_) => {}
            }
        }
    }
    let text = format!(
        "  wrote {files} files, {:.1} MB, in {:.1} ms\n",
        bytes as f64 / 1e6,
        took.as_secs_f64() * 1e3
    );
    let _ = std::io::Write::write_all(&mut std::io::stdout().lock(), text.as_bytes());
}

/// Prints what was made. A closed standard output (`| head`) is not an error.
fn print_summary(world: &World, out: &Path, took: std::time::Duration) {
    let mut text = String::new();
    summarize(&mut text, world, out, took).expect("formatting into a String");
    let _ = std::io::Write::write_all(&mut std::io::stdout().lock(), text.as_bytes());
}

fn summarize(
    f: &mut String,
    world: &World,
    out: &Path,
    took: std::time::Duration,
) -> std::fmt::Result {
    use std::fmt::Write;
    let r = &world.resolved;
    writeln!(
        f,
        "wrote {} (seed {}, {} level(s) of {} x {} cells, pitch {} m, made in {:.1} ms)",
        out.display(),
        r.seed,
        r.levels,
        r.rows,
        r.cols,
        r.tile_pitch,
        took.as_secs_f64() * 1e3
    )?;
    for l in &world.levels {
        let a = &l.achieved;
        let requested: Vec<String> = l
            .requested
            .iter()
            .map(|(k, v)| format!("{v} {k}"))
            .collect();
        writeln!(
            f,
            "  level {}: {} cells, {} T-junctions, {} intersections, {} loops, {} dead ends{}",
            l.level,
            l.cells,
            a.t_junctions,
            a.intersections,
            a.loops,
            a.dead_ends,
            if requested.is_empty() {
                String::new()
            } else {
                format!(" (asked: {})", requested.join(", "))
            }
        )?;
    }
    if let Some(m) = world.mesh() {
        writeln!(
            f,
            "  mesh: {} tiles, {} visual triangles, {} collision triangles",
            m.tiles.len(),
            m.visual.triangle_count(),
            m.collision.triangle_count()
        )?;
    }
    let reachable = world.reachable_from_start();
    let occupied = world.occupancy.occupied_count();
    if reachable != occupied {
        writeln!(
            f,
            "  note: {} of {occupied} cells are not reachable from the start",
            occupied - reachable
        )?;
    }
    Ok(())
}
