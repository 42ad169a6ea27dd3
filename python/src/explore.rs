//! The closed loop from Python: one robot in a world, stepped by a policy (the explore crate's
//! `Env`), which `python/subtgraph/explore.py` wraps as the Gymnasium environment
//! `subtgraph/Explore-v0`. The world is made here (a preset or pipeline, with `[artifacts]`
//! added when it has none) or rebuilt from a world folder; what the loop needs of it (its ray
//! casters, start and artifacts) is kept and the world itself dropped, so an environment holds
//! its collision surface's hierarchy and its robot's map, not the world's meshes.

use std::path::PathBuf;

use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use subtgraph_app::pipeline::PipelineSource;
use subtgraph_app::{Error, Frontend, GenerateRequest};
use subtgraph_explore::body::{Body, Command};
use subtgraph_explore::detect::Detector;
use subtgraph_explore::env::{Env, EnvOptions, OnCollision, TERMS, Weights};
use subtgraph_explore::lidar::Lidar;
use subtgraph_explore::radio::RadioModel;
use subtgraph_explore::{ExploreError, Site};

use crate::errors::{OrRaise, raise};

/// The explore crate's environment, as Python steps it.
#[pyclass(module = "subtgraph._native", name = "ExploreCore")]
pub struct PyExplore {
    env: Env,
    /// Where the world came from, in words.
    source: String,
}

/// An explore error as the Python exception its kind belongs to.
fn explore_error(py: Python<'_>, e: ExploreError) -> PyErr {
    match e {
        ExploreError::Unknown { .. }
        | ExploreError::OutOfBounds { .. }
        | ExploreError::Sense(_) => raise(py, "ConfigError", &e.to_string()),
        ExploreError::MapTooLarge { .. } => raise(py, "TooLargeError", &e.to_string()),
        other => raise(py, "Error", &other.to_string()),
    }
}

/// The world a folder, a pipeline or a preset makes, surveyed into a site.
fn site_of(
    py: Python<'_>,
    preset: Option<&str>,
    pipeline: Option<PathBuf>,
    world: Option<PathBuf>,
    seed: Option<u64>,
    world_index: u64,
    artifacts: bool,
) -> PyResult<(Site, String)> {
    let made: Result<(subtgraph_core::World, String), Error> = py.detach(|| {
        if let Some(folder) = &world {
            subtgraph_app::explore::truth_grid(folder)?;
            let w = subtgraph_app::sense::world_of(folder, &[])?;
            return Ok((w, format!("world folder {}", folder.display())));
        }
        let source = match &pipeline {
            Some(p) => PipelineSource::File(p.clone()),
            None => PipelineSource::Preset(preset.unwrap_or("cave").to_owned()),
        };
        let (mut p, description) = source.load()?;
        if artifacts && p.artifacts.is_none() {
            p.artifacts = Some(Default::default());
        }
        p.export.clear();
        let seed = seed.unwrap_or(p.world.seed).checked_add(world_index);
        let request = GenerateRequest {
            source: PipelineSource::Given {
                pipeline: Box::new(p),
                description: description.clone(),
            },
            seed,
            frontend: Frontend::Python,
            ..GenerateRequest::default()
        };
        Ok((request.generate()?.world, description))
    });
    let (world, description) = made.or_raise(py)?;
    let site = py.detach(|| {
        let survey = subtgraph_survey::WorldSurvey::new(&world).map_err(Error::from)?;
        Site::of(&survey).map_err(Error::from)
    });
    Ok((site.or_raise(py)?, description))
}

#[pymethods]
impl PyExplore {
    /// Makes the world and the environment; see `subtgraph.explore.ExploreEnv`.
    #[new]
    #[pyo3(signature = (preset=None, pipeline=None, world=None, seed=None, world_index=0, platform="ground", lidar=subtgraph_explore::lidar::DEFAULT_MODEL, lidar_columns=None, control_rate=10.0, map_voxel=0.5, max_steps=3000, on_collision="refuse", rewards=None, breadcrumbs=6, noiseless=false, build_map=true, artifacts=true))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        preset: Option<&str>,
        pipeline: Option<PathBuf>,
        world: Option<PathBuf>,
        seed: Option<u64>,
        world_index: u64,
        platform: &str,
        lidar: &str,
        lidar_columns: Option<usize>,
        control_rate: f64,
        map_voxel: f64,
        max_steps: u64,
        on_collision: &str,
        rewards: Option<&Bound<'_, PyDict>>,
        breadcrumbs: usize,
        noiseless: bool,
        build_map: bool,
        artifacts: bool,
    ) -> PyResult<PyExplore> {
        let given = [preset.is_some(), pipeline.is_some(), world.is_some()];
        if given.iter().filter(|g| **g).count() > 1 {
            return Err(raise(
                py,
                "ConfigError",
                "give one of preset=, pipeline= or world= (a world folder), not several",
            ));
        }
        if world.is_some() && seed.is_some() {
            return Err(raise(
                py,
                "ConfigError",
                "seed= picks a preset's or pipeline's world; a world folder has its own (leave seed= out)",
            ));
        }
        let body = Body::named(platform).map_err(|e| explore_error(py, e))?;
        let lidar = Lidar::named(lidar, lidar_columns, |p| std::fs::read_to_string(p).ok())
            .map_err(|e| explore_error(py, e))?;
        let on_collision = match on_collision {
            "refuse" => OnCollision::Refuse,
            "end" => OnCollision::End,
            other => {
                return Err(raise(
                    py,
                    "ConfigError",
                    &format!(
                        "on_collision='{other}': choose 'refuse' (the motion stops short, the episode goes on) or 'end' (the episode ends)"
                    ),
                ));
            }
        };
        let mut weights = Weights::default();
        if let Some(r) = rewards {
            for (k, v) in r.iter() {
                let name: String = k.extract()?;
                let w: f64 = v.extract().map_err(|_| {
                    raise(
                        py,
                        "ConfigError",
                        &format!("rewards['{name}'] must be a number"),
                    )
                })?;
                weights.set(&name, w).map_err(|e| explore_error(py, e))?;
            }
        }
        let (site, source) = site_of(py, preset, pipeline, world, seed, world_index, artifacts)?;
        let options = EnvOptions {
            body,
            lidar,
            control_hz: control_rate,
            map_voxel,
            max_steps,
            on_collision,
            weights,
            breadcrumbs,
            radio: RadioModel::default(),
            detector: Detector::default(),
            noiseless,
            build_map,
            max_map_bytes: 4 << 30,
        };
        let env = py
            .detach(|| Env::new(site, options))
            .map_err(|e| explore_error(py, e))?;
        Ok(PyExplore { env, source })
    }

    /// Starts an episode; `seed` draws the noise and the reports' errors.
    fn reset(&mut self, py: Python<'_>, seed: u64) {
        py.detach(|| self.env.reset(seed));
    }

    /// One control step with a command in SI units (m/s, rad/s, m/s up); returns
    /// `(reward, terminated, truncated, info)`.
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        speed: f64,
        yaw_rate: f64,
        climb: f64,
    ) -> PyResult<(f64, bool, bool, Bound<'py, PyDict>)> {
        let command = Command {
            speed,
            yaw_rate,
            climb,
        };
        let s = self.env.step(command);
        let info = PyDict::new(py);
        info.set_item("time", self.env.time())?;
        info.set_item("refused", s.refused.map(|r| r.name()))?;
        info.set_item("detected", s.detections.len())?;
        info.set_item("delivered", s.delivered)?;
        info.set_item("linked", self.env.linked)?;
        info.set_item("breadcrumbs", self.env.crumbs())?;
        info.set_item("position", self.env.robot.state.position.to_vec())?;
        let terms = PyDict::new(py);
        for (name, v) in TERMS.iter().zip(s.terms) {
            terms.set_item(*name, v)?;
        }
        info.set_item("reward_terms", terms)?;
        Ok((s.reward, s.terminated, s.truncated, info))
    }

    /// What the episode has done so far: `{explored_m3, distance_m, artifacts_detected,
    /// artifacts_delivered, artifacts, breadcrumbs}`.
    fn totals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let r = &self.env.robot;
        let d = PyDict::new(py);
        d.set_item(
            "explored_m3",
            r.map.free as f64 * self.env.options.map_voxel.powi(3),
        )?;
        d.set_item("distance_m", r.odometer)?;
        d.set_item(
            "artifacts_detected",
            r.detected.iter().filter(|x| **x).count(),
        )?;
        d.set_item(
            "artifacts_delivered",
            r.reports.iter().filter(|x| x.delivered.is_some()).count(),
        )?;
        d.set_item("artifacts", self.env.site.artifacts.len())?;
        d.set_item("breadcrumbs", self.env.crumbs())?;
        d.set_item("map_bytes", r.map.bytes())?;
        Ok(d)
    }

    /// The ranges image, `float32 [rings, columns]` metres (0: no return).
    fn ranges<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let (r, c) = (self.env.options.lidar.rings, self.env.options.lidar.columns);
        PyArray1::from_slice(py, &self.env.ranges).reshape([r, c])
    }

    /// The ranges image as sensor-frame points, `float32 [rings * columns, 3]`.
    fn points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let mut out = vec![0.0f32; 3 * self.env.ranges.len()];
        self.env.points(&mut out);
        PyArray1::from_vec(py, out).reshape([self.env.ranges.len(), 3])
    }

    /// The IMU: specific force (m/s^2) and angular rate (rad/s) in the body frame, with the
    /// ADIS16448's white noise unless noiseless.
    fn imu<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        PyArray1::from_iter(py, self.env.imu_noisy().iter().map(|v| *v as f32))
    }

    /// The pose relative to the spawn: `x y z yaw pitch roll`.
    fn pose<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        PyArray1::from_iter(py, self.env.pose().iter().map(|v| *v as f32))
    }

    /// The map around the robot, `uint8 [nz, ny, nx]`: 0 unknown, 1 free, 2 occupied.
    fn local_map<'py>(
        &self,
        py: Python<'py>,
        nz: usize,
        ny: usize,
        nx: usize,
    ) -> PyResult<Bound<'py, PyArray3<u8>>> {
        let mut out = vec![0u8; nx * ny * nz];
        self.env.local_map([nx, ny, nz], &mut out);
        PyArray1::from_vec(py, out).reshape([nz, ny, nx])
    }

    /// The artifacts in view, nearest first: `float32 [max, 4]` rows of body-frame centre and
    /// class number (1 up, in `subtgraph`'s class order; 0 rows: none).
    fn artifacts_in_view<'py>(
        &self,
        py: Python<'py>,
        max: usize,
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let mut out = vec![0.0f32; 4 * max];
        for (i, (p, class)) in self.env.in_view(max).into_iter().enumerate() {
            let number = subtgraph_core::artifacts::ArtifactClass::ALL
                .iter()
                .position(|c| *c == class)
                .map_or(0, |k| k + 1);
            out[4 * i..4 * i + 4].copy_from_slice(&[
                p[0] as f32,
                p[1] as f32,
                p[2] as f32,
                number as f32,
            ]);
        }
        PyArray1::from_vec(py, out).reshape([max, 4])
    }

    /// `{rings, columns, max_range, max_speed, max_reverse, max_yaw_rate, max_climb, flies,
    /// dt, map_voxel, detection_range, artifacts, source, lidar, platform}`.
    fn describe<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let o = &self.env.options;
        let d = PyDict::new(py);
        d.set_item("rings", o.lidar.rings)?;
        d.set_item("columns", o.lidar.columns)?;
        d.set_item("max_range", o.lidar.model.range_m[1])?;
        d.set_item("max_speed", o.body.max_speed)?;
        d.set_item("max_reverse", o.body.max_reverse)?;
        d.set_item("max_yaw_rate", o.body.max_yaw_rate)?;
        d.set_item("max_climb", o.body.max_climb)?;
        d.set_item("flies", o.body.flies())?;
        d.set_item("dt", self.env.dt())?;
        d.set_item("map_voxel", o.map_voxel)?;
        d.set_item("detection_range", o.detector.range_m)?;
        d.set_item("artifacts", self.env.site.artifacts.len())?;
        d.set_item("source", &self.source)?;
        d.set_item("lidar", &o.lidar.model.name)?;
        d.set_item("platform", o.body.name)?;
        d.set_item("world_seed", self.env.site.seed)?;
        Ok(d)
    }
}
