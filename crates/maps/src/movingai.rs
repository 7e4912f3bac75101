//! Moving AI `.map` files: reader and writer.

use planner_api::{CostRule, Grid, GridError};

use crate::costs::TerrainWeights;

use crate::error::{MapError, MapErrorKind};
use crate::text::{
    end_of_file, is_blank, lines, parse_u32, show_char, show_token, tokens, unexpected, width,
    Origin,
};

/// The cell symbols a Moving AI map may contain, as listed in messages.
const SYMBOLS: &str = "one of '.', 'G', 'S' (passable) or '@', 'O', 'T', 'W' (blocked)";

/// Whether a Moving AI map symbol is passable for this crate, or `None` for an unknown symbol.
///
/// `.` (ground), `G` (ground) and `S` (swamp) are passable; `@` and `O` (out of bounds),
/// `T` (trees) and `W` (water) are blocked. See the crate docs for the `S` and `W` choice.
pub fn movingai_passable(symbol: char) -> Option<bool> {
    match symbol {
        '.' | 'G' | 'S' => Some(true),
        '@' | 'O' | 'T' | 'W' => Some(false),
        _ => None,
    }
}

/// [`parse`], then weights by terrain letter ([`crate::costs`]): ground `.` and `G` (and
/// every blocked cell) 1, swamp `S` `terrain.swamp`, water `W` `terrain.water` and free when
/// given (else blocked, the benchmark's rule).
pub(crate) fn parse_terrain(
    text: &str,
    origin: &str,
    max_cells: u64,
    terrain: TerrainWeights,
    rule: CostRule,
) -> Result<Grid, MapError> {
    let mut grid = parse(text, origin, max_cells)?;
    let (w, h) = (grid.width() as usize, grid.height() as usize);
    // The text parsed: its rows are the `h` lines after the first line whose first token
    // is `map` (no other header key starts with it), each of `w` symbols.
    let rows = lines(text)
        .skip_while(|(_, line)| tokens(line).first().map(|&(_, t)| t) != Some("map"))
        .skip(1)
        .take(h);
    let mut weights = Vec::with_capacity(w * h);
    let mut water = Vec::new();
    for (_, line) in rows {
        for symbol in line.chars().take(w) {
            let index = weights.len();
            weights.push(match symbol {
                'S' => terrain.swamp,
                'W' => match terrain.water {
                    Some(weight) => {
                        water.push(index);
                        weight
                    }
                    None => 1,
                },
                _ => 1,
            });
        }
    }
    for index in water {
        let cell = grid.cell(index);
        grid.set_free(cell, true);
    }
    grid.with_weights(weights, rule)
        .map_err(|e| MapError::new(origin, 0, 0, MapErrorKind::Grid(e)))
}

/// Parses the text of a Moving AI `.map` file into a grid.
///
/// The header is the keys `type octile`, `height H` and `width W` in any order (each once;
/// blank lines allowed), ended by a line `map`; then exactly `H` rows of `W` symbols follow
/// (see [`movingai_passable`]), optionally followed by blank lines. CRLF line ends are
/// accepted. `origin` names the text in error messages (usually the file name).
///
/// Errors, with line and column, on anything else: an unknown or repeated key, a missing
/// key, a `type` other than `octile`, a size that is not a positive 32-bit integer or
/// exceeds [`crate::DEFAULT_MAX_CELLS`] cells (see [`crate::ReadOptions::max_cells`]), too
/// few or too many rows, a short or long row, or an unknown symbol. Never panics, and
/// allocates no more than the text's size, whatever the header declares.
pub fn parse_movingai(text: &str, origin: &str) -> Result<Grid, MapError> {
    parse(text, origin, crate::DEFAULT_MAX_CELLS)
}

/// [`parse_movingai`] with at most `max_cells` cells.
pub(crate) fn parse(text: &str, origin: &str, max_cells: u64) -> Result<Grid, MapError> {
    let o = Origin(origin);
    let mut all = lines(text);
    let mut kind_line = None;
    let mut height: Option<(u32, usize)> = None;
    let mut width_: Option<(u32, usize)> = None;
    let map_line = loop {
        let Some((number, line)) = all.next() else {
            let (line, column) = end_of_file(text);
            return Err(o.at(
                line,
                column,
                unexpected(
                    "a header ('type octile', 'height H', 'width W') ended by 'map'",
                    "end of file",
                ),
            ));
        };
        let toks = tokens(line);
        let Some(&(key_column, key)) = toks.first() else {
            continue;
        };
        let key: &'static str = match key {
            "map" => {
                if let Some(&(column, extra)) = toks.get(1) {
                    return Err(o.at(
                        number,
                        column,
                        unexpected("end of line after 'map'", show_token(extra)),
                    ));
                }
                break number;
            }
            "type" => "type",
            "height" => "height",
            "width" => "width",
            other => {
                return Err(o.at(
                    number,
                    key_column,
                    unexpected("'type', 'height', 'width' or 'map'", show_token(other)),
                ))
            }
        };
        let Some(&(value_column, value)) = toks.get(1) else {
            return Err(o.at(
                number,
                width(line) + 1,
                unexpected(format!("a value after '{key}'"), "end of line"),
            ));
        };
        if let Some(&(column, extra)) = toks.get(2) {
            return Err(o.at(
                number,
                column,
                unexpected(
                    format!("end of line after the {key} value"),
                    show_token(extra),
                ),
            ));
        }
        let first_line = match key {
            "type" => kind_line,
            "height" => height.map(|(_, line)| line),
            _ => width_.map(|(_, line)| line),
        };
        if let Some(first_line) = first_line {
            return Err(o.at(
                number,
                key_column,
                MapErrorKind::DuplicateKey { key, first_line },
            ));
        }
        if key == "type" {
            if value != "octile" {
                return Err(o.at(
                    number,
                    value_column,
                    unexpected("'octile' as the type", show_token(value)),
                ));
            }
            kind_line = Some(number);
            continue;
        }
        let n = parse_u32(value, key).map_err(|kind| o.at(number, value_column, kind))?;
        if n == 0 {
            return Err(o.at(
                number,
                value_column,
                unexpected(format!("a positive integer for {key}"), show_token(value)),
            ));
        }
        if key == "height" {
            height = Some((n, number));
        } else {
            width_ = Some((n, number));
        }
    };
    let missing = |key| o.at(map_line, 1, MapErrorKind::MissingKey { key });
    if kind_line.is_none() {
        return Err(missing("type"));
    }
    let (height, _) = height.ok_or_else(|| missing("height"))?;
    let (width_, _) = width_.ok_or_else(|| missing("width"))?;
    let cells = u64::from(width_) * u64::from(height);
    if cells > max_cells {
        return Err(o.at(
            map_line,
            1,
            MapErrorKind::TooManyCells {
                width: u64::from(width_),
                height: u64::from(height),
                max_cells,
            },
        ));
    }
    if cells > Grid::MAX_CELLS {
        return Err(o.at(map_line, 1, MapErrorKind::Grid(GridError::TooLarge)));
    }
    // Both fit in usize: cells <= 2^31.
    let (w, h) = (width_ as usize, height as usize);

    let rest: Vec<(usize, &str)> = all.collect();
    let mut free = Vec::with_capacity((w * h).min(text.len()));
    for row in 0..h {
        let Some(&(number, line)) = rest.get(row) else {
            let (line, column) = end_of_file(text);
            return Err(o.at(
                line,
                column,
                MapErrorKind::RowCount {
                    expected: h,
                    found: row,
                },
            ));
        };
        if is_blank(line) && rest[row..].iter().all(|&(_, l)| is_blank(l)) {
            return Err(o.at(
                number,
                1,
                MapErrorKind::RowCount {
                    expected: h,
                    found: row,
                },
            ));
        }
        let len = width(line);
        if len != w {
            return Err(o.at(
                number,
                len.min(w) + 1,
                MapErrorKind::RowWidth {
                    expected: w,
                    found: len,
                    reference: format!("width {w}"),
                },
            ));
        }
        for (index, symbol) in line.chars().enumerate() {
            match movingai_passable(symbol) {
                Some(passable) => free.push(passable),
                None => {
                    return Err(o.at(number, index + 1, unexpected(SYMBOLS, show_char(symbol))))
                }
            }
        }
    }
    if let Some(&(number, line)) = rest.iter().skip(h).find(|&&(_, l)| !is_blank(l)) {
        let column = line.chars().take_while(|c| c.is_whitespace()).count() + 1;
        return Err(o.at(
            number,
            column,
            unexpected(
                format!("end of file after the last row (height {h})"),
                show_token(line.trim()),
            ),
        ));
    }
    Grid::from_free_cells(width_, height, free)
        .map_err(|e| o.at(map_line, 1, MapErrorKind::Grid(e)))
}

/// Writes `grid` as a Moving AI `.map` file: `type octile`, `height H`, `width W`, `map`,
/// then one line per row with `.` for free and `@` for blocked cells, every line ended by
/// `\n`. [`parse_movingai`] reads the result back to an identical grid.
///
/// ```
/// use planner_api::Grid;
/// use planner_maps::{parse_movingai, to_movingai};
/// let grid = Grid::from_ascii("..#\n#..").unwrap();
/// let text = to_movingai(&grid);
/// assert_eq!(text, "type octile\nheight 2\nwidth 3\nmap\n..@\n@..\n");
/// assert_eq!(parse_movingai(&text, "x.map").unwrap(), grid);
/// ```
pub fn to_movingai(grid: &Grid) -> String {
    let w = grid.width() as usize;
    let mut out = format!(
        "type octile\nheight {}\nwidth {}\nmap\n",
        grid.height(),
        grid.width()
    );
    out.reserve(grid.len() + grid.height() as usize);
    for row in grid.free_cells().chunks(w.max(1)) {
        out.extend(row.iter().map(|&free| if free { '.' } else { '@' }));
        out.push('\n');
    }
    out
}
