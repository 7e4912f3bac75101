//! Breadth-first search on the grid, as seed 003 defines it: a FIFO queue, a cell marked
//! visited when it is enqueued, parent links; returns a path with the fewest moves.
//!
//! # Definition
//! Seed 003 (`003_9eb9a51f185ccb81.txt`), section II.C.1: enqueue the start and mark it
//! visited; dequeue the front cell; if it is the goal, follow the parent links back to the
//! start; otherwise enqueue its valid, unvisited neighbours, marking them visited; repeat
//! until the queue is empty. The goal is tested when a cell is **dequeued**, as in the
//! seed (and as seed 000's A*); `planner-dfs` does the same, so the two count alike.
//! Every cell is enqueued at most once, so the path found has the fewest moves: the
//! shortest path in steps on the 4-connected grid (with 8 or more directions, the fewest
//! moves, not the shortest Euclidean length).
//!
//! # Counters ([`Counter::FRONTIER`], then `n_open_insertions`)
//! - `n_expanded`: cells dequeued, the goal included (its neighbours are not checked);
//! - `n_neighbor_checks`: moves checked, all `k` of them for every dequeued non-goal cell
//!   (`k` = 4, or 8 with diagonals), in the configured order;
//! - `n_blocked`: checks whose target is out of bounds or blocked, or, for a diagonal
//!   without corner cutting, passes a blocked cell ([`MoveSet::apply`] fails);
//! - `n_skipped`: checks whose target is already marked visited: enqueued before, whether
//!   still in the queue or already dequeued (the cell's parent is one of them);
//! - `peak_open`: the most cells waiting in the queue at once, the start's 1 included,
//!   measured after each cell's neighbours are enqueued: the memory indicator;
//! - `n_open_insertions`: cells ever enqueued, the start included.
//!
//! Every run obeys `n_neighbor_checks = n_blocked + n_skipped + (n_open_insertions - 1)`
//! and `n_neighbor_checks = k * (n_expanded - f)`, with `f` = 1 if the goal was found,
//! else 0 (a run stopped by the budget stops before a dequeue, so every dequeued cell was
//! checked in full); when the queue runs empty, `n_open_insertions = n_expanded` as well,
//! and when the budget stops the search, `n_open_insertions > n_expanded`.
//!
//! Every counter and path equals that of `planner_testkit::reference_frontier` (seed
//! 003's definition written again with a `VecDeque` as the queue) on 2,000 random grids
//! and seed 003's maps (`tests/`), and on every run of the configs (xtask's
//! `every_bfs_and_dfs_run_matches_the_reference_search`).
//!
//! # Budget
//! One expansion is one dequeue; the budget is asked before each. When it refuses, the
//! search ends with [`Status::BudgetExhausted`](planner_api::Status::BudgetExhausted), no path, and the counters so far.
//!
//! # Seed 003's data
//! On `maps/wpi/map1.txt` this gives the report's Table I lengths 18, 14 and 16 for pairs
//! 1-3. On `maps/wpi/map3.txt` it gives 70, 39 and 41 for pairs 1-3: Table II's "Map 1"
//! (70) is pair 1, and its "Map 2" (41) is **pair 3**, `(3,2)` to `(14,12)`. (`planner-dfs`
//! with the seed's order confirms this: it reproduces the report's DFS lengths 196 and 73
//! on pairs 1 and 3.) `map2.txt` pair 2 has its goal `(12, 3)` on an `X`: building the
//! [`Problem`] fails with an error naming that cell.
//!
//! # Design
//! Per-cell masks of the safe moves, built once per grid from [`MoveSet`] (cached while
//! the grid is the same), so the loop does no bounds or obstacle test; visited marks are
//! generation stamps, so a new search clears nothing; the queue is a flat array of at most
//! one entry per cell. Nothing is allocated per expansion.
//!
//! # Example
//! ```
//! use planner_api::{Budget, Cell, Grid, Planner, Problem, Status};
//! use planner_bfs::{Bfs, Config};
//!
//! let grid = Grid::from_ascii("
//!     ...
//!     .#.
//!     ...
//! ").unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(2, 2)).unwrap();
//! let mut bfs = Bfs::new(Config::default()).unwrap();
//! let outcome = bfs.plan(&problem, &Budget::unlimited());
//! assert_eq!(outcome.status, Status::Found);
//! // Right first (the order is R L D U): along the top row, then down.
//! let path = outcome.path.unwrap();
//! assert_eq!(path.cells()[1], Cell::new(1, 0));
//! assert_eq!(path.metrics().steps, 4);
//! // Dequeued: (0,0) (1,0) (0,1) (2,0) (0,2) (2,1) (1,2) (2,2).
//! assert_eq!(outcome.counters.get("n_expanded"), Some(8));
//! assert_eq!(outcome.counters.get("n_neighbor_checks"), Some(28));
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

/// The configuration of BFS and of DFS (TOML/JSON keys as the field names).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// Neighbourhood, written as its number of directions (`moves = 4` or `8`, also 16, 32, 48).
    /// Default 4, seed 003's.
    #[schemars(with = "u32", extend("enum" = [4, 8, 16, 32, 48]))]
    pub moves: Connectivity,
    /// Whether 8-connected diagonals may cut corners (only with `moves = 8`). Default false.
    pub corner_cutting: bool,
    /// Order in which the neighbours are checked and put on the frontier, e.g. `"R L D U"`
    /// (see [`NeighborOrder`]). Default `R L D U`, seed 000's order; seed 003 lists "left,
    /// right, up, and down" (`"L R U D"`). For BFS any order gives the same path length;
    /// for DFS the last one pushed is expanded first, and `"L R U D"` reproduces seed 003's
    /// DFS lengths.
    #[schemars(with = "String")]
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
    #[error("parameter `order`: {0}")]
    Order(MoveOrderError),
    /// `corner_cutting` was asked for a neighbourhood other than 8.
    #[error("parameter `corner_cutting`: {0}")]
    CornerCutting(MoveOrderError),
}

impl planner_api::ParamKey for ConfigError {
    fn param_key(&self) -> &str {
        match self {
            ConfigError::Order(_) => "order",
            ConfigError::CornerCutting(_) => "corner_cutting",
        }
    }
}

/// Which end of the frontier is expanded next: the discipline that makes a frontier
/// search breadth-first or depth-first.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Discipline {
    /// A queue: the cell enqueued first is expanded first (BFS).
    Fifo,
    /// A stack: the cell pushed last is expanded first (seed 003's DFS).
    Lifo,
}

/// The search shared by BFS and DFS (`planner-dfs` uses it with [`Discipline::Lifo`]): mark
/// a cell visited when it enters the frontier, test the goal when it leaves, parent links.
/// The counters are the crate docs' for either discipline.
///
/// Keeps its per-cell buffers between searches; the safe-move masks are rebuilt only when
/// the grid changes.
#[derive(Debug, Clone)]
pub struct FrontierSearch {
    discipline: Discipline,
    moves: MoveSet,
    adjacency: Option<Adjacency>,
    /// `mark[p] == stamp` when padded cell `p` is visited in the current search.
    mark: Vec<u32>,
    stamp: u32,
    /// Parent of each visited cell (padded index); the start's is itself.
    parent: Vec<u32>,
    /// The frontier: `frontier[head..]` (a FIFO keeps what it expanded below `head`).
    frontier: Vec<u32>,
}

impl FrontierSearch {
    /// The move set in use.
    pub fn move_set(&self) -> &MoveSet {
        &self.moves
    }

    /// A search with `moves` in their order and the frontier `discipline`.
    pub fn new(moves: MoveSet, discipline: Discipline) -> FrontierSearch {
        FrontierSearch {
            discipline,
            moves,
            adjacency: None,
            mark: Vec::new(),
            stamp: 0,
            parent: Vec::new(),
            frontier: Vec::new(),
        }
    }

    /// The moves, in the order they are checked and put on the frontier.
    pub fn moves(&self) -> &MoveSet {
        &self.moves
    }

    /// Searches `problem` within `budget`. Lists the dequeued cells in
    /// [`Outcome::expanded`] when the budget asks ([`Budget::record_expanded`]), and refuses
    /// with [`Outcome::over_memory`] when the adjacency and the per-cell arrays (20 bytes
    /// per padded cell and the grid's copy) are over [`Budget::max_memory_mb`].
    pub fn search(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        let grid = problem.grid();
        let needed = Adjacency::bytes_for(grid, &self.moves)
            + 12 * Adjacency::padded_len_for(grid, &self.moves) as u64;
        if let Err(shortfall) = budget.check_memory(needed, grid) {
            let counters = SearchStats::default()
                .report(Counter::FRONTIER)
                .with(Counter::OpenInsertions.name(), 0);
            return Outcome::over_memory(shortfall, counters);
        }
        let adjacency = Adjacency::cached(&mut self.adjacency, grid, &self.moves);
        let len = adjacency.padded_len();
        if self.mark.len() != len {
            // Allocated zeroed: the system commits the pages a search writes.
            self.mark = vec![0; len];
            self.parent = vec![0; len];
            self.stamp = 0;
        }
        let record = budget.record_expanded;
        let mut expanded = Vec::new();
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

        self.frontier.clear();
        self.frontier.reserve(grid.len());
        self.frontier.push(start as u32);
        self.mark[start] = stamp;
        self.parent[start] = start as u32;
        stats.peak_open = 1;
        let mut n_insertions = 1u64;
        let mut head = 0usize;
        let mut found = false;
        let mut exhausted = false;
        while head < self.frontier.len() {
            if !clock.allows(stats.n_expanded) {
                exhausted = true;
                break;
            }
            let p = match self.discipline {
                Discipline::Fifo => {
                    head += 1;
                    self.frontier[head - 1]
                }
                Discipline::Lifo => match self.frontier.pop() {
                    Some(top) => top,
                    None => break,
                },
            } as usize;
            stats.n_expanded += 1;
            if record {
                expanded.push(adjacency.cell(p));
            }
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
                    self.frontier.push(q as u32);
                    n_insertions += 1;
                }
            }
            stats.peak_open = stats.peak_open.max((self.frontier.len() - head) as u64);
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
        .with_expanded(expanded)
    }
}

/// The move set of a validated `config`.
pub fn move_set(config: &Config) -> Result<MoveSet, ConfigError> {
    MoveSet::new(config.moves, config.corner_cutting, &config.order).map_err(|e| match e {
        MoveOrderError::CornerCutting(_) => ConfigError::CornerCutting(e),
        other => ConfigError::Order(other),
    })
}

/// Breadth-first search (registry name `bfs`): [`FrontierSearch`] with a queue.
#[derive(Debug, Clone)]
pub struct Bfs {
    config: Config,
    search: FrontierSearch,
}

impl Bfs {
    /// A planner with a validated `config`.
    ///
    /// Errors when `order` does not list the moves of `moves` correctly, or when
    /// `corner_cutting` is set for a neighbourhood other than 8.
    pub fn new(config: Config) -> Result<Bfs, ConfigError> {
        let search = FrontierSearch::new(move_set(&config)?, Discipline::Fifo);
        Ok(Bfs { config, search })
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The moves, in the order they are checked.
    pub fn moves(&self) -> &MoveSet {
        self.search.moves()
    }
}

impl Planner for Bfs {
    fn name(&self) -> &str {
        "bfs"
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
