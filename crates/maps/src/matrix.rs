//! 0/1 matrices (`.csv`): by default seed 000's equation (1), `1` traversable and `0` an
//! obstacle; [`CsvConvention::OneIsObstacle`] reads the more common opposite.

use std::fmt;

use planner_api::{Cell, Grid};

use crate::error::MapError;
use crate::text::{lines, show_char, show_token, unexpected, Origin, RowBlock};

/// Which value of a `.csv` matrix is an obstacle (the configs' `obstacle = 0` or `1`).
///
/// Both conventions are in use: seed 000's equation (1) says `m(x, y) = 1` denotes a
/// traversable cell (the default here, kept so that existing map sets read as before),
/// while most occupancy grids, seed 003's matrix among them, write `1` for an obstacle.
/// A problem whose start and goal are both blocked in one convention and free in the
/// other suggests the wrong one was chosen: see [`csv_inversion_hint`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum CsvConvention {
    /// `0` is an obstacle, `1` traversable (seed 000, equation (1); the default).
    #[default]
    ZeroIsObstacle,
    /// `1` is an obstacle, `0` traversable.
    OneIsObstacle,
}

impl CsvConvention {
    /// The convention whose obstacle value is `value` (`0` or `1`), `None` otherwise.
    pub fn from_obstacle_value(value: u8) -> Option<CsvConvention> {
        match value {
            0 => Some(CsvConvention::ZeroIsObstacle),
            1 => Some(CsvConvention::OneIsObstacle),
            _ => None,
        }
    }

    /// The value that is an obstacle: `0` or `1`.
    pub fn obstacle_value(self) -> u8 {
        match self {
            CsvConvention::ZeroIsObstacle => 0,
            CsvConvention::OneIsObstacle => 1,
        }
    }

    /// The other convention.
    pub fn other(self) -> CsvConvention {
        match self {
            CsvConvention::ZeroIsObstacle => CsvConvention::OneIsObstacle,
            CsvConvention::OneIsObstacle => CsvConvention::ZeroIsObstacle,
        }
    }
}

/// Why a `.csv` problem looks written for the other [`CsvConvention`]: its start and goal
/// are inside the grid and blocked in `convention`, so both are free in the other one
/// (every cell of a 0/1 matrix swaps between free and blocked).
///
/// Displays as one sentence for an error or warning, for example
/// `start (0, 0) and goal (2, 1) are blocked with obstacle = 0 but free with obstacle = 1:
/// the map looks written with 1 = obstacle`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct InversionHint {
    /// The convention the grid was read with.
    pub convention: CsvConvention,
    /// The start cell, blocked in `convention`.
    pub start: Cell,
    /// The goal cell, blocked in `convention`.
    pub goal: Cell,
}

impl fmt::Display for InversionHint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (this, other) = (
            self.convention.obstacle_value(),
            self.convention.other().obstacle_value(),
        );
        write!(
            f,
            "start {} and goal {} are blocked with obstacle = {this} but free with obstacle = {other}: the map looks written with {other} = obstacle",
            self.start, self.goal
        )
    }
}

/// Whether the problem `start` to `goal` on `grid`, a `.csv` matrix read with
/// `convention`, looks inverted: `Some` exactly when both cells are inside the grid and
/// blocked, that is, the problem is invalid in this convention and valid in the other.
/// A problem that is invalid in both (a cell outside the grid, or one blocked cell and one
/// free) gives `None`.
///
/// ```
/// use planner_api::Cell;
/// use planner_maps::{csv_inversion_hint, parse_matrix, CsvConvention};
///
/// // Written with 1 = obstacle, read with the default 0 = obstacle.
/// let grid = parse_matrix("0,0,1\n1,0,0\n", "m.csv").unwrap();
/// let (start, goal) = (Cell::new(0, 0), Cell::new(2, 1));
/// assert!(!grid.is_free(start) && !grid.is_free(goal));
/// let hint = csv_inversion_hint(&grid, CsvConvention::ZeroIsObstacle, start, goal).unwrap();
/// assert_eq!(
///     hint.to_string(),
///     "start (0, 0) and goal (2, 1) are blocked with obstacle = 0 but free with obstacle = 1: \
///      the map looks written with 1 = obstacle"
/// );
/// // A free start is no sign of inversion.
/// assert_eq!(csv_inversion_hint(&grid, CsvConvention::ZeroIsObstacle, Cell::new(2, 0), goal), None);
/// ```
pub fn csv_inversion_hint(
    grid: &Grid,
    convention: CsvConvention,
    start: Cell,
    goal: Cell,
) -> Option<InversionHint> {
    let blocked = |cell: Cell| grid.contains(cell) && !grid.is_free(cell);
    (blocked(start) && blocked(goal)).then_some(InversionHint {
        convention,
        start,
        goal,
    })
}

/// Parses a 0/1 matrix: one row per line, values `0` or `1` separated by a comma and/or
/// whitespace (`1,0,1`, `1 0 1` and `1, 0, 1` all work).
///
/// **`1` is traversable and `0` is an obstacle** ([`CsvConvention::ZeroIsObstacle`]),
/// exactly as seed 000 equation (1) (`m(x, y) = 1` denotes a traversable cell). This is
/// the opposite of many occupancy conventions, including seed 003's own matrix
/// (1 = obstacle): read those with [`CsvConvention::OneIsObstacle`] through
/// [`crate::MapFormat::parse_with`] or [`crate::read_map_with`].
///
/// Lines whose first non-blank character is `#` are comments; blank lines may come before
/// and after the rows, not between them. Errors, with line and column, on any other value,
/// an empty value (`1,,0` or a trailing comma), a ragged row, a blank line between rows,
/// no rows at all, or more than [`crate::DEFAULT_MAX_CELLS`] cells.
pub fn parse_matrix(text: &str, origin: &str) -> Result<Grid, MapError> {
    parse(
        text,
        origin,
        CsvConvention::ZeroIsObstacle,
        crate::DEFAULT_MAX_CELLS,
    )
}

/// [`parse_matrix`] in `convention` with at most `max_cells` cells.
pub(crate) fn parse(
    text: &str,
    origin: &str,
    convention: CsvConvention,
    max_cells: u64,
) -> Result<Grid, MapError> {
    let o = Origin(origin);
    let one_is_free = convention == CsvConvention::ZeroIsObstacle;
    let mut free = Vec::new();
    let mut rows = RowBlock::new(max_cells);
    for (number, line) in lines(text) {
        let body = line.trim();
        if body.starts_with('#') {
            continue;
        }
        if body.is_empty() {
            rows.blank(number);
            continue;
        }
        rows.start_row(o, number, "matrix")?;
        let before = free.len();
        let end_column = parse_row(o, number, line, one_is_free, &mut free)?;
        let len = free.len() - before;
        // A width error points at the first value too many, or after the last value.
        rows.row(o, number, len, |expected| {
            if len > expected {
                value_column(line, expected)
            } else {
                end_column
            }
        })?;
    }
    rows.grid(o, text, free, "rows of '0' and '1'")
}

/// Parses one row's values into `free`; returns the column just after the last value.
fn parse_row(
    o: Origin<'_>,
    number: usize,
    line: &str,
    one_is_free: bool,
    free: &mut Vec<bool>,
) -> Result<usize, MapError> {
    let chars: Vec<char> = line.chars().collect();
    let mut at = 0;
    let skip_spaces = |at: &mut usize| {
        while chars.get(*at).is_some_and(|c| c.is_whitespace()) {
            *at += 1;
        }
    };
    skip_spaces(&mut at);
    loop {
        let from = at;
        while chars
            .get(at)
            .is_some_and(|&c| c != ',' && !c.is_whitespace())
        {
            at += 1;
        }
        let value: String = chars[from..at].iter().collect();
        match value.as_str() {
            "1" => free.push(one_is_free),
            "0" => free.push(!one_is_free),
            "" => {
                let found = chars
                    .get(at)
                    .map_or_else(|| "end of line".to_owned(), |&c| show_char(c));
                return Err(o.at(number, at + 1, unexpected("'0' or '1'", found)));
            }
            other => {
                return Err(o.at(
                    number,
                    from + 1,
                    unexpected("'0' or '1'", show_token(other)),
                ))
            }
        }
        let end_column = at + 1;
        skip_spaces(&mut at);
        match chars.get(at) {
            None => return Ok(end_column),
            Some(',') => {
                at += 1;
                skip_spaces(&mut at);
            }
            Some(_) => {}
        }
    }
}

/// The 1-based column of the value with 0-based index `index` in a row that parsed.
fn value_column(line: &str, index: usize) -> usize {
    let mut seen = 0;
    let mut in_value = false;
    for (column, ch) in line.chars().enumerate() {
        let separator = ch == ',' || ch.is_whitespace();
        if !separator && !in_value {
            if seen == index {
                return column + 1;
            }
            seen += 1;
        }
        in_value = !separator;
    }
    line.chars().count() + 1
}
