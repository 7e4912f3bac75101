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
//! # Counters ([`Counter::FRONTIER`], then `n_open_insertions`)
//! - `n_expanded`: cells popped, the goal included (its neighbours are not checked);
//! - `n_neighbor_checks`: moves checked, all `k` of them for every popped non-goal cell
//!   (`k` = 4, or 8 with diagonals), in the configured order;
//! - `n_blocked`: checks whose target is out of bounds or blocked, or, for a diagonal
//!   without corner cutting, passes a blocked cell ([`MoveSet::apply`] fails);
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
//! # Budget
//! One expansion is one pop; the budget is asked before each. When it refuses, the search
//! ends with [`Status::BudgetExhausted`](planner_api::Status::BudgetExhausted), no path, and the counters so far.
//!
//! # Design
//! Per-cell masks of the safe moves, built once per grid from [`MoveSet`] (cached while
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

use planner_api::{
    Budget, Cell, Connectivity, Counter, MoveOrderError, MoveSet, NeighborOrder, Outcome, Path,
    Planner, Problem, SearchStats,
};
use serde::{Deserialize, Serialize};
use thiserror::Error;

use planner_api::Adjacency;

/// The planner's configuration (TOML/JSON keys as the field names).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// Neighbourhood, written as its number of directions (`moves = 4` or `8`, also 16, 32, 48).
    /// Default 4, seed 003's.
    pub moves: Connectivity,
    /// Whether 8-connected diagonals may cut corners (only with `moves = 8`). Default false.
    pub corner_cutting: bool,
    /// Order in which the neighbours are checked and pushed, e.g. `"R L D U"` (see
    /// [`NeighborOrder`]); the last pushed is expanded first. Default `R L D U`, seed 000's
    /// order; `"L R U D"` is seed 003's and reproduces its DFS lengths.
    pub order: NeighborOrder,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            moves: Connectivity::Four,
            corner_cutting: false,
            order: NeighborOrder::default(),
        }
    }
}

/// A configuration that cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ConfigError {
    /// `order` does not fit `moves`.
    #[error("invalid order: {0}")]
    Order(MoveOrderError),
    /// `corner_cutting` was asked for a neighbourhood other than 8.
    #[error("invalid corner_cutting: {0}")]
    CornerCutting(MoveOrderError),
}

/// Depth-first search (registry name `dfs`).
///
/// Keeps its per-cell buffers between calls to [`Planner::plan`]; the safe-move masks are
/// rebuilt only when the grid changes.
#[derive(Debug, Clone)]
pub struct Dfs {
    config: Config,
    moves: MoveSet,
    adjacency: Option<Adjacency>,
    /// `mark[p] == stamp` when padded cell `p` is visited in the current search.
    mark: Vec<u32>,
    stamp: u32,
    /// Parent of each visited cell (padded index); the start's is itself.
    parent: Vec<u32>,
    /// The stack (padded indices).
    stack: Vec<u32>,
}

impl Dfs {
    /// A planner with a validated `config`.
    ///
    /// Errors when `order` does not list the moves of `moves` correctly, or when
    /// `corner_cutting` is set for a neighbourhood other than 8.
    pub fn new(config: Config) -> Result<Dfs, ConfigError> {
        let moves = MoveSet::new(config.moves, config.corner_cutting, &config.order).map_err(
            |e| match e {
                MoveOrderError::CornerCutting(_) => ConfigError::CornerCutting(e),
                other => ConfigError::Order(other),
            },
        )?;
        Ok(Dfs {
            config,
            moves,
            adjacency: None,
            mark: Vec::new(),
            stamp: 0,
            parent: Vec::new(),
            stack: Vec::new(),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The moves, in the order they are checked and pushed.
    pub fn moves(&self) -> &MoveSet {
        &self.moves
    }
}

impl Planner for Dfs {
    fn name(&self) -> &str {
        "dfs"
    }

    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        let grid = problem.grid();
        let adjacency = Adjacency::cached(&mut self.adjacency, grid, &self.moves);
        let len = adjacency.padded_len();
        if self.mark.len() != len {
            self.mark.clear();
            self.mark.resize(len, 0);
            self.parent.resize(len, 0);
            self.stamp = 0;
        }
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.mark.fill(0);
            self.stamp = 1;
        }
        let stamp = self.stamp;
        let k = adjacency.n_moves() as u64;
        let start = adjacency.index(problem.start());
        let goal = adjacency.index(problem.goal());
        let mut clock = budget.start();
        let mut stats = SearchStats::default();

        self.stack.clear();
        self.stack.reserve(grid.len());
        self.stack.push(start as u32);
        self.mark[start] = stamp;
        self.parent[start] = start as u32;
        stats.peak_open = 1;
        let mut n_insertions = 1u64;
        let mut found = false;
        let mut exhausted = false;
        while let Some(&top) = self.stack.last() {
            if !clock.allows(stats.n_expanded) {
                exhausted = true;
                break;
            }
            self.stack.pop();
            let p = top as usize;
            stats.n_expanded += 1;
            if p == goal {
                found = true;
                break;
            }
            let mut safe = adjacency.mask(p);
            stats.n_neighbor_checks += k;
            stats.n_blocked += k - u64::from(safe.count_ones());
            while safe != 0 {
                let m = safe.trailing_zeros();
                safe &= safe - 1;
                let q = adjacency.neighbor(p, m);
                if self.mark[q] == stamp {
                    stats.n_skipped += 1;
                } else {
                    self.mark[q] = stamp;
                    self.parent[q] = p as u32;
                    self.stack.push(q as u32);
                    n_insertions += 1;
                }
            }
            stats.peak_open = stats.peak_open.max(self.stack.len() as u64);
        }
        let counters = stats
            .report(Counter::FRONTIER)
            .with(Counter::OpenInsertions.name(), n_insertions);
        if found {
            let mut cells: Vec<Cell> = Vec::new();
            let mut p = goal;
            loop {
                cells.push(adjacency.cell(p));
                if p == start {
                    break;
                }
                p = self.parent[p] as usize;
            }
            cells.reverse();
            Outcome::found(Path::new(cells), counters)
        } else if exhausted {
            Outcome::budget_exhausted(None, counters)
        } else {
            Outcome::no_path(counters)
        }
    }
}
