//! The one module that reads the core's [`World`]: every field the Python `World` shows is
//! read here, so a change of the core's world model is adapted in this file alone.
//!
//! Arrays are numpy views of the world's own memory, not copies: the Python object owns the
//! world, never changes it (the class is frozen), and each array keeps it alive as its base.
//! The views are read-only, since writing into them would change a world its files, graph
//! and meshes were made from.

use std::path::PathBuf;
use std::sync::OnceLock;

use numpy::ndarray::{ArrayView, Dimension, IxDyn};
use numpy::{Element, PyArray, PyArrayDyn};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use subtgraph_app::pipeline::NamedExporter;
use subtgraph_app::{Error, folder, pipeline};
use subtgraph_core::World;
use subtgraph_core::export::MemoryWriter;
use subtgraph_core::grid::Cell;
use subtgraph_core::mesh::Mesh;
use subtgraph_core::params::{ComponentSpec, Params};

use crate::errors::OrRaise;

/// A cell as Python sees it: `(level, row, col)`.
type PyCell = (usize, usize, usize);

/// A mesh as Python sees it: vertices `float32 [n, 3]` and triangles `uint32 [m, 3]`.
type PyMesh<'py> = (Bound<'py, PyArrayDyn<f32>>, Bound<'py, PyArrayDyn<u32>>);

/// A generated world, as the Python package's `World` wraps it.
#[pyclass(module = "subtgraph._native", name = "World", frozen)]
pub struct PyWorld {
    world: World,
    /// The pipeline's exporters, built when the world was generated: what `export` writes.
    exporters: Vec<NamedExporter>,
    /// Plugins the generating run loaded (exporters a later `files` call may name).
    plugins: Vec<PathBuf>,
    codes: OnceLock<Vec<u8>>,
    tiles: OnceLock<Vec<u8>>,
    /// The visual surface's ray caster (the world survey's scan rays) and materials, built on
    /// the first cast.
    scene: OnceLock<subtgraph_sensors::Scene>,
    /// What the cameras see (the visual surface, services and artifacts), built on the first
    /// render.
    camera_scene: OnceLock<subtgraph_sensors::camera::scene::CameraScene>,
}

impl PyWorld {
    /// Wraps a generated world with the exporters its pipeline names.
    pub fn new(world: World, exporters: Vec<NamedExporter>, plugins: Vec<PathBuf>) -> Self {
        PyWorld {
            world,
            exporters,
            plugins,
            codes: OnceLock::new(),
            tiles: OnceLock::new(),
            scene: OnceLock::new(),
            camera_scene: OnceLock::new(),
        }
    }
}

/// The world's sensing scene (built once), or a `ValueError` for a world without meshes.
fn scene_of(w: &PyWorld) -> PyResult<&subtgraph_sensors::Scene> {
    if let Some(s) = w.scene.get() {
        return Ok(s);
    }
    // The world's survey holds the one ray-cast hierarchy; the scene keeps it (an `Arc`).
    let value_error =
        |e: &dyn std::fmt::Display| pyo3::exceptions::PyValueError::new_err(e.to_string());
    let survey = subtgraph_survey::WorldSurvey::new(&w.world).map_err(|e| value_error(&e))?;
    let scene = subtgraph_sensors::Scene::of_survey(&survey).map_err(|e| value_error(&e))?;
    Ok(w.scene.get_or_init(|| scene))
}

/// The cameras' scene of the world (built once), or a `ValueError` for a world without meshes.
fn camera_scene_of(w: &PyWorld) -> PyResult<&subtgraph_sensors::camera::scene::CameraScene> {
    if let Some(s) = w.camera_scene.get() {
        return Ok(s);
    }
    use subtgraph_core::survey::Survey;
    let value_error =
        |e: &dyn std::fmt::Display| pyo3::exceptions::PyValueError::new_err(e.to_string());
    let survey = subtgraph_survey::WorldSurvey::new(&w.world).map_err(|e| value_error(&e))?;
    let artifacts = survey.artifacts().map_or(&[][..], |a| &a.artifacts);
    let scene = subtgraph_sensors::camera::scene::CameraScene::of(&w.world, artifacts)
        .map_err(|e| value_error(&e))?;
    Ok(w.camera_scene.get_or_init(|| scene))
}

/// A finite 4 x 4 pose matrix's rigid part.
fn pose_of(m: &numpy::PyReadonlyArray2<'_, f64>) -> PyResult<subtgraph_sensors::frames::Pose> {
    let m = m.as_array();
    if m.shape() != [4, 4] || m.iter().any(|x| !x.is_finite()) {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "pose must be a finite 4 x 4 matrix, not {:?}",
            m.shape()
        )));
    }
    Ok(subtgraph_sensors::frames::Pose {
        translation: [m[[0, 3]], m[[1, 3]], m[[2, 3]]],
        rotation: [
            [m[[0, 0]], m[[0, 1]], m[[0, 2]]],
            [m[[1, 0]], m[[1, 1]], m[[1, 2]]],
            [m[[2, 0]], m[[2, 1]], m[[2, 2]]],
        ],
    })
}

/// Rows of three numbers from an `(n, 3)` array.
fn triples(a: &numpy::PyReadonlyArray2<'_, f64>, what: &str) -> PyResult<Vec<[f64; 3]>> {
    let v = a.as_array();
    if v.ncols() != 3 {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "{what} must be an (n, 3) array, not {:?}",
            v.shape()
        )));
    }
    Ok(v.rows().into_iter().map(|r| [r[0], r[1], r[2]]).collect())
}

/// A read-only numpy view of `view`, whose memory `owner` holds.
fn borrowed<'py, T: Element, D: Dimension>(
    owner: &Bound<'py, PyWorld>,
    view: ArrayView<'_, T, D>,
) -> PyResult<Bound<'py, PyArray<T, D>>> {
    // SAFETY: the memory belongs to the world inside `owner`, which is frozen (no method
    // changes it) and is dropped only when the last reference to `owner` goes; the array holds
    // one as its base object, and is made read-only below, before Python sees it.
    let array = unsafe { PyArray::borrow_from_array(&view, owner.clone().into_any()) };
    array.getattr("flags")?.setattr("writeable", false)?;
    Ok(array)
}

fn dyn_view<'a, T>(data: &'a [T], shape: &[usize]) -> ArrayView<'a, T, IxDyn> {
    ArrayView::from_shape(IxDyn(shape), data).expect("lengths match the world's shape")
}

/// `(n, k)` rows from a slice of `[T; k]`.
fn rows<'py, T: Element, const K: usize>(
    owner: &Bound<'py, PyWorld>,
    data: &[[T; K]],
) -> PyResult<Bound<'py, PyArrayDyn<T>>> {
    borrowed(owner, dyn_view(data.as_flattened(), &[data.len(), K]))
}

fn mesh_of<'a>(w: &'a World, which: &str) -> PyResult<&'a Mesh> {
    let m = w.mesh().ok_or_else(|| {
        pyo3::exceptions::PyValueError::new_err(
            "this world has no mesh: generate it with mesh=True and a pipeline that has a [tileset]",
        )
    })?;
    match which {
        "visual" => Ok(&m.visual),
        "collision" => Ok(&m.collision),
        _ => Err(pyo3::exceptions::PyValueError::new_err(format!(
            "mesh '{which}': choose 'visual' or 'collision'"
        ))),
    }
}

impl PyWorld {
    /// The exporters for `formats` (names, like the command line's `--format`), each checked
    /// against the world's geometry.
    fn exporters_for(&self, formats: &[String]) -> Result<Vec<NamedExporter>, Error> {
        let registry = subtgraph_app::registry_with(&self.world.pipeline, &self.plugins)?;
        let mut p = self.world.pipeline.clone();
        p.export.clear();
        pipeline::add_formats(&mut p, formats)?;
        self.rebuild(&registry, &p.export)
    }

    fn rebuild(
        &self,
        registry: &subtgraph_core::Registry,
        specs: &[ComponentSpec],
    ) -> Result<Vec<NamedExporter>, Error> {
        let mut out = Vec::new();
        for spec in specs {
            let exporter = registry.exporters.build(spec)?;
            if exporter.needs_geometry() && self.world.mesh().is_none() {
                return Err(no_mesh(&spec.type_name));
            }
            out.push(NamedExporter {
                name: spec.type_name.clone(),
                exporter,
            });
        }
        Ok(out)
    }

    /// Runs exporters into memory.
    fn run(&self, exporters: &[NamedExporter]) -> Result<MemoryWriter, Error> {
        let mut out = MemoryWriter::default();
        let survey = subtgraph_survey::WorldSurvey::new(&self.world)?;
        for e in exporters {
            e.exporter
                .export(&self.world, &survey, &mut out)
                .map_err(|source| Error::Export {
                    exporter: e.name.clone(),
                    source,
                })?;
        }
        pipeline::check_plugins()?;
        Ok(out)
    }
}

/// An exporter that writes geometry asked of a world without a mesh.
fn no_mesh(exporter: &str) -> Error {
    Error::Usage(format!(
        "exporter '{exporter}' writes geometry, but this world has no mesh: generate it with mesh=True and a pipeline with a [tileset]"
    ))
}

fn files_dict<'py>(py: Python<'py>, files: &MemoryWriter) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (path, bytes) in &files.files {
        d.set_item(path, PyBytes::new(py, bytes))?;
    }
    Ok(d)
}

/// One MJCF document from the main file and its included part files: each `<include>` line
/// replaced by the part's assets and bodies (MJCF allows repeated sections), so MuJoCo loads
/// it from a string with no files.
fn inline_includes(files: &MemoryWriter) -> Result<String, Error> {
    let text = |path: &str| -> Result<&str, Error> {
        let bytes = files
            .get(path)
            .ok_or_else(|| Error::Input(format!("exporter 'mjcf' wrote no {path}")))?;
        std::str::from_utf8(bytes)
            .map_err(|_| Error::Input(format!("exporter 'mjcf' wrote {path} not as UTF-8")))
    };
    let mut out = String::new();
    for line in text("mujoco/world.xml")?.lines() {
        let Some(file) = line
            .trim()
            .strip_prefix("<include file=\"")
            .and_then(|l| l.strip_suffix("\"/>"))
        else {
            out.push_str(line);
            out.push('\n');
            continue;
        };
        let part = text(&format!("mujoco/{file}"))?;
        for l in part.lines() {
            let t = l.trim_start();
            if t.starts_with("<mujoco") || t.starts_with("</mujoco>") || t.starts_with("<compiler")
            {
                continue;
            }
            out.push_str(l);
            out.push('\n');
        }
    }
    Ok(out)
}

#[pymethods]
impl PyWorld {
    /// `uint8 [levels, rows, cols]`: the original's spatial codes (0 empty, 1 dead end,
    /// 2 straight, 3 corner, 4 T-junction, 5 intersection, 11 shaft up, 111 shaft landing).
    #[getter]
    fn occupancy<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArrayDyn<u8>>> {
        let me = slf.get();
        let codes = me.codes.get_or_init(|| me.world.spatial_codes());
        borrowed(slf, dyn_view(codes, &me.world.occupancy.shape()))
    }

    /// `uint8 [levels, rows, cols, 3]`: per cell its spatial code, its openings (bit 0 east,
    /// 1 north, 2 west, 3 south) and its quarter turns; zeros for empty cells.
    #[getter]
    fn tiles<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArrayDyn<u8>>> {
        let me = slf.get();
        let tiles = me.tiles.get_or_init(|| {
            me.world
                .tiles
                .as_slice()
                .iter()
                .flat_map(|t| match t {
                    Some(t) => [t.kind.spatial_code(), t.openings, t.rotation],
                    None => [0, 0, 0],
                })
                .collect()
        });
        let [l, r, c] = me.world.occupancy.shape();
        borrowed(slf, dyn_view(tiles, &[l, r, c, 3]))
    }

    /// `(levels, rows, cols)`.
    #[getter]
    fn shape(&self) -> (usize, usize, usize) {
        let [l, r, c] = self.world.occupancy.shape();
        (l, r, c)
    }

    /// The world's seed.
    #[getter]
    fn seed(&self) -> u64 {
        self.world.resolved.seed
    }

    /// Metres between tile centres.
    #[getter]
    fn tile_pitch(&self) -> f64 {
        self.world.resolved.tile_pitch
    }

    /// Metres between levels.
    #[getter]
    fn level_height(&self) -> f64 {
        self.world.resolved.level_height
    }

    /// The start cell `(level, row, col)`.
    #[getter]
    fn start(&self) -> Option<(usize, usize, usize)> {
        self.world.start.map(|c| (c.level, c.row, c.col))
    }

    /// Shafts as `((level, row, col) foot, (level, row, col) landing)`.
    #[getter]
    fn shafts(&self) -> Vec<(PyCell, PyCell)> {
        let t = |c: Cell| (c.level, c.row, c.col);
        self.world
            .shafts
            .iter()
            .map(|s| (t(s.up), t(s.landing)))
            .collect()
    }

    /// The world-frame position in metres of a cell's centre on its floor.
    fn cell_position(&self, level: usize, row: usize, col: usize) -> PyResult<(f64, f64, f64)> {
        let [l, r, c] = self.world.occupancy.shape();
        if level >= l || row >= r || col >= c {
            return Err(pyo3::exceptions::PyIndexError::new_err(format!(
                "cell ({level}, {row}, {col}) is outside the world's {l} x {r} x {c} cells"
            )));
        }
        let p = self.world.cell_position(Cell::new(level, row, col));
        Ok((p[0], p[1], p[2]))
    }

    /// The graph (nodes and edges) as JSON text.
    fn graph_json(&self) -> String {
        serde_json::to_string(&self.world.graph).expect("plain data serializes")
    }

    /// Requested against achieved counts per level, as JSON text.
    fn levels_json(&self) -> String {
        serde_json::to_string(&self.world.levels).expect("plain data serializes")
    }

    /// The resolved pipeline as `world.toml` holds it.
    fn world_toml(&self) -> String {
        subtgraph_exporters::world_toml_text(&self.world.pipeline)
    }

    /// Whether the world has meshes.
    #[getter]
    fn has_mesh(&self) -> bool {
        self.world.mesh().is_some()
    }

    /// `(vertices float32 [n, 3], triangles uint32 [m, 3])` of the visual or collision mesh.
    fn mesh<'py>(slf: &Bound<'py, Self>, which: &str) -> PyResult<PyMesh<'py>> {
        let m = mesh_of(&slf.get().world, which)?;
        Ok((rows(slf, &m.positions)?, rows(slf, &m.triangles)?))
    }

    /// Per-vertex normals `float32 [n, 3]` of a mesh (pointing into the passage).
    fn mesh_normals<'py>(
        slf: &Bound<'py, Self>,
        which: &str,
    ) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
        let m = mesh_of(&slf.get().world, which)?;
        rows(slf, &m.normals)
    }

    /// Per-triangle material indices `uint8 [m]` of a mesh (into `material_names`).
    fn mesh_materials<'py>(
        slf: &Bound<'py, Self>,
        which: &str,
    ) -> PyResult<Bound<'py, PyArrayDyn<u8>>> {
        let m = mesh_of(&slf.get().world, which)?;
        if m.materials.is_empty() {
            return Ok(PyArrayDyn::zeros(
                slf.py(),
                IxDyn(&[m.triangles.len()]),
                false,
            ));
        }
        borrowed(slf, dyn_view(&m.materials, &[m.materials.len()]))
    }

    /// Distances in metres from each origin along each direction (normalised) to the first
    /// triangle of the visual surface (with a mine's services), `inf` where none is within `max_range`: `float64 [n]`. Casts in
    /// parallel with the GIL released. A NaN or infinite origin, or a direction that is zero,
    /// NaN or infinite, is a `ValueError` naming its row.
    #[pyo3(signature = (origins, directions, max_range=f64::INFINITY))]
    fn raycast<'py>(
        slf: &Bound<'py, Self>,
        origins: numpy::PyReadonlyArray2<'py, f64>,
        directions: numpy::PyReadonlyArray2<'py, f64>,
        max_range: f64,
    ) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
        let py = slf.py();
        let o = triples(&origins, "origins")?;
        let d = triples(&directions, "directions")?;
        if o.len() != d.len() {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "{} origins but {} directions: give one direction per origin",
                o.len(),
                d.len()
            )));
        }
        crate::rays::check_rays(&o, &d)?;
        let scene = scene_of(slf.get())?;
        let ranges = py.detach(|| {
            let rays: Vec<subtgraph_core::raycast::Ray> = o
                .iter()
                .zip(&d)
                .map(|(&origin, &dir)| {
                    let len = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt();
                    subtgraph_core::raycast::Ray {
                        origin,
                        dir: dir.map(|x| x / len),
                    }
                })
                .collect();
            let max = if max_range.is_finite() {
                max_range
            } else {
                1e7
            };
            scene
                .caster
                .cast_all(&rays, max)
                .into_iter()
                .map(|h| h.map_or(f64::INFINITY, |h| h.t))
                .collect::<Vec<f64>>()
        });
        Ok(numpy::PyArray1::from_vec(py, ranges))
    }

    /// One scan of a LiDAR model (`os1-32`, `os1-64`, `os1-128`, `vlp-16`, `mid-360`, or a
    /// LiDAR table's path) standing still at `pose` (a 4 x 4 world-from-sensor matrix, a rigid
    /// transform: a `ValueError` otherwise): its returns as `float64 [n, 3]` in the sensor's
    /// frame (x forward, z up), without range noise unless `noise` (drawn from `seed`).
    #[pyo3(signature = (pose, model=subtgraph_sensors::lidar::DEFAULT, noise=false, seed=0))]
    fn lidar_scan<'py>(
        slf: &Bound<'py, Self>,
        pose: numpy::PyReadonlyArray2<'py, f64>,
        model: &str,
        noise: bool,
        seed: u64,
    ) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
        let py = slf.py();
        let m = pose.as_array();
        if m.shape() != [4, 4] || m.iter().any(|x| !x.is_finite()) {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "pose must be a finite 4 x 4 matrix, not {:?}",
                m.shape()
            )));
        }
        let pose = subtgraph_sensors::frames::Pose {
            translation: [m[[0, 3]], m[[1, 3]], m[[2, 3]]],
            rotation: [
                [m[[0, 0]], m[[0, 1]], m[[0, 2]]],
                [m[[1, 0]], m[[1, 1]], m[[1, 2]]],
                [m[[2, 0]], m[[2, 1]], m[[2, 2]]],
            ],
        };
        crate::rays::check_rigid(&pose.rotation, [m[[3, 0]], m[[3, 1]], m[[3, 2]], m[[3, 3]]])?;
        let lidar =
            subtgraph_sensors::lidar::LidarModel::named(model, |p| std::fs::read_to_string(p).ok())
                .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
        let scene = scene_of(slf.get())?;
        let points = py.detach(|| {
            subtgraph_sensors::lidar::scan::still_scan(scene, &lidar, pose, noise, seed)
        });
        let n = points.len();
        let flat: Vec<f64> = points.into_iter().flatten().collect();
        numpy::PyArrayMethods::reshape(&numpy::PyArray1::from_vec(py, flat), [n, 3])
    }

    /// One frame of a camera model (`mono`, `stereo`, `fisheye-stereo`, `d435i`, or a
    /// camera table's path) whose camera `index` has its optical frame at `pose` (a 4 x 4
    /// world-from-camera matrix, x right, y down, z forward), lit by the `platform`'s lamps
    /// beside it (`lamp_lumens` each instead, 0 for none; `ambient` lux from everywhere),
    /// exposed by its own metering, without shot and read noise unless `noise`: a dict of
    /// `rgb` (`uint8 [h, w, 3]`, or `[h, w]` for a monochrome camera), `depth` (`float32
    /// [h, w]`, metres along the optical axis, 0 where nothing is seen), `labels` (`uint16
    /// [h, w]`, semantic class ids) and `instances` (`uint32 [h, w]`). `legend()` says what
    /// the class ids are.
    #[pyo3(signature = (pose, camera="stereo", index=0, noise=false, seed=0, lamp_lumens=None, ambient=0.0, platform="ground"))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        slf: &Bound<'py, Self>,
        pose: numpy::PyReadonlyArray2<'py, f64>,
        camera: &str,
        index: usize,
        noise: bool,
        seed: u64,
        lamp_lumens: Option<f64>,
        ambient: f64,
        platform: &str,
    ) -> PyResult<Bound<'py, PyDict>> {
        let py = slf.py();
        let value_error =
            |e: &dyn std::fmt::Display| pyo3::exceptions::PyValueError::new_err(e.to_string());
        let pose = pose_of(&pose)?;
        let request = subtgraph_sensors::CameraRequest {
            model: camera.to_owned(),
            lamp_lumens,
            ambient_lux: ambient,
            ..Default::default()
        };
        let model = subtgraph_sensors::request::camera_options(&request, !noise)
            .map_err(|e| value_error(&e))?
            .model;
        if index >= model.cameras.len() {
            return Err(pyo3::exceptions::PyIndexError::new_err(format!(
                "camera '{camera}' has {} camera(s); index must be below that",
                model.cameras.len()
            )));
        }
        let platform =
            subtgraph_sensors::platform::Platform::named(platform).map_err(|e| value_error(&e))?;
        let scene = camera_scene_of(slf.get())?;
        let still = py.detach(|| {
            subtgraph_sensors::camera::still::render(
                scene,
                &model,
                &platform,
                index,
                pose,
                lamp_lumens,
                ambient,
                !noise,
                seed,
            )
        });
        let (h, w) = (still.height, still.width);
        let out = PyDict::new(py);
        let rgb = numpy::PyArray1::from_vec(py, still.image);
        if still.channels == 3 {
            out.set_item("rgb", numpy::PyArrayMethods::reshape(&rgb, [h, w, 3])?)?;
        } else {
            out.set_item("rgb", numpy::PyArrayMethods::reshape(&rgb, [h, w])?)?;
        }
        let depth = numpy::PyArray1::from_vec(py, still.depth);
        out.set_item("depth", numpy::PyArrayMethods::reshape(&depth, [h, w])?)?;
        let labels = numpy::PyArray1::from_vec(py, still.labels);
        out.set_item("labels", numpy::PyArrayMethods::reshape(&labels, [h, w])?)?;
        let instances = numpy::PyArray1::from_vec(py, still.instances);
        out.set_item(
            "instances",
            numpy::PyArrayMethods::reshape(&instances, [h, w])?,
        )?;
        Ok(out)
    }

    /// What `render`'s class ids and instance ids are, as JSON text: `{"legend": [...],
    /// "instances": {...}}`, as a sequence's `sequence.json` gives them.
    fn legend(&self) -> PyResult<String> {
        let scene = camera_scene_of(self)?;
        Ok(serde_json::json!({"legend": &scene.legend, "instances": &scene.instances}).to_string())
    }

    /// The tile set's material names.
    fn material_names(&self) -> Vec<String> {
        self.world
            .mesh()
            .map(|m| m.materials.iter().map(|x| x.name.clone()).collect())
            .unwrap_or_default()
    }

    /// The files the exporters for `formats` write (the world's own exporters when `None`),
    /// in memory: `{path: bytes}`, paths relative to the world folder.
    #[pyo3(signature = (formats=None))]
    fn files<'py>(
        &self,
        py: Python<'py>,
        formats: Option<Vec<String>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let files = py
            .detach(|| match &formats {
                // The exporters the world was generated with (without those left out under
                // mesh=False).
                None => self.run(&self.exporters),
                Some(f) => self.run(&self.exporters_for(f)?),
            })
            .or_raise(py)?;
        files_dict(py, &files)
    }

    /// The MJCF as one self-contained document and its mesh files: `(xml, {path: bytes})`.
    /// Without `visual` there are no mesh files (collision height fields only, loads in a
    /// tenth of the time).
    #[pyo3(signature = (visual=false))]
    fn mjcf<'py>(&self, py: Python<'py>, visual: bool) -> PyResult<(String, Bound<'py, PyDict>)> {
        let (xml, files) = py
            .detach(|| -> Result<_, Error> {
                if self.world.mesh().is_none() {
                    return Err(no_mesh("mjcf"));
                }
                let mut table = toml::Table::new();
                if !visual {
                    table.insert("visual".into(), toml::Value::String("none".into()));
                }
                let spec = ComponentSpec {
                    type_name: "mjcf".into(),
                    params: Params::from_table("export", table),
                };
                let exporter = subtgraph_app::registry().exporters.build(&spec)?;
                let files = self.run(&[NamedExporter {
                    name: "mjcf".into(),
                    exporter,
                }])?;
                let xml = inline_includes(&files)?;
                let mut assets = MemoryWriter::default();
                for (path, bytes) in files.files {
                    if !path.ends_with(".xml") {
                        assets.files.push((path, bytes));
                    }
                }
                Ok((xml, assets))
            })
            .or_raise(py)?;
        Ok((xml, files_dict(py, &files)?))
    }

    /// Writes the world folder at `folder`, atomically, as `subtgraph generate --out` does:
    /// complete or absent, never over a folder the tool did not write (`force` replaces only
    /// a world folder it wrote). `formats` replaces the exporters the world was generated
    /// with; its `world.toml` records what was written.
    #[pyo3(signature = (folder, formats=None, force=false))]
    fn export(
        &self,
        py: Python<'_>,
        folder: PathBuf,
        formats: Option<Vec<String>>,
        force: bool,
    ) -> PyResult<()> {
        py.detach(|| -> Result<(), Error> {
            let built;
            let (exporters, world_toml) = match &formats {
                None => (&self.exporters, None),
                Some(f) => {
                    built = self.exporters_for(f)?;
                    let mut p = self.world.pipeline.clone();
                    p.export.clear();
                    pipeline::add_formats(&mut p, f)?;
                    (&built, Some(subtgraph_exporters::world_toml_text(&p)))
                }
            };
            folder::sweep_stale_beside(&folder);
            let out = folder::Out {
                path: &folder,
                kind: folder::Kind::World,
                force,
                reading: &[],
            };
            pipeline::write_folder_recording(&self.world, exporters, &out, world_toml.as_deref())?;
            Ok(())
        })
        .or_raise(py)
    }

    fn __repr__(&self) -> String {
        let [l, r, c] = self.world.occupancy.shape();
        format!(
            "World(seed={}, levels={l}, rows={r}, cols={c}, nodes={}, edges={}, mesh={})",
            self.world.resolved.seed,
            self.world.graph.nodes.len(),
            self.world.graph.edges.len(),
            self.world.mesh().is_some()
        )
    }
}
