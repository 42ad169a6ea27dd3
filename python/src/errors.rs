//! Errors as Python exceptions: the command line's message, and where the CLI would point
//! (file, line, column, key), raised as the matching subclass of `subtgraph.Error`
//! (defined in `subtgraph/errors.py`, where their documentation is).

use pyo3::prelude::*;
use pyo3::types::PyDict;

use subtgraph::folder::FolderError;
use subtgraph_core::error::{ConfigError, Error, shorten};
use subtgraph_plugins::PluginError;

/// Where an error points in a pipeline file.
#[derive(Default)]
struct Place {
    file: Option<String>,
    line: Option<usize>,
    column: Option<usize>,
    key: Option<String>,
}

impl From<&ConfigError> for Place {
    fn from(c: &ConfigError) -> Self {
        Place {
            file: Some(c.location.file.to_string()),
            line: Some(c.location.line),
            column: Some(c.location.column),
            key: (!c.key.is_empty()).then(|| c.key.clone()),
        }
    }
}

/// The exception class of an error and where it points.
fn classify(e: &anyhow::Error) -> (&'static str, Place) {
    for cause in e.chain() {
        if let Some(c) = cause.downcast_ref::<ConfigError>() {
            return ("ConfigError", c.into());
        }
        if let Some(core) = cause.downcast_ref::<Error>() {
            return match core {
                Error::Config(c) => ("ConfigError", c.into()),
                Error::Unsatisfiable { .. } => ("GenerationError", Place::default()),
                Error::TooLarge(_) => ("TooLargeError", Place::default()),
                Error::Import { source_name, .. } => (
                    "OccupancyError",
                    Place {
                        file: Some(source_name.clone()),
                        ..Place::default()
                    },
                ),
                _ => ("ComponentError", Place::default()),
            };
        }
        if cause.downcast_ref::<FolderError>().is_some() {
            return ("FolderError", Place::default());
        }
        if cause.downcast_ref::<PluginError>().is_some() {
            return ("PluginError", Place::default());
        }
    }
    ("Error", Place::default())
}

/// An instance of `subtgraph.errors.NAME` with this message and place.
fn exception<'py>(
    py: Python<'py>,
    class: &str,
    message: &str,
    place: Place,
) -> PyResult<Bound<'py, PyAny>> {
    let cls = py.import("subtgraph.errors")?.getattr(class)?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("file", place.file)?;
    kwargs.set_item("line", place.line)?;
    kwargs.set_item("column", place.column)?;
    kwargs.set_item("key", place.key)?;
    cls.call((message,), Some(&kwargs))
}

/// A Python exception of class `subtgraph.errors.NAME` carrying `message`.
pub fn raise(py: Python<'_>, class: &str, message: &str) -> PyErr {
    match exception(py, class, &shorten(message), Place::default()) {
        Ok(e) => PyErr::from_value(e),
        Err(e) => e,
    }
}

/// [`raise`] about a key of a pipeline given from Python (`file` is `<dict>`).
pub fn raise_at(py: Python<'_>, class: &str, message: &str, file: &str, key: &str) -> PyErr {
    let place = Place {
        file: Some(file.to_owned()),
        key: (!key.is_empty()).then(|| key.to_owned()),
        ..Place::default()
    };
    match exception(py, class, &shorten(message), place) {
        Ok(e) => PyErr::from_value(e),
        Err(e) => e,
    }
}

/// The Python exception for an error of the library: the message the command line prints
/// (every cause once, long values cut), as the subclass of `subtgraph.Error` it belongs to.
pub fn to_py(py: Python<'_>, e: &anyhow::Error) -> PyErr {
    let message = shorten(&subtgraph::make::message(e)).into_owned();
    let (class, place) = classify(e);
    match exception(py, class, &message, place) {
        Ok(e) => PyErr::from_value(e),
        Err(e) => e,
    }
}

/// Converts a library result into a Python one.
pub trait OrRaise<T> {
    /// The value, or the error as a Python exception.
    fn or_raise(self, py: Python<'_>) -> PyResult<T>;
}

impl<T, E: Into<anyhow::Error>> OrRaise<T> for Result<T, E> {
    fn or_raise(self, py: Python<'_>) -> PyResult<T> {
        self.map_err(|e| to_py(py, &e.into()))
    }
}
