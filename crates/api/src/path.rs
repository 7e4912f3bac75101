//! Paths, their quality metrics (seed 000 section 2.4) and their validity.
//!
//! # Metrics
//! For a path of `L` cells `n_0 .. n_{L-1}` with moves `Δ_i = n_i - n_{i-1}`:
//! - `steps`, D = L - 1 (equation 22);
//! - `turns`, T = the number of `i >= 2` with `Δ_i ≠ Δ_{i-1}` (equation 24);
//! - `score` = Σ c_i with c_i = 1 for the first or a straight move and 2 for a move that
//!   turns (equations 25-26), so `score = D + T`;
//! - `length`, the Euclidean length of the polyline through the cell centres
//!   (seeds 002 and 003).
//!
//! For moves longer than one cell (any-angle segments) two moves are "the same direction"
//! when their vectors are positive multiples of each other, so a straight line split into
//! several segments has no turns.
//!
//! # Ranking
//! [`PathRank`] orders paths lexicographically by (D, then T, then Score), the paper's best-path
//! rule; Backtracking, A* tie-breaking studies and later planners all select with it.

use std::cmp::Ordering;

use serde::{Deserialize, Serialize};

use crate::error::PathError;
use crate::grid::{Cell, Grid};
use crate::moves::{segment_is_free, MoveSet};

/// A path as the sequence of cells it visits, start first.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Path {
    cells: Vec<Cell>,
}

/// Seed 000's path-quality metrics plus the Euclidean length.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PathMetrics {
    /// D: number of moves, `L - 1`.
    pub steps: u64,
    /// T: number of direction changes between consecutive moves.
    pub turns: u64,
    /// Σ c_i: 1 per straight or first move, 2 per turning move (`steps + turns`).
    pub score: u64,
    /// Euclidean length of the polyline through the cell centres.
    pub length: f64,
}

/// The lexicographic order (D, then T, then Score): less is better.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct PathRank {
    /// D.
    pub steps: u64,
    /// T.
    pub turns: u64,
    /// Score.
    pub score: u64,
}

/// The rule a path's consecutive cells must satisfy in [`Path::validate`].
#[derive(Debug, Clone, Copy)]
pub enum PathRule<'a> {
    /// Every pair of consecutive cells is joined by a move of this set that is valid on
    /// the grid (including its corner and segment checks).
    Moves(&'a MoveSet),
    /// Any-angle: every segment between consecutive waypoints crosses no blocked cell
    /// (exact traversal, see [`crate::moves::for_each_segment_cell`]).
    AnyAngle,
}

impl Path {
    /// A path through `cells`, start first. Not validated; see [`Path::validate`].
    pub fn new(cells: Vec<Cell>) -> Path {
        Path { cells }
    }

    /// The cells, start first.
    pub fn cells(&self) -> &[Cell] {
        &self.cells
    }

    /// Consumes the path and returns its cells.
    pub fn into_cells(self) -> Vec<Cell> {
        self.cells
    }

    /// Number of cells, `L`.
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    /// Whether the path has no cell at all.
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// The first cell, if any.
    pub fn start(&self) -> Option<Cell> {
        self.cells.first().copied()
    }

    /// The last cell, if any.
    pub fn goal(&self) -> Option<Cell> {
        self.cells.last().copied()
    }

    /// D, T, Score and Euclidean length (module docs). An empty or one-cell path has all zero.
    pub fn metrics(&self) -> PathMetrics {
        let mut turns = 0;
        let mut length = 0.0;
        let mut previous: Option<(i64, i64)> = None;
        for pair in self.cells.windows(2) {
            let delta = delta(pair[0], pair[1]);
            length += pair[0].euclidean(pair[1]);
            if let Some(previous) = previous {
                if !same_direction(previous, delta) {
                    turns += 1;
                }
            }
            previous = Some(delta);
        }
        let steps = self.cells.len().saturating_sub(1) as u64;
        PathMetrics {
            steps,
            turns,
            score: steps + turns,
            length,
        }
    }

    /// The (D, T, Score) rank of this path.
    pub fn rank(&self) -> PathRank {
        self.metrics().rank()
    }

    /// Checks that the path is non-empty, every cell is in bounds and free, and every pair
    /// of consecutive cells satisfies `rule`. Returns the first violation.
    pub fn validate(&self, grid: &Grid, rule: PathRule<'_>) -> Result<(), PathError> {
        if self.cells.is_empty() {
            return Err(PathError::Empty);
        }
        for (index, &cell) in self.cells.iter().enumerate() {
            if !grid.contains(cell) {
                return Err(PathError::OutOfBounds { index, cell });
            }
            if !grid.is_free(cell) {
                return Err(PathError::Blocked { index, cell });
            }
        }
        for (index, pair) in self.cells.windows(2).enumerate() {
            let (from, to) = (pair[0], pair[1]);
            let ok = match rule {
                PathRule::Moves(moves) => moves
                    .find(from, to)
                    .is_some_and(|mv| moves.apply(grid, from, mv) == Some(to)),
                PathRule::AnyAngle => from != to && segment_is_free(grid, from, to),
            };
            if !ok {
                return Err(PathError::BadMove {
                    index: index + 1,
                    from,
                    to,
                });
            }
        }
        Ok(())
    }
}

/// Appends to `cells` the cells after `from` on the way to `to`, `to` included: diagonal
/// steps while both offsets remain, then straight ones. This is how a jump of Jump Point
/// Search reaches its jump point, so JPS planners expand their parent chains with it.
///
/// ```
/// use planner_api::{push_octile_leg, Cell};
///
/// let mut cells = vec![Cell::new(1, 1)];
/// push_octile_leg(&mut cells, Cell::new(1, 1), Cell::new(4, 0));
/// assert_eq!(cells, [Cell::new(1, 1), Cell::new(2, 0), Cell::new(3, 0), Cell::new(4, 0)]);
/// ```
pub fn push_octile_leg(cells: &mut Vec<Cell>, from: Cell, to: Cell) {
    let (sx, sy) = (to.x.cmp(&from.x) as i32, to.y.cmp(&from.y) as i32);
    let (ax, ay) = (to.x.abs_diff(from.x), to.y.abs_diff(from.y));
    let (mut x, mut y) = (from.x, from.y);
    for _ in 0..ax.min(ay) {
        (x, y) = (x.wrapping_add_signed(sx), y.wrapping_add_signed(sy));
        cells.push(Cell::new(x, y));
    }
    let (sx, sy) = if ax > ay { (sx, 0) } else { (0, sy) };
    for _ in 0..ax.abs_diff(ay) {
        (x, y) = (x.wrapping_add_signed(sx), y.wrapping_add_signed(sy));
        cells.push(Cell::new(x, y));
    }
}

impl From<Vec<Cell>> for Path {
    fn from(cells: Vec<Cell>) -> Path {
        Path { cells }
    }
}

impl PathMetrics {
    /// The (D, T, Score) rank.
    pub fn rank(&self) -> PathRank {
        PathRank {
            steps: self.steps,
            turns: self.turns,
            score: self.score,
        }
    }
}

impl PathRank {
    /// Whether `self` is strictly better than `other` (smaller in the lexicographic order).
    pub fn is_better_than(&self, other: &PathRank) -> bool {
        self.cmp(other) == Ordering::Less
    }
}

fn delta(a: Cell, b: Cell) -> (i64, i64) {
    (
        i64::from(b.x) - i64::from(a.x),
        i64::from(b.y) - i64::from(a.y),
    )
}

/// Whether two move vectors point the same way (positive multiples of each other).
fn same_direction(a: (i64, i64), b: (i64, i64)) -> bool {
    a.0 * b.1 == a.1 * b.0 && a.0 * b.0 + a.1 * b.1 > 0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::moves::{Connectivity, MoveSet};

    fn path(cells: &[(u32, u32)]) -> Path {
        Path::new(cells.iter().map(|&c| c.into()).collect())
    }

    fn check(cells: &[(u32, u32)], expect: (u64, u64, u64)) {
        let m = path(cells).metrics();
        assert_eq!((m.steps, m.turns, m.score), expect, "{cells:?}");
    }

    #[test]
    fn metrics_by_hand() {
        check(&[], (0, 0, 0));
        check(&[(0, 0)], (0, 0, 0));
        check(&[(0, 0), (1, 0)], (1, 0, 1));
        // Right, right, down, down: one turn; score 1 + 1 + 2 + 1.
        check(&[(0, 0), (1, 0), (2, 0), (2, 1), (2, 2)], (4, 1, 5));
        // A staircase turns at every move after the first.
        check(&[(0, 0), (1, 0), (1, 1), (2, 1), (2, 2)], (4, 3, 7));
        // Any-angle: a straight line in two segments has no turn; a reversal is a turn.
        check(&[(0, 0), (2, 1), (6, 3)], (2, 0, 2));
        check(&[(0, 0), (2, 0), (1, 0)], (2, 1, 3));
        let m = path(&[(0, 0), (3, 4), (3, 0)]).metrics();
        assert_eq!(m.length, 9.0);
    }

    #[test]
    fn rank_is_lexicographic() {
        let a = PathRank {
            steps: 10,
            turns: 5,
            score: 15,
        };
        let b = PathRank {
            steps: 10,
            turns: 4,
            score: 14,
        };
        let c = PathRank {
            steps: 9,
            turns: 8,
            score: 17,
        };
        assert!(b.is_better_than(&a));
        assert!(c.is_better_than(&b));
        assert!(!a.is_better_than(&a));
    }

    #[test]
    fn validation() {
        let grid = Grid::from_ascii(
            "
            ...
            .#.
            ...
            ",
        )
        .unwrap();
        let four = MoveSet::standard(Connectivity::Four);
        let eight = MoveSet::standard(Connectivity::Eight);
        let good = path(&[(0, 0), (1, 0), (2, 0), (2, 1)]);
        assert_eq!(good.validate(&grid, PathRule::Moves(&four)), Ok(()));
        assert_eq!(
            path(&[(0, 0), (1, 1)]).validate(&grid, PathRule::Moves(&eight)),
            Err(PathError::Blocked {
                index: 1,
                cell: Cell::new(1, 1)
            })
        );
        assert_eq!(
            path(&[(0, 0), (2, 0), (2, 1)]).validate(&grid, PathRule::Moves(&four)),
            Err(PathError::BadMove {
                index: 1,
                from: Cell::new(0, 0),
                to: Cell::new(2, 0)
            })
        );
        // Corner cut: (1,0) -> (0,1) passes between free (0,0) and blocked (1,1).
        assert!(path(&[(1, 0), (0, 1)])
            .validate(&grid, PathRule::Moves(&eight))
            .is_err());
        assert_eq!(
            path(&[(0, 0), (2, 0), (2, 2)]).validate(&grid, PathRule::AnyAngle),
            Ok(())
        );
        assert!(path(&[(0, 0), (2, 2)])
            .validate(&grid, PathRule::AnyAngle)
            .is_err());
        assert_eq!(
            path(&[(0, 0), (3, 0)]).validate(&grid, PathRule::AnyAngle),
            Err(PathError::OutOfBounds {
                index: 1,
                cell: Cell::new(3, 0)
            })
        );
        assert_eq!(
            Path::default().validate(&grid, PathRule::AnyAngle),
            Err(PathError::Empty)
        );
    }
}
