//! The shared vocabulary of gridplan: grids, problems, moves, paths, counters and the
//! [`Planner`] trait.
//!
//! # Design
//! Every planner crate depends on this one and on nothing else of gridplan's, and this
//! crate depends on no planner. Planners are plain values built from a validated config;
//! [`Planner::plan`] takes `&mut self` so that a planner can keep its per-cell arrays
//! between calls and allocate nothing per expansion, and it returns an [`Outcome`] whose
//! [`Status`] says how the search ended: found, no path, or budget exhausted (with the best
//! path so far). Invalid input is caught earlier, when a [`Problem`] is built, as a typed
//! [`ProblemError`] naming the cell.
//!
//! Counters are counted as plain integers in [`SearchStats`] and reported as an ordered
//! [`Counters`] list, so a planner reports only what applies to it and may add counters of
//! its own; see [`counters`] for the names and their exact meaning (seed 000 Table 2).
//!
//! ```
//! use planner_api::{Cell, Grid, Path, Problem};
//! let grid = Grid::from_ascii("
//!     ...
//!     #..
//! ").unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(2, 1)).unwrap();
//! let path = Path::new(vec![Cell::new(0, 0), Cell::new(1, 0), Cell::new(1, 1), Cell::new(2, 1)]);
//! let m = path.metrics();
//! assert_eq!((m.steps, m.turns, m.score), (3, 2, 5));
//! assert_eq!(problem.goal(), Cell::new(2, 1));
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod adjacency;
pub mod blocked;
pub mod cost;
pub mod counters;
pub mod coverage;
pub mod error;
pub mod grid;
pub mod incremental;
pub mod moves;
pub mod pages;
pub mod path;
pub mod planner;
pub mod specs;
pub mod weights;

#[cfg(test)]
mod test_rng;

pub use adjacency::Adjacency;
pub use blocked::{BlockedBits, BlockedCounts};
pub use cost::Cost;
pub use counters::{Counter, Counters, SearchStats};
pub use coverage::{
    reachable_cells, CoverageMetrics, CoverageOutcome, CoveragePlanner, CoverageProblem, ReturnLeg,
};
pub use error::{Endpoint, GridError, MoveOrderError, PathError, ProblemError};
pub use grid::{cell_hypot, packed_words, Cell, Grid};
pub use incremental::{path_cost, CellChange, ChangeError, IncrementalPlanner};
pub use moves::{
    for_each_segment_cell, segment_is_free, walk_segment, Connectivity, Direction, IndexedMove,
    IndexedMoves, Move, MoveSet, NeighborOrder, SegmentWalk,
};
pub use path::{push_octile_leg, Path, PathMetrics, PathRank, PathRule};
pub use planner::{
    Budget, BudgetClock, CancelFlag, CancelPool, LentFlag, Mark, MemoryShortfall, Outcome, Planner,
    Problem, SearchEvent, SearchEventKind, Series, Status, MAX_SEARCH_EVENTS,
};
pub use specs::{CostsCondition, ParamError, ParamKey, PathSpec, PlannerSpecs, SEED_PARAM};
pub use weights::{weighted_move_cost, CostRule, Weights};
