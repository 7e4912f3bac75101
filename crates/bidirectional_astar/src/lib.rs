//! Bidirectional A\*: one A\* forward from the start towards the goal and one backward
//! from the goal towards the start, stopped by Pohl's rule (I. Pohl, "Bi-directional
//! Search", Machine Intelligence 6, 1971, pp. 127-140): stop when the best meeting cost is
//! at most the larger of the two frontiers' least `f`. The proof for this implementation is
//! below.
//!
//! # The search
//! - Grid: 4-connected moves with cost 1 and the Manhattan heuristic, or 8-connected moves
//!   without corner cutting with costs 1 and `sqrt 2` and the octile heuristic. Both
//!   heuristics are consistent, and the moves are symmetric (a move is safe from `a` to `b`
//!   exactly when its reverse is safe from `b` to `a`), so the backward search runs the
//!   same moves from the goal, with `h` the distance estimate to the start.
//! - Each direction is A\* with its own OPEN, CLOSED, g and parents: OPEN ordered by `f`,
//!   then larger `g`, then first pushed; CLOSED nodes are never reopened (with a consistent
//!   heuristic a closed node's g is optimal in its direction).
//! - Meeting: whenever a node's g improves in one direction and the node has been reached
//!   in the other (it is in that direction's OPEN or CLOSED), `g_F + g_B` is a start-goal
//!   path's cost; the least such cost is `mu`, and its node the meeting point
//!   (`n_meeting_updates` counts the improvements of `mu`). The start is reached forward and
//!   the goal backward from the beginning, so `start = goal` meets at once with `mu = 0`.
//! - Which side expands: the one whose OPEN holds fewer nodes, forward on ties (Pohl's
//!   cardinality criterion).
//! - Stopping rule (Pohl): before each expansion, stop when `mu <= max(fmin_F, fmin_B)`,
//!   the least `f` in either OPEN, or when either OPEN is empty. The path is the forward
//!   parents from the start to the meeting point, then the backward parents to the goal.
//!
//! # Why the stopping rule is correct
//! Let `C*` be the optimal cost and `P` an optimal path, and suppose the rule stops with
//! `mu > C*`. Take the first node `n` of `P` not CLOSED forward. If there is none, the goal
//! is CLOSED forward, and when its g last improved (to its optimal value `C*`) it was
//! reached backward (`g_B(goal) = 0`), so `mu <= C*`. Otherwise `n` is the start or its
//! predecessor on `P` is CLOSED forward with optimal g, so `n` is in the forward OPEN with
//! optimal `g_F(n)`, and `f_F(n) = g_F(n) + h_F(n) <= g_F(n) + d(n, goal) = C*` since
//! `h_F` is admissible. So `fmin_F <= C* < mu`, and the forward OPEN is not empty; the same
//! holds backward, so neither stopping condition held: a contradiction. Hence the search
//! stops with `mu = C*`, the length A\* finds (tested on every `.scen` file in
//! `maps/movingai`, 4- and 8-connected).
//!
//! # Weighted grids
//! On a grid with cell weights ([`planner_api::weights`]) costs are exact integer
//! [`Cost`] units: a move from `a` to `b` costs half its length times
//! `k_from * w(a) + k_to * w(b)` by the grid's [`planner_api::CostRule`], and the backward
//! search, which follows moves in reverse, charges each move what it costs forward (the
//! entered cell is the one it expands from). Both heuristics are multiplied by the grid's
//! smallest weight, which keeps them admissible and consistent, so the proof above holds
//! unchanged (costs are still non-negative). `tests/weighted.rs` holds the costs to the
//! test kit's weighted Dijkstra on 10,000 random grids. Unweighted grids run in `f64` as
//! before (the two forms are one search loop with a const generic).
//!
//! # Counters
//! Totals under A\*'s names (`n_expanded`, `n_neighbor_checks`, `n_blocked`, `n_skipped`,
//! `n_open_insertions` (start and goal both counted), `n_relaxations`, and `peak_open`, the
//! most nodes in both OPENs together), then the same seven for each direction prefixed
//! `forward_` and `backward_` (`peak_open` there is that direction's own peak), then
//! `n_meeting_updates`. Every expanded node checks all its moves (the search never stops
//! on an expansion), so `n_neighbor_checks = k * n_expanded` with `k` moves. One expansion
//! of the budget is one expansion in either direction. Every counter and path equals that
//! of `planner_testkit::reference_bidirectional_astar`, the search written again with std's
//! binary heaps and planner-api's moves and move costs, 4- and 8-connected, on 3,000 small
//! random grids and 1,500 random weighted ones (`tests/reference.rs`) and on every run of
//! the configs (xtask's `every_bidirectional_astar_run_matches_the_reference_search`).
//!
//! ```
//! use planner_api::{Budget, Cell, Grid, Planner, Problem, Status};
//! use planner_bidirectional_astar::{BidirectionalAStar, Config};
//!
//! let grid = Grid::from_ascii("
//!     .....
//!     ..#..
//!     .....
//! ").unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 1), Cell::new(4, 1)).unwrap();
//! let mut search = BidirectionalAStar::new(Config::default()).unwrap();
//! let outcome = search.plan(&problem, &Budget::unlimited());
//! assert_eq!(outcome.status, Status::Found);
//! // Around the block: a diagonal, two straight moves, a diagonal: 2 + 2 sqrt 2.
//! let length = outcome.path.unwrap().metrics().length;
//! assert!((length - (2.0 + 2.0 * 2f64.sqrt())).abs() < 1e-12);
//! let c = &outcome.counters;
//! assert_eq!(
//!     c.get("n_expanded"),
//!     Some(c.get("forward_n_expanded").unwrap() + c.get("backward_n_expanded").unwrap())
//! );
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

use planner_search::neighbourhood::PaddedWeights;
use planner_search::{QuadHeap, Stamped};

use planner_api::{
    Adjacency, Budget, Cell, Connectivity, Cost, Counter, Counters, Grid, MemoryShortfall,
    MoveOrderError, MoveSet, NeighborOrder, Outcome, Path, PathSpec, Planner, PlannerSpecs,
    Problem, SearchEvent, SearchEventKind, SearchStats, Status,
};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The registry name of this planner.
pub const NAME: &str = "bidirectional_astar";

/// Parameters; every field has a default.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// 4 (Manhattan heuristic) or 8 (octile heuristic) directions. Default 8.
    #[schemars(with = "u32", extend("enum" = [4, 8]))]
    pub moves: Connectivity,
    /// Diagonal moves past a blocked corner: must be false (the Moving AI benchmark's
    /// rule). Default false.
    pub corner_cutting: bool,
    /// Neighbour order, e.g. `"R L D U"` (see [`NeighborOrder`]), the same in both
    /// directions. Default `"R L D U"`, diagonals after.
    #[schemars(with = "String")]
    pub order: NeighborOrder,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            moves: Connectivity::Eight,
            corner_cutting: false,
            order: NeighborOrder::default(),
        }
    }
}

/// A parameter bidirectional A\* cannot run with.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConfigError {
    /// `moves` is neither 4 nor 8.
    #[error("parameter `moves`: bidirectional A* runs 4 or 8 directions; {0} is not supported")]
    Moves(Connectivity),
    /// `corner_cutting` is true.
    #[error("parameter `corner_cutting`: corner cutting is not supported")]
    CornerCutting,
    /// `order` does not fit `moves`.
    #[error("parameter `order`: {0}")]
    Order(#[from] MoveOrderError),
}

impl planner_api::ParamKey for ConfigError {
    fn param_key(&self) -> &str {
        match self {
            ConfigError::Moves(_) => "moves",
            ConfigError::CornerCutting => "corner_cutting",
            ConfigError::Order(_) => "order",
        }
    }
}

const FORWARD: usize = 0;
const BACKWARD: usize = 1;

/// Per-cell state of both directions; `stamp[d]` is `generation << 1 | closed`. `g` holds
/// the bits of an `f64` on an unweighted grid (non-negative, so the bits order as the
/// numbers) and [`Cost`] units on a weighted one.
#[derive(Debug, Clone, Copy, Default)]
struct Node {
    g: [u64; 2],
    parent: [u32; 2],
    stamp: [u32; 2],
}

/// An OPEN entry, a min-heap key: least `f`, then largest `g` (`g_rev` is the complement
/// of its bits), then first pushed. Costs are non-negative, so their bit patterns order as
/// the numbers do.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Entry {
    f: u64,
    g_rev: u64,
    seq: u64,
    node: u32,
}

/// The bidirectional A\* planner. Build with [`BidirectionalAStar::new`]; reuse it for many
/// queries (per-cell arrays and OPEN lists are kept).
#[derive(Debug, Clone)]
pub struct BidirectionalAStar {
    moves: MoveSet,
    eight: bool,
    adjacency: Option<Adjacency>,
    nodes: Stamped<Node>,
    open: [QuadHeap<Entry>; 2],
    /// A weighted grid's weights in the adjacency's padded layout.
    weight_cells: PaddedWeights,
}

/// What one search produced.
#[derive(Debug, Clone, PartialEq)]
pub struct Search {
    /// How it ended.
    pub status: Status,
    /// The path when found (or the best one met when the budget ran out).
    pub path: Option<Path>,
    /// `mu`, the path's cost, when there is a path.
    pub cost: Option<f64>,
    /// On a weighted grid, `mu` exactly in [`Cost`] units, when there is a path.
    pub exact_cost: Option<Cost>,
    /// Counters of the forward and the backward search.
    pub stats: [SearchStats; 2],
    /// Most nodes in both OPENs together.
    pub peak_open: u64,
    /// Improvements of the best meeting cost.
    pub n_meeting_updates: u64,
    /// The expanded cells of both directions in expansion order, when the budget asked
    /// for them ([`Budget::record_expanded`]); else empty. A cell expanded by both
    /// directions is listed twice.
    pub expanded: Vec<Cell>,
    /// The steps of both directions in order, when the budget asked
    /// ([`Budget::record_events`]): every push into a direction's OPEN (`generating` a
    /// node's first there, `updating` one that lowers its `g` there) and every expansion,
    /// each with its parent in that direction's tree (towards the start forward, the goal
    /// backward), its `g` from that direction's end and `f`, at most
    /// [`planner_api::MAX_SEARCH_EVENTS`]. A cell both directions reach has steps of each.
    pub events: Vec<SearchEvent>,
    /// Set when the per-cell state did not fit [`Budget::max_memory_mb`] (nothing was
    /// allocated or searched).
    pub memory: Option<MemoryShortfall>,
}

impl Search {
    /// The reported counters (crate docs, "Counters").
    pub fn counters(&self) -> Counters {
        let mut total = self.stats[FORWARD];
        total += self.stats[BACKWARD];
        total.peak_open = self.peak_open;
        let mut counters = total.report(Counter::ASTAR);
        for (prefix, stats) in [
            ("forward_", &self.stats[FORWARD]),
            ("backward_", &self.stats[BACKWARD]),
        ] {
            for &counter in Counter::ASTAR {
                counters.push(format!("{prefix}{}", counter.name()), stats.get(counter));
            }
        }
        counters.push("n_meeting_updates", self.n_meeting_updates);
        counters
    }
}

impl BidirectionalAStar {
    /// A planner with `config`, validated.
    pub fn new(config: Config) -> Result<BidirectionalAStar, ConfigError> {
        let eight = match config.moves {
            Connectivity::Four => false,
            Connectivity::Eight => true,
            other => return Err(ConfigError::Moves(other)),
        };
        if config.corner_cutting {
            return Err(ConfigError::CornerCutting);
        }
        Ok(BidirectionalAStar {
            moves: MoveSet::new(config.moves, false, &config.order)?,
            eight,
            adjacency: None,
            nodes: Stamped::default(),
            open: [QuadHeap::default(), QuadHeap::default()],
            weight_cells: PaddedWeights::default(),
        })
    }

    /// Builds the move masks and node arrays for `grid`, and on a weighted grid its
    /// weights in the padded layout (done by the first search on a grid otherwise).
    pub fn prepare(&mut self, grid: &Grid) {
        let adjacency = Adjacency::cached(&mut self.adjacency, grid, &self.moves);
        self.nodes.fit(adjacency.padded_len());
        if grid.is_weighted() {
            let (reach, stride) = (adjacency.reach(), adjacency.stride());
            let padded_len = adjacency.padded_len();
            self.weight_cells
                .get_or_build(grid, reach, stride, padded_len);
        }
    }

    /// The bytes of the adjacency and the node records (32 bytes per padded cell) for
    /// `grid`, and on a weighted grid its padded weights (2 bytes per padded cell).
    pub fn memory_bytes_for(&self, grid: &Grid) -> u64 {
        let padded = Adjacency::padded_len_for(grid, &self.moves) as u64;
        let weights = if grid.is_weighted() { 2 * padded } else { 0 };
        Adjacency::bytes_for(grid, &self.moves)
            + padded * std::mem::size_of::<Node>() as u64
            + weights
    }

    /// Runs the search on `problem` within `budget`.
    pub fn search(&mut self, problem: &Problem<'_>, budget: &Budget) -> Search {
        let grid = problem.grid();
        if let Err(shortfall) = budget.check_memory(self.memory_bytes_for(grid), grid) {
            return Search {
                status: Status::BudgetExhausted,
                path: None,
                cost: None,
                exact_cost: None,
                stats: [SearchStats::default(); 2],
                peak_open: 0,
                n_meeting_updates: 0,
                expanded: Vec::new(),
                events: Vec::new(),
                memory: Some(shortfall),
            };
        }
        self.prepare(grid);
        // A copy of the loop that records (never timed) and one that does not.
        let record = budget.record_expanded || budget.record_events;
        match (grid.weights(), record) {
            (Some(_), false) => self.run::<true, false>(problem, budget),
            (None, false) => self.run::<false, false>(problem, budget),
            (Some(_), true) => self.run::<true, true>(problem, budget),
            (None, true) => self.run::<false, true>(problem, budget),
        }
    }

    /// The search after the memory check. `W` is true on a weighted grid: costs are then
    /// exact [`Cost`] units, a move from `a` to `b` costs `half * (k_from * w(a) + k_to *
    /// w(b))` ([`planner_api::weights`]; the backward search, which follows moves in
    /// reverse, charges the same for the same move) and the heuristics are multiplied by
    /// the smallest weight; false is the unweighted search in `f64`, as before.
    fn run<const W: bool, const RECORD: bool>(
        &mut self,
        problem: &Problem<'_>,
        budget: &Budget,
    ) -> Search {
        let grid = problem.grid();
        let (record, record_events) = (
            RECORD && budget.record_expanded,
            RECORD && budget.record_events,
        );
        let mut expanded = Vec::new();
        let mut events = Vec::new();
        // A value of `g` or `f` as a number (exact units or `f64` bits).
        let number = |x: u64| match W {
            true => Cost::from_units(x).to_f64(),
            false => f64::from_bits(x),
        };
        let mut note = |kind, cell: Cell, parent: Option<Cell>, g: u64, f: u64| {
            if events.len() < planner_api::MAX_SEARCH_EVENTS {
                events.push(SearchEvent {
                    kind,
                    cell,
                    parent,
                    g: number(g),
                    f: number(f),
                });
            }
        };
        let Some(adjacency) = self.adjacency.as_ref() else {
            unreachable!("prepare fills the adjacency cache");
        };
        let (stamps, nodes) = self.nodes.begin();
        let (open_stamp, closed_stamp) = (stamps.open, stamps.closed);
        let open = &mut self.open;
        open[FORWARD].clear();
        open[BACKWARD].clear();

        let n_moves = adjacency.n_moves() as u64;
        let mut costs = [0u64; 8];
        for (slot, mv) in costs.iter_mut().zip(self.moves.moves()) {
            *slot = match W {
                true => mv.exact_cost().units() / 2,
                false => mv.cost.to_bits(),
            };
        }
        let (min_weight, (k_from, k_to)) = grid
            .weights()
            .map_or((1, (0, 0)), |w| (u64::from(w.min()), w.rule().factors()));
        // `prepare` (just called) built them for this grid.
        let weight_cells: &[u16] = if W { self.weight_cells.cells() } else { &[] };
        // Sums and infinity in the representation of `g`.
        // Weighted sums stop one below infinity (`Cost::MAX`, planner-api's weights docs,
        // "The range"): a goal reached through saturated costs is still reached.
        let add = |a: u64, b: u64| -> u64 {
            if W {
                a.saturating_add(b).min(u64::MAX - 1)
            } else {
                (f64::from_bits(a) + f64::from_bits(b)).to_bits()
            }
        };
        let infinity = if W { u64::MAX } else { f64::INFINITY.to_bits() };
        let zero = 0u64;
        let eight = self.eight;
        // Direction d heads for targets[d].
        let targets = [problem.goal(), problem.start()];
        let h = |d: usize, c: Cell| -> u64 {
            let t = targets[d];
            if W {
                let estimate = if eight {
                    Cost::octile_distance(c.x.abs_diff(t.x), c.y.abs_diff(t.y))
                } else {
                    Cost::steps(c.manhattan(t))
                };
                estimate.times(min_weight).units().min(u64::MAX - 1)
            } else if eight {
                c.octile(t).to_bits()
            } else {
                (c.manhattan(t) as f64).to_bits()
            }
        };
        let mut seq = 0u64;
        let mut stats = [SearchStats::default(); 2];
        let mut n_safe = [0u64; 2];
        let mut peak_open = 0u64;
        let mut n_meeting_updates = 0u64;
        let mut mu = infinity;
        let mut meet = usize::MAX;

        for (d, cell) in [(FORWARD, problem.start()), (BACKWARD, problem.goal())] {
            let p = adjacency.index(cell);
            let node = &mut nodes[p];
            node.g[d] = zero;
            node.parent[d] = p as u32;
            node.stamp[d] = open_stamp;
            open[d].push(Entry {
                f: h(d, cell),
                g_rev: !0,
                seq,
                node: p as u32,
            });
            if record_events {
                note(SearchEventKind::Generating, cell, None, zero, h(d, cell));
            }
            seq += 1;
            stats[d].n_open_insertions = 1;
            stats[d].peak_open = 1;
        }
        let start_index = adjacency.index(problem.start());
        if start_index == adjacency.index(problem.goal()) {
            mu = zero;
            meet = start_index;
            n_meeting_updates = 1;
        }
        peak_open = peak_open.max(2);

        let mut clock = budget.start();
        let status = loop {
            // The least live f of each OPEN, dropping entries of CLOSED or improved nodes.
            let mut fmin = [infinity; 2];
            for d in [FORWARD, BACKWARD] {
                while let Some(top) = open[d].peek() {
                    let node = &nodes[top.node as usize];
                    if node.stamp[d] == closed_stamp || node.g[d] != !top.g_rev {
                        open[d].pop();
                    } else {
                        fmin[d] = top.f;
                        break;
                    }
                }
            }
            if open[FORWARD].is_empty() || open[BACKWARD].is_empty() || mu <= fmin[0].max(fmin[1]) {
                break if mu != infinity {
                    Status::Found
                } else {
                    Status::NoPath
                };
            }
            let d = if in_open(&stats, BACKWARD) < in_open(&stats, FORWARD) {
                BACKWARD
            } else {
                FORWARD
            };
            let other = 1 - d;
            if !clock.allows(stats[FORWARD].n_expanded + stats[BACKWARD].n_expanded) {
                break Status::BudgetExhausted;
            }
            let Some(entry) = open[d].pop() else {
                unreachable!("OPEN {d} was checked to be non-empty");
            };
            let p = entry.node as usize;
            nodes[p].stamp[d] = closed_stamp;
            stats[d].n_expanded += 1;
            if record {
                expanded.push(adjacency.cell(p));
            }
            let g_node = nodes[p].g[d];
            if record_events {
                let parent = nodes[p].parent[d] as usize;
                let parent = (parent != p).then(|| adjacency.cell(parent));
                let cell = adjacency.cell(p);
                note(SearchEventKind::Expanding, cell, parent, g_node, entry.f);
            }
            let w_p = if W { u64::from(weight_cells[p]) } else { 0 };
            let mut mask = adjacency.mask(p);
            while mask != 0 {
                let m = mask.trailing_zeros();
                mask &= mask - 1;
                n_safe[d] += 1;
                let q = adjacency.neighbor(p, m);
                let next = &mut nodes[q];
                if next.stamp[d] == closed_stamp {
                    stats[d].n_skipped += 1;
                    continue;
                }
                let cost = costs[(m & 7) as usize];
                let g_new = if W {
                    // Forward the move is p -> q; backward it is q -> p.
                    let w_q = u64::from(weight_cells[q]);
                    let factor = match d {
                        FORWARD => k_from * w_p + k_to * w_q,
                        _ => k_from * w_q + k_to * w_p,
                    };
                    add(g_node, cost.saturating_mul(factor))
                } else {
                    add(g_node, cost)
                };
                let known = next.stamp[d] == open_stamp;
                if known && g_new >= next.g[d] {
                    continue;
                }
                stats[d].n_relaxations += 1;
                stats[d].n_open_insertions += u64::from(!known);
                next.g[d] = g_new;
                next.parent[d] = p as u32;
                next.stamp[d] = open_stamp;
                if next.stamp[other] >> 1 == stamps.generation && add(g_new, next.g[other]) < mu {
                    mu = add(g_new, next.g[other]);
                    meet = q;
                    n_meeting_updates += 1;
                }
                let f = add(g_new, h(d, adjacency.cell(q)));
                open[d].push(Entry {
                    f,
                    g_rev: !g_new,
                    seq,
                    node: q as u32,
                });
                if record_events {
                    let kind = match known {
                        true => SearchEventKind::Updating,
                        false => SearchEventKind::Generating,
                    };
                    let (cell, parent) = (adjacency.cell(q), adjacency.cell(p));
                    note(kind, cell, Some(parent), g_new, f);
                }
                seq += 1;
            }
            stats[d].peak_open = stats[d].peak_open.max(in_open(&stats, d));
            peak_open = peak_open.max(in_open(&stats, FORWARD) + in_open(&stats, BACKWARD));
        };
        for d in [FORWARD, BACKWARD] {
            stats[d].n_neighbor_checks = n_moves * stats[d].n_expanded;
            stats[d].n_blocked = stats[d].n_neighbor_checks - n_safe[d];
        }
        let path = (mu != infinity).then(|| {
            let mut cells = Vec::new();
            let mut node = meet;
            loop {
                cells.push(adjacency.cell(node));
                let parent = nodes[node].parent[FORWARD] as usize;
                if parent == node {
                    break;
                }
                node = parent;
            }
            cells.reverse();
            node = meet;
            loop {
                let parent = nodes[node].parent[BACKWARD] as usize;
                if parent == node {
                    break;
                }
                node = parent;
                cells.push(adjacency.cell(node));
            }
            Path::new(cells)
        });
        let (cost, exact_cost) = match (path.is_some(), W) {
            (false, _) => (None, None),
            (true, true) => (
                Some(Cost::from_units(mu).to_f64()),
                Some(Cost::from_units(mu)),
            ),
            (true, false) => (Some(f64::from_bits(mu)), None),
        };
        Search {
            status,
            cost,
            exact_cost,
            path,
            stats,
            peak_open,
            n_meeting_updates,
            expanded,
            events,
            memory: None,
        }
    }
}

/// Nodes in direction `d`'s OPEN: each inserted node is expanded at most once.
fn in_open(stats: &[SearchStats; 2], d: usize) -> u64 {
    stats[d].n_open_insertions - stats[d].n_expanded
}

impl Planner for BidirectionalAStar {
    fn name(&self) -> &str {
        NAME
    }

    /// Deterministic; every step is one of the configured 4 or 8 moves; admissible (its
    /// paths are least-cost, the crate docs' proof), on weighted grids too.
    fn specs(&self) -> PlannerSpecs {
        PlannerSpecs::deterministic(PathSpec::Moves(self.moves.clone()))
            .with_cell_costs()
            .with_admissible(true)
    }

    fn prepare_bytes(&self, grid: &Grid) -> u64 {
        self.memory_bytes_for(grid)
    }

    fn prepare(&mut self, grid: &Grid) {
        BidirectionalAStar::prepare(self, grid);
    }

    /// Lists the expanded cells of both directions in expansion order when the budget
    /// asks ([`Budget::record_expanded`]), one per `n_expanded` (a cell both directions
    /// expand twice), and their steps with [`Budget::record_events`] ([`Search::events`]),
    /// in a copy of the loop of its own; refuses with [`Outcome::over_memory`] when
    /// [`BidirectionalAStar::memory_bytes_for`] the grid is over [`Budget::max_memory_mb`].
    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        let search = self.search(problem, budget);
        let counters = search.counters();
        match search.memory {
            Some(shortfall) => Outcome::over_memory(shortfall, counters),
            None => Outcome {
                events: search.events,
                ..Outcome::new(search.status, search.path, counters).with_expanded(search.expanded)
            },
        }
    }
}
