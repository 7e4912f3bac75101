//! The one registry of planners: registry name -> constructor from TOML parameters.
//!
//! Names are the planner crates' directory names. Each planner crate owns its
//! `#[serde(deny_unknown_fields)]` `Config`; the registry only deserializes the parameters
//! into it and calls the crate's validating constructor. `cargo xtask new-planner <name>`
//! adds a line between the markers below.

use planner_api::{CoveragePlanner, Planner};
use serde::de::DeserializeOwned;
use serde::Deserialize;

/// How a planner's results vary between repeats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Counters are a pure function of (map, problem, config): repeats only re-time it.
    Deterministic,
    /// Takes a `seed` parameter; the runner sets it to `seed + repeat` for each repeat.
    Stochastic,
}

/// One registered planner.
pub struct Entry {
    /// Registry name (the crate's directory name).
    pub name: &'static str,
    /// One line for `--help` and error messages.
    pub summary: &'static str,
    /// Deterministic or seeded.
    pub kind: Kind,
    /// Builds the planner from its parameters (a TOML table without the `planner` key).
    pub build: fn(toml::Table) -> Result<Box<dyn Planner>, String>,
}

/// Every planner, in the order `--help` lists them.
pub const PLANNERS: &[Entry] = &[
    // (registry start)
    Entry {
        name: planner_astar::NAME,
        summary: "A* with seed 000's counters; heuristics, weight, tie-breaking, 4-48 directions",
        kind: Kind::Deterministic,
        build: |params| build(params, planner_astar::AStar::new),
    },
    Entry {
        name: "backtracking",
        summary: "exhaustive Backtracking (seed 000): every simple path, best by (D, T, Score)",
        kind: Kind::Deterministic,
        build: |params| build(params, planner_backtracking::Backtracking::new),
    },
    Entry {
        name: "bfs",
        summary: "breadth-first search (seed 003): FIFO, visited on enqueue; shortest in steps",
        kind: Kind::Deterministic,
        build: |params| build(params, planner_bfs::Bfs::new),
    },
    Entry {
        name: "dfs",
        summary: "depth-first search (seed 003): LIFO, visited on push; a path, not the shortest",
        kind: Kind::Deterministic,
        build: |params| build(params, planner_dfs::Dfs::new),
    },
    Entry {
        name: planner_lexastar::NAME,
        summary: "A* over (cell, heading) with lexicographic (steps, turns): Backtracking's best in polynomial time",
        kind: Kind::Deterministic,
        build: |params| build(params, planner_lexastar::LexAStar::new),
    },
    Entry {
        name: planner_rrt::NAME,
        summary: "RRT (seed 003) on grid cells: seeded, goal bias, 4/8 steering, longer steps",
        kind: Kind::Stochastic,
        build: |params| build(params, planner_rrt::Rrt::new),
    },
    Entry {
        name: planner_pastar::NAME,
        summary: "PA-star (seed 002): straight line, obstacle size, handover points, merged local A*",
        kind: Kind::Deterministic,
        build: |params| build(params, planner_pastar::PaStar::new),
    },
    Entry {
        name: planner_theta_star::NAME,
        summary: "Theta* (Nash et al. 2007): any-angle A* on cell centres, line of sight on relaxation",
        kind: Kind::Deterministic,
        build: |params| build(params, planner_theta_star::ThetaStar::new),
    },
    Entry {
        name: planner_lazy_theta_star::NAME,
        summary: "Lazy Theta* (Nash et al. 2010): any-angle, line of sight checked on expansion",
        kind: Kind::Deterministic,
        build: |params| build(params, planner_lazy_theta_star::LazyThetaStar::new),
    },
    Entry {
        name: planner_bidirectional_astar::NAME,
        summary: "bidirectional A*, 4 or 8 directions, Pohl's stopping rule; A*'s lengths",
        kind: Kind::Deterministic,
        build: |params| build(params, planner_bidirectional_astar::BidirectionalAStar::new),
    },
    // (registry end)
];

/// One registered coverage planner: a grid and a start in, a coverage path out
/// ([`CoveragePlanner`], seed 004). Configs run it on `problems = "start"` map sets (or on
/// any problem, ignoring the goal).
pub struct CoverageEntry {
    /// Registry name (the crate's directory name).
    pub name: &'static str,
    /// One line for `--help` and error messages.
    pub summary: &'static str,
    /// Builds the planner from its parameters (a TOML table without the `planner` key).
    pub build: fn(toml::Table) -> Result<Box<dyn CoveragePlanner>, String>,
}

/// Every coverage planner. All are deterministic.
pub const COVERAGE: &[CoverageEntry] = &[CoverageEntry {
    name: planner_coverage::NAME,
    summary: "coverage (seed 004): spiral or zigzag filling, backtracking points, A* returns",
    build: |params| {
        let config = planner_coverage::Config::deserialize(toml::Value::Table(params))
            .map_err(|e| e.to_string())?;
        let planner = planner_coverage::Coverage::new(config).map_err(|e| e.to_string())?;
        Ok(Box::new(planner))
    },
}];

/// The coverage planner named `name`.
pub fn find_coverage(name: &str) -> Option<&'static CoverageEntry> {
    COVERAGE.iter().find(|e| e.name == name)
}

/// The entry named `name`.
pub fn find(name: &str) -> Option<&'static Entry> {
    PLANNERS.iter().find(|e| e.name == name)
}

/// The registered names, for error messages.
pub fn names() -> Vec<&'static str> {
    PLANNERS
        .iter()
        .map(|e| e.name)
        .chain(COVERAGE.iter().map(|e| e.name))
        .collect()
}

/// Deserializes `params` into the planner's config `C` and validates it with `new`.
fn build<C, P, E>(
    params: toml::Table,
    new: fn(C) -> Result<P, E>,
) -> Result<Box<dyn Planner>, String>
where
    C: DeserializeOwned,
    P: Planner + 'static,
    E: std::fmt::Display,
{
    let config = C::deserialize(toml::Value::Table(params)).map_err(|e| e.to_string())?;
    let planner = new(config).map_err(|e| e.to_string())?;
    Ok(Box::new(planner))
}
