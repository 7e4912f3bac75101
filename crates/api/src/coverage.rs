//! Coverage path planning: the [`CoveragePlanner`] trait, coverage problems, outcomes and
//! metrics (seed 004).
//!
//! Coverage is a different job from start-goal planning: from a start cell, the robot must
//! visit every free cell it can reach. A coverage planner shares the grid, the moves, the
//! path metrics and the counters of start-goal planners, but takes a [`CoverageProblem`]
//! (a grid and a start, validated when built) and returns a [`CoverageOutcome`]: one path
//! that starts at the start and visits the cells in order, the stretches of it that are
//! returns to earlier points ([`ReturnLeg`]), and [`CoverageMetrics`].
//!
//! # Metrics
//! [`CoverageMetrics::measure`] defines them from the grid, the start and the path alone,
//! so every coverage planner is measured the same way:
//! - `n_reachable`: free cells in the start's 4-connected component ([`reachable_cells`]).
//!   With 8-connected moves that may not cut corners the reachable set is the same: a
//!   diagonal move needs both orthogonal cells it passes between to be free, so its two
//!   ends are 4-connected as well.
//! - `n_covered`: distinct reachable cells on the path;
//! - `percent`: `100 * n_covered / n_reachable`;
//! - `n_revisits`: path cells entered when already covered, `len(path) - n_covered` for a
//!   path of reachable cells (a cell entered three times counts two revisits);
//! - `path`: the path's [`PathMetrics`] (steps, turns, score, Euclidean length).
//!
//! ```
//! use planner_api::{Cell, CoverageMetrics, CoverageProblem, Grid, Path};
//! let grid = Grid::from_ascii("
//!     ..#
//!     ..#
//!     #.#
//! ").unwrap();
//! assert!(CoverageProblem::new(&grid, Cell::new(2, 0)).is_err());
//! let problem = CoverageProblem::new(&grid, Cell::new(0, 0)).unwrap();
//! // Right, down, left, back right, down: five cells covered, one revisit.
//! let path = Path::new(
//!     [(0, 0), (1, 0), (1, 1), (0, 1), (1, 1), (1, 2)].map(Cell::from).to_vec(),
//! );
//! let m = CoverageMetrics::measure(problem.grid(), problem.start(), &path);
//! assert_eq!((m.n_reachable, m.n_covered, m.n_revisits), (5, 5, 1));
//! assert_eq!(m.percent, 100.0);
//! assert!(m.is_complete());
//! ```

use serde::{Deserialize, Serialize};

use crate::counters::Counters;
use crate::error::{Endpoint, ProblemError};
use crate::grid::{Cell, Grid};
use crate::path::{Path, PathMetrics};
use crate::planner::{Budget, MemoryShortfall, Status};

/// A coverage query: a grid and the start cell. Construction validates the start.
#[derive(Debug, Clone, Copy)]
pub struct CoverageProblem<'g> {
    grid: &'g Grid,
    start: Cell,
}

impl<'g> CoverageProblem<'g> {
    /// A coverage problem from `start` on `grid`.
    ///
    /// Errors, naming the cell, when the start is out of bounds or blocked
    /// ([`ProblemError`] with [`Endpoint::Start`]).
    pub fn new(grid: &'g Grid, start: Cell) -> Result<CoverageProblem<'g>, ProblemError> {
        if !grid.contains(start) {
            return Err(ProblemError::OutOfBounds {
                endpoint: Endpoint::Start,
                cell: start,
                width: grid.width(),
                height: grid.height(),
            });
        }
        if !grid.is_free(start) {
            return Err(ProblemError::Blocked {
                endpoint: Endpoint::Start,
                cell: start,
            });
        }
        Ok(CoverageProblem { grid, start })
    }

    /// The grid.
    pub fn grid(&self) -> &'g Grid {
        self.grid
    }

    /// The start cell (in bounds and free).
    pub fn start(&self) -> Cell {
        self.start
    }
}

/// A stretch of a coverage path that returns to an earlier point (a backtracking point,
/// seed 004 section 2.3): the cells `path[start..=end]`, from where filling stopped to the
/// point where it resumes, `path[end]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct ReturnLeg {
    /// Index in the path of the cell the return leaves from.
    pub start: usize,
    /// Index in the path of the point returned to.
    pub end: usize,
}

/// How much of the reachable free space a coverage path covers, and at what cost; see the
/// module docs for the exact definitions.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CoverageMetrics {
    /// Free cells 4-connected to the start (the start included).
    pub n_reachable: u64,
    /// Distinct reachable cells on the path.
    pub n_covered: u64,
    /// `100 * n_covered / n_reachable`.
    pub percent: f64,
    /// Path cells entered when already covered.
    pub n_revisits: u64,
    /// Steps, turns, score and Euclidean length of the whole path.
    pub path: PathMetrics,
}

impl CoverageMetrics {
    /// The metrics of a run that measured no coverage (it did not run): zero coverage and
    /// revisits, and `path`'s own metrics.
    pub fn unmeasured(path: &Path) -> CoverageMetrics {
        CoverageMetrics {
            n_reachable: 0,
            n_covered: 0,
            percent: 0.0,
            n_revisits: 0,
            path: path.metrics(),
        }
    }

    /// Measures `path` as a coverage path from `start` on `grid` (module docs).
    ///
    /// Cells of the path outside the reachable set (which a valid path from `start` never
    /// has) are neither covered nor revisits. Allocates two flags per grid cell.
    pub fn measure(grid: &Grid, start: Cell, path: &Path) -> CoverageMetrics {
        let reachable = reachable_cells(grid, start);
        let n_reachable = reachable.iter().filter(|&&r| r).count() as u64;
        let mut covered = vec![false; grid.len()];
        let mut n_covered = 0u64;
        let mut n_revisits = 0u64;
        for &cell in path.cells() {
            if !grid.contains(cell) {
                continue;
            }
            let index = grid.index(cell);
            if !reachable[index] {
                continue;
            }
            if covered[index] {
                n_revisits += 1;
            } else {
                covered[index] = true;
                n_covered += 1;
            }
        }
        let percent = if n_reachable == 0 {
            0.0
        } else {
            100.0 * n_covered as f64 / n_reachable as f64
        };
        CoverageMetrics {
            n_reachable,
            n_covered,
            percent,
            n_revisits,
            path: path.metrics(),
        }
    }

    /// Whether every reachable cell is covered.
    pub fn is_complete(&self) -> bool {
        self.n_reachable > 0 && self.n_covered == self.n_reachable
    }
}

/// The free cells 4-connected to `start`, as row-major flags (all false when `start` is
/// blocked or outside the grid). Breadth-first; allocates one flag per cell and a queue.
pub fn reachable_cells(grid: &Grid, start: Cell) -> Vec<bool> {
    let mut reachable = vec![false; grid.len()];
    if !grid.is_free(start) {
        return reachable;
    }
    let free = grid.free_cells();
    let width = grid.width() as usize;
    let height = grid.height() as usize;
    let first = grid.index(start);
    reachable[first] = true;
    let mut queue = vec![first];
    let mut head = 0;
    while let Some(&index) = queue.get(head) {
        head += 1;
        let (x, y) = (index % width, index / width);
        let neighbours = [
            (x + 1 < width).then(|| index + 1),
            (x > 0).then(|| index - 1),
            (y + 1 < height).then(|| index + width),
            (y > 0).then(|| index - width),
        ];
        for next in neighbours.into_iter().flatten() {
            if free[next] && !reachable[next] {
                reachable[next] = true;
                queue.push(next);
            }
        }
    }
    reachable
}

/// The result of one [`CoveragePlanner::cover`] call.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CoverageOutcome {
    /// [`Status::Found`] when the planner finished (for a complete planner, every reachable
    /// cell is covered: see `metrics`); [`Status::BudgetExhausted`] when the budget ran out,
    /// with the path so far. Coverage planners never report [`Status::NoPath`].
    pub status: Status,
    /// The coverage path, the start first; every move is a move of the planner's
    /// neighbourhood.
    pub path: Path,
    /// The stretches of `path` that return to a backtracking point, in order.
    pub returns: Vec<ReturnLeg>,
    /// Coverage, revisits and path metrics of `path` ([`CoverageMetrics::measure`]).
    pub metrics: CoverageMetrics,
    /// The planner's counters, in its order.
    pub counters: Counters,
    /// Set when the planner did not run: its per-cell state is over
    /// [`Budget::max_memory_mb`] ([`CoverageOutcome::over_memory`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub memory: Option<MemoryShortfall>,
}

impl CoverageOutcome {
    /// The outcome of a run refused because its per-cell state does not fit the budget's
    /// memory limit: [`Status::BudgetExhausted`], the path of the start alone, nothing
    /// measured (measuring would allocate per cell), and `counters` (the planner's, zero).
    pub fn over_memory(shortfall: MemoryShortfall, start: Cell, counters: Counters) -> Self {
        let path = Path::new(vec![start]);
        CoverageOutcome {
            status: Status::BudgetExhausted,
            metrics: CoverageMetrics::unmeasured(&path),
            path,
            returns: Vec::new(),
            counters,
            memory: Some(shortfall),
        }
    }
}

/// A coverage path planner: from a start cell, a path visiting every reachable free cell.
///
/// Like [`crate::Planner`]: built from its own validated config, may keep scratch buffers
/// between calls (hence `&mut self`), does no I/O, and returns counters that are a pure
/// function of (grid, start, config) whenever the budget has no wall-clock limit.
pub trait CoveragePlanner: Send + Sync {
    /// The planner's registry name, e.g. `coverage`.
    fn name(&self) -> &str;

    /// What the planner is: seeded or not, and the rule its paths obey.
    fn specs(&self) -> crate::specs::PlannerSpecs;

    /// Covers from `problem`'s start within `budget`. Never panics on a valid problem.
    fn cover(&mut self, problem: &CoverageProblem<'_>, budget: &Budget) -> CoverageOutcome;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn start_validation_names_the_cell() {
        let grid = Grid::from_ascii("..\n.#").unwrap();
        let err = CoverageProblem::new(&grid, Cell::new(1, 1)).unwrap_err();
        assert_eq!(err.to_string(), "start (1, 1) is blocked");
        let err = CoverageProblem::new(&grid, Cell::new(0, 2)).unwrap_err();
        assert_eq!(err.to_string(), "start (0, 2) is outside the 2x2 grid");
    }

    #[test]
    fn reachable_is_the_4_component() {
        // (2, 1) touches the start's component only diagonally, through a blocked corner.
        let grid = Grid::from_ascii(
            "
            ..#.
            .#..
            ##..
            ",
        )
        .unwrap();
        let r = reachable_cells(&grid, Cell::new(0, 0));
        assert_eq!(r.iter().filter(|&&x| x).count(), 3);
        let r = reachable_cells(&grid, Cell::new(3, 0));
        assert_eq!(r.iter().filter(|&&x| x).count(), 5);
        assert!(reachable_cells(&grid, Cell::new(1, 1)).iter().all(|&x| !x));
    }

    #[test]
    fn partial_coverage() {
        let grid = Grid::from_ascii("....").unwrap();
        let path = Path::new(vec![Cell::new(0, 0), Cell::new(1, 0)]);
        let m = CoverageMetrics::measure(&grid, Cell::new(0, 0), &path);
        assert_eq!((m.n_reachable, m.n_covered, m.percent), (4, 2, 50.0));
        assert!(!m.is_complete());
    }
}
