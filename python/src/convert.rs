//! Python values to TOML and back: a pipeline given as a dict, and a component's keys handed
//! to a Python class.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// How deep dicts and lists may nest in a pipeline given as a dict.
///
/// The walk below recurses once per level, so without a bound a dict nested 20,000 deep
/// (or one that contains itself) overflowed the stack and killed the interpreter. No
/// pipeline key is more than four deep (`topology.structure[0].pillars[0]`), and the TOML
/// reader the dict is handed to stops at 80; 64 leaves plugins' own tables room while
/// refusing, with the key, long before either limit.
pub const MAX_DEPTH: usize = 64;

/// A Python value as TOML, or the dotted `key` at fault and a message saying what it accepts.
pub fn py_to_toml(v: &Bound<'_, PyAny>, key: &str) -> Result<toml::Value, (String, String)> {
    convert(v, key, 0).map_err(|m| (key_of(&m), m))
}

/// The key a message of [`convert`] starts with.
fn key_of(message: &str) -> String {
    message.split(": ").next().unwrap_or_default().to_owned()
}

/// `v` at `key`, `depth` dicts and lists down from the pipeline: the depth is checked before
/// anything inside `v` is looked at.
fn convert(v: &Bound<'_, PyAny>, key: &str, depth: usize) -> Result<toml::Value, String> {
    let container = v.is_instance_of::<PyDict>()
        || v.is_instance_of::<PyList>()
        || v.is_instance_of::<PyTuple>();
    if container && depth >= MAX_DEPTH {
        return Err(format!(
            "{key}: dicts and lists nest more than {MAX_DEPTH} deep here (a dict that contains \
             itself does too); no pipeline key is more than a few deep \
             (topology.structure[0].pillars): write the value this key takes"
        ));
    }
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract().unwrap_or(false)));
    }
    if v.is_instance_of::<PyInt>() {
        return v.extract::<i64>().map(toml::Value::Integer).map_err(|_| {
            format!("{key}: the integer {v} is out of range (TOML integers are 64-bit signed)")
        });
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(v.extract().unwrap_or(f64::NAN)));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(v.extract().unwrap_or_default()));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut t = toml::Table::new();
        for (k, item) in d.iter() {
            let k: String = k
                .extract()
                .map_err(|_| format!("{key}: keys must be strings, not {}", type_name(&k)))?;
            let dotted = if key.is_empty() {
                k.clone()
            } else {
                format!("{key}.{k}")
            };
            t.insert(k, convert(&item, &dotted, depth + 1)?);
        }
        return Ok(toml::Value::Table(t));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let mut out = Vec::new();
        for (i, item) in v.try_iter().map_err(|e| format!("{key}: {e}"))?.enumerate() {
            let item = item.map_err(|e| format!("{key}: {e}"))?;
            out.push(convert(&item, &format!("{key}[{i}]"), depth + 1)?);
        }
        return Ok(toml::Value::Array(out));
    }
    Err(format!(
        "{key}: a {} cannot be written in a pipeline; use numbers, strings, booleans, lists and dicts",
        type_name(v)
    ))
}

fn type_name(v: &Bound<'_, PyAny>) -> String {
    v.get_type()
        .name()
        .map_or_else(|_| "value".to_owned(), |n| n.to_string())
}

/// A TOML value as Python.
pub fn toml_to_py<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::String(s) => PyString::new(py, s).into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(f) => PyFloat::new(py, *f).into_any(),
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        toml::Value::Datetime(d) => PyString::new(py, &d.to_string()).into_any(),
        toml::Value::Array(a) => {
            let items = a
                .iter()
                .map(|x| toml_to_py(py, x))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        toml::Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t {
                d.set_item(k, toml_to_py(py, x)?)?;
            }
            d.into_any()
        }
    })
}
