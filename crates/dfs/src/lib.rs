//! Depth-first search on the grid, as seed 003 defines it: a LIFO stack, a cell marked
//! visited when it is pushed, parent links; returns a valid path, not necessarily the
//! shortest.
//!
//! # Definition
//! Seed 003 (`003_9eb9a51f185ccb81.txt`), section II.C.2: push the start (marked
//! visited); pop the top cell; if it is the goal, follow the parent links back to the
//! start; otherwise push all its valid, unvisited neighbours, marking them visited (a
//! cell's parent is the cell that pushed it, never changed later); repeat until the stack
//! is empty. The goal is tested when a cell is **popped**, as in `planner-bfs`, so the two
//! count alike.
//!
//! Neighbours are checked and pushed in the configured order, so the **last** one pushed
//! is expanded first: with the default `R L D U` the search goes up first. Seed 003 lists
//! its moves as "left, right, up, and down"; with `order = "L R U D"` this planner
//! reproduces every DFS length of the report: 38, 26 and 20 on `maps/wpi/map1.txt` pairs
//! 1-3 (Table I) and 196 and 73 on `maps/wpi/map3.txt` pairs 1 and 3 (Table II's "Map 1"
//! and "Map 2"; the latter is pair 3, as `planner-bfs` also finds).
//!
//! # Counters ([`Counter::FRONTIER`](planner_api::Counter::FRONTIER), then `n_open_insertions`)
//! - `n_expanded`: cells popped, the goal included (its neighbours are not checked);
//! - `n_neighbor_checks`: moves checked, all `k` of them for every popped non-goal cell
//!   (`k` = 4, or 8 with diagonals), in the configured order;
//! - `n_blocked`: checks whose target is out of bounds or blocked, or, for a diagonal
//!   without corner cutting, passes a blocked cell ([`MoveSet::apply`](planner_api::MoveSet::apply) fails);
//! - `n_skipped`: checks whose target is already marked visited: pushed before, whether
//!   still on the stack or already popped (the cell's parent is one of them);
//! - `peak_open`: the most cells on the stack at once, the start's 1 included, measured
//!   after each cell's neighbours are pushed: the memory indicator;
//! - `n_open_insertions`: cells ever pushed, the start included.
//!
//! The identities are those of `planner-bfs`: every run obeys
//! `n_neighbor_checks = n_blocked + n_skipped + (n_open_insertions - 1)` and
//! `n_neighbor_checks = k * (n_expanded - f)`, with `f` = 1 if the goal was found, else 0
//! (a run stopped by the budget stops before a pop); on an empty stack
//! `n_open_insertions = n_expanded` as well, and when the budget stops the search,
//! `n_open_insertions > n_expanded`.
//!
//! Every counter and path equals that of `planner_testkit::reference_frontier` (seed
//! 003's definition written again with a `VecDeque` as the stack) on 2,000 random grids
//! and seed 003's maps (`tests/`), and on every run of the configs (xtask's
//! `every_bfs_and_dfs_run_matches_the_reference_search`).
//!
//! # Budget
//! One expansion is one pop; the budget is asked before each. When it refuses, the search
//! ends with [`Status::BudgetExhausted`](planner_api::Status::BudgetExhausted), no path, and the counters so far.
//!
//! # Design
//! The search is `planner-bfs`'s [`FrontierSearch`] with a
//! stack: the two planners differ only in which end of the frontier they expand, and they
//! share their parameters ([`Config`]). Per-cell masks of the safe moves, built once per grid from [`MoveSet`] (cached while
//! the grid is the same), so the loop does no bounds or obstacle test; visited marks are
//! generation stamps, so a new search clears nothing; the stack is a flat array of at most
//! one entry per cell. Nothing is allocated per expansion.
//!
//! # Example
//! ```
//! use planner_api::{Budget, Cell, Grid, Planner, Problem, Status};
//! use planner_dfs::{Config, Dfs};
//!
//! let grid = Grid::from_ascii("
//!     ...
//!     .#.
//!     ...
//! ").unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(2, 2)).unwrap();
//! let mut dfs = Dfs::new(Config::default()).unwrap();
//! let outcome = dfs.plan(&problem, &Budget::unlimited());
//! assert_eq!(outcome.status, Status::Found);
//! // (0,0) pushes (1,0) then (0,1); (0,1), pushed last, is popped first: down the left side.
//! let cells = outcome.path.unwrap().into_cells();
//! assert_eq!(cells[1], Cell::new(0, 1));
//! assert_eq!(cells.len(), 5);
//! // Popped: (0,0) (0,1) (0,2) (1,2) (2,2).
//! assert_eq!(outcome.counters.get("n_expanded"), Some(5));
//! assert_eq!(outcome.counters.get("n_neighbor_checks"), Some(16));
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

use planner_api::{Budget, MoveSet, Outcome, Planner, Problem};
pub use planner_bfs::{Config, ConfigError};
use planner_bfs::{Discipline, FrontierSearch};

/// Depth-first search (registry name `dfs`): `planner-bfs`'s frontier search with a stack.
#[derive(Debug, Clone)]
pub struct Dfs {
    config: Config,
    search: FrontierSearch,
}

impl Dfs {
    /// A planner with a validated `config` (the same parameters as BFS).
    ///
    /// Errors when `order` does not list the moves of `moves` correctly, or when
    /// `corner_cutting` is set for a neighbourhood other than 8.
    pub fn new(config: Config) -> Result<Dfs, ConfigError> {
        let search = FrontierSearch::new(planner_bfs::move_set(&config)?, Discipline::Lifo);
        Ok(Dfs { config, search })
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The moves, in the order they are checked and pushed.
    pub fn moves(&self) -> &MoveSet {
        self.search.moves()
    }
}

impl Planner for Dfs {
    fn name(&self) -> &str {
        "dfs"
    }

    fn specs(&self) -> planner_api::PlannerSpecs {
        planner_api::PlannerSpecs::deterministic(planner_api::PathSpec::Moves(
            self.search.move_set().clone(),
        ))
    }

    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        self.search.search(problem, budget)
    }
}
