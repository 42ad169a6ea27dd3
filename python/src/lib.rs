//! Python bindings of subtgraph (the `subtgraph._native` extension module; the package's
//! Python half, `python/subtgraph/`, wraps it with the documented API).
//!
//! Generation reuses the command line's steps ([`subtgraph::make`]): the same pipeline
//! loading, registry, components, world and atomic folder, so a world made from Python is
//! byte for byte the one `subtgraph generate` makes, and an error carries the same message.
//! The GIL is released while a world is generated or exported.
#![allow(unsafe_code)]

mod callbacks;
mod convert;
mod errors;
mod world;

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyType};

use subtgraph::make;
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

/// The pipeline from `preset=` or `pipeline=` (a path, TOML text or a dict), and where it
/// came from.
fn load(
    py: Python<'_>,
    preset: Option<&str>,
    pipeline: Option<&Bound<'_, PyAny>>,
) -> PyResult<(Pipeline, String)> {
    let Some(pipeline) = pipeline else {
        let name = preset.unwrap_or("cave");
        if subtgraph::presets::text(name).is_none() {
            return Err(raise(
                py,
                "ConfigError",
                &format!(
                    "unknown preset '{name}'; the presets are: {}",
                    subtgraph::presets::names()
                ),
            ));
        }
        return make::load_pipeline(None, Some(name)).or_raise(py);
    };
    if preset.is_some() {
        return Err(raise(
            py,
            "ConfigError",
            "give preset= or pipeline=, not both (a pipeline that starts from a preset's values can be written out from subtgraph.preset_text(NAME))",
        ));
    }
    if let Ok(d) = pipeline.cast::<PyDict>() {
        let table = convert::py_to_toml(d.as_any(), "")
            .map_err(|(key, m)| errors::raise_at(py, "ConfigError", &m, "<dict>", &key))?;
        let text = toml::to_string(&table).map_err(|e| raise(py, "ConfigError", &e.to_string()))?;
        let p = Pipeline::parse(&text, "<dict>").or_raise(py)?;
        return Ok((p, "a dict from Python".into()));
    }
    if let Ok(text) = pipeline.extract::<String>() {
        if text.contains('\n') || text.contains('=') {
            let p = Pipeline::parse(&text, "<string>").or_raise(py)?;
            return Ok((p, "TOML text from Python".into()));
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
    make::load_pipeline(Some(&path), None).or_raise(py)
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
    let budget = subtgraph::memory::budget(max_memory)
        .map_err(|e| raise(py, "ConfigError", &make::message(&e)))?;
    let (mut p, source) = load(py, preset, pipeline)?;
    if let Some(name) = tileset {
        p.tileset = Some(subtgraph_core::params::ComponentSpec::named(name));
    }
    if !mesh {
        p.tileset = None;
    }
    if let Some(seed) = seed {
        if seed > i64::MAX as u64 {
            return Err(raise(
                py,
                "ConfigError",
                "seed must be at most 2^63 - 1 (9223372036854775807)",
            ));
        }
        p.world.seed = seed;
    }
    make::add_formats(&mut p, formats.as_deref().unwrap_or_default()).or_raise(py)?;
    let plugins = plugins_with(plugins);
    let failures = Arc::new(Failures::default());
    let built = (|| -> anyhow::Result<_> {
        let mut registry = make::registry_with(&p, &plugins)?;
        callbacks::register_all(py, &mut registry, &failures)?;
        let (components, skipped) = make::build_and_skipped(&p, &registry, !mesh)?;
        Ok((components, skipped))
    })();
    if let Some(e) = failures.take(py) {
        return Err(e);
    }
    let (components, skipped) = built.or_raise(py)?;
    for name in skipped {
        warn(
            py,
            &format!(
                "skipping exporter '{name}': it writes geometry, and mesh=False asked for none"
            ),
        )?;
    }
    let made = py.detach(|| make::generate(&p, &components, &source, &budget));
    if let Some(e) = failures.take(py) {
        return Err(e);
    }
    let world = made.or_raise(py)?;
    Ok(PyWorld::new(world, components.exporters, plugins))
}

fn warn(py: Python<'_>, message: &str) -> PyResult<()> {
    py.import("warnings")?.call_method1("warn", (message,))?;
    Ok(())
}

/// `[(name, summary)]` of the presets.
#[pyfunction]
fn presets() -> Vec<(String, String)> {
    subtgraph::presets::PRESETS
        .iter()
        .map(|(n, _)| (n.to_string(), subtgraph::presets::summary(n).to_owned()))
        .collect()
}

/// A preset's pipeline text.
#[pyfunction]
fn preset_text(py: Python<'_>, name: &str) -> PyResult<String> {
    subtgraph::presets::text(name)
        .map(str::to_owned)
        .ok_or_else(|| {
            raise(
                py,
                "ConfigError",
                &format!(
                    "unknown preset '{name}'; the presets are: {}",
                    subtgraph::presets::names()
                ),
            )
        })
}

/// `[(kind, name, origin, summary)]` of every component the registry has, as
/// `subtgraph list` shows them (Python ones and loaded plugins included).
#[pyfunction]
fn components(py: Python<'_>) -> PyResult<Vec<(String, String, String, String)>> {
    let mut registry =
        make::registry_with(&Pipeline::default(), &plugins_with(None)).or_raise(py)?;
    callbacks::register_all(py, &mut registry, &Arc::new(Failures::default())).or_raise(py)?;
    let mut out = Vec::new();
    fn rows<T: ?Sized>(
        c: &subtgraph_core::registry::Catalogue<T>,
        out: &mut Vec<(String, String, String, String)>,
    ) {
        for (name, e) in c.entries() {
            out.push((
                c.kind().into(),
                name.into(),
                e.origin.clone(),
                e.summary.clone(),
            ));
        }
    }
    rows(&registry.route_descriptors, &mut out);
    rows(&registry.constraint_shapes, &mut out);
    rows(&registry.tilesets, &mut out);
    rows(&registry.exporters, &mut out);
    Ok(out)
}

/// Loads a plugin library for every later run; returns the names it adds.
#[pyfunction]
fn load_plugin(py: Python<'_>, path: PathBuf) -> PyResult<Vec<String>> {
    let before = subtgraph::registry();
    let mut after = subtgraph::registry();
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
        make::registry_with(&Pipeline::default(), &plugins_with(None)).or_raise(py)?;
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
    let plugins = plugins_with(plugins);
    let failures = Arc::new(Failures::default());
    let mut skipped: Vec<String> = Vec::new();
    let sources = (|| -> anyhow::Result<Vec<subtgraph::dataset::Source>> {
        if seed > i64::MAX as u64 {
            anyhow::bail!("seed must be at most 2^63 - 1 (9223372036854775807)");
        }
        if count == 0 {
            anyhow::bail!("count must be at least 1 (worlds per source)");
        }
        if jobs == Some(0) {
            anyhow::bail!("jobs must be at least 1");
        }
        let files = pipelines.unwrap_or_default();
        let names = presets.unwrap_or_default();
        if files.is_empty() && names.is_empty() {
            anyhow::bail!(
                "name at least one source: pipelines=[...] or presets=[...] ({})",
                subtgraph::presets::names()
            );
        }
        let chosen = files
            .iter()
            .map(|f| (Some(f.as_path()), None))
            .chain(names.iter().map(|n| (None::<&Path>, Some(n.as_str()))));
        let mut sources = Vec::new();
        let opts = make::SourceOptions {
            tileset: tileset.as_deref(),
            no_mesh: !mesh,
            formats: formats.as_deref().unwrap_or_default(),
            plugins: &plugins,
        };
        for (file, preset) in chosen {
            let (mut source, left_out) =
                make::dataset_source(file, preset, &opts, &mut |registry| {
                    callbacks::register_all(py, registry, &failures)?;
                    Ok(())
                })?;
            // Runs first in every world folder: a world made after a Python callback failed
            // is not written.
            source
                .components
                .exporters
                .insert(0, callbacks::gate(&failures));
            sources.push(source);
            for name in left_out {
                if !skipped.contains(&name) {
                    skipped.push(name);
                }
            }
        }
        Ok(sources)
    })();
    if let Some(e) = failures.take(py) {
        return Err(e);
    }
    let sources = sources.or_raise(py)?;
    for name in skipped {
        warn(
            py,
            &format!(
                "skipping exporter '{name}': it writes geometry, and mesh=False asked for none"
            ),
        )?;
    }
    let opts = subtgraph::dataset::Options {
        count,
        seed,
        out,
        jobs: jobs.unwrap_or_else(|| {
            std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
        }),
        shard: subtgraph::dataset::Shard::ALL,
        max_memory: subtgraph::memory::budget(max_memory)
            .map_err(|e| raise(py, "ConfigError", &make::message(&e)))?,
    };
    let summary = py.detach(|| subtgraph::dataset::run(&sources, &opts));
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
    let crop: subtgraph::stats::Crop = crop
        .parse()
        .map_err(|m: String| raise(py, "ConfigError", &m))?;
    py.detach(|| subtgraph::stats::run(&inputs, &out, crop))
        .or_raise(py)
}

/// The extension module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyWorld>()?;
    m.add_class::<callbacks::PySegment>()?;
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
