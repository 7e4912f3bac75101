//! GIF animations of one search (`gridplan plan --gif FILE`): the map, the expanded cells
//! appearing in expansion order, then the path, looping.
//!
//! A map of at most [`MAX_SIDE`] (512) cells a side is drawn cell by cell: each cell is a
//! square of `scale` pixels, `scale` = 512 / the map's longer side, between 1 and 8.
//!
//! A larger map is downsampled, so that the time and memory an animation takes are bounded
//! whatever the size of the map (a 4096 x 4096 map took 35 s and 214 MB drawn cell by
//! cell): a pixel is a square block of `k` x `k` cells, `k` = ceil(longer side / 512), so
//! the picture is at most 512 pixels a side (ceil(width / k) x ceil(height / k)). A
//! pixel's colour is, in this order of precedence: goal, then start, when the block holds
//! the goal or the start; path (in the last frame) when the path passes one of its cells;
//! expanded when any of its cells was expanded so far; otherwise the share of its cells
//! that are blocked (a block on the right or bottom edge may hold fewer than `k` x `k`):
//! free (white) when none is, blocked (dark) when all are, and in between one of
//! [`GREY_LEVELS`] greys, darker as the share grows (the share rounded up to the next
//! fifteenth, so one blocked cell of a block is never drawn free). A ROS `map_server` map's
//! unknown cells ([`Search::unknown`]) are drawn in their own blue-grey, whether the grid
//! makes them blocked or free, as the SVG figures draw them apart from walls: a block whose
//! cells are all unknown is that colour, and another block's share is of its known cells
//! (so unknown cells neither darken nor lighten it). A wall one cell thick
//! thus shows as a faint grey line, as the SVG figure's thin walls do, rather than
//! vanishing (a block drawn blocked only when most of its cells were dropped a one-cell
//! wall across a 5000 x 5000 map from every frame). The map's blocks are
//! counted once, in one pass over the cells; each frame then applies its expanded cells,
//! and the last frame the path, to the blocks, so a frame costs the pixels of the picture
//! and not the cells of the map. Pixels stand for the same colours as the cell-by-cell
//! drawing, which is the `k` = 1 case (a map of up to 512 cells a side is drawn exactly as
//! before blocks were introduced).
//!
//! The expansions are shown in at most [`MAX_FRAMES`] frames (the k-th frame shows
//! the first `k * n / frames` expanded cells), then one frame with the path held for two
//! seconds. When the file would be larger than the size limit (5 MB for `plan --gif`), the
//! frame count is halved until it fits; a map whose two frames do not fit is an error.

use std::borrow::Cow;

use planner_api::{Cell, Grid};

/// The most frames of expansions.
pub const MAX_FRAMES: usize = 64;

/// The longest side of the picture, in blocks of cells: a map over this many cells a side
/// is drawn one pixel per block of `k` x `k` cells, `k` = ceil(longer side / `MAX_SIDE`)
/// (module docs).
pub const MAX_SIDE: u32 = 512;

/// The size limit of `plan --gif` files: 5 MB.
pub const MAX_GIF_BYTES: usize = 5_000_000;

/// Why no animation was written.
#[derive(Debug, thiserror::Error)]
pub enum AnimError {
    /// The encoder failed.
    #[error("GIF encoding: {0}")]
    Encoding(#[from] gif::EncodingError),
    /// The map is larger than a GIF can be (65535 pixels a side).
    #[error("a {width}x{height} map is too large for a GIF")]
    TooLarge {
        /// Map width.
        width: u32,
        /// Map height.
        height: u32,
    },
    /// Even two frames exceed the size limit.
    #[error("even a two-frame animation of this map is over {limit} bytes")]
    OverLimit {
        /// The limit.
        limit: usize,
    },
}

/// Palette indices.
const FREE: u8 = 0;
const BLOCKED: u8 = 1;
const EXPANDED: u8 = 2;
const PATH: u8 = 3;
const START: u8 = 4;
const GOAL: u8 = 5;

/// The first of the greys of blocks partly blocked: index `GREY + level - 1` for levels 1
/// to [`GREY_LEVELS`].
const GREY: u8 = 6;

/// A ROS map's unknown cells (module docs), after the greys.
const UNKNOWN: u8 = GREY + GREY_LEVELS;

/// The grey levels of a block partly blocked (module docs): level `l` stands for a share of
/// blocked cells over `(l - 1) / 15` and at most `l / 15`.
pub const GREY_LEVELS: u8 = 15;

/// The free and blocked tones the greys lie between.
const FREE_RGB: u8 = 255;
const BLOCKED_RGB: u8 = 40;

/// RGB of the palette (32 entries: six colours, the greys, unknown, then unused).
const PALETTE: [u8; 96] = palette();

const fn palette() -> [u8; 96] {
    let mut rgb = [0u8; 96];
    let named: [u8; 18] = [
        FREE_RGB,
        FREE_RGB,
        FREE_RGB, // free
        BLOCKED_RGB,
        BLOCKED_RGB,
        BLOCKED_RGB, // blocked
        150,
        200,
        255, // expanded
        230,
        80,
        20, // path
        0,
        160,
        60, // start
        200,
        0,
        0, // goal
    ];
    let mut i = 0;
    while i < named.len() {
        rgb[i] = named[i];
        i += 1;
    }
    let mut level = 1;
    while level <= GREY_LEVELS {
        // Evenly between free (level 0) and blocked (level 16): 242 down to 53.
        let tone = FREE_RGB - ((FREE_RGB - BLOCKED_RGB) as u16 * level as u16 / 16) as u8;
        let at = 3 * (GREY + level - 1) as usize;
        rgb[at] = tone;
        rgb[at + 1] = tone;
        rgb[at + 2] = tone;
        level += 1;
    }
    // Unknown: a blue-grey, apart from the greys of partly blocked blocks.
    let at = 3 * UNKNOWN as usize;
    rgb[at] = 160;
    rgb[at + 1] = 180;
    rgb[at + 2] = 200;
    rgb
}

/// The palette index of a block with `blocked` of its `cells` blocked: the free cells'
/// (0), a grey, or the blocked cells' (1) (module docs).
pub fn block_index(blocked: usize, cells: usize) -> u8 {
    if blocked == 0 || cells == 0 {
        FREE
    } else if blocked >= cells {
        BLOCKED
    } else {
        let levels = usize::from(GREY_LEVELS);
        // Rounded up, so that one blocked cell is at least the first grey.
        let level = (blocked * levels).div_ceil(cells).clamp(1, levels);
        GREY + level as u8 - 1
    }
}

/// The RGB colour of palette index `index` (black past the palette).
pub fn palette_rgb(index: u8) -> [u8; 3] {
    let at = 3 * usize::from(index);
    match PALETTE.get(at..at + 3) {
        Some(&[r, g, b]) => [r, g, b],
        _ => [0, 0, 0],
    }
}

/// What to animate.
#[derive(Debug, Clone, Copy)]
pub struct Search<'a> {
    /// The map.
    pub grid: &'a Grid,
    /// Start.
    pub start: Cell,
    /// Goal.
    pub goal: Cell,
    /// Expanded cells in order.
    pub expanded: &'a [Cell],
    /// The path's cells (waypoints; consecutive ones joined by straight segments).
    pub path: &'a [Cell],
    /// One flag per cell, row-major, true where a ROS map does not know the cell (drawn
    /// apart, module docs); `None` for none.
    pub unknown: Option<&'a [bool]>,
}

/// The animation of `search` as GIF bytes, at most `limit` bytes (module docs).
pub fn gif(search: &Search<'_>, limit: usize) -> Result<Vec<u8>, AnimError> {
    let (width, height) = (search.grid.width(), search.grid.height());
    let longer = width.max(height).max(1);
    let k = longer.div_ceil(MAX_SIDE).max(1);
    let blocks = Blocks::new(search.grid, search.unknown, k);
    let scale = (MAX_SIDE / longer).clamp(1, 8);
    if u64::from(blocks.width) * u64::from(scale) > 65_535
        || u64::from(blocks.height) * u64::from(scale) > 65_535
    {
        return Err(AnimError::TooLarge { width, height });
    }
    let mut frames = MAX_FRAMES.min(search.expanded.len().max(1));
    loop {
        let bytes = encode(search, &blocks, scale, frames)?;
        if bytes.len() <= limit {
            return Ok(bytes);
        }
        if frames <= 1 {
            return Err(AnimError::OverLimit { limit });
        }
        frames /= 2;
    }
}

/// The map at `k` x `k` cells a pixel: per pixel, blocked or free (module docs).
struct Blocks {
    /// Cells per pixel side.
    k: u32,
    /// Pixels across and down.
    width: u32,
    height: u32,
    /// Per pixel, its block's share of blocked cells as a palette index
    /// ([`block_index`]).
    base: Vec<u8>,
}

impl Blocks {
    /// `grid` in blocks of `k` x `k` cells, `unknown` (one flag per cell, if given)
    /// marking the cells drawn apart: one pass over its cells.
    fn new(grid: &Grid, unknown: Option<&[bool]>, k: u32) -> Blocks {
        let (w, h) = (grid.width() as usize, grid.height() as usize);
        let ku = k as usize;
        let (width, height) = (grid.width().div_ceil(k), grid.height().div_ceil(k));
        let (pw, ph) = (width as usize, height as usize);
        let mut base = vec![FREE; pw * ph];
        // Known blocked cells and unknown cells of one row of blocks.
        let mut blocked = vec![0usize; pw];
        let mut unknowns = vec![0usize; pw];
        let is_unknown = |i: usize| unknown.is_some_and(|u| u.get(i).copied().unwrap_or(false));
        for (y, row) in grid.free_cells().chunks(w.max(1)).enumerate().take(h) {
            for (x, &free) in row.iter().enumerate() {
                if is_unknown(y * w + x) {
                    unknowns[x / ku] += 1;
                } else {
                    blocked[x / ku] += usize::from(!free);
                }
            }
            if (y + 1) % ku == 0 || y + 1 == h {
                let rows = y % ku + 1;
                let by = y / ku;
                for (bx, (count, unknown)) in blocked.iter_mut().zip(&mut unknowns).enumerate() {
                    let cells = rows * ku.min(w - bx * ku);
                    base[by * pw + bx] = match *unknown >= cells {
                        true => UNKNOWN,
                        false => block_index(*count, cells - *unknown),
                    };
                    (*count, *unknown) = (0, 0);
                }
            }
        }
        Blocks {
            k,
            width,
            height,
            base,
        }
    }

    /// The pixel of `cell` (`None` outside the picture).
    fn pixel(&self, cell: Cell) -> Option<usize> {
        let (x, y) = (cell.x / self.k, cell.y / self.k);
        (x < self.width && y < self.height).then(|| y as usize * self.width as usize + x as usize)
    }
}

/// Encodes `frames` expansion frames and the path frame.
fn encode(
    search: &Search<'_>,
    blocks: &Blocks,
    scale: u32,
    frames: usize,
) -> Result<Vec<u8>, AnimError> {
    let (width, height) = (blocks.width as usize, blocks.height as usize);
    let mut cells = blocks.base.clone();
    let s = scale as usize;
    let (pixel_width, pixel_height) = (width * s, height * s);
    let mut out = Vec::new();
    {
        let mut encoder =
            gif::Encoder::new(&mut out, pixel_width as u16, pixel_height as u16, &PALETTE)?;
        encoder.set_repeat(gif::Repeat::Infinite)?;
        let mut pixels = vec![0u8; pixel_width * pixel_height];
        let mut write = |cells: &[u8], delay: u16| -> Result<(), AnimError> {
            for y in 0..height {
                let row = &cells[y * width..(y + 1) * width];
                let first = y * s * pixel_width;
                for (x, &value) in row.iter().enumerate() {
                    pixels[first + x * s..first + (x + 1) * s].fill(value);
                }
                for k in 1..s {
                    pixels.copy_within(first..first + pixel_width, first + k * pixel_width);
                }
            }
            let frame = gif::Frame {
                width: pixel_width as u16,
                height: pixel_height as u16,
                delay,
                buffer: Cow::Borrowed(&pixels),
                ..gif::Frame::default()
            };
            encoder.write_frame(&frame)?;
            Ok(())
        };
        let set = |cells: &mut [u8], cell: Cell, value: u8| {
            if let Some(i) = blocks.pixel(cell) {
                cells[i] = value;
            }
        };
        let mark_ends = |cells: &mut [u8]| {
            set(cells, search.start, START);
            set(cells, search.goal, GOAL);
        };
        let n = search.expanded.len();
        let mut shown = 0;
        for k in 1..=frames {
            let upto = (k * n).checked_div(frames).unwrap_or(n);
            for &cell in &search.expanded[shown..upto] {
                set(&mut cells, cell, EXPANDED);
            }
            shown = upto;
            mark_ends(&mut cells);
            write(&cells, 6)?;
        }
        for pair in search.path.windows(2) {
            for cell in segment(pair[0], pair[1]) {
                set(&mut cells, cell, PATH);
            }
        }
        if let [only] = search.path {
            set(&mut cells, *only, PATH);
        }
        mark_ends(&mut cells);
        write(&cells, 200)?;
    }
    Ok(out)
}

/// The cells a straight segment between two cell centres passes, sampled every quarter
/// cell (for drawing only).
fn segment(a: Cell, b: Cell) -> Vec<Cell> {
    let (dx, dy) = (
        f64::from(b.x) - f64::from(a.x),
        f64::from(b.y) - f64::from(a.y),
    );
    let steps = ((dx.abs().max(dy.abs())) * 4.0).ceil().max(1.0) as u32;
    (0..=steps)
        .map(|i| {
            let t = f64::from(i) / f64::from(steps);
            Cell::new(
                (f64::from(a.x) + dx * t).round() as u32,
                (f64::from(a.y) + dy * t).round() as u32,
            )
        })
        .collect()
}

/// The animation of a `plan` run (`plan --gif FILE`), at most [`MAX_GIF_BYTES`]; the run
/// needs its expanded cells recorded.
pub fn plan_gif(result: &planner_runner::plan::PlanResult) -> Result<Vec<u8>, AnimError> {
    let r = &result.record;
    let path = r.path.as_ref().map_or(&[][..], |p| p.cells());
    gif(
        &Search {
            grid: &result.grid,
            start: r.start,
            goal: r.goal,
            expanded: &result.expanded,
            path,
            unknown: result.unknown.as_deref(),
        },
        MAX_GIF_BYTES,
    )
}
