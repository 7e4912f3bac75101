//! The one registry of planners: registry name -> [`Factory`] from a TOML parameter table.
//!
//! This is the only crate of the workspace that names planners (tidy checks it: no other
//! library crate depends on a planner crate, and a planner crate never depends on this
//! one). The experiment runner, the reports and the paper sections take planners as data
//! (a [`Factory`] and its registry name) from here. Names are the planner
//! crates' directory names. Each planner crate owns its `#[serde(deny_unknown_fields)]`
//! `Config` and a validating constructor whose error implements
//! [`planner_api::ParamKey`]; [`Factory::path`] and [`Factory::coverage`] do the rest.
//! `cargo xtask new-planner <name>` adds an entry between the markers below, and the
//! crate to this crate's `Cargo.toml`.
//!
//! - [`factory`]: the typed boundary ([`Factory`], [`Task`], [`Built`]).
//! - [`schema`]: every planner's declared parameters, from its `Config`.
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod factory;
pub mod schema;

use planner_api::ParamError;

pub use factory::{Built, Factory, Task};

/// One registered planner.
pub struct Entry {
    /// Registry name (the crate's directory name).
    pub name: &'static str,
    /// One line for `planners` and error messages.
    pub summary: &'static str,
    /// Start-goal planning or coverage.
    pub task: Task,
    /// Builds the factory from the label's parameters (the table without the runner's own
    /// keys `planner`, `budget` and `compare`).
    pub factory: fn(&toml::Table) -> Result<Factory, ParamError>,
}

impl Entry {
    /// The factories the tests and the `edits` fuzz target run for this entry: its
    /// defaults, and `moves = 8` where its config takes that key (so a planner whose
    /// default is another move set is also checked 8-connected).
    pub fn variants(&self) -> Result<Vec<Factory>, ParamError> {
        let mut out = vec![(self.factory)(&toml::Table::new())?];
        let mut eight = toml::Table::new();
        eight.insert("moves".to_string(), toml::Value::Integer(8));
        if let Ok(factory) = (self.factory)(&eight) {
            out.push(factory);
        }
        Ok(out)
    }
}

/// Every planner, in the order `planners` lists them.
pub const PLANNERS: &[Entry] = &[
    // (registry start)
    Entry {
        name: planner_astar::NAME,
        summary: "A* with seed 000's counters; heuristics, weight, tie-breaking, 4-48 directions",
        task: Task::StartGoal,
        factory: |params| Factory::path(planner_astar::NAME, params, planner_astar::AStar::new),
    },
    Entry {
        name: "backtracking",
        summary: "exhaustive Backtracking (seed 000): every simple path, best by (D, T, Score)",
        task: Task::StartGoal,
        factory: |params| {
            Factory::path(
                "backtracking",
                params,
                planner_backtracking::Backtracking::new,
            )
        },
    },
    Entry {
        name: "bfs",
        summary: "breadth-first search (seed 003): FIFO, visited on enqueue; shortest in steps",
        task: Task::StartGoal,
        factory: |params| Factory::path("bfs", params, planner_bfs::Bfs::new),
    },
    Entry {
        name: "dfs",
        summary: "depth-first search (seed 003): LIFO, visited on push; a path, not the shortest",
        task: Task::StartGoal,
        factory: |params| Factory::path("dfs", params, planner_dfs::Dfs::new),
    },
    Entry {
        name: planner_lexastar::NAME,
        summary: "A* over (cell, heading) with lexicographic (steps, turns): Backtracking's best in polynomial time",
        task: Task::StartGoal,
        factory: |params| {
            Factory::path(
                planner_lexastar::NAME,
                params,
                planner_lexastar::LexAStar::new,
            )
        },
    },
    Entry {
        name: planner_rrt::NAME,
        summary: "RRT (seed 003) on grid cells: seeded, goal bias, 4/8 steering, longer steps",
        task: Task::StartGoal,
        factory: |params| Factory::path(planner_rrt::NAME, params, planner_rrt::Rrt::new),
    },
    Entry {
        name: planner_pastar::NAME,
        summary: "PA-star (seed 002): straight line, obstacle size, handover points, merged local A*",
        task: Task::StartGoal,
        factory: |params| Factory::path(planner_pastar::NAME, params, planner_pastar::PaStar::new),
    },
    Entry {
        name: planner_capso::NAME,
        summary: "CAPSO (seed 002's reference [44]): cubic spline through control points, chaotic adaptive PSO with beetle antennae search; seeded",
        task: Task::StartGoal,
        factory: |params| Factory::path(planner_capso::NAME, params, planner_capso::Capso::new),
    },
    Entry {
        name: planner_theta_star::NAME,
        summary: "Theta* (Nash et al. 2007): any-angle A* on cell centres, line of sight on relaxation",
        task: Task::StartGoal,
        factory: |params| {
            Factory::path(
                planner_theta_star::NAME,
                params,
                planner_theta_star::ThetaStar::new,
            )
        },
    },
    Entry {
        name: planner_lazy_theta_star::NAME,
        summary: "Lazy Theta* (Nash et al. 2010): any-angle, line of sight checked on expansion",
        task: Task::StartGoal,
        factory: |params| {
            Factory::path(
                planner_lazy_theta_star::NAME,
                params,
                planner_lazy_theta_star::LazyThetaStar::new,
            )
        },
    },
    Entry {
        name: planner_bidirectional_astar::NAME,
        summary: "bidirectional A*, 4 or 8 directions, Pohl's stopping rule; A*'s lengths",
        task: Task::StartGoal,
        factory: |params| {
            Factory::path(
                planner_bidirectional_astar::NAME,
                params,
                planner_bidirectional_astar::BidirectionalAStar::new,
            )
        },
    },
    Entry {
        name: planner_coverage::NAME,
        summary: "coverage (seed 004): spiral or zigzag filling, backtracking points, A* returns",
        task: Task::Coverage,
        factory: |params| {
            Factory::coverage(
                planner_coverage::NAME,
                params,
                planner_coverage::Coverage::new,
            )
        },
    },
    Entry {
        name: planner_rrt_star::NAME,
        summary: "RRT* (Karaman and Frazzoli 2011): RRT plus choose-parent and rewiring; cost series",
        task: Task::StartGoal,
        factory: |params| {
            Factory::path(planner_rrt_star::NAME, params, planner_rrt_star::RrtStar::new)
        },
    },
    Entry {
        name: planner_rrt_connect::NAME,
        summary: "RRT-Connect (Kuffner and LaValle 2000): two trees, extend and connect",
        task: Task::StartGoal,
        factory: |params| {
            Factory::path(
                planner_rrt_connect::NAME,
                params,
                planner_rrt_connect::RrtConnect::new,
            )
        },
    },
    Entry {
        name: planner_jps::NAME,
        summary: "Jump Point Search, 8-connected without corner cutting: jps, jps_prime, jps_plus, optional goal bounding (exact octile costs)",
        task: Task::StartGoal,
        factory: |params| Factory::path(planner_jps::NAME, params, planner_jps::Jps::new),
    },
    Entry {
        name: planner_lpastar::NAME,
        summary: "Lifelong Planning A* (Koenig, Likhachev and Furcy 2004), 4 or 8 moves without corner cutting, exact costs, cell weights that change; incremental",
        task: Task::StartGoal,
        factory: |params| Factory::incremental(planner_lpastar::NAME, params, planner_lpastar::LpaStar::new),
    },
    Entry {
        name: planner_dstar_lite::NAME,
        summary: "D* Lite (Koenig and Likhachev 2002, optimized, with km), 4 or 8 moves without corner cutting, exact costs, cell weights that change; incremental",
        task: Task::StartGoal,
        factory: |params| Factory::incremental(planner_dstar_lite::NAME, params, planner_dstar_lite::DStarLite::new),
    },
    Entry {
        name: planner_weighted_jps::NAME,
        summary: "Jump Point Search on weighted grids: jumps through uniform terrain, every cell where weights change searched as by A*; 8-connected without corner cutting, least-cost paths",
        task: Task::StartGoal,
        factory: |params| Factory::path(planner_weighted_jps::NAME, params, planner_weighted_jps::WeightedJps::new),
    },
    // (registry end)
];

/// The entry named `name`.
pub fn find(name: &str) -> Option<&'static Entry> {
    PLANNERS.iter().find(|e| e.name == name)
}

/// The registered names, for error messages.
pub fn names() -> Vec<&'static str> {
    PLANNERS.iter().map(|e| e.name).collect()
}

/// The incremental planners' names, in registry order: the entries whose factory (with
/// default parameters) is [`Factory::incremental`]. A planner becomes one of them by its
/// registry entry alone; the replanning experiments (planner-replan) read this list.
pub fn incremental_names() -> Vec<&'static str> {
    PLANNERS
        .iter()
        .filter(|e| (e.factory)(&toml::Table::new()).is_ok_and(|f| f.is_incremental()))
        .map(|e| e.name)
        .collect()
}

/// A new incremental planner registered as `name`, with the parameters `params` (`None`:
/// `name` is not a registered incremental planner).
pub fn build_incremental(
    name: &str,
    params: &toml::Table,
) -> Option<Result<Box<dyn planner_api::IncrementalPlanner>, ParamError>> {
    let entry = find(name)?;
    match (entry.factory)(params) {
        Ok(factory) => factory.build_incremental(),
        // Bad parameters: an error only for an incremental planner.
        Err(e) => incremental_names().contains(&entry.name).then_some(Err(e)),
    }
}
