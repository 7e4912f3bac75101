//! 0/1 matrices (`.csv`), seed 000 equation (1): `1` traversable, `0` obstacle.

use planner_api::Grid;

use crate::error::MapError;
use crate::text::{lines, show_char, show_token, unexpected, Origin, RowBlock};

/// Parses a 0/1 matrix: one row per line, values `0` or `1` separated by a comma and/or
/// whitespace (`1,0,1`, `1 0 1` and `1, 0, 1` all work).
///
/// **`1` is traversable and `0` is an obstacle**, exactly as seed 000 equation (1)
/// (`m(x, y) = 1` denotes a traversable cell). This is the opposite of many occupancy
/// conventions, including seed 003's own matrix (1 = obstacle): invert such data first.
///
/// Lines whose first non-blank character is `#` are comments; blank lines may come before
/// and after the rows, not between them. Errors, with line and column, on any other value,
/// an empty value (`1,,0` or a trailing comma), a ragged row, a blank line between rows, or
/// no rows at all.
pub fn parse_matrix(text: &str, origin: &str) -> Result<Grid, MapError> {
    let o = Origin(origin);
    let mut free = Vec::new();
    let mut rows = RowBlock::default();
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
        let end_column = parse_row(o, number, line, &mut free)?;
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
            "1" => free.push(true),
            "0" => free.push(false),
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
