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
//! Per the paper's main loop, a driver calls [`IncrementalPlanner::move_start`] with the
//! agent's cell when it has moved, then [`IncrementalPlanner::apply`] with the cells it
//! saw change, then [`IncrementalPlanner::replan`]. Moves and costs are LPA*'s: 4 moves,
//! or 8 without corner cutting, in exact [`planner_api::Cost`] units.
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

use planner_api::{
    Budget, Cell, CellChange, ChangeError, Grid, IncrementalPlanner, Outcome, PathSpec, Planner,
    PlannerSpecs, Problem,
};
use planner_lpastar::engine::Engine;
use planner_lpastar::{checked_changes, checked_start, outcome};
pub use planner_lpastar::{Config, ConfigError};

/// The registry name of this planner.
pub const NAME: &str = "dstar_lite";

/// The D* Lite planner. Build with [`DStarLite::new`].
#[derive(Debug, Clone)]
pub struct DStarLite {
    config: Config,
    engine: Engine,
}

impl DStarLite {
    /// A planner with `config`, validated.
    pub fn new(config: Config) -> Result<DStarLite, ConfigError> {
        let eight = config.eight()?;
        Ok(DStarLite {
            config,
            engine: Engine::new(eight),
        })
    }

    /// The engine, for inspection (g-values, km).
    pub fn engine(&self) -> &Engine {
        &self.engine
    }
}

impl IncrementalPlanner for DStarLite {
    fn name(&self) -> &str {
        NAME
    }

    fn specs(&self) -> PlannerSpecs {
        PlannerSpecs::deterministic(PathSpec::Moves(self.config.move_set()))
            .with_admissible(true)
            .with_incremental()
    }

    /// The search is rooted at the goal, towards the start.
    fn reset(&mut self, problem: &Problem<'_>) {
        self.engine
            .reset(problem.grid(), problem.goal(), problem.start());
    }

    fn grid(&self) -> Option<&Grid> {
        self.engine.grid()
    }

    fn start(&self) -> Option<Cell> {
        self.engine.target()
    }

    /// Keeps the search: `km` grows by the heuristic between the old and new start.
    fn move_start(&mut self, cell: Cell) -> Result<(), ChangeError> {
        checked_start(self.engine.grid(), cell)?;
        self.engine.move_target(cell);
        Ok(())
    }

    fn apply(&mut self, changes: &[CellChange]) -> Result<(), ChangeError> {
        let changes = checked_changes(self.engine.grid(), changes)?;
        self.engine.apply(&changes);
        Ok(())
    }

    fn replan(&mut self, budget: &Budget) -> Outcome {
        let computed = self.engine.compute(budget);
        outcome(&mut self.engine, computed, false)
    }
}

impl Planner for DStarLite {
    fn name(&self) -> &str {
        NAME
    }

    /// Unseeded and admissible; paths are moves of the configured set; incremental.
    fn specs(&self) -> PlannerSpecs {
        IncrementalPlanner::specs(self)
    }

    /// A first D* Lite search from scratch (backward A* with D* Lite's counters).
    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        IncrementalPlanner::reset(self, problem);
        IncrementalPlanner::replan(self, budget)
    }
}
