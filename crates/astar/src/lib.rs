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
//! The main decision is to make every search allocation-free after the first: the
//! per-cell arrays live in the planner and are not cleared between searches but reset
//! through the list of cells the last search inserted into OPEN, so a query touching 100
//! cells of a 512 x 512 map costs 100 cells, not 262,144. They are small, so that a
//! search's neighbour tests hit the cache: one status byte per cell (unseen, OPEN, CLOSED,
//! and the move it was reached by, which gives the path back), and `g`, read only for
//! cells already in OPEN. Moves come from planner-api's [`Adjacency`] (padded layout and
//! per-move index offsets, so the neighbour loop has no bounds test). For 4 and 8
//! directions the safe moves of a cell come from a bit-packed copy of the grid instead of
//! the adjacency's 8-byte masks: its 3 x 3 neighbourhood (three 2-byte loads) indexes a
//! 512-entry table; the same code of a bit-packed CLOSED set masks out the moves to
//! CLOSED cells at once (they are the skipped checks), so the loop over the remaining
//! moves has no branch on CLOSED. The blocked checks are counted as the clear bits.
//!
//! Memory is bounded by the work, not the grid, except for the bit grid (one bit per
//! cell): the per-cell arrays (status byte, `g`, CLOSED bits) are allocated zeroed, so the
//! operating system commits their pages only when a search first writes them, and with
//! the bit grid A* builds no [`Adjacency`] (whose masks take 8 bytes per cell). Before
//! sizing them for a grid, a search checks their full size (what a search touching every
//! cell would commit) against [`Budget::max_memory_mb`] and, when it does not fit,
//! returns [`Outcome::over_memory`] without allocating.
//!
//! With [`Budget::record_expanded`] set, [`Outcome::expanded`] lists the expanded cells in
//! expansion order (the goal last when found), one per `n_expanded`; the search is
//! otherwise the same. The flag is a constant of the search loop, so with it off the loop
//! has no recording code; the recording copies read the heuristic at run time (one copy
//! for all five heuristics: figures are never timed, and the build is shorter). With
//! [`Budget::record_events`] set, [`Outcome::events`] records the search step by step in
//! the same copy: every push into OPEN (`generating` a node's first, `updating` one that
//! lowers its `g`) and every expansion, each with the node's parent, `g` and `f` (as OPEN
//! orders it: `g` plus the heuristic times the configured weight, and on a weighted grid
//! times the smallest cell weight), at most [`planner_api::MAX_SEARCH_EVENTS`] of them.
//! `tests/events.rs` holds them to the counters, the expanded cells, the path and the
//! heuristics written out.
//!
//! Costs are [`planner_api::Cost`]s, fixed point in units of `2^-32`: every path cost
//! is an integer sum of its moves' costs, so equal path costs are equal numbers and tie
//! exactly, whatever the order of the moves (proven exact for 4 and 8 directions up to
//! costs of 251,797; ties exact and an epsilon of half a unit per move for longer moves;
//! see [`planner_api::cost`]). With `f64` sums of `sqrt 2`, rounding noise broke ties and
//! high-g-first expanded 25 % more nodes on the Moving AI random maps.
//!
//! OPEN (planner-search's `bucket` module) gives entries out in exactly the order of the full key (f, tie,
//! push sequence), and is chosen per search by what the costs allow. With unit moves and
//! an integer heuristic that changes by at most 1 per move (Manhattan, Chebyshev, zero) and
//! weight 0 or 1, `f` is an integer that never drops along an edge and rises by at most 2,
//! so OPEN is four slots of one `f` each: a queue (FIFO), a stack (LIFO), or runs of equal
//! `g` (high g first; a child always lands on top). Otherwise it is a ring of `f` buckets
//! of width 1/16 in front of the least bucket, sorted when it comes up, with a binary heap
//! for the entries pushed into it since, itself behind a sorted front of eight entries that
//! catches the common new minimum. An improved node is
//! pushed again and its older entry is skipped when it comes out (the node is then
//! CLOSED), or dropped unseen when its bucket comes up; `peak_open` counts nodes in OPEN,
//! not entries. The tests hold every variant to a plain `BinaryHeap` transcription of
//! Fig. 4, counter for counter.
//!
//! # Weighted grids
//! On a grid with cell weights ([`planner_api::weights`]) a move costs its length times
//! the weights by the grid's [`planner_api::CostRule`] (the mean of the two cells' weights
//! by default, or the entered cell's), in exact integer [`Cost`] units: half the move's
//! length times `k_from * w(from) + k_to * w(to)`, one multiplication per relaxed move. The
//! heuristic is multiplied by the grid's smallest weight `w_min`, so it stays admissible
//! and consistent (every move costs at least its length times `w_min`), and with it found
//! paths are least-cost with 4 and 8 directions (held to the test kit's weighted Dijkstra
//! on 10,000 random grids in `tests/weighted.rs`). A move of 16, 32 or 48 directions is
//! charged by the same rule for its two end cells only, not for the cells it crosses, so
//! such a path may cross costly cells without paying for them: A* declares
//! [`PlannerSpecs::cell_costs`](planner_api::PlannerSpecs::cell_costs) with 4 and 8
//! directions only (with longer moves its specs name `moves` in
//! [`PlannerSpecs::cell_costs_only_with`](planner_api::PlannerSpecs::cell_costs_only_with)),
//! and the runner refuses it a weighted map unless the config says `costs = "ignore"`.
//! Weighted searches run a second copy of the search loop (a
//! const generic), always with the bucket OPEN, whose ring is sized for the largest
//! weighted move; the unweighted loop has no weight code at all, so unweighted searches
//! and their counters are unchanged. The zero heuristic makes this Dijkstra's algorithm.
//!
//! ```
//! use planner_api::{Budget, Cell, Cost, CostRule, Grid, Problem};
//! use planner_astar::{AStar, Config};
//!
//! // A heavy cell (weight 9) between start and goal: going around it is cheaper.
//! let grid = Grid::from_ascii("...\n...").unwrap();
//! let grid = grid.with_weights(vec![1, 9, 1, 1, 1, 1], CostRule::Mean).unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(2, 0)).unwrap();
//! let search = AStar::new(Config::default()).unwrap().search(&problem, &Budget::unlimited());
//! // Straight: (1 + 9) / 2 + (9 + 1) / 2 = 10; around: four moves of weight 1 = 4.
//! assert_eq!(search.exact_cost, Some(Cost::steps(4)));
//! assert_eq!(search.path.unwrap().cells().len(), 5);
//! ```
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

use planner_api::SearchEventKind::{Expanding, Generating, Updating};
use planner_api::{
    Adjacency, Budget, Cell, Connectivity, Cost, CostRule, Counter, Grid, MemoryShortfall,
    MoveOrderError, MoveSet, NeighborOrder, Outcome, Path, Planner, Problem, SearchEvent,
    SearchStats, Status,
};
use planner_search::bucket::{self as open, BucketOpen, IntOpen, Open};
use planner_search::neighbourhood::{
    set_free_cells, update_free_cells, MoveTable, PaddedWeights, BIT_COUNT,
};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The registry name of this planner.
pub const NAME: &str = "astar";

/// The heuristic `h(n)`, a distance estimate from `n` to the goal.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default, schemars::JsonSchema,
)]
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

    /// The estimate from `(x, y)` to `(gx, gy)`, as `f64`.
    pub fn estimate(self, x: u32, y: u32, gx: u32, gy: u32) -> f64 {
        self.cost(x, y, gx, gy).to_f64()
    }

    /// The estimate from `(x, y)` to `(gx, gy)` in the fixed point A* searches with:
    /// exact for Manhattan, Chebyshev, zero and octile (`(max - min) + min * sqrt 2` as
    /// [`Cost::octile`], the same sum as the costs of the moves), Euclidean rounded to the
    /// nearest unit of `2^-32` ([`Cost::euclidean`]).
    #[inline]
    pub fn cost(self, x: u32, y: u32, gx: u32, gy: u32) -> Cost {
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
/// `f` and `g` are [`Cost`]s, so equality is exact: two paths of equal length, whatever
/// the order of their moves, tie (see [`planner_api::cost`] for the proof and its limits).
/// With the Euclidean heuristic or a weight other than 0 and 1, `h` is rounded to the
/// nearest `2^-32`.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum TieBreak {
    /// The entry pushed first is popped first (the paper's rule). A node improved while in
    /// OPEN is pushed again with a lower f (its h is unchanged), so its newer entry comes
    /// out first.
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// Neighbourhood: 4, 8, 16, 32 or 48 directions. Default 4.
    #[schemars(with = "u32", extend("enum" = [4, 8, 16, 32, 48]))]
    pub moves: Connectivity,
    /// Allow diagonal moves between two blocked orthogonal cells' corner (8 only). Default false.
    pub corner_cutting: bool,
    /// Neighbour order, e.g. `"R L D U"` (see [`NeighborOrder`]). Default `"R L D U"`.
    #[schemars(with = "String")]
    pub order: NeighborOrder,
    /// Heuristic. Default Manhattan.
    pub heuristic: Heuristic,
    /// Seed 002's `beta` in `f = g + beta * h`: finite and `>= 0`. Default 1.
    #[schemars(range(min = 0))]
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
    /// The path's cost `g(goal)` when found (steps on 4-connected grids, else Euclidean length;
    /// on a weighted grid the weighted cost, [`planner_api::weights`]).
    pub cost: Option<f64>,
    /// `g(goal)` exactly, in [`Cost`] units, when found.
    pub exact_cost: Option<Cost>,
    /// The counters.
    pub stats: SearchStats,
    /// The expanded cells in expansion order, when the budget asked for them
    /// ([`Budget::record_expanded`]); else empty.
    pub expanded: Vec<Cell>,
    /// The search step by step, when the budget asked for it ([`Budget::record_events`]):
    /// every push into OPEN (`generating` the first time, `updating` after) and every
    /// expansion, with parent, `g` and `f`, at most [`planner_api::MAX_SEARCH_EVENTS`].
    pub events: Vec<SearchEvent>,
    /// Set when the per-cell state did not fit [`Budget::max_memory_mb`] (nothing was
    /// allocated or searched).
    pub memory: Option<MemoryShortfall>,
}

impl Search {
    fn new(status: Status, path: Option<Path>, cost: Option<f64>, stats: SearchStats) -> Search {
        Search {
            status,
            path,
            cost,
            exact_cost: None,
            stats,
            expanded: Vec::new(),
            events: Vec::new(),
            memory: None,
        }
    }
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
    cells: Cells,
    bits: FreeBits,
    /// Whether the integer OPEN fits the moves, heuristic and weight (else the buckets).
    integral: bool,
    opens: Opens,
    /// The OPEN lists of searches on weighted grids (always the bucket form), configured
    /// for the largest move cost they were last used with.
    weighted_opens: Opens,
    weighted_max_cost: Option<Cost>,
    /// A weighted grid's weights in the padded layout.
    weight_cells: PaddedWeights,
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

/// Padded index to cell coordinates without a division instruction: for `p < 2^32`,
/// `floor(p / stride) = (p * ceil(2^64 / stride)) >> 64` exactly (Lemire, Kaser and Kurz,
/// "Faster remainder by direct computation", 2019, Theorem 1: 64 bits of reciprocal
/// suffice for 32-bit numerators and divisors).
#[derive(Debug, Clone, Copy)]
struct Rows {
    stride: u64,
    reciprocal: u64,
    reach: u64,
}

impl Rows {
    /// Precondition: `stride >= 2`.
    fn new(stride: usize, reach: usize) -> Rows {
        let stride = stride as u64;
        Rows {
            stride,
            reciprocal: u64::MAX / stride + 1,
            reach: reach as u64,
        }
    }

    /// The grid cell `(x, y)` of padded index `p`, as [`Adjacency::cell`].
    #[inline(always)]
    fn cell(&self, p: usize) -> (u32, u32) {
        let p = p as u64;
        let row = if p <= u64::from(u32::MAX) {
            ((u128::from(self.reciprocal) * u128::from(p)) >> 64) as u64
        } else {
            p / self.stride
        };
        let column = p - row * self.stride;
        ((column - self.reach) as u32, (row - self.reach) as u32)
    }
}

/// A cell's status bits in `AStar::state`: not yet seen by this search.
const UNSEEN: u8 = 0;
/// Inserted into OPEN (and still there unless also `CLOSED`).
const OPEN: u8 = 1;
/// Expanded (set together with `OPEN`).
const CLOSED: u8 = 3;
/// The status bits.
const STATUS: u8 = 3;

/// The per-cell search state, kept between searches.
#[derive(Debug, Clone, Default)]
struct Cells {
    /// Per padded cell: `parent move << 2 | status` (`UNSEEN`, `OPEN` or `OPEN | CLOSED`),
    /// one byte so that the neighbour tests read an array a quarter of a megabyte for
    /// 512 x 512 cells, which stays in cache.
    state: Vec<u8>,
    /// Per padded cell: `g` in [`Cost`] units, valid where `state` is not `UNSEEN`. Raw
    /// `u64`s so that the array is allocated zeroed (`calloc`): like `state` and `closed`,
    /// the operating system commits its pages when a search first writes them, so a
    /// search that touches few cells of a large grid commits little of it.
    g: Vec<u64>,
    /// The cells the last search inserted into OPEN: [`Cells::fit`] resets exactly those.
    touched: Vec<u32>,
    /// With the bit grid ([`FreeBits`]) and moves other than the four axis ones
    /// ([`moves_beside`]): the CLOSED cells as bits in its layout.
    closed: Vec<u8>,
}

/// [`Cells::fit`] clears the per-cell arrays whole when the last search touched at least
/// this share (one in so many) of the cells.
const WHOLE_RESET_SHARE: usize = 16;

impl Cells {
    /// Bytes per padded cell of the per-cell arrays at their full size (what a search
    /// that reaches every cell commits): state, `g`, `touched`, and the CLOSED bits.
    const BYTES_PER_CELL: f64 = 1.0 + 8.0 + 4.0 + 0.125;

    /// Sizes the arrays for `padded_len` cells (and the CLOSED bits when `with_bits`),
    /// and resets the cells the last search touched, so that every cell is unseen.
    fn fit(&mut self, padded_len: usize, with_bits: bool) {
        if self.state.len() != padded_len {
            self.state = vec![UNSEEN; padded_len];
            self.g = vec![0; padded_len];
            self.closed.clear();
            self.touched.clear();
        }
        if with_bits && self.closed.len() != padded_len / 8 + 3 {
            self.closed = vec![0; padded_len / 8 + 3];
        }
        // Every cell the last search saw went through OPEN: reset those, and only those,
        // unless they are many, when clearing the arrays whole (sequential stores) is the
        // cheaper.
        if self.touched.len() >= padded_len / WHOLE_RESET_SHARE {
            self.state.fill(UNSEEN);
            self.closed.fill(0);
        } else {
            for &q in &self.touched {
                self.state[q as usize] = UNSEEN;
                if let Some(byte) = self.closed.get_mut(q as usize / 8) {
                    *byte = 0;
                }
            }
        }
        self.touched.clear();
    }
}

/// The padded layout of planner-api's [`Adjacency`] (the grid inside a border of `reach`
/// cells, row-major) without its per-cell move masks: what the search needs to index cells
/// and follow moves. With the bit grid ([`FreeBits`]) the masks are not needed, so A*
/// then builds no [`Adjacency`], which would take 8 bytes per cell up front.
#[derive(Debug, Clone, Copy)]
struct Layout {
    reach: usize,
    stride: usize,
    padded_len: usize,
    delta: [isize; 64],
    n_moves: usize,
}

impl Layout {
    /// The layout [`Adjacency::build`] gives `grid` and `moves` (the same formulas).
    fn new(grid: &Grid, moves: &MoveSet) -> Layout {
        let reach = moves
            .moves()
            .iter()
            .map(|m| m.dx.unsigned_abs().max(m.dy.unsigned_abs()) as usize)
            .max()
            .unwrap_or(1);
        let stride = grid.width() as usize + 2 * reach;
        let padded_len = stride * (grid.height() as usize + 2 * reach);
        let mut delta = [0isize; 64];
        for (slot, mv) in delta.iter_mut().zip(moves.moves()) {
            *slot = (i64::from(mv.dy) * stride as i64 + i64::from(mv.dx)) as isize;
        }
        Layout {
            reach,
            stride,
            padded_len,
            delta,
            n_moves: moves.moves().len(),
        }
    }

    /// Whether the search uses the bit grid (moves of reach 1: 4 and 8 directions).
    fn uses_bits(&self) -> bool {
        self.reach == 1 && self.n_moves <= 8
    }

    /// The padded index of `cell`, as [`Adjacency::index`].
    #[inline]
    fn index(&self, cell: Cell) -> usize {
        (cell.y as usize + self.reach) * self.stride + cell.x as usize + self.reach
    }

    /// The cell of padded index `p`, as [`Adjacency::cell`].
    fn cell(&self, p: usize) -> Cell {
        Cell::new(
            (p % self.stride - self.reach) as u32,
            (p / self.stride - self.reach) as u32,
        )
    }

    /// The target of move `m` from padded cell `p`, as [`Adjacency::neighbor`].
    #[inline(always)]
    fn neighbor(&self, p: usize, m: u32) -> usize {
        p.wrapping_add_signed(self.delta[(m & 63) as usize])
    }

    /// The bytes A* needs for `grid` at most: the per-cell arrays at full size, the bit
    /// grid or the adjacency ([`Adjacency::bytes_for`]: its masks, its copy of the grid
    /// and what its build packs), and on a weighted grid the padded weights (2 bytes a
    /// cell). `moves` are the set this layout is for.
    fn state_bytes(&self, grid: &Grid, moves: &MoveSet) -> u64 {
        let padded = self.padded_len as f64;
        let tables = if self.uses_bits() {
            padded / 8.0
        } else {
            Adjacency::bytes_for(grid, moves) as f64
        };
        let weights = if grid.is_weighted() {
            2.0 * padded
        } else {
            0.0
        };
        (padded * Cells::BYTES_PER_CELL + tables + weights).ceil() as u64
    }
}

/// `prepare` builds an [`Adjacency`] (16 directions and more) only up to this many bytes
/// of masks; a larger one is built by the first search, after its memory check.
const PREPARE_ADJACENCY_LIMIT: usize = 256 << 20;

/// The free cells of the grid as one bit per padded cell (the layout of [`Adjacency`]),
/// and for move sets of reach 1 (4 and 8 directions) a table from the 3 x 3
/// neighbourhood of a cell to its safe moves: a node's move mask then comes from three
/// 2-byte loads from an array of `padded cells / 8` bytes (33 KB for 512 x 512, which stays
/// in the L1 cache) instead of an 8-byte load per cell from the masks (2 MB); for the four
/// axis moves, from three loads ([`FreeBits::safe_beside`]).
#[derive(Debug, Clone, Default)]
struct FreeBits {
    /// The grid revision the bits were built for.
    revision: Option<u64>,
    /// Bit `p % 8` of byte `p / 8` is set when padded cell `p` is free; two bytes of slack.
    bytes: Vec<u8>,
    /// Padded row length.
    stride: usize,
    /// Safe-move mask by neighbourhood code: bit `3 * (dy + 1) + (dx + 1)` is the cell at
    /// offset `(dx, dy)` (planner-search's table, as Theta\*'s).
    table: MoveTable,
    /// By neighbourhood code: the moves whose target is set in the code.
    target_table: MoveTable,
}

impl FreeBits {
    /// The bits of `grid` when `moves` reach one cell (built on first use of a grid), else
    /// `None` (the search then reads the adjacency masks).
    fn get_or_build(
        &mut self,
        grid: &planner_api::Grid,
        layout: &Layout,
        moves: &MoveSet,
    ) -> Option<&FreeBits> {
        if !layout.uses_bits() {
            return None;
        }
        let same_layout =
            self.stride == layout.stride && self.bytes.len() == layout.padded_len / 8 + 3;
        match self.revision {
            Some(revision) if revision == grid.revision() && same_layout => {}
            // Edited in place since: the edited cells' bits follow.
            Some(revision) if same_layout => match grid.changed_since(revision) {
                Some(changed) => {
                    update_free_cells(&mut self.bytes, grid, changed, layout.reach, layout.stride);
                    self.revision = Some(grid.revision());
                }
                None => self.build(grid, layout, moves),
            },
            _ => self.build(grid, layout, moves),
        }
        Some(self)
    }

    /// Fills the bits of `grid` in `layout` and the tables of `moves`.
    fn build(&mut self, grid: &planner_api::Grid, layout: &Layout, moves: &MoveSet) {
        self.stride = layout.stride;
        self.bytes.clear();
        self.bytes.resize(layout.padded_len / 8 + 3, 0);
        set_free_cells(&mut self.bytes, grid, layout.reach, layout.stride);
        self.table = MoveTable::safe(moves);
        self.target_table = MoveTable::targets(moves);
        self.revision = Some(grid.revision());
    }

    /// Three bits of `bits` (this layout) from bit `shift` of byte `byte` on.
    #[inline(always)]
    fn three(bits: &[u8], byte: usize, shift: usize) -> usize {
        // One range check and one two-byte load (indexing the two bytes apart took two
        // of each: the profile's hottest line). Out of range cannot happen for a grid
        // cell's neighbourhood (two bytes of slack); it would read as blocked.
        match bits.get(byte..byte + 2) {
            Some(&[low, high]) => (usize::from(u16::from_le_bytes([low, high])) >> shift) & 7,
            _ => 0,
        }
    }

    /// The safe moves from padded cell `p` (a free grid cell) for a move set of at most
    /// [`FEW_MOVES`] moves along the axes: the neighbourhood code of the four cells beside
    /// `p` only (three loads rather than three two-byte ones), as [`FreeBits::masks`] gives.
    #[inline(always)]
    fn safe_beside(&self, p: usize) -> u64 {
        let bit = |at: usize| {
            self.bytes
                .get(at / 8)
                .map_or(0, |&byte| usize::from(byte >> (at % 8) & 1))
        };
        // Bit 3 (dy + 1) + dx + 1 of the code is the cell at offset (dx, dy).
        let code = bit(p - self.stride) << 1
            | Self::three(&self.bytes, (p - 1) / 8, (p - 1) % 8) << 3
            | bit(p + self.stride) << 7;
        self.table.get(code)
    }

    /// The safe moves from padded cell `p` (a free grid cell), as [`Adjacency::mask`], and
    /// the moves from `p` whose target is set in `closed` (this layout). The two 3 x 3
    /// neighbourhood codes are read at the same byte offsets, computed once.
    #[inline(always)]
    fn masks(&self, closed: &[u8], p: usize) -> (u64, u64) {
        let (mut free, mut shut) = (0, 0);
        for (row, at) in [p - self.stride - 1, p - 1, p + self.stride - 1]
            .into_iter()
            .enumerate()
        {
            let (byte, shift) = (at / 8, at % 8);
            free |= Self::three(&self.bytes, byte, shift) << (3 * row);
            shut |= Self::three(closed, byte, shift) << (3 * row);
        }
        (self.table.get(free), self.target_table.get(shut))
    }
}

impl AStar {
    /// A planner with `config`, validated.
    pub fn new(config: Config) -> Result<AStar, ConfigError> {
        if !config.weight.is_finite() || config.weight < 0.0 {
            return Err(ConfigError::Weight(config.weight));
        }
        let moves = MoveSet::new(config.moves, config.corner_cutting, &config.order)?;
        let costs = || moves.moves().iter().map(|m| m.exact_cost());
        let integral = IntOpen::<{ open::FIFO }>::fits(
            costs(),
            config.weight,
            config.heuristic.is_consistent_integer_on_unit_moves(),
        );
        let mut opens = Opens::default();
        if !integral {
            let max_cost = costs().max().unwrap_or(Cost::ONE);
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
            cells: Cells::default(),
            bits: FreeBits::default(),
            opens,
            weighted_opens: Opens::default(),
            weighted_max_cost: None,
            weight_cells: PaddedWeights::default(),
        })
    }

    /// The bytes a search on `grid` needs at most (its memory check): the per-cell arrays
    /// at full size, the bit grid or the adjacency's masks, and on a weighted grid the
    /// padded weights.
    pub fn memory_bytes_for(&self, grid: &Grid) -> u64 {
        Layout::new(grid, &self.moves).state_bytes(grid, &self.moves)
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The move set in use.
    pub fn move_set(&self) -> &MoveSet {
        &self.moves
    }

    /// The bytes of the per-grid tables the planner holds, which are written in full
    /// when built: the bit grid (4 and 8 directions) or the adjacency's masks and copy of
    /// the grid (more directions). The per-cell search arrays are not counted: they are
    /// allocated zeroed and committed by the system only where searches write them.
    pub fn table_bytes(&self) -> usize {
        let adjacency = self
            .adjacency
            .as_ref()
            .map_or(0, |a| 8 * a.padded_len() + a.padded_len() / 8);
        adjacency + self.bits.bytes.len() + self.bits.table.bytes() + self.bits.target_table.bytes()
    }

    /// Runs A* on `problem` within `budget` and returns the path with raw counters.
    pub fn search(&mut self, problem: &Problem<'_>, budget: &Budget) -> Search {
        if let Some(weights) = problem.grid().weights() {
            return self.search_weighted(problem, budget, weights.max(), weights.rule());
        }
        let mut opens = std::mem::take(&mut self.opens);
        let search = match (self.integral, self.config.tie_break) {
            (true, TieBreak::Fifo) => {
                self.run_with::<_, UNWEIGHTED>(&mut opens.int_fifo, problem, budget)
            }
            (true, TieBreak::Lifo) => {
                self.run_with::<_, UNWEIGHTED>(&mut opens.int_lifo, problem, budget)
            }
            (true, TieBreak::LowG) => {
                self.run_with::<_, UNWEIGHTED>(&mut opens.int_low_g, problem, budget)
            }
            (true, TieBreak::HighG) => {
                self.run_with::<_, UNWEIGHTED>(&mut opens.int_high_g, problem, budget)
            }
            (false, TieBreak::Fifo) => {
                self.run_with::<_, UNWEIGHTED>(&mut opens.fifo, problem, budget)
            }
            (false, TieBreak::Lifo) => {
                self.run_with::<_, UNWEIGHTED>(&mut opens.lifo, problem, budget)
            }
            (false, TieBreak::LowG) => {
                self.run_with::<_, UNWEIGHTED>(&mut opens.low_g, problem, budget)
            }
            (false, TieBreak::HighG) => {
                self.run_with::<_, UNWEIGHTED>(&mut opens.high_g, problem, budget)
            }
        };
        self.opens = opens;
        search
    }

    /// [`AStar::search`] on a weighted grid: always the bucket OPEN (weighted move costs
    /// are not unit steps), its ring sized for the largest weighted move.
    fn search_weighted(
        &mut self,
        problem: &Problem<'_>,
        budget: &Budget,
        max_weight: u16,
        rule: CostRule,
    ) -> Search {
        let max_move = self
            .moves
            .moves()
            .iter()
            .map(|m| m.exact_cost())
            .max()
            .unwrap_or(Cost::ONE);
        let max_cost = max_move.times(u64::from(max_weight));
        if self.weighted_max_cost != Some(max_cost) {
            let weight = self.config.weight;
            let opens = &mut self.weighted_opens;
            // Buckets `WEIGHTED_NARROWING` times narrower, relative to the costs, than
            // the unweighted search's.
            let scale = u64::from(max_weight) / WEIGHTED_NARROWING;
            match self.config.tie_break {
                TieBreak::Fifo => opens.fifo.configure_scaled(max_cost, weight, scale),
                TieBreak::Lifo => opens.lifo.configure_scaled(max_cost, weight, scale),
                TieBreak::LowG => opens.low_g.configure_scaled(max_cost, weight, scale),
                TieBreak::HighG => opens.high_g.configure_scaled(max_cost, weight, scale),
            }
            self.weighted_max_cost = Some(max_cost);
        }
        let mut opens = std::mem::take(&mut self.weighted_opens);
        let search = match (rule, self.config.tie_break) {
            (CostRule::Mean, TieBreak::Fifo) => {
                self.run_with::<_, MEAN>(&mut opens.fifo, problem, budget)
            }
            (CostRule::Mean, TieBreak::Lifo) => {
                self.run_with::<_, MEAN>(&mut opens.lifo, problem, budget)
            }
            (CostRule::Mean, TieBreak::LowG) => {
                self.run_with::<_, MEAN>(&mut opens.low_g, problem, budget)
            }
            (CostRule::Mean, TieBreak::HighG) => {
                self.run_with::<_, MEAN>(&mut opens.high_g, problem, budget)
            }
            (CostRule::Entered, TieBreak::Fifo) => {
                self.run_with::<_, ENTERED>(&mut opens.fifo, problem, budget)
            }
            (CostRule::Entered, TieBreak::Lifo) => {
                self.run_with::<_, ENTERED>(&mut opens.lifo, problem, budget)
            }
            (CostRule::Entered, TieBreak::LowG) => {
                self.run_with::<_, ENTERED>(&mut opens.low_g, problem, budget)
            }
            (CostRule::Entered, TieBreak::HighG) => {
                self.run_with::<_, ENTERED>(&mut opens.high_g, problem, budget)
            }
        };
        self.weighted_opens = opens;
        search
    }

    /// [`AStar::run`] with the configured heuristic and the budget's recording flag as
    /// constants, so that a search that records nothing has no recording code at all.
    fn run_with<O: Open, const W: u8>(
        &mut self,
        open: &mut O,
        problem: &Problem<'_>,
        budget: &Budget,
    ) -> Search {
        // A copy of the loop per case, so that neither carries the other's code: with one
        // loop for both, den520d's 4- and 8-connected bench lines took 2-3 % more time.
        if self.moves.moves().len() <= FEW_MOVES as usize {
            self.run_heuristic::<O, W, true>(open, problem, budget)
        } else {
            self.run_heuristic::<O, W, false>(open, problem, budget)
        }
    }

    /// [`AStar::run`] with the configured heuristic and recording; `FEW` is whether the
    /// move set has at most [`FEW_MOVES`] moves. A search that records its expanded cells
    /// (for a figure, never timed) reads the heuristic at run time ([`RUNTIME`]): one copy
    /// of the loop per OPEN list, rule and move count instead of five, the same estimates.
    fn run_heuristic<O: Open, const W: u8, const FEW: bool>(
        &mut self,
        open: &mut O,
        problem: &Problem<'_>,
        budget: &Budget,
    ) -> Search {
        if budget.record_expanded || budget.record_events {
            return self.run::<O, RUNTIME, true, W, FEW>(open, problem, budget);
        }
        match self.config.heuristic {
            Heuristic::Manhattan => self.run::<O, MANHATTAN, false, W, FEW>(open, problem, budget),
            Heuristic::Octile => self.run::<O, OCTILE, false, W, FEW>(open, problem, budget),
            Heuristic::Euclidean => self.run::<O, EUCLIDEAN, false, W, FEW>(open, problem, budget),
            Heuristic::Chebyshev => self.run::<O, CHEBYSHEV, false, W, FEW>(open, problem, budget),
            Heuristic::Zero => self.run::<O, ZERO, false, W, FEW>(open, problem, budget),
        }
    }

    /// The search itself, with the OPEN list `open`, heuristic `H` (one of the constants
    /// [`MANHATTAN`] ... [`ZERO`], or [`RUNTIME`] for the configured one read at run time)
    /// and `RECORD` true to list the expanded cells. Counters are locals until it returns.
    /// `W` is [`MEAN`] or [`ENTERED`] on a weighted grid with that cost rule (precondition:
    /// the grid's): moves then cost
    /// `half * (k_from * w(p) + k_to * w(q))` ([`planner_api::weights`], the factors
    /// constants) and the heuristic is multiplied by the grid's smallest weight;
    /// [`UNWEIGHTED`] compiles the unweighted loop as it was, with no weight code. `FEW`:
    /// at most [`FEW_MOVES`] moves. Never inlined: each copy is a function of its own (all
    /// of them inlined into one took 3.5 % more time on den520d's 4-connected bench line).
    #[inline(never)]
    fn run<O: Open, const H: u8, const RECORD: bool, const W: u8, const FEW: bool>(
        &mut self,
        open: &mut O,
        problem: &Problem<'_>,
        budget: &Budget,
    ) -> Search {
        let grid = problem.grid();
        let layout = Layout::new(grid, &self.moves);
        if let Err(shortfall) = budget.check_memory(layout.state_bytes(grid, &self.moves), grid) {
            let mut search =
                Search::new(Status::BudgetExhausted, None, None, SearchStats::default());
            search.memory = Some(shortfall);
            return search;
        }
        let adjacency = match layout.uses_bits() {
            true => {
                self.adjacency = None;
                None
            }
            false => Some(&*Adjacency::cached(&mut self.adjacency, grid, &self.moves)),
        };
        let bits = self.bits.get_or_build(grid, &layout, &self.moves);
        let (weight_cells, min_weight) = match (W, grid.weights()) {
            (MEAN | ENTERED, Some(weights)) => (
                self.weight_cells.get_or_build(
                    grid,
                    layout.reach,
                    layout.stride,
                    layout.padded_len,
                ),
                u64::from(weights.min()),
            ),
            _ => (&[][..], 1),
        };
        // The rule's factors as constants of this copy of the loop.
        let (k_from, k_to) = match W {
            MEAN => CostRule::Mean.factors(),
            ENTERED => CostRule::Entered.factors(),
            _ => (0, 0),
        };
        // The four axis moves' masks come from the cells beside (`FreeBits::safe_beside`);
        // the CLOSED bits serve the masks of `FreeBits::masks` only.
        let beside = moves_beside(&self.moves);
        self.cells.fit(layout.padded_len, bits.is_some() && !beside);
        let mut expanded = Vec::new();
        let mut events = Vec::new();
        // The copy that records (never timed) asks the budget what to record.
        let (record_cells, record_events) = (
            RECORD && budget.record_expanded,
            RECORD && budget.record_events,
        );
        // One search step, while there is room for it.
        let mut note = |kind, cell, parent: Option<Cell>, g: Cost, f: Cost| {
            if events.len() < planner_api::MAX_SEARCH_EVENTS {
                events.push(SearchEvent {
                    kind,
                    cell,
                    parent,
                    g: g.to_f64(),
                    f: f.to_f64(),
                });
            }
        };
        let Cells {
            state,
            g,
            touched,
            closed,
        } = &mut self.cells;
        let (state, g, closed) = (&mut state[..], &mut g[..], &mut closed[..]);
        open.clear();

        let n_moves = layout.n_moves as u64;
        let mut step = [(0u32, 0u32, Cost::ZERO); 64];
        for (slot, mv) in step.iter_mut().zip(self.moves.moves()) {
            // Wrapping offsets: x + dx stays in the grid whenever the move's mask bit is set.
            // Weighted: half the move's cost, times the weight factor per move below.
            let cost = match W != UNWEIGHTED {
                true => Cost::from_units(mv.exact_cost().units() / 2),
                false => mv.exact_cost(),
            };
            *slot = (mv.dx as u32, mv.dy as u32, cost);
        }
        let goal = problem.goal();
        let goal_index = layout.index(goal);
        let weight = self.config.weight;
        let unweighted = weight == 1.0;
        let heuristic = self.config.heuristic;
        let h = |x: u32, y: u32| {
            let h = match H {
                RUNTIME => heuristic.cost(x, y, goal.x, goal.y),
                _ => estimate::<H>(x.abs_diff(goal.x), y.abs_diff(goal.y)),
            };
            let h = if W != UNWEIGHTED {
                h.times(min_weight)
            } else {
                h
            };
            if unweighted {
                h
            } else {
                h.scaled(weight)
            }
        };
        let rows = Rows::new(layout.stride, layout.reach);
        debug_assert_eq!(FEW, layout.n_moves <= FEW_MOVES as usize);

        let mut clock = budget.start();
        let start = problem.start();
        let start_index = layout.index(start);
        state[start_index] = OPEN;
        touched.push(start_index as u32);
        g[start_index] = Cost::ZERO.units();
        open.push(start_index as u32, h(start.x, start.y), Cost::ZERO);
        if record_events {
            note(Generating, start, None, Cost::ZERO, h(start.x, start.y));
        }
        // Without the bit grid, the safe moves come from the adjacency's masks.
        let masks: &[u64] = adjacency.map_or(&[], Adjacency::masks);
        let mut tally = Tally {
            n_open_insertions: 1,
            peak_open: 1,
            ..Tally::default()
        };

        while let Some(p) = open.pop(|q| state[q as usize] & STATUS == CLOSED) {
            let p = p as usize;
            if state[p] & STATUS == CLOSED {
                continue; // The older entry of a node improved while in OPEN.
            }
            if !clock.allows(tally.n_expanded) {
                let stats = tally.stats(n_moves, tally.n_expanded);
                let mut search = Search::new(Status::BudgetExhausted, None, None, stats);
                search.expanded = expanded;
                search.events = events;
                return search;
            }
            state[p] |= CLOSED;
            tally.n_expanded += 1;
            if record_cells {
                expanded.push(layout.cell(p));
            }
            if record_events {
                let cell = layout.cell(p);
                let parent = (p != start_index).then(|| layout.cell(parent_of(&layout, state, p)));
                let g_p = Cost::from_units(g[p]);
                note(Expanding, cell, parent, g_p, g_p + h(cell.x, cell.y));
            }
            if p == goal_index {
                let path = reconstruct(&layout, state, start_index, goal_index);
                let cost = Cost::from_units(g[p]).to_f64();
                // The goal's moves are not checked.
                let stats = tally.stats(n_moves, tally.n_expanded - 1);
                let mut search = Search::new(Status::Found, Some(path), Some(cost), stats);
                search.exact_cost = Some(Cost::from_units(g[p]));
                search.expanded = expanded;
                search.events = events;
                return search;
            }
            let (x, y) = rows.cell(p);
            let g_node = Cost::from_units(g[p]);
            let from_factor = if W != UNWEIGHTED {
                k_from * u64::from(weight_cells[p])
            } else {
                0
            };
            // Set bits in increasing order are the safe moves in the configured order. With
            // the bit grid and eight moves, the moves to CLOSED cells are masked out at once
            // (no branch per move): they are the skipped ones. The four axis moves are tried
            // one by one in any case (`FEW`), and their mask comes from the four cells
            // beside `p` alone: 6 % (den520d) and 7 % (random512-10-0) faster than the
            // 3 x 3 masks with CLOSED bits on the bench's 4-connected lines.
            let mut mask = match bits {
                Some(bits) if beside => {
                    // The loop below finds the moves to CLOSED cells by their state.
                    let safe = bits.safe_beside(p);
                    tally.n_safe += u64::from(BIT_COUNT[safe as usize & 255]);
                    safe
                }
                Some(bits) => {
                    let (safe, targets) = bits.masks(closed, p);
                    let to_closed = safe & targets;
                    closed[p / 8] |= 1 << (p % 8);
                    // Masks of reach-1 sets fit in a byte; a table counts their bits (the
                    // baseline x86-64 target has no popcount instruction).
                    tally.n_safe += u64::from(BIT_COUNT[safe as usize & 255]);
                    tally.n_skipped += u64::from(BIT_COUNT[to_closed as usize & 255]);
                    safe & !to_closed
                }
                None => {
                    let safe = masks[p];
                    tally.n_safe += u64::from(safe.count_ones());
                    safe
                }
            };
            // A move's relaxation, written once for both loops below (a closure kept the
            // counters in memory: 25 % slower).
            macro_rules! relax {
                ($m:expr) => {{
                    let m: u32 = $m;
                    let q = layout.neighbor(p, m);
                    let status = state[q] & STATUS;
                    if status == CLOSED {
                        tally.n_skipped += 1;
                        continue;
                    }
                    let (dx, dy, cost) = step[(m & 63) as usize];
                    let cost = if W != UNWEIGHTED {
                        cost.times(from_factor + k_to * u64::from(weight_cells[q]))
                    } else {
                        cost
                    };
                    let g_temp = g_node + cost;
                    let known = status == OPEN;
                    if !known || g_temp.units() < g[q] {
                        tally.n_relaxations += 1;
                        tally.n_open_insertions += u64::from(!known);
                        if !known {
                            touched.push(q as u32);
                        }
                        state[q] = OPEN | (m as u8) << 2;
                        g[q] = g_temp.units();
                        let f = g_temp + h(x.wrapping_add(dx), y.wrapping_add(dy));
                        open.push(q as u32, f, g_temp);
                        if record_events {
                            let kind = if known { Updating } else { Generating };
                            note(kind, layout.cell(q), Some(layout.cell(p)), g_temp, f);
                        }
                    }
                }};
            }
            if FEW {
                // Every move in turn, its bit tested: a loop of fixed length, whose end is
                // predicted, where the loop over the set bits below ends after a varying
                // number of them (4 % faster on the 4-connected bench lines, slower on
                // the 8-connected ones).
                for m in 0..FEW_MOVES {
                    if mask >> m & 1 == 1 {
                        relax!(m);
                    }
                }
            } else {
                while mask != 0 {
                    let m = mask.trailing_zeros();
                    mask &= mask - 1;
                    relax!(m);
                }
            }
            // OPEN only grows while a node's moves are tried: its peak is reached here.
            tally.peak_open = tally
                .peak_open
                .max(tally.n_open_insertions - tally.n_expanded);
        }
        let stats = tally.stats(n_moves, tally.n_expanded);
        let mut search = Search::new(Status::NoPath, None, None, stats);
        search.expanded = expanded;
        search.events = events;
        search
    }
}

/// Move sets of at most this many moves have their moves tried in a loop of fixed length.
const FEW_MOVES: u32 = 4;

/// Whether `moves` are at most [`FEW_MOVES`] unit moves along the axes, so that the four
/// cells beside a cell decide its safe moves ([`FreeBits::safe_beside`]).
fn moves_beside(moves: &MoveSet) -> bool {
    let moves = moves.moves();
    moves.len() <= FEW_MOVES as usize
        && moves
            .iter()
            .all(|mv| mv.dx.abs() + mv.dy.abs() == 1 && mv.via.is_empty())
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

/// The kinds of grid as const-generic parameters of the search loop: no weights, or
/// weights under [`CostRule::Mean`] or [`CostRule::Entered`] (whose factors are then
/// constants of the loop).
const UNWEIGHTED: u8 = 0;
const MEAN: u8 = 1;
const ENTERED: u8 = 2;

/// Weighted searches' buckets are this many times narrower, relative to the move costs,
/// than the unweighted search's (see `AStar::search_weighted`): with random weights the
/// heuristic (times the smallest weight) is weak, OPEN is wide, and narrower buckets keep
/// the heap of the current one small. Callgrind on the weighted bench's den520d line
/// (every 16th scenario, weights 1-255): 1.599, 1.540, 1.500, 1.489, 1.525 and 1.850
/// billion instructions for 1, 2, 4, 8, 16 and 64 times narrower. Time disagrees with the
/// count (unpredictable branches and scattered loads are not in it): the bench's binaries
/// at 8 and 4, alternated three times on a quiet machine (2026-12-05, load below 1), took
/// 52.0-52.1 and 49.5-50.0 ms on den520d's weighted searches and the same within the
/// noise on random512-10-0's (960-1073 and 989-1032 ms); 2 was about as fast as 4 on
/// den520d, 16 and 32 slower.
const WEIGHTED_NARROWING: u64 = 4;

/// The heuristics as const-generic parameters of the search loop.
const MANHATTAN: u8 = 0;
const OCTILE: u8 = 1;
const EUCLIDEAN: u8 = 2;
const CHEBYSHEV: u8 = 3;
const ZERO: u8 = 4;
/// The configured heuristic, chosen at run time ([`Heuristic::cost`], which gives the
/// constants' estimates).
const RUNTIME: u8 = 5;

/// Heuristic `H` of the offsets `dx`, `dy` to the goal, as [`Heuristic::cost`].
#[inline(always)]
fn estimate<const H: u8>(dx: u32, dy: u32) -> Cost {
    match H {
        MANHATTAN => Cost::steps(u64::from(dx) + u64::from(dy)),
        OCTILE => Cost::octile_distance(dx, dy),
        EUCLIDEAN => Cost::euclidean(dx, dy),
        CHEBYSHEV => Cost::steps(u64::from(dx.max(dy))),
        _ => Cost::ZERO,
    }
}

/// The path from `start` to `goal` by the parent moves in `state` (its high six bits).
fn reconstruct(layout: &Layout, state: &[u8], start: usize, goal: usize) -> Path {
    let mut cells: Vec<Cell> = vec![layout.cell(goal)];
    let mut node = goal;
    while node != start {
        node = parent_of(layout, state, node);
        cells.push(layout.cell(node));
    }
    cells.reverse();
    Path::new(cells)
}

/// The parent of reached node `p` (not the start): the cell its recorded move came from.
fn parent_of(layout: &Layout, state: &[u8], p: usize) -> usize {
    let m = state[p] >> 2;
    p.wrapping_add_signed(-layout.delta[m as usize])
}

impl Planner for AStar {
    fn name(&self) -> &str {
        NAME
    }

    /// Unseeded; every step is one of the configured moves. Admissible when the weight is
    /// at most 1 (or the heuristic is zero) and the heuristic never overestimates under the
    /// moves: Euclidean, Chebyshev and zero always; octile for 4 and 8 directions; Manhattan
    /// for 4 only. Honours cell weights with 4 and 8 directions only (see the crate docs,
    /// "Cell weights").
    fn specs(&self) -> planner_api::PlannerSpecs {
        let heuristic = self.config.heuristic;
        let directions = self.config.moves;
        let fits = match heuristic {
            Heuristic::Euclidean | Heuristic::Chebyshev | Heuristic::Zero => true,
            Heuristic::Octile => matches!(directions, Connectivity::Four | Connectivity::Eight),
            Heuristic::Manhattan => directions == Connectivity::Four,
        };
        let admissible = heuristic == Heuristic::Zero || (fits && self.config.weight <= 1.0);
        let specs = planner_api::PlannerSpecs::deterministic(planner_api::PathSpec::Moves(
            self.moves.clone(),
        ))
        .with_admissible(admissible);
        match directions {
            Connectivity::Four | Connectivity::Eight => specs.with_cell_costs(),
            _ => specs.with_cell_costs_only_with(
                "moves",
                "4 or 8",
                "a longer move is charged for its two end cells only, not for the cells it \
                 crosses",
            ),
        }
    }

    /// The search's whole state ([`AStar::memory_bytes_for`]): `prepare` sizes its
    /// per-cell arrays as well as the tables.
    fn prepare_bytes(&self, grid: &planner_api::Grid) -> u64 {
        self.memory_bytes_for(grid)
    }

    /// Builds the bit grid (4 and 8 directions) or the adjacency (more directions, when
    /// its masks take at most 256 MiB; a larger one is built by the first search, after
    /// checking the memory budget) and sizes the per-cell arrays, which are allocated
    /// zeroed and committed by the operating system as searches touch them; on a weighted
    /// grid, also its weights in the padded layout.
    fn prepare(&mut self, grid: &planner_api::Grid) {
        let layout = Layout::new(grid, &self.moves);
        if grid.is_weighted() {
            self.weight_cells
                .get_or_build(grid, layout.reach, layout.stride, layout.padded_len);
        }
        if layout.uses_bits() {
            self.adjacency = None;
            self.bits.get_or_build(grid, &layout, &self.moves);
        } else if layout.padded_len.saturating_mul(8) <= PREPARE_ADJACENCY_LIMIT {
            Adjacency::cached(&mut self.adjacency, grid, &self.moves);
        } else {
            return;
        }
        self.cells.fit(
            layout.padded_len,
            layout.uses_bits() && !moves_beside(&self.moves),
        );
    }

    /// Records the expanded cells when the budget asks ([`Budget::record_expanded`]);
    /// refuses with [`Outcome::over_memory`] when its per-cell state for the grid (13.1
    /// bytes per padded cell, and about 9.1 more per cell for more than 8 directions) is over
    /// [`Budget::max_memory_mb`].
    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        let search = self.search(problem, budget);
        let counters = search.stats.report(Counter::ASTAR);
        match search.memory {
            Some(shortfall) => Outcome::over_memory(shortfall, counters),
            None => Outcome {
                events: search.events,
                ..Outcome::new(search.status, search.path, counters).with_expanded(search.expanded)
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_divide_exactly() {
        for stride in [3usize, 4, 5, 7, 514, 1026, 65_537, 1 << 20, (1 << 31) + 3] {
            let rows = Rows::new(stride, 1);
            let mut state = 0x9E37_79B9_7F4A_7C15u64;
            for k in 0..20_000u64 {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                // Small indices, random 32-bit ones, the top of the range, and beyond it.
                let p = match k % 4 {
                    0 => k as usize + stride + 1,
                    1 => (state as u32) as usize,
                    2 => u32::MAX as usize - (k as usize % 1000),
                    _ => (state % (1 << 40)) as usize,
                };
                let (row, column) = (p / stride, p % stride);
                if row == 0 || column == 0 {
                    continue;
                }
                let expect = ((column - 1) as u32, (row - 1) as u32);
                assert_eq!(rows.cell(p), expect, "p {p} stride {stride}");
            }
        }
    }
}
