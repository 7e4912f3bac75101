//! RRT (rapidly-exploring random tree) on occupancy grids, seeded and reproducible.
//!
//! The algorithm is seed 003's section II.D (`shared/seeds/003_9eb9a51f185ccb81.txt`;
//! LaValle's RRT on the grid's cells), evaluated in its Tables I-II:
//!
//! 1. The tree starts as the start cell; it is kept as parent links over grid cells.
//! 2. Each iteration draws a sample: the goal with probability `goal_bias`, else a free
//!    cell uniformly at random (the goal included).
//! 3. The nearest tree node to the sample by Euclidean distance between cell centres
//!    (exact integer squared distances; ties go to the node added first).
//! 4. Steer from it toward the sample ([`steer`]): by default one 4-connected step, along
//!    the axis of the larger of `|dx|`, `|dy|` (ties: along x).
//! 5. If the new cell is already in the tree, nothing happens (`n_duplicates`); else if
//!    the segment between the two cell centres crosses a blocked cell
//!    ([`SegmentChecker`], planner-api's exact traversal) the step is rejected
//!    (`n_collisions`); else the new cell joins the tree with the nearest node as parent.
//! 6. When the new cell is the goal, the path is read back along the parent links.
//!    Otherwise the search stops after `max_iterations` iterations, or when the
//!    [`Budget`] runs out (one iteration is one expansion), with
//!    [`Status::BudgetExhausted`] and no path.
//!
//! RRT cannot prove that there is no path, so it never reports [`Status::NoPath`]: an
//! unreachable goal ends in [`Status::BudgetExhausted`].
//!
//! # Design
//! The main decision is the nearest-neighbour index. Seed 003's RRT scans the whole tree
//! for every sample and took over 10 s (and failed) on map3, its larger map. Here the
//! nodes are filed in a [`BucketGrid`]: blocks of 4 x 4 cells searched in growing rings
//! around the sample with exact Euclidean pruning. The index returns exactly what a
//! linear scan returns (tested, also as whole runs), so it changes speed, never results;
//! any other [`NearestIndex`] can be plugged in with [`Rrt::with_index`].
//!
//! A k-d tree crate (`kiddo` 6.3) was considered and not taken: tree nodes are integer
//! cells, so equal distances are common and the result must not depend on how a
//! library orders ties; it needs Rust 1.89, above the workspace's 1.85; and the bucket
//! grid is a hundred lines over flat arrays that are reused between searches. Measured
//! with `cargo bench -p planner-rrt` on map3 pair 1 (100 seeds), a search takes a median
//! of about 0.45 ms, 3-4x less than with a linear scan; on Moving AI's den520d
//! (256 x 257) 4-7x less. Block side 4 is a compromise: side 1 is faster on map3 (the
//! one-step tree fills the cells it reaches) but several times slower on den520d, where
//! side 8 is a little faster.
//!
//! Reproducibility: the generator is `rand_chacha::ChaCha8Rng` keyed by the config's
//! `seed` (key = the seed's 8 little-endian bytes, then zeros). Only its raw `u64`
//! output is used: the goal coin compares the top 53 bits as a fraction in `[0, 1)`
//! with `goal_bias`, and the free cell is chosen by Lemire's multiply-shift with
//! rejection (exactly uniform). Each iteration draws the coin, then (without goal) the
//! cell. Nothing depends on `rand`'s distributions, on the machine or on threads.
//!
//! # Shared pieces
//! RRT* (`planner-rrt_star`) and RRT-Connect (`planner-rrt_connect`) are built from this
//! crate's parts rather than copies of them: the seeded generator and the free-cell
//! [`Sampler`] ([`sample`]), [`steer`], the [`Tree`] of distinct cells with its
//! [`NearestIndex`] ([`BucketGrid`], which also answers RRT*'s radius queries), the
//! [`SegmentChecker`] and [`check_sampling`] for the parameters they share.
//!
//! # Steering
//! [`Steer::Four`] and [`Steer::Eight`] choose the unit moves; `step` is how many unit
//! moves one extension makes. Each unit move is the move of the neighbourhood that ends
//! nearest (Euclidean) to the sample: for four, along the axis of the larger `|d|`
//! component (ties along x, as right/left come first in seed 000's order); for eight,
//! diagonal whenever both components are non-zero. The walk stops at the sample. With
//! `step = 1` the tree's edges are unit moves, so paths are valid 4- or 8-connected
//! paths (a diagonal edge must not cut a corner, the segment rule of `planner-api`);
//! with `step > 1` they are any-angle segments ([`PathRule::AnyAngle`](planner_api::PathRule::AnyAngle)). Every unit move
//! strictly shortens the distance to the sample, so the new cell is nearer to the sample
//! than every tree node, and a duplicate happens exactly when the sample already is a
//! tree node.
//!
//! # Counters
//! Reported in this order: `n_iterations`, `n_samples`, `n_goal_samples`,
//! `n_collisions`, `tree_size`, then `n_duplicates` and `n_expanded` (= `n_iterations`,
//! what the budget counts). Identities (tested): `n_samples = n_iterations`,
//! `n_goal_samples <= n_samples`, and
//! `n_collisions + n_duplicates + (tree_size - 1) = n_iterations`. Every status, path and
//! counter equals that of `planner_testkit::reference_rrt`, the run written again from
//! this page (the draws, a linear scan for the nearest node, planner-api's segment test),
//! on 600 random runs (`tests/rrt.rs`) and on every run of the configs (xtask's
//! `every_rrt_run_matches_the_reference_run`).
//!
//! ```
//! use planner_api::{Budget, Cell, Grid, Planner, Problem, Status};
//! use planner_rrt::{Config, Rrt};
//!
//! let grid = Grid::from_ascii("
//!     ...
//!     ...
//!     ...
//! ").unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(2, 2)).unwrap();
//! // goal_bias = 1 samples only the goal, so the run can be followed by hand:
//! // d = (2, 2) is a tie, so x first; then (1, 2): y; then (1, 1): x; then y.
//! let mut rrt = Rrt::new(Config { goal_bias: 1.0, ..Config::default() }).unwrap();
//! let outcome = rrt.plan(&problem, &Budget::unlimited());
//! assert_eq!(outcome.status, Status::Found);
//! let path: Vec<(u32, u32)> = outcome.path.unwrap().cells().iter().map(|c| (c.x, c.y)).collect();
//! assert_eq!(path, [(0, 0), (1, 0), (1, 1), (2, 1), (2, 2)]);
//! assert_eq!(outcome.counters.get("n_iterations"), Some(4));
//! assert_eq!(outcome.counters.get("tree_size"), Some(5));
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

mod collision;
mod index;
pub mod sample;
mod tree;

pub use collision::SegmentChecker;
pub use index::{squared_distance, BucketGrid, NearestIndex};
pub use sample::Sampler;
pub use tree::{NodeId, Tree};

use planner_api::{Budget, Cell, Connectivity, Counters, Outcome, Path, Planner, Problem, Status};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The registry name of this planner.
pub const NAME: &str = "rrt";

/// The unit moves that steering takes toward a sample.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Steer {
    /// Right, left, down, up: seed 003's "one step in a 4-connected manner". Config value `"four"`.
    #[default]
    Four,
    /// The four axis moves and the four diagonals. Config value `"eight"`.
    Eight,
}

impl Steer {
    /// The neighbourhood whose moves join the cells of a tree whose edges are extensions
    /// of `step` unit moves: 4 or 8-connected when `step = 1`, `None` (any-angle edges)
    /// when `step > 1`. Edges are checked by [`SegmentChecker`], so a diagonal unit edge
    /// never cuts a blocked corner.
    pub fn path_moves(self, step: u32) -> Option<Connectivity> {
        match (step, self) {
            (1, Steer::Four) => Some(Connectivity::Four),
            (1, Steer::Eight) => Some(Connectivity::Eight),
            _ => None,
        }
    }

    /// The squared Euclidean length of the longest extension `step` unit moves can make:
    /// `step^2` for [`Steer::Four`] (the walk stays within `step` of its start) and
    /// `2 step^2` for [`Steer::Eight`] (`step` diagonals). RRT*'s radius cap.
    pub fn reach_squared(self, step: u32) -> u64 {
        let step = u64::from(step);
        match self {
            Steer::Four => step * step,
            Steer::Eight => 2 * step * step,
        }
    }
}

/// RRT's parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// Seed of the random generator; the same seed gives the same tree, path and counters
    /// everywhere. Default 0.
    pub seed: u64,
    /// Probability of sampling the goal instead of a uniform free cell, in `0..=1`.
    /// Default 0.05.
    #[schemars(range(min = 0, max = 1))]
    pub goal_bias: f64,
    /// Iterations before giving up with [`Status::BudgetExhausted`] (0 gives up at once,
    /// unless start = goal). Default 100,000.
    pub max_iterations: u64,
    /// Unit moves used to steer (`"four"` or `"eight"`). Default `"four"`.
    pub steer: Steer,
    /// Unit moves per extension, at least 1; above 1 the tree's edges are any-angle
    /// segments. Default 1.
    #[schemars(range(min = 1))]
    pub step: u32,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            seed: 0,
            goal_bias: 0.05,
            max_iterations: 100_000,
            steer: Steer::Four,
            step: 1,
        }
    }
}

impl Config {
    /// The neighbourhood whose moves join consecutive path cells, for
    /// [`PathRule::Moves`](planner_api::PathRule::Moves): 4 or 8-connected when `step = 1`; `None` when `step > 1`,
    /// where paths satisfy [`PathRule::AnyAngle`](planner_api::PathRule::AnyAngle) (every RRT path does).
    pub fn path_moves(&self) -> Option<Connectivity> {
        self.steer.path_moves(self.step)
    }
}

/// A parameter outside its allowed range.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConfigError {
    /// `goal_bias` is below 0, above 1 or NaN.
    #[error("parameter `goal_bias` must be between 0 and 1, got {0}")]
    GoalBias(f64),
    /// `step` is 0.
    #[error("parameter `step` must be at least 1, got {0}")]
    Step(u32),
}

impl planner_api::ParamKey for ConfigError {
    fn param_key(&self) -> &str {
        self.parameter()
    }
}

impl ConfigError {
    /// The name of the offending parameter, as in the config: `goal_bias` or `step`.
    pub fn parameter(&self) -> &'static str {
        match self {
            ConfigError::GoalBias(_) => "goal_bias",
            ConfigError::Step(_) => "step",
        }
    }
}

/// RRT's counters as plain integers; see the crate docs for their identities.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize)]
pub struct RrtStats {
    /// Iterations run (each draws one sample); also what the budget counts as expansions.
    pub n_iterations: u64,
    /// Samples drawn, goal samples included.
    pub n_samples: u64,
    /// Samples that were the goal by the `goal_bias` coin (a uniform draw that happens
    /// to land on the goal is not counted here).
    pub n_goal_samples: u64,
    /// Extensions rejected because their segment crosses a blocked cell.
    pub n_collisions: u64,
    /// Extensions that led to a cell already in the tree (the sample was a tree node).
    pub n_duplicates: u64,
    /// Tree nodes, the start included.
    pub tree_size: u64,
}

impl RrtStats {
    /// The counters in reporting order: `n_iterations`, `n_samples`, `n_goal_samples`,
    /// `n_collisions`, `tree_size`, `n_duplicates`, `n_expanded`.
    pub fn counters(&self) -> Counters {
        Counters::new()
            .with("n_iterations", self.n_iterations)
            .with("n_samples", self.n_samples)
            .with("n_goal_samples", self.n_goal_samples)
            .with("n_collisions", self.n_collisions)
            .with("tree_size", self.tree_size)
            .with("n_duplicates", self.n_duplicates)
            .with("n_expanded", self.n_iterations)
    }
}

/// The cell reached from `from` by up to `step` unit moves of `steer` toward `toward`,
/// stopping at `toward`.
///
/// Each unit move is the one that ends nearest to `toward`: with [`Steer::Four`] along
/// the axis of the larger of `|dx|`, `|dy|`, along x on a tie; with [`Steer::Eight`]
/// diagonal when both are non-zero. The result lies in the bounding box of the two cells,
/// so it is inside any grid that holds both. Does not look at obstacles.
pub fn steer(from: Cell, toward: Cell, steer: Steer, step: u32) -> Cell {
    let (mut x, mut y) = (from.x, from.y);
    let toward_x = |x: u32| if toward.x > x { x + 1 } else { x - 1 };
    let toward_y = |y: u32| if toward.y > y { y + 1 } else { y - 1 };
    for _ in 0..step {
        let (ax, ay) = (x.abs_diff(toward.x), y.abs_diff(toward.y));
        if ax == 0 && ay == 0 {
            break;
        }
        match steer {
            Steer::Four if ax >= ay => x = toward_x(x),
            Steer::Four => y = toward_y(y),
            Steer::Eight => {
                if ax > 0 {
                    x = toward_x(x);
                }
                if ay > 0 {
                    y = toward_y(y);
                }
            }
        }
    }
    Cell::new(x, y)
}

/// The RRT planner, generic over its nearest-neighbour index (a [`BucketGrid`] unless
/// built with [`Rrt::with_index`]).
///
/// Keeps its buffers (sampler, tree, index) between calls: after the first search on a
/// grid size nothing is allocated but the path.
#[derive(Debug, Clone)]
pub struct Rrt<I: NearestIndex = BucketGrid> {
    config: Config,
    sampler: Sampler,
    tree: Tree<I>,
    stats: RrtStats,
}

impl Rrt {
    /// An RRT with a [`BucketGrid`] index. Errors, naming the parameter, when `goal_bias`
    /// is outside `0..=1` or `step` is 0.
    pub fn new(config: Config) -> Result<Rrt, ConfigError> {
        Rrt::with_index(config, BucketGrid::default())
    }
}

/// Checks the parameters RRT, RRT* and RRT-Connect share: `goal_bias` in `0..=1` (not
/// NaN) and `step` at least 1.
pub fn check_sampling(goal_bias: f64, step: u32) -> Result<(), ConfigError> {
    if !(0.0..=1.0).contains(&goal_bias) {
        return Err(ConfigError::GoalBias(goal_bias));
    }
    if step == 0 {
        return Err(ConfigError::Step(step));
    }
    Ok(())
}

impl<I: NearestIndex> Rrt<I> {
    /// An RRT that finds nearest nodes with `index`; validates `config` as [`Rrt::new`].
    pub fn with_index(config: Config, index: I) -> Result<Rrt<I>, ConfigError> {
        check_sampling(config.goal_bias, config.step)?;
        Ok(Rrt {
            config,
            sampler: Sampler::default(),
            tree: Tree::with_index(index),
            stats: RrtStats::default(),
        })
    }

    /// The validated config.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The counters of the last search (all zero before the first).
    pub fn stats(&self) -> RrtStats {
        self.stats
    }

    /// The last search's tree: each node's cell and its parent's cell (`None` for the
    /// start), in the order the nodes were added.
    pub fn tree(&self) -> impl Iterator<Item = (Cell, Option<Cell>)> + '_ {
        self.tree.edges()
    }
}

impl<I: NearestIndex> Planner for Rrt<I> {
    fn name(&self) -> &str {
        NAME
    }

    /// Seeded; paths are the tree's vertices, joined by free segments of up to `step`
    /// cells, so they are checked by the any-angle rule.
    fn specs(&self) -> planner_api::PlannerSpecs {
        planner_api::PlannerSpecs::seeded(planner_api::PathSpec::AnyAngle)
    }

    fn reseed(&mut self, seed: u64) {
        self.config.seed = seed;
    }

    /// Refuses with [`Outcome::over_memory`] when the tree for every free cell and the
    /// sampler's list of them ([`Tree::bytes_for`], [`Sampler::bytes_for`]) are over
    /// [`Budget::max_memory_mb`].
    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        let grid = problem.grid();
        let n_free = grid.n_free() as u64;
        let bytes = self.tree.bytes_for(grid, n_free) + Sampler::bytes_for(n_free);
        if let Err(shortfall) = budget.check_memory(bytes, grid) {
            self.stats = RrtStats::default();
            return Outcome::over_memory(shortfall, self.stats.counters());
        }
        let (start, goal) = (problem.start(), problem.goal());
        let config = &self.config;
        let (goal_bias, steering, step) = (config.goal_bias, config.steer, config.step);
        let max_iterations = config.max_iterations;

        self.sampler.reset(grid);
        self.tree.reset(grid, start);
        let mut checker = SegmentChecker::default();
        let mut stats = RrtStats::default();
        let mut clock = budget.start();
        let mut rng = sample::rng_for_seed(self.config.seed);
        let mut found = start == goal;
        while !found && stats.n_iterations < max_iterations && clock.allows(stats.n_iterations) {
            stats.n_iterations += 1;
            stats.n_samples += 1;
            // At least the start is free, so the sampler's population is not empty.
            let (target, is_goal) = self.sampler.goal_biased(&mut rng, grid, goal, goal_bias);
            stats.n_goal_samples += u64::from(is_goal);
            let Some(near) = self.tree.nearest(target) else {
                break; // unreachable: the start is always in the tree
            };
            let from = self.tree.cell(near);
            let new = steer(from, target, steering, step);
            if self.tree.node_at(new).is_some() {
                stats.n_duplicates += 1;
            } else if !checker.is_free(grid, from, new) {
                stats.n_collisions += 1;
            } else {
                self.tree.add(new, near);
                found = new == goal;
            }
        }
        stats.tree_size = self.tree.len() as u64;
        self.stats = stats;
        let last = self.tree.len() as u32 - 1;
        Outcome::new(
            if found {
                Status::Found
            } else {
                Status::BudgetExhausted
            },
            found.then(|| Path::new(self.tree.path_to(last))),
            stats.counters(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(from: (u32, u32), toward: (u32, u32), how: Steer, step: u32, expect: (u32, u32)) {
        let got = steer(from.into(), toward.into(), how, step);
        assert_eq!(
            (got.x, got.y),
            expect,
            "{from:?} -> {toward:?}, {how:?}, step {step}"
        );
    }

    #[test]
    fn steering_by_hand() {
        use Steer::{Eight, Four};
        // Larger component first; ties along x.
        check((5, 5), (9, 7), Four, 1, (6, 5));
        check((5, 5), (6, 9), Four, 1, (5, 6));
        check((5, 5), (2, 2), Four, 1, (4, 5));
        check((5, 5), (5, 0), Four, 1, (5, 4));
        // Reaching the sample stops the walk.
        check((5, 5), (5, 5), Four, 3, (5, 5));
        check((5, 5), (6, 6), Four, 9, (6, 6));
        // (4, 2): x, x (now a tie 2, 2), x: (3, 0) from the origin.
        check((0, 0), (4, 2), Four, 3, (3, 0));
        check((0, 0), (4, 2), Four, 4, (3, 1));
        // Eight: diagonal while both components are non-zero, then straight.
        check((5, 5), (9, 6), Eight, 1, (6, 6));
        check((5, 5), (5, 9), Eight, 1, (5, 6));
        check((0, 0), (4, 1), Eight, 2, (2, 1));
        check((9, 9), (0, 7), Eight, 3, (6, 7));
    }

    /// An extension never goes farther than [`Steer::reach_squared`] says (RRT*'s cap).
    #[test]
    fn steering_stays_within_its_reach() {
        for how in [Steer::Four, Steer::Eight] {
            for step in 1..6 {
                for (fx, fy, tx, ty) in [(0, 0, 9, 3), (5, 5, 0, 0), (3, 8, 4, 0), (7, 7, 7, 7)] {
                    let from = Cell::new(fx, fy);
                    let new = steer(from, Cell::new(tx, ty), how, step);
                    assert!(squared_distance(from, new) <= how.reach_squared(step));
                }
            }
        }
        // The longest extensions reach it exactly: straight for four, diagonal for eight.
        let origin = Cell::new(0, 0);
        let straight = steer(origin, Cell::new(20, 0), Steer::Four, 3);
        assert_eq!(
            squared_distance(origin, straight),
            Steer::Four.reach_squared(3)
        );
        let diagonal = steer(origin, Cell::new(20, 20), Steer::Eight, 3);
        assert_eq!(
            squared_distance(origin, diagonal),
            Steer::Eight.reach_squared(3)
        );
    }

    #[test]
    fn config_validation_names_the_parameter() {
        let bad = |config: Config| {
            let err = Rrt::new(config).unwrap_err();
            assert!(err.to_string().contains(err.parameter()));
            err.to_string()
        };
        assert_eq!(
            bad(Config {
                goal_bias: 1.5,
                ..Config::default()
            }),
            "parameter `goal_bias` must be between 0 and 1, got 1.5"
        );
        assert!(bad(Config {
            goal_bias: f64::NAN,
            ..Config::default()
        })
        .contains("goal_bias"));
        assert!(bad(Config {
            goal_bias: -0.1,
            ..Config::default()
        })
        .contains("goal_bias"));
        assert_eq!(
            bad(Config {
                step: 0,
                ..Config::default()
            }),
            "parameter `step` must be at least 1, got 0"
        );
        for goal_bias in [0.0, 1.0] {
            assert!(Rrt::new(Config {
                goal_bias,
                ..Config::default()
            })
            .is_ok());
        }
    }

    #[test]
    fn config_from_toml() {
        let config: Config = toml::from_str("seed = 7\nsteer = \"eight\"\nstep = 3").unwrap();
        assert_eq!(
            config,
            Config {
                seed: 7,
                steer: Steer::Eight,
                step: 3,
                ..Config::default()
            }
        );
        assert!(toml::from_str::<Config>("steer = \"six\"").is_err());
        assert!(toml::from_str::<Config>("sead = 7").is_err());
        assert_eq!(config.path_moves(), None);
        assert_eq!(Config::default().path_moves(), Some(Connectivity::Four));
    }
}
