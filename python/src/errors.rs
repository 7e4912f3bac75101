//! Errors as Python exceptions: every failure becomes one of the classes of
//! `gridplan/_errors.py` (or `ValueError`/`TypeError`), with the command line's message,
//! its control characters escaped as the command line escapes them for the terminal
//! ([`planner_text::terminal`]); the attributes keep the text as it is.
//!
//! Work that runs without the GIL returns a [`Failure`], which holds no Python object
//! except an already built [`PyErr`]; [`Failure::into_pyerr`] builds the exception once
//! the GIL is back. [`guarded`] turns a panic into a [`Failure::Panic`].

use std::panic::{catch_unwind, AssertUnwindSafe};

use planner_runner::{ErrorClass, RunnerError};
use planner_text::terminal;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Why a call failed.
#[derive(Debug)]
pub enum Failure {
    /// An error of the runner (config, map, parameter, problem, ...).
    Runner(RunnerError),
    /// A map or scenario file that cannot be read.
    Map(planner_maps::MapError),
    /// A map file's scenarios that do not fit it (the command line's message).
    MapMismatch {
        /// The scenario file.
        file: String,
        /// Its 1-based line.
        line: usize,
        /// The message.
        message: String,
    },
    /// A start or goal that cannot be planned.
    Problem {
        /// `start` or `goal`.
        endpoint: &'static str,
        /// The cell as given.
        cell: (i64, i64),
        /// The message.
        message: String,
    },
    /// A start or goal of whole numbers, one beyond `i64`: a cell on no grid
    /// (`ProblemError`, its `cell` the pair as Python values).
    Beyond {
        /// `start` or `goal`.
        endpoint: &'static str,
        /// The cell as given.
        cell: Box<(crate::planner::Coordinate, crate::planner::Coordinate)>,
        /// The message.
        message: String,
    },
    /// A planner argument (a parameter or the budget) of the wrong kind.
    Param {
        /// The parameter's key.
        key: String,
        /// The message.
        message: String,
    },
    /// A value out of its range (`ValueError`).
    Value(String),
    /// A value of the wrong type (`TypeError`).
    Type(String),
    /// Rust code panicked; the panic was caught.
    Panic(String),
    /// An object that cannot serve calls in this process (`GridplanError`).
    Unusable(String),
    /// A Python error raised while talking to Python.
    Python(PyErr),
}

impl From<RunnerError> for Failure {
    fn from(error: RunnerError) -> Failure {
        Failure::Runner(error)
    }
}

impl From<PyErr> for Failure {
    fn from(error: PyErr) -> Failure {
        Failure::Python(error)
    }
}

impl From<planner_maps::MapError> for Failure {
    fn from(error: planner_maps::MapError) -> Failure {
        Failure::Map(error)
    }
}

impl From<Failure> for PyErr {
    fn from(failure: Failure) -> PyErr {
        Python::attach(|py| failure.into_pyerr(py))
    }
}

/// Runs `work`, turning a panic into [`Failure::Panic`].
pub fn guarded<T>(work: impl FnOnce() -> Result<T, Failure>) -> Result<T, Failure> {
    catch_unwind(AssertUnwindSafe(work)).unwrap_or_else(|payload| {
        let what = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".to_string());
        Err(Failure::Panic(what))
    })
}

impl Failure {
    /// The Python exception.
    pub fn into_pyerr(self, py: Python<'_>) -> PyErr {
        let built = match self {
            Failure::Python(error) => return error,
            Failure::Value(message) => {
                return PyValueError::new_err(terminal(&message).into_owned())
            }
            Failure::Type(message) => return PyTypeError::new_err(terminal(&message).into_owned()),
            Failure::Panic(what) => raise(
                py,
                "GridplanError",
                format!("internal error (a bug in gridplan, please report it): {what}"),
                &[],
            ),
            Failure::Unusable(message) => raise(py, "GridplanError", message, &[]),
            Failure::Map(error) => map_error(py, &error),
            Failure::MapMismatch {
                file,
                line,
                message,
            } => raise(
                py,
                "MapError",
                message,
                &[
                    ("file", Attr::from(file)),
                    ("line", Attr::from(line)),
                    ("column", Attr::from(0usize)),
                ],
            ),
            Failure::Problem {
                endpoint,
                cell,
                message,
            } => raise(
                py,
                "ProblemError",
                message,
                &[
                    ("endpoint", Attr::from(endpoint)),
                    ("cell", Attr::from(cell)),
                ],
            ),
            Failure::Beyond {
                endpoint,
                cell,
                message,
            } => {
                let pair = cell.0.to_python(py).and_then(|x| {
                    let y = cell.1.to_python(py)?;
                    Ok(pyo3::types::PyTuple::new(py, [x, y])?.into_any())
                });
                match pair {
                    Ok(pair) => return problem_pyerr(py, endpoint, pair, message),
                    Err(error) => return error,
                }
            }
            Failure::Param { key, message } => {
                raise(py, "ParameterError", message, &[("key", Attr::from(key))])
            }
            Failure::Runner(error) => runner_error(py, error),
        };
        built.unwrap_or_else(|e| e)
    }
}

/// The `ProblemError` of `endpoint` at `cell`, a pair of Python integers (which may be too
/// large for any Rust integer).
pub fn problem_pyerr(
    py: Python<'_>,
    endpoint: &str,
    cell: Bound<'_, PyAny>,
    message: String,
) -> PyErr {
    let built = raise(
        py,
        "ProblemError",
        message,
        &[
            ("endpoint", Attr::from(endpoint)),
            ("cell", Attr::Object(cell.unbind())),
        ],
    );
    built.unwrap_or_else(|e| e)
}

fn map_error(py: Python<'_>, error: &planner_maps::MapError) -> PyResult<PyErr> {
    raise(
        py,
        "MapError",
        error.to_string(),
        &[
            ("file", Attr::from(error.file.as_str())),
            ("line", Attr::from(error.line)),
            ("column", Attr::from(error.column)),
        ],
    )
}

/// The exception of a runner error: its class from [`RunnerError::class`] (the command
/// line's exit status follows the same class; a `merge:` or `report:` context keeps it),
/// its message the whole one, its attributes from the innermost error.
fn runner_error(py: Python<'_>, error: RunnerError) -> PyResult<PyErr> {
    let message = error.to_string();
    let class = match error.class() {
        ErrorClass::Config => "ConfigError",
        ErrorClass::Map => "MapError",
        ErrorClass::Problem => "ProblemError",
        ErrorClass::Parameter => "ParameterError",
        ErrorClass::Usage => return Ok(PyValueError::new_err(terminal(&message).into_owned())),
        ErrorClass::Output => "OutputError",
        ErrorClass::Determinism => "DeterminismError",
        ErrorClass::Other => "GridplanError",
    };
    raise(py, class, message, &attributes(error.innermost()))
}

/// The attributes of the exception of `error` (its class's keyword arguments).
fn attributes(error: &RunnerError) -> Vec<(&'static str, Attr)> {
    match error {
        RunnerError::Config(e) => vec![
            ("file", Attr::from(e.file.display().to_string())),
            ("line", Attr::from(e.line)),
            ("column", Attr::from(e.column)),
        ],
        RunnerError::Map(e) => vec![
            ("file", Attr::from(e.file.as_str())),
            ("line", Attr::from(e.line)),
            ("column", Attr::from(e.column)),
        ],
        RunnerError::Param(_, e) | RunnerError::Build(_, e) => {
            vec![("key", Attr::from(e.key.clone()))]
        }
        RunnerError::UnknownPlanner { .. } | RunnerError::UnknownLabel { .. } => {
            vec![("key", Attr::from("planner"))]
        }
        RunnerError::Problem { error, .. } | RunnerError::InvertedProblem { error, .. } => {
            let (endpoint, cell) = match *error {
                planner_api::ProblemError::OutOfBounds { endpoint, cell, .. }
                | planner_api::ProblemError::Blocked { endpoint, cell } => (endpoint, cell),
            };
            vec![
                ("endpoint", Attr::from(endpoint.to_string())),
                ("cell", Attr::from((cell.x, cell.y))),
            ]
        }
        _ => Vec::new(),
    }
}

/// An attribute value of an exception.
enum Attr {
    Text(String),
    Number(usize),
    Cell((i64, i64)),
    Object(Py<PyAny>),
}

impl From<String> for Attr {
    fn from(text: String) -> Attr {
        Attr::Text(text)
    }
}

impl From<&str> for Attr {
    fn from(text: &str) -> Attr {
        Attr::Text(text.to_string())
    }
}

impl From<usize> for Attr {
    fn from(n: usize) -> Attr {
        Attr::Number(n)
    }
}

impl From<(i64, i64)> for Attr {
    fn from(cell: (i64, i64)) -> Attr {
        Attr::Cell(cell)
    }
}

impl From<(u32, u32)> for Attr {
    fn from((x, y): (u32, u32)) -> Attr {
        Attr::Cell((i64::from(x), i64::from(y)))
    }
}

/// An instance of `gridplan._errors.<class>` with `message` and the attributes.
fn raise<'py>(
    py: Python<'py>,
    class: &str,
    message: String,
    attributes: &[(&str, Attr)],
) -> PyResult<PyErr> {
    let class = py.import("gridplan._errors")?.getattr(class)?;
    let kwargs = PyDict::new(py);
    for (name, value) in attributes {
        match value {
            Attr::Text(text) => kwargs.set_item(name, text)?,
            Attr::Number(n) => kwargs.set_item(name, n)?,
            Attr::Cell(cell) => kwargs.set_item(name, cell)?,
            Attr::Object(value) => kwargs.set_item(name, value)?,
        }
    }
    let instance = class.call((terminal(&message),), Some(&kwargs))?;
    Ok(PyErr::from_value(instance))
}
