//! Planners for maps that change: the [`IncrementalPlanner`] interface beside
//! [`Planner`](crate::Planner).
//!
//! A one-shot [`Planner`](crate::Planner) solves a fixed map from scratch. An incremental
//! planner (LPA*, D* Lite) keeps its search between calls: it owns a copy of the map it
//! plans on, is told which cells changed ([`CellChange`]: blocked or freed, and on a
//! weighted map a new weight) and where the agent now stands, and
//! [`IncrementalPlanner::replan`] repairs the previous search instead of starting over.
//! Each `replan` reports the counters of that repair alone, so a driver can sum them or
//! look at their distribution.
//!
//! The order of calls in a session: [`IncrementalPlanner::reset`] with a problem (its
//! grid is copied), then any sequence of [`IncrementalPlanner::move_start`],
//! [`IncrementalPlanner::apply`] and [`IncrementalPlanner::replan`]. A driver that both
//! moves the agent and reports changes calls `move_start` before `apply` (D* Lite's key
//! modifier must be updated before the changed vertices are keyed).
//!
//! Incremental planners declare themselves through [`PlannerSpecs::incremental`], so a
//! runner knows it can feed them changes.
//!
//! ```
//! use planner_api::incremental::{path_cost, CellChange};
//! use planner_api::{Cell, Cost, Path};
//! let change = CellChange::blocked(Cell::new(3, 4));
//! assert!(!change.free);
//! let path = Path::new(vec![Cell::new(0, 0), Cell::new(1, 1), Cell::new(2, 1)]);
//! assert_eq!(path_cost(&path), Cost::SQRT_2 + Cost::ONE);
//! ```

use thiserror::Error;

use crate::cost::Cost;
use crate::grid::{Cell, Grid};
use crate::path::Path;
use crate::planner::{Budget, Outcome, Problem};
use crate::specs::PlannerSpecs;

/// One cell's new state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CellChange {
    /// The cell.
    pub cell: Cell,
    /// Whether it is now free (`false`: now blocked).
    pub free: bool,
    /// Its new weight ([`crate::weights`]), or `None` to keep it. Only a weighted map takes
    /// one, and never 0.
    pub weight: Option<u16>,
}

impl CellChange {
    /// `cell` became blocked.
    pub const fn blocked(cell: Cell) -> CellChange {
        CellChange {
            cell,
            free: false,
            weight: None,
        }
    }

    /// `cell` became free.
    pub const fn freed(cell: Cell) -> CellChange {
        CellChange {
            cell,
            free: true,
            weight: None,
        }
    }

    /// This change with the cell's new weight: a costmap's update, where a cell's cost
    /// changes and it stays free (or is blocked or freed at the same time).
    ///
    /// ```
    /// use planner_api::{Cell, CellChange};
    /// let change = CellChange::freed(Cell::new(2, 3)).with_weight(40);
    /// assert_eq!((change.free, change.weight), (true, Some(40)));
    /// ```
    pub const fn with_weight(self, weight: u16) -> CellChange {
        CellChange {
            weight: Some(weight),
            ..self
        }
    }
}

/// A change or a start an incremental planner cannot take.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ChangeError {
    /// [`IncrementalPlanner::apply`] or [`IncrementalPlanner::move_start`] before
    /// [`IncrementalPlanner::reset`].
    #[error("the planner has no map yet: call reset first")]
    NotStarted,
    /// A changed cell outside the map.
    #[error("changed cell {cell} is outside the {width}x{height} map")]
    OutOfBounds {
        /// The cell.
        cell: Cell,
        /// Map width.
        width: u32,
        /// Map height.
        height: u32,
    },
    /// A new start outside the map or on a blocked cell.
    #[error("new start {cell} is outside the map or blocked")]
    BadStart {
        /// The cell.
        cell: Cell,
    },
    /// A new weight of 0 (weights are at least 1).
    #[error("changed cell {cell} gets weight 0; weights are at least 1")]
    ZeroWeight {
        /// The cell.
        cell: Cell,
    },
    /// A new weight on a map without weights.
    #[error("changed cell {cell} gets a weight, but the map has no weights")]
    Unweighted {
        /// The cell.
        cell: Cell,
    },
}

/// A planner that repairs its search when the map changes (see the [module docs](self)).
///
/// Like [`Planner`](crate::Planner) it does no I/O, never panics on valid input, honours
/// the [`Budget`] of each `replan` (expansion and time limits; the memory limit when it
/// sizes its per-cell state), and its counters are a pure function of the call sequence
/// when the budget has no wall-clock limit.
pub trait IncrementalPlanner: Send + Sync {
    /// The planner's registry name, e.g. `dstar_lite`.
    fn name(&self) -> &str;

    /// What the planner is; [`PlannerSpecs::incremental`] is set.
    fn specs(&self) -> PlannerSpecs;

    /// Begins a session on a copy of `problem`'s grid, start and goal, forgetting any
    /// previous search. Searches nothing.
    fn reset(&mut self, problem: &Problem<'_>);

    /// [`IncrementalPlanner::reset`] for a session whose replans get `budget`: a planner
    /// that builds per-grid tables when it is reset or a change is applied (before any
    /// replan's own memory check) builds them only within `budget`'s memory limit. The
    /// default, for planners that size their state in `replan`, is `reset`. Drivers that
    /// hold a budget reset through this.
    fn reset_within(&mut self, problem: &Problem<'_>, budget: &Budget) {
        let _ = budget;
        self.reset(problem);
    }

    /// The planner's current map (the reset grid with every applied change).
    fn grid(&self) -> Option<&Grid>;

    /// The current start (the agent's cell).
    fn start(&self) -> Option<Cell>;

    /// Moves the start to `cell` (the agent drove there). D* Lite keeps its search (the
    /// key modifier grows); a planner whose search is rooted at the start restarts.
    fn move_start(&mut self, cell: Cell) -> Result<(), ChangeError>;

    /// Applies `changes` to the planner's map and marks the vertices whose edges changed;
    /// the search is repaired by the next [`IncrementalPlanner::replan`]. A change that
    /// does not change the cell is ignored. The start and goal may be blocked by a change;
    /// the next replan then reports no path.
    fn apply(&mut self, changes: &[CellChange]) -> Result<(), ChangeError>;

    /// Repairs (or, the first time, computes) the shortest path from the current start to
    /// the goal on the current map. The counters are those of this call alone.
    fn replan(&mut self, budget: &Budget) -> Outcome;
}

/// The exact cost of `path`: the sum of [`Cost::of_move`] over its steps (what the exact
/// planners' `g` adds up, in the same units).
pub fn path_cost(path: &Path) -> Cost {
    path.cells()
        .windows(2)
        .map(|w| {
            let dx = i64::from(w[1].x) - i64::from(w[0].x);
            let dy = i64::from(w[1].y) - i64::from(w[0].y);
            Cost::of_move(dx as i32, dy as i32)
        })
        .fold(Cost::ZERO, Cost::saturating_add)
}
