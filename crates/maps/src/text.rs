//! Line splitting, tokens, numbers and error positions shared by the parsers.

use planner_api::{Grid, GridError};

use crate::error::{MapError, MapErrorKind};

/// The lines of `text` with their 1-based numbers. A UTF-8 byte-order mark is skipped, and
/// a `\r` before each `\n` is dropped, so CRLF and LF files read alike. A text ending with
/// `\n` yields a final empty line (where the end of file is).
pub(crate) fn lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    text.split('\n')
        .enumerate()
        .map(|(index, line)| (index + 1, line.strip_suffix('\r').unwrap_or(line)))
}

/// Whether a line holds only whitespace.
pub(crate) fn is_blank(line: &str) -> bool {
    line.chars().all(char::is_whitespace)
}

/// Number of characters in `s`: columns are counted in characters, not bytes.
pub(crate) fn width(s: &str) -> usize {
    s.chars().count()
}

/// The rest of `line` from its 1-based character `column` on (empty past its end): the
/// columns of [`tokens`] are characters, not byte offsets.
pub(crate) fn from_column(line: &str, column: usize) -> &str {
    let byte = line
        .char_indices()
        .nth(column.saturating_sub(1))
        .map_or(line.len(), |(byte, _)| byte);
    &line[byte..]
}

/// The whitespace-separated tokens of `line` with their 1-based columns.
pub(crate) fn tokens(line: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start: Option<(usize, usize)> = None; // (byte, column)
    let mut column = 0;
    for (byte, ch) in line.char_indices() {
        column += 1;
        match (ch.is_whitespace(), start) {
            (true, Some((from, col))) => {
                out.push((col, &line[from..byte]));
                start = None;
            }
            (false, None) => start = Some((byte, column)),
            _ => {}
        }
    }
    if let Some((from, col)) = start {
        out.push((col, &line[from..]));
    }
    out
}

/// A character quoted for a message: `'Q'`, `'\t'`.
pub(crate) fn show_char(ch: char) -> String {
    format!("'{}'", ch.escape_debug())
}

/// A token quoted for a message, shortened to 24 characters.
pub(crate) fn show_token(token: &str) -> String {
    const MAX: usize = 24;
    let mut shown: String = token.chars().take(MAX).collect::<String>();
    if token.chars().nth(MAX).is_some() {
        shown.push_str("...");
    }
    format!("'{}'", shown.escape_debug())
}

/// The [`MapErrorKind::Unexpected`] kind.
pub(crate) fn unexpected(expected: impl Into<String>, found: impl Into<String>) -> MapErrorKind {
    MapErrorKind::Unexpected {
        expected: expected.into(),
        found: found.into(),
    }
}

/// Parses a non-negative decimal integer made of ASCII digits only (no sign, no spaces).
/// `what` names the number in messages.
pub(crate) fn parse_u32(token: &str, what: &'static str) -> Result<u32, MapErrorKind> {
    if token.is_empty() {
        return Err(unexpected(
            format!("an integer for {what}"),
            "an empty field",
        ));
    }
    if let Some(digits) = token.strip_prefix('-') {
        if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) {
            return Err(unexpected(
                format!("a non-negative integer for {what}"),
                show_token(token),
            ));
        }
    }
    if !token.bytes().all(|b| b.is_ascii_digit()) {
        return Err(unexpected(
            format!("an integer for {what}"),
            show_token(token),
        ));
    }
    // Only ASCII digits remain, so the only possible failure is overflow.
    token
        .parse::<u32>()
        .map_err(|_| MapErrorKind::NumberTooLarge {
            what,
            text: token.to_owned(),
        })
}

/// Where errors go: the origin (file name) of the text being parsed.
#[derive(Clone, Copy)]
pub(crate) struct Origin<'a>(pub(crate) &'a str);

impl Origin<'_> {
    /// An error at `line`, `column`.
    pub(crate) fn at(self, line: usize, column: usize, kind: MapErrorKind) -> MapError {
        MapError::new(self.0, line, column, kind)
    }
}

/// The position of the end of the text: the last line's number and the column after it.
pub(crate) fn end_of_file(text: &str) -> (usize, usize) {
    lines(text)
        .last()
        .map_or((1, 1), |(number, line)| (number, width(line) + 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_have_columns() {
        assert_eq!(tokens("  ab\tc  d"), vec![(3, "ab"), (6, "c"), (9, "d")]);
        assert_eq!(tokens(""), vec![]);
        assert_eq!(tokens("é x"), vec![(1, "é"), (3, "x")]);
        assert_eq!(from_column("é x", 3), "x");
        assert_eq!(from_column("é x", 1), "é x");
        assert_eq!(from_column("é x", 4), "");
    }

    #[test]
    fn lines_strip_cr_and_bom() {
        let got: Vec<_> = lines("\u{feff}a\r\nb\n").collect();
        assert_eq!(got, vec![(1, "a"), (2, "b"), (3, "")]);
        assert_eq!(end_of_file("ab\ncd"), (2, 3));
        assert_eq!(end_of_file("ab\n"), (2, 1));
    }

    #[test]
    fn numbers() {
        assert_eq!(parse_u32("4294967295", "x"), Ok(u32::MAX));
        assert!(matches!(
            parse_u32("4294967296", "x"),
            Err(MapErrorKind::NumberTooLarge { .. })
        ));
        assert!(parse_u32("+1", "x").is_err());
        assert!(parse_u32("-", "x").is_err());
    }
}

/// The body of a grid file (seed 003 `.txt`, `.csv`): one block of rows, each as wide as
/// the first, with blank lines allowed before and after the block but not inside it.
#[derive(Debug)]
pub(crate) struct RowBlock {
    /// The most cells the block may have ([`crate::ReadOptions::max_cells`]).
    max_cells: u64,
    /// (width, line) of the first row.
    first: Option<(usize, usize)>,
    n_rows: usize,
    /// The first blank line after a row.
    blank_after: Option<usize>,
}

impl RowBlock {
    /// An empty block that may grow to `max_cells` cells.
    pub(crate) fn new(max_cells: u64) -> RowBlock {
        RowBlock {
            max_cells,
            first: None,
            n_rows: 0,
            blank_after: None,
        }
    }

    /// Notes that line `number` is blank.
    pub(crate) fn blank(&mut self, number: usize) {
        if self.n_rows > 0 && self.blank_after.is_none() {
            self.blank_after = Some(number);
        }
    }

    /// Checks that a row may start on line `number`: no blank line since the last row.
    /// `what` names the rows in the message ("map", "matrix").
    pub(crate) fn start_row(
        &self,
        o: Origin<'_>,
        number: usize,
        what: &str,
    ) -> Result<(), MapError> {
        match self.blank_after {
            Some(blank) => Err(o.at(
                blank,
                1,
                unexpected(
                    format!("no blank line between {what} rows (rows continue on line {number})"),
                    "a blank line",
                ),
            )),
            None => Ok(()),
        }
    }

    /// Records the row on line `number`, `len` cells wide; a width other than the first
    /// row's is an error at `column(expected_width)`.
    pub(crate) fn row(
        &mut self,
        o: Origin<'_>,
        number: usize,
        len: usize,
        column: impl FnOnce(usize) -> usize,
    ) -> Result<(), MapError> {
        match self.first {
            None => self.first = Some((len, number)),
            Some((expected, first)) if expected != len => {
                return Err(o.at(
                    number,
                    column(expected),
                    MapErrorKind::RowWidth {
                        expected,
                        found: len,
                        reference: format!("as in the first row, line {first}"),
                    },
                ));
            }
            Some(_) => {}
        }
        self.n_rows += 1;
        let (width, height) = (len as u64, self.n_rows as u64);
        if width.saturating_mul(height) > self.max_cells {
            return Err(o.at(
                number,
                1,
                MapErrorKind::TooManyCells {
                    width,
                    height,
                    max_cells: self.max_cells,
                },
            ));
        }
        Ok(())
    }

    /// The grid of the rows' row-major `free` flags. Without any row, an error at the end
    /// of `text` saying that `expected` rows were expected.
    pub(crate) fn grid(
        &self,
        o: Origin<'_>,
        text: &str,
        free: Vec<bool>,
        expected: &str,
    ) -> Result<Grid, MapError> {
        let Some((row_width, first)) = self.first else {
            let (line, column) = end_of_file(text);
            return Err(o.at(line, column, unexpected(expected, "end of file")));
        };
        let too_large = || o.at(first, 1, MapErrorKind::Grid(GridError::TooLarge));
        let w = u32::try_from(row_width).map_err(|_| too_large())?;
        let h = u32::try_from(self.n_rows).map_err(|_| too_large())?;
        Grid::from_free_cells(w, h, free).map_err(|e| o.at(first, 1, MapErrorKind::Grid(e)))
    }
}
