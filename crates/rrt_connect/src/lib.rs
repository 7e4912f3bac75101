//! RRT-Connect on occupancy grids, seeded and reproducible bit for bit.
//!
//! The algorithm is Kuffner and LaValle's RRT-Connect ("RRT-Connect: An efficient approach
//! to single-query path planning", ICRA 2000, `RRT_CONNECT_PLANNER` with `EXTEND` and
//! `CONNECT`), built from planner-rrt's pieces: the same seeded generator and free-cell
//! sampler, steering, trees of distinct cells with their bucket-grid index, and exact
//! segment checks. Two trees grow, one from the start and one from the goal. Each
//! iteration:
//!
//! 1. Draws a free cell uniformly (no goal bias: the goal tree plays that part).
//! 2. `EXTEND(T_a, sample)`: from the nearest node of the active tree `T_a`, steer toward
//!    the sample ([`planner_rrt::steer`], `steer` and `step` as in RRT). A segment that
//!    crosses a blocked cell is *trapped*; a sample that already is a node of `T_a` is
//!    *reached* at once (a duplicate, nothing added); otherwise the new cell joins `T_a`
//!    (*reached* if it is the sample, else *advanced*).
//! 3. Unless trapped, `CONNECT(T_b, q)`: extend the other tree toward `q` (the node that
//!    `EXTEND` reached or added) again and again while it advances.
//! 4. The trees swap roles.
//!
//! The trees *meet* when an extension's new cell is a node of the other tree: that new
//! edge joins them, and the path is the first tree's path to the extended node followed by
//! the other tree's path from the met node back to its root, oriented start to goal. A
//! `CONNECT` toward a node of `T_a` always ends by meeting (its last step lands on that
//! node) unless it is trapped or the budget runs out first; an `EXTEND` toward a sample
//! may meet the other tree on its way, which also ends the search (a choice for grids,
//! where nodes are cells: the paper's continuous trees never share a configuration). So the two trees never hold
//! the same cell, and the joined path visits every cell at most once.
//!
//! The search stops when the trees meet ([`Status::Found`]), after `max_iterations`
//! iterations, or when the [`Budget`] runs out; one expansion is one extension attempt
//! (the one `EXTEND` of an iteration and each step of its `CONNECT`), so the budget bounds
//! the work even when a `CONNECT` runs long. RRT-Connect cannot prove that there is no path:
//! an unreachable goal ends in [`Status::BudgetExhausted`] without a path.
//!
//! # Steering and nearest nodes
//! Every unit move of [`planner_rrt::steer`] strictly shortens the distance to the target,
//! so a new cell is nearer to the target than every node of the tree being extended: it is
//! a node of that tree only when the target is (the duplicate case above).
//!
//! # Paths
//! Edges are free segments between cell centres, checked from the extended node to the new
//! cell; planner-api's traversal visits the same cells in both directions (tested in
//! planner-rrt), so the goal tree's edges, walked backwards in the path, are just as
//! free. Paths pass [`PathRule::AnyAngle`](planner_api::PathRule::AnyAngle); with `step = 1`
//! they are 4-connected (`"four"`) or 8-connected without corner cutting (`"eight"`),
//! [`Config::path_moves`].
//!
//! # Counters
//! `n_iterations` (= samples drawn), `n_extensions` (extension attempts, also
//! `n_expanded`), `n_collisions` (trapped extensions), `n_duplicates` (samples already in
//! the active tree), `start_tree_size`, `goal_tree_size` (roots included),
//! `n_connect_steps` (`CONNECT` extensions that advanced or met; trapped ones count only
//! as collisions), `n_segment_checks`,
//! `n_segment_cells`. Identity: `n_extensions = n_collisions + n_duplicates +
//! (start_tree_size - 1) + (goal_tree_size - 1) + [met]`, where `[met]` is 1 when found
//! with start != goal. Start = goal is found at once, with one root in each tree. Every
//! status, path and counter equals that of `planner_testkit::reference_rrt_connect`, the
//! run written again from this page (flat trees, a linear scan for the nearest node), on
//! 600 random runs (`tests/rrt_connect.rs`) and on every run of the configs (xtask's
//! `every_rrt_connect_run_matches_the_reference_run`).
//!
//! ```
//! use planner_api::{Budget, Cell, Grid, Planner, Problem, Status};
//! use planner_rrt_connect::{Config, RrtConnect};
//!
//! let grid = Grid::from_ascii("
//!     ......
//!     .####.
//!     ......
//! ").unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 1), Cell::new(5, 1)).unwrap();
//! let outcome = RrtConnect::new(Config::default()).unwrap().plan(&problem, &Budget::unlimited());
//! assert_eq!(outcome.status, Status::Found);
//! let path = outcome.path.unwrap();
//! assert_eq!((path.start(), path.goal()), (Some(Cell::new(0, 1)), Some(Cell::new(5, 1))));
//! // Around the wall, above or below: 7 unit moves.
//! assert_eq!(path.metrics().steps, 7);
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

use planner_api::{
    Budget, BudgetClock, Cell, Connectivity, Counters, Outcome, Path, Planner, Problem, Status,
};
use planner_rrt::{
    check_sampling, sample, steer, BucketGrid, NearestIndex, NodeId, Sampler, SegmentChecker,
    Steer, Tree,
};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The registry name.
pub const NAME: &str = "rrt_connect";

/// RRT-Connect's parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// Seed of the random generator (as RRT's); the same seed gives the same trees, path
    /// and counters everywhere. Default 0.
    pub seed: u64,
    /// Iterations (samples) before giving up with [`Status::BudgetExhausted`].
    /// Default 100,000.
    pub max_iterations: u64,
    /// Unit moves used to steer (`"four"` or `"eight"`). Default `"four"`.
    pub steer: Steer,
    /// Unit moves per extension, at least 1; above 1 the trees' edges are any-angle
    /// segments. Default 1.
    #[schemars(range(min = 1))]
    pub step: u32,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            seed: 0,
            max_iterations: 100_000,
            steer: Steer::Four,
            step: 1,
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
    /// `step` is 0 (checked as RRT checks it).
    #[error(transparent)]
    Sampling(#[from] planner_rrt::ConfigError),
}

impl planner_api::ParamKey for ConfigError {
    fn param_key(&self) -> &str {
        self.parameter()
    }
}

impl ConfigError {
    /// The name of the offending parameter: `step`.
    pub fn parameter(&self) -> &'static str {
        match self {
            ConfigError::Sampling(e) => e.parameter(),
        }
    }
}

/// RRT-Connect's counters as plain integers; see the crate docs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize)]
pub struct RrtConnectStats {
    /// Iterations run, one sample each.
    pub n_iterations: u64,
    /// Extension attempts (`EXTEND` and every `CONNECT` step); what the budget counts.
    pub n_extensions: u64,
    /// Extensions trapped by a blocked cell on their segment.
    pub n_collisions: u64,
    /// Samples that already were nodes of the active tree.
    pub n_duplicates: u64,
    /// Nodes of the tree rooted at the start.
    pub start_tree_size: u64,
    /// Nodes of the tree rooted at the goal.
    pub goal_tree_size: u64,
    /// `CONNECT` extensions that advanced or met the other tree.
    pub n_connect_steps: u64,
    /// Segments checked for collision.
    pub n_segment_checks: u64,
    /// Cells visited by those checks.
    pub n_segment_cells: u64,
}

impl RrtConnectStats {
    /// The counters in reporting order (crate docs), then `n_expanded` (= `n_extensions`).
    pub fn counters(&self) -> Counters {
        Counters::new()
            .with("n_iterations", self.n_iterations)
            .with("n_extensions", self.n_extensions)
            .with("n_collisions", self.n_collisions)
            .with("n_duplicates", self.n_duplicates)
            .with("start_tree_size", self.start_tree_size)
            .with("goal_tree_size", self.goal_tree_size)
            .with("n_connect_steps", self.n_connect_steps)
            .with("n_segment_checks", self.n_segment_checks)
            .with("n_segment_cells", self.n_segment_cells)
            .with("n_expanded", self.n_extensions)
    }
}

/// How one extension ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Extension {
    /// The segment toward the target crosses a blocked cell.
    Trapped,
    /// A new node short of the target.
    Advanced(NodeId),
    /// The target is a node now (added, or already there).
    Reached(NodeId),
    /// The new cell is a node of the other tree: the trees meet along the edge from
    /// `from` (this tree) to `to` (the other tree).
    Met { from: NodeId, to: NodeId },
}

/// The RRT-Connect planner, generic over its nearest-neighbour index (a [`BucketGrid`]
/// unless built with [`RrtConnect::with_index`]).
///
/// Keeps its buffers between calls: after the first search on a grid size nothing is
/// allocated but the path.
#[derive(Debug, Clone)]
pub struct RrtConnect<I: NearestIndex + Clone = BucketGrid> {
    config: Config,
    sampler: Sampler,
    /// The tree rooted at the start, then the one rooted at the goal.
    trees: [Tree<I>; 2],
    stats: RrtConnectStats,
}

impl RrtConnect {
    /// An RRT-Connect with [`BucketGrid`] indexes. Errors, naming the parameter, when
    /// `step` is 0.
    pub fn new(config: Config) -> Result<RrtConnect, ConfigError> {
        RrtConnect::with_index(config, BucketGrid::default())
    }
}

/// The state one search threads through its extensions.
struct Search<'a> {
    grid: &'a planner_api::Grid,
    steer: Steer,
    step: u32,
    clock: BudgetClock,
    checker: SegmentChecker,
    stats: RrtConnectStats,
}

impl Search<'_> {
    /// Whether the budget allows one more extension.
    fn allows(&mut self) -> bool {
        self.clock.allows(self.stats.n_extensions)
    }

    /// `EXTEND(trees[active], target)`, meeting `trees[1 - active]` if the new cell is one
    /// of its nodes. The caller has asked the budget ([`Search::allows`]).
    fn extend<I: NearestIndex>(
        &mut self,
        trees: &mut [Tree<I>; 2],
        active: usize,
        target: Cell,
    ) -> Extension {
        self.stats.n_extensions += 1;
        let [first, second] = trees;
        let (tree, other) = if active == 0 {
            (first, &*second)
        } else {
            (second, &*first)
        };
        let Some(near) = tree.nearest(target) else {
            return Extension::Trapped; // unreachable: a tree always holds its root
        };
        let from = tree.cell(near);
        let new = steer(from, target, self.steer, self.step);
        if new == from {
            // The target is a node of this tree already.
            self.stats.n_duplicates += 1;
            return Extension::Reached(near);
        }
        if !self.checker.is_free(self.grid, from, new) {
            self.stats.n_collisions += 1;
            return Extension::Trapped;
        }
        if let Some(to) = other.node_at(new) {
            return Extension::Met { from: near, to };
        }
        let node = tree.add(new, near);
        if new == target {
            Extension::Reached(node)
        } else {
            Extension::Advanced(node)
        }
    }
}

impl<I: NearestIndex + Clone> RrtConnect<I> {
    /// An RRT-Connect whose two trees find nearest nodes with copies of `index`;
    /// validates `config` as [`RrtConnect::new`].
    pub fn with_index(config: Config, index: I) -> Result<RrtConnect<I>, ConfigError> {
        check_sampling(0.0, config.step)?;
        Ok(RrtConnect {
            config,
            sampler: Sampler::default(),
            trees: [Tree::with_index(index.clone()), Tree::with_index(index)],
            stats: RrtConnectStats::default(),
        })
    }

    /// The validated config.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The counters of the last search (all zero before the first).
    pub fn stats(&self) -> RrtConnectStats {
        self.stats
    }

    /// The last search's trees, rooted at the start and at the goal: each node's cell and
    /// its parent's cell (`None` for the root), in the order the nodes were added.
    pub fn trees(&self) -> [impl Iterator<Item = (Cell, Option<Cell>)> + '_; 2] {
        [self.trees[0].edges(), self.trees[1].edges()]
    }

    /// The path when the trees met along the edge from node `from` of `trees[active]` to
    /// node `to` of the other tree: oriented from the start (tree 0) to the goal (tree 1).
    fn joined_path(&self, active: usize, from: NodeId, to: NodeId) -> Path {
        let mut cells = self.trees[active].path_to(from);
        let mut rest = self.trees[1 - active].path_to(to);
        rest.reverse();
        cells.extend(rest);
        if active == 1 {
            cells.reverse();
        }
        Path::new(cells)
    }

    fn run(&mut self, search: &mut Search<'_>, rng: &mut ChaCha8Rng) -> Option<Path> {
        let grid = search.grid;
        let mut active = 0;
        while search.stats.n_iterations < self.config.max_iterations {
            if !search.allows() {
                return None;
            }
            search.stats.n_iterations += 1;
            // At least the start is free, so the sampler's population is not empty.
            let sample = self.sampler.uniform(rng, grid);
            let reached = match search.extend(&mut self.trees, active, sample) {
                Extension::Trapped => None,
                Extension::Advanced(node) | Extension::Reached(node) => Some(node),
                Extension::Met { from, to } => return Some(self.joined_path(active, from, to)),
            };
            if let Some(node) = reached {
                let target = self.trees[active].cell(node);
                let other = 1 - active;
                loop {
                    if !search.allows() {
                        return None;
                    }
                    match search.extend(&mut self.trees, other, target) {
                        Extension::Advanced(_) => search.stats.n_connect_steps += 1,
                        Extension::Met { from, to } => {
                            search.stats.n_connect_steps += 1;
                            return Some(self.joined_path(other, from, to));
                        }
                        // Reached cannot happen (the target is a node of the other tree,
                        // so the last step meets it); Trapped ends the connect.
                        Extension::Reached(_) | Extension::Trapped => break,
                    }
                }
            }
            active = 1 - active;
        }
        None
    }
}

impl<I: NearestIndex + Clone> Planner for RrtConnect<I> {
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

    /// Refuses with [`Outcome::over_memory`] when two trees for every free cell and the
    /// sampler's list of them are over [`Budget::max_memory_mb`].
    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        let grid = problem.grid();
        let n_free = grid.n_free() as u64;
        let bytes = self.trees[0].bytes_for(grid, n_free)
            + self.trees[1].bytes_for(grid, n_free)
            + Sampler::bytes_for(n_free);
        if let Err(shortfall) = budget.check_memory(bytes, grid) {
            self.stats = RrtConnectStats::default();
            return Outcome::over_memory(shortfall, self.stats.counters());
        }
        let (start, goal) = (problem.start(), problem.goal());
        self.sampler.reset(grid);
        self.trees[0].reset(grid, start);
        self.trees[1].reset(grid, goal);
        let mut search = Search {
            grid,
            steer: self.config.steer,
            step: self.config.step,
            clock: budget.start(),
            checker: SegmentChecker::default(),
            stats: RrtConnectStats::default(),
        };
        let path = if start == goal {
            Some(Path::new(vec![start]))
        } else {
            let mut rng = sample::rng_for_seed(self.config.seed);
            self.run(&mut search, &mut rng)
        };
        let mut stats = search.stats;
        stats.start_tree_size = self.trees[0].len() as u64;
        stats.goal_tree_size = self.trees[1].len() as u64;
        stats.n_segment_checks = search.checker.n_checks;
        stats.n_segment_cells = search.checker.n_cells;
        self.stats = stats;
        let status = if path.is_some() {
            Status::Found
        } else {
            Status::BudgetExhausted
        };
        Outcome::new(status, path, stats.counters())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn config_validation_names_the_parameter() {
        let err = RrtConnect::new(Config {
            step: 0,
            ..Config::default()
        })
        .unwrap_err();
        assert_eq!(err.parameter(), "step");
        assert_eq!(
            err.to_string(),
            "parameter `step` must be at least 1, got 0"
        );
    }

    #[test]
    fn config_from_toml() {
        let config: Config = toml::from_str("seed = 2\nsteer = \"eight\"").unwrap();
        assert_eq!(
            config,
            Config {
                seed: 2,
                steer: Steer::Eight,
                ..Config::default()
            }
        );
        assert!(toml::from_str::<Config>("goal_bias = 0.1").is_err());
        assert_eq!(config.path_moves(), Some(Connectivity::Eight));
    }
}
