//! The results model: one [`RunRecord`] per run, with a typed [`RunStatus`].

use planner_api::{Cell, Counters, Mark, Path, ReturnLeg, Series, Status};
use serde::{Deserialize, Serialize};

/// How a run ended: the planner's [`Status`], or the problem could not be planned.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    /// A path was found.
    Found,
    /// The search proved there is no path.
    NoPath,
    /// The budget ran out first.
    BudgetExhausted,
    /// The start or goal is blocked or outside the grid; the planner was not run.
    InvalidProblem,
}

impl RunStatus {
    /// Every status, in a fixed order (the OMPL logs' `status` enum numbers them so).
    pub const ALL: [RunStatus; 4] = [
        RunStatus::Found,
        RunStatus::NoPath,
        RunStatus::BudgetExhausted,
        RunStatus::InvalidProblem,
    ];

    /// The snake-case name used in results.
    pub fn as_str(self) -> &'static str {
        match self {
            RunStatus::Found => "found",
            RunStatus::NoPath => "no_path",
            RunStatus::BudgetExhausted => "budget_exhausted",
            RunStatus::InvalidProblem => "invalid_problem",
        }
    }
}

impl From<Status> for RunStatus {
    fn from(status: Status) -> RunStatus {
        match status {
            Status::Found => RunStatus::Found,
            Status::NoPath => RunStatus::NoPath,
            Status::BudgetExhausted => RunStatus::BudgetExhausted,
        }
    }
}

impl std::fmt::Display for RunStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

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
    /// The seed a seeded planner ran with.
    pub seed: Option<u64>,
    /// How the run ended.
    pub status: RunStatus,
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
    /// The scenario file's bucket, for problems from a `.scen` file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bucket: Option<u32>,
    /// Whether the path starts and ends at the problem's cells and obeys the rule the
    /// planner declares in its specs (its moves, or any-angle segments).
    pub valid: Option<bool>,
    /// `false` when the planner declares its heuristic inadmissible for its moves (not
    /// optimal by design, such as seed 002's TA-star); absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub admissible: Option<bool>,
    /// The planner's counters, in its order.
    pub counters: Counters,
    /// Wall time of the search alone (`plan` or `cover`), in milliseconds (timing: not
    /// deterministic). Zero for an invalid problem, which was not run: the result tables
    /// leave its time, setup time and peak heap empty (`null`), not measured.
    pub time_ms: f64,
    /// Wall time of the run's setup, in milliseconds: building the planner (when the
    /// worker has none for this label yet) and its per-grid tables (when the grid
    /// changed). Zero when a worker's planner was reused on the same grid.
    pub setup_ms: f64,
    /// Peak heap bytes of the run: what the planner held as its search started (its setup
    /// for this grid and the buffers it kept from the worker's earlier runs) plus the peak
    /// its search added (memory: not deterministic, it depends on the earlier runs).
    pub peak_heap_bytes: u64,
    /// The path's cells.
    pub path: Option<Path>,
    /// Coverage planners only: the stretches of `path` that return to a backtracking point.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub returns: Option<Vec<ReturnLeg>>,
    /// The cells the planner marked in its outcome (PA-star's handover points), if any.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub marks: Vec<Mark>,
    /// The sequences the planner recorded (a swarm's convergence curve), if any.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub series: Vec<Series>,
    /// On a map with cell weights: the path's cost under the map's weights and move cost
    /// rule (`planner_api::weights`), beside its `length`; absent on unweighted maps. A
    /// planner run with `costs = "ignore"` plans on the unweighted map, and this is still
    /// its path's weighted cost.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cost: Option<f64>,
}

impl RunRecord {
    /// Whether the run found a path.
    pub fn is_found(&self) -> bool {
        self.status == RunStatus::Found
    }

    /// Whether the problem was invalid (the planner did not run).
    pub fn is_invalid(&self) -> bool {
        self.status == RunStatus::InvalidProblem
    }
}

/// Counts of compared published numbers (a report's comparison with the seeds' values).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Reproduction {
    /// Numbers compared.
    pub compared: usize,
    /// Numbers equal to the published value.
    pub matched: usize,
}
