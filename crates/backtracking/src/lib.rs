//! Seed 000's exhaustive Backtracking planner: enumerates every simple path from the start
//! to the goal and keeps the best by the lexicographic (D, T, Score) order.
//!
//! # Definition
//! Seed 000 (`000_03f90818fe97c4a6.txt`), section 2.3 and its Fig. 5: a depth-first
//! recursion `Backtrack(n_k)` over the current path `P`; a cell may not repeat within `P`
//! (its `Visited` mark is set when it joins `P` and cleared when it leaves, equations
//! 15-19), so every simple start-goal path is found exactly once. Solutions are ranked by
//! [`PathRank`], the order of section 2.4: fewer steps D, then fewer turns T, then lower
//! Score. **On a full tie the first solution found is kept** (a later one replaces the best
//! only when it is strictly better).
//!
//! # Counters (section 2.5, Table 2), per call of `Backtrack`
//! - `n_expanded` += 1 for every call, the root call and goal calls included;
//! - at the goal: `n_solutions` += 1, the path is compared with the best, and the call
//!   returns without checking any neighbour;
//! - otherwise, for each move in order: `n_neighbor_checks` += 1; an unsafe target (out of
//!   bounds, blocked, or for a diagonal without corner cutting a blocked cell it passes
//!   between: [`MoveSet::apply`]) counts in `n_blocked`; a target on the current path in
//!   `n_skipped`; any other target is recursed into, and on return `n_backtracks` += 1;
//! - a non-goal call that recursed into no neighbour is a dead end, `n_dead_ends`;
//! - `max_depth` is the most cells the current path ever held (goal included): the
//!   paper's "recursion depth" memory indicator.
//!
//! With `k` moves per cell, every complete run obeys
//! - `n_neighbor_checks = k * (n_expanded - n_solutions)` (every non-goal call checks all
//!   `k` moves),
//! - `n_neighbor_checks = n_blocked + n_skipped + (n_expanded - 1)` (every check is
//!   blocked, skipped, or makes one of the calls other than the root),
//! - `n_backtracks = n_expanded - 1` (every call but the root returns once).
//!
//! On the paper's 4-connected grid `k = 4`; these hold in every column of Tables 6 and 8,
//! and this planner reproduces all 120 Backtracking numbers of Tables 3, 4, 6 and 8 on the
//! reconstructed maps in `maps/paper/`. With `moves = 8` the identities hold with `k = 8`
//! (and so on for 16, 32, 48): a call checks its 8 moves, and `n_blocked` then includes
//! the diagonal moves refused because they would cut a blocked corner.
//!
//! # Budget
//! The budget is consulted before every call (one call is one expansion). When it refuses
//! one, the search stops at once with [`Status::BudgetExhausted`](planner_api::Status::BudgetExhausted), the best path found so
//! far and the counters of exactly the work done: the refused call and the checks that
//! would have followed in the calls still on the path are not counted, and no open call
//! counts as returned. For such a truncated run, with `L` the number of cells on the path
//! when it stopped (`1 <= L <= max_depth`; `L = 0` and every counter 0 for a zero budget):
//! - `n_neighbor_checks = n_blocked + n_skipped + (n_expanded - 1)` still holds exactly;
//! - `n_backtracks = n_expanded - L` (the `L - 1` open calls above the root never returned);
//! - `n_neighbor_checks = k * (n_expanded - n_solutions) - u` where `u`, the checks the
//!   open calls had not done yet, satisfies `1 <= u <= (k - 1) * (L - 1) + k`.
//!
//! A wall-clock limit is read through [`BudgetClock`] at every
//! expansion (the clock itself reads the time once per 1024); an expansion limit alone
//! costs one decrement per expansion.
//!
//! # Design
//! The recursion of Fig. 5 runs on an explicit stack of 16-byte frames (no recursion: a
//! path of 262,144 cells on a 512x512 map is fine), over one 64-bit word per cell of a
//! padded grid: the mask of the moves that are safe from the cell (built once per grid
//! from [`MoveSet`], cached while the grid is the same) and the `Visited` bit.
//!
//! While a call is open the path above it does not change, so which of its moves are
//! unsafe, lead onto the path, or lead to a free cell is fixed when it is entered. A call
//! therefore counts its blocked and skipped checks when it is entered and iterates only
//! its free neighbours; a call without any is a dead end and returns at once without
//! being pushed. `n_neighbor_checks` and `n_backtracks` are computed at the end from the
//! calls made and the calls still open (the two facts in parentheses above), and a
//! truncated run subtracts the checks its open calls had not reached. The counters are
//! those of the step-by-step procedure: `tests/search.rs` compares every counter with a
//! literal transcription of Fig. 5 at every budget on map 1, and at several budgets on
//! seeded random grids with 4, 8 and 16 directions.
//!
//! The turns of the current path are a running count, so a solution's rank is known in
//! O(1) (as the integer `D << 32 | T`, which orders exactly as [`PathRank`] since
//! `Score = D + T`), and the path is copied only when a solution beats the best. Nothing
//! is allocated per step. On the open 6x6 grid (18,470,411 calls, 1,262,816 solutions)
//! `cargo bench -p planner-backtracking` measured about 108 million calls per second of
//! thread CPU time on the development machine.
//!
//! # Parallel enumeration (optional)
//! With `parallel = true`, [`Prune::Off`] and an unlimited budget (no cancel flag either),
//! the root's subtrees (one per safe first move) are enumerated on the rayon pool and
//! merged in move order;
//! the outcome, counters included, equals the serial run's. Otherwise the search is serial.
//!
//! # Pruning (not in the paper)
//! [`Prune::Bound`] is a branch and bound on (D, T): a safe, unvisited neighbour is not
//! recursed into when no completion through it can beat the best path so far (steps so
//! far plus a lower bound on the remaining steps exceeds the best D, or equals it while
//! the turns so far already reach the best T). It returns the same best path but
//! **changes every counter** (fewer calls) and adds `n_pruned`, the neighbours not
//! recursed into; the second identity becomes
//! `n_neighbor_checks = n_blocked + n_skipped + n_pruned + (n_expanded - 1)` and
//! `n_solutions` counts only the solutions still reached. It is off by default.
//!
//! # Example: the paper's map 1 (Table 6, first column)
//! ```
//! use planner_api::{Budget, Cell, Grid, Planner, Problem, Status};
//! use planner_backtracking::{Backtracking, Config};
//!
//! // Rows top to bottom; `.` free, `#` blocked.
//! let rows = ["......", "###..#", "##....", "####.#", "####.#", "####.."];
//! let grid = Grid::from_ascii(&rows.join("\n")).unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(5, 5)).unwrap();
//! let mut planner = Backtracking::new(Config::default()).unwrap();
//! let outcome = planner.plan(&problem, &Budget::unlimited());
//! assert_eq!(outcome.status, Status::Found);
//! let m = outcome.path.unwrap().metrics();
//! assert_eq!((m.steps, m.turns, m.score), (10, 2, 12));
//! let c = &outcome.counters;
//! let get = |name| c.get(name).unwrap();
//! assert_eq!(
//!     [get("n_expanded"), get("n_neighbor_checks"), get("n_blocked"), get("n_skipped")],
//!     [48, 176, 78, 51]
//! );
//! assert_eq!([get("n_solutions"), get("n_dead_ends"), get("n_backtracks")], [4, 12, 47]);
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

use planner_api::{
    Budget, BudgetClock, Cell, Connectivity, Counter, MoveOrderError, MoveSet, NeighborOrder,
    Outcome, Path, PathRank, Planner, Problem, SearchStats,
};
use planner_search::neighbourhood::BIT_COUNT;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use planner_api::adjacency::{Adjacency, SCRATCH as VISITED};

/// Optional pruning beyond the paper; every mode other than [`Prune::Off`] changes the counters.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Prune {
    /// The paper's exhaustive enumeration (default).
    #[default]
    Off,
    /// Branch and bound on (D, T); see the crate docs. Reports `n_pruned` as well.
    Bound,
}

/// The planner's configuration (TOML/JSON keys as the field names).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// Neighbourhood, written as its number of directions (`moves = 4` or `8`, also 16, 32, 48).
    /// Default 4, the paper's.
    #[schemars(with = "u32", extend("enum" = [4, 8, 16, 32, 48]))]
    pub moves: Connectivity,
    /// Whether 8-connected diagonals may cut corners (only with `moves = 8`). Default false.
    pub corner_cutting: bool,
    /// Order in which the moves are tried, e.g. `"R L D U"` (see [`NeighborOrder`]).
    /// Default `R L D U`, the paper's right, left, down, up.
    #[schemars(with = "String")]
    pub order: NeighborOrder,
    /// Pruning mode. Default [`Prune::Off`], the paper's exhaustive search.
    pub prune: Prune,
    /// Enumerate the root's subtrees (one per safe first move) in parallel on the rayon
    /// thread pool. The outcome, counters included, is identical to the serial run's.
    /// Applies only with [`Prune::Off`] and an unlimited budget (a budget is spent in the
    /// serial order, and branch and bound prunes with the best of the earlier subtrees);
    /// otherwise the search runs serially. Default false.
    pub parallel: bool,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            moves: Connectivity::Four,
            corner_cutting: false,
            order: NeighborOrder::default(),
            prune: Prune::Off,
            parallel: false,
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

/// Builds the move set of a config, naming the offending parameter on error.
fn move_set(config: &Config) -> Result<MoveSet, ConfigError> {
    MoveSet::new(config.moves, config.corner_cutting, &config.order).map_err(|e| match e {
        MoveOrderError::CornerCutting(_) => ConfigError::CornerCutting(e),
        other => ConfigError::Order(other),
    })
}

/// One open call of `Backtrack` on the explicit stack (16 bytes, no padding).
#[derive(Debug, Clone, Copy, Default)]
struct Frame {
    /// Moves still to try (bit m = move m): the free neighbours not yet recursed into,
    /// or with pruning every safe move not yet checked, and then also [`DESCENDED`].
    remaining: u64,
    /// Padded index of the call's cell.
    cell: u32,
    /// The move that entered this cell; [`NO_MOVE`] for the root.
    entered_by: u32,
}

/// `Frame::entered_by` of the root.
const NO_MOVE: u32 = u32::MAX;

/// With pruning, the bit of `Frame::remaining` set once the call recursed into a neighbour
/// (above every move bit; without pruning every call pushed below the root descends).
const DESCENDED: u64 = 1 << 63;

/// Seed 000's exhaustive Backtracking planner (registry name `backtracking`).
///
/// Keeps its per-cell buffers between calls to [`Planner::plan`]; the safe-move masks are
/// rebuilt only when the grid changes.
#[derive(Debug, Clone)]
pub struct Backtracking {
    config: Config,
    moves: MoveSet,
    adjacency: Option<Adjacency>,
    stack: Vec<Frame>,
    best: Vec<u32>,
    lower_bound: Vec<u32>,
}

/// The result of one enumeration, before it is turned into an [`Outcome`].
struct Run {
    stats: SearchStats,
    pruned: u64,
    complete: bool,
    best: Option<PathRank>,
}

impl Backtracking {
    /// A planner with a validated `config`.
    ///
    /// Errors when `order` does not list the moves of `moves` correctly, or when
    /// `corner_cutting` is set for a neighbourhood other than 8.
    pub fn new(config: Config) -> Result<Backtracking, ConfigError> {
        let moves = move_set(&config)?;
        Ok(Backtracking {
            config,
            moves,
            adjacency: None,
            stack: Vec::new(),
            best: Vec::new(),
            lower_bound: Vec::new(),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The moves, in the order they are tried.
    pub fn moves(&self) -> &MoveSet {
        &self.moves
    }

    /// The bytes a search on `grid` within `budget` allocates at most: the move masks (and
    /// their copy of the grid), a 16-byte frame per cell, with [`Prune::Bound`] a 4-byte
    /// bound per padded cell, and when the budget lets the root's moves run in parallel
    /// ([`Config::parallel`]) a copy of the masks and frames per move (the most tasks there
    /// can be, whatever the machine's threads, so that whether a run fits does not depend
    /// on the machine).
    pub fn memory_bytes_for(&self, grid: &planner_api::Grid, budget: &Budget) -> u64 {
        let padded = Adjacency::padded_len_for(grid, &self.moves) as u64;
        let frames = grid.len() as u64 * std::mem::size_of::<Frame>() as u64;
        let bound = match self.config.prune {
            Prune::Bound => 4 * padded,
            _ => 0,
        };
        let tasks = match self.may_run_in_parallel(budget) {
            true => self.moves.moves().len() as u64,
            false => 0,
        };
        Adjacency::bytes_for(grid, &self.moves) + frames + bound + tasks * (8 * padded + frames)
    }

    /// Whether the config and `budget` let the root's moves run in parallel
    /// ([`Config::parallel`], no pruning, no limit that needs the serial order); a search
    /// then does when its start has two or more moves and is not the goal.
    fn may_run_in_parallel(&self, budget: &Budget) -> bool {
        self.config.parallel
            && self.config.prune == Prune::Off
            && budget.max_expansions.is_none()
            && budget.max_time.is_none()
            && budget.cancel.is_none()
    }

    fn run(&mut self, problem: &Problem<'_>, budget: &Budget) -> Run {
        let grid = problem.grid();
        let may_run_in_parallel = self.may_run_in_parallel(budget);
        let adjacency = Adjacency::cached(&mut self.adjacency, grid, &self.moves);
        let start = adjacency.index(problem.start());
        let goal = adjacency.index(problem.goal());
        // The path holds each cell at most once, so at most `len - 1` frames are ever below
        // the top. Frames are written before they are read: no clearing between searches.
        if self.stack.len() < grid.len() {
            self.stack.resize(grid.len(), Frame::default());
        }
        self.best.clear();
        if self.config.prune == Prune::Bound {
            fill_lower_bound(&mut self.lower_bound, adjacency, &self.moves, problem);
        }
        let root_moves = adjacency.mask(start) & adjacency.all();
        let parallel = may_run_in_parallel && start != goal && root_moves.count_ones() >= 2;
        if parallel {
            return run_parallel(adjacency, start, goal, &mut self.best, grid.len());
        }
        let (n_moves, all) = (adjacency.n_moves(), adjacency.all());
        let (cells, delta) = adjacency.split_mut();
        let mut search = Search {
            cells,
            delta,
            n_moves,
            all,
            stack: &mut self.stack,
            best: &mut self.best,
            lower_bound: &self.lower_bound,
        };
        search.dispatch(self.config.prune, start, goal, budget, u64::MAX)
    }
}

/// The serial search split at the root: one task per safe first move, each a serial
/// search whose root may take only that move, merged in move order. Each task counts the
/// root call too, so the merge removes the extra copies of the root's own counts; the
/// best is taken in task order with the serial rule (strictly better replaces), so ties
/// keep the first found exactly as the serial run does.
fn run_parallel(
    adjacency: &Adjacency,
    start: usize,
    goal: usize,
    best_path: &mut Vec<u32>,
    n_cells: usize,
) -> Run {
    use rayon::prelude::*;
    let root_moves = adjacency.mask(start) & adjacency.all();
    let tasks: Vec<u32> = (0..64).filter(|m| root_moves >> m & 1 == 1).collect();
    let runs: Vec<(Run, Vec<u32>)> = tasks
        .par_iter()
        .map(|&m| {
            let mut cells = adjacency.masks().to_vec();
            let mut stack = vec![Frame::default(); n_cells];
            let mut best = Vec::new();
            let mut search = Search {
                cells: &mut cells,
                delta: adjacency.deltas(),
                n_moves: adjacency.n_moves(),
                all: adjacency.all(),
                stack: &mut stack,
                best: &mut best,
                lower_bound: &[],
            };
            let run = search.dispatch(Prune::Off, start, goal, &Budget::unlimited(), 1 << m);
            (run, best)
        })
        .collect();
    let k = adjacency.n_moves() as u64;
    let extra_roots = runs.len() as u64 - 1;
    let root_blocked = k - u64::from(root_moves.count_ones());
    let mut stats = SearchStats::default();
    let mut best: Option<PathRank> = None;
    for (run, path) in runs {
        let s = &run.stats;
        stats.n_expanded += s.n_expanded;
        stats.n_blocked += s.n_blocked;
        stats.n_skipped += s.n_skipped;
        stats.n_solutions += s.n_solutions;
        stats.n_dead_ends += s.n_dead_ends;
        stats.max_depth = stats.max_depth.max(s.max_depth);
        if let Some(rank) = run.best {
            if best.is_none_or(|b| rank < b) {
                best = Some(rank);
                *best_path = path;
            }
        }
    }
    stats.n_expanded -= extra_roots;
    stats.n_blocked -= extra_roots * root_blocked;
    stats.n_neighbor_checks = k * (stats.n_expanded - stats.n_solutions);
    stats.n_backtracks = stats.n_expanded - 1;
    Run {
        stats,
        pruned: 0,
        complete: true,
        best,
    }
}

/// Fills `lower_bound` (padded layout) with a lower bound on the number of moves from each
/// grid cell to the goal: Manhattan distance for 4 directions, else the Chebyshev distance
/// divided by the longest move's reach, rounded up.
fn fill_lower_bound(
    lower_bound: &mut Vec<u32>,
    adjacency: &Adjacency,
    moves: &MoveSet,
    problem: &Problem<'_>,
) {
    let goal = problem.goal();
    let reach = moves
        .moves()
        .iter()
        .map(|m| m.dx.unsigned_abs().max(m.dy.unsigned_abs()))
        .max()
        .unwrap_or(1)
        .max(1);
    let four = moves.connectivity() == Connectivity::Four;
    lower_bound.clear();
    lower_bound.resize(adjacency.padded_len(), 0);
    for cell in problem.grid().cells() {
        let bound = if four {
            u32::try_from(cell.manhattan(goal)).unwrap_or(u32::MAX)
        } else {
            (cell.chebyshev(goal) as u32).div_ceil(reach)
        };
        lower_bound[adjacency.index(cell)] = bound;
    }
}

/// The borrowed state of one enumeration.
struct Search<'a> {
    /// Per padded cell: the safe-move mask, and the [`VISITED`] mark while the cell is on
    /// the current path (one array, so one load tells both).
    cells: &'a mut [u64],
    /// Padded index offset of each move.
    delta: &'a [isize; 64],
    /// Number of moves.
    n_moves: usize,
    /// Bits `0..n_moves`.
    all: u64,
    stack: &'a mut [Frame],
    best: &'a mut Vec<u32>,
    lower_bound: &'a [u32],
}

/// Set bits of a move mask; `K` as in [`Search::run`] (the masks have at most 8 bits when `K` is 4 or 8).
#[inline(always)]
fn popcount<const K: usize>(mask: u64) -> u64 {
    if K == 4 || K == 8 {
        u64::from(BIT_COUNT[(mask & 0xff) as usize])
    } else {
        u64::from(mask.count_ones())
    }
}

/// Whether entering a cell by move `m` changes direction after a cell entered by
/// `previous`. From the root ([`NO_MOVE`]) every move counts as a change; the running
/// count starts at -1 (wrapping) to cancel it, since the first move is never a turn.
#[inline(always)]
fn turns(previous: u32, m: u32) -> u32 {
    u32::from(previous != m)
}

/// Asks the budget clock for one more expansion after `n_expanded`: the next value of
/// `n_expanded` at which to ask again, or `None` when the budget is exhausted.
#[cold]
#[inline(never)]
fn ask_clock(clock: &mut BudgetClock, n_expanded: u64, timed: bool) -> Option<u64> {
    if clock.allows(n_expanded) {
        Some(if timed { n_expanded + 1 } else { u64::MAX })
    } else {
        None
    }
}

/// Copies the current path (the frames below the top, the top's cell, the goal) into `best`.
/// Out of line and cold, so that the hot loop keeps nothing live for it.
#[cold]
#[inline(never)]
fn record_path(best: &mut Vec<u32>, below: &[Frame], top: u32, goal: u32) {
    best.clear();
    best.extend(below.iter().map(|f| f.cell));
    best.push(top);
    best.push(goal);
}

/// The rank key `D << 32 | T` of a path: since Score = D + T, ordering keys as integers
/// orders paths exactly as [`PathRank`] does (D, then T, then Score), in one comparison.
/// Both D and T are below 2^31 (a path visits each of at most 2^31 cells once).
#[inline(always)]
fn rank_key(steps: u64, turns: u64) -> u64 {
    steps << 32 | turns
}

/// The [`PathRank`] of a rank key.
fn rank_of(key: u64) -> PathRank {
    let (steps, turns) = (key >> 32, key & 0xffff_ffff);
    PathRank {
        steps,
        turns,
        score: steps + turns,
    }
}

impl Search<'_> {
    /// Runs the search specialised for `prune` and the number of moves. The root tries
    /// only the moves in `root_mask` (all: `u64::MAX`).
    fn dispatch(
        &mut self,
        prune: Prune,
        start: usize,
        goal: usize,
        budget: &Budget,
        root_mask: u64,
    ) -> Run {
        match prune {
            Prune::Off => match self.n_moves {
                4 => self.run::<false, 4>(start, goal, budget, root_mask),
                8 => self.run::<false, 8>(start, goal, budget, root_mask),
                _ => self.run::<false, 0>(start, goal, budget, root_mask),
            },
            Prune::Bound => self.run::<true, 0>(start, goal, budget, root_mask),
        }
    }

    /// The neighbour of padded cell `p` by move `m`.
    #[inline(always)]
    fn neighbor(&self, p: usize, m: u32) -> usize {
        p.wrapping_add_signed(self.delta[(m & 63) as usize])
    }

    /// The moves of padded cell `p` whose target is on the current path (bit m = move m).
    /// Border cells are never visited, so an unsafe move may set no bit or a harmless one.
    /// `K` is the number of moves when known at compile time (4 or 8), else 0.
    #[inline(always)]
    fn visited_mask<const K: usize>(&self, p: usize) -> u64 {
        let n = if K == 0 { self.n_moves } else { K };
        let mut mask = 0u64;
        for m in 0..n {
            let q = self.neighbor(p, m as u32);
            mask |= self.cells.get(q).map_or(0, |w| w >> 63) << m;
        }
        mask
    }

    /// Fig. 5 on an explicit stack. `PRUNE` selects the branch and bound; `K` is the number
    /// of moves (4 or 8) when specialised, else 0.
    ///
    /// While a call is open the current path above it does not change, so which of its
    /// neighbours are blocked, on the path, or free is fixed when it is entered: without
    /// pruning the call's blocked and skipped checks are counted then and only its free
    /// neighbours are iterated, and a call with no free neighbour is a dead end that
    /// returns at once without being pushed. The turns of the current path are kept in a
    /// running count, adjusted on every push and pop.
    #[inline(never)]
    fn run<const PRUNE: bool, const K: usize>(
        &mut self,
        start: usize,
        goal: usize,
        budget: &Budget,
        root_mask: u64,
    ) -> Run {
        let k = if K == 0 {
            self.n_moves as u64
        } else {
            K as u64
        };
        let mut clock = budget.start();
        // A time limit or a cancel flag is read by the clock on its own interval.
        let timed = budget.max_time.is_some() || budget.cancel.is_some();
        // Expansions are counted locally; the clock is asked when `n_expanded` reaches
        // `next_check`: at the expansion limit, or at every expansion under a time limit
        // or a cancel flag.
        let mut next_check = if timed {
            0
        } else {
            budget.max_expansions.unwrap_or(u64::MAX)
        };
        let mut stats = SearchStats::default();
        let mut pruned = 0u64;

        if next_check == 0 {
            if !clock.allows(0) {
                return Run {
                    stats,
                    pruned,
                    complete: false,
                    best: None,
                };
            }
            next_check = if timed { 1 } else { u64::MAX };
        }
        // The root call. From here on `n_expanded = next_check - left`: the loop only
        // counts `left` down, and asks the clock when it reaches zero.
        let mut max_depth = 1u64;
        let mut left = next_check - 1;
        if start == goal {
            self.best.push(start as u32);
            stats.n_expanded = 1;
            stats.n_solutions = 1;
            stats.max_depth = 1;
            return Run {
                stats,
                pruned,
                complete: true,
                best: Some(rank_of(0)),
            };
        }
        let root_safe = self.cells[start] & self.all;
        // Every non-goal call checks all k moves, and every call but the root returns once:
        // `n_neighbor_checks` and `n_backtracks` are computed from the calls made and the
        // calls still open when the search ends, not counted one by one in the loop.
        let mut n_blocked = k - popcount::<K>(root_safe);
        let mut n_skipped = 0u64;
        let mut n_solutions = 0u64;
        let mut n_dead_ends = 0u64;
        // Rank key of the best solution so far; u64::MAX for none.
        let mut best = u64::MAX;
        self.cells[start] |= VISITED;
        let mut top = Frame {
            remaining: root_safe & root_mask,
            cell: start as u32,
            entered_by: NO_MOVE,
        };
        // Frames below `top` are stack[..depth]; the current path has depth + 1 cells.
        let mut depth = 0usize;
        // Turns of the current path (start to top), kept as `u32::MAX` (that is, -1) at the
        // root: see [`turns`].
        let mut path_turns = u32::MAX;
        // Set when the budget refuses a call: the move that would have made it.
        let mut refused: Option<u32> = None;
        loop {
            if (if PRUNE {
                top.remaining & !DESCENDED
            } else {
                top.remaining
            }) == 0
            {
                // Every move of this call has been checked: return from it.
                self.cells[top.cell as usize] &= !VISITED;
                if depth == 0 {
                    // Without pruning, every call pushed below the root descends, and
                    // the root does unless it has no safe move at all.
                    let descended = if PRUNE {
                        top.remaining & DESCENDED != 0
                    } else {
                        root_safe & root_mask != 0
                    };
                    n_dead_ends += u64::from(!descended);
                    break;
                }
                if PRUNE {
                    n_dead_ends += u64::from(top.remaining & DESCENDED == 0);
                }
                depth -= 1;
                let parent = self.stack[depth];
                path_turns = path_turns.wrapping_sub(turns(parent.entered_by, top.entered_by));
                top = parent;
                continue;
            }
            let m = top.remaining.trailing_zeros();
            top.remaining &= top.remaining - 1;
            let next = self.neighbor(top.cell as usize, m);
            let word = self.cells[next];
            if PRUNE && word & VISITED != 0 {
                n_skipped += 1;
                continue;
            }
            let next_turns = path_turns.wrapping_add(turns(top.entered_by, m));
            // Steps from the start to `next`.
            let steps = depth as u64 + 1;
            if PRUNE && best != u64::MAX {
                let b = rank_of(best);
                let lower = steps + u64::from(self.lower_bound[next]);
                if lower > b.steps || (lower == b.steps && u64::from(next_turns) >= b.turns) {
                    pruned += 1;
                    continue;
                }
            }
            if left == 0 {
                match ask_clock(&mut clock, next_check, timed) {
                    Some(next) => {
                        left = next - next_check;
                        next_check = next;
                    }
                    None => {
                        refused = Some(m);
                        break;
                    }
                }
            }
            left -= 1;
            if PRUNE {
                top.remaining |= DESCENDED;
            }
            max_depth = max_depth.max(steps + 1);
            if next == goal {
                // A goal call: record the solution and return at once. A solution
                // replaces the best only when strictly better: ties keep the first.
                n_solutions += 1;
                let key = rank_key(steps, u64::from(next_turns));
                if key < best {
                    best = key;
                    record_path(self.best, &self.stack[..depth], top.cell, next as u32);
                }
                continue;
            }
            let safe = word & self.all;
            n_blocked += k - popcount::<K>(safe);
            let remaining = if PRUNE {
                safe
            } else {
                let on_path = safe & self.visited_mask::<K>(next);
                n_skipped += popcount::<K>(on_path);
                let free = safe ^ on_path;
                if free == 0 {
                    // A dead end: it returns at once.
                    n_dead_ends += 1;
                    continue;
                }
                free
            };
            self.cells[next] = word | VISITED;
            self.stack[depth] = top;
            depth += 1;
            path_turns = next_turns;
            top = Frame {
                remaining,
                cell: next as u32,
                entered_by: m,
            };
        }

        let n_expanded = next_check - left;
        let complete = refused.is_none();
        // Calls still open: the root and the `depth` calls above it (none when complete).
        let open = if complete { 0 } else { depth as u64 + 1 };
        let mut n_checks = k * (n_expanded - n_solutions);
        let n_backtracks = n_expanded - 1 - open.saturating_sub(1);
        if let Some(refused) = refused {
            // Uncount the checks the open calls had not reached: in the deepest call the
            // refused move and those after it, in every other the moves after the one that
            // entered its child. Unwinding from the deepest call, the visited marks are
            // those each call saw when it was entered.
            let mut first_unchecked = refused;
            let mut frame = top;
            loop {
                let p = frame.cell as usize;
                let unchecked = self.all >> first_unchecked;
                let safe = (self.cells[p] & self.all) >> first_unchecked;
                n_checks -= u64::from(unchecked.count_ones());
                n_blocked -= u64::from((unchecked & !safe).count_ones());
                if !PRUNE {
                    let on_path = safe & (self.visited_mask::<K>(p) >> first_unchecked);
                    n_skipped -= u64::from(on_path.count_ones());
                }
                self.cells[p] &= !VISITED;
                if depth == 0 {
                    break;
                }
                first_unchecked = frame.entered_by + 1;
                depth -= 1;
                frame = self.stack[depth];
            }
        }
        stats.n_expanded = n_expanded;
        stats.n_neighbor_checks = n_checks;
        stats.n_blocked = n_blocked;
        stats.n_skipped = n_skipped;
        stats.n_solutions = n_solutions;
        stats.n_dead_ends = n_dead_ends;
        stats.n_backtracks = n_backtracks;
        stats.max_depth = max_depth;
        Run {
            stats,
            pruned,
            complete,
            best: (best != u64::MAX).then(|| rank_of(best)),
        }
    }
}

impl Planner for Backtracking {
    fn name(&self) -> &str {
        "backtracking"
    }

    fn specs(&self) -> planner_api::PlannerSpecs {
        planner_api::PlannerSpecs::deterministic(planner_api::PathSpec::Moves(self.moves.clone()))
    }

    /// Refuses with [`Outcome::over_memory`] when [`Backtracking::memory_bytes_for`] the
    /// grid and budget is over [`Budget::max_memory_mb`].
    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        let grid = problem.grid();
        if let Err(shortfall) = budget.check_memory(self.memory_bytes_for(grid, budget), grid) {
            let mut counters = SearchStats::default().report(Counter::BACKTRACKING);
            if self.config.prune != Prune::Off {
                counters.push("n_pruned", 0);
            }
            return Outcome::over_memory(shortfall, counters);
        }
        let run = self.run(problem, budget);
        let mut counters = run.stats.report(Counter::BACKTRACKING);
        if self.config.prune != Prune::Off {
            counters.push("n_pruned", run.pruned);
        }
        let path = match (&run.best, &self.adjacency) {
            (Some(_), Some(adjacency)) => Some(Path::new(
                self.best
                    .iter()
                    .map(|&p| adjacency.cell(p as usize))
                    .collect::<Vec<Cell>>(),
            )),
            _ => None,
        };
        match (run.complete, path) {
            (true, Some(path)) => Outcome::found(path, counters),
            (true, None) => Outcome::no_path(counters),
            (false, path) => Outcome::budget_exhausted(path, counters),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rank_key_orders_as_path_rank() {
        let pairs = [
            (0, 0),
            (1, 0),
            (1, 5),
            (2, 0),
            (2, 1),
            (7, 3),
            (7, 4),
            (9, 0),
            (1 << 30, 1 << 30),
        ];
        for &(d1, t1) in &pairs {
            for &(d2, t2) in &pairs {
                let rank = |d: u64, t: u64| PathRank {
                    steps: d,
                    turns: t,
                    score: d + t,
                };
                assert_eq!(
                    rank_key(d1, t1).cmp(&rank_key(d2, t2)),
                    rank(d1, t1).cmp(&rank(d2, t2)),
                    "({d1}, {t1}) vs ({d2}, {t2})"
                );
                assert_eq!(rank_of(rank_key(d1, t1)), rank(d1, t1));
            }
        }
    }

    #[test]
    fn frames_are_16_bytes() {
        assert_eq!(std::mem::size_of::<Frame>(), 16);
    }
}
