//! Values between Python and the runner: planner parameters (Python to TOML, the form a
//! config's `[planners.label]` table has), resolved parameters (JSON to Python), and
//! integer arguments of any size ([`Int`]).

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use pyo3::Borrowed;

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
            .map_err(|_| beyond(key, value));
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
        return value
            .extract::<i64>()
            .map(toml::Value::Integer)
            .map_err(|_| beyond(key, value));
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

/// The error of an integer given for parameter `key` that a config's TOML integer cannot
/// hold: parameters (`seed` too) and budget values take 64-bit signed integers, as a
/// config does.
fn beyond(key: &str, value: &Bound<'_, PyAny>) -> Failure {
    let negative = value.lt(0).unwrap_or(false);
    let text = value
        .str()
        .map(|s| s.to_string())
        .unwrap_or_else(|_| "the integer".into());
    let budget = key == "budget" || key.starts_with("budget.");
    let message = match (budget, negative) {
        (true, true) => format!("{key}: {text} is negative; a budget is at least 0"),
        (true, false) => format!(
            "{key}: {text} is more than {}, the largest a budget takes",
            i64::MAX
        ),
        (false, true) => format!(
            "parameter `{key}`: {text} is less than {}, the smallest integer a parameter takes",
            i64::MIN
        ),
        (false, false) => format!(
            "parameter `{key}`: {text} is more than {}, the largest integer a parameter takes",
            i64::MAX
        ),
    };
    Failure::Param {
        key: key.to_string(),
        message,
    }
}

/// A dict of parameters (string keys) as a TOML table; `within` names the enclosing key
/// (empty at the top). A key whose value is None is left out, so that it keeps its
/// default (the value `planners()` reports for a parameter without one).
pub fn to_table(dict: &Bound<'_, PyDict>, within: &str) -> Result<toml::Table, Failure> {
    let mut table = toml::Table::new();
    for (key, value) in dict.iter() {
        if value.is_none() {
            continue;
        }
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

/// An integer argument of any size, for the function that takes it to check and name in
/// its error (pyo3 turns an integer too large for a Rust type into an `OverflowError` whose
/// message names no argument). Anything but an integer is `operator.index`'s `TypeError`,
/// to which pyo3 adds a note naming the argument.
pub enum Int {
    /// A value that fits an `i64`.
    Fits(i64),
    /// One that does not: its sign and its digits.
    Beyond { negative: bool, text: String },
}

impl<'a, 'py> FromPyObject<'a, 'py> for Int {
    type Error = PyErr;

    fn extract(value: Borrowed<'a, 'py, PyAny>) -> PyResult<Int> {
        if let Ok(n) = value.extract::<i64>() {
            return Ok(Int::Fits(n));
        }
        // Any integer, NumPy's included (else the TypeError of `operator.index`).
        let int = value
            .py()
            .import("operator")?
            .call_method1("index", (&*value,))?;
        Ok(Int::Beyond {
            negative: int.lt(0)?,
            text: int.str()?.to_string(),
        })
    }
}

impl std::fmt::Display for Int {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Int::Fits(n) => write!(f, "{n}"),
            Int::Beyond { text, .. } => f.write_str(text),
        }
    }
}

impl Int {
    /// The value if it lies from 0 to `max`, else the `ValueError` of argument `name`
    /// (`hint` says what it takes).
    pub fn at_most(&self, name: &str, max: u64, hint: &str) -> Result<u64, Failure> {
        let negative = match self {
            Int::Fits(n) => match u64::try_from(*n) {
                Ok(v) if v <= max => return Ok(v),
                Ok(_) => false,
                Err(_) => true,
            },
            Int::Beyond { negative, .. } => *negative,
        };
        let what = match negative {
            true => "negative".to_string(),
            false => format!("more than {max}"),
        };
        Err(Failure::Value(format!("{name}: {self} is {what}; {hint}")))
    }
}
