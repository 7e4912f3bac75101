//! `gridplan._gridplan`: the native half of the `gridplan` Python package (PyO3).
//!
//! The package (`python/gridplan/__init__.py`) re-exports what this module defines and
//! adds what is easier in Python: the exception classes (`gridplan/_errors.py`, raised
//! from here by name), and the DataFrame of `run_experiment` (pandas is optional).
//!
//! Everything goes through planner-runner, the library the command lines use: planners
//! are built by the registry's factories ([`planner_registry`]), one plan is one
//! [`planner_runner::run::run_one`], an experiment is [`planner_runner::run_all`], and the
//! records' columns are runs.csv's ([`planner_runner::output::runs_csv`]). The GIL is
//! released while maps are read, while planning and while an experiment runs, and a
//! panic in Rust code is caught and raised as `gridplan.GridplanError`, never unwound into
//! the interpreter.
#![deny(missing_docs)]
#![warn(clippy::unwrap_used)]

mod errors;
mod experiment;
mod grid;
mod interrupt;
mod plan;
mod planner;
mod replanner;
mod values;
mod warn;

use pyo3::prelude::*;

/// Counts heap bytes per thread, as the command lines do, so that `peak_heap_bytes` is
/// measured ([`planner_runner::alloc`]).
#[global_allocator]
static ALLOCATOR: planner_runner::alloc::Counting = planner_runner::alloc::Counting;

/// The native module: classes `Grid`, `Problem`, `Outcome`, `PlannerInfo`, `Planner`,
/// `Replanner`; functions
/// `read_map`, `planners`, `plan` and `run_experiment_rows`.
#[pymodule]
fn _gridplan(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // The output locks this process takes name it (the runner reads no process state).
    planner_runner::outdir::set_lock_holder(std::process::id());
    // The library's warnings become Python warnings (`warn`).
    warn::install();
    m.add_class::<grid::Grid>()?;
    m.add_class::<grid::MapFrame>()?;
    m.add_class::<grid::MapProblem>()?;
    m.add_class::<plan::Outcome>()?;
    m.add_class::<plan::PlannerInfo>()?;
    m.add_class::<planner::Planner>()?;
    m.add_class::<replanner::Replanner>()?;
    m.add_function(wrap_pyfunction!(grid::read_map, m)?)?;
    m.add_function(wrap_pyfunction!(plan::planners, m)?)?;
    m.add_function(wrap_pyfunction!(plan::plan, m)?)?;
    m.add_function(wrap_pyfunction!(experiment::run_experiment_rows, m)?)?;
    m.add_function(wrap_pyfunction!(experiment::compare, m)?)?;
    m.add(
        "DEFAULT_PLAN_EXPANSIONS",
        planner_runner::plan::DEFAULT_PLAN_EXPANSIONS,
    )?;
    Ok(())
}
