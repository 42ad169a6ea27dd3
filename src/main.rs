//! The `subtgraph` command line: argument parsing and printing. Each subcommand is one file of
//! `commands/`: its arguments (a clap `Args`), the request of the application library
//! (`subtgraph-app`) they make, the one call that runs it, and what is printed. A new command
//! is a new file there and one line in [`Command`].

mod commands;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use commands::{
    dataset, explore, generate, plugins, presets, preview, report, score, sense, stats, validate,
};

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
    Generate(generate::Args),
    /// Make a dataset: COUNT worlds per source (pipeline files and presets), in parallel.
    ///
    /// World i of source NAME gets the seed derive_seed(--seed, NAME, i) and the folder
    /// OUT/NAME-000i, written atomically. Complete worlds are kept, so an interrupted run
    /// resumes where it stopped. OUT/index.json and OUT/index.csv list every world folder.
    Dataset(dataset::Args),
    /// Variability statistics of worlds (the paper's "Topological Analysis"): IoU, mirror
    /// asymmetry, tile mix, sizes, constraint satisfaction, graph statistics; JSON, CSV and
    /// plots (SVG and PNG).
    Stats(stats::Args),
    /// Check a pipeline file: syntax, keys, component names, that its layout can be made and
    /// that the tile set can build it. No mesh is made (`generate` makes it), so this is quick
    /// even for large worlds.
    Validate(validate::Args),
    /// Plugins: list what plugin libraries register.
    Plugins {
        #[command(subcommand)]
        command: plugins::Command,
    },
    /// List the built-in presets.
    Presets,
    /// Grade a robot's run against a world's ground truth: artifact reports by the DARPA
    /// rule (same class within 5 m, each artifact once), and a map's coverage of the free
    /// space (per level and graph edge) and error; or an estimated trajectory (--trajectory)
    /// against a ground-truth one: APE, RPE, drift, points, as evo computes them; or a
    /// topometric segmentation of a level (--segmentation): per-class IoU, precision, recall,
    /// confusion and node detection against the world's tile kinds. JSON, CSV, pictures.
    Score(score::Args),
    /// Statistics over whole datasets from score folders: per method the mean, median and a
    /// seeded bootstrap 95 % interval of every metric (over worlds and per preset) and the
    /// success rate with a Wilson interval; two methods' paired differences with Wilcoxon's
    /// signed-rank test; each metric against the worlds' parameters. JSON, CSV, PNG and an
    /// index.html that opens offline.
    Report(report::Args),
    /// Draw a shaded perspective picture of a world's mesh (no GPU needed).
    Preview(preview::Args),
    /// Record a sensor sequence along a route through a world: a LiDAR, an IMU and ground-truth
    /// poses, as a ROS 2 bag (bag/), a KITTI folder (kitti/), ground_truth.tum and
    /// sequence.json (models, extrinsics, route, a label per scan). No simulator needed.
    Sense(Box<sense::Args>),
    /// Robots exploring a world in a closed loop: the frontier baseline (or random commands)
    /// drives each, its LiDAR maps, artifacts in view are reported to the base station over a
    /// radio after the SubT virtual competition's, with breadcrumbs. Writes a run folder
    /// (trajectories, map, reports, radio log) that `score --run` grades. No simulator needed.
    Explore(Box<explore::Args>),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    subtgraph::folder::install_signal_handlers();
    let done = match cli.command {
        Command::Generate(a) => generate::run(a),
        Command::Dataset(a) => dataset::run(a),
        Command::Stats(a) => stats::run(a),
        Command::Validate(a) => validate::run(a),
        Command::Plugins { command } => plugins::run(command),
        Command::Presets => presets::run(),
        Command::Score(a) => score::run(a),
        Command::Report(a) => report::run(a),
        Command::Preview(a) => preview::run(a),
        Command::Sense(a) => sense::run(*a),
        Command::Explore(a) => explore::run(*a),
    };
    match done {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // Every message passes through `shorten`, so no path that echoes a user's value can
            // print a huge one whole.
            eprintln!(
                "error: {}",
                subtgraph::core::error::shorten(&subtgraph::app::message(&e))
            );
            ExitCode::FAILURE
        }
    }
}
