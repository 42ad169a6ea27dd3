//! Errors as Python exceptions: the command line's message, and where the CLI would point
//! (file, line, column, key), raised as the matching subclass of `subtgraph.Error`
//! (defined in `subtgraph/errors.py`, where their documentation is).

use pyo3::prelude::*;
use pyo3::types::PyDict;

use subtgraph_app::Error;
use subtgraph_app::folder::FolderError;
use subtgraph_core::error::{ConfigError, shorten};

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

/// The exception class of an error and where it points: by the variant of the application
/// library's error (the one inside a folder's failure, when writing it failed).
fn classify(e: &Error) -> (&'static str, Place) {
    match e {
        Error::Config(c) => ("ConfigError", c.into()),
        Error::Core(core) => classify_core(core),
        Error::Unmakeable { source, .. } => classify_core(source),
        Error::Usage(_) | Error::UnknownPreset { .. } | Error::NoTileset { .. } => {
            ("ConfigError", Place::default())
        }
        Error::TooLarge(_) => ("TooLargeError", Place::default()),
        Error::TileSet { .. } | Error::Export { .. } | Error::WorldFiles(_) | Error::Survey(_) => {
            ("ComponentError", Place::default())
        }
        Error::Plugin(_) | Error::PluginFailed(_) => ("PluginError", Place::default()),
        Error::Folder(FolderError::Content(inner)) => match inner.downcast_ref::<Error>() {
            Some(inner) => classify(inner),
            None => ("FolderError", Place::default()),
        },
        Error::Folder(_) => ("FolderError", Place::default()),
        _ => ("Error", Place::default()),
    }
}

/// The exception class of a generation error and where it points.
fn classify_core(core: &subtgraph_core::Error) -> (&'static str, Place) {
    match core {
        subtgraph_core::Error::Config(c) => ("ConfigError", c.into()),
        subtgraph_core::Error::Unsatisfiable { .. } => ("GenerationError", Place::default()),
        subtgraph_core::Error::TooLarge(_) => ("TooLargeError", Place::default()),
        subtgraph_core::Error::Import { source_name, .. } => (
            "OccupancyError",
            Place {
                file: Some(source_name.clone()),
                ..Place::default()
            },
        ),
        _ => ("ComponentError", Place::default()),
    }
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
pub fn to_py(py: Python<'_>, e: &Error) -> PyErr {
    let message = shorten(&subtgraph_app::message(e)).into_owned();
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

impl<T, E: Into<Error>> OrRaise<T> for Result<T, E> {
    fn or_raise(self, py: Python<'_>) -> PyResult<T> {
        self.map_err(|e| to_py(py, &e.into()))
    }
}
