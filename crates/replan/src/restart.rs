//! A* from scratch behind the incremental interface: the baseline every incremental
//! planner is compared with.
//!
//! [`Restart`] keeps its own copy of the map, applies changes to it, and answers each
//! replan with a new planner-astar search (exact costs, the consistent heuristic of the
//! moves, the paper's FIFO ties), from the agent to the goal (forward) or from the goal to
//! the agent (backward, the direction D* Lite searches in), the path then reversed. On a
//! weighted map the backward search is exact under the symmetric mean rule only: under the
//! entered cell's rule ([`planner_api::CostRule::Entered`]) a reversed path charges the
//! cells it leaves, so its cost is not the forward path's (the oracle records such a
//! replan as a mismatch). A* builds a bit-packed copy of a changed map before it searches
//! ([`Planner::prepare`]); that happens in [`IncrementalPlanner::apply`], so drivers time
//! it as update time, apart from the replan (see [`crate::ReplanRecord`]), and only within
//! the memory limit of the budget given to [`IncrementalPlanner::reset_within`] (over it,
//! nothing is built and the replan's own memory check refuses).

use planner_api::{
    Budget, Cell, CellChange, ChangeError, Grid, IncrementalPlanner, Outcome, Path, PathSpec,
    Planner, PlannerSpecs, Problem,
};
use planner_astar::AStar;

/// A* from scratch at every replan (see the [module docs](self)).
#[derive(Debug, Clone)]
pub struct Restart {
    astar: AStar,
    backward: bool,
    grid: Option<Grid>,
    start: Cell,
    goal: Cell,
    /// The memory limit of the session's budget, for what `reset` and `apply` build.
    memory: Budget,
}

impl Restart {
    /// Forward (`backward = false`) or backward A* with 8 moves without corner cutting
    /// (`eight`) or 4 moves.
    pub fn new(eight: bool, backward: bool) -> Restart {
        let astar = crate::oracle::exact_astar(eight);
        Restart {
            astar,
            backward,
            grid: None,
            start: Cell::new(0, 0),
            goal: Cell::new(0, 0),
            memory: Budget::unlimited(),
        }
    }

    /// The bytes of A*'s per-grid tables now held ([`AStar::table_bytes`]).
    pub fn table_bytes(&self) -> usize {
        self.astar.table_bytes()
    }
}

impl IncrementalPlanner for Restart {
    fn name(&self) -> &str {
        if self.backward {
            "astar_backward"
        } else {
            "astar"
        }
    }

    /// Not incremental: every replan is a search from scratch.
    fn specs(&self) -> PlannerSpecs {
        PlannerSpecs::deterministic(PathSpec::Moves(self.astar.move_set().clone()))
            .with_admissible(true)
    }

    fn reset(&mut self, problem: &Problem<'_>) {
        self.reset_within(problem, &Budget::unlimited());
    }

    fn reset_within(&mut self, problem: &Problem<'_>, budget: &Budget) {
        self.memory = Budget {
            max_memory_mb: budget.max_memory_mb,
            ..Budget::unlimited()
        };
        self.grid = Some(problem.grid().clone());
        self.start = problem.start();
        self.goal = problem.goal();
        self.astar.prepare_within(problem.grid(), &self.memory);
    }

    fn grid(&self) -> Option<&Grid> {
        self.grid.as_ref()
    }

    fn start(&self) -> Option<Cell> {
        self.grid.as_ref().map(|_| self.start)
    }

    fn move_start(&mut self, cell: Cell) -> Result<(), ChangeError> {
        planner_lpastar::checked_start(self.grid.as_ref(), cell)?;
        self.start = cell;
        Ok(())
    }

    /// Applies the changes to the map in place and brings A*'s bit-packed map up to date
    /// when a cell changed (its changed cells' bits, `Grid::changed_since`).
    fn apply(&mut self, changes: &[CellChange]) -> Result<(), ChangeError> {
        let changes = planner_lpastar::checked_changes(self.grid.as_ref(), changes)?;
        let Some(grid) = self.grid.as_mut() else {
            return Err(ChangeError::NotStarted);
        };
        let mut changed = false;
        for change in changes {
            if let Some(weight) = change.weight {
                if grid.weight(change.cell) != weight {
                    changed |= grid.set_weight(change.cell, weight);
                }
            }
            if grid.is_free(change.cell) != change.free {
                grid.set_free(change.cell, change.free);
                changed = true;
            }
        }
        if changed {
            self.astar.prepare_within(grid, &self.memory);
        }
        Ok(())
    }

    fn replan(&mut self, budget: &Budget) -> Outcome {
        let Some(grid) = self.grid.as_ref() else {
            return Outcome::no_path(planner_api::Counters::new());
        };
        let (from, to) = if self.backward {
            (self.goal, self.start)
        } else {
            (self.start, self.goal)
        };
        let Ok(problem) = Problem::new(grid, from, to) else {
            // A blocked start or goal: no path, and nothing searched.
            return Outcome::no_path(planner_api::Counters::new().with("n_expanded", 0));
        };
        let mut outcome = self.astar.plan(&problem, budget);
        if self.backward {
            outcome.path = outcome.path.map(|p| {
                let mut cells = p.into_cells();
                cells.reverse();
                Path::new(cells)
            });
        }
        outcome
    }
}
