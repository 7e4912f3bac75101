//! Moving AI `.scen` scenario files.

use planner_api::{Cell, Grid};
use serde::{Deserialize, Serialize};

use crate::error::{MapError, MapErrorKind};
use crate::text::{
    end_of_file, is_blank, lines, parse_u32, show_token, tokens, unexpected, width, Origin,
};
use crate::ProblemSpec;

/// One line of a Moving AI `.scen` file: a start-goal query with its optimal length.
///
/// The optimal length is for 8-connected moves costing 1 and sqrt 2 without corner
/// cutting (a diagonal needs both orthogonal neighbours passable), as the benchmark defines.
/// Older files give it to 5 or 6 significant digits, newer ones to 8 decimals: compare
/// with a relative tolerance of about 1e-5.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Scenario {
    /// Bucket (groups scenarios of similar length).
    pub bucket: u32,
    /// The map as the file names it: `maps/dao/arena.map` (older files) or `arena.map`.
    pub map: String,
    /// Map width the scenario was made for.
    pub width: u32,
    /// Map height the scenario was made for.
    pub height: u32,
    /// Start cell (x = column, y = row).
    pub start: Cell,
    /// Goal cell.
    pub goal: Cell,
    /// Optimal 8-connected octile length without corner cutting.
    pub optimal_length: f64,
    /// 1-based line of the `.scen` file this scenario came from.
    pub line: usize,
    /// 1-based column of the width on that line, where an error about the map's size
    /// points ([`Scenario::check_size`]); 0 when unknown (a scenario not read from a file).
    #[serde(default)]
    pub size_column: usize,
}

impl Scenario {
    /// Whether the scenario names the map file `name`: the last component of its map field
    /// (which some files write with a directory, `/` or `\` separated) is `name`.
    ///
    /// ```
    /// let text = "version 1\n0\tmaps/den520d.map\t3\t3\t0\t0\t1\t1\t1.4\n";
    /// let s = planner_maps::parse_scenarios(text, "d.scen").unwrap().remove(0);
    /// assert!(s.names_map("den520d.map") && !s.names_map("arena.map"));
    /// ```
    pub fn names_map(&self, name: &str) -> bool {
        self.map.rsplit(['/', '\\']).next().unwrap_or(&self.map) == name
    }

    /// The start-goal pair, keeping the line number.
    pub fn problem_spec(&self) -> ProblemSpec {
        ProblemSpec {
            start: self.start,
            goal: self.goal,
            line: self.line,
        }
    }

    /// The map's base name, without directories (`maps/dao/arena.map` gives `arena.map`).
    /// Match scenarios to maps by this name: the two file styles differ in the directory.
    pub fn map_name(&self) -> &str {
        self.map.rsplit(['/', '\\']).next().unwrap_or(&self.map)
    }

    /// Checks that the scenario's declared width and height are the grid's.
    ///
    /// `origin` names the `.scen` file; the error names this scenario's line and the
    /// column of its width ([`Scenario::size_column`]). Start and goal are checked later,
    /// by [`planner_api::Problem::new`].
    pub fn check_size(&self, grid: &Grid, origin: &str) -> Result<(), MapError> {
        if (self.width, self.height) == (grid.width(), grid.height()) {
            return Ok(());
        }
        Err(MapError::new(
            origin,
            self.line,
            self.size_column,
            MapErrorKind::SizeMismatch {
                scen_width: self.width,
                scen_height: self.height,
                width: grid.width(),
                height: grid.height(),
            },
        ))
    }
}

/// The number of tab-separated fields on a scenario line.
const FIELDS: usize = 9;

/// Parses the text of a Moving AI `.scen` file.
///
/// The first line is `version 1` (or `version 1.0`); every other non-blank line has 9
/// tab-separated fields: bucket, map, width, height, start x, start y, goal x, goal y,
/// optimal length. Blank lines (such as trailing ones) are skipped and CRLF is accepted.
/// Each [`Scenario`] keeps its 1-based line number. `origin` names the text in messages.
///
/// Errors, with line and column, on a missing or other version, a line without exactly 9
/// fields, an empty map name, a number that is not a non-negative 32-bit integer, or an
/// optimal length that is not a finite non-negative number. Coordinates are not checked
/// against the width and height here (see [`Scenario::check_size`] and
/// [`planner_api::Problem::new`]).
pub fn parse_scenarios(text: &str, origin: &str) -> Result<Vec<Scenario>, MapError> {
    let o = Origin(origin);
    let mut all = lines(text);
    let (number, first) = all.next().unwrap_or((1, ""));
    let toks = tokens(first);
    let version_expected = "'version 1' on the first line";
    match toks.as_slice() {
        [] => {
            let found = if is_blank(text) {
                "end of file"
            } else {
                "a blank line"
            };
            let (line, column) = if is_blank(text) {
                end_of_file(text)
            } else {
                (number, 1)
            };
            return Err(o.at(line, column, unexpected(version_expected, found)));
        }
        [(column, word), ..] if *word != "version" => {
            return Err(o.at(
                number,
                *column,
                unexpected(version_expected, show_token(word)),
            ));
        }
        [_] => {
            return Err(o.at(
                number,
                width(first) + 1,
                unexpected("a version number after 'version'", "end of line"),
            ));
        }
        [_, (column, version), rest @ ..] => {
            if *version != "1" && *version != "1.0" {
                return Err(o.at(
                    number,
                    *column,
                    unexpected("version 1 or 1.0", show_token(version)),
                ));
            }
            if let Some((column, extra)) = rest.first() {
                return Err(o.at(
                    number,
                    *column,
                    unexpected("end of line after the version", show_token(extra)),
                ));
            }
        }
    }

    let mut out = Vec::new();
    for (number, line) in all {
        if is_blank(line) {
            continue;
        }
        out.push(parse_line(o, number, line)?);
    }
    Ok(out)
}

/// One scenario line (not blank).
fn parse_line(o: Origin<'_>, number: usize, line: &str) -> Result<Scenario, MapError> {
    // Each field with the 1-based column of its first character.
    let mut fields: Vec<(usize, &str)> = Vec::with_capacity(FIELDS);
    let mut column = 1;
    for field in line.split('\t') {
        fields.push((column, field));
        column += width(field) + 1;
    }
    if fields.len() != FIELDS {
        let column = match fields.get(FIELDS) {
            Some(&(column, _)) => column,
            None => width(line) + 1,
        };
        return Err(o.at(
            number,
            column,
            MapErrorKind::FieldCount {
                found: fields.len(),
            },
        ));
    }
    // Surrounding spaces inside a field are tolerated; the column moves to the value.
    let trimmed = |index: usize| -> (usize, &str) {
        let (column, field) = fields[index];
        let lead = field.chars().take_while(|c| c.is_whitespace()).count();
        (column + lead, field.trim())
    };
    let int = |index: usize, what: &'static str| -> Result<u32, MapError> {
        let (column, value) = trimmed(index);
        parse_u32(value, what).map_err(|kind| o.at(number, column, kind))
    };
    let bucket = int(0, "bucket")?;
    let (map_column, map) = trimmed(1);
    if map.is_empty() {
        return Err(o.at(
            number,
            map_column,
            unexpected("a map name", "an empty field"),
        ));
    }
    let (size_column, _) = trimmed(2);
    let width_ = int(2, "width")?;
    let height = int(3, "height")?;
    let start = Cell::new(int(4, "start x")?, int(5, "start y")?);
    let goal = Cell::new(int(6, "goal x")?, int(7, "goal y")?);
    let (length_column, length) = trimmed(8);
    let optimal_length = parse_length(length).map_err(|kind| o.at(number, length_column, kind))?;
    Ok(Scenario {
        bucket,
        map: map.to_owned(),
        width: width_,
        height,
        start,
        goal,
        optimal_length,
        line: number,
        size_column,
    })
}

/// A finite, non-negative decimal number.
fn parse_length(token: &str) -> Result<f64, MapErrorKind> {
    let expected = "a non-negative number for the optimal length";
    if token.is_empty() {
        return Err(unexpected(expected, "an empty field"));
    }
    let plain = token
        .bytes()
        .all(|b| b.is_ascii_digit() || matches!(b, b'.' | b'e' | b'E' | b'+' | b'-'));
    match token.parse::<f64>() {
        Ok(value) if plain && value.is_finite() && value >= 0.0 && !token.starts_with('-') => {
            Ok(value)
        }
        _ => Err(unexpected(expected, show_token(token))),
    }
}
