//! The one error type of this crate: what went wrong, and where.

use std::fmt;

use planner_api::GridError;
use thiserror::Error;

/// A file that could not be read or parsed, with the position of the problem.
///
/// Displays as `file:line:column: message` (both 1-based). Errors about a whole line
/// have `column == 0` and display as `file:line: message`; errors about the whole file
/// (I/O, extension) have `line == 0` and display as `file: message`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MapError {
    /// The file name given by the caller (`origin`) or the path that was read.
    pub file: String,
    /// 1-based line, or 0 when the error concerns the whole file.
    pub line: usize,
    /// 1-based column in characters, or 0 when the error concerns the whole line.
    pub column: usize,
    /// What went wrong.
    pub kind: MapErrorKind,
}

impl MapError {
    /// An error at `line`, `column` of `file`.
    pub fn new(file: &str, line: usize, column: usize, kind: MapErrorKind) -> MapError {
        MapError {
            file: file.to_owned(),
            line,
            column,
            kind,
        }
    }
}

impl fmt::Display for MapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.line, self.column) {
            (0, _) => write!(f, "{}: {}", self.file, self.kind),
            (line, 0) => write!(f, "{}:{}: {}", self.file, line, self.kind),
            (line, column) => write!(f, "{}:{}:{}: {}", self.file, line, column, self.kind),
        }
    }
}

impl std::error::Error for MapError {}

/// Something a reader accepted but ignored or doubts, with its position: a key that
/// `map_server` does not read, a value it reads in a surprising way. The file is still
/// read; the caller decides whether to print the warning.
///
/// Displays like [`MapError`]: `file:line:column: message`, `file:line: message` or
/// `file: message`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MapWarning {
    /// The file name given by the caller or the path that was read.
    pub file: String,
    /// 1-based line, or 0 when the warning concerns the whole file.
    pub line: usize,
    /// 1-based column in characters, or 0 when the warning concerns the whole line.
    pub column: usize,
    /// What was ignored or doubted, lowercase.
    pub message: String,
}

impl fmt::Display for MapWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.line, self.column) {
            (0, _) => write!(f, "{}: {}", self.file, self.message),
            (line, 0) => write!(f, "{}:{}: {}", self.file, line, self.message),
            (line, column) => write!(f, "{}:{}:{}: {}", self.file, line, column, self.message),
        }
    }
}

/// What went wrong while reading a map or scenario file. Messages are lowercase and say
/// what was expected.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum MapErrorKind {
    /// The file could not be read.
    #[error("cannot read the file: {message}")]
    Io {
        /// The operating system's message.
        message: String,
    },
    /// The path names something other than a regular file (a directory, a device such as
    /// `/dev/zero`, a FIFO, a socket): such a file may never end, so it is not read.
    #[error("not a regular file ({what}): gridplan reads its inputs (maps, images, scenarios, configs, weights) from regular files only")]
    NotRegularFile {
        /// What the path names (`a directory`, `a character device`, ...).
        what: &'static str,
    },
    /// A file larger than the reader's limit ([`crate::ReadOptions::max_file_bytes`]).
    #[error("the file has {bytes} bytes, more than the limit of {max_bytes} bytes")]
    FileTooLarge {
        /// The file's size.
        bytes: u64,
        /// The limit.
        max_bytes: u64,
    },
    /// A map or image declaring more cells than the reader's limit
    /// ([`crate::ReadOptions::max_cells`]); nothing was allocated for them.
    #[error("a {width}x{height} map has {cells} cells, more than the limit of {max_cells} cells", cells = u128::from(*width) * u128::from(*height))]
    TooManyCells {
        /// Declared (or, for row formats, counted so far) width.
        width: u64,
        /// Declared (or counted so far) height.
        height: u64,
        /// The limit.
        max_cells: u64,
    },
    /// The extension names no supported format.
    #[error("unsupported file extension {found}, expected {supported}")]
    UnsupportedExtension {
        /// The extension found, quoted, or `none`.
        found: String,
        /// The supported extensions.
        supported: &'static str,
    },
    /// The general case: something other than what the format allows at this position.
    #[error("expected {expected}, found {found}")]
    Unexpected {
        /// What the format allows here.
        expected: String,
        /// What the file has (quoted text, `end of line` or `end of file`).
        found: String,
    },
    /// A number that does not fit in 32 bits.
    #[error("{what} {text} is too large (at most 4294967295)")]
    NumberTooLarge {
        /// Which number (`height`, `start x`, ...).
        what: &'static str,
        /// The digits found.
        text: String,
    },
    /// A Moving AI header without one of `type`, `height`, `width`.
    #[error("missing header key '{key}' before 'map'")]
    MissingKey {
        /// The missing key.
        key: &'static str,
    },
    /// A Moving AI header key given twice.
    #[error("duplicate header key '{key}', already given on line {first_line}")]
    DuplicateKey {
        /// The repeated key.
        key: &'static str,
        /// Where it was first given.
        first_line: usize,
    },
    /// Text that is not valid YAML (ROS `map_server` files), as the YAML parser says.
    #[error("invalid YAML: {message}")]
    Yaml {
        /// The parser's message.
        message: String,
    },
    /// A required key missing from a ROS `map_server` YAML file.
    #[error("missing key '{key}'")]
    MissingField {
        /// The missing key.
        key: &'static str,
    },
    /// An image that cannot be decoded (ROS `map_server` maps).
    #[error("cannot decode the image: {message}")]
    Image {
        /// The decoder's message.
        message: String,
    },
    /// An image whose pixel data ends before the size its header declares: the file is
    /// cut short, or its compressed data damaged. Only the pixels it held were read.
    #[error("the pixel data ends after {pixels} of the {width}x{height} pixels the header declares ({reason}): the file is cut short or damaged")]
    ImageCutShort {
        /// Pixels read before the data ended.
        pixels: u64,
        /// Declared width.
        width: u32,
        /// Declared height.
        height: u32,
        /// The decoder's message.
        reason: String,
    },
    /// Graded costs asked of a `mode: trinary` map (or an image without a YAML), whose
    /// cells are only free, occupied or unknown: without a cost for unknown cells the
    /// option would change nothing but make the grid a weighted one.
    #[error("graded costs (--graded, --lethal, `costs`) read a map_server map of mode scale or raw; this map is mode trinary (cells free, occupied or unknown), so they change nothing: give unknown cells a cost (--unknown N, `costs = {{ unknown = N }}`) or leave them out")]
    GradedTrinary,
    /// A PNG whose header declares pixels that its compressed data cannot hold: nothing
    /// was decoded.
    #[error("the header declares {width}x{height} pixels, {needed} bytes, but the file's {compressed} bytes of compressed pixel data inflate to at most {at_most} bytes: the file is cut short or damaged")]
    ImageDataTooSmall {
        /// Declared width.
        width: u32,
        /// Declared height.
        height: u32,
        /// The bytes the pixels take (their bits, without the rows' filter bytes).
        needed: u64,
        /// The bytes of compressed pixel data (`IDAT` chunks) the file holds.
        compressed: u64,
        /// The most they inflate to.
        at_most: u64,
    },
    /// Not enough memory for a map's cells (the allocation failed; the map is within
    /// [`crate::ReadOptions::max_cells`]).
    #[error("not enough memory for the map's {cells} cells")]
    OutOfMemory {
        /// The map's cells.
        cells: u64,
    },
    /// A file named by another file (a ROS YAML's `image`, a GPPC scenario's `patch`)
    /// that cannot be read: the error is placed where the name is written, and says
    /// the path the name resolves to when that differs from the name.
    #[error("{what} {}{}: {reason}", quoted(.name), resolved(.name, .path))]
    NamedFile {
        /// What the file is to the one naming it (`image`, `patch file`).
        what: &'static str,
        /// The name as written.
        name: String,
        /// The path read (the name resolved against the naming file's directory).
        path: String,
        /// Why it cannot be read ([`MapErrorKind::Io`], [`MapErrorKind::NotRegularFile`]
        /// or [`MapErrorKind::FileTooLarge`]).
        reason: Box<MapErrorKind>,
    },
    /// Fewer map rows than the declared height.
    #[error("expected {expected} rows (height {expected}), found {found}")]
    RowCount {
        /// The declared height.
        expected: usize,
        /// Rows present.
        found: usize,
    },
    /// A map row of the wrong length.
    #[error("expected {expected} cells ({reference}), found {found}")]
    RowWidth {
        /// Cells the row should have.
        expected: usize,
        /// Cells it has.
        found: usize,
        /// Where the expected width comes from (`width 49`, `as in the first row, line 6`).
        reference: String,
    },
    /// A scenario line without exactly 9 tab-separated fields.
    #[error("expected 9 tab-separated fields, found {found}")]
    FieldCount {
        /// Fields present.
        found: usize,
    },
    /// The rows parse but make no valid [`planner_api::Grid`] (too many cells).
    #[error("invalid grid: {0}")]
    Grid(GridError),
    /// A GPPC dynamic scenario's patch command whose patch does not fit the map: names
    /// the first patch cell that falls outside.
    #[error("patch {patch} ({patch_width}x{patch_height}) placed at ({x}, {y}) puts its cell {cell} outside the {width}x{height} map")]
    PatchOutside {
        /// The patch's number.
        patch: u32,
        /// The patch's width.
        patch_width: u32,
        /// The patch's height.
        patch_height: u32,
        /// Column of the patch's top-left cell.
        x: u32,
        /// Row of the patch's top-left cell.
        y: u32,
        /// The first cell (row-major) outside the map.
        cell: planner_api::Cell,
        /// Map width.
        width: u32,
        /// Map height.
        height: u32,
    },
    /// A GPPC dynamic scenario's command naming a patch the patch file does not have.
    #[error("patch {patch} does not exist: the patch file has {patches} patches")]
    UnknownPatch {
        /// The patch number named.
        patch: u32,
        /// Patches in the file.
        patches: usize,
    },
    /// A GPPC dynamic scenario's query whose start or goal lies outside the map.
    #[error("{endpoint} {cell} is outside the {width}x{height} map")]
    QueryOutside {
        /// `start` or `goal`.
        endpoint: &'static str,
        /// The cell.
        cell: planner_api::Cell,
        /// Map width.
        width: u32,
        /// Map height.
        height: u32,
    },
    /// A scenario whose declared map size differs from the grid's.
    #[error(
        "the scenario is for a {scen_width}x{scen_height} map, but the grid is {width}x{height}"
    )]
    SizeMismatch {
        /// Width declared by the scenario.
        scen_width: u32,
        /// Height declared by the scenario.
        scen_height: u32,
        /// Grid width.
        width: u32,
        /// Grid height.
        height: u32,
    },
}

/// A file name quoted for a message, whole (unlike a token, it is never shortened).
fn quoted(name: &str) -> String {
    format!("'{}'", name.escape_debug())
}

/// ` (path)` when `path` differs from the `name` it was resolved from, else nothing.
fn resolved(name: &str, path: &str) -> String {
    if name == path {
        String::new()
    } else {
        format!(" ({path})")
    }
}
