//! Jump Point Search: optimal 8-connected grid paths that expand only jump points.
//!
//! Sources: Harabor and Grastien, "Online Graph Pruning for Pathfinding on Grid Maps"
//! (AAAI 2011, <https://doi.org/10.1609/aaai.v25i1.7994>), and "Improving Jump Point
//! Search" (ICAPS 2014, <https://doi.org/10.1609/icaps.v24i1.13633>): block-based jumps,
//! pruned intermediate jump points and JPS+.
//!
//! # Preconditions
//! JPS is defined here for 8-connected moves **without corner cutting**, the Moving AI
//! rule: a diagonal move needs both orthogonal cells beside it free; straight moves cost 1
//! and diagonal ones `sqrt 2`. [`Config`] rejects `moves` other than 8 and
//! `corner_cutting = true` with an error naming the key. The heuristic is octile distance.
//!
//! # The search
//! A* over jump points. A node reached by a move in direction `d` expands only the
//! directions its pruning rules keep, and each direction is a *jump*: a walk that stops at
//! the first jump point, which becomes a successor with cost `g + octile distance`.
//! Without corner cutting (the 2014 paper's setting) the rules are:
//! - after a straight move east, keep east; if the cell north is free and the cell
//!   north-west blocked, also north and north-east (a *forced* neighbour), and the same
//!   for south; likewise for the other three straight directions;
//! - after a diagonal move, keep its two component directions and the diagonal itself
//!   (diagonal moves have no forced neighbours under this rule);
//! - the start expands all eight directions.
//!
//! A straight jump stops at the goal or at a cell where the rule above finds a forced
//! neighbour; a diagonal jump stops at the goal or at a cell from which one of the two
//! straight component jumps reaches a jump point. A jump that meets a wall (or the
//! grid's edge, or a diagonal move that would cut a corner) yields nothing.
//!
//! **Choices where the papers leave room.** A node reached at equal cost by moves in
//! different directions expands the union of their directions (each relaxation that ties
//! adds its direction). OPEN pops the least `f`. Among equal `f`, entries pushed with the
//! `f` of the entry last taken from the heap come first, last in first out (a successor
//! on the way to the goal keeps its parent's `f`, so this skips most heap operations);
//! the others come by larger `g` (to 1/1024, as the `pathfinding` crate's A* prefers
//! larger `g`), then lower record index. The path between a node and its successor is
//! diagonal first, then straight, which is how every jump reaches it.
//!
//! # Variants ([`Variant`])
//! - `jps`: the 2011 algorithm with the 2014 paper's block-based straight jumps: the grid
//!   is kept bit-packed (plus a transposed copy for vertical jumps), and a straight jump
//!   reads 64 cells at a time from its row and the two rows beside it, finding the first
//!   blocked or forced cell with one bit count.
//! - `jps_prime` (2014's "JPS'", pruned intermediate jump points): a diagonal jump does not
//!   stop where a component jump finds a jump point; that jump point becomes a successor
//!   of the node being expanded and the diagonal walk goes on.
//! - `jps_plus` (2014's JPS+ with pruned intermediate points, "JPS+'"): the jump
//!   distances of every cell and direction are computed once per grid (see
//!   [`Jps::precompute`]; 8 bytes per cell) and reused for every query on that grid, so a
//!   jump is a table read. Where the goal is not on a jump's way the results are the
//!   online ones; where it is, a straight jump stops at the goal, and a diagonal walk
//!   with the goal in its quadrant at `m` diagonal steps (`m` = the smaller of the goal's
//!   offsets) stops at that cell (the *target jump point*, on the goal's row or column)
//!   when the table's jump reaches at least that far.
//!
//! The grid's derived data (bit rows and columns, the jump table, the goal bounds) is
//! cached in the planner and rebuilt only for a grid with other cells (checked by
//! [`Grid::revision`], then by comparing cells); after edits in place
//! ([`Grid::changed_since`]) the bit rows and columns follow the edited cells, and the
//! jump table and goal bounds are rebuilt.
//!
//! # Goal bounding
//! With [`Config::goal_bounding`], any variant prunes by goal bounds (Rabin and Sturtevant,
//! AAAI 2016, kept for jump points only as in Hu, Harabor, Qin and Yin, JAIR 2021): for
//! every jump point and direction, the bounding box of the cells that some shortest path
//! leaving the point that way reaches; an expansion skips the directions whose box does
//! not hold the goal. The boxes hold every shortest path, not only JPS's canonical ones
//! (a choice: larger boxes than the papers', but no reliance on JPS's own pruning), so the
//! path found is still a shortest one, possibly another of the same cost, and the counters
//! drop. They cost one Dijkstra search over the grid per jump point, once per grid, on
//! the rayon pool, and 64 bytes per jump point: on den520d 12,351 jump points, about 15 s
//! on the 2-core test machine and 1 MB, after which JPS+ expanded 19,167 nodes for its
//! 888 scenarios instead of 38,063, in half the time (`cargo bench -p planner-jps --bench
//! movingai -- --goal-bounding den520d`, which prints both). A query that has to build
//! them stops the build when its budget's time limit passes or its cancel flag is raised
//! (read before each jump point's search): it ends `budget_exhausted` with zero counters
//! and no boxes are kept, so the next query builds them again; the expansion limit is the
//! search's alone. [`Planner::prepare`] and [`Jps::precompute`] build them ahead of the
//! queries, without a limit. On a grid wider or taller than 65,535 cells there are no
//! boxes.
//!
//! # Precomputation and memory
//! Every variant keeps the bit grid: two bit copies with padding, 90,464 bytes for a
//! 512 x 512 map. `jps_plus` adds the jump table, 8 bytes per cell: 2,097,152 bytes for
//! 512 x 512 (random512-10-0), built in 15 to 40 ms on the shared 2-core test machine
//! (plus a transient 4 bytes per cell while it is built); `cargo bench -p planner-jps --bench
//! movingai` prints the time and sizes on each run. The per-query state is 18 bytes per
//! cell (cost, parent, a generation tag, so nothing is cleared between queries, and a
//! two-byte open-or-closed mark). Goal bounds add 4 bytes per node record and 64 per jump
//! point (and, while they are built, at most 37 bytes per cell of Dijkstra scratch for
//! each of the build's 8 groups of jump points, whatever the machine's threads, so that
//! whether a search fits a memory budget does not depend on the machine).
//!
//! # Costs
//! Costs are exact: `g` is a [`Cost`], a count of straight and of diagonal moves compared
//! in integers, so equal path costs compare equal. OPEN orders by the `f64` value of the
//! exact `f`; two different costs below 2^20 differ by more than 2^-21 (because
//! `|s - d sqrt 2| >= 1 / (s + d sqrt 2)`), far above rounding, so this order is exact on any
//! grid where path costs stay below 2^20.
//!
//! # Counters
//! - `n_expanded`: jump points popped from OPEN and expanded (the goal included, as in A*).
//! - `n_scanned` (`jps`, `jps_prime`): cells the jumps move onto. A straight jump that
//!   stops at a jump point `k` cells on, or at a wall after `k` free cells, counts `k`;
//!   each diagonal step onto a cell counts 1, plus the straight component jumps from there.
//!   Block-based jumps read 64 cells at a time but count the cells up to their stop.
//! - `n_lookups` (`jps_plus`): jump-table entries read.
//! - `n_open_insertions`: first insertions into OPEN (the start's included).
//! - `n_relaxations`: times a jump point gets a new parent and `g` (its first reach
//!   included); a reach at equal `g` only adds its direction.
//! - `peak_open`: the most nodes in OPEN at once.
//!
//! Every counter, jump point and path of the three variants equals that of
//! `planner_testkit::reference_jps`, the same search written again with every jump walked
//! cell by cell and std's binary heap, on 3,000 small random grids and 32 large ones
//! (`tests/reference.rs`) and on every JPS run of `configs/movingai.toml` (xtask's
//! `every_jps_run_matches_the_reference_search`).
//!
//! # Recording
//! With [`Budget::record_expanded`] the expanded jump points are listed in
//! [`Outcome::expanded`]; with [`Budget::record_events`] the search is recorded step by
//! step ([`Outcome::events`]): each push of a jump point into OPEN (`generating` the first
//! time, `updating` when a cheaper jump reaches it), with the jump point it was jumped to
//! from as parent, `g` and `f = g + octile(cell, goal)`, and each expansion. The recording
//! search is a copy of the loop of its own (a const parameter), so the timed one has no
//! recording code. Scanned cells are not steps. Tested against the counters, the path
//! and the heuristic in `tests/events.rs`.
//!
//! # Example
//! From (0, 0) to the goal G = (3, 2) on a 4 x 3 grid with one blocked cell at (1, 1):
//! ```
//! use planner_api::{Budget, Cell, Grid, Planner, Problem, Status};
//! use planner_jps::{Config, Jps, Variant};
//!
//! let grid = Grid::from_ascii("
//!     ....
//!     .#..
//!     ....
//! ").unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(3, 2)).unwrap();
//! for (variant, counters) in [
//!     (Variant::Jps, "n_expanded=4 n_scanned=10 n_open_insertions=6 n_relaxations=5 peak_open=3"),
//!     (Variant::JpsPrime, "n_expanded=3 n_scanned=9 n_open_insertions=5 n_relaxations=4 peak_open=3"),
//!     (Variant::JpsPlus, "n_expanded=3 n_lookups=14 n_open_insertions=5 n_relaxations=4 peak_open=3"),
//! ] {
//!     let mut jps = Jps::new(Config { variant, ..Config::default() }).unwrap();
//!     let outcome = jps.plan(&problem, &Budget::unlimited());
//!     assert_eq!(outcome.status, Status::Found);
//!     assert_eq!(outcome.counters.to_string(), counters);
//!     let path = outcome.path.unwrap();
//!     let cells: Vec<(u32, u32)> = path.cells().iter().map(|c| (c.x, c.y)).collect();
//!     assert_eq!(cells, [(0, 0), (1, 0), (2, 0), (3, 1), (3, 2)]);
//!     assert!((path.metrics().length - (3.0 + 2f64.sqrt())).abs() < 1e-12);
//!     let first_mark = outcome.marks.first().map(|m| (m.cell, m.label.as_str()));
//!     assert_eq!(first_mark, Some((Cell::new(2, 0), "J1")));
//! }
//! ```
//! Hand count for `jps` (f = g + h, h octile to G). The start expands all eight
//! directions. East moves onto (1, 0) (not forced: the row below is blocked at (1, 1)) and
//! (2, 0), forced since (2, 1) is free and (1, 1), one step back, blocked: a jump point, 2
//! cells scanned. South likewise stops at the forced (0, 2) after 2 cells. The other six
//! directions fail at their first move (south-east onto the blocked (1, 1), the rest off
//! the grid): 0 cells. So far 4 scanned, 3 insertions (the start's included), 2
//! relaxations. OPEN: (2, 0) with f = 2 + (1 + sqrt 2) = 4.41, (0, 2) with f = 2 + 3 = 5.
//!
//! (2, 0) is expanded (reached moving east: east; the free (2, 1) below with the blocked
//! (1, 1) behind adds south and south-east). East: (3, 0), then the border: 1 cell.
//! South: (2, 1), then (2, 2), forced by (1, 2) free and (1, 1) blocked: 2 cells, a jump
//! point with f = 4 + 1 = 5. South-east: one diagonal step to (3, 1) (1 cell), whose east
//! jump fails (0) and whose south jump reaches G (1): (3, 1) is a jump point with
//! f = (2 + sqrt 2) + 1 = 4.41. Now 9 scanned, 5 insertions, 4 relaxations, and OPEN holds 5 - 2 = 3
//! nodes (`peak_open`). (3, 1) is expanded (reached diagonally: south-east, east, south):
//! south reaches G after 1 cell (10 scanned; G inserted, f = 4.41), east and south-east
//! leave the grid. G is popped and is the fourth expansion. Path cost `3 + sqrt 2`; the
//! marks are the jump points between start and goal, J1 = (2, 0) and J2 = (3, 1).
//!
//! `jps_prime` scans the same cells up to (2, 0)'s south-east walk, where the south jump's
//! result G becomes a successor of (2, 0) directly and (3, 1) is never inserted: 9 cells,
//! 3 expansions, 5 insertions, 4 relaxations, peak 3. `jps_plus` reads 8 entries at the
//! start (all jumps end at a wall), 3 for (2, 0)'s east, south and south-east, where G is
//! in the quadrant 1 diagonal step away, within the table's reach of 1: the target jump
//! point (3, 1), whose east and south entries are read (2; south meets G) and then its
//! south-east entry (1; the walk ends): 14 lookups.
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

mod bits;
mod bounds;
mod cost;
mod plus;

use bits::{diagonal, BitGrid, DX, DY};
use bounds::{GoalBounds, Stopped};
pub use cost::Cost;
use planner_api::{
    push_octile_leg, Budget, Cell, Connectivity, Counters, Grid, Mark, MoveSet, Outcome, ParamKey,
    Path, PathSpec, Planner, PlannerSpecs, Problem, SearchEvent, SearchEventKind, Status,
};
use planner_search::FrontHeap as Open;
use plus::JumpTable;
use serde::{Deserialize, Serialize};
use std::time::Instant;
use thiserror::Error;

/// The registry name of this planner.
pub const NAME: &str = "jps";

/// Which Jump Point Search runs (see the crate docs).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Variant {
    /// Online JPS (2011) with block-based jumps (2014).
    #[default]
    Jps,
    /// Online JPS with pruned intermediate jump points (2014's JPS').
    JpsPrime,
    /// Jump distances precomputed per grid, with pruned intermediate points (2014's JPS+).
    JpsPlus,
}

impl Variant {
    /// The name used in configs: `jps`, `jps_prime`, `jps_plus`.
    pub fn as_str(self) -> &'static str {
        match self {
            Variant::Jps => "jps",
            Variant::JpsPrime => "jps_prime",
            Variant::JpsPlus => "jps_plus",
        }
    }
}

/// JPS's parameters. Every field has a default; see [`Config::default`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// The variant: `"jps"`, `"jps_prime"` or `"jps_plus"`. Default `"jps"`.
    pub variant: Variant,
    /// Neighbourhood; JPS is defined here for 8 only (any other value is an error). Default 8.
    #[schemars(with = "u32", extend("enum" = [8]))]
    pub moves: Connectivity,
    /// Corner cutting; must be false (the Moving AI rule). Default false.
    pub corner_cutting: bool,
    /// Report the path's jump points as marks `J1`, `J2`, ... (start and goal excluded).
    /// Default true.
    pub marks: bool,
    /// Goal bounding ([crate docs](crate#goal-bounding)): per jump point and direction,
    /// the box of the cells a shortest path leaving that way reaches, computed once per
    /// grid (one Dijkstra search per jump point); an expansion skips the directions whose
    /// box misses the goal. Paths stay optimal. Any variant. Default false.
    pub goal_bounding: bool,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            variant: Variant::Jps,
            moves: Connectivity::Eight,
            corner_cutting: false,
            marks: true,
            goal_bounding: false,
        }
    }
}

/// A parameter JPS cannot run with.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConfigError {
    /// `moves` is not 8.
    #[error("parameter `moves`: JPS is defined here for 8-connected moves only, got {0}")]
    Moves(u32),
    /// `corner_cutting` is true.
    #[error(
        "parameter `corner_cutting`: JPS is defined here without corner cutting (a diagonal move needs both orthogonal cells free)"
    )]
    CornerCutting,
}

impl ParamKey for ConfigError {
    fn param_key(&self) -> &str {
        match self {
            ConfigError::Moves(_) => "moves",
            ConfigError::CornerCutting => "corner_cutting",
        }
    }
}

/// What the grid's precomputation holds, from [`Jps::precompute`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Prepared {
    /// Bytes of the bit-packed rows and columns (every variant).
    pub bit_grid_bytes: usize,
    /// Bytes of the jump table (`jps_plus` only, else 0).
    pub jump_table_bytes: usize,
    /// Bytes of the goal bounds (with `goal_bounding`, else 0).
    pub goal_bounds_bytes: usize,
    /// Jump points with goal bounds (with `goal_bounding`, else 0).
    pub goal_bounded_points: usize,
}

/// The planner. Build with [`Jps::new`]; reuse it for many queries on a grid.
#[derive(Debug, Clone)]
pub struct Jps {
    config: Config,
    /// The moves the paths are made of (for [`PlannerSpecs`]).
    moves: MoveSet,
    bits: Option<BitGrid>,
    table: Option<JumpTable>,
    bounds: Option<GoalBounds>,
    nodes: Vec<Node>,
    generation: u32,
    open: Open,
    /// Two bytes per node record: `2 m` when the node is in OPEN in this search, `2 m + 1`
    /// when it is closed, anything else when this search has not reached it (`m` =
    /// `mark`): 128 KiB for 256 x 256, half a megabyte for 512 x 512, which stays in cache,
    /// so relaxing a jump point that is closed or new (most relaxations) reads no node
    /// record.
    state: Vec<u16>,
    /// The current search's `m` in `state`; it cycles through 1 to 32,767, and the array is
    /// cleared when it wraps.
    mark: u16,
    /// The jump points of the last path found, start to goal (a reused buffer).
    chain: Vec<u32>,
}

/// Per-cell search state, 16 bytes. `tag` is `generation << 9 | incoming << 1 | closed`,
/// where `incoming` holds the directions of the moves that reached the node at cost `g`
/// (bit `d`; 0 for the start, which expands all directions). A record is read only when
/// `Jps::state` says this search has reached the node, so nothing is cleared between
/// searches.
#[derive(Debug, Clone, Copy, Default)]
struct Node {
    g: Cost,
    parent: u32,
    tag: u32,
}

impl Node {
    #[inline(always)]
    fn incoming(self) -> u8 {
        (self.tag >> 1) as u8
    }
}

/// The search's counters as plain integers.
#[derive(Debug, Clone, Copy, Default)]
struct Tally {
    n_expanded: u64,
    n_scanned: u64,
    n_open_insertions: u64,
    n_relaxations: u64,
    peak_open: u64,
}

const JPS: u8 = 0;
const JPS_PRIME: u8 = 1;
const JPS_PLUS: u8 = 2;

impl Jps {
    /// A planner with `config`, validated.
    pub fn new(config: Config) -> Result<Jps, ConfigError> {
        if config.moves != Connectivity::Eight {
            return Err(ConfigError::Moves(config.moves.n_directions()));
        }
        if config.corner_cutting {
            return Err(ConfigError::CornerCutting);
        }
        Ok(Jps {
            config,
            moves: MoveSet::standard(Connectivity::Eight),
            bits: None,
            table: None,
            bounds: None,
            nodes: Vec::new(),
            generation: 0,
            open: Open::default(),
            state: Vec::new(),
            mark: 0,
            chain: Vec::new(),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// Builds (or finds cached) the grid's derived data: the bit grid, for `jps_plus` the
    /// jump table, and with `goal_bounding` the goal bounds (without a time limit).
    /// [`Planner::plan`] calls it; call it first to time the precomputation apart from the
    /// queries ([`Planner::prepare`] calls it too).
    pub fn precompute(&mut self, grid: &Grid) -> Prepared {
        match self.precompute_until(grid, &|| false) {
            Ok(prepared) => prepared,
            Err(Stopped) => unreachable!("nothing stops the build"),
        }
    }

    /// [`Jps::precompute`], giving up the goal bounds' build (none are kept) when `stop`
    /// says so; it is read before each jump point's search.
    fn precompute_until(
        &mut self,
        grid: &Grid,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<Prepared, Stopped> {
        let (bits, rebuilt) = BitGrid::cached(&mut self.bits, grid);
        if rebuilt {
            self.bounds = None;
        }
        if self.config.variant == Variant::JpsPlus && (rebuilt || self.table.is_none()) {
            self.table = Some(JumpTable::build(bits));
        }
        if self.config.goal_bounding && self.bounds.is_none() {
            // The jump points are where the table's jumps end (any variant's).
            let built;
            let table = match &self.table {
                Some(table) => table,
                None => {
                    built = JumpTable::build(bits);
                    &built
                }
            };
            self.bounds = GoalBounds::build(bits, table, index_shift(grid), stop)?;
        }
        Ok(Prepared {
            bit_grid_bytes: bits.memory_bytes(),
            jump_table_bytes: self.table.as_ref().map_or(0, JumpTable::memory_bytes),
            goal_bounds_bytes: self.bounds.as_ref().map_or(0, GoalBounds::memory_bytes),
            goal_bounded_points: self.bounds.as_ref().map_or(0, GoalBounds::n_jump_points),
        })
    }

    /// The bytes of the grid's derived data and the per-query state for `grid`, at most:
    /// two bit copies (with a 64-bit word of padding per row and column, rounded up to 3
    /// words), the node records and open-or-closed marks (18 bytes each, rows of a power-of-two
    /// length), and for `jps_plus` the jump table and its transient (12 bytes per cell).
    pub fn memory_bytes_for(&self, grid: &Grid) -> u64 {
        let (w, h) = (u64::from(grid.width()), u64::from(grid.height()));
        let bit_grid = 8 * ((w.div_ceil(64) + 3) * (h + 2) + (h.div_ceil(64) + 3) * (w + 2));
        let records = (h << index_shift(grid)) * 18;
        let table = match (self.config.variant, self.config.goal_bounding) {
            (Variant::JpsPlus, _) | (_, true) => 12 * w * h,
            _ => 0,
        };
        // Goal bounds: a slot per record and 64 bytes per jump point (at most every cell),
        // and while they are built the Dijkstra scratch of each of the build's groups.
        let bounds = match self.config.goal_bounding {
            true => {
                let scratch = bounds::SCRATCH_BYTES_PER_CELL * w * h * bounds::BUILD_GROUPS;
                (h << index_shift(grid)) * 4 + 64 * w * h + scratch
            }
            false => 0,
        };
        bit_grid + records + table + bounds
    }

    fn search<const VARIANT: u8, const RECORD: bool>(
        &mut self,
        problem: &Problem<'_>,
        budget: &Budget,
    ) -> Outcome {
        let grid = problem.grid();
        let counter_names = [
            "n_expanded",
            if VARIANT == JPS_PLUS {
                "n_lookups"
            } else {
                "n_scanned"
            },
            "n_open_insertions",
            "n_relaxations",
            "peak_open",
        ];
        let zero_counters = || {
            let mut counters = Counters::new();
            for name in counter_names {
                counters.push(name, 0);
            }
            counters
        };
        if let Err(shortfall) = budget.check_memory(self.memory_bytes_for(grid), grid) {
            return Outcome::over_memory(shortfall, zero_counters());
        }
        let record = budget.record_expanded;
        let mut expanded = Vec::new();
        // The goal bounds' build stops at the budget's time limit or cancel flag.
        let deadline = budget.max_time.map(|limit| Instant::now() + limit);
        let stop = || budget.is_cancelled() || deadline.is_some_and(|d| Instant::now() >= d);
        if self.precompute_until(grid, &stop).is_err() {
            return Outcome::budget_exhausted(None, zero_counters());
        }
        self.size_nodes(grid);
        let (Some(bits), table, bounds) = (&self.bits, &self.table, &self.bounds) else {
            unreachable!("precompute fills the bit grid")
        };
        self.generation += 1;
        if self.generation >= 1 << 23 {
            self.nodes.fill(Node::default());
            self.generation = 1;
        }
        self.mark += 1;
        if self.mark >= 1 << 15 {
            self.state.fill(0);
            self.mark = 1;
        }
        self.open.clear();
        let mut search = Search {
            bits,
            table: table.as_ref(),
            bounds: bounds.as_ref(),
            nodes: &mut self.nodes,
            state: &mut self.state,
            open_mark: 2 * self.mark,
            closed_mark: 2 * self.mark + 1,
            open: &mut self.open,
            shift: index_shift(grid),
            goal: problem.goal(),
            generation: self.generation << 9,
            tally: Tally::default(),
            events: Vec::new(),
        };
        let start = problem.start();
        let start_index = search.index(start.x, start.y);
        search.nodes[start_index as usize] = Node {
            g: Cost::default(),
            parent: start_index,
            tag: search.generation,
        };
        search.state[start_index as usize] = search.open_mark;
        search.push(start_index, Cost::default(), start.x, start.y);
        if RECORD {
            search.note(
                SearchEventKind::Generating,
                start_index,
                None,
                Cost::default(),
            );
        }
        search.tally.n_open_insertions = 1;
        search.tally.peak_open = 1;
        let goal = problem.goal();
        let goal_index = search.index(goal.x, goal.y);
        let mut clock = budget.start();
        let status = loop {
            let Some((_, tie_and_node)) = search.open.pop() else {
                break Status::NoPath;
            };
            let p = tie_and_node as u32;
            let node = search.nodes[p as usize];
            if node.tag & 1 != 0 {
                continue; // An older entry of a node improved while in OPEN.
            }
            if !clock.allows(search.tally.n_expanded) {
                break Status::BudgetExhausted;
            }
            search.nodes[p as usize].tag |= 1;
            search.state[p as usize] = search.closed_mark;
            search.tally.n_expanded += 1;
            if record {
                expanded.push(Cell::new(p & ((1 << search.shift) - 1), p >> search.shift));
            }
            if RECORD {
                let parent = (p != start_index).then_some(node.parent);
                search.note(SearchEventKind::Expanding, p, parent, node.g);
            }
            if p == goal_index {
                break Status::Found;
            }
            search.expand::<VARIANT, RECORD>(p, node);
            let t = &mut search.tally;
            t.peak_open = t.peak_open.max(t.n_open_insertions - t.n_expanded);
        };
        let tally = search.tally;
        let events = std::mem::take(&mut search.events);
        let mut counters = Counters::new();
        for (name, value) in counter_names.into_iter().zip([
            tally.n_expanded,
            tally.n_scanned,
            tally.n_open_insertions,
            tally.n_relaxations,
            tally.peak_open,
        ]) {
            counters.push(name, value);
        }
        let outcome = match status {
            Status::Found => {
                let (path, marks) = self.reconstruct(grid, start_index, goal_index);
                let mut outcome = Outcome::found(path, counters);
                outcome.marks = marks;
                outcome
            }
            Status::NoPath => Outcome::no_path(counters),
            Status::BudgetExhausted => Outcome::budget_exhausted(None, counters),
        };
        let mut outcome = outcome.with_expanded(expanded);
        outcome.events = events;
        outcome
    }

    /// Sizes the node records for `grid`: rows of a power-of-two length, so that a
    /// record's cell is two bit operations away (no division per expansion).
    fn size_nodes(&mut self, grid: &Grid) {
        let len = (grid.height() as usize) << index_shift(grid);
        if self.nodes.len() != len {
            self.nodes = vec![Node::default(); len];
            self.generation = 0;
            self.state = vec![0; len];
            self.mark = 0;
        }
    }

    /// The cell-by-cell path through the parent chain, each leg diagonal first, and the
    /// chain's interior jump points as marks (when configured).
    fn reconstruct(&mut self, grid: &Grid, start: u32, goal: u32) -> (Path, Vec<Mark>) {
        let shift = index_shift(grid);
        let cell = |i: u32| Cell::new(i & ((1 << shift) - 1), i >> shift);
        let chain = &mut self.chain;
        chain.clear();
        chain.push(goal);
        let mut at = goal;
        let mut n_cells = 1;
        while at != start {
            let parent = self.nodes[at as usize].parent;
            let (a, b) = (cell(at), cell(parent));
            n_cells += a.x.abs_diff(b.x).max(a.y.abs_diff(b.y)) as usize;
            at = parent;
            chain.push(at);
        }
        chain.reverse();
        let mut cells = Vec::with_capacity(n_cells);
        cells.push(cell(start));
        for leg in chain.windows(2) {
            push_octile_leg(&mut cells, cell(leg[0]), cell(leg[1]));
        }
        let marks = if self.config.marks && chain.len() > 2 {
            chain[1..chain.len() - 1]
                .iter()
                .enumerate()
                .map(|(i, &j)| Mark::new(cell(j), format!("J{}", i + 1)))
                .collect()
        } else {
            Vec::new()
        };
        (Path::new(cells), marks)
    }
}

/// One search's state: the grid's data, the node records, OPEN and the counters.
struct Search<'a> {
    bits: &'a BitGrid,
    table: Option<&'a JumpTable>,
    /// With `goal_bounding`: the grid's goal bounds.
    bounds: Option<&'a GoalBounds>,
    nodes: &'a mut [Node],
    state: &'a mut [u16],
    /// The values of `state` for a node in OPEN and a closed one.
    open_mark: u16,
    closed_mark: u16,
    open: &'a mut Open,
    /// Node `(x, y)` is record `y << shift | x`.
    shift: u32,
    goal: Cell,
    /// The generation in the tag's position (`generation << 9`).
    generation: u32,
    tally: Tally,
    /// The recorded steps (a search that records them; [`Budget::record_events`]).
    events: Vec<SearchEvent>,
}

/// The row length of the node records, as a power of two: `1 << shift >= width`. At most
/// twice the width, so records number below 2^32 (grids have at most 2^31 cells).
fn index_shift(grid: &Grid) -> u32 {
    grid.width().next_power_of_two().trailing_zeros()
}

/// The directions a node keeps after a move in direction `d` (the pruning rules of the
/// crate docs), for each 3 x 3 neighbourhood of the node (as `BitGrid::neighbourhood`
/// gives it: bit `3 (dy + 1) + dx + 1` set for a free cell at offset `(dx, dy)`).
static PRUNED: [[u8; 512]; 8] = pruned_table();

/// Builds [`PRUNED`] from the rules.
const fn pruned_table() -> [[u8; 512]; 8] {
    const fn free(around: usize, dx: i32, dy: i32) -> bool {
        around >> (3 * (dy + 1) + dx + 1) & 1 != 0
    }
    let mut table = [[0u8; 512]; 8];
    let mut d = 0;
    while d < 8 {
        let (dx, dy) = (DX[d], DY[d]);
        let mut around = 0;
        while around < 512 {
            let mut out = 1u8 << d;
            if d < 2 {
                // Forced: the cell beside free, the one beside it one step back blocked.
                if free(around, 0, 1) && !free(around, -dx, 1) {
                    out |= 1 << 2 | 1 << diagonal(dx, 1);
                }
                if free(around, 0, -1) && !free(around, -dx, -1) {
                    out |= 1 << 3 | 1 << diagonal(dx, -1);
                }
            } else if d < 4 {
                if free(around, 1, 0) && !free(around, 1, -dy) {
                    out |= 1 | 1 << diagonal(1, dy);
                }
                if free(around, -1, 0) && !free(around, -1, -dy) {
                    out |= 1 << 1 | 1 << diagonal(-1, dy);
                }
            } else {
                out |= 1 << (dx < 0) as usize | 1 << (2 + (dy < 0) as usize);
            }
            table[d][around] = out;
            around += 1;
        }
        d += 1;
    }
    table
}

/// The direction of the last move on the way from `(x, y)` to `(tx, ty)`, diagonal first:
/// the diagonal when the offsets are equal in size, else the straight move along the
/// larger one.
#[inline(always)]
fn last_direction(x: u32, y: u32, tx: u32, ty: u32) -> usize {
    let (dx, dy) = (tx as i64 - x as i64, ty as i64 - y as i64);
    if dx.abs() == dy.abs() {
        diagonal(dx.signum() as i32, dy.signum() as i32)
    } else if dx.abs() > dy.abs() {
        usize::from(dx < 0)
    } else {
        2 + usize::from(dy < 0)
    }
}

impl Search<'_> {
    #[inline(always)]
    fn index(&self, x: u32, y: u32) -> u32 {
        (y << self.shift) | x
    }

    /// Pushes node `i` with cost `g` at `(x, y)` into OPEN: least `f` first, then largest
    /// `g`, then lowest index.
    #[inline(always)]
    fn push(&mut self, i: u32, g: Cost, x: u32, y: u32) {
        let h = Cost::octile(x.abs_diff(self.goal.x), y.abs_diff(self.goal.y));
        let f = (g + h).value();
        // Larger g first among equal f, to 1/1024 (a tie rule, not a cost).
        let tie = u32::MAX - (g.value() * 1024.0) as u32;
        self.open
            .push((f.to_bits(), u64::from(tie) << 32 | u64::from(i)));
    }

    /// Records one step: node `i` with its `parent` (record indices) and cost `g`, and
    /// `f = g + octile(i, goal)` as OPEN orders it; nothing beyond
    /// [`planner_api::MAX_SEARCH_EVENTS`].
    fn note(&mut self, kind: SearchEventKind, i: u32, parent: Option<u32>, g: Cost) {
        if self.events.len() >= planner_api::MAX_SEARCH_EVENTS {
            return;
        }
        let cell = |i: u32| Cell::new(i & ((1 << self.shift) - 1), i >> self.shift);
        let at = cell(i);
        let h = Cost::octile(at.x.abs_diff(self.goal.x), at.y.abs_diff(self.goal.y));
        self.events.push(SearchEvent {
            kind,
            cell: at,
            parent: parent.map(cell),
            g: g.value(),
            f: (g + h).value(),
        });
    }

    /// Offers `(tx, ty)` as a successor of node `parent` at `(x, y)` with cost `g`.
    #[inline(always)]
    fn relax<const RECORD: bool>(
        &mut self,
        parent: u32,
        g: Cost,
        x: u32,
        y: u32,
        tx: u32,
        ty: u32,
    ) {
        let i = self.index(tx, ty);
        let state = self.state[i as usize];
        if state == self.closed_mark {
            return; // Closed: known without reading the larger node record.
        }
        let g_new = g + Cost::octile(tx.abs_diff(x), ty.abs_diff(y));
        let direction = 2u32 << last_direction(x, y, tx, ty);
        let known = state == self.open_mark;
        if !known {
            // First reached in this search: the record is written, never read.
            self.tally.n_relaxations += 1;
            self.tally.n_open_insertions += 1;
            self.state[i as usize] = self.open_mark;
        } else {
            let node = &mut self.nodes[i as usize];
            if g_new == node.g {
                node.tag |= direction;
                return;
            }
            if g_new > node.g {
                return;
            }
            self.tally.n_relaxations += 1;
        }
        self.nodes[i as usize] = Node {
            g: g_new,
            parent,
            tag: self.generation | direction,
        };
        self.push(i, g_new, tx, ty);
        if RECORD {
            let kind = match known {
                true => SearchEventKind::Updating,
                false => SearchEventKind::Generating,
            };
            self.note(kind, i, Some(parent), g_new);
        }
    }

    /// The directions node `(x, y)` expands, by the pruning rules, for its incoming moves:
    /// [`PRUNED`]'s entries for its 3 x 3 neighbourhood.
    #[inline(always)]
    fn directions(&self, x: u32, y: u32, incoming: u8) -> u8 {
        if incoming == 0 {
            return 0xff;
        }
        let around = self.bits.neighbourhood(x, y);
        let mut out = 0u8;
        let mut rest = incoming;
        while rest != 0 {
            let d = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            out |= PRUNED[d][around];
        }
        out
    }

    /// Expands node `p` (its record `node`): every kept direction's jump, and a
    /// relaxation of every jump point found.
    #[inline(always)]
    fn expand<const VARIANT: u8, const RECORD: bool>(&mut self, p: u32, node: Node) {
        let (x, y) = (p & ((1 << self.shift) - 1), p >> self.shift);
        let mut directions = self.directions(x, y, node.incoming());
        if let Some(bounds) = self.bounds {
            directions &= bounds.toward(p, self.goal.x, self.goal.y);
        }
        while directions != 0 {
            let d = directions.trailing_zeros() as usize;
            directions &= directions - 1;
            if VARIANT == JPS_PLUS {
                if d < 4 {
                    // One copy per direction, so that `d` is a constant in each.
                    let jump = match d {
                        0 => self.plus_straight(x, y, 0),
                        1 => self.plus_straight(x, y, 1),
                        2 => self.plus_straight(x, y, 2),
                        _ => self.plus_straight(x, y, 3),
                    };
                    if let Some((tx, ty)) = jump {
                        self.relax::<RECORD>(p, node.g, x, y, tx, ty);
                    }
                } else {
                    match d {
                        4 => self.plus_diagonal::<RECORD>(p, node.g, x, y, 4),
                        5 => self.plus_diagonal::<RECORD>(p, node.g, x, y, 5),
                        6 => self.plus_diagonal::<RECORD>(p, node.g, x, y, 6),
                        _ => self.plus_diagonal::<RECORD>(p, node.g, x, y, 7),
                    }
                }
            } else if d < 4 {
                let (found, k) = self.bits.jump(x, y, d, self.goal);
                self.tally.n_scanned += u64::from(k);
                if found {
                    let (tx, ty) = step(x, y, d, k);
                    self.relax::<RECORD>(p, node.g, x, y, tx, ty);
                }
            } else {
                self.online_diagonal::<VARIANT, RECORD>(p, node.g, x, y, d);
            }
        }
    }

    /// The online diagonal jump from node `p` at `(x, y)` in direction `d`.
    #[inline(always)]
    fn online_diagonal<const VARIANT: u8, const RECORD: bool>(
        &mut self,
        p: u32,
        g: Cost,
        x: u32,
        y: u32,
        d: usize,
    ) {
        let bits = self.bits;
        let (dx, dy) = (DX[d], DY[d]);
        let (horizontal, vertical) = (usize::from(dx < 0), 2 + usize::from(dy < 0));
        let (mut cx, mut cy) = (x as i32, y as i32);
        loop {
            let (nx, ny) = (cx + dx, cy + dy);
            if !(bits.free(nx, ny) && bits.free(nx, cy) && bits.free(cx, ny)) {
                return;
            }
            self.tally.n_scanned += 1;
            let (ux, uy) = (nx as u32, ny as u32);
            if (ux, uy) == (self.goal.x, self.goal.y) {
                self.relax::<RECORD>(p, g, x, y, ux, uy);
                return;
            }
            for component in [horizontal, vertical] {
                let (found, k) = bits.jump(ux, uy, component, self.goal);
                self.tally.n_scanned += u64::from(k);
                if found {
                    if VARIANT == JPS {
                        self.relax::<RECORD>(p, g, x, y, ux, uy);
                        return;
                    }
                    let (tx, ty) = step(ux, uy, component, k);
                    self.relax::<RECORD>(p, g, x, y, tx, ty);
                }
            }
            (cx, cy) = (nx, ny);
        }
    }

    /// The JPS+ straight jump from `(x, y)` in direction `d`: the goal when it is on the
    /// way, else the table's jump point, if any.
    #[inline(always)]
    fn plus_straight(&mut self, x: u32, y: u32, d: usize) -> Option<(u32, u32)> {
        let table = self.table?;
        let goal = self.goal;
        // The common case, a near entry: one read, and the goal is on the way only when it
        // lies on the jump's line `1 ..= reach` cells on (the wrapping subtraction turns
        // an offset of 0 or behind into a huge one).
        let entry = table.entry(x, y, d);
        if entry != plus::FAR_JUMP && entry != plus::FAR_WALL {
            self.tally.n_scanned += 1;
            let reach = u32::from(entry.unsigned_abs());
            let (same_line, offset) = match d {
                0 => (goal.y == y, goal.x.wrapping_sub(x)),
                1 => (goal.y == y, x.wrapping_sub(goal.x)),
                2 => (goal.x == x, goal.y.wrapping_sub(y)),
                _ => (goal.x == x, y.wrapping_sub(goal.y)),
            };
            return if same_line && offset.wrapping_sub(1) < reach {
                Some((goal.x, goal.y))
            } else if entry > 0 {
                Some(step(x, y, d, reach))
            } else {
                None
            };
        }
        let to_goal = match d {
            0 if goal.y == y && goal.x > x => goal.x - x,
            1 if goal.y == y && goal.x < x => x - goal.x,
            2 if goal.x == x && goal.y > y => goal.y - y,
            3 if goal.x == x && goal.y < y => y - goal.y,
            _ => u32::MAX,
        };
        // Cells moved by far entries so far.
        let mut base = 0;
        loop {
            self.tally.n_scanned += 1;
            let (cx, cy) = step(x, y, d, base);
            let entry = table.entry(cx, cy, d);
            if entry == plus::FAR_JUMP || entry == plus::FAR_WALL {
                if to_goal <= base + plus::SPAN {
                    return Some((goal.x, goal.y));
                }
                base += plus::SPAN;
                continue;
            }
            let reach = base + u32::from(entry.unsigned_abs());
            return if to_goal <= reach {
                Some((goal.x, goal.y))
            } else if entry > 0 {
                Some(step(x, y, d, reach))
            } else {
                None
            };
        }
    }

    /// The JPS+ diagonal walk from node `p` at `(x, y)` in direction `d`, pruned
    /// intermediate points: at each diagonal jump point (or target jump point) the
    /// component jumps' results become successors of `p`, and the walk goes on.
    #[inline(always)]
    fn plus_diagonal<const RECORD: bool>(&mut self, p: u32, g: Cost, x: u32, y: u32, d: usize) {
        let Some(table) = self.table else { return };
        let (dx, dy) = (DX[d], DY[d]);
        let (horizontal, vertical) = (usize::from(dx < 0), 2 + usize::from(dy < 0));
        let goal = self.goal;
        let (mut cx, mut cy) = (x, y);
        loop {
            self.tally.n_scanned += 1;
            let entry = table.entry(cx, cy, d);
            let far = entry == plus::FAR_JUMP || entry == plus::FAR_WALL;
            let reach = if far {
                plus::SPAN
            } else {
                u32::from(entry.unsigned_abs())
            };
            // The goal's offsets along the walk's two axes (grid coordinates are below
            // 2^31, so the wrapped differences read as `i32` are the signed offsets).
            let ahead_x = if dx > 0 {
                goal.x.wrapping_sub(cx)
            } else {
                cx.wrapping_sub(goal.x)
            } as i32;
            let ahead_y = if dy > 0 {
                goal.y.wrapping_sub(cy)
            } else {
                cy.wrapping_sub(goal.y)
            } as i32;
            let target = ahead_x.min(ahead_y);
            let (k, stops) = if target > 0 && target as u32 <= reach {
                (target as u32, true)
            } else if far {
                (reach, false)
            } else if entry > 0 {
                (reach, true)
            } else {
                return;
            };
            (cx, cy) = step(cx, cy, d, k);
            if !stops {
                continue;
            }
            if (cx, cy) == (goal.x, goal.y) {
                self.relax::<RECORD>(p, g, x, y, cx, cy);
                return;
            }
            for component in [horizontal, vertical] {
                if let Some((tx, ty)) = self.plus_straight(cx, cy, component) {
                    self.relax::<RECORD>(p, g, x, y, tx, ty);
                }
            }
        }
    }
}

/// The cell `k` moves from `(x, y)` in direction `d` (inside the grid by the caller).
#[inline(always)]
fn step(x: u32, y: u32, d: usize, k: u32) -> (u32, u32) {
    (
        x.wrapping_add_signed(DX[d] * k as i32),
        y.wrapping_add_signed(DY[d] * k as i32),
    )
}

impl Planner for Jps {
    fn name(&self) -> &str {
        NAME
    }

    /// Deterministic; every step is an 8-connected move without corner cutting; admissible:
    /// every variant, with or without goal bounding, returns a least-cost path (the crate
    /// docs; the octile heuristic is consistent and pruning keeps an optimal path).
    fn specs(&self) -> PlannerSpecs {
        PlannerSpecs::deterministic(PathSpec::Moves(self.moves.clone())).with_admissible(true)
    }

    fn prepare_bytes(&self, grid: &Grid) -> u64 {
        self.memory_bytes_for(grid)
    }

    fn prepare(&mut self, grid: &Grid) {
        self.precompute(grid);
        self.size_nodes(grid);
    }

    /// Lists the expanded jump points (not the cells scanned between them) in
    /// [`Outcome::expanded`] when the budget asks ([`Budget::record_expanded`]), one per
    /// `n_expanded`; refuses with [`Outcome::over_memory`] when
    /// [`Jps::memory_bytes_for`] the grid is over [`Budget::max_memory_mb`].
    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        // A copy of the search that records its steps, never timed: the timed one has no
        // recording code at all.
        match (self.config.variant, budget.record_events) {
            (Variant::Jps, false) => self.search::<JPS, false>(problem, budget),
            (Variant::JpsPrime, false) => self.search::<JPS_PRIME, false>(problem, budget),
            (Variant::JpsPlus, false) => self.search::<JPS_PLUS, false>(problem, budget),
            (Variant::Jps, true) => self.search::<JPS, true>(problem, budget),
            (Variant::JpsPrime, true) => self.search::<JPS_PRIME, true>(problem, budget),
            (Variant::JpsPlus, true) => self.search::<JPS_PLUS, true>(problem, budget),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The open-or-closed marks wrap after 32,767 searches; the array is cleared then, so
    /// no mark of an earlier search reads as this one's.
    #[test]
    fn searches_across_the_mark_wrap_agree() {
        let grid = Grid::from_ascii(
            "
            ....
            .#..
            ....
        ",
        )
        .unwrap();
        let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(3, 2)).unwrap();
        for variant in [Variant::Jps, Variant::JpsPrime, Variant::JpsPlus] {
            let mut jps = Jps::new(Config {
                variant,
                ..Config::default()
            })
            .unwrap();
            let expected = jps.plan(&problem, &Budget::unlimited()).counters;
            // The next searches use the last mark before the wrap, then mark 1 again, the
            // first search's.
            jps.mark = (1 << 15) - 2;
            for _ in 0..3 {
                let outcome = jps.plan(&problem, &Budget::unlimited());
                assert_eq!(outcome.counters, expected, "{variant:?}");
            }
            assert_eq!(jps.mark, 2);
        }
    }
}
