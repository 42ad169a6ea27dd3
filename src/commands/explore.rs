//! `subtgraph explore`.

use std::path::PathBuf;

use subtgraph::app::{Error, ExploreRequest};

/// `explore`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    /// A world folder made with ground truth (`--format ground-truth`).
    world: PathBuf,
    /// Robots, spawned along the entrance's passage.
    #[arg(long, default_value_t = 1, value_name = "N")]
    robots: usize,
    /// Simulated seconds.
    #[arg(long, default_value_t = 600.0, value_name = "SECONDS")]
    duration: f64,
    /// ground or aerial.
    #[arg(long, default_value = "ground", value_name = "P")]
    platform: String,
    #[arg(
        long,
        default_value = subtgraph_explore::lidar::DEFAULT_MODEL,
        value_name = "MODEL",
        help = subtgraph_sensors::lidar::CHOICES
    )]
    lidar: String,
    /// Columns a turn of each scan (default 180, one every 2 degrees; the model's own for
    /// the full scan).
    #[arg(long, value_name = "N")]
    lidar_columns: Option<usize>,
    /// frontier (the baseline) or random (a uniformly random command every step).
    #[arg(long, default_value = "frontier", value_name = "NAME")]
    planner: String,
    /// Breadcrumbs (radio repeaters) each robot carries.
    #[arg(long, default_value_t = 6, value_name = "N")]
    breadcrumbs: usize,
    /// The robots' map voxel, metres.
    #[arg(long, default_value_t = 0.5, value_name = "METRES")]
    map_voxel: f64,
    /// Control steps a second.
    #[arg(long, default_value_t = 10.0, value_name = "HZ")]
    control_rate: f64,
    /// Seed of the range noise, the reports' errors and random commands (default: the
    /// world's).
    #[arg(long)]
    seed: Option<u64>,
    /// No range noise.
    #[arg(long)]
    noiseless: bool,
    /// The run folder (must not exist, unless --force and `explore` wrote it).
    #[arg(long)]
    out: PathBuf,
    /// Replace a run folder written earlier.
    #[arg(long)]
    force: bool,
    /// A plugin library the world needs (repeatable): the plugins a world folder's world.toml
    /// names are never loaded unless named here.
    #[arg(long = "plugin", value_name = "PATH")]
    plugins: Vec<PathBuf>,
}

impl Args {
    /// The request these arguments make.
    pub fn request(self) -> ExploreRequest {
        ExploreRequest {
            world: self.world,
            out: self.out,
            robots: self.robots,
            duration: self.duration,
            platform: self.platform,
            lidar: self.lidar,
            lidar_columns: self.lidar_columns,
            planner: self.planner,
            breadcrumbs: self.breadcrumbs,
            map_voxel: self.map_voxel,
            control_hz: self.control_rate,
            seed: self.seed,
            noiseless: self.noiseless,
            force: self.force,
            plugins: self.plugins,
        }
    }
}

/// Runs the mission and prints what it did.
pub fn run(a: Args) -> Result<(), Error> {
    let request = a.request();
    let explored = request.run(&|t, of| {
        if t >= of - 1e-6 || (t as u64) % 300 == 0 {
            eprint!("\r  {t:.0} of {of:.0} simulated s");
            if t >= of - 1e-6 {
                eprintln!();
            }
        }
    })?;
    super::print(&format!("{explored}\n"));
    Ok(())
}
