//! Lexicographic A*: the path that is best by (steps, then turns, then score), exactly and
//! in polynomial time.
//!
//! Seed 000 ranks paths by distance D, then turns T, then Score (section 2.4, equations
//! 22-26 and the "lexicographic ranking approach" below Fig. 5), and finds the best one only
//! by exhaustive Backtracking over all simple paths (section 2.3), at exponential cost; its
//! A* returns *a* shortest path whose turns depend on tie-breaking (maps 4, 5 and 10 of
//! Tables 3-4). This crate answers the seed's future-work item of a heuristic search that
//! puts motion quality into the evaluation function.
//!
//! # Design
//! The main decision is to search states `(cell, heading)`, where the heading is the
//! direction of the last move, instead of cells: whether a move turns depends on the
//! previous move, so over states the cost of a move is local. A move `d` from `(c, h)`
//! leads to `(c + d, d)` and costs the pair `(1, τ)` with `τ = 1` when `h ≠ d` and `0`
//! otherwise. The start state has no heading, so its moves never turn (the paper's
//! `c_1 = 1`). The goal is reached in any heading. Costs are pairs of integers `(D, T)`
//! compared lexicographically ([`Cost`]), which is exact; since `Score = D + T`, two paths
//! with equal D and T have equal Score, so minimising `(D, T)` minimises `(D, T, Score)`,
//! the order of [`planner_api::PathRank`].
//!
//! A path that visits a cell twice is never best: cutting out the loop removes at least
//! two steps and adds no turn (the loop's moves sum to zero, so they contain a change of
//! direction, which pays for the at most one turn the cut may add at the junction). So the best path over
//! states is a simple path, and the search and seed 000's Backtracking (which enumerates
//! simple paths only) optimise over the same set. This holds for the weighted objective
//! too.
//!
//! A per-state record (g, parent heading, closed) and a per-cell record (best g of its
//! states, expanded) live in the planner, in pages allocated on first write
//! ([`planner_api::pages::Pages`]: memory follows the states a search touches, not the
//! grid), and are invalidated by a generation stamp, OPEN
//! is a binary heap with lazy deletion, and moves come from [`IndexedMoves`], as in
//! `planner-astar`. The parent of a state is stored as one byte, the heading of the
//! previous state (its cell is `cell - heading`). The start state has no slot: it is a
//! sentinel in OPEN, and no move leads into it.
//!
//! # The heuristic and its consistency
//! `h(c, h) = (M(c), H(c, h))`, where `M` is the Manhattan (4-connected) or Chebyshev
//! (8-connected) distance to the goal `g`, and `H` is a lower bound on the turns still
//! needed, computed from the heading and the goal's relative position ([`heuristic`]).
//!
//! **Steps.** `M(c) <= 1 + M(c + d)` for every unit move `d` (triangle inequality; each
//! move has length 1 in that norm), and `M(g) = 0`. When the inequality is strict,
//! `h(s) < c(s, s') + h(s')` lexicographically whatever the turns; so the second component
//! matters only on moves with `M(c) = 1 + M(c')`. We prove more, `H(s) <= τ + H(s')` on
//! every move, which also makes `M + λH` consistent for the weighted objective.
//!
//! **4-connected**, `H ∈ {0, 1, 2}`. Let `R(c)` be the set of axis directions pointing
//! from `c` towards `g` (one per non-zero coordinate of `g - c`, so `|R| <= 2`). Every
//! path from `c` to `g` moves in every direction of `R(c)`, and a move sequence that takes
//! `k` distinct values changes direction at least `k - 1` times. Hence
//! `H(c, h) = |R(c) \ {h}|` for a heading `h`, and `max(|R(c)| - 1, 0)` for the start
//! (no heading), is a lower bound. For a move `d` from `s = (c, h)` to `s' = (c', d)`:
//! - `d ∈ R(c)` (towards the goal): moving along `d` can only clear `d`'s coordinate, so
//!   `R(c') \ {d} = R(c) \ {d}` and `H(s') = |R(c)| - 1`. If `h = d`, `τ = 0` and
//!   `H(s) = |R| - 1 = H(s')`. If `h ≠ d`, `τ = 1` and `H(s) <= |R| = 1 + H(s')`. With no
//!   heading, `τ = 0` and `H(s) = |R| - 1 = H(s')`.
//! - `d ∉ R(c)` (away, or sideways off the goal's row or column): then `R(c') ⊇ R(c)` and
//!   `-d ∈ R(c')`, so `d ∉ R(c')` and `H(s') = |R(c')| >= |R(c)| >= H(s)`.
//!
//! **8-connected**, `H ∈ {0, 1}`. Call `c` *in line* with the unit move `u` when
//! `g - c = k u` for some `k >= 1`. `H(c, h) = 0` when `c = g`, or `c` is in line with `u`
//! and `h` is `u` or no heading; else `H = 1`. It is a lower bound: off line, a path needs
//! two distinct directions, hence a change; in line with `u ≠ h`, a path of `h` moves only
//! ends at `c + j h ≠ g`, so some move differs from `h`. Consistency needs only: `H(s) = 1`
//! and `τ = 0` imply `H(s') = 1`. With `τ = 0`, `h = d` or `h` is none. If `H(s') = 0`
//! then `g - c' = k d` with `k >= 0`, so `g - c = (k + 1) d`: `c` is in line with `d`, and
//! `H(s) = 0` (for `h = d` or none), a contradiction. A bound of 2 (as for 4-connected) is
//! not used: with diagonals, a heading pointing away can still be one of only two
//! directions that reach the goal (heading up, goal at `(2, 1)`: up, then down-right twice).
//!
//! **Goal states** have `h = (0, 0)`. Costs are pairs in the totally ordered group
//! `(Z², lex)` and every move costs at least `(1, 0)`, so the textbook A* argument carries
//! over unchanged: with a consistent `h`, `f` never decreases along a path, a state's `g`
//! is optimal when it is popped (states are never reopened), and the first goal state
//! popped is optimal over all headings. The tests check consistency exhaustively on small
//! grids and admissibility against an uninformed lexicographic Dijkstra.
//!
//! # Dominance pruning
//! From cell `c`, any continuation available to a state `(c, h)` is available to another
//! state `(c, h')` of the same cell for at most one more turn (only its first move can
//! turn differently). So with [`Config::dominance`] (the default) a newly generated state
//! whose `g` is no better than `g(c, h') + (0, 1)` for a state of `c` already reached
//! (`+ λ` in weighted mode) is discarded, counted in `n_dominated`. On den520d this cuts
//! the states expanded from 2.7 to 1.15 times A*'s cells (see the bench).
//!
//! It stays exact. Fix an optimal cell path `v_0 .. v_n` of cost `C*` and call a reached
//! state `t` at `v_i` a *witness* when `g(t)` plus the cost of following the path from
//! `v_i` with `t`'s heading is at most `C*`. The start is a witness at `v_0`; take a
//! witness with the largest `i`. If it is in OPEN, its `f <= C*` (admissibility), so it is
//! popped before any goal state costing more. If it was expanded and `i < n`, its move to
//! `v_{i+1}` produced a state `u` that was (a) already closed, hence with `g` no larger
//! (with a consistent `h`, `f` is popped in non-decreasing order), or (b) given this `g`
//! or already holding one no larger, or (c) dominated by a state `t'` of `v_{i+1}` with
//! `g(t') + (0, 1) <= g(u)`, whose extra turn costs at most `(0, 1)`. Each makes a witness
//! at `v_{i+1}`, against maximality. So a witness sits at the goal, and the first goal
//! state popped costs `C*`. The tests run every check with and without pruning.
//!
//! # Objectives
//! - [`Objective::Lexicographic`] (default): minimise `(D, T)` with integer pairs; the heap
//!   key is `f = (D + M, T + H)` packed into a `u128`. No floating point.
//! - [`Objective::Weighted`]: minimise `D + λ T` (`lambda >= 0`). `λ = 0` gives plain
//!   shortest paths (over states, so with 4 or 8 times A*'s states); `λ = 1` minimises
//!   the paper's Score `D + T`. `g` is still kept as the integer pair `(D, T)`; the
//!   weighted value `D + λ T` and the key `(D + M) + λ (T + H)` are evaluated in `f64`
//!   from those integers, which is exact when `λ` is a dyadic rational such as `0.5` or
//!   `1/1024` and otherwise within rounding.
//!
//! The lexicographic order is the limit of small `λ`: if `P` is lexicographically best and
//! `0 < λ T(P) < 1`, then a weighted-best `Q` has `D(Q) <= D(P) + λ (T(P) - T(Q)) < D(P) + 1`,
//! so `D(Q) = D(P)` and then `T(Q) = T(P)`; as `T(P) <= D(P) - 1`, any `λ < 1 / D(P)` works.
//! This crate does not implement lexicographic mode as a small `λ`, which would need a
//! bound on D in advance and lose exactness in floating point; it compares integer pairs.
//!
//! # Weighted grids
//! Seed 000's D is the number of moves on a 4-connected grid, each of length 1. On a grid
//! with cell weights ([`planner_api::weights`]) and 4-connected moves, D becomes the
//! path's cost under the grid's [`planner_api::CostRule`]: a move from a cell of weight
//! `a` to one of weight `b` costs `(a + b) / 2` (mean) or `b` (entered) instead of 1, so
//! with every weight 1 the weighted D is the seed's D. Turns stay as they are: the
//! search finds the least-cost path, then among those the one with fewest turns
//! ([`Objective::Weighted`]: the least `D + lambda T` with the weighted D). D is kept in
//! integers, doubled (`a + b` or `2 b` per move, exact), the steps heuristic is the
//! Manhattan distance times `2 w_min` (`w_min` the grid's smallest weight: every move
//! costs at least that, so the heuristic stays consistent and the proofs above carry
//! over: they use only that a move's D is at least the drop of the steps heuristic, that
//! a loop costs D > 0, and that a move's D depends on its cells and not on headings), and
//! `lambda` is doubled with it. [`Search::weighted_cost`] gives the path's cost in
//! [`planner_api::Cost`] units, what the test kit's weighted Dijkstra computes
//! (`tests/weighted.rs` checks it on thousands of random weighted grids).
//!
//! With 8-connected moves the seed's D counts a diagonal as one step, like an axis move,
//! while a weighted grid charges a diagonal `sqrt 2` times its weights: weighting D would
//! either break the seed's D at weight 1 or disagree with the grid's cost rule. So only the
//! 4-connected planner declares [`planner_api::PlannerSpecs::cell_costs`]; the runner
//! refuses the 8-connected one a weighted map (unless the config says `costs =
//! "ignore"`), and called directly it plans as if the grid had no weights.
//!
//! # Options
//! - 4- or 8-connected moves ([`Config::moves`]); with 8, D counts moves (a diagonal is one
//!   step, as in [`planner_api::PathMetrics`], not `sqrt 2`), and a turn is any change of
//!   heading, counted 1 whatever its angle (45, 90, 135 or 180 degrees), again as
//!   `PathMetrics` counts it. The steps heuristic is then Chebyshev, the turn bound 0 or 1.
//! - Neighbour order ([`Config::order`]): the order moves are generated, hence the FIFO
//!   order among equal keys and which of several equally good paths comes out.
//! - Dominance pruning ([`Config::dominance`], default on; see above).
//! - Tie-breaking: among OPEN entries with equal key (both components in lexicographic mode,
//!   the `f64` value in weighted mode), the entry pushed first is popped first (FIFO).
//!
//! # Counters
//! As `planner-astar`'s ([`Counter::ASTAR`]), but on states: `n_expanded` counts states
//! popped and closed (the start state and the goal state included), `n_neighbor_checks`
//! the moves tried from expanded non-goal states (4 or 8 each, the reversal included),
//! `n_blocked` targets out of bounds, blocked or corner-cut, `n_skipped` target states
//! already CLOSED, `n_open_insertions` first insertions of a state (the start's included),
//! `n_relaxations` new parent and g, `peak_open` the most states in OPEN. Two extra
//! counters follow: `n_dominated`, target states discarded by dominance, and
//! `n_cells_expanded`, the distinct cells among expanded states, to compare with A*'s
//! cell-based `n_expanded`. A budget counts state expansions; when it runs out there is
//! no path (as in A*, no complete path exists before the goal is popped). Every counter and
//! path of the lexicographic search on a grid without weights equals that of
//! `planner_testkit::reference_lexastar`, the search written again with flat arrays and
//! std's binary heap, 4- and 8-connected, with and without dominance, on 2,060 random grids
//! (`tests/reference.rs`) and on every run of the configs (xtask's
//! `every_lexastar_run_is_best_by_steps_then_turns`).
//!
//! ```
//! use planner_api::{Budget, Cell, Grid, Planner, Problem, Status};
//! use planner_lexastar::{Config, LexAStar};
//!
//! // The six shortest paths across an open 3x3 room have 4 steps and 1, 2 or 3 turns;
//! // lexastar returns one with a single turn.
//! let grid = Grid::from_ascii("
//!     ...
//!     ...
//!     ...
//! ").unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(2, 2)).unwrap();
//! let mut planner = LexAStar::new(Config::default()).unwrap();
//! let outcome = planner.plan(&problem, &Budget::unlimited());
//! assert_eq!(outcome.status, Status::Found);
//! let m = outcome.path.unwrap().metrics();
//! assert_eq!((m.steps, m.turns, m.score), (4, 1, 5));
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use planner_api::pages::Pages;
use planner_api::{
    Budget, Cell, Connectivity, Counter, Grid, IndexedMoves, MemoryShortfall, MoveOrderError,
    MoveSet, NeighborOrder, Outcome, Path, Planner, Problem, SearchStats, Status,
};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The registry name of this planner.
pub const NAME: &str = "lexastar";

/// What the search minimises.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Objective {
    /// `(D, T)` lexicographically, with exact integer pairs: seed 000's best-path rule.
    #[default]
    Lexicographic,
    /// `D + lambda * T`, evaluated in `f64` (see the crate docs).
    Weighted,
}

/// Lexicographic A*'s parameters. Every field has a default; see [`Config::default`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// Neighbourhood: 4 or 8 directions. Default 4.
    #[schemars(with = "u32", extend("enum" = [4, 8]))]
    pub moves: Connectivity,
    /// Allow diagonal moves past a blocked corner (8 only). Default false.
    pub corner_cutting: bool,
    /// Neighbour order, e.g. `"R L D U"` (see [`NeighborOrder`]). Default `"R L D U"`.
    #[schemars(with = "String")]
    pub order: NeighborOrder,
    /// What to minimise. Default [`Objective::Lexicographic`].
    pub objective: Objective,
    /// The weight of a turn in [`Objective::Weighted`]: finite and `>= 0`; ignored in
    /// lexicographic mode. Default 1 (minimise Score = D + T).
    #[schemars(range(min = 0))]
    pub lambda: f64,
    /// Discard a generated state when another state of the same cell, with one more turn,
    /// costs no more (see the crate docs); exact, and the default because it cuts the
    /// states expanded. Default true.
    pub dominance: bool,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            moves: Connectivity::Four,
            corner_cutting: false,
            order: NeighborOrder::default(),
            objective: Objective::Lexicographic,
            lambda: 1.0,
            dominance: true,
        }
    }
}

/// A parameter that lexicographic A* cannot run with.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConfigError {
    /// `moves` is not 4 or 8.
    #[error("parameter `moves` must be 4 or 8, got {0}")]
    Moves(u32),
    /// `lambda` is negative, infinite or NaN.
    #[error("parameter `lambda` must be a finite number >= 0, got {0}")]
    Lambda(f64),
    /// `order` or `corner_cutting` does not fit `moves`.
    #[error("parameter `order`/`corner_cutting`: {0}")]
    Order(#[from] MoveOrderError),
}

impl planner_api::ParamKey for ConfigError {
    fn param_key(&self) -> &str {
        match self {
            ConfigError::Moves(_) => "moves",
            ConfigError::Lambda(_) => "lambda",
            ConfigError::Order(e) => e.param_key(),
        }
    }
}

/// A cost or cost estimate: steps and turns, ordered lexicographically (steps first).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default, Serialize, Deserialize,
)]
pub struct Cost {
    /// D, the number of moves.
    pub steps: u64,
    /// T, the number of heading changes.
    pub turns: u64,
}

impl Cost {
    /// The cost `(steps, turns)`.
    pub const fn new(steps: u64, turns: u64) -> Cost {
        Cost { steps, turns }
    }

    /// Seed 000's Score, `steps + turns`.
    pub fn score(self) -> u64 {
        self.steps + self.turns
    }

    /// `steps + lambda * turns` in `f64`.
    pub fn weighted(self, lambda: f64) -> f64 {
        self.steps as f64 + lambda * self.turns as f64
    }

    /// The componentwise sum.
    pub fn plus(self, other: Cost) -> Cost {
        Cost::new(self.steps + other.steps, self.turns + other.turns)
    }
}

/// The heuristic `h((cell, heading))` towards `goal`: Manhattan (4-connected) or Chebyshev
/// (8-connected) distance for the steps, and a lower bound of 0, 1 or 2 (4-connected) or 0
/// or 1 (8-connected) for the turns (see the crate docs for the definition and the proof
/// of consistency).
///
/// `heading` is the `(dx, dy)` of the last move, `None` for the start state. Preconditions:
/// `connectivity` is [`Connectivity::Four`] or [`Connectivity::Eight`] (any other value is
/// given the 8-connected turn bound, which is not proven for larger neighbourhoods), and
/// `heading`, when given, is a unit move of that neighbourhood.
pub fn heuristic(
    connectivity: Connectivity,
    cell: Cell,
    heading: Option<(i32, i32)>,
    goal: Cell,
) -> Cost {
    let (hx, hy) = heading.unwrap_or((0, 0));
    let (steps, turns) = estimate(
        connectivity == Connectivity::Four,
        cell.x,
        cell.y,
        hx,
        hy,
        goal.x,
        goal.y,
    );
    Cost::new(steps, turns)
}

/// [`heuristic`] in the hot loop's terms; `(hx, hy) = (0, 0)` means no heading.
#[inline]
fn estimate(four: bool, x: u32, y: u32, hx: i32, hy: i32, gx: u32, gy: u32) -> (u64, u64) {
    let dx = i64::from(gx) - i64::from(x);
    let dy = i64::from(gy) - i64::from(y);
    let (sx, sy) = (dx.signum(), dy.signum());
    let (ax, ay) = (dx.unsigned_abs(), dy.unsigned_abs());
    let none = hx == 0 && hy == 0;
    if four {
        let toward = u64::from(sx != 0) + u64::from(sy != 0);
        let turns = if none {
            toward.saturating_sub(1)
        } else {
            let heading_toward =
                (hx != 0 && i64::from(hx) == sx) || (hy != 0 && i64::from(hy) == sy);
            toward - u64::from(heading_toward)
        };
        (ax + ay, turns)
    } else {
        let turns = if ax == 0 && ay == 0 {
            0
        } else if ax == 0 || ay == 0 || ax == ay {
            // In line with the unit move (sx, sy).
            u64::from(!none && (i64::from(hx), i64::from(hy)) != (sx, sy))
        } else {
            1
        };
        (ax.max(ay), turns)
    }
}

/// What a search produced, with the raw counters.
#[derive(Debug, Clone, PartialEq)]
pub struct Search {
    /// How it ended.
    pub status: Status,
    /// The path when found (cells, start first).
    pub path: Option<Path>,
    /// The path's `(D, T)` when found, D counting moves; its Score is [`Cost::score`].
    pub cost: Option<Cost>,
    /// On a weighted grid with 4-connected moves (see the crate docs), the found path's
    /// cost under the grid's rule, which the search minimised first; `None` otherwise.
    pub weighted_cost: Option<planner_api::Cost>,
    /// The counters, on states.
    pub stats: SearchStats,
    /// Distinct cells among the expanded states.
    pub n_cells_expanded: u64,
    /// Generated states discarded by dominance (see [`Config::dominance`]).
    pub n_dominated: u64,
    /// The cells of the expanded states in expansion order, when the budget asked for
    /// them ([`Budget::record_expanded`]); else empty. A cell is listed once per expanded
    /// state of it, so the list has `n_expanded` entries.
    pub expanded: Vec<Cell>,
    /// Set when the records did not fit [`Budget::max_memory_mb`] (nothing was allocated
    /// or searched).
    pub memory: Option<MemoryShortfall>,
}

/// The lexicographic A* planner. Build with [`LexAStar::new`]; reuse it for many queries.
#[derive(Debug, Clone)]
pub struct LexAStar {
    config: Config,
    moves: MoveSet,
    compiled: Option<IndexedMoves>,
    generation: u32,
    /// Per state, at `cell * n_headings + heading`; one record, so one cache line per
    /// state. Allocated in pages on first write, so memory follows the states touched.
    states: Pages<Slot>,
    /// Per cell: the best `g` of its states and when a state was first expanded (pages
    /// allocated on first write).
    cells: Pages<CellSlot>,
    lex_heap: BinaryHeap<Entry<u128>>,
    weighted_heap: BinaryHeap<Entry<Weighted>>,
}

/// What the search knows about one state.
#[derive(Debug, Clone, Copy)]
struct Slot {
    /// Best known `(D, T)` from the start.
    g: Cost,
    /// Generation when first reached; the other fields are valid only when current.
    seen: u32,
    /// The heading of the predecessor state, [`NO_HEADING`] for the start's successors.
    parent: u8,
    /// In CLOSED.
    closed: bool,
}

impl Default for Slot {
    fn default() -> Slot {
        Slot {
            g: Cost::default(),
            seen: 0,
            parent: NO_HEADING,
            closed: false,
        }
    }
}

/// What the search knows about one cell.
#[derive(Debug, Clone, Copy, Default)]
struct CellSlot {
    /// The least `g` given to any state of this cell (valid when `best_seen` is current).
    best: Cost,
    /// Generation when `best` was set.
    best_seen: u32,
    /// Generation when a state of this cell was first expanded.
    expanded: u32,
}

/// The heading of the start state, and the "parent" of the start's successors.
const NO_HEADING: u8 = u8::MAX;
/// The state id of the start state, which has no slot in the per-state arrays.
const START_STATE: usize = usize::MAX;

impl LexAStar {
    /// A planner with `config`, validated: `moves` must be 4 or 8, `lambda` finite and
    /// `>= 0`, `order` and `corner_cutting` must fit `moves`.
    pub fn new(config: Config) -> Result<LexAStar, ConfigError> {
        if !matches!(config.moves, Connectivity::Four | Connectivity::Eight) {
            return Err(ConfigError::Moves(config.moves.n_directions()));
        }
        if !config.lambda.is_finite() || config.lambda < 0.0 {
            return Err(ConfigError::Lambda(config.lambda));
        }
        let moves = MoveSet::new(config.moves, config.corner_cutting, &config.order)?;
        Ok(LexAStar {
            config,
            moves,
            compiled: None,
            generation: 0,
            states: Pages::default(),
            cells: Pages::default(),
            lex_heap: BinaryHeap::new(),
            weighted_heap: BinaryHeap::new(),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The move set in use; a state's heading is the index of its last move in it.
    pub fn move_set(&self) -> &MoveSet {
        &self.moves
    }

    /// Prepares the per-state arrays for `grid` and starts a new generation.
    fn prepare(&mut self, grid: &Grid) {
        if !self.compiled.as_ref().is_some_and(|c| c.fits(grid)) {
            self.compiled = Some(IndexedMoves::new(&self.moves, grid));
        }
        let n_states = grid.len() * self.moves.moves().len();
        if self.states.len() != n_states || self.cells.len() != grid.len() {
            self.states = Pages::new(n_states);
            self.cells = Pages::new(grid.len());
            self.generation = 0;
        }
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            self.states.fill_default();
            self.cells.fill_default();
            self.generation = 1;
        }
        self.lex_heap.clear();
        self.weighted_heap.clear();
    }

    /// The bytes of the per-state and per-cell records for `grid` with every page
    /// allocated (what a search touching every state holds): 24 bytes per state (4 or 8
    /// per cell) and 24 per cell, and the page tables.
    pub fn memory_bytes_for(&self, grid: &Grid) -> u64 {
        Pages::<Slot>::full_bytes(grid.len() * self.moves.moves().len())
            + Pages::<CellSlot>::full_bytes(grid.len())
    }

    /// The bytes the per-state and per-cell records hold now: the pages the searches on
    /// the current grid have written, and the page tables.
    pub fn resident_bytes(&self) -> usize {
        self.states.resident_bytes() + self.cells.resident_bytes()
    }

    /// Runs the search on `problem` within `budget` (counting state expansions) and returns
    /// the path with raw counters. With an exhausted budget there is no path. When
    /// [`LexAStar::memory_bytes_for`] the grid is over [`Budget::max_memory_mb`], allocates
    /// nothing, expands nothing and sets [`Search::memory`].
    pub fn search(&mut self, problem: &Problem<'_>, budget: &Budget) -> Search {
        let grid = problem.grid();
        if let Err(shortfall) = budget.check_memory(self.memory_bytes_for(grid), grid) {
            return Search {
                status: Status::BudgetExhausted,
                path: None,
                cost: None,
                weighted_cost: None,
                stats: SearchStats::default(),
                n_cells_expanded: 0,
                n_dominated: 0,
                expanded: Vec::new(),
                memory: Some(shortfall),
            };
        }
        let weighted = grid.is_weighted() && self.config.moves == Connectivity::Four;
        match (self.config.objective, weighted) {
            (Objective::Lexicographic, false) => self.run::<u128, false>(problem, budget),
            (Objective::Weighted, false) => self.run::<Weighted, false>(problem, budget),
            (Objective::Lexicographic, true) => self.run::<u128, true>(problem, budget),
            (Objective::Weighted, true) => self.run::<Weighted, true>(problem, budget),
        }
    }

    /// The search; with `WEIGHTED` (a weighted grid, 4-connected moves) D is the doubled
    /// weighted cost (crate docs).
    fn run<K: Key, const WEIGHTED: bool>(
        &mut self,
        problem: &Problem<'_>,
        budget: &Budget,
    ) -> Search {
        let grid = problem.grid();
        self.prepare(grid);
        // Doubled D doubles lambda, so `D + lambda T` keeps its order.
        let lambda = if WEIGHTED {
            2.0 * self.config.lambda
        } else {
            self.config.lambda
        };
        let (weights, (k_from, k_to), h_scale): (&[u16], (u64, u64), u64) = match grid.weights() {
            Some(w) if WEIGHTED => (w.cells(), w.rule().factors(), 2 * u64::from(w.min())),
            _ => (&[], (0, 0), 1),
        };
        let dominance = self.config.dominance;
        let four = self.config.moves == Connectivity::Four;
        let generation = self.generation;
        let LexAStar {
            compiled,
            states,
            cells,
            lex_heap,
            weighted_heap,
            ..
        } = self;
        let heap = K::heap(lex_heap, weighted_heap);
        let Some(compiled) = compiled.as_ref() else {
            unreachable!("prepare compiles the moves")
        };
        let moves = compiled.moves();
        let n_headings = moves.len();
        let free = grid.free_cells();
        let width = grid.width() as usize;
        let goal = problem.goal();
        let goal_index = grid.index(goal);
        let start_index = grid.index(problem.start());

        let mut stats = SearchStats::default();
        let mut n_cells_expanded = 0;
        let mut n_dominated = 0;
        let mut clock = budget.start();
        let mut n_pushed: u64 = 0;
        let mut n_open: u64 = 1;
        let (m0, t0) = estimate(
            four,
            problem.start().x,
            problem.start().y,
            0,
            0,
            goal.x,
            goal.y,
        );
        let m0 = if WEIGHTED { m0 * h_scale } else { m0 };
        let record = budget.record_expanded;
        let mut expanded = Vec::new();
        let start_cell = cells.get_mut(start_index);
        start_cell.best = Cost::default();
        start_cell.best_seen = generation;
        heap.push(Entry {
            key: K::key(Cost::new(m0, t0), lambda),
            seq: 0,
            state: START_STATE,
        });
        n_pushed += 1;
        stats.n_open_insertions = 1;
        stats.peak_open = 1;

        while let Some(entry) = heap.pop() {
            let state = entry.state;
            let (node, heading, g_state) = if state == START_STATE {
                (start_index, NO_HEADING, Cost::default())
            } else {
                let slot = states.get(state);
                if slot.closed {
                    continue; // A stale entry of a state improved after it was pushed.
                }
                (state / n_headings, (state % n_headings) as u8, slot.g)
            };
            if !clock.allows(stats.n_expanded) {
                return Search {
                    status: Status::BudgetExhausted,
                    path: None,
                    cost: None,
                    weighted_cost: None,
                    stats,
                    n_cells_expanded,
                    n_dominated,
                    expanded,
                    memory: None,
                };
            }
            if state != START_STATE {
                states.get_mut(state).closed = true;
            }
            n_open -= 1;
            stats.n_expanded += 1;
            if record {
                expanded.push(grid.cell(node));
            }
            let node_cell = cells.get_mut(node);
            if node_cell.expanded != generation {
                node_cell.expanded = generation;
                n_cells_expanded += 1;
            }
            if node == goal_index {
                let path = reconstruct(grid, compiled, states, state, start_index);
                return Search {
                    status: Status::Found,
                    weighted_cost: WEIGHTED.then(|| {
                        planner_api::Cost::from_units(
                            g_state
                                .steps
                                .saturating_mul(planner_api::Cost::ONE.units() / 2),
                        )
                    }),
                    cost: Some(if WEIGHTED {
                        Cost::new(path.len() as u64 - 1, g_state.turns)
                    } else {
                        g_state
                    }),
                    path: Some(path),
                    stats,
                    n_cells_expanded,
                    n_dominated,
                    expanded,
                    memory: None,
                };
            }
            let x = (node % width) as u32;
            let y = (node / width) as u32;
            for (k, mv) in moves.iter().enumerate() {
                stats.n_neighbor_checks += 1;
                let Some(next) = compiled.target(free, x, y, node, k) else {
                    stats.n_blocked += 1;
                    continue;
                };
                let next_state = next * n_headings + k;
                let slot = states.get_mut(next_state);
                let known = slot.seen == generation;
                if known && slot.closed {
                    stats.n_skipped += 1;
                    continue;
                }
                let turn = u64::from(heading != NO_HEADING && usize::from(heading) != k);
                let step = if WEIGHTED {
                    k_from * u64::from(weights[node]) + k_to * u64::from(weights[next])
                } else {
                    1
                };
                let g_next = Cost::new(g_state.steps + step, g_state.turns + turn);
                let cell = cells.get_mut(next);
                if dominance && cell.best_seen == generation {
                    // Another state of this cell, plus one turn, is at least as good.
                    let with_turn = Cost::new(cell.best.steps, cell.best.turns + 1);
                    if !K::better(g_next, with_turn, lambda) {
                        n_dominated += 1;
                        continue;
                    }
                }
                if !known || K::better(g_next, slot.g, lambda) {
                    stats.n_relaxations += 1;
                    if !known {
                        slot.seen = generation;
                        slot.closed = false;
                        stats.n_open_insertions += 1;
                        n_open += 1;
                        stats.peak_open = stats.peak_open.max(n_open);
                    }
                    slot.g = g_next;
                    slot.parent = heading;
                    if cell.best_seen != generation || K::better(g_next, cell.best, lambda) {
                        cell.best = g_next;
                        cell.best_seen = generation;
                    }
                    let nx = x.wrapping_add_signed(mv.dx);
                    let ny = y.wrapping_add_signed(mv.dy);
                    let (hm, ht) = estimate(four, nx, ny, mv.dx, mv.dy, goal.x, goal.y);
                    let hm = if WEIGHTED { hm * h_scale } else { hm };
                    heap.push(Entry {
                        key: K::key(g_next.plus(Cost::new(hm, ht)), lambda),
                        seq: n_pushed,
                        state: next_state,
                    });
                    n_pushed += 1;
                }
            }
        }
        Search {
            status: Status::NoPath,
            path: None,
            cost: None,
            weighted_cost: None,
            stats,
            n_cells_expanded,
            n_dominated,
            expanded,
            memory: None,
        }
    }
}

/// Follows parent headings from `state` back to the start. `state` is a goal state or
/// [`START_STATE`].
fn reconstruct(
    grid: &Grid,
    compiled: &IndexedMoves,
    states: &Pages<Slot>,
    state: usize,
    start_index: usize,
) -> Path {
    let n_headings = compiled.len();
    let moves = compiled.moves();
    if state == START_STATE {
        return Path::new(vec![grid.cell(start_index)]);
    }
    let mut node = state / n_headings;
    let mut heading = state % n_headings;
    let mut cells = vec![grid.cell(node)];
    loop {
        // The predecessor is one move back along this state's heading, with the heading
        // stored as this state's parent.
        let previous = states.get(node * n_headings + heading).parent;
        node = (node as isize - moves[heading].delta) as usize;
        cells.push(grid.cell(node));
        if previous == NO_HEADING {
            break;
        }
        heading = usize::from(previous);
    }
    cells.reverse();
    Path::new(cells)
}

impl Planner for LexAStar {
    fn name(&self) -> &str {
        NAME
    }

    /// Declares [`planner_api::PlannerSpecs::cell_costs`] with 4-connected moves only (see
    /// the crate docs).
    fn specs(&self) -> planner_api::PlannerSpecs {
        let specs = planner_api::PlannerSpecs::deterministic(planner_api::PathSpec::Moves(
            self.moves.clone(),
        ));
        if self.config.moves == Connectivity::Four {
            specs.with_cell_costs()
        } else {
            specs.with_cell_costs_only_with(
                "moves",
                "4",
                "the seed's D counts a diagonal as one step, where a weighted grid charges \
                 sqrt 2 times its weights",
            )
        }
    }

    /// Lists the cells of the expanded states when the budget asks
    /// ([`Budget::record_expanded`]), one per `n_expanded` (a cell once per expanded state
    /// of it; `n_cells_expanded` counts the distinct ones); refuses with
    /// [`Outcome::over_memory`] when [`LexAStar::memory_bytes_for`] the grid is over
    /// [`Budget::max_memory_mb`].
    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        let search = self.search(problem, budget);
        let counters = search
            .stats
            .report(Counter::ASTAR)
            .with("n_dominated", search.n_dominated)
            .with("n_cells_expanded", search.n_cells_expanded);
        match search.memory {
            Some(shortfall) => Outcome::over_memory(shortfall, counters),
            None => {
                Outcome::new(search.status, search.path, counters).with_expanded(search.expanded)
            }
        }
    }
}

/// A heap key for one objective.
trait Key: Copy + Ord {
    /// The key of an entry whose `f = g + h` is `f`.
    fn key(f: Cost, lambda: f64) -> Self;
    /// Whether `new` is strictly better than `old` as a `g`.
    fn better(new: Cost, old: Cost, lambda: f64) -> bool;
    /// This key's heap among the planner's two.
    fn heap<'a>(
        lex: &'a mut BinaryHeap<Entry<u128>>,
        weighted: &'a mut BinaryHeap<Entry<Weighted>>,
    ) -> &'a mut BinaryHeap<Entry<Self>>;
}

/// Lexicographic `(steps, turns)` packed as `steps << 64 | turns`.
impl Key for u128 {
    #[inline]
    fn key(f: Cost, _lambda: f64) -> u128 {
        (u128::from(f.steps) << 64) | u128::from(f.turns)
    }

    #[inline]
    fn better(new: Cost, old: Cost, _lambda: f64) -> bool {
        new < old
    }

    fn heap<'a>(
        lex: &'a mut BinaryHeap<Entry<u128>>,
        _weighted: &'a mut BinaryHeap<Entry<Weighted>>,
    ) -> &'a mut BinaryHeap<Entry<u128>> {
        lex
    }
}

/// `steps + lambda * turns`, ordered by `f64::total_cmp` (never NaN: lambda is finite).
#[derive(Debug, Clone, Copy)]
struct Weighted(f64);

impl Ord for Weighted {
    fn cmp(&self, other: &Weighted) -> Ordering {
        self.0.total_cmp(&other.0)
    }
}

impl PartialOrd for Weighted {
    fn partial_cmp(&self, other: &Weighted) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for Weighted {
    fn eq(&self, other: &Weighted) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Weighted {}

impl Key for Weighted {
    #[inline]
    fn key(f: Cost, lambda: f64) -> Weighted {
        Weighted(f.weighted(lambda))
    }

    #[inline]
    fn better(new: Cost, old: Cost, lambda: f64) -> bool {
        new.weighted(lambda) < old.weighted(lambda)
    }

    fn heap<'a>(
        _lex: &'a mut BinaryHeap<Entry<u128>>,
        weighted: &'a mut BinaryHeap<Entry<Weighted>>,
    ) -> &'a mut BinaryHeap<Entry<Weighted>> {
        weighted
    }
}

/// An OPEN entry; the heap pops the greatest, so the order is reversed: least key first,
/// then the least push sequence number (FIFO).
#[derive(Debug, Clone, Copy)]
struct Entry<K> {
    key: K,
    seq: u64,
    state: usize,
}

impl<K: Ord> Ord for Entry<K> {
    fn cmp(&self, other: &Entry<K>) -> Ordering {
        other
            .key
            .cmp(&self.key)
            .then_with(|| other.seq.cmp(&self.seq))
    }
}

impl<K: Ord> PartialOrd for Entry<K> {
    fn partial_cmp(&self, other: &Entry<K>) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl<K: Ord> PartialEq for Entry<K> {
    fn eq(&self, other: &Entry<K>) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl<K: Ord> Eq for Entry<K> {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heuristic_by_hand() {
        let four = Connectivity::Four;
        let eight = Connectivity::Eight;
        let goal = Cell::new(3, 3);
        let at = |x, y| Cell::new(x, y);
        // Off both axes: goal is right and down. Heading right or down: one turn left;
        // heading left or up: two; no heading: one.
        assert_eq!(
            heuristic(four, at(0, 0), Some((1, 0)), goal),
            Cost::new(6, 1)
        );
        assert_eq!(
            heuristic(four, at(0, 0), Some((0, 1)), goal),
            Cost::new(6, 1)
        );
        assert_eq!(
            heuristic(four, at(0, 0), Some((-1, 0)), goal),
            Cost::new(6, 2)
        );
        assert_eq!(
            heuristic(four, at(0, 0), Some((0, -1)), goal),
            Cost::new(6, 2)
        );
        assert_eq!(heuristic(four, at(0, 0), None, goal), Cost::new(6, 1));
        // Same column, goal below: heading down 0, anything else 1, no heading 0.
        assert_eq!(
            heuristic(four, at(3, 1), Some((0, 1)), goal),
            Cost::new(2, 0)
        );
        assert_eq!(
            heuristic(four, at(3, 1), Some((0, -1)), goal),
            Cost::new(2, 1)
        );
        assert_eq!(
            heuristic(four, at(3, 1), Some((1, 0)), goal),
            Cost::new(2, 1)
        );
        assert_eq!(heuristic(four, at(3, 1), None, goal), Cost::new(2, 0));
        assert_eq!(heuristic(four, goal, Some((-1, 0)), goal), Cost::new(0, 0));
        // 8-connected: the diagonal (0,0)-(3,3) is in line with down-right.
        assert_eq!(
            heuristic(eight, at(0, 0), Some((1, 1)), goal),
            Cost::new(3, 0)
        );
        assert_eq!(
            heuristic(eight, at(0, 0), Some((1, 0)), goal),
            Cost::new(3, 1)
        );
        assert_eq!(heuristic(eight, at(0, 0), None, goal), Cost::new(3, 0));
        // Off line: (1, 0) to (3, 3) needs two directions.
        assert_eq!(
            heuristic(eight, at(1, 0), Some((1, 1)), goal),
            Cost::new(3, 1)
        );
        assert_eq!(heuristic(eight, at(1, 0), None, goal), Cost::new(3, 1));
        assert_eq!(heuristic(eight, goal, Some((1, 0)), goal), Cost::new(0, 0));
    }

    #[test]
    fn cost_order_is_lexicographic() {
        assert!(Cost::new(10, 5) < Cost::new(11, 0));
        assert!(Cost::new(10, 2) < Cost::new(10, 3));
        assert_eq!(Cost::new(10, 2).score(), 12);
        assert_eq!(Cost::new(10, 2).weighted(0.5), 11.0);
        let a = <u128 as Key>::key(Cost::new(10, 5), 0.0);
        let b = <u128 as Key>::key(Cost::new(11, 0), 0.0);
        assert!(a < b);
    }
}
