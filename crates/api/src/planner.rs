//! The [`Planner`] trait, problems, budgets and outcomes.

use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use crate::counters::Counters;
use crate::error::{Endpoint, ProblemError};
use crate::grid::{Cell, Grid};
use crate::path::Path;
use crate::specs::PlannerSpecs;

/// A start-goal query on a grid. Construction validates both cells.
#[derive(Debug, Clone, Copy)]
pub struct Problem<'g> {
    grid: &'g Grid,
    start: Cell,
    goal: Cell,
}

impl<'g> Problem<'g> {
    /// A problem from `start` to `goal` on `grid`.
    ///
    /// Errors, naming the cell, when the start or goal is out of bounds or blocked.
    /// A goal that is free but unreachable is not an error: planners report
    /// [`Status::NoPath`].
    pub fn new(grid: &'g Grid, start: Cell, goal: Cell) -> Result<Problem<'g>, ProblemError> {
        for (endpoint, cell) in [(Endpoint::Start, start), (Endpoint::Goal, goal)] {
            if !grid.contains(cell) {
                return Err(ProblemError::OutOfBounds {
                    endpoint,
                    cell,
                    width: grid.width(),
                    height: grid.height(),
                });
            }
            if !grid.is_free(cell) {
                return Err(ProblemError::Blocked { endpoint, cell });
            }
        }
        Ok(Problem { grid, start, goal })
    }

    /// The grid.
    pub fn grid(&self) -> &'g Grid {
        self.grid
    }

    /// The start cell (in bounds and free).
    pub fn start(&self) -> Cell {
        self.start
    }

    /// The goal cell (in bounds and free).
    pub fn goal(&self) -> Cell {
        self.goal
    }
}

/// Limits on one search. The default is unlimited.
///
/// An expansion limit keeps results deterministic; a wall-clock limit does not (what a
/// search reaches in a given time depends on the machine), so configs that snapshot
/// counters should use expansions.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Budget {
    /// Stop after this many expansions (each planner says what one expansion is).
    pub max_expansions: Option<u64>,
    /// Stop after this much wall-clock time, checked every [`BudgetClock::TIME_CHECK_INTERVAL`] expansions.
    #[serde(default, with = "optional_millis", rename = "max_time_ms")]
    pub max_time: Option<Duration>,
}

impl Budget {
    /// No limit.
    pub fn unlimited() -> Budget {
        Budget::default()
    }

    /// At most `n` expansions.
    pub fn expansions(n: u64) -> Budget {
        Budget {
            max_expansions: Some(n),
            max_time: None,
        }
    }

    /// This budget with a wall-clock limit as well.
    pub fn with_time(self, limit: Duration) -> Budget {
        Budget {
            max_time: Some(limit),
            ..self
        }
    }

    /// Starts the clock for one search.
    pub fn start(&self) -> BudgetClock {
        BudgetClock {
            max_expansions: self.max_expansions.unwrap_or(u64::MAX),
            deadline: self.max_time.map(|limit| Instant::now() + limit),
            until_time_check: BudgetClock::TIME_CHECK_INTERVAL,
            exhausted: false,
        }
    }
}

mod optional_millis {
    use std::time::Duration;

    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(value: &Option<Duration>, s: S) -> Result<S::Ok, S::Error> {
        match value {
            Some(d) => s.serialize_some(&(d.as_millis() as u64)),
            None => s.serialize_none(),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Duration>, D::Error> {
        Ok(Option::<u64>::deserialize(d)?.map(Duration::from_millis))
    }
}

/// The running state of a [`Budget`] during one search.
///
/// Call [`BudgetClock::allows`] before each expansion with the number done so far.
#[derive(Debug, Clone)]
pub struct BudgetClock {
    max_expansions: u64,
    deadline: Option<Instant>,
    until_time_check: u32,
    exhausted: bool,
}

impl BudgetClock {
    /// How many expansions pass between two reads of the clock.
    pub const TIME_CHECK_INTERVAL: u32 = 1024;

    /// Whether one more expansion is allowed after `n_expanded` of them. Once it has said
    /// no it keeps saying no, and [`BudgetClock::is_exhausted`] turns true.
    #[inline]
    pub fn allows(&mut self, n_expanded: u64) -> bool {
        if self.exhausted {
            return false;
        }
        if n_expanded >= self.max_expansions {
            self.exhausted = true;
            return false;
        }
        if let Some(deadline) = self.deadline {
            self.until_time_check -= 1;
            if self.until_time_check == 0 {
                self.until_time_check = Self::TIME_CHECK_INTERVAL;
                if Instant::now() >= deadline {
                    self.exhausted = true;
                    return false;
                }
            }
        }
        true
    }

    /// Whether the budget has run out.
    pub fn is_exhausted(&self) -> bool {
        self.exhausted
    }
}

/// How a search ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// A path was found; exhaustive planners found the best one.
    Found,
    /// The search completed and proved there is no path.
    NoPath,
    /// The budget ran out first; the outcome carries the best path found so far, if any.
    BudgetExhausted,
}

impl Status {
    /// The snake-case name used in results: `found`, `no_path`, `budget_exhausted`.
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Found => "found",
            Status::NoPath => "no_path",
            Status::BudgetExhausted => "budget_exhausted",
        }
    }
}

/// The result of one [`Planner::plan`] call.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Outcome {
    /// How the search ended.
    pub status: Status,
    /// The path: present when found; for an exhausted budget, the best found so far if any.
    pub path: Option<Path>,
    /// The counters that apply to this planner, in its order.
    pub counters: Counters,
    /// Cells the planner points out in its result, in its order (PA-star's handover
    /// points); usually none. Figures draw them and run records list them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub marks: Vec<Mark>,
    /// Named sequences a planner records along its search, such as a swarm's best fitness
    /// per iteration or an optimising planner's cost after each improvement; usually none.
    /// Reports chart them and run records keep them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub series: Vec<Series>,
}

/// A named sequence of (x, y) points a planner records during one search, for example
/// (iteration, best cost). Points are in the order they were recorded.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Series {
    /// What the sequence is, e.g. `best_fitness`.
    pub name: String,
    /// What x counts, e.g. `iteration`.
    pub x: String,
    /// The points.
    pub points: Vec<[f64; 2]>,
}

impl Series {
    /// An empty series named `name` whose x axis counts `x`.
    pub fn new(name: impl Into<String>, x: impl Into<String>) -> Series {
        Series {
            name: name.into(),
            x: x.into(),
            points: Vec::new(),
        }
    }
}

/// A cell a planner points out in its result, with a short label (a few characters, as
/// figures write it beside the cell).
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Mark {
    /// The marked cell.
    pub cell: Cell,
    /// Its label, e.g. `H1`.
    pub label: String,
}

impl Mark {
    /// A mark from its parts.
    pub fn new(cell: Cell, label: impl Into<String>) -> Mark {
        Mark {
            cell,
            label: label.into(),
        }
    }
}

impl Outcome {
    /// An outcome from its status, path and counters, without marks or series.
    pub fn new(status: Status, path: Option<Path>, counters: Counters) -> Outcome {
        Outcome {
            status,
            path,
            counters,
            marks: Vec::new(),
            series: Vec::new(),
        }
    }

    /// A found path.
    pub fn found(path: Path, counters: Counters) -> Outcome {
        Outcome {
            status: Status::Found,
            path: Some(path),
            counters,
            marks: Vec::new(),
            series: Vec::new(),
        }
    }

    /// A completed search without a path.
    pub fn no_path(counters: Counters) -> Outcome {
        Outcome {
            status: Status::NoPath,
            path: None,
            counters,
            marks: Vec::new(),
            series: Vec::new(),
        }
    }

    /// An exhausted budget, with the best path so far if any.
    pub fn budget_exhausted(path: Option<Path>, counters: Counters) -> Outcome {
        Outcome {
            status: Status::BudgetExhausted,
            path,
            counters,
            marks: Vec::new(),
            series: Vec::new(),
        }
    }
}

/// A start-goal path planner.
///
/// Implementations are built from their own validated config (each planner crate owns a
/// `#[serde(deny_unknown_fields)]` config struct), may keep scratch buffers that they
/// reuse across calls (hence `&mut self`), do no I/O, and return counters that are a pure
/// function of (grid, problem, config, seed) whenever the budget has no wall-clock limit.
///
/// A planner is built once and may serve many queries, on one grid or several: the
/// runner calls [`Planner::prepare`] for a grid before timing queries on it (so per-grid
/// tables are setup, not planning time) and, for a seeded planner, [`Planner::reseed`]
/// before each query.
pub trait Planner: Send + Sync {
    /// The planner's registry name, e.g. `astar`.
    fn name(&self) -> &str;

    /// What the planner is: seeded or not, and the rule its paths obey.
    fn specs(&self) -> PlannerSpecs;

    /// Sets the seed of the next [`Planner::plan`] call. Seeded planners must override
    /// it; the default, for unseeded ones, does nothing.
    fn reseed(&mut self, _seed: u64) {}

    /// Builds whatever per-grid tables the planner keeps (move masks, node arrays), so a
    /// following [`Planner::plan`] on `grid` does not. Optional: `plan` must work without
    /// it. The default does nothing.
    fn prepare(&mut self, _grid: &Grid) {}

    /// Searches `problem` within `budget`. Never panics on a valid problem.
    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn problem_validation_names_the_cell() {
        let grid = Grid::from_ascii("..\n.#").unwrap();
        let err = Problem::new(&grid, Cell::new(0, 0), Cell::new(1, 1)).unwrap_err();
        assert_eq!(err.to_string(), "goal (1, 1) is blocked");
        let err = Problem::new(&grid, Cell::new(2, 0), Cell::new(0, 1)).unwrap_err();
        assert_eq!(err.to_string(), "start (2, 0) is outside the 2x2 grid");
        assert!(Problem::new(&grid, Cell::new(0, 0), Cell::new(0, 0)).is_ok());
    }

    #[test]
    fn budget_clock() {
        let mut clock = Budget::expansions(3).start();
        assert!(clock.allows(0) && clock.allows(2));
        assert!(!clock.allows(3));
        assert!(clock.is_exhausted());
        assert!(!clock.allows(0));
        let mut unlimited = Budget::unlimited().start();
        assert!(unlimited.allows(u64::MAX - 1));
        let mut timed = Budget::unlimited().with_time(Duration::ZERO).start();
        let allowed = (0..2 * BudgetClock::TIME_CHECK_INTERVAL as u64)
            .take_while(|&n| timed.allows(n))
            .count();
        assert_eq!(allowed, BudgetClock::TIME_CHECK_INTERVAL as usize - 1);
    }

    #[test]
    fn budget_toml_shape() {
        let budget: Budget =
            serde_json::from_str(r#"{"max_expansions": 5, "max_time_ms": 20}"#).unwrap();
        assert_eq!(
            budget,
            Budget::expansions(5).with_time(Duration::from_millis(20))
        );
        assert!(serde_json::from_str::<Budget>(r#"{"max_steps": 5}"#).is_err());
    }
}
