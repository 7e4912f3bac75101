//! `Planner`: a registry planner built and prepared for one grid once, then asked many
//! queries without per-call setup.
//!
//! `gridplan.plan` builds the planner and its per-grid tables (A*'s bit grid, JPS's
//! jump table, ...) on every call. A `Planner` keeps them: its runs go through the same
//! [`run_one`] as `plan`'s, with a [`Workspace`] that lives as long as the object, so the
//! planner is built and prepared for the grid by the first query and reused after.
//! `plan_many` runs a batch of queries on a rayon pool with the GIL released, one
//! workspace per pool thread (each prepared once), threads taking the next query as they
//! finish one, and returns the results as NumPy arrays in query order. Counters do not
//! depend on the number of threads: each is a pure function of (grid, query, planner).
//!
//! Calls on one `Planner` from several Python threads run one after another: each holds
//! the planner's state while it plans, and the others wait, Ctrl-C ending a wait
//! ([`Exclusive`]). A process forked while a thread held it cannot use it (that thread is
//! not there to let go): its calls raise `GridplanError`, saying to make a new `Planner`.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use numpy::ndarray::{Array1, Array2};
use numpy::{PyArray1, PyArray2, PyReadonlyArray2};
use planner_api::Budget;
use planner_runner::config::{Experiment, MapEntry, ProblemEntry};
use planner_runner::record::RunRecord;
use planner_runner::run::{run_one, RunSpec, Workspace};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::errors::{guarded, Failure};
use crate::grid::{endpoint, to_cell, Grid};
use crate::interrupt::{Exclusive, Held, Unheld};
use crate::plan::{outcome, problem_error, to_budget, Outcome};
use crate::values::Int;

/// How long `Planner.plan` waits for another call's hold on the planner before it asks
/// Python for signals (as [`crate::interrupt`]'s calls do).
const POLL: Duration = Duration::from_millis(50);

/// The experiment (one map, one planner; its problems are the current call's queries)
/// and the workspaces: one for `plan`, one per thread of `plan_many`'s pool.
struct State {
    experiment: Experiment,
    single: Workspace,
    workers: Vec<Mutex<Workspace>>,
    /// `plan_many`'s pool and the process that built it: a process forked from that one
    /// has none of its threads, and builds its own.
    pool: Option<(u32, rayon::ThreadPool)>,
}

/// `Planner(grid, planner="astar", *, budget=None, **params)`: registry planner `planner`
/// built once for `grid` with its parameters and `budget` (as `gridplan.plan` takes them);
/// its per-grid tables are built by the first query and reused by every later one.
///
/// - `plan(start, goal=None)`: one query, `gridplan.plan`'s `Outcome`.
/// - `plan_many(starts, goals=None, *, threads=0, paths=False)`: a batch of queries
///   (`(N, 2)` arrays of `(x, y)`) on threads; a dict of arrays in query order.
///
/// Calls on one planner from several threads run one after another. The stub
/// (`gridplan/__init__.pyi`) documents every argument in full.
#[pyclass(module = "gridplan", frozen)]
pub struct Planner {
    /// One call at a time works with it; the others wait, interruptibly ([`Exclusive`]).
    state: Exclusive<State>,
    /// The grid (the experiment's map holds a copy), for errors raised before the state is
    /// had.
    grid: Arc<planner_api::Grid>,
    /// Cancel flags for `plan_many` batches, one per batch at a time (raised when Ctrl-C
    /// interrupts it), kept for reuse: a flag is never freed.
    flags: planner_api::CancelPool,
    /// The registry name.
    name: String,
    coverage: bool,
}

/// One query's cells, checked: a negative or too large coordinate (one beyond `i64`
/// too) is a `ProblemError` naming the endpoint (and the query's index in a batch).
fn cells(
    grid: &planner_api::Grid,
    start: &Row,
    goal: Option<&Row>,
    query: Option<usize>,
) -> Result<(planner_api::Cell, Option<planner_api::Cell>), Failure> {
    let prefix = query.map(|i| format!("query {i}: ")).unwrap_or_default();
    let cell = |endpoint: &'static str, row: &Row| match row {
        Row::At(x, y) => {
            to_cell((*x, *y)).ok_or_else(|| match problem_error(endpoint, (*x, *y), grid) {
                Failure::Problem {
                    endpoint,
                    cell,
                    message,
                } => Failure::Problem {
                    endpoint,
                    cell,
                    message: format!("{prefix}{message}"),
                },
                failure => failure,
            })
        }
        Row::Beyond(pair) => Err(Failure::Beyond {
            endpoint,
            message: format!(
                "{prefix}{}",
                crate::plan::outside(endpoint, &pair.0, &pair.1, grid)
            ),
            cell: pair.clone(),
        }),
    };
    let start_cell = cell("start", start)?;
    let goal_cell = match goal {
        Some(goal) => Some(cell("goal", goal)?),
        None => None,
    };
    Ok((start_cell, goal_cell))
}

impl Planner {
    /// The state, once no other call holds it, unless `give_up()` says so first (`None`).
    /// A panic while planning is caught inside the holder (`guarded`) and leaves consistent
    /// state, as every call replaces the problems.
    fn hold(&self, give_up: impl Fn() -> bool) -> Result<Option<Held<'_, State>>, Failure> {
        match self.state.hold(give_up) {
            Ok(held) => Ok(Some(held)),
            Err(Unheld::GaveUp) => Ok(None),
            Err(Unheld::Forked) => Err(Failure::Unusable(
                "this Planner was in use by another thread when the process forked, and that \
                 thread does not exist in this process: make a new Planner here"
                    .into(),
            )),
        }
    }

    /// The problem entry of one query, or the error `plan` raises for it.
    fn entry(
        &self,
        grid: &planner_api::Grid,
        index: usize,
        (start, goal): (planner_api::Cell, Option<planner_api::Cell>),
        query: Option<usize>,
    ) -> Result<ProblemEntry, Failure> {
        let goal = match (goal, self.coverage) {
            (Some(_), true) => {
                return Err(Failure::Value(format!(
                    "`{}` is a coverage planner: it covers from the start and takes no goal",
                    self.name
                )))
            }
            (None, true) => start,
            (None, false) => {
                return Err(Failure::Value(format!(
                    "`{}` plans from a start to a goal: give the goal",
                    self.name
                )))
            }
            (Some(goal), false) => goal,
        };
        let entry = ProblemEntry::new(grid, index, start, goal, None);
        if entry.invalid.is_some() {
            if let Err(error) = planner_api::Problem::new(grid, start, goal) {
                let prefix = query.map(|i| format!("query {i}: ")).unwrap_or_default();
                return Err(crate::plan::problem_failure(&error, &prefix));
            }
        }
        Ok(entry)
    }
}

/// One coordinate of a cell array's row, a whole number.
#[derive(Debug, Clone, PartialEq)]
pub enum Coordinate {
    /// One that fits `i64`.
    Fits(i64),
    /// An integer beyond `i64` (a `uint64` above `i64::MAX`, a Python `int` of any size),
    /// as decimal text.
    Int(String),
    /// A whole float beyond `i64` (`1e30`).
    Float(f64),
}

impl std::fmt::Display for Coordinate {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Coordinate::Fits(v) => write!(f, "{v}"),
            Coordinate::Int(text) => f.write_str(text),
            Coordinate::Float(v) => write!(f, "{v:?}"),
        }
    }
}

impl Coordinate {
    /// The coordinate as a Python value: an `int` (of any size), or the whole `float`.
    pub fn to_python<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        match self {
            Coordinate::Fits(v) => Ok(v.into_pyobject(py)?.into_any()),
            Coordinate::Int(text) => py
                .import("builtins")?
                .getattr("int")?
                .call1((text.as_str(),)),
            Coordinate::Float(v) => Ok(v.into_pyobject(py)?.into_any()),
        }
    }
}

/// One row of a cell array: whole numbers `x`, `y`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Row {
    /// Both fit `i64`.
    At(i64, i64),
    /// One of them does not: a cell on no grid (boxed, so that the usual row stays small).
    Beyond(Box<(Coordinate, Coordinate)>),
}

impl Row {
    /// The row of two coordinates.
    fn new(x: Coordinate, y: Coordinate) -> Row {
        match (&x, &y) {
            (Coordinate::Fits(x), Coordinate::Fits(y)) => Row::At(*x, *y),
            _ => Row::Beyond(Box::new((x, y))),
        }
    }
}

/// A whole float as a coordinate (`None`: not a whole number, NaN or infinite).
fn whole_float(v: f64) -> Option<Coordinate> {
    // Whole numbers in i64's range convert exactly; 2^63 itself does not fit.
    const LIMIT: f64 = 9_223_372_036_854_775_808.0;
    match (v.fract() == 0.0, (-LIMIT..LIMIT).contains(&v)) {
        (false, _) => None,
        (true, true) => Some(Coordinate::Fits(v as i64)),
        (true, false) => Some(Coordinate::Float(v)),
    }
}

/// `(N, 2)` cells of whole numbers from any array-like (`None` stays `None`): an integer
/// array (signed or unsigned), a float array whose values are all whole numbers (as
/// `np.floor` gives them), an object array of Python integers (of any size) or floats, and
/// nothing else. Whole numbers beyond `i64` (`2**64`, a `uint64` above `2**63 - 1`, `1e30`)
/// are kept as [`Row::Beyond`], a cell on no grid, for the caller to refuse as it refuses
/// any cell off the grid (`plan_many`: a `ProblemError` naming the query). A float that is
/// not a whole number (0.5, NaN, infinity) is a `ValueError` naming the query; a boolean,
/// string or other array (or an object array holding anything but numbers) a `TypeError`,
/// where a cast would silently plan another cell.
pub(crate) fn cell_array(
    py: Python<'_>,
    name: &str,
    value: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<Vec<Row>>> {
    let Some(value) = value.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    let numpy = py.import("numpy")?;
    let array = numpy.call_method1("asarray", (value,))?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    // An empty sequence (`[]`) is no queries, as an empty (0, 2) array is.
    if shape == [0] {
        return Ok(Some(Vec::new()));
    }
    if shape.len() != 2 || shape[1] != 2 {
        return Err(Failure::Value(format!(
            "{name}: expected an (N, 2) array of (x, y) cells, got shape {}",
            array.getattr("shape")?.repr()?
        ))
        .into_pyerr(py));
    }
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    let not_a_cell = |query: usize, shown: String| {
        Failure::Value(format!(
            "{name}: query {query}: {shown} is not a cell (whole numbers x, y)"
        ))
        .into_pyerr(py)
    };
    let rows = |dtype: &str| array.call_method1("astype", (dtype,));
    match kind.as_str() {
        "i" => {
            let converted = rows("int64")?;
            let view: PyReadonlyArray2<'_, i64> = converted.extract()?;
            Ok(Some(
                view.as_array()
                    .outer_iter()
                    .map(|row| Row::At(row[0], row[1]))
                    .collect(),
            ))
        }
        "u" => {
            let converted = rows("uint64")?;
            let view: PyReadonlyArray2<'_, u64> = converted.extract()?;
            let coordinate = |v: u64| match i64::try_from(v) {
                Ok(v) => Coordinate::Fits(v),
                Err(_) => Coordinate::Int(v.to_string()),
            };
            Ok(Some(
                view.as_array()
                    .outer_iter()
                    .map(|row| Row::new(coordinate(row[0]), coordinate(row[1])))
                    .collect(),
            ))
        }
        "f" => {
            let converted = rows("float64")?;
            let view: PyReadonlyArray2<'_, f64> = converted.extract()?;
            view.as_array()
                .outer_iter()
                .enumerate()
                .map(
                    |(query, row)| match (whole_float(row[0]), whole_float(row[1])) {
                        (Some(x), Some(y)) => Ok(Row::new(x, y)),
                        _ => Err(not_a_cell(query, format!("({:?}, {:?})", row[0], row[1]))),
                    },
                )
                .collect::<PyResult<Vec<_>>>()
                .map(Some)
        }
        "O" => {
            // Python integers too large for any NumPy integer (NumPy keeps them as
            // objects), or integers and floats mixed.
            let operator = py.import("operator")?;
            let floating = numpy.getattr("floating")?;
            let boolean = numpy.getattr("bool_")?;
            let items: Vec<Vec<Bound<'_, PyAny>>> = array.call_method0("tolist")?.extract()?;
            items
                .iter()
                .enumerate()
                .map(|(query, row)| {
                    let shown = || -> PyResult<String> {
                        let parts = row
                            .iter()
                            .map(|v| Ok(v.repr()?.to_string()))
                            .collect::<PyResult<Vec<String>>>()?;
                        Ok(format!("({})", parts.join(", ")))
                    };
                    let mut coordinates = Vec::with_capacity(2);
                    for item in row {
                        let is_float = item.is_instance_of::<pyo3::types::PyFloat>()
                            || item.is_instance(&floating)?;
                        let is_bool = item.is_instance_of::<pyo3::types::PyBool>()
                            || item.is_instance(&boolean)?;
                        let coordinate = if is_float {
                            match whole_float(item.extract::<f64>()?) {
                                Some(c) => c,
                                None => return Err(not_a_cell(query, shown()?)),
                            }
                        } else if let (false, Ok(int)) =
                            (is_bool, operator.call_method1("index", (item,)))
                        {
                            match int.extract::<i64>() {
                                Ok(v) => Coordinate::Fits(v),
                                Err(_) => Coordinate::Int(int.str()?.to_string()),
                            }
                        } else {
                            return Err(Failure::Type(format!(
                                "{name}: query {query}: expected integer cells, got {}",
                                shown()?
                            ))
                            .into_pyerr(py));
                        };
                        coordinates.push(coordinate);
                    }
                    let mut coordinates = coordinates.into_iter();
                    match (coordinates.next(), coordinates.next()) {
                        (Some(x), Some(y)) => Ok(Row::new(x, y)),
                        _ => Err(not_a_cell(query, shown()?)),
                    }
                })
                .collect::<PyResult<Vec<_>>>()
                .map(Some)
        }
        _ => Err(Failure::Type(format!(
            "{name}: expected integer cells, got dtype {}",
            array.getattr("dtype")?.str()?
        ))
        .into_pyerr(py)),
    }
}

#[pymethods]
impl Planner {
    /// Builds registry planner `planner` with its parameters for `grid`.
    #[new]
    #[pyo3(signature = (grid, planner = "astar", *, budget = None, **params))]
    fn new(
        grid: &Bound<'_, Grid>,
        planner: &str,
        budget: Option<&Bound<'_, PyAny>>,
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Planner> {
        let py = grid.py();
        let table = crate::plan::params_table(planner, params)?;
        let budget: Budget = to_budget(budget).map_err(|e| e.into_pyerr(py))?;
        let grid: Arc<planner_api::Grid> = grid.get().inner.clone();
        let kept = grid.clone();
        let name = planner.to_string();
        let built = py.detach(move || {
            guarded(|| {
                let spec = crate::plan::planner_spec(&grid, &name, table, budget)?;
                let coverage = spec.is_coverage();
                let map = MapEntry {
                    name: "grid".into(),
                    path: Default::default(),
                    grid: (*grid).clone(),
                    problems: Vec::new(),
                    frame: None,
                    unknown: None,
                };
                let origin = planner_api::Cell::new(0, 0);
                let entry = ProblemEntry::new(&map.grid, 1, origin, origin, None);
                let experiment = Experiment::single(map, entry, spec, 0);
                Ok((experiment, coverage, name))
            })
        });
        let (experiment, coverage, name) = built.map_err(|e| e.into_pyerr(py))?;
        Ok(Planner {
            state: Exclusive::new(State {
                experiment,
                single: Workspace::default(),
                workers: Vec::new(),
                pool: None,
            }),
            grid: kept,
            flags: planner_api::CancelPool::new(),
            name,
            coverage,
        })
    }

    /// The registry name.
    #[getter]
    fn name(&self) -> &str {
        &self.name
    }

    /// Plans one query from `start` to `goal` (cells `(x, y)`; no goal for coverage
    /// planners), as `gridplan.plan(grid, start, goal, planner=..., **params)` would, and
    /// returns its `Outcome`. A start or goal off the grid or blocked raises
    /// `ProblemError`. Ctrl-C takes effect when the search ends.
    #[pyo3(signature = (start, goal = None))]
    fn plan(
        &self,
        py: Python<'_>,
        start: &Bound<'_, PyAny>,
        goal: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Outcome> {
        let start = endpoint("start", start, &self.grid)?;
        let goal = goal.map(|g| endpoint("goal", g, &self.grid)).transpose()?;
        let call = crate::warn::Call::begin();
        // While another thread's call holds the planner, this one waits without the GIL in
        // steps of `POLL`, asking Python for signals between them: Ctrl-C ends the wait.
        let record = loop {
            let until = Instant::now() + POLL;
            let step = py.detach(|| {
                guarded(|| {
                    let Some(mut state) = self.hold(|| Instant::now() >= until)? else {
                        return Ok(None);
                    };
                    let State {
                        experiment, single, ..
                    } = &mut *state;
                    let grid = &experiment.maps[0].grid;
                    let (start, goal) =
                        (Row::At(start.0, start.1), goal.map(|(x, y)| Row::At(x, y)));
                    let query = cells(grid, &start, goal.as_ref(), None)?;
                    let entry = self.entry(grid, 1, query, None)?;
                    experiment.maps[0].problems = vec![entry];
                    Ok(Some(run_one(experiment, &SPEC_0, single, None)?))
                })
            });
            match step {
                Ok(Some(record)) => break Ok(record),
                Ok(None) => {
                    if let Err(interrupt) = py.check_signals() {
                        break Err(interrupt);
                    }
                }
                Err(failure) => break Err(failure.into_pyerr(py)),
            }
        };
        let record = call.end(py, record)?;
        outcome(py, record)
    }

    /// Plans query `i` from `starts[i]` to `goals[i]` (`(N, 2)` arrays of `(x, y)`; no
    /// goals for coverage planners) on `threads` threads (0: one per core, at most 256)
    /// with the GIL released, and returns a dict of arrays in query order:
    ///
    /// - `status` (str), `length` and `cost` (float64, NaN without a path; `cost` also
    ///   NaN on an unweighted grid), `steps`, `turns` and `score` (int64, -1 without a
    ///   path), `valid` (bool, False without a path), `error` (str, empty when none),
    ///   `time_ms` (float64, the search alone);
    /// - `counters`: name -> int64 array of every counter one of the runs reported (-1 in
    ///   a run without it; no queries, no counters);
    /// - `seed`: the seed a seeded planner ran every query with (None for other planners
    ///   and for no queries);
    /// - with `paths=True`, `paths` (a list of (N, 2) arrays), `marks` and `series` (lists
    ///   of `Outcome.marks` and `Outcome.series`).
    ///
    /// A start or goal off the grid or blocked raises `ProblemError` naming the query.
    /// Ctrl-C raises `KeyboardInterrupt`; the planner stays usable.
    #[pyo3(
        signature = (starts, goals = None, *, threads = Int::Fits(0), paths = false),
        text_signature = "($self, starts, goals=None, *, threads=0, paths=False)"
    )]
    fn plan_many<'py>(
        &self,
        py: Python<'py>,
        starts: &Bound<'py, PyAny>,
        goals: Option<&Bound<'py, PyAny>>,
        threads: Int,
        paths: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let Some(starts) = cell_array(py, "starts", Some(starts))? else {
            return Err(Failure::Value("starts: expected an (N, 2) array".into()).into_pyerr(py));
        };
        // As many threads as a config's `threads` allows: a pool of a million threads
        // would take the machine's memory before the first query.
        let max = planner_runner::config::MAX_THREADS;
        let threads = threads
            .at_most("threads", max as u64, "use 0 for one per core")
            .map_err(|e| e.into_pyerr(py))? as usize;
        let goals = cell_array(py, "goals", goals)?;
        if let Some(goals) = &goals {
            if goals.len() != starts.len() {
                return Err(Failure::Value(format!(
                    "goals: {} goals for {} starts",
                    goals.len(),
                    starts.len()
                ))
                .into_pyerr(py));
            }
        }
        let call = crate::warn::Call::begin();
        // The batch runs on a thread of its own while this one, holding the GIL every 50
        // ms, asks Python for signals: Ctrl-C (a notebook's interrupt) raises the batch's
        // cancel flag, no query starts after it, the running ones stop at their next budget
        // check, and KeyboardInterrupt is raised here once they have.
        // The flag goes back to the pool however this call ends.
        let lent = self.flags.lend();
        let cancel = lent.flag();
        let work = || {
            let _mark = call.mark_worker();
            let records = guarded(|| {
                // Ctrl-C while another call holds the planner ends the wait: nothing ran.
                let Some(mut state) = self.hold(|| cancel.is_cancelled())? else {
                    return Ok(Vec::new());
                };
                let State {
                    experiment,
                    workers,
                    pool,
                    ..
                } = &mut *state;
                let grid = &experiment.maps[0].grid;
                let mut entries = Vec::with_capacity(starts.len());
                for (i, start) in starts.iter().enumerate() {
                    let goal = goals.as_ref().map(|g| &g[i]);
                    let query = cells(grid, start, goal, Some(i))?;
                    entries.push(self.entry(grid, i + 1, query, Some(i))?);
                }
                experiment.maps[0].problems = entries;
                let threads = match threads {
                    0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
                    n => n,
                };
                let pid = std::process::id();
                if pool
                    .as_ref()
                    .is_none_or(|(owner, p)| *owner != pid || p.current_num_threads() != threads)
                {
                    // A pool built by the process this one was forked from has no threads
                    // here, and dropping it would signal threads that do not exist.
                    if let Some((owner, inherited)) = pool.take() {
                        match owner == pid {
                            true => drop(inherited),
                            false => std::mem::forget(inherited),
                        }
                    }
                    let built = rayon::ThreadPoolBuilder::new()
                        .num_threads(threads)
                        .build()
                        .map_err(|e| Failure::Value(format!("threads: {e}")))?;
                    *pool = Some((pid, built));
                }
                if workers.len() < threads {
                    workers.resize_with(threads, || Mutex::new(Workspace::default()));
                }
                let Some((_, pool)) = pool.as_ref() else {
                    unreachable!("the pool was built above");
                };
                experiment.planners[0].budget.cancel = Some(cancel);
                let experiment = &*experiment;
                let n = experiment.maps[0].problems.len();
                let next = AtomicUsize::new(0);
                let workers = &workers[..];
                // Each thread takes the next query until none is left; results carry
                // their index, so their order does not depend on the threads.
                let parts = pool.broadcast(|ctx| {
                    // What this thread's runs warn of is this call's.
                    let _mark = call.mark_worker();
                    let mut workspace = workers[ctx.index()]
                        .lock()
                        .unwrap_or_else(|e| e.into_inner());
                    let mut done = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        if i >= n || cancel.is_cancelled() {
                            break;
                        }
                        let spec = RunSpec {
                            problem: i,
                            ..SPEC_0
                        };
                        done.push((i, run_one(experiment, &spec, &mut workspace, None)));
                    }
                    done
                });
                // The flag is this batch's: the planner's other calls do not hold it.
                state.experiment.planners[0].budget.cancel = None;
                let mut records: Vec<Option<RunRecord>> = (0..n).map(|_| None).collect();
                for (i, record) in parts.into_iter().flatten() {
                    records[i] = Some(record?);
                }
                Ok(records.into_iter().flatten().collect::<Vec<_>>())
            });
            records
        };
        let records = crate::interrupt::interruptible(
            py,
            || cancel.cancel(),
            || Err(Failure::Value("the batch's thread panicked".into())),
            work,
        )
        .and_then(|records| records.map_err(|e| e.into_pyerr(py)));
        let records = call.end(py, records)?;
        arrays(py, &records, paths)
    }
}

/// Run 0 of problem 0 with the only planner on the only map.
const SPEC_0: RunSpec = RunSpec {
    map: 0,
    problem: 0,
    planner: 0,
    repeat: 0,
};

/// The records as a dict of arrays (see the stub).
fn arrays<'py>(
    py: Python<'py>,
    records: &[RunRecord],
    with_paths: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    let status = PyList::new(py, records.iter().map(|r| r.status.as_str()))?;
    let numpy = py.import("numpy")?;
    // A string array whatever the count (numpy makes an empty list float64).
    let as_str = PyDict::new(py);
    as_str.set_item("dtype", "str")?;
    out.set_item(
        "status",
        numpy.call_method("asarray", (status,), Some(&as_str))?,
    )?;
    let floats = |f: &dyn Fn(&RunRecord) -> f64| {
        PyArray1::from_owned_array(py, Array1::from_iter(records.iter().map(f)))
    };
    out.set_item("length", floats(&|r| r.length.unwrap_or(f64::NAN)))?;
    // `Outcome.cost`'s value, NaN where it is None (no path, or no weights).
    out.set_item("cost", floats(&|r| r.cost.unwrap_or(f64::NAN)))?;
    out.set_item("time_ms", floats(&|r| r.time_ms))?;
    let ints = |f: &dyn Fn(&RunRecord) -> i64| {
        PyArray1::from_owned_array(py, Array1::from_iter(records.iter().map(f)))
    };
    let or_minus_one = |v: Option<u64>| v.map_or(-1, |v| i64::try_from(v).unwrap_or(i64::MAX));
    out.set_item("steps", ints(&|r| or_minus_one(r.steps)))?;
    out.set_item("turns", ints(&|r| or_minus_one(r.turns)))?;
    out.set_item("score", ints(&|r| or_minus_one(r.score)))?;
    // `Outcome.valid`, False where it is None (no path: `status` tells the two apart).
    out.set_item(
        "valid",
        PyArray1::from_owned_array(
            py,
            Array1::from_iter(records.iter().map(|r| r.valid == Some(true))),
        ),
    )?;
    let errors = PyList::new(
        py,
        records
            .iter()
            .map(|r| r.error.as_deref().unwrap_or_default()),
    )?;
    out.set_item(
        "error",
        numpy.call_method("asarray", (errors,), Some(&as_str))?,
    )?;
    // Every query's runs with the same seed (repeat 0's), as `plan`'s.
    out.set_item("seed", records.first().and_then(|r| r.seed))?;
    let counters = PyDict::new(py);
    let mut names: Vec<String> = Vec::new();
    for record in records {
        for (name, _) in record.counters.iter() {
            if !names.iter().any(|n| n == name) {
                names.push(name.to_string());
            }
        }
    }
    for name in &names {
        counters.set_item(name, ints(&|r| or_minus_one(r.counters.get(name))))?;
    }
    out.set_item("counters", counters)?;
    if with_paths {
        let list = PyList::empty(py);
        for record in records {
            let cells = record.path.as_ref().map(|p| p.cells()).unwrap_or_default();
            let path = Array2::from_shape_fn((cells.len(), 2), |(i, j)| {
                i64::from(if j == 0 { cells[i].x } else { cells[i].y })
            });
            list.append(PyArray2::from_owned_array(py, path))?;
        }
        out.set_item("paths", list)?;
        let (marks, series) = (PyList::empty(py), PyList::empty(py));
        for record in records {
            marks.append(crate::plan::marks_list(py, &record.marks)?)?;
            series.append(crate::plan::series_dict(py, &record.series)?)?;
        }
        out.set_item("marks", marks)?;
        out.set_item("series", series)?;
    }
    Ok(out)
}
