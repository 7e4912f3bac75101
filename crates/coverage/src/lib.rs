//! Coverage path planning by backtracking with A* returns: seed 004 (Dang et al.), after
//! the BSA algorithm of González et al. (<https://doi.org/10.1109/ROBOT.2005.1570413>).
//!
//! From a start cell the robot fills the free space with a simple pattern, then returns to
//! the nearest place where it left free cells behind and fills again, until none is left:
//!
//! 1. **Filling** with 4-connected moves, a visited cell counting as an obstacle:
//!    - [`Pattern::Spiral`], section 2.1, with a reference lateral side (RLS, [`Side`]) and
//!      the opposite side (OLS). Rule 1: no open neighbour ends the spiral; rule 2: an open
//!      RLS: turn to the RLS and move forward; rule 3: an obstacle in front: turn to the
//!      OLS; rule 4: move forward. With the RLS on the left, the spiral turns clockwise.
//!    - [`Pattern::Zigzag`], section 2.2: rule 1 as above; rule 2: move to the first open
//!      neighbour in counter-clockwise order, by default right, up, left, down, which from
//!      the top-left corner sweeps rows (boustrophedon). [`Rotation::Clockwise`] is the
//!      variant the section mentions; its default first direction is down (down, left,
//!      up, right), the mirror image in the main diagonal, which sweeps columns.
//! 2. **Backtracking points** (section 2.3): after every move, the cell just left is
//!    marked when it still has an open 4-neighbour (another filling direction was
//!    possible there). A marked point is dropped once its 4-neighbourhood is covered.
//! 3. **Returns** (section 2.4): when filling ends, the points with covered neighbourhoods
//!    are dropped; if none remains the run is over. Otherwise the robot goes to the
//!    *nearest* remaining point by A* (planner-astar) with 8-connected moves without corner
//!    cutting and the octile heuristic of equation 2 (D = 1, D2 = sqrt 2), over every free
//!    cell, and resumes filling there. Every cell the return passes is covered too (the
//!    robot drives over it), and is marked as a backtracking point by the rule above.
//!
//! # Nearest
//! The nearest point is the one with the least 8-connected path cost from the cell where
//! filling stopped (`s + d sqrt 2` for `s` straight and `d` diagonal moves, compared
//! exactly in integers); among equal costs, the point marked last. It is found with A*
//! alone, by branch and bound: points are taken in increasing octile distance (a lower
//! bound of the cost), ties by the point marked last, A* runs to each, and the scan stops
//! at the first point whose octile distance exceeds the best cost found. Every A*
//! expansion counts in `n_return_expansions`, the searches in `n_return_searches`.
//!
//! # Run time
//! A run's time follows its work, and its budget bounds every part of it:
//! - The budget counts fill moves plus A* expansions (see "Counters"). The rest of the
//!   work is either paid for by that count or cheap: a return leg's cells were expanded
//!   by the A* search that found it; the points' index (below) costs `O(1)` per covered
//!   cell and per marking; a nearest-point scan that reads as far as cost `D` enters
//!   `O(D)` blocks of 8 x 8 cells plus `O(log)` per point it gives, in proportion to the
//!   A* searches it feeds (a path of cost `D` has at least `D / sqrt 2` moves, each
//!   expanded); the start and the final measure are linear in the grid, once.
//! - The live points are kept in an index (`points.rs`): a point is dropped by the cover
//!   that closes its neighbourhood (at most four checks per covered cell), and each
//!   return takes them from a count pyramid over 8 x 8 blocks, best first by lower bound
//!   then marking order, only as far as the branch and bound reads. Points, searches,
//!   counters and path are those of the seed's procedure (every return: drop the closed
//!   points from the list, sort all of it by bound, scan), which cost `O(P log P)` per
//!   return for `P` points alive: quadratic in the map. On random square maps of 250, 500
//!   and 1000 cells a side with 20 % walls (spiral from a corner) that took 0.86 s, 12.1 s
//!   and 222 s, 80 % of it sorting and 12 % in the list's retain (perf, 500 cells); with
//!   the index 0.05 s, 0.19 s and 0.86 s, the same paths and counters (`tests/coverage.rs`
//!   pins a million-cell run's).
//! - Between A* searches the deadline and the cancel flag are read before each search
//!   (A* reads them itself only every [`planner_api::BudgetClock::TIME_CHECK_INTERVAL`]
//!   expansions, which a return's short searches never reach, and the run's clock ticks
//!   once per fill move): a time limit or a cancel ends a run dominated by returns at its
//!   next search. Expansion-only budgets never read the clock, so counters stay
//!   deterministic.
//!
//! # Weighted grids
//! On a grid with cell weights ([`planner_api::weights`]) the return legs are least-cost
//! under the grid's [`planner_api::CostRule`]: A* honours the weights, and the nearest
//! point is the one with the least weighted cost (in exact [`planner_api::Cost`] units,
//! ties again to the point marked last). The branch and bound uses the octile distance
//! times the grid's smallest weight as the lower bound (every move costs at least its
//! length times it). Filling is unchanged: its moves follow the seed's rules, not costs.
//! `tests/weighted.rs` holds every return leg to the test kit's weighted Dijkstra, for
//! its cost and for being the cheapest way to any point left.
//!
//! # Completeness
//! Invariant: every covered cell with an open 4-neighbour is a marked point or the
//! robot's cell (a cell is checked when left; covering only closes neighbourhoods). When
//! filling stops, the robot's cell has no open neighbour; when no point remains, no covered
//! cell has an open neighbour, so the covered set is the start's whole 4-connected
//! component. Each filling phase covers at least one new cell, so the run ends. Hence
//! coverage is 100 % of the reachable cells on every map (tested on thousands).
//!
//! # Choices where the seed is silent
//! - A spiral phase's first heading: from [`Config::heading`] (default right), turning
//!   towards the OLS, the first heading with an open front and an obstacle on the RLS
//!   (else the first with an open front). After a return the same rule applies.
//! - Seed 004 reports "backtracking points" per map (three for spiral, two for zigzag in
//!   Fig. 8): counted here as `n_backtracking_points`, the returns to a point (a point
//!   returned to twice counts twice), since marked points whose neighbourhoods fill up are
//!   dropped without a return. `n_marked_points` counts every marking.
//!
//! # Counters
//! `n_reachable`, `n_covered`, `n_revisits` (see [`planner_api::CoverageMetrics`]),
//! `n_moves` (path steps), `n_turns` (path turns), `n_backtracking_points`,
//! `n_marked_points`, `n_fill_moves`, `n_return_moves`, `n_return_searches`,
//! `n_return_expansions`. The budget counts fill moves plus A* expansions. Every counter
//! and path equals that of `planner_testkit::reference_coverage`, the run written again
//! from these rules with the test kit's reference A* for the returns, for both patterns,
//! on 1,000 random grids and 100 random weighted ones (`tests/reference.rs`) and on every
//! run of `configs/coverage.toml` (xtask's `every_coverage_run_matches_the_reference_run`).
//!
//! ```
//! use planner_api::{
//!     Budget, Cell, Connectivity, CoveragePlanner, CoverageProblem, Grid, MoveSet,
//!     PathRule, ReturnLeg, Status,
//! };
//! use planner_coverage::{Config, Coverage, Pattern};
//!
//! let grid = Grid::from_ascii("
//!     .....
//!     .##..
//!     .....
//! ").unwrap();
//! let problem = CoverageProblem::new(&grid, Cell::new(0, 0)).unwrap();
//! let mut zigzag = Coverage::new(Config { pattern: Pattern::Zigzag, ..Config::default() }).unwrap();
//! let outcome = zigzag.cover(&problem, &Budget::unlimited());
//! assert_eq!(outcome.status, Status::Found);
//! assert!(outcome.metrics.is_complete());
//! // By hand: row 0 rightwards, down to (4,1), left to (3,1), down to (3,2), right to the
//! // dead end (4,2). The marked points left are (0,0) (open below) and (3,2) (open to
//! // the left); (3,2) is nearer, one step back. Then row 2 leftwards and up to (0,1).
//! let cells: Vec<(u32, u32)> = outcome.path.cells().iter().map(|c| (c.x, c.y)).collect();
//! assert_eq!(cells, [(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (4, 1), (3, 1), (3, 2),
//!     (4, 2), (3, 2), (2, 2), (1, 2), (0, 2), (0, 1)]);
//! assert_eq!(outcome.returns, [ReturnLeg { start: 8, end: 9 }]);
//! assert_eq!((outcome.metrics.n_covered, outcome.metrics.n_revisits), (13, 1));
//! assert_eq!(outcome.counters.get("n_backtracking_points"), Some(1));
//! let eight = MoveSet::standard(Connectivity::Eight);
//! assert!(outcome.path.validate(&grid, PathRule::Moves(&eight)).is_ok());
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

mod fill;
pub mod generate;
mod points;

use std::cmp::Ordering;
use std::time::{Duration, Instant};

use planner_api::{
    Budget, Cell, Connectivity, Counters, CoverageMetrics, CoverageOutcome, CoveragePlanner,
    CoverageProblem, Grid, Path, Problem, ReturnLeg, Status,
};
use planner_astar::{AStar, Heuristic};
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::fill::Field;
use crate::points::Points;

/// The registry name of this planner.
pub const NAME: &str = "coverage";

/// The filling pattern.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Pattern {
    /// Section 2.1: follow obstacles on the reference lateral side.
    #[default]
    Spiral,
    /// Section 2.2: the first open neighbour in a fixed rotation order.
    Zigzag,
}

/// The spiral's reference lateral side (RLS); the opposite lateral side (OLS) is the other.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// Obstacles on the left: a clockwise spiral on screen.
    #[default]
    Left,
    /// Obstacles on the right: a counter-clockwise spiral on screen.
    Right,
}

/// A 4-connected heading on screen, rows growing downwards. Written `"R"`, `"D"`, `"L"`,
/// `"U"` (or `"right"`, `"down"`, `"left"`, `"up"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Heading {
    /// `(x+1, y)`.
    #[serde(rename = "R", alias = "right")]
    Right,
    /// `(x, y+1)`.
    #[serde(rename = "D", alias = "down")]
    Down,
    /// `(x-1, y)`.
    #[serde(rename = "L", alias = "left")]
    Left,
    /// `(x, y-1)`.
    #[serde(rename = "U", alias = "up")]
    Up,
}

/// In configs `"R"`, `"D"`, `"L"`, `"U"` or their aliases `"right"`, `"down"`, `"left"`, `"up"`.
impl schemars::JsonSchema for Heading {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "Heading".into()
    }

    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({
            "type": "string",
            "enum": ["R", "D", "L", "U", "right", "down", "left", "up"]
        })
    }
}

/// The zigzag's rotation order, as seen on screen.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Rotation {
    /// Right, up, left, down from right (section 2.2's rule).
    #[default]
    #[serde(alias = "ccw")]
    CounterClockwise,
    /// Right, down, left, up from right (the variant of Fig. 4).
    #[serde(alias = "cw")]
    Clockwise,
}

/// The planner's parameters. Pattern-specific ones are optional and rejected with the
/// other pattern, so a config cannot set a parameter that does nothing.
///
/// A config serializes as it runs (runs.json, `gridplan planners coverage`): the pattern's
/// own parameters left unset show their defaults, the other pattern's show as unset.
#[derive(Debug, Clone, PartialEq, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// `"spiral"` (default) or `"zigzag"`.
    pub pattern: Pattern,
    /// Spiral only: the RLS, `"left"` (default) or `"right"`.
    #[schemars(extend("default" = "left"))]
    pub reference_side: Option<Side>,
    /// Spiral only: the heading scanned first when a phase starts (default `"R"`).
    #[schemars(extend("default" = "R"))]
    pub heading: Option<Heading>,
    /// Zigzag only: `"counter_clockwise"` (default) or `"clockwise"`.
    pub rotation: Option<Rotation>,
    /// Zigzag only: the first direction of the order; default `"R"` counter-clockwise,
    /// `"D"` clockwise.
    pub first: Option<Heading>,
}

impl Serialize for Config {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        /// The config as it runs: the pattern's own parameters with their defaults.
        #[derive(Serialize)]
        struct AsRun {
            pattern: Pattern,
            reference_side: Option<Side>,
            heading: Option<Heading>,
            rotation: Option<Rotation>,
            first: Option<Heading>,
        }
        let spiral = self.pattern == Pattern::Spiral;
        let rotation = self.rotation.or((!spiral).then(Rotation::default));
        let first = self.first.or(match rotation {
            _ if spiral => None,
            Some(Rotation::Clockwise) => Some(Heading::Down),
            _ => Some(Heading::Right),
        });
        AsRun {
            pattern: self.pattern,
            reference_side: self.reference_side.or(spiral.then(Side::default)),
            heading: self.heading.or(spiral.then_some(Heading::Right)),
            rotation,
            first,
        }
        .serialize(serializer)
    }
}

impl Default for Config {
    fn default() -> Config {
        Config {
            pattern: Pattern::Spiral,
            reference_side: None,
            heading: None,
            rotation: None,
            first: None,
        }
    }
}

/// A parameter the planner cannot run with.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ConfigError {
    /// A parameter of the other pattern.
    #[error("parameter `{parameter}` applies only to pattern = \"{applies_to}\"")]
    OtherPattern {
        /// The parameter given.
        parameter: &'static str,
        /// The pattern it belongs to.
        applies_to: &'static str,
    },
}

impl planner_api::ParamKey for ConfigError {
    fn param_key(&self) -> &str {
        match self {
            ConfigError::OtherPattern { parameter, .. } => parameter,
        }
    }
}

/// The exact cost `straight + diagonal * sqrt 2` of an 8-connected path or octile distance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Octile {
    straight: u64,
    diagonal: u64,
}

impl Octile {
    fn between(a: Cell, b: Cell) -> Octile {
        let dx = u64::from(a.x.abs_diff(b.x));
        let dy = u64::from(a.y.abs_diff(b.y));
        Octile {
            straight: dx.max(dy) - dx.min(dy),
            diagonal: dx.min(dy),
        }
    }

    fn of_path(cells: &[Cell]) -> Octile {
        let mut cost = Octile {
            straight: 0,
            diagonal: 0,
        };
        for pair in cells.windows(2) {
            if pair[0].x != pair[1].x && pair[0].y != pair[1].y {
                cost.diagonal += 1;
            } else {
                cost.straight += 1;
            }
        }
        cost
    }
}

impl Ord for Octile {
    /// Compares `s1 + d1 sqrt 2` with `s2 + d2 sqrt 2` exactly: `a = s1 - s2` against
    /// `b sqrt 2` with `b = d2 - d1`, by signs and then squares.
    fn cmp(&self, other: &Octile) -> Ordering {
        let a = i128::from(self.straight) - i128::from(other.straight);
        let b = i128::from(other.diagonal) - i128::from(self.diagonal);
        match (a.signum(), b.signum()) {
            (0, 0) => Ordering::Equal,
            (sa, sb) if sa >= 0 && sb <= 0 => Ordering::Greater,
            (sa, sb) if sa <= 0 && sb >= 0 => Ordering::Less,
            (1, _) => (a * a).cmp(&(2 * b * b)),
            _ => (2 * b * b).cmp(&(a * a)),
        }
    }
}

impl PartialOrd for Octile {
    fn partial_cmp(&self, other: &Octile) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// A return's cost, or a lower bound of it: exact octile on an unweighted grid, weighted
/// [`planner_api::Cost`] units on a weighted one (one kind per run).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Distance {
    Octile(Octile),
    Weighted(planner_api::Cost),
}

impl Distance {
    /// A lower bound of the cost from `a` to `b`: the octile distance, times the smallest
    /// weight on a weighted grid.
    fn bound(grid: &Grid, a: Cell, b: Cell) -> Distance {
        match grid.weights() {
            None => Distance::Octile(Octile::between(a, b)),
            Some(w) => Distance::Weighted(
                planner_api::Cost::octile_distance(a.x.abs_diff(b.x), a.y.abs_diff(b.y))
                    .times(u64::from(w.min())),
            ),
        }
    }

    /// The cost of the path `cells`.
    fn of_path(grid: &Grid, cells: &[Cell]) -> Distance {
        if grid.is_weighted() {
            Distance::Weighted(grid.path_cost(cells))
        } else {
            Distance::Octile(Octile::of_path(cells))
        }
    }
}

/// Plain-integer counters of one run (see the crate docs).
#[derive(Debug, Clone, Copy, Default)]
struct Stats {
    n_backtracking_points: u64,
    n_marked_points: u64,
    n_fill_moves: u64,
    n_return_moves: u64,
    n_return_searches: u64,
    n_return_expansions: u64,
}

/// The coverage planner. Build with [`Coverage::new`]; reuse it for many runs.
#[derive(Debug, Clone)]
pub struct Coverage {
    config: Config,
    side: Side,
    heading: usize,
    order: [usize; 4],
    astar: AStar,
    visited: Vec<bool>,
    points: Points,
}

impl Coverage {
    /// The bytes a run on `grid` allocates at most: a visited flag and the live points'
    /// index per cell (a marking order and block counts, at most 5 bytes; 6 counted),
    /// the return legs' A* ([`AStar::memory_bytes_for`]), and the measure of the path
    /// ([`CoverageMetrics::measure`]: two flags and a queue slot, 10 bytes a cell).
    pub fn memory_bytes_for(&self, grid: &Grid) -> u64 {
        16 * grid.len() as u64 + self.astar.memory_bytes_for(grid)
    }

    /// A planner with `config`, validated: pattern-specific parameters must match
    /// `config.pattern`.
    pub fn new(config: Config) -> Result<Coverage, ConfigError> {
        let other = |parameter, applies_to| ConfigError::OtherPattern {
            parameter,
            applies_to,
        };
        match config.pattern {
            Pattern::Spiral => {
                if config.rotation.is_some() {
                    return Err(other("rotation", "zigzag"));
                }
                if config.first.is_some() {
                    return Err(other("first", "zigzag"));
                }
            }
            Pattern::Zigzag => {
                if config.reference_side.is_some() {
                    return Err(other("reference_side", "spiral"));
                }
                if config.heading.is_some() {
                    return Err(other("heading", "spiral"));
                }
            }
        }
        let rotation = config.rotation.unwrap_or_default();
        let first = config.first.unwrap_or(match rotation {
            Rotation::CounterClockwise => Heading::Right,
            Rotation::Clockwise => Heading::Down,
        });
        let astar = AStar::new(planner_astar::Config {
            moves: Connectivity::Eight,
            heuristic: Heuristic::Octile,
            ..planner_astar::Config::default()
        });
        // The A* config is fixed and valid; a failure here would be a bug in planner-astar.
        let Ok(astar) = astar else {
            unreachable!("8-connected octile A* is a valid planner-astar config")
        };
        Ok(Coverage {
            side: config.reference_side.unwrap_or_default(),
            heading: fill::heading_index(config.heading.unwrap_or(Heading::Right)),
            order: fill::zigzag_order(rotation, fill::heading_index(first)),
            config,
            astar,
            visited: Vec::new(),
            points: Points::default(),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// Enters `next`: appends it to the path, covers it, drops the points beside it whose
    /// neighbourhood it closes, and marks the cell just left as a backtracking point when
    /// it still has an open neighbour (and is not a live point already).
    fn enter(&mut self, grid: &Grid, path: &mut Vec<Cell>, next: usize, stats: &mut Stats) {
        let Some(&from) = path.last() else {
            return;
        };
        let from = grid.index(from);
        self.visited[next] = true;
        path.push(grid.cell(next));
        let field = field(grid, &self.visited);
        self.points.drop_closed_around(&field, next);
        // A point dropped never comes back (its neighbourhood stays covered), so "live" is
        // the seed's "marked": a point is marked at most once.
        if !self.points.contains(from) && field.any_open(from) {
            stats.n_marked_points += 1;
            // One marking per cell at most: orders fit a u32, as the cell indices do.
            let order = u32::try_from(stats.n_marked_points).unwrap_or(u32::MAX);
            self.points.insert(from, order);
        }
    }
}

fn field<'a>(grid: &'a Grid, visited: &'a [bool]) -> Field<'a> {
    Field {
        free: grid.free_cells(),
        visited,
        width: grid.width() as usize,
        height: grid.height() as usize,
    }
}

/// What is left of a budget: expansions and the deadline, and its cancel flag.
struct Remaining {
    max_expansions: Option<u64>,
    deadline: Option<Instant>,
    cancel: Option<planner_api::CancelFlag>,
}

impl Remaining {
    /// Whether the cancel flag is raised or the deadline has passed.
    fn is_over(&self) -> bool {
        self.cancel
            .is_some_and(planner_api::CancelFlag::is_cancelled)
            || self.deadline.is_some_and(|d| Instant::now() >= d)
    }

    /// The budget for a sub-search after `used` units of work.
    fn budget(&self, used: u64) -> Budget {
        Budget {
            max_expansions: self.max_expansions.map(|m| m.saturating_sub(used)),
            max_time: self.deadline.map(|d| {
                d.saturating_duration_since(Instant::now())
                    .max(Duration::ZERO)
            }),
            cancel: self.cancel,
            ..Budget::default()
        }
    }
}

impl CoveragePlanner for Coverage {
    fn name(&self) -> &str {
        NAME
    }

    /// Fill moves are 4-connected and A* returns 8-connected without corner cutting: every
    /// step is an 8-connected move. Return legs honour cell weights (crate docs).
    fn specs(&self) -> planner_api::PlannerSpecs {
        planner_api::PlannerSpecs::deterministic(planner_api::PathSpec::Moves(
            planner_api::MoveSet::standard(planner_api::Connectivity::Eight),
        ))
        .with_cell_costs()
    }

    /// Refuses with [`CoverageOutcome::over_memory`] when [`Coverage::memory_bytes_for`]
    /// the grid is over [`Budget::max_memory_mb`].
    fn cover(&mut self, problem: &CoverageProblem<'_>, budget: &Budget) -> CoverageOutcome {
        let grid = problem.grid();
        let start = problem.start();
        if let Err(shortfall) = budget.check_memory(self.memory_bytes_for(grid), grid) {
            return CoverageOutcome::over_memory(shortfall, start, zero_counters());
        }
        let len = grid.len();
        self.visited.clear();
        self.visited.resize(len, false);
        self.points
            .reset(grid.width() as usize, grid.height() as usize);
        let remaining = Remaining {
            max_expansions: budget.max_expansions,
            deadline: budget.max_time.map(|t| Instant::now() + t),
            cancel: budget.cancel,
        };
        let mut clock = budget.start();
        let mut stats = Stats::default();
        let mut work: u64 = 0;
        let mut path: Vec<Cell> = vec![start];
        let mut returns: Vec<ReturnLeg> = Vec::new();
        self.visited[grid.index(start)] = true;
        let mut status = Status::Found;

        'run: loop {
            // Filling from the robot's cell until rule 1 holds.
            let mut here = grid.index(*path.last().unwrap_or(&start));
            let mut heading = {
                let field = field(grid, &self.visited);
                fill::spiral_start(&field, here, self.side, self.heading)
            };
            loop {
                let next = {
                    let field = field(grid, &self.visited);
                    match self.config.pattern {
                        Pattern::Spiral => fill::spiral_move(&field, here, &mut heading, self.side),
                        Pattern::Zigzag => fill::zigzag_move(&field, here, &self.order),
                    }
                };
                let Some(next) = next else { break };
                if !clock.allows(work) {
                    status = Status::BudgetExhausted;
                    break 'run;
                }
                work += 1;
                stats.n_fill_moves += 1;
                self.enter(grid, &mut path, next, &mut stats);
                here = next;
            }

            // The points whose neighbourhood is covered were dropped as it closed (`enter`);
            // stop when none remains.
            if self.points.is_empty() {
                break;
            }

            // The nearest point by branch and bound over A* searches (crate docs), the
            // points taken nearest bound first from the index (`points.rs`).
            let from = grid.cell(here);
            self.points.begin(grid, from);
            let mut best: Option<(Distance, u32, Path)> = None;
            while let Some((bound, order, point)) = self.points.next(grid, from) {
                if best.as_ref().is_some_and(|(cost, _, _)| bound > *cost) {
                    break;
                }
                // Searches too short to read the clock themselves (A* reads it every
                // `TIME_CHECK_INTERVAL` expansions) add up: read it before each (crate
                // docs, "Run time").
                if remaining.is_over() {
                    status = Status::BudgetExhausted;
                    break 'run;
                }
                let target = grid.cell(point);
                let Ok(query) = Problem::new(grid, from, target) else {
                    continue; // Both cells are free and covered: unreachable.
                };
                let search = self.astar.search(&query, &remaining.budget(work));
                work += search.stats.n_expanded;
                stats.n_return_expansions += search.stats.n_expanded;
                stats.n_return_searches += 1;
                match (search.status, search.path) {
                    (Status::Found, Some(found)) => {
                        let cost = Distance::of_path(grid, found.cells());
                        let better = match &best {
                            None => true,
                            Some((best_cost, best_order, _)) => {
                                cost < *best_cost || (cost == *best_cost && order > *best_order)
                            }
                        };
                        if better {
                            best = Some((cost, order, found));
                        }
                    }
                    (Status::BudgetExhausted, _) => {
                        status = Status::BudgetExhausted;
                        break 'run;
                    }
                    _ => {} // No path: impossible, covered cells are connected.
                }
            }
            let Some((_, _, route)) = best else {
                break; // Unreachable points only: cannot happen, see the crate docs.
            };
            let leg_start = path.len() - 1;
            for &cell in route.cells().iter().skip(1) {
                self.enter(grid, &mut path, grid.index(cell), &mut stats);
                stats.n_return_moves += 1;
            }
            returns.push(ReturnLeg {
                start: leg_start,
                end: path.len() - 1,
            });
            stats.n_backtracking_points += 1;
        }

        let path = Path::new(path);
        let metrics = CoverageMetrics::measure(grid, start, &path);
        let counters = counters(&metrics, &stats);
        CoverageOutcome {
            status,
            path,
            returns,
            metrics,
            counters,
            memory: None,
        }
    }
}

/// A run's counters, in reporting order (crate docs).
fn counters(metrics: &CoverageMetrics, stats: &Stats) -> Counters {
    Counters::new()
        .with("n_reachable", metrics.n_reachable)
        .with("n_covered", metrics.n_covered)
        .with("n_revisits", metrics.n_revisits)
        .with("n_moves", metrics.path.steps)
        .with("n_turns", metrics.path.turns)
        .with("n_backtracking_points", stats.n_backtracking_points)
        .with("n_marked_points", stats.n_marked_points)
        .with("n_fill_moves", stats.n_fill_moves)
        .with("n_return_moves", stats.n_return_moves)
        .with("n_return_searches", stats.n_return_searches)
        .with("n_return_expansions", stats.n_return_expansions)
}

/// The counters of a run that did not run: every one 0.
fn zero_counters() -> Counters {
    counters(
        &CoverageMetrics::unmeasured(&Path::default()),
        &Stats::default(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn octile_order_is_exact() {
        let o = |straight, diagonal| Octile { straight, diagonal };
        // 3 + 0 sqrt 2 = 3 < 1 + 2 sqrt 2 = 3.83 < 4.
        assert!(o(3, 0) < o(1, 2));
        assert!(o(1, 2) < o(4, 0));
        // sqrt 2 * 5 = 7.07 > 7.
        assert!(o(0, 5) > o(7, 0));
        assert!(o(0, 5) < o(8, 0));
        assert_eq!(o(2, 2).cmp(&o(2, 2)), Ordering::Equal);
        assert!(o(2, 3) > o(2, 2) && o(3, 2) > o(2, 2));
        assert_eq!(Octile::between(Cell::new(5, 1), Cell::new(1, 3)), o(2, 2));
    }

    #[test]
    fn pattern_parameters_are_checked() {
        let err = Coverage::new(Config {
            pattern: Pattern::Zigzag,
            heading: Some(Heading::Up),
            ..Config::default()
        })
        .unwrap_err();
        assert_eq!(
            err.to_string(),
            "parameter `heading` applies only to pattern = \"spiral\""
        );
        assert!(Coverage::new(Config {
            rotation: Some(Rotation::Clockwise),
            ..Config::default()
        })
        .is_err());
    }
}
