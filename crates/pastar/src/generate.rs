//! The maps of seed 002's section 4 (PA-star), generated (`cargo xtask gen-pastar-maps`
//! writes them to `maps/pastar/`).
//!
//! The paper's maps were lost with its figures, so these are maps *in the shape* of
//! section 4.1 and Table 2, made by a fixed recipe (the rectangles of the 140 x 120 maps
//! are listed below) and a seeded generator (`rand_chacha::ChaCha8Rng`, seed per map), so
//! that the same command always writes the same bytes (tested). Coordinates: `x` is the
//! column, `y` the row, `(0, 0)` the top-left cell. "140 units in length and 120 in
//! width" is read as 140 columns and 120 rows: the start `(20, 10)` and goal `(70, 110)`
//! then lie 10 rows from the top and from the bottom edge, the symmetric setting.
//!
//! | file | size | problems | obstacles |
//! |---|---|---|---|
//! | `open-140x120.map` | 140 x 120 | (20,10) -> (70,110) | none (4.3.1, Table 6) |
//! | `two-140x120.map` | 140 x 120 | (20,10) -> (70,110) | two rectangles on the line, 15 rows apart (4.3.2, Table 7) |
//! | `several-140x120.map` | 140 x 120 | (20,10) -> (70,110) | five seeded rectangles on the line and eight off it (4.3.3, Table 8) |
//! | `random200-1.map`, `random200-2.map` | 200 x 200 | (25,35) -> (140,190) | 70 seeded rectangles of 3-16 cells (4.3.5, Table 10 scenarios 1 and 2) |
//! | `scenario500.map` | 500 x 500 | (50,250) -> (400,200); (50,425) -> (400,225) | 45 seeded rectangles of 15-70 cells and 15 discs of radius 8-30 (4.3.4, Table 9) |
//!
//! Every start and goal keeps a free disc of radius 3 around it, and a map is accepted
//! only if each of its goals is 4-connected to its start (else the next seed is tried; the
//! seeds that were taken are the ones in [`specs`]).

use planner_api::{Cell, Grid};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// One generated map.
#[derive(Debug, Clone)]
pub struct GeneratedMap {
    /// File name under `maps/pastar/`.
    pub name: &'static str,
    /// The grid.
    pub grid: Grid,
    /// The start-goal pairs the configs use with it.
    pub pairs: Vec<(Cell, Cell)>,
}

/// The 140 x 120 start and goal (section 4.1.1, Test 1).
pub const SMALL_PAIR: (Cell, Cell) = (Cell::new(20, 10), Cell::new(70, 110));
/// The 200 x 200 start and goal (Table 2).
pub const RANDOM_PAIR: (Cell, Cell) = (Cell::new(25, 35), Cell::new(140, 190));
/// The 500 x 500 scenarios' starts and goals (Table 2).
pub const LARGE_PAIRS: [(Cell, Cell); 2] = [
    (Cell::new(50, 250), Cell::new(400, 200)),
    (Cell::new(50, 425), Cell::new(400, 225)),
];

/// Blocks the cells of the rectangle with corners `(x0, y0)` and `(x1, y1)` (inclusive),
/// clipped to the grid.
fn rect(grid: &mut Grid, x0: i64, y0: i64, x1: i64, y1: i64) {
    for y in y0.max(0)..=y1.min(i64::from(grid.height()) - 1) {
        for x in x0.max(0)..=x1.min(i64::from(grid.width()) - 1) {
            grid.set_free(Cell::new(x as u32, y as u32), false);
        }
    }
}

/// Blocks the cells whose centres lie within `r` of `(cx, cy)`.
fn disc(grid: &mut Grid, cx: i64, cy: i64, r: i64) {
    for y in (cy - r).max(0)..=(cy + r).min(i64::from(grid.height()) - 1) {
        for x in (cx - r).max(0)..=(cx + r).min(i64::from(grid.width()) - 1) {
            if (x - cx).pow(2) + (y - cy).pow(2) <= r * r {
                grid.set_free(Cell::new(x as u32, y as u32), false);
            }
        }
    }
}

/// Frees the cells within 3 of `cell` (start and goal clearance).
fn clear(grid: &mut Grid, cell: Cell) {
    let (cx, cy) = (i64::from(cell.x), i64::from(cell.y));
    for y in (cy - 3).max(0)..=(cy + 3).min(i64::from(grid.height()) - 1) {
        for x in (cx - 3).max(0)..=(cx + 3).min(i64::from(grid.width()) - 1) {
            if (x - cx).pow(2) + (y - cy).pow(2) <= 9 {
                grid.set_free(Cell::new(x as u32, y as u32), true);
            }
        }
    }
}

/// Whether `goal` is 4-connected to `start` through free cells.
fn connected(grid: &Grid, start: Cell, goal: Cell) -> bool {
    let mut seen = vec![false; grid.len()];
    let mut stack = vec![start];
    seen[grid.index(start)] = true;
    while let Some(cell) = stack.pop() {
        if cell == goal {
            return true;
        }
        for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
            if let Some(next) = grid.offset(cell, dx, dy) {
                let i = grid.index(next);
                if grid.is_free(next) && !seen[i] {
                    seen[i] = true;
                    stack.push(next);
                }
            }
        }
    }
    false
}

/// A point on the line from `a` to `b` at parameter `t`, rounded to a cell.
fn on_line((a, b): (Cell, Cell), t: f64) -> (i64, i64) {
    let x = f64::from(a.x) + t * (f64::from(b.x) - f64::from(a.x));
    let y = f64::from(a.y) + t * (f64::from(b.y) - f64::from(a.y));
    (x.round() as i64, y.round() as i64)
}

fn empty(width: u32, height: u32) -> Grid {
    match Grid::new(width, height) {
        Ok(grid) => grid,
        Err(e) => unreachable!("fixed sizes are valid: {e}"),
    }
}

/// Draws obstacles with `draw(rng, grid)` from `seed` upwards until every pair is
/// connected; returns the grid.
fn seeded(
    width: u32,
    height: u32,
    seed: u64,
    pairs: &[(Cell, Cell)],
    draw: impl Fn(&mut ChaCha8Rng, &mut Grid),
) -> Grid {
    for attempt in 0.. {
        let mut rng = ChaCha8Rng::seed_from_u64(seed + attempt);
        let mut grid = empty(width, height);
        draw(&mut rng, &mut grid);
        for &(s, g) in pairs {
            clear(&mut grid, s);
            clear(&mut grid, g);
        }
        if pairs.iter().all(|&(s, g)| connected(&grid, s, g)) {
            return grid;
        }
    }
    unreachable!("the attempts never end")
}

/// The maps, in the order of the table in the module docs.
pub fn specs() -> Vec<GeneratedMap> {
    let mut maps = Vec::new();
    maps.push(GeneratedMap {
        name: "open-140x120.map",
        grid: empty(140, 120),
        pairs: vec![SMALL_PAIR],
    });

    // Two obstacles on the line, close enough that equation 9 decides whether their
    // local searches merge: 7 x 7 blocks centred at (40, 50) and (49, 69). With r = 4 their
    // handover cells are 12.53 apart, so R_threshold 12 keeps two local searches and 13
    // merges them: the step of the paper's Fig. 13.
    let mut two = empty(140, 120);
    rect(&mut two, 37, 47, 43, 53);
    rect(&mut two, 46, 66, 52, 72);
    maps.push(GeneratedMap {
        name: "two-140x120.map",
        grid: two,
        pairs: vec![SMALL_PAIR],
    });

    // Several obstacles: five rectangles centred on the line at t = 0.15 .. 0.85 with
    // seeded sizes and offsets, and eight seeded rectangles anywhere.
    let several = seeded(140, 120, 3, &[SMALL_PAIR], |rng, grid| {
        for k in 0..5 {
            let t = 0.15 + 0.175 * f64::from(k);
            let (cx, cy) = on_line(SMALL_PAIR, t);
            let (cx, cy) = (cx + rng.gen_range(-3..=3), cy + rng.gen_range(-2..=2));
            let (hw, hh) = (rng.gen_range(2..=4), rng.gen_range(2..=4));
            rect(grid, cx - hw, cy - hh, cx + hw, cy + hh);
        }
        for _ in 0..8 {
            let (x, y) = (rng.gen_range(0..140), rng.gen_range(0..120));
            let (w, h) = (rng.gen_range(3..=14), rng.gen_range(3..=14));
            rect(grid, x, y, x + w - 1, y + h - 1);
        }
    });
    maps.push(GeneratedMap {
        name: "several-140x120.map",
        grid: several,
        pairs: vec![SMALL_PAIR],
    });

    for (name, seed) in [("random200-1.map", 200), ("random200-2.map", 300)] {
        let grid = seeded(200, 200, seed, &[RANDOM_PAIR], |rng, grid| {
            for _ in 0..70 {
                let (x, y) = (rng.gen_range(0..200), rng.gen_range(0..200));
                let (w, h) = (rng.gen_range(3..=16), rng.gen_range(3..=16));
                rect(grid, x, y, x + w - 1, y + h - 1);
            }
        });
        maps.push(GeneratedMap {
            name,
            grid,
            pairs: vec![RANDOM_PAIR],
        });
    }

    let large = seeded(500, 500, 500, &LARGE_PAIRS, |rng, grid| {
        for _ in 0..45 {
            let (x, y) = (rng.gen_range(0..500), rng.gen_range(0..500));
            let (w, h) = (rng.gen_range(15..=70), rng.gen_range(15..=70));
            rect(grid, x, y, x + w - 1, y + h - 1);
        }
        for _ in 0..15 {
            let (x, y) = (rng.gen_range(0..500), rng.gen_range(0..500));
            disc(grid, x, y, rng.gen_range(8..=30));
        }
    });
    maps.push(GeneratedMap {
        name: "scenario500.map",
        grid: large,
        pairs: LARGE_PAIRS.to_vec(),
    });
    maps
}
