//! Route descriptors and constraint shapes written in Python, registered at run time.
//!
//! A route descriptor's `offset(t, segment)` is called for every guide point of every route,
//! from the generator's threads: each call takes the GIL for itself only (generation runs
//! with it released), so Python threads keep running between calls. The core's trait has no
//! error path (a descriptor is a pure function), so a failure (an exception, a value that is
//! not a finite number, an offset that would put the route outside the level) is recorded in
//! the run's [`Failures`], later calls return 0 without calling Python, and the run raises
//! `subtgraph.CallbackError` naming the callback before anything is returned or written.
//!
//! A constraint shape is data (footprint, arms, rotations, clearance): the Python class is
//! instantiated once when the pipeline's components are built, with the structure's keys as
//! keyword arguments, and its answers are checked and copied, so generation never calls back.

use std::sync::{Arc, Mutex};

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyType};

use subtgraph_core::Registry;
use subtgraph_core::error::ConfigError;
use subtgraph_core::grid::Direction;
use subtgraph_core::params::Params;
use subtgraph_core::route::{RouteDescriptor, Segment};
use subtgraph_core::shape::{Arm, ConstraintShape, Heading, Offset};

/// What kind of component a Python object was registered as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// `@subtgraph.route_descriptor(NAME)`.
    Route,
    /// `@subtgraph.constraint_shape(NAME)`.
    Shape,
}

/// A component written in Python.
pub struct Registered {
    /// Route descriptor or shape.
    pub kind: Kind,
    /// Its `type` name.
    pub name: String,
    /// The function or class.
    pub object: Py<PyAny>,
    /// One line saying what it is (the docstring's first line).
    pub summary: String,
}

/// Every Python component registered in this interpreter, in registration order.
pub static REGISTERED: Mutex<Vec<Registered>> = Mutex::new(Vec::new());

/// The first failure of a Python callback in one run, with the exception it raised.
#[derive(Default)]
pub struct Failures {
    first: Mutex<Option<(String, Option<PyErr>)>>,
}

impl Failures {
    fn failed(&self) -> bool {
        self.first
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .is_some()
    }

    fn record(&self, message: String, cause: Option<PyErr>) {
        let mut first = self.first.lock().unwrap_or_else(|e| e.into_inner());
        if first.is_none() {
            *first = Some((message, cause));
        }
    }

    /// The recorded failure as `subtgraph.CallbackError` (its cause the callback's own
    /// exception), if any.
    pub fn take(&self, py: Python<'_>) -> Option<PyErr> {
        let (message, cause) = self
            .first
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .take()?;
        let err = crate::errors::raise(py, "CallbackError", &message);
        err.set_cause(py, cause);
        Some(err)
    }
}

/// A segment as Python sees it: the straight segment a route descriptor bends.
#[pyclass(module = "subtgraph._native", name = "Segment", frozen)]
pub struct PySegment {
    /// Start, `(row, col)`.
    #[pyo3(get)]
    start: (f64, f64),
    /// End, `(row, col)`.
    #[pyo3(get)]
    end: (f64, f64),
    /// Rows of the level.
    #[pyo3(get)]
    rows: usize,
    /// Columns of the level.
    #[pyo3(get)]
    cols: usize,
    /// Which side the route bends to: 1.0 or -1.0.
    #[pyo3(get)]
    side: f64,
    seg: Segment,
}

#[pymethods]
impl PySegment {
    /// Euclidean length in cells.
    fn length(&self) -> f64 {
        self.seg.length()
    }

    /// The point `(row, col)` at `t` moved `offset` cells along the unit perpendicular.
    fn point(&self, t: f64, offset: f64) -> (f64, f64) {
        let p = self.seg.point(t, offset);
        (p[0], p[1])
    }

    fn __repr__(&self) -> String {
        format!(
            "Segment(start={:?}, end={:?}, rows={}, cols={}, side={})",
            self.start, self.end, self.rows, self.cols, self.side
        )
    }
}

fn segment(s: &Segment) -> PySegment {
    PySegment {
        start: (s.start[0], s.start[1]),
        end: (s.end[0], s.end[1]),
        rows: s.rows,
        cols: s.cols,
        side: s.side,
        seg: *s,
    }
}

/// A route descriptor calling a Python function (or an instance's `offset` method).
struct PythonRoute {
    name: String,
    offset: Py<PyAny>,
    failures: Arc<Failures>,
}

impl PythonRoute {
    fn fail(&self, message: String, cause: Option<PyErr>) -> f64 {
        self.failures.record(
            format!("route descriptor '{}' (Python): {message}", self.name),
            cause,
        );
        0.0
    }
}

impl RouteDescriptor for PythonRoute {
    fn offset(&self, t: f64, s: &Segment) -> f64 {
        if self.failures.failed() {
            return 0.0;
        }
        let called = Python::attach(|py| -> Result<f64, (String, Option<PyErr>)> {
            let seg = Py::new(py, segment(s)).map_err(|e| (e.to_string(), Some(e)))?;
            let value = self.offset.call1(py, (t, seg)).map_err(|e| {
                (
                    format!(
                        "raised {} at t = {t}",
                        e.value(py)
                            .repr()
                            .map_or_else(|_| e.to_string(), |r| r.to_string())
                    ),
                    Some(e),
                )
            })?;
            value.extract::<f64>(py).map_err(|_| {
                let shown = value
                    .bind(py)
                    .repr()
                    .map_or_else(|_| "?".to_owned(), |r| r.to_string());
                (
                    format!("returned {} at t = {t}, not a number: return the sideways offset in cells as a float", subtgraph_core::error::excerpt(&shown)),
                    None,
                )
            })
        });
        match called {
            Err((message, cause)) => self.fail(message, cause),
            Ok(x) if !x.is_finite() => self.fail(
                format!("returned {x} at t = {t}: an offset must be a finite number of cells"),
                None,
            ),
            Ok(x) => {
                // Near the border a guide is clamped to the level, as the built-in
                // descriptors' are; an offset taking it far outside is a bug of the callback.
                let [r, c] = s.point(t, x);
                let slack = (s.rows.min(s.cols) as f64 / 4.0).max(2.0);
                let inside = |v: f64, n: usize| v >= -slack && v <= n as f64 - 1.0 + slack;
                if inside(r, s.rows) && inside(c, s.cols) {
                    x
                } else {
                    self.fail(
                        format!(
                            "returned {x} at t = {t}, which puts the route at row {r:.1}, column {c:.1}, outside the level's {} x {} cells (by more than {slack} cells, a quarter of its smaller side); keep offsets within the level (the segment passed in has rows, cols and length())",
                            s.rows, s.cols
                        ),
                        None,
                    )
                }
            }
        }
    }
}

/// A Python exception as one line: `TypeError: message`.
fn describe(py: Python<'_>, e: &PyErr) -> String {
    let name = e
        .get_type(py)
        .name()
        .map_or_else(|_| "exception".to_owned(), |n| n.to_string());
    format!("{name}: {}", e.value(py))
}

/// Keyword arguments from a component's table.
fn kwargs<'py>(py: Python<'py>, params: &Params) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (k, v) in params.to_table() {
        d.set_item(k, crate::convert::toml_to_py(py, &v)?)?;
    }
    Ok(d)
}

/// Builds the Python object for a component: a class is instantiated with the table's keys;
/// a function takes none.
fn instantiate<'py>(
    py: Python<'py>,
    object: &Bound<'py, PyAny>,
    what: &str,
    name: &str,
    params: &Params,
    failures: &Failures,
) -> Result<Option<Bound<'py, PyAny>>, ConfigError> {
    if !object.is_instance_of::<PyType>() {
        if let Some(key) = params.to_table().keys().next() {
            return Err(params.error(
                key,
                format!("{what} '{name}' is a Python function and takes no keys: remove `{key}`, or decorate a class whose __init__ takes it"),
            ));
        }
        return Ok(None);
    }
    let args = kwargs(py, params).map_err(|e| params.error("type", describe(py, &e)))?;
    match object.call((), Some(&args)) {
        Ok(o) => Ok(Some(o)),
        Err(e) => {
            let message = format!("{what} '{name}' (Python): {}", describe(py, &e));
            failures.record(message.clone(), Some(e));
            Err(params.error("type", message))
        }
    }
}

/// Adds the Python components to a registry; their failures during a run go to `failures`.
pub fn register_all(
    py: Python<'_>,
    registry: &mut Registry,
    failures: &Arc<Failures>,
) -> Result<(), subtgraph_core::registry::DuplicateName> {
    let registered = REGISTERED.lock().unwrap_or_else(|e| e.into_inner());
    for r in registered.iter() {
        let object = r.object.clone_ref(py);
        let name = r.name.clone();
        let failures = failures.clone();
        match r.kind {
            Kind::Route => registry.route_descriptors.register(
                &r.name,
                "python",
                &r.summary,
                Arc::new(move |params: &Params| {
                    Python::attach(|py| {
                        let object = object.bind(py);
                        let offset = match instantiate(py, object, "route descriptor", &name, params, &failures)? {
                            Some(instance) => instance.getattr("offset").map_err(|e| {
                                params.error("type", format!("route descriptor '{name}' (Python): its class needs a method offset(self, t, segment): {}", describe(py, &e)))
                            })?,
                            None => object.clone(),
                        };
                        Ok(Box::new(PythonRoute {
                            name: name.clone(),
                            offset: offset.unbind(),
                            failures: failures.clone(),
                        }) as Box<dyn RouteDescriptor>)
                    })
                }),
            )?,
            Kind::Shape => registry.constraint_shapes.register(
                &r.name,
                "python",
                &r.summary,
                Arc::new(move |params: &Params| {
                    Python::attach(|py| {
                        let object = object.bind(py);
                        let instance = instantiate(py, object, "constraint shape", &name, params, &failures)?
                            .unwrap_or_else(|| object.clone());
                        let instance = if instance.is_callable() && !object.is_instance_of::<PyType>() {
                            instance.call0().map_err(|e| params.error("type", format!("constraint shape '{name}' (Python): {}", describe(py, &e))))?
                        } else {
                            instance
                        };
                        shape_from(py, &instance)
                            .map(|s| Box::new(s) as Box<dyn ConstraintShape>)
                            .map_err(|m| params.error("type", format!("constraint shape '{name}' (Python): {m}")))
                    })
                }),
            )?,
        }
    }
    Ok(())
}

/// A constraint shape as plain data, read once from a Python object.
struct DataShape {
    footprint: Vec<Offset>,
    arms: Vec<Arm>,
    rotations: u8,
    clearance: i32,
}

impl ConstraintShape for DataShape {
    fn footprint(&self) -> Vec<Offset> {
        self.footprint.clone()
    }
    fn arms(&self) -> Vec<Arm> {
        self.arms.clone()
    }
    fn rotations(&self) -> u8 {
        self.rotations
    }
    fn clearance(&self) -> i32 {
        self.clearance
    }
}

/// An attribute, called when it is a method.
fn value<'py>(o: &Bound<'py, PyAny>, name: &str) -> PyResult<Option<Bound<'py, PyAny>>> {
    if let Ok(d) = o.cast::<PyDict>() {
        return d.get_item(name);
    }
    if !o.hasattr(name)? {
        return Ok(None);
    }
    let v = o.getattr(name)?;
    if v.is_callable() {
        v.call0().map(Some)
    } else {
        Ok(Some(v))
    }
}

fn direction(s: &str) -> Result<Direction, String> {
    match s {
        "east" => Ok(Direction::East),
        "north" => Ok(Direction::North),
        "west" => Ok(Direction::West),
        "south" => Ok(Direction::South),
        _ => Err(format!(
            "heading '{}' is not a direction: write \"north\", \"east\", \"south\" or \"west\", or a pair of perpendicular ones for a quadrant",
            subtgraph_core::error::excerpt(s)
        )),
    }
}

/// The most cells a Python shape's footprint may have (its 4-connectivity check compares
/// every pair of cells).
const MAX_FOOTPRINT: usize = 4096;

fn shape_from(py: Python<'_>, o: &Bound<'_, PyAny>) -> Result<DataShape, String> {
    let py_err = |e: PyErr| describe(py, &e);
    let footprint = value(o, "footprint")
        .map_err(py_err)?
        .ok_or("it has no `footprint`: give a list of (d_row, d_col) cells")?;
    // Its length before its items: a list of a hundred million cells is refused without
    // being copied.
    if let Ok(n) = footprint.len() {
        if n > MAX_FOOTPRINT {
            return Err(format!(
                "`footprint` has {n} cells: give between 1 and {MAX_FOOTPRINT}"
            ));
        }
    }
    let footprint: Vec<(i32, i32)> = footprint.extract().map_err(|e: PyErr| {
        format!(
            "`footprint` must be a list of (d_row, d_col) integer pairs: {}",
            describe(py, &e)
        )
    })?;
    if footprint.is_empty() || footprint.len() > MAX_FOOTPRINT {
        return Err(format!(
            "`footprint` has {} cells: give between 1 and {MAX_FOOTPRINT}",
            footprint.len()
        ));
    }
    if footprint.iter().any(|&(r, c)| r.abs() > 64 || c.abs() > 64) {
        return Err("`footprint` cells must lie within 64 cells of the centre".into());
    }
    // 4-connected: every cell reachable from the first through neighbours.
    let mut seen = vec![false; footprint.len()];
    let mut stack = vec![0];
    seen[0] = true;
    while let Some(i) = stack.pop() {
        let (r, c) = footprint[i];
        for (j, &(r2, c2)) in footprint.iter().enumerate() {
            if !seen[j] && (r - r2).abs() + (c - c2).abs() == 1 {
                seen[j] = true;
                stack.push(j);
            }
        }
    }
    if let Some(j) = seen.iter().position(|s| !s) {
        return Err(format!(
            "`footprint` must be 4-connected, but cell {:?} touches no other cell",
            footprint[j]
        ));
    }
    let raw: Vec<Bound<'_, PyAny>> = value(o, "arms")
        .map_err(py_err)?
        .ok_or("it has no `arms`: give a list of ((d_row, d_col), heading)")?
        .extract()
        .map_err(|e: PyErr| format!("`arms` must be a list: {}", describe(py, &e)))?;
    let mut arms = Vec::new();
    for (i, a) in raw.iter().enumerate() {
        let (from, heading): ((i32, i32), Bound<'_, PyAny>) = a.extract().map_err(|_| {
            format!("arm {i} must be ((d_row, d_col), heading), like ((0, 1), \"east\") or ((1, 1), (\"south\", \"east\"))")
        })?;
        if !footprint.contains(&from) {
            return Err(format!(
                "arm {i} leaves from {from:?}, which is not a footprint cell"
            ));
        }
        let heading = if let Ok(d) = heading.extract::<String>() {
            Heading::Axis(direction(&d)?)
        } else {
            let (a, b): (String, String) = heading.extract().map_err(|_| {
                format!("arm {i}: the heading must be a direction name or a pair of them")
            })?;
            let (a, b) = (direction(&a)?, direction(&b)?);
            if a == b || a.rotated(2) == b {
                return Err(format!(
                    "arm {i}: a quadrant needs two perpendicular directions, not {a:?} and {b:?}"
                ));
            }
            Heading::Quadrant(a, b)
        };
        arms.push(Arm { from, heading });
    }
    let rotations = match value(o, "rotations").map_err(py_err)? {
        Some(v) => v
            .extract::<u8>()
            .ok()
            .filter(|r| matches!(r, 1 | 2 | 4))
            .ok_or("`rotations` must be 1, 2 or 4 (distinct quarter turns)")?,
        None => 4,
    };
    let clearance = match value(o, "clearance").map_err(py_err)? {
        Some(v) => v
            .extract::<i32>()
            .ok()
            .filter(|c| (1..=subtgraph_core::generate::MAX_CLEARANCE).contains(c))
            .ok_or(format!(
                "`clearance` must be a whole number of cells from 1 to {}",
                subtgraph_core::generate::MAX_CLEARANCE
            ))?,
        None => 2,
    };
    Ok(DataShape {
        footprint,
        arms,
        rotations,
        clearance,
    })
}

/// Refuses to write a world once a Python callback of the run has failed: its offsets after
/// the failure were made up (0), so the world is not the one asked for.
struct Gate(Arc<Failures>);

impl subtgraph_core::export::Exporter for Gate {
    fn export(
        &self,
        _world: &subtgraph_core::World,
        _survey: &dyn subtgraph_core::survey::Survey,
        _out: &mut dyn subtgraph_core::export::WorldWriter,
    ) -> Result<(), subtgraph_core::export::ExportError> {
        match &*self.0.first.lock().unwrap_or_else(|e| e.into_inner()) {
            Some((message, _)) => Err(subtgraph_core::export::ExportError::Unsupported(
                message.clone(),
            )),
            None => Ok(()),
        }
    }
}

/// An exporter that fails, so the world folder is not written, once `failures` has one.
pub fn gate(failures: &Arc<Failures>) -> subtgraph_app::pipeline::NamedExporter {
    subtgraph_app::pipeline::NamedExporter {
        name: "python callbacks".into(),
        exporter: Box::new(Gate(failures.clone())),
    }
}
