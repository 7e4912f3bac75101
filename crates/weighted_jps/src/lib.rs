//! Jump Point Search on weighted grids: optimal 8-connected paths under cell costs that
//! expand only jump points where the terrain is uniform, and every cell where it is not.
//!
//! Sources: Harabor and Grastien's Jump Point Search ("Online Graph Pruning for
//! Pathfinding on Grid Maps", AAAI 2011, <https://doi.org/10.1609/aaai.v25i1.7994>; the
//! rules without corner cutting of "Improving Jump Point Search", ICAPS 2014,
//! <https://doi.org/10.1609/icaps.v24i1.13633>, as planner-jps implements them), and the
//! idea of Carlson, Moghadam, Harabor, Stuckey and Ebrahimi's Weighted Jump Point Search
//! (JPSW, "Optimal Pathfinding on Weighted Grid Maps", AAAI 2023): prune symmetric paths
//! only where the weights make them symmetric. **This is not the paper's algorithm**: its
//! full text is not in the repository, so the pruning below is a simpler rule proved here
//! (next section), weaker than JPSW's wherever weights change (it searches those cells as
//! A* does), and exactly JPS's on a grid without weights.
//!
//! # The rule and why it keeps an optimal path
//! Moves are 8-connected without corner cutting (a diagonal move needs both orthogonal
//! cells beside it free); a move's cost is the grid's ([`planner_api::weights`]: its length
//! times the mean of its two cells' weights, or times the entered cell's weight), and 1 per
//! unit of length without weights. A free cell is **uniform** when every free cell of its
//! 3 x 3 neighbourhood has its weight.
//!
//! JPS prunes a neighbour `n` of a node `x` reached from `p` when a path from `p` to `n`
//! that avoids `x` costs no more than `p -> x -> n` (Harabor and Grastien 2011, its
//! neighbour pruning rules).
//! Every cell of both paths lies in `x`'s 3 x 3 neighbourhood, and a move's cost depends
//! only on its length and its two end cells' weights. When `x` is uniform, every move
//! between free cells of that neighbourhood costs its length times the one weight `w`, so
//! each comparison is the unweighted one times `w`: JPS's pruning rules, and its jumps
//! (which skip nodes whose pruned neighbourhood is the next cell on the way), hold at `x`
//! unchanged. At a cell that is not uniform nothing is pruned: it is a jump point, and its
//! expansion tries all eight directions, as A*'s does. So:
//!
//! - the start, and every node that is not uniform, expand all eight directions;
//! - a uniform node reached by a straight move keeps that direction, and for each side
//!   whose cell is free while the cell beside it one step back is blocked, also that side
//!   and the diagonal between (a *forced* neighbour); reached by a diagonal move, it keeps
//!   the diagonal and its two straight components (diagonal moves have no forced
//!   neighbours without corner cutting);
//! - a straight jump stops (a jump point) at the goal, at a cell that is not uniform, or at
//!   a forced neighbour; a diagonal jump at the goal, at a cell that is not uniform, or at a
//!   cell from which one of its two straight component jumps reaches a jump point; a jump
//!   that meets a blocked cell, the grid's edge or a corner it would cut yields nothing.
//!
//! Along a jump through uniform cells the weight is constant (consecutive cells lie in each
//! other's neighbourhoods), so the search reads the weights only to cost the moves. The
//! tests compare every path's cost with an exact Dijkstra search (planner-testkit's
//! oracle) on thousands of random weighted grids whose weights come in patches, so that
//! jumps cross uniform regions and stop at their edges, and with planner-jps on grids
//! without weights.
//!
//! **Choices.** A* over jump points with the octile heuristic times the grid's smallest
//! weight (consistent, so the first path popped is optimal). OPEN is planner-search's
//! bucket list, ties broken by lower `g` first and then push order. A node reached at equal
//! cost by moves in different directions expands the union of their directions; should an
//! equal-cost arrival by a new direction come after the node was expanded, the node is
//! expanded again for that direction only (counted in `n_reopened`; with lower `g` first
//! among equal `f`, every equal-cost predecessor of a node is expanded before it, so the
//! tests see none). The path between a node and its successor is diagonal first, then
//! straight, as the jump went.
//!
//! # Tables per grid
//! Built once per grid revision ([`Planner::prepare`], or the first search): the grid with
//! a blocked border one cell wide, its weights, the uniform flags, and per cell and
//! direction the jump from it, the goal aside (the moves to its jump point, or to the
//! blocked cell or cut corner that ends it: JPS+'s distances, Rabin and Silva, "An Extreme
//! A* Speed Optimization for Static Uniform Cost Grids", Game AI Pro 2, 2015, with weight
//! changes as jump points). A jump is then one table read and a look at the goal: a
//! straight jump that reaches the goal stops there, and a diagonal one stops where it
//! crosses the goal's row or column if the goal is that cell or that cell's straight jump
//! reaches it (JPS+'s target jump points). Along a jump every move after the first has one
//! weight (crate docs above), so its cost is two products. 36 bytes per cell of the
//! bordered grid for the tables and 19 for the search's nodes.
//!
//! When the grid's cells are edited in place ([`Grid::set_free`], [`Grid::set_weight`]: a
//! costmap's updates as the robot drives), the tables are brought up to date from the
//! grid's log of changed cells ([`Grid::changed_since`]) instead of rebuilt: the jumps of
//! the cells within two moves of an edit are recomputed, and behind each one that changed,
//! back along its line until a jump comes out as before (`Prepared::update`; when more
//! than one cell in 32 changed, a rebuild). Tested equal to a rebuild after 4,171 rounds
//! of random edits, and every plan after edits at the oracle's cost. `cargo bench -p
//! planner-registry --bench change` on a 2048 x 2048 grid (2026-12-06, four runs): the
//! next plan after one changed cell 0.01 ms, a full build (a new grid) 190-216 ms (270 ms
//! when the eight directions' entries were interleaved per cell); A* and JPS build theirs
//! for a new grid in 1.9-2.3 and 5.7-6.9 ms.
//!
//! # Speed, measured
//! `cargo bench -p planner-weighted_jps --bench costmap -- --repeats=3 --clock=cpu` (the
//! same paths' costs as planner-astar's on every problem; 2026-12-06, this 2-core machine,
//! two runs):
//!
//! | map | problems | A* expansions | weighted_jps expansions | A* ms | weighted_jps ms |
//! |---|---:|---:|---:|---:|---:|
//! | nav2's warehouse as graded costs (1 + costmap cost), 200 seeded pairs, 27 unreachable | 200 | 52,344,370 | 395,037 | 6967.1, 7001.5 | 111.8, 117.6 (60-62x faster) |
//! | arena, 7 x 7 terrain patches of weights 1-9 | 160 | 130,128 | 121,369 | 14.0, 14.5 | 22.6, 23.4 (1.6x slower) |
//!
//! The same bench at commit c71916f, straight jumps from the table and diagonal ones
//! stepping cell by cell, took 231.1 ms on the warehouse (a version before it, every jump
//! stepping, not committed, 3583.5 ms). Where the weights change every few cells almost
//! no cell is uniform, the search expands nearly A*'s nodes, and each expansion jumps eight
//! ways: use A* there. On a robot's costmap, whose free space is one weight with gradients
//! around the obstacles, the jumps cross the free space in one expansion.
//!
//! # Counters
//! `n_expanded` (jump points expanded, reopened ones included), `n_jumps` (jumps tried:
//! reads of the jump table), `n_open_insertions`, `n_relaxations` (a node given a new parent and
//! cost), `peak_open`, `n_reopened` (expansions for a direction that arrived after the
//! node's first expansion). Every counter, jump point and path equals that of
//! `planner_testkit::reference_weighted_jps`, the same search written again without the
//! tables (jumps walked cell by cell, std's binary heap), on 3,000 random weighted grids and
//! 4,000 without weights (`tests/reference.rs`) and on every run of `configs/weighted.toml`
//! (xtask's `every_weighted_run_matches_the_oracle`).
//!
//! # Recording
//! With [`Budget::record_events`] the search is recorded step by step ([`Outcome::events`]):
//! each push of a jump point into OPEN with a new cost (`generating` the first time,
//! `updating` after) with its parent, `g` and `f = g + h` in cost units, and each
//! expansion, reopened ones included; a push that only adds a direction to an expanded
//! node at its own cost is no step (its expansion again is). The recording search is a
//! copy of its own (a const parameter). Tested against the counters, the path's cost and
//! the heuristic in `tests/events.rs`.
//!
//! ```
//! use planner_api::{Budget, Cell, CostRule, Grid, Planner, Problem, Status};
//! use planner_weighted_jps::{Config, WeightedJps};
//!
//! // A band of weight 20 across the middle but for the right column: going round it
//! // (17 + 2 sqrt 2) is cheaper than crossing it (41).
//! let grid = Grid::from_ascii("
//!     ..........
//!     ..........
//!     ..........
//!     ..........
//! ").unwrap();
//! let mut weights = vec![1u16; 40];
//! for x in 0..9 {
//!     weights[10 + x] = 20;
//!     weights[20 + x] = 20;
//! }
//! let grid = grid.with_weights(weights, CostRule::Mean).unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(0, 3)).unwrap();
//! let outcome = WeightedJps::new(Config::default()).unwrap().plan(&problem, &Budget::unlimited());
//! assert_eq!(outcome.status, Status::Found);
//! let path = outcome.path.unwrap();
//! assert!(path.cells().contains(&Cell::new(9, 1)));
//! let cost = grid.path_cost(path.cells()).to_f64();
//! assert!((cost - (17.0 + 2.0 * 2f64.sqrt())).abs() < 1e-9);
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

use planner_api::{
    push_octile_leg, Budget, Cell, Connectivity, Cost, Counters, Grid, Mark, MoveSet,
    NeighborOrder, Outcome, ParamKey, Path, PathSpec, Planner, PlannerSpecs, Problem, SearchEvent,
    SearchEventKind, Status,
};
use planner_search::bucket::{BucketOpen, Open, LOW_G};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The registry name.
pub const NAME: &str = "weighted_jps";

/// Parameters; every field has a default.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// Neighbourhood; defined here for 8 only (any other value is an error). Default 8.
    #[schemars(with = "u32", extend("enum" = [8]))]
    pub moves: Connectivity,
    /// Corner cutting; must be false (a diagonal move needs both orthogonal cells free).
    /// Default false.
    pub corner_cutting: bool,
    /// Report the path's jump points as marks `J1`, `J2`, ... (start and goal excluded).
    /// Default true.
    pub marks: bool,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            moves: Connectivity::Eight,
            corner_cutting: false,
            marks: true,
        }
    }
}

/// A parameter the planner cannot run with.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConfigError {
    /// `moves` is not 8.
    #[error("parameter `moves`: weighted_jps is defined for 8-connected moves only, got {0}")]
    Moves(u32),
    /// `corner_cutting` is true.
    #[error(
        "parameter `corner_cutting`: weighted_jps is defined without corner cutting (a diagonal move needs both orthogonal cells free)"
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

/// The eight directions as `(dx, dy)`: four straight ones (east, west, south, north),
/// then four diagonals (south-east, south-west, north-east, north-west).
const DIRECTIONS: [(i32, i32); 8] = [
    (1, 0),
    (-1, 0),
    (0, 1),
    (0, -1),
    (1, 1),
    (-1, 1),
    (1, -1),
    (-1, -1),
];

/// Every direction, as a set of direction bits.
const ALL: u8 = 0xff;

/// The index in [`DIRECTIONS`] of `(dx, dy)`, a non-zero step.
const fn direction(dx: i32, dy: i32) -> usize {
    match (dx, dy) {
        (1, 0) => 0,
        (-1, 0) => 1,
        (0, 1) => 2,
        (0, -1) => 3,
        (1, 1) => 4,
        (-1, 1) => 5,
        (1, -1) => 6,
        _ => 7,
    }
}

/// The grid's cells in a layout with a blocked border one cell wide (so a jump needs no
/// bounds test), with the weights and the uniform flags (crate docs).
#[derive(Debug, Clone, Default)]
struct Prepared {
    revision: Option<u64>,
    stride: usize,
    /// Rows of the grid (without the border).
    height: usize,
    free: Vec<bool>,
    uniform: Vec<bool>,
    /// Per direction `k` and cell `p` (at `[k][p]`): the jump from the cell, the goal aside, as
    /// `steps << 1 | stops`, where `stops` says whether it ends at a jump point `steps`
    /// moves away, and otherwise `steps` moves can be made before a blocked cell or a cut
    /// corner.
    runs: [Vec<u32>; 8],
    weights: Vec<u16>,
    /// The smallest weight of any cell (1 without weights).
    min_weight: u16,
    /// Per direction: the index offset of one step.
    delta: [isize; 8],
}

impl Prepared {
    /// Bytes per padded cell: the free and uniform flags, the weight and the eight runs.
    const BYTES_PER_CELL: u64 = 4 + 32;

    fn padded_len(grid: &Grid) -> u64 {
        (u64::from(grid.width()) + 2) * (u64::from(grid.height()) + 2)
    }

    fn build(&mut self, grid: &Grid) {
        let (width, height) = (grid.width() as usize, grid.height() as usize);
        let stride = width + 2;
        let len = stride * (height + 2);
        self.free.clear();
        self.free.resize(len, false);
        self.weights.clear();
        self.weights.resize(len, 1);
        for y in 0..height {
            let (row, at) = (y * width..(y + 1) * width, (y + 1) * stride + 1);
            self.free[at..at + width].copy_from_slice(&grid.free_cells()[row.clone()]);
            if let Some(w) = grid.weights() {
                self.weights[at..at + width].copy_from_slice(&w.cells()[row]);
            }
        }
        self.delta = DIRECTIONS.map(|(dx, dy)| dy as isize * stride as isize + dx as isize);
        self.uniform.clear();
        self.uniform.resize(len, false);
        for y in 1..=height {
            for x in 1..=width {
                let p = y * stride + x;
                self.uniform[p] = self.is_uniform(p);
            }
        }
        self.build_runs(width, height, stride);
        self.stride = stride;
        self.height = height;
        self.min_weight = grid.weights().map_or(1, |w| w.min());
        self.revision = Some(grid.revision());
    }

    /// Whether `n_changed` edited cells are brought in by [`Prepared::update`] rather than
    /// a rebuild of tables of `len` cells: at most one cell in 32 (an edit recomputes up
    /// to 25 cells' jumps in each direction through a heap, and a rebuild every cell's in
    /// one pass).
    fn updates(n_changed: usize, len: usize) -> bool {
        n_changed.saturating_mul(32) <= len
    }

    /// Whether the cell at `p` is free and uniform: every free cell of its 3 x 3
    /// neighbourhood has its weight.
    #[inline(always)]
    fn is_uniform(&self, p: usize) -> bool {
        let w = self.weights[p];
        self.free[p]
            && self.delta.iter().all(|&d| {
                let q = p.wrapping_add_signed(d);
                !self.free[q] || self.weights[q] == w
            })
    }

    /// Brings the tables built for an earlier revision of `grid` up to date after the
    /// edits of `changed` cells ([`Grid::changed_since`]) instead of rebuilding them. A
    /// cell's jump in direction `k` reads the cells within two moves of it and the jump
    /// from the cell one move ahead (a diagonal one also the straight jumps from there,
    /// [`Prepared::jump_from`]); so the jumps of the cells within two moves of an edit are
    /// recomputed, and from each one that changed the cell one move behind, and so on
    /// back along the line until a jump comes out as it was, in the order of
    /// [`Prepared::build_runs`] (each cell after the one ahead of it); then the diagonal
    /// directions, also from the cells behind a changed straight jump. Tested equal to a
    /// rebuild after random edits (this module's tests).
    fn update(&mut self, grid: &Grid, edited: &[Cell]) {
        let stride = self.stride;
        let (width, height) = (stride - 2, self.height);
        for &cell in edited {
            let p = self.index(cell);
            self.free[p] = grid.is_free(cell);
            self.weights[p] = grid.weight(cell);
        }
        // The cells within `reach` moves of an edit, inside the grid.
        let around = |cell: Cell, reach: u32| {
            let (x0, y0) = (cell.x.saturating_sub(reach), cell.y.saturating_sub(reach));
            let x1 = (cell.x + reach).min(width as u32 - 1);
            let y1 = (cell.y + reach).min(height as u32 - 1);
            (y0..=y1).flat_map(move |y| (x0..=x1).map(move |x| Cell::new(x, y)))
        };
        for &cell in edited {
            for near in around(cell, 1) {
                let p = self.index(near);
                self.uniform[p] = self.is_uniform(p);
            }
        }
        let seeds: Vec<usize> = edited
            .iter()
            .flat_map(|&cell| around(cell, 2))
            .map(|cell| self.index(cell))
            .collect();
        let mut straight_changes: [Vec<usize>; 4] = Default::default();
        let mut queue = std::collections::BinaryHeap::new();
        for k in 0..8 {
            let (dx, dy) = DIRECTIONS[k];
            // The position of `p` in `build_runs`' order for this direction.
            let order = |p: usize| {
                let (x, y) = (p % stride, p / stride);
                let row = if dy == 1 { height - y } else { y - 1 };
                let column = if dx == 1 { width - x } else { x - 1 };
                row * width + column
            };
            queue.clear();
            queue.extend(seeds.iter().map(|&p| std::cmp::Reverse((order(p), p))));
            if k >= 4 {
                let (kx, ky) = (direction(dx, 0), direction(0, dy));
                // A cell whose straight jump changed is the cell ahead of this one.
                for &q in straight_changes[kx].iter().chain(&straight_changes[ky]) {
                    let p = q.wrapping_add_signed(-self.delta[k]);
                    if self.is_inside(p) {
                        queue.push(std::cmp::Reverse((order(p), p)));
                    }
                }
            }
            while let Some(std::cmp::Reverse((_, p))) = queue.pop() {
                let ahead = self.runs[k][p.wrapping_add_signed(self.delta[k])];
                let jump = self.jump_in(k, p, ahead);
                if jump == self.runs[k][p] {
                    continue;
                }
                self.runs[k][p] = jump;
                if k < 4 {
                    straight_changes[k].push(p);
                }
                let behind = p.wrapping_add_signed(-self.delta[k]);
                if self.is_inside(behind) {
                    queue.push(std::cmp::Reverse((order(behind), behind)));
                }
            }
        }
        self.min_weight = grid.weights().map_or(1, |w| w.min());
        self.revision = Some(grid.revision());
    }

    /// Whether padded index `p` is a cell of the grid (not the border).
    fn is_inside(&self, p: usize) -> bool {
        let (x, y) = (p % self.stride, p / self.stride);
        (1..self.stride - 1).contains(&x) && (1..=self.height).contains(&y)
    }

    /// [`Prepared::jump_from`] for a direction known at run time.
    fn jump_in(&self, k: usize, p: usize, ahead: u32) -> u32 {
        match k {
            0 => self.jump_from::<0>(p, ahead),
            1 => self.jump_from::<1>(p, ahead),
            2 => self.jump_from::<2>(p, ahead),
            3 => self.jump_from::<3>(p, ahead),
            4 => self.jump_from::<4>(p, ahead),
            5 => self.jump_from::<5>(p, ahead),
            6 => self.jump_from::<6>(p, ahead),
            _ => self.jump_from::<7>(p, ahead),
        }
    }

    /// The jump from the cell at `p` in direction `K` ([`Prepared::runs`]), given the jump
    /// `ahead` from the cell one move on in that direction (and for a diagonal `K` the
    /// straight jumps in `runs`).
    #[inline(always)]
    fn jump_from<const K: usize>(&self, p: usize, ahead: u32) -> u32 {
        if !self.free[p] {
            return 0;
        }
        let next = p.wrapping_add_signed(self.delta[K]);
        let (allowed, stop) = if K < 4 {
            let forced = sides(K).iter().any(|&s| self.forced(next, K, s));
            (self.free[next], !self.uniform[next] || forced)
        } else {
            let (dx, dy) = DIRECTIONS[K];
            let (kx, ky) = (direction(dx, 0), direction(0, dy));
            let allowed = self.free[next]
                && self.free[p.wrapping_add_signed(self.delta[kx])]
                && self.free[p.wrapping_add_signed(self.delta[ky])];
            let straight_stops = (self.runs[kx][next] | self.runs[ky][next]) & 1 == 1;
            (allowed, !self.uniform[next] || straight_stops)
        };
        if !allowed {
            0
        } else if stop {
            1 << 1 | 1
        } else {
            (ahead >> 1).saturating_add(1) << 1 | (ahead & 1)
        }
    }

    /// The jumps of every cell ([`Prepared::runs`]), each computed from the cell one move
    /// ahead's: a straight jump stops one move on at a cell that is not uniform or has a
    /// forced neighbour for the direction, a diagonal one at a cell that is not uniform or
    /// whose straight component jumps stop; a jump ends before a blocked cell (or a cut
    /// corner), and otherwise goes on as the jump from the cell ahead. Straight directions
    /// first: the diagonal ones read them.
    fn build_runs(&mut self, width: usize, height: usize, stride: usize) {
        self.fill::<0>(width, height, stride);
        self.fill::<1>(width, height, stride);
        self.fill::<2>(width, height, stride);
        self.fill::<3>(width, height, stride);
        self.fill::<4>(width, height, stride);
        self.fill::<5>(width, height, stride);
        self.fill::<6>(width, height, stride);
        self.fill::<7>(width, height, stride);
    }

    /// [`Prepared::build_runs`] for direction `K`.
    fn fill<const K: usize>(&mut self, width: usize, height: usize, stride: usize) {
        let (dx, dy) = DIRECTIONS[K];
        let d = self.delta[K];
        let mut runs = std::mem::take(&mut self.runs[K]);
        runs.clear();
        runs.resize(self.free.len(), 0);
        // Cells in an order that visits each cell's next one first.
        for row in 0..height {
            let y = if dy == 1 { height - row } else { row + 1 };
            for column in 0..width {
                let x = if dx == 1 { width - column } else { column + 1 };
                let p = y * stride + x;
                if self.free[p] {
                    runs[p] = self.jump_from::<K>(p, runs[p.wrapping_add_signed(d)]);
                }
            }
        }
        self.runs[K] = runs;
    }

    /// Whether a straight move in direction `k` onto `p` makes side `s`'s cell a forced
    /// neighbour: free, while the cell beside it one step back is blocked (crate docs).
    #[inline(always)]
    fn forced(&self, p: usize, k: usize, s: usize) -> bool {
        let side = p.wrapping_add_signed(self.delta[s]);
        self.free[side] && !self.free[side.wrapping_add_signed(-self.delta[k])]
    }

    /// The tables for `grid`: as they are, brought up to date after edits
    /// ([`Prepared::update`]), or rebuilt.
    fn get_or_build(&mut self, grid: &Grid) -> &Prepared {
        let same_shape =
            self.stride == grid.width() as usize + 2 && self.height == grid.height() as usize;
        match self.revision {
            Some(revision) if revision == grid.revision() => {}
            Some(revision) if same_shape => match grid.changed_since(revision) {
                Some(changed) => {
                    let changed: Vec<Cell> = changed.collect();
                    if Prepared::updates(changed.len(), self.free.len()) {
                        self.update(grid, &changed);
                    } else {
                        self.build(grid);
                    }
                }
                None => self.build(grid),
            },
            _ => self.build(grid),
        }
        self
    }

    fn index(&self, cell: Cell) -> usize {
        (cell.y as usize + 1) * self.stride + cell.x as usize + 1
    }

    fn cell(&self, p: usize) -> Cell {
        Cell::new((p % self.stride - 1) as u32, (p / self.stride - 1) as u32)
    }
}

/// Node states.
const UNSEEN: u8 = 0;
const OPEN: u8 = 1;
const CLOSED: u8 = 2;

/// The per-cell search state, kept between searches (the cells a search touched are reset
/// by the next one).
#[derive(Debug, Clone, Default)]
struct Nodes {
    state: Vec<u8>,
    g: Vec<u64>,
    parent: Vec<u32>,
    /// The directions of the moves that reached the node at its cost.
    directions: Vec<u8>,
    /// Directions that reached an expanded node at its cost after its expansion.
    reopen: Vec<u8>,
    touched: Vec<u32>,
}

impl Nodes {
    /// Bytes per padded cell.
    const BYTES_PER_CELL: u64 = 1 + 8 + 4 + 1 + 1 + 4;

    fn fit(&mut self, len: usize) {
        if self.state.len() != len {
            *self = Nodes {
                state: vec![UNSEEN; len],
                g: vec![0; len],
                parent: vec![0; len],
                directions: vec![0; len],
                reopen: vec![0; len],
                touched: Vec::new(),
            };
        }
        for &p in &self.touched {
            self.state[p as usize] = UNSEEN;
            self.reopen[p as usize] = 0;
        }
        self.touched.clear();
    }
}

/// The search's counters (crate docs).
#[derive(Debug, Clone, Copy, Default)]
struct Tally {
    n_expanded: u64,
    n_jumps: u64,
    n_open_insertions: u64,
    n_relaxations: u64,
    peak_open: u64,
    n_reopened: u64,
}

impl Tally {
    fn counters(&self) -> Counters {
        let mut counters = Counters::new();
        for (name, value) in [
            ("n_expanded", self.n_expanded),
            ("n_jumps", self.n_jumps),
            ("n_open_insertions", self.n_open_insertions),
            ("n_relaxations", self.n_relaxations),
            ("peak_open", self.peak_open),
            ("n_reopened", self.n_reopened),
        ] {
            counters.push(name, value);
        }
        counters
    }
}

/// The planner.
#[derive(Debug, Clone)]
pub struct WeightedJps {
    config: Config,
    moves: MoveSet,
    prepared: Prepared,
    nodes: Nodes,
    open: BucketOpen<LOW_G>,
    /// The largest weight the OPEN list's ring was configured for.
    open_weight: Option<u16>,
}

impl WeightedJps {
    /// A planner with `config`, validated.
    pub fn new(config: Config) -> Result<WeightedJps, ConfigError> {
        if config.moves != Connectivity::Eight {
            return Err(ConfigError::Moves(config.moves.n_directions()));
        }
        if config.corner_cutting {
            return Err(ConfigError::CornerCutting);
        }
        let moves = MoveSet::new(Connectivity::Eight, false, &NeighborOrder::default())
            .map_err(|_| ConfigError::Moves(8))?;
        Ok(WeightedJps {
            config,
            moves,
            prepared: Prepared::default(),
            nodes: Nodes::default(),
            open: BucketOpen::default(),
            open_weight: None,
        })
    }

    /// The bytes a search on `grid` needs at most: the prepared layout and the per-cell
    /// node state.
    pub fn memory_bytes_for(&self, grid: &Grid) -> u64 {
        Prepared::padded_len(grid).saturating_mul(Prepared::BYTES_PER_CELL + Nodes::BYTES_PER_CELL)
    }
}

/// One search's view of the prepared grid: jumps and move costs.
struct Jumper<'a> {
    grid: &'a Prepared,
    goal: usize,
    /// Half the straight and the diagonal move's cost units, and the cost rule's factors
    /// (`planner_api::CostRule::factors`).
    half: [u64; 2],
    factors: (u64, u64),
    jumps: u64,
}

impl Jumper<'_> {
    /// The cost units of the move from `from` to `to`, diagonal or not.
    #[inline(always)]
    fn step_cost(&self, from: usize, to: usize, diagonal: bool) -> u64 {
        let w = &self.grid.weights;
        let factor = self.factors.0 * u64::from(w[from]) + self.factors.1 * u64::from(w[to]);
        self.half[usize::from(diagonal)].saturating_mul(factor)
    }

    /// The straight jump from `p` in direction `k < 4`: the jump point and the cost of the
    /// way there, or `None`. One read of the runs table ([`Prepared::runs`]), and the goal
    /// when it lies on the way.
    fn straight(&mut self, p: usize, k: usize) -> Option<(usize, u64)> {
        self.jumps += 1;
        let run = self.grid.runs[k][p];
        let (mut steps, stops) = ((run >> 1) as usize, run & 1 == 1);
        let to_goal = self.steps_to_goal(p, k);
        let stops = match to_goal {
            Some(t) if t <= steps => {
                steps = t;
                true
            }
            _ => stops,
        };
        if steps == 0 || !stops {
            return None;
        }
        let d = self.grid.delta[k];
        let first = p.wrapping_add_signed(d);
        let end = p.wrapping_add_signed(d * steps as isize);
        // Past the first step every cell has the first one's weight (crate docs).
        let first_cost = self.step_cost(p, first, false);
        let rest = self
            .step_cost(first, first, false)
            .saturating_mul(steps as u64 - 1);
        Some((end, first_cost.saturating_add(rest)))
    }

    /// The steps from `p` to the goal in straight direction `k`, when the goal lies that
    /// way on `p`'s row or column.
    #[inline(always)]
    fn steps_to_goal(&self, p: usize, k: usize) -> Option<usize> {
        let (stride, goal) = (self.grid.stride, self.goal);
        let (px, py, gx, gy) = (p % stride, p / stride, goal % stride, goal / stride);
        match k {
            0 if py == gy && gx > px => Some(gx - px),
            1 if py == gy && gx < px => Some(px - gx),
            2 if px == gx && gy > py => Some(gy - py),
            3 if px == gx && gy < py => Some(py - gy),
            _ => None,
        }
    }

    /// The diagonal jump from `p` in direction `k >= 4`, as [`Jumper::straight`]: one read
    /// of the runs table, and where the goal's row or column crosses the jump's way, a look
    /// at whether the goal is that cell or its straight jump there reaches the goal.
    fn diagonal(&mut self, p: usize, k: usize) -> Option<(usize, u64)> {
        self.jumps += 1;
        let run = self.grid.runs[k][p];
        let steps = (run >> 1) as usize;
        if steps == 0 {
            return None;
        }
        let mut end = if run & 1 == 1 { steps } else { usize::MAX };
        let (dx, dy) = DIRECTIONS[k];
        let (kx, ky) = (direction(dx, 0), direction(0, dy));
        let stride = self.grid.stride;
        let (px, py) = ((p % stride) as i64, (p / stride) as i64);
        let (gx, gy) = ((self.goal % stride) as i64, (self.goal / stride) as i64);
        let (dx, dy) = (i64::from(dx), i64::from(dy));
        // At `t` moves the jump reaches the goal's row (then the goal lies `along` cells
        // further in `x`) or its column.
        for (t, along, straight) in [
            ((gy - py) * dy, (gx - px) * dx - (gy - py) * dy, kx),
            ((gx - px) * dx, (gy - py) * dy - (gx - px) * dx, ky),
        ] {
            if t < 1 || t as usize > steps.min(end) || along < 0 {
                continue;
            }
            let c = p.wrapping_add_signed(self.grid.delta[k] * t as isize);
            let reach = i64::from(self.grid.runs[straight][c] >> 1);
            if along == 0 || along <= reach {
                end = end.min(t as usize);
            }
        }
        if end == usize::MAX {
            return None;
        }
        let first = p.wrapping_add_signed(self.grid.delta[k]);
        let first_cost = self.step_cost(p, first, true);
        let rest = self
            .step_cost(first, first, true)
            .saturating_mul(end as u64 - 1);
        Some((
            p.wrapping_add_signed(self.grid.delta[k] * end as isize),
            first_cost.saturating_add(rest),
        ))
    }

    /// The directions a node at `p` expands when reached by the directions `arrived`
    /// (crate docs): all eight when it is not uniform or was not reached by a move.
    fn successors(&self, p: usize, arrived: u8) -> u8 {
        if arrived == 0 || !self.grid.uniform[p] {
            return ALL;
        }
        let mut keep = 0u8;
        for k in (0..8).filter(|k| arrived >> k & 1 == 1) {
            let (dx, dy) = DIRECTIONS[k];
            if k < 4 {
                keep |= 1 << k;
                for s in sides(k) {
                    if self.grid.forced(p, k, s) {
                        let (sx, sy) = DIRECTIONS[s];
                        keep |= 1 << s | 1 << direction(dx + sx, dy + sy);
                    }
                }
            } else {
                keep |= 1 << k | 1 << direction(dx, 0) | 1 << direction(0, dy);
            }
        }
        keep
    }
}

/// The two straight directions beside straight direction `k`.
const fn sides(k: usize) -> [usize; 2] {
    if k < 2 {
        [2, 3]
    } else {
        [0, 1]
    }
}

impl WeightedJps {
    /// Runs the search (crate docs) on `problem` within `budget`; `RECORD`: the copy that
    /// records its steps ([`Budget::record_events`]; never timed).
    fn search<const RECORD: bool>(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        let grid = problem.grid();
        let mut tally = Tally::default();
        if let Err(shortfall) = budget.check_memory(self.memory_bytes_for(grid), grid) {
            return Outcome::over_memory(shortfall, tally.counters());
        }
        let max_weight = grid.weights().map_or(1, |w| w.max());
        if self.open_weight != Some(max_weight) {
            let max_move = Cost::SQRT_2.times(u64::from(max_weight));
            self.open
                .configure_scaled(max_move, 1.0, u64::from(max_weight));
            self.open_weight = Some(max_weight);
        }
        let prepared = self.prepared.get_or_build(grid);
        let len = prepared.free.len();
        self.nodes.fit(len);
        let nodes = &mut self.nodes;
        let open = &mut self.open;
        open.clear();
        let rule = grid
            .weights()
            .map_or(planner_api::CostRule::Mean, |w| w.rule());
        let (start, goal) = (problem.start(), problem.goal());
        let (start_index, goal_index) = (prepared.index(start), prepared.index(goal));
        let mut jumper = Jumper {
            grid: prepared,
            goal: goal_index,
            half: [Cost::ONE.units() / 2, Cost::SQRT_2.units() / 2],
            factors: rule.factors(),
            jumps: 0,
        };
        let min_weight = u64::from(prepared.min_weight);
        let h = |p: usize| {
            let cell = prepared.cell(p);
            let (dx, dy) = (cell.x.abs_diff(goal.x), cell.y.abs_diff(goal.y));
            let diagonals = dx.min(dy);
            Cost::octile(u64::from(dx.max(dy) - diagonals), u64::from(diagonals)).times(min_weight)
        };
        // One step, while there is room for it: node `p` with its parent, `g` (units) and
        // `f = g + h` as OPEN orders it.
        let mut events = Vec::new();
        let mut note = |kind, p: usize, parent: Option<usize>, g: u64| {
            if RECORD && events.len() < planner_api::MAX_SEARCH_EVENTS {
                let g = Cost::from_units(g);
                events.push(SearchEvent {
                    kind,
                    cell: prepared.cell(p),
                    parent: parent.map(|q| prepared.cell(q)),
                    g: g.to_f64(),
                    f: (g + h(p)).to_f64(),
                });
            }
        };
        nodes.state[start_index] = OPEN;
        nodes.g[start_index] = 0;
        nodes.parent[start_index] = start_index as u32;
        nodes.directions[start_index] = 0;
        nodes.touched.push(start_index as u32);
        open.push(start_index as u32, h(start_index), Cost::ZERO);
        note(SearchEventKind::Generating, start_index, None, 0);
        tally.n_open_insertions = 1;
        tally.peak_open = 1;
        let mut clock = budget.start();
        let mut expanded = Vec::new();
        let status = loop {
            let Some(p) =
                open.pop(|q| nodes.state[q as usize] == CLOSED && nodes.reopen[q as usize] == 0)
            else {
                break Status::NoPath;
            };
            let p = p as usize;
            let directions = match nodes.state[p] {
                CLOSED if nodes.reopen[p] == 0 => continue, // An older entry.
                CLOSED => {
                    tally.n_reopened += 1;
                    std::mem::take(&mut nodes.reopen[p])
                }
                _ => nodes.directions[p],
            };
            if !clock.allows(tally.n_expanded) {
                break Status::BudgetExhausted;
            }
            let reopened = nodes.state[p] == CLOSED;
            nodes.state[p] = CLOSED;
            tally.n_expanded += 1;
            if budget.record_expanded {
                expanded.push(prepared.cell(p));
            }
            if RECORD {
                let parent = nodes.parent[p] as usize;
                let parent = (parent != p).then_some(parent);
                note(SearchEventKind::Expanding, p, parent, nodes.g[p]);
            }
            if p == goal_index {
                break Status::Found;
            }
            let expand = if reopened {
                // Only the late directions' successors (a subset of all eight when the
                // node is not uniform, which expanded all eight already).
                match prepared.uniform[p] {
                    true => jumper.successors(p, directions),
                    false => 0,
                }
            } else {
                jumper.successors(p, directions)
            };
            let g_p = nodes.g[p];
            for k in (0..8).filter(|k| expand >> k & 1 == 1) {
                let jump = match k < 4 {
                    true => jumper.straight(p, k),
                    false => jumper.diagonal(p, k),
                };
                let Some((q, cost)) = jump else {
                    continue;
                };
                // The direction of the last move into `q`: the jump's own.
                let bit = 1u8 << k;
                let g_q = g_p.saturating_add(cost);
                // A push that only adds a direction to a node at its own cost (below) is
                // no step; the node's expansion again is.
                let kind = match nodes.state[q] {
                    UNSEEN => SearchEventKind::Generating,
                    _ => SearchEventKind::Updating,
                };
                match nodes.state[q] {
                    UNSEEN => {
                        nodes.state[q] = OPEN;
                        nodes.touched.push(q as u32);
                        tally.n_open_insertions += 1;
                    }
                    OPEN if g_q > nodes.g[q] => continue,
                    OPEN if g_q == nodes.g[q] => {
                        nodes.directions[q] |= bit;
                        continue;
                    }
                    OPEN => {}
                    _ if g_q == nodes.g[q] => {
                        // Expanded already, reached again at its cost by a new direction.
                        if nodes.directions[q] & bit == 0 {
                            nodes.directions[q] |= bit;
                            nodes.reopen[q] |= bit;
                            open.push(
                                q as u32,
                                Cost::from_units(g_q) + h(q),
                                Cost::from_units(g_q),
                            );
                        }
                        continue;
                    }
                    _ if g_q > nodes.g[q] => continue,
                    _ => {
                        // Cheaper than when it was expanded (only with costs beyond the
                        // exact range of `Cost`): searched again from this cost.
                        nodes.state[q] = OPEN;
                        nodes.reopen[q] = 0;
                    }
                }
                tally.n_relaxations += 1;
                nodes.g[q] = g_q;
                nodes.parent[q] = p as u32;
                nodes.directions[q] = bit;
                open.push(
                    q as u32,
                    Cost::from_units(g_q) + h(q),
                    Cost::from_units(g_q),
                );
                if RECORD {
                    note(kind, q, Some(p), g_q);
                }
            }
            tally.peak_open = tally
                .peak_open
                .max(tally.n_open_insertions.saturating_sub(tally.n_expanded));
        };
        tally.n_jumps = jumper.jumps;
        let counters = tally.counters();
        let outcome = match status {
            Status::Found => {
                let (path, marks) = reconstruct(prepared, nodes, start_index, goal_index);
                let mut outcome = Outcome::found(path, counters);
                if self.config.marks {
                    outcome.marks = marks;
                }
                outcome
            }
            Status::BudgetExhausted => Outcome::budget_exhausted(None, counters),
            _ => Outcome::no_path(counters),
        };
        let mut outcome = outcome.with_expanded(expanded);
        outcome.events = events;
        outcome
    }
}

/// The path from the start to the goal through the jump points' parents, each leg diagonal
/// first, then straight; and the jump points between as marks.
fn reconstruct(prepared: &Prepared, nodes: &Nodes, start: usize, goal: usize) -> (Path, Vec<Mark>) {
    let mut chain = vec![goal];
    let mut at = goal;
    while at != start {
        at = nodes.parent[at] as usize;
        chain.push(at);
    }
    chain.reverse();
    let mut cells = vec![prepared.cell(start)];
    for leg in chain.windows(2) {
        push_octile_leg(&mut cells, prepared.cell(leg[0]), prepared.cell(leg[1]));
    }
    let marks = match chain.len() {
        0..=2 => Vec::new(),
        n => chain[1..n - 1]
            .iter()
            .enumerate()
            .map(|(i, &j)| Mark::new(prepared.cell(j), format!("J{}", i + 1)))
            .collect(),
    };
    (Path::new(cells), marks)
}

impl Planner for WeightedJps {
    fn name(&self) -> &str {
        NAME
    }

    /// Unseeded; every step is an 8-connected move without corner cutting; optimal under
    /// the grid's cell costs.
    fn specs(&self) -> PlannerSpecs {
        PlannerSpecs::deterministic(PathSpec::Moves(self.moves.clone()))
            .with_admissible(true)
            .with_cell_costs()
    }

    fn prepare_bytes(&self, grid: &Grid) -> u64 {
        self.memory_bytes_for(grid)
    }

    /// Builds the padded layout with the weights and uniform flags (kept until the grid
    /// changes) and sizes the per-cell node state.
    fn prepare(&mut self, grid: &Grid) {
        let len = self.prepared.get_or_build(grid).free.len();
        self.nodes.fit(len);
    }

    /// Records the expanded jump points when the budget asks
    /// ([`Budget::record_expanded`]). Refuses with [`Outcome::over_memory`] when its tables
    /// and per-cell state for the
    /// grid (55 bytes per cell of the grid with a one-cell border) are over
    /// [`Budget::max_memory_mb`].
    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        match budget.record_events {
            true => self.search::<true>(problem, budget),
            false => self.search::<false>(problem, budget),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner_api::CostRule;

    /// Random edits (cells blocked and freed, new weights one cell at a time and in 3 x 3
    /// patches) brought in by [`Prepared::update`] give the tables a rebuild gives.
    #[test]
    fn updated_tables_equal_rebuilt_ones() {
        let mut next = planner_testkit::xorshift(0x5eed_u64);
        let palette = [1u16, 1, 1, 2, 5, 9];
        let mut n_updates = 0u64;
        for round in 0..400 {
            let (w, h) = (8 + (next() % 33) as u32, 8 + (next() % 33) as u32);
            let density = next() % 30;
            let free: Vec<bool> = (0..w * h).map(|_| next() % 100 >= density).collect();
            let mut grid = Grid::from_free_cells(w, h, free).unwrap();
            let weighted = round % 3 != 0;
            if weighted {
                let weights = (0..w * h).map(|_| palette[(next() % 6) as usize]).collect();
                grid = grid.with_weights(weights, CostRule::Mean).unwrap();
            }
            let mut prepared = Prepared::default();
            prepared.get_or_build(&grid);
            for step in 0..12 {
                let before = grid.revision();
                for _ in 0..1 + next() % 5 {
                    let cell = Cell::new(
                        (next() % u64::from(w)) as u32,
                        (next() % u64::from(h)) as u32,
                    );
                    match next() % 3 {
                        0 => grid.set_free(cell, next() % 2 == 0),
                        1 if weighted => {
                            grid.set_weight(cell, palette[(next() % 6) as usize]);
                        }
                        _ if weighted => {
                            let weight = palette[(next() % 6) as usize];
                            for dy in 0..3 {
                                for dx in 0..3 {
                                    if let Some(c) = grid.offset(cell, dx, dy) {
                                        grid.set_weight(c, weight);
                                    }
                                }
                            }
                        }
                        _ => grid.set_free(cell, true),
                    }
                }
                let n_changed = grid.changed_since(before).map(Iterator::count);
                let len = prepared.free.len();
                n_updates += u64::from(n_changed.is_some_and(|n| Prepared::updates(n, len)));
                prepared.get_or_build(&grid);
                let mut rebuilt = Prepared::default();
                rebuilt.get_or_build(&grid);
                let at = format!("round {round} step {step}");
                assert_eq!(prepared.free, rebuilt.free, "{at}");
                assert_eq!(prepared.weights, rebuilt.weights, "{at}");
                assert_eq!(prepared.uniform, rebuilt.uniform, "{at}");
                for k in 0..8 {
                    let differs = (0..rebuilt.runs[k].len())
                        .find(|&p| prepared.runs[k][p] != rebuilt.runs[k][p]);
                    assert_eq!(differs, None, "{at}: direction {k}");
                }
                assert_eq!(prepared.min_weight, rebuilt.min_weight, "{at}");
                assert_eq!(prepared.revision, Some(grid.revision()));
            }
        }
        // 4,171 of the 4,800 rounds are brought in by `update` (the others edit more than
        // one cell in 32 and rebuild).
        assert_eq!(n_updates, 4171);
    }
}
