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
//! | `.csv` | 0/1 matrix, seed 000 equation (1) | [`parse_matrix`] | `1` (default; `0` with [`CsvConvention::OneIsObstacle`]) | `0` (default) | none |
//! | `.yaml`, `.yml` | ROS `map_server` YAML naming a PGM or PNG image (seed 004) | [`read_ros_map`], [`parse_ros_yaml`] | value 0 (free) | occupied, unknown | none |
//! | `.pgm`, `.png` | an occupancy image alone, read with `map_server`'s defaults ([`RosYaml::defaults`]) | [`ros_map_from_image_bytes`] | value 0 (free) | occupied, unknown | none |
//!
//! Coordinates everywhere: `x` = column, `y` = row, `(0, 0)` the top-left cell.
//!
//! Cell costs are opt-in ([`ReadOptions::costs`], [`costs`]): graded ROS maps (map_server's
//! `scale` and `raw` modes) through nav2's costmap cost bands, Moving AI terrain weights
//! for `S` and `W`, and `.csv` weight files ([`read_weights`]). Without them every reader
//! gives an unweighted grid.
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
//! - In a `.csv` matrix `1` is traversable and `0` an obstacle by default, exactly as seed
//!   000 (section 2.1, equation (1): `m(x, y) = 1` denotes a traversable cell). This is the
//!   opposite of many occupancy-grid conventions, seed 003's included (1 = obstacle), so
//!   [`ReadOptions::csv`] chooses, and [`csv_inversion_hint`] says when a problem looks
//!   written for the other convention.
//! - [`to_movingai`] writes only `.` and `@`.
//!
//! # Design
//! Parsing and validation are separate. A parser accepts exactly its format and reports
//! anything else as a [`MapError`] naming the file, line and column (1-based) and what was
//! expected, for example `maps/wpi/bad.txt:7:12: expected '.' or 'X', found 'Q'`; no input
//! makes a parser panic (each has a fuzz target, `fuzz/README.md`). Memory is bounded by
//! [`ReadOptions`]: only regular files are read, up to [`ReadOptions::max_file_bytes`],
//! a `.map` header or an image declaring more than [`ReadOptions::max_cells`] cells is an
//! error before anything is allocated for its cells, `.txt` and `.csv` reading stops
//! at the row that passes the limit, and an image's cells take memory as its pixel data
//! is read, so a file declaring more than it holds costs what it holds. What a reader
//! accepts but ignores (a ROS YAML key `map_server` does not read) is a [`MapWarning`]
//! ([`read_map_with`]).
//!
//! Start-goal pairs are returned as they are written
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

pub mod costs;
mod error;
pub mod gppc;
mod matrix;
mod movingai;
mod ros;
mod scen;
mod seed003;
mod text;

use std::path::Path;

use planner_api::{Cell, Grid, Problem, ProblemError};
use serde::{Deserialize, Serialize};

pub use costs::{
    costmap_cost, parse_weights, read_weights, CostBands, CostOptions, TerrainWeights,
};
pub use error::{MapError, MapErrorKind, MapWarning};
pub use matrix::{csv_inversion_hint, parse_matrix, CsvConvention, InversionHint};
pub use movingai::{movingai_passable, parse_movingai, to_movingai};
pub use ros::{
    metres, parse_ros_yaml, read_ros_map, read_ros_map_with, ros_grid, ros_map_from_image_bytes,
    ros_occupancy_value, FrameError, MapFrame, RosMap, RosMode, RosOptions, RosYaml,
};
pub use scen::{parse_scenarios, Scenario};
pub use seed003::parse_seed003;

/// A map file: its grid, the start-goal pairs it carries, and the format it was read from.
#[derive(Debug, Clone, PartialEq)]
pub struct MapFile {
    /// The occupancy grid.
    pub grid: Grid,
    /// Start-goal pairs in file order, not yet validated against the grid (empty for
    /// formats that carry none).
    pub problems: Vec<ProblemSpec>,
    /// The format the file was parsed as.
    pub format: MapFormat,
    /// Where the cells lie in the ROS map frame: a `map_server` YAML's `resolution` and
    /// `origin` (`None` for the other formats, an image read without a YAML included, and
    /// a YAML whose frame is unusable: [`MapFile::frame_error`]).
    pub frame: Option<MapFrame>,
    /// Why a `map_server` YAML's map has no [`MapFile::frame`]: its `resolution` is not
    /// positive, or its extent is beyond the range of numbers; `None` when it has one and
    /// for the other formats, which have no frame to lose.
    pub frame_error: Option<FrameError>,
    /// One flag per cell, row-major, true where a ROS `map_server` map (or an image read
    /// as one) does not know the cell (occupancy `-1`), for figures that draw such cells
    /// apart from walls; `None` for the other formats and for maps with no unknown cell.
    pub unknown: Option<Vec<bool>>,
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
    /// 0/1 matrix, `.csv` ([`parse_matrix`]; [`ReadOptions::csv`] says which value is an
    /// obstacle).
    Matrix,
    /// ROS `map_server` YAML and image, `.yaml` or `.yml` ([`read_ros_map`], default options).
    Ros,
    /// A PGM or PNG image given directly, `.pgm` or `.png`: read like a `map_server` image
    /// with `map_server`'s defaults ([`RosYaml::defaults`]: trinary mode, occupied above
    /// 0.65, free below 0.196, not negated).
    Image,
}

/// The extensions [`read_map`] supports, as listed in errors.
const MAP_EXTENSIONS: &str =
    "one of .map (Moving AI), .txt (seed 003), .csv (0/1 matrix), .yaml/.yml (ROS map_server), .pgm/.png (an occupancy image); .scen files hold scenarios, not maps";

/// The default of [`ReadOptions::max_cells`]: [`Grid::MAX_CELLS`] (2^31 cells), the largest
/// grid there is. A caller with a memory budget lowers it with [`max_cells_for_memory_mb`]
/// (the runner does, from `max_memory_mb`), so real large maps are read when they fit the
/// budget instead of being refused at a fixed size.
pub const DEFAULT_MAX_CELLS: u64 = Grid::MAX_CELLS;

/// Bytes per cell a reader holds at its peak, besides the file's own bytes: the grid (one
/// byte a cell) and one value a cell it is built from (the ROS occupancy value, computed
/// from a PGM's, PPM's, PAM's or PBM's samples as they are read, or from a PNG's rows as
/// they are decoded, one row held at a time; a text format's row). An interlaced PNG holds
/// its values twice while they are put in row order, before the grid is built, and
/// `inflation_radius` adds its distance transform.
pub const READ_BYTES_PER_CELL: u64 = 2;

/// The fewest cells [`max_cells_for_memory_mb`] allows, whatever the budget: 2^24 (a
/// 4096 x 4096 map, 32 MiB to read). A budget too small for a planner's arrays (even 0)
/// still reads an ordinary map, so that the planner can say what it would need.
pub const MIN_BUDGET_CELLS: u64 = 1 << 24;

/// The most cells a map read within a budget of `max_memory_mb` MiB may have:
/// `max_memory_mb` MiB / [`READ_BYTES_PER_CELL`], at least [`MIN_BUDGET_CELLS`] and at
/// most [`Grid::MAX_CELLS`].
///
/// ```
/// use planner_maps::{max_cells_for_memory_mb, DEFAULT_MAX_CELLS, MIN_BUDGET_CELLS};
/// // A 20000 x 20000 map (4 * 10^8 cells) is read within 1000 MiB, not within 500.
/// assert!(max_cells_for_memory_mb(1000) >= 20_000 * 20_000);
/// assert!(max_cells_for_memory_mb(500) < 20_000 * 20_000);
/// assert_eq!(max_cells_for_memory_mb(0), MIN_BUDGET_CELLS);
/// assert_eq!(max_cells_for_memory_mb(u64::MAX), DEFAULT_MAX_CELLS);
/// ```
pub fn max_cells_for_memory_mb(max_memory_mb: u64) -> u64 {
    (max_memory_mb.saturating_mul(1 << 20) / READ_BYTES_PER_CELL)
        .clamp(MIN_BUDGET_CELLS, Grid::MAX_CELLS)
}

/// The default of [`ReadOptions::max_file_bytes`]: 2^30 bytes (1 GiB).
pub const DEFAULT_MAX_FILE_BYTES: u64 = 1 << 30;

/// How [`read_map_with`] and [`MapFormat::parse_with`] read: limits that bound the memory
/// any input can make a reader use, and the choices a format leaves open.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ReadOptions {
    /// The most cells a map may have ([`DEFAULT_MAX_CELLS`] by default; a memory budget's
    /// with [`max_cells_for_memory_mb`]). A header or image declaring more is an error
    /// ([`MapErrorKind::TooManyCells`]) before anything is allocated for the cells; row
    /// formats (`.txt`, `.csv`) stop at the row that passes it. A `.map` header declaring
    /// more cells than its file has bytes reserves no more than the file's size.
    pub max_cells: u64,
    /// The largest file, in bytes, that is read ([`DEFAULT_MAX_FILE_BYTES`] by default);
    /// larger is [`MapErrorKind::FileTooLarge`]. Files other than regular files (devices
    /// such as `/dev/zero`, FIFOs, directories) are never read
    /// ([`MapErrorKind::NotRegularFile`]).
    pub max_file_bytes: u64,
    /// Which value of a `.csv` matrix is an obstacle (default `0`, seed 000).
    pub csv: CsvConvention,
    /// Inflation for ROS `map_server` maps and images (default none).
    pub ros: RosOptions,
    /// Cell costs: graded ROS maps, Moving AI terrain (default none: unweighted grids).
    pub costs: CostOptions,
}

impl Default for ReadOptions {
    fn default() -> ReadOptions {
        ReadOptions {
            max_cells: DEFAULT_MAX_CELLS,
            max_file_bytes: DEFAULT_MAX_FILE_BYTES,
            csv: CsvConvention::default(),
            ros: RosOptions::default(),
            costs: CostOptions::default(),
        }
    }
}

/// A map file as [`read_map_with`] reads it: the file, and what the reader ignored or
/// doubts (today only ROS `map_server` YAML files have warnings: keys `map_server` does not
/// read, values it reads in a surprising way).
#[derive(Debug, Clone, PartialEq)]
pub struct MapRead {
    /// The map.
    pub file: MapFile,
    /// Warnings in file order, each naming file, line and column.
    pub warnings: Vec<MapWarning>,
}

impl MapFormat {
    /// The file extension of this format, without the dot (`png` for [`MapFormat::Image`],
    /// which also reads `.pgm`).
    pub fn extension(self) -> &'static str {
        match self {
            MapFormat::MovingAi => "map",
            MapFormat::Seed003 => "txt",
            MapFormat::Matrix => "csv",
            MapFormat::Ros => "yaml",
            MapFormat::Image => "png",
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
            Some("png" | "pgm") => Ok(MapFormat::Image),
            other => Err(unsupported(path, other, MAP_EXTENSIONS)),
        }
    }

    /// Parses `text` in this format with the default [`ReadOptions`]; `origin` names it in
    /// error messages. For [`MapFormat::Ros`], `text` is the YAML and `origin` its path:
    /// the image is read from the file the YAML names, relative to `origin`'s directory.
    /// For [`MapFormat::Image`], `text` is the image (an ASCII PGM, say).
    pub fn parse(self, text: &str, origin: &str) -> Result<MapFile, MapError> {
        self.parse_with(text, origin, &ReadOptions::default())
            .map(|read| read.file)
    }

    /// [`MapFormat::parse`] with `options`, keeping the warnings.
    pub fn parse_with(
        self,
        text: &str,
        origin: &str,
        options: &ReadOptions,
    ) -> Result<MapRead, MapError> {
        let max_cells = options.max_cells;
        let grid = match self {
            MapFormat::Ros | MapFormat::Image => {
                let map = if self == MapFormat::Ros {
                    ros::ros_map_from_yaml_text(text, Path::new(origin), options)?
                } else {
                    ros::ros_map_from_image_bytes(text.as_bytes(), origin, None, options)?
                };
                // A frame needs a positive resolution (the YAML's warning says when it is not)
                // and an extent within the range of numbers (said here).
                let (frame, frame_error) = match self {
                    MapFormat::Ros => match map.frame().checked() {
                        Ok(frame) => (Some(frame), None),
                        Err(error) => (None, Some(error)),
                    },
                    _ => (None, None),
                };
                let unknown = map.unknown_cells();
                let mut warnings = map.yaml.warnings;
                if let Some(error @ FrameError::BeyondRange { .. }) = frame_error {
                    warnings.push(MapWarning {
                        file: origin.to_string(),
                        line: 0,
                        column: 0,
                        message: format!("{error}: map positions are meaningless"),
                    });
                }
                let file = MapFile {
                    unknown,
                    grid: map.grid,
                    problems: Vec::new(),
                    format: self,
                    frame,
                    frame_error,
                };
                return Ok(MapRead { file, warnings });
            }
            MapFormat::Seed003 => {
                return seed003::parse(text, origin, max_cells).map(|file| MapRead {
                    file,
                    warnings: Vec::new(),
                })
            }
            MapFormat::MovingAi => match options.costs.terrain {
                None => movingai::parse(text, origin, max_cells)?,
                Some(terrain) => {
                    movingai::parse_terrain(text, origin, max_cells, terrain, options.costs.rule)?
                }
            },
            MapFormat::Matrix => matrix::parse(text, origin, options.csv, max_cells)?,
        };
        Ok(MapRead {
            file: MapFile {
                grid,
                problems: Vec::new(),
                format: self,
                frame: None,
                frame_error: None,
                unknown: None,
            },
            warnings: Vec::new(),
        })
    }

    /// Parses the bytes of a file in this format: the text formats must be UTF-8 (an error
    /// at the first byte that is not), an image is decoded. The entry point for input that
    /// is not in a file (the fuzz targets use it); `origin` names the bytes in messages and,
    /// for [`MapFormat::Ros`], is the path the image is resolved against.
    pub fn parse_bytes(
        self,
        bytes: &[u8],
        origin: &str,
        options: &ReadOptions,
    ) -> Result<MapRead, MapError> {
        if self == MapFormat::Image {
            let map = ros::ros_map_from_image_bytes(bytes, origin, None, options)?;
            return Ok(MapRead {
                file: MapFile {
                    unknown: map.unknown_cells(),
                    grid: map.grid,
                    problems: Vec::new(),
                    format: self,
                    frame: None,
                    frame_error: None,
                },
                warnings: map.yaml.warnings,
            });
        }
        self.parse_with(utf8(bytes, origin)?, origin, options)
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

/// Reads a map file with the default [`ReadOptions`], choosing the format by extension:
/// `.map`, `.txt`, `.csv`, `.yaml`, `.pgm` or `.png` (see [`MapFormat::from_path`]). Errors
/// name the path as given.
pub fn read_map(path: &Path) -> Result<MapFile, MapError> {
    read_map_with(path, &ReadOptions::default()).map(|read| read.file)
}

/// Reads a map file with `options`, keeping the warnings (see [`read_map`]). Only regular
/// files are read, and only up to [`ReadOptions::max_file_bytes`].
pub fn read_map_with(path: &Path, options: &ReadOptions) -> Result<MapRead, MapError> {
    let format = MapFormat::from_path(path)?;
    let origin = path.display().to_string();
    let bytes = read_file(path, &origin, options.max_file_bytes)?;
    format.parse_bytes(&bytes, &origin, options)
}

/// Reads a Moving AI `.scen` file (see [`parse_scenarios`]); any other extension is an
/// error. Errors name the path as given. Only regular files of at most
/// [`DEFAULT_MAX_FILE_BYTES`] are read.
pub fn read_scenarios(path: &Path) -> Result<Vec<Scenario>, MapError> {
    let extension = path.extension().map(|e| e.to_string_lossy().to_lowercase());
    if extension.as_deref() != Some("scen") {
        return Err(unsupported(path, extension.as_deref(), ".scen"));
    }
    let origin = path.display().to_string();
    let bytes = read_file(path, &origin, DEFAULT_MAX_FILE_BYTES)?;
    parse_scenarios(utf8(&bytes, &origin)?, &origin)
}

/// The text of the regular file at `path` (at most `max_bytes` bytes, UTF-8), read with the
/// same guards as the map readers: anything but a regular file (a directory, `/dev/zero`, a
/// FIFO) is refused before it is opened, a larger file is [`MapErrorKind::FileTooLarge`],
/// and a byte that is not UTF-8 is an error at its line and column. Errors name the path
/// as given. For the other text files a project reads (experiment configs, published
/// values).
///
/// ```
/// use std::path::Path;
/// use planner_maps::{read_text_file, MapErrorKind};
///
/// let error = read_text_file(Path::new("/dev/zero"), 1 << 20).unwrap_err();
/// assert!(matches!(error.kind, MapErrorKind::NotRegularFile { .. }));
/// ```
pub fn read_text_file(path: &Path, max_bytes: u64) -> Result<String, MapError> {
    let origin = path.display().to_string();
    let bytes = read_file(path, &origin, max_bytes)?;
    utf8(&bytes, &origin)?;
    String::from_utf8(bytes).map_err(|e| {
        MapError::new(
            &origin,
            0,
            0,
            MapErrorKind::Io {
                message: e.to_string(),
            },
        )
    })
}

/// Writes `bytes` to `path` whole or not at all: into a new file beside it (created, never
/// opened through a link), then renamed over it, so that an error or an interruption leaves
/// the old file as it was and a link at `path` is replaced, not written through. A
/// read-only file at `path` is refused (`PermissionDenied`), as writing it in place would
/// be: the rename would replace it regardless of its bits. For the files gridplan writes
/// beside a user's (a map written by `cargo xtask`, a picture of `plan`).
pub fn write_whole(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write as _;
    if std::fs::symlink_metadata(path).is_ok_and(|m| m.is_file() && m.permissions().readonly()) {
        return Err(std::io::Error::new(
            std::io::ErrorKind::PermissionDenied,
            "the file is read-only",
        ));
    }
    let name = path
        .file_name()
        .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file name"))?;
    let mut partial = std::ffi::OsString::from(".");
    partial.push(name);
    partial.push(format!(".gridplan-{}.partial", std::process::id()));
    let partial = path.with_file_name(partial);
    let written = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&partial)
        .and_then(|mut out| out.write_all(bytes).and_then(|()| out.sync_all()))
        .and_then(|()| std::fs::rename(&partial, path));
    if written.is_err() {
        let _ = std::fs::remove_file(&partial);
    }
    written
}

/// The bytes of the regular file at `path`, at most `max_bytes` of them; errors name
/// `origin`. A path that names anything but a regular file (after following symbolic
/// links) is refused before it is opened, so a FIFO cannot block and a device cannot
/// stream forever; the size is checked again on the open file, and reading stops after
/// `max_bytes + 1` bytes whatever the file does meanwhile.
pub(crate) fn read_file(path: &Path, origin: &str, max_bytes: u64) -> Result<Vec<u8>, MapError> {
    use std::io::Read;
    let io = |e: std::io::Error| {
        MapError::new(
            origin,
            0,
            0,
            MapErrorKind::Io {
                message: e.to_string(),
            },
        )
    };
    let whole = |kind| MapError::new(origin, 0, 0, kind);
    let check = |metadata: &std::fs::Metadata| -> Result<(), MapError> {
        if !metadata.is_file() {
            return Err(whole(MapErrorKind::NotRegularFile {
                what: file_kind(&metadata.file_type()),
            }));
        }
        if metadata.len() > max_bytes {
            return Err(whole(MapErrorKind::FileTooLarge {
                bytes: metadata.len(),
                max_bytes,
            }));
        }
        Ok(())
    };
    check(&std::fs::metadata(path).map_err(io)?)?;
    let file = std::fs::File::open(path).map_err(io)?;
    let metadata = file.metadata().map_err(io)?;
    check(&metadata)?;
    let mut bytes = Vec::with_capacity(usize::try_from(metadata.len()).unwrap_or(0));
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > max_bytes {
        return Err(whole(MapErrorKind::FileTooLarge {
            bytes: bytes.len() as u64,
            max_bytes,
        }));
    }
    Ok(bytes)
}

/// `error`, from reading a file that another file names, placed where the name is written
/// (`origin`, `line`, `column`) when the file cannot be read at all
/// ([`MapErrorKind::NamedFile`]); an error about its contents keeps its own place.
pub(crate) fn at_name(
    error: MapError,
    origin: &str,
    (line, column): (usize, usize),
    what: &'static str,
    name: &str,
) -> MapError {
    match error.kind {
        MapErrorKind::Io { .. }
        | MapErrorKind::NotRegularFile { .. }
        | MapErrorKind::FileTooLarge { .. }
            if error.line == 0 =>
        {
            MapError::new(
                origin,
                line,
                column,
                MapErrorKind::NamedFile {
                    what,
                    name: name.to_owned(),
                    path: error.file,
                    reason: Box::new(error.kind),
                },
            )
        }
        _ => error,
    }
}

/// What a file type that is not a regular file is, for messages ("a FIFO", "a character
/// device", ...).
pub fn file_kind(file_type: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_char_device() {
            return "a character device";
        }
        if file_type.is_block_device() {
            return "a block device";
        }
        if file_type.is_fifo() {
            return "a FIFO";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    if file_type.is_dir() {
        "a directory"
    } else {
        "neither a file nor a directory"
    }
}

/// The bytes as UTF-8 text; an error at the first byte that is not UTF-8.
pub(crate) fn utf8<'b>(bytes: &'b [u8], origin: &str) -> Result<&'b str, MapError> {
    std::str::from_utf8(bytes).map_err(|e| {
        let valid = e.valid_up_to();
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
