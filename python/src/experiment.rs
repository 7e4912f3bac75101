//! `run_experiment`: a config's sweep through [`planner_runner::run_all`], its records as
//! rows with runs.csv's columns.
//!
//! The columns are the header [`planner_runner::output::runs_csv`] writes for these
//! records (its fixed columns, then one per counter in order of first appearance), so
//! the rows cannot drift from runs.csv: a column this module cannot fill is an error,
//! which the package's tests would show.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use planner_api::{CancelFlag, CancelPool};

use planner_runner::record::RunRecord;
use planner_runner::sweep::SweepArgs;
use planner_runner::{RunOptions, RunnerError};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use pyo3::IntoPyObjectExt;

use crate::errors::{guarded, Failure};
use crate::values::Int;

/// Runs the experiment config at `config` with `threads` workers (0: the config's
/// `threads`, where 0 means one per core) and returns `(columns, kinds, rows)`: runs.csv's
/// column names, each column's kind ([`kind`]: `"uint"`, `"float"`, `"bool"` or `"text"`,
/// runs.parquet's types), and one dict per record in the run order, keyed by those
/// columns.
///
/// With `output`, the sweep is the command line's ([`planner_runner::sweep::experiment`]:
/// the results directory written under [`planner_runner::outdir`]'s rules) and the rows
/// are the records of the runs.json it wrote; `lock_wait` is how many seconds it waits
/// for another sweep on the same output ([`SweepArgs::lock_wait`]), and `resume` keeps
/// the runs an interrupted (or finished) sweep of the same config recorded there, as
/// `experiment --resume` does ([`SweepArgs::resume`]).
#[pyfunction]
#[pyo3(
    signature = (config, *, threads = Int::Fits(0), output = None, lock_wait = 120.0, resume = false),
    text_signature = "(config, *, threads=0, output=None, lock_wait=120.0, resume=False)"
)]
pub fn run_experiment_rows(
    py: Python<'_>,
    config: PathBuf,
    threads: Int,
    output: Option<PathBuf>,
    lock_wait: f64,
    resume: bool,
) -> PyResult<Py<PyTuple>> {
    // More than the runner allows is its error (naming its limit).
    let threads = threads.at_most(
        "threads",
        usize::MAX as u64,
        "use 0 for the config's threads",
    )? as usize;
    if resume && output.is_none() {
        return Err(PyValueError::new_err(
            "resume: a sweep resumes from its output directory; give `output` (a sweep in memory records nothing to resume)",
        ));
    }
    let lock_wait = Duration::try_from_secs_f64(lock_wait).map_err(|_| {
        PyValueError::new_err(format!(
            "lock_wait: {lock_wait} is not a number of seconds (0 or more)"
        ))
    })?;
    let call = crate::warn::Call::begin();
    // Ctrl-C stops the sweep: no run starts after it (`stop`), and in memory the running
    // searches stop at their next budget check (the flag in every label's budget); the
    // KeyboardInterrupt is raised once the sweep has ended. A sweep to `output` keeps the
    // runs it finished in its stream area, as the command line's interrupted sweep does.
    let stop = AtomicBool::new(false);
    let lent = FLAGS.lend();
    let cancel = lent.flag();
    let work = || {
        let _mark = call.mark_worker();
        guarded(|| {
            let records = match &output {
                None => sweep(&config, threads, cancel)?,
                Some(dir) => sweep_to(&config, threads, (dir, resume), lock_wait, &stop)?,
            };
            Ok((csv_columns(&records), records))
        })
    };
    let swept = crate::interrupt::interruptible(
        py,
        || {
            stop.store(true, Ordering::SeqCst);
            cancel.cancel();
        },
        || Err(Failure::Value("the sweep's thread panicked".into())),
        work,
    );
    drop(lent);
    // What the config, the maps and a resume warned of.
    let (columns, records) = call.end(py, swept.and_then(|swept| swept.map_err(PyErr::from)))?;
    let fixed = csv_columns(&[]);
    let rows = PyList::empty(py);
    for record in &records {
        let row = PyDict::new(py);
        for column in &columns {
            row.set_item(column, value(py, record, column, &fixed)?)?;
        }
        rows.append(row)?;
    }
    let kinds: Vec<&str> = columns.iter().map(|c| kind(c)).collect();
    Ok((columns, kinds, rows).into_pyobject(py)?.unbind())
}

/// The kind of runs.csv's column `column`, as runs.parquet types it: `"text"` (map,
/// planner, algorithm, status, error), `"float"` (length, optimal_length, time_ms,
/// setup_ms, cost), `"bool"` (valid), else `"uint"` (an unsigned 64-bit integer: problem,
/// the cells' coordinates, repeat, seed, steps, turns, score, peak_heap_bytes, bucket and
/// every counter).
pub fn kind(column: &str) -> &'static str {
    match column {
        "map" | "planner" | "algorithm" | "status" | "error" => "text",
        "length" | "optimal_length" | "time_ms" | "setup_ms" | "cost" => "float",
        "valid" => "bool",
        _ => "uint",
    }
}

/// Cancel flags of the sweeps running in memory, one per sweep at a time, kept for reuse
/// (a flag is never freed).
static FLAGS: CancelPool = CancelPool::new();

/// The records of a sweep of `config`, in memory; `cancel` stops every search.
fn sweep(config: &Path, threads: usize, cancel: CancelFlag) -> Result<Vec<RunRecord>, Failure> {
    let mut experiment = planner_runner::config::load(config).map_err(RunnerError::from)?;
    for planner in &mut experiment.planners {
        planner.budget.cancel = Some(cancel);
    }
    let options = RunOptions {
        threads,
        progress: None,
        heap: Some(&planner_runner::alloc::Meter),
        stop: None,
    };
    Ok(planner_runner::run_all(&experiment, &options)?)
}

/// What a resumed sweep found, said as a warning (the command line says it on stderr).
struct ResumeNote;

impl planner_runner::sweep::Progress for ResumeNote {
    fn start(&self, _total: u64, _done: u64) {}
    fn set(&self, _done: u64) {}
    fn finish(&self) {}
    fn resumed(&self, done: u64, total: u64, output: &Path) {
        match done {
            0 => tracing::warn!(
                "resume: nothing to resume in {}; every run runs",
                output.display()
            ),
            _ => tracing::warn!(
                "resume: {done} of {total} runs already recorded in {}",
                output.display()
            ),
        }
    }
}

/// The records of a sweep of `config` written to the results directory `dir`, as the
/// command line writes it (`resume`: as `experiment --resume`).
fn sweep_to(
    config: &Path,
    threads: usize,
    (dir, resume): (&Path, bool),
    lock_wait: Duration,
    stop: &AtomicBool,
) -> Result<Vec<RunRecord>, Failure> {
    // The sweep's errors are typed (the config's, the output's, a figure mismatch found
    // late): each becomes its exception class.
    let renderer = planner_paper::renderer();
    // The commit and host, gathered as the command line gathers them (the runner reads
    // no environment and starts no process).
    let machine = gridplan::machine(config);
    let args = SweepArgs {
        threads,
        output: Some(dir),
        machine: &machine,
        heap: Some(&planner_runner::alloc::Meter),
        keep_records: true,
        lock_wait,
        stop: Some(stop),
        resume,
        progress: Some(&ResumeNote),
        ..SweepArgs::new(config, &renderer)
    };
    let report = planner_runner::sweep::experiment(&args)?;
    Ok(report.records)
}

/// runs.csv's header for `records`, as planner-runner writes it.
pub fn csv_columns(records: &[RunRecord]) -> Vec<String> {
    let csv = planner_runner::output::runs_csv(records);
    let header = csv.split(|b| *b == b'\n').next().unwrap_or_default();
    String::from_utf8_lossy(header)
        .split(',')
        .map(str::to_string)
        .collect()
}

/// The value of `column` for `record`: runs.csv's cell, typed (None for an empty cell).
/// `fixed` are runs.csv's columns before the counters.
fn value<'py>(
    py: Python<'py>,
    r: &RunRecord,
    column: &str,
    fixed: &[String],
) -> PyResult<Bound<'py, PyAny>> {
    fn some<'py, T: IntoPyObject<'py>>(py: Python<'py>, v: T) -> PyResult<Bound<'py, PyAny>> {
        v.into_bound_py_any(py)
    }
    match column {
        "map" => some(py, r.map.as_str()),
        "problem" => some(py, r.problem),
        "start_x" => some(py, r.start.x),
        "start_y" => some(py, r.start.y),
        "goal_x" => some(py, r.goal.x),
        "goal_y" => some(py, r.goal.y),
        "planner" => some(py, r.planner.as_str()),
        "algorithm" => some(py, r.algorithm.as_str()),
        "repeat" => some(py, r.repeat),
        "seed" => some(py, r.seed),
        "status" => some(py, r.status.as_str()),
        "steps" => some(py, r.steps),
        "turns" => some(py, r.turns),
        "score" => some(py, r.score),
        "length" => some(py, r.length),
        "optimal_length" => some(py, r.optimal_length),
        "valid" => some(py, r.valid),
        // Not measured for an invalid problem, which was not run: None, as runs.csv's
        // empty cell.
        "time_ms" => some(py, (!r.is_invalid()).then_some(r.time_ms)),
        "setup_ms" => some(py, (!r.is_invalid()).then_some(r.setup_ms)),
        "peak_heap_bytes" => some(py, (!r.is_invalid()).then_some(r.peak_heap_bytes)),
        "bucket" => some(py, r.bucket),
        "error" => some(py, r.error.as_deref()),
        "cost" => some(py, r.cost),
        counter => match r.counters.get(counter) {
            Some(v) => some(py, v),
            // A counter this record's planner does not report: an empty cell.
            None if !fixed.iter().any(|c| c == counter) => Ok(py.None().into_bound(py)),
            None => Err(Failure::Panic(format!(
                "runs.csv has a column `{counter}` that gridplan's Python package does not know"
            ))
            .into()),
        },
    }
}

/// `gridplan.compare`: the results directories `old` and `new` compared run by run
/// ([`planner_report::compare::compare`]), as the dict of `gridplan compare --json`.
#[pyfunction]
#[pyo3(
    signature = (old, new, *, examples = Int::Fits(10)),
    text_signature = "(old, new, *, examples=10)"
)]
pub fn compare<'py>(
    py: Python<'py>,
    old: PathBuf,
    new: PathBuf,
    examples: Int,
) -> PyResult<Bound<'py, PyAny>> {
    let examples = examples.at_most(
        "examples",
        usize::MAX as u64,
        "give how many differing runs to list",
    )? as usize;
    let json = py
        .detach(|| guarded(|| Ok(planner_report::compare::compare(&old, &new, examples)?.json())))
        .map_err(PyErr::from)?;
    crate::values::json_to_py(py, &json)
}
