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
//! The main decision is to make every search allocation-free after the first: one
//! per-cell record (g, parent, stamp) lives in the planner and is invalidated by a
//! generation stamp instead of being cleared, so a query touching 100 cells of a 512 x 512
//! map costs 100 cells, not 262,144. Moves come from planner-api's [`Adjacency`]: per-cell
//! masks of the safe moves over a padded grid, built once per grid, so the neighbour loop
//! has no bounds or obstacle test and walks the set bits in the configured order; the
//! blocked checks are counted as the clear bits.
//!
//! OPEN (module `open`) gives entries out in exactly the order of the full key (f, tie,
//! push sequence), and is chosen per search by what the costs allow. With unit moves and
//! an integer heuristic that changes by at most 1 per move (Manhattan, Chebyshev, zero) and
//! weight 0 or 1, `f` is an integer that never drops along an edge and rises by at most 2,
//! so OPEN is four slots of one `f` each: a queue (FIFO), a stack (LIFO), or runs of equal
//! `g` (high g first; a child always lands on top). Otherwise it is a ring of `f` buckets
//! of width 1/16 in front of a binary heap that holds the least bucket, itself behind a
//! sorted front of eight entries that catches the common new minimum. An improved node is
//! pushed again and its older entry is skipped when it comes out (the node is then
//! CLOSED), or dropped unseen when its bucket comes up; `peak_open` counts nodes in OPEN,
//! not entries. The tests hold every variant to a plain `BinaryHeap` transcription of
//! Fig. 4, counter for counter.
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

mod open;

use open::{BucketOpen, IntOpen, Open};
use planner_api::{
    Adjacency, Budget, Cell, Connectivity, Counter, MoveOrderError, MoveSet, NeighborOrder,
    Outcome, Path, Planner, Problem, SearchStats, Status,
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
    /// Whether the estimate is an integer that changes by at most 1 along a unit move
    /// (one step right, left, down or up): Manhattan, Chebyshev and zero.
    pub fn is_consistent_integer_on_unit_moves(self) -> bool {
        matches!(
            self,
            Heuristic::Manhattan | Heuristic::Chebyshev | Heuristic::Zero
        )
    }

    /// The estimate from `(x, y)` to `(gx, gy)`.
    #[inline]
    pub fn estimate(self, x: u32, y: u32, gx: u32, gy: u32) -> f64 {
        let (dx, dy) = (x.abs_diff(gx), y.abs_diff(gy));
        match self {
            Heuristic::Manhattan => estimate::<MANHATTAN>(dx, dy),
            Heuristic::Octile => estimate::<OCTILE>(dx, dy),
            Heuristic::Euclidean => estimate::<EUCLIDEAN>(dx, dy),
            Heuristic::Chebyshev => estimate::<CHEBYSHEV>(dx, dy),
            Heuristic::Zero => estimate::<ZERO>(dx, dy),
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
    /// The entry pushed first is popped first (the paper's rule). A node improved while in
    /// OPEN is pushed again; if rounding left its f unchanged, its older entry comes out
    /// first and the node is expanded there, with its improved g.
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

impl planner_api::ParamKey for ConfigError {
    fn param_key(&self) -> &str {
        match self {
            ConfigError::Weight(_) => "weight",
            ConfigError::Moves(e) => e.param_key(),
        }
    }
}

/// The A* planner. Build with [`AStar::new`]; reuse it for many queries.
#[derive(Debug, Clone)]
pub struct AStar {
    config: Config,
    moves: MoveSet,
    adjacency: Option<Adjacency>,
    generation: u32,
    nodes: Vec<Node>,
    /// Whether the integer OPEN fits the moves, heuristic and weight (else the buckets).
    integral: bool,
    opens: Opens,
}

/// One OPEN list per tie rule and implementation. The configuration picks one (see
/// `AStar::new`), and only that one is ever configured or holds memory.
#[derive(Debug, Clone, Default)]
struct Opens {
    fifo: BucketOpen<{ open::FIFO }>,
    lifo: BucketOpen<{ open::LIFO }>,
    low_g: BucketOpen<{ open::LOW_G }>,
    high_g: BucketOpen<{ open::HIGH_G }>,
    int_fifo: IntOpen<{ open::FIFO }>,
    int_lifo: IntOpen<{ open::LIFO }>,
    int_low_g: IntOpen<{ open::LOW_G }>,
    int_high_g: IntOpen<{ open::HIGH_G }>,
}

/// Per-cell search state, one record per padded cell so that a relaxation touches one
/// cache line. `stamp` is `generation << 1 | closed`: a record from an older search
/// counts as unseen, so nothing is cleared between searches.
#[derive(Debug, Clone, Copy, Default)]
struct Node {
    g: f64,
    parent: u32,
    stamp: u32,
}

impl AStar {
    /// A planner with `config`, validated.
    pub fn new(config: Config) -> Result<AStar, ConfigError> {
        if !config.weight.is_finite() || config.weight < 0.0 {
            return Err(ConfigError::Weight(config.weight));
        }
        let moves = MoveSet::new(config.moves, config.corner_cutting, &config.order)?;
        let costs = || moves.moves().iter().map(|m| m.cost);
        let integral = IntOpen::<{ open::FIFO }>::fits(
            costs(),
            config.weight,
            config.heuristic.is_consistent_integer_on_unit_moves(),
        );
        let mut opens = Opens::default();
        if !integral {
            let max_cost = costs().fold(0.0, f64::max);
            match config.tie_break {
                TieBreak::Fifo => opens.fifo.configure(max_cost, config.weight),
                TieBreak::Lifo => opens.lifo.configure(max_cost, config.weight),
                TieBreak::LowG => opens.low_g.configure(max_cost, config.weight),
                TieBreak::HighG => opens.high_g.configure(max_cost, config.weight),
            }
        }
        Ok(AStar {
            integral,
            config,
            moves,
            adjacency: None,
            generation: 0,
            nodes: Vec::new(),
            opens,
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

    /// Runs A* on `problem` within `budget` and returns the path with raw counters.
    pub fn search(&mut self, problem: &Problem<'_>, budget: &Budget) -> Search {
        let mut opens = std::mem::take(&mut self.opens);
        let search = match (self.integral, self.config.tie_break) {
            (true, TieBreak::Fifo) => self.run_with(&mut opens.int_fifo, problem, budget),
            (true, TieBreak::Lifo) => self.run_with(&mut opens.int_lifo, problem, budget),
            (true, TieBreak::LowG) => self.run_with(&mut opens.int_low_g, problem, budget),
            (true, TieBreak::HighG) => self.run_with(&mut opens.int_high_g, problem, budget),
            (false, TieBreak::Fifo) => self.run_with(&mut opens.fifo, problem, budget),
            (false, TieBreak::Lifo) => self.run_with(&mut opens.lifo, problem, budget),
            (false, TieBreak::LowG) => self.run_with(&mut opens.low_g, problem, budget),
            (false, TieBreak::HighG) => self.run_with(&mut opens.high_g, problem, budget),
        };
        self.opens = opens;
        search
    }

    /// [`AStar::run`] with the configured heuristic as a constant.
    fn run_with<O: Open>(
        &mut self,
        open: &mut O,
        problem: &Problem<'_>,
        budget: &Budget,
    ) -> Search {
        match self.config.heuristic {
            Heuristic::Manhattan => self.run::<O, MANHATTAN>(open, problem, budget),
            Heuristic::Octile => self.run::<O, OCTILE>(open, problem, budget),
            Heuristic::Euclidean => self.run::<O, EUCLIDEAN>(open, problem, budget),
            Heuristic::Chebyshev => self.run::<O, CHEBYSHEV>(open, problem, budget),
            Heuristic::Zero => self.run::<O, ZERO>(open, problem, budget),
        }
    }

    /// The search itself, with the OPEN list `open` and heuristic `H` (one of the
    /// constants [`MANHATTAN`] ... [`ZERO`]). Counters are locals until it returns.
    fn run<O: Open, const H: u8>(
        &mut self,
        open: &mut O,
        problem: &Problem<'_>,
        budget: &Budget,
    ) -> Search {
        let grid = problem.grid();
        let adjacency = Adjacency::cached(&mut self.adjacency, grid, &self.moves);
        if self.nodes.len() != adjacency.padded_len() {
            self.nodes = vec![Node::default(); adjacency.padded_len()];
            self.generation = 0;
        }
        self.generation += 1;
        if self.generation >= 1 << 31 {
            self.nodes.fill(Node::default());
            self.generation = 1;
        }
        let open_stamp = self.generation << 1;
        let closed_stamp = open_stamp | 1;
        let nodes = &mut self.nodes[..];
        open.clear();

        let n_moves = adjacency.n_moves() as u64;
        let mut step = [(0u32, 0u32, 0.0f64); 64];
        for (slot, mv) in step.iter_mut().zip(self.moves.moves()) {
            // Wrapping offsets: x + dx stays in the grid whenever the move's mask bit is set.
            *slot = (mv.dx as u32, mv.dy as u32, mv.cost);
        }
        let goal = problem.goal();
        let goal_index = adjacency.index(goal);
        let weight = self.config.weight;
        let h = |x: u32, y: u32| weight * estimate::<H>(x.abs_diff(goal.x), y.abs_diff(goal.y));

        let mut clock = budget.start();
        let start = problem.start();
        let start_index = adjacency.index(start);
        nodes[start_index] = Node {
            g: 0.0,
            parent: start_index as u32,
            stamp: open_stamp,
        };
        open.push(start_index as u32, h(start.x, start.y), 0.0);
        let mut tally = Tally {
            n_open_insertions: 1,
            peak_open: 1,
            ..Tally::default()
        };

        while let Some(p) = open.pop(|q| nodes[q as usize].stamp == closed_stamp) {
            let p = p as usize;
            if nodes[p].stamp == closed_stamp {
                continue; // The older entry of a node improved while in OPEN.
            }
            if !clock.allows(tally.n_expanded) {
                return Search {
                    status: Status::BudgetExhausted,
                    path: None,
                    cost: None,
                    stats: tally.stats(n_moves, tally.n_expanded),
                };
            }
            nodes[p].stamp = closed_stamp;
            tally.n_expanded += 1;
            if p == goal_index {
                let path = reconstruct(adjacency, nodes, start_index, goal_index);
                return Search {
                    status: Status::Found,
                    path: Some(path),
                    cost: Some(nodes[p].g),
                    // The goal's moves are not checked.
                    stats: tally.stats(n_moves, tally.n_expanded - 1),
                };
            }
            let Cell { x, y } = adjacency.cell(p);
            let g_node = nodes[p].g;
            let mut mask = adjacency.mask(p);
            // Set bits in increasing order are the safe moves in the configured order.
            while mask != 0 {
                let m = mask.trailing_zeros();
                mask &= mask - 1;
                tally.n_safe += 1;
                let q = adjacency.neighbor(p, m);
                let next = &mut nodes[q];
                if next.stamp == closed_stamp {
                    tally.n_skipped += 1;
                    continue;
                }
                let (dx, dy, cost) = step[(m & 63) as usize];
                let g_temp = g_node + cost;
                let known = next.stamp == open_stamp;
                if !known || g_temp < next.g {
                    tally.n_relaxations += 1;
                    tally.n_open_insertions += u64::from(!known);
                    *next = Node {
                        g: g_temp,
                        parent: p as u32,
                        stamp: open_stamp,
                    };
                    let f = g_temp + h(x.wrapping_add(dx), y.wrapping_add(dy));
                    open.push(q as u32, f, g_temp);
                }
            }
            // OPEN only grows while a node's moves are tried: its peak is reached here.
            tally.peak_open = tally
                .peak_open
                .max(tally.n_open_insertions - tally.n_expanded);
        }
        Search {
            status: Status::NoPath,
            path: None,
            cost: None,
            stats: tally.stats(n_moves, tally.n_expanded),
        }
    }
}

/// The search loop's counters, kept as plain locals (a `SearchStats` is built once, at
/// the end). Neighbour checks and blocked moves follow from the safe moves tried.
#[derive(Debug, Clone, Copy, Default)]
struct Tally {
    n_expanded: u64,
    /// Safe moves tried: the set bits of the expanded nodes' move masks.
    n_safe: u64,
    n_skipped: u64,
    n_relaxations: u64,
    n_open_insertions: u64,
    peak_open: u64,
}

impl Tally {
    /// The counters, when `n_checked` expanded nodes tried all `n_moves` moves.
    fn stats(&self, n_moves: u64, n_checked: u64) -> SearchStats {
        let n_neighbor_checks = n_moves * n_checked;
        SearchStats {
            n_expanded: self.n_expanded,
            n_neighbor_checks,
            n_blocked: n_neighbor_checks - self.n_safe,
            n_skipped: self.n_skipped,
            n_open_insertions: self.n_open_insertions,
            n_relaxations: self.n_relaxations,
            peak_open: self.peak_open,
            ..SearchStats::default()
        }
    }
}

/// The heuristics as const-generic parameters of the search loop.
const MANHATTAN: u8 = 0;
const OCTILE: u8 = 1;
const EUCLIDEAN: u8 = 2;
const CHEBYSHEV: u8 = 3;
const ZERO: u8 = 4;

/// Heuristic `H` of the offsets `dx`, `dy` to the goal, as [`Heuristic::estimate`].
#[inline(always)]
fn estimate<const H: u8>(dx: u32, dy: u32) -> f64 {
    let (dx, dy) = (f64::from(dx), f64::from(dy));
    match H {
        MANHATTAN => dx + dy,
        OCTILE => dx.max(dy) + (std::f64::consts::SQRT_2 - 1.0) * dx.min(dy),
        EUCLIDEAN => dx.hypot(dy),
        CHEBYSHEV => dx.max(dy),
        _ => 0.0,
    }
}

fn reconstruct(adjacency: &Adjacency, nodes: &[Node], start: usize, goal: usize) -> Path {
    let mut cells: Vec<Cell> = vec![adjacency.cell(goal)];
    let mut node = goal;
    while node != start {
        node = nodes[node].parent as usize;
        cells.push(adjacency.cell(node));
    }
    cells.reverse();
    Path::new(cells)
}

impl Planner for AStar {
    fn name(&self) -> &str {
        NAME
    }

    fn specs(&self) -> planner_api::PlannerSpecs {
        planner_api::PlannerSpecs::deterministic(planner_api::PathSpec::Moves(self.moves.clone()))
    }

    fn prepare(&mut self, grid: &planner_api::Grid) {
        let adjacency = Adjacency::cached(&mut self.adjacency, grid, &self.moves);
        if self.nodes.len() != adjacency.padded_len() {
            self.nodes = vec![Node::default(); adjacency.padded_len()];
            self.generation = 0;
        }
    }

    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        let search = self.search(problem, budget);
        Outcome::new(
            search.status,
            search.path,
            search.stats.report(Counter::ASTAR),
        )
    }
}
