//! One planning query from the page: a map (read with planner-maps, then the page's wall
//! edits applied), a start and goal, a registry planner with `key=value` parameters,
//! planned through planner-runner's [`run_single`] exactly as `gridplan plan` plans it
//! (the same cost refusal, [`refuses_costs`], and the same run through `run_one`), so the
//! counters equal `plan --json`'s (but for a search stopped by the server's wall-clock
//! limit, [`Caps::max_time`]); then once more with the expanded cells recorded
//! ([`planner_runner::expanded::record_search`], which checks that the second run
//! repeats the first), for the playback, unless the first ran out of time or was
//! cancelled.
//!
//! These are the only call sites of the runner's planning API in this crate (the
//! registry, [`run_single`], the plan result's JSON), so a move of the runner's modules
//! changes this file alone.
//!
//! [`run_single`]: planner_runner::plan::run_single
//! [`refuses_costs`]: planner_runner::plan::refuses_costs

use std::path::Path;
use std::time::{Duration, Instant};

use planner_api::{Budget, CancelFlag, Cell, Grid};
use planner_runner::config::{self, MapEntry, ProblemEntry};
use planner_runner::plan::{PlanResult, DEFAULT_PLAN_EXPANSIONS};
use planner_runner::usage::UsageError;
use planner_runner::{Experiment, RunStatus};

/// The wall-clock limit of a query's search by default ([`Caps::max_time`]): one minute.
pub const DEFAULT_MAX_TIME: Duration = Duration::from_secs(60);

/// Limits a query gets whatever it asks for.
#[derive(Debug, Clone, Copy)]
pub struct Caps {
    /// The most expansions one run may do.
    pub max_expansions: u64,
    /// The most memory a planner's per-cell state may take, in MiB.
    pub max_memory_mb: u64,
    /// The longest a query's search may run: it then ends with status
    /// `budget_exhausted` ([`planner_api::Budget::max_time`]), and its expanded cells are
    /// not recorded (the recording run would take as long again). A search that ends
    /// before it is run once more, without it, to record its cells (about as long as the
    /// first), so a query holds its place for at most about twice `max_time`.
    pub max_time: Duration,
}

impl Default for Caps {
    /// `plan`'s default expansion budget (ten million expansions), 2 GiB, and
    /// [`DEFAULT_MAX_TIME`] (one minute). Ten million expansions take seconds for the
    /// grid searches, but a sampling planner's evaluation may cost far more than an
    /// expansion (CAPSO with a large population and many samples per segment does about
    /// ten thousand a second), so the wall-clock limit is what bounds how long a plan
    /// holds one of the server's places. A search that ends on it has counters that
    /// depend on the machine, as a sweep's run with `max_time` does.
    fn default() -> Caps {
        Caps {
            max_expansions: DEFAULT_PLAN_EXPANSIONS,
            max_memory_mb: 2048,
            max_time: DEFAULT_MAX_TIME,
        }
    }
}

/// What can go wrong with a query (all are the user's input: HTTP 400).
#[derive(Debug, thiserror::Error)]
pub enum QueryError {
    /// The runner refused it (unknown planner or parameter, a setting `plan --set` would
    /// refuse, bad cell, ...).
    #[error(transparent)]
    Runner(#[from] planner_runner::RunnerError),
    /// A wall edit outside the grid.
    #[error("wall edit at ({x}, {y}): outside the {width}x{height} grid")]
    Edit {
        /// Column.
        x: u32,
        /// Row.
        y: u32,
        /// Grid width.
        width: u32,
        /// Grid height.
        height: u32,
    },
    /// A wall edit whose `free` is neither 0 (wall) nor 1 (free).
    #[error("wall edit {index} [{x}, {y}, {free}]: free must be 0 (wall) or 1 (free), not {free}")]
    EditValue {
        /// The edit's index in the request's `edits`.
        index: usize,
        /// Column.
        x: u32,
        /// Row.
        y: u32,
        /// The value given.
        free: u8,
    },
    /// A coverage planner (the page plans start-goal queries).
    #[error("`{0}` is a coverage planner; the page plans start-goal queries")]
    Coverage(String),
    /// A planner that cannot honour cell costs, on a weighted map.
    #[error("planner `{planner}` does not honour cell costs, and map `{map}` has them; ask to ignore costs to plan without them")]
    Costs {
        /// The planner's registry name.
        planner: String,
        /// The map's name.
        map: String,
    },
}

/// One query.
#[derive(Debug, Clone)]
pub struct Query<'a> {
    /// The map's name (shown in the record).
    pub map_name: &'a str,
    /// The map's file (resolved under the served directory).
    pub map_path: &'a Path,
    /// Start cell.
    pub start: Cell,
    /// Goal cell.
    pub goal: Cell,
    /// Registry name.
    pub planner: &'a str,
    /// `key=value` settings, as `plan --set` takes them.
    pub set: &'a [String],
    /// Expansion budget asked for (capped by [`Caps::max_expansions`]).
    pub max_expansions: Option<u64>,
    /// On a weighted grid, plan with a planner that cannot honour cell costs on the grid
    /// without them (else it is refused, as `plan` refuses it).
    pub ignore_costs: bool,
    /// Raised to stop the search ([`planner_api::Budget::cancel`]): the run ends with
    /// status `budget_exhausted` at the planner's next budget check, and records no
    /// expanded cells.
    pub cancel: Option<CancelFlag>,
}

/// The request's wall edits `[x, y, free]` as `(x, y, free)`: `free` 0 is a wall, 1 a
/// free cell, and any other value is refused ([`QueryError::EditValue`]).
pub fn edits_from_values(edits: &[(u32, u32, u8)]) -> Result<Vec<(u32, u32, bool)>, QueryError> {
    edits
        .iter()
        .enumerate()
        .map(|(index, &(x, y, free))| match free {
            0 => Ok((x, y, false)),
            1 => Ok((x, y, true)),
            _ => Err(QueryError::EditValue { index, x, y, free }),
        })
        .collect()
}

/// The grid `grid` with `edits` applied: `(x, y, free)` each.
pub fn apply_edits(grid: &mut Grid, edits: &[(u32, u32, bool)]) -> Result<(), QueryError> {
    for &(x, y, free) in edits {
        let cell = Cell::new(x, y);
        if !grid.contains(cell) {
            return Err(QueryError::Edit {
                x,
                y,
                width: grid.width(),
                height: grid.height(),
            });
        }
        grid.set_free(cell, free);
    }
    Ok(())
}

/// The `key=value` settings as a planner table, parsed as `plan --set` parses them and
/// refused with its errors ([`UsageError`]): a setting without `=` or without a key, a
/// value written as a number that is not one ([`planner_runner::plan::setting_value`]),
/// and one key given two different values (the same value twice is one setting).
pub fn settings_table(set: &[String]) -> Result<toml::Table, QueryError> {
    let mut params = toml::Table::new();
    let mut given: Vec<(&str, &str)> = Vec::new();
    for assignment in set {
        let (key, value) = assignment
            .split_once('=')
            .filter(|(key, _)| !key.trim().is_empty())
            .ok_or_else(|| UsageError::Assignment(assignment.clone()))
            .map_err(planner_runner::RunnerError::from)?;
        let (key, value) = (key.trim(), value.trim());
        if let Some(&(_, first)) = given.iter().find(|(k, _)| *k == key) {
            if first != value {
                return Err(planner_runner::RunnerError::from(UsageError::SetTwice {
                    key: key.to_string(),
                    first: first.to_string(),
                    second: value.to_string(),
                })
                .into());
            }
        }
        given.push((key, value));
        let parsed = planner_runner::plan::setting_value(value).ok_or_else(|| {
            planner_runner::RunnerError::from(UsageError::SetNumber {
                key: key.to_string(),
                value: value.to_string(),
            })
        })?;
        params.insert(key.to_string(), parsed);
    }
    Ok(params)
}

/// Plans `query` on `grid` within `caps`: the run's result (its JSON is `plan --json`'s)
/// with the expanded cells recorded, but for a cancelled run ([`Query::cancel`]) and one
/// that ran out of time ([`Caps::max_time`]), which record none.
pub fn plan(query: &Query<'_>, grid: Grid, caps: &Caps) -> Result<PlanResult, QueryError> {
    let budget = Budget {
        max_expansions: Some(
            query
                .max_expansions
                .unwrap_or(DEFAULT_PLAN_EXPANSIONS)
                .min(caps.max_expansions),
        ),
        max_time: Some(caps.max_time),
        max_memory_mb: Some(caps.max_memory_mb),
        record_expanded: false,
        record_events: false,
        cancel: query.cancel,
    };
    let params = settings_table(query.set)?;
    let mut spec = config::planner_from_table(query.planner, query.planner, params, budget)?;
    if spec.is_coverage() {
        return Err(QueryError::Coverage(query.planner.to_string()));
    }
    spec.ignore_costs = query.ignore_costs;
    if planner_runner::plan::refuses_costs(&spec, &grid) {
        return Err(QueryError::Costs {
            planner: query.planner.to_string(),
            map: query.map_name.to_string(),
        });
    }
    let entry = ProblemEntry::new(&grid, 1, query.start, query.goal, None);
    if let Err(error) = planner_api::Problem::new(&grid, query.start, query.goal) {
        return Err(planner_runner::RunnerError::Problem {
            map: query.map_path.to_path_buf(),
            error,
        }
        .into());
    }
    let map = MapEntry {
        name: query.map_name.to_string(),
        path: query.map_path.to_path_buf(),
        grid,
        problems: Vec::new(),
        frame: None,
        // The page draws a ROS map's unknown cells itself, from the map it loaded.
        unknown: None,
    };
    // The recording run is made here rather than by `run_single`, so that a search that
    // ran out of time is not run for as long again to record its cells.
    let recording = Experiment::single(map.clone(), entry.clone(), spec.clone(), 0);
    let started = Instant::now();
    let mut result =
        planner_runner::plan::run_single(map, entry, spec, 0, query.planner, false, false)?;
    let out_of_time =
        result.record.status == RunStatus::BudgetExhausted && started.elapsed() >= caps.max_time;
    if out_of_time || result.budget.is_cancelled() {
        return Ok(result);
    }
    let (map, mut spec) = (&recording.maps[0], recording.planners[0].clone());
    // The timed run ended before the limit, so its result does not depend on it: the
    // recording run goes without it, and is checked to repeat the timed run.
    spec.budget.max_time = None;
    let (expanded, events) = planner_runner::expanded::record_search(
        &recording,
        map,
        &map.problems[0],
        &spec,
        &result.record,
        // The steps too, so that the page can show OPEN's frontier (planners that record
        // them: A*).
        true,
    )
    .map_err(planner_runner::RunnerError::from)?;
    result.expanded = expanded;
    result.events = events;
    Ok(result)
}
