//! D* Lite on 4- and 8-connected grids, with exact costs.
//!
//! Koenig and Likhachev, "D* Lite", AAAI 2002, <https://cdn.aaai.org/AAAI/2002/AAAI02-072.pdf>:
//! the optimized version (its Fig. 4). D* Lite is LPA* searching backwards, from the goal
//! to the agent, so that when the agent moves the g-values (distances to the goal) stay
//! valid: only the start moves, and instead of re-keying the whole queue the key modifier
//! grows, `km += h(s_last, s_start)`, and keys popped out of date are re-inserted. The
//! search is planner-lpastar's [`engine`](planner_lpastar::engine) with the goal as its
//! root and the agent as its target; the engine's docs give the rules, the queue's total
//! order (key, then row-major index), the path trace (from the agent, each step to the
//! neighbour minimising `c + g`, ties in move order) and the counters.
//!
//! Per the paper's main loop, a driver calls
//! [`move_start`](planner_api::IncrementalPlanner::move_start) with the agent's cell when
//! it has moved, then [`apply`](planner_api::IncrementalPlanner::apply) with the cells it
//! saw change, then [`replan`](planner_api::IncrementalPlanner::replan). Moves and costs
//! are LPA*'s: 4 moves, or 8 without corner cutting, in exact [`planner_api::Cost`] units,
//! on weighted maps too, whose weights may change as the robot drives (a costmap; see
//! planner-lpastar's docs). Under the entered cell's rule the cost of a move depends on
//! its direction; D* Lite's search runs from the goal, and charges each edge the way the
//! agent will drive it, toward the goal.
//!
//! ```
//! use planner_api::{Budget, Cell, CellChange, Grid, IncrementalPlanner, Problem, Status};
//! use planner_dstar_lite::{Config, DStarLite};
//!
//! let grid = Grid::from_ascii("
//!     .....
//!     .....
//!     .....
//! ").unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 1), Cell::new(4, 1)).unwrap();
//! let mut dstar = DStarLite::new(Config { moves: 8 }).unwrap();
//! dstar.reset(&problem);
//! assert_eq!(dstar.replan(&Budget::unlimited()).path.unwrap().len(), 5);
//! // The agent drives one cell and sees a wall ahead.
//! dstar.move_start(Cell::new(1, 1)).unwrap();
//! dstar.apply(&[CellChange::blocked(Cell::new(2, 1)), CellChange::blocked(Cell::new(2, 0))]).unwrap();
//! let repaired = dstar.replan(&Budget::unlimited());
//! assert_eq!(repaired.status, Status::Found);
//! let path = repaired.path.unwrap();
//! assert_eq!(path.cells()[0], Cell::new(1, 1));
//! // Down-right would cut the corner of (2, 1): down, right, right, up-right.
//! assert_eq!(path.len(), 5);
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub use planner_lpastar::{Config, ConfigError, Incremental, Rooting};

/// The registry name of this planner.
pub const NAME: &str = "dstar_lite";

/// D* Lite's rooting: the search grows from the goal to the agent, so a moved agent keeps
/// it (`km += h(s_last, s_start)`); the path is traced from the agent.
#[derive(Debug, Clone, Copy, Default)]
pub struct AtGoal;

impl Rooting for AtGoal {
    const NAME: &'static str = NAME;
    const AT_GOAL: bool = true;
}

/// The D* Lite planner: planner-lpastar's [`Incremental`] search rooted at the goal. Build
/// with [`DStarLite::new`].
pub type DStarLite = Incremental<AtGoal>;
