//! `subtgraph sense`.

use std::path::PathBuf;
use std::time::Instant;

use subtgraph::app::{CameraRequest, Error, SenseRequest, memory, sense};

/// `sense`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    /// A world folder made with ground truth (`generate --format ground-truth`).
    world: PathBuf,
    /// The sequence folder to write (must not exist, unless --force and subtgraph sense wrote it).
    #[arg(long)]
    out: PathBuf,
    /// ground (a wheeled robot: corridors and ramps) or aerial (a quadrotor: shafts too).
    #[arg(long, default_value = "ground")]
    platform: String,
    /// out-and-back (to the farthest dead end and back), loop, levels, coverage, or straight
    /// to a study's target: shaft (the nearest, up and back: aerial), edge:N, node:N.
    #[arg(long, default_value = "out-and-back")]
    route: String,
    #[arg(
        long,
        default_value = subtgraph_sensors::lidar::DEFAULT,
        value_name = "MODEL",
        help = subtgraph_sensors::lidar::CHOICES_OR_NONE
    )]
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
    /// Outputs besides sequence.json and ground_truth.tum: bag, kitti, euroc, tum-rgbd
    /// (default: bag, kitti with a LiDAR, euroc with a camera, tum-rgbd with an RGB-D one).
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
    /// Start this many seconds into the route: a window of it (with --duration).
    #[arg(long, value_name = "SECONDS")]
    start: Option<f64>,
    /// Dust, fog, mist, wet rock, drips: a FILE.toml of [[conditions]] tables, or none.
    #[arg(long, value_name = "FILE", default_value = "none")]
    conditions: String,
    /// Seed of the route's choices and the noise (default: the world's seed).
    #[arg(long)]
    seed: Option<u64>,
    /// The most disk the folder may take, like 20G (default: the free space less 1 GB).
    #[arg(long, value_name = "SIZE")]
    max_disk: Option<String>,
    /// Replace --out if it is a sensor sequence subtgraph sense wrote.
    #[arg(long)]
    force: bool,
    /// A plugin library the world needs (repeatable): the plugins a world folder's world.toml
    /// names are never loaded unless named here.
    #[arg(long = "plugin", value_name = "PATH")]
    plugins: Vec<PathBuf>,
    /// Cameras too: mono, stereo, fisheye-stereo, d435i, or a camera table FILE.toml.
    #[arg(long, value_name = "MODEL")]
    camera: Option<String>,
    /// Camera frames a second, instead of the model's.
    #[arg(long, value_name = "HZ", requires = "camera")]
    camera_rate: Option<f64>,
    /// Expose the cameras row by row (the model's readout time), not all at once.
    #[arg(long, requires = "camera")]
    rolling_shutter: bool,
    /// Blur the images by the motion during each exposure (five times the rendering).
    #[arg(long, requires = "camera")]
    motion_blur: bool,
    /// Each lamp's output in lumens instead of the platform's (0: lamps off).
    #[arg(long, value_name = "LUMENS", requires = "camera")]
    lamp_lumens: Option<f64>,
    /// Light reaching everything from everywhere, lux (default 0: none underground).
    #[arg(long, value_name = "LUX", default_value_t = 0.0, requires = "camera")]
    ambient: f64,
}

/// Writes the sequence, with a progress line, and prints what it holds and how fast it went.
pub fn run(a: Args) -> Result<(), Error> {
    let max_disk = match a.max_disk.as_deref() {
        // The sizes the memory limit takes, said of the disk.
        Some(s) => Some(memory::parse_size_of(s, "--max-disk", "20G")?),
        None => None,
    };
    let request = SenseRequest {
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
        start: a.start,
        conditions: Some(a.conditions),
        seed: a.seed,
        max_disk,
        force: a.force,
        camera: a.camera.map(|model| CameraRequest {
            model,
            rate: a.camera_rate,
            rolling_shutter: a.rolling_shutter,
            motion_blur: a.motion_blur,
            lamp_lumens: a.lamp_lumens,
            ambient_lux: a.ambient,
        }),
    };
    let started = Instant::now();
    let sensed = sense::run_with(&request, &a.plugins, &|scan, of| {
        if (scan + 1) % 500 == 0 || scan + 1 == of {
            eprint!("\r  scan {} of {of}", scan + 1);
            if scan + 1 == of {
                eprintln!();
            }
        }
    })?;
    let took = started.elapsed().as_secs_f64();
    if let Some((parent, n)) = &sensed.swept {
        eprintln!(
            "note: removed {n} unfinished folder(s) in {} left by runs that were killed",
            parent.display()
        );
    }
    let s = &sensed.summary;
    if let Some(c) = &s.camera {
        super::print(&format!(
            "cameras: {} frames, {} images, {:.1} M pixels rendered: {:.1} images/s\n",
            c.frames,
            c.images,
            c.pixels as f64 / 1e6,
            c.images as f64 / took
        ));
    }
    super::print(&format!(
        "wrote {} ({} scans, {:.1} s of sensor time, {:.0} m driven, {} of {} rays returned, {:.1} MB, {} degenerate scans) in {took:.1} s (world rebuilt, ray caster built and route planned in {:.1} s): {:.1} M rays/s, {:.0} scans/s\n",
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
    ));
    Ok(())
}
