//! `explore`: robots exploring a world folder's world from its entrance, driven by the
//! frontier baseline (or random commands), for a simulated time; a run folder `score --run`
//! grades. The loop itself lives in the explore crate (`subtgraph-explore`); this module is
//! its host: the request checked before anything heavy, the world rebuilt from its folder
//! (as `sense` does, see [`crate::sense::world_of`]), and the run folder written atomically,
//! recorded as written by `explore` so that `explore --force` replaces only a run.
//!
//! The world folder must hold its ground truth (`--format ground-truth`): `score` grades the
//! run against it, and the run's `explored.npy` is written on its free-space grid.

use std::path::{Path, PathBuf};
use std::time::Instant;

use subtgraph_explore::body::Body;
use subtgraph_explore::detect::Detector;
use subtgraph_explore::lidar::Lidar;
use subtgraph_explore::map::Grid;
use subtgraph_explore::radio::RadioModel;
use subtgraph_explore::run::Written;
use subtgraph_explore::{Mission, Options, Policy, Site};
use subtgraph_schema::FreeSpace;
use subtgraph_survey::WorldSurvey;

use crate::folder::{Kind, Out};
use crate::{Error, memory};

/// What `explore` is asked.
#[derive(Clone, Debug, PartialEq)]
pub struct ExploreRequest {
    /// The world folder (with its ground truth).
    pub world: PathBuf,
    /// The run folder to write.
    pub out: PathBuf,
    /// Robots.
    pub robots: usize,
    /// Simulated seconds.
    pub duration: f64,
    /// `ground` or `aerial`.
    pub platform: String,
    /// A LiDAR model's name (or a table's path).
    pub lidar: String,
    /// Columns a turn of each scan (default: the explore crate's, 180).
    pub lidar_columns: Option<usize>,
    /// `frontier` or `random`.
    pub planner: String,
    /// Breadcrumbs each robot carries.
    pub breadcrumbs: usize,
    /// The map's voxel, metres.
    pub map_voxel: f64,
    /// Control steps a second.
    pub control_hz: f64,
    /// The seed of noise, reports and random commands (default: the world's).
    pub seed: Option<u64>,
    /// No range noise.
    pub noiseless: bool,
    /// Replace `out` if `explore` wrote it.
    pub force: bool,
    /// Plugin libraries the world needs (`--plugin`): the plugins a world folder's
    /// `world.toml` names are never loaded unless named here.
    pub plugins: Vec<PathBuf>,
}

impl Default for ExploreRequest {
    fn default() -> Self {
        ExploreRequest {
            world: PathBuf::new(),
            out: PathBuf::new(),
            robots: 1,
            duration: 600.0,
            platform: "ground".into(),
            lidar: subtgraph_explore::lidar::DEFAULT_MODEL.into(),
            lidar_columns: None,
            planner: "frontier".into(),
            breadcrumbs: 6,
            map_voxel: 0.5,
            control_hz: 10.0,
            seed: None,
            noiseless: false,
            force: false,
            plugins: Vec::new(),
        }
    }
}

/// A finished run.
#[derive(Clone, Debug)]
pub struct Explored {
    /// What was written.
    pub written: Written,
    /// The run folder.
    pub out: PathBuf,
    /// Seconds to rebuild the world and set the mission up.
    pub setup_s: f64,
    /// Seconds the mission ran (wall clock).
    pub run_s: f64,
    /// Simulated seconds.
    pub simulated_s: f64,
    /// Artifacts in the world.
    pub artifacts: usize,
    /// Breadcrumbs dropped.
    pub breadcrumbs: usize,
    /// Metres driven, all robots.
    pub distance_m: f64,
}

impl std::fmt::Display for Explored {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let w = &self.written;
        writeln!(
            f,
            "explored {:.0} simulated s in {:.1} s ({:.0}x real time; {:.1} s to set up): {:.0} m driven, {} of {} artifacts detected, {} reported over the radio, {} breadcrumbs, {} map points",
            self.simulated_s,
            self.run_s,
            self.simulated_s / self.run_s.max(1e-9),
            self.setup_s,
            self.distance_m,
            w.detected,
            self.artifacts,
            w.delivered,
            self.breadcrumbs,
            w.map_points
        )?;
        write!(f, "wrote {}", self.out.display())
    }
}

impl ExploreRequest {
    /// The mission's options, every name and number checked (`seed` for a missing seed).
    pub fn options(&self, seed: u64) -> Result<Options, Error> {
        let body = Body::named(&self.platform)?;
        let lidar = Lidar::named(&self.lidar, self.lidar_columns, |p| {
            std::fs::read_to_string(p).ok()
        })?;
        let policy = Policy::named(&self.planner)?;
        let options = Options {
            robots: self.robots,
            body,
            lidar,
            duration: self.duration,
            control_hz: self.control_hz,
            map_voxel: self.map_voxel,
            policy,
            breadcrumbs: self.breadcrumbs,
            radio: RadioModel::default(),
            detector: Detector::default(),
            seed: self.seed.unwrap_or(seed),
            noiseless: self.noiseless,
            max_map_bytes: memory::budget(None)?.bytes / 2,
        };
        options.check()?;
        Ok(options)
    }

    fn destination<'a>(&'a self, reading: &'a [&'a Path]) -> Out<'a> {
        Out {
            path: &self.out,
            kind: Kind::Explore,
            force: self.force,
            reading,
        }
    }

    /// Runs the mission and writes the run folder; `progress` is told the simulated seconds
    /// and the duration now and then. Names, numbers, the world folder and `--out` are
    /// checked before the world is rebuilt.
    pub fn run(&self, progress: &dyn Fn(f64, f64)) -> Result<Explored, Error> {
        self.options(0)?;
        let truth = truth_grid(&self.world)?;
        let reading = [self.world.as_path()];
        self.destination(&reading).check()?;
        let started = Instant::now();
        let world = crate::sense::world_of(&self.world, &self.plugins)?;
        let survey = WorldSurvey::new(&world)?;
        let site = Site::of(&survey)?;
        let options = self.options(world.resolved.seed)?;
        let about = serde_json::json!({
            "folder": self.world.display().to_string(),
            "seed": world.resolved.seed,
            "levels": world.resolved.levels,
            "tile_pitch_m": world.resolved.tile_pitch,
            "collision_triangles": site.collision.triangle_count(),
        });
        drop(survey);
        drop(world);
        let mut mission = Mission::new(site, options, None)?;
        let setup_s = started.elapsed().as_secs_f64();
        let running = Instant::now();
        let duration = self.duration;
        mission.run(&|t| progress(t, duration));
        let run_s = running.elapsed().as_secs_f64();
        let mut written = None;
        crate::folder::write_atomically(&self.destination(&reading), |w| {
            written = Some(subtgraph_explore::run::write_run(
                w.root(),
                &mission,
                about.clone(),
                Some(&truth),
            )?);
            Ok::<(), Error>(())
        })?;
        Ok(Explored {
            written: written.expect("written"),
            out: self.out.clone(),
            setup_s,
            run_s,
            simulated_s: mission.time,
            artifacts: mission.site.artifacts.len(),
            breadcrumbs: mission.crumbs.len(),
            distance_m: mission.robots.iter().map(|r| r.odometer).sum(),
        })
    }
}

/// The world folder's free-space grid, or why the folder cannot be explored.
pub fn truth_grid(world: &Path) -> Result<Grid, Error> {
    if !world.join("world.toml").is_file() {
        return Err(Error::Input(format!(
            "{}: {}; pass a world folder made by `subtgraph generate`",
            world.display(),
            if world.is_dir() {
                "it has no world.toml"
            } else {
                "no such folder"
            }
        )));
    }
    for file in ["ground_truth/graph.json", "ground_truth/free_space.json"] {
        if !world.join(file).is_file() {
            return Err(Error::Input(format!(
                "{} has no ground truth ({file}), which the run is scored against: generate the world with --format ground-truth (or add [[export]] type = \"ground-truth\" to its pipeline)",
                world.display()
            )));
        }
    }
    let doc: FreeSpace = crate::score::world::read_doc(
        world,
        "generate the world again with --format ground-truth",
    )?;
    let [nz, ny, nx] = doc.shape;
    Ok(Grid {
        origin: doc.origin,
        voxel: doc.voxel_m,
        n: [nx, ny, nz],
    })
}
