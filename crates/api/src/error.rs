//! Error types. Messages are lowercase without a trailing period.

use thiserror::Error;

use crate::grid::Cell;
use crate::moves::Connectivity;

/// Which end of a problem a [`ProblemError`] is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Endpoint {
    /// The start cell.
    Start,
    /// The goal cell.
    Goal,
}

impl std::fmt::Display for Endpoint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Endpoint::Start => "start",
            Endpoint::Goal => "goal",
        })
    }
}

/// A start or goal that cannot be planned from or to.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ProblemError {
    /// The cell lies outside the grid.
    #[error("{endpoint} {cell} is outside the {width}x{height} grid")]
    OutOfBounds {
        /// Start or goal.
        endpoint: Endpoint,
        /// The offending cell.
        cell: Cell,
        /// Grid width.
        width: u32,
        /// Grid height.
        height: u32,
    },
    /// The cell is an obstacle.
    #[error("{endpoint} {cell} is blocked")]
    Blocked {
        /// Start or goal.
        endpoint: Endpoint,
        /// The offending cell.
        cell: Cell,
    },
}

/// A grid that cannot be built.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum GridError {
    /// Zero width or height, or no rows at all.
    #[error("a grid needs at least one row and one column")]
    Empty,
    /// More than [`crate::Grid::MAX_CELLS`] cells.
    #[error("grid too large: at most 2^31 cells are supported")]
    TooLarge,
    /// The cell vector's length disagrees with width x height.
    #[error("expected {expected} cells, found {found}")]
    CellCount {
        /// width x height.
        expected: usize,
        /// Cells given.
        found: usize,
    },
    /// An ASCII row of another width than the first row (0-based row).
    #[error("row {row} has {found} cells, expected {expected}")]
    RaggedRow {
        /// 0-based row index.
        row: usize,
        /// Width of the first row.
        expected: usize,
        /// Width of this row.
        found: usize,
    },
    /// A cell weight of zero (weights are at least 1; 0-based cell index).
    #[error("cell {index} has weight 0; weights are integers from 1 to 65535")]
    ZeroWeight {
        /// Row-major index of the cell.
        index: usize,
    },
    /// A character other than `.` or `#` in an ASCII grid (0-based row and column).
    #[error("row {row}, column {column}: unexpected {found:?}, expected '.' or '#'")]
    UnknownCell {
        /// 0-based row index.
        row: usize,
        /// 0-based column index.
        column: usize,
        /// The character found.
        found: char,
    },
}

/// A neighbour order or move-set option that does not fit the neighbourhood.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum MoveOrderError {
    /// A token other than R, L, D, U, DR, DL, UR, UL.
    #[error("unknown direction {0:?}, expected one of R L D U DR DL UR UL")]
    UnknownToken(String),
    /// A direction listed twice.
    #[error("direction {0} is listed twice")]
    Repeated(&'static str),
    /// The order does not list every required direction.
    #[error("the order must list R, L, D and U once each (and, for {0}, either no diagonal or all of DR DL UR UL)")]
    Incomplete(Connectivity),
    /// A diagonal in a 4-connected order.
    #[error("order {0:?} lists a diagonal, but the neighbourhood is 4-connected")]
    DiagonalInFour(String),
    /// Corner cutting asked for a neighbourhood other than eight.
    #[error("corner cutting applies only to 8-connected moves, not {0}")]
    CornerCutting(Connectivity),
}

/// The first way in which a path breaks its rule (indices are 0-based positions in the path).
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum PathError {
    /// A path must have at least one cell.
    #[error("the path is empty")]
    Empty,
    /// A cell outside the grid.
    #[error("path cell {index} {cell} is outside the grid")]
    OutOfBounds {
        /// Position in the path.
        index: usize,
        /// The cell.
        cell: Cell,
    },
    /// A blocked cell.
    #[error("path cell {index} {cell} is blocked")]
    Blocked {
        /// Position in the path.
        index: usize,
        /// The cell.
        cell: Cell,
    },
    /// Two consecutive cells not joined by an allowed move or free segment.
    #[error("path move {index} from {from} to {to} is not allowed")]
    BadMove {
        /// Position of `to` in the path.
        index: usize,
        /// Previous cell.
        from: Cell,
        /// This cell.
        to: Cell,
    },
}
