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
//! Paths are drawn through the centres of the listed cells, so any-angle paths (moves
//! longer than one cell) draw as straight segments between their waypoints; step indices
//! label the listed cells. Cells outside the grid are not drawn. Text from labels, notes
//! and titles is escaped, control characters become spaces, and text too long for the
//! image is cut with an ellipsis.
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
mod render;

use planner_api::{Cell, Grid, Path};
use serde::{Deserialize, Serialize};

pub use palette::{colour, PALETTE};
pub use render::clean as xml_text;

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
    /// the layer's colour under its path in panels, with a legend line giving their
    /// number; empty for none. Overlays do not draw them.
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
/// Draws the grid (free cells white, blocked cells dark, grid lines when cells are at
/// least 6 px), the layer's expanded cells (if any) as a light fill, the path as a polyline through the centres of its cells in the first
/// palette colour, the step index in each path cell and an arrow on each move (sparser on
/// small cells, see the crate docs), `S` on `start` and `G` on `goal`, `title` above and
/// the layer's label and note below. `start` and `goal` outside the grid are not drawn.
pub fn draw_path(
    grid: &Grid,
    start: Cell,
    goal: Cell,
    layer: &Layer<'_>,
    title: &str,
    style: &Style,
) -> String {
    render::panels(grid, start, goal, std::slice::from_ref(layer), title, style)
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
pub fn draw_comparison(
    grid: &Grid,
    start: Cell,
    goal: Cell,
    layers: &[Layer<'_>],
    title: &str,
    style: &Style,
) -> String {
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
        render::panels(grid, start, goal, layers, title, style)
    } else {
        render::overlay(grid, start, goal, layers, title, style)
    }
}

/// One path coloured by time (viridis, dark violet at the first move to yellow at the
/// last), with `markers` as diamonds, as an SVG document: the figure for coverage paths.
///
/// The path's first cell is marked `S` and its last `E`; step indices and arrows follow
/// `style` as in [`draw_path`] (a cell visited more than once lists its indices), and the
/// legend shows the colour ramp from step 0 to the last step and the number of markers.
pub fn draw_timeline(
    grid: &Grid,
    path: &Path,
    markers: &[Marker],
    title: &str,
    style: &Style,
) -> String {
    render::timeline(grid, path, markers, title, style)
}
