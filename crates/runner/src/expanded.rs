//! The expanded cells of the runs a sweep's figures draw, recorded at run time.
//!
//! With `figures_expanded = true`, each drawn (map, problem, label) is run once more with
//! [`planner_api::Budget::record_expanded`] on, apart from the timed runs (whose records
//! stay as they were), and its counters, status and path must equal the timed repeat 0's:
//! a difference is a determinism bug and an error ([`ExpandedError::Mismatch`]; not
//! checked for budgets with a wall-clock limit, whose counters depend on the machine).
//! The sweep does this before it hands its results to the report, so no later step runs
//! a planner. Which problems are drawn is the config's (`figures_pick`,
//! `figures_per_map`; [`pick`]).

use indexmap::IndexMap;
use planner_api::{Cell, Problem};
use planner_registry::Built;
use serde::{Deserialize, Serialize};

use crate::config::{Experiment, FigureMode, FigurePick, MapEntry, PlannerSpec, ProblemEntry};
use crate::index::ResultsIndex;
use crate::record::{RunRecord, RunStatus};
use crate::stream::{Place, StreamError, StreamProblem};

/// Why the expanded cells could not be recorded.
#[derive(Debug, thiserror::Error)]
pub enum ExpandedError {
    /// The run with recording on did not repeat the timed run.
    #[error(
        "{label} on {map} problem {problem}: the run recording expanded cells gave \
         {recorded}, the timed run {timed}; runs must be deterministic (a bug)"
    )]
    Mismatch {
        /// The planner label.
        label: String,
        /// The map file name.
        map: String,
        /// The 1-based problem.
        problem: usize,
        /// The timed run's status and counters.
        timed: String,
        /// The recording run's status and counters.
        recorded: String,
    },
    /// The planner could not be built again (its config built for the timed run).
    #[error("planner `{0}`: {1}")]
    Build(String, planner_api::ParamError),
}

/// The expanded cells of the drawn runs, by (map name, 1-based problem, label), in the
/// order they were recorded; `expanded.jsonl` in a results directory.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ExpandedCells {
    cells: IndexMap<(String, usize, String), Vec<Cell>>,
}

/// One line of `expanded.jsonl`.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Line {
    map: String,
    problem: usize,
    planner: String,
    expanded: Vec<Cell>,
}

impl ExpandedCells {
    /// The cells run `label` expanded on problem `problem` of map `map`, if recorded.
    pub fn get(&self, map: &str, problem: usize, label: &str) -> Option<&[Cell]> {
        self.cells
            .get(&(map.to_string(), problem, label.to_string()))
            .map(Vec::as_slice)
    }

    /// Records the cells of one run.
    pub fn insert(&mut self, map: &str, problem: usize, label: &str, cells: Vec<Cell>) {
        self.cells
            .insert((map.to_string(), problem, label.to_string()), cells);
    }

    /// Whether nothing is recorded.
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// Adds every run of `other` (a shard's cells, when merging).
    pub fn extend(&mut self, other: ExpandedCells) {
        self.cells.extend(other.cells);
    }

    /// The cells as JSON Lines, one `{"map","problem","planner","expanded"}` object per run,
    /// in recording order (`expanded.jsonl`).
    pub fn to_jsonl(&self) -> Result<Vec<u8>, crate::RunnerError> {
        let mut out = Vec::new();
        for ((map, problem, planner), cells) in &self.cells {
            let line = Line {
                map: map.clone(),
                problem: *problem,
                planner: planner.clone(),
                expanded: cells.clone(),
            };
            serde_json::to_writer(&mut out, &line).map_err(crate::RunnerError::Json)?;
            out.push(b'\n');
        }
        Ok(out)
    }

    /// Reads `expanded.jsonl` text; `what` names the file in errors (with the line).
    pub fn from_jsonl(text: &str, what: &str) -> Result<ExpandedCells, crate::RunnerError> {
        let mut all = ExpandedCells::default();
        for (n, line) in text.lines().enumerate() {
            let line: Line = serde_json::from_str(line).map_err(|e| {
                let place = Place::Line(n as u64 + 1);
                StreamError::new(what, place, StreamProblem::Json(e))
            })?;
            all.insert(&line.map, line.problem, &line.planner, line.expanded);
        }
        Ok(all)
    }
}

/// Runs every drawn (map, problem, label) of `experiment` once more with expanded cells
/// recorded (when the config asks: `figures_expanded`, and figures are drawn); in the
/// order the figures draw them, so the first mismatch is reported.
pub fn record_all(
    experiment: &Experiment,
    records: &[RunRecord],
) -> Result<ExpandedCells, ExpandedError> {
    let mut all = ExpandedCells::default();
    if !experiment.figures_expanded || experiment.figures == FigureMode::None {
        return Ok(all);
    }
    let index = ResultsIndex::new(records);
    for map in &experiment.maps {
        let limit = experiment.figure_limit(map);
        for problem in pick(&map.problems, experiment.figures_pick, limit) {
            if problem.invalid.is_some() {
                continue;
            }
            for planner in &experiment.planners {
                if let Some(timed) = index.first(&map.name, problem.index, &planner.label) {
                    let cells = record_expanded(experiment, map, problem, planner, timed)?;
                    all.insert(&map.name, problem.index, &planner.label, cells);
                }
            }
        }
    }
    Ok(all)
}

/// Runs `planner` on `problem` of `map` again with [`planner_api::Budget::record_expanded`]
/// on (with the seed and budget of `timed`'s run) and returns the expanded cells, after
/// checking that status, counters and path equal `timed`'s. Coverage planners and
/// invalid problems give none.
pub fn record_expanded(
    experiment: &Experiment,
    map: &MapEntry,
    problem: &ProblemEntry,
    planner: &PlannerSpec,
    timed: &RunRecord,
) -> Result<Vec<Cell>, ExpandedError> {
    record_search(experiment, map, problem, planner, timed, false).map(|(cells, _)| cells)
}

/// [`record_expanded`], and with `events` the search step by step as well
/// ([`planner_api::Budget::record_events`]; empty for planners that do not record it).
pub fn record_search(
    experiment: &Experiment,
    map: &MapEntry,
    problem: &ProblemEntry,
    planner: &PlannerSpec,
    timed: &RunRecord,
    events: bool,
) -> Result<(Vec<Cell>, Vec<planner_api::SearchEvent>), ExpandedError> {
    // The grid the timed run planned on: without its weights for `costs = "ignore"`
    // (the recording run planned on the weights, and its counters differed).
    let unweighted =
        (planner.ignore_costs && map.grid.is_weighted()).then(|| map.grid.without_weights());
    let grid = unweighted.as_ref().unwrap_or(&map.grid);
    let Ok(query) = Problem::new(grid, problem.start, problem.goal) else {
        return Ok((Vec::new(), Vec::new()));
    };
    let built = planner
        .factory
        .build()
        .map_err(|e| ExpandedError::Build(planner.label.clone(), e))?;
    let Built::Path(mut p) = built else {
        return Ok((Vec::new(), Vec::new()));
    };
    let budget = crate::run::effective_budget(planner)
        .recording_expanded(true)
        .recording_events(events);
    p.prepare_within(grid, &budget);
    if let Some(seed) = planner.factory.seed_for(experiment.seed, timed.repeat) {
        p.reseed(seed);
    }
    let outcome = p.plan(&query, &budget);
    let same = RunStatus::from(outcome.status) == timed.status
        && outcome.counters == timed.counters
        // Records keep paths only as `paths` says: compare a kept one.
        && (timed.path.is_none() || outcome.path == timed.path);
    if !same && budget.max_time.is_none() {
        return Err(ExpandedError::Mismatch {
            label: planner.label.clone(),
            map: map.name.clone(),
            problem: problem.index,
            timed: format!("{} {}", timed.status, timed.counters),
            recorded: format!("{} {}", outcome.status.as_str(), outcome.counters),
        });
    }
    Ok((outcome.expanded, outcome.events))
}

/// The problems of a map to draw, at most `limit`, in map order.
pub fn pick(problems: &[ProblemEntry], how: FigurePick, limit: usize) -> Vec<&ProblemEntry> {
    let valid = problems.iter().filter(|p| p.invalid.is_none());
    let mut chosen: Vec<&ProblemEntry> = match how {
        FigurePick::First => return problems.iter().take(limit).collect(),
        FigurePick::Hardest => {
            let hardness = |p: &ProblemEntry| {
                p.optimal_length
                    .unwrap_or_else(|| p.start.euclidean(p.goal))
            };
            let mut all: Vec<&ProblemEntry> = valid.collect();
            // Hardest first; ties keep map order (the sort is stable).
            all.sort_by(|a, b| hardness(b).total_cmp(&hardness(a)));
            all.truncate(limit);
            all
        }
        FigurePick::Buckets => {
            let mut firsts: Vec<&ProblemEntry> = Vec::new();
            for p in valid {
                if !firsts.iter().any(|f| f.bucket == p.bucket) {
                    firsts.push(p);
                }
            }
            firsts.sort_by_key(|p| p.bucket);
            if firsts.len() > limit && limit > 0 {
                let n = firsts.len();
                let step = (n - 1) as f64 / (limit.max(2) - 1) as f64;
                let mut spread: Vec<&ProblemEntry> = (0..limit)
                    .map(|i| firsts[((i as f64 * step).round() as usize).min(n - 1)])
                    .collect();
                spread.dedup_by_key(|p| p.index);
                spread
            } else {
                firsts.truncate(limit);
                firsts
            }
        }
    };
    chosen.sort_by_key(|p| p.index);
    chosen
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner_api::{Cell, Grid};

    fn problems() -> Vec<ProblemEntry> {
        let grid = Grid::new(10, 1).unwrap();
        (0..6)
            .map(|i| ProblemEntry {
                bucket: Some(i / 2),
                ..ProblemEntry::new(
                    &grid,
                    i as usize + 1,
                    Cell::new(0, 0),
                    Cell::new(i, 0),
                    Some(f64::from(i)),
                )
            })
            .collect()
    }

    fn check(how: FigurePick, limit: usize, expect: &[usize]) {
        let all = problems();
        let got: Vec<usize> = pick(&all, how, limit).iter().map(|p| p.index).collect();
        assert_eq!(got, expect, "{how:?} {limit}");
    }

    #[test]
    fn figures_pick_first_hardest_and_one_per_bucket() {
        check(FigurePick::First, 2, &[1, 2]);
        // Optima 0..5: the two largest are problems 6 and 5.
        check(FigurePick::Hardest, 2, &[5, 6]);
        // Buckets 0, 1, 2 begin at problems 1, 3, 5.
        check(FigurePick::Buckets, 3, &[1, 3, 5]);
        // Two of three buckets: the first and the last.
        check(FigurePick::Buckets, 2, &[1, 5]);
    }
}
