//! Theta\*: any-angle path planning on grid cell centres (Nash, Daniel, Koenig and Felner,
//! "Theta\*: Any-Angle Path Planning on Grids", AAAI 2007, pp. 1177-1183,
//! <http://idm-lab.org/bib/abstracts/Koen07f.html>; the journal version, Daniel, Nash, Koenig
//! and Felner, JAIR 39, 2010, <https://jair.org/index.php/jair/article/view/10676>, calls it
//! Basic Theta\*).
//!
//! Theta\* is A\* on the 8-connected grid whose relaxation may take a shortcut: when the
//! node `s` being expanded has a parent `p = parent(s)` that sees the neighbour `s'`,
//! `s'` is offered `g(p) + |p s'|` with parent `p` ("path 2"); otherwise it is offered
//! `g(s) + c(s, s')` with parent `s` ("path 1"), exactly A\*'s. Paths are therefore
//! sequences of waypoints joined by straight segments at any angle.
//!
//! # Definitions used here
//! - Nodes are cell centres; edges are the 8-connected moves without corner cutting
//!   (planner-api's [`Adjacency`] over [`MoveSet`] `8`), costing 1 and `sqrt 2`.
//! - Line of sight between two cells is planner-api's exact segment traversal
//!   ([`planner_api::for_each_segment_cell`]) in its fast form, [`planner_api::walk_segment`],
//!   the function behind [`planner_api::segment_is_free`] and so behind [`Path::validate`]
//!   with [`planner_api::PathRule::AnyAngle`]: every path this crate returns passes that
//!   check. The search computes it on a bit-packed copy of the grid, one masked word test
//!   per row or column the segment crosses, with free boxes skipped through a summed-area
//!   table ([`SightGrid`]; the same answers and cell counts as `walk_segment`, tested). A
//!   segment through a grid vertex needs both side cells free, so a diagonal grid move
//!   without corner cutting is itself a segment with line of sight.
//! - `c(a, b)` is the Euclidean distance between cell centres ([`Cell::euclidean`]), and
//!   `h(s) = |s goal|`, which is consistent: `h(a) <= |a b| + h(b)` by the triangle
//!   inequality.
//! - The start is its own parent. When `parent(s) = s` (the start only) no line of sight is
//!   checked: path 2 would be path 1.
//! - CLOSED nodes are never reopened; the search stops when the goal is popped.
//! - Line of sight is checked only where it can matter: a neighbour already in OPEN whose
//!   g neither path 1 nor path 2 would replace is left as it is unchecked, which is what
//!   either answer would give ([`AnyAngle::skip_hopeless`]; false checks every relaxation).
//!
//! # Costs and the epsilon
//! Lengths are sums of square roots, so costs are `f64` and two mathematically equal
//! lengths may differ in their last bits. [`EPSILON`] (`2^-24`, about `6e-8`) absorbs that
//! in two places: a node's g is replaced only by one smaller by more than `EPSILON`, and
//! OPEN orders by `f` rounded to a multiple of `EPSILON`, then larger `g` first, then the
//! order of insertion. Each of the two can leave a length `EPSILON` longer than the exact
//! rule would, so a path of `k` waypoint updates is within `k * EPSILON` (below `1e-4`
//! for every path of fewer than 1600 segments) of what exact arithmetic gives; the tests
//! use a relative slack of `1e-4`.
//!
//! # Never longer than the 8-connected optimum
//! Claim: with these edges and this `h`, every node `s` that Theta\* expands has
//! `g(s) <= d8(s)`, the 8-connected shortest distance from the start (in exact arithmetic;
//! with the epsilon above, up to `EPSILON` per node on the way). In particular the goal's
//! path is never longer than the 8-connected optimum (A\*'s on the same grid).
//!
//! 1. `g(s) = g(parent(s)) + |parent(s) s|` for every node reached, and parents are
//!    CLOSED nodes, whose g never changes again.
//! 2. Relaxing `s'` from `s` offers at most `g(s) + c(s, s')`: path 1 offers exactly that,
//!    and path 2 offers `g(p) + |p s'| <= g(p) + |p s| + |s s'| = g(s) + c(s, s')` by the
//!    triangle inequality and step 1. Since g only decreases, after `s` is expanded
//!    `g(s') <= g(s) + c(s, s')` for every neighbour `s'` not CLOSED.
//! 3. Suppose `s` is the first node expanded with `g(s) > d8(s)`. Take a shortest
//!    8-connected path `π` from the start to `s`, and on it the last node `n` that is
//!    CLOSED (the start is); its successor `m` on `π` is not CLOSED. `n` was expanded
//!    before `s`, so `g(n) <= d8(n)`, and by step 2 `g(m) <= d8(n) + c(n, m) = d8(m)`. If
//!    `m = s` this contradicts `g(s) > d8(s)`. Otherwise `m` is in OPEN with
//!    `f(m) = g(m) + h(m) <= d8(m) + d8(m, s) + h(s) = d8(s) + h(s) < g(s) + h(s) = f(s)`
//!    (`h(m) <= |m s| + h(s) <= d8(m, s) + h(s)`), so OPEN would have given out `m`
//!    before `s`: a contradiction either way.
//!
//! The tests check the bound on every scenario of every `.scen` file in `maps/movingai`
//! against the scenario's stated optimum, and on seeded random maps against planner-astar.
//! The bound is against the 8-connected optimum. The true shortest any-angle path can be
//! shorter still, and Theta\* is not guaranteed to find it (the JAIR paper says so).
//!
//! # Counters
//! A\*'s (`n_expanded`, `n_neighbor_checks`, `n_blocked`, `n_skipped`,
//! `n_open_insertions`, `n_relaxations`, `peak_open`, with A\*'s meanings for the 8 grid
//! moves), then `n_los_checks` (line-of-sight checks made) and `n_los_cells` (cells those
//! checks visited, both ends included, up to and including the first blocked cell).
//! planner-lazy_theta_star reuses this search ([`AnyAngle`]) and adds
//! `n_parent_repairs`. Every counter and waypoint of both, with and without
//! [`AnyAngle::skip_hopeless`], equals that of `planner_testkit::reference_theta_star`, the
//! search written again with planner-api's `walk_segment` for line of sight and std's
//! binary heap, on 3,000 small random grids and 60 larger ones (`tests/reference.rs`) and
//! on every run of the configs (xtask's `every_theta_star_run_matches_the_reference_search`).
//!
//! ```
//! use planner_api::{Budget, Cell, Grid, Path, PathRule, Planner, Problem, Status};
//! use planner_theta_star::{Config, ThetaStar};
//!
//! let grid = Grid::from_ascii("
//!     ......
//!     .###..
//!     ......
//! ").unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 2), Cell::new(5, 0)).unwrap();
//! let mut theta = ThetaStar::new(Config::default()).unwrap();
//! let outcome = theta.plan(&problem, &Budget::unlimited());
//! assert_eq!(outcome.status, Status::Found);
//! let path = outcome.path.unwrap();
//! assert!(path.validate(&grid, PathRule::AnyAngle).is_ok());
//! // Along the bottom row, then one straight segment past the wall's right end:
//! // 4 + sqrt 5, shorter than the 8-connected optimum 5 + sqrt 2.
//! assert_eq!(path.cells(), &[Cell::new(0, 2), Cell::new(4, 2), Cell::new(5, 0)]);
//! assert!((path.metrics().length - (4.0 + 5f64.sqrt())).abs() < 1e-12);
//! assert!(outcome.counters.get("n_los_checks").unwrap() > 0);
//! ```
//!
//! # Budget
//! The planner honours the expansion and time limits of its [`planner_api::Budget`]
//! and its memory limit ([`Budget::max_memory_mb`](planner_api::Budget::max_memory_mb):
//! it refuses with [`planner_api::Outcome::over_memory`] when its move masks, node records
//! and line-of-sight bits would not fit).
//!
//! # Recording
//! With [`Budget::record_expanded`](planner_api::Budget::record_expanded),
//! [`planner_api::Outcome::expanded`] lists the expanded cells in order (one per
//! `n_expanded`; search-effort figures draw them). With
//! [`Budget::record_events`](planner_api::Budget::record_events),
//! [`planner_api::Outcome::events`] records the search step by step: every push into OPEN
//! (`generating` a node's first, `updating` one that lowers its `g`) with the parent it
//! was offered (the expanded node's parent for path 2, the node itself for path 1), and
//! every expansion with its parent (for Lazy Theta\*, after a repair), each with `g` and
//! `f = g + |cell goal|`, at most [`planner_api::MAX_SEARCH_EVENTS`]. Searches that record
//! run a copy of the loop of their own, so timed searches carry no recording code.
//! `tests/events.rs` holds both to the counters and the path.
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

mod sight;

pub use sight::SightGrid;

use planner_search::bucket::{BucketOpen, Open, HIGH_G};
use planner_search::neighbourhood::{CellBits, MoveTable, BIT_COUNT};
use planner_search::Stamped;

use planner_api::{
    Adjacency, BlockedBits, Budget, Cell, Connectivity, Cost, Counter, Counters, MemoryShortfall,
    MoveSet, NeighborOrder, Outcome, Path, PathSpec, Planner, PlannerSpecs, Problem, SearchEvent,
    SearchEventKind, SearchStats, Status,
};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The registry name of this planner.
pub const NAME: &str = "theta_star";

/// The tolerance of cost comparisons, `2^-24` (module docs, "Costs and the epsilon").
pub const EPSILON: f64 = 1.0 / 16_777_216.0;

/// Parameters of Theta\* and Lazy Theta\*. Both exist so that a configuration copied from
/// 8-connected A\* is accepted, and anything else is refused by name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// The grid edges: must be 8 (the 8-connected moves). Default 8.
    #[schemars(with = "u32", extend("enum" = [8]))]
    pub moves: Connectivity,
    /// Diagonal grid edges past a blocked corner: must be false (line of sight never cuts
    /// a corner, and the length bound needs the grid edges to be segments with line of
    /// sight). Default false.
    pub corner_cutting: bool,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            moves: Connectivity::Eight,
            corner_cutting: false,
        }
    }
}

/// A parameter Theta\* or Lazy Theta\* cannot run with.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ConfigError {
    /// `moves` is not 8.
    #[error(
        "parameter `moves`: any-angle search expands the 8-connected moves; {0} is not supported"
    )]
    Moves(Connectivity),
    /// `corner_cutting` is true.
    #[error(
        "parameter `corner_cutting`: any-angle search never cuts corners; true is not supported"
    )]
    CornerCutting,
}

impl planner_api::ParamKey for ConfigError {
    fn param_key(&self) -> &str {
        match self {
            ConfigError::Moves(_) => "moves",
            ConfigError::CornerCutting => "corner_cutting",
        }
    }
}

impl Config {
    /// Checks the parameters (see [`ConfigError`]).
    pub fn validate(&self) -> Result<(), ConfigError> {
        if self.moves != Connectivity::Eight {
            return Err(ConfigError::Moves(self.moves));
        }
        if self.corner_cutting {
            return Err(ConfigError::CornerCutting);
        }
        Ok(())
    }
}

/// Where line of sight is checked: the one difference between the two planners.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Variant {
    /// Theta\*: when a neighbour is relaxed, between the expanded node's parent and the
    /// neighbour.
    Theta,
    /// Lazy Theta\* (Nash, Koenig and Tovey, AAAI 2010): a neighbour is given the expanded
    /// node's parent unchecked; when it is expanded, line of sight to its parent is
    /// checked, and if blocked, the parent becomes the CLOSED grid neighbour `n` with the
    /// least `g(n) + c(n, s)` ("SetVertex"; the first such neighbour in move order on ties).
    Lazy,
}

/// The counters of one any-angle search.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct AnyAngleStats {
    /// A\*'s counters for the grid moves.
    pub search: SearchStats,
    /// Line-of-sight checks made.
    pub n_los_checks: u64,
    /// Cells visited by those checks (both ends included, up to the first blocked one).
    pub n_los_cells: u64,
    /// Lazy Theta\* only: expanded nodes whose parent had no line of sight and was replaced.
    pub n_parent_repairs: u64,
}

impl AnyAngleStats {
    /// The reported counters: A\*'s, then `n_los_checks`, `n_los_cells`, and for Lazy
    /// Theta\* `n_parent_repairs`.
    pub fn report(&self, variant: Variant) -> Counters {
        let mut counters = self
            .search
            .report(Counter::ASTAR)
            .with("n_los_checks", self.n_los_checks)
            .with("n_los_cells", self.n_los_cells);
        if variant == Variant::Lazy {
            counters.push("n_parent_repairs", self.n_parent_repairs);
        }
        counters
    }
}

/// What one search produced.
#[derive(Debug, Clone, PartialEq)]
pub struct Search {
    /// How it ended.
    pub status: Status,
    /// The waypoints when found.
    pub path: Option<Path>,
    /// `g(goal)`, the path's length as summed during the search, when found.
    pub cost: Option<f64>,
    /// The counters.
    pub stats: AnyAngleStats,
    /// Set when the search did not run: its per-cell state is over the budget's memory
    /// limit ([`AnyAngle::memory_bytes_for`]).
    pub memory: Option<MemoryShortfall>,
    /// The expanded cells in order, when the budget asked ([`Budget::record_expanded`]).
    pub expanded: Vec<Cell>,
    /// The search step by step, when the budget asked ([`Budget::record_events`]; module
    /// docs, "Recording").
    pub events: Vec<SearchEvent>,
}

impl Search {
    /// The planner's outcome of this search by `variant` (its counters named for it).
    pub fn outcome(self, variant: Variant) -> Outcome {
        let counters = self.stats.report(variant);
        match self.memory {
            Some(shortfall) => Outcome::over_memory(shortfall, counters),
            None => Outcome {
                events: self.events,
                ..Outcome::new(self.status, self.path, counters).with_expanded(self.expanded)
            },
        }
    }

    /// A search that ended with `status` and nothing recorded.
    fn ended(status: Status, stats: AnyAngleStats) -> Search {
        Search {
            status,
            path: None,
            cost: None,
            stats,
            memory: None,
            expanded: Vec::new(),
            events: Vec::new(),
        }
    }
}

/// Per-cell state; `stamp` is `generation << 1 | closed`, so nothing is cleared between
/// searches.
#[derive(Debug, Clone, Copy, Default)]
struct Node {
    g: f64,
    parent: u32,
    stamp: u32,
}

/// OPEN's key of an `f`: `f` rounded to a multiple of [`EPSILON`], in units of `EPSILON`
/// ([`KEY_FRACTION_BITS`] fractional bits). OPEN ([`BucketOpen`] with [`HIGH_G`]) orders
/// by this key, then larger `g` (passed as its bits: costs are non-negative, so their bits
/// order as they do), then first pushed.
///
/// A relaxation from `s` offers at most `g(s) + sqrt 2` (path 2 is never longer than path
/// 1, module docs, step 2; Lazy Theta\*'s repair likewise), so every `g` is below `sqrt 2`
/// times the expansions, at most [`Grid::MAX_CELLS`](planner_api::Grid::MAX_CELLS)
/// `= 2^31`; `h` is at most `width + height <= 2^31 + 1`; so `f < 2^33` and the key is
/// below `2^57`. Precondition: `0 <= f < 2^38` (the key below `2^62`), as every search's.
/// Equal to `(f / EPSILON).round()` there (tested).
#[inline]
pub fn open_key(f: f64) -> Cost {
    // `round` (halves away from zero) without its library call: for `0 <= x < 2^62` the
    // truncation and the fraction `x - trunc(x)` are exact (through i64: one instruction
    // each way on x86-64).
    let x = f / EPSILON;
    let whole = x as i64;
    Cost::from_units((whole + i64::from(x - whole as f64 >= 0.5)) as u64)
}

/// The fractional bits of [`open_key`]'s units: `EPSILON = 2^-24`.
pub const KEY_FRACTION_BITS: u32 = 24;
const _: () = assert!(EPSILON == 1.0 / (1u64 << KEY_FRACTION_BITS) as f64);

/// The grid's free cells and the search's CLOSED ones as bits, read a 3 x 3 neighbourhood
/// at a time (planner-search's [`neighbourhood`](planner_search::neighbourhood)): a node's
/// safe moves from three two-byte loads instead of an 8-byte load per cell from the
/// adjacency's masks, which `perf` showed missing the cache, and its moves to CLOSED cells
/// masked out at once instead of a branch per neighbour on its record, which callgrind's
/// branch simulation counted as mispredicted about 2.6 times per expansion on den520d.
#[derive(Debug, Clone)]
struct Neighbourhood {
    /// The revision of the grid `free` was filled from.
    revision: Option<u64>,
    free: CellBits,
    /// The CLOSED bits, and the cells whose bits the last search set: the next one clears
    /// those instead of the whole array, so a search costs the cells it touches.
    closed: CellBits,
    closed_cells: Vec<u32>,
    safe: MoveTable,
    targets: MoveTable,
}

/// The search shared by Theta\* and Lazy Theta\*: per-cell arrays kept between queries,
/// the grid's move masks cached, OPEN reused.
#[derive(Debug, Clone)]
pub struct AnyAngle {
    moves: MoveSet,
    adjacency: Option<Adjacency>,
    sight: Option<SightGrid>,
    nodes: Stamped<Node>,
    neighbourhood: Neighbourhood,
    open: BucketOpen<HIGH_G>,
    /// Theta\* only: whether line of sight is left unchecked where it cannot change the
    /// search, for a neighbour already in OPEN whose g neither path would replace (default
    /// true). Paths and A\*'s counters are the same either way; only `n_los_checks` and
    /// `n_los_cells` differ. False checks every relaxation, as the paper's pseudocode does.
    pub skip_hopeless: bool,
}

impl AnyAngle {
    /// A search with `config`, validated.
    pub fn new(config: &Config) -> Result<AnyAngle, ConfigError> {
        config.validate()?;
        let moves = MoveSet::new(Connectivity::Eight, false, &NeighborOrder::default())
            .map_err(|_| ConfigError::Moves(config.moves))?;
        Ok(AnyAngle {
            neighbourhood: Neighbourhood {
                revision: None,
                free: CellBits::default(),
                closed: CellBits::default(),
                closed_cells: Vec::new(),
                safe: MoveTable::safe(&moves),
                targets: MoveTable::targets(&moves),
            },
            moves,
            adjacency: None,
            sight: None,
            nodes: Stamped::default(),
            open: BucketOpen::default(),
            skip_hopeless: true,
        })
    }

    /// The bytes of the move masks (and their copy of the grid), the node records (16
    /// bytes per padded cell), the free and CLOSED cells' bits (a bit per padded cell each)
    /// and the grid for line of sight (a bit per cell, twice, rows and columns rounded up to
    /// 64, and its summed-area table, 4 bytes per cell plus a row and a column) for `grid`.
    pub fn memory_bytes_for(&self, grid: &planner_api::Grid) -> u64 {
        let padded = Adjacency::padded_len_for(grid, &self.moves) as u64;
        Adjacency::bytes_for(grid, &self.moves)
            + padded * std::mem::size_of::<Node>() as u64
            + 2 * CellBits::bytes_for(padded as usize)
            + BlockedBits::bytes_for(grid)
    }

    /// Builds the move masks, the bit-packed grid for line of sight and the node arrays
    /// for `grid` (done by the first search on a grid otherwise).
    pub fn prepare(&mut self, grid: &planner_api::Grid) {
        let adjacency = Adjacency::cached(&mut self.adjacency, grid, &self.moves);
        self.nodes.fit(adjacency.padded_len());
        let built = self.neighbourhood.revision;
        if built != Some(grid.revision()) {
            self.neighbourhood.free.follow_free(grid, adjacency, built);
            self.neighbourhood.revision = Some(grid.revision());
        }
        SightGrid::cached(&mut self.sight, grid);
    }

    /// Runs `variant` on `problem` within `budget` (one expansion is one node taken from
    /// OPEN and CLOSED).
    pub fn search(&mut self, problem: &Problem<'_>, budget: &Budget, variant: Variant) -> Search {
        // A copy of the loop that records and one that does not, so that timed searches
        // carry no recording code (with it, both planners took 1-2 % more time on the
        // bench's den520d line).
        match budget.record_expanded || budget.record_events {
            true => self.run::<true>(problem, budget, variant),
            false => self.run::<false>(problem, budget, variant),
        }
    }

    /// [`AnyAngle::search`], recording what the budget asks for when `RECORD`.
    fn run<const RECORD: bool>(
        &mut self,
        problem: &Problem<'_>,
        budget: &Budget,
        variant: Variant,
    ) -> Search {
        let grid = problem.grid();
        if let Err(shortfall) = budget.check_memory(self.memory_bytes_for(grid), grid) {
            return Search {
                memory: Some(shortfall),
                ..Search::ended(Status::BudgetExhausted, AnyAngleStats::default())
            };
        }
        self.prepare(grid);
        let (Some(adjacency), Some(sight)) = (self.adjacency.as_ref(), self.sight.as_ref()) else {
            unreachable!("prepare fills the adjacency and sight caches");
        };
        let (stamps, nodes) = self.nodes.begin();
        let (open_stamp, closed_stamp) = (stamps.open, stamps.closed);
        let Neighbourhood {
            free,
            closed,
            closed_cells,
            safe: safe_moves,
            targets,
            ..
        } = &mut self.neighbourhood;
        if !closed.fit(adjacency.padded_len()) {
            for &p in closed_cells.iter() {
                closed.unset(p as usize);
            }
        }
        closed_cells.clear();
        let stride = adjacency.stride();
        let open = &mut self.open;
        // Moves cost at most sqrt 2 (path 2 is never longer than path 1), and h is
        // consistent: the f values in OPEN span at most 2 sqrt 2.
        open.configure_fraction(std::f64::consts::SQRT_2, 1.0, KEY_FRACTION_BITS);
        let skip_hopeless = self.skip_hopeless;

        // Per move: its cost, and its offset, so a neighbour's cell is found without
        // dividing its index by the row stride.
        let mut costs = [0.0f64; 8];
        let mut offsets = [(0i32, 0i32); 8];
        for ((slot, offset), mv) in costs
            .iter_mut()
            .zip(offsets.iter_mut())
            .zip(self.moves.moves())
        {
            *slot = mv.cost;
            *offset = (mv.dx, mv.dy);
        }
        let goal = problem.goal();
        let goal_index = adjacency.index(goal);
        let h = |c: Cell| {
            let (dx, dy) = (
                f64::from(c.x.abs_diff(goal.x)),
                f64::from(c.y.abs_diff(goal.y)),
            );
            (dx * dx + dy * dy).sqrt()
        };
        let mut stats = AnyAngleStats::default();
        let mut n_safe = 0u64;
        // Recording (never timed; constant false in the timed copy of the loop).
        let (record_cells, record_events) = (
            RECORD && budget.record_expanded,
            RECORD && budget.record_events,
        );
        let mut expanded = Vec::new();
        let mut events = Vec::new();
        let mut note = |kind, cell: Cell, parent: Option<Cell>, g: f64| {
            if events.len() < planner_api::MAX_SEARCH_EVENTS {
                events.push(SearchEvent {
                    kind,
                    cell,
                    parent,
                    g,
                    f: g + h(cell),
                });
            }
        };
        let line_of_sight = |stats: &mut AnyAngleStats, a: Cell, b: Cell| {
            let walk = sight.walk(grid, a, b);
            stats.n_los_checks += 1;
            stats.n_los_cells += walk.n_cells;
            walk.free
        };

        let mut clock = budget.start();
        let start = problem.start();
        let start_index = adjacency.index(start);
        nodes[start_index] = Node {
            g: 0.0,
            parent: start_index as u32,
            stamp: open_stamp,
        };
        open.push(
            start_index as u32,
            open_key(h(start)),
            Cost::from_units(0f64.to_bits()),
        );
        stats.search.n_open_insertions = 1;
        stats.search.peak_open = 1;
        if record_events {
            note(SearchEventKind::Generating, start, None, 0.0);
        }

        let finish = |stats: &mut AnyAngleStats, n_safe: u64, n_checked: u64| {
            let s = &mut stats.search;
            s.n_neighbor_checks = 8 * n_checked;
            s.n_blocked = s.n_neighbor_checks - n_safe;
        };

        while let Some(node) = open.pop(|n| nodes[n as usize].stamp == closed_stamp) {
            let p = node as usize;
            if nodes[p].stamp == closed_stamp {
                // An older entry of a node improved while in OPEN: an improvement lowers g
                // by more than EPSILON, so its key by at least one unit, and the newer
                // entry came out first.
                continue;
            }
            if !clock.allows(stats.search.n_expanded) {
                let n = stats.search.n_expanded;
                finish(&mut stats, n_safe, n);
                return Search {
                    expanded,
                    events,
                    ..Search::ended(Status::BudgetExhausted, stats)
                };
            }
            let cell = adjacency.cell(p);
            if variant == Variant::Lazy && nodes[p].parent as usize != p {
                let parent_cell = adjacency.cell(nodes[p].parent as usize);
                if !line_of_sight(&mut stats, parent_cell, cell) {
                    // SetVertex: the best CLOSED grid neighbour. One exists: the node that
                    // put `p` into OPEN (moves are symmetric).
                    stats.n_parent_repairs += 1;
                    let mut best: Option<(f64, usize)> = None;
                    let mut mask = adjacency.mask(p);
                    while mask != 0 {
                        let m = mask.trailing_zeros();
                        mask &= mask - 1;
                        let q = adjacency.neighbor(p, m);
                        if nodes[q].stamp == closed_stamp {
                            let g = nodes[q].g + costs[(m & 7) as usize];
                            if best.is_none_or(|(b, _)| g < b) {
                                best = Some((g, q));
                            }
                        }
                    }
                    if let Some((g, q)) = best {
                        nodes[p].g = g;
                        nodes[p].parent = q as u32;
                    }
                }
            }
            nodes[p].stamp = closed_stamp;
            closed.set(p);
            closed_cells.push(p as u32);
            stats.search.n_expanded += 1;
            if record_cells {
                expanded.push(cell);
            }
            if record_events {
                let parent = nodes[p].parent as usize;
                let parent = (parent != p).then(|| adjacency.cell(parent));
                note(SearchEventKind::Expanding, cell, parent, nodes[p].g);
            }
            if p == goal_index {
                let n = stats.search.n_expanded - 1;
                finish(&mut stats, n_safe, n);
                let path = reconstruct(adjacency, nodes, start_index, goal_index);
                return Search {
                    path: Some(path),
                    cost: Some(nodes[p].g),
                    expanded,
                    events,
                    ..Search::ended(Status::Found, stats)
                };
            }
            let g_node = nodes[p].g;
            let parent = nodes[p].parent as usize;
            let g_parent = nodes[parent].g;
            let parent_cell = adjacency.cell(parent);
            // The safe moves (eight at most: a byte) less those to CLOSED cells, counted as
            // skipped, without a branch per move.
            let safe = safe_moves.get(free.code(p, stride));
            debug_assert_eq!(safe, adjacency.mask(p));
            let to_closed = safe & targets.get(closed.code(p, stride));
            n_safe += u64::from(BIT_COUNT[safe as usize & 255]);
            stats.search.n_skipped += u64::from(BIT_COUNT[to_closed as usize & 255]);
            // Under debug assertions (CI's tests): the bits say CLOSED exactly where the
            // stamps do, after any number of searches by this planner.
            #[cfg(debug_assertions)]
            for m in 0..8 {
                if safe >> m & 1 == 1 {
                    let shut = nodes[adjacency.neighbor(p, m)].stamp == closed_stamp;
                    debug_assert_eq!(to_closed >> m & 1 == 1, shut);
                }
            }
            let mut mask = safe & !to_closed;
            while mask != 0 {
                let m = mask.trailing_zeros();
                mask &= mask - 1;
                let q = adjacency.neighbor(p, m);
                let (dx, dy) = offsets[(m & 7) as usize];
                // Inside the grid: `q` is a free cell (its move bit is set).
                let q_cell = Cell::new(
                    cell.x.wrapping_add_signed(dx),
                    cell.y.wrapping_add_signed(dy),
                );
                debug_assert_eq!(q_cell, adjacency.cell(q));
                let known = nodes[q].stamp == open_stamp;
                let path_1 = g_node + costs[(m & 7) as usize];
                // A node in OPEN whose parent is already `parent` holds path 2's g to the
                // bit: `g(parent) + |parent q|` from the same values (a CLOSED parent's g
                // never changes, and a grid move's cost is `cell_hypot` of its offset, so
                // path 1 from `parent` gave the same sum). Path 2 cannot replace it, so its
                // distance is not computed again; every counter and path is as before.
                let holds_path_2 = known && nodes[q].parent as usize == parent;
                let (g_new, new_parent) = if parent == p {
                    (path_1, p)
                } else {
                    let path_2 = || g_parent + parent_cell.euclidean(q_cell);
                    match variant {
                        Variant::Lazy if holds_path_2 => continue,
                        Variant::Lazy => (path_2(), parent),
                        Variant::Theta => {
                            // Neither path can replace g(q): line of sight decides nothing.
                            // Path 1 first: it is the cheaper to compute. (Costs are
                            // finite sums of distances, never NaN.) Path 2's distance is
                            // computed at most once per relaxation, and only when needed.
                            let mut known_path_2 = None;
                            if skip_hopeless && known {
                                let bar = nodes[q].g - EPSILON;
                                if path_1 >= bar {
                                    if holds_path_2 {
                                        continue;
                                    }
                                    let via = path_2();
                                    if via >= bar {
                                        continue;
                                    }
                                    known_path_2 = Some(via);
                                }
                            }
                            if line_of_sight(&mut stats, parent_cell, q_cell) {
                                (known_path_2.unwrap_or_else(path_2), parent)
                            } else {
                                (path_1, p)
                            }
                        }
                    }
                };
                if !known || g_new < nodes[q].g - EPSILON {
                    stats.search.n_relaxations += 1;
                    stats.search.n_open_insertions += u64::from(!known);
                    nodes[q] = Node {
                        g: g_new,
                        parent: new_parent as u32,
                        stamp: open_stamp,
                    };
                    open.push(
                        q as u32,
                        open_key(g_new + h(q_cell)),
                        Cost::from_units(g_new.to_bits()),
                    );
                    if record_events {
                        let kind = match known {
                            true => SearchEventKind::Updating,
                            false => SearchEventKind::Generating,
                        };
                        note(kind, q_cell, Some(adjacency.cell(new_parent)), g_new);
                    }
                }
            }
            // Nodes in OPEN: every inserted node is expanded at most once.
            let s = &mut stats.search;
            s.peak_open = s.peak_open.max(s.n_open_insertions - s.n_expanded);
        }
        let n = stats.search.n_expanded;
        finish(&mut stats, n_safe, n);
        Search {
            expanded,
            events,
            ..Search::ended(Status::NoPath, stats)
        }
    }
}

fn reconstruct(adjacency: &Adjacency, nodes: &[Node], start: usize, goal: usize) -> Path {
    let mut cells = vec![adjacency.cell(goal)];
    let mut node = goal;
    while node != start {
        node = nodes[node].parent as usize;
        cells.push(adjacency.cell(node));
    }
    cells.reverse();
    Path::new(cells)
}

/// The Theta\* planner. Build with [`ThetaStar::new`]; reuse it for many queries.
#[derive(Debug, Clone)]
pub struct ThetaStar {
    search: AnyAngle,
}

impl ThetaStar {
    /// A planner with `config`, validated.
    pub fn new(config: Config) -> Result<ThetaStar, ConfigError> {
        Ok(ThetaStar {
            search: AnyAngle::new(&config)?,
        })
    }

    /// Runs Theta\* and returns the path with its cost and raw counters.
    pub fn search(&mut self, problem: &Problem<'_>, budget: &Budget) -> Search {
        self.search.search(problem, budget, Variant::Theta)
    }
}

impl Planner for ThetaStar {
    fn name(&self) -> &str {
        NAME
    }

    /// Deterministic; paths are waypoints joined by segments with line of sight.
    fn specs(&self) -> PlannerSpecs {
        PlannerSpecs::deterministic(PathSpec::AnyAngle)
    }

    fn prepare_bytes(&self, grid: &planner_api::Grid) -> u64 {
        self.search.memory_bytes_for(grid)
    }

    fn prepare(&mut self, grid: &planner_api::Grid) {
        self.search.prepare(grid);
    }

    /// Refuses with [`Outcome::over_memory`] when [`AnyAngle::memory_bytes_for`] the grid
    /// is over [`Budget::max_memory_mb`].
    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        let search = self.search(problem, budget);
        search.outcome(Variant::Theta)
    }
}
