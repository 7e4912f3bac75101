//! The seed-003 text format (`.txt`): `#` comment header with start-goal pairs, rows of
//! `.` and `X`.

use planner_api::Cell;

use crate::error::{MapError, MapErrorKind};
use crate::text::{lines, parse_u32, show_char, show_token, unexpected, width, Origin, RowBlock};
use crate::{MapFile, MapFormat, ProblemSpec};

/// Parses the seed-003 text format into a grid and its start-goal pairs.
///
/// - Lines whose first non-blank character is `#` are comments. A comment of the form
///   `# Start: (x,y) Goal: (x,y)` or `# 1. Start: (x,y) | Goal: (x,y)` is a start-goal
///   pair: an optional number followed by `.` or `)`, then `Start:`, a coordinate pair,
///   an optional `|`, `Goal:` and a coordinate pair, with any spaces between the parts.
///   Pairs are kept in file order (the numbers are ignored; map2.txt numbers all its
///   pairs "1."). Coordinates are `(x, y)` = (column, row). Any other comment is ignored.
/// - Every other non-blank line is a map row of `.` (free) and `X` (obstacle); all rows
///   as wide as the first. Trailing whitespace is ignored; blank lines may come before
///   and after the rows, not between them.
///
/// Pairs are not checked against the grid: a pair on an obstacle or outside the map is a
/// problem specification like any other, and [`planner_api::Problem::new`] rejects it
/// naming the cell. Errors, with line and column, on a malformed pair line, a symbol
/// other than `.` or `X`, a ragged row, a blank line between rows, no rows at all, or more
/// than [`crate::DEFAULT_MAX_CELLS`] cells (see [`crate::ReadOptions::max_cells`]).
pub fn parse_seed003(text: &str, origin: &str) -> Result<MapFile, MapError> {
    parse(text, origin, crate::DEFAULT_MAX_CELLS)
}

/// [`parse_seed003`] with at most `max_cells` cells.
pub(crate) fn parse(text: &str, origin: &str, max_cells: u64) -> Result<MapFile, MapError> {
    let o = Origin(origin);
    let mut problems = Vec::new();
    let mut free = Vec::new();
    let mut rows = RowBlock::new(max_cells);
    for (number, raw) in lines(text) {
        let line = raw.trim_end();
        let body = line.trim_start();
        if body.starts_with('#') {
            if let Some(spec) = parse_pair(o, number, line)? {
                problems.push(spec);
            }
            continue;
        }
        if body.is_empty() {
            rows.blank(number);
            continue;
        }
        rows.start_row(o, number, "map")?;
        let len = width(line);
        rows.row(o, number, len, |expected| len.min(expected) + 1)?;
        for (index, symbol) in line.chars().enumerate() {
            match symbol {
                '.' => free.push(true),
                'X' => free.push(false),
                other => {
                    return Err(o.at(
                        number,
                        index + 1,
                        unexpected("'.' or 'X'", show_char(other)),
                    ))
                }
            }
        }
    }
    let grid = rows.grid(o, text, free, "map rows of '.' and 'X'")?;
    Ok(MapFile {
        grid,
        problems,
        format: MapFormat::Seed003,
        frame: None,
        frame_error: None,
        unknown: None,
    })
}

/// A cursor over one comment line, with 1-based columns for errors.
struct Cursor<'a> {
    o: Origin<'a>,
    number: usize,
    chars: Vec<char>,
    at: usize,
}

impl Cursor<'_> {
    fn peek(&self) -> Option<char> {
        self.chars.get(self.at).copied()
    }

    fn skip_spaces(&mut self) {
        while self.peek().is_some_and(char::is_whitespace) {
            self.at += 1;
        }
    }

    fn rest_starts_with(&self, word: &str) -> bool {
        (self.at..)
            .zip(word.chars())
            .all(|(index, expected)| self.chars.get(index) == Some(&expected))
    }

    /// What is at the cursor, for messages.
    fn found_char(&self) -> String {
        self.peek()
            .map_or_else(|| "end of line".to_owned(), show_char)
    }

    /// The non-space word at the cursor, for messages.
    fn found_word(&self) -> String {
        let word: String = self.chars[self.at.min(self.chars.len())..]
            .iter()
            .take_while(|c| !c.is_whitespace())
            .collect();
        if word.is_empty() {
            "end of line".to_owned()
        } else {
            show_token(&word)
        }
    }

    fn error(&self, kind: MapErrorKind) -> MapError {
        self.o.at(self.number, self.at + 1, kind)
    }

    fn expect_char(&mut self, expected: char) -> Result<(), MapError> {
        if self.peek() == Some(expected) {
            self.at += 1;
            Ok(())
        } else {
            Err(self.error(unexpected(show_char(expected), self.found_char())))
        }
    }

    fn integer(&mut self, what: &'static str) -> Result<u32, MapError> {
        let from = self.at;
        if self.peek() == Some('-') {
            self.at += 1;
        }
        while self.peek().is_some_and(|c| c.is_ascii_digit()) {
            self.at += 1;
        }
        let token: String = self.chars[from..self.at].iter().collect();
        if token.is_empty() || token == "-" {
            self.at = from;
            return Err(self.error(unexpected(
                format!("an integer for {what}"),
                self.found_char(),
            )));
        }
        parse_u32(&token, what).map_err(|kind| self.o.at(self.number, from + 1, kind))
    }

    /// `(x, y)` with optional spaces.
    fn cell(&mut self, x_name: &'static str, y_name: &'static str) -> Result<Cell, MapError> {
        self.skip_spaces();
        self.expect_char('(')?;
        self.skip_spaces();
        let x = self.integer(x_name)?;
        self.skip_spaces();
        self.expect_char(',')?;
        self.skip_spaces();
        let y = self.integer(y_name)?;
        self.skip_spaces();
        self.expect_char(')')?;
        Ok(Cell::new(x, y))
    }
}

/// A start-goal pair from a comment line, or `None` for any other comment.
fn parse_pair(o: Origin<'_>, number: usize, line: &str) -> Result<Option<ProblemSpec>, MapError> {
    let chars: Vec<char> = line.chars().collect();
    let Some(hash) = chars.iter().position(|&c| c == '#') else {
        return Ok(None);
    };
    let mut c = Cursor {
        o,
        number,
        chars,
        at: hash + 1,
    };
    c.skip_spaces();
    // Optional numbering: digits followed by '.' or ')'.
    let before = c.at;
    while c.peek().is_some_and(|ch| ch.is_ascii_digit()) {
        c.at += 1;
    }
    if c.at > before && matches!(c.peek(), Some('.' | ')')) {
        c.at += 1;
        c.skip_spaces();
    } else {
        c.at = before;
    }
    if !c.rest_starts_with("Start:") {
        return Ok(None);
    }
    c.at += "Start:".len();
    let start = c.cell("start x", "start y")?;
    c.skip_spaces();
    if c.peek() == Some('|') {
        c.at += 1;
        c.skip_spaces();
    }
    if !c.rest_starts_with("Goal:") {
        return Err(c.error(unexpected("'Goal:'", c.found_word())));
    }
    c.at += "Goal:".len();
    let goal = c.cell("goal x", "goal y")?;
    c.skip_spaces();
    if c.peek().is_some() {
        return Err(c.error(unexpected("end of line after the goal", c.found_word())));
    }
    Ok(Some(ProblemSpec {
        start,
        goal,
        line: number,
    }))
}
