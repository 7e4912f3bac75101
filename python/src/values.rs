//! Values between Python and the runner: planner parameters (Python to TOML, the form a
//! config's `[planners.label]` table has) and resolved parameters (JSON to Python).

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

use crate::errors::Failure;

/// `value`, given for parameter `key`, as the TOML value a config would hold.
pub fn to_toml(key: &str, value: &Bound<'_, PyAny>) -> Result<toml::Value, Failure> {
    if let Ok(b) = value.cast::<PyBool>() {
        return Ok(toml::Value::Boolean(b.is_true()));
    }
    if let Ok(s) = value.cast::<PyString>() {
        return Ok(toml::Value::String(s.extract::<String>()?));
    }
    if value.is_instance_of::<PyInt>() {
        return value
            .extract::<i64>()
            .map(toml::Value::Integer)
            .map_err(|_| Failure::Param {
                key: key.to_string(),
                message: format!("parameter `{key}`: {value} does not fit a 64-bit signed integer"),
            });
    }
    if let Ok(f) = value.cast::<PyFloat>() {
        return Ok(toml::Value::Float(f.value()));
    }
    if let Ok(items) = value.cast::<PyList>() {
        return items
            .iter()
            .map(|item| to_toml(key, &item))
            .collect::<Result<Vec<_>, _>>()
            .map(toml::Value::Array);
    }
    if let Ok(items) = value.cast::<PyTuple>() {
        return items
            .iter()
            .map(|item| to_toml(key, &item))
            .collect::<Result<Vec<_>, _>>()
            .map(toml::Value::Array);
    }
    if let Ok(dict) = value.cast::<PyDict>() {
        return to_table(dict, key).map(toml::Value::Table);
    }
    // NumPy scalars: integers have `__index__`, floating-point numbers `__float__`.
    if value.hasattr("__index__")? {
        if let Ok(i) = value.extract::<i64>() {
            return Ok(toml::Value::Integer(i));
        }
    }
    if value.hasattr("__float__")? {
        if let Ok(f) = value.extract::<f64>() {
            return Ok(toml::Value::Float(f));
        }
    }
    Err(Failure::Param {
        key: key.to_string(),
        message: format!(
            "parameter `{key}`: a planner parameter is a bool, int, float, str, list or dict, got {}",
            value.get_type().name()?
        ),
    })
}

/// A dict of parameters (string keys) as a TOML table; `within` names the enclosing key
/// (empty at the top).
pub fn to_table(dict: &Bound<'_, PyDict>, within: &str) -> Result<toml::Table, Failure> {
    let mut table = toml::Table::new();
    for (key, value) in dict.iter() {
        let key: String = key.extract().map_err(|_| Failure::Param {
            key: within.to_string(),
            message: format!("parameter names are strings, got {key:?}"),
        })?;
        let full = if within.is_empty() {
            key.clone()
        } else {
            format!("{within}.{key}")
        };
        table.insert(key, to_toml(&full, &value)?);
    }
    Ok(table)
}

/// A JSON value as the Python value `json.loads` would give.
pub fn json_to_py<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        serde_json::Value::Null => py.None().into_bound(py),
        serde_json::Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        serde_json::Value::Number(n) => {
            if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any()
            } else if let Some(u) = n.as_u64() {
                u.into_pyobject(py)?.into_any()
            } else {
                n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any()
            }
        }
        serde_json::Value::String(s) => s.into_pyobject(py)?.into_any(),
        serde_json::Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(json_to_py(py, item)?)?;
            }
            list.into_any()
        }
        serde_json::Value::Object(map) => {
            let dict = PyDict::new(py);
            for (key, item) in map {
                dict.set_item(key, json_to_py(py, item)?)?;
            }
            dict.into_any()
        }
    })
}
