//! PA-star: seed 002's path planner "based on a heuristic method" (Yan et al., sections 3
//! and 4, Figs. 1 and 7, Algorithms 1 and 2, equations 4-9), built on planner-astar.
//!
//! # The pipeline
//! 1. **Straight line** (Step 1-2). The segment between the centres of S and E is walked
//!    cell by cell with planner-api's exact traversal ([`planner_api::for_each_segment_cell`];
//!    a segment through a grid vertex touches the two side cells too). If it crosses no
//!    blocked cell, the path is `[S, E]` and no search runs: every search counter is 0.
//! 2. **Obstacles crossed** (Step 3). Each blocked cell on the line belongs to an obstacle:
//!    its connected component of blocked cells, **8-connected** (cells touching at a
//!    corner are one obstacle, because no move and no segment may pass between them:
//!    planner-api forbids corner cutting). Obstacles are numbered in the order the line
//!    first enters them; a non-convex obstacle that the line leaves and re-enters is one
//!    obstacle, whose crossing runs from the first entry to the last exit.
//! 3. **Size** (Algorithm 1): the largest Euclidean distance between two of the
//!    obstacle's cell centres (a `w x h` rectangle gives `sqrt((w-1)^2 + (h-1)^2)`),
//!    computed by convex hull and rotating calipers ([`geometry`]), not by the `O(n^2)`
//!    loop (tested against it).
//! 4. **Handover points** (equations 4-6). A circle of radius `r` around the obstacle's
//!    centre O (the centroid of its cell centres) meets the line S-E in M and N. The radius
//!    is [`Radius::Size`] (section 3.1: "the circle radius is the size of the obstacle")
//!    or a number of cells ([`Radius::Cells`], section 4.2's tuned `r`; default 4, Table 5).
//!    The point nearer S along S-E is the local start, the other the local goal: equation
//!    6 compares x only (`D = x_M - x_N`), which assumes `x_start < x_goal` and fails on
//!    a vertical line; ordering by the position along S-E is what it means in that case
//!    and works in all.
//! 5. **Snapping**. Handover points are continuous; local searches need cells. The
//!    intersections are clamped to the segment S-E (a point beyond S would make the path
//!    walk away from the goal and back; see "Where the paper is ambiguous") and snapped
//!    to the cell on the line whose centre projects nearest. The local start must lie
//!    before the obstacle's first crossed cell and the local goal after its last: when the
//!    circle is small (or misses the line because O lies farther than `r` from it) the
//!    handover points become the last free line cell before the obstacle and the first
//!    free line cell after it. A blocked snapped cell moves along the line, away from the
//!    obstacle, to the next free cell (S and E are free, so one exists).
//! 6. **Merging** (equation 9, Step 4). Local segments are sorted along the line. The
//!    next segment joins the current one when its local start lies within `r_threshold`
//!    (Euclidean, between cell centres) of the current local goal, or when the two
//!    overlap along the line (then the straight piece between them would run backwards
//!    over an obstacle, so they are always merged). Default `r_threshold = 13` (4.3.2).
//! 7. **Straight pieces**. The pieces S -> start(1), goal(i) -> start(i+1), goal(n) -> E
//!    join cell centres that lie near, not on, the line, so each is checked by exact
//!    traversal; if one crosses a blocked cell, its far end moves back along the line
//!    (start(i+1) toward goal(i); goal(n) toward E) until it does not, at worst to the
//!    near end, where the piece vanishes.
//! 8. **Local A\*** (section 3.4, Step 5). Each segment is searched by planner-astar with
//!    `f = g + beta * h`, `h` Euclidean (equations 7-8), and the `Connecting_distance`
//!    neighbourhood of Algorithm 2 (1 -> 8 directions, 2 -> 16, 3 -> 32, 4 -> 48;
//!    planner-api takes Table 1's 48 for 4, where Algorithm 2 literally yields 56, see
//!    [`planner_api::moves`]). A long move is allowed only if its segment crosses no
//!    blocked cell. There is no second A* here.
//! 9. **Join** (Step 6): `[S, path(1), ..., path(n), E]`, straight between, and checked
//!    with [`PathRule::AnyAngle`]. The length is Euclidean.
//!
//! # Failures, fallback and budget
//! Every local start is joined to S, and every local goal to E, by free segments and
//! local paths, and a free segment's cells are 4-connected; every neighbourhood here
//! contains the four axis moves. So a local search can fail only if S and E are not
//! connected. Should one fail anyway (or should the joined path fail the validity check,
//! which the construction excludes), PA-star falls back to one A* search from S to E with
//! the same neighbourhood, `beta` and heuristic, counts it in `n_fallbacks`, and reports
//! that search's outcome. A solvable problem is therefore never reported unsolved.
//!
//! The [`Budget`] is shared by all searches of one query: each local search gets the
//! expansions and time left. When it runs out the outcome is
//! [`Status::BudgetExhausted`] without a path (no complete path exists yet). The line
//! walk, the component labelling and the hulls are not counted as expansions. The memory
//! limit ([`Budget::max_memory_mb`]) is checked once, before anything else, even when the
//! line is free: a query that would need more for its per-cell state (the local A*'s and
//! the labelling's, [`PaStar::memory_bytes_for`]) is refused with
//! [`Outcome::over_memory`], as every planner refuses it.
//!
//! # Counters
//! The local searches' (and a fallback's) A* counters summed with `+=` of
//! [`SearchStats`] (counts add, `peak_open` is the largest of one search), in
//! [`Counter::ASTAR`] order, then `n_obstacles_crossed`, `n_local_segments` (searches
//! run, after merging), `n_merged` (merges done, overlaps included: `n_local_segments =
//! n_obstacles_crossed - n_merged` when no fallback ran) and `n_fallbacks`.
//!
//! # Design
//! The main decision is to treat handover points as positions along the traversal of
//! S-E (indices into the list of cells the line touches) rather than as free points in
//! the plane: clamping, snapping, the before/after-the-obstacle rule, merging and the
//! straight-piece repair then become index arithmetic on one list, every handover cell
//! is a free cell on the line, and the guarantee above follows. Per-cell labels use a
//! generation stamp, so a query costs the cells it touches, not the grid.
//!
//! # Where the paper is ambiguous
//! - Radius: section 3.1 says the circle's radius is the obstacle's size; section 4.2
//!   tunes a constant `r` and Table 5 sets `r = 4`. Both are offered; the default is 4.
//!   Table 4's lengths grow for `r >= 20` (up to 130.06 at 45-50), which suggests the
//!   paper intersects the infinite line (eq. 4), so that M lands beyond S; we clamp to
//!   the segment, so large radii give local searches from S or to E instead.
//! - Centre O: not defined; the centroid of the obstacle's cells (inside its convex hull,
//!   so with `r = size` the whole obstacle lies inside the circle).
//! - Algorithm 1's `|obstacle(i) - obstacle(j)|`: Euclidean distance between cell centres.
//! - Equation 9 vs Step 4: Step 4 writes the merged segment as `[local_goal(i),
//!   local_start(i)]` and section 3.5 as `[x_M2, x_N2]`; both mean the start of the first
//!   and the goal of the last segment, as Fig. 5's `[S M1 P3 N2 E]` shows.
//!
//! # Where the paper's claim fails
//! Section 4.3 reports PA-star shorter than TA-star, RA-star1 and RA-star2 in every
//! scenario. On the generated maps of `configs/pastar.toml` (`maps/pastar/`; lengths):
//!
//! | scenario | PA-star (r = 4) | PA-star, r = size | TA-star | RA-star1 | RA-star2 |
//! |---|---:|---:|---:|---:|---:|
//! | no obstacle | 111.80 | 111.80 | 120.71 | 120.71 | 120.71 |
//! | two obstacles on the line | 118.97 | 115.52 | 120.71 | 120.71 | 120.71 |
//! | several obstacles on the line | 126.93 | 115.84 | 131.25 | 121.30 | 125.40 |
//! | 200 x 200, 1 | 213.33 | 206.52 | 221.62 | 215.76 | 216.59 |
//! | 200 x 200, 2 | 211.99 | 197.60 | 213.76 | 202.63 | 214.35 |
//! | 500 x 500, 1 | 568.85 | 457.02 | 481.17 | 474.30 | 499.91 |
//! | 500 x 500, 2 | 451.26 | 421.41 | 438.11 | 438.11 | 455.51 |
//!
//! PA-star is never longer than TA-star on the no-obstacle and line-obstacle maps (tested),
//! but with Table 5's `r = 4` it loses to RA-star1 (exact 8-connected A*) on the
//! several-obstacle map and on one 200 x 200 map, and to every reference on the 500 x 500
//! map, by up to 20 %. The cause is the fixed radius: around an obstacle much larger
//! than the circle the handover points are the line's last free cell before it and first
//! after it, so the local path starts at the obstacle's face and hugs it, and the
//! straight pieces outside it cannot bend early. The paper's Fig. 5 draws circles that
//! contain their obstacles, which `r = 4` can do only for obstacles about 8 cells across;
//! the 140 x 120 maps here are made so (7 x 7 blocks), the others are not. With the
//! radius equal to the obstacle's size (section 3.1) PA-star is shorter than every
//! reference in every scenario here (on large obstacles its local search then spans most
//! of S-E and it becomes a 16-direction A*). Section 4.2 finds small `r` best (Table 4);
//! on the several-obstacle map `configs/pastar-radius.toml` finds the opposite (129.96
//! for `r <= 5.1`, 120.49 to 121.85 from `r = 8` up).
//!
//! ```
//! use planner_api::{Budget, Cell, Grid, Planner, Problem, Status};
//! use planner_pastar::{Config, PaStar};
//!
//! let grid = Grid::from_ascii("
//!     ..........
//!     ..........
//!     ....##....
//!     ....##....
//!     ..........
//!     ..........
//! ").unwrap();
//! let mut pastar = PaStar::new(Config::default()).unwrap();
//! // A free line: the path is [S, E] and nothing is searched.
//! let free = Problem::new(&grid, Cell::new(0, 0), Cell::new(9, 0)).unwrap();
//! let outcome = pastar.plan(&free, &Budget::unlimited());
//! assert_eq!(outcome.path.unwrap().cells(), &[Cell::new(0, 0), Cell::new(9, 0)]);
//! assert_eq!(outcome.counters.get("n_expanded"), Some(0));
//! // Through the 2 x 2 block: one obstacle, one local search around it.
//! let blocked = Problem::new(&grid, Cell::new(0, 3), Cell::new(9, 2)).unwrap();
//! let outcome = pastar.plan(&blocked, &Budget::unlimited());
//! assert_eq!(outcome.status, Status::Found);
//! assert_eq!(outcome.counters.get("n_obstacles_crossed"), Some(1));
//! assert_eq!(outcome.counters.get("n_local_segments"), Some(1));
//! assert!(outcome.path.unwrap().validate(&grid, planner_api::PathRule::AnyAngle).is_ok());
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod generate;
pub mod geometry;

use std::fmt;
use std::time::{Duration, Instant};

use planner_api::{
    for_each_segment_cell, segment_is_free, Budget, Cell, Connectivity, Counter, Counters, Grid,
    Mark, MoveSet, NeighborOrder, Outcome, Path, PathRule, Planner, Problem, SearchStats, Status,
};
use planner_astar::{AStar, Heuristic, TieBreak};
use serde::de::{self, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use thiserror::Error;

use geometry::Point;

/// The registry name of this planner.
pub const NAME: &str = "pastar";

/// The radius of the circle around an obstacle whose intersections with S-E are the
/// handover points (equation 5).
///
/// In TOML: `radius = "size"` or `radius = 4` (a number of cells).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Radius {
    /// The obstacle's size by Algorithm 1 (section 3.1).
    Size,
    /// A fixed radius in cells, finite and `> 0` (section 4.2's `r`).
    Cells(f64),
}

impl Default for Radius {
    /// `Cells(4.0)`: Table 5's tuned `r`.
    fn default() -> Radius {
        Radius::Cells(4.0)
    }
}

impl fmt::Display for Radius {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Radius::Size => f.write_str("size"),
            Radius::Cells(r) => write!(f, "{r}"),
        }
    }
}

/// In configs `"size"` or a number of cells.
impl schemars::JsonSchema for Radius {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "Radius".into()
    }

    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({
            "anyOf": [{ "type": "number", "exclusiveMinimum": 0 }, { "const": "size" }]
        })
    }
}

impl Serialize for Radius {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            Radius::Size => serializer.serialize_str("size"),
            Radius::Cells(r) => serializer.serialize_f64(*r),
        }
    }
}

impl<'de> Deserialize<'de> for Radius {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Radius, D::Error> {
        struct RadiusVisitor;
        impl Visitor<'_> for RadiusVisitor {
            type Value = Radius;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("\"size\" or a number of cells")
            }
            fn visit_str<E: de::Error>(self, text: &str) -> Result<Radius, E> {
                if text == "size" {
                    Ok(Radius::Size)
                } else {
                    Err(E::invalid_value(de::Unexpected::Str(text), &self))
                }
            }
            fn visit_f64<E: de::Error>(self, r: f64) -> Result<Radius, E> {
                Ok(Radius::Cells(r))
            }
            fn visit_i64<E: de::Error>(self, r: i64) -> Result<Radius, E> {
                Ok(Radius::Cells(r as f64))
            }
            fn visit_u64<E: de::Error>(self, r: u64) -> Result<Radius, E> {
                Ok(Radius::Cells(r as f64))
            }
        }
        deserializer.deserialize_any(RadiusVisitor)
    }
}

/// PA-star's parameters; the defaults are the paper's final choice (Table 5, 4.3.2).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// `Connecting_distance` of the local A* (Algorithm 2): 1, 2, 3 or 4 for 8, 16, 32 or
    /// 48 directions. Default 2 (Table 5).
    #[schemars(range(min = 1, max = 4))]
    pub connecting_distance: u32,
    /// `beta` in `f = g + beta * h` (equation 7): finite and `>= 0`. Default 1 (Table 5).
    #[schemars(range(min = 0))]
    pub beta: f64,
    /// The handover circle's radius: `"size"` or a number of cells. Default 4 (Table 5).
    pub radius: Radius,
    /// `R_threshold` of equation 9, in cells: finite and `>= 0`. Default 13 (4.3.2).
    #[schemars(range(min = 0))]
    pub r_threshold: f64,
    /// Tie-breaking among equal `f` in the local A* (planner-astar's). Default FIFO.
    pub tie_break: TieBreak,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            connecting_distance: 2,
            beta: 1.0,
            radius: Radius::default(),
            r_threshold: 13.0,
            tie_break: TieBreak::Fifo,
        }
    }
}

/// A parameter PA-star cannot run with.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConfigError {
    /// `connecting_distance` is not 1, 2, 3 or 4.
    #[error("parameter `connecting_distance` must be 1, 2, 3 or 4, got {0}")]
    ConnectingDistance(u32),
    /// `beta` is negative, infinite or NaN.
    #[error("parameter `beta` must be a finite number >= 0, got {0}")]
    Beta(f64),
    /// `radius` is a number that is not finite and positive.
    #[error("parameter `radius` must be \"size\" or a finite number > 0, got {0}")]
    Radius(f64),
    /// `r_threshold` is negative, infinite or NaN.
    #[error("parameter `r_threshold` must be a finite number >= 0, got {0}")]
    RThreshold(f64),
    /// The local A* rejected its configuration.
    #[error("local A*: {0}")]
    AStar(#[from] planner_astar::ConfigError),
}

impl planner_api::ParamKey for ConfigError {
    fn param_key(&self) -> &str {
        match self {
            ConfigError::ConnectingDistance(_) => "connecting_distance",
            ConfigError::Beta(_) => "beta",
            ConfigError::Radius(_) => "radius",
            ConfigError::RThreshold(_) => "r_threshold",
            ConfigError::AStar(e) => e.param_key(),
        }
    }
}

/// One obstacle the line S-E crosses.
#[derive(Debug, Clone, PartialEq)]
pub struct Obstacle {
    /// The first of its cells the line touches.
    pub first_cell: Cell,
    /// Number of cells of the obstacle (its 8-connected component).
    pub n_cells: usize,
    /// Its size by Algorithm 1: the largest distance between two of its cell centres.
    pub size: f64,
    /// The circle's centre O: the centroid of its cell centres, `(x, y)`.
    pub centre: (f64, f64),
    /// The circle's radius.
    pub radius: f64,
    /// Where the circle meets the infinite line S-E, as parameters `t` of
    /// `S + t (E - S)`, smaller first (M, N of equations 4-6); `None` if it misses.
    pub circle: Option<(f64, f64)>,
    /// First and last index into the line's cells ([`Report::line`]) of its cells.
    pub crossing: (usize, usize),
    /// The snapped local start and goal before merging, as indices into the line's cells
    /// ([`Report::line`]): free cells, before the first and after the last crossing.
    pub handover: (usize, usize),
}

/// One local search after merging.
#[derive(Debug, Clone, PartialEq)]
pub struct LocalSegment {
    /// The local start (a free cell on the line).
    pub start: Cell,
    /// The local goal (a free cell on the line).
    pub goal: Cell,
    /// How many obstacles it goes around.
    pub n_obstacles: usize,
    /// The local A* path, when the search found one.
    pub path: Option<Path>,
}

/// PA-star's own counters besides the A* ones.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PaStarStats {
    /// The local searches' (and a fallback's) A* counters, summed.
    pub search: SearchStats,
    /// Obstacles (8-connected components of blocked cells) the line S-E touches.
    pub n_obstacles_crossed: u64,
    /// Local searches run (segments after merging).
    pub n_local_segments: u64,
    /// Merges of two consecutive segments (equation 9, or overlap).
    pub n_merged: u64,
    /// Global A* searches run because a local step failed (see the crate docs).
    pub n_fallbacks: u64,
}

impl PaStarStats {
    /// The reported counters: [`Counter::ASTAR`], then PA-star's four.
    pub fn counters(&self) -> Counters {
        self.search
            .report(Counter::ASTAR)
            .with("n_obstacles_crossed", self.n_obstacles_crossed)
            .with("n_local_segments", self.n_local_segments)
            .with("n_merged", self.n_merged)
            .with("n_fallbacks", self.n_fallbacks)
    }
}

/// Everything one PA-star query did, for tests and figures.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// The outcome [`Planner::plan`] returns.
    pub outcome: Outcome,
    /// The cells the line S-E touches, in order from S to E.
    pub line: Vec<Cell>,
    /// The obstacles crossed, in the order the line enters them.
    pub obstacles: Vec<Obstacle>,
    /// The local segments after merging, along the line.
    pub segments: Vec<LocalSegment>,
    /// The counters.
    pub stats: PaStarStats,
}

/// A local segment as indices into the line's cells.
#[derive(Debug, Clone, Copy)]
struct Span {
    start: usize,
    goal: usize,
    n_obstacles: usize,
}

/// The PA-star planner. Build with [`PaStar::new`]; reuse it for many queries.
#[derive(Debug, Clone)]
pub struct PaStar {
    config: Config,
    astar: AStar,
    generation: u32,
    stamp: Vec<u32>,
    component: Vec<u32>,
    stack: Vec<usize>,
    cells: Vec<Point>,
    scratch: Vec<Point>,
    hull: Vec<Point>,
}

impl PaStar {
    /// A planner with `config`, validated.
    pub fn new(config: Config) -> Result<PaStar, ConfigError> {
        let moves = Connectivity::from_connecting_distance(config.connecting_distance)
            .ok_or(ConfigError::ConnectingDistance(config.connecting_distance))?;
        if !config.beta.is_finite() || config.beta < 0.0 {
            return Err(ConfigError::Beta(config.beta));
        }
        if let Radius::Cells(r) = config.radius {
            if !r.is_finite() || r <= 0.0 {
                return Err(ConfigError::Radius(r));
            }
        }
        if !config.r_threshold.is_finite() || config.r_threshold < 0.0 {
            return Err(ConfigError::RThreshold(config.r_threshold));
        }
        let astar = AStar::new(planner_astar::Config {
            moves,
            corner_cutting: false,
            order: NeighborOrder::default(),
            heuristic: Heuristic::Euclidean,
            weight: config.beta,
            tie_break: config.tie_break,
        })?;
        Ok(PaStar {
            config,
            astar,
            generation: 0,
            stamp: Vec::new(),
            component: Vec::new(),
            stack: Vec::new(),
            cells: Vec::new(),
            scratch: Vec::new(),
            hull: Vec::new(),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The bytes a query on `grid` needs at most (its memory check): the local A*'s
    /// ([`AStar::memory_bytes_for`]) and the obstacle labelling's two `u32` per cell.
    pub fn memory_bytes_for(&self, grid: &Grid) -> u64 {
        let labels = (grid.len() as u64).saturating_mul(2 * std::mem::size_of::<u32>() as u64);
        self.astar.memory_bytes_for(grid).saturating_add(labels)
    }

    /// The local A*'s move set (Algorithm 2's neighbourhood for `connecting_distance`).
    pub fn local_moves(&self) -> &MoveSet {
        self.astar.move_set()
    }

    /// Runs PA-star on `problem` within `budget` and reports every intermediate result.
    ///
    /// The outcome marks the handover points the path uses: each local segment's start
    /// `H<k>` and goal `H<k>'`, in order along the line (after merging, so one pair may
    /// serve several obstacles). There are none when the line is free, and none after a
    /// fallback to one A* search from S to E, whose path need not pass them.
    pub fn plan_detailed(&mut self, problem: &Problem<'_>, budget: &Budget) -> Report {
        let mut report = self.run(problem, budget);
        if report.stats.n_fallbacks > 0 {
            return report;
        }
        report.outcome.marks = (1..)
            .zip(&report.segments)
            .flat_map(|(k, segment)| {
                [
                    Mark::new(segment.start, format!("H{k}")),
                    Mark::new(segment.goal, format!("H{k}'")),
                ]
            })
            .collect();
        report
    }

    /// [`PaStar::plan_detailed`] without the marks.
    fn run(&mut self, problem: &Problem<'_>, budget: &Budget) -> Report {
        let grid = problem.grid();
        let (s, e) = (problem.start(), problem.goal());
        let mut line = Vec::new();
        for_each_segment_cell(s, e, |cell| {
            line.push(cell);
            true
        });
        let mut report = Report {
            outcome: Outcome::no_path(Counters::new()),
            line,
            obstacles: Vec::new(),
            segments: Vec::new(),
            stats: PaStarStats::default(),
        };
        if let Err(shortfall) = budget.check_memory(self.memory_bytes_for(grid), grid) {
            report.outcome = Outcome::over_memory(shortfall, report.stats.counters());
            return report;
        }
        if report.line.iter().all(|&c| grid.is_free(c)) {
            let cells = if s == e { vec![s] } else { vec![s, e] };
            report.outcome = Outcome::found(Path::new(cells), report.stats.counters());
            return report;
        }
        self.find_obstacles(grid, s, e, &mut report);
        report.stats.n_obstacles_crossed = report.obstacles.len() as u64;
        let spans = self.spans(grid, &mut report);

        let deadline = budget.max_time.map(|limit| Instant::now() + limit);
        let mut cells = vec![s];
        let mut failed = false;
        for span in &spans {
            let (start, goal) = (report.line[span.start], report.line[span.goal]);
            report.stats.n_local_segments += 1;
            let search = match Problem::new(grid, start, goal) {
                Ok(local) => {
                    let left = remaining(budget, deadline, report.stats.search.n_expanded);
                    self.astar.search(&local, &left)
                }
                Err(_) => unreachable!("handover cells are free cells of the grid"),
            };
            report.stats.search += search.stats;
            report.segments.push(LocalSegment {
                start,
                goal,
                n_obstacles: span.n_obstacles,
                path: search.path.clone(),
            });
            match (search.status, search.path) {
                (Status::Found, Some(path)) => {
                    for &cell in path.cells() {
                        if cells.last() != Some(&cell) {
                            cells.push(cell);
                        }
                    }
                }
                (Status::BudgetExhausted, _) => {
                    let counters = report.stats.counters();
                    report.outcome = match search.memory {
                        Some(shortfall) => Outcome::over_memory(shortfall, counters),
                        None => Outcome::budget_exhausted(None, counters),
                    };
                    return report;
                }
                _ => {
                    failed = true;
                    break;
                }
            }
        }
        if !failed {
            if cells.last() != Some(&e) {
                cells.push(e);
            }
            let path = Path::new(cells);
            if path.validate(grid, PathRule::AnyAngle).is_ok() {
                report.outcome = Outcome::found(path, report.stats.counters());
                return report;
            }
        }
        // Fallback: one A* search from S to E (see the crate docs).
        report.stats.n_fallbacks += 1;
        let left = remaining(budget, deadline, report.stats.search.n_expanded);
        let search = self.astar.search(problem, &left);
        report.stats.search += search.stats;
        let counters = report.stats.counters();
        report.outcome = match search.memory {
            Some(shortfall) => Outcome::over_memory(shortfall, counters),
            None => Outcome::new(search.status, search.path, counters),
        };
        report
    }

    /// Labels the obstacles the line touches, in order of first contact, with their
    /// size, centre, circle and snapped handover cells.
    fn find_obstacles(&mut self, grid: &Grid, s: Cell, e: Cell, report: &mut Report) {
        self.prepare(grid);
        let generation = self.generation;
        let line = &report.line;
        for (k, &cell) in line.iter().enumerate() {
            if grid.is_free(cell) {
                continue;
            }
            let index = grid.index(cell);
            if self.stamp[index] == generation {
                let id = self.component[index] as usize;
                report.obstacles[id].crossing.1 = k;
                continue;
            }
            let id = report.obstacles.len() as u32;
            self.flood_fill(grid, index, id);
            let n_cells = self.cells.len();
            let (sx, sy) = self
                .cells
                .iter()
                .fold((0i64, 0i64), |(ax, ay), &(x, y)| (ax + x, ay + y));
            let centre = (sx as f64 / n_cells as f64, sy as f64 / n_cells as f64);
            let size = (geometry::diameter_squared(&self.cells, &mut self.scratch, &mut self.hull)
                as f64)
                .sqrt();
            let radius = match self.config.radius {
                Radius::Size => size,
                Radius::Cells(r) => r,
            };
            report.obstacles.push(Obstacle {
                first_cell: cell,
                n_cells,
                size,
                centre,
                radius,
                circle: circle_line(s, e, centre, radius),
                crossing: (k, k),
                handover: (k, k),
            });
        }
        // Snap the handover points now that every crossing is known.
        let projections: Vec<f64> = line.iter().map(|&c| project(s, e, c)).collect();
        let nearest = |t: f64| {
            let t = t.clamp(0.0, 1.0);
            projections
                .iter()
                .enumerate()
                .min_by(|a, b| (a.1 - t).abs().total_cmp(&(b.1 - t).abs()))
                .map_or(0, |(k, _)| k)
        };
        for obstacle in &mut report.obstacles {
            let (first, last) = obstacle.crossing;
            // S and E are free, so first >= 1 and last <= line.len() - 2.
            let mut start = first - 1;
            let mut goal = last + 1;
            if let Some((t_m, t_n)) = obstacle.circle {
                start = start.min(nearest(t_m));
                goal = goal.max(nearest(t_n));
            }
            while !grid.is_free(line[start]) {
                start -= 1;
            }
            while !grid.is_free(line[goal]) {
                goal += 1;
            }
            obstacle.handover = (start, goal);
        }
    }

    /// The merged, repaired local segments as indices into the line.
    fn spans(&self, grid: &Grid, report: &mut Report) -> Vec<Span> {
        let line = &report.line;
        let mut raw: Vec<Span> = report
            .obstacles
            .iter()
            .map(|o| Span {
                start: o.handover.0,
                goal: o.handover.1,
                n_obstacles: 1,
            })
            .collect();
        raw.sort_by_key(|span| span.start);
        let threshold = self.config.r_threshold;
        let mut spans: Vec<Span> = Vec::with_capacity(raw.len());
        for span in raw {
            match spans.last_mut() {
                Some(current)
                    if span.start <= current.goal
                        || line[current.goal].euclidean(line[span.start]) <= threshold =>
                {
                    current.goal = current.goal.max(span.goal);
                    current.n_obstacles += span.n_obstacles;
                    report.stats.n_merged += 1;
                }
                _ => spans.push(span),
            }
        }
        // Straight pieces: move a far end back along the line until the piece is free.
        let mut previous = 0;
        for span in &mut spans {
            while span.start > previous
                && !(grid.is_free(line[span.start])
                    && segment_is_free(grid, line[previous], line[span.start]))
            {
                span.start -= 1;
            }
            previous = span.goal;
        }
        let end = line.len() - 1;
        if let Some(last) = spans.last_mut() {
            while last.goal < end
                && !(grid.is_free(line[last.goal])
                    && segment_is_free(grid, line[last.goal], line[end]))
            {
                last.goal += 1;
            }
        }
        spans
    }

    fn prepare(&mut self, grid: &Grid) {
        if self.stamp.len() != grid.len() {
            self.stamp = vec![0; grid.len()];
            self.component = vec![0; grid.len()];
            self.generation = 0;
        }
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            self.stamp.fill(0);
            self.generation = 1;
        }
    }

    /// Labels the 8-connected component of blocked cells containing `seed` with `id` and
    /// leaves its cells in `self.cells`.
    fn flood_fill(&mut self, grid: &Grid, seed: usize, id: u32) {
        let generation = self.generation;
        let free = grid.free_cells();
        let (width, height) = (grid.width() as i64, grid.height() as i64);
        self.cells.clear();
        self.stack.clear();
        self.stack.push(seed);
        self.stamp[seed] = generation;
        self.component[seed] = id;
        while let Some(index) = self.stack.pop() {
            let cell = grid.cell(index);
            let (x, y) = (i64::from(cell.x), i64::from(cell.y));
            self.cells.push((x, y));
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let (nx, ny) = (x + dx, y + dy);
                    if (dx, dy) == (0, 0) || nx < 0 || ny < 0 || nx >= width || ny >= height {
                        continue;
                    }
                    let next = (ny * width + nx) as usize;
                    if !free[next] && self.stamp[next] != generation {
                        self.stamp[next] = generation;
                        self.component[next] = id;
                        self.stack.push(next);
                    }
                }
            }
        }
    }
}

/// The budget left after `used` expansions, with the time left until `deadline`.
fn remaining(budget: &Budget, deadline: Option<Instant>, used: u64) -> Budget {
    Budget {
        max_expansions: budget.max_expansions.map(|m| m.saturating_sub(used)),
        max_time: deadline.map(|d| {
            d.saturating_duration_since(Instant::now())
                .max(Duration::ZERO)
        }),
        ..*budget
    }
}

/// The parameter `t` of the projection of `c`'s centre onto the line `S + t (E - S)`.
fn project(s: Cell, e: Cell, c: Cell) -> f64 {
    let (dx, dy) = (
        f64::from(e.x) - f64::from(s.x),
        f64::from(e.y) - f64::from(s.y),
    );
    let len2 = dx * dx + dy * dy;
    if len2 == 0.0 {
        return 0.0;
    }
    ((f64::from(c.x) - f64::from(s.x)) * dx + (f64::from(c.y) - f64::from(s.y)) * dy) / len2
}

/// Where the circle of `radius` around `centre` meets the infinite line through the
/// centres of `s` and `e` (equations 4 and 5), as parameters `t` of `S + t (E - S)`,
/// smaller first; `None` when it misses.
fn circle_line(s: Cell, e: Cell, centre: (f64, f64), radius: f64) -> Option<(f64, f64)> {
    let (sx, sy) = (f64::from(s.x), f64::from(s.y));
    let (dx, dy) = (f64::from(e.x) - sx, f64::from(e.y) - sy);
    let (fx, fy) = (sx - centre.0, sy - centre.1);
    let a = dx * dx + dy * dy;
    let b = 2.0 * (fx * dx + fy * dy);
    let c = fx * fx + fy * fy - radius * radius;
    let discriminant = b * b - 4.0 * a * c;
    if a == 0.0 || discriminant < 0.0 {
        return None;
    }
    let root = discriminant.sqrt();
    Some(((-b - root) / (2.0 * a), (-b + root) / (2.0 * a)))
}

impl Planner for PaStar {
    fn name(&self) -> &str {
        NAME
    }

    /// Paths join straight-line stretches (exact traversal cells) and local A* paths
    /// (moves up to the 48-direction neighbourhood), so they are checked by the any-angle
    /// rule.
    fn specs(&self) -> planner_api::PlannerSpecs {
        planner_api::PlannerSpecs::deterministic(planner_api::PathSpec::AnyAngle)
    }

    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        self.plan_detailed(problem, budget).outcome
    }
}
