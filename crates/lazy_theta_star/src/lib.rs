//! Lazy Theta\* (Nash, Koenig and Tovey, "Lazy Theta\*: Any-Angle Path Planning and Path
//! Length Analysis in 3D", AAAI 2010, pp. 147-154, <https://doi.org/10.1609/aaai.v24i1.7566>).
//!
//! Theta\* checks line of sight once per relaxed neighbour; Lazy Theta\* assumes it and
//! checks once per expanded node. A neighbour `s'` of the expanded node `s` is offered
//! `g(parent(s)) + |parent(s) s'|` with parent `parent(s)`, unchecked ("path 2"
//! always). When `s'` is later taken from OPEN, line of sight from its parent is checked,
//! and if it is blocked, the parent becomes the CLOSED grid neighbour `n` of `s'` with the
//! least `g(n) + c(n, s')` ("SetVertex"; such a neighbour exists, as the node that put `s'`
//! into OPEN is one). Every expanded node but the start is checked, as the paper's
//! SetVertex does, even when its parent is a grid neighbour. The goal is checked too,
//! before the search stops on it, so every
//! segment of the path has line of sight and the path passes
//! [`planner_api::PathRule::AnyAngle`].
//!
//! Everything else (the grid, the line-of-sight traversal, costs, [`EPSILON`], OPEN's
//! order, the counters) is planner-theta_star's, whose search this crate runs with
//! [`Variant::Lazy`]; see that crate's docs. Counters: Theta\*'s plus `n_parent_repairs`,
//! the expanded nodes whose parent was replaced.
//!
//! # Which to use
//! On the Moving AI benchmark maps Lazy Theta\* is the faster of the two: `cargo bench -p
//! planner-theta_star --bench movingai -- --repeats=3 --clock=cpu den520d random512-10-0`
//! (2026-12-04, quiet machine) took 573.3 ms against Theta\*'s 635.6 on den520d's 888
//! scenarios and 2,689.0 against 2,953.7 on random512-10-0's 1,670, with paths on average
//! 0.03 % and 0.06 % longer than Theta\*'s (at most 0.78 % and 1.03 %) and never longer than
//! the 8-connected optimum there. Prefer it for speed; prefer Theta\* when a path no
//! longer than the 8-connected optimum must be guaranteed on every map (Theta\*'s bound,
//! which Lazy Theta\* lacks: below).
//!
//! # No length guarantee
//! A repaired node's g grows after it left OPEN, so the argument that bounds Theta\*'s
//! length by the 8-connected optimum (planner-theta_star's docs, step 3) fails here:
//! Lazy Theta\* may return a path longer than A\*'s on the same grid, and longer than
//! Theta\*'s. `tests/lazy.rs` measures it on the Moving AI scenarios in `maps/movingai`
//! (and asserts that the excess over the optimum stays below 1% there), and
//! `cargo bench -p planner-theta_star --bench movingai` reports it over every scenario.
//!
//! ```
//! use planner_api::{Budget, Cell, Grid, PathRule, Planner, Problem, Status};
//! use planner_lazy_theta_star::{Config, LazyThetaStar};
//!
//! let grid = Grid::from_ascii("
//!     ......
//!     .###..
//!     ......
//! ").unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 2), Cell::new(5, 0)).unwrap();
//! let mut lazy = LazyThetaStar::new(Config::default()).unwrap();
//! let outcome = lazy.plan(&problem, &Budget::unlimited());
//! assert_eq!(outcome.status, Status::Found);
//! let path = outcome.path.unwrap();
//! assert!(path.validate(&grid, PathRule::AnyAngle).is_ok());
//! assert!(outcome.counters.get("n_parent_repairs").is_some());
//! ```
//!
//! # Budget
//! The planner honours the expansion and time limits of its [`planner_api::Budget`]
//! and its memory limit ([`Budget::max_memory_mb`](planner_api::Budget::max_memory_mb):
//! it refuses with [`planner_api::Outcome::over_memory`] when its move masks, node records
//! and line-of-sight bits would not fit). It records its expanded cells and its steps as
//! Theta\* does (planner-theta_star's docs, "Recording"): an expansion's parent is the
//! one line of sight confirmed or the repair chose.
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

use planner_api::{Budget, Grid, Outcome, PathSpec, Planner, PlannerSpecs, Problem};
use planner_theta_star::AnyAngle;

pub use planner_theta_star::{Config, ConfigError, Search, Variant, EPSILON};

/// The registry name of this planner.
pub const NAME: &str = "lazy_theta_star";

/// The Lazy Theta\* planner. Build with [`LazyThetaStar::new`]; reuse it for many queries.
#[derive(Debug, Clone)]
pub struct LazyThetaStar {
    search: AnyAngle,
}

impl LazyThetaStar {
    /// A planner with `config`, validated (the same parameters as Theta\*).
    pub fn new(config: Config) -> Result<LazyThetaStar, ConfigError> {
        Ok(LazyThetaStar {
            search: AnyAngle::new(&config)?,
        })
    }

    /// Runs Lazy Theta\* and returns the path with its cost and raw counters.
    pub fn search(&mut self, problem: &Problem<'_>, budget: &Budget) -> Search {
        self.search.search(problem, budget, Variant::Lazy)
    }
}

impl Planner for LazyThetaStar {
    fn name(&self) -> &str {
        NAME
    }

    /// Deterministic; paths are waypoints joined by segments with line of sight.
    fn specs(&self) -> PlannerSpecs {
        PlannerSpecs::deterministic(PathSpec::AnyAngle)
    }

    fn prepare_bytes(&self, grid: &Grid) -> u64 {
        self.search.memory_bytes_for(grid)
    }

    fn prepare(&mut self, grid: &Grid) {
        self.search.prepare(grid);
    }

    /// Refuses with [`Outcome::over_memory`] when the grid's per-cell state is over
    /// [`Budget::max_memory_mb`] (planner-theta_star's `AnyAngle::memory_bytes_for`).
    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        self.search(problem, budget).outcome(Variant::Lazy)
    }
}
