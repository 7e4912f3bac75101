//! `Replanner`: an incremental planner (LPA*, D* Lite: the registry's incremental entries)
//! kept between calls, for a robot whose map changes as it drives.
//!
//! `Planner` answers independent queries; a `Replanner` holds one session: a start and a
//! goal on its own copy of the grid. `update` tells it cells that changed (blocked, freed,
//! reweighted), `move_to` that the agent moved, and `plan` repairs the path, its counters
//! those of that call alone (D* Lite's repairs expand far fewer nodes than a search from
//! scratch). The planner is planner-api's [`IncrementalPlanner`], built by
//! [`planner_registry::build_incremental`] from the same parameters a config's table
//! takes; the calls run with the GIL released.

use std::time::Instant;

use numpy::PyReadonlyArray1;
use planner_api::{Budget, Cell, CellChange, IncrementalPlanner, Problem};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{guarded, Failure};
use crate::grid::{endpoint, given_cell, to_cell, GivenCell, Grid};
use crate::interrupt::{Exclusive, Held};
use crate::plan::{
    build_outcome, problem_error, problem_failure, to_budget, Outcome, OutcomeParts,
};
use crate::planner::Row;

/// `Replanner(grid, planner="dstar_lite", *, start, goal, budget=None, **params)`: an
/// incremental planner's session (`"dstar_lite"`, `"lpastar"`) on its own copy of `grid`,
/// from `start` to `goal`. `plan()` computes the path the first time and repairs it after
/// `update(cells, *, free=None, weights=None)` (cells that changed) and `move_to(cell)`
/// (the agent moved); each outcome's counters are that call's alone. Each `plan` gets
/// `budget`, as `gridplan.plan`'s. The stub (`gridplan/__init__.pyi`) documents every
/// argument in full.
#[pyclass(module = "gridplan", frozen)]
pub struct Replanner {
    /// One call at a time works with it ([`Exclusive`]; a process forked while a thread
    /// held it is told so instead of waiting forever).
    planner: Exclusive<Box<dyn IncrementalPlanner>>,
    budget: Budget,
    goal: Cell,
    name: String,
    /// The map frame of the grid it began with (updates keep the cells where they are).
    frame: Option<planner_maps::MapFrame>,
    /// The grid's `(width, height)`, which updates keep.
    size: (u32, u32),
}

impl Replanner {
    /// The planner, once no other call holds it. A panic inside a call is caught by
    /// `guarded` while it is held; the session is then as the planner left it, which its
    /// next call reports on.
    fn lock(&self) -> Result<Held<'_, Box<dyn IncrementalPlanner>>, Failure> {
        self.planner.hold(|| false).map_err(|_| {
            Failure::Unusable(
                "this Replanner was in use by another thread when the process forked, and \
                 that thread does not exist in this process: make a new Replanner here"
                    .into(),
            )
        })
    }
}

/// The cell `(x, y)` of `grid`, or the `ValueError` naming `what`.
fn grid_cell(grid: &planner_api::Grid, (x, y): (i64, i64), what: &str) -> Result<Cell, Failure> {
    to_cell((x, y))
        .filter(|&c| grid.contains(c))
        .ok_or_else(|| {
            Failure::Value(format!(
                "{what}: ({x}, {y}) is outside the {}x{} grid",
                grid.width(),
                grid.height()
            ))
        })
}

/// Values for `n` cells from a scalar or a 1-D array-like of length `n`, as `T` (through
/// NumPy's `dtype`, checked to be `kind`: `b` booleans, `i`/`u` integers).
fn per_cell<'py, T: numpy::Element + Copy>(
    py: Python<'py>,
    name: &str,
    value: &Bound<'py, PyAny>,
    n: usize,
    dtype: &str,
    kinds: &[&str],
) -> PyResult<Vec<T>> {
    let numpy = py.import("numpy")?;
    let array = numpy.call_method1("asarray", (value,))?;
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    if !kinds.contains(&kind.as_str()) {
        return Err(Failure::Type(format!(
            "{name}: expected {}, got dtype {}",
            if dtype == "bool" {
                "booleans"
            } else {
                "integers"
            },
            array.getattr("dtype")?.str()?
        ))
        .into_pyerr(py));
    }
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    let array = match shape.as_slice() {
        [] => numpy.call_method1("full", (n, array.clone(), array.getattr("dtype")?))?,
        [m] if *m == n => array,
        _ => {
            return Err(Failure::Value(format!(
                "{name}: expected one value or {n} (one per cell), got shape {}",
                array.getattr("shape")?.repr()?
            ))
            .into_pyerr(py))
        }
    };
    let converted = array.call_method1("astype", (dtype,))?;
    let view: PyReadonlyArray1<'_, T> = converted.extract()?;
    Ok(view.as_array().iter().copied().collect())
}

#[pymethods]
impl Replanner {
    /// Begins a session of incremental planner `planner` on a copy of `grid`.
    #[new]
    #[pyo3(signature = (grid, planner = "dstar_lite", *, start, goal, budget = None, **params))]
    fn new(
        grid: &Bound<'_, Grid>,
        planner: &str,
        start: &Bound<'_, PyAny>,
        goal: &Bound<'_, PyAny>,
        budget: Option<&Bound<'_, PyAny>>,
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Replanner> {
        let py = grid.py();
        let start = endpoint("start", start, &grid.get().inner)?;
        let goal = endpoint("goal", goal, &grid.get().inner)?;
        let table = crate::plan::params_table(planner, params)?;
        let budget = to_budget(budget).map_err(|e| e.into_pyerr(py))?;
        let frame = grid.get().frame;
        let grid = grid.get().inner.clone();
        let size = (grid.width(), grid.height());
        let name = planner.to_string();
        let built = py.detach(|| {
            guarded(|| {
                let mut planner = match planner_registry::build_incremental(&name, &table) {
                    Some(Ok(planner)) => planner,
                    Some(Err(e)) => {
                        return Err(Failure::Param {
                            key: e.key,
                            message: e.message,
                        })
                    }
                    None => {
                        return Err(Failure::Value(format!(
                            "`{name}` is not an incremental planner (incremental planners: {}); \
                             gridplan.Planner plans independent queries with any planner",
                            planner_registry::incremental_names().join(", ")
                        )))
                    }
                };
                let start_cell =
                    to_cell(start).ok_or_else(|| problem_error("start", start, &grid))?;
                let goal_cell = to_cell(goal).ok_or_else(|| problem_error("goal", goal, &grid))?;
                let problem = Problem::new(&grid, start_cell, goal_cell)
                    .map_err(|error| problem_failure(&error, ""))?;
                planner.reset_within(&problem, &budget);
                Ok((planner, goal_cell))
            })
        });
        let (planner, goal) = built.map_err(|e| e.into_pyerr(py))?;
        Ok(Replanner {
            planner: Exclusive::new(planner),
            budget,
            goal,
            name: planner_name(&name),
            frame,
            size,
        })
    }

    /// The registry name.
    #[getter]
    fn name(&self) -> &str {
        &self.name
    }

    /// The current start, the agent's cell.
    #[getter]
    fn start(&self, py: Python<'_>) -> PyResult<Option<(u32, u32)>> {
        let planner = self.lock().map_err(|e| e.into_pyerr(py))?;
        Ok(planner.start().map(|c| (c.x, c.y)))
    }

    /// The goal.
    #[getter]
    fn goal(&self) -> (u32, u32) {
        (self.goal.x, self.goal.y)
    }

    /// The planner's map: the grid it began with and every update since.
    #[getter]
    fn grid(&self, py: Python<'_>) -> PyResult<Option<Grid>> {
        let planner = self.lock().map_err(|e| e.into_pyerr(py))?;
        Ok(planner.grid().map(|g| Grid {
            inner: std::sync::Arc::new(g.clone()),
            frame: self.frame,
        }))
    }

    /// Computes the path (the first time) or repairs it after updates and moves.
    fn plan(&self, py: Python<'_>) -> PyResult<Outcome> {
        let call = crate::warn::Call::begin();
        let done = py.detach(|| {
            guarded(|| {
                let mut planner = self.lock()?;
                let started = Instant::now();
                let outcome = planner.replan(&self.budget);
                let time_ms = started.elapsed().as_secs_f64() * 1e3;
                let (valid, cost) = match (&outcome.path, planner.grid(), planner.start()) {
                    (Some(path), Some(grid), Some(start)) => {
                        let rule = planner.specs().path_rule;
                        let valid = path.start() == Some(start)
                            && path.goal() == Some(self.goal)
                            && path.validate(grid, rule.rule()).is_ok();
                        let cost = grid
                            .is_weighted()
                            .then(|| grid.path_cost(path.cells()).to_f64());
                        (Some(valid), cost)
                    }
                    _ => (None, None),
                };
                Ok((outcome, valid, cost, time_ms))
            })
        });
        let (outcome, valid, cost, time_ms) = call.end(py, done.map_err(|e| e.into_pyerr(py)))?;
        build_outcome(
            py,
            OutcomeParts {
                status: outcome.status.as_str(),
                path: outcome.path.as_ref(),
                counters: &outcome.counters,
                marks: &outcome.marks,
                series: &outcome.series,
                seed: None,
                valid,
                time_ms,
                cost,
            },
        )
    }

    /// Tells the planner that `cells` changed: blocked or freed (`free`), reweighted
    /// (`weights`, on a weighted grid), or both; the next `plan` repairs the path.
    #[pyo3(signature = (cells, *, free = None, weights = None))]
    fn update(
        &self,
        py: Python<'_>,
        cells: &Bound<'_, PyAny>,
        free: Option<&Bound<'_, PyAny>>,
        weights: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        // No changes (an empty list or array, as a robot's step that saw none) are fine.
        let size: usize = py
            .import("numpy")?
            .call_method1("size", (cells,))?
            .extract()?;
        let cells = match size {
            0 => Vec::new(),
            _ => crate::planner::cell_array(py, "cells", Some(cells))?.unwrap_or_default(),
        };
        let n = cells.len();
        let free: Option<Vec<bool>> = match free.filter(|f| !f.is_none()) {
            Some(value) => Some(per_cell(py, "free", value, n, "bool", &["b"])?),
            None => None,
        };
        // Weights as the values given: unsigned arrays read as `u64` (a `uint64` of 2^63 cast
        // to `int64` would be named by its wrapped, negative value), signed ones as `i64`.
        let weights: Option<Vec<i128>> = match weights.filter(|w| !w.is_none()) {
            Some(value) => {
                let kind: String = py
                    .import("numpy")?
                    .call_method1("asarray", (value,))?
                    .getattr("dtype")?
                    .getattr("kind")?
                    .extract()?;
                Some(match kind.as_str() {
                    "u" => per_cell::<u64>(py, "weights", value, n, "uint64", &["u"])?
                        .into_iter()
                        .map(i128::from)
                        .collect(),
                    _ => per_cell::<i64>(py, "weights", value, n, "int64", &["i", "u"])?
                        .into_iter()
                        .map(i128::from)
                        .collect(),
                })
            }
            None => None,
        };
        if free.is_none() && weights.is_none() {
            return Err(Failure::Type(
                "update: give `free` (whether each cell is now free) or `weights` (its new weight), or both".into(),
            )
            .into_pyerr(py));
        }
        let done = py.detach(|| {
            guarded(|| {
                let mut planner = self.lock()?;
                let Some(grid) = planner.grid() else {
                    return Err(Failure::Value("the session has no map".into()));
                };
                let mut changes = Vec::with_capacity(n);
                for (i, row) in cells.iter().enumerate() {
                    let what = format!("cells[{i}]");
                    let cell = match row {
                        Row::At(x, y) => grid_cell(grid, (*x, *y), &what)?,
                        // Whole numbers beyond `i64`: a cell on no grid.
                        Row::Beyond(pair) => {
                            return Err(Failure::Value(format!(
                                "{what}: ({}, {}) is outside the {}x{} grid",
                                pair.0,
                                pair.1,
                                grid.width(),
                                grid.height()
                            )))
                        }
                    };
                    let weight = match &weights {
                        Some(w) => {
                            if !grid.is_weighted() {
                                return Err(Failure::Value(
                                    "weights: the grid has no weights (Grid.with_weights gives it some)".into(),
                                ));
                            }
                            match u16::try_from(w[i]) {
                                Ok(v) if v >= 1 => Some(v),
                                _ => {
                                    return Err(Failure::Value(format!(
                                        "weights[{i}]: {} is not a weight (1 to 65535)",
                                        w[i]
                                    )))
                                }
                            }
                        }
                        None => None,
                    };
                    changes.push(CellChange {
                        cell,
                        free: free.as_ref().map_or(grid.is_free(cell), |f| f[i]),
                        weight,
                    });
                }
                planner
                    .apply(&changes)
                    .map_err(|e| Failure::Value(format!("update: {e}")))
            })
        });
        done.map_err(|e| e.into_pyerr(py))
    }

    /// The agent moved to `cell`: the next `plan` plans from there.
    fn move_to(&self, py: Python<'_>, cell: &Bound<'_, PyAny>) -> PyResult<()> {
        let cell = match given_cell("move_to", cell)? {
            GivenCell::At(x, y) => (x, y),
            GivenCell::Beyond(x, y) => {
                let (width, height) = self.size;
                return Err(Failure::Value(format!(
                    "move_to: ({x}, {y}) is outside the {width}x{height} grid"
                ))
                .into_pyerr(py));
            }
        };
        let done = py.detach(|| {
            guarded(|| {
                let mut planner = self.lock()?;
                let Some(grid) = planner.grid() else {
                    return Err(Failure::Value("the session has no map".into()));
                };
                let to = grid_cell(grid, cell, "move_to")?;
                planner
                    .move_start(to)
                    .map_err(|e| Failure::Value(format!("move_to: {e}")))
            })
        });
        done.map_err(|e| e.into_pyerr(py))
    }

    fn __repr__(&self) -> String {
        let start = self.lock().ok().and_then(|planner| planner.start());
        format!(
            "Replanner({:?}, start={}, goal=({}, {}))",
            self.name,
            start.map_or("None".into(), |c| format!("({}, {})", c.x, c.y)),
            self.goal.x,
            self.goal.y
        )
    }
}

/// The planner's name as the registry spells it (`name` was found there).
fn planner_name(name: &str) -> String {
    planner_registry::find(name).map_or_else(|| name.to_string(), |e| e.name.to_string())
}
