//! Python values to TOML and back: a pipeline given as a dict, and a component's keys handed
//! to a Python class.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// A Python value as TOML, or the dotted `key` at fault and a message saying what it accepts.
pub fn py_to_toml(v: &Bound<'_, PyAny>, key: &str) -> Result<toml::Value, (String, String)> {
    convert(v, key).map_err(|m| (key_of(&m), m))
}

/// The key a message of [`convert`] starts with.
fn key_of(message: &str) -> String {
    message.split(": ").next().unwrap_or_default().to_owned()
}

fn convert(v: &Bound<'_, PyAny>, key: &str) -> Result<toml::Value, String> {
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
            t.insert(k, convert(&item, &dotted)?);
        }
        return Ok(toml::Value::Table(t));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let mut out = Vec::new();
        for (i, item) in v.try_iter().map_err(|e| format!("{key}: {e}"))?.enumerate() {
            let item = item.map_err(|e| format!("{key}: {e}"))?;
            out.push(convert(&item, &format!("{key}[{i}]"))?);
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
