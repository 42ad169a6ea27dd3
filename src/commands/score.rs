//! `subtgraph score`.

use std::path::PathBuf;

use subtgraph::app::{Error, ScoreRequest};

/// `score`'s arguments.
#[derive(clap::Args)]
pub struct Args {
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
}

/// Scores the run and prints the summary.
pub fn run(a: Args) -> Result<(), Error> {
    let scored = ScoreRequest {
        world: a.world,
        reports: a.reports,
        map: a.map,
        radius: a.radius,
        tolerance: a.tolerance,
        out: a.out,
        force: a.force,
    }
    .run()?;
    super::print(&format!("{scored}\n"));
    Ok(())
}
