//! RRT* on occupancy grids, seeded and reproducible bit for bit.
//!
//! The algorithm is Karaman and Frazzoli's RRT* ("Sampling-based algorithms for optimal
//! motion planning", IJRR 30(7), 2011, Algorithm 6 with the `Extend` of its Algorithm 4),
//! built from planner-rrt's pieces: the same seeded sampler, steering, tree of distinct
//! cells with its bucket-grid index, and exact segment checks. Each iteration:
//!
//! 1. Draws a sample: the goal with probability `goal_bias`, else a free cell uniformly
//!    ([`planner_rrt::Sampler::goal_biased`], the same draws as RRT).
//! 2. Takes the nearest tree node and steers from it toward the sample
//!    ([`planner_rrt::steer`], `steer` and `step` as in RRT). A new cell that is already
//!    a node is a duplicate (nothing happens); an extension whose segment crosses a
//!    blocked cell is a collision (nothing happens).
//! 3. Otherwise finds the near set: every node within radius
//!    `r = min(gamma * (ln n / n)^(1/2), eta)` of the new cell, where `n` is the number
//!    of nodes before the new one (the paper's `card V`), `d = 2`, and `eta` the longest
//!    extension steering can make (`step` for four, `step * sqrt 2` for eight;
//!    [`planner_rrt::Steer::reach_squared`]).
//! 4. Choose parent: the new node's parent is the node `x` among the nearest and the
//!    near set that minimises `cost(x) + |x - new|` over collision-free segments (the
//!    nearest, whose segment was checked in step 2, is the initial choice).
//! 5. Rewire: every near node `x` with `cost(new) + |new - x| < cost(x)` and a free
//!    segment gets the new node as parent; the costs of its descendants are updated.
//! 6. When the new cell is the goal, the goal is in the tree; from then on its cost (the
//!    Euclidean length of its tree path) can only decrease, and every decrease is recorded.
//!
//! The search stops `iterations_after_solution` iterations after the goal joined the tree,
//! or after `max_iterations` iterations in all, or when the [`Budget`] runs out (one
//! iteration is one expansion; an iteration's work is bounded by its near set, at most the
//! cells within `eta`). The outcome is the goal's tree path.
//!
//! # Status
//! - [`Status::Found`]: the goal is in the tree and the search stopped by its own
//!   iteration limits. Start = goal is found at once with a one-cell path.
//! - [`Status::BudgetExhausted`]: the caller's budget stopped the search (with the best
//!   path so far if the goal is in the tree), or `max_iterations` ran out before the goal
//!   joined the tree (without a path). Like RRT, RRT* cannot prove that there is no path,
//!   so an unreachable goal ends here, never in [`Status::NoPath`].
//!
//! # The radius constant
//! The paper's Theorem 38 makes RRT* asymptotically optimal when
//! `gamma > gamma* = (2 (1 + 1/d))^(1/d) (mu(X_free) / zeta_d)^(1/d)`, with `mu(X_free)`
//! the free area and `zeta_d` the volume of the unit ball. On a grid with unit cells,
//! `d = 2`, `mu(X_free)` = the number of free cells and `zeta_2 = pi`, so
//! `gamma* = sqrt(3 n_free / pi)` ([`gamma_lower_bound`]). The `gamma` parameter sets the
//! constant; without it the planner uses `1.1 * gamma*` of the map it plans on (OMPL's
//! default `rewire_factor` of 1.1). A smaller `gamma` is accepted (any positive value) but
//! loses the guarantee. With the default, `gamma^2 ln n / n = 1.1555 (n_free / n) ln n >=
//! 1.1555 ln n` (a tree has at most `n_free` nodes), so with `step = 1` the cap binds from
//! `n = 3` on for four-way steering (`eta^2 = 1`) and from `n = 6` on for eight-way
//! (`eta^2 = 2`): `gamma` matters for longer steps (with `step = 4` and eight-way steering
//! on seed 003's map3, 760 free cells, once the tree has 135 nodes).
//!
//! # Choices where the paper leaves room
//! - Grid nodes are distinct cells (as in planner-rrt), so the tree holds at most every
//!   free cell; once it does, every sample is a duplicate and the cost stops improving.
//!   The paper's samples never repeat; a duplicate here does nothing, as in RRT.
//! - The near set is taken with `|x - new|^2 <= floor(r^2)` in exact integer squared
//!   distances (`r^2` is computed once per iteration in `f64` with `ln`).
//! - Ties: choose-parent keeps the earlier candidate on equal cost (the nearest first,
//!   then near nodes by increasing id); rewiring visits near nodes by increasing id.
//! - A segment is checked only when its candidate would improve a cost (the outcome is
//!   the paper's, which checks first; the counters count the checks made). A segment
//!   checked in choose-parent is not checked again when rewiring: planner-api's traversal
//!   visits the same cells in both directions (tested in planner-rrt).
//! - Costs are `f64` sums of [`Cell::euclidean`] along the tree path from the start, in
//!   path order, so the reported cost equals [`Path::metrics`]'s `length` exactly.
//!
//! # Against RRT on the same seed
//! Steps 1-2 make the same draws and the same nodes as RRT with the same `seed`,
//! `goal_bias`, `steer` and `step` (the nearest node depends on the nodes, not on their
//! parents). By induction every node's cost is at most its RRT cost: choose-parent starts
//! from RRT's parent, and rewiring only lowers costs (float addition is monotone). So the
//! first solution is found at the same iteration as RRT's and is never longer, and later
//! improvements only shorten it (tested on every seed of the tests).
//!
//! # Paths
//! Edges are free segments between cell centres (any-angle,
//! [`PathRule::AnyAngle`](planner_api::PathRule::AnyAngle)). With `step = 1` the radius is
//! at most one unit move, so every edge is a unit move: paths are 4-connected (`"four"`) or
//! 8-connected without corner cutting (`"eight"`), [`Config::path_moves`].
//!
//! # Counters
//! `n_iterations`, `n_samples`, `n_goal_samples`, `n_collisions`, `tree_size` and
//! `n_duplicates` as in RRT (identity: `n_collisions + n_duplicates + tree_size - 1 =
//! n_iterations`); then `n_near` (near nodes found), `n_parent_changes` (new nodes whose
//! chosen parent is not the nearest), `n_rewires`, `n_cost_updates` (descendant costs
//! updated after rewires), `n_segment_checks` and `n_segment_cells` (cells the checks
//! visited), `n_improvements` (goal-cost decreases, the first solution included: the
//! points of the `best_cost` series), `first_solution_iteration` (only when the goal is in
//! the tree), and `n_expanded` (= `n_iterations`). Every status, path, counter and
//! `best_cost` point equals that of `planner_testkit::reference_rrt_star`, the run written
//! again from this page (a scan of every node for the nearest and near nodes), on 540
//! random runs (`tests/rrt_star.rs`) and on every run of the configs (xtask's
//! `every_rrt_star_run_matches_the_reference_run`).
//!
//! The outcome's series `best_cost` (x: `iteration`) holds `[iteration, cost]` after each
//! improvement, the first solution first.
//!
//! ```
//! use planner_api::{Budget, Cell, Grid, Planner, Problem, Status};
//! use planner_rrt_star::{Config, RrtStar};
//!
//! let grid = Grid::from_ascii("
//!     ..........
//!     ..######..
//!     ..........
//!     ..........
//! ").unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 1), Cell::new(9, 1)).unwrap();
//! for seed in 0..5 {
//!     let config = Config { seed, steer: planner_rrt::Steer::Eight, step: 3, ..Config::default() };
//!     let outcome = RrtStar::new(config).unwrap().plan(&problem, &Budget::unlimited());
//!     assert_eq!(outcome.status, Status::Found);
//!     let length = outcome.path.as_ref().unwrap().metrics().length;
//!     // The cost series ends at the returned path's length...
//!     let series = &outcome.series[0];
//!     assert_eq!((series.name.as_str(), series.x.as_str()), ("best_cost", "iteration"));
//!     assert_eq!(series.points.last().unwrap()[1], length);
//!     // ...which is never above RRT's with the same seed, steering and step.
//!     let rrt = planner_rrt::Rrt::new(planner_rrt::Config {
//!         seed,
//!         steer: planner_rrt::Steer::Eight,
//!         step: 3,
//!         ..planner_rrt::Config::default()
//!     })
//!     .unwrap()
//!     .plan(&problem, &Budget::unlimited());
//!     assert!(length <= rrt.path.unwrap().metrics().length);
//!     // Over the wall's corners: no shorter than (0, 1) -> (2, 0) -> (7, 0) -> (9, 1).
//!     assert!(length >= 2.0 * 5f64.sqrt() + 5.0 - 1e-9);
//! }
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

use planner_api::{
    Budget, Cell, Connectivity, Counters, Outcome, Path, Planner, Problem, Series, Status,
};
use planner_rrt::{
    check_sampling, sample, steer, BucketGrid, NearestIndex, NodeId, Sampler, SegmentChecker,
    Steer, Tree,
};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The registry name.
pub const NAME: &str = "rrt_star";

const NONE: u32 = u32::MAX;

/// RRT*'s parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// Seed of the random generator (as RRT's); the same seed gives the same tree, path,
    /// counters and series everywhere. Default 0.
    pub seed: u64,
    /// Probability of sampling the goal instead of a uniform free cell, in `0..=1`.
    /// Default 0.05.
    #[schemars(range(min = 0, max = 1))]
    pub goal_bias: f64,
    /// Iterations in all before stopping (with or without a solution). Default 100,000.
    pub max_iterations: u64,
    /// Iterations run after the goal joined the tree, improving its cost; 0 stops at the
    /// first solution. Default 5,000.
    pub iterations_after_solution: u64,
    /// Unit moves used to steer (`"four"` or `"eight"`). Default `"four"`.
    pub steer: Steer,
    /// Unit moves per extension, at least 1. Default 1.
    #[schemars(range(min = 1))]
    pub step: u32,
    /// The radius constant `gamma`, positive and finite; absent: `1.1 *`
    /// [`gamma_lower_bound`] of the map's free cells. Default absent.
    #[schemars(extend("exclusiveMinimum" = 0))]
    pub gamma: Option<f64>,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            seed: 0,
            goal_bias: 0.05,
            max_iterations: 100_000,
            iterations_after_solution: 5_000,
            steer: Steer::Four,
            step: 1,
            gamma: None,
        }
    }
}

impl Config {
    /// The neighbourhood whose moves join consecutive path cells when `step = 1`
    /// (4- or 8-connected); `None` when `step > 1`, where paths are any-angle.
    pub fn path_moves(&self) -> Option<Connectivity> {
        self.steer.path_moves(self.step)
    }
}

/// A parameter outside its allowed range; the message names the parameter.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConfigError {
    /// `goal_bias` or `step`, checked as RRT checks them.
    #[error(transparent)]
    Sampling(#[from] planner_rrt::ConfigError),
    /// `gamma` is not a positive finite number.
    #[error("parameter `gamma` must be positive and finite, got {0}")]
    Gamma(f64),
}

impl planner_api::ParamKey for ConfigError {
    fn param_key(&self) -> &str {
        self.parameter()
    }
}

impl ConfigError {
    /// The name of the offending parameter: `goal_bias`, `step` or `gamma`.
    pub fn parameter(&self) -> &'static str {
        match self {
            ConfigError::Sampling(e) => e.parameter(),
            ConfigError::Gamma(_) => "gamma",
        }
    }
}

/// The paper's lower bound on `gamma` for a grid with `n_free` free unit cells:
/// `gamma* = (2 (1 + 1/2))^(1/2) (n_free / pi)^(1/2) = sqrt(3 n_free / pi)` (Theorem 38,
/// `d = 2`).
///
/// ```
/// let bound = planner_rrt_star::gamma_lower_bound(100);
/// assert!((bound - (300.0 / std::f64::consts::PI).sqrt()).abs() < 1e-12);
/// ```
pub fn gamma_lower_bound(n_free: usize) -> f64 {
    (3.0 * n_free as f64 / std::f64::consts::PI).sqrt()
}

/// `floor(r^2)` for the near radius `r = min(gamma (ln n / n)^(1/2), eta)` with
/// `eta^2 = reach_squared`, as an exact threshold on integer squared distances.
/// `n = 1` gives 0 (`ln 1 = 0`): the near set of the first extension is empty.
pub fn near_radius_squared(gamma: f64, n: usize, reach_squared: u64) -> u64 {
    let n = n.max(1) as f64;
    let shrinking = gamma * gamma * n.ln() / n;
    let reach = reach_squared as f64;
    // Both are finite and non-negative, so the floor of their minimum fits a u64.
    shrinking.min(reach).floor() as u64
}

/// RRT*'s counters as plain integers; see the crate docs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize)]
pub struct RrtStarStats {
    /// Iterations run (each draws one sample); also what the budget counts as expansions.
    pub n_iterations: u64,
    /// Samples drawn, goal samples included.
    pub n_samples: u64,
    /// Samples that were the goal by the `goal_bias` coin.
    pub n_goal_samples: u64,
    /// Extensions rejected because their segment crosses a blocked cell.
    pub n_collisions: u64,
    /// Tree nodes, the start included.
    pub tree_size: u64,
    /// Extensions that led to a cell already in the tree.
    pub n_duplicates: u64,
    /// Near nodes found, summed over iterations.
    pub n_near: u64,
    /// New nodes whose chosen parent is not the nearest node.
    pub n_parent_changes: u64,
    /// Near nodes given the new node as parent.
    pub n_rewires: u64,
    /// Descendant costs updated after rewires.
    pub n_cost_updates: u64,
    /// Segments checked for collision (steering, choose-parent and rewiring).
    pub n_segment_checks: u64,
    /// Cells visited by those checks.
    pub n_segment_cells: u64,
    /// Decreases of the goal's cost, the first solution included.
    pub n_improvements: u64,
    /// The iteration whose new node was the goal; `None` while it is not in the tree
    /// (0 when start = goal).
    pub first_solution_iteration: Option<u64>,
}

impl RrtStarStats {
    /// The counters in reporting order (crate docs).
    pub fn counters(&self) -> Counters {
        let mut counters = Counters::new()
            .with("n_iterations", self.n_iterations)
            .with("n_samples", self.n_samples)
            .with("n_goal_samples", self.n_goal_samples)
            .with("n_collisions", self.n_collisions)
            .with("tree_size", self.tree_size)
            .with("n_duplicates", self.n_duplicates)
            .with("n_near", self.n_near)
            .with("n_parent_changes", self.n_parent_changes)
            .with("n_rewires", self.n_rewires)
            .with("n_cost_updates", self.n_cost_updates)
            .with("n_segment_checks", self.n_segment_checks)
            .with("n_segment_cells", self.n_segment_cells)
            .with("n_improvements", self.n_improvements);
        if let Some(iteration) = self.first_solution_iteration {
            counters.push("first_solution_iteration", iteration);
        }
        counters.with("n_expanded", self.n_iterations)
    }
}

/// Whether a near node's segment to the new node has been checked, and how it came out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Checked {
    Unknown,
    Free,
    Blocked,
}

/// The RRT* planner, generic over its nearest-neighbour index (a [`BucketGrid`] unless
/// built with [`RrtStar::with_index`]).
///
/// Keeps its buffers between calls: after the first search on a grid size nothing is
/// allocated but the path and the series.
#[derive(Debug, Clone)]
pub struct RrtStar<I: NearestIndex = BucketGrid> {
    config: Config,
    sampler: Sampler,
    tree: Tree<I>,
    /// Per node: the length of its tree path from the start, and of its edge to its parent.
    cost: Vec<f64>,
    edge: Vec<f64>,
    /// Per node: children as an intrusive doubly linked list.
    first_child: Vec<u32>,
    next_sibling: Vec<u32>,
    prev_sibling: Vec<u32>,
    /// Scratch: the near set, its checked segments, and the cost-update stack.
    near: Vec<NodeId>,
    near_checked: Vec<Checked>,
    stack: Vec<NodeId>,
    stats: RrtStarStats,
}

impl RrtStar {
    /// An RRT* with a [`BucketGrid`] index. Errors, naming the parameter, when
    /// `goal_bias` is outside `0..=1`, `step` is 0, or `gamma` is not positive and finite.
    pub fn new(config: Config) -> Result<RrtStar, ConfigError> {
        RrtStar::with_index(config, BucketGrid::default())
    }
}

impl<I: NearestIndex> RrtStar<I> {
    /// An RRT* that finds nearest and near nodes with `index`; validates as [`RrtStar::new`].
    pub fn with_index(config: Config, index: I) -> Result<RrtStar<I>, ConfigError> {
        check_sampling(config.goal_bias, config.step)?;
        if let Some(gamma) = config.gamma {
            if !(gamma.is_finite() && gamma > 0.0) {
                return Err(ConfigError::Gamma(gamma));
            }
        }
        Ok(RrtStar {
            config,
            sampler: Sampler::default(),
            tree: Tree::with_index(index),
            cost: Vec::new(),
            edge: Vec::new(),
            first_child: Vec::new(),
            next_sibling: Vec::new(),
            prev_sibling: Vec::new(),
            near: Vec::new(),
            near_checked: Vec::new(),
            stack: Vec::new(),
            stats: RrtStarStats::default(),
        })
    }

    /// The validated config.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The counters of the last search (all zero before the first).
    pub fn stats(&self) -> RrtStarStats {
        self.stats
    }

    /// The last search's tree: each node's cell, its parent's cell (`None` for the start)
    /// and its cost, in the order the nodes were added.
    pub fn tree(&self) -> impl Iterator<Item = (Cell, Option<Cell>, f64)> + '_ {
        self.tree
            .edges()
            .zip(&self.cost)
            .map(|((cell, parent), &cost)| (cell, parent, cost))
    }

    fn add_node(&mut self, cell: Cell, parent: NodeId, edge: f64) -> NodeId {
        let node = self.tree.add(cell, parent);
        self.cost.push(self.cost[parent as usize] + edge);
        self.edge.push(edge);
        self.first_child.push(NONE);
        self.next_sibling.push(NONE);
        self.prev_sibling.push(NONE);
        self.link(node, parent);
        node
    }

    fn link(&mut self, node: NodeId, parent: NodeId) {
        let first = self.first_child[parent as usize];
        self.next_sibling[node as usize] = first;
        self.prev_sibling[node as usize] = NONE;
        if first != NONE {
            self.prev_sibling[first as usize] = node;
        }
        self.first_child[parent as usize] = node;
    }

    fn unlink(&mut self, node: NodeId, parent: NodeId) {
        let (prev, next) = (
            self.prev_sibling[node as usize],
            self.next_sibling[node as usize],
        );
        if prev != NONE {
            self.next_sibling[prev as usize] = next;
        } else {
            self.first_child[parent as usize] = next;
        }
        if next != NONE {
            self.prev_sibling[next as usize] = prev;
        }
    }

    /// Makes `new` the parent of `node` with edge length `edge`, and updates the costs of
    /// `node`'s subtree. Precondition: `new` is not in `node`'s subtree (it is a leaf
    /// outside it: its cost plus a positive edge is below `node`'s cost).
    fn rewire(&mut self, node: NodeId, new: NodeId, edge: f64, stats: &mut RrtStarStats) {
        if let Some(old) = self.tree.parent(node) {
            self.unlink(node, old);
        }
        self.tree.set_parent(node, new);
        self.link(node, new);
        self.edge[node as usize] = edge;
        self.cost[node as usize] = self.cost[new as usize] + edge;
        stats.n_rewires += 1;
        self.stack.clear();
        self.stack.push(node);
        while let Some(parent) = self.stack.pop() {
            let mut child = self.first_child[parent as usize];
            while child != NONE {
                self.cost[child as usize] = self.cost[parent as usize] + self.edge[child as usize];
                stats.n_cost_updates += 1;
                self.stack.push(child);
                child = self.next_sibling[child as usize];
            }
        }
    }

    fn reset(&mut self, problem: &Problem<'_>) {
        let grid = problem.grid();
        self.sampler.reset(grid);
        self.tree.reset(grid, problem.start());
        for buffer in [&mut self.cost, &mut self.edge] {
            buffer.clear();
            buffer.reserve(grid.n_free());
            buffer.push(0.0);
        }
        for buffer in [
            &mut self.first_child,
            &mut self.next_sibling,
            &mut self.prev_sibling,
        ] {
            buffer.clear();
            buffer.reserve(grid.n_free());
            buffer.push(NONE);
        }
    }
}

impl<I: NearestIndex> Planner for RrtStar<I> {
    fn name(&self) -> &str {
        NAME
    }

    /// Seeded; the tree's edges are free segments of up to `step` cells, checked by the
    /// any-angle rule.
    fn specs(&self) -> planner_api::PlannerSpecs {
        planner_api::PlannerSpecs::seeded(planner_api::PathSpec::AnyAngle)
    }

    fn reseed(&mut self, seed: u64) {
        self.config.seed = seed;
    }

    /// Refuses with [`Outcome::over_memory`] when the tree for every free cell, the
    /// sampler's list of them and the per-node costs and child links (28 bytes a free
    /// cell) are over [`Budget::max_memory_mb`].
    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        let grid = problem.grid();
        let per_node = 2 * std::mem::size_of::<f64>() + 3 * std::mem::size_of::<u32>();
        let n_free = grid.n_free() as u64;
        let bytes = self.tree.bytes_for(grid, n_free)
            + Sampler::bytes_for(n_free)
            + per_node as u64 * n_free;
        if let Err(shortfall) = budget.check_memory(bytes, grid) {
            self.stats = RrtStarStats::default();
            return Outcome::over_memory(shortfall, self.stats.counters());
        }
        let (start, goal) = (problem.start(), problem.goal());
        self.reset(problem);
        let config = self.config.clone();
        let gamma = config
            .gamma
            .unwrap_or_else(|| 1.1 * gamma_lower_bound(grid.n_free()));
        let reach_squared = config.steer.reach_squared(config.step);

        let mut stats = RrtStarStats::default();
        let mut checker = SegmentChecker::default();
        let mut series = Series::new("best_cost", "iteration");
        let mut goal_node = (start == goal).then_some(0);
        let mut best_cost = f64::INFINITY;
        if goal_node.is_some() {
            best_cost = 0.0;
            stats.first_solution_iteration = Some(0);
            stats.n_improvements = 1;
            series.points.push([0.0, 0.0]);
        }
        let mut clock = budget.start();
        let mut rng = sample::rng_for_seed(config.seed);
        let mut cut = false;
        loop {
            if let Some(found_at) = stats.first_solution_iteration {
                // Start = goal cannot improve: stop at once.
                if start == goal
                    || stats.n_iterations - found_at >= config.iterations_after_solution
                {
                    break;
                }
            }
            if stats.n_iterations >= config.max_iterations {
                break;
            }
            if !clock.allows(stats.n_iterations) {
                cut = true;
                break;
            }
            stats.n_iterations += 1;
            stats.n_samples += 1;
            // At least the start is free, so the sampler's population is not empty.
            let (target, is_goal) =
                self.sampler
                    .goal_biased(&mut rng, grid, goal, config.goal_bias);
            stats.n_goal_samples += u64::from(is_goal);
            let Some(nearest) = self.tree.nearest(target) else {
                break; // unreachable: the start is always in the tree
            };
            let from = self.tree.cell(nearest);
            let new_cell = steer(from, target, config.steer, config.step);
            if self.tree.node_at(new_cell).is_some() {
                stats.n_duplicates += 1;
                continue;
            }
            if !checker.is_free(grid, from, new_cell) {
                stats.n_collisions += 1;
                continue;
            }

            // The near set, by increasing id, before the new node joins.
            let radius_squared = near_radius_squared(gamma, self.tree.len(), reach_squared);
            self.near.clear();
            self.tree.within(new_cell, radius_squared, &mut self.near);
            self.near.sort_unstable();
            stats.n_near += self.near.len() as u64;
            self.near_checked.clear();
            self.near_checked.resize(self.near.len(), Checked::Unknown);

            // Choose parent.
            let mut parent = nearest;
            let mut parent_edge = from.euclidean(new_cell);
            let mut parent_cost = self.cost[nearest as usize] + parent_edge;
            for (k, &x) in self.near.iter().enumerate() {
                if x == nearest {
                    self.near_checked[k] = Checked::Free;
                    continue;
                }
                let x_cell = self.tree.cell(x);
                let edge = x_cell.euclidean(new_cell);
                let cost = self.cost[x as usize] + edge;
                if cost < parent_cost {
                    let free = checker.is_free(grid, x_cell, new_cell);
                    self.near_checked[k] = if free {
                        Checked::Free
                    } else {
                        Checked::Blocked
                    };
                    if free {
                        (parent, parent_edge, parent_cost) = (x, edge, cost);
                    }
                }
            }
            if parent != nearest {
                stats.n_parent_changes += 1;
            }
            let new = self.add_node(new_cell, parent, parent_edge);

            // Rewire.
            for k in 0..self.near.len() {
                let x = self.near[k];
                if x == parent {
                    continue;
                }
                let x_cell = self.tree.cell(x);
                let edge = new_cell.euclidean(x_cell);
                if self.cost[new as usize] + edge >= self.cost[x as usize] {
                    continue;
                }
                let free = match self.near_checked[k] {
                    Checked::Free => true,
                    Checked::Blocked => false,
                    Checked::Unknown => checker.is_free(grid, new_cell, x_cell),
                };
                if free {
                    self.rewire(x, new, edge, &mut stats);
                }
            }

            if new_cell == goal {
                goal_node = Some(new);
                stats.first_solution_iteration = Some(stats.n_iterations);
            }
            if let Some(goal_node) = goal_node {
                let cost = self.cost[goal_node as usize];
                if cost < best_cost {
                    best_cost = cost;
                    stats.n_improvements += 1;
                    series.points.push([stats.n_iterations as f64, cost]);
                }
            }
        }
        stats.tree_size = self.tree.len() as u64;
        stats.n_segment_checks = checker.n_checks;
        stats.n_segment_cells = checker.n_cells;
        self.stats = stats;
        let path = goal_node.map(|node| Path::new(self.tree.path_to(node)));
        let status = if path.is_some() && !cut {
            Status::Found
        } else {
            Status::BudgetExhausted
        };
        let mut outcome = Outcome::new(status, path, stats.counters());
        outcome.series.push(series);
        outcome
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radius_by_hand() {
        // n = 1: ln 1 = 0.
        assert_eq!(near_radius_squared(10.0, 1, 25), 0);
        // gamma^2 ln n / n = 100 * ln 100 / 100 = 4.605...: floor 4, below the cap 25.
        assert_eq!(near_radius_squared(10.0, 100, 25), 4);
        // 100 * ln 2 / 2 = 34.6: capped at 25.
        assert_eq!(near_radius_squared(10.0, 2, 25), 25);
        assert_eq!(Steer::Eight.reach_squared(3), 18);
        // The default gamma on a 10 x 10 free grid: 1.1 * sqrt(300 / pi) = 10.75.
        assert!((1.1 * gamma_lower_bound(100) - 10.749).abs() < 1e-3);
        // The crate docs' claims: map3's 760 free cells, eight-way steering with step 4
        // (cap 32): the radius shrinks below the cap from 135 nodes on; with step 1 the
        // cap binds from n = 3 (four) and n = 6 (eight) even when n = n_free.
        let gamma = 1.1 * gamma_lower_bound(760);
        assert_eq!(near_radius_squared(gamma, 134, 32), 32);
        assert!(near_radius_squared(gamma, 135, 32) < 32);
        for n_free in 3..2000 {
            let gamma = 1.1 * gamma_lower_bound(n_free);
            assert_eq!(near_radius_squared(gamma, n_free, 1), 1, "{n_free}");
            if n_free >= 6 {
                assert_eq!(near_radius_squared(gamma, n_free, 2), 2, "{n_free}");
                assert_eq!(near_radius_squared(gamma, 6, 2), 2, "{n_free}");
            }
            assert_eq!(near_radius_squared(gamma, 3, 1), 1, "{n_free}");
        }
    }

    #[test]
    fn config_validation_names_the_parameter() {
        let bad = |config: Config| {
            let err = RrtStar::new(config).unwrap_err();
            assert!(err.to_string().contains(err.parameter()), "{err}");
            err.to_string()
        };
        for gamma in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(bad(Config {
                gamma: Some(gamma),
                ..Config::default()
            })
            .starts_with("parameter `gamma` must be positive and finite"));
        }
        assert_eq!(
            bad(Config {
                goal_bias: 2.0,
                ..Config::default()
            }),
            "parameter `goal_bias` must be between 0 and 1, got 2"
        );
        assert_eq!(
            bad(Config {
                step: 0,
                ..Config::default()
            }),
            "parameter `step` must be at least 1, got 0"
        );
        assert!(RrtStar::new(Config {
            gamma: Some(0.5),
            ..Config::default()
        })
        .is_ok());
    }

    #[test]
    fn config_from_toml() {
        let config: Config =
            toml::from_str("seed = 4\ngamma = 12.5\niterations_after_solution = 0\nstep = 3")
                .unwrap();
        assert_eq!(
            config,
            Config {
                seed: 4,
                gamma: Some(12.5),
                iterations_after_solution: 0,
                step: 3,
                ..Config::default()
            }
        );
        assert!(toml::from_str::<Config>("gama = 3.0").is_err());
        assert_eq!(config.path_moves(), None);
    }
}
