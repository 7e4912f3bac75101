//! Expanding an experiment into runs and running them in parallel.
//!
//! Runs are listed in a fixed order (map, problem, planner, repeat), executed on a rayon
//! pool, and collected by index, so the records do not depend on the thread count; only
//! the timing and memory fields do.

use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use planner_api::{Cell, Counters, Path, Problem};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::alloc;
use crate::config::Experiment;

/// One run's result: everything counted, measured and found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// Map file name.
    pub map: String,
    /// 1-based problem index within the map.
    pub problem: usize,
    /// Start cell.
    pub start: Cell,
    /// Goal cell.
    pub goal: Cell,
    /// Planner label from the config.
    pub planner: String,
    /// Registry name.
    pub algorithm: String,
    /// 0-based repeat.
    pub repeat: u32,
    /// The seed a stochastic planner ran with.
    pub seed: Option<u64>,
    /// `found`, `no_path`, `budget_exhausted`, or `invalid_problem`.
    pub status: String,
    /// Why the problem is invalid, if it is.
    pub error: Option<String>,
    /// D, when a path came back.
    pub steps: Option<u64>,
    /// T.
    pub turns: Option<u64>,
    /// Score.
    pub score: Option<u64>,
    /// Euclidean length.
    pub length: Option<f64>,
    /// The optimal length the scenario file states, if any.
    pub optimal_length: Option<f64>,
    /// Whether the path passed planner-api's validity check (any-angle rule, or 8-connected
    /// moves with corner cutting for planners configured with `corner_cutting = true`).
    pub valid: Option<bool>,
    /// The planner's counters, in its order.
    pub counters: Counters,
    /// Wall time of `plan`, in milliseconds (timing: not deterministic).
    pub time_ms: f64,
    /// Peak heap bytes of building the planner and planning (memory: not deterministic
    /// across allocators, stable on one build).
    pub peak_heap_bytes: u64,
    /// The path's cells.
    pub path: Option<Path>,
    /// Coverage planners only: the stretches of `path` that return to a backtracking point.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub returns: Option<Vec<planner_api::ReturnLeg>>,
    /// The cells the planner marked in its outcome (PA-star's handover points), if any.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub marks: Vec<planner_api::Mark>,
    /// The sequences the planner recorded (CAPSO's best fitness per iteration), if any.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub series: Vec<planner_api::Series>,
}

/// One run to do.
#[derive(Debug, Clone, Copy)]
struct RunSpec {
    map: usize,
    problem: usize,
    planner: usize,
    repeat: u32,
}

/// Runs every (map, problem, planner, repeat) of `experiment` on `threads` threads
/// (0 = the experiment's setting, which 0 makes one per core) and returns the records in
/// the fixed order.
pub fn run_all(
    experiment: &Experiment,
    threads: usize,
    progress: bool,
) -> Result<Vec<RunRecord>, String> {
    let specs = expand(experiment);
    let threads = if threads == 0 {
        experiment.threads
    } else {
        threads
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| format!("cannot start {threads} worker threads: {e}"))?;
    let bar = if progress {
        let bar =
            ProgressBar::with_draw_target(Some(specs.len() as u64), ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} runs ({eta})",
        ) {
            bar.set_style(style);
        }
        bar
    } else {
        ProgressBar::hidden()
    };
    let records: Vec<Result<RunRecord, String>> = pool.install(|| {
        specs
            .par_iter()
            .map(|spec| {
                let record = run_one(experiment, spec);
                bar.inc(1);
                record
            })
            .collect()
    });
    bar.finish_and_clear();
    records.into_iter().collect()
}

fn expand(experiment: &Experiment) -> Vec<RunSpec> {
    let mut specs = Vec::new();
    for (m, map) in experiment.maps.iter().enumerate() {
        for (p, problem) in map.problems.iter().enumerate() {
            for planner in 0..experiment.planners.len() {
                let repeats = if problem.invalid.is_some() {
                    1
                } else {
                    experiment.repeats
                };
                for repeat in 0..repeats {
                    specs.push(RunSpec {
                        map: m,
                        problem: p,
                        planner,
                        repeat,
                    });
                }
            }
        }
    }
    specs
}

fn run_one(experiment: &Experiment, spec: &RunSpec) -> Result<RunRecord, String> {
    let map = &experiment.maps[spec.map];
    let entry = &map.problems[spec.problem];
    let planner_spec = &experiment.planners[spec.planner];
    let span = tracing::debug_span!(
        "run",
        map = %map.name,
        problem = entry.index,
        planner = %planner_spec.label,
        repeat = spec.repeat
    );
    let _guard = span.enter();
    let mut record = RunRecord {
        map: map.name.clone(),
        problem: entry.index,
        start: entry.start,
        goal: entry.goal,
        planner: planner_spec.label.clone(),
        algorithm: planner_spec.name.to_string(),
        repeat: spec.repeat,
        seed: planner_spec.seed_for(experiment.seed, spec.repeat),
        status: "invalid_problem".into(),
        error: entry.invalid.clone(),
        steps: None,
        turns: None,
        score: None,
        length: None,
        optimal_length: entry.optimal_length,
        valid: None,
        counters: Counters::new(),
        time_ms: 0.0,
        peak_heap_bytes: 0,
        path: None,
        returns: None,
        marks: Vec::new(),
        series: Vec::new(),
    };
    let Ok(problem) = Problem::new(&map.grid, entry.start, entry.goal) else {
        tracing::warn!(error = ?entry.invalid, "skipping an invalid problem");
        return Ok(record);
    };
    if planner_spec.coverage {
        crate::coverage::run(&map.grid, entry.start, planner_spec, &mut record)?;
        return Ok(record);
    }
    let baseline = alloc::start();
    let mut planner = planner_spec
        .build(experiment.seed, spec.repeat)
        .map_err(|e| format!("planner `{}`: {e}", planner_spec.label))?;
    let started = Instant::now();
    let outcome = planner.plan(&problem, &planner_spec.budget);
    record.time_ms = started.elapsed().as_secs_f64() * 1e3;
    drop(planner);
    record.peak_heap_bytes = alloc::peak_since_start(baseline);
    tracing::debug!(
        status = outcome.status.as_str(),
        time_ms = record.time_ms,
        "done"
    );
    record.status = outcome.status.as_str().into();
    record.counters = outcome.counters;
    record.marks = outcome.marks;
    record.series = outcome.series;
    if let Some(path) = outcome.path {
        let m = path.metrics();
        record.steps = Some(m.steps);
        record.turns = Some(m.turns);
        record.score = Some(m.score);
        record.length = Some(m.length);
        let ends_right = path.start() == Some(entry.start) && path.goal() == Some(entry.goal);
        let rule_moves = planner_spec.path_rule_moves();
        let rule = match &rule_moves {
            Some(moves) => planner_api::PathRule::Moves(moves),
            None => planner_api::PathRule::AnyAngle,
        };
        let valid = ends_right && path.validate(&map.grid, rule).is_ok();
        if !valid {
            tracing::warn!("the planner returned an invalid path");
        }
        record.valid = Some(valid);
        record.path = Some(path);
    }
    Ok(record)
}
