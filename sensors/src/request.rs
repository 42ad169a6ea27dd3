//! `subtgraph sense`: a typed request, checked before anything heavy is done, run against the
//! application that hosts it (which rebuilds worlds and writes folders atomically).

use std::path::{Path, PathBuf};

use subtgraph_core::World;
use subtgraph_survey::WorldSurvey;

use crate::camera::scene::CameraScene;
use crate::camera::{CameraModel, Overrides as CameraOverrides};
use crate::camera_stream::CameraOptions;
use crate::conditions::Conditions;
use crate::error::{HostError, SenseError};
use crate::graph::RouteGraph;
use crate::imu::ImuModel;
use crate::lidar::{LidarModel, Overrides};
use crate::platform::Platform;
use crate::route::RouteKind;
use crate::scene::Scene;
use crate::sequence::{Options, Sequence, Summary};
use crate::write::Formats;
use subtgraph_core::survey::Survey;

/// What `subtgraph sense` is asked for. [`Default`] gives the command line's defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct SenseRequest {
    /// The world folder (with `world.toml` and `ground_truth/graph.json`).
    pub world: PathBuf,
    /// The sequence folder to write.
    pub out: PathBuf,
    /// `ground` or `aerial`.
    pub platform: String,
    /// `out-and-back`, `loop`, `levels` or `coverage`.
    pub route: String,
    /// A built-in LiDAR model's name, a LiDAR table's path (`.toml`), or `none`.
    pub lidar: String,
    /// Scans a second, overriding the model's.
    pub lidar_rate: Option<f64>,
    /// Farthest return, metres, overriding the model's.
    pub max_range: Option<f64>,
    /// IMU samples a second.
    pub imu_rate: f64,
    /// Added to the IMU's time stamps, seconds.
    pub imu_time_offset: f64,
    /// `bag`, `kitti` (comma lists allowed); empty means both.
    pub formats: Vec<String>,
    /// Publish wheel odometry (ground platform).
    pub wheel_odometry: bool,
    /// No range noise, no IMU noise or drift.
    pub noiseless: bool,
    /// Stop after this many seconds.
    pub duration: Option<f64>,
    /// Start this many seconds into the route (a window).
    pub start: Option<f64>,
    /// A conditions file (`[[conditions]]` tables), or `none` (and `None`) for clear air.
    pub conditions: Option<String>,
    /// The seed of the route's choices and the noise (default: the world's).
    pub seed: Option<u64>,
    /// The most bytes the folder may take (default: the free space where it goes, less 1 GB).
    pub max_disk: Option<u64>,
    /// Replace `out` if subtgraph wrote it.
    pub force: bool,
    /// The cameras: a built-in camera model's name or a camera table's path (`None`: no
    /// camera), and how to render them.
    pub camera: Option<CameraRequest>,
}

/// What `--camera` and its options ask for.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct CameraRequest {
    /// A built-in camera model's name, or a camera table's path (`.toml`).
    pub model: String,
    /// Frames a second, overriding the model's.
    pub rate: Option<f64>,
    /// Expose row by row with the model's readout time.
    pub rolling_shutter: bool,
    /// Average instants over each exposure.
    pub motion_blur: bool,
    /// Each lamp's lumens instead of the platform's (0: off).
    pub lamp_lumens: Option<f64>,
    /// Light from everywhere, lux.
    pub ambient_lux: f64,
}

impl Default for SenseRequest {
    fn default() -> Self {
        SenseRequest {
            world: PathBuf::new(),
            out: PathBuf::new(),
            platform: "ground".into(),
            route: "out-and-back".into(),
            lidar: crate::lidar::DEFAULT.into(),
            lidar_rate: None,
            max_range: None,
            imu_rate: 200.0,
            imu_time_offset: 0.0,
            formats: Vec::new(),
            wheel_odometry: false,
            noiseless: false,
            duration: None,
            start: None,
            conditions: None,
            seed: None,
            max_disk: None,
            force: false,
            camera: None,
        }
    }
}

/// What the application provides: the world of a folder, and an atomic folder to write into.
///
/// The command line implements it with its registry (built-ins and plugins) and its `folder`
/// module: `world` rebuilds the world from the folder's `world.toml` (a world records its seed
/// and whole resolved configuration, so it comes back exactly), and `write_folder` gives `fill`
/// a temporary folder beside `out` that is moved into place only once `fill` succeeds, and
/// removed otherwise.
pub trait Host {
    /// The world a world folder was made from.
    fn world(&self, folder: &Path) -> Result<World, HostError>;

    /// Writes the folder `out` through `fill`, atomically; `force` replaces a folder this tool
    /// wrote, and nothing else.
    fn write_folder(
        &self,
        out: &Path,
        force: bool,
        fill: &mut dyn FnMut(&Path) -> Result<(), SenseError>,
    ) -> Result<(), SenseError>;

    /// Told each scan's index as it is written (for a progress line).
    fn progress(&self, _scan: u64, _of: u64) {}
}

/// The options a request names, checked (names, bounds), with `seed` for a missing seed.
pub fn options(r: &SenseRequest, seed: u64) -> Result<Options, SenseError> {
    let platform = Platform::named(&r.platform)?;
    let route = RouteKind::named(&r.route)?;
    let lidar = if r.lidar == "none" {
        if let Some((what, v)) = [("--lidar-rate", r.lidar_rate), ("--max-range", r.max_range)]
            .into_iter()
            .find_map(|(w, v)| v.map(|v| (w, v)))
        {
            return Err(SenseError::OutOfBounds {
                what: what.into(),
                value: v.to_string(),
                bounds: "left out with --lidar none".into(),
            });
        }
        None
    } else {
        let lidar = LidarModel::named(&r.lidar, |p| std::fs::read_to_string(p).ok())?;
        Some(
            Overrides {
                rate_hz: r.lidar_rate,
                max_range_m: r.max_range,
                noiseless: r.noiseless,
            }
            .apply(lidar)?,
        )
    };
    let camera = r
        .camera
        .as_ref()
        .map(|c| camera_options(c, r.noiseless))
        .transpose()?;
    if lidar.is_none() && camera.is_none() {
        return Err(SenseError::OutOfBounds {
            what: "--lidar".into(),
            value: "none".into(),
            bounds: "given a --camera (a sequence needs a LiDAR or a camera)".into(),
        });
    }
    let mut imu = ImuModel::adis16448(r.imu_rate);
    imu.time_offset_s = r.imu_time_offset;
    if r.noiseless {
        imu = imu.noiseless();
    }
    imu.check()?;
    if let Some(d) = r.duration
        && !(d > 0.0 && d.is_finite())
    {
        // Before the world is rebuilt (issue 37, item 19).
        return Err(SenseError::OutOfBounds {
            what: "--duration".into(),
            value: format!("{d} s"),
            bounds: "a positive number of seconds".into(),
        });
    }
    let depth = camera.as_ref().map(|c| c.model.depth_range_m.is_some());
    Ok(Options {
        platform,
        route,
        formats: Formats::for_sensors(&r.formats, lidar.is_some(), depth)?,
        lidar,
        camera,
        imu,
        wheel_odometry: r.wheel_odometry,
        seed: r.seed.unwrap_or(seed),
        duration: r.duration,
        start: r.start,
        conditions: None,
    })
}

/// The camera options a request names, checked.
pub fn camera_options(c: &CameraRequest, noiseless: bool) -> Result<CameraOptions, SenseError> {
    let model = CameraModel::named(&c.model, |p| std::fs::read_to_string(p).ok())?;
    let model = CameraOverrides {
        rate_hz: c.rate,
        rolling_shutter: c.rolling_shutter,
    }
    .apply(model)?;
    if let Some(l) = c.lamp_lumens
        && !(l.is_finite() && (0.0..=100_000.0).contains(&l))
    {
        return Err(SenseError::OutOfBounds {
            what: "--lamp-lumens".into(),
            value: l.to_string(),
            bounds: "0 (lamps off) to 100,000 lumens a lamp".into(),
        });
    }
    if !(c.ambient_lux.is_finite() && (0.0..=100_000.0).contains(&c.ambient_lux)) {
        return Err(SenseError::OutOfBounds {
            what: "--ambient".into(),
            value: format!("{} lux", c.ambient_lux),
            bounds: "0 (none, underground) to 100,000 lux (daylight)".into(),
        });
    }
    Ok(CameraOptions {
        model,
        motion_blur: c.motion_blur,
        lamp_lumens: c.lamp_lumens,
        ambient_lux: c.ambient_lux,
        noiseless,
    })
}

/// Reads a world folder's route graph, or says why it has none.
pub fn read_graph(world: &Path) -> Result<RouteGraph, SenseError> {
    if !world.join("world.toml").is_file() {
        return Err(SenseError::NoWorld {
            path: world.to_owned(),
            why: if world.is_dir() {
                "it has no world.toml".into()
            } else {
                "no such folder".into()
            },
        });
    }
    let path = world.join("ground_truth/graph.json");
    if !path.is_file() {
        return Err(SenseError::NoGroundTruth {
            path: world.to_owned(),
        });
    }
    let text = std::fs::read_to_string(&path).map_err(|source| SenseError::Io {
        what: "reading",
        path: path.clone(),
        source,
    })?;
    RouteGraph::from_json(&text, &path.display().to_string())
}

/// The conditions a `--conditions` value names: `None` for clear air (`none`, or no value),
/// or the file's tables checked against the world's graph.
pub fn read_conditions(
    value: Option<&str>,
    graph: &RouteGraph,
) -> Result<Option<Conditions>, SenseError> {
    match value {
        None | Some("none") => Ok(None),
        Some(path) => {
            let text = std::fs::read_to_string(path).map_err(|e| SenseError::BadConditions {
                path: path.to_owned(),
                why: format!("cannot be read ({e}); pass a [[conditions]] file, or none"),
            })?;
            Conditions::parse(&text, path, graph).map(Some)
        }
    }
}

/// Free bytes on the file system that `out` goes to (its nearest existing ancestor).
pub fn free_space(out: &Path) -> Option<u64> {
    #[cfg(unix)]
    {
        let dir = out
            .ancestors()
            .find(|a| !a.as_os_str().is_empty() && a.is_dir())
            .unwrap_or(Path::new("."));
        let s = rustix::fs::statvfs(dir).ok()?;
        Some(s.f_bavail.saturating_mul(s.f_frsize))
    }
    #[cfg(not(unix))]
    {
        let _ = out;
        None
    }
}

impl SenseRequest {
    /// Makes the sequence: checks the request and the world folder, then (in the host's
    /// atomic folder) rebuilds the world, plans the route, refuses a sequence past the disk
    /// limit, and writes it.
    pub fn run(&self, host: &dyn Host) -> Result<Summary, SenseError> {
        // Names and bounds first, with a placeholder seed: nothing heavy yet.
        options(self, 0)?;
        let graph = read_graph(&self.world)?;
        // The conditions, checked against the graph before the world is rebuilt.
        let conditions = read_conditions(self.conditions.as_deref(), &graph)?;
        let limit = match self.max_disk {
            Some(b) => b,
            None => free_space(&self.out).map_or(u64::MAX, |f| f.saturating_sub(1 << 30)),
        };
        let mut summary = None;
        host.write_folder(&self.out, self.force, &mut |dir| {
            let started = std::time::Instant::now();
            let world = host
                .world(&self.world)
                .map_err(|source| SenseError::Rebuild {
                    folder: self.world.clone(),
                    source,
                })?;
            check_graph(&world, &graph, &self.world)?;
            let mut options = options(self, world.resolved.seed)?;
            options.conditions = conditions.clone();
            // The survey of the world: its one ray-cast hierarchy is what the scans ask.
            let survey = WorldSurvey::new(&world)?;
            let scene = Scene::of_survey(&survey)?;
            if let Some(p) = graph.stray(&scene.caster, 4.0 * scene.tile_pitch) {
                return Err(SenseError::BadGraph {
                    path: self.world.join("ground_truth/graph.json").display().to_string(),
                    why: format!(
                        "the point ({:.1}, {:.1}, {:.1}) is more than {} m from any rock of the world: the graph was edited, or is another world's; make the world again with `subtgraph generate`",
                        p[0],
                        p[1],
                        p[2],
                        4.0 * scene.tile_pitch
                    ),
                });
            }
            let camera_scene = match &options.camera {
                Some(_) => Some(CameraScene::of(
                    &world,
                    survey.artifacts().map_or(&[][..], |a| &a.artifacts),
                )?),
                None => None,
            };
            let mut sequence = Sequence::plan(&scene, &graph, options)?;
            if let Some(cs) = &camera_scene {
                sequence = sequence.with_camera_scene(cs);
            }
            sequence.check_disk(limit)?;
            let about = serde_json::json!({
                "folder": self.world.display().to_string(),
                "seed": world.resolved.seed,
                "levels": world.resolved.levels,
                "tile_pitch_m": world.resolved.tile_pitch,
                "surface_triangles": scene.caster.triangle_count(),
            });
            let scans = sequence.scans;
            let prepare_s = started.elapsed().as_secs_f64();
            let mut written = sequence.write(dir, about, &mut |k| host.progress(k, scans))?;
            written.prepare_s = prepare_s;
            summary = Some(written);
            Ok(())
        })?;
        Ok(summary.expect("written"))
    }
}

/// Refuses a graph that is not the rebuilt world's (a folder made by another version).
fn check_graph(world: &World, graph: &RouteGraph, folder: &Path) -> Result<(), SenseError> {
    let (n, e) = (world.graph.nodes.len(), world.graph.edges.len());
    if n != graph.nodes.len() || e != graph.edges.len() {
        return Err(SenseError::NoWorld {
            path: folder.to_owned(),
            why: format!(
                "its world.toml makes a world of {n} nodes and {e} edges but its ground_truth/graph.json has {} and {} (the folder was made by another version of subtgraph, or edited): generate it again",
                graph.nodes.len(),
                graph.edges.len()
            ),
        });
    }
    Ok(())
}
