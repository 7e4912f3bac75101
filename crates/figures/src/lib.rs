//! SVG figures of paths on occupancy grids, for gridplan's experiment runner.
//!
//! Three kinds of figure:
//! - [`draw_path`]: one planner's path on one problem, as in seed 000's Figs. 7-18 ("each
//!   figure displays the grid layout together with the computed path, including step
//!   indices and movement directions", section 3): obstacles, start `S` and goal `G`, the
//!   path as a polyline through the cell centres, the step index in each path cell, an
//!   arrow on each move, a title and a legend with the layer's note (metrics or status);
//! - [`draw_comparison`]: several planners on one map, either one panel per planner side by
//!   side (maps up to [`PANEL_LIMIT`] cells a side, like seed 000's A*-versus-Backtracking
//!   figures) or overlaid in distinct colours with a legend (larger maps, like seed 002's
//!   Figs. 12-18, which draw several planners' any-angle paths over one map);
//! - [`draw_timeline`]: one long path coloured by time with marked cells, for coverage
//!   paths and their backtracking points (seed 004).
//!
//! # Design
//! Figures are built as an element tree with the [`svg`](https://docs.rs/svg) crate, never
//! by pasting strings, and returned as a `String`. Output is deterministic: the same input
//! gives byte-identical SVG (attributes are written sorted by name, numbers are rounded to
//! two decimals, no ids, no timestamps), so figures can be diffed between runs.
//!
//! Sizes adapt to the map. The cell size is `Style::cell_px` (48 px when 0) reduced so that
//! the whole image fits in `Style::max_px` in both directions. Below
//! [`LABEL_MIN_CELL_PX`] per cell, step indices are left out (unless [`StepLabels::Always`])
//! and arrows become sparse: one every 60 px along the path, at most 60 per path, instead
//! of one per move. Obstacles are drawn as few rectangles (runs of blocked cells in a row,
//! merged downwards with identical runs below) in one scaled group: the 512x512 Moving AI
//! map `random512-10-0` (10 % blocked, scattered) draws in about 1 MB, a 30 %-random
//! 512x512 map in about 2.5 MB, maps of rooms and walls in far less.
//!
//! # Large maps
//! Rectangles grow with the map (a 4096x4096 30 %-random map took 3.1 million, 145 MB of
//! SVG and 2.7 GB to build), so a map of more than [`VECTOR_MAX_CELLS`] cells (512x512)
//! draws its cell layers as pictures instead: the map (free, blocked, unknown, cost
//! shading) as one PNG, and each panel's expanded cells as another over it, embedded as
//! `data:` URIs in `<image>` elements that show their pixels as squares
//! (`image-rendering: pixelated`). A pixel is a block of `k` x `k` cells, `k` the smallest
//! that keeps the picture within the pixels the map takes in the figure and within
//! [`RASTER_MAX_SIDE`] (1024) a side; the block's colour is the mean of its cells' colours,
//! and a block is expanded when any of its cells was; the key says `k`. The path, its
//! arrows, marks, `S` and `G` stay vectors, drawn through the centres of their own cells
//! as on any map. Drawing is one pass over the cells, and its memory a few bytes per pixel
//! (7.9 MB at its peak for a 2048x2048 map); the 4096x4096 map draws in about half a
//! second as a 0.9 MB SVG. Maps up to 512x512 draw their cells as rectangles, as before.
//!
//! # Unknown cells, weights, keys
//! A map that tells unknown cells apart ([`MapView::with_unknown`], a ROS `map_server`
//! map's `-1` cells) draws them in `map_server`'s grey, apart from the dark blocked cells.
//! A weighted grid shades its free cells by weight (brown, more opaque for heavier cells),
//! and each layer's note gives its path's cost (`cost=220.88`, [`Grid::path_cost`], as the
//! runner records it) unless the note gives one (`cost=`). There, a fill of expanded cells
//! would turn the shading's hues into the layer's, so expanded cells are drawn as the
//! outline of their region (its edges towards free cells that were not expanded), in the
//! layer's colour, and the shading inside shows as it is. A key line under the figure says what the
//! colours mean when there is more than free and blocked: blocked and unknown, the
//! weight scale from the lowest weight to the highest, a picture's pixel size. Figures
//! of maps without unknown cells, weights or pictures have no key and are as before.
//!
//! Paths are drawn through the centres of the listed cells, so any-angle paths (moves
//! longer than one cell) draw as straight segments between their waypoints; step indices
//! label the listed cells. Cells outside the grid are not drawn. Text from labels, notes
//! and titles is escaped and control characters become spaces.
//!
//! # Notes are never cut
//! A title, a layer's label or a marker's label too long for the image is cut with an
//! ellipsis, but a layer's note (its metrics, status and cost) and a panel's
//! expanded-cells line never are: they wrap at spaces onto as many lines as the room
//! beside their panel (or, in an overlay, the legend's line after the label, then under
//! it) needs, and the figure grows by those lines, its cells shrinking to keep
//! `Style::max_px`. A word is never broken: a panel's column (and so the figure) widens
//! until the widest word of every note fits, and so does an overlay's legend, even past
//! `max_px` for a map of a few cells a side. A timeline's legend line is never narrower
//! than the figure. A note that fits on one line is drawn as before.
//!
//! Colours: layers take the Okabe-Ito palette ([`PALETTE`]), time is viridis; both are
//! colour-blind safe. Start and goal are black with white letters and different shapes
//! (disc for `S`, square for `G`), so they do not depend on colour either.
//!
//! ```
//! use planner_api::{Cell, Grid, Path};
//! use planner_figures::{draw_path, Layer, Style};
//! let grid = Grid::from_ascii("
//!     ...
//!     .#.
//!     ...
//! ").unwrap();
//! let path = Path::new(vec![
//!     Cell::new(0, 0), Cell::new(1, 0), Cell::new(2, 0), Cell::new(2, 1), Cell::new(2, 2),
//! ]);
//! let layer = Layer::new("astar", Some(&path), "found, D=4 T=1 Score=5");
//! let svg = draw_path(&grid, Cell::new(0, 0), Cell::new(2, 2), &layer, "demo", &Style::default());
//! assert!(svg.starts_with("<svg"));
//! // Steps 1, 2 and 3 are labelled; steps 0 and 4 are the S and G marks.
//! assert_eq!(svg.matches(r#"class="step""#).count(), 3);
//! assert_eq!(svg.matches(r#"class="arrow""#).count(), 4);
//! // Same input, same bytes.
//! let again = draw_path(&grid, Cell::new(0, 0), Cell::new(2, 2), &layer, "demo", &Style::default());
//! assert_eq!(svg, again);
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

mod obstacles;
mod palette;
mod raster;
mod render;

use planner_api::{Cell, Grid, Path};
use serde::{Deserialize, Serialize};

pub use palette::{colour, PALETTE};
pub use render::clean as xml_text;

/// Maps of at most this many cells (512 x 512) draw their cells as SVG rectangles;
/// larger ones draw them as a picture (see the crate docs, "Large maps").
pub const VECTOR_MAX_CELLS: usize = 512 * 512;

/// The most pixels on each side of the picture of a large map's cells (and of the picture
/// of a panel's expanded cells over it).
pub const RASTER_MAX_SIDE: u32 = 1024;

/// The map a figure is drawn on: its grid and, for maps that tell unknown cells apart (a
/// ROS `map_server` map's `-1` cells), which cells are unknown. A `&Grid` converts into
/// one without unknown cells, so every `draw_*` function takes either.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapView<'a> {
    /// The grid: free and blocked cells, and weights if it has them.
    pub grid: &'a Grid,
    /// One flag per cell in the grid's row-major order, true where the map does not know
    /// the cell (drawn grey, whether the grid makes it blocked or free); `None` for none.
    /// Cells past the end of a shorter slice are known; entries past the grid's cells are
    /// ignored.
    pub unknown: Option<&'a [bool]>,
}

impl<'a> MapView<'a> {
    /// `grid` with no unknown cells.
    pub fn new(grid: &'a Grid) -> MapView<'a> {
        MapView {
            grid,
            unknown: None,
        }
    }

    /// The map with `unknown` (one flag per cell, row-major) marking its unknown cells.
    pub fn with_unknown(self, unknown: &'a [bool]) -> MapView<'a> {
        MapView {
            unknown: Some(unknown),
            ..self
        }
    }

    /// Whether the cell at row-major `index` is unknown.
    pub(crate) fn is_unknown(&self, index: usize) -> bool {
        self.unknown
            .is_some_and(|u| u.get(index).copied().unwrap_or(false))
    }

    /// Whether any cell of the grid is unknown.
    pub(crate) fn has_unknown(&self) -> bool {
        self.unknown
            .is_some_and(|u| u.iter().take(self.grid.len()).any(|&x| x))
    }
}

impl<'a> From<&'a Grid> for MapView<'a> {
    fn from(grid: &'a Grid) -> MapView<'a> {
        MapView::new(grid)
    }
}

/// Maps with at most this many cells on each side are compared in panels side by side
/// under [`Layout::Auto`]; larger ones are overlaid.
pub const PANEL_LIMIT: u32 = 64;

/// The smallest cell size, in pixels, at which step indices are drawn under
/// [`StepLabels::Auto`] and arrows are drawn on every move rather than sparsely.
pub const LABEL_MIN_CELL_PX: f64 = 12.0;

/// When step indices are written into the path's cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StepLabels {
    /// When cells are at least [`LABEL_MIN_CELL_PX`] pixels (never in overlays).
    #[default]
    Auto,
    /// Always, however small the cells (unreadable on large maps unless zoomed).
    Always,
    /// Never.
    Never,
}

/// How [`draw_comparison`] arranges several layers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Layout {
    /// Panels when the map has at most [`PANEL_LIMIT`] cells on each side or there is at
    /// most one layer, an overlay otherwise.
    #[default]
    Auto,
    /// One panel per layer, in a grid of panels chosen to make cells as large as possible
    /// within `max_px` (side by side when that fits).
    Panels,
    /// All layers on one map, each in its palette colour, with a legend.
    Overlay,
}

/// How figures are sized and what they show. `Style::default()` suits both seed 000's
/// 6x6 maps and 512x512 benchmark maps.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Style {
    /// Preferred cell size in pixels; 0 (the default), negative or non-finite means 48.
    /// Reduced as needed so that the image fits in `max_px`.
    pub cell_px: f64,
    /// The largest image width and height in pixels (default 1200); 0, negative or
    /// non-finite means unbounded. Titles, legends and margins take a fixed few dozen
    /// pixels, so a bound smaller than those cannot be met.
    pub max_px: f64,
    /// When to write step indices (default [`StepLabels::Auto`]).
    pub step_labels: StepLabels,
    /// Whether to draw direction arrows along the path (default true).
    pub arrows: bool,
    /// How [`draw_comparison`] arranges layers (default [`Layout::Auto`]).
    pub layout: Layout,
}

impl Default for Style {
    fn default() -> Style {
        Style {
            cell_px: 0.0,
            max_px: 1200.0,
            step_labels: StepLabels::Auto,
            arrows: true,
            layout: Layout::Auto,
        }
    }
}

/// One planner's result to draw: its name, its path (if any) and a note.
#[derive(Debug, Clone, PartialEq)]
pub struct Layer<'a> {
    /// Name shown in the legend, e.g. the planner's registry name.
    pub label: &'a str,
    /// The path, start first; `None` (or an empty path) draws only the map, `S` and `G`.
    pub path: Option<&'a Path>,
    /// Text shown with the label, e.g. `"found, D=10 T=2 Score=12"` or `"budget exhausted"`.
    pub note: String,
    /// Cells to mark on this layer's path, e.g. the planner's [`Outcome`] marks.
    ///
    /// [`Outcome`]: planner_api::Outcome
    pub markers: &'a [Marker],
    /// The cells the planner expanded ([`Outcome::expanded`]), drawn as a light fill of
    /// the layer's colour (on a weighted grid, the outline of their region) under its path
    /// in panels, with a legend line giving their number; empty for none. Overlays do not
    /// draw them.
    ///
    /// [`Outcome::expanded`]: planner_api::Outcome::expanded
    pub expanded: &'a [Cell],
}

impl<'a> Layer<'a> {
    /// A layer from its parts.
    pub fn new(label: &'a str, path: Option<&'a Path>, note: impl Into<String>) -> Layer<'a> {
        Layer {
            label,
            path,
            note: note.into(),
            markers: &[],
            expanded: &[],
        }
    }

    /// The layer with `expanded` drawn under its path.
    pub fn with_expanded(self, expanded: &'a [Cell]) -> Layer<'a> {
        Layer { expanded, ..self }
    }

    /// The layer with `markers` drawn on it.
    pub fn with_markers(self, markers: &'a [Marker]) -> Layer<'a> {
        Layer { markers, ..self }
    }
}

/// An extra marked cell with a short label, e.g. a coverage backtracking point or a
/// planner's [`Mark`](planner_api::Mark) (the same type). Markers outside the grid are not
/// drawn; labels are left out when there are more than 40 markers.
pub use planner_api::Mark as Marker;

/// One planner's path on the grid, as an SVG document.
///
/// Draws the map (free cells white, blocked cells dark, unknown cells grey, weighted cells
/// shaded, grid lines when cells are at least 6 px; a picture on large maps, see the crate
/// docs), the layer's expanded cells (if any) as a light fill (an outline on weighted
/// grids), the path as a polyline through the centres of its cells in the first
/// palette colour, the step index in each path cell and an arrow on each move (sparser on
/// small cells, see the crate docs), `S` on `start` and `G` on `goal`, `title` above and
/// the layer's label and note below. `start` and `goal` outside the grid are not drawn.
pub fn draw_path<'g>(
    map: impl Into<MapView<'g>>,
    start: Cell,
    goal: Cell,
    layer: &Layer<'_>,
    title: &str,
    style: &Style,
) -> String {
    let map = map.into();
    render::panels(&map, start, goal, std::slice::from_ref(layer), title, style)
}

/// Several planners' paths on one map, as an SVG document.
///
/// With [`Layout::Panels`] each layer gets the panel [`draw_path`] would draw (in its own
/// palette colour), arranged side by side (wrapping into rows when that gives larger
/// cells); with [`Layout::Overlay`] all paths share one map, earlier layers drawn wider
/// underneath so that shared stretches stay visible, with one legend line per layer;
/// [`Layout::Auto`] picks panels for maps up to [`PANEL_LIMIT`] a side, and whenever a
/// layer has expanded cells (overlays do not draw them). Overlays write step indices
/// only with [`StepLabels::Always`]. With no layer, draws the map alone.
pub fn draw_comparison<'g>(
    map: impl Into<MapView<'g>>,
    start: Cell,
    goal: Cell,
    layers: &[Layer<'_>],
    title: &str,
    style: &Style,
) -> String {
    let map = map.into();
    let grid = map.grid;
    let panels = match style.layout {
        Layout::Panels => true,
        Layout::Overlay => false,
        Layout::Auto => {
            layers.len() <= 1
                || (grid.width() <= PANEL_LIMIT && grid.height() <= PANEL_LIMIT)
                || layers.iter().any(|l| !l.expanded.is_empty())
        }
    };
    if panels {
        render::panels(&map, start, goal, layers, title, style)
    } else {
        render::overlay(&map, start, goal, layers, title, style)
    }
}

/// One path coloured by time (viridis, dark violet at the first move to yellow at the
/// last), with `markers` as diamonds, as an SVG document: the figure for coverage paths.
///
/// The path's first cell is marked `S` and its last `E`; step indices and arrows follow
/// `style` as in [`draw_path`] (a cell visited more than once lists its indices), and the
/// legend shows the colour ramp from step 0 to the last step and the number of markers
/// (and, on a weighted grid, the path's cost).
pub fn draw_timeline<'g>(
    map: impl Into<MapView<'g>>,
    path: &Path,
    markers: &[Marker],
    title: &str,
    style: &Style,
) -> String {
    render::timeline(&map.into(), path, markers, title, style)
}
