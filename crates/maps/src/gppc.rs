//! The GPPC 2023 dynamic track's scenario (`.scen`, version 2) and patch (`.patch`) files.
//!
//! The Grid-Based Path Planning Competition's dynamic start kit (gppc-dev/startkit-dynamic,
//! `Problem_Definition.md` and the files' headers; a sample is in `maps/gppc-dynamic/`)
//! describes a map that changes between queries. A scenario is a header
//!
//! ```text
//! version 2
//! height 1024
//! width 1024
//! cost 1 octile
//! patch switch_sc1_Aurora_TheFrozenSea.patch
//! commands
//! ```
//!
//! and then one command per line: `P b p x y` places patch `p` with its top-left cell at
//! column `x`, row `y` (every cell of the patch replaces the map's), and `Q b sx sy gx gy c`
//! is a query from `(sx, sy)` to `(gx, gy)` whose optimal octile cost (8 moves, no corner
//! cutting) on the map as patched so far is `c`, or `-1` when there is no path. `b` is
//! the batch the command belongs to (the sample's batches: patches, then the queries they
//! precede). A patch file is `type patch`, `patches N`, then `N` patches, each
//! `patch i`, `height h`, `width w`, `map` and `h` rows of Moving AI symbols
//! ([`crate::movingai_passable`]). Patch 0 of the sample is the whole initial map, placed by
//! the first command `P 0 0 0 0`.
//!
//! Reading follows the crate's rules: every error has file, line and column; a patch that
//! does not fit the map at its `P` command, or a query endpoint outside it, names the
//! cell ([`MapErrorKind::PatchOutside`], [`MapErrorKind::QueryOutside`]); memory is
//! bounded by the text (a header's declared size allocates nothing), and a map of more
//! than [`Grid::MAX_CELLS`] cells, which no grid can hold, is an error at its width.
//! [`GppcScenario::read_patches`] reads the patch file a scenario names: one that cannot
//! be read is an error at the scenario's line and column that name it.
//!
//! ```
//! use planner_api::{Cell, Grid};
//! use planner_maps::gppc::{parse_gppc_patches, parse_gppc_scenario, GppcCommand};
//!
//! let scen = parse_gppc_scenario(
//!     "version 2\nheight 3\nwidth 4\ncost 1 octile\npatch tiny.patch\ncommands\nP 0 0 0 0\nQ 0 0 0 3 2 4.4142135624\nP 1 1 2 1\nQ 1 0 0 3 2 -1\n",
//!     "tiny.scen",
//! ).unwrap();
//! let patches = parse_gppc_patches(
//!     "type patch\npatches 2\npatch 0\nheight 3\nwidth 4\nmap\n....\n....\n....\npatch 1\nheight 2\nwidth 2\nmap\n@@\n@@\n",
//!     "tiny.patch",
//! ).unwrap();
//! scen.validate(&patches, "tiny.scen").unwrap();
//! let mut grid = Grid::new(4, 3).unwrap();
//! let mut changed = 0;
//! for command in &scen.commands {
//!     if let GppcCommand::Patch { patch, x, y, .. } = *command {
//!         changed += patches.apply(&mut grid, patch, x, y).len();
//!     }
//! }
//! assert_eq!(changed, 4);
//! assert!(!grid.is_free(Cell::new(3, 2)));
//! ```

use std::path::Path;

use planner_api::{Cell, CellChange, Grid};

use crate::error::{MapError, MapErrorKind};
use crate::movingai::movingai_passable;
use crate::text::{
    end_of_file, from_column, is_blank, lines, parse_u32, show_char, show_token, tokens,
    unexpected, width, Origin,
};

/// A version-2 scenario: the map's size, the patch file it names, and its commands.
#[derive(Debug, Clone, PartialEq)]
pub struct GppcScenario {
    /// Map width.
    pub width: u32,
    /// Map height.
    pub height: u32,
    /// The patch file's name as written (relative to the scenario's folder).
    pub patch_file: String,
    /// The 1-based line and column of [`GppcScenario::patch_file`] in the scenario.
    pub patch_file_at: (usize, usize),
    /// The commands in file order.
    pub commands: Vec<GppcCommand>,
}

/// One command of a scenario.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GppcCommand {
    /// `P batch patch x y`: place `patch` with its top-left cell at `(x, y)`.
    Patch {
        /// The batch number.
        batch: u32,
        /// The patch number.
        patch: u32,
        /// Column of the top-left cell.
        x: u32,
        /// Row of the top-left cell.
        y: u32,
        /// 1-based line.
        line: usize,
    },
    /// `Q batch sx sy gx gy cost`: a query and its recorded optimum.
    Query {
        /// The batch number.
        batch: u32,
        /// Start cell.
        start: Cell,
        /// Goal cell.
        goal: Cell,
        /// The recorded optimal octile cost; `None` for `-1` (no path).
        cost: Option<f64>,
        /// 1-based line.
        line: usize,
    },
}

/// One patch: a small grid of Moving AI symbols.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Patch {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Free flags, row-major.
    pub free: Vec<bool>,
}

/// A patch file's patches, by number.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PatchSet {
    /// The patches; patch `i` is `patches[i]`.
    pub patches: Vec<Patch>,
}

impl PatchSet {
    /// Places patch `patch` with its top-left cell at `(x, y)` on `grid` and returns the
    /// cells whose state changed, in row-major order. Cells outside the grid and unknown
    /// patches are skipped: [`GppcScenario::validate`] rejects them beforehand.
    pub fn apply(&self, grid: &mut Grid, patch: u32, x: u32, y: u32) -> Vec<CellChange> {
        let mut changes = Vec::new();
        let Some(p) = self.patches.get(patch as usize) else {
            return changes;
        };
        for row in 0..p.height {
            for column in 0..p.width {
                let cell = Cell::new(x.saturating_add(column), y.saturating_add(row));
                let free = p.free[(row * p.width + column) as usize];
                if grid.contains(cell) && grid.is_free(cell) != free {
                    grid.set_free(cell, free);
                    changes.push(CellChange {
                        cell,
                        free,
                        weight: None,
                    });
                }
            }
        }
        changes
    }
}

impl GppcScenario {
    /// Reads and parses the patch file this scenario names, resolved against the folder of
    /// `scen_path` (the scenario's own path, which names it in errors, as
    /// [`parse_gppc_scenario`]'s `origin`), a regular file of at most `max_bytes` bytes
    /// ([`crate::read_text_file`]). A patch file that cannot be read is an error at the
    /// scenario's line and column that name it ([`MapErrorKind::NamedFile`]); errors in
    /// its text name the patch file.
    pub fn read_patches(&self, scen_path: &Path, max_bytes: u64) -> Result<PatchSet, MapError> {
        let path = scen_path
            .parent()
            .unwrap_or(Path::new("."))
            .join(&self.patch_file);
        let text = crate::read_text_file(&path, max_bytes).map_err(|e| {
            let scen = scen_path.display().to_string();
            crate::at_name(e, &scen, self.patch_file_at, "patch file", &self.patch_file)
        })?;
        parse_gppc_patches(&text, &path.display().to_string())
    }

    /// Checks every command against the map size and `patches`: a `P` naming a missing
    /// patch or one that does not fit, a `Q` with an endpoint outside the map, are errors
    /// at the command's line (`origin` is the scenario's name).
    pub fn validate(&self, patches: &PatchSet, origin: &str) -> Result<(), MapError> {
        let o = Origin(origin);
        for command in &self.commands {
            match *command {
                GppcCommand::Patch {
                    patch, x, y, line, ..
                } => {
                    let Some(p) = patches.patches.get(patch as usize) else {
                        return Err(o.at(
                            line,
                            0,
                            MapErrorKind::UnknownPatch {
                                patch,
                                patches: patches.patches.len(),
                            },
                        ));
                    };
                    let right = u64::from(x) + u64::from(p.width);
                    let bottom = u64::from(y) + u64::from(p.height);
                    if right > u64::from(self.width) || bottom > u64::from(self.height) {
                        // The first cell (row-major) of the patch outside the map.
                        let cell = if x >= self.width || y >= self.height {
                            Cell::new(x, y)
                        } else if right > u64::from(self.width) {
                            Cell::new(self.width, y)
                        } else {
                            Cell::new(x, self.height)
                        };
                        return Err(o.at(
                            line,
                            0,
                            MapErrorKind::PatchOutside {
                                patch,
                                patch_width: p.width,
                                patch_height: p.height,
                                x,
                                y,
                                cell,
                                width: self.width,
                                height: self.height,
                            },
                        ));
                    }
                }
                GppcCommand::Query {
                    start, goal, line, ..
                } => {
                    for (endpoint, cell) in [("start", start), ("goal", goal)] {
                        if cell.x >= self.width || cell.y >= self.height {
                            return Err(o.at(
                                line,
                                0,
                                MapErrorKind::QueryOutside {
                                    endpoint,
                                    cell,
                                    width: self.width,
                                    height: self.height,
                                },
                            ));
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

/// The tokens of a header line `key value...`, checked: the key, then exactly `n` values.
fn header<'a>(
    o: Origin<'_>,
    number: usize,
    line: &'a str,
    key: &str,
    n: usize,
) -> Result<Vec<(usize, &'a str)>, MapError> {
    let toks = tokens(line);
    match toks.first() {
        Some(&(_, k)) if k == key => {}
        Some(&(column, other)) => {
            return Err(o.at(
                number,
                column,
                unexpected(format!("'{key}'"), show_token(other)),
            ))
        }
        None => return Err(o.at(number, 1, unexpected(format!("'{key}'"), "an empty line"))),
    }
    if toks.len() < n + 1 {
        return Err(o.at(
            number,
            width(line) + 1,
            unexpected(format!("{n} value(s) after '{key}'"), "end of line"),
        ));
    }
    if let Some(&(column, extra)) = toks.get(n + 1) {
        return Err(o.at(
            number,
            column,
            unexpected(format!("end of line after '{key}'"), show_token(extra)),
        ));
    }
    Ok(toks[1..].to_vec())
}

/// The next non-blank line, or an error at the end of the file expecting `what`.
fn next_line<'a>(
    o: Origin<'_>,
    text: &str,
    all: &mut impl Iterator<Item = (usize, &'a str)>,
    what: &str,
) -> Result<(usize, &'a str), MapError> {
    for (number, line) in all.by_ref() {
        if !is_blank(line) {
            return Ok((number, line));
        }
    }
    let (line, column) = end_of_file(text);
    Err(o.at(line, column, unexpected(what, "end of file")))
}

/// A positive 32-bit size value.
fn positive(
    o: Origin<'_>,
    number: usize,
    (column, token): (usize, &str),
    what: &'static str,
) -> Result<u32, MapError> {
    let n = parse_u32(token, what).map_err(|kind| o.at(number, column, kind))?;
    if n == 0 {
        return Err(o.at(
            number,
            column,
            unexpected(format!("a positive integer for {what}"), show_token(token)),
        ));
    }
    Ok(n)
}

/// Parses a version-2 scenario (see the [module docs](self)). `origin` names the text in
/// errors.
pub fn parse_gppc_scenario(text: &str, origin: &str) -> Result<GppcScenario, MapError> {
    let o = Origin(origin);
    let mut all = lines(text);
    let (number, line) = next_line(o, text, &mut all, "'version 2'")?;
    let version = header(o, number, line, "version", 1)?;
    if version[0].1 != "2" {
        return Err(o.at(
            number,
            version[0].0,
            unexpected("version '2'", show_token(version[0].1)),
        ));
    }
    let (number, line) = next_line(o, text, &mut all, "'height H'")?;
    let height = positive(
        o,
        number,
        header(o, number, line, "height", 1)?[0],
        "height",
    )?;
    let (number, line) = next_line(o, text, &mut all, "'width W'")?;
    let width_ = positive(o, number, header(o, number, line, "width", 1)?[0], "width")?;
    // The map is allocated whole (all free until patched): a size no grid can take is an
    // error here, at the width, not a replay that quietly answers nothing.
    if u64::from(width_) * u64::from(height) > Grid::MAX_CELLS {
        return Err(o.at(
            number,
            1,
            MapErrorKind::TooManyCells {
                width: u64::from(width_),
                height: u64::from(height),
                max_cells: Grid::MAX_CELLS,
            },
        ));
    }
    let (number, line) = next_line(o, text, &mut all, "'cost 1 octile'")?;
    let cost = header(o, number, line, "cost", 2)?;
    if cost[0].1 != "1" || cost[1].1 != "octile" {
        return Err(o.at(
            number,
            cost[0].0,
            unexpected(
                "'1 octile' (the only cost model)",
                show_token(from_column(line, cost[0].0)),
            ),
        ));
    }
    let (number, line) = next_line(o, text, &mut all, "'patch FILE'")?;
    let (patch_column, patch_file) = header(o, number, line, "patch", 1)?[0];
    let (patch_file, patch_file_at) = (patch_file.to_owned(), (number, patch_column));
    let (number, line) = next_line(o, text, &mut all, "'commands'")?;
    header(o, number, line, "commands", 0)?;
    let mut commands = Vec::new();
    for (number, line) in all {
        if is_blank(line) {
            continue;
        }
        let toks = tokens(line);
        let (column, kind) = toks[0];
        let n = match kind {
            "P" => 4,
            "Q" => 6,
            other => {
                return Err(o.at(
                    number,
                    column,
                    unexpected("a command 'P' or 'Q'", show_token(other)),
                ))
            }
        };
        if toks.len() != n + 1 {
            let (column, found) = toks
                .get(n + 1)
                .map_or((width(line) + 1, "end of line".to_owned()), |&(c, t)| {
                    (c, show_token(t))
                });
            let expected = if n == 4 {
                "'P batch patch x y' (4 numbers)"
            } else {
                "'Q batch sx sy gx gy cost' (6 numbers)"
            };
            return Err(o.at(number, column, unexpected(expected, found)));
        }
        let int = |i: usize, what: &'static str| {
            let (column, token) = toks[i];
            parse_u32(token, what).map_err(|kind| o.at(number, column, kind))
        };
        if kind == "P" {
            commands.push(GppcCommand::Patch {
                batch: int(1, "batch")?,
                patch: int(2, "patch")?,
                x: int(3, "x")?,
                y: int(4, "y")?,
                line: number,
            });
        } else {
            let (column, token) = toks[6];
            let cost = match token {
                "-1" => None,
                _ => match token.parse::<f64>() {
                    Ok(c)
                        if c.is_finite()
                            && c >= 0.0
                            && token.bytes().all(|b| b.is_ascii_digit() || b == b'.') =>
                    {
                        Some(c)
                    }
                    _ => {
                        return Err(o.at(
                            number,
                            column,
                            unexpected(
                                "a cost (a non-negative decimal number, or -1 for no path)",
                                show_token(token),
                            ),
                        ))
                    }
                },
            };
            commands.push(GppcCommand::Query {
                batch: int(1, "batch")?,
                start: Cell::new(int(2, "start x")?, int(3, "start y")?),
                goal: Cell::new(int(4, "goal x")?, int(5, "goal y")?),
                cost,
                line: number,
            });
        }
    }
    Ok(GppcScenario {
        width: width_,
        height,
        patch_file,
        patch_file_at,
        commands,
    })
}

/// Parses a patch file (see the [module docs](self)). `origin` names the text in errors.
/// The patches' cells are read from the text, so memory is bounded by its size.
pub fn parse_gppc_patches(text: &str, origin: &str) -> Result<PatchSet, MapError> {
    let o = Origin(origin);
    let mut all = lines(text);
    let (number, line) = next_line(o, text, &mut all, "'type patch'")?;
    let kind = header(o, number, line, "type", 1)?;
    if kind[0].1 != "patch" {
        return Err(o.at(
            number,
            kind[0].0,
            unexpected("'patch' as the type", show_token(kind[0].1)),
        ));
    }
    let (number, line) = next_line(o, text, &mut all, "'patches N'")?;
    let count_token = header(o, number, line, "patches", 1)?[0];
    let count =
        parse_u32(count_token.1, "patches").map_err(|kind| o.at(number, count_token.0, kind))?;
    let mut patches = Vec::new();
    for index in 0..count {
        let (number, line) = next_line(o, text, &mut all, &format!("'patch {index}'"))?;
        let id = header(o, number, line, "patch", 1)?[0];
        if id.1 != index.to_string() {
            return Err(o.at(
                number,
                id.0,
                unexpected(format!("patch number {index}"), show_token(id.1)),
            ));
        }
        let (number, line) = next_line(o, text, &mut all, "'height H'")?;
        let h = positive(
            o,
            number,
            header(o, number, line, "height", 1)?[0],
            "height",
        )?;
        let (number, line) = next_line(o, text, &mut all, "'width W'")?;
        let w = positive(o, number, header(o, number, line, "width", 1)?[0], "width")?;
        let (number, line) = next_line(o, text, &mut all, "'map'")?;
        header(o, number, line, "map", 0)?;
        let mut free = Vec::new();
        for row in 0..h {
            let Some((number, line)) = all.next() else {
                let (line, column) = end_of_file(text);
                return Err(o.at(
                    line,
                    column,
                    MapErrorKind::RowCount {
                        expected: h as usize,
                        found: row as usize,
                    },
                ));
            };
            let len = width(line);
            if len != w as usize {
                return Err(o.at(
                    number,
                    len.min(w as usize) + 1,
                    MapErrorKind::RowWidth {
                        expected: w as usize,
                        found: len,
                        reference: format!("width {w} of patch {index}"),
                    },
                ));
            }
            for (column, symbol) in line.chars().enumerate() {
                match movingai_passable(symbol) {
                    Some(passable) => free.push(passable),
                    None => {
                        return Err(o.at(
                            number,
                            column + 1,
                            unexpected(
                                "a Moving AI map symbol ('.', 'G', 'S', '@', 'O', 'T', 'W')",
                                show_char(symbol),
                            ),
                        ))
                    }
                }
            }
        }
        patches.push(Patch {
            width: w,
            height: h,
            free,
        });
    }
    if let Some((number, line)) = all.find(|&(_, l)| !is_blank(l)) {
        let column = line.chars().take_while(|c| c.is_whitespace()).count() + 1;
        return Err(o.at(
            number,
            column,
            unexpected(
                format!("end of file after the last of {count} patches"),
                show_token(line.trim()),
            ),
        ));
    }
    Ok(PatchSet { patches })
}

#[cfg(test)]
mod tests {
    use super::*;

    const SCEN: &str = "version 2\nheight 3\nwidth 4\ncost 1 octile\npatch t.patch\ncommands\nP 0 0 0 0\nQ 0 0 0 3 2 4.5\n";
    const PATCHES: &str = "type patch\npatches 2\npatch 0\nheight 3\nwidth 4\nmap\n....\n....\n....\npatch 1\nheight 2\nwidth 2\nmap\n@@\n@.\n";

    #[test]
    fn reads_and_applies() {
        let scen = parse_gppc_scenario(SCEN, "t.scen").unwrap();
        assert_eq!(
            (scen.width, scen.height, scen.patch_file.as_str()),
            (4, 3, "t.patch")
        );
        assert_eq!(
            scen.commands[1],
            GppcCommand::Query {
                batch: 0,
                start: Cell::new(0, 0),
                goal: Cell::new(3, 2),
                cost: Some(4.5),
                line: 8
            }
        );
        let set = parse_gppc_patches(PATCHES, "t.patch").unwrap();
        let mut grid = Grid::new(4, 3).unwrap();
        assert!(set.apply(&mut grid, 0, 0, 0).is_empty());
        let changes = set.apply(&mut grid, 1, 2, 1);
        assert_eq!(
            changes,
            vec![
                CellChange::blocked(Cell::new(2, 1)),
                CellChange::blocked(Cell::new(3, 1)),
                CellChange::blocked(Cell::new(2, 2)),
            ]
        );
        // Placing patch 0 again frees them: a patch replaces every cell it covers.
        assert_eq!(set.apply(&mut grid, 0, 0, 0).len(), 3);
    }

    #[test]
    fn errors_name_file_line_column_and_cell() {
        let err = |text: &str| parse_gppc_scenario(text, "s.scen").unwrap_err().to_string();
        assert_eq!(
            err("version 1\n"),
            "s.scen:1:9: expected version '2', found '1'"
        );
        assert_eq!(
            err(&SCEN.replace("Q 0 0 0 3 2 4.5", "Q 0 0 0 3 2 x")),
            "s.scen:8:13: expected a cost (a non-negative decimal number, or -1 for no path), found 'x'"
        );
        // Columns count characters: wide whitespace before the key moves the column, and
        // the excerpt starts at the value, not inside a character.
        assert_eq!(
            err(&SCEN.replace("cost 1 octile", "\u{3000}\u{3000}\u{3000}cost 1 octilX")),
            "s.scen:4:9: expected '1 octile' (the only cost model), found '1 octilX'"
        );
        // A map no grid can hold is refused at its width (the replay allocates it whole).
        assert_eq!(
            err(&SCEN.replace("height 3\nwidth 4", "height 4000000000\nwidth 4000000000")),
            "s.scen:3:1: a 4000000000x4000000000 map has 16000000000000000000 cells, more than \
             the limit of 2147483648 cells"
        );
        assert!(parse_gppc_scenario(
            &SCEN.replace("height 3\nwidth 4", "height 32768\nwidth 65536"),
            "s.scen"
        )
        .is_ok());
        assert_eq!(
            err(&SCEN.replace("P 0 0 0 0", "P 0 0 0")),
            "s.scen:7:8: expected 'P batch patch x y' (4 numbers), found end of line"
        );
        assert_eq!(
            err(&SCEN.replace("P 0 0 0 0", "R 0 0 0 0")),
            "s.scen:7:1: expected a command 'P' or 'Q', found 'R'"
        );
        assert_eq!(
            err(&SCEN.replace("P 0 0 0 0", "P 0 0 -4 0")),
            "s.scen:7:7: expected a non-negative integer for x, found '-4'"
        );
        let perr = |text: &str| parse_gppc_patches(text, "p.patch").unwrap_err().to_string();
        assert_eq!(perr(&PATCHES.replace("@.", "@Q")), "p.patch:15:2: expected a Moving AI map symbol ('.', 'G', 'S', '@', 'O', 'T', 'W'), found 'Q'");
        assert_eq!(
            perr(&PATCHES.replace("@.", "@")),
            "p.patch:15:2: expected 2 cells (width 2 of patch 1), found 1"
        );
        assert_eq!(
            perr(&PATCHES.replace("patch 1", "patch 7")),
            "p.patch:10:7: expected patch number 1, found '7'"
        );
        assert_eq!(
            perr(&PATCHES.replace("patches 2", "patches 3")),
            "p.patch:16:1: expected 'patch 2', found end of file"
        );
        let set = parse_gppc_patches(PATCHES, "p.patch").unwrap();
        let scen = parse_gppc_scenario(&SCEN.replace("P 0 0 0 0", "P 0 1 3 2"), "s.scen").unwrap();
        assert_eq!(
            scen.validate(&set, "s.scen").unwrap_err().to_string(),
            "s.scen:7: patch 1 (2x2) placed at (3, 2) puts its cell (4, 2) outside the 4x3 map"
        );
        let scen = parse_gppc_scenario(&SCEN.replace("P 0 0 0 0", "P 0 5 0 0"), "s.scen").unwrap();
        assert_eq!(
            scen.validate(&set, "s.scen").unwrap_err().to_string(),
            "s.scen:7: patch 5 does not exist: the patch file has 2 patches"
        );
        let scen =
            parse_gppc_scenario(&SCEN.replace("Q 0 0 0 3 2", "Q 0 0 0 3 9"), "s.scen").unwrap();
        assert_eq!(
            scen.validate(&set, "s.scen").unwrap_err().to_string(),
            "s.scen:8: goal (3, 9) is outside the 4x3 map"
        );
    }
}
