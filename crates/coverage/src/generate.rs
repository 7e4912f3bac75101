//! Seeded map generators for coverage experiments and tests.
//!
//! Every generator is a pure function of its parameters and seed: the random numbers come
//! from ChaCha8 (`rand_chacha::ChaCha8Rng::seed_from_u64(seed)`), drawn in the order each
//! function documents, so the maps under `maps/coverage/` regenerate bit for bit
//! (`crates/coverage/tests/maps.rs` checks it).
//!
//! - [`random_blocks`]: rectangles of random size at random places, like the random
//!   obstacles of seed 004's 30 x 30 map (section 3);
//! - [`random_cells`]: every cell blocked independently with a given probability;
//! - [`rooms`]: rooms joined by one-cell corridors;
//! - [`keep_component`]: blocks every free cell the start cannot reach, so that "free" and
//!   "reachable" are the same on a generated map.
//!
//! ```
//! use planner_api::{reachable_cells, Cell};
//! use planner_coverage::generate::{keep_component, random_blocks};
//! let mut grid = random_blocks(30, 30, 10, 5, Cell::new(0, 0), 1).unwrap();
//! keep_component(&mut grid, Cell::new(0, 0));
//! let reachable = reachable_cells(&grid, Cell::new(0, 0));
//! assert_eq!(reachable.iter().filter(|&&r| r).count(), grid.n_free());
//! assert_eq!(grid, random_blocks(30, 30, 10, 5, Cell::new(0, 0), 1).map(|mut g| {
//!     keep_component(&mut g, Cell::new(0, 0));
//!     g
//! }).unwrap());
//! ```

use planner_api::{reachable_cells, Cell, Grid, GridError};
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use thiserror::Error;

/// Parameters no map can be generated from.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum GenerateError {
    /// The grid itself (a zero or too large side).
    #[error("invalid grid: {0}")]
    Grid(#[from] GridError),
    /// A parameter out of its range.
    #[error("parameter `{name}`: {message}")]
    Parameter {
        /// The parameter.
        name: &'static str,
        /// What it must be.
        message: String,
    },
}

fn parameter(name: &'static str, message: impl Into<String>) -> GenerateError {
    GenerateError::Parameter {
        name,
        message: message.into(),
    }
}

/// A `width` x `height` grid with `n_blocks` rectangles blocked.
///
/// For each rectangle in turn the generator draws its width and height, each uniform in
/// `1..=max_side`, then its top-left cell, `x` uniform in `0..width` and `y` in
/// `0..height`; the rectangle is clipped to the grid. Finally `keep` is made free (it must
/// lie inside the grid). Pockets the rectangles cut off stay free: see [`keep_component`].
pub fn random_blocks(
    width: u32,
    height: u32,
    n_blocks: u32,
    max_side: u32,
    keep: Cell,
    seed: u64,
) -> Result<Grid, GenerateError> {
    let mut grid = Grid::new(width, height)?;
    if max_side == 0 {
        return Err(parameter("max_side", "must be at least 1"));
    }
    check_keep(&grid, keep)?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for _ in 0..n_blocks {
        let w = rng.gen_range(1..=max_side);
        let h = rng.gen_range(1..=max_side);
        let x0 = rng.gen_range(0..width);
        let y0 = rng.gen_range(0..height);
        for y in y0..y0.saturating_add(h).min(height) {
            for x in x0..x0.saturating_add(w).min(width) {
                grid.set_free(Cell::new(x, y), false);
            }
        }
    }
    grid.set_free(keep, true);
    Ok(grid)
}

/// A `width` x `height` grid whose cells, in row-major order, are each blocked with
/// probability `density` (one `gen_bool(density)` per cell, `keep`'s draw included), then
/// `keep` made free. `density` must lie in `[0, 1]`.
pub fn random_cells(
    width: u32,
    height: u32,
    density: f64,
    keep: Cell,
    seed: u64,
) -> Result<Grid, GenerateError> {
    let mut grid = Grid::new(width, height)?;
    if !(0.0..=1.0).contains(&density) {
        return Err(parameter(
            "density",
            format!("must lie in [0, 1], got {density}"),
        ));
    }
    check_keep(&grid, keep)?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let free: Vec<bool> = (0..grid.len()).map(|_| !rng.gen_bool(density)).collect();
    grid = Grid::from_free_cells(width, height, free)?;
    grid.set_free(keep, true);
    Ok(grid)
}

/// The shape of a [`rooms`] map: a `cols` x `rows` lattice of square lattice cells of
/// `cell` x `cell` grid cells, one room in each.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rooms {
    /// Lattice columns (at least 1).
    pub cols: u32,
    /// Lattice rows (at least 1).
    pub rows: u32,
    /// Side of a lattice cell in grid cells (at least 4).
    pub cell: u32,
    /// Probability that a lattice edge outside the spanning tree also gets a corridor.
    pub extra: f64,
}

/// A map of rooms and corridors, and its start: the top-left cell of the top-left room.
///
/// The grid is `cols * cell` x `rows * cell`, all blocked at first. Draws, in order:
/// 1. for each lattice cell in row-major order, its room: width and height each uniform in
///    `ceil(cell / 2)..=cell - 1`, then the left and top offsets uniform in
///    `0..=cell - 1 - side`, so the last row and column of every lattice cell stay blocked
///    and rooms never touch;
/// 2. the lattice edges (each cell to its right, then to its lower neighbour, in row-major
///    order) shuffled with `SliceRandom::shuffle`; taken in that order, an edge joining two
///    components (union-find) gets a corridor, which makes a random spanning tree; any
///    other edge gets one when `gen_bool(extra)` says so (drawn only for those edges).
///
/// A corridor is one cell wide and L-shaped between the room centres `(x0 + w / 2,
/// y0 + h / 2)`: along the first room's centre row to the second's centre column, then
/// along that column. It stays inside the two lattice cells. Every room is reachable.
pub fn rooms(spec: Rooms, seed: u64) -> Result<(Grid, Cell), GenerateError> {
    if spec.cols == 0 || spec.rows == 0 {
        return Err(parameter(
            "cols/rows",
            "the lattice needs at least one cell",
        ));
    }
    if spec.cell < 4 {
        return Err(parameter(
            "cell",
            format!("must be at least 4, got {}", spec.cell),
        ));
    }
    if !(0.0..=1.0).contains(&spec.extra) {
        return Err(parameter(
            "extra",
            format!("must lie in [0, 1], got {}", spec.extra),
        ));
    }
    let width = spec
        .cols
        .checked_mul(spec.cell)
        .ok_or(GenerateError::Grid(GridError::TooLarge))?;
    let height = spec
        .rows
        .checked_mul(spec.cell)
        .ok_or(GenerateError::Grid(GridError::TooLarge))?;
    let mut grid = Grid::new(width, height)?;
    for cell in 0..grid.len() {
        let c = grid.cell(cell);
        grid.set_free(c, false);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let n = (spec.cols * spec.rows) as usize;
    let mut centres = Vec::with_capacity(n);
    let mut start = Cell::new(0, 0);
    let min_side = spec.cell.div_ceil(2);
    for j in 0..spec.rows {
        for i in 0..spec.cols {
            let w = rng.gen_range(min_side..=spec.cell - 1);
            let h = rng.gen_range(min_side..=spec.cell - 1);
            let x0 = i * spec.cell + rng.gen_range(0..=spec.cell - 1 - w);
            let y0 = j * spec.cell + rng.gen_range(0..=spec.cell - 1 - h);
            for y in y0..y0 + h {
                for x in x0..x0 + w {
                    grid.set_free(Cell::new(x, y), true);
                }
            }
            if (i, j) == (0, 0) {
                start = Cell::new(x0, y0);
            }
            centres.push(Cell::new(x0 + w / 2, y0 + h / 2));
        }
    }
    let cols = spec.cols as usize;
    let mut edges = Vec::new();
    for k in 0..n {
        if (k % cols) + 1 < cols {
            edges.push((k, k + 1));
        }
        if k + cols < n {
            edges.push((k, k + cols));
        }
    }
    edges.shuffle(&mut rng);
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut k: usize) -> usize {
        while parent[k] != k {
            parent[k] = parent[parent[k]];
            k = parent[k];
        }
        k
    }
    for (a, b) in edges {
        let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
        let carve = if ra != rb {
            parent[ra] = rb;
            true
        } else {
            rng.gen_bool(spec.extra)
        };
        if carve {
            corridor(&mut grid, centres[a], centres[b]);
        }
    }
    Ok((grid, start))
}

/// Frees the L-shaped corridor from `a` along row `a.y` to column `b.x`, then to `b`.
fn corridor(grid: &mut Grid, a: Cell, b: Cell) {
    for x in a.x.min(b.x)..=a.x.max(b.x) {
        grid.set_free(Cell::new(x, a.y), true);
    }
    for y in a.y.min(b.y)..=a.y.max(b.y) {
        grid.set_free(Cell::new(b.x, y), true);
    }
}

/// Blocks every free cell that is not 4-connected to `keep` (nothing stays free when
/// `keep` is blocked or outside the grid).
pub fn keep_component(grid: &mut Grid, keep: Cell) {
    let reachable = reachable_cells(grid, keep);
    for (index, reach) in reachable.into_iter().enumerate() {
        if !reach {
            let cell = grid.cell(index);
            grid.set_free(cell, false);
        }
    }
}

fn check_keep(grid: &Grid, keep: Cell) -> Result<(), GenerateError> {
    if grid.contains(keep) {
        Ok(())
    } else {
        Err(parameter(
            "keep",
            format!(
                "{keep} is outside the {}x{} grid",
                grid.width(),
                grid.height()
            ),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rooms_are_connected_and_start_is_free() {
        for seed in 0..20 {
            let spec = Rooms {
                cols: 3,
                rows: 2,
                cell: 8,
                extra: 0.3,
            };
            let (grid, start) = rooms(spec, seed).unwrap();
            assert_eq!((grid.width(), grid.height()), (24, 16));
            assert!(grid.is_free(start));
            let reach = reachable_cells(&grid, start);
            assert_eq!(reach.iter().filter(|&&r| r).count(), grid.n_free());
        }
    }

    #[test]
    fn parameters_are_checked() {
        let bad = random_cells(4, 4, 1.5, Cell::new(0, 0), 0).unwrap_err();
        assert_eq!(
            bad.to_string(),
            "parameter `density`: must lie in [0, 1], got 1.5"
        );
        assert!(random_blocks(4, 4, 1, 2, Cell::new(4, 0), 0).is_err());
        assert!(random_blocks(0, 4, 1, 2, Cell::new(0, 0), 0).is_err());
        let spec = Rooms {
            cols: 1,
            rows: 1,
            cell: 3,
            extra: 0.0,
        };
        assert!(rooms(spec, 0).is_err());
    }

    #[test]
    fn density_extremes() {
        let full = random_cells(5, 3, 1.0, Cell::new(2, 1), 9).unwrap();
        assert_eq!(full.n_free(), 1);
        let empty = random_cells(5, 3, 0.0, Cell::new(2, 1), 9).unwrap();
        assert_eq!(empty.n_free(), 15);
    }
}
