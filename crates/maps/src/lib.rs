//! Map and scenario files for gridplan: readers that return a [`Grid`] plus its start-goal
//! problems, and a writer for the Moving AI format the repository's own maps use.
//!
//! # Formats
//! The format is chosen by file extension ([`read_map`], [`read_scenarios`]); an unknown
//! extension is an error listing the supported ones.
//!
//! | extension | format | parser | passable | blocked | problems |
//! |---|---|---|---|---|---|
//! | `.map` | Moving AI map: `type octile`, `height H`, `width W` (any order), `map`, `H` rows | [`parse_movingai`] | `.` `G` `S` | `@` `O` `T` `W` | none (they live in the `.scen`) |
//! | `.scen` | Moving AI scenarios: `version 1`, then 9 tab-separated fields per line | [`parse_scenarios`] | | | every line, with its optimal length |
//! | `.txt` | seed 003 text map: `#` comment header, rows of `.` and `X` | [`parse_seed003`] | `.` | `X` | `# Start: (x,y) Goal: (x,y)` and `# 1. Start: (x,y) \| Goal: (x,y)` comments |
//! | `.csv` | 0/1 matrix, seed 000 equation (1) | [`parse_matrix`] | `1` | `0` | none |
//! | `.yaml`, `.yml` | ROS `map_server` YAML naming a PGM or PNG image (seed 004) | [`read_ros_map`] | value 0 (free) | occupied, unknown | none |
//!
//! Coordinates everywhere: `x` = column, `y` = row, `(0, 0)` the top-left cell.
//!
//! ## Symbol choices
//! - Moving AI `S` (swamp) is **passable** and `W` (water) is **blocked**. The Moving AI
//!   format ([movingai.com/benchmarks/formats.html](https://movingai.com/benchmarks/formats.html))
//!   calls swamp passable from regular terrain and water traversable but not passable from
//!   terrain: a land unit cannot enter water, and a [`Grid`] only knows free and blocked, so
//!   water is an obstacle. `G` (ground) is passable like `.`; `@`, `O` (out of bounds) and
//!   `T` (trees) are blocked. None of the repository's maps contain `S` or `W`.
//! - In a `.txt` map every line starting with `#` is a comment (seed 003, section II.B
//!   "Input Parsing"), so `#` can never mean an obstacle there.
//! - In a `.csv` matrix `1` is traversable and `0` an obstacle, exactly as seed 000
//!   (section 2.1, equation (1): `m(x, y) = 1` denotes a traversable cell). This is the
//!   opposite of many occupancy-grid conventions, seed 003's included (1 = obstacle).
//! - [`to_movingai`] writes only `.` and `@`.
//!
//! # Design
//! Parsing and validation are separate. A parser accepts exactly its format and reports
//! anything else as a [`MapError`] naming the file, line and column (1-based) and what was
//! expected, for example `maps/wpi/bad.txt:7:12: expected '.' or 'X', found 'Q'`; no input
//! makes a parser panic, and a header declaring a huge map allocates nothing before the
//! rows are there. Start-goal pairs, however, are returned as they are written
//! ([`ProblemSpec`]): a pair on an obstacle (map2.txt's second goal, `(12, 3)`) is a
//! specification like any other, and [`ProblemSpec::problem`] (that is,
//! [`planner_api::Problem::new`]) rejects it later with an error naming the cell.
//!
//! ```
//! use planner_api::Cell;
//! use planner_maps::{parse_movingai, parse_seed003, to_movingai};
//!
//! let file = parse_seed003(
//!     "# Map 0\n# Start goal pairs:\n# 1. Start: (0,0) | Goal: (2,1)\n\n..X\n...\n",
//!     "tiny.txt",
//! )
//! .unwrap();
//! assert_eq!((file.grid.width(), file.grid.height()), (3, 2));
//! assert!(!file.grid.is_free(Cell::new(2, 0)));
//! assert_eq!(file.problems[0].goal, Cell::new(2, 1));
//! assert!(file.problems[0].problem(&file.grid).is_ok());
//!
//! // Moving AI round trip.
//! let text = to_movingai(&file.grid);
//! assert_eq!(parse_movingai(&text, "tiny.map").unwrap(), file.grid);
//!
//! // Errors name the position and what was expected.
//! let err = parse_seed003("..X\n.Q.\n", "bad.txt").unwrap_err();
//! assert_eq!(err.to_string(), "bad.txt:2:2: expected '.' or 'X', found 'Q'");
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

mod error;
mod matrix;
mod movingai;
mod ros;
mod scen;
mod seed003;
mod text;

use std::path::Path;

use planner_api::{Cell, Grid, Problem, ProblemError};
use serde::{Deserialize, Serialize};

pub use error::{MapError, MapErrorKind};
pub use matrix::parse_matrix;
pub use movingai::{movingai_passable, parse_movingai, to_movingai};
pub use ros::{
    parse_ros_yaml, read_ros_map, ros_grid, ros_occupancy_value, RosMap, RosMode, RosOptions,
    RosYaml,
};
pub use scen::{parse_scenarios, Scenario};
pub use seed003::parse_seed003;

/// A map file: its grid, the start-goal pairs it carries, and the format it was read from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MapFile {
    /// The occupancy grid.
    pub grid: Grid,
    /// Start-goal pairs in file order, not yet validated against the grid (empty for
    /// formats that carry none).
    pub problems: Vec<ProblemSpec>,
    /// The format the file was parsed as.
    pub format: MapFormat,
}

/// A start-goal pair as written in a file, before validation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct ProblemSpec {
    /// Start cell (x = column, y = row).
    pub start: Cell,
    /// Goal cell.
    pub goal: Cell,
    /// 1-based line the pair came from, 0 if none.
    pub line: usize,
}

impl ProblemSpec {
    /// The validated [`Problem`] on `grid`: errors, naming the cell, when the start or goal
    /// is outside the grid or blocked (see [`Problem::new`]).
    pub fn problem<'g>(&self, grid: &'g Grid) -> Result<Problem<'g>, ProblemError> {
        Problem::new(grid, self.start, self.goal)
    }
}

/// The map formats [`read_map`] reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum MapFormat {
    /// Moving AI `.map` ([`parse_movingai`]).
    MovingAi,
    /// Seed 003's text format, `.txt` ([`parse_seed003`]).
    Seed003,
    /// 0/1 matrix, `.csv` ([`parse_matrix`]).
    Matrix,
    /// ROS `map_server` YAML and image, `.yaml` or `.yml` ([`read_ros_map`], default options).
    Ros,
}

/// The extensions [`read_map`] supports, as listed in errors.
const MAP_EXTENSIONS: &str =
    "one of .map (Moving AI), .txt (seed 003), .csv (0/1 matrix), .yaml/.yml (ROS map_server); .scen files are read by read_scenarios";

impl MapFormat {
    /// The file extension of this format, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            MapFormat::MovingAi => "map",
            MapFormat::Seed003 => "txt",
            MapFormat::Matrix => "csv",
            MapFormat::Ros => "yaml",
        }
    }

    /// The format named by `path`'s extension (case-insensitive); an error listing the
    /// supported extensions otherwise.
    pub fn from_path(path: &Path) -> Result<MapFormat, MapError> {
        let extension = path.extension().map(|e| e.to_string_lossy().to_lowercase());
        match extension.as_deref() {
            Some("map") => Ok(MapFormat::MovingAi),
            Some("txt") => Ok(MapFormat::Seed003),
            Some("csv") => Ok(MapFormat::Matrix),
            Some("yaml" | "yml") => Ok(MapFormat::Ros),
            other => Err(unsupported(path, other, MAP_EXTENSIONS)),
        }
    }

    /// Parses `text` in this format; `origin` names it in error messages. For
    /// [`MapFormat::Ros`], `text` is the YAML and `origin` its path: the image is read from
    /// the file the YAML names, relative to `origin`'s directory.
    pub fn parse(self, text: &str, origin: &str) -> Result<MapFile, MapError> {
        let grid = match self {
            MapFormat::Ros => {
                ros::ros_map_from_yaml_text(text, Path::new(origin), &RosOptions::default())?.grid
            }
            MapFormat::Seed003 => return parse_seed003(text, origin),
            MapFormat::MovingAi => parse_movingai(text, origin)?,
            MapFormat::Matrix => parse_matrix(text, origin)?,
        };
        Ok(MapFile {
            grid,
            problems: Vec::new(),
            format: self,
        })
    }
}

fn unsupported(path: &Path, extension: Option<&str>, supported: &'static str) -> MapError {
    MapError::new(
        &path.display().to_string(),
        0,
        0,
        MapErrorKind::UnsupportedExtension {
            found: extension.map_or_else(|| "none".to_owned(), |e| format!("'.{e}'")),
            supported,
        },
    )
}

/// Reads a map file, choosing the format by extension: `.map`, `.txt`, `.csv` or `.yaml`
/// (see [`MapFormat::from_path`]). Errors name the path as given.
pub fn read_map(path: &Path) -> Result<MapFile, MapError> {
    let format = MapFormat::from_path(path)?;
    let origin = path.display().to_string();
    let text = read_text(path, &origin)?;
    format.parse(&text, &origin)
}

/// Reads a Moving AI `.scen` file (see [`parse_scenarios`]); any other extension is an
/// error. Errors name the path as given.
pub fn read_scenarios(path: &Path) -> Result<Vec<Scenario>, MapError> {
    let extension = path.extension().map(|e| e.to_string_lossy().to_lowercase());
    if extension.as_deref() != Some("scen") {
        return Err(unsupported(path, extension.as_deref(), ".scen"));
    }
    let origin = path.display().to_string();
    let text = read_text(path, &origin)?;
    parse_scenarios(&text, &origin)
}

/// The file's text; an error at the first byte that is not UTF-8.
fn read_text(path: &Path, origin: &str) -> Result<String, MapError> {
    let bytes = std::fs::read(path).map_err(|e| {
        MapError::new(
            origin,
            0,
            0,
            MapErrorKind::Io {
                message: e.to_string(),
            },
        )
    })?;
    String::from_utf8(bytes).map_err(|e| {
        let bytes = e.as_bytes();
        let valid = e.utf8_error().valid_up_to();
        let prefix = String::from_utf8_lossy(&bytes[..valid]);
        let line = prefix.matches('\n').count() + 1;
        let column = prefix.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        MapError::new(
            origin,
            line,
            column,
            MapErrorKind::Unexpected {
                expected: "UTF-8 text".to_owned(),
                found: format!("byte 0x{:02x}", bytes.get(valid).copied().unwrap_or(0)),
            },
        )
    })
}
