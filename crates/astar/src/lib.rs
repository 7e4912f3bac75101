//! A* on occupancy grids, counting exactly what seed 000 counts.
//!
//! The algorithm is seed 000's section 2.2 and Fig. 4 (Hart, Nilsson and Raphael's A*,
//! <https://doi.org/10.1109/TSSC.1968.300136>), with seed 002's weighted evaluation
//! `f = g + beta * h` (equation 7):
//!
//! 1. Insert the start into OPEN (`n_open_insertions = 1`).
//! 2. Pop the OPEN node with the least `f` (ties: [`TieBreak`]); move it to CLOSED;
//!    `n_expanded += 1`. If it is the goal, stop: the goal counts as expanded and its
//!    neighbours are not checked.
//! 3. For each move in the configured order: `n_neighbor_checks += 1`; a target that is
//!    out of bounds or blocked, or a long move whose segment crosses a blocked cell, is
//!    unsafe (`n_blocked += 1`); a target in CLOSED is skipped (`n_skipped += 1`); else, if
//!    it is not in OPEN or `g + cost < g(target)`, it is relaxed (`n_relaxations += 1`: new
//!    parent, g, f) and, when not yet in OPEN, inserted (`n_open_insertions += 1`).
//!    A target in OPEN whose g does not improve counts only as a neighbour check.
//!
//! CLOSED nodes are never reopened, as in the paper, so with an inconsistent heuristic
//! (a weight `beta > 1`, or Manhattan on 8-connected moves) the path may be longer than
//! optimal; that is the point of seed 002's weight.
//!
//! Consequences that every 4-connected run where the goal is found obeys (tested, and
//! true of every column of the paper's Tables 5 and 7):
//! `n_neighbor_checks = 4 * (n_expanded - 1)` (every expanded node but the goal checks
//! its four moves), and `n_open_insertions <= n_relaxations + 1`, with equality exactly
//! when no node already in OPEN is improved. That is so on every paper map, but not in
//! general: even with the consistent Manhattan heuristic an OPEN node can later be
//! reached by a path two steps shorter (the tests find such grids).
//!
//! # Design
//! The main decision is to make every search allocation-free after the first: per-cell
//! arrays (g, parent, closed) live in the planner and are invalidated by a generation
//! stamp instead of being cleared, so a query touching 100 cells of a 512 x 512 map costs
//! 100 cells, not 262,144. OPEN is a binary heap with lazy deletion: an improved node is
//! pushed again and its stale entry is dropped when popped (it is then CLOSED).
//! `peak_open` counts nodes in OPEN, not heap entries.
//!
//! # Defaults
//! The defaults are the paper's: 4-connected moves in the order right, left, down, up,
//! the Manhattan heuristic, `beta = 1`, and FIFO among equal `f` (the node inserted first
//! is popped first). With them, the twelve maps in `maps/paper/` reproduce every A*
//! number of seed 000's Tables 3, 4, 5 and 7.
//!
//! ```
//! use planner_api::{Budget, Cell, Grid, Planner, Problem, Status};
//! use planner_astar::{AStar, Config};
//!
//! let grid = Grid::from_ascii("
//!     ...
//!     .#.
//!     .#.
//! ").unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 2), Cell::new(2, 2)).unwrap();
//! let mut astar = AStar::new(Config::default()).unwrap();
//! let outcome = astar.plan(&problem, &Budget::unlimited());
//! assert_eq!(outcome.status, Status::Found);
//! assert_eq!(outcome.path.unwrap().metrics().steps, 6);
//! // Exactly the seven path cells are expanded; all but the goal check four moves.
//! assert_eq!(outcome.counters.get("n_expanded"), Some(7));
//! assert_eq!(outcome.counters.get("n_neighbor_checks"), Some(24));
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use planner_api::{
    Budget, Cell, Connectivity, Counter, Grid, IndexedMoves, MoveOrderError, MoveSet,
    NeighborOrder, Outcome, Path, Planner, Problem, SearchStats, Status,
};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The registry name of this planner.
pub const NAME: &str = "astar";

/// The heuristic `h(n)`, a distance estimate from `n` to the goal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Heuristic {
    /// `|dx| + |dy|` (seed 000 equation 7). Admissible and consistent on 4-connected grids only.
    #[default]
    Manhattan,
    /// `max + (sqrt 2 - 1) * min` of `|dx|, |dy|`: the exact open-grid cost of 8-connected
    /// moves. Admissible and consistent for 4 and 8 directions. Seed 002's RA-star1
    /// heuristic `(H_sum - 2 H_min) + sqrt 2 H_min` (equations 13-15) is this same function.
    Octile,
    /// `sqrt(dx^2 + dy^2)` (seed 002 equation 8). Admissible for every neighbourhood.
    Euclidean,
    /// `max(|dx|, |dy|)`. Admissible for 4 and 8 directions.
    Chebyshev,
    /// `0`: A* becomes Dijkstra's algorithm (uniform-cost search).
    Zero,
}

impl Heuristic {
    /// The estimate from `(x, y)` to `(gx, gy)`.
    #[inline]
    pub fn estimate(self, x: u32, y: u32, gx: u32, gy: u32) -> f64 {
        let dx = f64::from(x.abs_diff(gx));
        let dy = f64::from(y.abs_diff(gy));
        match self {
            Heuristic::Manhattan => dx + dy,
            Heuristic::Octile => dx.max(dy) + (std::f64::consts::SQRT_2 - 1.0) * dx.min(dy),
            Heuristic::Euclidean => dx.hypot(dy),
            Heuristic::Chebyshev => dx.max(dy),
            Heuristic::Zero => 0.0,
        }
    }
}

/// Which of several OPEN nodes with equal `f` is popped first.
///
/// It decides which of several shortest paths comes out, and so T and Score.
/// Equality of `f` is exact floating-point equality (exact for the 4-connected grid with
/// Manhattan; for irrational costs, values that differ in the last bit are not ties).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum TieBreak {
    /// The entry pushed first is popped first (the paper's rule).
    #[default]
    Fifo,
    /// The entry pushed last is popped first.
    Lifo,
    /// Lower `g` first, then FIFO.
    LowG,
    /// Higher `g` (closer to the goal by `h`) first, then FIFO.
    HighG,
}

/// A*'s parameters. Every field has a default; see [`Config::default`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// Neighbourhood: 4, 8, 16, 32 or 48 directions. Default 4.
    pub moves: Connectivity,
    /// Allow diagonal moves between two blocked orthogonal cells' corner (8 only). Default false.
    pub corner_cutting: bool,
    /// Neighbour order, e.g. `"R L D U"` (see [`NeighborOrder`]). Default `"R L D U"`.
    pub order: NeighborOrder,
    /// Heuristic. Default Manhattan.
    pub heuristic: Heuristic,
    /// Seed 002's `beta` in `f = g + beta * h`: finite and `>= 0`. Default 1.
    pub weight: f64,
    /// Tie-breaking among equal `f`. Default FIFO.
    pub tie_break: TieBreak,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            moves: Connectivity::Four,
            corner_cutting: false,
            order: NeighborOrder::default(),
            heuristic: Heuristic::Manhattan,
            weight: 1.0,
            tie_break: TieBreak::Fifo,
        }
    }
}

/// A parameter that A* cannot run with.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConfigError {
    /// `weight` is negative, infinite or NaN.
    #[error("parameter `weight` must be a finite number >= 0, got {0}")]
    Weight(f64),
    /// `order` or `corner_cutting` does not fit `moves`.
    #[error("parameter `order`/`corner_cutting`: {0}")]
    Moves(#[from] MoveOrderError),
}

/// What a search produced, with the raw counters (for planners that sum several searches).
#[derive(Debug, Clone, PartialEq)]
pub struct Search {
    /// How it ended.
    pub status: Status,
    /// The path when found.
    pub path: Option<Path>,
    /// The path's cost `g(goal)` when found (steps on 4-connected grids, else Euclidean length).
    pub cost: Option<f64>,
    /// The counters.
    pub stats: SearchStats,
}

/// The A* planner. Build with [`AStar::new`]; reuse it for many queries.
#[derive(Debug, Clone)]
pub struct AStar {
    config: Config,
    moves: MoveSet,
    compiled: Option<IndexedMoves>,
    generation: u32,
    seen: Vec<u32>,
    closed: Vec<bool>,
    g: Vec<f64>,
    parent: Vec<u32>,
    heap: BinaryHeap<Entry>,
}

impl AStar {
    /// A planner with `config`, validated.
    pub fn new(config: Config) -> Result<AStar, ConfigError> {
        if !config.weight.is_finite() || config.weight < 0.0 {
            return Err(ConfigError::Weight(config.weight));
        }
        let moves = MoveSet::new(config.moves, config.corner_cutting, &config.order)?;
        Ok(AStar {
            config,
            moves,
            compiled: None,
            generation: 0,
            seen: Vec::new(),
            closed: Vec::new(),
            g: Vec::new(),
            parent: Vec::new(),
            heap: BinaryHeap::new(),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The move set in use.
    pub fn move_set(&self) -> &MoveSet {
        &self.moves
    }

    /// Prepares the per-cell arrays for `grid` and starts a new generation.
    fn prepare(&mut self, grid: &Grid) {
        if !self.compiled.as_ref().is_some_and(|c| c.fits(grid)) {
            self.compiled = Some(IndexedMoves::new(&self.moves, grid));
        }
        let len = grid.len();
        if self.seen.len() != len {
            self.seen = vec![0; len];
            self.closed = vec![false; len];
            self.g = vec![0.0; len];
            self.parent = vec![0; len];
            self.generation = 0;
        }
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            self.seen.fill(0);
            self.generation = 1;
        }
        self.heap.clear();
    }

    /// Runs A* on `problem` within `budget` and returns the path with raw counters.
    pub fn search(&mut self, problem: &Problem<'_>, budget: &Budget) -> Search {
        let grid = problem.grid();
        self.prepare(grid);
        let AStar {
            config,
            compiled,
            generation,
            seen,
            closed,
            g,
            parent,
            heap,
            ..
        } = self;
        let generation = *generation;
        let Some(compiled) = compiled.as_ref() else {
            unreachable!("prepare compiles the moves")
        };
        let free = grid.free_cells();
        let width = grid.width() as usize;
        let goal = problem.goal();
        let goal_index = grid.index(goal);
        let heuristic = config.heuristic;
        let weight = config.weight;
        let tie_break = config.tie_break;
        let h = |index: usize| {
            let cell = grid.cell(index);
            weight * heuristic.estimate(cell.x, cell.y, goal.x, goal.y)
        };

        let mut stats = SearchStats::default();
        let mut clock = budget.start();
        let mut n_pushed: u64 = 0;
        let mut n_open: u64 = 0;
        let push = |heap: &mut BinaryHeap<Entry>, node: usize, g_node: f64, n_pushed: &mut u64| {
            let seq = match tie_break {
                TieBreak::Lifo => u64::MAX - *n_pushed,
                _ => *n_pushed,
            };
            let tie = match tie_break {
                TieBreak::LowG => g_node,
                TieBreak::HighG => -g_node,
                TieBreak::Fifo | TieBreak::Lifo => 0.0,
            };
            *n_pushed += 1;
            heap.push(Entry {
                f: g_node + h(node),
                tie,
                seq,
                node: node as u32,
            });
        };

        let start_index = grid.index(problem.start());
        seen[start_index] = generation;
        closed[start_index] = false;
        g[start_index] = 0.0;
        parent[start_index] = start_index as u32;
        push(heap, start_index, 0.0, &mut n_pushed);
        stats.n_open_insertions = 1;
        n_open += 1;
        stats.peak_open = 1;

        while let Some(entry) = heap.pop() {
            let node = entry.node as usize;
            if closed[node] {
                continue; // A stale entry of a node improved after it was pushed.
            }
            if !clock.allows(stats.n_expanded) {
                return Search {
                    status: Status::BudgetExhausted,
                    path: None,
                    cost: None,
                    stats,
                };
            }
            closed[node] = true;
            n_open -= 1;
            stats.n_expanded += 1;
            if node == goal_index {
                let path = reconstruct(grid, parent, start_index, goal_index);
                return Search {
                    status: Status::Found,
                    path: Some(path),
                    cost: Some(g[node]),
                    stats,
                };
            }
            let x = (node % width) as u32;
            let y = (node / width) as u32;
            let g_node = g[node];
            for (k, mv) in compiled.moves().iter().enumerate() {
                stats.n_neighbor_checks += 1;
                let Some(next) = compiled.target(free, x, y, node, k) else {
                    stats.n_blocked += 1;
                    continue;
                };
                let known = seen[next] == generation;
                if known && closed[next] {
                    stats.n_skipped += 1;
                    continue;
                }
                let g_temp = g_node + mv.cost;
                if !known || g_temp < g[next] {
                    stats.n_relaxations += 1;
                    if !known {
                        seen[next] = generation;
                        closed[next] = false;
                        stats.n_open_insertions += 1;
                        n_open += 1;
                        stats.peak_open = stats.peak_open.max(n_open);
                    }
                    g[next] = g_temp;
                    parent[next] = node as u32;
                    push(heap, next, g_temp, &mut n_pushed);
                }
            }
        }
        Search {
            status: Status::NoPath,
            path: None,
            cost: None,
            stats,
        }
    }
}

fn reconstruct(grid: &Grid, parent: &[u32], start: usize, goal: usize) -> Path {
    let mut cells: Vec<Cell> = vec![grid.cell(goal)];
    let mut node = goal;
    while node != start {
        node = parent[node] as usize;
        cells.push(grid.cell(node));
    }
    cells.reverse();
    Path::new(cells)
}

impl Planner for AStar {
    fn name(&self) -> &str {
        NAME
    }

    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        let search = self.search(problem, budget);
        Outcome {
            status: search.status,
            path: search.path,
            counters: search.stats.report(Counter::ASTAR),
        }
    }
}

/// An OPEN entry; the heap pops the greatest, so the order is reversed.
#[derive(Debug, Clone, Copy)]
struct Entry {
    f: f64,
    tie: f64,
    seq: u64,
    node: u32,
}

impl Ord for Entry {
    fn cmp(&self, other: &Entry) -> Ordering {
        other
            .f
            .total_cmp(&self.f)
            .then_with(|| other.tie.total_cmp(&self.tie))
            .then_with(|| other.seq.cmp(&self.seq))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Entry) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for Entry {
    fn eq(&self, other: &Entry) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Entry {}
