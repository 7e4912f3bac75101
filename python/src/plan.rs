//! `planners()`, `plan()` and its `Outcome`.
//!
//! `plan` builds the planner exactly as a config label is built
//! ([`planner_runner::config::planner_from_table`]: the registry's factory, the planner
//! crate's own config with its `deny_unknown_fields` and validation) and runs it through
//! [`planner_runner::run::run_one`], the function every run of `plan` and `experiment`
//! goes through, with the GIL released.

use std::sync::Arc;

use numpy::ndarray::Array2;
use numpy::PyArray2;
use planner_api::{Budget, Problem};
use planner_registry as registry;
use planner_runner::config::{self, Experiment, MapEntry, ProblemEntry};
use planner_runner::record::{RunRecord, RunStatus};
use planner_runner::run::{run_one, RunSpec, Workspace};
use planner_runner::Task;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::errors::{guarded, Failure};
use crate::grid::{endpoint, to_cell, Grid};
use crate::values::{json_to_py, to_table, to_toml};

/// What a registered planner is, from the registry and its factory.
#[pyclass(module = "gridplan", frozen, get_all)]
pub struct PlannerInfo {
    /// The registry name (`planner=` of `plan`, `planner =` in a config).
    pub name: &'static str,
    /// One line about it.
    pub summary: &'static str,
    /// `"start_goal"` or `"coverage"` (covers from a start; no goal).
    pub task: &'static str,
    /// Whether its results depend on a seed (parameter `seed`).
    pub seeded: bool,
    /// With its defaults: `True` when its paths are least-cost by design, `False` when it
    /// trades optimality on purpose, `None` when it makes no claim.
    pub admissible: Option<bool>,
    /// Whether it honours cell weights (else a weighted map is refused unless the call
    /// says `costs="ignore"`).
    pub cell_costs: bool,
    /// Whether it can be fed map changes and repair its search.
    pub incremental: bool,
    /// With its defaults: `"any-angle"`, or the moves its paths step by, e.g.
    /// `"8-connected"` (with `", corners cut"` when diagonals may pass a blocked corner;
    /// `planner_api::PathSpec`'s text).
    pub path_rule: String,
    /// Every parameter with its default, as the planner crate's config resolves an empty
    /// table.
    pub parameters: Py<PyDict>,
}

#[pymethods]
impl PlannerInfo {
    /// Pickling (and `copy`): the registry name, whose entry is read again.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, (&'static str,))> {
        Ok((slf.get_type().getattr("_from_state")?, (slf.get().name,)))
    }

    /// The registry's planner `name`, as `planners()` lists it.
    #[classmethod]
    #[pyo3(name = "_from_state")]
    fn from_state(cls: &Bound<'_, pyo3::types::PyType>, name: &str) -> PyResult<PlannerInfo> {
        match registry::find(name) {
            Some(entry) => info(cls.py(), entry),
            None => {
                Err(Failure::Value(format!("PlannerInfo: no registered planner `{name}`")).into())
            }
        }
    }

    fn __repr__(&self) -> String {
        format!(
            "PlannerInfo(name={:?}, task={:?}, seeded={})",
            self.name,
            self.task,
            if self.seeded { "True" } else { "False" }
        )
    }
}

/// Every registered planner, in the registry's order, with its declared parameters.
#[pyfunction]
pub fn planners(py: Python<'_>) -> PyResult<Vec<PlannerInfo>> {
    registry::PLANNERS
        .iter()
        .map(|entry| info(py, entry))
        .collect()
}

/// What the registry's `entry` is, with its parameters' defaults.
fn info(py: Python<'_>, entry: &'static registry::Entry) -> PyResult<PlannerInfo> {
    let factory = guarded(|| {
        (entry.factory)(&toml::Table::new())
            .map_err(|e| Failure::from(planner_runner::RunnerError::Param(entry.name.into(), e)))
    })?;
    let parameters = json_to_py(py, factory.resolved())?;
    let parameters = match parameters.cast_into::<PyDict>() {
        Ok(dict) => dict,
        Err(_) => PyDict::new(py),
    };
    let specs = factory.specs();
    Ok(PlannerInfo {
        name: entry.name,
        summary: entry.summary,
        task: task_name(entry.task),
        seeded: specs.seeded,
        admissible: specs.admissible,
        cell_costs: specs.cell_costs,
        incremental: specs.incremental,
        path_rule: specs.path_rule.to_string(),
        parameters: parameters.unbind(),
    })
}

fn task_name(task: Task) -> &'static str {
    match task {
        Task::StartGoal => "start_goal",
        Task::Coverage => "coverage",
    }
}

/// The result of one `plan`: a value, which its arrays (read-only) and the dicts and lists
/// it gives (copies) cannot change; it pickles, and equals an outcome of the same results.
#[pyclass(module = "gridplan", frozen)]
pub struct Outcome {
    /// `"found"`, `"no_path"` or `"budget_exhausted"`.
    #[pyo3(get)]
    pub status: &'static str,
    /// The path's cells as an (N, 2) int64 array of `(x, y)` rows; (0, 2) without a path.
    pub path: Py<PyAny>,
    /// `{"steps", "turns", "score", "length"}` of the path (seed 000's D, T, Score and the
    /// Euclidean length), or None without a path.
    pub metrics: Py<PyAny>,
    /// The planner's counters in its order (`n_expanded`, `n_neighbor_checks`, ...).
    pub counters: Py<PyDict>,
    /// The cells the planner marks, as `(label, (x, y))` pairs (PA-star's handover points).
    pub marks: Py<PyList>,
    /// Sequences the planner recorded (CAPSO's `best_fitness`, RRT*'s `best_cost`): name ->
    /// (N, 2) float64 array of points.
    pub series: Py<PyDict>,
    /// The seed a seeded planner ran with, else None.
    #[pyo3(get)]
    pub seed: Option<u64>,
    /// Whether the path joins start and goal and obeys the planner's declared rule; None
    /// without a path.
    #[pyo3(get)]
    pub valid: Option<bool>,
    /// Wall time of the search alone, in milliseconds.
    #[pyo3(get)]
    pub time_ms: f64,
    /// On a weighted grid, the path's cost under the grid's cost rule; else None.
    #[pyo3(get)]
    pub cost: Option<f64>,
    /// With `plan(..., record=True)`, the cells the search expanded in order, an (N, 2)
    /// int64 array (empty for planners that do not record them); else None.
    pub expanded: Option<Py<PyAny>>,
    /// With `plan(..., record=True)`, the search step by step where the planner records it
    /// (A*, bidirectional A*, Theta*, Lazy Theta*): a dict of equal-length arrays, `kind` (`"generating"`, `"updating"`,
    /// `"expanding"`), `x`, `y`, `parent_x`, `parent_y` (-1 for the start), `g`, `f`
    /// (empty for the other planners); else None.
    pub events: Option<Py<PyDict>>,
}

impl Outcome {
    /// The fields `==` compares besides the status, seed, validity and cost: every one but
    /// `time_ms`, a measurement.
    fn values<'py>(&self, py: Python<'py>) -> [Bound<'py, PyAny>; 7] {
        let or_none =
            |value: Option<Bound<'py, PyAny>>| value.unwrap_or_else(|| py.None().into_bound(py));
        [
            self.path.bind(py).clone(),
            self.metrics.bind(py).clone(),
            self.counters.bind(py).clone().into_any(),
            self.marks.bind(py).clone().into_any(),
            self.series.bind(py).clone().into_any(),
            or_none(self.expanded.as_ref().map(|e| e.bind(py).clone())),
            or_none(self.events.as_ref().map(|e| e.bind(py).clone().into_any())),
        ]
    }
}

/// Whether two of an outcome's values are equal: arrays element by element (NaN equal to
/// NaN), dicts key by key, anything else by `==`.
fn same(a: &Bound<'_, PyAny>, b: &Bound<'_, PyAny>) -> PyResult<bool> {
    let py = a.py();
    let numpy = py.import("numpy")?;
    let ndarray = numpy.getattr("ndarray")?;
    match (a.is_instance(&ndarray)?, b.is_instance(&ndarray)?) {
        (true, true) => {
            let floats = |x: &Bound<'_, PyAny>| -> PyResult<bool> {
                Ok(x.getattr("dtype")?.getattr("kind")?.extract::<String>()? == "f")
            };
            let options = PyDict::new(py);
            options.set_item("equal_nan", floats(a)? && floats(b)?)?;
            return numpy
                .call_method("array_equal", (a, b), Some(&options))?
                .is_truthy();
        }
        (false, false) => {}
        _ => return Ok(false),
    }
    if let (Ok(a), Ok(b)) = (a.cast::<PyDict>(), b.cast::<PyDict>()) {
        if a.len() != b.len() {
            return Ok(false);
        }
        for (key, value) in a.iter() {
            match b.get_item(&key)? {
                Some(other) if same(&value, &other)? => {}
                _ => return Ok(false),
            }
        }
        return Ok(true);
    }
    a.eq(b)
}

/// `array` made read-only: an outcome's arrays are part of its value.
fn read_only(array: Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
    let options = PyDict::new(array.py());
    options.set_item("write", false)?;
    array.call_method("setflags", (), Some(&options))?;
    Ok(array.unbind())
}

/// A read-only copy of `value` as an array.
fn array_copy(value: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
    read_only(
        value
            .py()
            .import("numpy")?
            .call_method1("array", (value,))?,
    )
}

/// A copy of a dict of arrays (`series`, `events`), each a read-only copy.
fn arrays_copy<'py>(value: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
    let copy = PyDict::new(value.py());
    for (key, array) in value.cast::<PyDict>()?.iter() {
        copy.set_item(key, array_copy(&array)?)?;
    }
    Ok(copy)
}

#[pymethods]
impl Outcome {
    /// The path's cells as an (N, 2) int64 array of `(x, y)` rows (read-only).
    #[getter]
    fn path(&self, py: Python<'_>) -> Py<PyAny> {
        self.path.clone_ref(py)
    }

    /// The path's `steps`, `turns`, `score` and `length` (a copy), or None.
    #[getter]
    fn metrics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        match self.metrics.bind(py).cast::<PyDict>() {
            Ok(dict) => Ok(dict.copy()?.into_any()),
            Err(_) => Ok(py.None().into_bound(py)),
        }
    }

    /// The planner's counters in its order (a copy).
    #[getter]
    fn counters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.counters.bind(py).copy()
    }

    /// The `(label, (x, y))` marks (a copy).
    #[getter]
    fn marks<'py>(&self, py: Python<'py>) -> Bound<'py, PyList> {
        let marks = self.marks.bind(py);
        marks.get_slice(0, marks.len())
    }

    /// Name -> (N, 2) float64 array of points (a copy of the dict; the arrays read-only).
    #[getter]
    fn series<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.series.bind(py).copy()
    }

    /// The expanded cells with `record=True` (read-only), else None.
    #[getter]
    fn expanded(&self, py: Python<'_>) -> Option<Py<PyAny>> {
        self.expanded.as_ref().map(|e| e.clone_ref(py))
    }

    /// The search's steps with `record=True` (a copy of the dict; the arrays read-only),
    /// else None.
    #[getter]
    fn events<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        self.events.as_ref().map(|e| e.bind(py).copy()).transpose()
    }

    /// Equal results: everything but `time_ms`.
    fn __eq__(&self, other: &Bound<'_, Outcome>) -> PyResult<bool> {
        let py = other.py();
        let other = other.get();
        if (self.status, self.seed, self.valid, self.cost)
            != (other.status, other.seed, other.valid, other.cost)
        {
            return Ok(false);
        }
        for (a, b) in self.values(py).iter().zip(other.values(py).iter()) {
            if !same(a, b)? {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// Pickling (and `copy`): every field, by name.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyDict>,))> {
        let py = slf.py();
        let outcome = slf.get();
        let state = PyDict::new(py);
        state.set_item("status", outcome.status)?;
        state.set_item("path", &outcome.path)?;
        state.set_item("metrics", &outcome.metrics)?;
        state.set_item("counters", &outcome.counters)?;
        state.set_item("marks", &outcome.marks)?;
        state.set_item("series", &outcome.series)?;
        state.set_item("seed", outcome.seed)?;
        state.set_item("valid", outcome.valid)?;
        state.set_item("time_ms", outcome.time_ms)?;
        state.set_item("cost", outcome.cost)?;
        state.set_item("expanded", &outcome.expanded)?;
        state.set_item("events", &outcome.events)?;
        Ok((slf.get_type().getattr("_from_state")?, (state,)))
    }

    /// The outcome `__reduce__` describes.
    #[classmethod]
    #[pyo3(name = "_from_state")]
    fn from_state(
        _cls: &Bound<'_, pyo3::types::PyType>,
        state: &Bound<'_, PyDict>,
    ) -> PyResult<Outcome> {
        let py = state.py();
        let item = |key: &str| -> PyResult<Bound<'_, PyAny>> {
            state.get_item(key)?.ok_or_else(|| {
                Failure::Value(format!("Outcome: the pickled state has no `{key}`")).into()
            })
        };
        let given: String = item("status")?.extract()?;
        let statuses = [
            RunStatus::Found,
            RunStatus::NoPath,
            RunStatus::BudgetExhausted,
            RunStatus::InvalidProblem,
        ];
        let Some(status) = statuses.iter().map(|s| s.as_str()).find(|s| *s == given) else {
            return Err(Failure::Value(format!("Outcome: status {given:?} is not one")).into());
        };
        let metrics = item("metrics")?;
        let metrics = match metrics.cast::<PyDict>() {
            Ok(dict) => dict.copy()?.into_any().unbind(),
            Err(_) => py.None(),
        };
        let marks = item("marks")?;
        let marks = marks.cast::<PyList>()?;
        let optional = |key: &str| -> PyResult<Option<Bound<'_, PyAny>>> {
            Ok(Some(item(key)?).filter(|v| !v.is_none()))
        };
        Ok(Outcome {
            status,
            path: array_copy(&item("path")?)?,
            metrics,
            counters: item("counters")?.cast::<PyDict>()?.copy()?.unbind(),
            marks: marks.get_slice(0, marks.len()).unbind(),
            series: arrays_copy(&item("series")?)?.unbind(),
            seed: item("seed")?.extract()?,
            valid: item("valid")?.extract()?,
            time_ms: item("time_ms")?.extract()?,
            cost: item("cost")?.extract()?,
            expanded: optional("expanded")?.map(|e| array_copy(&e)).transpose()?,
            events: optional("events")?
                .map(|e| arrays_copy(&e).map(Bound::unbind))
                .transpose()?,
        })
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let n = self
            .path
            .bind(py)
            .getattr("shape")?
            .get_item(0)?
            .extract::<usize>()?;
        Ok(format!(
            "Outcome(status={:?}, path=<{n} cells>)",
            self.status
        ))
    }
}

/// Plans from `start` to `goal` on `grid` with registry planner `planner`; returns an
/// `Outcome` (`status`, `path`, `metrics`, `counters`, `cost`, ...).
///
/// - `start`, `goal`: cells `(x, y)`, any two integers (a tuple, list or NumPy array);
///   no goal for coverage planners. One off the grid or blocked raises `ProblemError`.
/// - `planner`: a registry name (`gridplan.planners()` lists them); `**params` its
///   parameters, as a config's `[planners.label]` table (one given as None keeps its
///   default; integers up to 2**63 - 1, as a config's). An unknown name, key or bad value
///   raises `ParameterError` naming it. On a weighted grid a planner that cannot honour
///   cell costs is refused (key `costs`) unless given `costs="ignore"`.
/// - `budget`: a number of expansions, or a dict of `max_expansions`, `max_time_ms` and
///   `max_memory_mb` (a bad value raises `ParameterError` with key `budget.<key>`);
///   without `max_expansions`, `DEFAULT_PLAN_EXPANSIONS`.
/// - `record=True`: the search is run once more to record it (`Outcome.expanded`,
///   `Outcome.events`); it must repeat the first run, else `DeterminismError`.
///
/// Ctrl-C stops the search at its next budget check and raises `KeyboardInterrupt`.
/// The stub (`gridplan/__init__.pyi`) documents every argument and field in full.
#[pyfunction]
#[pyo3(signature = (grid, start, goal = None, *, planner = "astar", budget = None, record = false, **params))]
#[allow(clippy::too_many_arguments)]
pub fn plan(
    py: Python<'_>,
    grid: &Bound<'_, Grid>,
    start: &Bound<'_, PyAny>,
    goal: Option<&Bound<'_, PyAny>>,
    planner: &str,
    budget: Option<&Bound<'_, PyAny>>,
    record: bool,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<Outcome> {
    let table = params_table(planner, params)?;
    let mut budget = to_budget(budget)?;
    let grid: Arc<planner_api::Grid> = grid.get().inner.clone();
    let start = endpoint("start", start, &grid)?;
    let goal = goal.map(|g| endpoint("goal", g, &grid)).transpose()?;
    let planner = planner.to_string();
    let call = crate::warn::Call::begin();
    // Ctrl-C (a notebook's interrupt) stops the search at its next budget check and
    // raises KeyboardInterrupt here (`interrupt`): a long search no longer holds the
    // interpreter until it ends.
    let lent = FLAGS.lend();
    let cancel = lent.flag();
    budget.cancel = Some(cancel);
    let work = || {
        let _mark = call.mark_worker();
        guarded(|| run(&grid, start, goal, &planner, table, budget, record))
    };
    let done = crate::interrupt::interruptible_query(
        py,
        || cancel.cancel(),
        || Err(Failure::Value("the search's thread panicked".into())),
        work,
    );
    drop(lent);
    // A run the planner's memory check refused, a path that breaks its rule.
    let (record, recorded) = call.end(py, done.and_then(|d| d.map_err(PyErr::from)))?;
    let mut outcome = outcome(py, record)?;
    if let Some((expanded, events)) = recorded {
        outcome.expanded = Some(cell_rows(py, &expanded)?);
        outcome.events = Some(event_arrays(py, &events)?);
    }
    Ok(outcome)
}

/// A call's `**params` as the TOML table of a config's planner table. An error is named
/// after registry planner `planner`, as the runner names its own (`planner `rrt`:
/// parameter `seed`: ...`); for a name the registry does not know, the planner's error
/// follows once the parameters are right.
pub(crate) fn params_table(
    planner: &str,
    params: Option<&Bound<'_, PyDict>>,
) -> Result<toml::Table, Failure> {
    let Some(dict) = params else {
        return Ok(toml::Table::new());
    };
    to_table(dict, "").map_err(|failure| match failure {
        Failure::Param { key, message } if registry::find(planner).is_some() => Failure::Param {
            key,
            message: format!("planner `{planner}`: {message}"),
        },
        other => other,
    })
}

/// Cancel flags of the `plan` calls running, one per call at a time, kept for reuse (a
/// flag is never freed).
static FLAGS: planner_api::CancelPool = planner_api::CancelPool::new();

/// `cells` as an (N, 2) int64 array of `(x, y)` rows.
fn cell_rows(py: Python<'_>, cells: &[planner_api::Cell]) -> PyResult<Py<PyAny>> {
    let rows = Array2::from_shape_fn((cells.len(), 2), |(i, j)| {
        i64::from(if j == 0 { cells[i].x } else { cells[i].y })
    });
    read_only(PyArray2::from_owned_array(py, rows).into_any())
}

/// `events` as a dict of equal-length read-only arrays (`Outcome::events`'s columns).
fn event_arrays(py: Python<'_>, events: &[planner_api::SearchEvent]) -> PyResult<Py<PyDict>> {
    use planner_api::SearchEvent;
    /// One column: `value` of every event.
    fn column<'py, T: numpy::Element>(
        py: Python<'py>,
        events: &[SearchEvent],
        value: impl Fn(&SearchEvent) -> T,
    ) -> Bound<'py, numpy::PyArray1<T>> {
        numpy::PyArray1::from_vec(py, events.iter().map(value).collect())
    }
    let parent = |e: &SearchEvent, pick: fn(planner_api::Cell) -> u32| {
        e.parent.map_or(-1, |p| i64::from(pick(p)))
    };
    let dict = PyDict::new(py);
    let kinds: Vec<&str> = events.iter().map(|e| e.kind.name()).collect();
    dict.set_item(
        "kind",
        py.import("numpy")?.call_method1("asarray", (kinds,))?,
    )?;
    dict.set_item("x", column(py, events, |e| i64::from(e.cell.x)))?;
    dict.set_item("y", column(py, events, |e| i64::from(e.cell.y)))?;
    dict.set_item("parent_x", column(py, events, |e| parent(e, |c| c.x)))?;
    dict.set_item("parent_y", column(py, events, |e| parent(e, |c| c.y)))?;
    dict.set_item("g", column(py, events, |e| e.g))?;
    dict.set_item("f", column(py, events, |e| e.f))?;
    for (_, array) in dict.iter() {
        read_only(array)?;
    }
    Ok(dict.unbind())
}

/// `budget`: None (plan's default, as on the command line), a maximum number of
/// expansions, or a dict with a config's `[budget]` keys.
pub(crate) fn to_budget(budget: Option<&Bound<'_, PyAny>>) -> Result<Budget, Failure> {
    let mut parsed = match budget {
        None => Budget::unlimited(),
        Some(value) if value.is_none() => Budget::unlimited(),
        Some(value) => match to_toml("budget", value)? {
            toml::Value::Integer(n) => Budget::expansions(u64::try_from(n).map_err(|_| {
                Failure::Param {
                    key: "budget".into(),
                    message: format!("budget: {n} expansions; a budget is at least 0"),
                }
            })?),
            toml::Value::Table(table) => budget_table(table)?,
            other => {
                return Err(Failure::Param {
                    key: "budget".into(),
                    message: format!(
                        "budget: expected a number of expansions or a dict of `max_expansions`, `max_time_ms` and `max_memory_mb`, got {}",
                        other.type_str()
                    ),
                })
            }
        },
    };
    if parsed.max_expansions.is_none() {
        parsed.max_expansions = Some(planner_runner::plan::DEFAULT_PLAN_EXPANSIONS);
    }
    Ok(parsed)
}

/// A budget dict's keys as a [`Budget`]; an error names the key at fault
/// (`budget.max_expansions`), the first one refused when read alone.
fn budget_table(table: toml::Table) -> Result<Budget, Failure> {
    let read = |table: toml::Table| -> Result<Budget, toml::de::Error> {
        serde::Deserialize::deserialize(toml::Value::Table(table))
    };
    let error = match read(table.clone()) {
        Ok(budget) => return Ok(budget),
        Err(error) => error,
    };
    let alone = |(key, value): (&String, &toml::Value)| {
        read(toml::Table::from_iter([(key.clone(), value.clone())]))
            .err()
            .map(|e| (key.clone(), value.clone(), e))
    };
    let Some((key, value, alone_error)) = table.iter().find_map(alone) else {
        return Err(Failure::Param {
            key: "budget".into(),
            message: format!("budget: {}", error.message().trim()),
        });
    };
    let message = alone_error.message().trim().to_string();
    let message = match value {
        toml::Value::Integer(n) if n < 0 => {
            format!("budget.{key}: {n} is negative; a budget is at least 0")
        }
        // The message names an unknown key itself.
        _ if message.starts_with("unknown field") => format!("budget: {message}"),
        _ => format!("budget.{key}: {message}"),
    };
    Err(Failure::Param {
        key: format!("budget.{key}"),
        message,
    })
}

/// The `ProblemError` exception of a start or goal that is off the grid or blocked, its
/// message after `prefix` (a batch's `query i: `).
pub(crate) fn problem_failure(error: &planner_api::ProblemError, prefix: &str) -> Failure {
    let (endpoint, cell) = match error {
        planner_api::ProblemError::OutOfBounds { endpoint, cell, .. }
        | planner_api::ProblemError::Blocked { endpoint, cell } => (*endpoint, *cell),
    };
    Failure::Problem {
        endpoint: match endpoint {
            planner_api::Endpoint::Start => "start",
            planner_api::Endpoint::Goal => "goal",
        },
        cell: (i64::from(cell.x), i64::from(cell.y)),
        message: format!("{prefix}{error}"),
    }
}

pub(crate) fn problem_error(
    endpoint: &'static str,
    cell: (i64, i64),
    grid: &planner_api::Grid,
) -> Failure {
    Failure::Problem {
        endpoint,
        cell,
        message: outside(endpoint, &cell.0, &cell.1, grid),
    }
}

/// The message of a start or goal `(x, y)` outside `grid`.
pub(crate) fn outside(
    endpoint: &str,
    x: &dyn std::fmt::Display,
    y: &dyn std::fmt::Display,
    grid: &planner_api::Grid,
) -> String {
    format!(
        "{endpoint} ({x}, {y}) is outside the {}x{} grid",
        grid.width(),
        grid.height()
    )
}

/// What `plan(..., record=True)` recorded: the expanded cells and the steps.
type Recorded = (Vec<planner_api::Cell>, Vec<planner_api::SearchEvent>);

/// The run's record, and with `record` the search recorded by a second run that must
/// repeat it ([`planner_runner::plan::run_single`]).
fn run(
    grid: &planner_api::Grid,
    start: (i64, i64),
    goal: Option<(i64, i64)>,
    planner: &str,
    params: toml::Table,
    budget: Budget,
    record: bool,
) -> Result<(RunRecord, Option<Recorded>), Failure> {
    let spec = planner_spec(grid, planner, params, budget)?;
    let start_cell = to_cell(start).ok_or_else(|| problem_error("start", start, grid))?;
    let goal_cell = match (goal, spec.is_coverage()) {
        (Some(_), true) => {
            return Err(Failure::Value(format!(
                "`{}` is a coverage planner: it covers from the start and takes no goal",
                spec.name
            )))
        }
        (None, true) => start_cell,
        (None, false) => {
            return Err(Failure::Value(format!(
                "`{}` plans from a start to a goal: give the goal",
                spec.name
            )))
        }
        (Some(goal), false) => to_cell(goal).ok_or_else(|| problem_error("goal", goal, grid))?,
    };
    Problem::new(grid, start_cell, goal_cell).map_err(|error| problem_failure(&error, ""))?;
    let map = MapEntry {
        name: "grid".into(),
        path: Default::default(),
        grid: grid.clone(),
        problems: Vec::new(),
        frame: None,
        unknown: None,
    };
    let entry = ProblemEntry::new(grid, 1, start_cell, goal_cell, None);
    if record {
        let name = spec.name.to_string();
        let result = planner_runner::plan::run_single(map, entry, spec, 0, &name, true, true)?;
        return Ok((result.record, Some((result.expanded, result.events))));
    }
    let single = Experiment::single(map, entry, spec, 0);
    let spec = RunSpec {
        map: 0,
        problem: 0,
        planner: 0,
        repeat: 0,
    };
    Ok((
        run_one(&single, &spec, &mut Workspace::default(), None)?,
        None,
    ))
}

/// Registry planner `planner` with the parameters `params` for `grid`, as a config's
/// planner table: the key `costs = "ignore"` lets a planner that cannot honour cell costs
/// plan on a weighted grid without them; without it such a planner is refused one.
pub(crate) fn planner_spec(
    grid: &planner_api::Grid,
    planner: &str,
    mut params: toml::Table,
    budget: Budget,
) -> Result<config::PlannerSpec, Failure> {
    let ignore = match params.remove("costs") {
        None => false,
        Some(toml::Value::String(s)) if s == "ignore" => true,
        Some(other) => {
            return Err(Failure::Param {
                key: "costs".into(),
                message: format!(
                    "costs: expected \"ignore\" (plan on a weighted grid without its weights), got {other}"
                ),
            })
        }
    };
    let mut spec = config::planner_from_table(planner, planner, params, budget)?;
    spec.ignore_costs = ignore;
    if grid.is_weighted() && !ignore && !spec.factory.specs().cell_costs {
        return Err(Failure::Param {
            key: "costs".into(),
            message: format!(
                "planner `{planner}` {}, and the grid has them; pass costs=\"ignore\" to plan without them",
                spec.factory.specs().cell_costs_refusal()
            ),
        });
    }
    Ok(spec)
}

pub(crate) fn outcome(py: Python<'_>, record: RunRecord) -> PyResult<Outcome> {
    build_outcome(
        py,
        OutcomeParts {
            status: record.status.as_str(),
            path: record.path.as_ref(),
            counters: &record.counters,
            marks: &record.marks,
            series: &record.series,
            seed: record.seed,
            valid: record.valid,
            time_ms: record.time_ms,
            cost: record.cost,
        },
    )
}

/// What an [`Outcome`] is made of: a run record's fields, or an incremental planner's
/// outcome and what its caller measured.
pub(crate) struct OutcomeParts<'a> {
    pub status: &'static str,
    pub path: Option<&'a planner_api::Path>,
    pub counters: &'a planner_api::Counters,
    pub marks: &'a [planner_api::Mark],
    pub series: &'a [planner_api::Series],
    pub seed: Option<u64>,
    pub valid: Option<bool>,
    pub time_ms: f64,
    pub cost: Option<f64>,
}

/// The Python [`Outcome`] of `parts`.
pub(crate) fn build_outcome(py: Python<'_>, parts: OutcomeParts<'_>) -> PyResult<Outcome> {
    let cells = parts.path.map(|p| p.cells()).unwrap_or_default();
    let path = Array2::from_shape_fn((cells.len(), 2), |(i, j)| {
        i64::from(if j == 0 { cells[i].x } else { cells[i].y })
    });
    let path = read_only(PyArray2::from_owned_array(py, path).into_any())?;
    let metrics = match parts.path {
        Some(p) => {
            let m = p.metrics();
            let dict = PyDict::new(py);
            dict.set_item("steps", m.steps)?;
            dict.set_item("turns", m.turns)?;
            dict.set_item("score", m.score)?;
            dict.set_item("length", m.length)?;
            dict.into_any().unbind()
        }
        None => py.None(),
    };
    let counters = PyDict::new(py);
    for (name, value) in parts.counters.iter() {
        counters.set_item(name, value)?;
    }
    let marks = marks_list(py, parts.marks)?;
    let series = series_dict(py, parts.series)?;
    Ok(Outcome {
        status: parts.status,
        path,
        metrics,
        counters: counters.unbind(),
        marks: marks.unbind(),
        series: series.unbind(),
        seed: parts.seed,
        valid: parts.valid,
        time_ms: parts.time_ms,
        cost: parts.cost,
        expanded: None,
        events: None,
    })
}

/// A run's marks as `Outcome.marks` gives them: a list of `(label, (x, y))`.
pub(crate) fn marks_list<'py>(
    py: Python<'py>,
    marks: &[planner_api::Mark],
) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for mark in marks {
        list.append((mark.label.as_str(), (mark.cell.x, mark.cell.y)))?;
    }
    Ok(list)
}

/// A run's series as `Outcome.series` gives them: name -> (N, 2) read-only float64 array.
pub(crate) fn series_dict<'py>(
    py: Python<'py>,
    series: &[planner_api::Series],
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for s in series {
        let points = Array2::from_shape_fn((s.points.len(), 2), |(i, j)| s.points[i][j]);
        let points = read_only(PyArray2::from_owned_array(py, points).into_any())?;
        dict.set_item(s.name.as_str(), points)?;
    }
    Ok(dict)
}
