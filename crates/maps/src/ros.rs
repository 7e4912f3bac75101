//! ROS `map_server` maps: a YAML file naming an image (PGM or PNG), read into a grid.
//!
//! # The YAML file
//! The file `map_server` and `map_saver` use (<https://wiki.ros.org/map_server#YAML_format>,
//! and ROS 2's `nav2_map_server`), parsed as YAML 1.2 by `saphyr-parser`: any layout YAML
//! allows (block or flow mappings and sequences, quoted or plain scalars, comments,
//! anchors and aliases, `---`) is read. The top level is a mapping with these keys:
//!
//! | key | value | required |
//! |---|---|---|
//! | `image` | image path, relative to the YAML file's directory unless absolute | yes |
//! | `resolution` | metres per cell | yes |
//! | `origin` | `[x, y, yaw]`: the pose of the lower-left cell in metres and radians | yes |
//! | `occupied_thresh` | occupancy probability above which a cell is occupied | yes |
//! | `free_thresh` | occupancy probability below which a cell is free | yes |
//! | `negate` | an integer (non-zero: negate), or a boolean (`true`, `yes`, `on`, ...) with a warning | yes |
//! | `mode` | `trinary` (default), `scale` or `raw` | no |
//!
//! The rules are `map_server`'s (ROS 1 `map_server` and ROS 2 `nav2_map_server`, both on
//! yaml-cpp): a value is read from its text whether quoted or not (`"0.05"` is a number,
//! `mode: "trinary"` a mode), and every file either of them accepts is accepted here.
//! What they accept silently is read with a [`MapWarning`] ([`RosYaml::warnings`]):
//! - a key neither reads (`map_type`, `map_name`, a misspelt `free_tresh`): ignored;
//! - `negate` other than `0` or `1`: non-zero negates, as in `map_server`;
//! - `negate` as a boolean (`yes`, `true`, `on`, ...): ROS 2's `nav2_map_server` reads it
//!   as that boolean (it tries `int`, then `bool`), ROS 1's `map_server` refuses the file
//!   (it reads an `int` only); read as ROS 2 does, with a warning saying both;
//! - `origin` with more than three numbers: ROS 1 reads the first three (ROS 2 refuses);
//! - `resolution` not positive, a threshold outside [0, 1], `free_thresh` above
//!   `occupied_thresh`: read as written, though the map frame or the thresholds are then
//!   meaningless;
//! - a second YAML document after the first: ignored, as yaml-cpp's `LoadFile` does.
//!
//! Errors, naming the file, line and column (1-based, in characters; lines are ended by
//! YAML's line breaks, `\n`, `\r\n` or a lone `\r`): invalid YAML; a top
//! level that is not a mapping; a missing required key; a value of the wrong kind (a
//! sequence for `image`, text for a number, fewer than three `origin` numbers, an unknown
//! `mode`, an empty `image`); and two choices stricter than `map_server`: a key given twice
//! (YAML 1.2 requires unique keys; which value yaml-cpp uses is an implementation detail)
//! and a number that is not finite (`.inf`, `.nan`), which makes no usable map. Nesting
//! deeper than 64 levels is refused, which bounds the reader's stack use.
//!
//! # The threshold rule
//! That of ROS 2's `nav2_map_server` (`map_io.cpp`, `loadMapFromFile`), which for
//! `trinary` 8-bit grey and RGB images is also ROS 1 `map_server`'s (`image_loader.cpp`).
//! For each pixel, `v` is the mean of its red, green and blue samples (a grey pixel's
//! three equal channels: its grey) and, with `mode: trinary` in an image that has an
//! alpha channel (a PNG's or PAM's own, or a PNG's `tRNS` transparency), of its alpha
//! too, as nav2 averages them: a grey and alpha pixel's `v` is `(3 grey + alpha) / 4`, so
//! an opaque grey 179 is `v = 198`. The shade is `v / maxval` at full precision, where `maxval` is
//! the largest sample value: 255 for 8-bit samples, 65535 for 16-bit ones (PNG), and
//! the header's for a PGM, PPM or PAM, whose samples are read as written (a sample above
//! it is an error). `p = 1 - shade`, or `p = shade` when `negate`, is the occupancy
//! probability: white is free, black occupied. (nav2's GraphicsMagick, built with 16-bit
//! quanta as ROS packages it, holds each sample as a multiple of 1/65535: exactly
//! `v / maxval` for 8- and 16-bit samples, within half a quantum of it for a PGM's other
//! maxvals.)
//!
//! Then, as ROS values:
//! - `trinary` and `scale`: `p > occupied_thresh` is occupied, `100`; `p < free_thresh`
//!   free, `0`;
//! - otherwise unknown, `-1`, in `trinary` mode; in `scale` mode the graded value
//!   `rint(100 (p - free_thresh) / (occupied_thresh - free_thresh))` (C's `rint`: to the
//!   nearest, halves to even), and unknown for any pixel that is not fully opaque
//!   (`alpha != maxval`; nav2 tests this first);
//! - `raw` mode skips the thresholds and `negate`, as nav2 does: the value is
//!   `round(255 shade)` (for 8-bit samples the mean `v` itself) when it is at most 100,
//!   else unknown `-1`.
//!
//! ROS 1 `map_server` differs in the last two (its `scale` is `1 + 98 (...)` truncated with
//! only a fully transparent pixel unknown, its `raw` the negated value as a signed byte);
//! gridplan follows ROS 2.
//!
//! # Costs (opt-in)
//! By default a grid is free exactly where the value is `0`. With
//! [`crate::CostOptions::graded`] the graded values become cell weights the way ROS 2
//! navigation's costmap does ([`crate::costs`]).
//!
//! An image given directly (`.pgm`, `.png`, without a YAML file) is read with
//! [`RosYaml::defaults`]: `map_server`'s default thresholds (occupied 0.65, free 0.196),
//! not negated, trinary.
//!
//! A cell of the [`Grid`] is free exactly when its value is `0`; occupied, partly occupied
//! and **unknown cells are blocked**, since seed 004 plans "on grid cells that are entirely
//! vacant" (section 3). [`RosOptions::inflation_radius`] then blocks every cell whose
//! centre lies within that many cells (Euclidean, centre to centre) of an occupied cell
//! (value >= 100; and of an unknown one with [`RosOptions::inflate_unknown`]), like the
//! inflation layer of the ROS cost map (seed 004, Fig. 10b). Inflation is an exact
//! Euclidean distance transform (Meijster, Roerdink and Hesselink 2000, "A general
//! algorithm for computing distance transforms in linear time"): its cost is linear in the
//! number of cells, whatever the radius.
//!
//! Grid row `y` is image row `y`, the top row first, so the grid looks like the image;
//! ROS's `OccupancyGrid` stores the bottom row first instead. [`RosMap::world`] gives a
//! cell centre's position in the map frame (the yaw of `origin` is ignored, as
//! `map_server` does).
//!
//! # Limits
//! Image dimensions are read from the header and checked against
//! [`ReadOptions::max_cells`] before the pixels are decoded; YAML and image files are read
//! only if they are regular files of at most [`ReadOptions::max_file_bytes`]. Memory then
//! follows the pixel data the file holds, not the size its header declares: a PGM's,
//! PPM's, PAM's or PBM's samples become occupancy values as they are read from the file's
//! bytes, one byte a pixel (a binary raster shorter than its size is an error before any
//! is allocated). A PNG whose compressed pixel data cannot inflate to the pixels its
//! header declares (deflate inflates a byte to at most 1032) is an error before any is
//! decoded ([`MapErrorKind::ImageDataTooSmall`]); otherwise it is decoded a row at a time
//! by the `png` crate, at its own depth (8 or 16 bits a sample), each row's values
//! computed as it comes, so pixel data that ends early is an error naming the pixels it
//! held ([`MapErrorKind::ImageCutShort`]) after about that much memory. An interlaced
//! PNG's values, which come pass by pass, are put in row order once all are read, a
//! second byte a cell for that moment. Memory that cannot be had for the values is
//! [`MapErrorKind::OutOfMemory`], not an abort.

use std::collections::HashMap;
use std::io::Cursor;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use planner_api::{Cell, Grid};
use saphyr_parser::{Event, Parser, ScalarStyle, Span};
use serde::Serialize;

use crate::error::{MapError, MapErrorKind, MapWarning};
use crate::text::{show_token, unexpected, Origin};
use crate::ReadOptions;

/// How the image's values become occupancy, the YAML's `mode`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum RosMode {
    /// Occupied, free or unknown (the default).
    #[default]
    Trinary,
    /// Occupied, free, or a value in 1..=99 between the thresholds.
    Scale,
    /// The pixel value is the occupancy value.
    Raw,
}

/// The contents of a `map_server` YAML file (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct RosYaml {
    /// The image path as written.
    pub image: String,
    /// Metres per cell.
    pub resolution: f64,
    /// `[x, y, yaw]` of the lower-left cell.
    pub origin: [f64; 3],
    /// Occupancy probability above which a cell is occupied.
    pub occupied_thresh: f64,
    /// Occupancy probability below which a cell is free.
    pub free_thresh: f64,
    /// Whether dark pixels are free.
    pub negate: bool,
    /// Trinary, scale or raw.
    pub mode: RosMode,
    /// What the file has that `map_server` ignores or reads surprisingly (module docs), in
    /// file order.
    pub warnings: Vec<MapWarning>,
}

impl RosYaml {
    /// The description `map_server` would give an image without a YAML file: occupied
    /// above 0.65, free below 0.196 (`map_server`'s defaults), not negated, trinary; one
    /// metre per cell and the origin at `[0, 0, 0]` (`map_server` has no default for
    /// these; they only place the map frame).
    pub fn defaults(image: &str) -> RosYaml {
        RosYaml {
            image: image.to_owned(),
            resolution: 1.0,
            origin: [0.0; 3],
            occupied_thresh: 0.65,
            free_thresh: 0.196,
            negate: false,
            mode: RosMode::Trinary,
            warnings: Vec::new(),
        }
    }
}

/// Options of [`read_ros_map`] beyond what the YAML says.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct RosOptions {
    /// Block every cell within this many cells of an occupied cell (0, the default: none).
    pub inflation_radius: u32,
    /// Inflate around unknown cells as well (default false, like ROS's cost map).
    pub inflate_unknown: bool,
}

/// A `map_server` map read into a grid.
#[derive(Debug, Clone, PartialEq)]
pub struct RosMap {
    /// Free where the value is 0 and no inflation reaches (module docs).
    pub grid: Grid,
    /// The ROS occupancy value of each cell (-1 unknown, 0 free, 1..=99 partly occupied,
    /// 100 occupied; raw mode may give others), row-major in grid order (top row first),
    /// before inflation.
    pub occupancy: Vec<i8>,
    /// The YAML file's contents (with its warnings), or [`RosYaml::defaults`] for an image
    /// read directly.
    pub yaml: RosYaml,
    /// The image file, resolved against the YAML file's directory.
    pub image_path: PathBuf,
}

impl RosMap {
    /// The map-frame position in metres of `cell`'s centre ([`MapFrame::world`]).
    pub fn world(&self, cell: Cell) -> (f64, f64) {
        self.frame().world(cell)
    }

    /// Where the map's cells lie in the map frame.
    pub fn frame(&self) -> MapFrame {
        MapFrame {
            resolution: self.yaml.resolution,
            origin: self.yaml.origin,
            width: self.grid.width(),
            height: self.grid.height(),
        }
    }

    /// One flag per cell, row-major, true where the occupancy is `-1` (unknown); `None`
    /// when no cell is unknown.
    pub fn unknown_cells(&self) -> Option<Vec<bool>> {
        self.occupancy
            .contains(&-1)
            .then(|| self.occupancy.iter().map(|&v| v == -1).collect())
    }
}

/// Where a `map_server` map's cells lie in the ROS map frame: its YAML's `resolution`
/// (metres per cell) and `origin` (`[x, y, yaw]`, the position of the lower-left corner of
/// the bottom-left cell; the yaw is ignored, as by nav2's costmap), and the grid's size.
/// Grid row 0 is the image's top row, so row `y` lies `height - 1 - y` rows above the
/// bottom one. The conversions are nav2's `Costmap2D::mapToWorld` and `worldToMap`
/// (<https://github.com/ros-navigation/navigation2>, `nav2_costmap_2d/src/costmap_2d.cpp`)
/// with that row flip.
///
/// ```
/// use planner_api::Cell;
/// use planner_maps::MapFrame;
///
/// // 0.05 m cells, the bottom-left corner at (-10, -10): a 400 x 400 map of 20 m square.
/// let frame = MapFrame { resolution: 0.05, origin: [-10.0, -10.0, 0.0], width: 400, height: 400 };
/// assert_eq!(frame.world(Cell::new(0, 399)), (-9.975, -9.975));
/// assert_eq!(frame.cell_at(-9.99, -9.99), Some(Cell::new(0, 399)));
/// assert_eq!(frame.cell_at(0.0, 0.0), Some(Cell::new(200, 199)));
/// assert_eq!(frame.cell_at(10.0, 0.0), None); // the right edge is outside, as in nav2
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MapFrame {
    /// Metres per cell.
    pub resolution: f64,
    /// `[x, y, yaw]` of the bottom-left cell's lower-left corner.
    pub origin: [f64; 3],
    /// Cells per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
}

impl MapFrame {
    /// The map-frame position in metres of `cell`'s centre:
    /// `origin + resolution * (x + 0.5, height - 1 - y + 0.5)`.
    pub fn world(&self, cell: Cell) -> (f64, f64) {
        let r = self.resolution;
        let [ox, oy, _] = self.origin;
        let rows_below = f64::from(self.height) - 1.0 - f64::from(cell.y);
        (
            ox + r * (f64::from(cell.x) + 0.5),
            oy + r * (rows_below + 0.5),
        )
    }

    /// The cell holding map-frame point `(x, y)` (metres): column
    /// `floor((x - origin_x) / resolution)`, and the row that many rows above the bottom
    /// one; `None` for a point outside the map (the lower and left edges are inside, the
    /// upper and right ones outside, as nav2's `worldToMap` has them, up to the rounding of
    /// the quotient) or not finite.
    pub fn cell_at(&self, x: f64, y: f64) -> Option<Cell> {
        let [ox, oy, _] = self.origin;
        if !(x >= ox && y >= oy && self.resolution > 0.0) {
            return None; // Also NaN.
        }
        let column = ((x - ox) / self.resolution).floor();
        let rows_below = ((y - oy) / self.resolution).floor();
        if !(column < f64::from(self.width) && rows_below < f64::from(self.height)) {
            return None;
        }
        // Both are whole numbers in 0..width and 0..height here.
        Some(Cell::new(
            column as u32,
            self.height - 1 - rows_below as u32,
        ))
    }

    /// The map's extent in the map frame: `[min_x, min_y, max_x, max_y]` in metres.
    pub fn bounds(&self) -> [f64; 4] {
        let [ox, oy, _] = self.origin;
        [
            ox,
            oy,
            ox + self.resolution * f64::from(self.width),
            oy + self.resolution * f64::from(self.height),
        ]
    }

    /// [`MapFrame::bounds`] for a person, as the errors of a point off the map say it:
    /// `x from -10 to 9.2 and y from -10 to 9.2 (metres, the map frame; the upper ends
    /// excluded)`, each number by [`metres`].
    pub fn extent(&self) -> String {
        let [x0, y0, x1, y1] = self.bounds().map(metres);
        format!(
            "x from {x0} to {x1} and y from {y0} to {y1} (metres, the map frame; the upper ends excluded)"
        )
    }

    /// This frame when it places the cells: a positive resolution, and an extent within
    /// the range of numbers; else why not.
    ///
    /// ```
    /// use planner_maps::{FrameError, MapFrame};
    ///
    /// let frame = MapFrame { resolution: 0.05, origin: [-10.0, -10.0, 0.0], width: 400, height: 400 };
    /// assert_eq!(frame.checked(), Ok(frame));
    /// let flat = MapFrame { resolution: 0.0, ..frame };
    /// assert_eq!(flat.checked(), Err(FrameError::ResolutionNotPositive { resolution: 0.0 }));
    /// assert_eq!(flat.checked().unwrap_err().to_string(), "resolution 0 is not positive");
    /// let huge = MapFrame { resolution: 1e308, ..frame };
    /// assert_eq!(
    ///     huge.checked().unwrap_err().to_string(),
    ///     "origin [-10, -10, 0] plus resolution 1e308 times the image's 400x400 cells is beyond the range of numbers"
    /// );
    /// ```
    pub fn checked(self) -> Result<MapFrame, FrameError> {
        // Also NaN, which a YAML cannot give.
        if self.resolution.is_nan() || self.resolution <= 0.0 {
            return Err(FrameError::ResolutionNotPositive {
                resolution: self.resolution,
            });
        }
        if !self.bounds().iter().all(|v| v.is_finite()) {
            return Err(FrameError::BeyondRange {
                origin: self.origin,
                resolution: self.resolution,
                width: self.width,
                height: self.height,
            });
        }
        Ok(self)
    }
}

/// Why a `map_server` map's YAML places no cell in the map frame ([`MapFrame::checked`],
/// [`crate::MapFile::frame_error`]): its map positions are meaningless, so points in
/// metres cannot be read on it.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum FrameError {
    /// The `resolution` (metres per cell) is zero or negative (`map_server` reads it as
    /// written, with a warning).
    #[error("resolution {} is not positive", shown_number(*.resolution))]
    ResolutionNotPositive {
        /// The YAML's resolution.
        resolution: f64,
    },
    /// The `origin` plus `resolution` times the image's size is beyond the range of
    /// numbers (a `resolution` of `1e308`, say).
    #[error("origin [{}] plus resolution {} times the image's {width}x{height} cells is beyond the range of numbers", .origin.map(metres).join(", "), metres(*.resolution))]
    BeyondRange {
        /// The YAML's origin.
        origin: [f64; 3],
        /// The YAML's resolution.
        resolution: f64,
        /// The image's width.
        width: u32,
        /// The image's height.
        height: u32,
    },
}

/// `value` metres for a person: at most six decimals (micrometres), trailing zeros left
/// out, so that `-1.4749999999999996` (a cell centre's sum) reads `-1.475`; from `1e9`
/// (a million kilometres) up, in scientific notation with at most six decimals, so that
/// no number is longer than a line (`1e300` is not written with its 301 digits).
///
/// ```
/// assert_eq!(planner_maps::metres(-1.4749999999999996), "-1.475");
/// assert_eq!(planner_maps::metres(9.200000000000003), "9.2");
/// assert_eq!(planner_maps::metres(-0.0000001), "0");
/// assert_eq!(planner_maps::metres(123456789.5), "123456789.5");
/// assert_eq!(planner_maps::metres(1e300), "1e300");
/// assert_eq!(planner_maps::metres(-1.23456789e12), "-1.234568e12");
/// assert_eq!(planner_maps::metres(f64::INFINITY), "inf");
/// ```
pub fn metres(value: f64) -> String {
    if value.is_finite() && value.abs() >= SCIENTIFIC_METRES {
        let text = format!("{value:.6e}");
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, ""));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        return format!("{mantissa}e{exponent}");
    }
    let text = format!("{value:.6}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    match text {
        "-0" => "0".to_string(),
        other => other.to_string(),
    }
}

/// The magnitude in metres from which [`metres`] writes scientific notation.
const SCIENTIFIC_METRES: f64 = 1e9;

/// A number from a YAML file for a message, as written in the shortest form that reads
/// back to it: `0.05`, `-1`, `1.5`; scientific notation for the very large and very small
/// (`1e308`, `-1e-9`), never hundreds of digits.
pub(crate) fn shown_number(value: f64) -> String {
    let text = format!("{value:?}");
    match text.strip_suffix(".0") {
        Some(whole) => whole.to_owned(),
        None => text,
    }
}

/// The keys `map_server` reads.
const KEYS: [&str; 7] = [
    "image",
    "resolution",
    "origin",
    "occupied_thresh",
    "free_thresh",
    "negate",
    "mode",
];

/// The deepest nesting of YAML sequences and mappings read.
const MAX_DEPTH: usize = 64;

/// A 1-based (line, column) position.
type Position = (usize, usize);

/// A YAML node with its position: as much of YAML as the format needs. Aliases share the
/// anchored node, so no input makes the tree larger than the text.
#[derive(Debug)]
enum Node {
    /// A scalar's text; `plain` when unquoted (only a plain scalar can be null).
    Scalar {
        text: String,
        plain: bool,
        at: Position,
    },
    Sequence {
        items: Vec<Rc<Node>>,
        at: Position,
    },
    Mapping {
        entries: Vec<(Rc<Node>, Rc<Node>)>,
        at: Position,
    },
}

impl Node {
    fn at(&self) -> Position {
        match self {
            Node::Scalar { at, .. } | Node::Sequence { at, .. } | Node::Mapping { at, .. } => *at,
        }
    }

    /// What the node is, for messages.
    fn describe(&self) -> String {
        match self {
            Node::Scalar { text, plain, .. } if *plain && is_null(text) => "null".to_owned(),
            Node::Scalar { text, .. } => show_token(text),
            Node::Sequence { .. } => "a sequence".to_owned(),
            Node::Mapping { .. } => "a mapping".to_owned(),
        }
    }
}

/// YAML's null spellings for a plain scalar (the empty value included).
fn is_null(text: &str) -> bool {
    matches!(text, "" | "~" | "null" | "Null" | "NULL")
}

/// The 1-based position of a span's start.
fn start(span: &Span) -> Position {
    (span.start.line(), span.start.col() + 1)
}

/// A sequence or mapping being built.
enum Frame {
    Sequence {
        items: Vec<Rc<Node>>,
        at: Position,
        anchor: usize,
    },
    Mapping {
        entries: Vec<(Rc<Node>, Rc<Node>)>,
        key: Option<Rc<Node>>,
        at: Position,
        anchor: usize,
    },
}

/// The first YAML document of `text` (`None` for a stream without one) and a warning when
/// more follows it.
fn load(text: &str, o: Origin<'_>) -> Result<(Option<Rc<Node>>, Vec<MapWarning>), MapError> {
    let mut parser = Parser::new_from_str(text);
    let mut stack: Vec<Frame> = Vec::new();
    let mut anchors: HashMap<usize, Rc<Node>> = HashMap::new();
    let mut root: Option<Rc<Node>> = None;
    let mut warnings = Vec::new();
    // The scanner may place an error at the end of the stream one line past the text's
    // last line: such a position is the end of the text.
    let (last_line, end_column) = yaml_end(text);
    let within = |marker: &saphyr_parser::Marker| {
        let position = (marker.line(), marker.col() + 1);
        if position > (last_line, end_column) {
            (last_line, end_column)
        } else {
            position
        }
    };
    let scan_error = |e: saphyr_parser::ScanError| {
        let (line, column) = within(e.marker());
        o.at(
            line,
            column,
            MapErrorKind::Yaml {
                message: e.info().to_owned(),
            },
        )
    };
    while let Some(next) = parser.next_event() {
        let (event, span) = next.map_err(scan_error)?;
        let at = start(&span);
        let node = match event {
            Event::DocumentEnd => {
                // yaml-cpp's LoadFile reads the first document only.
                match parser.next_event() {
                    None | Some(Ok((Event::StreamEnd, _))) => {}
                    Some(Ok((_, span))) => warnings.push(MapWarning {
                        file: o.0.to_owned(),
                        line: start(&span).0,
                        column: start(&span).1,
                        message: "a second YAML document is ignored, as map_server does"
                            .to_owned(),
                    }),
                    Some(Err(e)) => warnings.push(MapWarning {
                        file: o.0.to_owned(),
                        line: within(e.marker()).0,
                        column: within(e.marker()).1,
                        message: format!(
                            "the text after the first YAML document is ignored, as map_server does (it is not valid YAML: {})",
                            e.info()
                        ),
                    }),
                }
                break;
            }
            Event::Nothing | Event::StreamStart | Event::StreamEnd | Event::DocumentStart(_) => {
                continue
            }
            Event::Alias(id) => anchors.get(&id).cloned().ok_or_else(|| {
                o.at(
                    at.0,
                    at.1,
                    unexpected(
                        "an alias of a complete anchored node",
                        "an alias inside its own anchor",
                    ),
                )
            })?,
            Event::Scalar(value, style, anchor, _tag) => {
                let node = Rc::new(Node::Scalar {
                    text: value.into_owned(),
                    plain: style == ScalarStyle::Plain,
                    at,
                });
                if anchor > 0 {
                    anchors.insert(anchor, Rc::clone(&node));
                }
                node
            }
            Event::SequenceStart(anchor, _) | Event::MappingStart(anchor, _) => {
                if stack.len() >= MAX_DEPTH {
                    return Err(o.at(
                        at.0,
                        at.1,
                        unexpected(
                            format!("at most {MAX_DEPTH} nested sequences and mappings"),
                            "more",
                        ),
                    ));
                }
                stack.push(if matches!(event, Event::SequenceStart(..)) {
                    Frame::Sequence {
                        items: Vec::new(),
                        at,
                        anchor,
                    }
                } else {
                    Frame::Mapping {
                        entries: Vec::new(),
                        key: None,
                        at,
                        anchor,
                    }
                });
                continue;
            }
            Event::SequenceEnd | Event::MappingEnd => {
                let (node, anchor) = match stack.pop() {
                    Some(Frame::Sequence { items, at, anchor }) => {
                        (Rc::new(Node::Sequence { items, at }), anchor)
                    }
                    Some(Frame::Mapping {
                        entries,
                        at,
                        anchor,
                        ..
                    }) => (Rc::new(Node::Mapping { entries, at }), anchor),
                    None => continue,
                };
                if anchor > 0 {
                    anchors.insert(anchor, Rc::clone(&node));
                }
                node
            }
        };
        match stack.last_mut() {
            None => root = Some(node),
            Some(Frame::Sequence { items, .. }) => items.push(node),
            Some(Frame::Mapping { entries, key, .. }) => match key.take() {
                Some(k) => entries.push((k, node)),
                None => *key = Some(node),
            },
        }
    }
    Ok((root, warnings))
}

/// The 1-based position just after the text's last character, with YAML's line breaks
/// (`\n`, `\r\n` and a lone `\r`, YAML 1.2 section 5.4) and a byte-order mark that is
/// no column, as the YAML parser counts them.
fn yaml_end(text: &str) -> Position {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let (mut line, mut column) = (1, 1);
    let mut chars = text.chars().peekable();
    while let Some(ch) = chars.next() {
        match ch {
            '\r' if chars.peek() == Some(&'\n') => {}
            '\r' | '\n' => (line, column) = (line + 1, 1),
            _ => column += 1,
        }
    }
    (line, column)
}

/// Parses the text of a `map_server` YAML file. `origin` names it in error messages and
/// warnings.
///
/// Errors, with line and column, and warnings as in the module docs. Never panics.
///
/// ```
/// use planner_maps::parse_ros_yaml;
///
/// let text = "image: map.pgm\nresolution: 0.05\norigin:\n  - -10\n  - -10\n  - 0\n\
///             negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\nmap_type: occupancy\n";
/// let yaml = parse_ros_yaml(text, "map.yaml").unwrap();
/// assert_eq!(yaml.origin, [-10.0, -10.0, 0.0]);
/// assert_eq!(
///     yaml.warnings[0].to_string(),
///     "map.yaml:10:1: key 'map_type' is not one map_server reads (image, resolution, \
///      origin, occupied_thresh, free_thresh, negate, mode): ignored"
/// );
/// let err = parse_ros_yaml("image: [map.pgm\n", "map.yaml").unwrap_err();
/// assert!(err.to_string().starts_with("map.yaml:2:1: invalid YAML: "), "{err}");
/// ```
pub fn parse_ros_yaml(text: &str, origin: &str) -> Result<RosYaml, MapError> {
    parse_ros_yaml_located(text, origin).map(|(yaml, _)| yaml)
}

/// [`parse_ros_yaml`], with the position of the `image` value.
fn parse_ros_yaml_located(text: &str, origin: &str) -> Result<(RosYaml, Position), MapError> {
    // The parser may place a node or an error at the end of the stream, one line past the
    // text's last line (an empty document after `---`, say): such a position is the end.
    let end = yaml_end(text);
    let clamp = |line: &mut usize, column: &mut usize| {
        if (*line, *column) > end {
            (*line, *column) = end;
        }
    };
    match parse_yaml_document(text, origin) {
        Ok((mut yaml, (mut line, mut column))) => {
            for w in &mut yaml.warnings {
                clamp(&mut w.line, &mut w.column);
            }
            clamp(&mut line, &mut column);
            Ok((yaml, (line, column)))
        }
        Err(mut e) => {
            clamp(&mut e.line, &mut e.column);
            Err(e)
        }
    }
}

/// [`parse_ros_yaml_located`] before positions are clamped to the text.
fn parse_yaml_document(text: &str, origin: &str) -> Result<(RosYaml, Position), MapError> {
    let o = Origin(origin);
    let (root, mut trailing) = load(text, o)?;
    let Some(root) = root else {
        let (line, column) = yaml_end(text);
        return Err(o.at(
            line,
            column,
            unexpected(
                "a mapping of map_server keys (image, resolution, ...)",
                "end of file",
            ),
        ));
    };
    let Node::Mapping { entries, at: top } = &*root else {
        let (line, column) = root.at();
        return Err(o.at(
            line,
            column,
            unexpected(
                "a mapping of map_server keys (image, resolution, ...)",
                root.describe(),
            ),
        ));
    };
    let mut warnings = Vec::new();
    let warn = |warnings: &mut Vec<MapWarning>, (line, column): Position, message: String| {
        warnings.push(MapWarning {
            file: origin.to_owned(),
            line,
            column,
            message,
        })
    };
    let error = |(line, column): Position, kind: MapErrorKind| o.at(line, column, kind);
    // The value of each known key, with the key's position.
    let mut values: [Option<(&Node, Position)>; 7] = [None; 7];
    for (key, value) in entries {
        let Node::Scalar { text: name, .. } = &**key else {
            warn(
                &mut warnings,
                key.at(),
                format!(
                    "{} as a key is not one map_server reads: ignored",
                    key.describe()
                ),
            );
            continue;
        };
        let Some(index) = KEYS.iter().position(|k| k == name) else {
            warn(
                &mut warnings,
                key.at(),
                format!(
                    "key {} is not one map_server reads ({}): ignored",
                    show_token(name),
                    KEYS.join(", ")
                ),
            );
            continue;
        };
        if let Some((_, (first_line, _))) = values[index] {
            return Err(error(
                key.at(),
                MapErrorKind::DuplicateKey {
                    key: KEYS[index],
                    first_line,
                },
            ));
        }
        values[index] = Some((&**value, key.at()));
    }
    let required = |index: usize| -> Result<&Node, MapError> {
        values[index]
            .map(|(node, _)| node)
            .ok_or_else(|| error(*top, MapErrorKind::MissingField { key: KEYS[index] }))
    };
    // A scalar's text, or an error naming what was expected.
    let scalar = |node: &Node, expected: &str| -> Result<String, MapError> {
        match node {
            Node::Scalar { text, plain, .. } if !(*plain && is_null(text)) => Ok(text.clone()),
            other => Err(error(other.at(), unexpected(expected, other.describe()))),
        }
    };
    let number = |node: &Node, what: &str| -> Result<f64, MapError> {
        let expected = format!("a number for '{what}'");
        let text = scalar(node, &expected)?;
        match parse_number(&text) {
            Some(v) if v.is_finite() => Ok(v),
            Some(_) => Err(error(
                node.at(),
                unexpected(format!("a finite number for '{what}'"), show_token(&text)),
            )),
            None => Err(error(node.at(), unexpected(expected, show_token(&text)))),
        }
    };

    let image_node = required(0)?;
    let image = scalar(image_node, "an image file name for 'image'")?;
    if image.is_empty() {
        return Err(error(
            image_node.at(),
            unexpected("an image file name for 'image'", "an empty string"),
        ));
    }
    let resolution_node = required(1)?;
    let resolution = number(resolution_node, "resolution")?;
    if resolution <= 0.0 {
        warn(
            &mut warnings,
            resolution_node.at(),
            format!(
                "{}: map positions are meaningless",
                FrameError::ResolutionNotPositive { resolution }
            ),
        );
    }
    let origin_node = required(2)?;
    let Node::Sequence { items, .. } = origin_node else {
        return Err(error(
            origin_node.at(),
            unexpected(
                "a sequence [x, y, yaw] for 'origin'",
                origin_node.describe(),
            ),
        ));
    };
    if items.len() < 3 {
        return Err(error(
            origin_node.at(),
            unexpected(
                "three numbers [x, y, yaw] for 'origin'",
                format!("{} items", items.len()),
            ),
        ));
    }
    if items.len() > 3 {
        warn(
            &mut warnings,
            origin_node.at(),
            format!(
                "'origin' has {} items: the first three are read, as ROS 1 map_server does",
                items.len()
            ),
        );
    }
    let mut pose = [0.0; 3];
    for (slot, item) in pose.iter_mut().zip(items) {
        *slot = number(item, "origin")?;
    }
    let occupied_node = required(3)?;
    let occupied_thresh = number(occupied_node, "occupied_thresh")?;
    let free_node = required(4)?;
    let free_thresh = number(free_node, "free_thresh")?;
    for (node, key, value) in [
        (occupied_node, "occupied_thresh", occupied_thresh),
        (free_node, "free_thresh", free_thresh),
    ] {
        if !(0.0..=1.0).contains(&value) {
            warn(
                &mut warnings,
                node.at(),
                format!(
                    "'{key}' {} is outside [0, 1]: read as written",
                    shown_number(value)
                ),
            );
        }
    }
    if free_thresh > occupied_thresh {
        warn(
            &mut warnings,
            free_node.at(),
            format!(
                "'free_thresh' {} is above 'occupied_thresh' {}: read as written",
                shown_number(free_thresh),
                shown_number(occupied_thresh)
            ),
        );
    }
    let negate_node = required(5)?;
    let negate_expected = "an integer or a boolean (0, 1, true, false) for 'negate'";
    let negate_text = scalar(negate_node, negate_expected)?;
    let negate = match parse_integer(&negate_text) {
        Some(value) => {
            if value != 0 && value != 1 {
                warn(
                    &mut warnings,
                    negate_node.at(),
                    format!("'negate' {value} is neither 0 nor 1: non-zero negates, as map_server reads it"),
                );
            }
            value != 0
        }
        None => {
            // ROS 1 reads `negate` as an int only (`doc["negate"] >> negate` into an int,
            // exiting with "The map does not contain a negate tag or it is invalid");
            // nav2 (map_io.cpp, loadMapYaml) tries `as<int>` and then `as<bool>`. A
            // boolean is read as nav2 reads it, never silently: which map a file means
            // depends on the map_server that reads it.
            let value = parse_bool(&negate_text).ok_or_else(|| {
                error(
                    negate_node.at(),
                    unexpected(negate_expected, show_token(&negate_text)),
                )
            })?;
            warn(
                &mut warnings,
                negate_node.at(),
                format!(
                    "'negate' {} is a boolean: ROS 2's nav2_map_server reads it as {value} (and so does gridplan), ROS 1's map_server refuses the file; write {}",
                    negate_text.trim(),
                    u8::from(value)
                ),
            );
            value
        }
    };
    let mode = match values[6] {
        None => RosMode::default(),
        Some((node, _)) => {
            let expected = "trinary, scale or raw for 'mode'";
            match scalar(node, expected)?.as_str() {
                "trinary" => RosMode::Trinary,
                "scale" => RosMode::Scale,
                "raw" => RosMode::Raw,
                other => return Err(error(node.at(), unexpected(expected, show_token(other)))),
            }
        }
    };
    warnings.sort_by_key(|w| (w.line, w.column));
    warnings.append(&mut trailing);
    let yaml = RosYaml {
        image,
        resolution,
        origin: pose,
        occupied_thresh,
        free_thresh,
        negate,
        mode,
        warnings,
    };
    Ok((yaml, image_node.at()))
}

/// A number as yaml-cpp reads a `double`: a decimal (`0.05`, `-10`, `1e-3`, `+2`, `.5`) or
/// YAML's `.inf`, `-.inf`, `.nan` spellings; surrounding spaces are ignored.
fn parse_number(text: &str) -> Option<f64> {
    let text = text.trim();
    match text {
        ".inf" | ".Inf" | ".INF" | "+.inf" | "+.Inf" | "+.INF" => return Some(f64::INFINITY),
        "-.inf" | "-.Inf" | "-.INF" => return Some(f64::NEG_INFINITY),
        ".nan" | ".NaN" | ".NAN" => return Some(f64::NAN),
        _ => {}
    }
    let ok = !text.is_empty()
        && text
            .chars()
            .all(|c| c.is_ascii_digit() || matches!(c, '.' | '-' | '+' | 'e' | 'E'));
    text.parse::<f64>().ok().filter(|_| ok)
}

/// A decimal integer, optionally signed, as yaml-cpp reads an `int` (surrounding spaces
/// ignored; hexadecimal and octal are not read).
fn parse_integer(text: &str) -> Option<i64> {
    let text = text.trim();
    let digits = text.strip_prefix(['+', '-']).unwrap_or(text);
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    text.parse().ok()
}

/// A boolean as yaml-cpp reads one.
fn parse_bool(text: &str) -> Option<bool> {
    match text.trim() {
        "y" | "Y" | "yes" | "Yes" | "YES" | "true" | "True" | "TRUE" | "on" | "On" | "ON" => {
            Some(true)
        }
        "n" | "N" | "no" | "No" | "NO" | "false" | "False" | "FALSE" | "off" | "Off" | "OFF" => {
            Some(false)
        }
        _ => None,
    }
}

/// The ROS occupancy value of one pixel by the module's threshold rule: its samples
/// (1 grey, 2 grey and alpha, 3 RGB, 4 RGBA), each from 0 to `maxval` (255 for 8-bit
/// samples, 65535 for 16-bit ones, a PGM's own maxval). A sample above `maxval` counts as
/// `maxval`; no samples, more than four, or a `maxval` of 0 give unknown, `-1`.
///
/// ```
/// use planner_maps::{ros_occupancy_value, RosYaml};
///
/// let yaml = RosYaml::defaults("m.pgm"); // trinary, free below 0.196, occupied above 0.65
/// assert_eq!(ros_occupancy_value(&yaml, &[205], 255), -1); // p = 50/255 = 0.19608
/// assert_eq!(ros_occupancy_value(&yaml, &[805], 1000), 0); // p = 0.195
/// // Grey and alpha: nav2 averages red, green, blue and alpha, (3 * 179 + 255) / 4 = 198.
/// assert_eq!(ros_occupancy_value(&yaml, &[179, 255], 255), -1); // p = 0.2235
/// ```
pub fn ros_occupancy_value(yaml: &RosYaml, pixel: &[u16], maxval: u16) -> i8 {
    let n = pixel.len();
    if n == 0 || n > 4 || maxval == 0 {
        return -1;
    }
    let sample = |i: usize| f64::from(pixel[i].min(maxval));
    let has_alpha = n == 2 || n == 4;
    // nav2 averages red, green and blue (a grey pixel's three equal channels) and, in
    // trinary mode, the alpha of an image that has one.
    let (mut sum, mut count) = if n <= 2 {
        (3.0 * sample(0), 3.0)
    } else {
        (sample(0) + sample(1) + sample(2), 3.0)
    };
    let alpha = if has_alpha {
        pixel[n - 1].min(maxval)
    } else {
        maxval
    };
    if yaml.mode == RosMode::Trinary && has_alpha {
        sum += f64::from(alpha);
        count += 1.0;
    }
    // nav2's shade: 0 for black, 1 for white.
    let shade = sum / count / f64::from(maxval);
    if yaml.mode == RosMode::Raw {
        // nav2: round(shade * 255), the un-negated mean, kept when within 0..=100.
        let raw = (shade * 255.0).round();
        return if raw <= 100.0 { raw as i8 } else { -1 };
    }
    if yaml.mode == RosMode::Scale && alpha != maxval {
        return -1;
    }
    let p = if yaml.negate { shade } else { 1.0 - shade };
    if p > yaml.occupied_thresh {
        100
    } else if p < yaml.free_thresh {
        0
    } else if yaml.mode == RosMode::Trinary {
        -1
    } else {
        let ratio = (p - yaml.free_thresh) / (yaml.occupied_thresh - yaml.free_thresh);
        // C's rint in the default rounding mode: to the nearest, halves to even.
        (100.0 * ratio).round_ties_even() as i8
    }
}

/// An image's width, height and occupancy values (row-major).
type Values = (u32, u32, Vec<i8>);

/// The occupancy values of a PGM, PPM, PAM or PBM image (`width`, `height`, the values)
/// from its samples at full precision. The caller has checked the header, and the pixel
/// count against its limit.
fn pnm_occupancy(bytes: &[u8], yaml: &RosYaml) -> Result<Values, MapErrorKind> {
    use image::codecs::pnm::PnmDecoder;
    use image::ImageDecoder as _;
    let image_error = |message: String| MapErrorKind::Image { message };
    let decoder = PnmDecoder::new(Cursor::new(bytes)).map_err(|e| image_error(e.to_string()))?;
    let channels = usize::from(decoder.color_type().channel_count()).clamp(1, 4);
    // The decoder has read the header and the one whitespace after it.
    let (rest, header) = decoder.into_inner();
    let raster =
        usize::try_from(rest.position()).map_or(&[][..], |at| &bytes[at.min(bytes.len())..]);
    pnm_samples(raster, &header, channels, yaml).map_err(image_error)
}

/// [`pnm_occupancy`]'s values from the samples of `raster`, `channels` to a pixel, as
/// they are read: the values are the only allocation, one byte a pixel and at most one a
/// byte of `raster` (a PBM's: [`pbm_bits`]).
fn pnm_samples(
    raster: &[u8],
    header: &image::codecs::pnm::PnmHeader,
    channels: usize,
    yaml: &RosYaml,
) -> Result<Values, String> {
    use image::codecs::pnm::SampleEncoding;
    let (width, height) = (header.width(), header.height());
    if let image::codecs::pnm::PnmSubtype::Bitmap(encoding) = header.subtype() {
        return pbm_bits(raster, encoding, (width, height), yaml).map(|v| (width, height, v));
    }
    // The decoder refuses a maxval of 0 or above 65535.
    let maxval = u16::try_from(header.maximal_sample())
        .map_err(|_| format!("maxval {} is above 65535", header.maximal_sample()))?;
    let pixels = usize::try_from(u64::from(width) * u64::from(height))
        .map_err(|_| format!("{width}x{height} pixels do not fit in memory"))?;
    let total = pixels.saturating_mul(channels);
    let short = |found: usize| {
        format!("expected {total} samples ({width}x{height} pixels of {channels}), found {found}")
    };
    let at = |index: usize| {
        let w = width.max(1) as usize;
        format!("pixel ({}, {})", index % w, index / w)
    };
    // A grey image's values by table, one entry a sample value (at most 64 Ki).
    let table: Option<Vec<i8>> = (channels == 1).then(|| {
        (0..=maxval)
            .map(|v| ros_occupancy_value(yaml, &[v], maxval))
            .collect()
    });
    let value = |pixel: &[u16]| match &table {
        Some(table) => table[usize::from(pixel[0])],
        None => ros_occupancy_value(yaml, pixel, maxval),
    };
    // Every pixel takes at least a byte of the raster, so a short file reserves little.
    let mut occupancy = Vec::with_capacity(pixels.min(raster.len()));
    let mut pixel = [0u16; 4];
    match header.subtype().sample_encoding() {
        SampleEncoding::Binary => {
            // Netpbm: one byte a sample up to maxval 255, else two, most significant first.
            let size = if maxval > 255 { 2 } else { 1 };
            let need = total.saturating_mul(size);
            if raster.len() < need {
                return Err(short(raster.len() / size));
            }
            for (index, samples) in raster[..need].chunks_exact(size * channels).enumerate() {
                for (value, sample) in pixel.iter_mut().zip(samples.chunks_exact(size)) {
                    *value = match *sample {
                        [high, low] => u16::from_be_bytes([high, low]),
                        [byte] => u16::from(byte),
                        _ => 0,
                    };
                }
                if let Some(v) = pixel[..channels].iter().find(|&&v| v > maxval) {
                    return Err(format!(
                        "{} has sample {v}, above the maxval {maxval}",
                        at(index)
                    ));
                }
                occupancy.push(value(&pixel[..channels]));
            }
        }
        SampleEncoding::Ascii => {
            let mut tokens = raster
                .split(|b| matches!(b, b' ' | b'\t' | b'\n' | b'\r' | b'\x0b' | b'\x0c'))
                .filter(|token| !token.is_empty());
            for index in 0..pixels {
                for (channel, sample) in pixel[..channels].iter_mut().enumerate() {
                    let token = tokens
                        .next()
                        .ok_or_else(|| short(index * channels + channel))?;
                    *sample = std::str::from_utf8(token)
                        .ok()
                        .filter(|t| t.bytes().all(|b| b.is_ascii_digit()))
                        .and_then(|t| t.parse::<u16>().ok())
                        .filter(|&v| v <= maxval)
                        .ok_or_else(|| {
                            format!(
                                "{} has sample {}, not a whole number from 0 to the maxval {maxval}",
                                at(index),
                                show_token(&String::from_utf8_lossy(token))
                            )
                        })?;
                }
                occupancy.push(value(&pixel[..channels]));
            }
        }
    }
    Ok((width, height, occupancy))
}

/// A PBM's values: a bit a pixel, 1 black and 0 white (as the samples 0 and 1 of maxval
/// 1), packed eight to a byte from the most significant bit with each row starting on a
/// byte (`P4`), or written as the digits `0` and `1` with or without whitespace between
/// them (`P1`). A raster too short is an error before the values are allocated (`P4`), or
/// when it ends (`P1`: every pixel takes a byte of it).
fn pbm_bits(
    raster: &[u8],
    encoding: image::codecs::pnm::SampleEncoding,
    (width, height): (u32, u32),
    yaml: &RosYaml,
) -> Result<Vec<i8>, String> {
    use image::codecs::pnm::SampleEncoding;
    let (w, h) = (width as usize, height as usize);
    let pixels = w.saturating_mul(h);
    let short = |found: usize| {
        format!("expected {pixels} samples ({width}x{height} pixels of 1), found {found}")
    };
    let [black, white] = [0, 1].map(|v| ros_occupancy_value(yaml, &[v], 1));
    match encoding {
        SampleEncoding::Binary => {
            let row_bytes = w.div_ceil(8);
            let need = row_bytes.saturating_mul(h);
            if raster.len() < need {
                return Err(short((raster.len() / row_bytes.max(1)).saturating_mul(w)));
            }
            let mut values = Vec::with_capacity(pixels);
            for row in raster[..need].chunks_exact(row_bytes.max(1)).take(h) {
                values.extend((0..w).map(|x| match (row[x / 8] >> (7 - x % 8)) & 1 {
                    1 => black,
                    _ => white,
                }));
            }
            Ok(values)
        }
        SampleEncoding::Ascii => {
            let mut values = Vec::with_capacity(pixels.min(raster.len()));
            let mut digits = raster
                .iter()
                .filter(|b| !matches!(b, b' ' | b'\t' | b'\n' | b'\r' | b'\x0b' | b'\x0c'));
            for index in 0..pixels {
                values.push(match digits.next() {
                    Some(b'1') => black,
                    Some(b'0') => white,
                    Some(&other) => {
                        return Err(format!(
                            "pixel ({}, {}) has sample {}, not 0 or 1",
                            index % w.max(1),
                            index / w.max(1),
                            show_token(&String::from_utf8_lossy(&[other]))
                        ))
                    }
                    None => return Err(short(index)),
                });
            }
            Ok(values)
        }
    }
}

/// The first bytes of every PNG file.
const PNG_SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";

/// The Adam7 passes of an interlaced PNG: first column, first row, column step, row step.
const ADAM7: [(usize, usize, usize, usize); 7] = [
    (0, 0, 8, 8),
    (4, 0, 8, 8),
    (0, 4, 4, 8),
    (2, 0, 4, 4),
    (0, 2, 2, 4),
    (1, 0, 2, 2),
    (0, 1, 1, 2),
];

/// The most bytes deflate inflates one compressed byte to: a length code and a distance
/// code of one bit each copy at most 258 bytes.
const MAX_INFLATE: u64 = 1032;

/// The bytes of a PNG's `IDAT` chunks (its compressed pixel data) as far as the file
/// holds them; a chunk cut short counts what is there.
fn idat_bytes(bytes: &[u8]) -> u64 {
    let mut total = 0u64;
    let mut rest = bytes.get(PNG_SIGNATURE.len()..).unwrap_or_default();
    while let Some((head, body)) = rest.split_first_chunk::<8>() {
        let [l0, l1, l2, l3, kind @ ..] = *head;
        let length = u32::from_be_bytes([l0, l1, l2, l3]) as usize;
        if &kind == b"IDAT" {
            total += length.min(body.len()) as u64;
        }
        if &kind == b"IEND" {
            break;
        }
        rest = body.get(length.saturating_add(4)..).unwrap_or_default();
    }
    total
}

/// The occupancy values of a PNG, decoded a row at a time by the `png` crate at the
/// image's own depth (8 or 16 bits a sample; lower depths and palettes expanded to 8 bits,
/// a `tRNS` chunk to an alpha channel), each row's values computed as it is decoded
/// without a converted copy. Memory follows the pixel data the file holds, whatever size
/// the header declares: pixels whose bytes the compressed data cannot inflate to are
/// [`MapErrorKind::ImageDataTooSmall`] before anything is decoded; otherwise the values
/// grow with the rows, and data that ends early is [`MapErrorKind::ImageCutShort`] after
/// what it held; memory that cannot be had is [`MapErrorKind::OutOfMemory`], not an
/// abort. An interlaced image's values come pass by pass and are put in row order at the
/// end (a second byte a cell for that moment). The caller has checked the header, and the
/// pixel count against its limit.
fn png_occupancy(bytes: &[u8], yaml: &RosYaml) -> Result<Values, MapErrorKind> {
    let image_error = |e: png::DecodingError| MapErrorKind::Image {
        message: e.to_string(),
    };
    let mut decoder = png::Decoder::new(Cursor::new(bytes));
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().map_err(image_error)?;
    let info = reader.info();
    let (width, height) = info.size();
    let interlaced = info.interlaced;
    let pixels = u64::from(width) * u64::from(height);
    // The pixels' bits without the rows' filter bytes: fewer than any layout inflates to.
    let needed = pixels.saturating_mul(info.bits_per_pixel() as u64) / 8;
    let compressed = idat_bytes(bytes);
    let at_most = compressed.saturating_mul(MAX_INFLATE);
    if needed > at_most {
        return Err(MapErrorKind::ImageDataTooSmall {
            width,
            height,
            needed,
            compressed,
            at_most,
        });
    }
    // The first frame of an animated PNG may be smaller than the image: not read.
    if info
        .frame_control()
        .is_some_and(|frame| (frame.width, frame.height) != (width, height))
    {
        return Err(MapErrorKind::Image {
            message: "an animated PNG whose first frame is not the whole image".to_owned(),
        });
    }
    let (colour, depth) = reader.output_color_type();
    let channels = colour.samples().clamp(1, 4);
    let (sample_bytes, maxval) = match depth {
        png::BitDepth::Sixteen => (2, u16::MAX),
        _ => (1, 255),
    };
    let out_of_memory = MapErrorKind::OutOfMemory { cells: pixels };
    let total = usize::try_from(pixels).map_err(|_| out_of_memory.clone())?;
    // The rows in the order they come, by their pixels: the image's, or each Adam7
    // pass's (the passes without pixels left out, as PNG leaves them out).
    let (w, h) = (width as usize, height as usize);
    let rows: Vec<(usize, usize)> = match interlaced {
        false => vec![(w, h)],
        true => ADAM7
            .iter()
            .map(|&(x0, y0, dx, dy)| {
                (
                    w.saturating_sub(x0).div_ceil(dx),
                    h.saturating_sub(y0).div_ceil(dy),
                )
            })
            .filter(|&(samples, lines)| samples > 0 && lines > 0)
            .collect(),
    };
    let line = reader
        .output_line_size(width)
        .ok_or_else(|| out_of_memory.clone())?;
    let mut row = Vec::new();
    row.try_reserve_exact(line)
        .map_err(|_| out_of_memory.clone())?;
    row.resize(line, 0u8);
    // An 8-bit grey image's values by table.
    let table: Vec<i8> = match (channels, maxval) {
        (1, 255) => (0..=255u16)
            .map(|v| ros_occupancy_value(yaml, &[v], 255))
            .collect(),
        _ => Vec::new(),
    };
    let mut values: Vec<i8> = Vec::new();
    let mut pixel = [0u16; 4];
    for (samples, lines) in rows {
        let bytes = samples * channels * sample_bytes;
        for _ in 0..lines {
            let cut_short = |reason: String| MapErrorKind::ImageCutShort {
                pixels: values.len() as u64,
                width,
                height,
                reason,
            };
            match reader.read_row(&mut row) {
                Ok(Some(_)) => {}
                Ok(None) => return Err(cut_short("the image data has no more rows".to_owned())),
                // Data that ends, or that cannot be inflated or unfiltered.
                Err(e @ (png::DecodingError::Format(_) | png::DecodingError::IoError(_))) => {
                    return Err(cut_short(e.to_string().trim_end_matches('.').to_owned()))
                }
                Err(e) => return Err(image_error(e)),
            }
            reserve_values(&mut values, samples, total)?;
            for samples in row[..bytes.min(line)].chunks_exact(channels * sample_bytes) {
                if !table.is_empty() {
                    values.push(table[usize::from(samples[0])]);
                    continue;
                }
                for (value, sample) in pixel.iter_mut().zip(samples.chunks_exact(sample_bytes)) {
                    *value = match *sample {
                        [high, low] => u16::from_be_bytes([high, low]),
                        [byte] => u16::from(byte),
                        _ => 0,
                    };
                }
                values.push(ros_occupancy_value(yaml, &pixel[..channels], maxval));
            }
        }
    }
    // The rest of the image data (its checksum), as a whole image's decoding reads it.
    match reader.read_row(&mut row) {
        Ok(None) => {}
        Ok(Some(_)) => {
            return Err(MapErrorKind::Image {
                message: "the image data has more rows than the header declares".to_owned(),
            })
        }
        Err(e) => return Err(image_error(e)),
    }
    drop(row);
    if !interlaced {
        return Ok((width, height, values));
    }
    // Pass by pass, each pass's rows top to bottom, each row left to right.
    let mut in_order: Vec<i8> = Vec::new();
    in_order
        .try_reserve_exact(total)
        .map_err(|_| out_of_memory.clone())?;
    in_order.resize(total, 0);
    let cells = ADAM7.iter().flat_map(|&(x0, y0, dx, dy)| {
        (y0..h)
            .step_by(dy)
            .flat_map(move |y| (x0..w).step_by(dx).map(move |x| y * w + x))
    });
    for (cell, value) in cells.zip(values) {
        in_order[cell] = value;
    }
    Ok((width, height, in_order))
}

/// Makes room in `values` for `more` values, of `total` in all: the capacity at least
/// doubles, never past `total`, so the values take memory as the pixels come; memory that
/// cannot be had is an error, not an abort.
fn reserve_values(values: &mut Vec<i8>, more: usize, total: usize) -> Result<(), MapErrorKind> {
    let need = values.len().saturating_add(more);
    if need <= values.capacity() {
        return Ok(());
    }
    let target = need.max(values.capacity().saturating_mul(2).min(total));
    values
        .try_reserve_exact(target - values.len())
        .map_err(|_| MapErrorKind::OutOfMemory {
            cells: total as u64,
        })
}

/// The grid of `occupancy` values (row-major, `width` x `height`): free exactly where the
/// value is 0, then inflated by `options` (module docs) in time linear in the number of
/// cells, whatever the radius.
///
/// Precondition: `occupancy.len() == width * height`; errors as [`Grid::from_free_cells`]
/// otherwise.
pub fn ros_grid(
    width: u32,
    height: u32,
    occupancy: &[i8],
    options: &RosOptions,
) -> Result<Grid, planner_api::GridError> {
    let mut free: Vec<bool> = occupancy.iter().map(|&v| v == 0).collect();
    if let Some(near) = inflated(width, height, occupancy, options) {
        for (cell, near) in free.iter_mut().zip(near) {
            *cell &= !near;
        }
    }
    Grid::from_free_cells(width, height, free)
}

/// The cells the inflation of `options` blocks (module docs), or `None` without inflation.
pub(crate) fn inflated(
    width: u32,
    height: u32,
    occupancy: &[i8],
    options: &RosOptions,
) -> Option<Vec<bool>> {
    let (w, h) = (width as usize, height as usize);
    if options.inflation_radius == 0 || w.checked_mul(h) != Some(occupancy.len()) {
        return None;
    }
    let source: Vec<bool> = occupancy
        .iter()
        .map(|&v| v >= 100 || (options.inflate_unknown && v < 0))
        .collect();
    Some(within_radius(w, h, options.inflation_radius, &source))
}

/// For each cell of a `w` x `h` row-major grid, whether a `source` cell's centre lies
/// within Euclidean distance `radius` of its centre: Meijster, Roerdink and Hesselink's
/// exact distance transform (2000), in O(w h) time for any radius.
///
/// Column distances beyond `radius + 1` are capped there: a capped term is more than
/// `radius^2` and so is the true one, and the uncapped terms are exact, so the minimum is
/// at most `radius^2` exactly when the true squared distance is. With the radius itself
/// capped at `w + h` (beyond the grid's diagonal), every square fits comfortably in `i128`.
fn within_radius(w: usize, h: usize, radius: u32, source: &[bool]) -> Vec<bool> {
    let mut out = vec![false; source.len()];
    if w == 0 || h == 0 || source.len() != w * h {
        return out;
    }
    let r = i128::from(radius).min(w as i128 + h as i128);
    let r_squared = r * r;
    let cap = r + 1;
    // Phase 1: g = distance to the nearest source in the same column, capped.
    let mut g = vec![cap; w * h];
    for x in 0..w {
        let mut d = cap;
        for y in 0..h {
            let i = y * w + x;
            d = if source[i] { 0 } else { (d + 1).min(cap) };
            g[i] = d;
        }
        let mut d = cap;
        for y in (0..h).rev() {
            let i = y * w + x;
            d = if g[i] == 0 { 0 } else { (d + 1).min(cap) };
            g[i] = g[i].min(d);
        }
    }
    // Phase 2: per row, the lower envelope of the parabolas (x - i)^2 + g(i)^2.
    let mut s = vec![0usize; w];
    let mut t = vec![0usize; w];
    for y in 0..h {
        let row = &g[y * w..(y + 1) * w];
        let f = |x: usize, i: usize| {
            let dx = x as i128 - i as i128;
            dx * dx + row[i] * row[i]
        };
        let sep = |i: usize, u: usize| {
            let (i2, u2) = (i as i128 * i as i128, u as i128 * u as i128);
            (u2 - i2 + row[u] * row[u] - row[i] * row[i]).div_euclid(2 * (u as i128 - i as i128))
        };
        let mut q: usize = 0;
        s[0] = 0;
        t[0] = 0;
        for u in 1..w {
            // Pop the segments whose parabola lies above u's at their start.
            let mut empty = false;
            while f(t[q], s[q]) > f(t[q], u) {
                if q == 0 {
                    empty = true;
                    break;
                }
                q -= 1;
            }
            if empty {
                s[0] = u;
            } else {
                let start = 1 + sep(s[q], u);
                if start < w as i128 {
                    q += 1;
                    s[q] = u;
                    t[q] = start.max(0) as usize;
                }
            }
        }
        for u in (0..w).rev() {
            out[y * w + u] = f(u, s[q]) <= r_squared;
            if u == t[q] && q > 0 {
                q -= 1;
            }
        }
    }
    out
}

/// Reads a `map_server` map with default limits and `options` (see [`read_ros_map_with`]).
pub fn read_ros_map(path: &Path, options: &RosOptions) -> Result<RosMap, MapError> {
    read_ros_map_with(
        path,
        &ReadOptions {
            ros: *options,
            ..ReadOptions::default()
        },
    )
}

/// Reads a `map_server` map: the YAML at `path`, then its image (PGM or PNG, found by
/// content) relative to the YAML's directory, into a grid with `options.ros`, within
/// `options`' limits.
///
/// Errors name the YAML file (line and column for its contents, and the `image` value's for
/// an image that cannot be read: [`MapErrorKind::NamedFile`]) or the image file (one that
/// cannot be decoded).
pub fn read_ros_map_with(path: &Path, options: &ReadOptions) -> Result<RosMap, MapError> {
    let origin = path.display().to_string();
    let bytes = crate::read_file(path, &origin, options.max_file_bytes)?;
    ros_map_from_yaml_text(crate::utf8(&bytes, &origin)?, path, options)
}

/// [`read_ros_map_with`] for YAML text already read from `path` (the image is resolved
/// against `path`'s directory).
pub(crate) fn ros_map_from_yaml_text(
    text: &str,
    path: &Path,
    options: &ReadOptions,
) -> Result<RosMap, MapError> {
    let origin = path.display().to_string();
    let (yaml, image_at) = parse_ros_yaml_located(text, &origin)?;
    let image_path = path.parent().unwrap_or(Path::new("")).join(&yaml.image);
    let image_origin = image_path.display().to_string();
    // An image that cannot be read is an error at the YAML's `image` value; one that
    // cannot be decoded names the image.
    let bytes = crate::read_file(&image_path, &image_origin, options.max_file_bytes)
        .map_err(|e| crate::at_name(e, &origin, image_at, "image", &yaml.image))?;
    ros_map_from_image_bytes(&bytes, &image_origin, Some(yaml), options)
}

/// Decodes the image `bytes` (PGM or PNG, found by content) into a map with `yaml`'s
/// thresholds ([`RosYaml::defaults`] when `None`) and `options.ros`' inflation. `origin`
/// names the image in errors and becomes [`RosMap::image_path`].
///
/// The dimensions are read from the header first: an image of more than
/// [`ReadOptions::max_cells`] pixels is an error before any pixel is decoded. The pixels
/// are then read as they come (a PNG a row at a time), so an image whose data ends before
/// its declared size is an error after allocating about what the data held (module
/// docs, "Limits").
///
/// ```
/// use planner_maps::{ros_map_from_image_bytes, ReadOptions};
///
/// // A 3 x 1 ASCII PGM: white (free), black (occupied), map_saver's grey 205 (unknown).
/// let map = ros_map_from_image_bytes(b"P2 3 1 255 255 0 205", "m.pgm", None, &ReadOptions::default()).unwrap();
/// assert_eq!(map.occupancy, [0, 100, -1]);
/// assert_eq!(map.grid.to_ascii(), ".##\n");
/// let small = ReadOptions { max_cells: 2, ..ReadOptions::default() };
/// let err = ros_map_from_image_bytes(b"P2 3 1 255 255 0 205", "m.pgm", None, &small).unwrap_err();
/// assert_eq!(err.to_string(), "m.pgm: a 3x1 map has 3 cells, more than the limit of 2 cells");
/// ```
pub fn ros_map_from_image_bytes(
    bytes: &[u8],
    origin: &str,
    yaml: Option<RosYaml>,
    options: &ReadOptions,
) -> Result<RosMap, MapError> {
    let yaml = yaml.unwrap_or_else(|| {
        let name = Path::new(origin)
            .file_name()
            .map_or_else(|| origin.to_owned(), |n| n.to_string_lossy().into_owned());
        RosYaml::defaults(&name)
    });
    let whole = |kind| MapError::new(origin, 0, 0, kind);
    let image_error = |e: image::ImageError| {
        whole(MapErrorKind::Image {
            message: e.to_string(),
        })
    };
    // The header only: without the decoder's default allocation limit, so that a huge
    // declared size is reported as such below (reading a header allocates at most what
    // the bytes hold).
    let mut header = image::ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| {
            whole(MapErrorKind::Image {
                message: e.to_string(),
            })
        })?;
    header.no_limits();
    let (width, height) = header.into_dimensions().map_err(image_error)?;
    if u64::from(width) * u64::from(height) > options.max_cells {
        return Err(whole(MapErrorKind::TooManyCells {
            width: u64::from(width),
            height: u64::from(height),
            max_cells: options.max_cells,
        }));
    }
    // PGM, PPM and PAM samples are read from the bytes at full precision (the decoder
    // would scale a maxval other than 255 or 65535 to 8 or 16 bits), a PNG a row at a
    // time: either way the values grow with the pixels the file holds.
    let (width, height, occupancy) = if bytes.starts_with(PNG_SIGNATURE) {
        png_occupancy(bytes, &yaml)
    } else {
        pnm_occupancy(bytes, &yaml)
    }
    .map_err(whole)?;
    if options.costs.graded
        && yaml.mode == RosMode::Trinary
        && options.costs.bands.unknown.is_none()
    {
        return Err(whole(MapErrorKind::GradedTrinary));
    }
    let grid = match options.costs.graded {
        false => ros_grid(width, height, &occupancy, &options.ros),
        true => crate::costs::graded_grid(
            width,
            height,
            &occupancy,
            inflated(width, height, &occupancy, &options.ros),
            &options.costs,
        ),
    }
    .map_err(|e| whole(MapErrorKind::Grid(e)))?;
    Ok(RosMap {
        grid,
        occupancy,
        yaml,
        image_path: PathBuf::from(origin),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn yaml(mode: RosMode, negate: bool) -> RosYaml {
        RosYaml {
            image: "m.pgm".into(),
            resolution: 0.05,
            origin: [0.0; 3],
            occupied_thresh: 0.65,
            free_thresh: 0.196,
            negate,
            mode,
            warnings: Vec::new(),
        }
    }

    #[test]
    fn threshold_rule_by_hand() {
        let t = yaml(RosMode::Trinary, false);
        // p = 1 - v / 255: v = 254 -> 0.0039 < 0.196 free; v = 0 -> 1 > 0.65 occupied;
        // v = 205 (map_saver's unknown grey) -> 50 / 255 = 0.19608, not < 0.196: unknown;
        // v = 206 -> 0.1922 free; v = 89 -> 0.651 occupied; v = 90 -> 0.647 unknown.
        let check = |y: &RosYaml, px: &[u16], maxval: u16, expect: i8| {
            assert_eq!(
                ros_occupancy_value(y, px, maxval),
                expect,
                "{px:?} / {maxval} {:?}",
                y.mode
            )
        };
        check(&t, &[254], 255, 0);
        check(&t, &[0], 255, 100);
        check(&t, &[205], 255, -1);
        check(&t, &[206], 255, 0);
        check(&t, &[89], 255, 100);
        check(&t, &[90], 255, -1);
        // Negated: black is free.
        check(&yaml(RosMode::Trinary, true), &[0], 255, 0);
        // RGB: the mean (0 + 255 + 255) / 3 = 170 -> p = 1/3, unknown.
        check(&t, &[0, 255, 255], 255, -1);
        // Full precision: 805 / 1000 -> p = 0.195, free (205 / 255 would be unknown);
        // 52691 / 65535 -> p = 0.19599, free (52691 / 257 = 205.02 would be unknown).
        check(&t, &[805], 1000, 0);
        check(&t, &[52691], u16::MAX, 0);
        check(&t, &[52690], u16::MAX, -1);
        check(&t, &[805, 805, 805], 1000, 0);
        // Scale (nav2): p = 1/3 -> rint(100 (0.3333 - 0.196) / 0.454) = rint(30.25) = 30;
        // v = 179 (nav2's TenByTen.pgm) -> p = 76/255 = 0.29804 -> rint(22.476) = 22 (ROS 1
        // would give 1 + 98 * 0.22476 = 23); not fully opaque -> -1, even when white.
        let s = yaml(RosMode::Scale, false);
        check(&s, &[170, 255], 255, 30);
        check(&s, &[179], 255, 22);
        check(&s, &[170, 0], 255, -1);
        check(&s, &[255, 254], 255, -1);
        check(&s, &[0, 255], 255, 100);
        // 52000 / 65535 -> p = 0.20653 -> rint(2.32) = 2 (202 / 255 would give 3); the
        // alpha of a 16-bit pixel is opaque at 65535 only; 700 / 1000 -> p = 0.3 -> 23.
        check(&s, &[52000], u16::MAX, 2);
        check(&s, &[52000, u16::MAX], u16::MAX, 2);
        check(&s, &[52000, 65534], u16::MAX, -1);
        check(&s, &[700, 1000], 1000, 23);
        // Trinary averages alpha in as nav2 does, beside red, green and blue (a grey
        // pixel's three equal channels): (3 * 170 + 0) / 4 = 127.5 -> p = 0.5, unknown;
        // opaque grey 179 -> (537 + 255) / 4 = 198 -> p = 0.2235, unknown (the mean of grey
        // and alpha, 217, would make it free); RGBA (0, 255, 255, 255) and a transparent
        // white (255, 255, 255, 0) -> 191.25 -> p = 0.25, unknown.
        check(&t, &[170, 0], 255, -1);
        check(&t, &[179, 255], 255, -1);
        check(&t, &[179], 255, -1);
        check(&t, &[220, 255], 255, 0);
        check(&t, &[0, 255, 255, 255], 255, -1);
        check(&t, &[255, 255, 255, 0], 255, -1);
        check(&t, &[255, 255, 255, 255], 255, 0);
        check(&t, &[0, 0], 255, 100);
        // Raw (nav2): round(255 shade) itself when at most 100, else -1; negate is ignored.
        let r = yaml(RosMode::Raw, false);
        check(&r, &[0], 255, 0);
        check(&r, &[100], 255, 100);
        check(&r, &[101], 255, -1);
        check(&r, &[255], 255, -1);
        check(&yaml(RosMode::Raw, true), &[40], 255, 40);
        // 16-bit: round(255 * 10280 / 65535) = round(40.0) = 40; alpha is left out.
        check(&r, &[10280], u16::MAX, 40);
        check(&r, &[10280, 0], u16::MAX, 40);
        // Degenerate input: no samples, five, maxval 0; a sample above maxval counts as it.
        check(&t, &[], 255, -1);
        check(&t, &[0; 5], 255, -1);
        check(&t, &[0], 0, -1);
        check(&t, &[900], 100, 0);
    }

    #[test]
    fn inflation_by_hand() {
        // One occupied cell in the middle of 5 x 5; radius 1 blocks its 4-neighbours
        // (distance 1) but not the diagonals (sqrt 2); radius 2 blocks 13 cells.
        let mut occ = vec![0i8; 25];
        occ[12] = 100;
        let options = |r| RosOptions {
            inflation_radius: r,
            inflate_unknown: false,
        };
        assert_eq!(ros_grid(5, 5, &occ, &options(0)).unwrap().n_free(), 24);
        assert_eq!(ros_grid(5, 5, &occ, &options(1)).unwrap().n_free(), 20);
        assert_eq!(ros_grid(5, 5, &occ, &options(2)).unwrap().n_free(), 12);
        // Unknown cells are blocked but inflate only when asked.
        occ[12] = -1;
        assert_eq!(ros_grid(5, 5, &occ, &options(1)).unwrap().n_free(), 24);
        let both = RosOptions {
            inflation_radius: 1,
            inflate_unknown: true,
        };
        assert_eq!(ros_grid(5, 5, &occ, &both).unwrap().n_free(), 20);
    }

    /// Whether a source lies within `radius` of each cell, by trying every pair.
    fn brute_force(w: usize, h: usize, radius: u32, source: &[bool]) -> Vec<bool> {
        let r = i128::from(radius);
        (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as i128, (i / w) as i128);
                (0..w * h).any(|j| {
                    let (sx, sy) = ((j % w) as i128, (j / w) as i128);
                    source[j] && (x - sx).pow(2) + (y - sy).pow(2) <= r * r
                })
            })
            .collect()
    }

    #[test]
    fn distance_transform_matches_brute_force() {
        // A small deterministic generator (64-bit LCG, Knuth's MMIX constants).
        let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            state >> 33
        };
        let mut n_checked = 0;
        for _ in 0..300 {
            let w = 1 + (next() % 12) as usize;
            let h = 1 + (next() % 12) as usize;
            let density = next() % 5; // 0: no source at all
            let source: Vec<bool> = (0..w * h).map(|_| next() % 10 < density).collect();
            for radius in [1, 2, 3, 5, 8, 20, u32::MAX] {
                assert_eq!(
                    within_radius(w, h, radius, &source),
                    brute_force(w, h, radius, &source),
                    "{w}x{h} radius {radius} sources {source:?}"
                );
                n_checked += 1;
            }
        }
        assert_eq!(n_checked, 2100);
    }

    #[test]
    fn huge_radius_is_clipped_to_the_grid() {
        // Issue 18: radius 100000 on a 6 x 4 map hung. One occupied cell blocks all.
        let mut occ = vec![0i8; 24];
        occ[7] = 100;
        let options = RosOptions {
            inflation_radius: 100_000,
            inflate_unknown: false,
        };
        assert_eq!(ros_grid(6, 4, &occ, &options).unwrap().n_free(), 0);
        let options = RosOptions {
            inflation_radius: u32::MAX,
            inflate_unknown: false,
        };
        assert_eq!(ros_grid(6, 4, &occ, &options).unwrap().n_free(), 0);
        // No source: nothing is blocked, whatever the radius.
        assert_eq!(ros_grid(6, 4, &[0; 24], &options).unwrap().n_free(), 24);
    }

    #[test]
    fn inflation_cost_is_linear_in_the_grid() {
        // A 1000 x 1000 map, a third of it occupied, radius 100000: the old per-source
        // window would visit about 3.3e5 sources x 1e6 cells; the transform visits each
        // cell a few times. All cells are within reach of some source.
        let (w, h) = (1000u32, 1000u32);
        let occ: Vec<i8> = (0..w * h)
            .map(|i| if i % 3 == 0 { 100 } else { 0 })
            .collect();
        let options = RosOptions {
            inflation_radius: 100_000,
            inflate_unknown: false,
        };
        assert_eq!(ros_grid(w, h, &occ, &options).unwrap().n_free(), 0);
        // Radius 1 on the same map: every cell has an occupied 4-neighbour or is one.
        let options = RosOptions {
            inflation_radius: 1,
            inflate_unknown: false,
        };
        assert_eq!(ros_grid(w, h, &occ, &options).unwrap().n_free(), 0);
    }
}
