//! `subtgraph score`: a run's artifact reports and map, a trajectory (`--trajectory`) or a
//! topometric segmentation (`--segmentation`).

use std::path::PathBuf;

use subtgraph::app::{
    Align, Associate, Error, ScoreRequest, SegmentationRequest, TrajectoryRequest,
};

/// `score`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    /// A world folder generated with [artifacts] (and free-space ground truth for --map); with
    /// --trajectory, a sensor sequence folder (its ground_truth.tum is the reference), the
    /// reference trajectory file itself, or a world folder with --reference.
    #[arg(value_name = "WORLD_OR_SEQUENCE")]
    world: PathBuf,
    /// The team's reports: CSV with columns time,class,x,y,z, or a JSON list of them.
    #[arg(long, required_unless_present_any = ["trajectory", "segmentation", "run"])]
    reports: Option<PathBuf>,
    /// A run folder (what `subtgraph explore` writes): its reports.csv counted only when the
    /// robot had a radio link to the base station at the report's time (connectivity.csv),
    /// its map.ply scored as --map, its explored.npy as the share of the free space explored,
    /// its radio log summed up.
    #[arg(long, value_name = "RUN", conflicts_with_all = ["reports", "map", "trajectory", "segmentation"])]
    run: Option<PathBuf>,
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
    /// Score an estimated trajectory instead: TUM (t x y z qx qy qz qw), KITTI (3x4 pose
    /// rows, times from --times or times.txt beside it), or a ROS 2 bag in MCAP storage (a
    /// pose topic: nav_msgs/Odometry, geometry_msgs/PoseStamped, PoseWithCovarianceStamped
    /// or TransformStamped).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["reports", "map"])]
    trajectory: Option<PathBuf>,
    /// The estimate's times file (one time a line), when it is KITTI.
    #[arg(long, value_name = "FILE", requires = "trajectory")]
    times: Option<PathBuf>,
    /// The estimate's topic, when it is a bag with more than one pose topic.
    #[arg(long, value_name = "TOPIC", requires = "trajectory")]
    topic: Option<String>,
    /// The ground-truth trajectory (TUM, KITTI or a bag), when WORLD_OR_SEQUENCE is not one.
    #[arg(long, value_name = "FILE", requires = "trajectory")]
    reference: Option<PathBuf>,
    /// The reference's times file, when it is KITTI.
    #[arg(long, value_name = "FILE", requires = "trajectory")]
    reference_times: Option<PathBuf>,
    /// The reference's topic, when it is a bag with more than one pose topic.
    #[arg(long, value_name = "TOPIC", requires = "trajectory")]
    reference_topic: Option<String>,
    /// nearest: each pose paired with the nearest in time within --max-diff (evo's
    /// association); interpolate: the reference interpolated at each estimate pose's time.
    #[arg(long, default_value = "nearest", value_parser = ["nearest", "interpolate"], requires = "trajectory")]
    associate: String,
    /// With --associate interpolate: reference poses further apart than this are not
    /// interpolated between (a gap in the ground truth).
    #[arg(
        long,
        default_value_t = 1.0,
        value_name = "SECONDS",
        requires = "trajectory"
    )]
    max_gap: f64,
    /// Poses further apart in time than this are not associated (evo's --t_max_diff).
    #[arg(
        long,
        default_value_t = 0.01,
        value_name = "SECONDS",
        requires = "trajectory"
    )]
    max_diff: f64,
    /// none: the estimate's first pose put on the reference's (evo --align_origin); se3:
    /// Umeyama rigid (evo -a); sim3: Umeyama with scale (evo -as).
    #[arg(long, default_value = "none", value_parser = ["none", "se3", "sim3"], requires = "trajectory")]
    align: String,
    /// RPE between poses this many frames apart (evo --delta N --delta_unit f).
    #[arg(
        long,
        default_value_t = 1,
        value_name = "FRAMES",
        requires = "trajectory"
    )]
    delta: usize,
    /// An APE above this many metres is a divergence: the run is flagged failed.
    #[arg(
        long,
        default_value_t = 10.0,
        value_name = "METRES",
        requires = "trajectory"
    )]
    fail_ape: f64,
    /// A step this many metres longer than the reference's is a jump: the run is flagged
    /// failed.
    #[arg(
        long,
        default_value_t = 1.0,
        value_name = "METRES",
        requires = "trajectory"
    )]
    fail_jump: f64,
    /// Score a topometric segmentation instead: an 8-bit greyscale PNG or an integer 2-D
    /// .npy on the grid of the world's ground_truth/maps/level-N.pgm, each pixel 0 (not
    /// labelled), 1 corridor, 2 junction, 3 intersection, 4 dead end or 5 shaft/ramp.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["reports", "map", "trajectory"])]
    segmentation: Option<PathBuf>,
    /// The segmentation's level, when its file name does not say (level-N.png).
    #[arg(long, value_name = "N", requires = "segmentation")]
    level: Option<usize>,
    /// A detected node within this many metres of a graph node may match it (default: half
    /// the tile pitch).
    #[arg(long, value_name = "METRES", requires = "segmentation")]
    node_radius: Option<f64>,
    /// The score folder (must not exist, unless --force and the tool wrote it).
    #[arg(long)]
    out: PathBuf,
    /// Replace a score folder written earlier.
    #[arg(long)]
    force: bool,
}

/// Scores the run and prints the summary.
pub fn run(a: Args) -> Result<(), Error> {
    if let Some(segmentation) = a.segmentation {
        let scored = SegmentationRequest {
            world: a.world,
            segmentation,
            level: a.level,
            node_radius: a.node_radius,
            out: a.out,
            force: a.force,
        }
        .run()?;
        super::print(&format!("{scored}\n"));
        return Ok(());
    }
    if let Some(estimate) = a.trajectory {
        let scored = TrajectoryRequest {
            world_or_sequence: a.world,
            estimate,
            times: a.times,
            reference: a.reference,
            reference_times: a.reference_times,
            topic: a.topic,
            reference_topic: a.reference_topic,
            associate: match a.associate.as_str() {
                "interpolate" => Associate::Interpolate,
                _ => Associate::Nearest,
            },
            max_diff: a.max_diff,
            max_gap: a.max_gap,
            align: match a.align.as_str() {
                "se3" => Align::Se3,
                "sim3" => Align::Sim3,
                _ => Align::None,
            },
            delta: a.delta,
            fail_ape: a.fail_ape,
            fail_jump: a.fail_jump,
            out: a.out,
            force: a.force,
        }
        .run()?;
        super::print(&format!("{scored}\n"));
        return Ok(());
    }
    let (reports, map) = match &a.run {
        Some(run) => {
            let files = subtgraph::app::score::run::locate(run)?;
            (files.reports, files.map)
        }
        None => (
            a.reports
                .expect("clap requires the reports file unless a trajectory is scored"),
            a.map,
        ),
    };
    let scored = ScoreRequest {
        world: a.world,
        reports,
        map,
        run: a.run,
        radius: a.radius,
        tolerance: a.tolerance,
        out: a.out,
        force: a.force,
    }
    .run()?;
    super::print(&format!("{scored}\n"));
    Ok(())
}
