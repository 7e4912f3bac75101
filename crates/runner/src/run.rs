//! Expanding an experiment into runs and running them in parallel.
//!
//! Runs are numbered in a fixed order (map, problem, planner label, repeat) by
//! [`RunList`], which computes the k-th run from the experiment without listing them, so
//! a sweep's memory does not grow with its repeats. They execute on a rayon pool and are
//! collected by index, so the records do not depend on the thread count; only the timing
//! and memory fields do.
//!
//! Each worker keeps one planner per label and reuses it across its runs ([`Workspace`]),
//! calling [`planner_api::Planner::prepare`] when the grid changes and
//! [`planner_api::Planner::reseed`] before each run of a seeded planner. [`run_one`] is
//! the one function that executes a run: `experiment` and `plan` both go through it.

use std::time::Instant;

use planner_api::{Budget, CancelFlag, Cost, Counters, CoverageProblem, Grid, Problem};
use rayon::prelude::*;

use crate::config::{Experiment, MapEntry, PlannerSpec, ProblemEntry};
use crate::record::{RunRecord, RunStatus};
use crate::RunnerError;
use planner_registry::Built;

/// One run to do: indices into the experiment's maps, problems and planners.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct RunSpec {
    /// Index into [`Experiment::maps`].
    pub map: usize,
    /// Index into the map's problems.
    pub problem: usize,
    /// Index into [`Experiment::planners`].
    pub planner: usize,
    /// 0-based repeat.
    pub repeat: u32,
}

/// The runs of an experiment in their fixed order, computed on demand.
///
/// Holds one offset per (map, problem), so its size is the number of problems, whatever
/// the number of repeats.
#[derive(Debug, Clone)]
pub struct RunList {
    /// For each (map, problem) in order: (map, problem, first run index, runs per planner).
    blocks: Vec<(usize, usize, u64, u64)>,
    n_runs: u64,
}

impl RunList {
    /// The run list of `experiment`: maps x problems x planners x repeats, where a problem
    /// that no label can run gets one run per planner (it is recorded, not planned;
    /// [`Experiment::repeats_of`]).
    pub fn new(experiment: &Experiment) -> RunList {
        let n_planners = experiment.planners.len() as u64;
        let mut blocks = Vec::new();
        let mut next = 0u64;
        for (m, map) in experiment.maps.iter().enumerate() {
            for (p, problem) in map.problems.iter().enumerate() {
                let repeats = experiment.repeats_of(problem);
                blocks.push((m, p, next, repeats));
                next += repeats * n_planners;
            }
        }
        RunList {
            blocks,
            n_runs: next,
        }
    }

    /// How many runs.
    pub fn len(&self) -> u64 {
        self.n_runs
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.n_runs == 0
    }

    /// The run with index `index` (< [`RunList::len`]).
    pub fn get(&self, index: u64) -> Option<RunSpec> {
        if index >= self.n_runs {
            return None;
        }
        let block = self.blocks.partition_point(|b| b.2 <= index) - 1;
        let (map, problem, first, repeats) = self.blocks[block];
        let offset = index - first;
        Some(RunSpec {
            map,
            problem,
            planner: (offset / repeats) as usize,
            repeat: (offset % repeats) as u32,
        })
    }
}

/// Measures the heap a run uses. The runner library installs no allocator; a binary that
/// counts allocations (xtask's counting allocator) provides this hook.
pub trait HeapMeter: Sync {
    /// Bytes currently allocated on this thread.
    fn current(&self) -> i64;
    /// Starts a peak measurement on this thread; returns the current bytes.
    fn start(&self) -> i64;
    /// The peak bytes on this thread since [`HeapMeter::start`], above `baseline`.
    fn peak_since(&self, baseline: i64) -> u64;
}

/// How to run a sweep.
#[derive(Clone, Copy, Default)]
pub struct RunOptions<'a> {
    /// Worker threads: 0 takes the experiment's `threads`, where 0 means one per core.
    pub threads: usize,
    /// Called with the number of runs done so far: after each run from the worker threads
    /// ([`run_all`]), or from the calling thread as it takes the finished runs
    /// ([`crate::stream::run_stream`]).
    pub progress: Option<&'a (dyn Fn(u64) + Sync)>,
    /// Measures peak heap per run; without it `peak_heap_bytes` is 0.
    pub heap: Option<&'a dyn HeapMeter>,
    /// Once set (by a binary's signal handler), a streamed sweep
    /// ([`crate::stream::run_stream`]) starts no new run, cancels the runs in progress
    /// (through their budget's [`CancelFlag`]; they are not recorded) and hands its sink
    /// every finished run; [`run_all`] ignores it.
    pub stop: Option<&'a std::sync::atomic::AtomicBool>,
}

/// One worker's planners, one per label, reused across its runs.
#[derive(Default)]
pub struct Workspace {
    slots: Vec<Option<Slot>>,
    /// The flag its runs' budgets carry ([`Workspace::cancelled_by`]).
    cancel: Option<CancelFlag>,
}

impl Workspace {
    /// A workspace whose runs stop, as if their budget ran out, once `flag` is raised
    /// ([`planner_api::Budget::cancel`]): what a streamed sweep raises when it is stopped.
    /// A run that ends while the flag is raised may have been cut short; its caller drops
    /// it.
    pub fn cancelled_by(flag: CancelFlag) -> Workspace {
        Workspace {
            slots: Vec::new(),
            cancel: Some(flag),
        }
    }
}

struct Slot {
    planner: Built,
    /// The map index the planner was last prepared for.
    grid: Option<usize>,
    /// Heap the planner holds between its calls: what its build, its setups and its
    /// searches allocated and did not free, less what its outcomes handed out (net bytes
    /// of this thread; the tables of an earlier grid it freed and the buffers it keeps
    /// from earlier searches included).
    retained: i64,
    /// For a planner run with `costs = "ignore"` on a weighted map: the map without its
    /// weights, made when the slot moves to the map.
    unweighted: Option<Grid>,
}

/// Runs every run of `experiment` and returns the records in the fixed order.
pub fn run_all(
    experiment: &Experiment,
    options: &RunOptions<'_>,
) -> Result<Vec<RunRecord>, RunnerError> {
    let list = RunList::new(experiment);
    let threads = match options.threads {
        0 => experiment.threads,
        n => n,
    };
    if threads > crate::config::MAX_THREADS {
        return Err(RunnerError::Threads(threads));
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(RunnerError::Pool)?;
    let done = std::sync::atomic::AtomicU64::new(0);
    // The workers log inside the caller's span, so that a subscriber that tells callers
    // apart by span (the Python package's) takes their events as the caller's.
    let span = tracing::Span::current();
    let records: Vec<Result<RunRecord, RunnerError>> = pool.install(|| {
        (0..list.len())
            .into_par_iter()
            .map_init(Workspace::default, |workspace, index| {
                let spec = list.get(index).ok_or(RunnerError::RunIndex(index))?;
                let record = span.in_scope(|| run_one(experiment, &spec, workspace, options.heap));
                if let Some(progress) = options.progress {
                    progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
                }
                record
            })
            .collect()
    });
    records.into_iter().collect()
}

/// Executes run `spec` of `experiment`, reusing `workspace`'s planner for its label.
pub fn run_one(
    experiment: &Experiment,
    spec: &RunSpec,
    workspace: &mut Workspace,
    heap: Option<&dyn HeapMeter>,
) -> Result<RunRecord, RunnerError> {
    let map = &experiment.maps[spec.map];
    let entry = &map.problems[spec.problem];
    let planner = &experiment.planners[spec.planner];
    let seed = planner.factory.seed_for(experiment.seed, spec.repeat);
    let mut record = blank_record(map, entry, planner, spec.repeat, seed);
    if let Some(why) = entry.invalid_for(planner.factory.task()) {
        // Said once per problem, by the first repeat of the first label that cannot run it
        // (which one shard of a sharded sweep runs), not once per run.
        let first = experiment.planners[..spec.planner]
            .iter()
            .all(|p| entry.invalid_for(p.factory.task()).is_none());
        if first && spec.repeat == 0 {
            tracing::warn!("{} problem {}: {why}; not run", map.name, entry.index);
        }
        return Ok(record);
    }
    if workspace.slots.len() < experiment.planners.len() {
        workspace
            .slots
            .resize_with(experiment.planners.len(), || None);
    }
    let setup_started = Instant::now();
    let baseline = heap.map(HeapMeter::current);
    // The sweep's flag where it has one, else the caller's own (the Python package's
    // Ctrl-C sets the planner's budget's flag).
    let budget = effective_budget(planner);
    let budget = Budget {
        cancel: workspace.cancel.or(budget.cancel),
        ..budget
    };
    let slot = match &mut workspace.slots[spec.planner] {
        Some(slot) => slot,
        empty => empty.insert(Slot {
            planner: planner
                .factory
                .build()
                .map_err(|e| RunnerError::Build(planner.label.clone(), e))?,
            grid: None,
            retained: 0,
            unweighted: None,
        }),
    };
    if slot.grid != Some(spec.map) {
        slot.unweighted =
            (planner.ignore_costs && map.grid.is_weighted()).then(|| map.grid.without_weights());
        if let Built::Path(p) = &mut slot.planner {
            let grid = slot.unweighted.as_ref().unwrap_or(&map.grid);
            p.prepare_within(grid, &budget);
        }
        slot.grid = Some(spec.map);
    }
    if let (Some(heap), Some(baseline)) = (heap, baseline) {
        // Building the planner and its setup for the grid (freeing an earlier grid's
        // tables counts down).
        slot.retained += heap.current() - baseline;
    }
    record.setup_ms = milliseconds(setup_started.elapsed());
    let run = Run {
        entry,
        planner,
        budget: &budget,
        seed,
        heap,
    };
    execute(&map.grid, &run, slot, &mut record);
    if let (Some(path), true) = (&record.path, map.grid.is_weighted()) {
        let cost = map.grid.path_cost(path.cells());
        record.cost = Some(cost.to_f64());
        if cost == Cost::MAX {
            // Saturated: the true cost, and the doubt about it (planner-api's weights docs,
            // "The range").
            let cost = map.grid.path_cost_f64(path.cells());
            record.cost = Some(cost);
            beyond_cost_range(planner, &mut record, entry, Some(cost));
        }
    }
    Ok(record)
}

/// Says that `planner`'s costs on `entry` reached [`Cost::MAX`], where they saturate: a
/// warning, and the record's error. `cost` is the true cost of the path it returned, if any.
/// The words of every error [`beyond_cost_range`] records, which [`not_run_reason`] tells
/// from a memory shortfall's.
const COSTS_SATURATE: &str = "where gridplan's costs saturate";

/// Why `record`'s planner was not run, when it was refused for a memory shortfall (its
/// per-cell state over the memory limit: status `budget_exhausted`, the shortfall as its
/// error). `None` for a run that ran, also one that stopped because its costs saturated
/// (whose error says so, and which more memory would not change).
pub fn not_run_reason(record: &RunRecord) -> Option<&str> {
    match (record.status, record.error.as_deref()) {
        (RunStatus::BudgetExhausted, Some(error)) if !error.contains(COSTS_SATURATE) => Some(error),
        _ => None,
    }
}

fn beyond_cost_range(
    planner: &PlannerSpec,
    record: &mut RunRecord,
    entry: &ProblemEntry,
    cost: Option<f64>,
) {
    let what = match cost {
        Some(cost) => format!(
            "its path costs {cost:.6e}, beyond {:.6e} {COSTS_SATURATE}, so it is not known to be least-cost",
            Cost::MAX.to_f64()
        ),
        None => format!(
            "its costs reached {:.6e}, {COSTS_SATURATE}, before it traced a path",
            Cost::MAX.to_f64()
        ),
    };
    tracing::warn!(
        "{} on {} problem {}: {what}",
        planner.label,
        record.map,
        entry.index
    );
    record.error = Some(what);
}

/// `elapsed` in milliseconds, as its whole nanoseconds over 1e6: the form the framed
/// stream stores as an integer ([`crate::frames`]), so a record read back from it is the
/// record measured, bit for bit.
fn milliseconds(elapsed: std::time::Duration) -> f64 {
    elapsed.as_nanos() as f64 / 1e6
}

fn blank_record(
    map: &MapEntry,
    entry: &ProblemEntry,
    planner: &PlannerSpec,
    repeat: u32,
    seed: Option<u64>,
) -> RunRecord {
    RunRecord {
        map: map.name.clone(),
        problem: entry.index,
        start: entry.start,
        goal: entry.goal,
        planner: planner.label.clone(),
        algorithm: planner.name.to_string(),
        repeat,
        seed,
        status: RunStatus::InvalidProblem,
        error: entry
            .invalid_for(planner.factory.task())
            .map(str::to_string),
        steps: None,
        turns: None,
        score: None,
        length: None,
        optimal_length: entry.optimal_length,
        bucket: entry.bucket,
        valid: None,
        admissible: (planner.factory.specs().admissible == Some(false)).then_some(false),
        counters: Counters::new(),
        time_ms: 0.0,
        setup_ms: 0.0,
        peak_heap_bytes: 0,
        path: None,
        returns: None,
        marks: Vec::new(),
        series: Vec::new(),
        cost: None,
    }
}

/// What one run plans with, besides the grid and the planner's slot.
struct Run<'a> {
    entry: &'a ProblemEntry,
    planner: &'a PlannerSpec,
    budget: &'a Budget,
    seed: Option<u64>,
    heap: Option<&'a dyn HeapMeter>,
}

/// Plans (or covers) with the slot's planner and fills `record`.
fn execute(grid: &Grid, run: &Run<'_>, slot: &mut Slot, record: &mut RunRecord) {
    let unweighted = slot.unweighted.take();
    let grid = unweighted.as_ref().unwrap_or(grid);
    execute_on(grid, run, slot, record);
    slot.unweighted = unweighted;
}

/// [`execute`] on the grid the planner plans on.
fn execute_on(grid: &Grid, run: &Run<'_>, slot: &mut Slot, record: &mut RunRecord) {
    let Run {
        entry,
        planner,
        budget,
        seed,
        heap,
    } = *run;
    let start_heap = heap.map(HeapMeter::start);
    let rule = planner.factory.specs().path_rule.clone();
    let (status, path) = match &mut slot.planner {
        Built::Path(p) => {
            let Ok(problem) = Problem::new(grid, entry.start, entry.goal) else {
                return;
            };
            if let Some(seed) = seed {
                p.reseed(seed);
            }
            let started = Instant::now();
            let outcome = p.plan(&problem, budget);
            record.time_ms = milliseconds(started.elapsed());
            let outcome = kept_by_planner(heap, start_heap, outcome, slot, record);
            record.counters = outcome.counters;
            record.marks = outcome.marks;
            record.series = outcome.series;
            if let Some(shortfall) = outcome.memory {
                not_run(planner, record, entry, shortfall);
            }
            if outcome.cost_overflow {
                beyond_cost_range(planner, record, entry, None);
            }
            (outcome.status, outcome.path)
        }
        Built::Coverage(c) => {
            let Ok(problem) = CoverageProblem::new(grid, entry.start) else {
                return;
            };
            let started = Instant::now();
            let outcome = c.cover(&problem, budget);
            record.time_ms = milliseconds(started.elapsed());
            let outcome = kept_by_planner(heap, start_heap, outcome, slot, record);
            record.counters = outcome.counters;
            record.returns = Some(outcome.returns);
            let path = match outcome.memory {
                Some(shortfall) => {
                    not_run(planner, record, entry, shortfall);
                    None
                }
                None => Some(outcome.path),
            };
            (outcome.status, path)
        }
    };
    record.status = status.into();
    if status == planner_api::Status::Found && path.is_none() {
        // `found` promises a path (planner-api's `Status`): recorded as an invalid one.
        tracing::warn!(
            "{} said found but returned no path ({} -> {})",
            planner.label,
            entry.start,
            entry.goal
        );
        record.valid = Some(false);
        record.error = Some("the planner said found but returned no path".into());
    }
    if let Some(path) = path {
        let m = path.metrics();
        record.steps = Some(m.steps);
        record.turns = Some(m.turns);
        record.score = Some(m.score);
        record.length = Some(m.length);
        let goal_ok = slot_is_coverage(&slot.planner) || path.goal() == Some(entry.goal);
        let valid = path.start() == Some(entry.start)
            && goal_ok
            && path.validate(grid, rule.rule()).is_ok();
        if !valid {
            tracing::warn!(
                "{} returned a path that breaks its declared rule or misses its ends ({} -> {})",
                planner.label,
                entry.start,
                entry.goal
            );
        }
        record.valid = Some(valid);
        record.path = Some(path);
    }
}

/// `outcome`, just returned by a search that started when this thread held `start`
/// bytes: sets the record's peak heap, what the slot's planner held as the search started
/// (its setup and the buffers it kept from earlier searches) plus the peak the search
/// added, and adds what the planner kept of the search's allocations (the thread's bytes
/// now, less the outcome's) to what it holds. The outcome's bytes are measured exactly by
/// dropping it once copied (the copy, returned, is what the record keeps); without a heap
/// meter it is returned as it is.
fn kept_by_planner<T: Clone>(
    heap: Option<&dyn HeapMeter>,
    start: Option<i64>,
    outcome: T,
    slot: &mut Slot,
    record: &mut RunRecord,
) -> T {
    let (Some(heap), Some(start)) = (heap, start) else {
        return outcome;
    };
    record.peak_heap_bytes = slot.retained.max(0) as u64 + heap.peak_since(start);
    let after = heap.current();
    let copy = outcome.clone();
    let with_both = heap.current();
    drop(outcome);
    let handed_out = with_both - heap.current();
    slot.retained += after - start - handed_out;
    copy
}

/// Says that `planner` did not run on `entry` because its per-cell state is over the
/// memory limit: a warning, and the record's error.
fn not_run(
    planner: &PlannerSpec,
    record: &mut RunRecord,
    entry: &ProblemEntry,
    shortfall: planner_api::MemoryShortfall,
) {
    tracing::warn!(
        "{} on {} problem {}: {shortfall}; not run",
        planner.label,
        record.map,
        entry.index
    );
    record.error = Some(shortfall.to_string());
}

/// The budget a run of `planner` gets: its own, with the memory limit
/// [`default_max_memory_mb`] when it sets none (`max_memory_mb` in its `budget`).
pub fn effective_budget(planner: &PlannerSpec) -> Budget {
    let mut budget = planner.budget;
    if budget.max_memory_mb.is_none() {
        budget.max_memory_mb = default_max_memory_mb();
    }
    budget
}

/// The memory limit runs get unless their budget sets `max_memory_mb`: half the
/// machine's memory (`MemTotal` of `/proc/meminfo`, read once), in MiB; `None` (no
/// limit) where it cannot be read. Planners do no I/O, so the runner reads it for them.
pub fn default_max_memory_mb() -> Option<u64> {
    static DEFAULT: std::sync::OnceLock<Option<u64>> = std::sync::OnceLock::new();
    *DEFAULT.get_or_init(|| {
        let text = std::fs::read_to_string("/proc/meminfo").ok()?;
        mem_total_kib(&text).map(|kib| kib / 1024 / 2)
    })
}

/// The `MemTotal:` value of a `/proc/meminfo` text, in KiB.
fn mem_total_kib(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemTotal:"))?;
    let mut words = line.split_whitespace().skip(1);
    let value: u64 = words.next()?.parse().ok()?;
    (words.next() == Some("kB")).then_some(value)
}

fn slot_is_coverage(built: &Built) -> bool {
    matches!(built, Built::Coverage(_))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mem_total_is_read_from_meminfo() {
        let text = "MemTotal:       24592716 kB\nMemFree:         1413016 kB\n";
        assert_eq!(mem_total_kib(text), Some(24_592_716));
        assert_eq!(mem_total_kib("MemFree: 5 kB\n"), None);
        assert_eq!(mem_total_kib("MemTotal: many kB\n"), None);
        assert_eq!(mem_total_kib("MemTotal: 5 MB\n"), None);
    }
}
