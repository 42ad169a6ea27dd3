//! Python bindings of subtgraph (the `subtgraph._native` extension module; the package's
//! Python half, `python/subtgraph/`, wraps it with the documented API).
//!
//! Every command runs through the application library (`subtgraph-app`), as the command line
//! does: the same requests (`GenerateRequest`, `DatasetRequest`, `StatsRequest`), registry,
//! components, world and atomic folder, so a world made from Python is byte for byte the one
//! `subtgraph generate` makes, and an error carries the same message.
//! The GIL is released while a world is generated or exported.
#![allow(unsafe_code)]

mod callbacks;
mod convert;
mod errors;
mod explore;
mod rays;
mod world;

use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyType};

use subtgraph_app::pipeline::{Adjustments, PipelineSource};
use subtgraph_app::presets as preset_files;
use subtgraph_app::{DatasetRequest, Error, Frontend, GenerateRequest, StatsRequest};
use subtgraph_core::Pipeline;

use callbacks::{Failures, Kind, REGISTERED, Registered};
use errors::{OrRaise, raise};
use world::PyWorld;

/// Plugins loaded with `load_plugin`, added to every run's registry.
static PLUGINS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn plugins_with(extra: Option<Vec<PathBuf>>) -> Vec<PathBuf> {
    let mut all = PLUGINS.lock().unwrap_or_else(|e| e.into_inner()).clone();
    all.extend(extra.unwrap_or_default());
    all
}

/// The pipeline from `preset=` or `pipeline=` (a path, TOML text or a dict).
fn load(
    py: Python<'_>,
    preset: Option<&str>,
    pipeline: Option<&Bound<'_, PyAny>>,
) -> PyResult<PipelineSource> {
    let Some(pipeline) = pipeline else {
        return Ok(PipelineSource::Preset(preset.unwrap_or("cave").to_owned()));
    };
    if preset.is_some() {
        return Err(raise(
            py,
            "ConfigError",
            "give preset= or pipeline=, not both (a pipeline that starts from a preset's values can be written out from subtgraph.preset_text(NAME))",
        ));
    }
    let given = |p: Pipeline, description: &str| PipelineSource::Given {
        pipeline: Box::new(p),
        description: description.into(),
    };
    if let Ok(d) = pipeline.cast::<PyDict>() {
        let table = convert::py_to_toml(d.as_any(), "")
            .map_err(|(key, m)| errors::raise_at(py, "ConfigError", &m, "<dict>", &key))?;
        let text = toml::to_string(&table).map_err(|e| raise(py, "ConfigError", &e.to_string()))?;
        let p = Pipeline::parse(&text, "<dict>").or_raise(py)?;
        return Ok(given(p, "a dict from Python"));
    }
    if let Ok(text) = pipeline.extract::<String>() {
        if text.contains('\n') || text.contains('=') {
            let p = Pipeline::parse(&text, "<string>").or_raise(py)?;
            return Ok(given(p, "TOML text from Python"));
        }
    }
    let path: PathBuf = pipeline.extract().map_err(|_| {
        raise(
            py,
            "ConfigError",
            &format!(
                "pipeline= takes a path, TOML text or a dict, not a {}",
                pipeline
                    .get_type()
                    .name()
                    .map_or_else(|_| "value".into(), |n| n.to_string())
            ),
        )
    })?;
    Ok(PipelineSource::File(path))
}

/// Builds and generates; see `subtgraph.generate` in `python/subtgraph/__init__.py`.
#[pyfunction]
#[pyo3(signature = (preset=None, pipeline=None, seed=None, formats=None, mesh=true, tileset=None, plugins=None, max_memory=None))]
#[allow(clippy::too_many_arguments)]
fn generate(
    py: Python<'_>,
    preset: Option<&str>,
    pipeline: Option<&Bound<'_, PyAny>>,
    seed: Option<u64>,
    formats: Option<Vec<String>>,
    mesh: bool,
    tileset: Option<&str>,
    plugins: Option<Vec<PathBuf>>,
    max_memory: Option<&str>,
) -> PyResult<PyWorld> {
    let request = GenerateRequest {
        source: load(py, preset, pipeline)?,
        seed,
        adjust: Adjustments {
            tileset: tileset.map(str::to_owned),
            no_mesh: !mesh,
            formats: formats.unwrap_or_default(),
        },
        plugins: plugins_with(plugins),
        occupancy: None,
        max_memory: max_memory.map(str::to_owned),
        frontend: Frontend::Python,
    };
    let failures = Arc::new(Failures::default());
    let prepared = request.prepare(&mut |registry| {
        callbacks::register_all(py, registry, &failures)?;
        Ok(())
    });
    if let Some(e) = failures.take(py) {
        return Err(e);
    }
    let prepared = prepared.or_raise(py)?;
    for name in &prepared.skipped {
        warn(
            py,
            &format!(
                "skipping exporter '{name}': it writes geometry, and mesh=False asked for none"
            ),
        )?;
    }
    let made = py.detach(|| request.make(prepared));
    if let Some(e) = failures.take(py) {
        return Err(e);
    }
    let made = made.or_raise(py)?;
    Ok(PyWorld::new(made.world, made.exporters, request.plugins))
}

fn warn(py: Python<'_>, message: &str) -> PyResult<()> {
    py.import("warnings")?.call_method1("warn", (message,))?;
    Ok(())
}

/// `[(name, summary)]` of the presets.
#[pyfunction]
fn presets() -> Vec<(String, String)> {
    preset_files::PRESETS
        .iter()
        .map(|(n, _)| (n.to_string(), preset_files::summary(n).to_owned()))
        .collect()
}

/// A preset's pipeline text.
#[pyfunction]
fn preset_text(py: Python<'_>, name: &str) -> PyResult<String> {
    preset_files::text(name).map(str::to_owned).ok_or_else(|| {
        errors::to_py(
            py,
            &Error::UnknownPreset {
                name: subtgraph_core::error::excerpt(name).into_owned(),
                known: preset_files::names(),
            },
        )
    })
}

/// `[(kind, name, origin, summary)]` of every component the registry has, as
/// `subtgraph list` shows them (Python ones and loaded plugins included).
#[pyfunction]
fn components(py: Python<'_>) -> PyResult<Vec<(String, String, String, String)>> {
    let mut registry =
        subtgraph_app::registry_with(&Pipeline::default(), &plugins_with(None)).or_raise(py)?;
    callbacks::register_all(py, &mut registry, &Arc::new(Failures::default())).or_raise(py)?;
    Ok(subtgraph_app::plugins::components(&registry)
        .into_iter()
        .map(|c| (c.kind, c.name, c.origin, c.summary))
        .collect())
}

/// Loads a plugin library for every later run; returns the names it adds.
#[pyfunction]
fn load_plugin(py: Python<'_>, path: PathBuf) -> PyResult<Vec<String>> {
    let before = subtgraph_app::registry();
    let mut after = subtgraph_app::registry();
    subtgraph_plugins::load(&path, &mut after).or_raise(py)?;
    let names = |r: &subtgraph_core::Registry| -> Vec<String> {
        let mut v: Vec<String> = Vec::new();
        v.extend(r.route_descriptors.names().iter().map(|s| s.to_string()));
        v.extend(r.constraint_shapes.names().iter().map(|s| s.to_string()));
        v.extend(r.tilesets.names().iter().map(|s| s.to_string()));
        v.extend(r.exporters.names().iter().map(|s| s.to_string()));
        v
    };
    let old = names(&before);
    let added = names(&after)
        .into_iter()
        .filter(|n| !old.contains(n))
        .collect();
    let mut plugins = PLUGINS.lock().unwrap_or_else(|e| e.into_inner());
    if !plugins.contains(&path) {
        plugins.push(path);
    }
    Ok(added)
}

/// Registers a Python route descriptor or constraint shape under `name`.
#[pyfunction]
fn register(py: Python<'_>, kind: &str, name: &str, object: Bound<'_, PyAny>) -> PyResult<()> {
    let kind = match kind {
        "route descriptor" => Kind::Route,
        "constraint shape" => Kind::Shape,
        _ => {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "unknown kind {kind}"
            )));
        }
    };
    if name.is_empty() || name.chars().any(|c| c.is_whitespace() || c == '"') {
        return Err(raise(
            py,
            "ConfigError",
            &format!(
                "'{name}' cannot be a `type` name: use letters, digits and dashes, like \"spiral\""
            ),
        ));
    }
    if !object.is_callable() && !object.is_instance_of::<PyType>() {
        return Err(pyo3::exceptions::PyTypeError::new_err(
            "decorate a function or a class",
        ));
    }
    let summary = object
        .getattr("__doc__")
        .ok()
        .and_then(|d| d.extract::<String>().ok())
        .and_then(|d| {
            d.lines()
                .map(str::trim)
                .find(|l| !l.is_empty())
                .map(str::to_owned)
        })
        .unwrap_or_else(|| "written in Python".into());
    // A taken name is an error, never an override: check against the built-ins, the loaded
    // plugins and the Python components so far.
    let mut registry =
        subtgraph_app::registry_with(&Pipeline::default(), &plugins_with(None)).or_raise(py)?;
    callbacks::register_all(py, &mut registry, &Arc::new(Failures::default())).or_raise(py)?;
    let (taken, what) = match kind {
        Kind::Route => (
            registry
                .route_descriptors
                .get(name)
                .ok()
                .map(|e| e.origin.clone()),
            "route descriptor",
        ),
        Kind::Shape => (
            registry
                .constraint_shapes
                .get(name)
                .ok()
                .map(|e| e.origin.clone()),
            "constraint shape",
        ),
    };
    if let Some(origin) = taken {
        return Err(raise(
            py,
            "ConfigError",
            &format!(
                "{what} '{name}' is already registered by {origin}; choose another name (two components cannot share a `type` name), or call subtgraph.unregister(\"{name}\") first to replace a Python one"
            ),
        ));
    }
    REGISTERED
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(Registered {
            kind,
            name: name.to_owned(),
            object: object.unbind(),
            summary,
        });
    Ok(())
}

/// Removes a Python component; returns whether one was registered under `name`.
#[pyfunction]
fn unregister(name: &str) -> bool {
    let mut r = REGISTERED.lock().unwrap_or_else(|e| e.into_inner());
    let before = r.len();
    r.retain(|x| x.name != name);
    r.len() != before
}

/// Makes a dataset as `subtgraph dataset` does; returns `{made, skipped, indexed}`.
#[pyfunction]
#[pyo3(signature = (out, presets=None, pipelines=None, count=1, seed=0, jobs=None, formats=None, mesh=true, tileset=None, plugins=None, max_memory=None))]
#[allow(clippy::too_many_arguments)]
fn dataset<'py>(
    py: Python<'py>,
    out: PathBuf,
    presets: Option<Vec<String>>,
    pipelines: Option<Vec<PathBuf>>,
    count: usize,
    seed: u64,
    jobs: Option<usize>,
    formats: Option<Vec<String>>,
    mesh: bool,
    tileset: Option<String>,
    plugins: Option<Vec<PathBuf>>,
    max_memory: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let request = DatasetRequest {
        pipelines: pipelines.unwrap_or_default(),
        presets: presets.unwrap_or_default(),
        count,
        seed,
        out,
        jobs,
        adjust: Adjustments {
            tileset,
            no_mesh: !mesh,
            formats: formats.unwrap_or_default(),
        },
        plugins: plugins_with(plugins),
        max_memory: max_memory.map(str::to_owned),
        frontend: Frontend::Python,
        ..DatasetRequest::default()
    };
    let opts = request.options().or_raise(py)?;
    let failures = Arc::new(Failures::default());
    let sources = request.sources(&mut |registry| {
        callbacks::register_all(py, registry, &failures)?;
        Ok(())
    });
    if let Some(e) = failures.take(py) {
        return Err(e);
    }
    let (mut sources, skipped) = sources.or_raise(py)?;
    for source in &mut sources {
        // Runs first in every world folder: a world made after a Python callback failed is
        // not written.
        source
            .components
            .exporters
            .insert(0, callbacks::gate(&failures));
    }
    for name in skipped {
        warn(
            py,
            &format!(
                "skipping exporter '{name}': it writes geometry, and mesh=False asked for none"
            ),
        )?;
    }
    let summary = py.detach(|| subtgraph_app::dataset::run(&sources, &opts));
    if let Some(e) = failures.take(py) {
        return Err(e);
    }
    let summary = summary.or_raise(py)?;
    let d = PyDict::new(py);
    d.set_item("made", summary.made)?;
    d.set_item("skipped", summary.skipped)?;
    d.set_item("indexed", summary.indexed)?;
    Ok(d)
}

/// Writes the variability statistics report as `subtgraph stats` does; returns its summary.
#[pyfunction]
#[pyo3(signature = (inputs, out, crop="common"))]
fn stats(py: Python<'_>, inputs: Vec<PathBuf>, out: PathBuf, crop: &str) -> PyResult<String> {
    let request = StatsRequest {
        inputs,
        out,
        crop: crop.parse().or_raise(py)?,
    };
    py.detach(|| request.run()).map(|r| r.summary).or_raise(py)
}

/// The extension module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyWorld>()?;
    m.add_class::<callbacks::PySegment>()?;
    m.add_class::<explore::PyExplore>()?;
    m.add_function(wrap_pyfunction!(generate, m)?)?;
    m.add_function(wrap_pyfunction!(presets, m)?)?;
    m.add_function(wrap_pyfunction!(preset_text, m)?)?;
    m.add_function(wrap_pyfunction!(components, m)?)?;
    m.add_function(wrap_pyfunction!(load_plugin, m)?)?;
    m.add_function(wrap_pyfunction!(register, m)?)?;
    m.add_function(wrap_pyfunction!(unregister, m)?)?;
    m.add_function(wrap_pyfunction!(dataset, m)?)?;
    m.add_function(wrap_pyfunction!(stats, m)?)?;
    m.add("VERSION", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
