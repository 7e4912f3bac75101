//! Per-cell masks of the safe moves, built once per grid from a [`MoveSet`]: the hot-loop
//! form of a neighbourhood for searches that keep per-cell arrays.
//!
//! Cells are indexed in a *padded* row-major layout: the grid surrounded by a border of
//! `reach` cells (the longest move's Chebyshev length), so that every neighbour of every
//! cell has an index inside the arrays and per-neighbour flags (visited marks) can be read
//! without a bounds test. Bit `m` of `safe[p]` is set when move `m` of the set (in the set's
//! order) may be taken from cell `p`: the target is in bounds and free and every cell the
//! move passes through (`Move::via`) is free, exactly [`MoveSet::apply`]. The hot loop then
//! needs no obstacle test at all: a clear bit is a blocked check, a set bit gives the
//! neighbour as `p + delta[m]`. Masks are `u64`, enough for the largest set (48 moves).

use crate::grid::{Cell, Grid};
use crate::moves::MoveSet;

/// A bit of every mask word that searches may use as a per-cell scratch flag (move masks
/// use bits 0..48 at most). [`Adjacency::build`] leaves it clear; a search that sets it
/// must clear it again before it returns.
pub const SCRATCH: u64 = 1 << 63;

/// The safe-move masks of one grid and the padded index offset of each move.
#[derive(Debug, Clone)]
pub struct Adjacency {
    /// The grid the masks were built for: the cache key.
    grid: Grid,
    /// The revision of the last grid found equal to `grid`: the fast cache check.
    revision: u64,
    /// Border width: the longest move's reach.
    reach: usize,
    /// Padded row length, `width + 2 * reach`.
    stride: usize,
    /// Bit `m` set when move `m` is safe from the padded cell (0 for blocked and border
    /// cells). Bit [`SCRATCH`] is the search's scratch mark, clear between searches.
    safe: Vec<u64>,
    /// Padded index offset `dy * stride + dx` of move `m`; entries past the set's size are 0.
    delta: [isize; 64],
    /// Number of moves in the set.
    n_moves: usize,
    /// All moves of the set: bits `0..n_moves`.
    all: u64,
}

impl Adjacency {
    /// Builds the masks of `grid` for `moves`.
    pub fn build(grid: &Grid, moves: &MoveSet) -> Adjacency {
        let width = i64::from(grid.width());
        let height = i64::from(grid.height());
        let free = grid.free_cells();
        let reach = reach_of(moves);
        let stride = grid.width() as usize + 2 * reach;
        let padded_len = Adjacency::padded_len_for(grid, moves);
        let mut delta = [0isize; 64];
        for (slot, mv) in delta.iter_mut().zip(moves.moves()) {
            // |dy * stride + dx| < 2^33, far inside isize on every supported target.
            *slot = (i64::from(mv.dy) * stride as i64 + i64::from(mv.dx)) as isize;
        }
        let is_free = |x: i64, y: i64| {
            x >= 0 && y >= 0 && x < width && y < height && free[(y * width + x) as usize]
        };
        let mut safe = vec![0u64; padded_len];
        for (index, &cell_free) in free.iter().enumerate() {
            if !cell_free {
                continue;
            }
            let (x, y) = (index as i64 % width, index as i64 / width);
            let mut mask = 0u64;
            for (m, mv) in moves.moves().iter().enumerate() {
                let ok = is_free(x + i64::from(mv.dx), y + i64::from(mv.dy))
                    && mv
                        .via
                        .iter()
                        .all(|&(vx, vy)| is_free(x + i64::from(vx), y + i64::from(vy)));
                if ok {
                    mask |= 1 << m;
                }
            }
            safe[(y as usize + reach) * stride + x as usize + reach] = mask;
        }
        let n_moves = moves.moves().len();
        let all = if n_moves >= 64 {
            u64::MAX
        } else {
            (1u64 << n_moves) - 1
        };
        Adjacency {
            grid: grid.clone(),
            revision: grid.revision(),
            reach,
            stride,
            safe,
            delta,
            n_moves,
            all,
        }
    }

    /// The number of padded cells an adjacency of `grid` and `moves` has (its
    /// [`Adjacency::padded_len`]), computed without building it.
    pub fn padded_len_for(grid: &Grid, moves: &MoveSet) -> usize {
        let reach = reach_of(moves);
        (grid.width() as usize + 2 * reach) * (grid.height() as usize + 2 * reach)
    }

    /// The bytes an adjacency of `grid` and `moves` takes (its masks and its copy of the
    /// grid), computed without building it: what a planner adds up before a
    /// [`Budget::check_memory`](crate::Budget::check_memory).
    pub fn bytes_for(grid: &Grid, moves: &MoveSet) -> u64 {
        8 * Adjacency::padded_len_for(grid, moves) as u64 + grid.len() as u64
    }

    /// Whether these masks were built for `grid`.
    pub fn is_for(&self, grid: &Grid) -> bool {
        self.grid == *grid
    }

    /// Number of padded cells: the length of per-cell arrays indexed like `safe`.
    pub fn padded_len(&self) -> usize {
        self.safe.len()
    }

    /// The padded index of `cell`. Precondition: the cell is in the grid.
    pub fn index(&self, cell: Cell) -> usize {
        (cell.y as usize + self.reach) * self.stride + cell.x as usize + self.reach
    }

    /// The cell at padded index `p`. Precondition: `p` is a grid cell, not a border cell.
    pub fn cell(&self, p: usize) -> Cell {
        // Both coordinates are below the grid's u32 sides.
        Cell::new(
            (p % self.stride - self.reach) as u32,
            (p / self.stride - self.reach) as u32,
        )
    }
}

impl Adjacency {
    /// The padded index reached from `p` by move `m` (`m < n_moves`; only meaningful when
    /// bit `m` of `mask(p)` is set).
    #[inline]
    pub fn neighbor(&self, p: usize, m: u32) -> usize {
        p.wrapping_add_signed(self.delta[(m & 63) as usize])
    }

    /// The move mask of padded cell `p` (0 for blocked and border cells).
    #[inline]
    pub fn mask(&self, p: usize) -> u64 {
        self.safe[p]
    }

    /// Every padded cell's mask.
    pub fn masks(&self) -> &[u64] {
        &self.safe
    }

    /// The masks, mutable for the [`SCRATCH`] bit, and the move deltas.
    pub fn split_mut(&mut self) -> (&mut [u64], &[isize; 64]) {
        (&mut self.safe, &self.delta)
    }

    /// The padded index offset of each move (entries past [`Adjacency::n_moves`] are 0).
    pub fn deltas(&self) -> &[isize; 64] {
        &self.delta
    }

    /// Number of moves in the set.
    pub fn n_moves(&self) -> usize {
        self.n_moves
    }

    /// Bits `0..n_moves`: every move of the set.
    pub fn all(&self) -> u64 {
        self.all
    }

    /// Padded row length, `width + 2 * reach`.
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// Border width.
    pub fn reach(&self) -> usize {
        self.reach
    }

    /// Returns the masks in `cache` when they were built for `grid`, else rebuilds them.
    /// Precondition: `moves` is the same set every time the cache is used.
    pub fn cached<'a>(
        cache: &'a mut Option<Adjacency>,
        grid: &Grid,
        moves: &MoveSet,
    ) -> &'a mut Adjacency {
        cached(cache, grid, moves)
    }
}

/// The longest move's Chebyshev length (1 for an empty set): the border's width.
fn reach_of(moves: &MoveSet) -> usize {
    moves
        .moves()
        .iter()
        .map(|m| m.dx.unsigned_abs().max(m.dy.unsigned_abs()) as usize)
        .max()
        .unwrap_or(1)
}

fn cached<'a>(cache: &'a mut Option<Adjacency>, grid: &Grid, moves: &MoveSet) -> &'a mut Adjacency {
    match cache {
        // Equal revisions mean equal grids: no need to compare the cells.
        Some(adjacency) if adjacency.revision == grid.revision() => {}
        Some(adjacency) if adjacency.is_for(grid) => adjacency.revision = grid.revision(),
        _ => *cache = Some(Adjacency::build(grid, moves)),
    }
    match cache {
        Some(adjacency) => adjacency,
        None => unreachable!("the adjacency cache was just filled"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::moves::{Connectivity, NeighborOrder};

    #[test]
    fn masks_agree_with_move_set_apply() {
        let grid = Grid::from_ascii(
            "
            ..#...
            .#..#.
            ......
            ##.#..
            ",
        )
        .unwrap();
        for (connectivity, cutting) in [
            (Connectivity::Four, false),
            (Connectivity::Eight, false),
            (Connectivity::Eight, true),
            (Connectivity::Sixteen, false),
        ] {
            let moves = MoveSet::new(connectivity, cutting, &NeighborOrder::default()).unwrap();
            let adjacency = Adjacency::build(&grid, &moves);
            for cell in grid.cells() {
                let index = adjacency.index(cell);
                assert_eq!(adjacency.cell(index), cell);
                for (m, mv) in moves.moves().iter().enumerate() {
                    let expect = if grid.is_free(cell) {
                        moves.apply(&grid, cell, mv)
                    } else {
                        None
                    };
                    let bit = adjacency.mask(index) >> m & 1 == 1;
                    assert_eq!(bit, expect.is_some(), "{connectivity} {cell} move {m}");
                    if let Some(to) = expect {
                        assert_eq!(
                            adjacency.cell(index.wrapping_add_signed(adjacency.deltas()[m])),
                            to
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn the_cache_follows_the_grid_through_edits_and_copies() {
        let moves = MoveSet::new(Connectivity::Four, false, &NeighborOrder::default()).unwrap();
        let mut grid = Grid::from_ascii("...\n...").unwrap();
        let centre = |cache: &mut Option<Adjacency>, grid: &Grid| {
            let adjacency = Adjacency::cached(cache, grid, &moves);
            adjacency.mask(adjacency.index(Cell::new(1, 0)))
        };
        let mut cache = None;
        // Right, left and down are safe from (1, 0); up leaves the grid.
        assert_eq!(centre(&mut cache, &grid), 0b0111);
        // An edit in place gives a new revision, so the masks are rebuilt.
        grid.set_free(Cell::new(2, 0), false);
        assert_eq!(centre(&mut cache, &grid), 0b0110);
        // A clone shares the revision; an equal grid built anew has its own but equal cells.
        let copy = grid.clone();
        assert_eq!(copy.revision(), grid.revision());
        let rebuilt = Grid::from_ascii("..#\n...").unwrap();
        assert_ne!(rebuilt.revision(), grid.revision());
        assert_eq!(rebuilt, grid);
        assert_eq!(centre(&mut cache, &copy), 0b0110);
        assert_eq!(centre(&mut cache, &rebuilt), 0b0110);
        grid.set_free(Cell::new(2, 0), true);
        assert_eq!(centre(&mut cache, &grid), 0b0111);
    }
}
