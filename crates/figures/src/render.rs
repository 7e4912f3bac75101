//! Layout and drawing of the three figure kinds.
//!
//! Everything is placed in pixels on one canvas; only the map's cell layers (obstacles,
//! unknown cells, costs, expanded cells) live in groups scaled to cell units, which keeps a
//! map's SVG small, and a large map's cell layers are pictures (`raster`).

use std::collections::BTreeMap;

use planner_api::{Cell, Grid, Path};
use svg::node::element::{
    Circle, Element, Group, Line, Path as SvgPath, Polygon, Polyline, Rectangle, TSpan,
};
use svg::node::Value;
use svg::{Document, Node};

use crate::obstacles::blocks;
use crate::palette::{colour, ramp, PALETTE};
use crate::raster::{self, blend, rgb, Palette, Raster};
use crate::{Layer, MapView, Marker, StepLabels, Style, LABEL_MIN_CELL_PX, VECTOR_MAX_CELLS};

const FONT: &str = "DejaVu Sans, Helvetica, Arial, sans-serif";
const MARGIN: f64 = 12.0;
/// Height of the title band above the map.
const TITLE_H: f64 = 30.0;
const TITLE_FS: f64 = 16.0;
const LABEL_FS: f64 = 13.0;
const NOTE_FS: f64 = 12.0;
/// Height of one legend line.
const LINE_H: f64 = 18.0;
/// Space between panels.
const GAP: f64 = 24.0;
/// Cell size when the style asks for none.
const AUTO_CELL_PX: f64 = 48.0;
/// Panels go side by side in one row while cells stay at least this large.
const COMFORTABLE_CELL_PX: f64 = 24.0;
/// Estimated advance of one character, as a fraction of the font size (DejaVu Sans is
/// about 0.55-0.63 for text and 0.64 for digits); used to fit text, never exact.
const CHAR_W: f64 = 0.62;
/// Grid lines are drawn when cells are at least this large.
const GRID_LINES_MIN_PX: f64 = 6.0;
/// Radius of a step-label disc, as a fraction of the cell.
const LABEL_R: f64 = 0.36;
/// Sparse arrows: at least this far apart along the path, and at most this many per path.
const ARROW_SPACING_PX: f64 = 60.0;
const MAX_SPARSE_ARROWS: f64 = 60.0;
/// Coverage paths are long: fewer arrows there.
const MAX_TIMELINE_ARROWS: f64 = 40.0;
/// Number of colour steps along a timeline path.
const TIMELINE_CHUNKS: usize = 128;
/// Marker labels are written only when there are at most this many markers.
const MAX_MARKER_LABELS: usize = 40;
const OBSTACLE: &str = "#3b3b3b";
/// Unknown cells: `map_saver`'s grey (205), as ROS tools show them.
const UNKNOWN: &str = "#cdcdcd";
const GRID_LINE: &str = "#c8c8c8";
const INK: &str = "#222222";

/// A number with at most two decimals and no trailing zeros: short, stable output.
pub(crate) fn num(x: f64) -> String {
    let r = (x * 100.0).round() / 100.0;
    let mut s = format!("{r:.2}");
    while s.ends_with('0') {
        s.pop();
    }
    if s.ends_with('.') {
        s.pop();
    }
    if s == "-0" {
        s = "0".to_owned();
    }
    s
}

/// User text made safe for XML: control characters (forbidden in XML 1.0 even escaped)
/// and the non-characters U+FFFE/U+FFFF become spaces. `&`, `<` and `>` are escaped by
/// the svg crate when the text is written. Also used by the runner's charts, so every
/// SVG gridplan writes cleans user text one way.
pub fn clean(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_control() || c == '\u{FFFE}' || c == '\u{FFFF}' {
                ' '
            } else {
                c
            }
        })
        .collect()
}

/// Estimated width of `s` at font size `fs`.
fn text_width(s: &str, fs: f64) -> f64 {
    s.chars().count() as f64 * fs * CHAR_W
}

/// `s` cleaned and cut with an ellipsis so that it fits in about `max_w` pixels.
fn fit_text(s: &str, fs: f64, max_w: f64) -> String {
    let s = clean(s);
    let n = s.chars().count();
    let room = (max_w / (fs * CHAR_W)).floor().max(1.0) as usize;
    if n <= room {
        s
    } else {
        let mut cut: String = s.chars().take(room.saturating_sub(1)).collect();
        cut.push('…');
        cut
    }
}

/// A `<tspan>` written with no line break before it, as the svg crate writes text: the
/// crate puts a line break before every other element, which in a `<text>` of wrapped
/// lines would reach its text as whitespace between the lines.
#[derive(Clone, Debug)]
struct Inline(TSpan);

impl std::fmt::Display for Inline {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl svg::node::NodeDefaultHash for Inline {
    fn default_hash(&self, state: &mut std::collections::hash_map::DefaultHasher) {
        self.0.default_hash(state)
    }
}

impl Node for Inline {
    fn get_name(&self) -> &str {
        "tspan"
    }

    fn is_bare(&self) -> bool {
        true
    }
}

/// `s` cleaned and broken at spaces into lines of about `room` pixels (`first` for the
/// first line), never cut: a word wider than its line gets a line of its own (and the first
/// line stays empty when its first word is wider than `first` but fits `room`). Each line
/// but the last keeps the space it was broken at, so the lines joined give `clean(s)`.
fn wrap(s: &str, fs: f64, first: f64, room: f64) -> Vec<String> {
    let mut lines = vec![String::new()];
    for piece in clean(s).split_inclusive(' ') {
        let (line, cap) = match lines.len() {
            1 => (&lines[0], first),
            n => (&lines[n - 1], room),
        };
        let width = text_width(&format!("{line}{}", piece.trim_end_matches(' ')), fs);
        let empty_first = lines.len() == 1 && line.is_empty();
        if width > cap && (!line.is_empty() || (empty_first && first < room)) {
            lines.push(String::new());
        }
        if let Some(line) = lines.last_mut() {
            line.push_str(piece);
        }
    }
    lines
}

/// The width of the widest word (text between spaces) of `s` at font size `fs`.
fn widest_word(s: &str, fs: f64) -> f64 {
    clean(s)
        .split(' ')
        .map(|w| text_width(w, fs))
        .fold(0.0, f64::max)
}

/// A `<text>` of `lines` (from [`wrap`]) at `x` from the line `y` on, one line every
/// [`LINE_H`] (`x_next` for the lines after the first): one line is a plain text, more
/// are `<tspan>`s placed line by line, so the element's text is the lines joined.
fn lines_text(x: f64, x_next: f64, y: f64, lines: &[String], fs: f64) -> Element {
    match lines {
        [line] => text(x, y, line.clone(), fs),
        _ => {
            let mut t = text(x, y, String::new(), fs);
            for (i, line) in lines.iter().enumerate() {
                let lx = if i == 0 { x } else { x_next };
                t.append(Inline(
                    TSpan::new(line.clone())
                        .set("x", num(lx))
                        .set("y", num(y + i as f64 * LINE_H)),
                ));
            }
            t
        }
    }
}

/// Builder-style attributes for a plain [`Element`].
trait Set {
    fn set<U: Into<Value>>(self, name: &str, value: U) -> Self;
}

impl Set for Element {
    fn set<U: Into<Value>>(mut self, name: &str, value: U) -> Element {
        self.assign(name, value);
        self
    }
}

/// A `<text>` element. Built as a plain element because the svg crate's own `Text` type
/// writes line breaks around its content, which then reach the text as spaces.
fn text(x: f64, y: f64, content: String, fs: f64) -> Element {
    let mut t = Element::new("text");
    if !content.is_empty() {
        t.append(svg::node::Text::new(content));
    }
    t.set("x", num(x))
        .set("y", num(y))
        .set("font-size", num(fs))
}

/// Where the map is drawn: top-left corner and cell size in pixels.
#[derive(Debug, Clone, Copy)]
struct Frame {
    ox: f64,
    oy: f64,
    cell: f64,
}

impl Frame {
    fn centre(&self, c: Cell) -> (f64, f64) {
        (
            self.ox + (f64::from(c.x) + 0.5) * self.cell,
            self.oy + (f64::from(c.y) + 0.5) * self.cell,
        )
    }

    fn corner(&self, c: Cell) -> (f64, f64) {
        (
            self.ox + f64::from(c.x) * self.cell,
            self.oy + f64::from(c.y) * self.cell,
        )
    }
}

/// The cell size for `cols_cells` x `rows_cells` cells of map plus fixed chrome of
/// `extra_w` x `extra_h` pixels: the preferred size, reduced to fit `max_px`, then
/// floored to whole pixels (from 4 px up, for crisp cells) or to 1/100 px.
fn fit_cell(style: &Style, cols_cells: f64, rows_cells: f64, extra_w: f64, extra_h: f64) -> f64 {
    let preferred = if style.cell_px.is_finite() && style.cell_px > 0.0 {
        style.cell_px
    } else {
        AUTO_CELL_PX
    };
    let max_px = if style.max_px.is_finite() && style.max_px > 0.0 {
        style.max_px
    } else {
        f64::INFINITY
    };
    let cell = preferred
        .min((max_px - extra_w) / cols_cells)
        .min((max_px - extra_h) / rows_cells);
    let cell = if cell >= 4.0 {
        cell.floor()
    } else {
        (cell * 100.0).floor() / 100.0
    };
    if cell >= 0.01 {
        cell
    } else {
        0.01
    }
}

fn max_px(style: &Style) -> f64 {
    if style.max_px.is_finite() && style.max_px > 0.0 {
        style.max_px
    } else {
        f64::INFINITY
    }
}

fn labels_on(style: &Style, cell: f64) -> bool {
    match style.step_labels {
        StepLabels::Always => true,
        StepLabels::Never => false,
        StepLabels::Auto => cell >= LABEL_MIN_CELL_PX,
    }
}

/// A new document of `w` x `h` pixels with a white background.
fn document(w: f64, h: f64) -> Document {
    let (w, h) = (w.ceil(), h.ceil());
    let mut doc = Document::new()
        .set("width", num(w))
        .set("height", num(h))
        .set("viewBox", format!("0 0 {} {}", num(w), num(h)))
        .set("font-family", FONT);
    doc.append(
        Rectangle::new()
            .set("width", "100%")
            .set("height", "100%")
            .set("fill", "#ffffff"),
    );
    doc
}

fn finish(doc: Document) -> String {
    let mut s = doc.to_string();
    s.push('\n');
    s
}

fn title_text(title: &str, width: f64) -> Element {
    text(
        MARGIN,
        MARGIN + TITLE_FS,
        fit_text(title, TITLE_FS, width - 2.0 * MARGIN),
        TITLE_FS,
    )
    .set("font-weight", "bold")
    .set("class", "title")
}

/// The transform of a group drawn in cell units at frame `f`.
fn cell_units(f: Frame) -> String {
    format!(
        "translate({} {}) scale({})",
        num(f.ox),
        num(f.oy),
        num(f.cell)
    )
}

/// The lowest and highest weight of a grid whose free cells are shaded by weight (a
/// weighted grid whose weights are not all equal).
fn shaded(grid: &Grid) -> Option<(u16, u16)> {
    let weights = grid.weights()?;
    (weights.max() > weights.min()).then(|| (weights.min(), weights.max()))
}

/// A weighted grid's free cells shaded by weight (issue 32): runs of equal weight in a row
/// as one rectangle each, in [`COST_FILL`] at an opacity rising linearly from 0 at the
/// grid's smallest weight to [`COST_MAX_OPACITY`] at its largest; cells of the smallest
/// weight are not drawn.
fn cost_group(grid: &Grid, f: Frame) -> Option<Group> {
    let weights = grid.weights()?;
    let (low, high) = shaded(grid)?;
    let mut g = Group::new()
        .set("class", "costs")
        .set("fill", COST_FILL)
        .set("shape-rendering", "crispEdges")
        .set("transform", cell_units(f));
    let width = grid.width() as usize;
    let free = grid.free_cells();
    for (y, row) in weights.cells().chunks(width).enumerate() {
        let free_row = &free[y * width..(y + 1) * width];
        let mut x = 0;
        while x < width {
            let mut end = x + 1;
            while end < width && row[end] == row[x] && free_row[end] == free_row[x] {
                end += 1;
            }
            if free_row[x] && row[x] > low {
                let share = f64::from(row[x] - low) / f64::from(high - low);
                g.append(
                    Rectangle::new()
                        .set("x", x)
                        .set("y", y)
                        .set("width", end - x)
                        .set("height", 1)
                        .set("fill-opacity", num(COST_MAX_OPACITY * share)),
                );
            }
            x = end;
        }
    }
    Some(g)
}

/// The colour of cell costs.
const COST_FILL: &str = "#a0522d";
/// The opacity of the largest weight's shading.
const COST_MAX_OPACITY: f64 = 0.6;

/// How one figure draws its map's cell layers: as rectangles (maps of up to
/// [`VECTOR_MAX_CELLS`] cells) or as pictures at one block size, the map's picture made
/// once per figure and shared by its panels.
enum Cells {
    Vector,
    Raster(Raster),
}

impl Cells {
    /// The drawing of `map`'s cells at `cell` pixels a cell.
    fn new(map: &MapView<'_>, cell: f64) -> Cells {
        let grid = map.grid;
        if grid.len() <= VECTOR_MAX_CELLS {
            return Cells::Vector;
        }
        let k = raster::block_size(grid.width().max(grid.height()), cell);
        let palette = Palette {
            free: [255; 3],
            blocked: rgb(OBSTACLE),
            unknown: rgb(UNKNOWN),
            cost: rgb(COST_FILL),
            cost_opacity: COST_MAX_OPACITY,
        };
        Cells::Raster(Raster::new(map, k, &palette))
    }

    /// Cells per pixel side of the pictures (1 for rectangles).
    fn block(&self) -> u32 {
        match self {
            Cells::Vector => 1,
            Cells::Raster(r) => r.k,
        }
    }
}

/// A picture of the grid's cells (`uri`, `r`'s pixels) at frame `f`, in an `<svg>` of the
/// map's size and cell units that clips the last row and column of blocks, which may
/// reach past the map. Pixels are drawn as squares (`image-rendering`), not smoothed.
fn picture(grid: &Grid, f: Frame, r: &Raster, uri: &str, class: &str) -> Element {
    let (w, h) = (f64::from(grid.width()), f64::from(grid.height()));
    let mut view = Element::new("svg")
        .set("x", num(f.ox))
        .set("y", num(f.oy))
        .set("width", num(w * f.cell))
        .set("height", num(h * f.cell))
        .set("viewBox", format!("0 0 {} {}", grid.width(), grid.height()))
        .set("preserveAspectRatio", "none")
        .set("class", class);
    view.append(
        Element::new("image")
            .set("width", u64::from(r.width) * u64::from(r.k))
            .set("height", u64::from(r.height) * u64::from(r.k))
            .set("preserveAspectRatio", "none")
            .set("image-rendering", "optimizeSpeed")
            .set("style", "image-rendering:pixelated")
            .set("href", uri),
    );
    view
}

/// The grid lines, when cells are large enough to show them.
fn grid_lines(grid: &Grid, f: Frame) -> Option<SvgPath> {
    if f.cell < GRID_LINES_MIN_PX {
        return None;
    }
    let (w, h) = (
        f64::from(grid.width()) * f.cell,
        f64::from(grid.height()) * f.cell,
    );
    let mut d = String::new();
    for x in 1..grid.width() {
        let px = f.ox + f64::from(x) * f.cell;
        d.push_str(&format!("M{} {}V{}", num(px), num(f.oy), num(f.oy + h)));
    }
    for y in 1..grid.height() {
        let py = f.oy + f64::from(y) * f.cell;
        d.push_str(&format!("M{} {}H{}", num(f.ox), num(py), num(f.ox + w)));
    }
    (!d.is_empty()).then(|| {
        SvgPath::new()
            .set("d", d)
            .set("stroke", GRID_LINE)
            .set("stroke-width", 1)
            .set("fill", "none")
    })
}

/// The cells flagged in `marked` (row-major) as few rectangles in `fill`, in a group of
/// class `class` scaled to cell units.
fn block_group(grid: &Grid, f: Frame, marked: &[bool], fill: &str, class: &str) -> Group {
    let mut g = Group::new()
        .set("class", class)
        .set("fill", fill)
        .set("shape-rendering", "crispEdges")
        .set("transform", cell_units(f));
    for b in blocks(grid.width() as usize, marked) {
        g.append(
            Rectangle::new()
                .set("x", b.x)
                .set("y", b.y)
                .set("width", b.w)
                .set("height", b.h),
        );
    }
    g
}

/// The map: free background, grid lines, unknown cells, cost shading on weighted grids,
/// obstacles, border; with `Cells::Raster`, the picture of all but the border (and the
/// grid lines, over it, when a pixel is a cell and cells are large).
fn map_group(map: &MapView<'_>, f: Frame, cells: &Cells) -> Group {
    let grid = map.grid;
    let (w, h) = (
        f64::from(grid.width()) * f.cell,
        f64::from(grid.height()) * f.cell,
    );
    let mut g = Group::new().set("class", "map");
    g.append(
        Rectangle::new()
            .set("x", num(f.ox))
            .set("y", num(f.oy))
            .set("width", num(w))
            .set("height", num(h))
            .set("fill", "#ffffff"),
    );
    match cells {
        Cells::Vector => {
            if let Some(lines) = grid_lines(grid, f) {
                g.append(lines);
            }
            if map.has_unknown() {
                let unknown: Vec<bool> = (0..grid.len()).map(|i| map.is_unknown(i)).collect();
                g.append(block_group(grid, f, &unknown, UNKNOWN, "unknown"));
            }
            if let Some(costs) = cost_group(grid, f) {
                g.append(costs);
            }
            let blocked: Vec<bool> = grid
                .free_cells()
                .iter()
                .enumerate()
                .map(|(i, &free)| !free && !map.is_unknown(i))
                .collect();
            g.append(block_group(grid, f, &blocked, OBSTACLE, "obstacles"));
        }
        Cells::Raster(r) => {
            if let Some(uri) = &r.uri {
                g.append(picture(grid, f, r, uri, "cells"));
            }
            if r.k == 1 {
                if let Some(lines) = grid_lines(grid, f) {
                    g.append(lines);
                }
            }
        }
    }
    g.append(
        Rectangle::new()
            .set("x", num(f.ox))
            .set("y", num(f.oy))
            .set("width", num(w))
            .set("height", num(h))
            .set("fill", "none")
            .set("stroke", INK)
            .set("stroke-width", 1),
    );
    g
}

/// The path's cells that lie inside the grid, with their index in the path.
fn cells_in(grid: &Grid, path: Option<&Path>) -> Vec<(usize, Cell)> {
    path.map(|p| {
        p.cells()
            .iter()
            .copied()
            .enumerate()
            .filter(|&(_, c)| grid.contains(c))
            .collect()
    })
    .unwrap_or_default()
}

/// Polyline vertices: repeated cells and the middle of straight runs dropped.
fn vertices(cells: &[(usize, Cell)]) -> Vec<Cell> {
    let mut out: Vec<Cell> = Vec::with_capacity(cells.len());
    for &(_, c) in cells {
        if out.last() == Some(&c) {
            continue;
        }
        if out.len() >= 2 {
            let (a, b) = (out[out.len() - 2], out[out.len() - 1]);
            let d1 = (
                i64::from(b.x) - i64::from(a.x),
                i64::from(b.y) - i64::from(a.y),
            );
            let d2 = (
                i64::from(c.x) - i64::from(b.x),
                i64::from(c.y) - i64::from(b.y),
            );
            let same = d1.0 * d2.1 == d1.1 * d2.0 && d1.0 * d2.0 + d1.1 * d2.1 > 0;
            if same {
                out.pop();
            }
        }
        out.push(c);
    }
    out
}

fn polyline(f: Frame, cells: &[Cell], colour: &str, width: f64) -> Option<Polyline> {
    if cells.len() < 2 {
        return None;
    }
    let points: Vec<String> = cells
        .iter()
        .map(|&c| {
            let (x, y) = f.centre(c);
            format!("{},{}", num(x), num(y))
        })
        .collect();
    Some(
        Polyline::new()
            .set("points", points.join(" "))
            .set("fill", "none")
            .set("stroke", colour)
            .set("stroke-width", num(width))
            .set("stroke-linejoin", "round")
            .set("stroke-linecap", "round"),
    )
}

/// A filled triangle centred at `m` pointing along the unit vector `u`.
fn arrow(m: (f64, f64), u: (f64, f64), len: f64, colour: &str, outline: &str) -> Polygon {
    let hw = 0.45 * len;
    let (nx, ny) = (-u.1, u.0);
    let tip = (m.0 + u.0 * len / 2.0, m.1 + u.1 * len / 2.0);
    let back = (m.0 - u.0 * len / 2.0, m.1 - u.1 * len / 2.0);
    let points = format!(
        "{},{} {},{} {},{}",
        num(tip.0),
        num(tip.1),
        num(back.0 + nx * hw),
        num(back.1 + ny * hw),
        num(back.0 - nx * hw),
        num(back.1 - ny * hw)
    );
    Polygon::new()
        .set("points", points)
        .set("fill", colour)
        .set("stroke", outline)
        .set("stroke-width", num((len / 12.0).clamp(0.5, 1.5)))
        .set("stroke-linejoin", "round")
        .set("class", "arrow")
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Arrows {
    None,
    /// One at the middle of every move.
    EveryMove,
    /// Evenly spaced along the path, at most this many.
    Sparse(f64),
}

/// Direction arrows along the moves between consecutive in-grid cells. `colour(i)` is the
/// fill for the move ending at path index `i`; `outline` the edge colour.
fn arrows(
    f: Frame,
    cells: &[(usize, Cell)],
    mode: Arrows,
    len: f64,
    colour: &dyn Fn(usize) -> String,
    outline: &str,
) -> Group {
    let mut g = Group::new().set("class", "arrows");
    let moves = cells
        .windows(2)
        .filter(|w| w[0].1 != w[1].1)
        .map(|w| (w[1].0, f.centre(w[0].1), f.centre(w[1].1)));
    match mode {
        Arrows::None => {}
        Arrows::EveryMove => {
            for (i, a, b) in moves {
                let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                let d = dx.hypot(dy);
                let m = ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0);
                g.append(arrow(m, (dx / d, dy / d), len, &colour(i), outline));
            }
        }
        Arrows::Sparse(max_arrows) => {
            let total: f64 = moves
                .clone()
                .map(|(_, a, b)| (b.0 - a.0).hypot(b.1 - a.1))
                .sum();
            let spacing = ARROW_SPACING_PX.max(total / max_arrows);
            // Arrows at spacing/2, 3 spacing/2, ... along the path.
            let mut next = spacing / 2.0;
            let mut walked = 0.0;
            for (i, a, b) in moves {
                let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                let d = dx.hypot(dy);
                while next <= walked + d {
                    let t = (next - walked) / d;
                    let m = (a.0 + dx * t, a.1 + dy * t);
                    g.append(arrow(m, (dx / d, dy / d), len, &colour(i), outline));
                    next += spacing;
                }
                walked += d;
            }
        }
    }
    g
}

/// The fill opacity of expanded cells: light enough that the path, obstacles and step
/// labels on top stay readable.
const EXPANDED_OPACITY: f64 = 0.3;

/// The width in pixels of the outline of expanded cells on a shaded grid: thicker on large
/// cells, at least 1.5 px.
fn outline_px(cell: f64) -> f64 {
    (0.08 * cell).clamp(1.5, 3.0)
}

/// A panel's expanded cells in `colour`, in one group of class `expanded`. Cells outside
/// the grid and repeats are left out.
///
/// On a grid without cost shading, a light fill: one rectangle per run of consecutive cells
/// in a row, in a group scaled to cell units (as the obstacles), so a search that expands
/// 100,000 cells draws a few thousand rectangles. On a shaded (weighted) grid, where a fill
/// would turn the shading's hues into its own, the outline of their region instead: the
/// edges between an expanded cell and a free cell that is not, so the shading inside shows
/// as it is. With `Cells::Raster`, the same as a picture over the map's, a block expanded
/// when any of its cells is.
fn expanded_group(
    map: &MapView<'_>,
    f: Frame,
    cells: &Cells,
    expanded: &[Cell],
    colour: &str,
) -> Group {
    let grid = map.grid;
    let outline = shaded(grid).is_some();
    if let Cells::Raster(r) = cells {
        let mut g = Group::new().set("class", "expanded");
        let uri = r.expanded_uri(grid, expanded, rgb(colour), EXPANDED_OPACITY, outline);
        if let Some(uri) = uri {
            g.append(picture(grid, f, r, &uri, "expanded-cells"));
        }
        return g;
    }
    if outline {
        let mut g = Group::new()
            .set("class", "expanded")
            .set("transform", cell_units(f));
        let d = outline_path(grid, expanded);
        if !d.is_empty() {
            g.append(
                SvgPath::new()
                    .set("d", d)
                    .set("fill", "none")
                    .set("stroke", colour)
                    .set("stroke-width", num(outline_px(f.cell) / f.cell))
                    .set("stroke-linecap", "square"),
            );
        }
        return g;
    }
    let mut g = Group::new()
        .set("class", "expanded")
        .set("fill", colour)
        .set("fill-opacity", EXPANDED_OPACITY)
        .set("shape-rendering", "crispEdges")
        .set("transform", cell_units(f));
    let mut sorted: Vec<Cell> = expanded
        .iter()
        .copied()
        .filter(|&c| grid.contains(c))
        .collect();
    sorted.sort_unstable_by_key(|c| (c.y, c.x));
    sorted.dedup();
    let mut i = 0;
    while i < sorted.len() {
        let first = sorted[i];
        let mut j = i + 1;
        while j < sorted.len() && sorted[j].y == first.y && sorted[j].x == first.x + (j - i) as u32
        {
            j += 1;
        }
        g.append(
            Rectangle::new()
                .set("x", first.x)
                .set("y", first.y)
                .set("width", j - i)
                .set("height", 1),
        );
        i = j;
    }
    g
}

/// The outline of the region of `expanded` cells, as path data in cell units: every edge
/// between an expanded cell and a free cell that is not, runs along a row or column
/// joined into one segment. Edges towards blocked cells (which no search expands) and
/// along the map's border are left out. Used on maps of at most [`VECTOR_MAX_CELLS`]
/// cells.
fn outline_path(grid: &Grid, expanded: &[Cell]) -> String {
    let (w, h) = (grid.width() as usize, grid.height() as usize);
    let mut marked = vec![false; grid.len()];
    for &c in expanded {
        if grid.contains(c) {
            marked[grid.index(c)] = true;
        }
    }
    let free = grid.free_cells();
    let edge = |a: usize, b: usize| {
        (marked[a] && !marked[b] && free[b]) || (marked[b] && !marked[a] && free[a])
    };
    let mut d = String::new();
    // Between rows y - 1 and y, and between columns x - 1 and x.
    for y in 1..h {
        let mut x = 0;
        while x < w {
            let first = x;
            while x < w && edge((y - 1) * w + x, y * w + x) {
                x += 1;
            }
            if x > first {
                d.push_str(&format!("M{first} {y}H{x}"));
            } else {
                x += 1;
            }
        }
    }
    for x in 1..w {
        let mut y = 0;
        while y < h {
            let first = y;
            while y < h && edge(y * w + x - 1, y * w + x) {
                y += 1;
            }
            if y > first {
                d.push_str(&format!("M{x} {first}V{y}"));
            } else {
                y += 1;
            }
        }
    }
    d
}

/// The number of distinct cells among `cells`.
fn n_distinct(cells: &[Cell]) -> usize {
    let mut sorted = cells.to_vec();
    sorted.sort_unstable_by_key(|c| (c.y, c.x));
    sorted.dedup();
    sorted.len()
}

/// Pale cells under a labelled path.
fn tint(f: Frame, cells: &[(usize, Cell)], colour: &str) -> Group {
    let mut g = Group::new()
        .set("class", "tint")
        .set("fill", colour)
        .set("fill-opacity", 0.15);
    let distinct: std::collections::BTreeSet<Cell> = cells.iter().map(|&(_, c)| c).collect();
    for c in distinct {
        let (x, y) = f.corner(c);
        g.append(
            Rectangle::new()
                .set("x", num(x))
                .set("y", num(y))
                .set("width", num(f.cell))
                .set("height", num(f.cell)),
        );
    }
    g
}

/// Step indices in white discs, one per distinct cell (a revisited cell lists its first
/// two indices, then an ellipsis if there are more); cells in `skip` get none.
/// `colour(i)` is the disc outline for the first visit at index `i`.
fn step_labels(
    f: Frame,
    cells: &[(usize, Cell)],
    skip: &[Cell],
    colour: &dyn Fn(usize) -> String,
) -> Group {
    let mut by_cell: BTreeMap<Cell, Vec<usize>> = BTreeMap::new();
    for &(i, c) in cells {
        if !skip.contains(&c) {
            by_cell.entry(c).or_default().push(i);
        }
    }
    // Draw in order of first visit so that output follows the path.
    let mut order: Vec<(usize, Cell, Vec<usize>)> =
        by_cell.into_iter().map(|(c, v)| (v[0], c, v)).collect();
    order.sort_unstable_by_key(|&(first, c, _)| (first, c));
    let r = LABEL_R * f.cell;
    let mut g = Group::new().set("class", "steps");
    for (first, c, indices) in order {
        let mut label = indices
            .iter()
            .take(2)
            .map(|i| i.to_string())
            .collect::<Vec<_>>()
            .join(",");
        if indices.len() > 2 {
            label.push('…');
        }
        let n = label.chars().count() as f64;
        // Fit the label in the disc: about 1.8 r wide, at most 0.4 cell tall.
        let fs = (0.4 * f.cell).min(1.8 * r / (0.64 * n));
        let (x, y) = f.centre(c);
        g.append(
            Circle::new()
                .set("cx", num(x))
                .set("cy", num(y))
                .set("r", num(r))
                .set("fill", "#ffffff")
                .set("stroke", colour(first))
                .set("stroke-width", num((0.05 * f.cell).max(1.0))),
        );
        g.append(
            text(x, y + 0.36 * fs, label, fs)
                .set("text-anchor", "middle")
                .set("fill", INK)
                .set("class", "step"),
        );
    }
    g
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Shape {
    Disc,
    Square,
}

/// A start or goal mark: a black disc or square with a white letter, as big as a step
/// label on large cells and at least 7 px in radius on small ones, drawn on top.
fn endpoint(grid: &Grid, f: Frame, cell: Cell, letter: &str, shape: Shape) -> Option<Group> {
    if !grid.contains(cell) {
        return None;
    }
    let r = if f.cell >= LABEL_MIN_CELL_PX {
        LABEL_R * f.cell + 1.0
    } else {
        (0.6 * f.cell).max(8.0)
    };
    let (x, y) = f.centre(cell);
    let mut g = Group::new().set("class", "endpoint");
    let stroke = num((r / 8.0).clamp(1.0, 2.0));
    match shape {
        Shape::Disc => g.append(
            Circle::new()
                .set("cx", num(x))
                .set("cy", num(y))
                .set("r", num(r))
                .set("fill", "#000000")
                .set("stroke", "#ffffff")
                .set("stroke-width", stroke),
        ),
        Shape::Square => {
            let s = 0.9 * r;
            g.append(
                Rectangle::new()
                    .set("x", num(x - s))
                    .set("y", num(y - s))
                    .set("width", num(2.0 * s))
                    .set("height", num(2.0 * s))
                    .set("fill", "#000000")
                    .set("stroke", "#ffffff")
                    .set("stroke-width", stroke),
            )
        }
    }
    let fs = 1.1 * r;
    g.append(
        text(x, y + 0.36 * fs, letter.to_owned(), fs)
            .set("text-anchor", "middle")
            .set("font-weight", "bold")
            .set("fill", "#ffffff"),
    );
    Some(g)
}

fn endpoints(grid: &Grid, f: Frame, start: Cell, goal: Cell, labels: (&str, &str)) -> Group {
    let mut g = Group::new();
    // Goal first so that a start on the goal stays visible.
    for mark in [
        endpoint(grid, f, goal, labels.1, Shape::Square),
        endpoint(grid, f, start, labels.0, Shape::Disc),
    ]
    .into_iter()
    .flatten()
    {
        g.append(mark);
    }
    g
}

/// Width of a path's line: thicker on large cells, at least 2 px.
fn line_width(cell: f64) -> f64 {
    if cell >= LABEL_MIN_CELL_PX {
        (0.08 * cell).clamp(2.0, 5.0)
    } else {
        (0.3 * cell).clamp(2.0, 3.0)
    }
}

/// Arrow length for a cell size.
fn arrow_len(cell: f64, mode: Arrows, line: f64) -> f64 {
    match mode {
        Arrows::EveryMove => 0.26 * cell,
        _ => (3.5 * line).max(10.0),
    }
}

fn arrow_mode(style: &Style, cell: f64, max_sparse: f64) -> Arrows {
    if !style.arrows {
        Arrows::None
    } else if cell >= LABEL_MIN_CELL_PX {
        Arrows::EveryMove
    } else {
        Arrows::Sparse(max_sparse)
    }
}

/// One layer's path: tint (when labelled), line, arrows, step labels.
#[allow(clippy::too_many_arguments)]
fn layer_group(
    grid: &Grid,
    f: Frame,
    path: Option<&Path>,
    colour: &str,
    width: f64,
    labels: bool,
    mode: Arrows,
    skip: &[Cell],
) -> Group {
    let cells = cells_in(grid, path);
    let mut g = Group::new().set("class", "layer");
    if labels {
        g.append(tint(f, &cells, colour));
    }
    if let Some(line) = polyline(f, &vertices(&cells), colour, width) {
        g.append(line.set("class", "path"));
    }
    let same = |_: usize| colour.to_owned();
    let len = arrow_len(f.cell, mode, width);
    g.append(arrows(f, &cells, mode, len, &same, "#ffffff"));
    if labels {
        g.append(step_labels(f, &cells, skip, &same));
    }
    g
}

/// `markers` on the map in `colour`: with `framed` (cells large enough for step labels) a
/// frame around each cell with its label in the top-left corner, clear of the step disc;
/// on small cells a diamond with the label beside it (left of it near the right edge),
/// labels only when there are at most [`MAX_MARKER_LABELS`] markers.
fn marker_group(grid: &Grid, f: Frame, markers: &[Marker], framed: bool, colour: &str) -> Group {
    let shown: Vec<&Marker> = markers.iter().filter(|m| grid.contains(m.cell)).collect();
    let mut mg = Group::new().set("class", "markers");
    let cell = f.cell;
    let r = (0.5 * cell).max(4.5);
    let right_edge = f.ox + f64::from(grid.width()) * cell;
    for m in &shown {
        let (x, y) = f.centre(m.cell);
        if framed {
            let t = (0.08 * cell).max(2.0);
            let (cx, cy) = f.corner(m.cell);
            mg.append(
                Rectangle::new()
                    .set("x", num(cx + t / 2.0))
                    .set("y", num(cy + t / 2.0))
                    .set("width", num(cell - t))
                    .set("height", num(cell - t))
                    .set("fill", "none")
                    .set("stroke", colour)
                    .set("stroke-width", num(t))
                    .set("class", "marker"),
            );
        } else {
            let d = format!(
                "M{} {}L{} {}L{} {}L{} {}Z",
                num(x),
                num(y - r),
                num(x + r),
                num(y),
                num(x),
                num(y + r),
                num(x - r),
                num(y)
            );
            mg.append(
                SvgPath::new()
                    .set("d", d)
                    .set("fill", colour)
                    .set("stroke", "#ffffff")
                    .set("stroke-width", 1)
                    .set("class", "marker"),
            );
        }
        if m.label.is_empty() || (!framed && shown.len() > MAX_MARKER_LABELS) {
            continue;
        }
        let (fs, lx, ly, anchor, max_w) = if framed {
            let (cx, cy) = f.corner(m.cell);
            let fs = (0.24 * cell).min(NOTE_FS);
            (
                fs,
                cx + 0.1 * cell,
                cy + 0.1 * cell + 0.8 * fs,
                "start",
                0.9 * cell,
            )
        } else if x + r + 50.0 > right_edge {
            (NOTE_FS, x - r - 2.0, y - r / 2.0, "end", 120.0)
        } else {
            (NOTE_FS, x + r + 2.0, y - r / 2.0, "start", 120.0)
        };
        mg.append(
            text(lx, ly, fit_text(&m.label, fs, max_w), fs)
                .set("text-anchor", anchor)
                .set("font-weight", "bold")
                .set("fill", if framed { colour } else { INK })
                .set("stroke", "#ffffff")
                .set("stroke-width", num((fs / 4.0).max(1.0)))
                .set("stroke-linejoin", "round")
                .set("paint-order", "stroke")
                .set("class", "marker-label"),
        );
    }
    mg
}

/// A colour swatch: a short thick line ending at `x + 16`, centred on the text line `y`.
fn swatch(x: f64, y: f64, colour: &str, width: f64) -> Line {
    Line::new()
        .set("x1", num(x))
        .set("y1", num(y - 4.5))
        .set("x2", num(x + 16.0))
        .set("y2", num(y - 4.5))
        .set("stroke", colour)
        .set("stroke-width", num(width.clamp(3.0, 6.0)))
}

/// One entry of a map's key.
enum KeyItem {
    /// A colour and what it means.
    Swatch(&'static str, &'static str),
    /// The cost shading from the lowest weight to the highest.
    Scale(u16, u16),
    /// The cells a pixel of a picture holds.
    Pixel(u32),
}

/// Height of the key's line.
const KEY_H: f64 = LINE_H + 4.0;
/// Width of a key's swatch and of each of its scale's steps.
const KEY_SWATCH: f64 = 11.0;
/// Steps of the key's cost scale.
const KEY_STEPS: usize = 5;

/// Whether `map`'s figure has a key: it has unknown cells, its cells are shaded by
/// weight, or they are drawn as a picture.
fn has_key(map: &MapView<'_>) -> bool {
    map.has_unknown() || shaded(map.grid).is_some() || map.grid.len() > VECTOR_MAX_CELLS
}

/// The key of `map` drawn with `cells`: what its colours mean beyond white (free) and dark
/// (blocked).
fn key_items(map: &MapView<'_>, cells: &Cells) -> Vec<KeyItem> {
    let mut items = Vec::new();
    if map.has_unknown() {
        items.push(KeyItem::Swatch(OBSTACLE, "blocked"));
        items.push(KeyItem::Swatch(UNKNOWN, "unknown"));
    }
    if let Some((low, high)) = shaded(map.grid) {
        items.push(KeyItem::Scale(low, high));
    }
    if let Cells::Raster(_) = cells {
        items.push(KeyItem::Pixel(cells.block()));
    }
    items
}

/// The text of a key item (a scale's text before and after its steps).
fn key_texts(item: &KeyItem) -> (String, String) {
    match *item {
        KeyItem::Swatch(_, label) => (String::new(), label.to_owned()),
        KeyItem::Scale(low, high) => (format!("cell weight {low}"), high.to_string()),
        KeyItem::Pixel(1) => (String::new(), "1 pixel = 1 cell".to_owned()),
        KeyItem::Pixel(k) => (
            String::new(),
            format!("1 pixel = {k} x {k} cells (their mean colour)"),
        ),
    }
}

/// The width of the key's line.
fn key_width(items: &[KeyItem]) -> f64 {
    items
        .iter()
        .map(|item| {
            let (before, after) = key_texts(item);
            let marks = match item {
                KeyItem::Swatch(..) => KEY_SWATCH + 4.0,
                KeyItem::Scale(..) => KEY_STEPS as f64 * KEY_SWATCH + 8.0,
                KeyItem::Pixel(_) => 0.0,
            };
            text_width(&before, NOTE_FS) + marks + text_width(&after, NOTE_FS) + 16.0
        })
        .sum()
}

/// The key's line from `x` on the text line `y`, in a group of class `key`.
fn key_group(items: &[KeyItem], x: f64, y: f64) -> Group {
    let mut g = Group::new().set("class", "key");
    let mut x = x;
    let square = |x: f64, fill: String| {
        Rectangle::new()
            .set("x", num(x))
            .set("y", num(y - 10.0))
            .set("width", num(KEY_SWATCH))
            .set("height", num(KEY_SWATCH))
            .set("fill", fill)
            .set("stroke", "#888888")
            .set("stroke-width", 0.5)
    };
    for item in items {
        let (before, after) = key_texts(item);
        if !before.is_empty() {
            g.append(text(x, y, before.clone(), NOTE_FS).set("fill", INK));
            x += text_width(&before, NOTE_FS) + 4.0;
        }
        match *item {
            KeyItem::Swatch(fill, _) => {
                g.append(square(x, fill.to_owned()));
                x += KEY_SWATCH + 4.0;
            }
            KeyItem::Scale(..) => {
                for step in 0..KEY_STEPS {
                    let t = step as f64 / (KEY_STEPS - 1) as f64;
                    let [r, gr, b] = blend([255; 3], rgb(COST_FILL), COST_MAX_OPACITY * t);
                    g.append(square(x, format!("#{r:02x}{gr:02x}{b:02x}")));
                    x += KEY_SWATCH;
                }
                x += 4.0;
            }
            KeyItem::Pixel(_) => {}
        }
        g.append(text(x, y, after.clone(), NOTE_FS).set("fill", INK));
        x += text_width(&after, NOTE_FS) + 16.0;
    }
    g
}

/// A panel's line about the layer's expanded cells (drawn when some layer has them).
fn expanded_line(layer: &Layer<'_>) -> String {
    if layer.expanded.is_empty() {
        "expanded cells: not recorded".to_owned()
    } else {
        let distinct = n_distinct(layer.expanded);
        let n = layer.expanded.len();
        if distinct == n {
            format!("expanded: {n} cells")
        } else {
            format!("expanded: {n} ({distinct} distinct cells)")
        }
    }
}

/// A layer's note, with its path's cost on a weighted grid (the sum of its moves' costs,
/// [`Grid::path_cost`], as the runner records it) unless the note gives one (`cost=`).
fn note_with_cost(grid: &Grid, layer: &Layer<'_>) -> String {
    match path_cost(grid, layer.path) {
        Some(cost) if !layer.note.contains("cost=") => {
            let space = if layer.note.is_empty() { "" } else { " " };
            format!("{}{space}cost={cost:.2}", layer.note)
        }
        _ => layer.note.clone(),
    }
}

/// The cost of `path` on a weighted grid: `None` on an unweighted one, for no or an empty
/// path, or one that leaves the grid.
fn path_cost(grid: &Grid, path: Option<&Path>) -> Option<f64> {
    let cells = path?.cells();
    if !grid.is_weighted() || cells.is_empty() || !cells.iter().all(|&c| grid.contains(c)) {
        return None;
    }
    let cost = grid.path_cost(cells);
    Some(if cost == planner_api::Cost::MAX {
        // Saturated: the sum in floating point, as the runner's record has it.
        grid.path_cost_f64(cells)
    } else {
        cost.to_f64()
    })
}

/// Panels: one map per layer, arranged in the grid of panels giving the largest cells.
pub(crate) fn panels(
    map: &MapView<'_>,
    start: Cell,
    goal: Cell,
    layers: &[Layer<'_>],
    title: &str,
    style: &Style,
) -> String {
    let grid = map.grid;
    let n = layers.len().max(1);
    let (w, h) = (f64::from(grid.width()), f64::from(grid.height()));
    let key_h = if has_key(map) { KEY_H } else { 0.0 };
    let with_expanded = layers.iter().any(|l| !l.expanded.is_empty());
    let notes: Vec<String> = layers.iter().map(|l| note_with_cost(grid, l)).collect();
    let expanded_lines: Vec<String> = layers.iter().map(expanded_line).collect();
    // A note's words are never cut: a column is at least as wide as the widest word of a
    // note (or of the expanded-cells line after its swatch).
    let word_w = notes
        .iter()
        .map(|note| widest_word(note, NOTE_FS))
        .chain(
            expanded_lines
                .iter()
                .filter(|_| with_expanded)
                .map(|line| widest_word(line, NOTE_FS) + 22.0),
        )
        .fold(0.0, f64::max);
    let title_w = (text_width(title, TITLE_FS) * 1.08 + 2.0 * MARGIN).min(max_px(style));
    // The layout for `extra` note lines beyond one a panel (and one expanded-cells line):
    // the cell size shrinks to keep `max_px` with them; repeated until every panel's
    // wrapped lines fit the lines it was laid out for (more lines only shrink cells and
    // the room beside them, so the count only grows, at most to the number of words).
    let mut extra = 0usize;
    let (cell, cols, foot_h, pitch, width, height, x0, cells, key, wrapped) = loop {
        let foot_h = if layers.is_empty() {
            0.0
        } else {
            (2 + usize::from(with_expanded) + extra) as f64 * LINE_H + 6.0
        };
        let chrome = |cols: usize, rows: usize| {
            (
                2.0 * MARGIN + (cols - 1) as f64 * GAP,
                2.0 * MARGIN + TITLE_H + rows as f64 * foot_h + (rows - 1) as f64 * GAP + key_h,
            )
        };
        // Side by side (as in the paper) as long as cells stay comfortably large, else the
        // arrangement with the largest cells; ties go to more columns.
        let options: Vec<(f64, usize)> = (1..=n)
            .map(|cols| {
                let rows = n.div_ceil(cols);
                let (ew, eh) = chrome(cols, rows);
                (
                    fit_cell(style, cols as f64 * w, rows as f64 * h, ew, eh),
                    cols,
                )
            })
            .collect();
        let largest = options.iter().map(|o| o.0).fold(0.0, f64::max);
        let enough = largest.min(COMFORTABLE_CELL_PX);
        let (cell, cols) = options
            .iter()
            .rev()
            .find(|o| o.0 >= enough)
            .copied()
            .unwrap_or((largest, 1));
        let rows = n.div_ceil(cols);
        let (ew, eh) = chrome(cols, rows);
        let (pw, ph) = (w * cell, h * cell);
        // The distance from one column to the next, less the gap: the panel, or the
        // widest word of a note when that is wider (the note's room is the gap too).
        let pitch = pw.max(word_w - GAP + 4.0);
        let content_w = ew + (cols - 1) as f64 * pitch + pw.max(word_w);
        let cells = Cells::new(map, cell);
        let key = key_items(map, &cells);
        let key_w = (key_width(&key) + 2.0 * MARGIN).min(max_px(style));
        let width = content_w.max(title_w).max(key_w).ceil();
        let height = eh + rows as f64 * ph;
        let x0 = MARGIN + (width - content_w) / 2.0;
        // Each layer's note and expanded-cells line, wrapped in the room beside its panel.
        let wrapped: Vec<(Vec<String>, Vec<String>)> = (0..layers.len())
            .map(|k| {
                let col = k % cols;
                let room = if col + 1 < cols {
                    pitch + GAP - 4.0
                } else {
                    width - (x0 + col as f64 * (pitch + GAP)) - MARGIN / 2.0
                };
                let note = wrap(&notes[k], NOTE_FS, room, room);
                let expanded = match with_expanded {
                    true => wrap(&expanded_lines[k], NOTE_FS, room - 22.0, room - 22.0),
                    false => Vec::new(),
                };
                (note, expanded)
            })
            .collect();
        let needed = wrapped
            .iter()
            .map(|(note, expanded)| note.len() + expanded.len())
            .max()
            .unwrap_or(0)
            .saturating_sub(1 + usize::from(with_expanded));
        if needed <= extra {
            break (
                cell, cols, foot_h, pitch, width, height, x0, cells, key, wrapped,
            );
        }
        extra = needed;
    };
    let ph = h * cell;

    let mut doc = document(width, height);
    doc.append(title_text(title, width));
    let labels = labels_on(style, cell);
    let mode = arrow_mode(style, cell, MAX_SPARSE_ARROWS);
    let lw = line_width(cell);
    for k in 0..n {
        let (col, row) = ((k % cols) as f64, (k / cols) as f64);
        let f = Frame {
            ox: x0 + col * (pitch + GAP),
            oy: MARGIN + TITLE_H + row * (ph + foot_h + GAP),
            cell,
        };
        let mut panel = Group::new().set("class", "panel");
        panel.append(map_group(map, f, &cells));
        if let Some(layer) = layers.get(k) {
            let colour = &colour(k);
            if !layer.expanded.is_empty() {
                panel.append(expanded_group(map, f, &cells, layer.expanded, colour));
            }
            panel.append(layer_group(
                grid,
                f,
                layer.path,
                colour,
                lw,
                labels,
                mode,
                &[start, goal],
            ));
            panel.append(marker_group(grid, f, layer.markers, labels, colour));
            panel.append(endpoints(grid, f, start, goal, ("S", "G")));
            // Legend: swatch and label, then the note; may use the gap beside the panel.
            let room = if col as usize + 1 < cols {
                pitch + GAP - 4.0
            } else {
                width - f.ox - MARGIN / 2.0
            };
            let y1 = f.oy + ph + LINE_H;
            panel.append(swatch(f.ox, y1, colour, lw));
            panel.append(
                text(
                    f.ox + 22.0,
                    y1,
                    fit_text(layer.label, LABEL_FS * 1.08, room - 22.0),
                    LABEL_FS,
                )
                .set("font-weight", "bold")
                .set("fill", INK)
                .set("class", "label"),
            );
            // One entry per layer: `layers.get(k)` found one.
            let (note, expanded) = wrapped
                .get(k)
                .map_or((&[][..], &[][..]), |(n, e)| (&n[..], &e[..]));
            panel.append(
                lines_text(f.ox, f.ox, y1 + LINE_H, note, NOTE_FS)
                    .set("fill", "#444444")
                    .set("class", "note"),
            );
            if with_expanded {
                let y3 = y1 + (1 + note.len()) as f64 * LINE_H;
                // On a shaded grid expanded cells are an outline, and so is their swatch.
                let fill = match shaded(grid) {
                    Some(_) => "none",
                    None => colour.as_str(),
                };
                panel.append(
                    Rectangle::new()
                        .set("x", num(f.ox + 3.0))
                        .set("y", num(y3 - 10.0))
                        .set("width", 11)
                        .set("height", 11)
                        .set("fill", fill)
                        .set("fill-opacity", EXPANDED_OPACITY)
                        .set("stroke", colour.as_str()),
                );
                panel.append(
                    lines_text(f.ox + 22.0, f.ox + 22.0, y3, expanded, NOTE_FS)
                        .set("fill", "#444444")
                        .set("class", "expanded-note"),
                );
            }
        } else {
            panel.append(endpoints(grid, f, start, goal, ("S", "G")));
        }
        doc.append(panel);
    }
    if !key.is_empty() {
        doc.append(key_group(&key, MARGIN, height - MARGIN - 4.0));
    }
    finish(doc)
}

/// Overlay: every layer on one map, earlier layers wider underneath, with a legend.
pub(crate) fn overlay(
    map: &MapView<'_>,
    start: Cell,
    goal: Cell,
    layers: &[Layer<'_>],
    title: &str,
    style: &Style,
) -> String {
    let grid = map.grid;
    let n = layers.len();
    let (w, h) = (f64::from(grid.width()), f64::from(grid.height()));
    let key_h = if has_key(map) { KEY_H } else { 0.0 };
    let notes: Vec<String> = layers.iter().map(|l| note_with_cost(grid, l)).collect();
    // A note's words are never cut: the legend is at least as wide as a note's widest
    // word after the swatch.
    let word_w = notes
        .iter()
        .map(|note| widest_word(note, NOTE_FS))
        .fold(0.0, f64::max);
    // The layout for `extra` legend lines beyond one a layer, repeated until the wrapped
    // notes fit them (as in `panels`).
    let mut extra = 0usize;
    let (cell, width, height, cells, key, wrapped) = loop {
        let legend_h = (n + extra) as f64 * LINE_H + 6.0;
        let cell = fit_cell(
            style,
            w,
            h,
            2.0 * MARGIN,
            2.0 * MARGIN + TITLE_H + legend_h + key_h,
        );
        let map_w = w * cell;
        let cells = Cells::new(map, cell);
        let key = key_items(map, &cells);
        let legend_w = layers
            .iter()
            .zip(&notes)
            .map(|(l, note)| {
                30.0 + text_width(l.label, LABEL_FS) * 1.08 + text_width(note, NOTE_FS)
            })
            .fold(text_width(title, TITLE_FS) * 1.08, f64::max)
            .max(key_width(&key));
        let width = (map_w + 2.0 * MARGIN)
            .max((legend_w + 2.0 * MARGIN).min(max_px(style)))
            .max(2.0 * MARGIN + 22.0 + word_w)
            .ceil();
        let height = 2.0 * MARGIN + TITLE_H + h * cell + legend_h + key_h;
        // Each layer's label and note: the note after the label, its further lines under
        // the label.
        let room = width - 2.0 * MARGIN - 22.0;
        let wrapped: Vec<(String, Vec<String>)> = layers
            .iter()
            .zip(&notes)
            .map(|(layer, note)| {
                let label = fit_text(layer.label, LABEL_FS * 1.08, room);
                let first = room - text_width(&label, LABEL_FS) * 1.08 - 8.0;
                let lines = wrap(note, NOTE_FS, first, room);
                (label, lines)
            })
            .collect();
        let needed = wrapped
            .iter()
            .map(|(_, lines)| lines.len() - 1)
            .sum::<usize>();
        if needed <= extra {
            break (cell, width, height, cells, key, wrapped);
        }
        extra = needed;
    };
    let map_w = w * cell;
    let f = Frame {
        ox: MARGIN + (width - 2.0 * MARGIN - map_w) / 2.0,
        oy: MARGIN + TITLE_H,
        cell,
    };
    let mut doc = document(width, height);
    doc.append(title_text(title, width));
    doc.append(map_group(map, f, &cells));
    let labels = style.step_labels == StepLabels::Always;
    let mode = arrow_mode(style, cell, MAX_SPARSE_ARROWS);
    let base = line_width(cell);
    let widths: Vec<f64> = (0..n)
        .map(|i| {
            if n > 1 {
                base * (1.0 + (n - 1 - i) as f64 / (n - 1) as f64)
            } else {
                base
            }
        })
        .collect();
    for (i, layer) in layers.iter().enumerate() {
        let colour = &colour(i);
        doc.append(layer_group(
            grid,
            f,
            layer.path,
            colour,
            widths[i],
            labels,
            mode,
            &[start, goal],
        ));
    }
    for (i, layer) in layers.iter().enumerate() {
        let colour = &colour(i);
        doc.append(marker_group(grid, f, layer.markers, labels, colour));
    }
    doc.append(endpoints(grid, f, start, goal, ("S", "G")));
    let mut legend = Group::new().set("class", "legend");
    let mut y = f.oy + h * cell;
    for (i, (label, lines)) in wrapped.into_iter().enumerate() {
        let colour = &colour(i);
        y += LINE_H;
        legend.append(swatch(MARGIN, y, colour, widths[i]));
        let note_x = MARGIN + 22.0 + text_width(&label, LABEL_FS) * 1.08 + 8.0;
        let mut line = text(MARGIN + 22.0, y, String::new(), LABEL_FS).set("fill", INK);
        line.append(
            TSpan::new(label)
                .set("font-weight", "bold")
                .set("class", "label"),
        );
        let mut note = match lines.as_slice() {
            [only] => TSpan::new(only.clone()).set("dx", 8),
            _ => {
                let mut note = TSpan::new(String::new());
                for (k, text) in lines.iter().enumerate() {
                    let (lx, ly) = match k {
                        0 => (note_x, y),
                        _ => (MARGIN + 22.0, y + k as f64 * LINE_H),
                    };
                    note.append(Inline(
                        TSpan::new(text.clone()).set("x", num(lx)).set("y", num(ly)),
                    ));
                }
                note
            }
        };
        note = note
            .set("font-size", num(NOTE_FS))
            .set("fill", "#444444")
            .set("class", "note");
        line.append(note);
        y += (lines.len() - 1) as f64 * LINE_H;
        legend.append(line);
    }
    doc.append(legend);
    if !key.is_empty() {
        doc.append(key_group(&key, MARGIN, height - MARGIN - 4.0));
    }
    finish(doc)
}

/// A path coloured by time with markers.
pub(crate) fn timeline(
    map: &MapView<'_>,
    path: &Path,
    markers: &[Marker],
    title: &str,
    style: &Style,
) -> String {
    let grid = map.grid;
    let (w, h) = (f64::from(grid.width()), f64::from(grid.height()));
    let key_h = if has_key(map) { KEY_H } else { 0.0 };
    let legend_h = 2.0 * LINE_H + 10.0;
    let cell = fit_cell(
        style,
        w,
        h,
        2.0 * MARGIN,
        2.0 * MARGIN + TITLE_H + legend_h + key_h,
    );
    let map_w = w * cell;
    let cells = Cells::new(map, cell);
    let key = key_items(map, &cells);
    let n_shown = markers.iter().filter(|m| grid.contains(m.cell)).count();
    let summary = format!(
        "{} marked cell{}; S start, E end{}",
        n_shown,
        if n_shown == 1 { "" } else { "s" },
        path_cost(grid, Some(path))
            .map(|cost| format!("; cost={cost:.2}"))
            .unwrap_or_default()
    );
    // The legend's numbers are never cut: the figure is at least as wide as its line.
    let width = (map_w + 2.0 * MARGIN)
        .max(
            (text_width(title, TITLE_FS) * 1.08 + 2.0 * MARGIN)
                .max(key_width(&key) + 2.0 * MARGIN)
                .min(max_px(style)),
        )
        .max(320.0)
        .max(text_width(&summary, NOTE_FS) + 2.0 * MARGIN)
        .ceil();
    let height = 2.0 * MARGIN + TITLE_H + h * cell + legend_h + key_h;
    let f = Frame {
        ox: MARGIN + (width - 2.0 * MARGIN - map_w) / 2.0,
        oy: MARGIN + TITLE_H,
        cell,
    };
    let mut doc = document(width, height);
    doc.append(title_text(title, width));
    doc.append(map_group(map, f, &cells));

    let cells = cells_in(grid, Some(path));
    let last = path.len().saturating_sub(1).max(1) as f64;
    let colour_at = |i: usize| ramp(i as f64 / last);
    let labels = labels_on(style, cell);
    let lw = line_width(cell);
    let mut g = Group::new().set("class", "layer");
    // A thin dark casing under the coloured line keeps the light end of the ramp visible;
    // on small cells the lines of a coverage path touch, and a casing would only darken.
    if cell >= GRID_LINES_MIN_PX {
        if let Some(casing) = polyline(f, &vertices(&cells), "#555555", lw + 1.5) {
            g.append(casing.set("class", "casing"));
        }
    }
    // The moves in TIMELINE_CHUNKS runs of equal length, each in the colour of its middle.
    let n_moves = cells.len().saturating_sub(1);
    let chunks = n_moves.min(TIMELINE_CHUNKS);
    for k in 0..chunks {
        let (a, b) = (k * n_moves / chunks, (k + 1) * n_moves / chunks);
        let mid = (cells[a].0 + cells[b].0) / 2;
        if let Some(line) = polyline(f, &vertices(&cells[a..=b]), &colour_at(mid), lw) {
            g.append(line.set("class", "path"));
        }
    }
    let mode = arrow_mode(style, cell, MAX_TIMELINE_ARROWS);
    // Dark edges: the arrows sit on a line of their own colour.
    g.append(arrows(
        f,
        &cells,
        mode,
        arrow_len(cell, mode, lw),
        &colour_at,
        INK,
    ));
    if labels {
        let ends: Vec<Cell> = [path.start(), path.goal()].into_iter().flatten().collect();
        g.append(step_labels(f, &cells, &ends, &colour_at));
    }
    doc.append(g);

    // Markers: vermillion (a colour viridis lacks).
    doc.append(marker_group(grid, f, markers, labels, PALETTE[1]));
    if let (Some(s), Some(e)) = (path.start(), path.goal()) {
        doc.append(endpoints(grid, f, s, e, ("S", "E")));
    }

    // Legend: the colour ramp with its first and last step, then the marker count.
    let mut legend = Group::new().set("class", "legend");
    let y = f.oy + h * cell + LINE_H;
    let bar_w = 160.0;
    let x = MARGIN + text_width("step 0", NOTE_FS) + 6.0;
    legend.append(text(MARGIN, y, "step 0".to_owned(), NOTE_FS).set("fill", INK));
    let steps = 32;
    for k in 0..steps {
        legend.append(
            Rectangle::new()
                .set("x", num(x + bar_w * k as f64 / steps as f64))
                .set("y", num(y - 10.0))
                .set("width", num(bar_w / steps as f64 + 0.3))
                .set("height", 10)
                .set("fill", ramp(k as f64 / (steps - 1) as f64)),
        );
    }
    legend.append(
        text(
            x + bar_w + 6.0,
            y,
            format!("step {}", path.len().saturating_sub(1)),
            NOTE_FS,
        )
        .set("fill", INK),
    );
    legend.append(text(MARGIN, y + LINE_H, summary, NOTE_FS).set("fill", INK));
    doc.append(legend);
    if !key.is_empty() {
        doc.append(key_group(&key, MARGIN, height - MARGIN - 4.0));
    }
    finish(doc)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weighted_cells_are_shaded_by_weight() {
        let grid = Grid::from_ascii("...\n.#.").unwrap();
        let grid = grid
            .with_weights(vec![1, 3, 3, 5, 9, 1], planner_api::CostRule::Mean)
            .unwrap();
        let f = Frame {
            ox: 0.0,
            oy: 0.0,
            cell: 10.0,
        };
        let svg = cost_group(&grid, f).unwrap().to_string();
        // Weights span 1 to 9 (the blocked cell's 9 counts). Row 0: weight 1 not drawn,
        // one run of two 3s (opacity 0.6 * 2 / 8 = 0.15); row 1: the 5 (0.6 * 4 / 8 = 0.3);
        // the blocked 9 and the 1 not drawn.
        let rects: Vec<&str> = svg.split("<rect").skip(1).collect();
        assert_eq!(rects.len(), 2, "{svg}");
        for (rect, attributes) in rects.iter().zip([
            ["fill-opacity=\"0.15\"", "width=\"2\"", "x=\"1\"", "y=\"0\""],
            ["fill-opacity=\"0.3\"", "width=\"1\"", "x=\"0\"", "y=\"1\""],
        ]) {
            for attribute in attributes {
                assert!(rect.contains(attribute), "{attribute} in {rect}");
            }
        }
        assert!(cost_group(&Grid::new(2, 2).unwrap(), f).is_none());
    }

    #[test]
    fn numbers_are_short_and_stable() {
        for (x, s) in [
            (0.0, "0"),
            (-0.001, "0"),
            (1.5, "1.5"),
            (2.0, "2"),
            (1.0 / 3.0, "0.33"),
            (12.345, "12.35"),
            (-7.1, "-7.1"),
        ] {
            assert_eq!(num(x), s, "{x}");
        }
    }

    #[test]
    fn text_is_cleaned_and_cut() {
        assert_eq!(clean("a\u{0}b\tc\u{FFFF}"), "a b c ");
        // 12 px * 0.62 = 7.44 px per char: 40 px hold 5 chars, so 4 and an ellipsis.
        assert_eq!(fit_text("abcdefghij", 12.0, 40.0), "abcd…");
        assert_eq!(fit_text("abc", 12.0, 40.0), "abc");
    }

    #[test]
    fn straight_runs_collapse() {
        let cells: Vec<(usize, Cell)> = [(0, 0), (1, 0), (2, 0), (2, 0), (2, 1), (3, 2), (4, 3)]
            .iter()
            .enumerate()
            .map(|(i, &(x, y))| (i, Cell::new(x, y)))
            .collect();
        let v: Vec<(u32, u32)> = vertices(&cells).iter().map(|c| (c.x, c.y)).collect();
        // Corners at (2,0) and (2,1); the diagonal (2,1)-(3,2)-(4,3) is one segment.
        assert_eq!(v, [(0, 0), (2, 0), (2, 1), (4, 3)]);
    }

    #[test]
    fn cell_fits_max_px() {
        let style = Style::default();
        // 6 cells: 48 px wins. 512 cells: (1200 - 24) / 512 = 2.296 -> 2.29.
        assert_eq!(fit_cell(&style, 6.0, 6.0, 24.0, 24.0), 48.0);
        assert_eq!(fit_cell(&style, 512.0, 512.0, 24.0, 24.0), 2.29);
        // 64 cells: 1176 / 64 = 18.375 -> 18.
        assert_eq!(fit_cell(&style, 64.0, 64.0, 24.0, 24.0), 18.0);
        let tiny = Style {
            max_px: 10.0,
            ..Style::default()
        };
        assert_eq!(fit_cell(&tiny, 6.0, 6.0, 24.0, 24.0), 0.01);
    }
}
